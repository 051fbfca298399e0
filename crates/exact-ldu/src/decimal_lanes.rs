//! The decimal text of many long integers at once, eight side by side with AVX-512 IFMA.
//!
//! An exact optimum on a real mesh commits thousands of values of thousands of digits (the
//! figure mesh at δ_max = 40: 10 432 numerators of ~13 500 digits), and every one is written in
//! decimal. `num-bigint` converts one integer by repeated division by `10^19`: a dependent chain
//! through all limbs per output limb, `k²/2` divisions for `k` limbs (~215 µs at 700 limbs).
//!
//! Here an integer of 52-bit digits `c_k` is written as `n = Σ_k c_k · 2^(52k)`, and each power
//! `2^(52k)` is known in base `T = 10^15` once for all integers (the table `P_k[j]`), so
//!
//! ```text
//! n = Σ_j T^j · V_j,   V_j = Σ_k c_k · P_k[j].
//! ```
//!
//! The `V_j` are sums of independent products, a matrix product ([`crate::lane_products`], eight
//! integers at a time in IFMA lanes): the same count of multiplications as the division's, at
//! the multiplier's throughput instead of a division's latency. One pass per integer then
//! carries the `V_j` into base-`T` chunks (bounds at [`normalise`]) and writes fifteen digits
//! per chunk.
//!
//! Bounds: `c_k < 2^52` and `P_k[j] < T < 2^49.83`, so each high half is below `2^49.83`; over
//! at most [`MAX_DIGITS`] `= 2^11` digits the low accumulator stays below `2^63` and the high one
//! below `2^60.83` (what [`normalise`] takes). Longer integers and short ones (the table is not
//! worth it) take `num-bigint`'s conversion, processors without IFMA
//! [`crate::decimal_words`]' word products; the text is the same either way.

use crate::decimal_words::{self, WordPowers};
use crate::ifma::{all_digits, ifma_available, DIGIT_BITS, LANES};
use crate::lane_products::PowerTable;
use num_bigint::{BigInt, Sign};
use rayon::prelude::*;

/// The decimal chunk: `10^15 < 2^50`.
const CHUNK: u64 = 1_000_000_000_000_000;

/// Decimal digits per chunk.
const CHUNK_DIGITS: usize = 15;

/// Integers of fewer 52-bit digits take `num-bigint`'s conversion (short and quadratic there
/// too, but the table would cost more than it saves).
const MIN_DIGITS: usize = 24;

/// Fewer long integers than this take `num-bigint`'s conversion: building the table costs
/// about what converting one or two of them does.
const MIN_BATCH: usize = 16;

/// Below this much work (`Σ (1 + d²)` over the integers' 52-bit digit counts `d`, about the
/// count of one-digit conversions it equals) the integers are converted on the calling thread:
/// handing work to the thread pool costs several microseconds, what a few hundred short
/// conversions take (the values of a small edit's report).
const SEQUENTIAL_WORK: usize = 256;

/// The most 52-bit digits an integer may have here (106 496 bits): the accumulators' bounds
/// above.
const MAX_DIGITS: usize = 2048;

/// The decimal text of every integer (`-` before negative ones), as `to_string` writes it, in
/// order; on all cores unless there is little to do.
pub fn decimal_texts(values: &[&BigInt]) -> Vec<String> {
    let digit_count = |v: &BigInt| v.bits().div_ceil(u64::from(DIGIT_BITS)) as usize;
    let work = values.iter().fold(0usize, |sum, v| {
        let d = digit_count(v);
        sum.saturating_add(d.saturating_mul(d).saturating_add(1))
    });
    if work < SEQUENTIAL_WORK {
        return values.iter().map(|v| short_text(v)).collect();
    }
    if !ifma_available() {
        return word_texts(values);
    }
    let mut long: Vec<usize> = (0..values.len())
        .filter(|&i| (MIN_DIGITS..=MAX_DIGITS).contains(&digit_count(values[i])))
        .collect();
    if long.len() < MIN_BATCH {
        return values.par_iter().map(|v| short_text(v)).collect();
    }
    // Groups of eight of about the same length (longest first): a lane shorter than its
    // group's longest computes zeros.
    long.sort_by_key(|&i| std::cmp::Reverse(digit_count(values[i])));
    let table = power_table(digit_count(values[long[0]]));
    let converted: Vec<(usize, String)> = long
        .par_chunks(LANES)
        .flat_map_iter(|group| {
            let members: Vec<&BigInt> = group.iter().map(|&i| values[i]).collect();
            group
                .iter()
                .copied()
                .zip(convert_group(&table, &members))
                .collect::<Vec<_>>()
        })
        .collect();
    let mut texts: Vec<Option<String>> = vec![None; values.len()];
    for (i, text) in converted {
        texts[i] = Some(text);
    }
    texts
        .into_par_iter()
        .zip(values.par_iter())
        .map(|(text, v)| text.unwrap_or_else(|| short_text(v)))
        .collect()
}

