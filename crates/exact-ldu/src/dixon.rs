//! Dixon's p-adic lifting: the exact solution of `A x = b` for a nonsingular integer matrix `A`,
//! at a cost that follows the size of the answer (J. D. Dixon, "Exact solution of linear
//! equations using p-adic expansions", Numer. Math. 40, 1982; FLINT's `fmpz_mat_solve_dixon`
//! follows the same scheme).
//!
//! With `C = A⁻¹ mod p` (an LU factoring modulo a word-sized prime), `r₀ = b` and
//!
//! ```text
//! xᵢ = C rᵢ mod p,    rᵢ₊₁ = (rᵢ − A xᵢ) / p        (an exact division),
//! ```
//!
//! `X_k = Σ_{i<k} xᵢ pⁱ` satisfies `A X_k = b − p^k r_k`, so `X_k ≡ x (mod p^k)`. Rational
//! reconstruction of `X_k` gives `x = numerators / denominator` as soon as `p^k > 2 N D` (`N`
//! and `D` bounding the numerators and the denominator). Every candidate is verified exactly
//! (`A · numerators = denominator · b`), so the answer is certain whatever the prime: the prime
//! only decides the speed. Attempts at `k = 8, 16, 24, …, ⌈1.25 k⌉, …` make the work follow the
//! actual size of the answer; the Hadamard bound caps `k`, so the lifting always ends.
//!
//! Why not fraction-free elimination here: the least-squares systems of edits on real meshes
//! have solutions with thousands of digits; elimination pays for every digit at every one of its
//! `n³` steps, lifting pays `n²` word operations per 31 bits of the answer.
//!
//! Complexity: `n³/3` word operations for the factoring (once per matrix), then per right-hand
//! side `k (n² + nnz(A))` word operations for `k ≈ (bits of numerators + denominator) / 31`
//! lifting steps, plus the reconstruction.

use crate::modular::{fill_reducing_order, lifting_primes, ModularLu, Modulus, SparseLdlt};
use num_bigint::{BigInt, BigUint, Sign};
use num_integer::Integer;
use num_traits::{One, Signed, ToPrimitive, Zero};

/// Residuals below this size stay in `i128` (with `|A| < 2^62` and digits below `2^31`, one
/// lifting step keeps them there).
const SMALL_RESIDUAL_BITS: u64 = 100;

/// Bits per lifting step, a lower bound of `log₂ p` for every prime used.
const BITS_PER_STEP: u64 = 30;

/// A nonsingular square integer matrix prepared for solving by lifting.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct LiftingSolver {
    n: usize,
    rows: Vec<Vec<(usize, BigInt)>>,
    /// The rows again, when every entry is below `2^62` in absolute value.
    small_rows: Option<Vec<Vec<(usize, i64)>>>,
    inverse: ModularInverse,
    /// `Σ_j ⌈log₂ ‖A_{:,j}‖⌉`, an upper bound of `log₂ |det A|` (Hadamard).
    hadamard_bits: u64,
}

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

impl LiftingSolver {
    /// Prepares a symmetric positive definite `A` (`n × n`, both triangles given as sparse
    /// rows, column indices increasing): `L D Lᵀ` modulo a prime in a fill-reducing order, so
    /// factoring and lifting follow the sparsity of `A`. Falls back to [`LiftingSolver::new`]
    /// (dense, any nonsingular matrix) when no prime tried gives nonzero pivots; `None` when
    /// `A` is singular.
    pub(crate) fn new_symmetric(n: usize, rows: Vec<Vec<(usize, BigInt)>>) -> Option<Self> {
        debug_assert_eq!(rows.len(), n);
        let pattern: Vec<Vec<(usize, u64)>> = rows
            .iter()
            .map(|row| row.iter().map(|(j, _)| (*j, 0)).collect())
            .collect();
        let order = fill_reducing_order(&pattern);
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
        let (small_rows, hadamard_bits) = Self::bounds(n, &rows)?;
        Some(LiftingSolver {
            n,
            rows,
            small_rows,
            inverse,
            hadamard_bits,
        })
    }

    /// The rows as machine integers when they all fit, and the Hadamard bound; `None` when a
    /// column of `A` is zero (`A` singular).
    #[allow(clippy::type_complexity)]
    fn bounds(
        n: usize,
        rows: &[Vec<(usize, BigInt)>],
    ) -> Option<(Option<Vec<Vec<(usize, i64)>>>, u64)> {
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
        let hadamard_bits: u64 = columns.iter().map(|c| norm_bits(c.iter().copied())).sum();
        let limit = BigInt::from(1i64 << 62);
        let small_rows = rows
            .iter()
            .map(|row| {
                row.iter()
                    .map(|(j, v)| (v.abs() < limit).then(|| (*j, v.to_i64().unwrap_or(0))))
                    .collect::<Option<Vec<_>>>()
            })
            .collect::<Option<Vec<_>>>();
        Some((small_rows, hadamard_bits))
    }

    /// Prepares `A` (`n × n`, sparse rows with column indices below `n`), factored densely
    /// modulo a prime; `None` when `A` is singular.
    pub(crate) fn new(n: usize, rows: Vec<Vec<(usize, BigInt)>>) -> Option<Self> {
        debug_assert_eq!(rows.len(), n);
        let (small_rows, hadamard_bits) = Self::bounds(n, &rows)?;
        // A prime that divides det A ≠ 0 is at least 2^30, so more than
        // `hadamard_bits / 30` such primes prove det A = 0.
        let mut failures = 0u64;
        for p in lifting_primes() {
            let modulus = Modulus::new(p);
            if let Some(lu) = ModularLu::factor(n, &residue_rows(&rows, &modulus), modulus) {
                return Some(LiftingSolver {
                    n,
                    rows,
                    small_rows,
                    inverse: ModularInverse::Dense(lu),
                    hadamard_bits,
                });
            }
            failures += 1;
            if failures * BITS_PER_STEP > hadamard_bits {
                return None;
            }
        }
        None
    }

