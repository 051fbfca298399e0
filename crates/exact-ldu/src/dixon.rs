//! Dixon's p-adic lifting: the exact solution of `A x = b` for a nonsingular integer matrix `A`,
//! at a cost that follows the size of the answer (J. D. Dixon, "Exact solution of linear
//! equations using p-adic expansions", Numer. Math. 40, 1982; FLINT's `fmpz_mat_solve_dixon`
//! follows the same scheme).
//!
//! With `C = A⁻¹ mod p` (a factoring modulo a word-sized prime: sparse `L D Lᵀ` in a
//! fill-reducing order for symmetric matrices, dense LU otherwise), `r₀ = b` and
//!
//! ```text
//! xᵢ = C rᵢ mod p,    rᵢ₊₁ = (rᵢ − A xᵢ) / p        (an exact division),
//! ```
//!
//! `X_k = Σ_{i<k} xᵢ pⁱ` satisfies `A X_k = b − p^k r_k`, so `X_k ≡ x (mod p^k)`. Rational
//! reconstruction of `X_k` gives `x = numerators / denominator` as soon as `p^k > 2 N D` (`N`
//! and `D` bounding the numerators and the denominator). Every candidate is verified exactly
//! (`A · numerators = denominator · b`), so the answer is certain whatever the prime: the prime
//! only decides the speed. Attempts at `k = 8, 16, 24, …, ⌈1.25 k⌉, …` (or first at the length
//! the last solve with this matrix needed) make the work follow the actual size of the answer;
//! the Hadamard bound caps `k`, so the lifting always ends. Attempts reconstruct three fixed
//! combinations of the entries only; once they give a denominator `d`, a second lifting of `d b`
//! with balanced digits gives the numerators directly ([`LiftingSolver::solve`]).
//!
//! Why not fraction-free elimination here: the least-squares systems of edits on real meshes
//! have solutions with thousands of digits; elimination pays for every digit at every one of its
//! `n³` steps, lifting pays `n²` word operations per 31 bits of the answer.
//!
//! Complexity: the factoring once per matrix (`n³/3` dense, `Σ_j |L_{:,j}|²` sparse), then per
//! right-hand side `2k (2 nnz(L) + nnz(A))` word operations (`n²` for `nnz(L)` when dense) for
//! `k ≈ (bits of numerators + denominator) / 31` steps of each phase, plus combining the digits.

use crate::bareiss_small::{self, SmallBareiss};
use crate::ldlt_symbolic::fill_reducing_order;
use crate::modular::{lifting_primes, ModularLu, Modulus, SparseLdlt};
use num_bigint::{BigInt, BigUint, Sign};
use num_integer::Integer;
use num_traits::{One, Signed, ToPrimitive, Zero};
use rayon::prelude::*;
use std::sync::OnceLock;

/// Residuals below this size stay in `i128` (with `|A| < 2^62` and digits below `2^31`, one
/// lifting step keeps them there).
const SMALL_RESIDUAL_BITS: u64 = 100;

/// Bits per lifting step, a lower bound of `log₂ p` for every prime used.
const BITS_PER_STEP: u64 = 30;

/// The rows as machine integers when they all fit (below `2^62`), and the Hadamard bound
/// `Σ_j ⌈log₂ ‖A_{:,j}‖⌉`.
type Bounds = (Option<Vec<Vec<(usize, i64)>>>, u64);

/// A nonsingular square integer matrix prepared for solving by lifting.
#[derive(Debug, Clone)]
pub(crate) struct LiftingSolver {
    n: usize,
    /// The rows as big integers: given, or made from `small_rows` when a solve first lifts
    /// (the small normal matrices of a generic edit are solved in words and never need them).
    rows: OnceLock<Vec<Vec<(usize, BigInt)>>>,
    /// The rows again, when every entry is below `2^62` in absolute value.
    small_rows: Option<Vec<Vec<(usize, i64)>>>,
    /// `A` eliminated fraction-free in `i128`, for small positive definite matrices: their
    /// solves are exact without lifting while the numbers fit.
    small: Option<SmallBareiss>,
    /// `A⁻¹ mod p`: made when the solver is made, or (beside `small`) at the first solve that
    /// lifts.
    inverse: OnceLock<ModularInverse>,
    /// `Σ_j ⌈log₂ ‖A_{:,j}‖⌉`, an upper bound of `log₂ |det A|` (Hadamard).
    hadamard_bits: u64,
    /// Steps the last solve needed: the first attempt of the next one (solves with one matrix
    /// have answers of about one size, and each failed attempt costs a reconstruction).
    last_steps: StepsMemo,
}

/// A memo of the lifting length; copies start with the same value, and two memos always compare
/// equal (it changes only the speed of a solve, never its answer).
#[derive(Debug, Default)]
struct StepsMemo(std::sync::atomic::AtomicUsize);

impl StepsMemo {
    fn get(&self) -> usize {
        self.0.load(std::sync::atomic::Ordering::Relaxed)
    }

    fn set(&self, steps: usize) {
        self.0.store(steps, std::sync::atomic::Ordering::Relaxed);
    }
}

impl Clone for StepsMemo {
    fn clone(&self) -> Self {
        StepsMemo(std::sync::atomic::AtomicUsize::new(self.get()))
    }
}

impl PartialEq for StepsMemo {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl Eq for StepsMemo {}

/// `⌈log₂ ‖v‖₂⌉` (an upper bound) from the exact sum of squares.
fn norm_bits<'a>(entries: impl Iterator<Item = &'a BigInt>) -> u64 {
    let squares: BigInt = entries.map(|v| v * v).sum();
    squares.bits().div_ceil(2)
}

/// `A⁻¹ mod p` as a factoring.
#[derive(Debug, Clone, PartialEq, Eq)]
enum ModularInverse {
    Dense(ModularLu),
    Sparse(SparseLdlt),
}

impl ModularInverse {
    fn modulus(&self) -> Modulus {
        match self {
            ModularInverse::Dense(lu) => lu.modulus(),
            ModularInverse::Sparse(ldlt) => ldlt.modulus(),
        }
    }

    fn solve_in_place(&self, b: &mut [u64], scratch: &mut Vec<u64>) {
        match self {
            ModularInverse::Dense(lu) => lu.solve_in_place(b, scratch),
            ModularInverse::Sparse(ldlt) => ldlt.solve_in_place(b, scratch),
        }
    }
}

/// How many primes the sparse symmetric factoring tries before the dense one takes over: a
/// prime fails only when it divides one of the leading principal minors, so a second failure is
/// already a rarity.
const SPARSE_ATTEMPTS: usize = 4;

/// The residues of `rows` modulo `modulus`, zeros dropped.
fn residue_rows(rows: &[Vec<(usize, BigInt)>], modulus: &Modulus) -> Vec<Vec<(usize, u64)>> {
    rows.iter()
        .map(|row| {
            row.iter()
                .map(|(j, v)| (*j, modulus.residue_big(v)))
                .filter(|(_, r)| *r != 0)
                .collect()
        })
        .collect()
}

