//! Weighted least squares with exact linear constraints (thesis, chapter 9, algorithm 15),
//! prepared once for an affine family of right-hand sides.
//!
//! Minimise `Σ w_s (x_s − h_s)²` subject to `A x = b` with `b = c_j − K α`. Only the `r`
//! independent rows `Â` of `A` are kept (`b̂` the matching entries of `b`). With `W⁻¹ = V / δ`
//! (`V` a positive integer diagonal) the Lagrange conditions (9.5)–(9.8) give
//!
//! ```text
//! G = Â V Âᵀ,   λ = G⁻¹ (Â h − b̂),   x = h − V Âᵀ λ
//! ```
//!
//! (the scale `δ` and the factor 2 of `M = 2W` cancel). Everything except `h` and `α` is fixed,
//! so preparing computes `H = V Âᵀ G⁻¹` exactly, as an integer matrix over its reduced common
//! denominator (much smaller than that of `G⁻¹`: the solution's denominators are what they are,
//! not `det G`), the rows of `K` and `c_j` at the independent positions, and, for the
//! weak-consistency test, one primitive integer vector `y` with `yᵀA = 0` per redundant row
//! together with `yᵀc_j` and `yᵀK`. An update computes the small residual
//! `ρ = Â h − ĉ_j + K̂ α` and `x = h − H ρ`: one pass of word-sized multiply-accumulate per entry
//! of `H`, then one reduction per result.

use crate::factorization::{ExactFactorization, SparseRow};
use crate::ldu::{Ldu, Simplification};
use crate::limbs::{Accumulator, Limbs};
use crate::qvec::QVec;
use crate::ring::{lcm, Int, Ring};
use api::backend::{check_len, validate_family, validate_weights};
use api::{
    BackendError, Factorization, Inconsistency, PreparedLeastSquares, Rational, RhsFamily,
    SolveError,
};
use num_bigint::BigInt;
use num_integer::Integer as _;
use num_traits::Zero;

/// One left-null-space vector `y` (`yᵀA = 0`) with its products against the family.
#[derive(Debug, Clone, PartialEq, Eq)]
struct ConsistencyCheck<R: Ring> {
    /// `y` on its support (original rows, increasing).
    y: Vec<(usize, R)>,
    /// `yᵀK` on the parameters where it is nonzero.
    y_k: Vec<(usize, R)>,
    /// `yᵀc_j` per column, as `(numerator, positive denominator)`.
    y_c: Vec<(R, R)>,
}

/// Least squares prepared by [`ExactFactorization::prepare_least_squares`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExactLeastSquares<R: Ring = Int> {
    n: usize,
    parameters: usize,
    a_hat: Vec<SparseRow<R>>,
    k_hat: Vec<SparseRow<R>>,
    c_hat: Vec<QVec<R>>,
    /// `H` (`n × r`) times `h_den`.
    h_rows: Vec<Vec<Limbs>>,
    /// Positive common denominator of `H`.
    h_den: BigInt,
    checks: Vec<ConsistencyCheck<R>>,
}

fn dot_sparse<R: Ring>(row: &[(usize, R)], x: &[R]) -> R {
    let mut acc = R::zero();
    for (c, v) in row {
        acc.add_mul(v, &x[*c]);
    }
    acc
}

