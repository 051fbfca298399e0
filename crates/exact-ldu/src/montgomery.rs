//! Montgomery arithmetic modulo an odd multi-limb modulus `m` of `k` limbs (`R = 2^(64k)`):
//! products modulo `m` without dividing, for the product chain of [`crate::reduce_over`].
//!
//! `num-bigint` computes `a b mod m` as a product followed by a long division of a `2k`-limb
//! number; on the ~700-bit denominators of a δ = 8 spline edit those divisions were most of an
//! exact update. Montgomery's reduction (REDC; Montgomery 1985) replaces each by `k` rows of
//! word multiplications of `m`, in place. Results carry factors `R⁻¹`, which are units modulo
//! the odd `m`: zero tests and GCDs with `m` are unchanged, which is all the reduction asks of
//! them. The values' own residues take only the few REDC rows that bring them below `2m`
//! (see [`Montgomery::residue_into`]).

use crate::gcd::{from_limbs, subtract_limbs};
use crate::montgomery_lanes::LaneMontgomery;
use num_bigint::BigUint;
use num_traits::One;

/// An odd modulus with `−m⁻¹ mod 2^64`.
#[derive(Debug, Clone)]
pub(crate) struct Montgomery {
    modulus: Vec<u64>,
    /// The modulus's length in bits.
    bits: u64,
    negated_inverse: u64,
    /// For moduli longer than [`SUBQUADRATIC_LIMBS`]: REDC through whole products.
    long: Option<LongModulus>,
    /// Eight chains at once, where the processor has AVX-512 IFMA.
    lanes: Option<LaneMontgomery>,
}

/// From this many limbs on, Montgomery products go through `num-bigint`'s sub-quadratic
/// multiplication ([`LongModulus`]) instead of word rows: measured 0.88× the rows' time at 96
/// limbs, 0.64× at 200, 0.37× at 680, and slower below (1.15× at 64).
const SUBQUADRATIC_LIMBS: usize = 96;

/// REDC by whole products for a long modulus `m` of `k` limbs (`R = 2^(64k)`): `t = a b`,
/// `q = (t mod R) · (−m⁻¹ mod R) mod R`, then `(t + q m) / R < 2m`. Three products of `k`
/// limbs, which `num-bigint` multiplies by Karatsuba (from 32 limbs) and Toom-3 (from 256),
/// where word rows cost `2k²` word products.
#[derive(Debug, Clone)]
struct LongModulus {
    modulus: BigUint,
    /// `−m⁻¹ mod R`.
    negated_inverse: BigUint,
    /// `R − 1`, to take a value modulo `R`.
    mask: BigUint,
    limbs: usize,
}

impl LongModulus {
    /// `inverse` is `m⁻¹ mod 2^64`; Newton's iteration `x ← x (2 − m x)` doubles its correct
    /// bits up to `R`.
    fn new(modulus: &BigUint, limbs: usize, inverse: u64) -> Self {
        let bits = 64 * limbs as u64;
        let mut x = BigUint::from(inverse);
        let mut known = 64u64;
        while known < bits {
            known = (2 * known).min(bits);
            let mask = (BigUint::one() << known) - 1u32;
            let two = BigUint::from(2u32);
            // 2 − m x modulo 2^known, kept non-negative by adding 2^known.
            let mx = (modulus * &x) & &mask;
            let factor = ((two + &mask + 1u32) - mx) & &mask;
            x = (x * factor) & &mask;
        }
        let mask = (BigUint::one() << bits) - 1u32;
        let negated_inverse = ((&mask + 1u32) - x) & &mask;
        LongModulus {
            modulus: modulus.clone(),
            negated_inverse,
            mask,
            limbs,
        }
    }

