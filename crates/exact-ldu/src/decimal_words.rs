//! The decimal text of long integers by machine-word products, on any processor: what
//! [`crate::decimal_texts`] uses where [`crate::decimal_lanes`]' AVX-512 IFMA kernel cannot run.
//!
//! The same change of base as a matrix product as there, in 64-bit words: an integer of limbs
//! `c_k` is `n = Σ_k c_k · 2^(64k)`, each power `2^(64k)` is known in base `T = 10^19` once for
//! all integers of a batch (the table `P_k[j]`), and
//!
//! ```text
//! n = Σ_j T^j · V_j,   V_j = Σ_k c_k · P_k[j].
//! ```
//!
//! `num-bigint` converts by divisions (repeated division by `10^19` below about 32 limbs,
//! divide and conquer with its long division above): every step waits for the one before. The
//! sums here are independent products and additions, four running side by side, one
//! `64 × 64 → 128`-bit multiplication each, and the table is read in the order it is stored
//! (per position `j`, the powers that have a digit there). Measured on batches of 256 integers on
//! this project's 2-core AMD EPYC (no IFMA), table included (`cargo bench -p benchmarks --bench
//! decimal`): 1.7× `num-bigint`'s speed at 11 limbs (a δ_max = 8 grid edit's values), 3.0× at
//! 110 (δ_max = 16 on the figure mesh), 1.9× at 700 (δ_max = 40); in a prototype 1.4× at 1 400,
//! where the divide and conquer's sub-quadratic products catch up; hence [`MAX_LIMBS`].
//!
//! Bounds: `c_k < 2^64` and `P_k[j] < T < 2^63.12`, so a product is below `2^127.12` and a sum
//! of at most [`MAX_LIMBS`] of them below `2^137.12`: a 128-bit accumulator and a count of its
//! wraps. With the carry from the position below (below `2^75`, see [`WordPowers::chunks`]),
//! each position is divided by `T` in two word divisions by the precomputed reciprocal.

use num_bigint::{BigInt, Sign};

/// The decimal chunk, `10^19`: the largest power of ten below `2^64`. Its top bit is set
/// (`10^19 > 2^63`), so it is already normalised for [`divide_two_words`].
const CHUNK: u64 = 10_000_000_000_000_000_000;

/// Decimal digits per chunk.
const CHUNK_DIGITS: usize = 19;

/// `⌊(2^128 − 1) / T⌋ − 2^64`: the reciprocal of the (normalised) chunk for the division of two
/// words by it (Möller and Granlund, "Improved division by invariant integers", 2011).
const CHUNK_RECIPROCAL: u64 = (u128::MAX / CHUNK as u128 - (1u128 << 64)) as u64;

/// Integers of more limbs take `num-bigint`'s conversion: its divide and conquer is within
/// 1.4× at 1 400 limbs and overtakes beyond, and the table grows as the square of this.
pub(crate) const MAX_LIMBS: usize = 1024;

/// Integers of fewer limbs take `num-bigint`'s conversion (batches of 256: 1.1× its speed at 6
/// limbs, 0.8× at 3; 1.7× at 11).
pub(crate) const MIN_LIMBS: usize = 8;

/// The powers `2^(64k)`, `k < limbs`, in base `T`, stored by position: for position `j`, the
/// digit `j` of every power from the first that has one (`first[j]`; the powers' lengths grow
/// with `k`) to the last, at `values[start[j]..start[j + 1]]`.
pub(crate) struct WordPowers {
    limbs: usize,
    first: Vec<usize>,
    start: Vec<usize>,
    values: Vec<u64>,
}

