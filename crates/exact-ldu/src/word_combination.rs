//! `(Σ cₖ xₖ) / d` rounded to `f64` as [`api::exact::fraction_to_f64`] rounds it, for big
//! integers `xₖ` and word-sized coefficients `cₖ`, without forming the sum as a `BigInt`: the
//! entries of an exact preview (`base · s − α r` over the solution's denominator per derived
//! value, [`crate::lsq`]), drawn and never kept, where the values have thousands of bits and the
//! coefficients a few dozen.
//!
//! First from the top limbs alone: the [`TOP_LIMBS`] top limbs of each `xₖ` times `cₖ` give the
//! sum up to less than one unit of its second limb per term, so the sum lies between two
//! numbers known exactly. The conversion is monotone (a shift rounding towards −∞ to 64
//! significant bits, a rounding to nearest, a division by the positive `d`, an exact power of
//! two), so when both bounds give the same normal `f64`, so does the sum: a few limbs per term
//! instead of thousands. Otherwise (a sum cancelling to its last limbs, a bound at a rounding
//! boundary) the whole sum: the products of each sign accumulated in one reused buffer each
//! (128-bit multiply-adds) and their difference written once. (Building a `BigInt` from that
//! would cost as much as the arithmetic: `num-bigint` takes digits only as 32-bit slices.)

use crate::gcd::subtract_limbs;
use api::exact::{top_bits_of_limbs, top_bits_of_limbs_above, TopBits};
use num_bigint::{BigInt, Sign};
use std::cell::RefCell;

/// Limbs of each term the first attempt reads: enough for the 53 bits of an `f64` through up
/// to ~120 bits of cancellation.
const TOP_LIMBS: usize = 3;

/// A sum of products of [`TOP_LIMBS`] limbs by a word, with room for the carries and the bounds.
type TopSum = [u64; TOP_LIMBS + 3];

thread_local! {
    /// The positive and negative sums.
    static SUMS: RefCell<(Vec<u64>, Vec<u64>)> = const { RefCell::new((Vec::new(), Vec::new())) };
}

/// `(Σ cₖ xₖ) / d` over `terms` `(xₖ, cₖ)` and `d > 0` given as [`TopBits`], rounded as
/// [`api::exact::fraction_to_f64`] rounds it (`terms` is iterated more than once).
pub(crate) fn word_combination_to_f64<'a>(
    terms: impl IntoIterator<Item = (&'a BigInt, i64)> + Clone,
    denominator: TopBits,
) -> f64 {
    let limbs = longest(terms.clone());
    if limbs > TOP_LIMBS {
        if let Some(value) = from_top_limbs(terms.clone(), limbs - TOP_LIMBS, denominator) {
            return value;
        }
    }
    whole_sum(terms, limbs).over(denominator)
}

/// The most limbs of any term's `xₖ`.
fn longest<'a>(terms: impl IntoIterator<Item = (&'a BigInt, i64)>) -> usize {
    terms
        .into_iter()
        .map(|(x, _)| x.magnitude().iter_u64_digits().len())
        .max()
        .unwrap_or(0)
}

/// The value from the limbs from `below` up, when the bounds on the rest agree (see the module
/// documentation).
fn from_top_limbs<'a>(
    terms: impl IntoIterator<Item = (&'a BigInt, i64)>,
    below: usize,
    denominator: TopBits,
) -> Option<f64> {
    let mut positive = TopSum::default();
    let mut negative = TopSum::default();
    // Terms of each sign: the limbs below `below` of each may add up to one unit of limb 1.
    let (mut rest_positive, mut rest_negative) = (0u64, 0u64);
    for (x, c) in terms {
        if c == 0 || x.sign() == Sign::NoSign {
            continue;
        }
        let magnitude = x.magnitude();
        let is_positive = (c > 0) == (x.sign() == Sign::Plus);
        let (sum, rest) = if is_positive {
            (&mut positive, &mut rest_positive)
        } else {
            (&mut negative, &mut rest_negative)
        };
        multiply_add(
            sum,
            magnitude.iter_u64_digits().skip(below),
            c.unsigned_abs(),
        );
        *rest += 1;
    }
    // The sum lies in [positive − negative − rest_negative·2^64, positive + rest_positive·2^64
    // − negative], in units of limb `below`.
    let mut low_negative = negative;
    add_at(&mut low_negative, 1, rest_negative);
    let mut high_positive = positive;
    add_at(&mut high_positive, 1, rest_positive);
    let low = difference_to_f64(&positive, &low_negative, below, denominator);
    let high = difference_to_f64(&high_positive, &negative, below, denominator);
    (low.to_bits() == high.to_bits() && low.is_normal()).then_some(low)
}

