//! Weighted least squares with exact linear constraints (thesis, chapter 9, algorithm 15),
//! prepared once for an affine family of right-hand sides.
//!
//! Minimise `Σ w_s (x_s − h_s)²` subject to `A x = b` with `b = c_j − K α`. Only the `r`
//! independent rows `Â` of `A` are kept (`b̂` the matching entries of `b`). With `W⁻¹ = V / δ`
//! (`V` a positive integer diagonal) the Lagrange conditions (9.5)–(9.8) give
//!
//! ```text
//! G = Â V Âᵀ,   G λ = Â h − b̂,   x = h − V Âᵀ λ
//! ```
//!
//! (the scale `δ` and the factor 2 of `M = 2W` cancel). Preparing forms the sparse integer
//! matrix `G` and factors it modulo a word-sized prime; each update solves `G λ = ρ` exactly by
//! p-adic lifting ([`crate::dixon`]), so its cost follows the size of this solution rather than
//! that of `G⁻¹` (on real meshes `G⁻¹` has thousands of digits in each of its `r²` entries, and
//! the thesis' explicit inverse cost minutes and gigabytes). Preparing also keeps the rows of `K`
//! and `c_j` at the independent positions and, for the weak-consistency test, one primitive
//! integer vector `y` with `yᵀA = 0` per redundant row together with `yᵀc_j` and `yᵀK`.

use crate::dixon::LiftingSolver;

mod affine;
use crate::factorization::{ExactFactorization, SparseRow};
use crate::qvec::QVec;
use crate::ring::{Int, Ring};
use crate::snap::Snapper;
use api::backend::{check_len, validate_family, validate_weights};
use api::{
    BackendError, Factorization, Inconsistency, PreparedLeastSquares, Rational, RhsFamily,
    SolveError,
};
use num_bigint::BigInt;
use num_traits::Zero;
use std::sync::{Arc, Mutex, OnceLock};

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
    /// `Â`: shared with the factorization when every row is independent.
    a_hat: Arc<Vec<SparseRow<R>>>,
    k_hat: Vec<SparseRow<R>>,
    c_hat: Vec<QVec<R>>,
    /// `V = δ W⁻¹`, one positive integer per unknown.
    v: Diagonal,
    /// `G = Â V Âᵀ` prepared for lifting (`None` when `r = 0`).
    normal: Option<LiftingSolver>,
    checks: Vec<ConsistencyCheck<R>>,
    /// The responses to the anchors and the last base per column ([`affine`]).
    memo: affine::AffineMemo,
    /// What snapped solves need, prepared at the first one ([`crate::snap`]).
    snapper: SnapMemo,
}

/// The preparation of snapped solves, made at the first one (`None` inside: snapping is not
/// possible for this edit and the optimum is committed). Like the other memos, copies keep the
/// contents and two memos compare equal: it is derived from the rest of the prepared data.
#[derive(Debug, Default, Clone)]
struct SnapMemo(OnceLock<Option<Snapper>>);

impl PartialEq for SnapMemo {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl Eq for SnapMemo {}

/// `V = δ W⁻¹`, the scales of the unknowns: unit weights (an edit that gives none, every
/// generic edit of a run file) keep no vector of big-integer ones, which cost an allocation
/// per unknown on every small edit.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Diagonal {
    /// `V = I` over this many unknowns.
    Unit(usize),
    /// One positive integer per unknown, not all of them 1.
    Scales(Vec<BigInt>),
}

impl Diagonal {
    /// `V` from its entries: [`Diagonal::Unit`] when every one is 1.
    fn of(v: Vec<BigInt>) -> Self {
        if v.iter().all(num_traits::One::is_one) {
            Diagonal::Unit(v.len())
        } else {
            Diagonal::Scales(v)
        }
    }

    fn is_unit(&self) -> bool {
        matches!(self, Diagonal::Unit(_))
    }

    /// `V_s` as an `i64`, when it fits.
    fn word(&self, s: usize) -> Option<i64> {
        match self {
            Diagonal::Unit(_) => Some(1),
            Diagonal::Scales(v) => num_traits::ToPrimitive::to_i64(&v[s]),
        }
    }

    /// Every entry (the ones made now for unit weights: only a snapped solve and a normal
    /// matrix not prepared by the factoring ask).
    fn entries(&self) -> std::borrow::Cow<'_, [BigInt]> {
        match self {
            Diagonal::Unit(n) => std::borrow::Cow::Owned(vec![BigInt::from(1); *n]),
            Diagonal::Scales(v) => std::borrow::Cow::Borrowed(v),
        }
    }
}

