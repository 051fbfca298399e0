//! Reducing fractions over one denominator in machine words: [`crate::reduce_over`] for values
//! and a denominator within 127 bits (the solutions of small edits and drag frames).
//!
//! One GCD per value, even in registers (Lehmer steps on two words), was half of a small exact
//! update. But the common factors have the structure [`crate::reduce`] describes: on edit
//! solutions `gcd(nᵢ, d)` is a product of small primes dividing `d`, or it contains the whole
//! rest of `d` (a value the constraints leave at a small denominator). So `d = 2ᵗ · S · B` is
//! split once per vector into its power of two, the primes of [`ODD_PRIMES`] with their
//! exponents, and the rest `B` (odd, no prime below 64), and every test is a multiplication:
//!
//! - `p | n` for an odd `p` is `n · p⁻¹ mod 2^128 ≤ ⌊(2^128 − 1) / p⌋`, and then `n · p⁻¹` is
//!   the quotient (exact division by the inverse modulo a power of two, Granlund and
//!   Montgomery 1994, section 9); the same test with `B` finds the values divisible by `B`;
//! - for the other values, every prime shared by `B` and some `nᵢ` divides
//!   `g = gcd(Π nᵢ mod B, B)`: the product runs as Montgomery multiplications modulo `B` (the
//!   powers of `2^128` it picks up are units modulo the odd `B`), and one GCD ends it. Usually
//!   `g = 1`; otherwise those values take one GCD each with `B`.
//!
//! The reduced denominators are divided alongside (by the same inverses), so no value costs a
//! division.

use crate::gcd::gcd_u128;

/// The odd primes below 64, split off the denominator by trial division (larger ones are
/// found through the product modulo `B`).
const ODD_PRIMES: [u128; 17] = [
    3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61,
];

/// `x⁻¹ mod 2^128` for odd `x` (Newton's iteration doubles the correct low bits: 5 from
/// `3x ⊕ 2`, then 10, 20, 40, 80, 160).
const fn inverse_mod_2_128(x: u128) -> u128 {
    let mut inv = x.wrapping_mul(3) ^ 2;
    let mut step = 0;
    while step < 5 {
        inv = inv.wrapping_mul(2u128.wrapping_sub(x.wrapping_mul(inv)));
        step += 1;
    }
    inv
}

/// An odd divisor with what exact division by it needs.
#[derive(Debug, Clone, Copy)]
struct OddDivisor {
    value: u128,
    /// `value⁻¹ mod 2^128`.
    inverse: u128,
    /// `⌊(2^128 − 1) / value⌋`: `n` is a multiple of `value` iff `n · inverse` is at most this.
    limit: u128,
}

impl OddDivisor {
    const fn new(value: u128) -> Self {
        OddDivisor {
            value,
            inverse: inverse_mod_2_128(value),
            limit: u128::MAX / value,
        }
    }

    /// `n / value` when `value` divides `n`.
    fn quotient(&self, n: u128) -> Option<u128> {
        let q = n.wrapping_mul(self.inverse);
        (q <= self.limit).then_some(q)
    }
}

/// The odd primes with their inverses, once.
const ODD_DIVISORS: [OddDivisor; 17] = {
    let mut out = [OddDivisor::new(3); 17];
    let mut i = 0;
    while i < ODD_PRIMES.len() {
        out[i] = OddDivisor::new(ODD_PRIMES[i]);
        i += 1;
    }
    out
};

/// `a · b` as `(high, low)` words of 128 bits.
fn mul_wide(a: u128, b: u128) -> (u128, u128) {
    let (a0, a1) = (a as u64 as u128, a >> 64);
    let (b0, b1) = (b as u64 as u128, b >> 64);
    let (p00, p01, p10, p11) = (a0 * b0, a0 * b1, a1 * b0, a1 * b1);
    // At most 3 (2^64 − 1): no overflow.
    let middle = (p00 >> 64) + (p01 as u64 as u128) + (p10 as u64 as u128);
    let low = (p00 as u64 as u128) | (middle << 64);
    let high = p11 + (p01 >> 64) + (p10 >> 64) + (middle >> 64);
    (high, low)
}

/// Montgomery multiplication modulo an odd `modulus < 2^127`: `a · b · 2^−128 mod modulus` for
/// `a < modulus` and any `b` (so `a b < modulus · 2^128`, as REDC requires).
struct Montgomery {
    modulus: u128,
    /// `−modulus⁻¹ mod 2^128`.
    negated_inverse: u128,
}