    /// `a · b · R⁻¹ mod m` for `a, b < m`.
    fn mul(&self, a: &BigUint, b: &BigUint) -> BigUint {
        let t = a * b;
        let q = ((&t & &self.mask) * &self.negated_inverse) & &self.mask;
        let u = (t + q * &self.modulus) >> (64 * self.limbs);
        if u >= self.modulus {
            u - &self.modulus
        } else {
            u
        }
    }
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
        let inverse = crate::word_division::word_inverse(low);
        let long = (limbs.len() >= SUBQUADRATIC_LIMBS)
            .then(|| LongModulus::new(modulus, limbs.len(), inverse));
        Some(Montgomery {
            lanes: LaneMontgomery::new(&limbs, inverse.wrapping_neg()),
            modulus: limbs,
            bits: modulus.bits(),
            negated_inverse: inverse.wrapping_neg(),
            long,
        })
    }

    pub(crate) fn limbs(&self) -> usize {
        self.modulus.len()
    }

    /// `t − m` in place when `t ≥ m` (`t` has `k + 1` limbs, below `2m`); then its low `k`
    /// limbs are the result.
    fn subtract_if_not_below(&self, t: &mut [u64]) {
        let k = self.limbs();
        let (low, high) = t.split_at_mut(k);
        subtract_if_not_below(low, high[0], &self.modulus);
    }

    /// One REDC row on `t`: adds the multiple `u m 2^(64 row)` that clears limb `row` (`t` long
    /// enough to take the carry).
    #[inline]
    fn redc_row(&self, t: &mut [u64], row: usize) {
        let k = self.limbs();
        let u = t[row].wrapping_mul(self.negated_inverse);
        let mut carry = 0;
        for (ti, &m) in t[row..].iter_mut().zip(&self.modulus) {
            (*ti, carry) = mul_add(*ti, u, m, carry);
        }
        for ti in &mut t[row + k..] {
            if carry == 0 {
                break;
            }
            let (sum, overflow) = ti.overflowing_add(carry);
            *ti = sum;
            carry = u64::from(overflow);
        }
    }

    /// [`Montgomery::residue_into`] as a new vector.
    #[cfg(test)]
    pub(crate) fn residue(&self, n: &BigUint) -> Vec<u64> {
        let mut residue = vec![0; self.limbs()];
        self.residue_into(n, &mut residue, &mut Vec::new());
        residue
    }

    /// `n · 2^(−64j) mod m` in `k` limbs for some `j ≥ 0`: zero exactly when `m` divides `n`
    /// (`2^(−64j)` is a unit modulo the odd `m`), which with GCDs against `m` is all the
    /// product chain asks of a residue. `j` REDC rows, just enough to bring `n` below `2m`:
    /// the values reduced are about as long as `m` (numerators over a multiple of it), so `j`
    /// is a row or two and this costs `O(k)` word operations per row, without the
    /// normalisation and allocations of a long division (full REDC, `k` rows, made the 7 000-bit
    /// denominators of a δ = 16 edit on a real mesh 30–70 % slower).
    ///
    /// Written into `out` (`k` limbs), the rows worked in `scratch` (reused: no allocation once
    /// it has grown).
    pub(crate) fn residue_into(&self, n: &BigUint, out: &mut [u64], scratch: &mut Vec<u64>) {
        let k = self.limbs();
        let (bits, modulus_bits) = (n.bits(), self.bits);
        let digits = n.iter_u64_digits();
        out.fill(0);
        if bits < modulus_bits {
            for (o, d) in out.iter_mut().zip(digits) {
                *o = d;
            }
            return;
        }
        // n < 2^bits and m ≥ 2^(modulus_bits − 1): after j rows with 2^(64j) ≥ n / m, the value
        // is below n / 2^(64j) + m ≤ 2m.
        let rows = (bits - modulus_bits + 1).div_ceil(64) as usize;
        let length = digits.len().max(rows + k) + 1;
        let t = scratch;
        t.clear();
        t.extend(digits);
        t.resize(length, 0);
        for row in 0..rows {
            self.redc_row(t, row);
        }
        self.subtract_if_not_below(&mut t[rows..]);
        out.copy_from_slice(&t[rows..rows + k]);
    }

    /// The same modulus with the scalar chain only (tests both paths on any processor).
    #[cfg(test)]
    pub(crate) fn without_lanes(mut self) -> Self {
        self.lanes = None;
        self
    }

    /// Whether [`Montgomery::lane_product`] runs here (the processor has AVX-512 IFMA).
    pub(crate) fn has_lanes(&self) -> bool {
        self.lanes.is_some()
    }

    /// `Π values` times a unit modulo `m`, below `m` in `k` limbs, by eight chains side by side
    /// ([`crate::montgomery_lanes`]); `None` without IFMA. The values are below `m` (residues).
    pub(crate) fn lane_product<'a>(
        &self,
        values: impl IntoIterator<Item = &'a [u64]>,
    ) -> Option<Vec<u64>> {
        let lanes = self.lanes.as_ref()?;
        let (mut product, _) = lanes.product(values);
        // Below 2m: one subtraction brings it below m.
        product.resize(self.limbs() + 1, 0);
        self.subtract_if_not_below(&mut product);
        product.truncate(self.limbs());
        Some(product)
    }

    /// `Π values` times a unit modulo `m` (a power of `R⁻¹`), below `m` in `k` limbs, on this
    /// thread; the values are below `m` (at most `k` limbs each). For moduli of up to 32 limbs
    /// two products run side by side ([`cios_pair_fixed`]) over alternate values and are
    /// multiplied at the end; longer ones go one product at a time ([`Montgomery::mul_assign`]).
    pub(crate) fn chain_product<'a>(
        &self,
        values: impl IntoIterator<Item = &'a [u64]>,
    ) -> Vec<u64> {
        let k = self.limbs();
        let values = values.into_iter();
        /// Moduli of up to 32 limbs take [`chain_fixed`] for their length.
        macro_rules! fixed_lengths {
            ($values:ident; $($n:literal)*) => {
                match k {
                    $($n => {
                        if let Ok(m) = <&[u64; $n]>::try_from(&self.modulus[..]) {
                            return chain_fixed(m, self.negated_inverse, $values).to_vec();
                        }
                    })*
                    _ => {}
                }
            };
        }
        fixed_lengths!(values; 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30 31 32);
        let mut scratch = Vec::new();
        values.fold(vec![1u64], |mut acc, v| {
            self.mul_assign(&mut acc, v, &mut scratch);
            acc
        })
    }

    /// `a · b · R⁻¹ mod m` for `a, b < m` (at most `k` limbs each).
    #[cfg(test)]
    pub(crate) fn mul(&self, a: &[u64], b: &[u64]) -> Vec<u64> {
        let mut product = a.to_vec();
        self.mul_assign(&mut product, b, &mut Vec::new());
        product
    }

    /// [`Montgomery::mul`] by the loop over slices, whatever the length.
    #[cfg(test)]
    fn mul_any_length(&self, a: &[u64], b: &[u64]) -> Vec<u64> {
        let mut product = a.to_vec();
        product.resize(self.limbs(), 0);
        self.mul_assign_any_length(&mut product, b, &mut Vec::new());
        product
    }

    /// `acc ← acc · b · R⁻¹ mod m` for `acc, b < m` (at most `k` limbs each; `acc` has `k`
    /// limbs after). Coarsely integrated operand scanning (Koç, Acar and Kaliski 1996): one
    /// row of the product `acc · bᵢ` and one REDC row alternate on a `k + 2`-limb window
    /// (`scratch`, reused, so no allocation once it has grown), which stays below `2m`.
    pub(crate) fn mul_assign(&self, acc: &mut Vec<u64>, b: &[u64], scratch: &mut Vec<u64>) {
        let k = self.limbs();
        acc.resize(k, 0);
        /// Moduli of up to 32 limbs (2 048 bits) take [`cios_fixed`] for their length.
        macro_rules! fixed_lengths {
            ($($n:literal)*) => {
                match k {
                    $($n => {
                        let mut padded = [0u64; $n];
                        padded[..b.len()].copy_from_slice(b);
                        if let (Ok(m), Ok(a)) = (
                            <&[u64; $n]>::try_from(&self.modulus[..]),
                            <&mut [u64; $n]>::try_from(&mut acc[..]),
                        ) {
                            cios_fixed(m, self.negated_inverse, a, &padded);
                            return;
                        }
                    })*
                    _ => {}
                }
            };
        }
        fixed_lengths!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30 31 32);
        if let Some(long) = &self.long {
            let product = long.mul(&from_limbs(acc), &from_limbs(b));
            acc.clear();
            acc.extend(product.iter_u64_digits());
            acc.resize(k, 0);
            return;
        }
        self.mul_assign_any_length(acc, b, scratch);
    }

    /// [`Montgomery::mul_assign`] for any length, the window in `scratch`.
    fn mul_assign_any_length(&self, acc: &mut [u64], b: &[u64], scratch: &mut Vec<u64>) {
        let k = self.limbs();
        let m = &self.modulus[..];
        scratch.clear();
        scratch.resize(k + 2, 0);
        let t = &mut scratch[..];
        for i in 0..k {
            let bi = b.get(i).copied().unwrap_or(0);
            let mut carry = 0;
            for (tj, &aj) in t[..k].iter_mut().zip(acc.iter()) {
                (*tj, carry) = mul_add(*tj, aj, bi, carry);
            }
            let (sum, overflow) = t[k].overflowing_add(carry);
            t[k] = sum;
            t[k + 1] = u64::from(overflow);
            let u = t[0].wrapping_mul(self.negated_inverse);
            let (_, mut carry) = mul_add(t[0], u, m[0], 0);
            for j in 1..k {
                (t[j - 1], carry) = mul_add(t[j], u, m[j], carry);
            }
            let (sum, overflow) = t[k].overflowing_add(carry);
            t[k - 1] = sum;
            t[k] = t[k + 1] + u64::from(overflow);
        }
        self.subtract_if_not_below(&mut t[..=k]);
        acc.copy_from_slice(&t[..k]);
    }
}

