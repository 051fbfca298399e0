//! Sums of digits times a shared table of powers, eight integers side by side with AVX-512
//! IFMA: for integers given by digits `c_k` (below `2^52`) and powers `P_k` given by their own
//! digits `P_k[j]` (below `2^52`, in whatever base the caller chose),
//!
//! ```text
//! V_j = Σ_k c_k · P_k[j]   for every position j.
//! ```
//!
//! That is a change of base written as a matrix product: the decimal text of a binary integer
//! (`P_k = 2^(52k)` in base `10^15`, [`crate::decimal_lanes`]) and a p-adic expansion made an
//! integer (`P_k = p^k` in base `2^52`, [`crate::padic_lanes`]). Done one integer at a time by
//! division or by a product tree, each step waits for the one before; here no product waits for
//! another. Lane `ℓ` of a register holds integer `ℓ` of a group of eight, `vpmadd52luq` /
//! `vpmadd52huq` add the low and high 52 bits of `c_k · P_k[j]` to two accumulators per
//! position, and eight positions at a time stay in registers while `k` runs; the table is read
//! once per group.
//!
//! Each low half is below `2^52`, so over at most [`MAX_TERMS`] digits a low accumulator stays
//! below `2^64`; the high halves are below `2^(b_c + b_P − 52)` for `b_c`-bit digits and
//! `b_P`-bit table entries, and their bound is the caller's to keep (each caller says how).

use crate::ifma::LANES;

/// The most digits an integer may have (the low accumulators' bound above: `4 095 · 2^52 <
/// 2^64`).
pub(crate) const MAX_TERMS: usize = 4095;

/// The powers `P_k`, laid out for the kernel: block `b` holds digits `8b … 8b + 7` of every
/// power that has digit `8b`, eight values per power (zeros past its length), from power
/// `first[b]` on (the powers' lengths never shrink, so each block's powers are consecutive).
pub(crate) struct PowerTable {
    /// The first power with digit `8b`, per block `b` (nondecreasing).
    first: Vec<usize>,
    /// Per block, eight digits per power from `first[b]`.
    blocks: Vec<Vec<u64>>,
}

impl PowerTable {
    /// The powers `P_0 = start` and `P_{k+1} = next(P_k)` for `k < count`, each in digits below
    /// `2^52`, lowest first, no power shorter than the one before.
    pub(crate) fn new(count: usize, start: Vec<u64>, mut next: impl FnMut(&mut Vec<u64>)) -> Self {
        let mut power = start;
        let mut first: Vec<usize> = Vec::new();
        let mut blocks: Vec<Vec<u64>> = Vec::new();
        for k in 0..count {
            for (b, digits) in power.chunks(LANES).enumerate() {
                if b == blocks.len() {
                    first.push(k);
                    blocks.push(Vec::with_capacity((count - k) * LANES));
                }
                let block = &mut blocks[b];
                block.extend_from_slice(digits);
                block.resize(block.len() + LANES - digits.len(), 0);
            }
            if k + 1 < count {
                next(&mut power);
            }
        }
        PowerTable { first, blocks }
    }

    /// The sums `V_j` of a group of up to eight integers, whose digits are given transposed
    /// (digit `k` of member `ℓ` at `k·8 + ℓ`, zeros for lanes without a member), at most as many
    /// per member as the table has powers and at most [`MAX_TERMS`]. Only where
    /// [`crate::ifma::ifma_available`] holds.
    pub(crate) fn group_sums(&self, transposed: &[u64]) -> GroupSums {
        let k_count = transposed.len() / LANES;
        debug_assert!(k_count <= MAX_TERMS);
        let block_count = self.first.iter().take_while(|&&f| f < k_count).count();
        let positions = block_count * LANES;
        let mut low = vec![0u64; positions * LANES];
        let mut high = vec![0u64; positions * LANES];
        #[cfg(target_arch = "x86_64")]
        // SAFETY: callers come here only where `ifma_available` found AVX-512F and IFMA.
        unsafe {
            x86::accumulate(self, transposed, k_count, block_count, &mut low, &mut high);
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            // Callers check for IFMA, which only x86-64 has.
            let _ = (&mut low, &mut high);
            unreachable!("the IFMA kernel runs on x86-64 only");
        }
        GroupSums {
            positions,
            low,
            high,
        }
    }
}