/// [`decimal_texts`] without IFMA: integers of [`decimal_words::MIN_LIMBS`] to
/// [`decimal_words::MAX_LIMBS`] limbs by word products with one table for the batch (when
/// there are at least [`MIN_BATCH`] of them), the others by `num-bigint`; on all cores.
fn word_texts(values: &[&BigInt]) -> Vec<String> {
    let limb_count = |v: &BigInt| v.bits().div_ceil(64) as usize;
    let words_take =
        |v: &BigInt| (decimal_words::MIN_LIMBS..=decimal_words::MAX_LIMBS).contains(&limb_count(v));
    let long = values.iter().filter(|v| words_take(v));
    if long.clone().count() < MIN_BATCH {
        return values.par_iter().map(|v| short_text(v)).collect();
    }
    let table = WordPowers::new(long.map(|v| limb_count(v)).max().unwrap_or(0));
    values
        .par_iter()
        .map(|v| {
            if words_take(v) {
                table.text(v)
            } else {
                short_text(v)
            }
        })
        .collect()
}

/// `v.to_string()`, through the machine integer's conversion when `v` fits one (a small edit's
/// values: `num-bigint` converts by digit vectors and allocations, ten times the work).
fn short_text(v: &BigInt) -> String {
    match i64::try_from(v) {
        Ok(x) => x.to_string(),
        Err(_) => v.to_string(),
    }
}

/// `2^(52k)` in base `T = 10^15` for `k < digits`.
fn power_table(digits: usize) -> PowerTable {
    PowerTable::new(digits, vec![1], |power| {
        // Times 2^52: each chunk's product plus the carry stays below 2^102, its quotient
        // below 2^53.
        let mut carry = 0u64;
        for chunk in power.iter_mut() {
            let (q, r) = divide_by_chunk((u128::from(*chunk) << 52) + u128::from(carry));
            *chunk = r;
            carry = q as u64;
        }
        while carry > 0 {
            power.push(carry % CHUNK);
            carry /= CHUNK;
        }
    })
}

/// The decimal text of up to eight integers of at most as many 52-bit digits as the table has
/// powers.
fn convert_group(table: &PowerTable, members: &[&BigInt]) -> Vec<String> {
    let digits: Vec<Vec<u64>> = members
        .iter()
        .map(|v| all_digits(&v.magnitude().to_u64_digits()))
        .collect();
    let k_count = digits.iter().map(Vec::len).max().unwrap_or(0);
    // Digit `k` of member `ℓ` at `k·8 + ℓ`.
    let mut transposed = vec![0u64; k_count * LANES];
    for (lane, member) in digits.iter().enumerate() {
        for (k, &c) in member.iter().enumerate() {
            transposed[k * LANES + lane] = c;
        }
    }
    let sums = table.group_sums(&transposed);
    members
        .iter()
        .enumerate()
        .map(|(lane, v)| {
            chunks_text(
                &normalise(sums.lane(lane)),
                v.sign() == Sign::Minus,
                chunk_digits,
            )
        })
        .collect()
}

