//! The solution of an update as an affine function of the anchor values:
//!
//! ```text
//! x(α, h) = base_j(h) − Σ_k α_k resp_k,
//! base_j(h) = h − V Âᵀ G⁻¹ (Â h − ĉ_j),      resp_k = V Âᵀ G⁻¹ K̂_{:,k}
//! ```
//!
//! (expand `x = h − V Âᵀ G⁻¹ (Â h − ĉ_j + K̂ α)`). The responses to the anchors are lifted once,
//! at the first update, and the base is kept for the last hints of each column: an update whose
//! hints are those of the previous one (a generic edit's steps, a drag with fixed hints) costs
//! `O(n · a)` big-number multiplications instead of a lifted solve. Both are memos of pure
//! functions of the prepared data: they never change an answer. Hints on the constraint set
//! (anchors at `β`) need no base for their first update, `x = h − Σ_k (α_k − β_k) resp_k`
//! directly; their base is formed only when a second update with them asks for it.

use super::{Diagonal, ExactLeastSquares};
use crate::dixon::{entries_per_task, LiftingSolver};
use crate::qvec::QVec;
use crate::ring::{lcm, Ring};
use crate::shared_once::SharedOnce;
use crate::word_combination::{word_combination, word_combination_to_f64};
use api::exact::{top_bits, top_bits_of_limbs, TopBits};
use api::words::{all_fit, checked_mul_i128};
use api::Rational;
use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{One, ToPrimitive, Zero};
use rayon::prelude::*;
use std::sync::{Arc, Mutex, OnceLock};

/// A rational vector as integer numerators over one positive denominator.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct Numerators {
    pub(super) num: Vec<BigInt>,
    pub(super) den: BigInt,
}

impl Numerators {
    /// `v` as big-integer numerators over its denominator.
    fn of<R: Ring>(v: &QVec<R>) -> Self {
        Numerators {
            num: v.num.iter().map(Ring::to_bigint).collect(),
            den: v.den.to_bigint(),
        }
    }

    /// Divides the numerators and the denominator by their common content, so every update
    /// built from this vector (and the GCDs that reduce its results) works on smaller numbers.
    fn without_content(mut self) -> Self {
        // The GCD `g` of the denominator and the first few entries, one by one: usually 1 by
        // then. When it is not, it is close to the content (a few small factors more, on the
        // figure mesh's δ_max = 40 solves: 1 300 against 1 270 bits over 45 000-bit
        // denominators). Every entry is divided by `g` once (in parallel); the content is the
        // GCD of `g` and the remainders, numbers of `g`'s length, and each entry without it is
        // `q · (g / content) + r / content` from its quotient and remainder — no GCD, and no
        // second division, of long numbers.
        let seed = self.num.len().min(CONTENT_SEED_ENTRIES);
        let g = gcd_with(self.den.clone(), &self.num[..seed]);
        if One::is_one(&g) {
            return self;
        }
        let per_task = entries_per_task(self.num.len(), (g.bits() / 64) as usize + 1);
        let divided: Vec<(BigInt, BigInt)> = self
            .num
            .par_iter()
            .with_min_len(per_task)
            .map(|x| x.div_rem(&g))
            .collect();
        let content = divided
            .par_chunks(per_task)
            .map(|chunk| gcd_with(g.clone(), chunk.iter().map(|(_, r)| r)))
            .reduce(|| g.clone(), |a, b| gcd_with(a, [&b]));
        if One::is_one(&content) {
            return self;
        }
        let cofactor = &g / &content;
        self.num = divided
            .into_par_iter()
            .with_min_len(per_task)
            .map(|(q, r)| {
                if One::is_one(&cofactor) {
                    q
                } else {
                    q * &cofactor + r / &content
                }
            })
            .collect();
        self.den /= &content;
        self
    }
}

/// `gcd(g, entries…)`, stopping once it reaches 1.
fn gcd_with<'a>(mut g: BigInt, entries: impl IntoIterator<Item = &'a BigInt>) -> BigInt {
    for x in entries {
        if One::is_one(&g) {
            break;
        }
        if !Zero::is_zero(x) {
            g = crate::gcd::gcd_bigint(&g, x);
        }
    }
    g
}

/// Entries whose GCD with the denominator [`Numerators::without_content`] takes one by one
/// before it divides every entry by that GCD.
const CONTENT_SEED_ENTRIES: usize = 4;

/// Unknowns from which the responses to several anchor coordinates are lifted in parallel
/// (below, handing them to rayon costs more than it saves).
const PARALLEL_RESPONSES_FROM: usize = 256;

/// The last hint vector of one column, as given, and its base (shared: a drag frame reads it
/// without copying its numerators).
type BaseMemo = Mutex<Option<(Vec<Rational>, Arc<Base>)>>;

/// Where an update starts ([`ExactLeastSquares::start`]).
pub(super) enum Start {
    /// A base of the hints, from the memo or just formed.
    Base(Arc<Base>),
    /// The hints themselves, on the constraint set with the anchors at `beta`: the update is
    /// `hints − Σ_k (α_k − β_k) resp_k`.
    Hints {
        hints: Numerators,
        beta: Vec<Rational>,
    },
}

/// A base with what [`combine`] derives from it and the responses, for every frame with these
/// hints: [`Scales`] for the last set of moving anchors.
///
/// When the hints lie on the constraint set with the anchors at `β` (the usual case), the first
/// update goes straight to its solution `h − Σ_k (α_k − β_k) resp_k` and keeps only `β`: the
/// base `h + Σ_k β_k resp_k` is formed when a second update with these hints asks for it (a
/// drag's next frame), and never for an edit updated once.
#[derive(Debug)]
pub(super) struct Base {
    numerators: OnceLock<Numerators>,
    /// `β`, when the numerators are deferred.
    anchors_on_hints: Option<Vec<Rational>>,
    scales: Mutex<Option<Arc<Scales>>>,
}

impl Base {
    /// A base formed at once.
    fn formed(numerators: Numerators) -> Self {
        Base {
            numerators: OnceLock::from(numerators),
            anchors_on_hints: None,
            scales: Mutex::new(None),
        }
    }

    /// A base `h + Σ_k β_k resp_k` formed when first read.
    fn deferred(beta: Vec<Rational>) -> Self {
        Base {
            numerators: OnceLock::new(),
            anchors_on_hints: Some(beta),
            scales: Mutex::new(None),
        }
    }

