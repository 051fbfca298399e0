//! The traits a linear-algebra backend implements.
//!
//! A [`LinearBackend`] factors an integer matrix `A` (`m × n`); the resulting [`Factorization`]
//! answers every question the editor asks about `A x = b`:
//!
//! * the rank, which rows are independent, and for each redundant row the combination of
//!   independent rows that reproduces it;
//! * a solution of `A x = b`, or an [`Inconsistency`] naming the rows that conflict;
//! * weak consistency (one right-hand side) and strong consistency (a whole affine family of
//!   right-hand sides `b(α) = c − K α`, as in the thesis, section 8.2.2);
//! * the null space;
//! * weighted least squares: the `x` with `A x = b` closest to hints `x'` in the norm
//!   `Σ w_s (x_s − x'_s)²`, prepared once for a family of right-hand sides and evaluated many
//!   times ([`PreparedLeastSquares`]).
//!
//! Questions are always asked with exact data (integer matrix, rational right-hand sides, hints and
//! weights); each backend answers in its own [`Value`] type: exact rationals for the exact
//! backend, `f64` for a floating-point one. That makes the answers of two backends directly
//! comparable.

use crate::exact::{fraction_to_f64, rational_to_f64, Integer, Rational};
use crate::matrix::IntMatrix;
use num_traits::One;
use std::fmt;

/// A number a backend answers in.
pub trait Value:
    Clone
    + fmt::Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + std::ops::Add<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Neg<Output = Self>
{
    /// The value as `f64` (rounded for exact values).
    fn to_f64(&self) -> f64;
    /// The value as an exact rational, when the backend is exact.
    fn to_exact(&self) -> Option<Rational>;
    /// An exact rational as a value of this type (rounded for float backends): for combining a
    /// backend's answers with exact data (the offsets of substituted unknowns, say).
    fn from_rational(r: &Rational) -> Self;
}

impl Value for Rational {
    fn to_f64(&self) -> f64 {
        rational_to_f64(self)
    }
    fn to_exact(&self) -> Option<Rational> {
        Some(self.clone())
    }
    fn from_rational(r: &Rational) -> Self {
        r.clone()
    }
}

impl Value for f64 {
    fn to_f64(&self) -> f64 {
        *self
    }
    fn to_exact(&self) -> Option<Rational> {
        None
    }
    fn from_rational(r: &Rational) -> Self {
        rational_to_f64(r)
    }
}

/// A redundant row and the combination of independent rows equal to it:
/// `A[row] = Σ coefficient · A[independent]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Redundancy<S> {
    /// The redundant row (index into `A`).
    pub row: usize,
    /// `(independent row, coefficient)` pairs with nonzero coefficients.
    pub combination: Vec<(usize, S)>,
}

/// Proof that `A x = b` has no solution: a vector `y` with `yᵀA = 0` and `yᵀb ≠ 0`.
///
/// Only the nonzero entries of `y` are listed; the rows they name are the constraints that
/// conflict with each other. The exact backend returns a primitive integer `y` whose support is
/// a minimal conflicting set (a circuit of the row matroid).
#[derive(Debug, Clone, PartialEq)]
pub struct Inconsistency<S> {
    /// Rows of `A` in the support of `y`, increasing.
    pub rows: Vec<usize>,
    /// `y` on those rows.
    pub certificate: Vec<S>,
    /// `yᵀ b`, nonzero.
    pub discrepancy: S,
}

/// An affine family of right-hand sides `b_j(α) = c_j − K α`, one constant vector per column
/// `j` of a multi-dimensional problem (`d` columns for parameters in `R^d`) and one integer
/// matrix `K` shared by all columns.
///
/// In an ECLES edit, `c_j = q_E − R_EF' P_F'` (column `j`) and `K = R_EA`; `α` are the anchor
/// values of column `j`.
#[derive(Debug, Clone, PartialEq)]
pub struct RhsFamily {
    /// The constant parts `c_j`, each of length `m`.
    pub constant: Vec<Vec<Rational>>,
    /// `K`, `m × a`.
    pub coefficients: IntMatrix,
}

impl RhsFamily {
    /// The family holding just the right-hand side `b` (one column, no parameters).
    pub fn single(rhs: Vec<Rational>) -> Self {
        let m = rhs.len();
        RhsFamily {
            constant: vec![rhs],
            coefficients: IntMatrix::zeros(m, 0),
        }
    }
}

