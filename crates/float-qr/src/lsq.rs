//! Weighted least squares with exact linear constraints in `f64`, prepared once for an affine
//! family of right-hand sides.
//!
//! Minimise `Σ w_s (x_s − h_s)²` subject to `Â x = b̂`, `b = c_j − K α`. With `D = W^{-1/2}`
//! and `x = h + D y` the objective becomes `‖y‖²` and the constraint `(Â D) y = b̂ − Â h`, so `y`
//! is the minimum-norm solution: with `(Â D)ᵀ = Q_B R_B`, `y = Q_B R_B⁻ᵀ (b̂ − Â h)`. Preparing
//! computes `D`, that QR, and the family in `f64`; an update is two triangular solves and a few
//! matrix–vector products (plus the weak-consistency check on all rows).

use crate::convert::{dot_with_magnitude, matrix_rows, rationals, FloatRow};
use crate::factorization::{Core, FloatFactorization, FloatRhs};
use api::backend::{check_len, validate_family, validate_weights};
use api::{BackendError, PreparedLeastSquares, Rational, RhsFamily, SolveError};
use nalgebra::{DMatrix, DVector};
use std::sync::Arc;

/// Least squares prepared by [`FloatFactorization`]'s `prepare_least_squares`.
#[derive(Debug, Clone)]
pub struct FloatLeastSquares {
    core: Arc<Core>,
    /// `c_j` per column of the family, in `f64`.
    constants: Vec<Vec<f64>>,
    /// `K` by rows, in `f64`.
    k_rows: Vec<FloatRow>,
    /// Number of parameters (columns of `K`).
    parameters: usize,
    /// `D = W^{-1/2}`.
    scale: Vec<f64>,
    /// `Q_B` (`n × r`) of `(Â D)ᵀ = Q_B R_B`.
    q_b: DMatrix<f64>,
    /// `R_B` (`r × r`).
    r_b: DMatrix<f64>,
}

impl FloatLeastSquares {
    pub(crate) fn prepare(
        f: &FloatFactorization,
        family: &RhsFamily,
        weights: &[Rational],
    ) -> Result<Self, BackendError> {
        let core = Arc::clone(f.core());
        let n = core.cols();
        validate_family(family, core.rows())?;
        validate_weights(weights, n)?;
        let scale = rationals(weights, "weights")?
            .into_iter()
            .enumerate()
            .map(|(s, w)| {
                let d = 1.0 / w.sqrt();
                if w > 0.0 && d.is_finite() && d > 0.0 {
                    Ok(d)
                } else {
                    Err(BackendError::Numerical(format!(
                        "weight {s} is too small or too large for f64"
                    )))
                }
            })
            .collect::<Result<Vec<f64>, _>>()?;
        let constants = family
            .constant
            .iter()
            .map(|c| rationals(c, "family constant column"))
            .collect::<Result<Vec<_>, _>>()?;
        let k_rows = matrix_rows(&family.coefficients, "family coefficient matrix")?;

        let r = core.independent().len();
        let mut b_t = DMatrix::<f64>::zeros(n, r);
        for (k, &i) in core.independent().iter().enumerate() {
            for (s, v) in core.row(i) {
                b_t[(*s, k)] = v * scale[*s];
            }
        }
        let qr = b_t.qr();
        Ok(FloatLeastSquares {
            constants,
            k_rows,
            parameters: family.coefficients.cols(),
            scale,
            q_b: qr.q(),
            r_b: qr.r(),
            core,
        })
    }

    /// Validates the column and `α`, and forms `b = c_j − K α` with its row magnitudes.
    fn rhs(&self, column: usize, alpha: &[Rational]) -> Result<FloatRhs, BackendError> {
        let Some(c) = self.constants.get(column) else {
            return Err(BackendError::NoSuchColumn {
                column,
                columns: self.constants.len(),
            });
        };
        check_len("parameter vector α", alpha.len(), self.parameters)?;
        let alpha = rationals(alpha, "parameter vector α")?;
        let (values, magnitudes) = c
            .iter()
            .zip(&self.k_rows)
            .map(|(ci, k)| {
                let (ka, ka_magnitude) = dot_with_magnitude(k, &alpha);
                (ci - ka, ci.abs() + ka_magnitude)
            })
            .unzip();
        Ok(FloatRhs { values, magnitudes })
    }
}

impl PreparedLeastSquares for FloatLeastSquares {
    type Scalar = f64;

    fn check(&self, column: usize, alpha: &[Rational]) -> Result<(), SolveError<f64>> {
        let rhs = self.rhs(column, alpha)?;
        self.core.weak_check(&rhs).map(|_| ())
    }

