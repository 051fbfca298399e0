//! The propagation analysis's solves on a small `M = [A; E_P]` in machine words.
//!
//! What a reached move's analysis reads off `M` does not depend on how `M` is factored: the
//! span of the reachable moves of the picked coordinates (written in [`super::row_basis`]'s
//! canonical form), the affine set of moves `particular + span(free)` (read per parameter by
//! [`super::follows`]: a forced move is the same in every particular solution, and the
//! projected span is the same for every basis of the null space). So for a small `M` whose
//! values stay in an `i64`, one elimination in machine words gives the same report as the
//! backend's factorization, without its big integers (on a 10-point edit the backend's
//! factoring, solves and null vectors of `M` were a third of the whole edit).
//!
//! The elimination is Gauss–Jordan, fraction-free, of `W = [M | s·m | E]`: `s·m` is the move
//! over the picked rows scaled to integers (zero on `A`'s rows), and `E` holds a unit column per
//! picked row, so every row of `W` stays `yᵀ [M | s·m | E]` for some `y`. Each row with a
//! nonzero entry in the pivot column becomes an integer combination of itself and the pivot
//! row, zero there: `row − (a/p)·pivot row` when the pivot `p` divides its entry `a` (values
//! grow by a sum), else `p·row − a·pivot row` over `gcd(p, a)`, divided by its content (values
//! stay small). Every step is invertible, so the rows end as a basis of the same row space and
//! the rows reduced to zero span `M`'s whole left null space. Then:
//!
//! - a row of `M` reduced to zero is `yᵀ M = 0`: its `E` part is `y_P`, and its move entry
//!   `s·y_P·m`. The reachable moves are the vectors orthogonal to every such `y_P` (a move
//!   `[0; m]` is in `M`'s column space exactly when every left null vector is orthogonal to
//!   it), and a nonzero move entry means the move is blocked;
//! - pivot row `r` (pivot column `c_r`) reads `W_{r,c_r} x_{c_r} + Σ_free W_{r,f} x_f =
//!   W_{r,move}`: the particular solution with free coordinates zero, and one null vector per
//!   free column.
//!
//! Products are checked: a value outside `i64` abandons the elimination, and the caller factors
//! `M` with the backend. So does a blocked move: the rows in its way are the backend's
//! certificate, as before.

use super::SparseRows;
use api::{Integer, Rational};
use num_integer::Integer as _;
use num_traits::{ToPrimitive, Zero};

/// Most columns of `M` eliminated in words: beyond this the dense elimination (cubic in the
/// columns) is left to the backend's sparse factoring.
pub(super) const MAX_COLUMNS: usize = 48;

/// `M = [A; E_P]` eliminated in machine words (see the module documentation).
pub(super) struct WordElimination {
    /// Columns of `M`.
    columns: usize,
    /// Entries per row of `W`: `columns + 1 + picked` (the move column is zero when no move
    /// was requested).
    width: usize,
    /// The rows of `W` one after another, pivot rows first (in pivot order): one buffer, not a
    /// vector per row (the elimination reads one column of every row per pivot).
    cells: Vec<i64>,
    /// The pivot column of each pivot row.
    pivot_columns: Vec<usize>,
    /// The move's scale `s` (the least common multiple of its denominators).
    scale: i64,
}

impl WordElimination {
    /// `[a; picked_rows]` eliminated with the move `requested` (over the picked rows), or
    /// `None` when `M` has more than [`MAX_COLUMNS`] columns or a value leaves an `i64`.
    pub(super) fn of(
        a: &impl SparseRows,
        picked_rows: &[Vec<(usize, Integer)>],
        requested: Option<&[Rational]>,
    ) -> Option<Self> {
        let columns = a.cols();
        let picked = picked_rows.len();
        if columns > MAX_COLUMNS || a.rows() + picked > 2 * MAX_COLUMNS {
            return None;
        }
        let (scale, moves) = match requested {
            Some(m) => scaled_to_integers(m)?,
            None => (1, vec![0; picked]),
        };
        let width = columns + 1 + picked;
        let mut cells = vec![0i64; (a.rows() + picked) * width];
        let (of_a, of_picked) = cells.split_at_mut(a.rows() * width);
        for (i, w) in of_a.chunks_exact_mut(width).enumerate() {
            for (c, v) in a.entries(i) {
                w[c] = v.to_i64()?;
            }
        }
        for (row, w) in picked_rows.iter().zip(of_picked.chunks_exact_mut(width)) {
            for (c, v) in row {
                w[*c] = v.to_i64()?;
            }
        }
        for (k, m) in moves.into_iter().enumerate() {
            let at = (a.rows() + k) * width;
            cells[at + columns] = m;
            cells[at + columns + 1 + k] = 1;
        }
        let mut elimination = WordElimination {
            columns,
            width,
            cells,
            pivot_columns: Vec::new(),
            scale,
        };
        elimination.eliminate()?;
        Some(elimination)
    }