/// [`Montgomery::mul_assign`] for a modulus of `K` limbs, `a ← a · b · R⁻¹ mod m`: with the
/// length known the compiler unrolls the rows and keeps the window in registers (1.7× faster
/// than the loop over slices on the 11-limb moduli of a δ = 8 spline edit).
fn cios_fixed<const K: usize>(m: &[u64; K], ninv: u64, a: &mut [u64; K], b: &[u64; K]) {
    let mut window = CiosWindow::<K>::new();
    for &bi in b {
        window.row(m, ninv, a, bi);
    }
    window.finish(m, a);
}

/// [`Montgomery::chain_product`] for a modulus of `K` limbs: values at even places into one
/// accumulator, at odd places into the other, both advanced together.
fn chain_fixed<'a, const K: usize>(
    m: &[u64; K],
    ninv: u64,
    mut values: impl Iterator<Item = &'a [u64]>,
) -> [u64; K] {
    let padded = |v: &[u64]| {
        let mut p = [0u64; K];
        p[..v.len()].copy_from_slice(v);
        p
    };
    let mut one = [0u64; K];
    one[0] = 1;
    let (mut even, mut odd) = (one, one);
    loop {
        match (values.next(), values.next()) {
            (Some(x), Some(y)) => {
                cios_pair_fixed(m, ninv, (&mut even, &padded(x)), (&mut odd, &padded(y)))
            }
            (Some(x), None) => {
                cios_fixed(m, ninv, &mut even, &padded(x));
                break;
            }
            _ => break,
        }
    }
    cios_fixed(m, ninv, &mut even, &odd);
    even
}

