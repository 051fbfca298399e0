//! Dividing big integers by one machine word, for [`crate::reduce_over`]: exact quotients by
//! multiplication with an inverse modulo `2^64` and remainders by precomputed powers of
//! `2^64`; the inverse also serves [`crate::montgomery`].
//!
//! `num-bigint` takes a remainder modulo a word with one 128-by-64-bit hardware division per
//! limb; modulo a word `p < 2^32` it is a sum of limbs times the powers `2^(64i) mod p`, one
//! product per limb and one division at the end.

use crate::gcd::assign_limbs;
use num_bigint::{BigInt, BigUint, Sign};
use num_traits::ToPrimitive;
use std::cell::RefCell;

/// `odd⁻¹ mod 2^64` by Newton's iteration (5, 10, 20, 40, 80 correct bits).
pub(crate) fn word_inverse(odd: u64) -> u64 {
    debug_assert!(odd & 1 == 1);
    let mut inverse = odd.wrapping_mul(3) ^ 2;
    for _ in 0..4 {
        inverse = inverse.wrapping_mul(2u64.wrapping_sub(odd.wrapping_mul(inverse)));
    }
    inverse
}

/// `x / c` for a nonzero divisor `c` of `x`: by [`exact_quotient_by_word`] when `|c|` fits a
/// word, else `num-bigint`'s long division.
pub(crate) fn exact_quotient(x: BigInt, c: &BigInt) -> BigInt {
    match c.magnitude().to_u64() {
        Some(word) if c.sign() == Sign::Minus => -exact_word_quotient(x, word),
        Some(word) => exact_word_quotient(x, word),
        None => x / c,
    }
}

/// `(⌊(u1·2^64 + u0) / d⌋, (u1·2^64 + u0) mod d)` for a normalised `d` (top bit set) and
/// `u1 < d`, given `reciprocal = ⌊(2^128 − 1) / d⌋ − 2^64`: Möller and Granlund's division of
/// two words by one ("Improved division by invariant integers", 2011, algorithm 4), two
/// multiplications and two corrections instead of the runtime's 128-bit division.
#[inline]
pub(crate) fn divide_two_words(u1: u64, u0: u64, d: u64, reciprocal: u64) -> (u64, u64) {
    debug_assert!(d >> 63 == 1 && u1 < d);
    let q = u128::from(reciprocal) * u128::from(u1) + ((u128::from(u1) << 64) | u128::from(u0));
    let mut q1 = ((q >> 64) as u64).wrapping_add(1);
    let q0 = q as u64;
    let mut r = u0.wrapping_sub(q1.wrapping_mul(d));
    if r > q0 {
        q1 = q1.wrapping_sub(1);
        r = r.wrapping_add(d);
    }
    if r >= d {
        q1 += 1;
        r -= d;
    }
    (q1, r)
}

/// `x / c` for a nonzero word `c` dividing `x`, by [`exact_quotient_by_word`].
pub(crate) fn exact_word_quotient(x: BigInt, c: u64) -> BigInt {
    debug_assert!(c != 0);
    if c == 1 {
        return x;
    }
    let (sign, magnitude) = x.into_parts();
    BigInt::from_biguint(sign, exact_quotient_by_word(magnitude, c))
}

thread_local! {
    /// The quotient's limbs on their way back into the dividend's own buffer.
    static QUOTIENT: RefCell<Vec<u64>> = const { RefCell::new(Vec::new()) };
}

/// `x / c` for a word `c > 1` dividing `x`, in `x`'s buffer. The odd part by Jebelean's exact
/// division (as in GMP's `divexact_1`): each quotient limb is the limb times `odd⁻¹ mod 2^64`,
/// the borrow into the next the high word of `qᵢ · odd` — two multiplications per limb where
/// `num-bigint` divides each limb in hardware (tens of cycles; 11 % of a δ = 8 spline
/// update). The power of two is shifted out on the way; the limbs pass through a reused
/// buffer (`num-bigint` lends its digits only for reading).
fn exact_quotient_by_word(mut x: BigUint, c: u64) -> BigUint {
    let shift = c.trailing_zeros();
    let odd = c >> shift;
    let inverse = word_inverse(odd);
    QUOTIENT.with_borrow_mut(|quotient| {
        let limbs = x.iter_u64_digits();
        let n = limbs.len();
        quotient.clear();
        quotient.resize(n, 0);
        // Quotient limb `i − 1` is complete once limb `i` is known (the shift takes its low bits).
        let mut borrow = 0u64;
        let mut previous = 0u64;
        for (i, limb) in limbs.enumerate() {
            let q = if odd == 1 {
                limb
            } else {
                let (t, under) = limb.overflowing_sub(borrow);
                let q = t.wrapping_mul(inverse);
                borrow = ((u128::from(q) * u128::from(odd)) >> 64) as u64 + u64::from(under);
                q
            };
            if i > 0 {
                quotient[i - 1] = if shift == 0 {
                    previous
                } else {
                    (previous >> shift) | (q << (64 - shift))
                };
            }
            previous = q;
        }
        if n > 0 {
            quotient[n - 1] = previous >> shift;
        }
        debug_assert_eq!(borrow, 0, "the divisor does not divide");
        assign_limbs(&mut x, quotient);
    });
    x
}

