//! Allocation-free sums of products of big integers.
//!
//! The hot loop of an ECLES update is `x_s = Σ_k H_sk ρ_k` with a fixed matrix `H` of
//! several-hundred-bit entries and small `ρ_k`. Done with `BigInt` operators every product and
//! every partial sum allocates; here each term is one pass of multiply-accumulate over machine
//! words into a buffer that is reused for the whole sum.

use crate::ring::Ring;
use num_bigint::{BigInt, BigUint, Sign};

/// A read-only signed big integer as sign and little-endian 64-bit limbs (no high zero limb).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Limbs {
    negative: bool,
    magnitude: Vec<u64>,
}

impl Limbs {
    /// From a big integer.
    pub fn from_bigint(v: &BigInt) -> Self {
        Limbs {
            negative: v.sign() == Sign::Minus,
            magnitude: v.magnitude().to_u64_digits(),
        }
    }

    /// From a machine integer.
    pub fn from_i64(v: i64) -> Self {
        Limbs {
            negative: v < 0,
            magnitude: if v == 0 {
                Vec::new()
            } else {
                vec![v.unsigned_abs()]
            },
        }
    }

    /// From any ring element.
    pub fn from_ring<R: Ring>(v: &R) -> Self {
        match v.to_i64() {
            Some(small) => Limbs::from_i64(small),
            None => Limbs::from_bigint(&v.to_bigint()),
        }
    }

    /// True for zero.
    pub fn is_zero(&self) -> bool {
        self.magnitude.is_empty()
    }
}

/// `target += a · b` over unsigned limbs, growing `target` as needed.
fn mul_add_into(target: &mut Vec<u64>, a: &[u64], b: &[u64]) {
    let needed = a.len() + b.len() + 1;
    if target.len() < needed {
        target.resize(needed, 0);
    }
    for (j, &bj) in b.iter().enumerate() {
        if bj == 0 {
            continue;
        }
        let mut carry: u128 = 0;
        for (i, &ai) in a.iter().enumerate() {
            let t = target[i + j] as u128 + ai as u128 * bj as u128 + carry;
            target[i + j] = t as u64;
            carry = t >> 64;
        }
        let mut k = a.len() + j;
        while carry != 0 {
            let t = target[k] as u128 + carry;
            target[k] = t as u64;
            carry = t >> 64;
            k += 1;
        }
    }
}

fn to_biguint(limbs: &[u64]) -> BigUint {
    let mut digits = Vec::with_capacity(limbs.len() * 2);
    for l in limbs {
        digits.push(*l as u32);
        digits.push((*l >> 32) as u32);
    }
    BigUint::new(digits)
}

/// An exact running sum `Σ ± a_i · b_i`, kept as separate positive and negative magnitudes.
#[derive(Debug, Clone, Default)]
pub struct Accumulator {
    positive: Vec<u64>,
    negative: Vec<u64>,
}

impl Accumulator {
    /// Sets the sum back to zero, keeping the buffers.
    pub fn clear(&mut self) {
        self.positive.iter_mut().for_each(|l| *l = 0);
        self.negative.iter_mut().for_each(|l| *l = 0);
    }

    /// Adds `a · b`.
    pub fn add_product(&mut self, a: &Limbs, b: &Limbs) {
        if a.is_zero() || b.is_zero() {
            return;
        }
        let target = if a.negative != b.negative {
            &mut self.negative
        } else {
            &mut self.positive
        };
        mul_add_into(target, &a.magnitude, &b.magnitude);
    }

    /// Subtracts `a · b`.
    pub fn sub_product(&mut self, a: &Limbs, b: &Limbs) {
        if a.is_zero() || b.is_zero() {
            return;
        }
        let target = if a.negative != b.negative {
            &mut self.positive
        } else {
            &mut self.negative
        };
        mul_add_into(target, &a.magnitude, &b.magnitude);
    }

    /// The sum as a big integer.
    pub fn to_bigint(&self) -> BigInt {
        let p = to_biguint(&self.positive);
        let n = to_biguint(&self.negative);
        if p >= n {
            BigInt::from_biguint(Sign::Plus, p - n)
        } else {
            BigInt::from_biguint(Sign::Minus, n - p)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn big(limbs: &[u64], negative: bool) -> BigInt {
        let m = BigInt::from_biguint(Sign::Plus, to_biguint(limbs));
        if negative {
            -m
        } else {
            m
        }
    }

    proptest! {
        #[test]
        fn sums_of_products_are_exact(
            terms in prop::collection::vec(
                (prop::collection::vec(any::<u64>(), 0..6), any::<bool>(),
                 prop::collection::vec(any::<u64>(), 0..3), any::<bool>(), any::<bool>()),
                0..8,
            )
        ) {
            let mut acc = Accumulator::default();
            let mut expected = BigInt::from(0);
            for (a, an, b, bn, subtract) in &terms {
                let (x, y) = (big(a, *an), big(b, *bn));
                let (lx, ly) = (Limbs::from_bigint(&x), Limbs::from_bigint(&y));
                if *subtract {
                    acc.sub_product(&lx, &ly);
                    expected -= &x * &y;
                } else {
                    acc.add_product(&lx, &ly);
                    expected += &x * &y;
                }
            }
            prop_assert_eq!(acc.to_bigint(), expected);
            acc.clear();
            prop_assert_eq!(acc.to_bigint(), BigInt::from(0));
        }
    }

    #[test]
    fn machine_integers_convert() {
        assert!(Limbs::from_i64(0).is_zero());
        let mut acc = Accumulator::default();
        acc.add_product(&Limbs::from_i64(i64::MIN), &Limbs::from_i64(-1));
        assert_eq!(acc.to_bigint(), -BigInt::from(i64::MIN));
    }
}
