//! The exact answers built on a factoring: solve (algorithm 14), weak and strong consistency
//! (sections 8.2.1, 8.2.2), redundancies, inconsistency certificates and the null space.

use crate::certified::CertifiedBasis;
use crate::dixon::LiftingSolver;
use crate::ldu::{Ldu, Simplification};
use crate::lsq::ExactLeastSquares;
use crate::qvec::QVec;
use crate::ring::{gcd_all, Int, Ring};
use api::backend::{check_len, validate_family};
use api::{
    BackendError, Factorization, Inconsistency, IntMatrix, IntegerNullSpace, Rational, Redundancy,
    RhsFamily, SolveError, StrongFailure,
};
use num_bigint::BigInt;
use num_traits::Zero;
use rayon::prelude::*;
use std::sync::{Arc, OnceLock};

/// A certified factoring forms its null space by one lifted solve per free column up to this
/// many free columns; beyond, on a matrix of at most [`FRACTION_FREE_NULL_SPACE_ENTRIES`]
/// entries, by the fraction-free LDU (made for it) and one back substitution per free column:
/// a hundred lifted solves (the null space of a strip of 50 parallelograms in every edit's
/// propagation analysis) cost twice that.
const LIFTED_NULL_VECTORS_UP_TO: usize = 16;

/// See [`LIFTED_NULL_VECTORS_UP_TO`]: the fraction-free LDU is dense, so only small matrices.
const FRACTION_FREE_NULL_SPACE_ENTRIES: usize = 1 << 16;

/// A sparse integer row: `(column, value)` by increasing column.
pub(crate) type SparseRow<R> = Vec<(usize, R)>;

/// An exactly factored matrix: the original rows and their factoring, shared (a copy costs two
/// reference counts: the factors are never changed once made).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExactFactorization<R: Ring = Int> {
    a: Arc<Vec<SparseRow<R>>>,
    cols: usize,
    factoring: Arc<Factoring<R>>,
}

/// How the rank and the redundancies were decided.
#[derive(Debug)]
enum Factoring<R: Ring> {
    /// The thesis' fraction-free LDU (algorithms 6–13).
    FractionFree(Ldu<R>),
    /// A small matrix whose rows are independent, proved by the fraction-free elimination of
    /// its Gram matrix `G = A Aᵀ` in machine words (nonzero pivots: `det G ≠ 0`), which is also
    /// what least squares needs ([`ExactFactorization::gram_solver`]). Rank, independent rows
    /// and consistency need nothing more (every right-hand side is consistent); the
    /// fraction-free LDU is made only when a solve or the null space asks for it, so those
    /// answers are the LDU's own.
    FullRowRank {
        gram: LiftingSolver,
        method: Simplification,
        ldu: OnceLock<Ldu<R>>,
    },
    /// A row basis found modulo a prime and proved over the integers ([`crate::certified`]).
    Certified(CertifiedBasis),
}

/// Equal factorings give equal answers: the LDU of a full-row-rank factoring is derived from
/// the matrix (made or not yet, it is the same).
impl<R: Ring> PartialEq for Factoring<R> {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Factoring::FractionFree(a), Factoring::FractionFree(b)) => a == b,
            (
                Factoring::FullRowRank {
                    gram: a,
                    method: ma,
                    ..
                },
                Factoring::FullRowRank {
                    gram: b,
                    method: mb,
                    ..
                },
            ) => a == b && ma == mb,
            (Factoring::Certified(a), Factoring::Certified(b)) => a == b,
            _ => false,
        }
    }
}

impl<R: Ring> Eq for Factoring<R> {}

/// The Gram matrix `A Aᵀ` of a small matrix with independent rows, prepared in words: `None`
/// unless `A` has at most [`crate::bareiss_small::MAX_ORDER`] rows, no more rows than columns,
/// entries and products that fit machine words, and independent rows (the elimination's
/// pivots, leading principal minors of `G`, all nonzero). Sums accumulate in `i128`, checked
/// ([`crate::gram_words`]).
fn full_row_rank_gram<R: Ring>(a: &[SparseRow<R>], cols: usize) -> Option<LiftingSolver> {
    let m = a.len();
    if m == 0 || m > crate::bareiss_small::MAX_ORDER || m > cols {
        return None;
    }
    let words = crate::gram_words::gram_rows(a, cols, |_| Some(1), |x| i64::try_from(x).ok())?;
    LiftingSolver::small_symmetric(m, &words)
}

