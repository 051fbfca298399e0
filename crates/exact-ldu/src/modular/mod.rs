//! Arithmetic modulo a word-sized prime and the factorings of a square integer matrix modulo
//! that prime: the "cheap inverse" of Dixon's p-adic lifting ([`crate::dixon`]) — a sparse
//! `L D Lᵀ` in a fill-reducing order for symmetric matrices ([`ldlt`]), a dense `P A = L U`
//! for the rest ([`dense`]) — and the row rank profile of a sparse matrix modulo a prime
//! ([`echelon`]), the first step of the certified row basis ([`crate::certified`]).
//!
//! Primes are below `2^31`, so a product of two residues is below `2^62` and a dot product
//! accumulates in `u128` without reducing every term.

mod dense;
mod echelon;
mod ldlt;

pub(crate) use dense::ModularLu;
pub(crate) use echelon::row_profile;
pub(crate) use ldlt::SparseLdlt;

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
        if n.is_multiple_of(small) {
            return n == small;
        }
    }
    let mut d = n - 1;
    let mut s = 0;
    while d.is_multiple_of(2) {
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

    /// The residue of a signed machine integer: Barrett on its magnitude (a 128-bit `%` is a
    /// call into the runtime's software division, once per entry and step of a lifting).
    #[inline]
    pub(crate) fn residue_i128(&self, v: i128) -> u64 {
        let r = self.reduce_wide(v.unsigned_abs());
        if v < 0 && r != 0 {
            self.p - r
        } else {
            r
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn primality_agrees_with_trial_division() {
        let trial = |n: u64| {
            n >= 2
                && (2..)
                    .take_while(|d| d * d <= n)
                    .all(|d| !n.is_multiple_of(d))
        };
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
        let p = i128::from(m.prime());
        for v in [
            0i128,
            1,
            -1,
            p,
            -p,
            -3 * p,
            p * p + 7,
            -(p * p) - 7,
            i128::MAX,
            i128::MIN,
            i128::MIN + 1,
            -987_654_321_987_654_321_987_654_321,
        ] {
            assert_eq!(i128::from(m.residue_i128(v)), v.rem_euclid(p), "{v}");
        }
        assert_eq!(m.residue_big(&BigInt::from(-5)), m.prime() - 5);
        let big = BigInt::from(3u8).pow(200u32) * -1;
        let expected = (BigInt::from(m.prime()) + (&big % m.prime())) % m.prime();
        assert_eq!(BigInt::from(m.residue_big(&big)), expected);
    }
}
