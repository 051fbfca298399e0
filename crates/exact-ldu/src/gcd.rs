//! Greatest common divisors of big integers by Lehmer's algorithm.
//!
//! `num-bigint` computes GCDs with the binary (Stein) algorithm, which shifts the whole number
//! once per bit: reducing a 400-bit fraction costs about 10 µs there, and reducing the results of
//! an exact solve is the largest cost of an ECLES update. Lehmer's algorithm (Knuth, TAOCP vol. 2,
//! 4.5.2, algorithm L) runs Euclid on the leading 63 bits of both numbers to find a 2 × 2
//! cofactor matrix, then applies it to the full numbers: one pass over the limbs per ~30
//! quotient bits instead of per bit.
//!
//! Above [`LARGE_GCD_BITS`] the GCD of `dashu-int` (a maintained big-integer crate whose Lehmer
//! variant works on double words) is faster even with the conversions: measured 2.0× at 7 100
//! bits (70 against 140 µs), 1.3× at 1 000 bits, equal at 200, slower below.

use num_bigint::{BigInt, BigUint};
use num_integer::Integer;
use num_traits::Zero;

/// Little-endian 64-bit limbs without high zero limbs.
pub(crate) type Limbs = Vec<u64>;

fn trim(v: &mut Limbs) {
    while v.last() == Some(&0) {
        v.pop();
    }
}

pub(crate) fn to_limbs(v: &BigUint) -> Limbs {
    v.to_u64_digits()
}

/// The value of the 64-bit limbs `v`, lowest first, in one allocation of its length.
pub(crate) fn from_limbs(v: &[u64]) -> BigUint {
    let mut value = BigUint::default();
    assign_limbs(&mut value, v);
    value
}

/// Sets `value` to the 64-bit limbs `v`, lowest first, in its own buffer.
pub(crate) fn assign_limbs(value: &mut BigUint, v: &[u64]) {
    // `num-bigint` takes digits only as 32 bits. On a little-endian machine a limb's two
    // digits, low first, are its bytes in memory: the limbs are read as digits in place.
    #[cfg(target_endian = "little")]
    value.assign_from_slice(bytemuck::cast_slice::<u64, u32>(v));
    #[cfg(not(target_endian = "little"))]
    {
        let digits: Vec<u32> = v
            .iter()
            .flat_map(|&limb| [limb as u32, (limb >> 32) as u32])
            .collect();
        value.assign_from_slice(&digits);
    }
}

/// The 63 bits of `v` starting at bit `shift` from the bottom (`v >> shift`, truncated).
fn bits_at(v: &[u64], shift: usize) -> u64 {
    let limb = shift / 64;
    let offset = shift % 64;
    let lo = v.get(limb).copied().unwrap_or(0);
    let hi = v.get(limb + 1).copied().unwrap_or(0);
    let word = if offset == 0 {
        lo
    } else {
        (lo >> offset) | (hi << (64 - offset))
    };
    word & (u64::MAX >> 1)
}

/// `a −= b` on the limbs `b` covers (least significant first, `a` at least as long), a borrow
/// out of the last of them dropped: the difference for `a ≥ b` of equal length, or the low
/// limbs of one whose borrow the caller holds elsewhere.
pub(crate) fn subtract_limbs(a: &mut [u64], b: &[u64]) {
    let mut borrow = false;
    for (a, b) in a.iter_mut().zip(b) {
        let (d, under1) = a.overflowing_sub(*b);
        let (d, under2) = d.overflowing_sub(u64::from(borrow));
        *a = d;
        borrow = under1 || under2;
    }
}

pub(crate) fn bit_len(v: &[u64]) -> usize {
    match v.last() {
        None => 0,
        Some(top) => v.len() * 64 - top.leading_zeros() as usize,
    }
}

/// `out = u·a − v·b`, which the caller knows to be non-negative.
fn combine(out: &mut Limbs, a: &[u64], u: u64, b: &[u64], v: u64) {
    let n = a.len().max(b.len());
    out.clear();
    let mut carry: i128 = 0;
    for i in 0..n {
        let ai = a.get(i).copied().unwrap_or(0) as i128;
        let bi = b.get(i).copied().unwrap_or(0) as i128;
        // Each product is below 2^127; split into limbs before adding to stay in range.
        let pa = ai as u128 * u as u128;
        let pb = bi as u128 * v as u128;
        let lo = (pa as u64) as i128 - (pb as u64) as i128 + carry;
        out.push(lo as u64);
        carry = (lo >> 64) + (pa >> 64) as i128 - (pb >> 64) as i128;
    }
    debug_assert!(carry >= 0, "combination must be non-negative");
    out.push(carry as u64);
    trim(out);
}

