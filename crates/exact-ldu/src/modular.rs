//! Arithmetic modulo a word-sized prime and the LU factoring of a square integer matrix modulo
//! that prime: the "cheap inverse" of Dixon's p-adic lifting ([`crate::dixon`]).
//!
//! `P A = L U (mod p)` with `P` a row permutation, `L` unit lower triangular and `U` upper
//! triangular with a nonzero diagonal; it exists exactly when `p ∤ det A`. Primes are below
//! `2^31`, so a product of two residues is below `2^62` and a dot product accumulates in `u128`
//! without reducing every term.

use num_bigint::{BigInt, Sign};
use num_traits::ToPrimitive;

/// Largest prime the lifting uses is the largest one below this bound.
const PRIME_BOUND: u64 = 1 << 31;

/// Deterministic primality test for `n < 2^32` (Miller–Rabin with bases 2, 7 and 61, which
/// is exact below 4 759 123 141).
fn is_prime(n: u64) -> bool {
    if n < 2 {
        return false;
    }
    for small in [2u64, 3, 5, 7, 11, 13, 61] {
        if n % small == 0 {
            return n == small;
        }
    }
    let mut d = n - 1;
    let mut s = 0;
    while d % 2 == 0 {
        d /= 2;
        s += 1;
    }
    let mul = |a: u64, b: u64| a * b % n;
    let pow = |mut b: u64, mut e: u64| {
        let mut r = 1u64;
        while e > 0 {
            if e & 1 == 1 {
                r = mul(r, b);
            }
            b = mul(b, b);
            e >>= 1;
        }
        r
    };
    'bases: for a in [2u64, 7, 61] {
        let mut x = pow(a, d);
        if x == 1 || x == n - 1 {
            continue;
        }
        for _ in 1..s {
            x = mul(x, x);
            if x == n - 1 {
                continue 'bases;
            }
        }
        return false;
    }
    true
}

/// The primes below `2^31`, largest first: the lifting takes the first one that does not divide
/// the determinant.
pub(crate) fn lifting_primes() -> impl Iterator<Item = u64> {
    (3..PRIME_BOUND).rev().step_by(2).filter(|&n| is_prime(n))
}

/// A prime modulus below `2^31` with Barrett reduction of 64- and 128-bit values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Modulus {
    p: u64,
    /// `⌊2^64 / p⌋`.
    barrett: u64,
    /// `2^64 mod p`.
    two_64: u64,
}

impl Modulus {
    /// The modulus `p` (`2 < p < 2^31`, odd).
    pub(crate) fn new(p: u64) -> Self {
        debug_assert!(p > 2 && p < PRIME_BOUND && p % 2 == 1);
        let barrett = (u128::from(u64::MAX) + 1).div_euclid(u128::from(p)) as u64;
        let two_64 = ((u128::from(u64::MAX) + 1) % u128::from(p)) as u64;
        Modulus { p, barrett, two_64 }
    }

    /// `p`.
    pub(crate) fn prime(&self) -> u64 {
        self.p
    }

    /// `x mod p` for any `u64`.
    #[inline]
    pub(crate) fn reduce(&self, x: u64) -> u64 {
        let q = ((u128::from(x) * u128::from(self.barrett)) >> 64) as u64;
        let r = x - q * self.p;
        if r >= self.p {
            r - self.p
        } else {
            r
        }
    }

    /// `x mod p` for a `u128` accumulator.
    #[inline]
    pub(crate) fn reduce_wide(&self, x: u128) -> u64 {
        let hi = self.reduce((x >> 64) as u64);
        let lo = self.reduce(x as u64);
        self.reduce(hi * self.two_64 + lo)
    }

    /// `a · b mod p` for residues.
    #[inline]
    pub(crate) fn mul(&self, a: u64, b: u64) -> u64 {
        self.reduce(a * b)
    }

    /// `a⁻¹ mod p` for a nonzero residue (Fermat).
    pub(crate) fn inverse(&self, a: u64) -> u64 {
        let (mut base, mut e, mut r) = (a, self.p - 2, 1u64);
        while e > 0 {
            if e & 1 == 1 {
                r = self.mul(r, base);
            }
            base = self.mul(base, base);
            e >>= 1;
        }
        r
    }

    /// The residue of a signed machine integer.
    #[inline]
    pub(crate) fn residue_i128(&self, v: i128) -> u64 {
        v.rem_euclid(i128::from(self.p)) as u64
    }

    /// The residue of a big integer.
    pub(crate) fn residue_big(&self, v: &BigInt) -> u64 {
        if let Some(small) = v.to_i128() {
            return self.residue_i128(small);
        }
        // Horner over the 32-bit digits, most significant first.
        let (sign, digits) = v.to_u32_digits();
        let mut r = 0u64;
        for d in digits.iter().rev() {
            r = self.reduce((r << 32) | u64::from(*d));
        }
        if sign == Sign::Minus && r != 0 {
            self.p - r
        } else {
            r
        }
    }
}

/// `P A = L U (mod p)` of a nonsingular square matrix, stored densely row by row: `L` strictly
/// below the diagonal (unit diagonal implied), `U` on and above it, and for each row of the
/// factors the row of `A` it came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct ModularLu {
    n: usize,
    modulus: Modulus,
    factors: Vec<u64>,
    /// `U`'s diagonal inverted, for the backward substitution.
    inverse_diagonal: Vec<u64>,
    /// Row `i` of the factors is row `rows[i]` of `A`.
    rows: Vec<usize>,
}

