//! A certified row basis: the rank, the independent rows and every other row as an exact
//! combination of them, found modulo a prime and proved over the integers.
//!
//! The fraction-free LDU ([`crate::ldu`]) pays for every digit of its entries at every one of
//! its `r·m·n` steps; on the reduced matrix `R_ED` of an edit on a real mesh (thousands of rows,
//! coefficients from triangle areas) that is most of a mouse-down. Here:
//!
//! 1. the row rank profile modulo a word-sized prime `p` ([`crate::modular::row_profile`]):
//!    the rows `Â` that are not combinations of earlier rows modulo `p`. They are independent
//!    over the rationals (a minor that is nonzero modulo `p` is nonzero);
//! 2. `G = Â Âᵀ` (positive definite, as `Â` has independent rows) prepared for p-adic lifting
//!    ([`crate::dixon`], sparse `L D Lᵀ` modulo a prime);
//! 3. for every other row `a_t`: the exact solution of `G λ = Â a_tᵀ`, then the proof
//!    `Âᵀ λ = a_tᵀ` over the integers. If it holds, `a_t = λᵀ Â` exactly: the row is redundant
//!    with that combination. If it fails for some row, `a_t` is not in the span of `Â`: `p` hid
//!    part of the rank, and the next prime is tried (after a few, the fraction-free LDU decides).
//!
//! So every answer is proved, whatever the prime; the prime only decides the speed. The
//! independent rows are the row rank profile (each row that is not a combination of the rows
//! before it), so which rows are called redundant does not depend on magnitudes. Solutions
//! (`x = Âᵀ λ`, `G λ = b̂`) are the minimum-norm ones; the null space is spanned by the
//! projections `d e_f − Âᵀ λ_f` (`G λ_f = Â e_f`) of the unit vectors of the non-pivot columns.
//!
//! Cost: the profile follows the fill of the echelon rows (small for mesh-like systems in their
//! natural order), the rest follows the size of the answers: one lifting per redundant row,
//! which for the local dependencies of spline conditions is a few steps each.

use crate::dixon::LiftingSolver;
use crate::factorization::SparseRow;
use crate::modular::{lifting_primes, row_profile, Modulus};
use crate::ring::{gcd_all, Ring};
use num_bigint::BigInt;
use num_traits::{One, Signed, Zero};
use rayon::prelude::*;

/// How many primes are tried before the fraction-free LDU takes over: a prime fails only when
/// it divides one of the minors that decide the profile, so a second failure is already rare.
const ATTEMPTS: usize = 3;

/// The redundant rows are proved in parallel above this many (below, threads cost more than
/// they save).
const PARALLEL_ABOVE: usize = 8;

/// A redundant row `t` with its primitive integer dependency `y` (`yᵀA = 0`, positive at `t`),
/// as `(row, value)` sorted by row.
type Dependency = (usize, Vec<(usize, BigInt)>);

/// A row basis proved over the integers (see the module documentation).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct CertifiedBasis {
    /// The independent rows, increasing.
    independent: Vec<usize>,
    /// A pivot column per independent row: `Â` restricted to them is nonsingular.
    pivot_columns: Vec<usize>,
    /// Per redundant row `t` (increasing): `(t, y)` with `y` the primitive integer vector with
    /// `yᵀA = 0`, positive at `t`, as `(row, value)` sorted by row.
    dependencies: Vec<Dependency>,
    /// `G = Â Âᵀ` for lifting (`None` when the rank is 0).
    normal: Option<LiftingSolver>,
}

impl CertifiedBasis {
    /// The certified basis of `rows` (`cols` columns), or `None` when no prime tried gave a
    /// profile that could be proved (the caller factors fraction-free instead).
    pub(crate) fn new<R: Ring>(rows: &[SparseRow<R>], cols: usize) -> Option<Self> {
        let big: Vec<Vec<(usize, BigInt)>> = rows
            .iter()
            .map(|row| row.iter().map(|(c, v)| (*c, v.to_bigint())).collect())
            .collect();
        lifting_primes()
            .take(ATTEMPTS)
            .find_map(|p| Self::attempt(&big, cols, Modulus::new(p)))
    }

