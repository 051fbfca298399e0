//! `Σ_k c_k x_k` for big integers `x_k` and multipliers `c_k` of one machine word, in limbs,
//! for [`crate::lsq`]'s affine combination `base − Σ α_k resp_k` of a drag frame.
//!
//! `num-bigint` forms each product `c_k x_k` as a new big integer (one allocation, and a
//! reallocation when the carry adds a limb) before adding it: on the spline grid's δ = 8 edit
//! the combination was 17 % of a reduced Update, most of it in the allocator. Here the
//! products of each sign are accumulated into two reused limb buffers with one
//! multiply-accumulate pass per term, and the result is built once.

use num_bigint::{BigInt, BigUint, Sign};
use num_traits::ToPrimitive;
use std::cell::RefCell;
use std::cmp::Ordering;

/// A multiplier that fits a word: its sign and magnitude.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct WordMultiplier {
    negative: bool,
    magnitude: u64,
}

impl WordMultiplier {
    /// `c` as a word multiplier, `None` when `|c| ≥ 2^64`.
    pub(crate) fn of(c: &BigInt) -> Option<Self> {
        Some(WordMultiplier {
            negative: c.sign() == Sign::Minus,
            magnitude: c.magnitude().to_u64()?,
        })
    }

    /// `−c`.
    pub(crate) fn negated(self) -> Self {
        WordMultiplier {
            negative: !self.negative && self.magnitude != 0,
            ..self
        }
    }
}

thread_local! {
    /// The positive and negative sums, and the result's 32-bit digits (`num-bigint` takes
    /// digits back only as 32-bit slices).
    static SCRATCH: RefCell<(Vec<u64>, Vec<u64>, Vec<u32>)> =
        const { RefCell::new((Vec::new(), Vec::new(), Vec::new())) };
}

/// `Σ_k c_k x_k`, exactly.
pub(crate) fn word_combination<'a>(
    terms: impl IntoIterator<Item = (WordMultiplier, &'a BigInt)>,
) -> BigInt {
    SCRATCH.with_borrow_mut(|(positive, negative, digits)| {
        positive.clear();
        negative.clear();
        for (c, x) in terms {
            if c.magnitude == 0 || x.sign() == Sign::NoSign {
                continue;
            }
            let sum = if c.negative == (x.sign() == Sign::Minus) {
                &mut *positive
            } else {
                &mut *negative
            };
            multiply_accumulate(sum, x.magnitude(), c.magnitude);
        }
        trim(positive);
        trim(negative);
        let (sign, larger, smaller) = match compare(positive, negative) {
            Ordering::Equal => return BigInt::from(0),
            Ordering::Greater => (Sign::Plus, &mut *positive, &*negative),
            Ordering::Less => (Sign::Minus, &mut *negative, &*positive),
        };
        subtract_in_place(larger, smaller);
        digits.clear();
        for limb in larger.iter() {
            digits.push(*limb as u32);
            digits.push((*limb >> 32) as u32);
        }
        BigInt::from_biguint(sign, BigUint::from_slice(digits))
    })
}

/// `sum += x · c`, growing `sum` as needed.
fn multiply_accumulate(sum: &mut Vec<u64>, x: &BigUint, c: u64) {
    let limbs = x.iter_u64_digits();
    let needed = limbs.len() + 1;
    if sum.len() < needed {
        sum.resize(needed, 0);
    }
    let mut carry = 0u64;
    let mut i = 0;
    for limb in limbs {
        let t = u128::from(limb) * u128::from(c) + u128::from(sum[i]) + u128::from(carry);
        sum[i] = t as u64;
        carry = (t >> 64) as u64;
        i += 1;
    }
    while carry != 0 {
        if i == sum.len() {
            sum.push(0);
        }
        let (s, overflow) = sum[i].overflowing_add(carry);
        sum[i] = s;
        carry = u64::from(overflow);
        i += 1;
    }
}

fn trim(v: &mut Vec<u64>) {
    while v.last() == Some(&0) {
        v.pop();
    }
}

/// Compares two trimmed magnitudes.
fn compare(a: &[u64], b: &[u64]) -> Ordering {
    a.len()
        .cmp(&b.len())
        .then_with(|| a.iter().rev().cmp(b.iter().rev()))
}

/// `a −= b` for trimmed magnitudes `a ≥ b`; `a` trimmed after.
fn subtract_in_place(a: &mut Vec<u64>, b: &[u64]) {
    let mut borrow = false;
    for (i, limb) in a.iter_mut().enumerate() {
        let subtrahend = b.get(i).copied().unwrap_or(0);
        if i >= b.len() && !borrow {
            break;
        }
        let (d, under1) = limb.overflowing_sub(subtrahend);
        let (d, under2) = d.overflowing_sub(u64::from(borrow));
        *limb = d;
        borrow = under1 || under2;
    }
    debug_assert!(!borrow, "the subtrahend is the larger");
    trim(a);
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn signed(limbs: &[u64], negative: bool) -> BigInt {
        let x = BigInt::from(crate::gcd::from_limbs(limbs));
        if negative {
            -x
        } else {
            x
        }
    }

    proptest! {
        /// The limb sums equal `num-bigint`'s products and sums, whatever the signs, lengths
        /// and cancellations (a term repeated with the opposite sign cancels exactly).
        #[test]
        fn combinations_equal_big_integer_arithmetic(
            terms in prop::collection::vec(
                (any::<u64>(), any::<bool>(), prop::collection::vec(any::<u64>(), 0..14), any::<bool>()),
                0..5,
            ),
            cancel in any::<bool>(),
        ) {
            let mut values: Vec<(BigInt, BigInt)> = terms
                .iter()
                .map(|(c, c_negative, x, x_negative)| {
                    let c = if *c_negative { -BigInt::from(*c) } else { BigInt::from(*c) };
                    (c, signed(x, *x_negative))
                })
                .collect();
            if cancel {
                if let Some((c, x)) = values.first().cloned() {
                    values.push((-c, x));
                }
            }
            let expected: BigInt = values.iter().map(|(c, x)| c * x).sum();
            let refs: Vec<(WordMultiplier, &BigInt)> = values
                .iter()
                .map(|(c, x)| (WordMultiplier::of(c).expect("a word"), x))
                .collect();
            prop_assert_eq!(word_combination(refs), expected);
        }
    }

    #[test]
    fn multipliers_beyond_a_word_are_refused() {
        assert_eq!(WordMultiplier::of(&(BigInt::from(u64::MAX) + 1)), None);
        assert_eq!(
            WordMultiplier::of(&-BigInt::from(u64::MAX)).map(|c| c.negative),
            Some(true)
        );
        assert_eq!(
            WordMultiplier::of(&BigInt::from(0)).map(WordMultiplier::negated),
            WordMultiplier::of(&BigInt::from(0))
        );
    }
}