    /// The memo of [`combine`]'s scales for this base.
    pub(super) fn scales(&self) -> &Mutex<Option<Arc<Scales>>> {
        &self.scales
    }
}

/// The parts of `base − Σ_k α_k resp_k` that do not depend on `α`, for one set of moving
/// anchors (those with `α_k ≠ 0`): the common denominator `L = lcm(b_den, r_den,k)`, the
/// ratios `L / b_den` and `L / r_den,k`, and the numerators as `i128` when they all fit (read
/// once, not converted every frame).
#[derive(Debug)]
pub(super) struct Scales {
    moving: Vec<bool>,
    common: BigInt,
    base_ratio: BigInt,
    ratios: Vec<BigInt>,
    words: Option<Words>,
}

/// The base's numerators and the moving responses' (`responses[k][s]`), as `i128`.
#[derive(Debug)]
struct Words {
    base: Vec<i128>,
    responses: Vec<Vec<i128>>,
}

impl Scales {
    fn new(base: &Numerators, responses: &[Numerators], moving: Vec<bool>) -> Self {
        let moved = || {
            responses
                .iter()
                .zip(&moving)
                .filter(|(_, m)| **m)
                .map(|(r, _)| r)
        };
        let mut common = base.den.clone();
        for r in moved() {
            common = num_integer::Integer::lcm(&common, &r.den);
        }
        let words = |v: &[BigInt]| all_fit(v.len(), v.iter().map(ToPrimitive::to_i128));
        let words = words(&base.num).and_then(|base| {
            Some(Words {
                base,
                responses: all_fit(responses.len(), moved().map(|r| words(&r.num)))?,
            })
        });
        Scales {
            base_ratio: &common / &base.den,
            ratios: moved().map(|r| &common / &r.den).collect(),
            common,
            moving,
            words,
        }
    }
}

/// The memos of [`ExactLeastSquares`]: the responses to the anchors and the last base per
/// column. Copies start with the same contents; two memos always compare equal (they hold
/// values derived from the rest of the prepared data, not part of it).
#[derive(Debug, Default)]
pub(super) struct AffineMemo {
    responses: SharedOnce<Vec<Numerators>>,
    bases: Vec<BaseMemo>,
    /// The first hint residual that had to be lifted, by whichever column needed it first.
    first_direction: SharedOnce<Arc<SolvedDirection>>,
    /// How many bases were lifted on their own (the first direction's included).
    #[cfg(test)]
    lifted_bases: std::sync::atomic::AtomicUsize,
}

/// A hint residual `ρ / ρ_den` with its projection `V Âᵀ G⁻¹ ρ / ρ_den`, lifted. The other
/// columns' residuals are often combinations of it and of the anchors' columns: hints that
/// translate the derived parameters by `d` (what a translation plans) leave in column `j` the
/// residual `d_j Â 1 − K̂ β_j`, the same direction in every column.
#[derive(Debug)]
struct SolvedDirection {
    rho: Vec<BigInt>,
    rho_den: BigInt,
    projected: Numerators,
}

impl AffineMemo {
    /// Empty memos for `columns` right-hand-side columns.
    pub(super) fn new(columns: usize) -> Self {
        AffineMemo {
            bases: (0..columns).map(|_| Mutex::new(None)).collect(),
            ..AffineMemo::default()
        }
    }
}

impl Clone for AffineMemo {
    fn clone(&self) -> Self {
        AffineMemo {
            responses: self.responses.clone(),
            first_direction: self.first_direction.clone(),
            #[cfg(test)]
            lifted_bases: std::sync::atomic::AtomicUsize::new(0),
            bases: self
                .bases
                .iter()
                .map(|m| Mutex::new(m.lock().map(|g| g.clone()).unwrap_or(None)))
                .collect(),
        }
    }
}

impl PartialEq for AffineMemo {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl Eq for AffineMemo {}

impl<R: Ring> ExactLeastSquares<R> {
    /// `V Âᵀ G⁻¹ ρ` for `ρ = rho / rho_den`, exactly: in machine words when everything fits,
    /// else lifted in big integers.
    fn projected(&self, normal: &LiftingSolver, rho: &[BigInt], rho_den: &BigInt) -> Numerators {
        self.projected_in_words(normal, rho, rho_den)
            .unwrap_or_else(|| self.projected_in_big_integers(normal, rho, rho_den))
    }

    /// [`Self::projected`] with `G⁻¹ ρ` lifted ([`LiftingSolver::solve`]) and every product a
    /// big integer.
    fn projected_in_big_integers(
        &self,
        normal: &LiftingSolver,
        rho: &[BigInt],
        rho_den: &BigInt,
    ) -> Numerators {
        let (lambda, lambda_den) = normal.solve(rho);
        let mut num: Vec<BigInt> = vec![<BigInt as Zero>::zero(); self.n];
        for (row, l) in self.a_hat.iter().zip(&lambda) {
            if Zero::is_zero(l) {
                continue;
            }
            for (s, a) in row {
                num[*s] += l * a.to_bigint();
            }
        }
        if let Diagonal::Scales(v) = &self.v {
            for (x, v) in num.iter_mut().zip(v) {
                *x *= v;
            }
        }
        Numerators {
            num,
            den: lambda_den * rho_den,
        }
    }

    /// [`Self::projected`] in machine words: `ρ` and the entries of `Â` and `V` in an `i64`,
    /// `λ = G⁻¹ ρ` solved fraction-free in words, and every sum of `Σ_r λ_r Â_rs` and its
    /// product by `V_s` in an `i128` (checked). The same numerators and denominator, without a
    /// big-integer product per entry of `Â` (on a 10-point chain these were half of each
    /// response); `None` when anything does not fit.
    fn projected_in_words(
        &self,
        normal: &LiftingSolver,
        rho: &[BigInt],
        rho_den: &BigInt,
    ) -> Option<Numerators> {
        let rho = all_fit(rho.len(), rho.iter().map(ToPrimitive::to_i64))?;
        let (lambda, lambda_den) = normal.solve_in_words(&rho)?;
        let mut sums = vec![0i128; self.n];
        for (row, &l) in self.a_hat.iter().zip(&lambda) {
            if l == 0 {
                continue;
            }
            for (s, a) in row {
                let term = i128::from(l) * i128::from(a.to_i64()?);
                sums[*s] = sums[*s].checked_add(term)?;
            }
        }
        let num = all_fit(
            sums.len(),
            sums.iter().enumerate().map(|(s, x)| {
                let scaled = checked_mul_i128(*x, i128::from(self.v.word(s)?))?;
                Some(crate::ring::bigint_from_i128(scaled))
            }),
        )?;
        Some(Numerators {
            num,
            den: BigInt::from(lambda_den) * rho_den,
        })
    }