impl<R: Ring> ExactLeastSquares<R> {
    /// Algorithm 15 (`LSQ.Solve`, thesis 9.1) up to the data of one update: `Â`, `H = V Âᵀ G⁻¹`
    /// for `G = Â V Âᵀ` (9.6)–(9.8), the family at the independent rows, and one left-null-space
    /// vector per redundant row for the weak check.
    pub(crate) fn prepare(
        f: &ExactFactorization<R>,
        family: &RhsFamily,
        weights: &[Rational],
    ) -> Result<Self, BackendError> {
        let m = f.rows();
        let n = f.cols();
        validate_family(family, m)?;
        validate_weights(weights, n)?;
        let ldu = f.ldu();
        let r = ldu.rank();
        let independent = &ldu.row_perm()[..r];

        // V = δ W⁻¹ with δ the lcm of the weight numerators.
        let mut delta = BigInt::from(1);
        for w in weights {
            delta = num_integer::Integer::lcm(&delta, w.numer());
        }
        let v: Vec<R> = weights
            .iter()
            .map(|w| R::from_bigint(&(w.denom() * (&delta / w.numer()))))
            .collect();

        let a_hat: Vec<SparseRow<R>> = independent
            .iter()
            .map(|&i| f.sparse_rows()[i].clone())
            .collect();
        let k_rows: Vec<SparseRow<R>> = family
            .coefficients
            .row_iter()
            .map(|row| row.iter().map(|(c, v)| (*c, R::from_bigint(v))).collect())
            .collect();
        let k_hat = independent.iter().map(|&i| k_rows[i].clone()).collect();
        let c_hat = family
            .constant
            .iter()
            .map(|c| {
                let picked: Vec<Rational> = independent.iter().map(|&i| c[i].clone()).collect();
                QVec::from_rationals(&picked)
            })
            .collect();

        let (g_inv, g_den) = inverse_of_normal_matrix(&a_hat, &v, n);
        let (h_rows, h_den) = projection_matrix(&a_hat, &v, &g_inv, &g_den, n);

        let constants: Vec<QVec<R>> = family
            .constant
            .iter()
            .map(|c| QVec::from_rationals(c))
            .collect();
        let checks = (r..m)
            .map(|t| {
                let y = f.dependency(t);
                let mut y_k_dense = vec![R::zero(); family.coefficients.cols()];
                for (i, yi) in &y {
                    for (c, kv) in &k_rows[*i] {
                        y_k_dense[*c] = y_k_dense[*c].add(&yi.mul(kv));
                    }
                }
                let y_k = y_k_dense
                    .into_iter()
                    .enumerate()
                    .filter(|(_, v)| !v.is_zero())
                    .collect();
                let y_c = constants
                    .iter()
                    .map(|c| {
                        let numer = y
                            .iter()
                            .fold(R::zero(), |acc, (i, yi)| acc.add(&yi.mul(&c.num[*i])));
                        let g = numer.gcd(&c.den);
                        if g.is_zero() || g.is_one() {
                            (numer, c.den.clone())
                        } else {
                            (numer.div_exact(&g), c.den.div_exact(&g))
                        }
                    })
                    .collect();
                ConsistencyCheck { y, y_k, y_c }
            })
            .collect();

        Ok(ExactLeastSquares {
            n,
            parameters: family.coefficients.cols(),
            a_hat,
            k_hat,
            c_hat,
            h_rows,
            h_den,
            checks,
        })
    }

    fn validate(&self, column: usize, alpha: &[Rational]) -> Result<(), BackendError> {
        if column >= self.c_hat.len() {
            return Err(BackendError::NoSuchColumn {
                column,
                columns: self.c_hat.len(),
            });
        }
        check_len("parameter vector α", alpha.len(), self.parameters)
    }

    /// Weak consistency of `A x = c_j − K α` through the prepared left-null-space vectors.
    fn check_prepared(&self, column: usize, alpha: &QVec<R>) -> Result<(), SolveError<Rational>> {
        let mut failing: Option<&ConsistencyCheck<R>> = None;
        for check in &self.checks {
            let (yc_num, yc_den) = &check.y_c[column];
            let yk_alpha = dot_sparse(&check.y_k, &alpha.num);
            // yᵀb = yc_num / yc_den − yk_alpha / alpha.den
            if yc_num.mul(&alpha.den) != yk_alpha.mul(yc_den)
                && failing.is_none_or(|f| check.y.len() < f.y.len())
            {
                failing = Some(check);
            }
        }
        let Some(check) = failing else {
            return Ok(());
        };
        let (yc_num, yc_den) = &check.y_c[column];
        let yk_alpha = dot_sparse(&check.y_k, &alpha.num);
        let discrepancy = Rational::new(yc_num.to_bigint(), yc_den.to_bigint())
            - Rational::new(yk_alpha.to_bigint(), alpha.den.to_bigint());
        Err(SolveError::Inconsistent(Inconsistency {
            rows: check.y.iter().map(|(i, _)| *i).collect(),
            certificate: check
                .y
                .iter()
                .map(|(_, v)| Rational::from_integer(v.to_bigint()))
                .collect(),
            discrepancy,
        }))
    }
}

