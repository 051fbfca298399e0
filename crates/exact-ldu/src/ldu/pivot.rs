//! Algorithm 7 (`LinSys.Pivot`, thesis 6.2): bring the pivot of stage `i` to `U_ii`.
//!
//! ```text
//! A = Π_R L D⁻¹ U Π_C  =  (Π_R P) (P⁻¹ L P) (P⁻¹ D P)⁻¹ (P⁻¹ U Q) (Q⁻¹ Π_C)
//! ```
//!
//! Exchanging two working rows (of `U`, `L`, `L_tt` and `Π_R`; the `D_tt` of the rows involved
//! are equal) or two working columns (of `U` and `Π_C`) at or after the stage keeps invariants
//! I1 and I2. Columns that are zero in the remaining rows are first gathered at the end
//! (`LinSys.GatherNonzeroColumns`), which may lower `j`.

use super::factor::WorkingFactors;
use super::Pivoting;
use crate::ring::Ring;
use std::cmp::Ordering;

impl<R: Ring> WorkingFactors<R> {
    /// Algorithm 7 (`LinSys.Pivot`, thesis 6.2): gathers the zero columns of rows `i..m` past
    /// `j`, chooses the pivot in rows `i..m`, columns `i..j` and swaps it to `(i, i)`.
    ///
    /// # Returns
    /// `false` when rows `i..m` of `U` are zero (the factoring is complete: rank `i`);
    /// otherwise `true` and `U_ii` is the pivot, nonzero.
    pub(super) fn pivot(&mut self, pivoting: Pivoting) -> bool {
        let i = self.i;
        self.j = gather_nonzero_columns(
            &mut self.u,
            &mut self.col_perm,
            &self.column_counts,
            i,
            self.j,
        );
        if self.j <= i {
            return false;
        }
        let choice = match pivoting {
            Pivoting::SmallestMagnitude => self.choose_smallest_pivot(),
            Pivoting::FirstNonzero => {
                choose_pivot(&self.u, &self.row_perm, &self.col_perm, i, self.j, pivoting)
            }
        };
        let Some((s, t)) = choice else {
            return false;
        };
        if t != i {
            swap_columns(&mut self.u, &mut self.col_perm, i, t);
        }
        if s != i {
            self.swap_rows(i, s);
        }
        true
    }

    /// `LinSys.SwapRows` (algorithm 7 step 18): exchanges working rows `a` and `b` of `U`,
    /// `L`, `L_tt`, the GCD method's primitive flags and `Π_R`. Both rows must be at or below
    /// the stage, where their `D_tt` are equal.
    pub(super) fn swap_rows(&mut self, a: usize, b: usize) {
        debug_assert!(a >= self.i && b >= self.i);
        self.u.swap(a, b);
        self.l.swap(a, b);
        self.l_diag.swap(a, b);
        self.primitive.swap(a, b);
        self.negated.swap(a, b);
        self.row_minimum.swap(a, b);
        self.row_perm.swap(a, b);
    }

    /// [`choose_pivot`] with [`Pivoting::SmallestMagnitude`], the same choice at `O(m + n)` per
    /// stage plus one scan per row that changed. Each row keeps the original column of its
    /// smallest entry in the active block ([`WorkingFactors::row_minimum`]); that stays the
    /// row's minimum until the row is eliminated against a pivot (`U_ti ≠ 0`, which clears it):
    /// the other updates of a stage (multiplying by the pivot, dividing by a content or by
    /// Turner's divisor, negating) scale the whole row, and the columns that leave the block
    /// (the pivot's, the zero ones) are not a row's nonzero minimum. The global choice is the
    /// smallest of the rows' minima under the same order (magnitude, original row, original
    /// column).
    fn choose_smallest_pivot(&mut self) -> Option<(usize, usize)> {
        let (i, j) = (self.i, self.j);
        let mut position = vec![0usize; self.col_perm.len()];
        for (q, &c) in self.col_perm.iter().enumerate() {
            position[c] = q;
        }
        let mut best: Option<(usize, usize)> = None;
        for p in i..self.u.len() {
            let cached = self.row_minimum[p].map(|c| position[c]);
            let q = match cached {
                Some(q) if q >= i && q < j && !self.u[p][q].is_zero() => Some(q),
                _ => {
                    let q = row_minimum(&self.u[p], &self.col_perm, i, j);
                    self.row_minimum[p] = q.map(|q| self.col_perm[q]);
                    q
                }
            };
            let Some(q) = q else {
                continue;
            };
            let better = match best {
                None => true,
                Some((bp, bq)) => match self.u[p][q].abs_cmp(&self.u[bp][bq]) {
                    Ordering::Less => true,
                    Ordering::Greater => false,
                    Ordering::Equal => {
                        (self.row_perm[p], self.col_perm[q])
                            < (self.row_perm[bp], self.col_perm[bq])
                    }
                },
            };
            if better {
                best = Some((p, q));
            }
        }
        best
    }
}