/// Solvers of the same matrix are equal, whichever of their parts were made yet (the big-integer
/// rows and the modular inverse are functions of the matrix).
impl PartialEq for LiftingSolver {
    fn eq(&self, other: &Self) -> bool {
        self.n == other.n
            && self.rows() == other.rows()
            && self.small_rows == other.small_rows
            && self.small == other.small
            && self.hadamard_bits == other.hadamard_bits
    }
}

impl Eq for LiftingSolver {}

/// Entries of a matrix kept in machine words are below this in absolute value.
const SMALL_ENTRY_LIMIT: u64 = 1 << 62;

/// Machine-word rows as big integers.
fn big_rows(words: &[Vec<(usize, i64)>]) -> Vec<Vec<(usize, BigInt)>> {
    words
        .iter()
        .map(|row| row.iter().map(|(j, v)| (*j, BigInt::from(*v))).collect())
        .collect()
}

/// The squared norms of the columns of `n`-column machine-word rows, `None` when one leaves a
/// `u128` (each square is below `2^124`).
fn word_column_squares(n: usize, rows: &[Vec<(usize, i64)>]) -> Option<Vec<u128>> {
    let mut squares = vec![0u128; n];
    for row in rows {
        for (j, v) in row {
            let v = v.unsigned_abs() as u128;
            squares[*j] = squares[*j].checked_add(v * v)?;
        }
    }
    Some(squares)
}

/// `Σ_j ⌈log₂ √s_j⌉` of the squared column norms `s_j`, `None` when a column is zero.
fn hadamard_bits_of_squares(squares: &[u128]) -> Option<u64> {
    if squares.contains(&0) {
        return None;
    }
    // ⌈log₂ √s⌉ = ⌈bits(s) / 2⌉, as `norm_bits` computes it.
    Some(
        squares
            .iter()
            .map(|s| u64::from(u128::BITS - s.leading_zeros()).div_ceil(2))
            .sum(),
    )
}

impl LiftingSolver {
    /// Prepares a symmetric positive definite `A` (`n × n`, both triangles given as sparse
    /// rows, column indices increasing): `L D Lᵀ` modulo a prime in a fill-reducing order, so
    /// factoring and lifting follow the sparsity of `A`. Falls back to [`LiftingSolver::new`]
    /// (dense, any nonsingular matrix) when no prime tried gives nonzero pivots; `None` when
    /// `A` is singular.
    pub(crate) fn new_symmetric(n: usize, rows: Vec<Vec<(usize, BigInt)>>) -> Option<Self> {
        debug_assert_eq!(rows.len(), n);
        if n <= bareiss_small::MAX_ORDER {
            let (small_rows, hadamard_bits) = Self::bounds(n, &rows)?;
            if let Some(small) = small_rows.as_ref().and_then(|r| SmallBareiss::factor(n, r)) {
                // Nonsingular (its determinant is the last pivot, nonzero): the modular
                // inverse waits for a solve that overflows.
                return Some(Self::from_parts(
                    n,
                    OnceLock::from(rows),
                    (small_rows, hadamard_bits),
                    Some(small),
                    OnceLock::new(),
                ));
            }
        }
        Self::lifted_symmetric(n, rows)
    }

    /// A symmetric positive definite `A` (`n × n`, both triangles given as sparse rows of
    /// machine integers) prepared by fraction-free elimination in words alone
    /// ([`SmallBareiss`]): `None` when a pivot is zero or a value reaches `2^62`. Never a
    /// modular factoring: a `Some` is an exact proof that `A` is nonsingular (its determinant
    /// is the last pivot), which [`crate::ExactFactorization`] takes as the proof that the rows
    /// of a matrix whose Gram matrix this is are independent.
    pub(crate) fn small_symmetric(n: usize, words: &[Vec<(usize, i64)>]) -> Option<Self> {
        let small = SmallBareiss::factor(n, words)?;
        let fits = words
            .iter()
            .flatten()
            .all(|(_, v)| v.unsigned_abs() < SMALL_ENTRY_LIMIT);
        let squares = fits.then(|| word_column_squares(n, words)).flatten();
        let (rows, bounds) = match squares {
            // The big-integer rows wait for a solve that lifts.
            Some(squares) => (
                OnceLock::new(),
                (Some(words.to_vec()), hadamard_bits_of_squares(&squares)?),
            ),
            None => {
                let rows = big_rows(words);
                let bounds = Self::bounds(n, &rows)?;
                (OnceLock::from(rows), bounds)
            }
        };
        Some(Self::from_parts(
            n,
            rows,
            bounds,
            Some(small),
            OnceLock::new(),
        ))
    }

    /// [`LiftingSolver::new_symmetric`] without the fraction-free path: every solve lifts.
    fn lifted_symmetric(n: usize, rows: Vec<Vec<(usize, BigInt)>>) -> Option<Self> {
        let order = fill_reducing_order(&rows);
        for p in lifting_primes().take(SPARSE_ATTEMPTS) {
            let modulus = Modulus::new(p);
            if let Some(ldlt) = SparseLdlt::factor(&residue_rows(&rows, &modulus), &order, modulus)
            {
                return Self::with_inverse(n, rows, ModularInverse::Sparse(ldlt));
            }
        }
        Self::new(n, rows)
    }

    /// The solver for `A` with `A⁻¹ mod p` given; `None` when a column of `A` is zero.
    fn with_inverse(
        n: usize,
        rows: Vec<Vec<(usize, BigInt)>>,
        inverse: ModularInverse,
    ) -> Option<Self> {
        let bounds = Self::bounds(n, &rows)?;
        Some(Self::from_parts(
            n,
            OnceLock::from(rows),
            bounds,
            None,
            OnceLock::from(inverse),
        ))
    }

    /// The solver from its parts: `bounds` as [`LiftingSolver::bounds`] gives them.
    fn from_parts(
        n: usize,
        rows: OnceLock<Vec<Vec<(usize, BigInt)>>>,
        (small_rows, hadamard_bits): Bounds,
        small: Option<SmallBareiss>,
        inverse: OnceLock<ModularInverse>,
    ) -> Self {
        LiftingSolver {
            n,
            rows,
            small_rows,
            small,
            inverse,
            hadamard_bits,
            last_steps: StepsMemo::default(),
        }
    }

    /// The rows as machine integers when they all fit, and the Hadamard bound; `None` when a
    /// column of `A` is zero (`A` singular).
    fn bounds(n: usize, rows: &[Vec<(usize, BigInt)>]) -> Option<Bounds> {
        let small_rows = rows
            .iter()
            .map(|row| {
                row.iter()
                    .map(|(j, v)| {
                        v.to_i64()
                            .filter(|x| x.unsigned_abs() < SMALL_ENTRY_LIMIT)
                            .map(|x| (*j, x))
                    })
                    .collect::<Option<Vec<_>>>()
            })
            .collect::<Option<Vec<_>>>();
        // Squared column norms in machine words while they fit.
        let word_norms = small_rows
            .as_ref()
            .and_then(|small| word_column_squares(n, small));
        let hadamard_bits = match word_norms {
            Some(squares) => hadamard_bits_of_squares(&squares)?,
            None => {
                let mut columns: Vec<Vec<&BigInt>> = vec![Vec::new(); n];
                for row in rows {
                    for (j, v) in row {
                        if !v.is_zero() {
                            columns[*j].push(v);
                        }
                    }
                }
                if columns.iter().any(Vec::is_empty) {
                    return None;
                }
                columns.iter().map(|c| norm_bits(c.iter().copied())).sum()
            }
        };
        Some((small_rows, hadamard_bits))
    }

