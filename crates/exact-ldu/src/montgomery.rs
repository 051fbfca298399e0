//! Montgomery arithmetic modulo an odd multi-limb modulus `m` of `k` limbs (`R = 2^(64k)`):
//! products modulo `m` without dividing, for the product chain of [`crate::reduce_over`].
//!
//! `num-bigint` computes `a b mod m` as a product followed by a long division of a `2k`-limb
//! number; on the ~700-bit denominators of a δ = 8 spline edit those divisions were most of an
//! exact update. Montgomery's reduction (REDC; Montgomery 1985) replaces each by `k` rows of
//! word multiplications of `m`, in place. Results carry factors `R⁻¹`, which are units modulo
//! the odd `m`: zero tests and GCDs with `m` are unchanged, which is all the reduction asks of
//! them. (The values' own residues stay long divisions: see [`Montgomery::residue`].)

use num_bigint::BigUint;

/// An odd modulus with `−m⁻¹ mod 2^64`.
#[derive(Debug, Clone)]
pub(crate) struct Montgomery {
    modulus: Vec<u64>,
    /// The modulus again, for [`Montgomery::residue`]'s division.
    big: BigUint,
    negated_inverse: u64,
}

/// `a + b · c + carry` as (low word, high word).
#[inline]
fn mul_add(a: u64, b: u64, c: u64, carry: u64) -> (u64, u64) {
    let t = u128::from(a) + u128::from(b) * u128::from(c) + u128::from(carry);
    (t as u64, (t >> 64) as u64)
}

impl Montgomery {
    /// `None` for an even modulus (zero included) or one of a single word below 2 (nothing to
    /// reduce by).
    pub(crate) fn new(modulus: &BigUint) -> Option<Self> {
        let limbs = modulus.to_u64_digits();
        let low = *limbs.first()?;
        if low & 1 == 0 || (limbs.len() == 1 && low < 2) {
            return None;
        }
        // Newton's iteration for low⁻¹ mod 2^64: 5, 10, 20, 40, 80 correct bits.
        let mut inverse = low.wrapping_mul(3) ^ 2;
        for _ in 0..4 {
            inverse = inverse.wrapping_mul(2u64.wrapping_sub(low.wrapping_mul(inverse)));
        }
        Some(Montgomery {
            modulus: limbs,
            big: modulus.clone(),
            negated_inverse: inverse.wrapping_neg(),
        })
    }

    fn limbs(&self) -> usize {
        self.modulus.len()
    }

    /// `t − m` in place when `t ≥ m` (`t` has `k + 1` limbs, below `2m`); then `t` is its
    /// low `k` limbs.
    fn subtract_if_not_below(&self, t: &mut Vec<u64>) {
        let k = self.limbs();
        let not_below = t[k] != 0
            || t[..k]
                .iter()
                .rev()
                .zip(self.modulus.iter().rev())
                .find(|(a, b)| a != b)
                .is_none_or(|(a, b)| a > b);
        if not_below {
            let mut borrow = false;
            for (x, m) in t.iter_mut().zip(&self.modulus) {
                let (d, b1) = x.overflowing_sub(*m);
                let (d, b2) = d.overflowing_sub(u64::from(borrow));
                *x = d;
                borrow = b1 || b2;
            }
            t[k] = t[k].wrapping_sub(u64::from(borrow));
        }
        t.truncate(k);
    }

    /// `n mod m` in `k` limbs: zero exactly when `m` divides `n`. A long division, not REDC:
    /// the values reduced are about as long as `m` (numerators over a multiple of it), so the
    /// quotient has a limb or two and the division costs `O(k)` word operations where REDC
    /// costs `k²` (on the 7 000-bit denominators of a δ = 16 edit on a real mesh, REDC made the
    /// update 30–70 % slower). The product chain takes these plain residues: its factors `R⁻¹`
    /// are units all the same.
    pub(crate) fn residue(&self, n: &BigUint) -> Vec<u64> {
        let mut t = (n % &self.big).to_u64_digits();
        t.resize(self.limbs(), 0);
        t
    }