/// `V = δ W⁻¹` (`δ` the lcm of the weights' numerators) in machine words, when the numerators,
/// their lcm and every `denominator · δ / numerator` fit in a `u64` (`None` otherwise: the
/// caller takes big integers). Group weights of a substitution are small integers.
fn scales_in_words(weights: &[Rational]) -> Option<Vec<u64>> {
    use num_traits::ToPrimitive;
    let mut delta: u64 = 1;
    for w in weights {
        let n = w.numer().to_u64()?;
        delta = (delta / num_integer::Integer::gcd(&delta, &n)).checked_mul(n)?;
    }
    weights
        .iter()
        .map(|w| {
            let (n, d) = (w.numer().to_u64()?, w.denom().to_u64()?);
            d.checked_mul(delta / n)
        })
        .collect()
}

fn dot_sparse<R: Ring>(row: &[(usize, R)], x: &[R]) -> R {
    let mut acc = R::zero();
    for (c, v) in row {
        acc.add_mul(v, &x[*c]);
    }
    acc
}

impl<R: Ring> ExactLeastSquares<R> {
    /// Algorithm 15 (`LSQ.Solve`, thesis 9.1) up to the data of one update: `Â`, `G = Â V Âᵀ`
    /// (9.6)–(9.8) factored modulo a prime for lifting (sparse `L D Lᵀ`), the family at the independent rows, and one left-null-space
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
        let r = f.rank();
        let independent = &f.independent_rows();

        // V = δ W⁻¹ with δ the lcm of the weight numerators (unit weights: V = I).
        let v = if weights.iter().all(num_traits::One::is_one) {
            Diagonal::Unit(n)
        } else if let Some(v) = scales_in_words(weights) {
            Diagonal::of(v.into_iter().map(BigInt::from).collect())
        } else {
            let mut delta = BigInt::from(1);
            for w in weights {
                delta = num_integer::Integer::lcm(&delta, w.numer());
            }
            Diagonal::of(
                weights
                    .iter()
                    .map(|w| w.denom() * (&delta / w.numer()))
                    .collect(),
            )
        };

        // Every row independent, in order (full row rank, the common case): `Â`, `K̂` and `ĉ`
        // are the rows themselves, shared or moved rather than copied.
        let all_rows =
            independent.len() == m && independent.iter().enumerate().all(|(k, &i)| k == i);
        let a_hat: Arc<Vec<SparseRow<R>>> = if all_rows {
            f.shared_sparse_rows()
        } else {
            Arc::new(
                independent
                    .iter()
                    .map(|&i| f.sparse_rows()[i].clone())
                    .collect(),
            )
        };
        let k_rows: Vec<SparseRow<R>> = family
            .coefficients
            .row_iter()
            .map(|row| row.iter().map(|(c, v)| (*c, R::from_bigint(v))).collect())
            .collect();
        let dependencies = f.dependencies();
        let constants: Vec<QVec<R>> = if dependencies.is_empty() {
            Vec::new()
        } else {
            family
                .constant
                .iter()
                .map(|c| QVec::from_rationals(c))
                .collect()
        };
        let c_hat = family
            .constant
            .iter()
            .map(|c| {
                if all_rows {
                    return QVec::from_rationals(c);
                }
                let picked: Vec<Rational> = independent.iter().map(|&i| c[i].clone()).collect();
                QVec::from_rationals(&picked)
            })
            .collect();

        // With unit weights G = Â Âᵀ, which a certified basis has already prepared.
        let normal = (r > 0).then(|| match f.gram_solver() {
            Some(gram) if v.is_unit() => gram.clone(),
            _ => LiftingSolver::new_symmetric(r, normal_matrix(&a_hat, &v, n))
                .expect("Â V Âᵀ is positive definite for independent rows Â and positive V"),
        });