    /// Prepares `A` (`n × n`, sparse rows with column indices below `n`), factored densely
    /// modulo a prime; `None` when `A` is singular.
    pub(crate) fn new(n: usize, rows: Vec<Vec<(usize, BigInt)>>) -> Option<Self> {
        debug_assert_eq!(rows.len(), n);
        let bounds = Self::bounds(n, &rows)?;
        let inverse = Self::dense_inverse(n, &rows, bounds.1)?;
        Some(Self::from_parts(
            n,
            OnceLock::from(rows),
            bounds,
            None,
            OnceLock::from(inverse),
        ))
    }

    /// `A⁻¹` modulo the first lifting prime that does not divide `det A`, factored densely;
    /// `None` when `A` is singular.
    fn dense_inverse(
        n: usize,
        rows: &[Vec<(usize, BigInt)>],
        hadamard_bits: u64,
    ) -> Option<ModularInverse> {
        // A prime that divides det A ≠ 0 is at least 2^30, so more than
        // `hadamard_bits / 30` such primes prove det A = 0.
        let mut failures = 0u64;
        for p in lifting_primes() {
            let modulus = Modulus::new(p);
            if let Some(lu) = ModularLu::factor(n, &residue_rows(rows, &modulus), modulus) {
                return Some(ModularInverse::Dense(lu));
            }
            failures += 1;
            if failures * BITS_PER_STEP > hadamard_bits {
                return None;
            }
        }
        None
    }

    /// The rows as big integers, made now from the machine-word rows if not given.
    fn rows(&self) -> &[Vec<(usize, BigInt)>] {
        self.rows.get_or_init(|| {
            big_rows(
                self.small_rows
                    .as_ref()
                    .expect("a solver is given its big-integer rows unless it keeps them in words"),
            )
        })
    }

    /// `A⁻¹ mod p`, made now if the solver was made without it.
    fn inverse(&self) -> &ModularInverse {
        self.inverse.get_or_init(|| {
            Self::dense_inverse(self.n, self.rows(), self.hadamard_bits).expect(
                "a matrix with a nonzero fraction-free determinant is nonsingular modulo some \
                 lifting prime",
            )
        })
    }

    /// [`LiftingSolver::solve`] of a right-hand side of machine words, when `A` was prepared
    /// by fraction-free elimination in words and every value on the way fits one; `None`
    /// otherwise (then [`LiftingSolver::solve`] answers).
    pub(crate) fn solve_in_words(&self, b: &[i64]) -> Option<(Vec<i64>, i64)> {
        self.small.as_ref()?.solve_words(b)
    }

    /// The exact solution of `A x = b` as `(numerators, denominator)`, denominator positive.
    ///
    /// Two phases. Lifting `b`, attempts reconstruct only three combinations of the entries
    /// until they give a denominator `d`; then `d b` is lifted with balanced digits, whose
    /// solution `d x` is an integer vector: its p-adic expansion ends, the residual becomes
    /// exactly zero, and the digits are the numerators — no reconstruction of the entries, no
    /// division by `p^k`, and no verification (a zero residual is `A · numerators = d b`
    /// exactly). Should the combinations have cancelled a factor of the denominator (the second
    /// phase then runs to its bound without ending), the entries are completed and verified.
    pub(crate) fn solve(&self, b: &[BigInt]) -> (Vec<BigInt>, BigInt) {
        debug_assert_eq!(b.len(), self.n);
        let n = self.n;
        if n == 0 {
            return (Vec::new(), BigInt::one());
        }
        if let Some(solution) = self.small.as_ref().and_then(|s| s.solve(b)) {
            return solution;
        }
        let p = self.inverse().modulus().prime();
        // Cramer and Hadamard: |den| ≤ 2^H, |num_i| ≤ ‖b‖ 2^H; p^k > 2 N D suffices.
        let b_bits = norm_bits(b.iter());
        let last_step =
            ((2 * self.hadamard_bits + b_bits + 2).div_ceil(BITS_PER_STEP) + 1) as usize;
        let mut lifting = Lifting::new(self, b, false);
        let mut combining = true;
        let hint = self.last_steps.get();
        let mut next_attempt = if hint > 0 {
            hint.min(last_step)
        } else {
            FIRST_ATTEMPT
        };
        loop {
            lifting.step(self);
            let step = lifting.steps;
            if step == next_attempt || step >= last_step || lifting.residual.is_zero() {
                if combining {
                    if let Some(den) = self.mixed_denominator(&lifting.mix, step, p) {
                        if let Some(solution) = self.solve_scaled(b, den, step) {
                            self.last_steps.set(step);
                            return solution;
                        }
                        // A wrong candidate at the early attempt (few digits allow one) is
                        // cheap to have tried; past it, reconstruct every entry instead.
                        combining = step < SECOND_ATTEMPT;
                    }
                }
                if !combining || step >= last_step {
                    if let Some(solution) = self.reconstruct(&lifting.digits, step, p, b) {
                        self.last_steps.set(step);
                        return solution;
                    }
                }
                assert!(
                    step < last_step,
                    "p-adic lifting: reconstruction failed beyond the Hadamard bound"
                );
                // Attempts are cheap next to lifting (a failed one stops at the first entry
                // that does not reconstruct): step by a quarter, overshooting the needed
                // length by at most 25 % (doubling would waste up to half).
                // After a hinted attempt the answer is only a little longer than the last.
                // After the early attempt for small answers, the schedule of longer ones.
                let stride = if step == hint { step / 16 } else { step / 4 };
                next_attempt = if step < SECOND_ATTEMPT {
                    SECOND_ATTEMPT
                } else {
                    step + stride.max(8)
                }
                .min(last_step);
            }
        }
    }

    /// The least common denominator of the combinations `z_m = Σᵢ c_{m,i} xᵢ` (the
    /// [`mixing_weights`]), reconstructed from their first `k` digits (`mix`: per step
    /// `Σᵢ c_{m,i} xᵢ,ₜ`, carries not yet propagated), when all reconstruct within the bounds:
    /// the common denominator of the whole solution unless the weights happen to cancel a factor
    /// (a candidate either way: a wrong one only costs the second phase its length). A factor
    /// of the denominator cannot hide in entries nobody looked at, as it did with sampled
    /// entries on the figure mesh's δ_max = 40 solves: a 1 260-bit factor that 31–47 % of the
    /// 2 814 entries have was missed by every one of five, then sixteen, samples, and the second
    /// phase ran its whole length of 3 362 steps (1 450 would have ended it), then reconstructed
    /// and verified every entry.
    fn mixed_denominator(&self, mix: &[[i128; MIXTURES]], k: usize, p: u64) -> Option<BigUint> {
        let powers = PadicPowers::new(p, k);
        let modulus = BigUint::from(p).pow(k as u32);
        let signed_modulus = BigInt::from(modulus.clone());
        let values = (0..MIXTURES)
            .map(|m| {
                let column: Vec<i128> = mix[..k].iter().map(|step| step[m]).collect();
                let z = powers.combine_by(&column, &|d| BigInt::from(d));
                z.mod_floor(&signed_modulus).into_parts().1
            })
            .collect();
        let bounds = ReconstructionBounds::new(&modulus, self.hadamard_bits);
        over_one_denominator(values, &modulus, &bounds).map(|(_, den)| den)
    }