impl<R: Ring> ExactFactorization<R> {
    /// Factors `matrix` fraction-free with the given simplification method. A small matrix
    /// whose rows are independent (the edits of a few points) is only proved so, by its Gram
    /// matrix in machine words, and factored when a solve or the null space needs the LDU.
    pub fn new(matrix: &IntMatrix, method: Simplification) -> Self {
        let a = Self::sparse(matrix);
        let factoring = match full_row_rank_gram(&a, matrix.cols()) {
            Some(gram) => Factoring::FullRowRank {
                gram,
                method,
                ldu: OnceLock::new(),
            },
            None => Factoring::FractionFree(Self::fraction_free(&a, matrix.cols(), method)),
        };
        ExactFactorization {
            a: Arc::new(a),
            cols: matrix.cols(),
            factoring: Arc::new(factoring),
        }
    }

    /// Factors `matrix` by the fraction-free LDU at once, whatever its shape: the same factors
    /// (and so the same answers) as [`ExactFactorization::new`] makes when a solve or the null
    /// space first asks, without the Gram proof that only least squares uses.
    pub fn fraction_free_now(matrix: &IntMatrix, method: Simplification) -> Self {
        let a = Self::sparse(matrix);
        let factoring = Factoring::FractionFree(Self::fraction_free(&a, matrix.cols(), method));
        ExactFactorization {
            a: Arc::new(a),
            cols: matrix.cols(),
            factoring: Arc::new(factoring),
        }
    }

    /// The certified row basis of `matrix` ([`crate::certified`]); fraction-free with `method`
    /// in the rare case that no prime tried gives a basis that can be proved.
    pub fn certified(matrix: &IntMatrix, method: Simplification) -> Self {
        let a = Self::sparse(matrix);
        let factoring = match CertifiedBasis::new(&a, matrix.cols()) {
            Some(basis) => Factoring::Certified(basis),
            None => Factoring::FractionFree(Self::fraction_free(&a, matrix.cols(), method)),
        };
        ExactFactorization {
            a: Arc::new(a),
            cols: matrix.cols(),
            factoring: Arc::new(factoring),
        }
    }

    /// Whether this is a factoring of `matrix` (the same shape and the same entries, compared
    /// by value without converting the matrix): the memo of the last factoring keeps no copy of
    /// the matrix it factored, only this factoring's own rows.
    pub(crate) fn is_of(&self, matrix: &IntMatrix) -> bool {
        self.cols == matrix.cols()
            && self.a.len() == matrix.rows()
            && self.a.iter().zip(matrix.row_iter()).all(|(ours, theirs)| {
                ours.len() == theirs.len()
                    && ours.iter().zip(theirs).all(|((c, v), (d, w))| {
                        c == d
                            && match (v.to_i64(), num_traits::ToPrimitive::to_i64(w)) {
                                (Some(x), Some(y)) => x == y,
                                (None, None) => v.to_bigint() == *w,
                                _ => false,
                            }
                    })
            })
    }

    fn sparse(matrix: &IntMatrix) -> Vec<SparseRow<R>> {
        matrix
            .row_iter()
            .map(|row| row.iter().map(|(c, v)| (*c, R::from_bigint(v))).collect())
            .collect()
    }

    fn fraction_free(a: &[SparseRow<R>], cols: usize, method: Simplification) -> Ldu<R> {
        let dense = a
            .iter()
            .map(|row| {
                let mut d = vec![R::zero(); cols];
                for (c, v) in row {
                    d[*c] = v.clone();
                }
                d
            })
            .collect();
        Ldu::factor(dense, cols, method).expect("the rows of an IntMatrix have its width")
    }

    /// The fraction-free factoring, when the matrix is factored that way (made now if it
    /// waited, see [`ExactFactorization::new`]).
    pub fn ldu(&self) -> Option<&Ldu<R>> {
        match self.factoring.as_ref() {
            Factoring::FractionFree(ldu) => Some(ldu),
            Factoring::FullRowRank { method, ldu, .. } => {
                Some(ldu.get_or_init(|| Self::fraction_free(&self.a, self.cols, *method)))
            }
            Factoring::Certified(_) => None,
        }
    }