impl Montgomery {
    fn new(divisor: &OddDivisor) -> Self {
        Montgomery {
            modulus: divisor.value,
            negated_inverse: divisor.inverse.wrapping_neg(),
        }
    }

    fn mul(&self, a: u128, b: u128) -> u128 {
        let (high, low) = mul_wide(a, b);
        let m = low.wrapping_mul(self.negated_inverse);
        let (mh, _) = mul_wide(m, self.modulus);
        // low + ml ≡ 0 (mod 2^128): it carries exactly when low ≠ 0. The sum `t` is below
        // 2 · modulus < 2^128.
        let carry = u128::from(low != 0);
        let t = high + mh + carry;
        if t >= self.modulus {
            t - self.modulus
        } else {
            t
        }
    }
}

/// A reduced fraction in words: `sign · magnitude / denominator`, `denominator > 0`.
pub(crate) type WordRatio = (i128, i128);

/// `numerators[i] / den` in lowest terms with positive denominators, or `None` when `den` is
/// zero or `den` or a value is `i128::MIN` (whose magnitude has no `i128`).
pub(crate) fn reduce_words(numerators: &[i128], den: i128) -> Option<Vec<WordRatio>> {
    if den == 0 || den == i128::MIN || numerators.contains(&i128::MIN) {
        return None;
    }
    let flip = den < 0;
    let d = den.unsigned_abs();
    // d = 2^twos · Π pᵉ · rest.
    let twos = d.trailing_zeros();
    let mut rest = d >> twos;
    let mut primes: Vec<(OddDivisor, u32)> = Vec::new();
    for divisor in &ODD_DIVISORS {
        let mut e = 0;
        while let Some(q) = divisor.quotient(rest) {
            rest = q;
            e += 1;
        }
        if e > 0 {
            primes.push((*divisor, e));
        }
    }
    let rest = (rest > 1).then(|| OddDivisor::new(rest));
    let montgomery = rest.as_ref().map(Montgomery::new);
    // Per value: its magnitude and reduced denominator after the small primes and `rest`;
    // `coprime_to_rest` unknown (the product decides) for the values `rest` does not divide.
    let mut out: Vec<(u128, u128, bool)> = Vec::with_capacity(numerators.len());
    let mut product: u128 = 1;
    for &n in numerators {
        let mut m = n.unsigned_abs();
        if m == 0 {
            out.push((0, 1, false));
            continue;
        }
        let shift = m.trailing_zeros().min(twos);
        m >>= shift;
        let mut reduced = d >> shift;
        for (divisor, e) in &primes {
            for _ in 0..*e {
                match divisor.quotient(m) {
                    Some(q) => {
                        m = q;
                        reduced = reduced.wrapping_mul(divisor.inverse);
                    }
                    None => break,
                }
            }
        }
        let mut pending = false;
        if let (Some(rest), Some(mont)) = (&rest, &montgomery) {
            match rest.quotient(m) {
                Some(q) => {
                    m = q;
                    reduced = reduced.wrapping_mul(rest.inverse);
                }
                None => {
                    product = mont.mul(product, m);
                    pending = true;
                }
            }
        }
        out.push((m, reduced, pending));
    }
    if let Some(rest) = &rest {
        if gcd_u128(product, rest.value) != 1 {
            // Some prime of `rest` divides some value: one GCD each for the candidates.
            for (m, reduced, pending) in &mut out {
                if *pending {
                    let g = gcd_u128(*m, rest.value);
                    *m /= g;
                    *reduced /= g;
                }
            }
        }
    }
    Some(
        numerators
            .iter()
            .zip(out)
            .map(|(&n, (m, reduced, _))| {
                // m ≤ |n| < 2^127 and reduced ≤ d < 2^127: both fit.
                let magnitude = m as i128;
                let negative = (n < 0) != flip;
                (
                    if negative { -magnitude } else { magnitude },
                    reduced as i128,
                )
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn reference(n: i128, d: i128) -> (i128, i128) {
        let g = num_integer::Integer::gcd(&n, &d);
        let (n, d) = (n / g, d / g);
        if d < 0 {
            (-n, -d)
        } else {
            (n, d)
        }
    }

    #[test]
    fn inverses_and_montgomery_products() {
        for x in [1u128, 3, 61, (1 << 126) + 1, u128::MAX] {
            assert_eq!(x.wrapping_mul(inverse_mod_2_128(x)), 1);
        }
        let m = Montgomery::new(&OddDivisor::new((1 << 126) + 15));
        let r = (1u128 << 127) % m.modulus; // 2^127 mod modulus
        let r = (r * 2) % m.modulus; // 2^128 mod modulus
        for (a, b) in [(5u128, 7u128), (m.modulus - 1, u128::MAX), (0, 9)] {
            // mont(a, b) · 2^128 ≡ a b (mod modulus): compare both sides through mul_wide.
            let got = m.mul(a % m.modulus, b);
            let lhs = mont_reference(got, r, m.modulus);
            let rhs = mont_reference(a % m.modulus, b % m.modulus, m.modulus);
            assert_eq!(lhs, rhs);
        }
    }

    /// `a · b mod m` by double-and-add (a slow reference).
    fn mont_reference(a: u128, b: u128, m: u128) -> u128 {
        let (mut acc, mut x, mut y) = (0u128, a % m, b);
        while y > 0 {
            if y & 1 == 1 {
                acc = (acc + x) % m;
            }
            x = (x + x) % m;
            y >>= 1;
        }
        acc
    }

    #[test]
    fn edit_like_denominators() {
        // A denominator of a δ = 3 spline edit: small primes times a large rest; values
        // sharing small factors, the whole rest, or nothing.
        let d: i128 = 111_705_071_369_956_129_423_697_087_335_500;
        let rest = d / 5;
        for n in [
            0,
            1,
            -1,
            225 * 7,
            d,
            -d,
            rest * 3,
            rest * 7 + 1,
            4275 * 11 + 4275,
            i128::MAX,
            -i128::MAX,
        ] {
            let got = reduce_words(&[n], d).expect("fits");
            assert_eq!(got[0], reference(n, d), "{n}");
        }
        // Primes above 64 shared with some values, not with all of the rest: the product
        // finds them, those values take a GCD each.
        let d = 3 * 67 * 4093 * 65_537;
        let values = [
            67 * 5,
            4093 * 2,
            65_537 * 67,
            7,
            3 * 67 * 4093 * 65_537 * 11,
        ];
        let got = reduce_words(&values, d).expect("fits");
        for (n, r) in values.iter().zip(got) {
            assert_eq!(r, reference(*n, d), "{n}");
        }
        assert_eq!(reduce_words(&[1], 0), None);
        assert_eq!(reduce_words(&[i128::MIN], 3), None);
        assert_eq!(reduce_words(&[3, 6], -9), Some(vec![(-1, 3), (-2, 3)]));
    }

    proptest! {
        /// The same reduced fractions as one GCD per value, for denominators made of small
        /// primes, primes above 64 shared with some values, and large rests.
        #[test]
        fn words_reduce_as_gcds(
            small in prop::collection::vec(prop::sample::select(vec![2i128, 3, 5, 19, 61]), 0..12),
            large in prop::collection::vec(prop::sample::select(vec![67i128, 4093, 65_537, 2_147_483_647]), 0..3),
            cofactor in 1i128..1_000_000,
            factors in prop::collection::vec((any::<i64>(), 0usize..4), 1..40),
            negative in any::<bool>(),
        ) {
            let mut d: i128 = cofactor;
            for p in small.iter().chain(&large) {
                d = d.checked_mul(*p).unwrap_or(d);
            }
            let d = if negative { -d } else { d };
            let primes: Vec<i128> = small.iter().chain(&large).copied().chain([cofactor]).collect();
            let numerators: Vec<i128> = factors
                .iter()
                .map(|(x, k)| {
                    let p = primes.get(*k).copied().unwrap_or(1);
                    i128::from(*x).checked_mul(p).unwrap_or(i128::from(*x))
                })
                .collect();
            let got = reduce_words(&numerators, d).expect("fits");
            for (n, r) in numerators.iter().zip(got) {
                prop_assert_eq!(r, reference(*n, d));
            }
        }

        /// Arbitrary words, including values near `2^127`.
        #[test]
        fn arbitrary_words(n in any::<i128>(), d in any::<i128>(), shift in 0u32..127) {
            prop_assume!(n != i128::MIN && d != 0 && d != i128::MIN);
            let d = d >> shift;
            prop_assume!(d != 0);
            let got = reduce_words(&[n], d).expect("fits");
            prop_assert_eq!(got[0], reference(n, d));
        }
    }
}