    /// The second phase: `A y = d b` lifted for `k` steps with balanced digits, so that
    /// `Yᵢ = Σ_t d_{t,i} p^t` is `d xᵢ` in the symmetric range modulo `p^k` — no product
    /// `d · Xᵢ`, no division by `p^k`. An entry whose `Yᵢ` is within the numerator bound is a
    /// numerator over `d` as it stands; one that is not (`d` lacks a factor of its
    /// denominator) is reconstructed, and the factor found joins the common denominator.
    /// When the residual vanishes, `d x` is an integer vector and the digits are exact.
    ///
    /// `d b` is never formed: the base-`p` digits `d_t` of `d` enter one per step (`d_t b` added
    /// to the residual before step `t`), so the residual stays as small as in the first phase.
    /// `None` when an entry does not reconstruct within the bounds.
    fn solve_scaled(&self, b: &[BigInt], den: BigUint, k: usize) -> Option<(Vec<BigInt>, BigInt)> {
        let p = self.inverse().modulus().prime();
        let n = self.n;
        let feed = Feed::new(b, base_p_digits(&den, p));
        if feed.digits.len() > k {
            return None;
        }
        let zero = vec![BigInt::zero(); n];
        let mut lifting = Lifting::new(self, &zero, true);
        let mut exact = false;
        while lifting.steps < k {
            if let Some(&digit) = feed.digits.get(lifting.steps) {
                lifting.residual.add_scaled(&feed, digit);
            }
            lifting.step(self);
            if lifting.steps >= feed.digits.len() && lifting.residual.is_zero() {
                exact = true;
                break;
            }
        }
        let steps = lifting.steps;
        let scaled = combine_entries(&lifting.digits, n, steps, p, true);
        let den = BigInt::from(den);
        if exact {
            // A · scaled = d b exactly: nothing to reconstruct or verify.
            return Some((scaled, den));
        }
        let modulus = BigInt::from(BigUint::from(p).pow(steps as u32));
        let bounds = ReconstructionBounds::new(modulus.magnitude(), self.hadamard_bits);
        let mut extra = BigUint::one();
        let mut numerators: Vec<BigInt> = Vec::with_capacity(n);
        for y in scaled {
            // Within the bound, `y` is `d xᵢ` itself (the only fraction within the bounds with
            // its residue has denominator 1), so its numerator over `d · extra` is `y · extra`:
            // no product modulo `p^k`, which only an entry that still needs a factor takes.
            if y.magnitude() <= &bounds.numerator {
                numerators.push(if extra.is_one() {
                    y
                } else {
                    y * BigInt::from(extra.clone())
                });
                continue;
            }
            let y = if extra.is_one() {
                y
            } else {
                symmetric_residue(
                    (y * BigInt::from(extra.clone()))
                        .mod_floor(&modulus)
                        .magnitude()
                        .clone(),
                    modulus.magnitude(),
                )
            };
            if y.magnitude() <= &bounds.numerator {
                numerators.push(y);
                continue;
            }
            let residue = y.mod_floor(&modulus).magnitude().clone();
            let room = &bounds.denominator / (den.magnitude() * &extra);
            let (a, d) =
                rational_reconstruction(&residue, modulus.magnitude(), &bounds.numerator, &room)?;
            let scale = BigInt::from(d.clone());
            for num in &mut numerators {
                *num *= &scale;
            }
            extra *= d;
            numerators.push(a);
        }
        self.verified(numerators, den * BigInt::from(extra), b)
    }

    /// Reconstructs the rational solution from `k` p-adic digits per entry and verifies it.
    fn reconstruct(
        &self,
        digits: &[u32],
        k: usize,
        p: u64,
        b: &[BigInt],
    ) -> Option<(Vec<BigInt>, BigInt)> {
        let (numerators, den) = self.reconstruct_entries(digits, k, p)?;
        self.verified(numerators, BigInt::from(den), b)
    }

    /// The candidate `numerators / den` when `A · numerators = den · b` holds exactly.
    fn verified(
        &self,
        numerators: Vec<BigInt>,
        den: BigInt,
        b: &[BigInt],
    ) -> Option<(Vec<BigInt>, BigInt)> {
        let words = (den.bits() / 64) as usize + 1;
        let rows = self.rows();
        let holds = rows
            .par_iter()
            .with_min_len(entries_per_task(rows.len(), words))
            .zip(b)
            .all(|(row, bi)| {
                let lhs: BigInt = row.iter().map(|(j, v)| v * &numerators[*j]).sum();
                lhs == &den * bi
            });
        holds.then_some((numerators, den))
    }

    /// The numerators of every entry over one denominator, reconstructed from `k` digits per
    /// entry, the denominator growing by the factor each entry needs; `None` at the first entry
    /// that does not reconstruct within the bounds.
    fn reconstruct_entries(
        &self,
        digits: &[u32],
        k: usize,
        p: u64,
    ) -> Option<(Vec<BigInt>, BigUint)> {
        let n = self.n;
        let modulus = BigUint::from(p).pow(k as u32);
        // The entries' p-adic values (the bulk of the work); the denominator then grows entry
        // by entry.
        let values: Vec<BigUint> = combine_entries(digits, n, k, p, false)
            .into_iter()
            .map(|v| v.into_parts().1)
            .collect();
        let bounds = ReconstructionBounds::new(&modulus, self.hadamard_bits);
        over_one_denominator(values, &modulus, &bounds)
    }
}

/// The fractions with residues `values` modulo `modulus` over one denominator, which grows by
/// the factor each value needs (so it is their least common denominator); `None` at the first
/// value that does not reconstruct within the bounds.
fn over_one_denominator(
    values: Vec<BigUint>,
    modulus: &BigUint,
    bounds: &ReconstructionBounds,
) -> Option<(Vec<BigInt>, BigUint)> {
    let ReconstructionBounds {
        numerator: num_bound,
        denominator: den_bound,
    } = bounds;
    let mut den = BigUint::one();
    let mut numerators: Vec<BigInt> = Vec::with_capacity(values.len());
    for x in values {
        let y = (&den * &x) % modulus;
        let symmetric = symmetric_residue(y.clone(), modulus);
        if symmetric.magnitude() <= num_bound {
            numerators.push(symmetric);
            continue;
        }
        // x ≡ (numerator / den) would need a larger numerator: den · x ≡ a / d.
        let (a, d) = rational_reconstruction(&y, modulus, num_bound, &(den_bound / &den))?;
        let scale = BigInt::from(d.clone());
        for num in &mut numerators {
            *num *= &scale;
        }
        den *= &d;
        numerators.push(a);
    }
    Some((numerators, den))
}