/// The base-`T` chunks (lowest first, no leading zero chunk; empty for zero) of
/// `Σ_j T^j (low_j + 2^52 high_j)`, for `low_j < 2^64` and `high_j < 2^61`: position `j` with
/// the carry `c` in is `u = low_j + 2^52 high_j + c < 2^64 + 2^113 + 2^65 < 2^114`, its chunk
/// `u mod T` and the carry out `⌊u / T⌋ < 2^65`.
fn normalise(positions: impl Iterator<Item = (u64, u64)>) -> Vec<u64> {
    let mut chunks = Vec::new();
    let mut carry = 0u128;
    for (low, high) in positions {
        let (q, r) = divide_by_chunk(u128::from(low) + (u128::from(high) << 52) + carry);
        chunks.push(r);
        carry = q;
    }
    finish_chunks(&mut chunks, carry, CHUNK);
    chunks
}

/// The last carry's base-`chunk` digits pushed onto `chunks`, then the leading zero chunks
/// dropped.
pub(crate) fn finish_chunks(chunks: &mut Vec<u64>, mut carry: u128, chunk: u64) {
    while carry > 0 {
        chunks.push((carry % u128::from(chunk)) as u64);
        carry /= u128::from(chunk);
    }
    while chunks.last() == Some(&0) {
        chunks.pop();
    }
}

/// `T` shifted to the top of a word: `T < 2^50` has 50 bits.
const CHUNK_SHIFT: u32 = CHUNK.leading_zeros();

/// `⌊(2^128 − 1) / (T·2^14)⌋ − 2^64`: the reciprocal of the normalised divisor (Möller and
/// Granlund, "Improved division by invariant integers", 2011).
const CHUNK_RECIPROCAL: u64 = (u128::MAX / ((CHUNK as u128) << CHUNK_SHIFT) - (1u128 << 64)) as u64;

/// `(⌊u / T⌋, u mod T)` for `u < 2^114`, by two multiplications instead of the runtime's
/// 128-bit division: the high word's share first (`u >> 64 < 2^50`, a quotient of at most
/// one), then Möller and Granlund's division of two words by the normalised `T` with its
/// precomputed reciprocal (their algorithm 4).
fn divide_by_chunk(u: u128) -> (u128, u64) {
    let (high, low) = ((u >> 64) as u64, u as u64);
    let (q_high, r_high) = (high / CHUNK, high % CHUNK);
    let d = CHUNK << CHUNK_SHIFT;
    // (u1, u0) = (r_high·2^64 + low)·2^14, u1 < d.
    let u1 = (r_high << CHUNK_SHIFT) | (low >> (64 - CHUNK_SHIFT));
    let u0 = low << CHUNK_SHIFT;
    let (q1, r) = crate::word_division::divide_two_words(u1, u0, d, CHUNK_RECIPROCAL);
    (
        (u128::from(q_high) << 64) | u128::from(q1),
        r >> CHUNK_SHIFT,
    )
}

/// The decimal text of base-`T` chunks (lowest first, no leading zero chunk), `-` first when
/// `negative` (and not zero): the top chunk as it is, every other one in `D` digits by `digits`
/// (fifteen here, nineteen for [`crate::decimal_words`]' chunks).
pub(crate) fn chunks_text<const D: usize>(
    chunks: &[u64],
    negative: bool,
    digits: impl Fn(u64) -> [u8; D],
) -> String {
    let Some((&top, rest)) = chunks.split_last() else {
        return "0".to_owned();
    };
    let sign = if negative { "-" } else { "" };
    let mut text = format!("{sign}{top}").into_bytes();
    text.reserve(rest.len() * D);
    for &chunk in rest.iter().rev() {
        text.extend_from_slice(&digits(chunk));
    }
    // Only ASCII digits were written.
    String::from_utf8(text).unwrap_or_default()
}

