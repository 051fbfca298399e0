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
//! The elimination is fraction-free Gauss–Jordan (Bareiss' exact division by the previous
//! pivot, applied to the rows above the pivot as well) of `W = [M | s·m | E]`: `s·m` is the move
//! over the picked rows scaled to integers (zero on `A`'s rows), and `E` holds a unit column per
//! picked row, so every row of `W` stays `yᵀ [M | s·m | E]` for some `y`. Every entry is then a
//! minor of `W` and each division is exact; after the last pivot every pivot entry is the same
//! `d ≠ 0`. Then:
//!
//! - a row of `M` reduced to zero is `yᵀ M = 0`: its `E` part is `y_P`, and its move entry
//!   `s·y_P·m`. The reachable moves are the vectors orthogonal to every such `y_P` (a move
//!   `[0; m]` is in `M`'s column space exactly when every left null vector is orthogonal to
//!   it), and a nonzero move entry means the move is blocked;
//! - pivot row `r` (pivot column `c_r`) reads `d x_{c_r} + Σ_free W_{r,f} x_f = W_{r,move}`: the
//!   particular solution with free coordinates zero is `x_{c_r} = W_{r,move} / (d s)`, and free
//!   column `f`'s null vector is `d e_f − Σ_r W_{r,f} e_{c_r}`.
//!
//! Products are checked: a value outside `i64` (or a division that is not exact, which the
//! minors rule out) abandons the elimination, and the caller factors `M` with the backend. So
//! does a blocked move: the rows in its way are the backend's certificate, as before.

use api::{IntMatrix, Integer, Rational};
use num_integer::Integer as _;
use num_traits::{ToPrimitive, Zero};

/// Most columns of `M` eliminated in words: beyond this the dense elimination (cubic in the
/// columns) is left to the backend's sparse factoring.
pub(super) const MAX_COLUMNS: usize = 48;

/// `M = [A; E_P]` eliminated in machine words (see the module documentation).
pub(super) struct WordElimination {
    /// Columns of `M`.
    columns: usize,
    /// Picked rows (the last rows of `M`, and the width of `E`).
    picked: usize,
    /// The rows of `W`, pivot rows first (in pivot order), each `columns + 1 + picked` wide
    /// (the move column is zero when no move was requested).
    rows: Vec<Vec<i64>>,
    /// The pivot column of each pivot row.
    pivot_columns: Vec<usize>,
    /// The common pivot entry `d` (1 when `M` is zero).
    pivot: i64,
    /// The move's scale `s` (the least common multiple of its denominators).
    scale: i64,
}

impl WordElimination {
    /// `[a; picked_rows]` eliminated with the move `requested` (over the picked rows), or
    /// `None` when `M` has more than [`MAX_COLUMNS`] columns or a value leaves an `i64`.
    pub(super) fn of(
        a: &IntMatrix,
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
        let dense = |row: &[(usize, Integer)]| -> Option<Vec<i64>> {
            let mut w = vec![0i64; width];
            for (c, v) in row {
                w[*c] = v.to_i64()?;
            }
            Some(w)
        };
        let mut rows = Vec::with_capacity(a.rows() + picked);
        for row in a.row_iter() {
            rows.push(dense(row)?);
        }
        for (k, (row, m)) in picked_rows.iter().zip(moves).enumerate() {
            let mut w = dense(row)?;
            w[columns] = m;
            w[columns + 1 + k] = 1;
            rows.push(w);
        }
        let mut elimination = WordElimination {
            columns,
            picked,
            rows,
            pivot_columns: Vec::new(),
            pivot: 1,
            scale,
        };
        elimination.eliminate()?;
        Some(elimination)
    }