        let checks = dependencies
            .into_iter()
            .map(|y| {
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
        let k_hat = if all_rows {
            k_rows
        } else {
            independent.iter().map(|&i| k_rows[i].clone()).collect()
        };

        Ok(ExactLeastSquares {
            n,
            parameters: family.coefficients.cols(),
            a_hat,
            k_hat,
            c_hat,
            v,
            normal,
            checks,
            memo: affine::AffineMemo::new(family.constant.len()),
            snapper: SnapMemo::default(),
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

/// `G = Â V Âᵀ` as sparse rows (`r × r`): `G_kl = Σ_s Â_ks V_s Â_ls`. In `i128` (checked,
/// [`crate::gram_words`]) when `r` is at most the order solved fraction-free and the entries of
/// `Â` and `V` fit an `i64` (the small edits' case, without a big-integer product per entry),
/// else in big integers.
fn normal_matrix<R: Ring>(
    a_hat: &[SparseRow<R>],
    v: &Diagonal,
    n: usize,
) -> Vec<Vec<(usize, BigInt)>> {
    if a_hat.len() <= crate::bareiss_small::MAX_ORDER {
        let in_words = crate::gram_words::gram_rows(
            a_hat,
            n,
            |s| v.word(s),
            |x| Some(crate::ring::bigint_from_i128(x)),
        );
        if let Some(g) = in_words {
            return g;
        }
    }
    normal_matrix_in_big_integers(a_hat, &v.entries(), n)
}

/// [`normal_matrix`] with every product a big integer, accumulated column by column of `Â` so
/// only pairs of rows that share an unknown are touched.
fn normal_matrix_in_big_integers<R: Ring>(
    a_hat: &[SparseRow<R>],
    v: &[BigInt],
    n: usize,
) -> Vec<Vec<(usize, BigInt)>> {
    let r = a_hat.len();
    let mut by_column: Vec<Vec<(usize, BigInt)>> = vec![Vec::new(); n];
    for (k, row) in a_hat.iter().enumerate() {
        for (s, val) in row {
            by_column[*s].push((k, val.to_bigint()));
        }
    }
    let mut g: Vec<std::collections::BTreeMap<usize, BigInt>> = vec![Default::default(); r];
    for (s, entries) in by_column.iter().enumerate() {
        for (k, aks) in entries {
            let scaled = aks * &v[s];
            for (l, als) in entries {
                *g[*k].entry(*l).or_default() += &scaled * als;
            }
        }
    }
    g.into_iter()
        .map(|row| row.into_iter().filter(|(_, v)| !Zero::is_zero(v)).collect())
        .collect()
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
            Some((numerators, den)) => crate::reduce::reduce_over(numerators, &den),
        })
    }

    /// The free values of a peeled basis on the grid, the others exact (see [`crate::snap`]);
    /// the optimum when this edit cannot be snapped.
    fn solve_snapped(
        &self,
        column: usize,
        alpha: &[Rational],
        hints: &[Rational],
        grid_bits: u32,
    ) -> Result<api::Snapped<Rational>, SolveError<Rational>> {
        self.validate(column, alpha)?;
        check_len("hints", hints.len(), self.n)?;
        let alpha_q = QVec::<R>::from_rationals(alpha);
        self.check_prepared(column, &alpha_q)?;
        let snapper = self.snapper.0.get_or_init(|| {
            Snapper::new(
                &self.a_hat,
                &self.v.entries(),
                normal_matrix(&self.a_hat, &self.v, self.n),
            )
        });
        if let Some(solved) = snapper.as_ref().and_then(|s| {
            s.solve(
                &self.a_hat,
                &self.v.entries(),
                &self.b_hat(column, &alpha_q),
                hints,
                grid_bits,
            )
        }) {
            return Ok(api::Snapped {
                values: solved.values,
                distance_bound: solved.distance_bound,
                optimum: false,
            });
        }
        Ok(api::Snapped {
            values: self.solve(column, alpha, hints)?,
            distance_bound: 0.0,
            optimum: true,
        })
    }

    /// The exact solution over its common denominator, not reduced.
    fn solve_unreduced(
        &self,
        column: usize,
        alpha: &[Rational],
        hints: &[Rational],
    ) -> Result<Option<Vec<api::Fraction>>, SolveError<Rational>> {
        Ok(Some(match self.numerators(column, alpha, hints)? {
            None => hints.iter().cloned().map(api::Fraction::from).collect(),
            Some((numerators, den)) => numerators
                .into_iter()
                .map(|numerator| api::Fraction {
                    numerator,
                    denominator: den.clone(),
                })
                .collect(),
        }))
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
        Ok(self
            .combined(column, alpha, hints, affine::combine_to_f64)?
            .unwrap_or_else(|| hints.iter().map(api::Value::to_f64).collect()))
    }
}

impl<R: Ring> ExactLeastSquares<R> {
    /// Algorithm 15 (`LSQ.Solve`) steps 7–8 for one `α` and hints: `ρ = Â h − b̂`,
    /// `G λ = ρ` by lifting, `x = h − V Âᵀ λ`. Checks, then computes the solution as
    /// numerators over one positive denominator
    /// (`None` when there is no constraint and the hints are the answer).
    #[allow(clippy::type_complexity)]
    fn numerators(
        &self,
        column: usize,
        alpha: &[Rational],
        hints: &[Rational],
    ) -> Result<Option<(Vec<BigInt>, BigInt)>, SolveError<Rational>> {
        self.combined(column, alpha, hints, |base, memo, responses, alpha| {
            let x = affine::combine(base, memo, responses, alpha);
            (x.num, x.den)
        })
    }

    /// [`Self::numerators`] as `combine` (`affine::combine` or one of its roundings) gives them
    /// from the hints' base solution and the responses to the anchor values.
    fn combined<T>(
        &self,
        column: usize,
        alpha: &[Rational],
        hints: &[Rational],
        combine: impl FnOnce(
            &affine::Numerators,
            Option<&Mutex<Option<Arc<affine::Scales>>>>,
            &[affine::Numerators],
            &QVec<R>,
        ) -> T,
    ) -> Result<Option<T>, SolveError<Rational>> {
        self.validate(column, alpha)?;
        check_len("hints", hints.len(), self.n)?;
        let alpha_q = QVec::<R>::from_rationals(alpha);
        self.check_prepared(column, &alpha_q)?;
        let Some(normal) = &self.normal else {
            return Ok(None);
        };
        Ok(Some(match self.start(normal, column, hints) {
            affine::Start::Base(base) => combine(
                self.base_numerators(normal, &base, hints),
                Some(base.scales()),
                self.responses(normal),
                &alpha_q,
            ),
            affine::Start::Hints { hints, beta } => {
                let shift: Vec<Rational> = alpha.iter().zip(&beta).map(|(a, b)| a - b).collect();
                combine(
                    &hints,
                    None,
                    self.responses(normal),
                    &QVec::from_rationals(&shift),
                )
            }
        }))
    }

    /// `b̂ = ĉ_j − K̂ α` at the independent rows, as rationals.
    fn b_hat(&self, column: usize, alpha: &QVec<R>) -> Vec<Rational> {
        let c = &self.c_hat[column];
        let c_den = c.den.to_bigint();
        let alpha_den = alpha.den.to_bigint();
        self.k_hat
            .iter()
            .zip(&c.num)
            .map(|(k_row, c_num)| {
                Rational::new(c_num.to_bigint(), c_den.clone())
                    - Rational::new(dot_sparse(k_row, &alpha.num).to_bigint(), alpha_den.clone())
            })
            .collect()
    }

    /// Number of redundant rows whose consistency each update checks.
    pub fn redundant_rows(&self) -> usize {
        self.checks.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Simplification;
    use api::IntMatrix;
    use num_traits::{One, Zero};

    /// `G = Â V Âᵀ` in words equals the big-integer product, and entries beyond `i64` take the
    /// big-integer path.
    #[test]
    fn normal_matrix_in_words_is_the_big_integer_one() {
        let rows: Vec<Vec<(usize, Int)>> = vec![
            vec![(0, Int::from_i64(2)), (2, Int::from_i64(-3))],
            vec![(1, Int::from_i64(1)), (2, Int::from_i64(5))],
        ];
        let v = vec![BigInt::from(1), BigInt::from(4), BigInt::from(7)];
        let g = normal_matrix(&rows, &Diagonal::of(v.clone()), 3);
        assert_eq!(g, normal_matrix_in_big_integers(&rows, &v, 3));
        // Row 0 · V · row 0 = 4 + 63, row 0 · V · row 1 = −105, row 1 · V · row 1 = 4 + 175.
        let expected = vec![
            vec![(0, BigInt::from(67)), (1, BigInt::from(-105))],
            vec![(0, BigInt::from(-105)), (1, BigInt::from(179))],
        ];
        assert_eq!(g, expected);
        let big = vec![BigInt::from(1) << 70, BigInt::from(4), BigInt::from(7)];
        let g = normal_matrix(&rows, &Diagonal::of(big), 3);
        assert_eq!(g[0][0].1, (BigInt::from(4) << 70) + 63);
    }

    #[test]
    fn scales_in_words_are_the_big_integer_ones() {
        let q = |n: i64, d: i64| Rational::new(n.into(), d.into());
        let weights = [q(2, 1), q(3, 1), q(4, 3), q(5, 7)];
        // δ = lcm(2, 3, 4, 5) = 60: V = (30, 20, 45, 84).
        assert_eq!(scales_in_words(&weights), Some(vec![30, 20, 45, 84]));
        // Numerators whose lcm passes 2^64 are left to big integers.
        let big = [q((1 << 62) - 1, 1), q((1 << 61) - 1, 1), q(3, 1)];
        assert_eq!(scales_in_words(&big), None);
    }

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