    /// One prime: the profile modulo `modulus`, then the proof of every redundant row.
    fn attempt(rows: &[Vec<(usize, BigInt)>], cols: usize, modulus: Modulus) -> Option<Self> {
        let residues: Vec<Vec<(usize, u64)>> = rows
            .iter()
            .map(|row| {
                row.iter()
                    .map(|(c, v)| (*c, modulus.residue_big(v)))
                    .filter(|(_, r)| *r != 0)
                    .collect()
            })
            .collect();
        let profile = row_profile(&residues, cols, modulus);
        let a_hat: Vec<&Vec<(usize, BigInt)>> =
            profile.independent.iter().map(|&i| &rows[i]).collect();
        let r = a_hat.len();
        let normal = if r == 0 {
            None
        } else {
            // Â has independent rows, so G is positive definite and this cannot fail; should
            // it, the fraction-free LDU answers instead.
            Some(LiftingSolver::new_symmetric(r, gram(&a_hat, cols))?)
        };
        let mut is_independent = vec![false; rows.len()];
        for &i in &profile.independent {
            is_independent[i] = true;
        }
        let redundant: Vec<usize> = (0..rows.len()).filter(|&t| !is_independent[t]).collect();
        let local = LocalRows::new(rows, &profile.independent, cols);
        let prove = |&t: &usize| {
            local
                .prove(rows, t)
                .or_else(|| prove_redundant(rows, &profile.independent, normal.as_ref(), t, cols))
                .map(|y| (t, y))
        };
        let dependencies: Option<Vec<Dependency>> = if redundant.len() > PARALLEL_ABOVE {
            redundant.par_iter().map(prove).collect()
        } else {
            redundant.iter().map(prove).collect()
        };
        Some(CertifiedBasis {
            independent: profile.independent,
            pivot_columns: profile.pivot_columns,
            dependencies: dependencies?,
            normal,
        })
    }

    /// The rank.
    pub(crate) fn rank(&self) -> usize {
        self.independent.len()
    }

    /// The independent rows, increasing.
    pub(crate) fn independent(&self) -> &[usize] {
        &self.independent
    }

    /// Per redundant row `t`, increasing: `(t, y)` with `y` its primitive integer dependency
    /// (`yᵀA = 0`, positive at `t`), sorted by row.
    pub(crate) fn dependencies(&self) -> &[Dependency] {
        &self.dependencies
    }

    /// `G = Â Âᵀ` prepared for lifting (`None` when the rank is 0).
    pub(crate) fn normal(&self) -> Option<&LiftingSolver> {
        self.normal.as_ref()
    }

    /// `Âᵀ λ` for the independent rows of `rows`, as a dense vector of length `cols`.
    pub(crate) fn combine_rows<R: Ring>(
        &self,
        rows: &[SparseRow<R>],
        lambda: &[BigInt],
        cols: usize,
    ) -> Vec<BigInt> {
        let mut x = vec![<BigInt as Zero>::zero(); cols];
        for (&i, l) in self.independent.iter().zip(lambda) {
            if Zero::is_zero(l) {
                continue;
            }
            for (c, v) in &rows[i] {
                x[*c] += l * v.to_bigint();
            }
        }
        x
    }

    /// The columns that are not pivot columns, increasing: the free columns of the null space.
    pub(crate) fn free_columns(&self, cols: usize) -> Vec<usize> {
        let mut pivot = vec![false; cols];
        for &c in &self.pivot_columns {
            pivot[c] = true;
        }
        (0..cols).filter(|&c| !pivot[c]).collect()
    }
}