    /// The exact solution of `A x = b` as `(numerators, denominator)`, denominator positive.
    pub(crate) fn solve(&self, b: &[BigInt]) -> (Vec<BigInt>, BigInt) {
        debug_assert_eq!(b.len(), self.n);
        let n = self.n;
        if n == 0 {
            return (Vec::new(), BigInt::one());
        }
        let modulus = self.inverse.modulus();
        // Cramer and Hadamard: |den| ≤ 2^H, |num_i| ≤ ‖b‖ 2^H; p^k > 2 N D suffices.
        let b_bits = norm_bits(b.iter());
        let last_step =
            ((2 * self.hadamard_bits + b_bits + 2).div_ceil(BITS_PER_STEP) + 1) as usize;
        let mut residual = Residual::new(b, self.small_rows.is_some());
        let mut digits: Vec<u32> = Vec::new();
        let mut work = vec![0u64; n];
        let mut scratch = Vec::with_capacity(n);
        let mut next_attempt = 8;
        let mut step = 0;
        loop {
            residual.residues(&modulus, &mut work);
            self.inverse.solve_in_place(&mut work, &mut scratch);
            digits.extend(work.iter().map(|&d| d as u32));
            residual.lift(self, &work, modulus.prime());
            step += 1;
            let exhausted = residual.is_zero();
            if step == next_attempt || step >= last_step || exhausted {
                if let Some(solution) = self.reconstruct(&digits, step, modulus.prime(), b) {
                    return solution;
                }
                assert!(
                    step < last_step,
                    "p-adic lifting: reconstruction failed beyond the Hadamard bound"
                );
                // A failed attempt stops at the first entry that does not reconstruct, so
                // attempts are cheap next to lifting: step by a quarter, overshooting the
                // needed length by at most 25 % (doubling would waste up to half).
                next_attempt = (step + (step / 4).max(8)).min(last_step);
            }
        }
    }

    /// Reconstructs the rational solution from `k` p-adic digits per entry and verifies it.
    fn reconstruct(
        &self,
        digits: &[u32],
        k: usize,
        p: u64,
        b: &[BigInt],
    ) -> Option<(Vec<BigInt>, BigInt)> {
        let n = self.n;
        let powers = PadicPowers::new(p, k);
        let modulus = BigUint::from(p).pow(k as u32);
        // Unique when 2 N D < p^k. The denominator divides det A, so D never needs to exceed
        // the Hadamard bound; what is left goes to the numerators (large right-hand sides
        // give large numerators over small denominators).
        // Powers of two: 2 N D = 2^(bits(p^k) − 2) < p^k.
        let budget = modulus.bits().saturating_sub(3);
        let den_bits = (budget / 2).min(self.hadamard_bits);
        let den_bound = BigUint::one() << den_bits;
        let num_bound = BigUint::one() << (budget - den_bits);
        let mut den = BigUint::one();
        let mut numerators: Vec<BigInt> = Vec::with_capacity(n);
        let mut column = Vec::with_capacity(k);
        for i in 0..n {
            column.clear();
            column.extend((0..k).map(|t| digits[t * n + i]));
            let x = powers.combine(&column);
            let y = (&den * &x) % &modulus;
            let symmetric = symmetric_residue(y.clone(), &modulus);
            if symmetric.magnitude() <= &num_bound {
                numerators.push(symmetric);
                continue;
            }
            // x ≡ (numerator / den) would need a larger numerator: den · x ≡ a / d.
            let (a, d) = rational_reconstruction(&y, &modulus, &num_bound, &(&den_bound / &den))?;
            let scale = BigInt::from(d.clone());
            for num in &mut numerators {
                *num *= &scale;
            }
            den *= &d;
            numerators.push(a);
        }
        let den = BigInt::from(den);
        for (row, bi) in self.rows.iter().zip(b) {
            let lhs: BigInt = row.iter().map(|(j, v)| v * &numerators[*j]).sum();
            if lhs != &den * bi {
                return None;
            }
        }
        Some((numerators, den))
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
fn rational_reconstruction(
    x: &BigUint,
    m: &BigUint,
    n_bound: &BigUint,
    d_bound: &BigUint,
) -> Option<(BigInt, BigUint)> {
    let (mut r0, mut r1) = (BigInt::from(m.clone()), BigInt::from(x.clone()));
    let (mut t0, mut t1) = (BigInt::zero(), BigInt::one());
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

    /// `Σ dᵢ pⁱ`, splitting at the largest power of two below the length (so the cost is that
    /// of a few balanced multiplications rather than `k` passes over a growing number).
    fn combine(&self, digits: &[u32]) -> BigUint {
        match digits.len() {
            0 => BigUint::zero(),
            1 => BigUint::from(digits[0]),
            len => {
                let level = (usize::BITS - 1 - (len - 1).leading_zeros()) as usize;
                let half = 1usize << level;
                let low = self.combine(&digits[..half]);
                let high = self.combine(&digits[half..]);
                if high.is_zero() {
                    low
                } else {
                    low + high * &self.squares[level]
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
    fn lift(&mut self, solver: &LiftingSolver, x: &[u64], p: u64) {
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
                for (r, row) in values.iter_mut().zip(&solver.rows) {
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
        }
    }
}