    /// True when the rank and the redundancies come from a certified row basis rather than the
    /// fraction-free LDU.
    pub fn is_certified(&self) -> bool {
        matches!(self.factoring.as_ref(), Factoring::Certified(_))
    }

    /// `Â Âᵀ` of the independent rows prepared for lifting, when a certified basis made it.
    pub(crate) fn gram_solver(&self) -> Option<&LiftingSolver> {
        match self.factoring.as_ref() {
            Factoring::FractionFree(_) => None,
            Factoring::FullRowRank { gram, .. } => Some(gram),
            Factoring::Certified(basis) => basis.normal(),
        }
    }

    pub(crate) fn sparse_rows(&self) -> &[SparseRow<R>] {
        &self.a
    }

    /// The rows of `A`, shared.
    pub(crate) fn shared_sparse_rows(&self) -> Arc<Vec<SparseRow<R>>> {
        Arc::clone(&self.a)
    }

    /// Per redundant row: the primitive integer `y` with `yᵀA = 0` supported on that row and
    /// the independent rows it depends on, as `(original row, y_row)` sorted by row.
    pub(crate) fn dependencies(&self) -> Vec<Vec<(usize, R)>> {
        match self.factoring.as_ref() {
            Factoring::FractionFree(ldu) => (ldu.rank()..ldu.rows())
                .map(|t| dependency(ldu, t))
                .collect(),
            Factoring::FullRowRank { .. } => Vec::new(),
            Factoring::Certified(basis) => basis
                .dependencies()
                .iter()
                .map(|(_, y)| y.iter().map(|(i, v)| (*i, R::from_bigint(v))).collect())
                .collect(),
        }
    }

