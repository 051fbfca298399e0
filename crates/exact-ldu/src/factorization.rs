//! The exact answers built on a factoring: solve (algorithm 14), weak and strong consistency
//! (sections 8.2.1, 8.2.2), redundancies, inconsistency certificates and the null space.

use crate::ldu::{Ldu, Simplification};
use crate::lsq::ExactLeastSquares;
use crate::qvec::QVec;
use crate::ring::{Int, Ring};
use api::backend::{check_len, validate_family};
use api::{
    BackendError, Factorization, Inconsistency, IntMatrix, Rational, Redundancy, RhsFamily,
    SolveError, StrongFailure,
};
use num_bigint::BigInt;
use num_traits::Zero;
use std::sync::Arc;

/// A sparse integer row: `(column, value)` by increasing column.
pub(crate) type SparseRow<R> = Vec<(usize, R)>;

/// An exactly factored matrix: the original rows and their fraction-free LDU factoring, shared
/// (a copy costs two reference counts: the factors are never changed once made).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExactFactorization<R: Ring = Int> {
    a: Arc<Vec<SparseRow<R>>>,
    ldu: Arc<Ldu<R>>,
}

impl<R: Ring> ExactFactorization<R> {
    /// Factors `matrix` with the given simplification method.
    pub fn new(matrix: &IntMatrix, method: Simplification) -> Self {
        let a: Vec<SparseRow<R>> = matrix
            .row_iter()
            .map(|row| row.iter().map(|(c, v)| (*c, R::from_bigint(v))).collect())
            .collect();
        let dense = a
            .iter()
            .map(|row| {
                let mut d = vec![R::zero(); matrix.cols()];
                for (c, v) in row {
                    d[*c] = v.clone();
                }
                d
            })
            .collect();
        let ldu = Ldu::factor(dense, matrix.cols(), method).expect("an IntMatrix is rectangular");
        ExactFactorization {
            a: Arc::new(a),
            ldu: Arc::new(ldu),
        }
    }

    /// The factoring itself.
    pub fn ldu(&self) -> &Ldu<R> {
        &self.ldu
    }

    pub(crate) fn sparse_rows(&self) -> &[SparseRow<R>] {
        &self.a
    }

    /// The right-hand side in `Π_R` order over a common denominator.
    pub(crate) fn permuted(&self, rhs: &[Rational]) -> QVec<R> {
        let permuted: Vec<Rational> = self
            .ldu
            .row_perm()
            .iter()
            .map(|&i| rhs[i].clone())
            .collect();
        QVec::from_rationals(&permuted)
    }

    /// Positions `t ≥ r` whose residual after forward substitution is nonzero.
    fn failing_positions(&self, forwarded: &QVec<R>) -> Vec<usize> {
        (self.ldu.rank()..self.ldu.rows())
            .filter(|&t| !forwarded.num[t].is_zero())
            .collect()
    }

    /// The primitive integer `y` with `yᵀA = 0` supported on redundant position `t` and the
    /// independent rows it depends on, as `(original row, y_row)` sorted by row.
    pub fn dependency(&self, t: usize) -> Vec<(usize, R)> {
        let w = self.ldu.redundancy_weights(t);
        let perm = self.ldu.row_perm();
        let mut y: Vec<(usize, R)> = Vec::new();
        y.push((perm[t], w.den.clone()));
        for (k, wk) in w.num.iter().enumerate() {
            if !wk.is_zero() {
                y.push((perm[k], wk.neg()));
            }
        }
        let values: Vec<R> = y.iter().map(|(_, v)| v.clone()).collect();
        let primitive = QVec::from_integers(values).primitive_integers();
        let mut y: Vec<(usize, R)> = y.into_iter().map(|(i, _)| i).zip(primitive).collect();
        y.sort_by_key(|(i, _)| *i);
        y
    }

    /// The certificate with the smallest support among the failing redundant positions.
    fn certificate(&self, failing: &[usize], rhs: &[Rational]) -> Inconsistency<Rational> {
        let mut best: Option<Vec<(usize, R)>> = None;
        for &t in failing {
            let y = self.dependency(t);
            if best.as_ref().is_none_or(|b| y.len() < b.len()) {
                best = Some(y);
            }
        }
        let y = best.unwrap_or_default();
        let discrepancy = y.iter().fold(Rational::zero(), |acc, (i, v)| {
            acc + &rhs[*i] * Rational::from_integer(v.to_bigint())
        });
        Inconsistency {
            rows: y.iter().map(|(i, _)| *i).collect(),
            certificate: y
                .iter()
                .map(|(_, v)| Rational::from_integer(v.to_bigint()))
                .collect(),
            discrepancy,
        }
    }

    /// Forward substitution plus the consistency verdict for one right-hand side: weak
    /// solvability (thesis 8.2.1, (8.10); `ECLES.CheckWeakSolvability`, algorithm 5), with the
    /// certificate of the smallest failing circuit.
    fn forward_checked(&self, rhs: &[Rational]) -> Result<QVec<R>, SolveError<Rational>> {
        check_len("right-hand side", rhs.len(), self.ldu.rows())?;
        let mut b = self.permuted(rhs);
        self.ldu.forward(&mut b);
        let failing = self.failing_positions(&b);
        if failing.is_empty() {
            Ok(b)
        } else {
            Err(SolveError::Inconsistent(self.certificate(&failing, rhs)))
        }
    }

