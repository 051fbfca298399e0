//! Algorithm 6 (`LinSys.LDUFactor`, thesis 6.1): the stages of the factoring.
//!
//! ```text
//! A = Π_R L D⁻¹ U Π_C                                   (I1, before and after every step)
//! ```
//!
//! Stage `i` finds a pivot (algorithm 7), scales `L_ii` and `D_ii` by it, eliminates column
//! `i` from every row below (algorithm 8) simplifying each new row (algorithm 9) and then
//! column `i` of `L` (algorithm 10). The working matrices are `m × m` (`L`, `D`) and `m × n`
//! (`U`) until the last step removes the zero rows of `U` (`LinSys.RemoveNullParts`).
//!
//! Invariant I2 between stages: rows and columns `0..i` of `U` and `L` are triangular with a
//! nonzero diagonal, rows `i..m` of `U` are zero in columns `0..i` and `j..n`, and `L` restricted
//! to rows and columns `i..m` is diagonal (`L_tt`, kept in [`WorkingFactors::l_diag`]; the thesis
//! starts it as the identity and the GCD method scales it). `D_tt` of every row `t ≥ i` has one
//! common value ([`WorkingFactors::pending_d`]): all start at 1 and every stage multiplies them
//! by the same pivot (and divides them by the same previous pivot in Turner's method).

use super::simplify::{make_rows_primitive, simplify_d_turner, simplify_l_column, simplify_u_row};
use super::{eliminate, Ldu, Pivoting, Simplification, StageSnapshot};
use crate::ring::Ring;

/// The matrices of Algorithm 6 between its steps, in working row and column order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct WorkingFactors<R: Ring> {
    /// `U`: all `m` rows, `n` entries each.
    pub(super) u: Vec<Vec<R>>,
    /// Row `k` of `L` below the diagonal block: `L[k][0..min(k + 1, i)]` (the diagonal entry
    /// is included once row `k` has been a pivot row).
    pub(super) l: Vec<Vec<R>>,
    /// `L_tt` of the rows `t ≥ i` that have not been pivot rows yet (unused below `i`).
    pub(super) l_diag: Vec<R>,
    /// GCD method: row `t` is known to be primitive in columns `i..n`.
    pub(super) primitive: Vec<bool>,
    /// GCD method: row `t` is stored as its negative (see
    /// [`eliminate::eliminate_variable_gcd`]); pivot rows are always stored as they are.
    pub(super) negated: Vec<bool>,
    /// Original column of row `t`'s smallest-magnitude entry in the active block, when known
    /// (the pivot search's memo; `None` means "scan the row").
    pub(super) row_minimum: Vec<Option<usize>>,
    /// Nonzero entries of each original column in rows `i..m` (kept up to date by the stages,
    /// so the pivot step finds zero columns without scanning them).
    pub(super) column_counts: Vec<usize>,
    /// `D_jj` of the finished stages `j < i`.
    pub(super) d: Vec<R>,
    /// `D_tt`, equal for every row `t ≥ i`.
    pub(super) pending_d: R,
    /// `Π_R`: working row `k` is row `row_perm[k]` of `A`.
    pub(super) row_perm: Vec<usize>,
    /// `Π_C`: working column `c` is column `col_perm[c]` of `A`.
    pub(super) col_perm: Vec<usize>,
    /// The stage: the next pivot goes to `(i, i)`.
    pub(super) i: usize,
    /// Columns `j..n` are zero in rows `i..m`.
    pub(super) j: usize,
}