/// `G⁻¹` for `G = Â V Âᵀ` as `(integer matrix, positive denominator)`.
fn inverse_of_normal_matrix<R: Ring>(
    a_hat: &[SparseRow<R>],
    v: &[R],
    n: usize,
) -> (Vec<Vec<R>>, R) {
    let r = a_hat.len();
    // Accumulate G column by column of Â: G_kl += A_ks V_s A_ls.
    let mut by_column: Vec<Vec<(usize, R)>> = vec![Vec::new(); n];
    for (k, row) in a_hat.iter().enumerate() {
        for (s, val) in row {
            by_column[*s].push((k, val.clone()));
        }
    }
    let mut g = vec![vec![R::zero(); r]; r];
    for (s, entries) in by_column.iter().enumerate() {
        for (k, aks) in entries {
            let scaled = aks.mul(&v[s]);
            for (l, als) in entries {
                g[*k][*l] = g[*k][*l].add(&scaled.mul(als));
            }
        }
    }
    let ldu = Ldu::factor(g, r, Simplification::Gcd).expect("G is square by construction");
    debug_assert_eq!(ldu.rank(), r, "Â V Âᵀ is positive definite");
    let columns: Vec<QVec<R>> = (0..r)
        .map(|k| {
            let mut e = QVec::zeros(r);
            let pos = ldu
                .row_perm()
                .iter()
                .position(|&i| i == k)
                .expect("row permutation is a bijection");
            e.num[pos] = R::one();
            ldu.forward(&mut e);
            let mut y = QVec {
                num: e.num.iter().zip(ldu.d()).map(|(z, d)| z.mul(d)).collect(),
                den: e.den,
            };
            ldu.backward(&mut y);
            let mut x = vec![R::zero(); r];
            for (p, val) in y.num.into_iter().enumerate() {
                x[ldu.col_perm()[p]] = val;
            }
            QVec { num: x, den: y.den }
        })
        .collect();
    let den = QVec::common_denominator(columns.iter());
    let mut inv = vec![vec![R::zero(); r]; r];
    for (k, col) in columns.iter().enumerate() {
        let f = den.div_exact(&col.den);
        for (i, val) in col.num.iter().enumerate() {
            inv[i][k] = val.mul(&f);
        }
    }
    (inv, den)
}

/// `H = V Âᵀ G⁻¹` as `(rows of H · h_den, h_den)` with `h_den` the reduced common denominator.
fn projection_matrix<R: Ring>(
    a_hat: &[SparseRow<R>],
    v: &[R],
    g_inv: &[Vec<R>],
    g_den: &R,
    n: usize,
) -> (Vec<Vec<Limbs>>, BigInt) {
    let r = a_hat.len();
    let mut by_column: Vec<Vec<(usize, BigInt)>> = vec![Vec::new(); n];
    for (l, row) in a_hat.iter().enumerate() {
        for (s, val) in row {
            by_column[*s].push((l, val.to_bigint()));
        }
    }
    let g_inv: Vec<Vec<BigInt>> = g_inv
        .iter()
        .map(|row| row.iter().map(Ring::to_bigint).collect())
        .collect();
    let rows: Vec<Vec<BigInt>> = by_column
        .iter()
        .enumerate()
        .map(|(s, column)| {
            let vs = v[s].to_bigint();
            (0..r)
                .map(|k| {
                    let mut sum = BigInt::from(0);
                    for (l, als) in column {
                        sum += als * &g_inv[*l][k];
                    }
                    sum * &vs
                })
                .collect()
        })
        .collect();
    // The content gcd(g_den, all entries) without one big GCD per entry: the GCD of g_den with
    // two fixed pseudo-random combinations of the entries is a multiple of the content (and
    // almost always equal to it); every entry is then divided by it, and an entry that leaves a
    // remainder shrinks the candidate by one exact GCD.
    let g_den = g_den.to_bigint();
    let mut combos = [BigInt::from(0), BigInt::from(0)];
    for (i, entry) in rows.iter().flatten().enumerate() {
        combos[0] += entry * BigInt::from(1 + (i as u64 * 7919) % 997);
        combos[1] += entry * BigInt::from(1 + (i as u64 * 104_729) % 991);
    }
    let mut content =
        crate::gcd::gcd_bigint(&g_den, &crate::gcd::gcd_bigint(&combos[0], &combos[1]));
    let rows = 'divide: loop {
        let mut divided = Vec::with_capacity(rows.len());
        for row in &rows {
            let mut out = Vec::with_capacity(row.len());
            for entry in row {
                let (q, rem) = entry.div_rem(&content);
                if !Zero::is_zero(&rem) {
                    content = crate::gcd::gcd_bigint(&content, entry);
                    continue 'divide;
                }
                out.push(Limbs::from_bigint(&q));
            }
            divided.push(out);
        }
        break divided;
    };
    let den = g_den / &content;
    (rows, den)
}

impl<R: Ring> PreparedLeastSquares for ExactLeastSquares<R> {
    type Scalar = Rational;

    fn check(&self, column: usize, alpha: &[Rational]) -> Result<(), SolveError<Rational>> {
        self.validate(column, alpha)?;
        self.check_prepared(column, &QVec::from_rationals(alpha))
    }