/// Bounds `N`, `D` on the numerators and the denominator with `2 N D < p^k`, so that a
/// fraction within them is the only one with its residue.
struct ReconstructionBounds {
    numerator: BigUint,
    denominator: BigUint,
}

impl ReconstructionBounds {
    /// The denominator divides `det A`, so `D` never needs to exceed the Hadamard bound; what
    /// is left goes to the numerators (large right-hand sides give large numerators over small
    /// denominators). Powers of two: `2 N D = 2^(bits(p^k) − 2) < p^k`.
    fn new(modulus: &BigUint, hadamard_bits: u64) -> Self {
        let budget = modulus.bits().saturating_sub(3);
        let den_bits = (budget / 2).min(hadamard_bits);
        ReconstructionBounds {
            numerator: BigUint::one() << (budget - den_bits),
            denominator: BigUint::one() << den_bits,
        }
    }
}

/// The step of the first reconstruction attempt of a solve with no hint from the last one.
/// Small answers (point systems, the null vectors of the propagation analysis: numerators and
/// denominators of a few digits) reconstruct after one or two steps; a failed attempt costs one
/// rational reconstruction, far less than the steps it may save (and it sets the hint of the
/// solves that follow).
const FIRST_ATTEMPT: usize = 2;

/// The second attempt, from which attempts follow every quarter of the steps so far.
const SECOND_ATTEMPT: usize = 8;

/// `2^64 / φ` (φ the golden ratio), rounded to odd: `i · GOLDEN mod 2^64` spreads `i = 1, 2, …`
/// evenly over the words (Fibonacci hashing).
const GOLDEN: u64 = 0x9E37_79B9_7F4A_7C15;

/// How many combinations of the entries the first phase reconstructs. One alone is no test:
/// almost every residue is some fraction with numerator and denominator near `√(p^k)`, and
/// such a false denominator would send the second phase to its whole length. A false one
/// leaves no room for the next combination's factor (as sampled entries did before), while the
/// true one fits them all.
const MIXTURES: usize = 3;

/// The weights `c_{m,i} ∈ [1, 256]` of combination `m` ([`LiftingSolver::mixed_denominator`]):
/// fixed (a solve is reproducible) and irregular (no pattern of the unknowns' order to line up
/// with): the top byte of SplitMix64's finaliser of `i · GOLDEN` and `m`.
fn mixing_weights(n: usize) -> Vec<[i64; MIXTURES]> {
    (1..=n as u64)
        .map(|i| {
            std::array::from_fn(|m| {
                let mut z =
                    i.wrapping_mul(GOLDEN) ^ (m as u64 + 1).wrapping_mul(0xBF58_476D_1CE4_E5B9);
                z ^= z >> 31;
                z = z.wrapping_mul(0x94D0_49BB_1331_11EB);
                z ^= z >> 29;
                1 + (z >> 56) as i64
            })
        })
        .collect()
}

/// Entries per parallel task where the entries of a solution are combined or checked
/// independently (each a few big-integer products).
const ENTRIES_PER_TASK: usize = 16;

/// Below this many `entries × words per entry`, per-entry loops run on the calling thread:
/// handing work to rayon costs tens of microseconds (more from a thread outside its pool).
const PARALLEL_WORDS: usize = 1 << 14;

/// The smallest number of entries per parallel task for `entries` entries of about `words`
/// words each: all of them (no split, the calling thread) when the work is small.
pub(crate) fn entries_per_task(entries: usize, words: usize) -> usize {
    if entries.saturating_mul(words) < PARALLEL_WORDS {
        entries.max(1)
    } else {
        ENTRIES_PER_TASK
    }
}

/// The digits of `v` in base `p`, least significant first.
fn base_p_digits(v: &BigUint, p: u64) -> Vec<u64> {
    let mut digits = Vec::new();
    let mut rest = v.clone();
    let p = BigUint::from(p);
    while !rest.is_zero() {
        let (q, r) = rest.div_rem(&p);
        digits.push(r.to_u64().unwrap_or(0));
        rest = q;
    }
    digits
}

/// The right-hand side `b` of the second phase, fed into the residual scaled by one digit of the
/// denominator per step.
struct Feed {
    big: Vec<BigInt>,
    /// `b` as machine integers when every entry is below `2^62` (then `digit · b` stays below
    /// `2^93` and a small residual stays small).
    small: Option<Vec<i128>>,
    digits: Vec<u64>,
}

impl Feed {
    fn new(b: &[BigInt], digits: Vec<u64>) -> Self {
        let small = b
            .iter()
            .map(|v| (v.bits() < 62).then(|| v.to_i128().unwrap_or(0)))
            .collect();
        Feed {
            big: b.to_vec(),
            small,
            digits,
        }
    }
}

/// `Σ_t δ_{t,i} p^t` for every entry `i < n`, from `steps` digits laid out step by step
/// (`digits[t·n + i] ∈ [0, p)`), balanced into `(−p/2, p/2]` when `balanced`: all entries at
/// once in IFMA lanes where they apply ([`crate::padic_lanes`]), otherwise each entry by halves,
/// in parallel (a few balanced multiplications each).
fn combine_entries(digits: &[u32], n: usize, steps: usize, p: u64, balanced: bool) -> Vec<BigInt> {
    crate::padic_lanes::combine(digits, n, steps, p, balanced).unwrap_or_else(|| {
        let powers = PadicPowers::new(p, steps);
        (0..n)
            .into_par_iter()
            .with_min_len(entries_per_task(n, steps / 2))
            .map_init(
                || Vec::with_capacity(steps),
                |column, i| {
                    column.clear();
                    column.extend((0..steps).map(|t| {
                        let d = digits[t * n + i];
                        if balanced {
                            balanced_digit(d, p)
                        } else {
                            i64::from(d)
                        }
                    }));
                    powers.combine_signed(column)
                },
            )
            .collect()
    })
}

/// The digit `d ∈ [0, p)` as the balanced digit in `(−p/2, p/2]`.
fn balanced_digit(d: u32, p: u64) -> i64 {
    let d = i64::from(d);
    let p = p as i64;
    if 2 * d > p {
        d - p
    } else {
        d
    }
}

/// The state of one lifting: the residual, the digits so far (step by step, `n` per step) and
/// the number of steps.
struct Lifting {
    residual: Residual,
    digits: Vec<u32>,
    /// The first phase's [`mixing_weights`], and per step the digits' combination `Σ cᵢ xᵢ,ₜ`
    /// (below `256 n p`: an `i128`).
    weights: Option<Vec<[i64; MIXTURES]>>,
    mix: Vec<[i128; MIXTURES]>,
    steps: usize,
    p: u64,
    /// Digits taken in `(−p/2, p/2]` (so the expansion of an integer solution ends).
    balanced: bool,
    work: Vec<u64>,
    signed: Vec<i64>,
    scratch: Vec<u64>,
}

