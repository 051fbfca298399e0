//! What the AVX-512 IFMA kernels share ([`crate::montgomery_lanes`]' product chains,
//! [`crate::lane_products`]' sums of digits times powers, for decimal text and p-adic
//! expansions): the run-time check for the instructions, values
//! split into 52-bit digits (`vpmadd52luq` / `vpmadd52huq` multiply 52-bit digits and add the
//! low or high half of each 104-bit product to a 64-bit lane), and transposed arrays of eight
//! lanes.

/// Bits per digit.
pub(crate) const DIGIT_BITS: u32 = 52;

/// `2^52 − 1`.
pub(crate) const DIGIT_MASK: u64 = (1 << DIGIT_BITS) - 1;

/// 64-bit lanes per register: eight values side by side.
pub(crate) const LANES: usize = 8;

/// Whether this processor runs AVX-512F with IFMA.
pub(crate) fn ifma_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512ifma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// The first `count` 52-bit digits of a value in 64-bit limbs.
pub(crate) fn to_digits(limbs: &[u64], count: usize) -> Vec<u64> {
    (0..count).map(|j| digit(limbs, j)).collect()
}

/// 52-bit digit `j` of a value in 64-bit limbs.
pub(crate) fn digit(limbs: &[u64], j: usize) -> u64 {
    let bit = j * DIGIT_BITS as usize;
    let (limb, offset) = (bit / 64, bit % 64);
    let low = limbs.get(limb).copied().unwrap_or(0) >> offset;
    let high = if offset > 64 - DIGIT_BITS as usize {
        limbs.get(limb + 1).copied().unwrap_or(0) << (64 - offset)
    } else {
        0
    };
    (low | high) & DIGIT_MASK
}

/// The value of 52-bit `digits` (least significant first) in 64-bit limbs, without leading
/// zero limbs: the inverse of [`to_digits`].
pub(crate) fn from_digits(digits: impl ExactSizeIterator<Item = u64>) -> Vec<u64> {
    let mut limbs = vec![0u64; (digits.len() * DIGIT_BITS as usize).div_ceil(64) + 1];
    for (j, digit) in digits.enumerate() {
        let bit = j * DIGIT_BITS as usize;
        let (limb, offset) = (bit / 64, bit % 64);
        limbs[limb] |= digit << offset;
        if offset > 64 - DIGIT_BITS as usize {
            limbs[limb + 1] |= digit >> (64 - offset);
        }
    }
    while limbs.last() == Some(&0) {
        limbs.pop();
    }
    limbs
}

/// The 52-bit digits of a value, as many as it has.
pub(crate) fn all_digits(limbs: &[u64]) -> Vec<u64> {
    to_digits(
        limbs,
        crate::gcd::bit_len(limbs).div_ceil(DIGIT_BITS as usize),
    )
}

#[cfg(target_arch = "x86_64")]
pub(crate) mod x86 {
    use super::LANES;
    use std::arch::x86_64::{__m512i, _mm512_loadu_si512, _mm512_storeu_si512};

    /// Register `j` of a transposed array: its eight lanes.
    #[inline]
    #[target_feature(enable = "avx512f")]
    pub(crate) fn load(v: &[u64], j: usize) -> __m512i {
        let lanes = &v[j * LANES..(j + 1) * LANES];
        // SAFETY: an unaligned load of the eight `u64` of `lanes`.
        unsafe { _mm512_loadu_si512(lanes.as_ptr().cast()) }
    }

    /// Writes register `j` of a transposed array.
    #[inline]
    #[target_feature(enable = "avx512f")]
    pub(crate) fn store(v: &mut [u64], j: usize, a: __m512i) {
        let lanes = &mut v[j * LANES..(j + 1) * LANES];
        // SAFETY: an unaligned store of eight `u64` into `lanes`.
        unsafe { _mm512_storeu_si512(lanes.as_mut_ptr().cast(), a) }
    }
}
