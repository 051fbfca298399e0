//! Product chains modulo an odd modulus `m`, eight chains at once with AVX-512 IFMA, for
//! [`crate::reduce_over`]'s certificate that the values are coprime to the rest of their
//! denominator (the product of their residues modulo the rest, then one GCD).
//!
//! The scalar chain ([`crate::montgomery`]) does one Montgomery product per value, `2k² + k`
//! 64-bit multiplications for a `k`-limb modulus, and is bound by the multiplier's throughput:
//! on the spline grid's δ = 8 edit it was 30 % of a reduced Update, on the figure mesh's δ = 16
//! edit (a 7 000-bit rest) 84 %. Here the operands are split into 52-bit digits and each of the
//! eight 64-bit lanes of a vector register carries its own chain (lane `ℓ` multiplies the
//! values `ℓ, ℓ + 8, …`): `vpmadd52luq` / `vpmadd52huq` multiply eight pairs of digits and add
//! the low or high 52 bits of each product to a 64-bit accumulator, so one instruction does the
//! work of eight scalar multiply-adds. The product is "almost Montgomery" (Gueron and Krasnov,
//! 2016): operands below `2m`, `2^(52d) ≥ 4m` for `d` digits, results below `2m` and in digits
//! again after one carry pass; the accumulators are normalised once per product (each gathers
//! at most `4·2^52` per row, and the carries of at most `2^12` per row, over at most `d` rows:
//! below `2^64` for `d ≤ 1 000`).
//!
//! Every factor a lane picks up besides the values (`2^(−52d)` per product, the padding's ones)
//! is a unit modulo the odd `m`: the chain's product shares its primes with `m` exactly as the
//! product of the values does, which is all the certificate needs. Without IFMA (checked at run
//! time) the scalar chain runs instead.

use crate::ifma::{digit, from_digits, ifma_available, to_digits, DIGIT_BITS, DIGIT_MASK, LANES};

/// Moduli of more digits take the scalar chain (the accumulator bound above: `4·2^52·1 000` plus
/// the carries is below `2^64`). Up to this length the lanes beat the scalar chain's REDC by
/// whole products: the figure mesh's δ_max = 40 optimum (a rest of 829 digits, 10 430 values)
/// took 1.6 s on both cores there, 0.85 s here.
const MAX_DIGITS: usize = 1000;

/// A modulus in 52-bit digits with its Montgomery constant, when this processor has IFMA.
#[derive(Debug, Clone)]
pub(crate) struct LaneMontgomery {
    /// `d` digits, `2^(52d) ≥ 4m`.
    digits: Vec<u64>,
    /// `−m⁻¹ mod 2^52`.
    negated_inverse: u64,
}

impl LaneMontgomery {
    /// For the odd modulus `m` (64-bit limbs, `m > 1`) and `−m⁻¹ mod 2^64`; `None` without
    /// AVX-512 IFMA or beyond [`MAX_DIGITS`].
    pub(crate) fn new(modulus: &[u64], negated_inverse: u64) -> Option<Self> {
        if !ifma_available() {
            return None;
        }
        Some(LaneMontgomery {
            digits: modulus_digits(modulus)?,
            negated_inverse: negated_inverse & DIGIT_MASK,
        })
    }

    /// Digits per operand.
    pub(crate) fn digits(&self) -> usize {
        self.digits.len()
    }

    /// The product of `values` (each below `2m`, in 64-bit limbs) times `2^(−52d·e)` for the
    /// `e` returned, below `2m` in 64-bit limbs. Value `i` goes to lane `i mod 8` (short lanes
    /// are padded with ones); after the chains the lanes are folded into lane 0 by three more
    /// products of each lane with a permutation of the others (lanes `ℓ` and `ℓ ⊕ 4`, `ℓ ⊕ 2`,
    /// `ℓ ⊕ 1`), so the eight chains join without leaving the registers.
    pub(crate) fn product<'a>(
        &self,
        values: impl IntoIterator<Item = &'a [u64]>,
    ) -> (Vec<u64>, usize) {
        let d = self.digits();
        // Blocks of eight values, transposed: digit `j` of the block's value `ℓ` at `j·8 + ℓ`.
        let mut blocks: Vec<u64> = Vec::new();
        let mut in_block = 0;
        for value in values {
            if in_block == 0 {
                let start = blocks.len();
                blocks.resize(start + d * LANES, 0);
                for j in 0..LANES {
                    // Padding: the value one (until a value takes the lane).
                    blocks[start + j] = 1;
                }
            }
            let start = blocks.len() - d * LANES;
            for (j, slot) in blocks[start..]
                .iter_mut()
                .skip(in_block)
                .step_by(LANES)
                .enumerate()
            {
                *slot = digit(value, j);
            }
            in_block = (in_block + 1) % LANES;
        }
        let steps = blocks.len() / (d * LANES);
        let mut accumulators = vec![0u64; d * LANES];
        accumulators[..LANES].fill(1);
        // SAFETY: a `LaneMontgomery` exists only where `new` found AVX-512F and IFMA.
        #[cfg(target_arch = "x86_64")]
        unsafe {
            x86::chain(
                &self.digits,
                self.negated_inverse,
                &blocks,
                &mut accumulators,
            );
        }
        // Each lane carries 2^(−52d) per step; the folds multiply them together: 8 steps each,
        // and one more per product of the folds (4 + 2 + 1).
        (
            lane_to_limbs(&accumulators, d, 0),
            LANES * steps + LANES - 1,
        )
    }
}