    /// Number of rows of `W`.
    fn row_count(&self) -> usize {
        self.cells.len() / self.width
    }

    /// Gauss–Jordan over `M`'s columns, fraction-free: a row with a nonzero entry `a` in the
    /// pivot column becomes `(p·row − a·pivot row) / gcd(p, a)`, divided by its content (or
    /// `row − a·pivot row` when `p` divides `a`, over the pivot row's nonzero entries). Rows
    /// with a zero there are not touched (most of them, in the sparse rows of a component),
    /// where Bareiss' division by the previous pivot would have to scale every row at every
    /// step. `None` on a value outside `i64`.
    fn eliminate(&mut self) -> Option<()> {
        let (width, rows) = (self.width, self.row_count());
        // The pivot row (a copy: every other row is updated from it) and its nonzero columns.
        let mut pivot_row = vec![0i64; width];
        let mut support = Vec::new();
        for c in 0..self.columns {
            let next = self.pivot_columns.len();
            // The candidate of least magnitude keeps the values small.
            let Some(chosen) = (next..rows)
                .filter(|&i| self.cells[i * width + c] != 0)
                .min_by_key(|&i| self.cells[i * width + c].unsigned_abs())
            else {
                continue;
            };
            if chosen != next {
                let (head, tail) = self.cells.split_at_mut(chosen * width);
                head[next * width..(next + 1) * width].swap_with_slice(&mut tail[..width]);
            }
            // A positive pivot: where it divides a row's entry, that row only takes a multiple
            // of the pivot row's nonzero entries.
            let stored = &mut self.cells[next * width..(next + 1) * width];
            if stored[c] < 0 {
                for x in stored.iter_mut() {
                    *x = x.checked_neg()?;
                }
            }
            pivot_row.copy_from_slice(stored);
            let p = pivot_row[c];
            support.clear();
            support.extend((0..width).filter(|&j| pivot_row[j] != 0));
            for (i, row) in self.cells.chunks_exact_mut(width).enumerate() {
                let a = row[c];
                if a == 0 || i == next {
                    continue;
                }
                // `g` is at most `p`, an `i64`'s magnitude: the quotients fit.
                let (p, a) = if p == 1 {
                    (1, a)
                } else {
                    let g = word_gcd(p, a.checked_abs()?);
                    (p / g, a / g)
                };
                if p == 1 {
                    // `row − a·pivot row`: the values grow by a sum, not a product, and the
                    // row keeps its content.
                    for &j in &support {
                        row[j] = row[j].checked_sub(a.checked_mul(pivot_row[j])?)?;
                    }
                } else {
                    for (x, &y) in row.iter_mut().zip(pivot_row.iter()) {
                        *x = p.checked_mul(*x)?.checked_sub(a.checked_mul(y)?)?;
                    }
                    divide_by_content(row);
                }
            }
            self.pivot_columns.push(c);
        }
        Some(())
    }

    /// The rank of `M`.
    pub(super) fn rank(&self) -> usize {
        self.pivot_columns.len()
    }

    /// The rows of `M` reduced to zero.
    fn zero_rows(&self) -> impl Iterator<Item = &[i64]> {
        self.cells[self.rank() * self.width..].chunks_exact(self.width)
    }

    /// The pivot rows with their pivot columns.
    fn pivot_rows(&self) -> impl Iterator<Item = (&[i64], &usize)> {
        self.cells.chunks_exact(self.width).zip(&self.pivot_columns)
    }

    /// Whether no move of the system takes the picked coordinates to the requested move.
    pub(super) fn blocked(&self) -> bool {
        self.zero_rows().any(|row| row[self.columns] != 0)
    }

    /// The picked parts `y_P` of left null vectors of `M` that span them all: the reachable
    /// moves are the vectors orthogonal to each.
    pub(super) fn lost_normals(&self) -> Vec<Vec<Integer>> {
        self.zero_rows()
            .map(|row| {
                row[self.columns + 1..]
                    .iter()
                    .map(|&y| Integer::from(y))
                    .collect()
            })
            .collect()
    }

    /// The requested move's particular solution with every free coordinate zero: pivot row
    /// `r` reads `W_{r,c_r} x_{c_r} + Σ_free W_{r,f} x_f = W_{r,move}`. As word fractions, made
    /// rationals only where the report shows a value (a forced move).
    pub(super) fn particular(&self) -> Vec<WordFraction> {
        let mut x = vec![WordFraction { num: 0, den: 1 }; self.columns];
        for (row, &c) in self.pivot_rows() {
            // Pivots are positive, and so is the scale.
            let den = i128::from(row[c]) * i128::from(self.scale);
            x[c] = WordFraction {
                num: i128::from(row[self.columns]),
                den,
            };
        }
        x
    }