impl Lifting {
    fn new(solver: &LiftingSolver, b: &[BigInt], balanced: bool) -> Self {
        let n = solver.n;
        Lifting {
            residual: Residual::new(b, solver.small_rows.is_some()),
            digits: Vec::new(),
            weights: (!balanced).then(|| mixing_weights(n)),
            mix: Vec::new(),
            steps: 0,
            p: solver.inverse().modulus().prime(),
            balanced,
            work: vec![0; n],
            signed: vec![0; n],
            scratch: Vec::with_capacity(n),
        }
    }

    /// One digit per entry: `xᵢ = A⁻¹ rᵢ mod p`, `rᵢ₊₁ = (rᵢ − A xᵢ) / p`.
    fn step(&mut self, solver: &LiftingSolver) {
        let modulus = solver.inverse().modulus();
        self.residual.residues(&modulus, &mut self.work);
        solver
            .inverse()
            .solve_in_place(&mut self.work, &mut self.scratch);
        self.digits.extend(self.work.iter().map(|&d| d as u32));
        if let Some(weights) = &self.weights {
            let mut mixed = [0i128; MIXTURES];
            for (c, &d) in weights.iter().zip(&self.work) {
                for (sum, &cm) in mixed.iter_mut().zip(c) {
                    *sum += i128::from(cm) * i128::from(d);
                }
            }
            self.mix.push(mixed);
        }
        for (s, &d) in self.signed.iter_mut().zip(&self.work) {
            *s = if self.balanced {
                balanced_digit(d as u32, self.p)
            } else {
                d as i64
            };
        }
        self.residual.lift(solver, &self.signed, self.p);
        self.steps += 1;
    }
}

/// `v` moved into `(−m/2, m/2]`.
fn symmetric_residue(v: BigUint, m: &BigUint) -> BigInt {
    if &v << 1 > *m {
        BigInt::from_biguint(Sign::Minus, m - v)
    } else {
        BigInt::from(v)
    }
}

/// The fraction `a / d` with `|a| ≤ n_bound`, `0 < d ≤ d_bound` and `a ≡ d x (mod m)`, by the
/// half-extended Euclidean algorithm (Wang's rational reconstruction); `None` when there is
/// none within the bounds.
///
/// While the remainder is far above `n_bound` the steps go in batches certified by the leading
/// bits (Lehmer, [`crate::gcd::lehmer_matrix`]): one pass over the numbers per ~30 quotient
/// bits instead of a big division per quotient. A batch shrinks the remainder by at most about
/// 64 bits, so batches stop [`LEHMER_MARGIN_BITS`] above the bound and single steps find the
/// exact stopping point.
fn rational_reconstruction(
    x: &BigUint,
    m: &BigUint,
    n_bound: &BigUint,
    d_bound: &BigUint,
) -> Option<(BigInt, BigUint)> {
    use crate::gcd::{apply_lehmer, bit_len, from_limbs, lehmer_matrix, to_limbs, Limbs};
    let stop = n_bound.bits() as usize + LEHMER_MARGIN_BITS;
    let (mut a, mut b): (Limbs, Limbs) = (to_limbs(m), to_limbs(x));
    let (mut t0, mut t1) = (BigInt::zero(), BigInt::one());
    let (mut next_a, mut next_b) = (Vec::new(), Vec::new());
    while bit_len(&b) > stop {
        let Some(matrix) = lehmer_matrix(&a, &b) else {
            break;
        };
        apply_lehmer(&a, &b, matrix, &mut next_a, &mut next_b);
        std::mem::swap(&mut a, &mut next_a);
        std::mem::swap(&mut b, &mut next_b);
        let [ca, cb, cc, cd] = matrix;
        let t = &t0 * ca + &t1 * cb;
        t1 = &t0 * cc + &t1 * cd;
        t0 = t;
    }
    let (mut r0, mut r1) = (BigInt::from(from_limbs(&a)), BigInt::from(from_limbs(&b)));
    let n_bound = BigInt::from(n_bound.clone());
    while r1 > n_bound {
        let (q, r) = r0.div_rem(&r1);
        r0 = std::mem::replace(&mut r1, r);
        let t = &t0 - &q * &t1;
        t0 = std::mem::replace(&mut t1, t);
    }
    if t1.is_zero() || t1.magnitude() > d_bound {
        return None;
    }
    let numerator = if t1.is_negative() { -r1 } else { r1 };
    Some((numerator, t1.magnitude().clone()))
}

/// How far above the numerator bound the Lehmer batches of [`rational_reconstruction`] stop.
const LEHMER_MARGIN_BITS: usize = 128;

/// `p^(2^ℓ)` for combining p-adic digits into integers by halves.
struct PadicPowers {
    /// `squares[ℓ] = p^(2^ℓ)`.
    squares: Vec<BigUint>,
}

impl PadicPowers {
    fn new(p: u64, k: usize) -> Self {
        let mut squares = vec![BigUint::from(p)];
        while (1usize << squares.len()) < k {
            let last = &squares[squares.len() - 1];
            squares.push(last * last);
        }
        PadicPowers { squares }
    }

    /// `Σ dᵢ pⁱ` for signed digits, splitting at the largest power of two below the length (so
    /// the cost is that of a few balanced multiplications rather than `k` passes over a growing
    /// number).
    fn combine_signed(&self, digits: &[i64]) -> BigInt {
        self.combine_by(digits, &|d| BigInt::from(d))
    }

    /// `Σ dᵢ pⁱ` by halves, each digit made an integer by `leaf`.
    fn combine_by<T: Copy>(&self, digits: &[T], leaf: &impl Fn(T) -> BigInt) -> BigInt {
        match digits.len() {
            0 => BigInt::zero(),
            1 => leaf(digits[0]),
            len => {
                let level = (usize::BITS - 1 - (len - 1).leading_zeros()) as usize;
                let half = 1usize << level;
                let low = self.combine_by(&digits[..half], leaf);
                let high = self.combine_by(&digits[half..], leaf);
                if high.is_zero() {
                    low
                } else {
                    let (sign, magnitude) = high.into_parts();
                    low + BigInt::from_biguint(sign, magnitude * &self.squares[level])
                }
            }
        }
    }
}

/// The residual `rᵢ` of the lifting: big integers while it is large (a large right-hand side),
/// `i128` once it is small and the matrix entries fit.
enum Residual {
    Big(Vec<BigInt>),
    Small(Vec<i128>),
}

impl Residual {
    fn new(b: &[BigInt], small_matrix: bool) -> Self {
        let mut r = Residual::Big(b.to_vec());
        if small_matrix {
            r.shrink();
        }
        r
    }