    fn solve(
        &self,
        column: usize,
        alpha: &[Rational],
        hints: &[Rational],
    ) -> Result<Vec<f64>, SolveError<f64>> {
        let rhs = self.rhs(column, alpha)?;
        check_len("hints", hints.len(), self.core.cols())?;
        let h = rationals(hints, "hints")?;
        self.core.weak_check(&rhs)?;
        let independent = self.core.independent();
        // b̂ − Â h
        let gap = DVector::from_iterator(
            independent.len(),
            independent
                .iter()
                .map(|&i| rhs.values[i] - dot_with_magnitude(self.core.row(i), &h).0),
        );
        let z = self.r_b.tr_solve_upper_triangular(&gap).ok_or_else(|| {
            BackendError::Numerical("singular triangular factor of the weighted rows".into())
        })?;
        let y = &self.q_b * z;
        let x: Vec<f64> = h
            .iter()
            .zip(&self.scale)
            .zip(y.iter())
            .map(|((h, d), y)| h + d * y)
            .collect();
        if x.iter().all(|v| v.is_finite()) {
            Ok(x)
        } else {
            Err(SolveError::Input(BackendError::Numerical(
                "the least-squares solution overflows f64".into(),
            )))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::FloatQr;
    use api::{Factorization, IntMatrix, LinearBackend};

    fn q(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    #[test]
    fn weighted_projection_onto_a_line() {
        // x0 + x1 = 2 with weights (1, 3) and hints (0, 0): minimise x0² + 3 x1²
        // → x = (3/2, 1/2).
        let a = IntMatrix::from_dense(2, &[vec![1, 1]]).expect("matrix");
        let f = FloatQr::default().factor(&a).expect("factor");
        let x = f
            .least_squares(&[q(2, 1)], &[q(0, 1), q(0, 1)], &[q(1, 1), q(3, 1)])
            .expect("solvable");
        assert!(
            (x[0] - 1.5).abs() < 1e-12 && (x[1] - 0.5).abs() < 1e-12,
            "{x:?}"
        );
    }

    #[test]
    fn family_columns_and_parameters() {
        // x0 − x1 = c_j − α0, twice (redundant), hints (0, 0).
        let a = IntMatrix::from_dense(2, &[vec![1, -1], vec![2, -2]]).expect("matrix");
        let k = IntMatrix::from_dense(1, &[vec![1], vec![2]]).expect("K");
        let family = RhsFamily {
            constant: vec![vec![q(4, 1), q(8, 1)], vec![q(0, 1), q(1, 1)]],
            coefficients: k,
        };
        let f = FloatQr::default().factor(&a).expect("factor");
        let ones = [q(1, 1), q(1, 1)];
        let p = f.prepare_least_squares(&family, &ones).expect("prepare");
        let x = p
            .solve(0, &[q(2, 1)], &[q(0, 1), q(0, 1)])
            .expect("column 0");
        assert!(
            (x[0] - 1.0).abs() < 1e-12 && (x[1] + 1.0).abs() < 1e-12,
            "{x:?}"
        );
        p.check(0, &[q(7, 3)]).expect("consistent for every α");
        let err = p
            .check(1, &[q(0, 1)])
            .expect_err("column 1 is inconsistent");
        let SolveError::Inconsistent(c) = err else {
            panic!("{err:?}")
        };
        assert_eq!(c.rows, vec![0, 1]);
        assert!(
            (c.discrepancy.abs() - 1.0).abs() < 1e-12 || (c.discrepancy.abs() - 0.5).abs() < 1e-12
        );
        assert!(matches!(
            p.check(2, &[q(0, 1)]),
            Err(SolveError::Input(BackendError::NoSuchColumn {
                column: 2,
                columns: 2
            }))
        ));
        assert!(matches!(
            p.solve(0, &[], &[q(0, 1), q(0, 1)]),
            Err(SolveError::Input(BackendError::DimensionMismatch { .. }))
        ));
        assert!(matches!(
            p.solve(0, &[q(0, 1)], &[q(0, 1)]),
            Err(SolveError::Input(BackendError::DimensionMismatch { .. }))
        ));
    }

    #[test]
    fn bad_weights_are_refused() {
        let a = IntMatrix::from_dense(2, &[vec![1, 1]]).expect("matrix");
        let f = FloatQr::default().factor(&a).expect("factor");
        let family = RhsFamily::single(vec![q(0, 1)]);
        assert!(matches!(
            f.prepare_least_squares(&family, &[q(1, 1), q(0, 1)]),
            Err(BackendError::NonPositiveWeight { index: 1, .. })
        ));
        assert!(matches!(
            f.prepare_least_squares(&family, &[q(1, 1)]),
            Err(BackendError::DimensionMismatch { .. })
        ));
        let tiny = Rational::new(1.into(), api::Integer::from(10).pow(400u32));
        assert!(matches!(
            f.prepare_least_squares(&family, &[q(1, 1), tiny]),
            Err(BackendError::Numerical(_))
        ));
    }
}