    /// Algorithm 14 (`LinSys.Solve`, thesis 8.1) after its forward substitution: `Y = D z`,
    /// `X̂ = Û⁻¹ Y`, `X̃ = 0`, `P = Π_C⁻¹ X` (8.5)–(8.9). Back-substitutes a forwarded
    /// right-hand side: `x̂ = Û⁻¹ D z`, `x̃ = 0`, in original column
    /// order.
    pub(crate) fn basic_solution(&self, forwarded: QVec<R>) -> QVec<R> {
        let r = self.ldu.rank();
        let mut y = QVec {
            num: forwarded
                .num
                .into_iter()
                .take(r)
                .zip(self.ldu.d())
                .map(|(z, d)| z.mul(d))
                .collect(),
            den: forwarded.den,
        };
        self.ldu.backward(&mut y);
        let mut x = vec![R::zero(); self.ldu.cols()];
        for (k, v) in y.num.into_iter().enumerate() {
            x[self.ldu.col_perm()[k]] = v;
        }
        let mut out = QVec { num: x, den: y.den };
        out.normalize();
        out
    }

    /// The null space as primitive integer vectors: one per free column, in `Π_C` order.
    pub fn null_space_integers(&self) -> Vec<Vec<BigInt>> {
        let r = self.ldu.rank();
        let n = self.ldu.cols();
        (r..n)
            .map(|f| {
                let mut y =
                    QVec::from_integers((0..r).map(|k| self.ldu.u_row(k)[f].neg()).collect());
                self.ldu.backward(&mut y);
                let mut x = vec![R::zero(); n];
                for (k, v) in y.num.iter().enumerate() {
                    x[self.ldu.col_perm()[k]] = v.clone();
                }
                x[self.ldu.col_perm()[f]] = y.den.clone();
                QVec::from_integers(x)
                    .primitive_integers()
                    .iter()
                    .map(Ring::to_bigint)
                    .collect()
            })
            .collect()
    }

    fn column_of(matrix: &IntMatrix, k: usize) -> Vec<Rational> {
        (0..matrix.rows())
            .map(|i| Rational::from_integer(matrix.get(i, k)))
            .collect()
    }
}

impl<R: Ring> Factorization for ExactFactorization<R> {
    type Scalar = Rational;
    type LeastSquares = ExactLeastSquares<R>;

    fn rows(&self) -> usize {
        self.ldu.rows()
    }

    fn cols(&self) -> usize {
        self.ldu.cols()
    }

    fn rank(&self) -> usize {
        self.ldu.rank()
    }

    fn independent_rows(&self) -> Vec<usize> {
        self.ldu.row_perm()[..self.ldu.rank()].to_vec()
    }

    fn redundancies(&self) -> Vec<Redundancy<Rational>> {
        let perm = self.ldu.row_perm();
        (self.ldu.rank()..self.ldu.rows())
            .map(|t| {
                let w = self.ldu.redundancy_weights(t);
                let coefficients = w.to_rationals();
                Redundancy {
                    row: perm[t],
                    combination: coefficients
                        .into_iter()
                        .enumerate()
                        .filter(|(_, c)| !c.is_zero())
                        .map(|(k, c)| (perm[k], c))
                        .collect(),
                }
            })
            .collect()
    }

    /// Algorithm 14 (`LinSys.Solve`, thesis 8.1): [`Ldu::forward`], the weak check (8.10), then
    /// the basic solution (`X̃ = 0`).
    fn solve(&self, rhs: &[Rational]) -> Result<Vec<Rational>, SolveError<Rational>> {
        let forwarded = self.forward_checked(rhs)?;
        Ok(self.basic_solution(forwarded).to_rationals())
    }

    fn check_consistent(&self, rhs: &[Rational]) -> Result<(), SolveError<Rational>> {
        self.forward_checked(rhs).map(|_| ())
    }

    /// Strong solvability (thesis 8.2.2, (8.15)–(8.16); `ECLES.CheckStrongSolvability`,
    /// algorithm 3): every column of `K`, then every constant, passes the weak check.
    fn check_strongly_consistent(
        &self,
        family: &RhsFamily,
    ) -> Result<Result<(), StrongFailure<Rational>>, BackendError> {
        validate_family(family, self.ldu.rows())?;
        // Directions first: when every column of K is in the range, a constant part outside it
        // means the current values themselves are inconsistent, which is then reported as such.
        for parameter in 0..family.coefficients.cols() {
            let k = Self::column_of(&family.coefficients, parameter);
            match self.forward_checked(&k) {
                Ok(_) => {}
                Err(SolveError::Inconsistent(inconsistency)) => {
                    return Ok(Err(StrongFailure::Direction {
                        parameter,
                        inconsistency,
                    }))
                }
                Err(SolveError::Input(e)) => return Err(e),
            }
        }
        for (column, c) in family.constant.iter().enumerate() {
            match self.forward_checked(c) {
                Ok(_) => {}
                Err(SolveError::Inconsistent(inconsistency)) => {
                    return Ok(Err(StrongFailure::Constant {
                        column,
                        inconsistency,
                    }))
                }
                Err(SolveError::Input(e)) => return Err(e),
            }
        }
        Ok(Ok(()))
    }

    fn null_space(&self) -> Vec<Vec<Rational>> {
        self.null_space_integers()
            .into_iter()
            .map(|v| v.into_iter().map(Rational::from_integer).collect())
            .collect()
    }

    fn prepare_least_squares(
        &self,
        family: &RhsFamily,
        weights: &[Rational],
    ) -> Result<Self::LeastSquares, BackendError> {
        ExactLeastSquares::prepare(self, family, weights)
    }
}