/// GCD of two-word values: Lehmer steps while the larger has two words (the leading 62 bits
/// certify a run of quotients, applied to the whole words at once), then binary GCD in one
/// word. The new pair of a Lehmer step is computed modulo `2^128`, which is exact: both values
/// are remainders of the Euclidean sequence, in `[0, a]`. (Binary GCD on two words spent one
/// iteration of several word operations per bit: a third of a small exact update.)
pub(crate) fn gcd_u128(mut a: u128, mut b: u128) -> u128 {
    if a < b {
        std::mem::swap(&mut a, &mut b);
    }
    loop {
        if b == 0 {
            return a;
        }
        if a >> 64 == 0 {
            return u128::from(crate::ring::binary_gcd(a as u64, b as u64));
        }
        let limbs = |v: u128| -> ([u64; 2], usize) {
            let words = [v as u64, (v >> 64) as u64];
            (words, if words[1] == 0 { 1 } else { 2 })
        };
        let ((wa, na), (wb, nb)) = (limbs(a), limbs(b));
        match lehmer_matrix(&wa[..na], &wb[..nb]) {
            Some([ca, cb, cc, cd]) => {
                let signed = |c: i64| c as i128 as u128;
                (a, b) = (
                    signed(ca)
                        .wrapping_mul(a)
                        .wrapping_add(signed(cb).wrapping_mul(b)),
                    signed(cc)
                        .wrapping_mul(a)
                        .wrapping_add(signed(cd).wrapping_mul(b)),
                );
            }
            None => (a, b) = (b, a % b),
        }
    }
}

/// `a < b` for trimmed limb vectors.
fn less(a: &[u64], b: &[u64]) -> bool {
    if a.len() != b.len() {
        return a.len() < b.len();
    }
    for (x, y) in a.iter().rev().zip(b.iter().rev()) {
        if x != y {
            return x < y;
        }
    }
    false
}

/// `gcd(a, b)` of magnitudes given as limbs.
fn gcd_limbs(mut a: Limbs, mut b: Limbs) -> Limbs {
    trim(&mut a);
    trim(&mut b);
    if less(&a, &b) {
        std::mem::swap(&mut a, &mut b);
    }
    let mut next_a = Vec::with_capacity(a.len() + 1);
    let mut next_b = Vec::with_capacity(a.len() + 1);
    loop {
        if b.is_empty() {
            return a;
        }
        if a.len() <= 2 {
            let word = |v: &[u64]| {
                v.iter()
                    .rev()
                    .fold(0u128, |acc, l| (acc << 64) | *l as u128)
            };
            let g = gcd_u128(word(&a), word(&b));
            let mut out = vec![g as u64, (g >> 64) as u64];
            trim(&mut out);
            return out;
        }
        let Some(matrix) = lehmer_matrix(&a, &b) else {
            // No quotient could be certified from the leading bits: one exact division step.
            let (ab, bb) = (from_limbs(&a), from_limbs(&b));
            let r = ab % &bb;
            a = b;
            b = to_limbs(&r);
            continue;
        };
        apply_lehmer(&a, &b, matrix, &mut next_a, &mut next_b);
        std::mem::swap(&mut a, &mut next_a);
        std::mem::swap(&mut b, &mut next_b);
    }
}