/// `(a − b)·2^(64 below) / d` as [`api::exact::fraction_to_f64`] rounds it.
fn difference_to_f64(a: &TopSum, b: &TopSum, below: usize, denominator: TopBits) -> f64 {
    let is_negative = a.iter().rev().lt(b.iter().rev());
    let (mut larger, smaller) = if is_negative { (*b, a) } else { (*a, b) };
    subtract_limbs(&mut larger, smaller);
    top_bits_of_limbs_above(&larger, below, is_negative).over(denominator)
}

/// `sum[at..] += v`.
fn add_at(sum: &mut [u64], mut at: usize, mut v: u64) {
    while v != 0 {
        let (s, over) = sum[at].overflowing_add(v);
        sum[at] = s;
        v = u64::from(over);
        at += 1;
    }
}

/// [`TopBits`] of `Σ cₖ xₖ`, every limb summed; `limbs` is the longest `xₖ`'s length.
fn whole_sum<'a>(terms: impl IntoIterator<Item = (&'a BigInt, i64)>, limbs: usize) -> TopBits {
    with_whole_sum(terms, limbs, top_bits_of_limbs)
}

/// `Σ cₖ xₖ` over `terms` `(xₖ, cₖ)`, exactly, for word-sized coefficients: the products of
/// each sign accumulated in limbs (128-bit multiply-adds into reused buffers) and the result
/// made a `BigInt` once, in one allocation of its length. A `BigInt` product per term allocated
/// a copy of `xₖ`, grew it by a limb for the carry (a reallocation and a copy) and allocated the
/// difference again: the exact update's entries (`base · s − α r` per derived value).
pub(crate) fn word_combination<'a>(
    terms: impl IntoIterator<Item = (&'a BigInt, i64)> + Clone,
) -> BigInt {
    let limbs = longest(terms.clone());
    with_whole_sum(terms, limbs, |magnitude, is_negative| {
        let value = crate::gcd::from_limbs(magnitude);
        let sign = if is_negative { Sign::Minus } else { Sign::Plus };
        BigInt::from_biguint(sign, value)
    })
}

/// `Σ cₖ xₖ` summed in the thread's buffers and given to `f` as its magnitude's limbs (with
/// leading zeros) and whether it is negative; `limbs` is the longest `xₖ`'s length.
fn with_whole_sum<'a, R>(
    terms: impl IntoIterator<Item = (&'a BigInt, i64)>,
    limbs: usize,
    f: impl FnOnce(&[u64], bool) -> R,
) -> R {
    // A product has at most `limbs + 1` limbs, a sum of fewer than 2^64 of them one more.
    let width = limbs + 2;
    SUMS.with_borrow_mut(|(positive, negative)| {
        positive.clear();
        positive.resize(width, 0);
        negative.clear();
        negative.resize(width, 0);
        for (x, c) in terms {
            if c == 0 || x.sign() == Sign::NoSign {
                continue;
            }
            let sum = if (c > 0) == (x.sign() == Sign::Plus) {
                &mut *positive
            } else {
                &mut *negative
            };
            multiply_add(sum, x.magnitude().iter_u64_digits(), c.unsigned_abs());
        }
        let is_negative = positive.iter().rev().lt(negative.iter().rev());
        let (larger, smaller) = if is_negative {
            (negative, &*positive)
        } else {
            (positive, &*negative)
        };
        subtract_limbs(larger, smaller);
        f(larger, is_negative)
    })
}