    /// The certificate with the smallest support among `failing` dependencies (`yᵀA = 0`,
    /// `yᵀb ≠ 0`).
    fn certificate(
        failing: impl IntoIterator<Item = Vec<(usize, R)>>,
        rhs: &[Rational],
    ) -> Inconsistency<Rational> {
        let y = failing.into_iter().min_by_key(Vec::len).unwrap_or_default();
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

    /// Weak solvability of `A x = rhs` (thesis 8.2.1, (8.10); `ECLES.CheckWeakSolvability`,
    /// algorithm 5), with the certificate of the smallest failing circuit. Fraction-free: the
    /// forward substitution, returned for the back substitution.
    fn forward_checked(&self, rhs: &[Rational]) -> Result<Option<QVec<R>>, SolveError<Rational>> {
        check_len("right-hand side", rhs.len(), self.a.len())?;
        match self.factoring.as_ref() {
            // Independent rows: every right-hand side is consistent.
            Factoring::FullRowRank { .. } => Ok(None),
            Factoring::FractionFree(ldu) => {
                let mut b = permuted(ldu, rhs);
                ldu.forward(&mut b);
                let failing: Vec<usize> = (ldu.rank()..ldu.rows())
                    .filter(|&t| !b.num[t].is_zero())
                    .collect();
                if failing.is_empty() {
                    Ok(Some(b))
                } else {
                    Err(SolveError::Inconsistent(Self::certificate(
                        failing.into_iter().map(|t| dependency(ldu, t)),
                        rhs,
                    )))
                }
            }
            Factoring::Certified(basis) => {
                let failing: Vec<Vec<(usize, R)>> = basis
                    .dependencies()
                    .iter()
                    .filter(|(_, y)| {
                        !y.iter()
                            .fold(Rational::zero(), |acc, (i, v)| {
                                acc + &rhs[*i] * Rational::from_integer(v.clone())
                            })
                            .is_zero()
                    })
                    .map(|(_, y)| y.iter().map(|(i, v)| (*i, R::from_bigint(v))).collect())
                    .collect();
                if failing.is_empty() {
                    Ok(None)
                } else {
                    Err(SolveError::Inconsistent(Self::certificate(failing, rhs)))
                }
            }
        }
    }

    /// A solution of `A x = rhs` after its consistency check. Fraction-free: algorithm 14
    /// (`LinSys.Solve`, thesis 8.1) after its forward substitution, `Y = D z`, `X̂ = Û⁻¹ Y`,
    /// `X̃ = 0`, `P = Π_C⁻¹ X` (8.5)–(8.9). Certified: the minimum-norm solution `Âᵀ λ` with
    /// `Â Âᵀ λ = b̂`.
    fn solution(&self, forwarded: Option<QVec<R>>, rhs: &[Rational]) -> Vec<Rational> {
        match self.factoring.as_ref() {
            Factoring::FractionFree(_) | Factoring::FullRowRank { .. } => {
                let ldu = self.ldu().expect("factored fraction-free");
                let forwarded = forwarded.unwrap_or_else(|| {
                    let mut b = permuted(ldu, rhs);
                    ldu.forward(&mut b);
                    b
                });
                basic_solution(ldu, forwarded).to_rationals()
            }
            Factoring::Certified(basis) => {
                let Some(normal) = basis.normal() else {
                    return vec![Rational::zero(); self.cols];
                };
                let picked: Vec<Rational> = basis
                    .independent()
                    .iter()
                    .map(|&i| rhs[i].clone())
                    .collect();
                let b_hat = QVec::<BigInt>::from_rationals(&picked);
                let (lambda, den) = normal.solve(&b_hat.num);
                let den = den * &b_hat.den;
                basis
                    .combine_rows(&self.a, &lambda, self.cols)
                    .into_iter()
                    .map(|x| Rational::new(x, den.clone()))
                    .collect()
            }
        }
    }

    /// The null space as primitive integer vectors: one per free column (fraction-free: in
    /// `Π_C` order; certified: the projections of the unit vectors of the non-pivot columns, or,
    /// beyond 16 of them on a matrix of at most 2^16 entries, the fraction-free LDU's).
    pub fn null_space_integers(&self) -> Vec<Vec<BigInt>> {
        match self.factoring.as_ref() {
            Factoring::FractionFree(_) | Factoring::FullRowRank { .. } => {
                null_space_fraction_free(self.ldu().expect("factored fraction-free"))
            }
            Factoring::Certified(basis) => {
                let free = basis.free_columns(self.cols);
                let Some(normal) = basis.normal() else {
                    return free
                        .into_iter()
                        .map(|f| {
                            let mut e = vec![<BigInt as Zero>::zero(); self.cols];
                            e[f] = BigInt::from(1);
                            e
                        })
                        .collect();
                };
                if free.len() > LIFTED_NULL_VECTORS_UP_TO
                    && self.a.len().saturating_mul(self.cols) <= FRACTION_FREE_NULL_SPACE_ENTRIES
                {
                    return null_space_fraction_free(&Self::fraction_free(
                        &self.a,
                        self.cols,
                        Simplification::default(),
                    ));
                }
                // One lifted solve per free column, independent: in parallel when they are
                // real work (the propagation analysis asks for the null space of every edit).
                let per_task = crate::dixon::entries_per_task(free.len(), self.cols);
                free.into_par_iter()
                    .with_min_len(per_task)
                    .map(|f| {
                        let column: Vec<BigInt> = basis
                            .independent()
                            .iter()
                            .map(|&i| {
                                self.a[i]
                                    .iter()
                                    .find(|(c, _)| *c == f)
                                    .map_or_else(<BigInt as Zero>::zero, |(_, v)| v.to_bigint())
                            })
                            .collect();
                        let (lambda, den) = normal.solve(&column);
                        let mut v: Vec<BigInt> = basis
                            .combine_rows(&self.a, &lambda, self.cols)
                            .into_iter()
                            .map(|x| -x)
                            .collect();
                        v[f] += den;
                        QVec::from_integers(v).primitive_integers()
                    })
                    .collect()
            }
        }
    }

    fn column_of(matrix: &IntMatrix, k: usize) -> Vec<Rational> {
        (0..matrix.rows())
            .map(|i| Rational::from_integer(matrix.get(i, k)))
            .collect()
    }
}

/// The right-hand side in `Π_R` order over a common denominator.
fn permuted<R: Ring>(ldu: &Ldu<R>, rhs: &[Rational]) -> QVec<R> {
    let permuted: Vec<Rational> = ldu.row_perm().iter().map(|&i| rhs[i].clone()).collect();
    QVec::from_rationals(&permuted)
}

/// The primitive integer `y` with `yᵀA = 0` supported on redundant position `t` of the
/// fraction-free factoring and the independent rows it depends on, as `(original row, y_row)`
/// sorted by row.
fn dependency<R: Ring>(ldu: &Ldu<R>, t: usize) -> Vec<(usize, R)> {
    let w = ldu.redundancy_weights(t);
    let perm = ldu.row_perm();
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

/// Back-substitutes a forwarded right-hand side: `x̂ = Û⁻¹ D z`, `x̃ = 0`, in original column
/// order.
fn basic_solution<R: Ring>(ldu: &Ldu<R>, forwarded: QVec<R>) -> QVec<R> {
    let r = ldu.rank();
    let mut y = QVec {
        num: forwarded
            .num
            .into_iter()
            .take(r)
            .zip(ldu.d())
            .map(|(z, d)| z.mul(d))
            .collect(),
        den: forwarded.den,
    };
    ldu.backward(&mut y);
    let mut x = vec![R::zero(); ldu.cols()];
    for (k, v) in y.num.into_iter().enumerate() {
        x[ldu.col_perm()[k]] = v;
    }
    let mut out = QVec { num: x, den: y.den };
    out.normalize();
    out
}

/// The null space of a fraction-free factoring: one primitive integer vector per free column,
/// in `Π_C` order.
fn null_space_fraction_free<R: Ring>(ldu: &Ldu<R>) -> Vec<Vec<BigInt>> {
    let r = ldu.rank();
    let n = ldu.cols();
    (r..n)
        .into_par_iter()
        .with_min_len(crate::dixon::entries_per_task(n - r, n))
        .map(|f| {
            let mut y = QVec::from_integers((0..r).map(|k| ldu.u_row(k)[f].neg()).collect());
            ldu.backward(&mut y);
            let mut x = vec![R::zero(); n];
            let QVec { num, den } = y;
            for (k, v) in num.into_iter().enumerate() {
                x[ldu.col_perm()[k]] = v;
            }
            x[ldu.col_perm()[f]] = den;
            // Divided by its content: primitive (the free entry, the denominator, is positive).
            let g = gcd_all(&x);
            x.iter()
                .map(|v| {
                    if v.is_zero() || g.is_one() {
                        v.to_bigint()
                    } else {
                        v.div_exact(&g).to_bigint()
                    }
                })
                .collect()
        })
        .collect()
}

impl<R: Ring> IntegerNullSpace for ExactFactorization<R> {
    fn integer_null_space(&self) -> Vec<Vec<BigInt>> {
        self.null_space_integers()
    }
}

impl<R: Ring> Factorization for ExactFactorization<R> {
    type Scalar = Rational;
    type LeastSquares = ExactLeastSquares<R>;

    fn rows(&self) -> usize {
        self.a.len()
    }

    fn cols(&self) -> usize {
        self.cols
    }

    fn rank(&self) -> usize {
        match self.factoring.as_ref() {
            Factoring::FractionFree(ldu) => ldu.rank(),
            Factoring::FullRowRank { .. } => self.a.len(),
            Factoring::Certified(basis) => basis.rank(),
        }
    }

    fn independent_rows(&self) -> Vec<usize> {
        match self.factoring.as_ref() {
            Factoring::FractionFree(ldu) => ldu.row_perm()[..ldu.rank()].to_vec(),
            Factoring::FullRowRank { .. } => (0..self.a.len()).collect(),
            Factoring::Certified(basis) => basis.independent().to_vec(),
        }
    }

    fn redundancies(&self) -> Vec<Redundancy<Rational>> {
        match self.factoring.as_ref() {
            Factoring::FractionFree(ldu) => {
                let perm = ldu.row_perm();
                (ldu.rank()..ldu.rows())
                    .map(|t| {
                        let w = ldu.redundancy_weights(t);
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
            Factoring::FullRowRank { .. } => Vec::new(),
            // y_t a_t + Σ y_i a_i = 0, so a_t = Σ (−y_i / y_t) a_i.
            Factoring::Certified(basis) => basis
                .dependencies()
                .iter()
                .map(|(t, y)| {
                    let at_t = y
                        .iter()
                        .find(|(i, _)| i == t)
                        .map_or_else(<BigInt as Zero>::zero, |(_, v)| v.clone());
                    Redundancy {
                        row: *t,
                        combination: y
                            .iter()
                            .filter(|(i, _)| i != t)
                            .map(|(i, v)| (*i, Rational::new(-v.clone(), at_t.clone())))
                            .collect(),
                    }
                })
                .collect(),
        }
    }

    /// Algorithm 14 (`LinSys.Solve`, thesis 8.1): [`Ldu::forward`], the weak check (8.10), then
    /// the basic solution (`X̃ = 0`); from a certified basis the minimum-norm solution.
    fn solve(&self, rhs: &[Rational]) -> Result<Vec<Rational>, SolveError<Rational>> {
        let forwarded = self.forward_checked(rhs)?;
        Ok(self.solution(forwarded, rhs))
    }

    /// Independent rows (fraction-free with the rank equal to the rows, or proved by the Gram
    /// matrix) make every right-hand side consistent: nothing is substituted.
    fn check_consistent(&self, rhs: &[Rational]) -> Result<(), SolveError<Rational>> {
        if let Factoring::FractionFree(ldu) = self.factoring.as_ref() {
            if ldu.rank() == ldu.rows() {
                check_len("right-hand side", rhs.len(), self.a.len())?;
                return Ok(());
            }
        }
        self.forward_checked(rhs).map(|_| ())
    }

    /// Strong solvability (thesis 8.2.2, (8.15)–(8.16); `ECLES.CheckStrongSolvability`,
    /// algorithm 3): every column of `K`, then every constant, passes the weak check.
    fn check_strongly_consistent(
        &self,
        family: &RhsFamily,
    ) -> Result<Result<(), StrongFailure<Rational>>, BackendError> {
        validate_family(family, self.a.len())?;
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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// On random small matrices of every rank: the Gram matrix proves the rows independent
        /// exactly when the fraction-free LDU finds full row rank, and every answer is then
        /// the LDU's (the same factors, made when asked): rank, independent rows, no
        /// redundancies, consistency of any right-hand side, a solution that satisfies the
        /// equations exactly, the null space of the same factors. Factored for solves
        /// ([`ExactFactorization::fraction_free_now`]), every rank gives that LDU at once.
        #[test]
        fn independent_rows_are_proved_by_the_gram_matrix(
            cols in 1usize..7,
            m in 1usize..6,
            entries in proptest::collection::vec(-3i64..4, 36),
            zero_rows in proptest::collection::vec(any::<bool>(), 6),
            rhs in proptest::collection::vec(-9i64..10, 6),
        ) {
            let rows: Vec<Vec<i64>> = (0..m)
                .map(|i| {
                    (0..cols)
                        .map(|j| if zero_rows[i] && i % 2 == 1 { 0 } else { entries[i * 6 + j] })
                        .collect()
                })
                .collect();
            let matrix = IntMatrix::from_dense(cols, &rows).expect("rectangular");
            for method in [Simplification::Gcd, Simplification::Turner, Simplification::None] {
                let f = ExactFactorization::<Int>::new(&matrix, method);
                let dense: Vec<Vec<Int>> = rows
                    .iter()
                    .map(|row| row.iter().map(|v| Int::from_i64(*v)).collect())
                    .collect();
                let ldu = Ldu::factor(dense, cols, method).expect("rectangular");
                // Factored for solves: the same LDU at once, whatever the rank.
                let now = ExactFactorization::<Int>::fraction_free_now(&matrix, method);
                prop_assert!(matches!(now.factoring.as_ref(), Factoring::FractionFree(_)));
                prop_assert_eq!(now.ldu(), Some(&ldu));
                prop_assert_eq!(now.rank(), f.rank());
                prop_assert_eq!(now.independent_rows(), ldu.row_perm()[..ldu.rank()].to_vec());
                prop_assert_eq!(now.null_space_integers(), null_space_fraction_free(&ldu));
                // The integer null space is the rational one's vectors: primitive, in the kernel.
                let integers = now.integer_null_space();
                prop_assert_eq!(integers.len(), cols - ldu.rank());
                for (v, q) in integers.iter().zip(now.null_space()) {
                    let as_rationals: Vec<Rational> =
                        v.iter().cloned().map(Rational::from_integer).collect();
                    prop_assert_eq!(&as_rationals, &q);
                    let content = v
                        .iter()
                        .fold(BigInt::from(0), |g, x| num_integer::Integer::gcd(&g, x));
                    prop_assert_eq!(content, BigInt::from(1));
                    for row in &rows {
                        let dot: BigInt = row.iter().zip(v).map(|(a, x)| x * BigInt::from(*a)).sum();
                        prop_assert_eq!(dot, BigInt::from(0));
                    }
                }
                // Consistency without substitution when the rows are independent: the same
                // verdict as the solve's own check, at every rank.
                let any_rhs: Vec<Rational> =
                    rhs[..m].iter().map(|v| Rational::from_integer(BigInt::from(*v))).collect();
                prop_assert_eq!(
                    now.check_consistent(&any_rhs).is_ok(),
                    now.forward_checked(&any_rhs).is_ok()
                );
                prop_assert_eq!(now.check_consistent(&any_rhs).is_ok(), now.solve(&any_rhs).is_ok());
                let proved = matches!(f.factoring.as_ref(), Factoring::FullRowRank { .. });
                prop_assert_eq!(proved, ldu.rank() == m);
                prop_assert_eq!(f.rank(), ldu.rank());
                let mut independent = f.independent_rows();
                independent.sort_unstable();
                let mut expected = ldu.row_perm()[..ldu.rank()].to_vec();
                expected.sort_unstable();
                prop_assert_eq!(independent, expected);
                if !proved {
                    continue;
                }
                prop_assert!(f.redundancies().is_empty());
                prop_assert!(f.gram_solver().is_some());
                let b: Vec<Rational> =
                    rhs[..m].iter().map(|v| Rational::from_integer(BigInt::from(*v))).collect();
                let x = f.solve(&b).expect("independent rows: consistent");
                for (row, bi) in rows.iter().zip(&b) {
                    let lhs: Rational = row
                        .iter()
                        .zip(&x)
                        .map(|(a, xj)| xj * Rational::from_integer(BigInt::from(*a)))
                        .sum();
                    prop_assert_eq!(&lhs, bi);
                }
                // The LDU made on demand is the fraction-free one, and solves as it does.
                prop_assert_eq!(f.ldu(), Some(&ldu));
                prop_assert_eq!(now.solve(&b).expect("consistent"), x);
                prop_assert_eq!(f.null_space_integers(), null_space_fraction_free(&ldu));
                prop_assert_eq!(f.null_space_integers().len(), cols - m);
            }
        }

        /// A certified factoring's null space, by lifted solves (few free columns) or by the
        /// fraction-free LDU (more than [`LIFTED_NULL_VECTORS_UP_TO`]): vectors of the kernel,
        /// as many as the columns less the rank, and independent (their own rank is that many).
        #[test]
        fn certified_null_spaces_are_bases_of_the_kernel(
            m in 1usize..7,
            cols in prop_oneof![Just(12usize), Just(30usize)],
            entries in proptest::collection::vec(-2i64..3, 6 * 30),
            copies in proptest::collection::vec(any::<bool>(), 6),
        ) {
            // Some rows repeat the one before: a rank below the number of rows.
            let mut rows: Vec<Vec<i64>> = Vec::new();
            for i in 0..m {
                let row = if i > 0 && copies[i] {
                    rows[i - 1].clone()
                } else {
                    entries[i * 30..i * 30 + cols].to_vec()
                };
                rows.push(row);
            }
            let matrix = IntMatrix::from_dense(cols, &rows).expect("rectangular");
            let f = ExactFactorization::<Int>::certified(&matrix, Simplification::Gcd);
            let kernel = f.null_space_integers();
            prop_assert_eq!(kernel.len(), cols - f.rank());
            for v in &kernel {
                for row in &rows {
                    let dot: BigInt = row.iter().zip(v).map(|(a, x)| x * BigInt::from(*a)).sum();
                    prop_assert_eq!(dot, BigInt::from(0));
                }
            }
            if !kernel.is_empty() {
                let as_rows: Vec<Vec<i64>> = kernel
                    .iter()
                    .map(|v| v.iter().map(|x| x.to_i64().expect("small")).collect())
                    .collect();
                let spanned = IntMatrix::from_dense(cols, &as_rows).expect("rectangular");
                let rank = ExactFactorization::<Int>::new(&spanned, Simplification::Gcd).rank();
                prop_assert_eq!(rank, kernel.len());
            }
        }
    }
}