/// `Â Âᵀ` as sparse rows with increasing columns, accumulated column by column of `Â`.
fn gram(a_hat: &[&Vec<(usize, BigInt)>], cols: usize) -> Vec<Vec<(usize, BigInt)>> {
    let mut by_column: Vec<Vec<(usize, &BigInt)>> = vec![Vec::new(); cols];
    for (k, row) in a_hat.iter().enumerate() {
        for (c, v) in row.iter() {
            by_column[*c].push((k, v));
        }
    }
    let mut g: Vec<std::collections::BTreeMap<usize, BigInt>> =
        vec![Default::default(); a_hat.len()];
    for entries in &by_column {
        for (k, akc) in entries {
            for (l, alc) in entries {
                *g[*k].entry(*l).or_default() += *akc * *alc;
            }
        }
    }
    g.into_iter()
        .map(|row| row.into_iter().filter(|(_, v)| !Zero::is_zero(v)).collect())
        .collect()
}

/// Local proofs of redundancy: the dependencies of spline-like systems are local (the
/// conditions around one vertex), so a redundant row is first written as a combination of the
/// independent rows near it — those sharing a column with it, then those sharing a column with
/// these, up to [`LOCAL_DEPTH`] steps and [`LOCAL_ROWS`] rows — by the fraction-free LDU of
/// that small system. A combination found there is the combination (the independent rows are
/// independent, so it is unique) and proves the row redundant; otherwise the lifting over all
/// independent rows decides.
struct LocalRows {
    /// Per column, the independent rows (indices into the rows) with an entry there.
    independent_in_column: Vec<Vec<usize>>,
}

/// Steps of row–column adjacency a local proof looks through.
const LOCAL_DEPTH: usize = 3;

/// Largest local system tried (independent rows); larger ones go to the lifting.
const LOCAL_ROWS: usize = 256;

impl LocalRows {
    fn new(rows: &[Vec<(usize, BigInt)>], independent: &[usize], cols: usize) -> Self {
        let mut independent_in_column = vec![Vec::new(); cols];
        for &i in independent {
            for (c, _) in &rows[i] {
                independent_in_column[*c].push(i);
            }
        }
        LocalRows {
            independent_in_column,
        }
    }

    /// The primitive dependency of row `t` on nearby independent rows, proved exactly, or
    /// `None` when none was found nearby.
    fn prove(&self, rows: &[Vec<(usize, BigInt)>], t: usize) -> Option<Vec<(usize, BigInt)>> {
        use std::collections::BTreeSet;
        let mut near: BTreeSet<usize> = BTreeSet::new();
        let mut frontier: BTreeSet<usize> = rows[t].iter().map(|(c, _)| *c).collect();
        let mut seen_columns = frontier.clone();
        for _ in 0..LOCAL_DEPTH {
            let mut reached = BTreeSet::new();
            for c in &frontier {
                for &i in &self.independent_in_column[*c] {
                    if near.insert(i) {
                        reached.insert(i);
                    }
                }
            }
            if near.len() > LOCAL_ROWS || reached.is_empty() {
                return None;
            }
            if let Some(y) = local_dependency(rows, &near, t) {
                return Some(y);
            }
            frontier = reached
                .iter()
                .flat_map(|&i| rows[i].iter().map(|(c, _)| *c))
                .filter(|c| seen_columns.insert(*c))
                .collect();
        }
        None
    }
}

