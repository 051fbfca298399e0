//! The integers `Σ_t δ_{t,i} p^t` of a lifted solve's p-adic digits, for all entries at once
//! (eight at a time in IFMA lanes, [`crate::lane_products`]).
//!
//! A lifted solve ([`crate::dixon`]) ends with `k` digits per entry, and each entry's digits
//! become one integer. By halves (`PadicPowers` in `dixon`) each entry costs a few balanced
//! big-integer products; on the figure mesh's δ_max = 40 optimum (2 814 unknowns, ~1 450 steps of
//! a 31-bit prime, 45 000-bit results) that was 0.5–1.25 s of the run on both cores. Here the
//! powers `p^t` are written once in 52-bit digits (`P_t[j]`) and every entry is
//! `Σ_j 2^(52j) V_j` with `V_j = Σ_t δ_t P_t[j]`: one matrix product for all entries, then one
//! carry pass each.
//!
//! The lanes multiply unsigned digits below `2^52`: a digit in `[0, p)` is taken as it is; a
//! balanced digit `δ ∈ (−p/2, p/2]` as `δ + p ∈ (p/2, 3p/2]`, and the sum of the added `p^(t+1)`,
//! `C = p (p^k − 1) / (p − 1)`, is subtracted at the end. With `p < 2^31` each digit is below
//! `2^33` and each product below `2^85`, so the high halves' sums stay below `2^45` over the
//! at most [`MAX_TERMS`] steps the lanes take.

use crate::ifma::{from_digits, ifma_available, DIGIT_BITS, DIGIT_MASK, LANES};
use crate::lane_products::{PowerTable, MAX_TERMS};
use num_bigint::{BigInt, BigUint};
use rayon::prelude::*;

/// Fewer steps take the product tree (a few products of a few limbs each).
const MIN_STEPS: usize = 64;

/// Fewer entries take the product tree: the table costs about one entry's combination.
const MIN_ENTRIES: usize = 16;

/// `Σ_{t<steps} δ_{t,i} p^t` for every entry `i < n`, `δ_{t,i}` being `digits[t·n + i] ∈ [0,
/// p)`, or that digit balanced into `(−p/2, p/2]` when `balanced` (as the lifting took it);
/// `None` where the lanes do not apply (no IFMA, fewer than [`MIN_STEPS`] steps or more than
/// [`MAX_TERMS`], fewer than [`MIN_ENTRIES`] entries, `p ≥ 2^31`): the caller combines by halves.
pub(crate) fn combine(
    digits: &[u32],
    n: usize,
    steps: usize,
    p: u64,
    balanced: bool,
) -> Option<Vec<BigInt>> {
    if !(MIN_STEPS..=MAX_TERMS).contains(&steps)
        || n < MIN_ENTRIES
        || p >= 1 << 31
        || digits.len() < steps * n
        || !ifma_available()
    {
        return None;
    }
    let table = PowerTable::new(steps, vec![1], |power| {
        // Times p: each digit's product plus the carry stays below 2^84.
        let mut carry = 0u128;
        for digit in power.iter_mut() {
            let t = u128::from(*digit) * u128::from(p) + carry;
            *digit = t as u64 & DIGIT_MASK;
            carry = t >> DIGIT_BITS;
        }
        while carry > 0 {
            power.push(carry as u64 & DIGIT_MASK);
            carry >>= DIGIT_BITS;
        }
    });
    let offset = if balanced {
        let p_big = BigUint::from(p);
        BigInt::from(&p_big * (p_big.pow(steps as u32) - 1u32) / (p - 1))
    } else {
        BigInt::default()
    };
    let lane_digit = |d: u32| -> u64 {
        let d = u64::from(d);
        // δ + p for the balanced digit δ of d: d + p when d ≤ p/2, d itself (δ = d − p) above.
        if balanced && 2 * d <= p {
            d + p
        } else {
            d
        }
    };
    let groups: Vec<Vec<BigInt>> = (0..n.div_ceil(LANES))
        .into_par_iter()
        .map(|g| {
            let start = g * LANES;
            let members = LANES.min(n - start);
            let mut transposed = vec![0u64; steps * LANES];
            for (t, row) in transposed.chunks_exact_mut(LANES).enumerate() {
                let from = &digits[t * n + start..t * n + start + members];
                for (slot, &d) in row.iter_mut().zip(from) {
                    *slot = lane_digit(d);
                }
            }
            let sums = table.group_sums(&transposed);
            (0..members)
                .map(|lane| BigInt::from(carried(sums.lane(lane))) - &offset)
                .collect()
        })
        .collect();
    Some(groups.into_iter().flatten().collect())
}