/// The fifteen digits of a chunk `x < 10^15`, by pairs from a table: the two halves below
/// `10^8` and their quarters below `10^4` are independent, so the divisions overlap.
pub(crate) fn chunk_digits(x: u64) -> [u8; CHUNK_DIGITS] {
    const PAIRS: &[u8; 200] = b"0001020304050607080910111213141516171819\
        2021222324252627282930313233343536373839\
        4041424344454647484950515253545556575859\
        6061626364656667686970717273747576777879\
        8081828384858687888990919293949596979899";
    let pair = |v: u32| -> [u8; 2] {
        let i = 2 * v as usize;
        [PAIRS[i], PAIRS[i + 1]]
    };
    let (high, low) = ((x / 100_000_000) as u32, (x % 100_000_000) as u32);
    let quarters = [high / 10_000, high % 10_000, low / 10_000, low % 10_000];
    let mut out = [0u8; CHUNK_DIGITS];
    // The first quarter has three digits (high < 10^7), the others four.
    out[0] = b'0' + (quarters[0] / 100) as u8;
    out[1..3].copy_from_slice(&pair(quarters[0] % 100));
    for (i, &q) in quarters[1..].iter().enumerate() {
        let at = 3 + 4 * i;
        out[at..at + 2].copy_from_slice(&pair(q / 100));
        out[at + 2..at + 4].copy_from_slice(&pair(q % 100));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_bigint::BigUint;
    use num_traits::One;
    use proptest::prelude::*;

    /// The table's chunks are those of the powers of `2^52`.
    #[test]
    fn the_table_holds_the_powers_of_two_to_the_52() {
        let table = power_table(60);
        for k in 0..60usize {
            let power = BigUint::one() << (52 * k);
            let expected: Vec<u64> = power
                .to_radix_le(10)
                .chunks(CHUNK_DIGITS)
                .map(|d| d.iter().rev().fold(0u64, |acc, &x| acc * 10 + u64::from(x)))
                .collect();
            let mut padded = expected.clone();
            padded.resize(expected.len().div_ceil(LANES) * LANES, 0);
            assert_eq!(table.stored_power(k), padded, "2^(52·{k})");
        }
    }

    /// Carrying the largest accumulators the bounds allow (`2^64 − 1` and `2^61 − 1` at every
    /// position) gives the value they stand for.
    #[test]
    fn normalising_the_largest_accumulators_keeps_their_value() {
        let positions: Vec<(u64, u64)> = (0..40)
            .map(|j| match j % 3 {
                0 => (u64::MAX, (1 << 61) - 1),
                1 => (0, (1 << 61) - 1),
                _ => (u64::MAX, CHUNK - 1),
            })
            .collect();
        let expected = positions
            .iter()
            .rev()
            .fold(BigUint::default(), |acc, &(low, high)| {
                acc * CHUNK + BigUint::from(low) + (BigUint::from(high) << 52)
            });
        let chunks = normalise(positions.into_iter());
        assert!(chunks.iter().all(|&c| c < CHUNK));
        assert_eq!(
            chunks_text(&chunks, false, chunk_digits),
            expected.to_string()
        );
        assert_eq!(
            chunks_text(&normalise([(0, 0), (0, 0)].into_iter()), true, chunk_digits),
            "0"
        );
    }

    fn integer(limbs: &[u64], negative: bool) -> BigInt {
        let magnitude = crate::gcd::from_limbs(limbs);
        let sign = if negative { Sign::Minus } else { Sign::Plus };
        BigInt::from_biguint(sign, magnitude)
    }

    /// Integers of every length around the thresholds (short ones, zero, the longest the
    /// lanes take and one digit more), of large digits and of chunks that are zero in
    /// decimal (powers of ten), positive and negative, in a batch long enough for the lanes.
    #[test]
    fn the_text_is_to_strings_at_every_length() {
        let mut values: Vec<BigInt> = vec![BigInt::default(), BigInt::from(-7)];
        for limbs in [
            1usize, 10, 19, 20, 21, 40, 333, 700, 1_663, 1_664, 1_665, 1_700,
        ] {
            // All bits set, then a power of ten of about that length, then mixed limbs.
            values.push(integer(&vec![u64::MAX; limbs], limbs % 2 == 0));
            values.push(
                BigInt::from(10u32).pow((limbs * 19) as u32) * if limbs % 3 == 0 { -1 } else { 1 },
            );
            let mixed: Vec<u64> = (0..limbs as u64)
                .map(|i| i.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ (i << 7))
                .collect();
            values.push(integer(&mixed, limbs % 3 == 1));
        }
        // 52 · 2048 = 106 496 bits: exactly the most digits, and one bit more.
        values.push(BigInt::from(1u32) << (52 * MAX_DIGITS - 1));
        values.push(BigInt::from(1u32) << (52 * MAX_DIGITS));
        let refs: Vec<&BigInt> = values.iter().collect();
        let texts = decimal_texts(&refs);
        for (v, text) in values.iter().zip(&texts) {
            assert_eq!(text, &v.to_string());
        }
    }

    /// Machine-word integers and their neighbours beyond the word: `to_string`'s text, in a
    /// short batch (the calling thread) and a long one (the pool).
    #[test]
    fn word_integers_and_their_neighbours_are_to_strings() {
        let mut values: Vec<BigInt> = Vec::new();
        for edge in [
            BigInt::from(i64::MIN),
            BigInt::from(i64::MAX),
            BigInt::default(),
        ] {
            for delta in -2i64..=2 {
                values.push(&edge + delta);
            }
        }
        values.push(BigInt::from(u64::MAX));
        values.push(-BigInt::from(u64::MAX));
        let refs: Vec<&BigInt> = values.iter().collect();
        let long_batch: Vec<&BigInt> = refs.iter().copied().cycle().take(400).collect();
        for batch in [&refs, &long_batch] {
            let texts = decimal_texts(batch);
            for (v, text) in batch.iter().zip(&texts) {
                assert_eq!(text, &v.to_string());
            }
        }
    }

    /// Chunk divisions at the edges: zero, multiples of `T` and their neighbours, the largest
    /// dividend allowed.
    #[test]
    fn chunk_division_at_the_edges() {
        let t = u128::from(CHUNK);
        let limit = (1u128 << 114) - 1;
        for u in [
            0,
            1,
            t - 1,
            t,
            t + 1,
            t * t,
            t * t - 1,
            (1 << 64) - 1,
            1 << 64,
            limit,
            limit / t * t,
            limit / t * t - 1,
        ] {
            assert_eq!(divide_by_chunk(u), (u / t, (u % t) as u64), "{u}");
        }
    }

    /// Fifteen digits, zeros kept.
    #[test]
    fn chunk_digits_pad_with_zeros() {
        for x in [
            0,
            7,
            10,
            99,
            100_000_000,
            123_456_789_012_345,
            CHUNK - 1,
            100_000_000_000_001,
        ] {
            assert_eq!(chunk_digits(x).to_vec(), format!("{x:015}").into_bytes());
        }
    }

    proptest! {
        /// Chunk division agrees with the runtime's 128-bit division below `2^114`.
        #[test]
        fn chunk_division_is_division(u in any::<u128>()) {
            let u = u >> 14;
            let t = u128::from(CHUNK);
            prop_assert_eq!(divide_by_chunk(u), (u / t, (u % t) as u64));
        }

        /// Fifteen digits of any chunk.
        #[test]
        fn chunk_digits_are_formats(x in 0..CHUNK) {
            prop_assert_eq!(chunk_digits(x).to_vec(), format!("{x:015}").into_bytes());
        }

        /// Random batches (of sizes around the batch threshold, lengths around the digit
        /// threshold) give `to_string`'s text.
        #[test]
        fn random_batches_give_to_strings_text(
            values in prop::collection::vec(
                (prop::collection::vec(any::<u64>(), 0..60), any::<bool>()),
                0..40,
            ),
        ) {
            let values: Vec<BigInt> = values.iter().map(|(l, n)| integer(l, *n)).collect();
            let refs: Vec<&BigInt> = values.iter().collect();
            let texts = decimal_texts(&refs);
            prop_assert_eq!(texts.len(), values.len());
            for (v, text) in values.iter().zip(&texts) {
                prop_assert_eq!(text, &v.to_string());
            }
        }
    }
}