/// The digits of an odd modulus `m > 1` with `2^(52d) ≥ 4m`, at most [`MAX_DIGITS`] of them.
fn modulus_digits(modulus: &[u64]) -> Option<Vec<u64>> {
    let bits = crate::gcd::bit_len(modulus);
    let count = (bits + 2).div_ceil(DIGIT_BITS as usize);
    if bits < 2 || modulus.first().is_none_or(|low| low & 1 == 0) || count > MAX_DIGITS {
        return None;
    }
    Some(to_digits(modulus, count))
}

/// Lane `lane` of transposed, normalised digits as 64-bit limbs.
fn lane_to_limbs(transposed: &[u64], d: usize, lane: usize) -> Vec<u64> {
    from_digits((0..d).map(|j| transposed[j * LANES + lane]))
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    use crate::ifma::x86::{load, store};
    use crate::ifma::{DIGIT_BITS, DIGIT_MASK, LANES};
    use std::arch::x86_64::{
        __m512i, _mm512_add_epi64, _mm512_and_si512, _mm512_madd52hi_epu64, _mm512_madd52lo_epu64,
        _mm512_permutexvar_epi64, _mm512_set1_epi64, _mm512_set_epi64, _mm512_setzero_si512,
        _mm512_srli_epi64,
    };

    /// `acc ← acc · block · 2^(−52d) mod m` lane by lane, for each block in turn (`blocks` and
    /// `accumulators` transposed as in [`super::LaneMontgomery::product`]).
    ///
    /// # Safety
    /// The processor must support AVX-512F and AVX-512 IFMA.
    #[target_feature(enable = "avx512f,avx512ifma")]
    pub(super) unsafe fn chain(
        modulus: &[u64],
        negated_inverse: u64,
        blocks: &[u64],
        accumulators: &mut [u64],
    ) {
        let d = modulus.len();
        let zero = _mm512_setzero_si512();
        let mask = _mm512_set1_epi64(DIGIT_MASK as i64);
        let ninv = _mm512_set1_epi64(negated_inverse as i64);
        let m: Vec<__m512i> = modulus
            .iter()
            .map(|&digit| _mm512_set1_epi64(digit as i64))
            .collect();
        let mut acc: Vec<__m512i> = (0..d).map(|j| load(accumulators, j)).collect();
        // The window of row `i` is `window[i..=i + d]`: sliding it up one digit per row instead
        // of moving `d` registers down.
        let mut window: Vec<__m512i> = vec![zero; 2 * d + 1];
        let mut b: Vec<__m512i> = vec![zero; d];
        let block_count = blocks.len() / (d * LANES);
        // After the blocks, the folds: `acc` times itself with lanes `ℓ ⊕ 4`, `ℓ ⊕ 2`, `ℓ ⊕ 1`.
        let folds = [4i64, 2, 1]
            .map(|x| _mm512_set_epi64(7 ^ x, 6 ^ x, 5 ^ x, 4 ^ x, 3 ^ x, 2 ^ x, 1 ^ x, x));
        for step in 0..block_count + folds.len() {
            if step < block_count {
                let block = &blocks[step * d * LANES..(step + 1) * d * LANES];
                for (j, bj) in b.iter_mut().enumerate() {
                    *bj = load(block, j);
                }
            } else {
                let fold = folds[step - block_count];
                for (bj, aj) in b.iter_mut().zip(&acc) {
                    *bj = _mm512_permutexvar_epi64(fold, *aj);
                }
            }
            window.fill(zero);
            for (i, &b) in b.iter().enumerate() {
                let t = &mut window[i..=i + d];
                for (j, a) in acc.iter().enumerate() {
                    t[j] = _mm512_madd52lo_epu64(t[j], *a, b);
                    t[j + 1] = _mm512_madd52hi_epu64(t[j + 1], *a, b);
                }
                let u = _mm512_madd52lo_epu64(zero, t[0], ninv);
                for (j, mj) in m.iter().enumerate() {
                    t[j] = _mm512_madd52lo_epu64(t[j], *mj, u);
                    t[j + 1] = _mm512_madd52hi_epu64(t[j + 1], *mj, u);
                }
                // The low 52 bits of `t[0]` are zero now: its carry moves up with the window.
                t[1] = _mm512_add_epi64(t[1], _mm512_srli_epi64::<DIGIT_BITS>(t[0]));
            }
            let mut carry = zero;
            for (a, t) in acc.iter_mut().zip(&window[d..2 * d]) {
                let v = _mm512_add_epi64(*t, carry);
                *a = _mm512_and_si512(v, mask);
                carry = _mm512_srli_epi64::<DIGIT_BITS>(v);
            }
        }
        for (j, a) in acc.iter().enumerate() {
            store(accumulators, j, *a);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gcd::from_limbs as big;
    use num_bigint::BigUint;
    use num_traits::One;
    use proptest::prelude::*;

    proptest! {
        /// Digits and back.
        #[test]
        fn digits_round_trip(limbs in prop::collection::vec(any::<u64>(), 0..12)) {
            let count = (crate::gcd::bit_len(&limbs) + 2).div_ceil(52);
            let digits = to_digits(&limbs, count);
            let mut transposed = vec![0u64; count * LANES];
            for (j, digit) in digits.iter().enumerate() {
                transposed[j * LANES + 3] = *digit;
            }
            prop_assert_eq!(big(&lane_to_limbs(&transposed, count, 3)), big(&limbs));
        }

        /// The product times `2^(52d·e)` is the product of the values modulo `m`, and below
        /// `2m`; for odd moduli of one to forty limbs and up to forty values below `2m` (so some
        /// lanes are padded, and with none at all the product is a unit).
        #[test]
        fn lanes_multiply_their_values(
            modulus in prop::collection::vec(any::<u64>(), 1..40),
            values in prop::collection::vec(prop::collection::vec(any::<u64>(), 0..41), 0..40),
        ) {
            let mut modulus = modulus;
            modulus[0] |= 1;
            let m = big(&modulus);
            prop_assume!(m > BigUint::one());
            let inverse = crate::word_division::word_inverse(modulus[0]).wrapping_neg();
            let Some(lanes) = LaneMontgomery::new(&modulus, inverse) else {
                // No IFMA here: the scalar chain serves (tested with `montgomery`).
                return Ok(());
            };
            let two_m: BigUint = &m << 1u32;
            let values: Vec<Vec<u64>> = values
                .iter()
                .map(|v| (big(v) % &two_m).to_u64_digits())
                .collect();
            let (product, exponent) = lanes.product(values.iter().map(Vec::as_slice));
            let expected = values.iter().fold(BigUint::one(), |acc, v| acc * big(v) % &m);
            let product = big(&product);
            prop_assert!(product < two_m);
            let shift = BigUint::one() << (52 * lanes.digits() * exponent);
            prop_assert_eq!(product * &shift % &m, expected);
        }
    }

    /// The longest modulus the lanes take (each accumulator gathers for 1 000 rows), with
    /// operands of large digits, gives the product; one digit more goes to the scalar chain.
    #[test]
    fn the_longest_moduli_keep_their_accumulators_in_64_bits() {
        // 2^(52·999 − 1) − 1: odd, 51 947 bits, so `2^(52d) ≥ 4m` first for d = 1 000.
        let m: BigUint = (BigUint::one() << (52 * 999 - 1)) - 1u32;
        let modulus = m.to_u64_digits();
        let inverse = crate::word_division::word_inverse(modulus[0]).wrapping_neg();
        assert_eq!(modulus_digits(&modulus).map(|d| d.len()), Some(MAX_DIGITS));
        let Some(lanes) = LaneMontgomery::new(&modulus, inverse) else {
            return;
        };
        let two_m: BigUint = &m << 1u32;
        // Below 2m: 2m − i (nearly all digits 2^52 − 1) and values of mixed digits.
        let values: Vec<Vec<u64>> = (1u32..=11)
            .map(|i| {
                let v = if i % 3 == 0 {
                    (&m * BigUint::from(i)) / 7u32
                } else {
                    &two_m - i
                };
                v.to_u64_digits()
            })
            .collect();
        let (product, exponent) = lanes.product(values.iter().map(Vec::as_slice));
        let expected = values
            .iter()
            .fold(BigUint::one(), |acc, v| acc * big(v) % &m);
        let product = big(&product);
        assert!(product < two_m);
        let shift = BigUint::one() << (52 * lanes.digits() * exponent);
        assert_eq!(product * &shift % &m, expected);
        let one_more: BigUint = (BigUint::one() << (52 * 1000 - 1)) - 1u32;
        assert_eq!(modulus_digits(&one_more.to_u64_digits()), None);
    }

    #[test]
    fn even_and_tiny_moduli_are_refused() {
        assert_eq!(modulus_digits(&[4]), None);
        assert_eq!(modulus_digits(&[1]), None);
        assert_eq!(modulus_digits(&[]), None);
        assert_eq!(modulus_digits(&[3]), Some(vec![3]));
        assert_eq!(modulus_digits(&[1 << 51 | 1]), Some(vec![1 << 51 | 1, 0]));
    }
}