/// The cofactors `[A, B, C, D]` of the Euclidean steps on `a ≥ b > 0` that the leading 62 bits
/// certify (Knuth's algorithm L): after them the pair is `(A a + B b, C a + D b)`. `None` when
/// not even one quotient is certain.
pub(crate) fn lehmer_matrix(a: &[u64], b: &[u64]) -> Option<[i64; 4]> {
    // Leading 62 bits of a and the same bits of b: every cofactor and intermediate below
    // stays under 2^63, so the emulated Euclid runs in machine words.
    let shift = bit_len(a).saturating_sub(62);
    let mut x = (bits_at(a, shift) & (u64::MAX >> 2)) as i64;
    let mut y = (bits_at(b, shift) & (u64::MAX >> 2)) as i64;
    let (mut ca, mut cb, mut cc, mut cd): (i64, i64, i64, i64) = (1, 0, 0, 1);
    loop {
        // Knuth's test: the quotient is certain when ⌊(x+A)/(y+C)⌋ = ⌊(x+B)/(y+D)⌋.
        let (xa, xb, yc, yd) = (x + ca, x + cb, y + cc, y + cd);
        if yc <= 0 || yd <= 0 || xa < 0 || xb < 0 {
            break;
        }
        // Quotients are mostly tiny: find small ones by subtraction, not division.
        let mut q = 0i64;
        let mut rem = xa;
        while rem >= yc && q < 4 {
            rem -= yc;
            q += 1;
        }
        if rem >= yc {
            q = xa / yc;
        }
        // ⌊xb/yd⌋ = q  ⇔  q·yd ≤ xb < (q+1)·yd, checked with one multiplication.
        let low = q as i128 * yd as i128;
        if (xb as i128) < low || xb as i128 >= low + yd as i128 {
            break;
        }
        (ca, cc) = (cc, ca - q * cc);
        (cb, cd) = (cd, cb - q * cd);
        (x, y) = (y, x - q * y);
    }
    (cb != 0).then_some([ca, cb, cc, cd])
}

/// `(A a + B b, C a + D b)` into `next_a`, `next_b` for a matrix of [`lehmer_matrix`]: in each
/// pair the signs differ (one may be zero), so each is a difference of two non-negative
/// products.
pub(crate) fn apply_lehmer(
    a: &[u64],
    b: &[u64],
    [ca, cb, cc, cd]: [i64; 4],
    next_a: &mut Limbs,
    next_b: &mut Limbs,
) {
    if cb <= 0 {
        combine(next_a, a, ca as u64, b, (-cb) as u64);
    } else {
        combine(next_a, b, cb as u64, a, (-ca) as u64);
    }
    if cd <= 0 {
        combine(next_b, a, cc as u64, b, (-cd) as u64);
    } else {
        combine(next_b, b, cd as u64, a, (-cc) as u64);
    }
}

/// Above this size (of the larger operand) GCDs go to `dashu-int`.
const LARGE_GCD_BITS: u64 = 256;

/// `gcd(|a|, |b|)` for unsigned big integers.
pub fn gcd_biguint(a: &BigUint, b: &BigUint) -> BigUint {
    if a.is_zero() {
        return b.clone();
    }
    if b.is_zero() {
        return a.clone();
    }
    let bits = a.bits().max(b.bits());
    if bits <= 128 {
        // Values that fit two words (the common case of small edits): binary GCD in registers.
        let word = |x: &BigUint| {
            x.iter_u64_digits()
                .enumerate()
                .fold(0u128, |acc, (k, d)| acc | (u128::from(d) << (64 * k)))
        };
        return BigUint::from(gcd_u128(word(a), word(b)));
    }
    if bits > LARGE_GCD_BITS {
        use dashu_int::ops::Gcd;
        let x = dashu_int::UBig::from_le_bytes(&a.to_bytes_le());
        let y = dashu_int::UBig::from_le_bytes(&b.to_bytes_le());
        return BigUint::from_bytes_le(&x.gcd(&y).to_le_bytes());
    }
    from_limbs(&gcd_limbs(to_limbs(a), to_limbs(b)))
}

/// `gcd(|a|, |b|)`, non-negative.
pub fn gcd_bigint(a: &BigInt, b: &BigInt) -> BigInt {
    BigInt::from(gcd_biguint(a.magnitude(), b.magnitude()))
}

/// `numer / denom` as a reduced rational (`denom ≠ 0`), with the fast GCD.
pub fn reduced_ratio(numer: BigInt, denom: BigInt) -> api::Rational {
    use num_traits::ToPrimitive;
    if let (Some(n), Some(d)) = (numer.to_i128(), denom.to_i128()) {
        if let Some(reduced) = reduced_small_ratio(n, d) {
            return reduced;
        }
    }
    let g = gcd_bigint(&numer, &denom);
    let (mut n, mut d) = if g.is_zero() || g == BigInt::from(1) {
        (numer, denom)
    } else {
        (numer.div_floor(&g), denom.div_floor(&g))
    };
    if d < BigInt::zero() {
        n = -n;
        d = -d;
    }
    if n.is_zero() {
        d = BigInt::from(1);
    }
    api::Rational::new_raw(n, d)
}