/// [`cios_fixed`] on two independent products at once, `a ← a · x · R⁻¹` and
/// `b ← b · y · R⁻¹ mod m`, their rows alternating: each row is a chain of dependent
/// carries, so one product alone waits on its multiplications' latency, while two keep the
/// multiplier busy (the product chain of [`Montgomery::chain_product`]).
fn cios_pair_fixed<const K: usize>(
    m: &[u64; K],
    ninv: u64,
    (a, x): (&mut [u64; K], &[u64; K]),
    (b, y): (&mut [u64; K], &[u64; K]),
) {
    let (mut first, mut second) = (CiosWindow::<K>::new(), CiosWindow::<K>::new());
    for (&xi, &yi) in x.iter().zip(y) {
        first.row(m, ninv, a, xi);
        second.row(m, ninv, b, yi);
    }
    first.finish(m, a);
    second.finish(m, b);
}

/// The `K + 2`-limb window of a coarsely integrated product `a · b · R⁻¹ mod m` (Koç, Acar
/// and Kaliski 1996): `t` and its two top limbs.
struct CiosWindow<const K: usize> {
    t: [u64; K],
    t_k: u64,
}

impl<const K: usize> CiosWindow<K> {
    fn new() -> Self {
        CiosWindow { t: [0; K], t_k: 0 }
    }

    /// One row: `t ← (t + a · bᵢ + u m) / 2^64` with `u` clearing the low limb.
    #[inline(always)]
    fn row(&mut self, m: &[u64; K], ninv: u64, a: &[u64; K], bi: u64) {
        let t = &mut self.t;
        let mut carry = 0;
        for j in 0..K {
            (t[j], carry) = mul_add(t[j], a[j], bi, carry);
        }
        let (sum, overflow) = self.t_k.overflowing_add(carry);
        let t_k1 = u64::from(overflow);
        let u = t[0].wrapping_mul(ninv);
        let (_, mut carry) = mul_add(t[0], u, m[0], 0);
        for j in 1..K {
            (t[j - 1], carry) = mul_add(t[j], u, m[j], carry);
        }
        let (sum, overflow) = sum.overflowing_add(carry);
        t[K - 1] = sum;
        self.t_k = t_k1 + u64::from(overflow);
    }

    /// The window, below `2m`, brought below `m` into `out`.
    #[inline(always)]
    fn finish(mut self, m: &[u64; K], out: &mut [u64; K]) {
        subtract_if_not_below(&mut self.t, self.t_k, m);
        *out = self.t;
    }
}