    /// Fraction-free Gauss–Jordan over `M`'s columns: `None` on a value outside `i64`.
    fn eliminate(&mut self) -> Option<()> {
        let width = self.columns + 1 + self.picked;
        let mut previous = 1i64;
        for c in 0..self.columns {
            let next = self.pivot_columns.len();
            // The candidate of least magnitude keeps the minors small.
            let Some(chosen) = (next..self.rows.len())
                .filter(|&i| self.rows[i][c] != 0)
                .min_by_key(|&i| self.rows[i][c].unsigned_abs())
            else {
                continue;
            };
            self.rows.swap(next, chosen);
            let (before, rest) = self.rows.split_at_mut(next);
            let (pivot_row, after) = rest.split_first_mut()?;
            let p = pivot_row[c];
            for row in before.iter_mut().chain(after.iter_mut()) {
                let a = row[c];
                if a == 0 && p == previous {
                    continue;
                }
                for j in 0..width {
                    let value = p
                        .checked_mul(row[j])?
                        .checked_sub(a.checked_mul(pivot_row[j])?)?;
                    row[j] = exact_quotient(value, previous)?;
                }
            }
            self.pivot_columns.push(c);
            previous = p;
        }
        self.pivot = previous;
        Some(())
    }

    /// The rank of `M`.
    pub(super) fn rank(&self) -> usize {
        self.pivot_columns.len()
    }

    /// The rows of `M` reduced to zero.
    fn zero_rows(&self) -> &[Vec<i64>] {
        &self.rows[self.rank()..]
    }

    /// Whether no move of the system takes the picked coordinates to the requested move.
    pub(super) fn blocked(&self) -> bool {
        self.zero_rows().iter().any(|row| row[self.columns] != 0)
    }

    /// The picked parts `y_P` of left null vectors of `M` that span them all: the reachable
    /// moves are the vectors orthogonal to each.
    pub(super) fn lost_normals(&self) -> Vec<Vec<Integer>> {
        self.zero_rows()
            .iter()
            .map(|row| {
                row[self.columns + 1..]
                    .iter()
                    .map(|&y| Integer::from(y))
                    .collect()
            })
            .collect()
    }

    /// The requested move's particular solution with every free coordinate zero.
    pub(super) fn particular(&self) -> Vec<Rational> {
        let mut x = vec![Rational::zero(); self.columns];
        let den = i128::from(self.pivot) * i128::from(self.scale);
        for (row, &c) in self.rows.iter().zip(&self.pivot_columns) {
            x[c] = word_ratio(i128::from(row[self.columns]), den);
        }
        x
    }

    /// One null vector of `M` per free column, primitive.
    pub(super) fn null_space(&self) -> Vec<Vec<Integer>> {
        let mut is_pivot = vec![false; self.columns];
        for &c in &self.pivot_columns {
            is_pivot[c] = true;
        }
        (0..self.columns)
            .filter(|&f| !is_pivot[f])
            .map(|f| {
                let mut v = vec![0i128; self.columns];
                v[f] = i128::from(self.pivot);
                for (row, &c) in self.rows.iter().zip(&self.pivot_columns) {
                    v[c] = -i128::from(row[f]);
                }
                let content = v.iter().fold(0i128, |g, &x| g.gcd(&x));
                v.into_iter()
                    .map(|x| Integer::from(if content > 1 { x / content } else { x }))
                    .collect()
            })
            .collect()
    }
}

/// `value / divisor` when it is exact and fits.
fn exact_quotient(value: i64, divisor: i64) -> Option<i64> {
    match divisor {
        1 => Some(value),
        -1 => value.checked_neg(),
        _ => (value.checked_rem(divisor)? == 0).then(|| value / divisor),
    }
}

/// `(s, s·m)` with `s` the least common multiple of the moves' denominators, when all fit.
fn scaled_to_integers(moves: &[Rational]) -> Option<(i64, Vec<i64>)> {
    let mut scale = 1i64;
    for m in moves {
        let d = m.denom().to_i64()?;
        scale = scale.checked_mul(d / scale.gcd(&d))?;
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

/// `n / d` in lowest terms (`d ≠ 0`).
fn word_ratio(n: i128, d: i128) -> Rational {
    let g = n.gcd(&d);
    let (n, d) = if d < 0 {
        (-n / g, -d / g)
    } else {
        (n / g, d / g)
    };
    Rational::new_raw(Integer::from(n), Integer::from(d))
}