    /// Whether [`Self::responses`] has been lifted already.
    pub(super) fn responses_ready(&self) -> bool {
        self.memo.responses.get().is_some()
    }

    /// `resp_k = V Âᵀ G⁻¹ K̂_{:,k}` for every anchor coordinate `k`, lifted at the first call.
    pub(super) fn responses(&self, normal: &LiftingSolver) -> &[Numerators] {
        self.memo.responses.get_or_init(|| {
            // Several anchor coordinates lift in parallel when each lifting is real work and
            // this is one of rayon's workers (from another thread, handing work over costs more).
            let per_task =
                if self.n >= PARALLEL_RESPONSES_FROM && rayon::current_thread_index().is_some() {
                    1
                } else {
                    self.parameters.max(1)
                };
            (0..self.parameters)
                .into_par_iter()
                .with_min_len(per_task)
                .map(|k| {
                    let rho: Vec<BigInt> = self
                        .k_hat
                        .iter()
                        .map(|row| {
                            row.iter()
                                .find(|(c, _)| *c == k)
                                .map(|(_, v)| v.to_bigint())
                                .unwrap_or_default()
                        })
                        .collect();
                    self.projected(normal, &rho, &BigInt::from(1))
                        .without_content()
                })
                .collect()
        })
    }

    /// What an update of column `column` with hints `given` starts from: the memo's base when
    /// `given` is the column's last hint vector, else a new base, remembered for the next
    /// update. Lifts the responses first if they are not ready (alongside the base's own
    /// solve, one per core).
    ///
    /// `base_j(h) = h − V Âᵀ G⁻¹ (Â h − ĉ_j)`. When the hints' residual is a combination of the
    /// anchors' columns, `Â h − ĉ_j = −K̂ β` (the usual case: the current values, which satisfy
    /// every constraint with the anchors at their current values `β`, suggested as hints), the
    /// base needs no solve of its own: `base_j(h) = h + Σ_k β_k resp_k`, and the update itself
    /// is `h − Σ_k (α_k − β_k) resp_k` (one combination, not two: [`Start::Hints`]).
    pub(super) fn start(&self, normal: &LiftingSolver, column: usize, given: &[Rational]) -> Start {
        let slot = &self.memo.bases[column];
        if let Ok(guard) = slot.lock() {
            if let Some((hints, base)) = guard.as_ref() {
                if api::identical_rationals(hints, given) {
                    return Start::Base(Arc::clone(base));
                }
            }
        }
        let h = &QVec::<R>::from_rationals(given);
        let (rho, common) = self.hint_residual(column, h);
        let hints = Numerators::of(h);
        let (start, base) = match self.anchor_combination(&rho, &common) {
            Some(beta) => {
                let base = Arc::new(Base::deferred(beta.clone()));
                (Start::Hints { hints, beta }, base)
            }
            None => {
                let base = self
                    .base_through_direction(normal, &hints, rho, common)
                    .without_content();
                let base = Arc::new(Base::formed(base));
                (Start::Base(Arc::clone(&base)), base)
            }
        };
        if let Ok(mut guard) = slot.lock() {
            *guard = Some((given.to_vec(), base));
        }
        start
    }