/// `low − m` in place when the value `high · 2^(64k) + low` (below `2m`) is at least `m`; the
/// result fits `low`'s `k` limbs.
fn subtract_if_not_below(low: &mut [u64], high: u64, modulus: &[u64]) {
    let not_below = high != 0
        || low
            .iter()
            .rev()
            .zip(modulus.iter().rev())
            .find(|(x, y)| x != y)
            .is_none_or(|(x, y)| x > y);
    if not_below {
        // The borrow out of the top limb is `high`'s, dropped with it.
        subtract_limbs(low, modulus);
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

    /// `mul(a, b) · R ≡ a b` modulo `m` and below it, the same by the word rows whatever the
    /// length, and for a short factor (the chain starts from `1`).
    fn check_products(
        mont: &Montgomery,
        m: &BigUint,
        a: &[u64],
        b: &[u64],
    ) -> Result<(), TestCaseError> {
        let k = mont.limbs();
        let r = r_mod(m, k);
        let (a, b) = (big(a) % m, big(b) % m);
        let mut a_limbs = a.to_u64_digits();
        a_limbs.resize(k, 0);
        let mut b_limbs = b.to_u64_digits();
        b_limbs.resize(k, 0);
        let p = big(&mont.mul(&a_limbs, &b_limbs));
        prop_assert!(&p < m);
        prop_assert_eq!((&p * &r) % m, (&a * &b) % m);
        prop_assert_eq!(big(&mont.mul_any_length(&a_limbs, &b_limbs)), p);
        let one = big(&mont.mul(&[1], &b_limbs));
        prop_assert_eq!((&one * &r) % m, b);
        Ok(())
    }

    proptest! {
        /// `residue(n) · 2^(64j) ≡ n` modulo `m` for some `j` and the products of
        /// [`check_products`], for moduli of one to a hundred limbs (the unrolled lengths up to
        /// 32, the word rows over slices above, whole products from 96) and values on both
        /// sides of `m R`.
        #[test]
        fn agrees_with_division(
            m in prop::collection::vec(any::<u64>(), 1..100),
            n in prop::collection::vec(any::<u64>(), 0..200),
            a in prop::collection::vec(any::<u64>(), 0..100),
            b in prop::collection::vec(any::<u64>(), 0..100),
        ) {
            let m = big(&m) | BigUint::from(1u32);
            prop_assume!(m > BigUint::from(1u32));
            let mont = Montgomery::new(&m).expect("odd");
            let k = mont.limbs();
            let n = big(&n);
            let t = mont.residue(&n);
            prop_assert_eq!(t.len(), k);
            let t = big(&t);
            prop_assert!(t < m);
            let n_mod = &n % &m;
            prop_assert!(
                (0..=200).any(|j| (&t << (64 * j)) % &m == n_mod),
                "no power of 2^64 takes the residue back to n mod m"
            );
            check_products(&mont, &m, &a, &b)?;
        }
    }

    proptest! {
        /// A chain's product is the values' product times `R⁻ʲ` for `j` the count of values or
        /// one more (the two accumulators' final product), below `m`: for no value, one, odd
        /// and even counts, moduli of the unrolled lengths and beyond, values shorter than `m`.
        #[test]
        fn chain_products_are_products(
            m in prop::collection::vec(any::<u64>(), 1..40),
            values in prop::collection::vec(prop::collection::vec(any::<u64>(), 0..40), 0..7),
        ) {
            let m = big(&m) | BigUint::from(1u32);
            prop_assume!(m > BigUint::from(1u32));
            let mont = Montgomery::new(&m).expect("odd");
            let k = mont.limbs();
            let values: Vec<Vec<u64>> = values
                .iter()
                .map(|v| (big(v) % &m).to_u64_digits())
                .collect();
            let product = big(&mont.chain_product(values.iter().map(Vec::as_slice)));
            prop_assert!(product < m);
            let expected = values.iter().fold(BigUint::from(1u32) % &m, |p, v| p * big(v) % &m);
            let r = r_mod(&m, k);
            let n = values.len();
            prop_assert!(
                [n, n + 1].iter().any(|&j| &product * r.modpow(&BigUint::from(j), &m) % &m == expected),
                "not the product times a power of R⁻¹"
            );
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]
        /// Long moduli (whole products): the same products as the word rows, and
        /// `mul(a, b) · R ≡ a b` modulo `m`, also for a short factor.
        #[test]
        fn long_moduli_agree_with_word_rows(
            m in prop::collection::vec(any::<u64>(), SUBQUADRATIC_LIMBS..300),
            a in prop::collection::vec(any::<u64>(), 0..300),
            b in prop::collection::vec(any::<u64>(), 0..300),
        ) {
            let m = big(&m) | BigUint::from(1u32);
            let mont = Montgomery::new(&m).expect("odd");
            prop_assert!(mont.long.is_some());
            check_products(&mont, &m, &a, &b)?;
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
