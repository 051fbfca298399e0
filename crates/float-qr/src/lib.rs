//! The floating-point backend of ecles-rs: column-pivoted Householder QR in `f64` (nalgebra),
//! answering the same questions as the exact backend so that the two can be cross-checked.
//!
//! # Method
//!
//! For an integer matrix `A` (`m × n`, converted to `f64`):
//!
//! * **Rank and independent rows.** A column-pivoted QR of `Aᵀ` (`n × m`): its columns are the
//!   rows of `A`, so the pivot order is an order of the rows of `A` in which each next row adds
//!   as much new direction as possible. The rank `r` is the length of the leading run of
//!   diagonal entries `|R_kk|` above `tolerance · max_k |R_kk|`, and the independent rows are the
//!   first `r` pivots. [`api::Factorization::rank_margin`] reports how far the kept and dropped
//!   diagonal magnitudes were from that threshold.
//! * **Solve.** With `Â` the `r` independent rows (full row rank) and `Âᵀ = Q₁ R₁` a thin QR,
//!   the minimum-norm solution of `Â x = b̂` is `x = Q₁ R₁⁻ᵀ b̂`.
//! * **Weak consistency** is decided on **all** rows of `A` with that `x`: row `i` passes when
//!   `|a_i·x − b_i| ≤ tolerance · s_i`, where `s_i` is the size a rounding error of that residual
//!   can reach: `‖a_i‖ ‖x‖ + |b_i|` (evaluating the residual) plus
//!   `Σ_k |w_ik| (‖Â‖_F ‖x‖ + |b̂_k|)` (what the QR solve leaves on the independent rows,
//!   carried to row `i` by its combination `w_i`; `w_i = e_k` for independent row `k`).
//!   For a family `b = c − K α` the magnitude `|b_i|` is replaced by `|c_i| + Σ_k |K_ik| |α_k|`,
//!   so cancellation while forming `b` cannot fake an inconsistency.
//!   A failing row is normally a redundant one (the independent rows are solved up to
//!   rounding); its combination `a_t ≈ Σ_k w_k â_k` gives the certificate
//!   `y = e_t − Σ_k w_k e_{ind_k}` with `yᵀA ≈ 0` and `yᵀb ≠ 0`. Among several failing rows the
//!   one with the smallest support is reported. Should an independent row fail (only possible
//!   when `Â` is too ill-conditioned for `f64`), the answer is
//!   [`api::BackendError::Numerical`] rather than a certificate.
//! * **Null space.** The last `n − r` columns of the full orthogonal factor of `Âᵀ = Q R`:
//!   an orthonormal basis of `{x : Â x = 0}`.
//! * **Weighted least squares.** Minimise `Σ w_s (x_s − h_s)²` subject to `Â x = b̂`.
//!   Substituting `x = h + W^{-1/2} y` turns it into the minimum-norm `y` of
//!   `(Â W^{-1/2}) y = b̂ − Â h`, solved with a QR of `(Â W^{-1/2})ᵀ` computed once per prepared
//!   family ([`FloatLeastSquares`]).
//!
//! Answers are `f64`, with the same shapes as the exact backend's rational answers. The
//! certificate of an inconsistency is normalised to `y_t = 1` on the failing redundant row (the
//! exact backend returns a primitive integer vector instead), so the two agree up to a factor.
//!
//! ```
//! use api::{Factorization, IntMatrix, LinearBackend, Rational};
//! use float_qr::FloatQr;
//!
//! // p1 + p2 - p3 = 0, p4 - p3 = 5, and the (redundant) difference of the two rows.
//! let a = IntMatrix::from_dense(4, &[vec![1, 1, -1, 0], vec![0, 0, -1, 1], vec![1, 1, 0, -1]])
//!     .unwrap();
//! let f = FloatQr::default().factor(&a).unwrap();
//! assert_eq!(f.rank(), 2);
//! let b: Vec<Rational> = [0, 5, -5].iter().map(|&v| Rational::from_integer(v.into())).collect();
//! let x = f.solve(&b).unwrap();
//! assert!((x[3] - x[2] - 5.0).abs() < 1e-12);
//! ```