impl WordPowers {
    /// The table for integers of at most `limbs` limbs (at most [`MAX_LIMBS`]).
    pub(crate) fn new(limbs: usize) -> Self {
        debug_assert!(limbs <= MAX_LIMBS);
        // Row k: 2^(64k) in base T, lowest digit first.
        let mut rows: Vec<Vec<u64>> = Vec::with_capacity(limbs);
        let mut power = vec![1u64];
        for _ in 0..limbs {
            let next = times_two_to_the_64(&power);
            rows.push(std::mem::replace(&mut power, next));
        }
        let positions = rows.last().map_or(0, Vec::len);
        let mut first = Vec::with_capacity(positions);
        let mut start = Vec::with_capacity(positions + 1);
        let mut values = Vec::with_capacity(rows.iter().map(Vec::len).sum());
        for j in 0..positions {
            // Every row from the first with a digit `j` has one: lengths never shrink.
            let k0 = rows.partition_point(|row| row.len() <= j);
            first.push(k0);
            start.push(values.len());
            values.extend(rows[k0..].iter().map(|row| row[j]));
        }
        start.push(values.len());
        WordPowers {
            limbs,
            first,
            start,
            values,
        }
    }

    /// The decimal text of `v` (at most as many limbs as the table's), as `to_string` writes it.
    pub(crate) fn text(&self, v: &BigInt) -> String {
        let limbs = v.magnitude().to_u64_digits();
        chunks_text(&self.chunks(&limbs), v.sign() == Sign::Minus)
    }

    /// The base-`T` chunks of the integer of `limbs` (lowest first, no leading zero chunk;
    /// empty for zero).
    ///
    /// Position `j` takes `u = V_j + c` with the carry `c` from below, then the chunk `u mod T`
    /// and the carry `⌊u / T⌋`. With `V_j < K · 2^127.12` for `K ≤ 2^10` limbs, the carries stay
    /// below `2^75` (`c < (2^137.12 + c) / 2^63.12`), so `u < 2^138`: its top word is below `T`
    /// and two divisions of two words by `T` give quotient and remainder.
    fn chunks(&self, limbs: &[u64]) -> Vec<u64> {
        debug_assert!(limbs.len() <= self.limbs);
        let k_count = limbs.len();
        // Positions with a power among the integer's limbs: those whose first power is below
        // `k_count`.
        let positions = self.first.partition_point(|&k0| k0 < k_count);
        let mut chunks = Vec::with_capacity(positions + 2);
        let mut carry = 0u128;
        for j in 0..positions {
            let k0 = self.first[j];
            let column = &self.values[self.start[j]..self.start[j + 1]];
            let (sum, wraps) = dot(&limbs[k0..], &column[..k_count - k0]);
            let chunk;
            (chunk, carry) = carry_position(sum, wraps, carry);
            chunks.push(chunk);
        }
        crate::decimal_lanes::finish_chunks(&mut chunks, carry, CHUNK);
        chunks
    }
}

/// `(u mod T, ⌊u / T⌋)` for `u = wraps · 2^128 + sum + carry` below `2^192` with a top word
/// below `T` (the bounds at [`WordPowers::chunks`]).
#[inline]
fn carry_position(sum: u128, wraps: u64, carry: u128) -> (u64, u128) {
    let (low, wrapped) = sum.overflowing_add(carry);
    let top = wraps + u64::from(wrapped);
    let (q_high, r) = divide_two_words(top, (low >> 64) as u64);
    let (q_low, chunk) = divide_two_words(r, low as u64);
    (chunk, (u128::from(q_high) << 64) | u128::from(q_low))
}

/// `Σ xᵢ yᵢ` as a 128-bit sum and the count of its wraps past `2^128`, in four interleaved
/// accumulators (each addition's carry waits only for its own accumulator's last one).
#[inline]
fn dot(xs: &[u64], ys: &[u64]) -> (u128, u64) {
    let mut sums = [0u128; 4];
    let mut wraps = [0u64; 4];
    let (x4, y4) = (xs.chunks_exact(4), ys.chunks_exact(4));
    let (x_rest, y_rest) = (x4.remainder(), y4.remainder());
    for (x, y) in x4.zip(y4) {
        for lane in 0..4 {
            let (s, w) = sums[lane].overflowing_add(u128::from(x[lane]) * u128::from(y[lane]));
            sums[lane] = s;
            wraps[lane] += u64::from(w);
        }
    }
    for (x, y) in x_rest.iter().zip(y_rest) {
        let (s, w) = sums[0].overflowing_add(u128::from(*x) * u128::from(*y));
        sums[0] = s;
        wraps[0] += u64::from(w);
    }
    let mut total = sums[0];
    let mut wrap_count = wraps.iter().sum::<u64>();
    for s in &sums[1..] {
        let (t, w) = total.overflowing_add(*s);
        total = t;
        wrap_count += u64::from(w);
    }
    (total, wrap_count)
}