/// Why a backend refused a question.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum BackendError {
    /// A vector or matrix has the wrong size.
    #[error("{what} has length {found}, expected {expected}")]
    DimensionMismatch {
        /// What was wrong.
        what: &'static str,
        /// The size expected.
        expected: usize,
        /// The size given.
        found: usize,
    },
    /// A least-squares weight is zero or negative.
    #[error("weight {index} is {weight}; weights must be positive")]
    NonPositiveWeight {
        /// Index of the weight.
        index: usize,
        /// The weight as text.
        weight: String,
    },
    /// A column index of a family does not exist.
    #[error("column {column} requested, but the family has {columns} columns")]
    NoSuchColumn {
        /// The column asked for.
        column: usize,
        /// Number of columns.
        columns: usize,
    },
    /// The backend could not represent the data (a float backend given non-finite values).
    #[error("numerical failure: {0}")]
    Numerical(String),
}

/// Either bad input or an inconsistent system.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError<S: fmt::Debug> {
    /// The question was malformed.
    #[error(transparent)]
    Input(#[from] BackendError),
    /// `A x = b` has no solution; the certificate names the conflicting rows.
    #[error("the system is inconsistent: rows {:?} conflict", .0.rows)]
    Inconsistent(Inconsistency<S>),
}

/// Which part of a family fails strong consistency.
#[derive(Debug, Clone, PartialEq)]
pub enum StrongFailure<S> {
    /// The constant part `c_j` of column `j` is not in the range of `A`.
    Constant {
        /// The column.
        column: usize,
        /// Certificate for `A x = c_j`.
        inconsistency: Inconsistency<S>,
    },
    /// Column `k` of `K` is not in the range of `A`: moving parameter `k` alone breaks the system.
    Direction {
        /// The column of `K` (the anchor coordinate).
        parameter: usize,
        /// Certificate for `A x = K[:, k]`.
        inconsistency: Inconsistency<S>,
    },
}

/// How safe a floating-point rank decision was: diagonal magnitudes of the triangular factor
/// relative to the largest one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RankMargin {
    /// Smallest kept diagonal magnitude, relative to the largest (1 when rank is 0).
    pub smallest_kept: f64,
    /// Largest dropped diagonal magnitude, relative to the largest (0 when nothing was dropped).
    pub largest_dropped: f64,
    /// The relative tolerance that separated them.
    pub tolerance: f64,
}

/// A backend: turns an integer matrix into a [`Factorization`].
pub trait LinearBackend {
    /// The factorization type.
    type Factorization: Factorization;
    /// Short name for reports (`"exact-ldu"`, `"float-qr"`).
    fn name(&self) -> &'static str;
    /// Factors `A`. Any shape and rank is allowed, including `0 × n` and `m × 0`.
    fn factor(&self, matrix: &IntMatrix) -> Result<Self::Factorization, BackendError>;
    /// Factors `A` where its solutions and null space will be asked for, not least squares:
    /// the same answers as [`LinearBackend::factor`], by whatever way of factoring suits
    /// that use (the exact backend then skips the proof of independent rows it keeps for
    /// least squares and makes the LDU those answers need at once).
    fn factor_for_solves(&self, matrix: &IntMatrix) -> Result<Self::Factorization, BackendError> {
        self.factor(matrix)
    }
}

/// A factored matrix `A` (`m × n`).
pub trait Factorization {
    /// Number type of the answers.
    type Scalar: Value;
    /// Least squares prepared for a family of right-hand sides.
    type LeastSquares: PreparedLeastSquares<Scalar = Self::Scalar>;

    /// `m`.
    fn rows(&self) -> usize;
    /// `n`.
    fn cols(&self) -> usize;
    /// The rank `r`.
    fn rank(&self) -> usize;
    /// `r` rows of `A` that are linearly independent and span its row space.
    fn independent_rows(&self) -> Vec<usize>;
    /// Every other row, with its combination of [`Self::independent_rows`].
    fn redundancies(&self) -> Vec<Redundancy<Self::Scalar>>;
    /// The margin of the rank decision, for backends that decide with a tolerance.
    fn rank_margin(&self) -> Option<RankMargin> {
        None
    }
    /// A solution of `A x = b` (length `n`), or the certificate that there is none.
    fn solve(&self, rhs: &[Rational]) -> Result<Vec<Self::Scalar>, SolveError<Self::Scalar>>;
    /// Weak consistency: `Ok` when `A x = b` has a solution.
    fn check_consistent(&self, rhs: &[Rational]) -> Result<(), SolveError<Self::Scalar>>;
    /// Strong consistency: `Ok` when `A x = b(α)` has a solution for every `α` and every column.
    /// The columns of `K` are checked before the constant parts, so a [`StrongFailure::Constant`]
    /// means the constant itself is out of range, whatever `α`.
    fn check_strongly_consistent(
        &self,
        family: &RhsFamily,
    ) -> Result<Result<(), StrongFailure<Self::Scalar>>, BackendError>;
    /// A basis of `{x : A x = 0}`: `n − r` vectors of length `n` (integer vectors for the exact
    /// backend).
    fn null_space(&self) -> Vec<Vec<Self::Scalar>>;
    /// Prepares weighted least squares for a family of right-hand sides: everything that does
    /// not depend on `α` or the hints is computed here, once.
    fn prepare_least_squares(
        &self,
        family: &RhsFamily,
        weights: &[Rational],
    ) -> Result<Self::LeastSquares, BackendError>;
    /// One-shot weighted least squares: the `x` with `A x = b` minimising
    /// `Σ w_s (x_s − hint_s)²`.
    fn least_squares(
        &self,
        rhs: &[Rational],
        hints: &[Rational],
        weights: &[Rational],
    ) -> Result<Vec<Self::Scalar>, SolveError<Self::Scalar>> {
        let prepared = self.prepare_least_squares(&RhsFamily::single(rhs.to_vec()), weights)?;
        prepared.solve(0, &[], hints)
    }
}