/// Row `t` as an exact combination of the rows `near` (independent), as its primitive
/// dependency `y`, or `None` when it is not one: `Â_Nᵀ λ = a_t` solved by the fraction-free
/// LDU on the columns of these rows (outside them both sides vanish).
fn local_dependency(
    rows: &[Vec<(usize, BigInt)>],
    near: &std::collections::BTreeSet<usize>,
    t: usize,
) -> Option<Vec<(usize, BigInt)>> {
    use api::{Factorization, Rational};
    let near: Vec<usize> = near.iter().copied().collect();
    let mut local_column = std::collections::BTreeMap::new();
    for &i in near.iter().chain([&t]) {
        for (c, _) in &rows[i] {
            let next = local_column.len();
            local_column.entry(*c).or_insert(next);
        }
    }
    // Â_Nᵀ: one row per column of the neighbourhood, one column per near row.
    let mut transposed: Vec<Vec<(usize, BigInt)>> = vec![Vec::new(); local_column.len()];
    for (k, &i) in near.iter().enumerate() {
        for (c, v) in &rows[i] {
            transposed[local_column[c]].push((k, v.clone()));
        }
    }
    let mut target = vec![Rational::zero(); local_column.len()];
    for (c, v) in &rows[t] {
        target[local_column[c]] = Rational::from_integer(v.clone());
    }
    let matrix = api::IntMatrix::from_sparse(near.len(), transposed).ok()?;
    let lambda =
        crate::ExactFactorization::<crate::ring::Int>::new(&matrix, crate::Simplification::Gcd)
            .solve(&target)
            .ok()?;
    // y = (−d λ, d at t) with d the common denominator, made primitive.
    let d = lambda.iter().fold(<BigInt as One>::one(), |acc, l| {
        num_integer::Integer::lcm(&acc, l.denom())
    });
    let mut y: Vec<(usize, BigInt)> = near
        .iter()
        .zip(&lambda)
        .filter(|(_, l)| !Zero::is_zero(*l))
        .map(|(&i, l)| (i, -(l.numer() * (&d / l.denom()))))
        .collect();
    y.push((t, d));
    y.sort_by_key(|(i, _)| *i);
    let values: Vec<BigInt> = y.iter().map(|(_, v)| v.clone()).collect();
    let g = gcd_all(&values);
    if !Ring::is_one(&g) && !Ring::is_zero(&g) {
        for (_, v) in &mut y {
            *v /= &g;
        }
    }
    Some(y)
}

