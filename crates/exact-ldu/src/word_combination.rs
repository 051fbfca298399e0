//! `Σ cₖ xₖ` for big integers `xₖ` and word-sized coefficients `cₖ`, scaled to 64 significant
//! bits ([`api::exact::TopBits`]) without forming a `BigInt`: the numerators of an exact
//! preview (`base · s − α r` per derived value, [`crate::lsq`]), drawn and never kept, where the
//! values have thousands of bits and the coefficients a few dozen.
//!
//! `num-bigint` forms each product as a copy of `xₖ` multiplied in place, then the sum as a third
//! number; here the products of each sign are accumulated in one reused buffer each (128-bit
//! multiply-adds) and the difference written once. (Building a `BigInt` from the result would
//! cost as much as the arithmetic: `num-bigint` takes digits only as 32-bit slices.)

use api::exact::{top_bits_of_limbs, TopBits};
use num_bigint::{BigInt, BigUint, Sign};
use std::cell::RefCell;

thread_local! {
    /// The positive and negative sums.
    static SUMS: RefCell<(Vec<u64>, Vec<u64>)> = const { RefCell::new((Vec::new(), Vec::new())) };
}

/// [`TopBits`] of `Σ cₖ xₖ` over `terms` `(xₖ, cₖ)` (iterated twice: for the length, then the
/// sum).
pub(crate) fn word_combination_top_bits<'a>(
    terms: impl IntoIterator<Item = (&'a BigInt, i64)> + Clone,
) -> TopBits {
    let limbs = terms
        .clone()
        .into_iter()
        .map(|(x, _)| x.magnitude().iter_u64_digits().len())
        .max()
        .unwrap_or(0);
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
            multiply_add(sum, x.magnitude(), c.unsigned_abs());
        }
        let is_negative = positive.iter().rev().lt(negative.iter().rev());
        let (larger, smaller) = if is_negative {
            (negative, &*positive)
        } else {
            (positive, &*negative)
        };
        subtract_in_place(larger, smaller);
        top_bits_of_limbs(larger, is_negative)
    })
}

/// `sum += x · c`; `sum` has a limb beyond `x`'s and room for the carries of earlier terms.
fn multiply_add(sum: &mut [u64], x: &BigUint, c: u64) {
    let mut carry = 0u64;
    let mut i = 0;
    for limb in x.iter_u64_digits() {
        let t = u128::from(limb) * u128::from(c) + u128::from(sum[i]) + u128::from(carry);
        sum[i] = t as u64;
        carry = (t >> 64) as u64;
        i += 1;
    }
    while carry != 0 {
        let (s, over) = sum[i].overflowing_add(carry);
        sum[i] = s;
        carry = u64::from(over);
        i += 1;
    }
}

/// `a −= b` for `a ≥ b` of equal length.
fn subtract_in_place(a: &mut [u64], b: &[u64]) {
    let mut borrow = false;
    for (a, b) in a.iter_mut().zip(b) {
        let (d, under1) = a.overflowing_sub(*b);
        let (d, under2) = d.overflowing_sub(u64::from(borrow));
        *a = d;
        borrow = under1 || under2;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::exact::top_bits;
    use proptest::prelude::*;

    fn big(limbs: &[u64], negative: bool) -> BigInt {
        let magnitude = limbs.iter().rev().fold(BigUint::default(), |acc, l| {
            (acc << 64u32) + BigUint::from(*l)
        });
        let sign = if negative { Sign::Minus } else { Sign::Plus };
        BigInt::from_biguint(sign, magnitude)
    }

    #[test]
    fn cancelling_terms_give_zero() {
        let x = big(&[u64::MAX, 7, u64::MAX], false);
        let y = -&x * 3;
        assert_eq!(
            word_combination_top_bits([(&x, 6), (&y, 2)]),
            top_bits(&BigInt::default())
        );
    }

    #[test]
    fn extreme_coefficients_carry_into_the_top() {
        let x = big(&[u64::MAX; 5], false);
        let y = big(&[u64::MAX; 5], true);
        for (a, b) in [
            (i64::MAX, i64::MIN),
            (i64::MIN, i64::MIN),
            (i64::MAX, i64::MAX),
        ] {
            assert_eq!(
                word_combination_top_bits([(&x, a), (&y, b)]),
                top_bits(&(&x * a + &y * b))
            );
        }
    }

    proptest! {
        /// The scaled sum is that of `num-bigint`'s sum, for any signs, lengths and
        /// coefficients.
        #[test]
        fn sums_are_those_of_big_integers(
            terms in prop::collection::vec(
                (prop::collection::vec(any::<u64>(), 0..12), any::<bool>(), any::<i64>()),
                1..5,
            ),
        ) {
            let values: Vec<(BigInt, i64)> =
                terms.iter().map(|(l, n, c)| (big(l, *n), *c)).collect();
            let expected = values.iter().fold(BigInt::default(), |acc, (x, c)| acc + x * c);
            prop_assert_eq!(
                word_combination_top_bits(values.iter().map(|(x, c)| (x, *c))),
                top_bits(&expected)
            );
        }
    }
}