    /// The numerators of `base`, a base of the hints `given`, formed now if they were deferred.
    pub(super) fn base_numerators<'a>(
        &self,
        normal: &LiftingSolver,
        base: &'a Base,
        given: &[Rational],
    ) -> &'a Numerators {
        base.numerators.get_or_init(|| {
            let hints = Numerators::of(&QVec::<R>::from_rationals(given));
            let beta = base.anchors_on_hints.as_deref().unwrap_or_default();
            let beta = QVec::<R>::from_rationals(beta);
            combine(&hints, None, self.responses(normal), &beta.negated()).without_content()
        })
    }

    /// `h − V Âᵀ G⁻¹ ρ / ρ_den` for a residual off the anchors' columns. The first such residual
    /// of this system is lifted and shared ([`AffineMemo::first_direction`]; a column that
    /// finds another lifting it helps and waits); a later one that is a combination
    /// `ρ / ρ_den = −K̂ β + γ · first` takes `h + Σ_k β_k resp_k − γ · projected(first)` without
    /// a lifting of its own; any other is lifted here.
    fn base_through_direction(
        &self,
        normal: &LiftingSolver,
        hints: &Numerators,
        rho: Vec<BigInt>,
        rho_den: BigInt,
    ) -> Numerators {
        let mut own: Option<(Vec<BigInt>, BigInt)> = Some((rho, rho_den));
        let first = self.memo.first_direction.get_or_init(|| {
            let (rho, rho_den) = own.take().unwrap_or_default();
            let projected = self.lifted_projection(normal, &rho, &rho_den);
            Arc::new(SolvedDirection {
                rho,
                rho_den,
                projected,
            })
        });
        let Some((rho, rho_den)) = own else {
            // This column's residual is the first direction.
            return difference(hints, &first.projected);
        };
        if let Some((beta, gamma)) = self.direction_combination(&rho, &rho_den, first) {
            let with_anchors = combine(hints, None, self.responses(normal), &beta.negated());
            let gamma = QVec::<R>::from_rationals(&[gamma]);
            return combine(
                &with_anchors,
                None,
                std::slice::from_ref(&first.projected),
                &gamma,
            );
        }
        difference(hints, &self.lifted_projection(normal, &rho, &rho_den))
    }

    /// [`Self::projected`], alongside the responses' lifting when they are not ready (one per
    /// core).
    fn lifted_projection(
        &self,
        normal: &LiftingSolver,
        rho: &[BigInt],
        rho_den: &BigInt,
    ) -> Numerators {
        #[cfg(test)]
        self.memo
            .lifted_bases
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        if self.responses_ready() {
            self.projected(normal, rho, rho_den)
        } else {
            rayon::join(
                || self.responses(normal),
                || self.projected(normal, rho, rho_den),
            )
            .1
        }
    }

    /// Some `(β, γ)` with `ρ / ρ_den = −K̂ β + γ · first.ρ / first.ρ_den`, when there is one
    /// (exact elimination with one unknown more than [`Self::anchor_combination`]).
    fn direction_combination(
        &self,
        rho: &[BigInt],
        rho_den: &BigInt,
        first: &SolvedDirection,
    ) -> Option<(QVec<R>, Rational)> {
        // `K̂ u + w · first.ρ = −ρ`; then `β = u / ρ_den` and `γ = −w · first.ρ_den / ρ_den`.
        let mut solution = self.integer_combination(rho, Some(&first.rho))?;
        let (w, w_den) = solution.pop()?;
        let gamma = Rational::new(-(w * &first.rho_den), w_den * rho_den);
        Some((QVec::from_rationals(&scaled_down(solution, rho_den)), gamma))
    }

    /// `Â h − ĉ_j` as numerators over one positive denominator.
    fn hint_residual(&self, column: usize, h: &QVec<R>) -> (Vec<BigInt>, BigInt) {
        let c = &self.c_hat[column];
        let common = lcm(&h.den, &c.den);
        let fh = common.div_exact(&h.den);
        let fc = common.div_exact(&c.den);
        let rho = self
            .a_hat
            .iter()
            .zip(&c.num)
            .map(|(row, ck)| {
                let mut s = super::dot_sparse(row, &h.num).mul(&fh);
                if !ck.is_zero() {
                    s = s.sub(&ck.mul(&fc));
                }
                s.to_bigint()
            })
            .collect();
        (rho, common.to_bigint())
    }

    /// Some `β` with `K̂ β = −ρ / ρ_den`, when there is one: exact elimination on the rows of
    /// `K̂` (as many unknowns as anchor coordinates), every row checked; `None` as soon as a row
    /// without anchors has a nonzero residual.
    fn anchor_combination(&self, rho: &[BigInt], rho_den: &BigInt) -> Option<Vec<Rational>> {
        // `K̂ u = −ρ`, then `β = u / ρ_den`.
        let solution = self.integer_combination(rho, None)?;
        Some(scaled_down(solution, rho_den))
    }

    /// A solution `(u, w)` of `K̂ u + w · extra = −ρ` (without `extra`, of `K̂ u = −ρ`) as
    /// `(numerator, denominator)` per unknown (`w` last), from the integer rows
    /// `[K̂_i | extra_i | −ρ_i]`; `None` when there is none (a row with no coefficient and a
    /// nonzero `ρ_i` ends the search at once).
    fn integer_combination(
        &self,
        rho: &[BigInt],
        extra: Option<&[BigInt]>,
    ) -> Option<Vec<(BigInt, BigInt)>> {
        let unknowns = self.parameters + usize::from(extra.is_some());
        let mut equations: Vec<Vec<BigInt>> = Vec::new();
        for (i, (row, r)) in self.k_hat.iter().zip(rho).enumerate() {
            let e = extra.and_then(|e| e.get(i));
            if row.is_empty() && e.is_none_or(Zero::is_zero) {
                if !Zero::is_zero(r) {
                    return None;
                }
                continue;
            }
            let mut equation = vec![<BigInt as Zero>::zero(); unknowns + 1];
            for (k, v) in row {
                equation[*k] = v.to_bigint();
            }
            if let Some(e) = e {
                equation[self.parameters] = e.clone();
            }
            equation[unknowns] = -r;
            equations.push(equation);
        }
        solve_consistent(equations, unknowns)
    }
}

/// `u / den` as rationals, from `(numerator, denominator)` pairs.
fn scaled_down(u: Vec<(BigInt, BigInt)>, den: &BigInt) -> Vec<Rational> {
    u.into_iter()
        .map(|(num, d)| Rational::new(num, d * den))
        .collect()
}

/// `h − p` over `h.den · p.den`.
fn difference(h: &Numerators, p: &Numerators) -> Numerators {
    Numerators {
        num: h
            .num
            .iter()
            .zip(&p.num)
            .map(|(hs, ps)| hs * &p.den - &h.den * ps)
            .collect(),
        den: &h.den * &p.den,
    }
}

/// A solution of the integer equations `[coefficients | right-hand side]` (free unknowns set to
/// zero) by fraction-free Gauss–Jordan elimination, as `(numerator, denominator)` per unknown,
/// or `None` when they are inconsistent. Each step replaces a row by `p · row − f · pivot row`
/// (`p` the pivot, `f` the row's entry in the pivot column) and divides it by its content, so
/// the numbers stay small; no rational is formed until the end.
fn solve_consistent(
    mut equations: Vec<Vec<BigInt>>,
    unknowns: usize,
) -> Option<Vec<(BigInt, BigInt)>> {
    let mut pivots: Vec<(usize, usize)> = Vec::new();
    let mut next = 0;
    for k in 0..unknowns {
        let Some(found) = (next..equations.len()).find(|&i| !Zero::is_zero(&equations[i][k]))
        else {
            continue;
        };
        equations.swap(next, found);
        let pivot_row = equations[next].clone();
        let pivot = &pivot_row[k];
        for (i, row) in equations.iter_mut().enumerate() {
            if i == next || Zero::is_zero(&row[k]) {
                continue;
            }
            let f = row[k].clone();
            let mut content = <BigInt as Zero>::zero();
            for (v, pv) in row.iter_mut().zip(&pivot_row) {
                *v = &*v * pivot - &f * pv;
                if !One::is_one(&content) && !Zero::is_zero(&*v) {
                    content = num_integer::Integer::gcd(&content, v);
                }
            }
            if !Zero::is_zero(&content) && !One::is_one(&content) {
                for v in row.iter_mut() {
                    *v /= &content;
                }
            }
        }
        pivots.push((next, k));
        next += 1;
    }
    if equations[next..]
        .iter()
        .any(|row| !Zero::is_zero(&row[unknowns]))
    {
        return None;
    }
    let mut beta = vec![(<BigInt as Zero>::zero(), <BigInt as One>::one()); unknowns];
    for (i, k) in pivots {
        let row = &equations[i];
        beta[k] = (row[unknowns].clone(), row[k].clone());
    }
    Some(beta)
}