/// A factorization whose null space is made of integer vectors (the exact backends): the basis
/// of [`Factorization::null_space`] without making every entry a rational, for callers that
/// read only spans and zeros (the propagation analysis projects it on every parameter).
pub trait IntegerNullSpace {
    /// The vectors of [`Factorization::null_space`], in the same order, as integers.
    fn integer_null_space(&self) -> Vec<Vec<Integer>>;
}

/// Weighted least squares with constraints `A x = c_j − K α`, prepared by
/// [`Factorization::prepare_least_squares`].
pub trait PreparedLeastSquares: Send + Sync {
    /// Number type of the answers.
    type Scalar: Value;
    /// Weak consistency of `A x = c_j − K α`.
    fn check(&self, column: usize, alpha: &[Rational]) -> Result<(), SolveError<Self::Scalar>>;
    /// Checks consistency, then returns the `x` with `A x = c_j − K α` closest to `hints` in the
    /// weighted norm.
    fn solve(
        &self,
        column: usize,
        alpha: &[Rational],
        hints: &[Rational],
    ) -> Result<Vec<Self::Scalar>, SolveError<Self::Scalar>>;
    /// Like [`PreparedLeastSquares::solve`] (same checks, same verdict) but the solution is
    /// returned rounded to `f64`, for drawing each frame of a drag. Backends may skip work that
    /// only an exact result needs (an exact backend skips reducing fractions).
    fn solve_approx(
        &self,
        column: usize,
        alpha: &[Rational],
        hints: &[Rational],
    ) -> Result<Vec<f64>, SolveError<Self::Scalar>> {
        self.solve(column, alpha, hints)
            .map(|x| x.iter().map(Value::to_f64).collect())
    }

    /// Like [`PreparedLeastSquares::solve`] (same checks, same verdict) but a point of the
    /// constraint set near the optimum whose values have small denominators: free values on
    /// the grid `2^−grid_bits`, the others exact consequences of the constraints (a snapped
    /// commit, for long editing sessions whose exact optima would grow without bound). Every
    /// constraint holds exactly; [`Snapped::distance_bound`] says how far it may be from the
    /// optimum. Backends whose values have no denominators to bound return the optimum.
    fn solve_snapped(
        &self,
        column: usize,
        alpha: &[Rational],
        hints: &[Rational],
        _grid_bits: u32,
    ) -> Result<Snapped<Self::Scalar>, SolveError<Self::Scalar>> {
        self.solve(column, alpha, hints).map(|values| Snapped {
            values,
            distance_bound: 0.0,
            optimum: true,
        })
    }

    /// Like [`PreparedLeastSquares::solve`] (same checks, same verdict, the same values) but
    /// exact fractions not reduced to lowest terms, for exact drag frames. `None` from backends
    /// whose answers are not exact or that have no cheaper unreduced form (then reduce
    /// [`PreparedLeastSquares::solve`]'s answer, or convert it).
    #[allow(clippy::type_complexity)]
    fn solve_unreduced(
        &self,
        _column: usize,
        _alpha: &[Rational],
        _hints: &[Rational],
    ) -> Result<Option<Vec<Fraction>>, SolveError<Self::Scalar>> {
        Ok(None)
    }
}

/// A solution of the constraints near the least-squares optimum
/// ([`PreparedLeastSquares::solve_snapped`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Snapped<S> {
    /// The values, satisfying every constraint exactly.
    pub values: Vec<S>,
    /// Every value is within this distance of the optimum's value (an upper bound, rounded
    /// up; 0 when `optimum`).
    pub distance_bound: f64,
    /// The values are the optimum itself: no snapped point was found, or the backend's values
    /// have no denominators to bound.
    pub optimum: bool,
}