mod column_order;
mod convert;
mod factorization;
mod lsq;
mod sparse_lsq;
mod sparse_rank;

pub use factorization::FloatFactorization;
pub use lsq::FloatLeastSquares;
pub use sparse_lsq::{SparseLeastSquares, Unsatisfied};
pub use sparse_rank::{sparse_part_row_rank, sparse_row_rank, SparseRowRank};

use api::{BackendError, IntMatrix, LinearBackend};

/// The default relative tolerance of [`FloatQr`]: `1e-10`.
///
/// Why this value:
///
/// * Constraint rows are small integers, so the diagonal magnitudes of the triangular factor of a
///   genuinely independent row stay far from zero relative to the largest one (for the matrices
///   the editor builds, ratios below `1e-6` are already unusual).
/// * A row that depends exactly on the others leaves, after the Householder steps, a diagonal
///   magnitude at rounding level: a few units of `f64::EPSILON ≈ 2.2e-16` times the matrix
///   scale, i.e. about `1e-15` relative.
/// * `1e-10` sits between the two with roughly five orders of magnitude of headroom on the
///   rounding side (rounding errors grow with the size and conditioning of the matrix) and still
///   keeps independent rows whose relative diagonal is as small as `1e-10`.
///
/// Anything below the tolerance relative to the largest diagonal magnitude is treated as zero.
/// The same relative tolerance decides weak consistency (a residual relative to the magnitude
/// of the terms that produced it; see the crate documentation).
pub const DEFAULT_TOLERANCE: f64 = 1e-10;

/// Why a [`FloatQr`] could not be built.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum FloatQrError {
    /// The tolerance is not a finite number in `(0, 1)`.
    #[error("tolerance {0} must be a finite number with 0 < tolerance < 1")]
    InvalidTolerance(f64),
}

/// The floating-point backend: column-pivoted QR in `f64` with a relative rank tolerance.
///
/// Used to cross-check the exact backend (`exact-ldu`): it answers the same questions through
/// the same traits, in `f64`, and reports how safe its rank decision was
/// ([`api::Factorization::rank_margin`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FloatQr {
    tolerance: f64,
}

impl FloatQr {
    /// A backend deciding rank and consistency with the given relative tolerance.
    ///
    /// The tolerance must be finite and strictly between 0 and 1: zero or negative would turn
    /// rounding noise into rank, and 1 or more would call every matrix rank 0.
    pub fn new(tolerance: f64) -> Result<Self, FloatQrError> {
        if tolerance.is_finite() && tolerance > 0.0 && tolerance < 1.0 {
            Ok(FloatQr { tolerance })
        } else {
            Err(FloatQrError::InvalidTolerance(tolerance))
        }
    }

    /// The relative tolerance.
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }
}

impl Default for FloatQr {
    /// The backend with [`DEFAULT_TOLERANCE`].
    fn default() -> Self {
        FloatQr {
            tolerance: DEFAULT_TOLERANCE,
        }
    }
}

impl LinearBackend for FloatQr {
    type Factorization = FloatFactorization;

    fn name(&self) -> &'static str {
        "float-qr"
    }

    fn factor(&self, matrix: &IntMatrix) -> Result<Self::Factorization, BackendError> {
        FloatFactorization::new(matrix, self.tolerance)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tolerance_is_validated() {
        assert!(FloatQr::new(1e-12).is_ok());
        for bad in [0.0, -1e-10, 1.0, 2.0, f64::NAN, f64::INFINITY] {
            assert!(
                matches!(FloatQr::new(bad), Err(FloatQrError::InvalidTolerance(_))),
                "{bad}"
            );
        }
        assert_eq!(FloatQr::default().tolerance(), DEFAULT_TOLERANCE);
        assert_eq!(FloatQr::default().name(), "float-qr");
    }
}