/// Algorithm 6 (`LinSys.LDUFactor`, thesis 6.1): the fraction-free factoring
/// `A = Π_R L D⁻¹ U Π_C` of the `m × n` matrix `rows` (`cols` entries each, checked by the
/// caller).
///
/// # Arguments
/// * `method`: how common factors are removed (thesis chapter 7).
/// * `pivoting`: the pivot rule of algorithm 7.
/// * `trace`: when given, receives `U` (all `m` rows) after every stage.
///
/// # Complexity
/// `Θ(m² n)` ring operations at full rank; with GCD or Turner simplification entries grow
/// linearly in the rank (thesis 6.5), without simplification exponentially.
pub(super) fn ldu_factor<R: Ring>(
    rows: Vec<Vec<R>>,
    cols: usize,
    method: Simplification,
    pivoting: Pivoting,
    mut trace: Option<&mut Vec<StageSnapshot>>,
) -> Ldu<R> {
    let mut w = WorkingFactors::new(rows, cols);
    if method == Simplification::Gcd {
        make_rows_primitive(&mut w.u, &mut w.l_diag, &mut w.primitive);
    }
    while w.i < w.rows() && w.i < w.j {
        if !w.pivot(pivoting) {
            break;
        }
        w.take_pivot();
        w.eliminate_below_pivot(method);
        let i = w.i;
        simplify_l_column(method, &mut w.l[i..], i, &mut w.d[i]);
        if let Some(stages) = trace.as_deref_mut() {
            stages.push(w.snapshot());
        }
        w.i += 1;
    }
    w.remove_null_parts(method)
}

/// Nonzero entries per column of `rows` (`cols` columns, working order = original order).
pub(super) fn column_counts<R: Ring>(rows: &[Vec<R>], cols: usize) -> Vec<usize> {
    let mut counts = vec![0; cols];
    for row in rows {
        for (c, v) in row.iter().enumerate() {
            if !v.is_zero() {
                counts[c] += 1;
            }
        }
    }
    counts
}

/// Adds (`add`) or removes the nonzero pattern of working row `row` to or from the counts by
/// original column.
fn count_nonzeros<R: Ring>(counts: &mut [usize], row: &[R], col_perm: &[usize], add: bool) {
    for (q, v) in row.iter().enumerate() {
        if !v.is_zero() {
            let c = &mut counts[col_perm[q]];
            if add {
                *c += 1;
            } else {
                *c -= 1;
            }
        }
    }
}

impl<R: Ring> WorkingFactors<R> {
    /// Algorithm 6 steps 1–2: `Π_R ← I`, `L ← I`, `D ← I`, `U ← A`, `Π_C ← I`, `i ← 1`,
    /// `j ← n` (0-based here: `i = 0`).
    pub(super) fn new(rows: Vec<Vec<R>>, cols: usize) -> Self {
        let m = rows.len();
        let column_counts = column_counts(&rows, cols);
        WorkingFactors {
            column_counts,
            u: rows,
            // Row k of L gets an entry per stage up to its own (at most `k + 1 ≤ cols`): sized
            // once rather than grown entry by entry (no more than the dense `U` beside it).
            l: (0..m)
                .map(|k| Vec::with_capacity((k + 1).min(cols)))
                .collect(),
            l_diag: vec![R::one(); m],
            primitive: vec![false; m],
            negated: vec![false; m],
            row_minimum: vec![None; m],
            d: Vec::new(),
            pending_d: R::one(),
            row_perm: (0..m).collect(),
            col_perm: (0..cols).collect(),
            i: 0,
            j: cols,
        }
    }

    /// `m`.
    pub(super) fn rows(&self) -> usize {
        self.u.len()
    }

    /// Algorithm 6 step 9: `L_ii ← L_ii U_ii`, `D_ii ← D_ii U_ii` for the pivot `U_ii` just
    /// brought into place; row `i` of `L` and `D_ii` become final (up to algorithm 10).
    pub(super) fn take_pivot(&mut self) {
        let i = self.i;
        eliminate::materialize(&mut self.u[i], &mut self.negated[i]);
        let pivot = &self.u[i][i];
        let lii = self.l_diag[i].mul(pivot);
        self.l[i].push(lii);
        self.d.push(self.pending_d.mul(pivot));
    }