    fn solve(
        &self,
        column: usize,
        alpha: &[Rational],
        hints: &[Rational],
    ) -> Result<Vec<Rational>, SolveError<Rational>> {
        Ok(match self.numerators(column, alpha, hints)? {
            None => hints.to_vec(),
            Some((numerators, den)) => numerators
                .into_iter()
                .map(|n| crate::gcd::reduced_ratio(n, den.clone()))
                .collect(),
        })
    }

    /// The exact solution rounded to `f64` without reducing it: the same verdict and the same
    /// values (to rounding) as [`PreparedLeastSquares::solve`], for drawing every frame of a
    /// drag, skipping the GCDs that dominate an exact update.
    fn solve_approx(
        &self,
        column: usize,
        alpha: &[Rational],
        hints: &[Rational],
    ) -> Result<Vec<f64>, SolveError<Rational>> {
        Ok(match self.numerators(column, alpha, hints)? {
            None => hints.iter().map(api::Value::to_f64).collect(),
            Some((numerators, den)) => numerators
                .into_iter()
                .map(|n| api::exact::rational_to_f64(&Rational::new_raw(n, den.clone())))
                .collect(),
        })
    }
}

impl<R: Ring> ExactLeastSquares<R> {
    /// Algorithm 15 (`LSQ.Solve`) steps 7–8 for one `α` and hints: `ρ = Â h − b̂`,
    /// `x = h − H ρ` (`Λ = G⁻¹ ρ` folded into `H`). Checks, then computes the solution as
    /// numerators over one positive denominator
    /// (`None` when there is no constraint and the hints are the answer).
    #[allow(clippy::type_complexity)]
    fn numerators(
        &self,
        column: usize,
        alpha: &[Rational],
        hints: &[Rational],
    ) -> Result<Option<(Vec<BigInt>, BigInt)>, SolveError<Rational>> {
        self.validate(column, alpha)?;
        check_len("hints", hints.len(), self.n)?;
        let alpha = QVec::<R>::from_rationals(alpha);
        self.check_prepared(column, &alpha)?;
        let h = QVec::<R>::from_rationals(hints);
        let r = self.a_hat.len();
        if r == 0 {
            return Ok(None);
        }
        let c = &self.c_hat[column];
        let common = lcm(&lcm(&h.den, &alpha.den), &c.den);
        let fh = common.div_exact(&h.den);
        let fa = common.div_exact(&alpha.den);
        let fc = common.div_exact(&c.den);
        // ρ = Â h − ĉ + K̂ α, over `common`.
        let rho: Vec<Limbs> = (0..r)
            .map(|k| {
                let mut s = dot_sparse(&self.a_hat[k], &h.num).mul(&fh);
                if !c.num[k].is_zero() {
                    s = s.sub(&c.num[k].mul(&fc));
                }
                let ka = dot_sparse(&self.k_hat[k], &alpha.num);
                if !ka.is_zero() {
                    s = s.add(&ka.mul(&fa));
                }
                Limbs::from_ring(&s)
            })
            .collect();
        // x = h − H ρ over h_den · common.
        let h_scale = Limbs::from_bigint(&(&self.h_den * fh.to_bigint()));
        let den = &self.h_den * common.to_bigint();
        let mut acc = Accumulator::default();
        let numerators = self
            .h_rows
            .iter()
            .zip(&h.num)
            .map(|(row, hs)| {
                acc.clear();
                acc.add_product(&Limbs::from_ring(hs), &h_scale);
                for (hk, rk) in row.iter().zip(&rho) {
                    acc.sub_product(hk, rk);
                }
                acc.to_bigint()
            })
            .collect();
        Ok(Some((numerators, den)))
    }

    /// Number of redundant rows whose consistency each update checks.
    pub fn redundant_rows(&self) -> usize {
        self.checks.len()
    }

    /// Bit size of the common denominator of `H = V Âᵀ G⁻¹` (a measure of the update cost).
    pub fn projection_denominator_bits(&self) -> u64 {
        self.h_den.bits()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::IntMatrix;
    use num_traits::{One, Zero};

    #[test]
    fn zero_weight_sum_is_rejected() {
        let a = IntMatrix::from_dense(2, &[vec![1, 1]]).expect("matrix");
        let f = ExactFactorization::<Int>::new(&a, Simplification::Gcd);
        let family = RhsFamily::single(vec![Rational::zero()]);
        let err = f
            .prepare_least_squares(&family, &[Rational::one(), Rational::zero()])
            .expect_err("zero weight");
        assert!(matches!(
            err,
            BackendError::NonPositiveWeight { index: 1, .. }
        ));
    }
}