    /// One null vector of `M` per free column `f`, primitive: `L e_f − Σ_r (L W_{r,f} /
    /// W_{r,c_r}) e_{c_r}` with `L` the least common multiple of the pivots involved; `None`
    /// when a value leaves an `i64`.
    pub(super) fn null_space(&self) -> Option<Vec<Vec<i64>>> {
        let mut is_pivot = vec![false; self.columns];
        for &c in &self.pivot_columns {
            is_pivot[c] = true;
        }
        (0..self.columns)
            .filter(|&f| !is_pivot[f])
            .map(|f| {
                let mut lcm = 1i64;
                for (row, &c) in self.pivot_rows().filter(|(row, _)| row[f] != 0) {
                    let p = row[c].checked_abs()?;
                    lcm = lcm.checked_mul(p / word_gcd(lcm, p))?;
                }
                let mut v = vec![0i64; self.columns];
                v[f] = lcm;
                for (row, &c) in self.pivot_rows().filter(|(row, _)| row[f] != 0) {
                    v[c] = (lcm / row[c]).checked_mul(row[f])?.checked_neg()?;
                }
                divide_by_content(&mut v);
                Some(v)
            })
            .collect()
    }
}

/// `row` divided by the GCD of its entries (unchanged when that is 0 or 1).
fn divide_by_content(row: &mut [i64]) {
    let mut content = 0u64;
    for &x in row.iter() {
        if x != 0 {
            content = content.gcd(&x.unsigned_abs());
            if content == 1 {
                return;
            }
        }
    }
    // A content of 2^63 (every entry 0 or `i64::MIN`) is left: it only costs primitivity.
    if let Ok(content) = i64::try_from(content) {
        if content > 1 {
            for x in row.iter_mut() {
                *x /= content;
            }
        }
    }
}

/// `(s, s·m)` with `s` the least common multiple of the moves' denominators, when all fit.
fn scaled_to_integers(moves: &[Rational]) -> Option<(i64, Vec<i64>)> {
    let mut scale = 1i64;
    for m in moves {
        let d = m.denom().to_i64()?;
        scale = scale.checked_mul(d / word_gcd(scale, d))?;
    }
    let scaled = moves
        .iter()
        .map(|m| {
            let (n, d) = (m.numer().to_i64()?, m.denom().to_i64()?);
            n.checked_mul(scale / d)
        })
        .collect::<Option<Vec<i64>>>()?;
    Some((scale, scaled))
}

/// The GCD of two nonnegative words, at least 1 unless both are 0.
fn word_gcd(a: i64, b: i64) -> i64 {
    (a.unsigned_abs().gcd(&b.unsigned_abs())) as i64
}

/// `num / den` with `den > 0`, not reduced: a value of the particular solution in words
/// (`num` an `i64`'s value or its negation, `den` a product of two `i64`s).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct WordFraction {
    num: i128,
    den: i128,
}

impl WordFraction {
    /// Whether the value is zero.
    pub(super) fn is_zero(&self) -> bool {
        self.num == 0
    }

    /// The value in lowest terms, by a GCD of words when both parts fit one.
    pub(super) fn to_rational(self) -> Rational {
        let WordFraction { num: n, den: d } = self;
        if n == 0 {
            return Rational::zero();
        }
        let g = match (u64::try_from(n.unsigned_abs()), u64::try_from(d)) {
            (Ok(a), Ok(b)) => i128::from(a.gcd(&b)),
            _ => n.gcd(&d),
        };
        // `g ≥ 1` divides both: the quotients keep their signs.
        Rational::new_raw(Integer::from(n / g), Integer::from(d / g))
    }
}

impl std::ops::Neg for &WordFraction {
    type Output = WordFraction;

    /// The negated value (`num` is within `±2^63`, so its negation fits).
    fn neg(self) -> WordFraction {
        WordFraction {
            num: -self.num,
            den: self.den,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fraction(num: i128, den: i128) -> WordFraction {
        WordFraction { num, den }
    }

    fn rational(n: i64, d: i64) -> Rational {
        Rational::new(Integer::from(n), Integer::from(d))
    }

    #[test]
    fn word_fractions_become_rationals_in_lowest_terms() {
        assert_eq!(fraction(6, 4).to_rational(), rational(3, 2));
        assert_eq!(fraction(-6, 4).to_rational(), rational(-3, 2));
        assert_eq!((-&fraction(-6, 4)).to_rational(), rational(3, 2));
        assert_eq!(fraction(0, 7).to_rational(), Rational::zero());
        assert!(fraction(0, 7).is_zero() && !fraction(1, 7).is_zero());
        // A denominator beyond a word (a pivot times the move's scale) reduces in `i128`.
        let big = fraction(3 << 40, 1 << 70);
        let expected = Rational::new(Integer::from(3), Integer::from(1u64 << 30));
        assert_eq!(big.to_rational(), expected);
        // The result is reduced as built, not only equal in value.
        let r = fraction(i128::from(i64::MIN), 1 << 64).to_rational();
        assert_eq!(
            (r.numer().clone(), r.denom().clone()),
            (Integer::from(-1), Integer::from(2))
        );
    }
}