    /// `r ← r + digit · b`.
    fn add_scaled(&mut self, feed: &Feed, digit: u64) {
        if digit == 0 {
            return;
        }
        if let (Residual::Small(values), Some(small)) = (&mut *self, &feed.small) {
            let digit = i128::from(digit);
            for (r, bi) in values.iter_mut().zip(small) {
                *r += digit * bi;
            }
            return;
        }
        if let Residual::Small(values) = self {
            *self = Residual::Big(values.iter().map(|v| BigInt::from(*v)).collect());
        }
        if let Residual::Big(values) = self {
            for (r, bi) in values.iter_mut().zip(&feed.big) {
                *r += bi * digit;
            }
        }
    }

    /// Moves to `i128` when every entry is below `2^SMALL_RESIDUAL_BITS`.
    fn shrink(&mut self) {
        if let Residual::Big(values) = self {
            if values.iter().all(|v| v.bits() < SMALL_RESIDUAL_BITS) {
                *self = Residual::Small(values.iter().map(|v| v.to_i128().unwrap_or(0)).collect());
            }
        }
    }

    fn residues(&self, modulus: &Modulus, out: &mut [u64]) {
        match self {
            Residual::Big(values) => {
                for (o, v) in out.iter_mut().zip(values) {
                    *o = modulus.residue_big(v);
                }
            }
            Residual::Small(values) => {
                for (o, v) in out.iter_mut().zip(values) {
                    *o = modulus.residue_i128(*v);
                }
            }
        }
    }

    fn is_zero(&self) -> bool {
        match self {
            Residual::Big(values) => values.iter().all(Zero::is_zero),
            Residual::Small(values) => values.iter().all(|v| *v == 0),
        }
    }

    /// `r ← (r − A x) / p`.
    fn lift(&mut self, solver: &LiftingSolver, x: &[i64], p: u64) {
        match self {
            Residual::Small(values) => {
                let rows = solver
                    .small_rows
                    .as_ref()
                    .expect("small residuals only with small matrix entries");
                let inverse = inverse_mod_2_128(p);
                for (r, row) in values.iter_mut().zip(rows) {
                    let mut acc = *r;
                    for &(j, a) in row {
                        acc -= i128::from(a) * i128::from(x[j]);
                    }
                    // Exact division by the odd p: multiply by p⁻¹ modulo 2^128.
                    *r = (acc as u128).wrapping_mul(inverse) as i128;
                }
            }
            Residual::Big(values) => {
                let p = BigInt::from(p);
                for (r, row) in values.iter_mut().zip(solver.rows()) {
                    let s: BigInt = row.iter().map(|(j, a)| a * x[*j]).sum();
                    *r = (&*r - s) / &p;
                }
                if solver.small_rows.is_some() {
                    self.shrink();
                }
            }
        }
    }
}