/// [`reduced_ratio`] of values within 127 bits, in machine words: no big-integer arithmetic,
/// only the two results allocated (the values of small edits and drag frames). `None` when a
/// value is `i128::MIN` (its magnitude has no `i128`) or the denominator is zero.
pub fn reduced_small_ratio(n: i128, d: i128) -> Option<api::Rational> {
    if d == 0 || n == i128::MIN || d == i128::MIN {
        return None;
    }
    if n == 0 {
        return Some(api::Rational::new_raw(BigInt::zero(), BigInt::from(1)));
    }
    // 0 < g ≤ |d| < 2^127.
    let g = gcd_u128(n.unsigned_abs(), d.unsigned_abs()) as i128;
    let (n, d) = if g == 1 { (n, d) } else { (n / g, d / g) };
    let (n, d) = if d < 0 { (-n, -d) } else { (n, d) };
    Some(api::Rational::new_raw(
        crate::ring::bigint_from_i128(n),
        crate::ring::bigint_from_i128(d),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Lehmer steps on two words give the GCD of `num-integer`, for values of any sizes
        /// and with large common factors.
        #[test]
        fn two_word_gcd_matches_num_integer(
            a in any::<u128>(),
            b in any::<u128>(),
            shift_a in 0u32..128,
            shift_b in 0u32..128,
            common in 1u64..,
        ) {
            let (a, b) = (a >> shift_a, b >> shift_b);
            prop_assert_eq!(gcd_u128(a, b), num_integer::Integer::gcd(&a, &b));
            let (ca, cb) = ((a >> 64).saturating_mul(u128::from(common)), (b >> 64).saturating_mul(u128::from(common)));
            prop_assert_eq!(gcd_u128(ca, cb), num_integer::Integer::gcd(&ca, &cb));
        }

        /// In machine words and in big integers, the same reduced rational (equal numerator
        /// and denominator, not only equal values); `num_rational`'s reduction is the reference.
        #[test]
        fn small_ratios_reduce_as_big_ones(
            n in any::<i128>(),
            d in any::<i128>().prop_filter("nonzero", |d| *d != 0),
            shift in 0u32..100,
        ) {
            let (n, d) = (n >> shift, d);
            let expected = api::Rational::new(BigInt::from(n), BigInt::from(d));
            let got = reduced_ratio(BigInt::from(n), BigInt::from(d));
            prop_assert_eq!(got.numer(), expected.numer());
            prop_assert_eq!(got.denom(), expected.denom());
        }
    }

    fn big(limbs: &[u64]) -> BigUint {
        from_limbs(limbs)
    }

    proptest! {
        #[test]
        fn lehmer_matches_binary_gcd(
            a in prop::collection::vec(any::<u64>(), 0..12),
            b in prop::collection::vec(any::<u64>(), 0..12),
            f in prop::collection::vec(any::<u64>(), 0..4),
        ) {
            let common = big(&f) + 1u32;
            let x = big(&a) * &common;
            let y = big(&b) * &common;
            prop_assert_eq!(gcd_biguint(&x, &y), num_integer::Integer::gcd(&x, &y));
        }

        #[test]
        fn reduced_ratio_matches_num_rational(n in any::<i64>(), d in any::<i64>(), s in 0u32..200) {
            prop_assume!(d != 0);
            let n = BigInt::from(n) << s;
            let d = BigInt::from(d) * BigInt::from(3).pow(s);
            prop_assert_eq!(reduced_ratio(n.clone(), d.clone()), api::Rational::new(n, d));
        }
    }

    #[test]
    fn edge_cases() {
        let z = BigUint::zero();
        let x = big(&[0, 0, 12]);
        assert_eq!(gcd_biguint(&z, &x), x);
        assert_eq!(gcd_biguint(&x, &z), x);
        assert_eq!(gcd_biguint(&x, &big(&[0, 0, 8])), big(&[0, 0, 4]));
        // Consecutive Fibonacci numbers: the worst case for Euclid.
        let (mut f0, mut f1) = (BigUint::from(0u32), BigUint::from(1u32));
        for _ in 0..700 {
            let f2 = &f0 + &f1;
            f0 = f1;
            f1 = f2;
        }
        assert_eq!(gcd_biguint(&f0, &f1), BigUint::from(1u32));
    }
}