/// The primitive dependency of row `t` on the independent rows, proved exactly; `None` when
/// `t` is not in their span (the prime hid part of the rank).
fn prove_redundant(
    rows: &[Vec<(usize, BigInt)>],
    independent: &[usize],
    normal: Option<&LiftingSolver>,
    t: usize,
    cols: usize,
) -> Option<Vec<(usize, BigInt)>> {
    let target = &rows[t];
    let Some(normal) = normal else {
        // Rank 0: only zero rows are redundant, with the dependency e_t.
        return target
            .iter()
            .all(|(_, v)| Zero::is_zero(v))
            .then(|| vec![(t, <BigInt as One>::one())]);
    };
    let mut dense_target = vec![<BigInt as Zero>::zero(); cols];
    for (c, v) in target {
        dense_target[*c] = v.clone();
    }
    let rhs: Vec<BigInt> = independent
        .iter()
        .map(|&i| {
            rows[i]
                .iter()
                .fold(<BigInt as Zero>::zero(), |acc, (c, v)| {
                    acc + v * &dense_target[*c]
                })
        })
        .collect();
    let (lambda, den) = normal.solve(&rhs);
    // Proof: Âᵀ λ = den · a_t on every column.
    let mut combined = vec![<BigInt as Zero>::zero(); cols];
    for (&i, l) in independent.iter().zip(&lambda) {
        if Zero::is_zero(l) {
            continue;
        }
        for (c, v) in &rows[i] {
            combined[*c] += l * v;
        }
    }
    let proved = combined
        .iter()
        .zip(&dense_target)
        .all(|(x, a)| *x == &den * a);
    if !proved {
        return None;
    }
    let mut y: Vec<(usize, BigInt)> = independent
        .iter()
        .zip(lambda)
        .filter(|(_, l)| !Zero::is_zero(l))
        .map(|(&i, l)| (i, -l))
        .collect();
    y.push((t, den));
    y.sort_by_key(|(i, _)| *i);
    let values: Vec<BigInt> = y.iter().map(|(_, v)| v.clone()).collect();
    let g = gcd_all(&values);
    if !Ring::is_one(&g) && !Ring::is_zero(&g) {
        for (_, v) in &mut y {
            *v /= &g;
        }
    }
    debug_assert!(y.iter().any(|(i, v)| *i == t && v.is_positive()));
    Some(y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::factorization::ExactFactorization;
    use crate::ldu::Simplification;
    use crate::ring::Int;
    use api::{Factorization, IntMatrix};

    fn two_rows_differing_by(k: &BigInt) -> IntMatrix {
        let rows = vec![
            vec![
                (0, BigInt::from(1)),
                (1, BigInt::from(1)),
                (2, BigInt::from(2)),
            ],
            vec![(0, BigInt::from(1)), (1, 1 + k), (2, BigInt::from(2))],
            vec![(0, BigInt::from(2)), (1, 2 + k), (2, BigInt::from(4))],
        ];
        IntMatrix::from_sparse(3, rows).expect("matrix")
    }

    /// A prime that divides a minor hides part of the rank; the proof of the redundant rows
    /// fails for it and the next prime gives the true rank with proved combinations.
    #[test]
    fn a_prime_that_hides_rank_is_caught_and_the_next_one_used() {
        let first = lifting_primes().next().expect("a prime");
        let a = two_rows_differing_by(&BigInt::from(first));
        let f = ExactFactorization::<Int>::certified(&a, Simplification::Gcd);
        assert!(f.is_certified());
        assert_eq!(f.rank(), 2);
        assert_eq!(f.independent_rows(), vec![0, 1]);
        let redundancy = &f.redundancies()[0];
        assert_eq!(redundancy.row, 2);
        assert_eq!(
            redundancy.combination,
            vec![(0, 1.into()), (1, 1.into())]
                .into_iter()
                .map(|(i, c): (usize, i64)| (i, api::Rational::from_integer(c.into())))
                .collect::<Vec<_>>()
        );
    }

    /// When every prime tried hides rank, the fraction-free LDU decides (same answers).
    #[test]
    fn when_every_prime_fails_the_fraction_free_ldu_decides() {
        let product = lifting_primes()
            .take(ATTEMPTS)
            .fold(BigInt::from(1), |acc, p| acc * p);
        let a = two_rows_differing_by(&product);
        let f = ExactFactorization::<Int>::certified(&a, Simplification::Gcd);
        assert!(!f.is_certified());
        assert_eq!(f.rank(), 2);
        assert_eq!(
            f.rank(),
            ExactFactorization::<Int>::new(&a, Simplification::Gcd).rank()
        );
    }

    /// The dependencies are primitive, positive at their redundant row and annihilate `A`.
    #[test]
    fn dependencies_are_primitive_left_null_vectors() {
        let dense = vec![
            vec![3, 0, 6, 0],
            vec![0, 2, 0, 4],
            vec![6, 4, 12, 8],
            vec![0, 0, 0, 0],
            vec![9, -2, 18, -4],
        ];
        let a = IntMatrix::from_dense(4, &dense).expect("matrix");
        let rows: Vec<SparseRow<Int>> = a
            .row_iter()
            .map(|row| row.iter().map(|(c, v)| (*c, Int::from_bigint(v))).collect())
            .collect();
        let basis = CertifiedBasis::new(&rows, 4).expect("certified");
        assert_eq!(basis.independent(), &[0, 1]);
        let redundant: Vec<usize> = basis.dependencies().iter().map(|(t, _)| *t).collect();
        assert_eq!(redundant, vec![2, 3, 4]);
        for (t, y) in basis.dependencies() {
            let at_t = &y.iter().find(|(i, _)| i == t).expect("own row").1;
            assert!(at_t.is_positive());
            let values: Vec<BigInt> = y.iter().map(|(_, v)| v.clone()).collect();
            assert!(Ring::is_one(&gcd_all(&values)));
            for (c, _) in dense[0].iter().enumerate() {
                let sum: i64 = y
                    .iter()
                    .map(|(i, v)| i64::try_from(v.clone()).expect("small") * dense[*i][c])
                    .sum();
                assert_eq!(sum, 0, "column {c} of the dependency of row {t}");
            }
        }
    }
}