/// `(⌊(u1·2^64 + u0) / T⌋, (u1·2^64 + u0) mod T)` for `u1 < T`, by the precomputed
/// reciprocal.
#[inline]
fn divide_two_words(u1: u64, u0: u64) -> (u64, u64) {
    crate::word_division::divide_two_words(u1, u0, CHUNK, CHUNK_RECIPROCAL)
}

/// `power · 2^64` in base `T` (digits below `T`, lowest first).
fn times_two_to_the_64(power: &[u64]) -> Vec<u64> {
    let mut next = Vec::with_capacity(power.len() + 1);
    let mut carry = 0u64;
    for &digit in power {
        // (digit · 2^64 + carry) / T: digit < T, so the quotient fits a word.
        let (q, r) = divide_two_words(digit, carry);
        next.push(r);
        carry = q;
    }
    while carry > 0 {
        next.push(carry % CHUNK);
        carry /= CHUNK;
    }
    next
}

/// The decimal text of base-`T` chunks (lowest first, no leading zero chunk), `-` first when
/// `negative` (and not zero): the top chunk as it is, every other one in nineteen digits.
fn chunks_text(chunks: &[u64], negative: bool) -> String {
    crate::decimal_lanes::chunks_text(chunks, negative, chunk_digits)
}

/// The nineteen digits of a chunk `x < 10^19`: four, then fifteen by
/// [`crate::decimal_lanes::chunk_digits`].
fn chunk_digits(x: u64) -> [u8; CHUNK_DIGITS] {
    const FIFTEEN: u64 = 1_000_000_000_000_000;
    let (high, low) = ((x / FIFTEEN) as u32, x % FIFTEEN);
    let mut out = [0u8; CHUNK_DIGITS];
    for (i, divisor) in [1000u32, 100, 10, 1].into_iter().enumerate() {
        out[i] = b'0' + (high / divisor % 10) as u8;
    }
    out[4..].copy_from_slice(&crate::decimal_lanes::chunk_digits(low));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_bigint::BigUint;
    use num_traits::One;
    use proptest::prelude::*;

    fn integer(limbs: &[u64], negative: bool) -> BigInt {
        let sign = if negative { Sign::Minus } else { Sign::Plus };
        BigInt::from_biguint(sign, crate::gcd::from_limbs(limbs))
    }

    /// Position `j` of the table holds digit `j` (base `10^19`) of every power `2^(64k)` that
    /// has one, from the first such power on.
    #[test]
    fn the_table_holds_the_powers_of_two_to_the_64() {
        let limbs = 40;
        let table = WordPowers::new(limbs);
        let t = BigUint::from(CHUNK);
        for k in 0..limbs {
            let mut power = BigUint::one() << (64 * k);
            let mut j = 0;
            while power > BigUint::default() {
                let digit = u64::try_from(&power % &t).expect("below 10^19");
                let k0 = table.first[j];
                assert!(k0 <= k, "power {k} has digit {j}");
                assert_eq!(
                    table.values[table.start[j] + k - k0],
                    digit,
                    "2^(64·{k}), digit {j}"
                );
                power /= &t;
                j += 1;
            }
            // No position past the power's length lists it.
            if j < table.first.len() {
                assert!(table.first[j] > k);
            }
        }
    }

    /// The largest integers the table takes (every limb `2^64 − 1`: the sums and carries at
    /// their bounds), powers of ten (chunks of zeros), their neighbours, zero and one, each
    /// positive and negative, give `to_string`'s text, with the table for the longest.
    #[test]
    fn the_text_is_to_strings_at_the_bounds() {
        let table = WordPowers::new(MAX_LIMBS);
        let mut values = vec![BigInt::default(), BigInt::one(), -BigInt::one()];
        for limbs in [1usize, 2, 3, 15, 16, 17, 100, 333, MAX_LIMBS] {
            let all_ones = integer(&vec![u64::MAX; limbs], false);
            let ten_power = BigInt::from(10u32).pow((limbs * 19 - 1) as u32);
            for v in [all_ones, ten_power.clone(), ten_power - 1u32] {
                values.push(-v.clone());
                values.push(v);
            }
        }
        for v in &values {
            assert!(v.magnitude().to_u64_digits().len() <= MAX_LIMBS);
            assert_eq!(table.text(v), v.to_string());
        }
    }

    /// Two-word division at the edges: zero, multiples of `T` and their neighbours, the largest
    /// dividend with `u1 < T`.
    #[test]
    fn two_word_division_at_the_edges() {
        let t = u128::from(CHUNK);
        for (u1, u0) in [
            (0, 0),
            (0, 1),
            (0, CHUNK - 1),
            (0, CHUNK),
            (0, u64::MAX),
            (1, 0),
            (CHUNK - 1, u64::MAX),
            (CHUNK - 1, 0),
        ] {
            let u = (u128::from(u1) << 64) | u128::from(u0);
            assert_eq!(
                divide_two_words(u1, u0),
                ((u / t) as u64, (u % t) as u64),
                "{u}"
            );
        }
    }

    /// A position's carry at the bounds: sums that wrap when the carry is added (the largest
    /// sum with the largest carry), a sum of exactly `T`, zero.
    #[test]
    fn positions_carry_at_the_bounds() {
        let t = BigUint::from(CHUNK);
        let largest_carry = (1u128 << 75) - 1;
        for (sum, wraps, carry) in [
            (u128::MAX, 1 << 10, largest_carry),
            (u128::MAX, 0, 1),
            (u128::MAX - 5, 3, 6),
            (u128::from(CHUNK), 0, 0),
            (0, 0, 0),
            (0, 1 << 10, 0),
        ] {
            let u = (BigUint::from(wraps) << 128) + sum + carry;
            let (chunk, carry_out) = carry_position(sum, wraps, carry);
            assert_eq!(BigUint::from(chunk), &u % &t, "{u}");
            assert_eq!(BigUint::from(carry_out), &u / &t, "{u}");
        }
    }

    /// Nineteen digits, zeros kept.
    #[test]
    fn chunk_digits_pad_with_zeros() {
        for x in [
            0,
            7,
            1_000,
            999_999_999_999_999,
            1_000_000_000_000_000,
            CHUNK - 1,
        ] {
            assert_eq!(chunk_digits(x).to_vec(), format!("{x:019}").into_bytes());
        }
    }

    proptest! {
        /// Two-word division agrees with the runtime's 128-bit division.
        #[test]
        fn two_word_division_is_division(u1 in 0..CHUNK, u0 in any::<u64>()) {
            let u = (u128::from(u1) << 64) | u128::from(u0);
            let t = u128::from(CHUNK);
            prop_assert_eq!(divide_two_words(u1, u0), ((u / t) as u64, (u % t) as u64));
        }

        /// Random integers of up to 80 limbs, with the table for 80, give `to_string`'s text.
        #[test]
        fn random_integers_give_to_strings_text(
            limbs in prop::collection::vec(any::<u64>(), 0..80),
            negative in any::<bool>(),
        ) {
            let v = integer(&limbs, negative);
            prop_assert_eq!(WordPowers::new(80).text(&v), v.to_string());
        }
    }
}