impl ModularLu {
    /// Factors `A` (`n × n`, given by sparse rows of residues) modulo `modulus`; `None` when
    /// `p` divides `det A` (in particular when `A` is singular).
    ///
    /// Complexity: `n³/3` multiply-adds modulo `p`, `n²` words.
    pub(crate) fn factor(n: usize, rows: &[Vec<(usize, u64)>], modulus: Modulus) -> Option<Self> {
        let mut a = vec![0u64; n * n];
        for (i, row) in rows.iter().enumerate() {
            for &(j, v) in row {
                a[i * n + j] = v;
            }
        }
        let mut perm: Vec<usize> = (0..n).collect();
        let mut inverse_diagonal = Vec::with_capacity(n);
        let p = modulus.prime();
        for k in 0..n {
            let pivot = (k..n).find(|&i| a[i * n + k] != 0)?;
            if pivot != k {
                for j in 0..n {
                    a.swap(k * n + j, pivot * n + j);
                }
                perm.swap(k, pivot);
            }
            let inv = modulus.inverse(a[k * n + k]);
            inverse_diagonal.push(inv);
            let (upper, lower) = a.split_at_mut((k + 1) * n);
            let pivot_row = &upper[k * n..(k + 1) * n];
            for row in lower.chunks_exact_mut(n) {
                if row[k] == 0 {
                    continue;
                }
                let l = modulus.mul(row[k], inv);
                row[k] = l;
                let minus_l = p - l;
                for j in k + 1..n {
                    if pivot_row[j] != 0 {
                        row[j] = modulus.reduce(row[j] + minus_l * pivot_row[j]);
                    }
                }
            }
        }
        Some(ModularLu {
            n,
            modulus,
            factors: a,
            inverse_diagonal,
            rows: perm,
        })
    }

    /// The modulus of the factoring.
    pub(crate) fn modulus(&self) -> Modulus {
        self.modulus
    }

    /// Solves `A x = b (mod p)`: `b` (residues, in the order of `A`'s rows) is replaced by `x`.
    pub(crate) fn solve_in_place(&self, b: &mut [u64], scratch: &mut Vec<u64>) {
        let n = self.n;
        let m = &self.modulus;
        let p = m.prime();
        scratch.clear();
        scratch.extend(self.rows.iter().map(|&r| b[r]));
        // Forward: L y = P b.
        for i in 0..n {
            let row = &self.factors[i * n..i * n + i];
            let mut acc: u128 = 0;
            for (l, y) in row.iter().zip(scratch.iter()) {
                acc += u128::from(l * y);
            }
            let s = m.reduce_wide(acc);
            scratch[i] = m.reduce(scratch[i] + p - s);
        }
        // Backward: U x = y.
        for i in (0..n).rev() {
            let row = &self.factors[i * n + i + 1..(i + 1) * n];
            let mut acc: u128 = 0;
            for (u, x) in row.iter().zip(scratch[i + 1..].iter()) {
                acc += u128::from(u * x);
            }
            let s = m.reduce_wide(acc);
            scratch[i] = m.mul(m.reduce(scratch[i] + p - s), self.inverse_diagonal[i]);
        }
        b.copy_from_slice(scratch);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn primality_agrees_with_trial_division() {
        let trial = |n: u64| n >= 2 && (2..).take_while(|d| d * d <= n).all(|d| n % d != 0);
        for n in 0..5000 {
            assert_eq!(is_prime(n), trial(n), "{n}");
        }
        let top: Vec<u64> = lifting_primes().take(3).collect();
        assert_eq!(top, vec![2_147_483_647, 2_147_483_629, 2_147_483_587]);
    }

    #[test]
    fn barrett_reduction_is_the_remainder() {
        let m = Modulus::new(2_147_483_629);
        for x in [
            0u64,
            1,
            2_147_483_628,
            2_147_483_629,
            u64::MAX,
            1 << 62,
            12_345_678_901_234,
        ] {
            assert_eq!(m.reduce(x), x % m.prime());
        }
        for x in [u128::MAX, 1u128 << 100, 987_654_321_987_654_321_987_654_321] {
            assert_eq!(u128::from(m.reduce_wide(x)), x % u128::from(m.prime()));
        }
        assert_eq!(m.mul(m.inverse(12345), 12345), 1);
        assert_eq!(m.residue_big(&BigInt::from(-5)), m.prime() - 5);
        let big = BigInt::from(3u8).pow(200u32) * -1;
        let expected = (BigInt::from(m.prime()) + (&big % m.prime())) % m.prime();
        assert_eq!(BigInt::from(m.residue_big(&big)), expected);
    }

    /// The defining equation `P A = L U (mod p)`, through solving: `A x = b` for the solution.
    #[test]
    fn the_factors_solve_the_system_modulo_p() {
        let m = Modulus::new(101);
        let a = [[0u64, 2, 3], [4, 5, 6], [7, 8, 10]];
        let rows: Vec<Vec<(usize, u64)>> = a
            .iter()
            .map(|r| {
                r.iter()
                    .copied()
                    .enumerate()
                    .filter(|(_, v)| *v != 0)
                    .collect()
            })
            .collect();
        let lu = ModularLu::factor(3, &rows, m).expect("nonsingular");
        let x = [5u64, 17, 99];
        let mut b: Vec<u64> = a
            .iter()
            .map(|r| r.iter().zip(&x).map(|(u, v)| u * v).sum::<u64>() % 101)
            .collect();
        lu.solve_in_place(&mut b, &mut Vec::new());
        assert_eq!(b, x);
        // det A = -5: singular modulo 5, refused.
        assert!(ModularLu::factor(3, &rows, Modulus::new(5)).is_none());
    }
}