/// `base − Σ_k α_k resp_k` over one denominator, `α = alpha / alpha_den`; with `memo`, the
/// base's [`Scales`] are taken from it (and kept there) when the same anchors move.
pub(super) fn combine<R: Ring>(
    base: &Numerators,
    memo: Option<&Mutex<Option<Arc<Scales>>>>,
    responses: &[Numerators],
    alpha: &QVec<R>,
) -> Numerators {
    match Combination::new(base, memo, responses, alpha) {
        None => base.clone(),
        Some(c) => Numerators {
            num: (0..base.num.len()).map(|s| c.entry(s)).collect(),
            den: c.den,
        },
    }
}

/// [`combine`] rounded to `f64` as [`api::exact::fraction_to_f64`] rounds each entry over the
/// denominator: what a preview draws. Long entries with word-sized scales are summed in limbs
/// and rounded there ([`word_combination_to_f64`]), never formed as big integers.
pub(super) fn combine_to_f64<R: Ring>(
    base: &Numerators,
    memo: Option<&Mutex<Option<Arc<Scales>>>>,
    responses: &[Numerators],
    alpha: &QVec<R>,
) -> Vec<f64> {
    match Combination::new(base, memo, responses, alpha) {
        None => base
            .num
            .iter()
            .map(|n| api::exact::fraction_to_f64(n, &base.den))
            .collect(),
        Some(c) => {
            let den = top_bits(&c.den);
            (0..base.num.len())
                .map(|s| c.entry_to_f64(s, den))
                .collect()
        }
    }
}

/// The terms of [`combine`] for one `α` with at least one moving anchor coordinate:
/// `x = (b (L / b_den) α_den − Σ a_k (L / r_den,k) r_k) / (L α_den)`.
struct Combination<'a> {
    base: &'a Numerators,
    scales: Arc<Scales>,
    /// The responses of the moving coordinates.
    moved: Vec<&'a Numerators>,
    /// `a_k (L / r_den,k)` per moving coordinate.
    factors: Vec<BigInt>,
    /// `α_den (L / b_den)`.
    base_scale: BigInt,
    /// The scales as `i128` when the numerators are `i128` too ([`Scales::words`]).
    small: Option<(i128, Vec<i128>)>,
    /// The scales as `i64` (negated factors) for long numerators.
    word: Option<(i64, Vec<i64>)>,
    /// `L α_den`.
    den: BigInt,
}

impl<'a> Combination<'a> {
    /// `None` when no anchor coordinate moves (the result is `base`).
    fn new<R: Ring>(
        base: &'a Numerators,
        memo: Option<&Mutex<Option<Arc<Scales>>>>,
        responses: &'a [Numerators],
        alpha: &QVec<R>,
    ) -> Option<Self> {
        let moving: Vec<bool> = alpha.num.iter().map(|a| !a.is_zero()).collect();
        if !moving.contains(&true) {
            return None;
        }
        let remembered = memo.and_then(|m| {
            m.lock()
                .ok()?
                .as_ref()
                .filter(|s| s.moving == moving)
                .map(Arc::clone)
        });
        let scales = remembered.unwrap_or_else(|| {
            let scales = Arc::new(Scales::new(base, responses, moving));
            if let Some(mut guard) = memo.and_then(|m| m.lock().ok()) {
                *guard = Some(Arc::clone(&scales));
            }
            scales
        });
        let factors: Vec<BigInt> = alpha
            .num
            .iter()
            .filter(|a| !a.is_zero())
            .zip(&scales.ratios)
            .map(|(a, ratio)| a.to_bigint() * ratio)
            .collect();
        let moved: Vec<&Numerators> = responses
            .iter()
            .zip(&scales.moving)
            .filter(|(_, m)| **m)
            .map(|(r, _)| r)
            .collect();
        let alpha_den = alpha.den.to_bigint();
        let base_scale = &alpha_den * &scales.base_ratio;
        // Small edits and drag frames: numerators and factors within an `i128` make each entry
        // a sum of `i128` products, computed without big-integer temporaries while it fits
        // (checked).
        let small = scales.words.as_ref().and_then(|_| {
            Some((
                ToPrimitive::to_i128(&base_scale)?,
                factors
                    .iter()
                    .map(ToPrimitive::to_i128)
                    .collect::<Option<Vec<i128>>>()?,
            ))
        });
        let word = ToPrimitive::to_i64(&base_scale).and_then(|bs| {
            let negated = factors
                .iter()
                .map(|f| ToPrimitive::to_i64(f)?.checked_neg())
                .collect::<Option<Vec<i64>>>()?;
            Some((bs, negated))
        });
        let den = &scales.common * alpha_den;
        Some(Combination {
            base,
            scales,
            moved,
            factors,
            base_scale,
            small,
            word,
            den,
        })
    }

    /// Entry `s` in `i128`, when the numerators and scales are and the sum stays there.
    fn entry_in_words(&self, s: usize) -> Option<i128> {
        let (bs, fs) = self.small.as_ref()?;
        let w = self.scales.words.as_ref()?;
        let mut sum = checked_mul_i128(w.base[s], *bs)?;
        for (r, f) in w.responses.iter().zip(fs) {
            sum = sum.checked_sub(checked_mul_i128(r[s], *f)?)?;
        }
        Some(sum)
    }

    /// Numerator `s` over [`Self::den`].
    fn entry(&self, s: usize) -> BigInt {
        if let Some(value) = self.entry_in_words(s) {
            return crate::ring::bigint_from_i128(value);
        }
        if let Some((bs, fs)) = &self.word {
            let responses = self.moved.iter().zip(fs).map(|(r, f)| (&r.num[s], *f));
            return word_combination(std::iter::once((&self.base.num[s], *bs)).chain(responses));
        }
        let mut value = &self.base.num[s] * &self.base_scale;
        for (r, f) in self.moved.iter().zip(&self.factors) {
            value -= f * &r.num[s];
        }
        value
    }

    /// Numerator `s` over [`Self::den`] rounded to `f64` as
    /// [`api::exact::fraction_to_f64`] rounds it; `den` is [`top_bits`] of [`Self::den`].
    fn entry_to_f64(&self, s: usize, den: TopBits) -> f64 {
        if let Some(value) = self.entry_in_words(s) {
            let magnitude = value.unsigned_abs();
            return top_bits_of_limbs(&[magnitude as u64, (magnitude >> 64) as u64], value < 0)
                .over(den);
        }
        if let Some((bs, fs)) = &self.word {
            let responses = self.moved.iter().zip(fs).map(|(r, f)| (&r.num[s], *f));
            return word_combination_to_f64(
                std::iter::once((&self.base.num[s], *bs)).chain(responses),
                den,
            );
        }
        top_bits(&self.entry(s)).over(den)
    }
}