/// The working column of the smallest nonzero magnitude in `row` among columns `i..j`, ties on
/// the lowest original column; `None` when the row is zero there.
fn row_minimum<R: Ring>(row: &[R], col_perm: &[usize], i: usize, j: usize) -> Option<usize> {
    let mut best: Option<usize> = None;
    for (q, v) in row.iter().enumerate().take(j).skip(i) {
        if v.is_zero() {
            continue;
        }
        let better = match best {
            None => true,
            Some(b) => match v.abs_cmp(&row[b]) {
                Ordering::Less => true,
                Ordering::Greater => false,
                Ordering::Equal => col_perm[q] < col_perm[b],
            },
        };
        if better {
            best = Some(q);
        }
    }
    best
}

/// `LinSys.GatherNonzeroColumns` (algorithm 7 step 3): moves every column among `i..j` that is
/// zero in rows `i..` past the new `j`, by swapping it with the last active column.
/// `counts[c]` is the number of nonzero entries of original column `c` in rows `i..`
/// ([`WorkingFactors::column_counts`]), so a zero column is found without scanning it.
///
/// # Returns
/// The new `j`: afterwards each column `i..j` has a nonzero entry in rows `i..`, and columns
/// `j..` are zero there.
///
/// # Complexity
/// `O(j − i)` count tests and `O(m)` per column moved.
pub(super) fn gather_nonzero_columns<R: Ring>(
    u: &mut [Vec<R>],
    col_perm: &mut [usize],
    counts: &[usize],
    i: usize,
    mut j: usize,
) -> usize {
    let mut q = i;
    while q < j {
        if counts[col_perm[q]] == 0 {
            j -= 1;
            if q != j {
                swap_columns(u, col_perm, q, j);
            }
        } else {
            q += 1;
        }
    }
    j
}

/// The pivot search of algorithm 7 (steps 6–11) over rows `i..m` and columns `i..j`.
///
/// With [`Pivoting::SmallestMagnitude`] the pivot is an entry of smallest nonzero absolute
/// value; among equal magnitudes the one of lowest original row, then lowest original column
/// (`row_perm`, `col_perm`). The thesis takes the first in the current scan order; breaking ties
/// on original indices makes the choice independent of the positions earlier pivots moved rows
/// to, so factoring the connected components of a matrix separately gives the same pivots
/// (ARCHITECTURE.md, "Decisions"). With [`Pivoting::FirstNonzero`] it is the first nonzero
/// entry in row-major order (the hand-worked examples of thesis chapter 7).
///
/// # Returns
/// The working position `(row, column)` of the pivot, or `None` when the block is zero.
///
/// # Complexity
/// `O((m − i)(j − i))` comparisons.
pub(super) fn choose_pivot<R: Ring>(
    u: &[Vec<R>],
    row_perm: &[usize],
    col_perm: &[usize],
    i: usize,
    j: usize,
    pivoting: Pivoting,
) -> Option<(usize, usize)> {
    let mut best: Option<(usize, usize)> = None;
    for (p, row) in u.iter().enumerate().skip(i) {
        for (q, v) in row.iter().enumerate().take(j).skip(i) {
            if v.is_zero() {
                continue;
            }
            let better = match (best, pivoting) {
                (None, _) => true,
                (Some(_), Pivoting::FirstNonzero) => false,
                (Some((bp, bq)), Pivoting::SmallestMagnitude) => match v.abs_cmp(&u[bp][bq]) {
                    Ordering::Less => true,
                    Ordering::Greater => false,
                    Ordering::Equal => (row_perm[p], col_perm[q]) < (row_perm[bp], col_perm[bq]),
                },
            };
            if better {
                best = Some((p, q));
            }
        }
    }
    best
}

/// `LinSys.SwapColumns` (algorithm 7 step 16): exchanges working columns `a` and `b` of `U`
/// and `Π_C`.
pub(super) fn swap_columns<R: Ring>(u: &mut [Vec<R>], col_perm: &mut [usize], a: usize, b: usize) {
    for row in u.iter_mut() {
        row.swap(a, b);
    }
    col_perm.swap(a, b);
}

#[cfg(test)]
mod tests {
    use super::super::factor::tests::{ints, matrix_4_3};
    use super::*;
    use crate::ring::Int;
    use proptest::prelude::*;

    fn block() -> impl Strategy<Value = (usize, Vec<Vec<i64>>)> {
        (1usize..=5, 1usize..=5).prop_flat_map(|(m, n)| {
            (
                Just(n),
                prop::collection::vec(prop::collection::vec(-3i64..=3, n), m),
            )
        })
    }