/// `sum += x · c` for the limbs `x`; `sum` has a limb beyond `x`'s and room for the carries of
/// earlier terms.
fn multiply_add(sum: &mut [u64], x: impl Iterator<Item = u64>, c: u64) {
    let mut carry = 0u64;
    let mut i = 0;
    for limb in x {
        let t = u128::from(limb) * u128::from(c) + u128::from(sum[i]) + u128::from(carry);
        sum[i] = t as u64;
        carry = (t >> 64) as u64;
        i += 1;
    }
    add_at(sum, i, carry);
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::exact::{fraction_to_f64, top_bits};
    use num_bigint::BigUint;
    use proptest::prelude::*;

    fn big(limbs: &[u64], negative: bool) -> BigInt {
        let magnitude = limbs.iter().rev().fold(BigUint::default(), |acc, l| {
            (acc << 64u32) + BigUint::from(*l)
        });
        let sign = if negative { Sign::Minus } else { Sign::Plus };
        BigInt::from_biguint(sign, magnitude)
    }

    /// The value of the sum computed in big integers, and this module's, bit for bit; the
    /// exact sum equal to the big integers' ([`word_combination`]).
    fn check(terms: &[(BigInt, i64)], d: &BigInt) -> Result<(), TestCaseError> {
        let sum = terms
            .iter()
            .fold(BigInt::default(), |acc, (x, c)| acc + x * c);
        prop_assert_eq!(
            word_combination(terms.iter().map(|(x, c)| (x, *c))),
            sum.clone()
        );
        let expected = fraction_to_f64(&sum, d);
        let found = word_combination_to_f64(terms.iter().map(|(x, c)| (x, *c)), top_bits(d));
        prop_assert!(
            found.to_bits() == expected.to_bits(),
            "{} against {} for {:?} / {}",
            found,
            expected,
            terms,
            d
        );
        Ok(())
    }

    #[test]
    fn cancelling_terms_give_zero() {
        let x = big(&[u64::MAX, 7, u64::MAX, 3, 9], false);
        let y = -&x * 3;
        let d = BigInt::from(7);
        let zero = word_combination([(&x, 6), (&y, 2)]);
        assert_eq!(zero, BigInt::default());
        assert_eq!(zero.sign(), Sign::NoSign);
        assert_eq!(
            word_combination_to_f64([(&x, 6), (&y, 2)], top_bits(&d)),
            0.0
        );
    }

    #[test]
    fn extreme_coefficients_carry_into_the_top() {
        let x = big(&[u64::MAX; 5], false);
        let y = big(&[u64::MAX; 5], true);
        let d = big(&[5, 1 << 40, 3, u64::MAX], false);
        for (a, b) in [
            (i64::MAX, i64::MIN),
            (i64::MIN, i64::MIN),
            (i64::MAX, i64::MAX),
        ] {
            check(&[(x.clone(), a), (y.clone(), b)], &d).expect("equal");
        }
    }

    /// Sums that cancel their top limbs (down to the last limb, or to one above the top limbs
    /// read first), and a negative sum whose rounding towards −∞ depends on the lowest limb:
    /// the top limbs cannot decide, the whole sum does.
    #[test]
    fn sums_the_top_limbs_cannot_decide_take_every_limb() {
        let d = big(&[1, 2, 3, 4, 5, 6], false);
        let x = big(&[9, 8, 7, 6, 5, 4, 3, 2], false);
        for low in [
            big(&[1], false),
            big(&[0, 0, 0, 1 << 20], false),
            big(&[3, 0, 0, 0, 1], true),
        ] {
            let y = -(&x * BigInt::from(5) + &low);
            check(&[(x.clone(), 15), (y, 3)], &d).expect("equal");
        }
        // −(2^63 + 2^11 + 2^10 − 1)·2^(64·7) − 1: rounded towards −∞ to 64 bits, then to the
        // even `f64` one unit of 2^12 further out.
        let x = big(
            &[1, 0, 0, 0, 0, 0, 0, (1 << 63) + (1 << 11) + (1 << 10) - 1],
            true,
        );
        check(&[(x, 1)], &BigInt::from(1)).expect("equal");
    }

    /// Sums cancelled down to the limbs where the top limbs' bounds meet the rounding: the
    /// remainders `2^k − j` (`j` small) of every length around the limbs below those read first,
    /// with coefficients large enough that each term's lower limbs carry into them.
    #[test]
    fn sums_near_the_bounds_of_the_top_limbs_round_as_the_whole_sums() {
        let x = big(
            &[
                0x9e37_79b9_7f4a_7c15,
                0xbf58_476d_1ce4_e5b9,
                0x94d0_49bb_1331_11eb,
                u64::MAX,
                1 << 62,
            ],
            false,
        );
        let d = big(&[0x2545_f491_4f6c_dd1d, 7], false);
        for k in 64..320u32 {
            for j in [0u64, 1, 2, 0x7ff, 0x800, 0x801, u64::MAX] {
                let low = (BigInt::from(1) << k) - BigInt::from(j);
                for (a, b) in [(1i64, 1i64), (3, (1 << 40) + 1), ((1 << 31) - 1, 1 << 30)] {
                    let y = -(&x * a + &low);
                    check(&[(x.clone(), a * b), (y, b)], &d).expect("equal");
                    check(&[(x.clone(), -a * b), (-(&x * a) - &low, -b)], &d).expect("equal");
                }
            }
        }
    }

    proptest! {
        /// The value is that of `num-bigint`'s sum, for any signs, lengths, coefficients and
        /// denominators, and for sums made to cancel.
        #[test]
        fn values_are_those_of_big_integer_sums(
            terms in prop::collection::vec(
                (prop::collection::vec(any::<u64>(), 0..12), any::<bool>(), any::<i64>()),
                1..5,
            ),
            d in prop::collection::vec(any::<u64>(), 1..8),
            cancel in prop::option::of((1i64..1000, 1i64..1000, prop::collection::vec(any::<u64>(), 0..12))),
        ) {
            let mut values: Vec<(BigInt, i64)> =
                terms.iter().map(|(l, n, c)| (big(l, *n), *c)).collect();
            let d = big(&d, false);
            prop_assume!(d.sign() == Sign::Plus);
            if let Some((a, b, low)) = cancel {
                // y = −(a x + low): (a b) x + b y = −b low, the top limbs cancelled.
                let x = values[0].0.clone();
                let y = -(&x * a + big(&low, false));
                values = vec![(x, a * b), (y, b)];
            }
            check(&values, &d)?;
        }
    }
}