#[cfg(test)]
impl PowerTable {
    /// Power `k`'s digits as stored, with the zeros up to its last block's end.
    pub(crate) fn stored_power(&self, k: usize) -> Vec<u64> {
        self.blocks
            .iter()
            .zip(&self.first)
            .take_while(|(_, &first)| first <= k)
            .flat_map(|(block, &first)| {
                block[(k - first) * LANES..(k - first + 1) * LANES].to_vec()
            })
            .collect()
    }
}

/// The sums of a group: per position `j` and lane `ℓ`, the low and high halves' sums, `V_j =
/// low + 2^52 · high`.
pub(crate) struct GroupSums {
    positions: usize,
    low: Vec<u64>,
    high: Vec<u64>,
}

impl GroupSums {
    /// `(low_j, high_j)` of lane `lane`, lowest position first (trailing positions may be zero).
    pub(crate) fn lane(&self, lane: usize) -> impl Iterator<Item = (u64, u64)> + '_ {
        (0..self.positions).map(move |j| (self.low[j * LANES + lane], self.high[j * LANES + lane]))
    }
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    use super::PowerTable;
    use crate::ifma::x86::{load, store};
    use crate::ifma::LANES;
    use std::arch::x86_64::{
        _mm512_madd52hi_epu64, _mm512_madd52lo_epu64, _mm512_set1_epi64, _mm512_setzero_si512,
    };

    /// The kernel of [`PowerTable::group_sums`]: per block of eight positions, sixteen
    /// accumulators in registers while the digits `k` run from the block's first power.
    ///
    /// # Safety
    /// The processor must support AVX-512F and AVX-512 IFMA.
    #[target_feature(enable = "avx512f,avx512ifma")]
    pub(super) unsafe fn accumulate(
        table: &PowerTable,
        digits: &[u64],
        k_count: usize,
        block_count: usize,
        low: &mut [u64],
        high: &mut [u64],
    ) {
        let zero = _mm512_setzero_si512();
        for (b, (block, &first)) in table
            .blocks
            .iter()
            .zip(&table.first)
            .take(block_count)
            .enumerate()
        {
            let mut lo = [zero; LANES];
            let mut hi = [zero; LANES];
            for (k, row) in (first..k_count).zip(block.chunks_exact(LANES)) {
                let c = load(digits, k);
                for t in 0..LANES {
                    let p = _mm512_set1_epi64(row[t] as i64);
                    lo[t] = _mm512_madd52lo_epu64(lo[t], c, p);
                    hi[t] = _mm512_madd52hi_epu64(hi[t], c, p);
                }
            }
            for t in 0..LANES {
                store(low, b * LANES + t, lo[t]);
                store(high, b * LANES + t, hi[t]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_bigint::BigUint;

    /// Each lane's sums are `Σ_k c_k P_k` (checked as integers: `Σ_j (low_j + 2^52 high_j)
    /// 2^(52j)` for powers in base `2^52`), for members of different lengths (a lane shorter
    /// than the table, an empty lane) and the largest digits.
    #[test]
    fn the_sums_are_digits_times_powers() {
        if !crate::ifma::ifma_available() {
            return;
        }
        // P_k = 3^(40k) in base 2^52.
        let step = BigUint::from(3u32).pow(40);
        let table = PowerTable::new(30, vec![1], |power| {
            let next = crate::ifma::all_digits(&(from_digits(power) * &step).to_u64_digits());
            *power = next;
        });
        let max = (1u64 << 52) - 1;
        let members: Vec<Vec<u64>> = vec![
            vec![max; 30],
            (0..30u64).map(|k| k * 0x1234_5678_9ABC % max).collect(),
            vec![7; 12],
            vec![],
            vec![0, 0, max],
        ];
        let mut transposed = vec![0u64; 30 * LANES];
        for (lane, member) in members.iter().enumerate() {
            for (k, &c) in member.iter().enumerate() {
                transposed[k * LANES + lane] = c;
            }
        }
        let sums = table.group_sums(&transposed);
        for (lane, member) in members.iter().enumerate() {
            let expected = member
                .iter()
                .enumerate()
                .fold(BigUint::default(), |acc, (k, &c)| {
                    acc + step.pow(k as u32) * c
                });
            let found =
                sums.lane(lane)
                    .enumerate()
                    .fold(BigUint::default(), |acc, (j, (lo, hi))| {
                        acc + ((BigUint::from(lo) + (BigUint::from(hi) << 52)) << (52 * j))
                    });
            assert_eq!(found, expected, "lane {lane}");
        }
    }

    fn from_digits(digits: &[u64]) -> BigUint {
        digits
            .iter()
            .rev()
            .fold(BigUint::default(), |acc, &d| (acc << 52) + d)
    }
}