    #[test]
    fn the_first_pivot_of_matrix_4_3_is_its_smallest_entry() {
        let (rows, cols) = matrix_4_3();
        let mut w = WorkingFactors::new(rows, cols);
        let before = w.product();
        assert!(w.pivot(Pivoting::SmallestMagnitude));
        // The −1 of row 1, column 0 (the 1 in row 2, column 0 and the −1 in row 3, column 2
        // tie, but lie in later rows).
        assert_eq!(w.u[0][0], Int::from_i64(-1));
        assert_eq!((w.row_perm[0], w.col_perm[0]), (1, 0));
        assert_eq!(w.product(), before);
    }

    #[test]
    fn a_zero_block_has_no_pivot() {
        let mut w = WorkingFactors::new(ints(&[vec![0, 0], vec![0, 0]]), 2);
        assert!(!w.pivot(Pivoting::SmallestMagnitude));
        assert_eq!(w.j, 0);
        assert_eq!(
            choose_pivot(&w.u, &w.row_perm, &w.col_perm, 0, 2, Pivoting::FirstNonzero),
            None
        );
    }

    #[test]
    fn ties_go_to_the_lowest_original_row_then_column() {
        // Working rows and columns reversed: the scan meets (0, 0) of A last.
        let u = ints(&[vec![2, 1], vec![1, 1]]);
        assert_eq!(
            choose_pivot(&u, &[1, 0], &[1, 0], 0, 2, Pivoting::SmallestMagnitude),
            Some((1, 1))
        );
        assert_eq!(
            choose_pivot(&u, &[1, 0], &[1, 0], 0, 2, Pivoting::FirstNonzero),
            Some((0, 0))
        );
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]

        /// Columns i..j have a nonzero in rows i.., columns j.. are zero there, and `U` is still
        /// `A Π_C⁻¹` column by column.
        #[test]
        fn gathering_moves_exactly_the_zero_columns((cols, rows) in block(), i in 0usize..3) {
            let i = i.min(rows.len() - 1).min(cols);
            let mut u = ints(&rows);
            let mut col_perm: Vec<usize> = (0..cols).collect();
            let counts = super::super::factor::column_counts(&u[i..], cols);
            let j = gather_nonzero_columns(&mut u, &mut col_perm, &counts, i, cols);
            for c in i..cols {
                let nonzero = u[i..].iter().any(|row| !row[c].is_zero());
                prop_assert_eq!(nonzero, c < j);
            }
            for (k, row) in u.iter().enumerate() {
                for (c, v) in row.iter().enumerate() {
                    prop_assert_eq!(v, &Int::from_i64(rows[k][col_perm[c]]));
                }
            }
        }

        /// The pivot is nonzero, no entry of the block is smaller, and among the smallest it
        /// has the lowest original (row, column).
        #[test]
        fn the_pivot_is_the_smallest_entry(
            (cols, rows, row_perm, col_perm) in block().prop_flat_map(|(cols, rows)| {
                let m = rows.len();
                (
                    Just(cols),
                    Just(rows),
                    Just((0..m).collect::<Vec<usize>>()).prop_shuffle(),
                    Just((0..cols).collect::<Vec<usize>>()).prop_shuffle(),
                )
            })
        ) {
            let u = ints(&rows);
            let pivot = choose_pivot(&u, &row_perm, &col_perm, 0, cols, Pivoting::SmallestMagnitude);
            let entries: Vec<(usize, usize)> = (0..rows.len())
                .flat_map(|p| (0..cols).map(move |q| (p, q)))
                .filter(|&(p, q)| rows[p][q] != 0)
                .collect();
            match pivot {
                None => prop_assert!(entries.is_empty()),
                Some((s, t)) => {
                    let v = rows[s][t].abs();
                    prop_assert!(v > 0);
                    for &(p, q) in &entries {
                        let w = rows[p][q].abs();
                        prop_assert!(
                            w > v || (w == v && (row_perm[s], col_perm[t]) <= (row_perm[p], col_perm[q]))
                        );
                    }
                }
            }
        }

        /// Algorithm 7 puts a nonzero pivot at (i, i) and keeps I1.
        #[test]
        fn pivoting_keeps_the_factoring((cols, rows) in block()) {
            let mut w = WorkingFactors::new(ints(&rows), cols);
            let before = w.product();
            if w.pivot(Pivoting::SmallestMagnitude) {
                prop_assert!(!w.u[0][0].is_zero());
            } else {
                prop_assert!(rows.iter().flatten().all(|&v| v == 0));
            }
            prop_assert_eq!(w.product(), before.clone());
            if w.rows() >= 2 {
                w.swap_rows(0, 1);
                prop_assert_eq!(w.product(), before);
            }
        }
    }
}