#[cfg(test)]
mod tests {
    use crate::factorization::ExactFactorization;
    use crate::lsq::ExactLeastSquares;
    use crate::ring::Int;
    use crate::Simplification;
    use api::{Factorization, IntMatrix, PreparedLeastSquares, Rational, RhsFamily};

    fn q(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    /// Without the content, numerators and denominator are those divided by the GCD of all of
    /// them, for 3, 40 and (in parallel) 1 500 long entries: a content every entry shares;
    /// one that the first entries exceed by a factor (13) the others lack; one that drops to 1
    /// at the first or only at the last entry; with zero entries.
    #[test]
    fn the_content_is_the_gcd_of_every_entry_and_the_denominator() {
        use super::Numerators;
        use num_bigint::BigInt;
        use num_traits::{One, Zero};
        let gcd = |g: BigInt, x: &BigInt| num_integer::Integer::gcd(&g, x);
        let factor: BigInt = BigInt::from(3u32).pow(700) * BigInt::from(1_000_003u32);
        let den: BigInt = &factor * BigInt::from(7u32).pow(900) * 11 * 13;
        for count in [3usize, 40, 1500] {
            let entry = |i: usize| {
                &factor * (BigInt::from(2u32).pow(64 * 60) * 13 * 13 + BigInt::from(13 * i + 1))
            };
            let shared: Vec<BigInt> = (0..count)
                .map(|i| if i % 5 == 2 { BigInt::zero() } else { entry(i) })
                .collect();
            let mut first_exceed = shared.clone();
            for x in first_exceed.iter_mut().take(4) {
                *x *= 13;
            }
            let mut last_lacks = shared.clone();
            *last_lacks.last_mut().expect("entries") = BigInt::from(2u32).pow(64 * 60) + 1;
            let mut first_lacks = shared.clone();
            first_lacks[0] = BigInt::from(5u32).pow(2000) + 1;
            let cases = [
                (shared, true),
                (first_exceed, true),
                (last_lacks, false),
                (first_lacks, false),
            ];
            for (case, (num, whole)) in cases.into_iter().enumerate() {
                let g: BigInt = num.iter().fold(den.clone(), gcd);
                assert_eq!(!g.is_one(), whole);
                if case == 1 && count > 3 {
                    // The first entries' GCD is 13 times the content.
                    let first: BigInt = num[..4].iter().fold(den.clone(), gcd);
                    assert_eq!(first, &g * 13);
                }
                let reduced = Numerators {
                    num: num.clone(),
                    den: den.clone(),
                }
                .without_content();
                assert_eq!(reduced.den, &den / &g, "{count} entries, case {case}");
                let expected: Vec<BigInt> = num.iter().map(|x| x / &g).collect();
                assert_eq!(reduced.num, expected, "{count} entries, case {case}");
            }
        }
    }

    /// Hints on the constraint set (`x0 + x1 = α` with `α = 3` for the hints `(1, 2)`) take the
    /// shortcut through the responses; hints off it take the solve. Both give the least-squares
    /// answer worked out by hand: the change is spread equally over the two unknowns.
    #[test]
    fn hints_on_the_constraint_set_need_no_solve_of_their_own() {
        let a = IntMatrix::from_dense(2, &[vec![1, 1]]).expect("matrix");
        let family = RhsFamily {
            constant: vec![vec![q(0, 1)]],
            coefficients: IntMatrix::from_dense(1, &[vec![-1]]).expect("K"),
        };
        let weights = vec![q(1, 1), q(1, 1)];
        let f = ExactFactorization::<Int>::new(&a, Simplification::Gcd);
        let prepared = f.prepare_least_squares(&family, &weights).expect("prepare");
        let on_set = vec![q(1, 1), q(2, 1)];
        let got = prepared.solve(0, &[q(5, 1)], &on_set).expect("consistent");
        assert_eq!(got, vec![q(2, 1), q(3, 1)]);
        let off_set = vec![q(1, 1), q(1, 1)];
        let got = prepared.solve(0, &[q(5, 1)], &off_set).expect("consistent");
        assert_eq!(got, vec![q(5, 2), q(5, 2)]);
        // Two anchors entering one row: β is any solution of K̂ β = −ρ.
        let family = RhsFamily {
            constant: vec![vec![q(1, 2)]],
            coefficients: IntMatrix::from_dense(2, &[vec![-1, -2]]).expect("K"),
        };
        let prepared = f.prepare_least_squares(&family, &weights).expect("prepare");
        // 1 + 2 = 1/2 + α0 + 2 α1 holds for α = (5/2, 0) and for (1/2, 1).
        let got = prepared
            .solve(0, &[q(1, 2), q(1, 1)], &on_set)
            .expect("consistent");
        assert_eq!(got, vec![q(1, 1), q(2, 1)]);
        let got = prepared
            .solve(0, &[q(3, 2), q(1, 1)], &on_set)
            .expect("consistent");
        assert_eq!(got, vec![q(3, 2), q(5, 2)]);
    }

    /// Hints that translate every unknown (by `d_j` in column `j`) leave residuals off the
    /// anchors' columns in both columns, along the same direction: the first column lifts its
    /// base, the second combines it, and both answers are the fresh ones. Hints along another
    /// direction are lifted on their own.
    #[test]
    fn translated_hints_lift_one_direction_for_all_columns() {
        // x0 − 2 x1 + x2 = 0, x3 = α (anchor), x4 − x0 = c_j, x1 = f_j (a fixed parameter).
        let rows = [
            [1, -2, 1, 0, 0],
            [0, 0, 0, 1, 0],
            [-1, 0, 0, 0, 1],
            [0, 1, 0, 0, 0],
        ];
        let a = IntMatrix::from_dense(5, &rows.map(|r| r.to_vec())).expect("matrix");
        let family = RhsFamily {
            constant: vec![
                vec![q(0, 1), q(0, 1), q(2, 1), q(1, 1)],
                vec![q(0, 1), q(0, 1), q(-1, 3), q(4, 1)],
            ],
            coefficients: IntMatrix::from_dense(1, &[vec![0], vec![-1], vec![0], vec![0]])
                .expect("K"),
        };
        let weights = vec![q(1, 1), q(2, 1), q(1, 1), q(1, 3), q(1, 1)];
        let f = ExactFactorization::<Int>::new(&a, Simplification::Gcd);
        let memoised = f.prepare_least_squares(&family, &weights).expect("prepare");
        // Current values on the constraints (α = 5 in column 0, 7/2 in column 1), translated.
        let current = [
            [q(0, 1), q(1, 1), q(2, 1), q(5, 1), q(2, 1)],
            [q(3, 1), q(4, 1), q(5, 1), q(7, 2), q(8, 3)],
        ];
        let shift = [q(3, 1), q(-5, 2)];
        let hints: Vec<Vec<Rational>> = (0..2)
            .map(|j| current[j].iter().map(|v| v + &shift[j]).collect())
            .collect();
        let alpha = [q(6, 1), q(1, 4)];
        let lifted = || {
            memoised
                .memo
                .lifted_bases
                .load(std::sync::atomic::Ordering::Relaxed)
        };
        for (j, expected_lifts) in [(0, 1), (1, 1)] {
            let fresh = f.prepare_least_squares(&family, &weights).expect("prepare");
            let alpha_j = std::slice::from_ref(&alpha[j]);
            let got = memoised.solve(j, alpha_j, &hints[j]).expect("consistent");
            assert_eq!(got, fresh.solve(j, alpha_j, &hints[j]).expect("consistent"));
            assert_eq!(lifted(), expected_lifts, "column {j}");
            for (i, row) in rows.iter().enumerate() {
                let lhs: Rational = row
                    .iter()
                    .zip(&got)
                    .map(|(c, x)| Rational::from_integer((*c).into()) * x)
                    .sum();
                let k = [0, -1, 0, 0][i];
                let rhs = &family.constant[j][i] - Rational::from_integer(k.into()) * &alpha[j];
                assert_eq!(lhs, rhs, "column {j}, row {i}");
            }
        }
        // Hints moved along another direction need a lifting of their own.
        let other: Vec<Rational> = current[1]
            .iter()
            .enumerate()
            .map(|(s, v)| v + q(s as i64, 1))
            .collect();
        let fresh = f.prepare_least_squares(&family, &weights).expect("prepare");
        let alpha_1 = std::slice::from_ref(&alpha[1]);
        assert_eq!(
            memoised.solve(1, alpha_1, &other).expect("consistent"),
            fresh.solve(1, alpha_1, &other).expect("consistent")
        );
        assert_eq!(lifted(), 2);
    }

    /// A projection in machine words has the numerators and denominator of the one in big
    /// integers (weights other than 1, so `V` enters); a `ρ` beyond a word is left to the big
    /// integers, and `projected` takes them.
    #[test]
    fn projections_in_words_are_those_in_big_integers() {
        use num_bigint::BigInt;
        let rows = [
            vec![1, -2, 1, 0, 0, 0],
            vec![0, 1, -2, 1, 0, 0],
            vec![0, 0, 1, -2, 1, 0],
            vec![0, 0, 0, 1, -2, 1],
        ];
        let a = IntMatrix::from_dense(6, &rows).expect("matrix");
        let family = RhsFamily {
            constant: vec![vec![q(0, 1); 4]],
            coefficients: IntMatrix::from_dense(1, &[vec![-1], vec![0], vec![0], vec![0]])
                .expect("K"),
        };
        let weights = vec![q(1, 1), q(3, 1), q(1, 2), q(5, 1), q(1, 1), q(2, 3)];
        let f = ExactFactorization::<Int>::new(&a, Simplification::Gcd);
        let prepared = f.prepare_least_squares(&family, &weights).expect("prepare");
        let normal = prepared.normal.as_ref().expect("a normal matrix");
        let big = |v: &[i64]| v.iter().map(|&x| BigInt::from(x)).collect::<Vec<_>>();
        for (rho, den) in [
            (vec![1, 0, 0, 0], 1),
            (vec![3, -7, 0, 11], 4),
            (vec![0, 0, 5, -1], 9),
        ] {
            let (rho, den) = (big(&rho), BigInt::from(den));
            let words = prepared
                .projected_in_words(normal, &rho, &den)
                .expect("a small system fits words");
            let lifted = prepared.projected_in_big_integers(normal, &rho, &den);
            assert!(words.num.iter().any(|x| !num_traits::Zero::is_zero(x)));
            assert_eq!(words, lifted);
        }
        let wide = vec![
            BigInt::from(1u8) << 70u32,
            BigInt::from(1),
            BigInt::from(0),
            BigInt::from(-2),
        ];
        let one = BigInt::from(1);
        assert!(prepared.projected_in_words(normal, &wide, &one).is_none());
        assert_eq!(
            prepared.projected(normal, &wide, &one),
            prepared.projected_in_big_integers(normal, &wide, &one)
        );
    }

    /// Updates answered from the memos (same hints, new anchor values) equal fresh solves, and
    /// new hints replace the memo: the memos never change an answer.
    #[test]
    fn memoised_updates_equal_fresh_solves() {
        // Two rows over four unknowns, one anchor coordinate entering both rows.
        let a = IntMatrix::from_dense(4, &[vec![1, -2, 0, 3], vec![0, 1, 5, -1]]).expect("matrix");
        let family = RhsFamily {
            constant: vec![vec![q(1, 2), q(-3, 1)], vec![q(0, 1), q(7, 3)]],
            coefficients: IntMatrix::from_dense(1, &[vec![2], vec![-1]]).expect("K"),
        };
        let weights = vec![q(1, 1), q(2, 1), q(1, 3), q(5, 1)];
        let f = ExactFactorization::<Int>::new(&a, Simplification::Gcd);
        let memoised = f.prepare_least_squares(&family, &weights).expect("prepare");
        let hints_a = vec![q(1, 1), q(-1, 2), q(3, 1), q(0, 1)];
        let hints_b = vec![q(2, 7), q(0, 1), q(1, 1), q(-4, 5)];
        for (column, hints, alpha) in [
            (0, &hints_a, q(0, 1)),
            (0, &hints_a, q(3, 2)),
            (0, &hints_a, q(-7, 1)),
            (1, &hints_a, q(3, 2)),
            (0, &hints_b, q(3, 2)),
            (0, &hints_b, q(1, 9)),
            (0, &hints_a, q(1, 9)),
        ] {
            let fresh = f.prepare_least_squares(&family, &weights).expect("prepare");
            let expected = fresh
                .solve(column, std::slice::from_ref(&alpha), hints)
                .expect("consistent");
            let got = memoised
                .solve(column, std::slice::from_ref(&alpha), hints)
                .expect("consistent");
            assert_eq!(got, expected);
            // The defining equation: A x = c_j − K α.
            for (i, row) in [[1, -2, 0, 3], [0, 1, 5, -1]].iter().enumerate() {
                let lhs: Rational = row
                    .iter()
                    .zip(&got)
                    .map(|(c, x)| Rational::from_integer((*c).into()) * x)
                    .sum();
                let k = [2, -1][i];
                let rhs = &family.constant[column][i] - Rational::from_integer(k.into()) * &alpha;
                assert_eq!(lhs, rhs);
            }
        }
    }

    /// The memo of the combination's scales follows the set of moving anchors: frames where
    /// one anchor stays, then both move, then the other stays give the fresh answers, unreduced
    /// fractions included (by value: a fresh update goes straight from the hints, a memoised
    /// one through their base, over another denominator).
    #[test]
    fn memoised_scales_follow_the_moving_anchors() {
        let a = IntMatrix::from_dense(4, &[vec![1, -2, 0, 3], vec![0, 1, 5, -1]]).expect("matrix");
        let family = RhsFamily {
            constant: vec![vec![q(1, 2), q(-3, 1)]],
            coefficients: IntMatrix::from_dense(2, &[vec![2, 1], vec![-1, 3]]).expect("K"),
        };
        let weights = vec![q(1, 1), q(2, 1), q(1, 3), q(5, 1)];
        let f = ExactFactorization::<Int>::new(&a, Simplification::Gcd);
        let memoised = f.prepare_least_squares(&family, &weights).expect("prepare");
        let hints = vec![q(1, 1), q(-1, 2), q(3, 1), q(0, 1)];
        for alpha in [
            [q(3, 2), q(0, 1)],
            [q(3, 2), q(-5, 7)],
            [q(0, 1), q(-5, 7)],
            [q(1, 3), q(4, 1)],
            [q(0, 1), q(0, 1)],
            [q(2, 1), q(0, 1)],
        ] {
            let fresh = f.prepare_least_squares(&family, &weights).expect("prepare");
            let unreduced = |prepared: &ExactLeastSquares<Int>| -> Vec<Rational> {
                prepared
                    .solve_unreduced(0, &alpha, &hints)
                    .expect("consistent")
                    .expect("unreduced values")
                    .into_iter()
                    .map(|f| f.reduced())
                    .collect()
            };
            assert_eq!(unreduced(&memoised), unreduced(&fresh));
            assert_eq!(
                memoised.solve(0, &alpha, &hints).expect("consistent"),
                fresh.solve(0, &alpha, &hints).expect("consistent")
            );
        }
    }

    /// The preview's entries are those of the combination, each rounded over the denominator
    /// as `fraction_to_f64` rounds it, bit for bit: with numerators in `i128`; long numerators
    /// with word-sized scales (summed in limbs); scales beyond a word; no moving coordinate.
    #[test]
    fn previews_round_the_combination_entry_by_entry() {
        use super::{combine, combine_to_f64, Numerators};
        use crate::qvec::QVec;
        use num_bigint::BigInt;
        let long = |seed: i64, bits: u32| -> BigInt {
            (BigInt::from(seed) << bits)
                + BigInt::from(seed * 7919 - 3) * (BigInt::from(3) << (bits / 2))
        };
        for bits in [10u32, 300, 4_000] {
            let base = Numerators {
                num: (-4..5).map(|i| long(i * 13 + 1, bits)).collect(),
                den: long(5, bits / 2),
            };
            let responses: Vec<Numerators> = (0..3)
                .map(|k| Numerators {
                    num: (-4..5).map(|i| long(i * (k + 2) - 11, bits)).collect(),
                    // Over multiples of the base's denominator, as the responses of a
                    // solve: the scales stay small.
                    den: &base.den * (k + 1),
                })
                .collect();
            for alpha in [
                vec![q(3, 2), q(0, 1), q(-7, 1)],
                vec![q(1, 3), q(-5, 7), q(11, 5)],
                // Scales beyond a word.
                vec![
                    Rational::new(long(3, 90), BigInt::from(7)),
                    q(1, 1),
                    q(0, 1),
                ],
                vec![q(0, 1), q(0, 1), q(0, 1)],
            ] {
                let alpha = QVec::<Int>::from_rationals(&alpha);
                let exact = combine(&base, None, &responses, &alpha);
                let rounded: Vec<f64> = exact
                    .num
                    .iter()
                    .map(|n| api::exact::fraction_to_f64(n, &exact.den))
                    .collect();
                let preview = combine_to_f64(&base, None, &responses, &alpha);
                let bits_of = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits_of(&preview), bits_of(&rounded), "{bits} bits");
            }
        }
    }