    /// Algorithm 6 steps 10–12: eliminates column `i` from every row `t > i`
    /// (`LinSys.EliminateVariable`, algorithm 8) and simplifies the new row
    /// (`LinSys.SimplifyURow`, algorithm 9; the GCD method does both in one pass,
    /// [`eliminate::eliminate_variable_gcd`]). Then the common `D_tt` of those rows takes step 3
    /// of algorithm 8, `D_tt ← D_tt U_ii`, and in Turner's method step 5 of algorithm 13,
    /// `D_tt ← D_tt / U_{i−1,i−1}`.
    ///
    /// Afterwards rows `i + 1..m` of `U` are zero in column `i`.
    ///
    /// # Complexity
    /// `Θ((m − i)(n − i))` ring operations.
    pub(super) fn eliminate_below_pivot(&mut self, method: Simplification) {
        let i = self.i;
        let pivot = self.u[i][i].clone();
        let turner_divisor = if method == Simplification::Turner && i >= 1 {
            Some(self.u[i - 1][i - 1].clone())
        } else {
            None
        };
        let (head, tail) = self.u.split_at_mut(i + 1);
        let pivot_row = &head[i];
        // The pivot row leaves the active rows.
        count_nonzeros(&mut self.column_counts, pivot_row, &self.col_perm, false);
        for (offset, row) in tail.iter_mut().enumerate() {
            let t = i + 1 + offset;
            let eliminated = !row[i].is_zero();
            if eliminated {
                // The row's entries change unevenly: its minimum and nonzero pattern with them.
                self.row_minimum[t] = None;
                count_nonzeros(&mut self.column_counts, row, &self.col_perm, false);
            }
            match method {
                Simplification::None | Simplification::Turner => {
                    eliminate::eliminate_variable(
                        row,
                        pivot_row,
                        &pivot,
                        i,
                        &mut self.l[t],
                        &self.l_diag[t],
                    );
                    simplify_u_row(
                        method,
                        &mut row[i + 1..],
                        &mut self.l_diag[t],
                        turner_divisor.as_ref(),
                    );
                }
                Simplification::Gcd => eliminate::eliminate_variable_gcd(
                    row,
                    pivot_row,
                    &pivot,
                    i,
                    &mut self.l[t],
                    &mut self.l_diag[t],
                    &mut self.primitive[t],
                    &mut self.negated[t],
                ),
            }
            if eliminated {
                count_nonzeros(&mut self.column_counts, row, &self.col_perm, true);
            }
        }
        self.pending_d = self.pending_d.mul(&pivot);
        if let Some(div) = &turner_divisor {
            self.pending_d = simplify_d_turner(&self.pending_d, div);
        }
    }

    /// `U` after the current stage, as the thesis prints it in chapter 7.
    fn snapshot(&self) -> StageSnapshot {
        self.u
            .iter()
            .zip(&self.negated)
            .map(|(row, &negated)| {
                row.iter()
                    .map(|v| if negated { v.neg() } else { v.clone() }.to_bigint())
                    .collect()
            })
            .collect()
    }

