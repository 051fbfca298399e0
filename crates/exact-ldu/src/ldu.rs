//! The fraction-free LDU factoring `A = Π_R L D⁻¹ U Π_C` (thesis (4.1), algorithms 6–13).
//!
//! For an `m × n` integer matrix `A` of rank `r` the factoring yields integer matrices
//! `L` (`m × r`, lower trapezoidal), `D` (`r × r`, diagonal) and `U` (`r × n`, upper
//! trapezoidal) and two permutations. The first `r` rows of `Π_R⁻¹ A` are independent; every
//! later row is the combination `L̃ L̂⁻¹` of them.
//!
//! # Conventions
//! * `row_perm[k]` is the row of `A` at position `k` of `Π_R⁻¹ A`; `col_perm[k]` is the column
//!   of `A` at position `k` of `A Π_C⁻¹`. Hence
//!   `A[row_perm[k]][col_perm[c]] = Σ_{j ≤ min(k, r−1)} L[k][j] · U[j][c] / D[j]`.
//! * Pivoting (algorithm 7): columns that are zero in the remaining rows are moved to the end
//!   (swapping with the last active column), then the pivot is an entry of smallest nonzero
//!   absolute value; ties go to the lowest original row, then the lowest original column (the
//!   thesis takes the first in the current scan order; see below).
//! * Elimination (algorithm 8): `L_ti ← L_tt U_ti`, `D_tt ← D_tt U_ii`,
//!   `U_ts ← U_ii U_ts − U_ti U_is`. The pending `D_tt` of all uneliminated rows are always equal,
//!   so they are kept as one value.
//! * Simplification (algorithms 9–13): `None`; `Gcd` divides each new row of `U` by the GCD of
//!   its entries (moving the factor into `L_tt`) and each column of `L` together with `D_ii` by
//!   their GCD; `Turner` divides each new row by the previous pivot `U_{i−1,i−1}` (Bareiss) and,
//!   as the invariant requires, `D_tt ← D_tt / U_{i−1,i−1}` (the printed algorithm 13 has a slip
//!   there).
//!
//! Two deliberate departures from the printed algorithms make the pivots of a block-diagonal
//! matrix independent of the order its blocks are eliminated in, so that factoring connected
//! components separately gives exactly the same rank, independent rows, combinations and
//! solutions as one factoring: ties in the pivot search are broken on original indices, and the
//! `Gcd` method makes every row primitive before the first stage (the thesis simplifies a row
//! after its first elimination). The thesis' worked examples come out unchanged.
//!
//! The `Gcd` method also takes two shortcuts with the same results as the plain steps: the
//! elimination multipliers are divided by `gcd(U_ii, U_ti)` first (the row GCD absorbs that
//! factor anyway), and a row with `U_ti = 0`, already primitive, is only negated when
//! `U_ii < 0` instead of being multiplied by `U_ii` and divided back.
//!
//! # Where each algorithm is
//!
//! | thesis | function (module under `ldu/`) |
//! |---|---|
//! | Algorithm 6, `LinSys.LDUFactor` (6.1) | `factor::ldu_factor`, its steps `WorkingFactors::{new, take_pivot, eliminate_below_pivot, remove_null_parts}` |
//! | Algorithm 7, `LinSys.Pivot` (6.2) | `pivot::WorkingFactors::pivot`, with `gather_nonzero_columns`, `choose_pivot`, `swap_columns`, `WorkingFactors::swap_rows` |
//! | Algorithm 8, `LinSys.EliminateVariable` (6.3) | `eliminate::eliminate_variable` (the GCD method: `eliminate::eliminate_variable_gcd`) |
//! | Algorithm 9, `LinSys.SimplifyURow` (6.4) | `simplify::simplify_u_row` |
//! | Algorithm 10, `LinSys.SimplifyLColumn` (6.4) | `simplify::simplify_l_column` |
//! | Algorithm 11, `LinSys.SimplifyURowGCD` (7.2) | `simplify::simplify_u_row_gcd` (before the first stage: `simplify::make_rows_primitive`) |
//! | Algorithm 12, `LinSys.SimplifyLColumnGCD` (7.2) | `simplify::simplify_l_column_gcd` |
//! | Algorithm 13, `LinSys.SimplifyURowTurner` (7.3) | `simplify::simplify_u_row_turner`, `simplify::simplify_d_turner` |
//! | Algorithm 14 steps 2–3, (8.5), (8.8), (8.10) | [`Ldu::forward`], [`Ldu::backward`], [`Ldu::redundancy_weights`] (`substitute`) |
//! | invariant I1, (4.1) | [`Ldu::reconstruct`] (`reconstruct`) |

mod eliminate;
mod factor;
mod pivot;
mod reconstruct;
mod simplify;
mod substitute;