/// Remainders modulo one word `p < 2^32` of values of at most `powers.len()` limbs.
#[derive(Debug, Clone)]
pub(crate) struct WordRemainder {
    modulus: u64,
    /// `2^(64i) mod p`.
    powers: Vec<u64>,
}

impl WordRemainder {
    /// For values of at most `limbs` limbs (longer ones still work, by extending the powers).
    pub(crate) fn new(modulus: u32, limbs: usize) -> Self {
        let mut remainder = WordRemainder {
            modulus: u64::from(modulus),
            powers: Vec::new(),
        };
        remainder.extend(limbs);
        remainder
    }

    fn extend(&mut self, limbs: usize) {
        let p = u128::from(self.modulus);
        let step = ((1u128 << 64) % p) as u64;
        while self.powers.len() < limbs {
            let next = match self.powers.last() {
                None => (1 % p) as u64,
                Some(&last) => ((u128::from(last) * u128::from(step)) % p) as u64,
            };
            self.powers.push(next);
        }
    }

    /// `x mod p`: each term `limb · 2^(64i) mod p` is below `2^96`, so `2^31` of them add up
    /// in a `u128` before the one division.
    pub(crate) fn of(&self, x: &BigUint) -> u64 {
        let digits = x.iter_u64_digits();
        if digits.len() > self.powers.len() {
            let mut longer = self.clone();
            longer.extend(digits.len());
            return longer.of(x);
        }
        let mut sum = 0u128;
        for (i, (limb, power)) in digits.zip(&self.powers).enumerate() {
            if i & ((1 << 31) - 1) == (1 << 31) - 1 {
                sum %= u128::from(self.modulus);
            }
            sum += u128::from(limb) * u128::from(*power);
        }
        (sum % u128::from(self.modulus)) as u64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_traits::Zero;
    use proptest::prelude::*;

    fn big(limbs: &[u64]) -> BigUint {
        crate::gcd::from_limbs(limbs)
    }

    proptest! {
        /// `(c · q) / c = q` with the sign of `x / c`, for words and for longer divisors.
        #[test]
        fn exact_quotients(
            q in prop::collection::vec(any::<u64>(), 0..20),
            c in prop::collection::vec(any::<u64>(), 1..3),
            negative_q in any::<bool>(),
            negative_c in any::<bool>(),
        ) {
            let c = BigInt::from(big(&c));
            prop_assume!(!c.is_zero());
            let c = if negative_c { -c } else { c };
            let q = BigInt::from(big(&q));
            let q = if negative_q { -q } else { q };
            prop_assert_eq!(exact_quotient(&q * &c, &c), q);
        }

        /// Words with long runs of trailing zeros (the powers of two of a denominator).
        #[test]
        fn exact_quotients_by_even_words(
            q in prop::collection::vec(any::<u64>(), 0..20),
            odd in any::<u64>(),
            shift in 0u32..64,
        ) {
            let c = BigInt::from((odd | 1) << shift);
            let q = BigInt::from(big(&q));
            prop_assert_eq!(exact_quotient(&q * &c, &c), q);
        }

        /// `x mod p` as `num-bigint` computes it, with the powers made for shorter values too.
        #[test]
        fn word_remainders(
            x in prop::collection::vec(any::<u64>(), 0..30),
            p in 1u32..,
            limbs in 0usize..30,
        ) {
            let x = big(&x);
            let expected = (&x % p).to_u64().expect("below p");
            prop_assert_eq!(WordRemainder::new(p, limbs).of(&x), expected);
        }
    }

    #[test]
    fn inverses() {
        for odd in [1u64, 3, 5, 0xffff_ffff_ffff_ffff, 0x1234_5678_9abc_def1] {
            assert_eq!(odd.wrapping_mul(word_inverse(odd)), 1);
        }
    }
}