    /// Algorithm 6 step 15 (`LinSys.RemoveNullParts`): `r ← i`, and the zero rows `r..m` of
    /// `U` are dropped (the columns `r..m` of `L` and `D` were never stored).
    pub(super) fn remove_null_parts(self, method: Simplification) -> Ldu<R> {
        let rank = self.i;
        let mut u = self.u;
        debug_assert!(u[rank..].iter().flatten().all(Ring::is_zero));
        u.truncate(rank);
        Ldu {
            rows: self.row_perm.len(),
            cols: self.col_perm.len(),
            rank,
            row_perm: self.row_perm,
            col_perm: self.col_perm,
            l: self.l,
            d: self.d,
            u,
            method,
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::ring::Int;
    use api::Rational;
    use proptest::prelude::*;

    /// Dense working rows of machine integers.
    pub(crate) fn ints(rows: &[Vec<i64>]) -> Vec<Vec<Int>> {
        rows.iter()
            .map(|r| r.iter().map(|&v| Int::from_i64(v)).collect())
            .collect()
    }

    /// A contract-suite matrix as working rows and its column count.
    fn working_rows(a: &api::IntMatrix) -> (Vec<Vec<Int>>, usize) {
        let rows = a
            .to_dense()
            .iter()
            .map(|r| r.iter().map(Int::from_bigint).collect())
            .collect();
        (rows, a.cols())
    }

    /// The thesis matrix (4.3) as working rows.
    pub(crate) fn matrix_4_3() -> (Vec<Vec<Int>>, usize) {
        working_rows(&backend_contract::thesis::matrix_4_3())
    }

    /// Turner's 4 × 4 example (thesis 7.1–7.3) as working rows.
    pub(crate) fn turner_matrix() -> (Vec<Vec<Int>>, usize) {
        working_rows(&backend_contract::thesis::turner_7_1())
    }

    pub(crate) fn rational(v: &Int) -> Rational {
        Rational::from_integer(v.to_bigint())
    }

    impl<R: Ring> WorkingFactors<R> {
        /// `Π_R L D⁻¹ U Π_C` of the working matrices, with `D_tt` of rows `t ≥ i` given by
        /// `pending(t)` (mid-stage, rows already eliminated carry `D_tt · U_ii`).
        pub(crate) fn product_with(&self, pending: impl Fn(usize) -> R) -> Vec<Vec<Rational>> {
            let m = self.rows();
            let n = self.col_perm.len();
            let zero = Rational::from_integer(0.into());
            let mut out = vec![vec![zero; n]; m];
            let d_of = |j: usize| {
                if j < self.d.len() {
                    self.d[j].clone()
                } else {
                    pending(j)
                }
            };
            for k in 0..m {
                let mut l_row: Vec<(usize, R)> = self.l[k].iter().cloned().enumerate().collect();
                if self.l[k].len() <= k {
                    l_row.push((k, self.l_diag[k].clone()));
                }
                for (j, lkj) in l_row {
                    if lkj.is_zero() {
                        continue;
                    }
                    let coeff = Rational::new(lkj.to_bigint(), d_of(j).to_bigint());
                    let coeff = if self.negated[j] { -coeff } else { coeff };
                    for c in 0..n {
                        out[self.row_perm[k]][self.col_perm[c]] +=
                            &coeff * Rational::from_integer(self.u[j][c].to_bigint());
                    }
                }
            }
            out
        }

        /// `Π_R L D⁻¹ U Π_C` between steps (every pending `D_tt` equal).
        pub(crate) fn product(&self) -> Vec<Vec<Rational>> {
            self.product_with(|_| self.pending_d.clone())
        }

        /// Checks invariant I2 between stages.
        pub(crate) fn assert_i2(&self) {
            let i = self.i;
            for k in 0..i {
                assert!(!self.u[k][k].is_zero(), "U_kk ≠ 0 for k < i");
                assert!(!self.d[k].is_zero(), "D_kk ≠ 0");
                assert_eq!(self.l[k].len(), k + 1, "row k of L is complete");
                assert!(!self.l[k][k].is_zero(), "L_kk ≠ 0");
            }
            for t in i..self.rows() {
                assert_eq!(
                    self.l[t].len(),
                    i,
                    "rows below the stage have i entries of L"
                );
                for c in (0..i).chain(self.j..self.col_perm.len()) {
                    assert!(
                        self.u[t][c].is_zero(),
                        "U[{t}][{c}] is zero below the stage"
                    );
                }
            }
        }
    }

    fn as_rationals(rows: &[Vec<Int>]) -> Vec<Vec<Rational>> {
        rows.iter()
            .map(|r| r.iter().map(rational).collect())
            .collect()
    }

    const METHODS: [Simplification; 3] = [
        Simplification::None,
        Simplification::Gcd,
        Simplification::Turner,
    ];

    /// Runs Algorithm 6 step by step, checking I1 and I2 after every step.
    fn factor_checked(rows: Vec<Vec<Int>>, cols: usize, method: Simplification) -> Ldu<Int> {
        let a = as_rationals(&rows);
        let mut w = WorkingFactors::new(rows.clone(), cols);
        assert_eq!(w.product(), a, "I1 at the start");
        if method == Simplification::Gcd {
            make_rows_primitive(&mut w.u, &mut w.l_diag, &mut w.primitive);
            assert_eq!(w.product(), a, "I1 after the rows are made primitive");
        }
        w.assert_i2();
        while w.i < w.rows() && w.i < w.j {
            if !w.pivot(Pivoting::SmallestMagnitude) {
                break;
            }
            assert_eq!(w.product(), a, "I1 after pivoting");
            w.take_pivot();
            assert_eq!(w.product(), a, "I1 after step 9");
            w.eliminate_below_pivot(method);
            assert_eq!(w.product(), a, "I1 after elimination");
            let i = w.i;
            assert!(w.u[i + 1..].iter().all(|row| row[i].is_zero()));
            simplify_l_column(method, &mut w.l[i..], i, &mut w.d[i]);
            assert_eq!(w.product(), a, "I1 after simplifying the column of L");
            w.i += 1;
            w.assert_i2();
        }
        let ldu = w.remove_null_parts(method);
        assert_eq!(ldu.reconstruct(), a, "I1 after removing the null parts");
        assert_eq!(
            ldu,
            ldu_factor(rows, cols, method, Pivoting::SmallestMagnitude, None)
        );
        ldu
    }

    #[test]
    fn every_step_keeps_the_invariants_on_the_thesis_matrices() {
        for method in METHODS {
            let (rows, cols) = matrix_4_3();
            assert_eq!(factor_checked(rows, cols, method).rank(), 3);
            let (rows, cols) = turner_matrix();
            assert_eq!(factor_checked(rows, cols, method).rank(), 4);
        }
    }

    #[test]
    fn the_start_is_the_trivial_factoring() {
        // Steps 1–2: Π_R = I, L = I, D = I, U = A, Π_C = I, i = 0, j = n.
        let (rows, cols) = matrix_4_3();
        let w = WorkingFactors::new(rows.clone(), cols);
        assert_eq!(w.product(), as_rationals(&rows));
        assert_eq!((w.i, w.j), (0, cols));
        assert_eq!(w.row_perm, (0..5).collect::<Vec<_>>());
        assert_eq!(w.col_perm, (0..cols).collect::<Vec<_>>());
        assert!(w.l_diag.iter().all(Ring::is_one) && w.pending_d.is_one());
        assert!(w.l.iter().all(Vec::is_empty) && w.d.is_empty());
        w.assert_i2();
    }

    #[test]
    fn step_9_scales_l_ii_and_d_ii_by_the_pivot() {
        let (rows, cols) = matrix_4_3();
        let mut w = WorkingFactors::new(rows, cols);
        assert!(w.pivot(Pivoting::SmallestMagnitude));
        let before = w.product();
        w.take_pivot();
        assert_eq!(w.l[0], vec![Int::from_i64(-1)]);
        assert_eq!(w.d, vec![Int::from_i64(-1)]);
        assert_eq!(w.product(), before);
    }

    #[test]
    fn removing_null_parts_keeps_the_nonzero_rows() {
        let (rows, cols) = matrix_4_3();
        let ldu = ldu_factor(
            rows,
            cols,
            Simplification::Turner,
            Pivoting::SmallestMagnitude,
            None,
        );
        assert_eq!((ldu.rows(), ldu.cols(), ldu.rank()), (5, 4, 3));
        assert_eq!(ldu.u.len(), 3);
        assert!(ldu.u.iter().enumerate().all(|(k, row)| !row[k].is_zero()));
    }

    #[test]
    fn the_trace_holds_u_after_every_stage() {
        let (rows, cols) = turner_matrix();
        let mut stages = Vec::new();
        let ldu = ldu_factor(
            rows,
            cols,
            Simplification::Turner,
            Pivoting::FirstNonzero,
            Some(&mut stages),
        );
        assert_eq!(stages.len(), ldu.rank());
        let last = stages.last().expect("four stages");
        for (k, row) in last.iter().enumerate() {
            let u: Vec<_> = ldu.u_row(k).iter().map(Ring::to_bigint).collect();
            assert_eq!(row, &u);
        }
    }

    fn small_matrix() -> impl Strategy<Value = (usize, Vec<Vec<i64>>)> {
        (0usize..=5, 0usize..=5).prop_flat_map(|(m, n)| {
            (
                Just(n),
                prop::collection::vec(prop::collection::vec(-4i64..=4, n), m),
            )
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// I1 and I2 hold after every step of every stage, for every method.
        #[test]
        fn invariants_hold_after_every_step((cols, rows) in small_matrix()) {
            for method in METHODS {
                factor_checked(ints(&rows), cols, method);
            }
        }
    }
}