/// An exact value as a fraction not reduced to lowest terms (positive denominator): the values of
/// an exact solution over their common denominator, as an exact drag frame returns them
/// ([`PreparedLeastSquares::solve_unreduced`]). Reducing costs a GCD per value, the largest part
/// of an exact update on real meshes; a frame that is drawn and then replaced never needs it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Fraction {
    /// The numerator.
    pub numerator: Integer,
    /// The denominator, positive.
    pub denominator: Integer,
}

impl Fraction {
    /// The value in lowest terms.
    pub fn reduced(&self) -> Rational {
        Rational::new(self.numerator.clone(), self.denominator.clone())
    }

    /// The value rounded to `f64`.
    pub fn to_f64(&self) -> f64 {
        fraction_to_f64(&self.numerator, &self.denominator)
    }
}

/// The sum as a fraction, not reduced: over the common denominator when the denominators are
/// equal, over `b d` with numerator `a d + c b` otherwise (`d = 1`: `a + c b` over `b`).
impl std::ops::Add for Fraction {
    type Output = Fraction;

    fn add(self, other: Fraction) -> Fraction {
        if self.denominator == other.denominator {
            Fraction {
                numerator: self.numerator + other.numerator,
                denominator: self.denominator,
            }
        } else if other.denominator.is_one() {
            Fraction {
                numerator: self.numerator + other.numerator * &self.denominator,
                denominator: self.denominator,
            }
        } else if self.denominator.is_one() {
            other + self
        } else {
            Fraction {
                numerator: self.numerator * &other.denominator
                    + other.numerator * &self.denominator,
                denominator: self.denominator * other.denominator,
            }
        }
    }
}

impl std::ops::Neg for Fraction {
    type Output = Fraction;

    fn neg(self) -> Fraction {
        Fraction {
            numerator: -self.numerator,
            denominator: self.denominator,
        }
    }
}

impl From<Rational> for Fraction {
    fn from(r: Rational) -> Self {
        let (numerator, denominator) = r.into_raw();
        Fraction {
            numerator,
            denominator,
        }
    }
}

/// Checks that every weight is positive; shared by backends.
pub fn validate_weights(weights: &[Rational], n: usize) -> Result<(), BackendError> {
    if weights.len() != n {
        return Err(BackendError::DimensionMismatch {
            what: "weights",
            expected: n,
            found: weights.len(),
        });
    }
    for (index, w) in weights.iter().enumerate() {
        // By signs: a comparison of rationals multiplies big integers.
        if !num_traits::Signed::is_positive(w) {
            return Err(BackendError::NonPositiveWeight {
                index,
                weight: crate::exact::format_rational(w),
            });
        }
    }
    Ok(())
}

/// Checks that a family fits an `m × n` matrix; shared by backends.
pub fn validate_family(family: &RhsFamily, m: usize) -> Result<(), BackendError> {
    if family.coefficients.rows() != m {
        return Err(BackendError::DimensionMismatch {
            what: "family coefficient matrix rows",
            expected: m,
            found: family.coefficients.rows(),
        });
    }
    for c in &family.constant {
        if c.len() != m {
            return Err(BackendError::DimensionMismatch {
                what: "family constant column",
                expected: m,
                found: c.len(),
            });
        }
    }
    Ok(())
}

/// Checks the length of a vector argument; shared by backends.
pub fn check_len(what: &'static str, found: usize, expected: usize) -> Result<(), BackendError> {
    if found == expected {
        Ok(())
    } else {
        Err(BackendError::DimensionMismatch {
            what,
            expected,
            found,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn fraction(n: i64, d: i64) -> Fraction {
        Fraction {
            numerator: n.into(),
            denominator: d.into(),
        }
    }

    proptest! {
        /// Sums and negations of unreduced fractions have the values of the rationals'.
        #[test]
        fn fraction_sums_and_negations_are_rational_ones(
            a in -500i64..500, b in 1i64..13, c in -500i64..500, d in 1i64..13,
            same in proptest::bool::ANY,
        ) {
            let d = if same { b } else { d };
            let sum = fraction(a, b) + fraction(c, d);
            prop_assert!(sum.denominator > Integer::from(0));
            prop_assert_eq!(sum.reduced(), fraction(a, b).reduced() + fraction(c, d).reduced());
            prop_assert_eq!((-fraction(a, b)).reduced(), -fraction(a, b).reduced());
            let integer = fraction(a, b) + fraction(c, 1);
            prop_assert_eq!(&integer.denominator, &Integer::from(b));
            prop_assert_eq!((fraction(c, 1) + fraction(a, b)).denominator, Integer::from(b));
        }
    }
}