/// `Σ_j 2^(52j) (low_j + 2^52 high_j)`, carried into 64-bit limbs.
fn carried(positions: impl Iterator<Item = (u64, u64)>) -> BigUint {
    let mut digits: Vec<u64> = Vec::new();
    let mut carry = 0u128;
    for (low, high) in positions {
        let v = u128::from(low) + (u128::from(high) << DIGIT_BITS) + carry;
        digits.push(v as u64 & DIGIT_MASK);
        carry = v >> DIGIT_BITS;
    }
    while carry > 0 {
        digits.push(carry as u64 & DIGIT_MASK);
        carry >>= DIGIT_BITS;
    }
    crate::gcd::from_limbs(&from_digits(digits.into_iter()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// `Σ_t δ_t p^t` the plain way.
    fn horner(digits: &[u32], n: usize, steps: usize, i: usize, p: u64, balanced: bool) -> BigInt {
        (0..steps).rev().fold(BigInt::default(), |acc, t| {
            let d = i64::from(digits[t * n + i]);
            let d = if balanced && 2 * d > p as i64 {
                d - p as i64
            } else {
                d
            };
            acc * p + d
        })
    }

    /// Digits `0`, `p − 1`, `(p ± 1)/2` (the balanced range's edges) and mixed ones, for the
    /// largest lifting prime and a small one, balanced and not, at the step thresholds and
    /// with a last group of fewer than eight entries.
    #[test]
    fn combinations_are_the_expansions() {
        if !ifma_available() {
            return;
        }
        let largest = crate::modular::lifting_primes().next().unwrap_or(3);
        for p in [largest, 65_537] {
            for (n, steps) in [(16, 64), (21, 65), (40, 300), (17, MAX_TERMS)] {
                let digits: Vec<u32> = (0..n * steps)
                    .map(|x| match x % 7 {
                        0 => 0,
                        1 => (p - 1) as u32,
                        2 => (p / 2) as u32,
                        3 => (p / 2 + 1) as u32,
                        _ => (((x as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 33) % p) as u32,
                    })
                    .collect();
                for balanced in [false, true] {
                    let combined =
                        combine(&digits, n, steps, p, balanced).expect("the lanes apply");
                    for (i, value) in combined.iter().enumerate() {
                        assert_eq!(
                            value,
                            &horner(&digits, n, steps, i, p, balanced),
                            "p {p}, n {n}, steps {steps}, entry {i}"
                        );
                    }
                }
            }
        }
    }

    /// Outside the lanes' range the caller is told to combine by halves.
    #[test]
    fn small_or_long_expansions_are_left_to_the_caller() {
        let digits = vec![1u32; 40 * (MAX_TERMS + 1)];
        assert!(combine(&digits, 40, MIN_STEPS - 1, 101, true).is_none());
        assert!(combine(&digits, MIN_ENTRIES - 1, 100, 101, true).is_none());
        assert!(combine(&digits, 40, MAX_TERMS + 1, 101, false).is_none());
        assert!(combine(&digits, 40, 100, 1 << 31, false).is_none());
    }

    proptest! {
        /// Random digits below `p`.
        #[test]
        fn random_digits_combine(
            n in 16usize..30,
            steps in 64usize..140,
            seed in any::<u64>(),
            balanced in any::<bool>(),
        ) {
            if !ifma_available() {
                return Ok(());
            }
            let p = 2_147_483_647u64;
            let mut state = seed | 1;
            let digits: Vec<u32> = (0..n * steps)
                .map(|_| {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    (state % p) as u32
                })
                .collect();
            let combined = combine(&digits, n, steps, p, balanced).expect("the lanes apply");
            for (i, value) in combined.iter().enumerate() {
                prop_assert_eq!(value, &horner(&digits, n, steps, i, p, balanced));
            }
        }
    }
}