    /// `a · b · R⁻¹ mod m` for `a, b < m` (at most `k` limbs each): the schoolbook product,
    /// then REDC.
    pub(crate) fn mul(&self, a: &[u64], b: &[u64]) -> Vec<u64> {
        let k = self.limbs();
        let mut t = vec![0u64; 2 * k + 1];
        for (i, &ai) in a.iter().enumerate() {
            let mut carry = 0;
            for (tj, &bj) in t[i..].iter_mut().zip(b) {
                (*tj, carry) = mul_add(*tj, ai, bj, carry);
            }
            t[i + b.len()] = carry;
        }
        self.redc(t)
    }

    /// `t R⁻¹ mod m` for `t < m R` given in `2k + 1` limbs: `k` rows, each adding the multiple
    /// `u m 2^(64i)` that clears limb `i`; then `t / R < 2m` and one conditional subtraction.
    fn redc(&self, mut t: Vec<u64>) -> Vec<u64> {
        let k = self.limbs();
        for i in 0..k {
            let u = t[i].wrapping_mul(self.negated_inverse);
            let mut carry = 0;
            for (ti, &m) in t[i..].iter_mut().zip(&self.modulus) {
                (*ti, carry) = mul_add(*ti, u, m, carry);
            }
            for ti in &mut t[i + k..] {
                if carry == 0 {
                    break;
                }
                let (sum, overflow) = ti.overflowing_add(carry);
                *ti = sum;
                carry = u64::from(overflow);
            }
        }
        t.drain(..k);
        self.subtract_if_not_below(&mut t);
        t
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

    /// `2^(64k) mod m`.
    fn r_mod(m: &BigUint, k: usize) -> BigUint {
        (BigUint::from(1u32) << (64 * k)) % m
    }

    proptest! {
        /// `residue(n) ≡ n` and `mul(a, b) · R ≡ a b` modulo `m`, results below `m`, for
        /// moduli of one to twelve limbs and values on both sides of `m R`.
        #[test]
        fn agrees_with_division(
            m in prop::collection::vec(any::<u64>(), 1..12),
            n in prop::collection::vec(any::<u64>(), 0..26),
            a in prop::collection::vec(any::<u64>(), 0..12),
            b in prop::collection::vec(any::<u64>(), 0..12),
        ) {
            let m = big(&m) | BigUint::from(1u32);
            prop_assume!(m > BigUint::from(1u32));
            let mont = Montgomery::new(&m).expect("odd");
            let k = mont.limbs();
            let r = r_mod(&m, k);
            let n = big(&n);
            let t = mont.residue(&n);
            prop_assert_eq!(t.len(), k);
            let t = big(&t);
            prop_assert!(t < m);
            prop_assert_eq!(t, &n % &m);
            let (a, b) = (big(&a) % &m, big(&b) % &m);
            let mut a_limbs = a.to_u64_digits();
            a_limbs.resize(k, 0);
            let mut b_limbs = b.to_u64_digits();
            b_limbs.resize(k, 0);
            let p = big(&mont.mul(&a_limbs, &b_limbs));
            prop_assert!(p < m);
            prop_assert_eq!((&p * &r) % &m, (&a * &b) % &m);
        }
    }

    #[test]
    fn zero_residues_are_multiples() {
        let m = (BigUint::from(1u32) << 673) - BigUint::from(5u32) * BigUint::from(7u32);
        let mont = Montgomery::new(&m).expect("odd");
        assert!(big(&mont.residue(&(&m * 12345u32))).is_zero());
        assert!(!big(&mont.residue(&(&m * 12345u32 + 1u32))).is_zero());
        assert!(big(&mont.residue(&(&m << 800))).is_zero());
        assert!(Montgomery::new(&BigUint::from(10u32)).is_none());
        assert!(Montgomery::new(&BigUint::from(1u32)).is_none());
        assert!(Montgomery::new(&BigUint::zero()).is_none());
    }
}
