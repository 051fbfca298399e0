//! The defining equations of the backend traits' answers, checked against the
//! [`oracle`](crate::oracle).
//!
//! Each function takes a matrix `A`, the question and a backend's answer, and returns the first
//! equation the answer breaks. They are the bodies of the [`crate::suite`] and can be used
//! directly for backends that answer only some of the questions (see [`crate::analysis`]).
//!
//! | answer | equation |
//! |---|---|
//! | rank `r` | `r = rank A` |
//! | independent rows `I` | `|I| = r`, distinct, `rank A[I] = r` |
//! | redundancies | one per row outside `I`, each `A[t] = Σ_{k∈I} w_k A[k]` |
//! | solution `x` | `A x = b` (or `b` out of range and a certificate) |
//! | certificate `y` | `yᵀA = 0`, `yᵀb = δ ≠ 0`; exact: `y` primitive integer, support a circuit |
//! | strong consistency | `Ok` ⇔ every column of `K` and every `c_j` in the range of `A`; a failure names one out of range, directions before constants |
//! | null space `N` | `n − r` vectors, `A v = 0`, independent; exact: primitive integers |
//! | least squares `x` | `A x = b` and `W (x − h) ⟂ ker A` |

mod least_squares;
mod null_space;
mod rows;
mod solve;

pub use least_squares::{approximation, family_rhs, least_squares, least_squares_answer};
pub use null_space::null_space;
pub use rows::{independent_rows, rank, rank_margin, redundancies};
pub use solve::{certificate, consistency_answer, equals, solution, solve_answer, strong_answer};

use crate::tolerance::{ensure, Num, Tolerance, Violation};
use api::{IntMatrix, Integer, Rational};

/// The result of a check.
pub type Check = Result<(), Violation>;

pub(super) fn zero() -> Integer {
    Integer::from(0)
}

/// `max_k |v_k|` as `f64`.
pub(super) fn norm_inf<N: Num>(v: &[N]) -> f64 {
    v.iter().map(Num::size).fold(0.0, f64::max)
}

/// `(Σ_j a_ij x_j − b_i, Σ_j |a_ij| · max(‖x‖∞, extra) + |b_i|)` per row: the residual and the
/// size a rounding error of it can reach (normwise, so entries that should be zero and carry
/// rounding noise do not set their own scale; `extra` is the size of other inputs the
/// solution was computed from, such as hints).
pub(super) fn residuals<N: Num>(
    a: &IntMatrix,
    x: &[N],
    b: &[Rational],
    extra: f64,
) -> Vec<(N, f64)> {
    let magnitude = norm_inf(x).max(extra);
    a.row_iter()
        .zip(b)
        .map(|(row, bi)| {
            let bi = N::of_rational(bi);
            let mut scale = bi.size();
            let mut s = N::zero().minus(&bi);
            for (j, v) in row {
                let aij = N::of_integer(v);
                scale += aij.size() * magnitude;
                s = s.plus(&aij.times(&x[*j]));
            }
            (s, scale)
        })
        .collect()
}

/// `(Σ_i y_i a_ij, Σ_i |a_ij| · ‖y‖∞)` per column `j`, for `y` given on `rows`.
pub(super) fn left_product<N: Num>(a: &IntMatrix, rows: &[usize], y: &[N]) -> Vec<(N, f64)> {
    let magnitude = norm_inf(y);
    let mut out = vec![(N::zero(), 0.0); a.cols()];
    for (&i, yi) in rows.iter().zip(y) {
        for (j, v) in a.row(i) {
            let aij = N::of_integer(v);
            out[*j].1 += aij.size() * magnitude;
            out[*j].0 = out[*j].0.plus(&aij.times(yi));
        }
    }
    out
}

/// Every residual of `A x = b` vanishes (see [`residuals`] for `extra`).
pub(super) fn residuals_vanish<N: Num>(
    a: &IntMatrix,
    x: &[N],
    b: &[Rational],
    extra: f64,
    tol: Tolerance,
) -> Check {
    for (i, (res, scale)) in residuals(a, x, b, extra).iter().enumerate() {
        ensure(tol.is_zero(res, *scale), || {
            format!("row {i} of A x = b is off by {res:?} (terms of size {scale:e})")
        })?;
    }
    Ok(())
}

pub(super) fn gcd(mut a: Integer, mut b: Integer) -> Integer {
    if a < zero() {
        a = -a;
    }
    if b < zero() {
        b = -b;
    }
    while b != zero() {
        let r = &a % &b;
        a = b;
        b = r;
    }
    a
}