    /// Fraction-free Gauss–Jordan: a solution with the free unknown at zero, checked against
    /// every equation; an inconsistent system refused.
    #[test]
    fn consistent_integer_equations_are_solved_and_inconsistent_ones_refused() {
        let int = |v: &[i64]| {
            v.iter()
                .map(|x| num_bigint::BigInt::from(*x))
                .collect::<Vec<_>>()
        };
        // 2 b0 + 3 b1 = 5, 4 b0 + 6 b1 = 10 (dependent), 3 b2 = −7: b1 free.
        let rows = vec![int(&[2, 3, 0, 5]), int(&[4, 6, 0, 10]), int(&[0, 0, 3, -7])];
        let beta = super::solve_consistent(rows.clone(), 3).expect("consistent");
        let beta: Vec<Rational> = beta.into_iter().map(|(n, d)| Rational::new(n, d)).collect();
        assert_eq!(beta, vec![q(5, 2), q(0, 1), q(-7, 3)]);
        for row in &rows {
            let lhs: Rational = row[..3]
                .iter()
                .zip(&beta)
                .map(|(a, b)| Rational::from_integer(a.clone()) * b)
                .sum();
            assert_eq!(lhs, Rational::from_integer(row[3].clone()));
        }
        let inconsistent = vec![int(&[2, 3, 0, 5]), int(&[4, 6, 0, 11])];
        assert!(super::solve_consistent(inconsistent, 3).is_none());
    }
}