/// `p⁻¹ mod 2^128` for odd `p` (Newton's iteration doubles the correct bits each step).
fn inverse_mod_2_128(p: u64) -> u128 {
    let p = u128::from(p);
    let mut inv: u128 = p; // correct to 3 bits for odd p
    for _ in 0..7 {
        inv = inv.wrapping_mul(2u128.wrapping_sub(p.wrapping_mul(inv)));
    }
    inv
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn sparse(rows: &[Vec<i64>]) -> Vec<Vec<(usize, BigInt)>> {
        rows.iter()
            .map(|r| {
                r.iter()
                    .enumerate()
                    .filter(|(_, v)| **v != 0)
                    .map(|(j, v)| (j, BigInt::from(*v)))
                    .collect()
            })
            .collect()
    }

    fn check_solution(rows: &[Vec<i64>], b: &[BigInt], (num, den): &(Vec<BigInt>, BigInt)) {
        assert!(den.is_positive());
        for (row, bi) in rows.iter().zip(b) {
            let lhs: BigInt = row.iter().zip(num).map(|(a, x)| BigInt::from(*a) * x).sum();
            assert_eq!(lhs, den * bi);
        }
    }

    /// The Hadamard bound in machine words is the big-integer one; a zero column is refused.
    #[test]
    fn word_bounds_are_the_big_integer_bounds() {
        let rows: Vec<Vec<i64>> = vec![vec![3, -(1 << 61), 0], vec![4, 5, 0], vec![0, 7, 1]];
        let (small, bits) = LiftingSolver::bounds(3, &sparse(&rows)).expect("no zero column");
        assert!(small.is_some());
        let expected: u64 = (0..3)
            .map(|j| {
                let column: Vec<BigInt> = rows.iter().map(|r| BigInt::from(r[j])).collect();
                norm_bits(column.iter())
            })
            .sum();
        assert_eq!(bits, expected);
        let zero_column: Vec<Vec<i64>> = vec![vec![1, 0], vec![2, 0]];
        assert!(LiftingSolver::bounds(2, &sparse(&zero_column)).is_none());
    }

    #[test]
    fn inverse_modulo_2_128_is_an_inverse() {
        for p in [3u64, 2_147_483_647, 2_147_483_629] {
            assert_eq!(u128::from(p).wrapping_mul(inverse_mod_2_128(p)), 1);
        }
    }

    #[test]
    fn singular_matrices_are_refused() {
        assert!(LiftingSolver::new(2, sparse(&[vec![1, 2], vec![2, 4]])).is_none());
        assert!(LiftingSolver::new(2, sparse(&[vec![1, 0], vec![3, 0]])).is_none());
    }

    #[test]
    fn reconstruction_inverts_the_residue() {
        let m = BigUint::from(1_000_003u32).pow(4);
        let bound: BigUint = ((&m - 1u32) >> 1u32).sqrt();
        let mi = BigInt::from(m.clone());
        // x = 355 / 113 mod m, through 113 u + m v = 1.
        let inverse = BigInt::from(113).extended_gcd(&mi).x;
        let x = (BigInt::from(-355) * inverse).mod_floor(&mi);
        let x = x.to_biguint().expect("non-negative");
        let (a, d) = rational_reconstruction(&x, &m, &bound, &bound).expect("in bounds");
        assert_eq!((a, d), (BigInt::from(-355), BigUint::from(113u32)));
        // Nothing small enough: d (10^20 + 7) for d ≤ 10 is below m and above 10.
        let tiny = BigUint::from(10u32);
        let x = BigUint::from(10u32).pow(20) + 7u32;
        assert!(rational_reconstruction(&x, &m, &tiny, &tiny).is_none());
    }

    proptest! {
        /// Large fractions (the Lehmer batches run for most of the steps) come back exactly.
        #[test]
        fn large_fractions_are_reconstructed(
            a_bits in 1u32..380, d_bits in 1u32..380, seed in any::<u64>(), negative in any::<bool>(),
        ) {
            let m = BigUint::from(2_147_483_629u32).pow(26);
            let bound: BigUint = ((&m - 1u32) >> 1u32).sqrt();
            let mi = BigInt::from(m.clone());
            let a = (BigInt::one() << a_bits) - BigInt::from(seed % 1000);
            let a = if negative { -a } else { a };
            let d = (BigInt::one() << d_bits) + BigInt::from(2 * (seed % 977) + 1);
            prop_assume!(a.gcd(&d).is_one());
            let inverse = d.extended_gcd(&mi).x;
            let x = (&a * inverse).mod_floor(&mi).to_biguint().expect("non-negative");
            let got = rational_reconstruction(&x, &m, &bound, &bound).expect("in bounds");
            prop_assert_eq!(got, (a, d.to_biguint().expect("positive")));
        }
    }

    /// A right-hand side far larger than the matrix: the residual starts as big integers.
    #[test]
    fn large_right_hand_sides_and_large_answers() {
        let rows = vec![vec![3, -1, 0], vec![-1, 3, -1], vec![0, -1, 3]];
        let solver = LiftingSolver::new(3, sparse(&rows)).expect("nonsingular");
        let big = BigInt::from(7).pow(300u32);
        let b = vec![big.clone(), -&big + 1, BigInt::from(5)];
        let solution = solver.solve(&b);
        check_solution(&rows, &b, &solution);
    }

    /// A small symmetric matrix prepared in words keeps no big-integer rows until a solve
    /// lifts: a right-hand side beyond words is lifted with the rows made then, and the solver
    /// equals the one given big-integer rows.
    #[test]
    fn solvers_prepared_in_words_lift_with_rows_made_on_demand() {
        let rows = vec![vec![4, -1, 0], vec![-1, 4, -2], vec![0, -2, 5]];
        let words: Vec<Vec<(usize, i64)>> = rows
            .iter()
            .map(|r| {
                r.iter()
                    .enumerate()
                    .filter(|(_, v)| **v != 0)
                    .map(|(j, v)| (j, *v))
                    .collect()
            })
            .collect();
        let solver = LiftingSolver::small_symmetric(3, &words).expect("positive definite");
        assert!(
            solver.rows.get().is_none(),
            "no big-integer rows before a lifting"
        );
        let big = BigInt::from(11).pow(60u32);
        let b = vec![big.clone(), BigInt::from(-3), -&big + 2];
        let solution = solver.solve(&b);
        check_solution(&rows, &b, &solution);
        assert!(solver.rows.get().is_some());
        let given = LiftingSolver::new_symmetric(3, sparse(&rows)).expect("positive definite");
        assert!(solver == given);
        // Words within bounds are still answered in words.
        let small = vec![BigInt::from(1), BigInt::from(2), BigInt::from(3)];
        check_solution(&rows, &small, &solver.solve(&small));
    }

    #[test]
    fn matrix_entries_beyond_machine_words() {
        let huge = BigInt::from(10).pow(30u32);
        let rows: Vec<Vec<(usize, BigInt)>> = vec![
            vec![(0, huge.clone()), (1, BigInt::from(1))],
            vec![(0, BigInt::from(1)), (1, BigInt::from(2))],
        ];
        let solver = LiftingSolver::new(2, rows.clone()).expect("nonsingular");
        let b = vec![BigInt::from(1), BigInt::from(1)];
        let (num, den) = solver.solve(&b);
        for (row, bi) in rows.iter().zip(&b) {
            let lhs: BigInt = row.iter().map(|(j, a)| a * &num[*j]).sum();
            assert_eq!(lhs, &den * bi);
        }
    }

    /// One entry has denominator 3, all others 1, and its weight in every combination is a
    /// multiple of 3: the combinations are integers, the second phase (over denominator 1)
    /// cannot end, and the completion of the entries gives the answer. With weights prime to 3
    /// the combinations find the 3 at once.
    #[test]
    fn a_denominator_the_combination_cancels_is_still_found() {
        let n = 300;
        let weights = mixing_weights(n);
        let b: Vec<BigInt> = (0..n as i64).map(|i| BigInt::from(3 * i + 1)).collect();
        for cancelled in [true, false] {
            let entry = (0..n)
                .find(|&i| weights[i].iter().all(|c| (c % 3 == 0) == cancelled))
                .expect("weights of both kinds among 300");
            let rows: Vec<Vec<i64>> = (0..n)
                .map(|i| {
                    (0..n)
                        .map(|j| match (i, j) {
                            _ if i == j && i == entry => 3,
                            _ if i == j => 1,
                            _ => 0,
                        })
                        .collect()
                })
                .collect();
            let solver = LiftingSolver::lifted_symmetric(n, sparse(&rows)).expect("nonsingular");
            let mut lifting = Lifting::new(&solver, &b, false);
            lifting.step(&solver);
            lifting.step(&solver);
            let p = solver.inverse().modulus().prime();
            let den = solver.mixed_denominator(&lifting.mix, 2, p);
            let expected = if cancelled { 1u32 } else { 3 };
            assert_eq!(den, Some(BigUint::from(expected)));
            let solution = solver.solve(&b);
            check_solution(&rows, &b, &solution);
            assert_eq!(solution.1, BigInt::from(3));
        }
    }

    proptest! {
        /// The defining equation `A x = b`, checked exactly on random nonsingular systems.
        #[test]
        fn lifted_solutions_solve_the_system(
            n in 1usize..9,
            entries in proptest::collection::vec(-40i64..40, 81),
            rhs in proptest::collection::vec(-1000i64..1000, 9),
        ) {
            // Diagonally dominant, so nonsingular.
            let rows: Vec<Vec<i64>> = (0..n)
                .map(|i| {
                    let mut row: Vec<i64> = (0..n).map(|j| entries[i * 9 + j]).collect();
                    row[i] = row.iter().map(|v| v.abs()).sum::<i64>() + 1;
                    row
                })
                .collect();
            let solver = LiftingSolver::new(n, sparse(&rows)).expect("nonsingular");
            let b: Vec<BigInt> = rhs[..n].iter().map(|v| BigInt::from(*v)).collect();
            let solution = solver.solve(&b);
            check_solution(&rows, &b, &solution);
            // The symmetric part A + Aᵀ off the diagonal, with a diagonal that makes it
            // diagonally dominant (so positive definite; A + Aᵀ itself need not be, and may be
            // singular), through the sparse factoring.
            let symmetric: Vec<Vec<i64>> = (0..n)
                .map(|i| {
                    let mut row: Vec<i64> = (0..n).map(|j| rows[i][j] + rows[j][i]).collect();
                    row[i] = (0..n).filter(|&j| j != i).map(|j| row[j].abs()).sum::<i64>() + 1;
                    row
                })
                .collect();
            let solver = LiftingSolver::lifted_symmetric(n, sparse(&symmetric)).expect("nonsingular");
            let solution = solver.solve(&b);
            check_solution(&symmetric, &b, &solution);
            // The fraction-free path gives the same answer, and so does its fallback to
            // lifting for a right-hand side beyond `i128` (the modular inverse made then).
            let small = LiftingSolver::new_symmetric(n, sparse(&symmetric)).expect("nonsingular");
            // Minors of at most four rows of entries below 2^10 stay below 2^62; larger
            // systems may lift instead, with the same answers.
            prop_assert!(n > 4 || small.small.is_some());
            prop_assert_eq!(small.solve(&b), solution);
            let huge: Vec<BigInt> = b.iter().map(|v| v * (BigInt::from(1) << 200) + 1).collect();
            let lifted = small.solve(&huge);
            check_solution(&symmetric, &huge, &lifted);
            prop_assert_eq!(lifted, solver.solve(&huge));
        }
    }
}