use crate::ring::Ring;
use api::BackendError;
use num_bigint::BigInt;

/// How common factors are removed during the factoring (thesis, chapter 7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Simplification {
    /// Plain fraction-free elimination: entries grow exponentially with the rank.
    None,
    /// Divide rows of `U` and columns of `L` by their GCD (smallest entries; the default).
    #[default]
    Gcd,
    /// Turner's GCD-free division by the previous pivot (Bareiss): linear growth, no GCDs.
    Turner,
}

/// How the pivot of each stage is chosen (after zero columns are moved to the end).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Pivoting {
    /// Full pivoting on the entry of smallest nonzero magnitude (algorithm 7; the default).
    #[default]
    SmallestMagnitude,
    /// The first nonzero entry in row-major order of the remaining block: no exchanges while
    /// the diagonal is nonzero (as in the hand-worked examples of thesis section 7).
    FirstNonzero,
}

/// The working matrix `U` after one elimination stage: all `m` rows, in working order.
pub type StageSnapshot = Vec<Vec<BigInt>>;

/// A fraction-free LDU factoring of an integer matrix.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ldu<R: Ring> {
    rows: usize,
    cols: usize,
    rank: usize,
    row_perm: Vec<usize>,
    col_perm: Vec<usize>,
    /// Row `k` holds `L[k][0..=min(k, r−1)]`.
    l: Vec<Vec<R>>,
    d: Vec<R>,
    /// Row `k < r` holds `U[k][0..n]` in permuted column order.
    u: Vec<Vec<R>>,
    method: Simplification,
}

fn check_rectangular<R>(rows: &[Vec<R>], cols: usize) -> Result<(), BackendError> {
    match rows.iter().find(|r| r.len() != cols) {
        Some(row) => Err(BackendError::DimensionMismatch {
            what: "matrix row",
            expected: cols,
            found: row.len(),
        }),
        None => Ok(()),
    }
}

impl<R: Ring> Ldu<R> {
    /// Factors the dense `m × n` matrix given by rows; every row must have `cols` entries.
    pub fn factor(
        rows: Vec<Vec<R>>,
        cols: usize,
        method: Simplification,
    ) -> Result<Self, BackendError> {
        check_rectangular(&rows, cols)?;
        Ok(factor::ldu_factor(
            rows,
            cols,
            method,
            Pivoting::SmallestMagnitude,
            None,
        ))
    }

    /// Factors like [`Ldu::factor`] with a chosen pivoting rule, and also returns the working
    /// matrix `U` (all `m` rows, working row and column order) after every stage, as the thesis
    /// prints it in chapter 7.
    pub fn factor_traced(
        rows: Vec<Vec<R>>,
        cols: usize,
        method: Simplification,
        pivoting: Pivoting,
    ) -> Result<(Self, Vec<StageSnapshot>), BackendError> {
        check_rectangular(&rows, cols)?;
        let mut stages = Vec::new();
        let ldu = factor::ldu_factor(rows, cols, method, pivoting, Some(&mut stages));
        Ok((ldu, stages))
    }

    /// `m`.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// `n`.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// The rank `r`.
    pub fn rank(&self) -> usize {
        self.rank
    }

    /// `Π_R` as a vector: position `k` of `Π_R⁻¹ A` holds row `row_perm()[k]` of `A`.
    pub fn row_perm(&self) -> &[usize] {
        &self.row_perm
    }

    /// `Π_C` as a vector: position `k` of `A Π_C⁻¹` holds column `col_perm()[k]` of `A`.
    pub fn col_perm(&self) -> &[usize] {
        &self.col_perm
    }

    /// Row `k` of `L` (`min(k + 1, r)` entries; the rest are zero).
    pub fn l_row(&self, k: usize) -> &[R] {
        &self.l[k]
    }

    /// `L[k][j]` (zero above the diagonal).
    pub fn l_at(&self, k: usize, j: usize) -> &R {
        &self.l[k][j]
    }

    /// The diagonal of `D`.
    pub fn d(&self) -> &[R] {
        &self.d
    }

    /// Row `k` of `U` (`n` entries, permuted column order).
    pub fn u_row(&self, k: usize) -> &[R] {
        &self.u[k]
    }

    /// The simplification method used.
    pub fn method(&self) -> Simplification {
        self.method
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ring::Int;

    #[test]
    fn ragged_rows_are_a_typed_error() {
        let rows = vec![
            vec![Int::from_i64(1), Int::from_i64(2)],
            vec![Int::from_i64(3)],
        ];
        assert!(matches!(
            Ldu::factor(rows, 2, Simplification::Gcd),
            Err(BackendError::DimensionMismatch {
                expected: 2,
                found: 1,
                ..
            })
        ));
    }
}
