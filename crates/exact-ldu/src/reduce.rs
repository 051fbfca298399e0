//! Reducing a vector of fractions over one denominator, `nᵢ / d`, to lowest terms.
//!
//! Entry by entry this is one big GCD per value, the largest cost of an exact update on real
//! meshes (denominators of thousands of digits). But the common factors are structured: on the
//! least-squares solutions of mesh edits `gcd(nᵢ, d)` is a product of small primes that divide
//! `d`, different for each value. So `d = S · B` is split into its smooth part `S` (primes below
//! [`SMALL_PRIME_BOUND`], those of one GCD of `d` with their product, once per vector) and the
//! rest `B`:
//!
//! - `gcd(nᵢ, S)` is read off `nᵢ`'s remainders modulo the word-sized prime powers of `S` (a
//!   pass over `nᵢ`'s limbs per group of them, instead of a GCD) and divided out exactly
//!   ([`crate::word_division`]);
//! - a value with a small reduced denominator (a parameter the constraints leave at its hint)
//!   is a multiple of `B`: its Montgomery residue (a row or two of REDC) is zero, and
//!   `gcd(nᵢ, B) = B`;
//! - every prime dividing both `B` and one of the other `nᵢ` divides
//!   `g = gcd(Π (nᵢ mod B) mod B, B)` (one product chain modulo `B` and one GCD). Usually
//!   `g = 1` and `B` is done; otherwise only `B_g`, the part of `B` made of the primes of `g`,
//!   matters: `gcd(nᵢ, B) = gcd(nᵢ mod B_g, B_g)`.
//!
//! On the figure mesh at δ_max = 16 (811 values over 7 100-bit denominators) this takes 20 ms
//! of CPU per coordinate against 60–110 ms for one GCD per value.

use crate::gcd::{from_limbs, gcd_bigint, gcd_biguint, reduced_ratio, Limbs};
use crate::montgomery::Montgomery;
use crate::word_division::{exact_quotient, exact_word_quotient, word_inverse, WordRemainder};
use api::words::all_fit;
use api::Rational;
use num_bigint::{BigInt, BigUint};
use num_integer::Integer;
use num_traits::{One, Signed, ToPrimitive, Zero};
use rayon::prelude::*;
use std::sync::{Arc, Mutex, OnceLock};

/// Below this many `bits of the denominator × values`, the plain entry-by-entry reduction is as
/// fast and parallel loops do not pay for their fork and join.
const COMMON_FACTOR_WORK: u64 = 1 << 16;

/// Values per product chain (chains run in parallel, their products are multiplied at the end).
const CHAIN: usize = 64;

/// Values per chunk of eight lane chains ([`Montgomery::lane_product`]): 32 per lane.
const LANE_CHAIN: usize = 256;

/// Primes below this bound are split off the denominator by trial division (larger shared
/// primes are still found, through `g`).
const SMALL_PRIME_BOUND: u32 = 1 << 12;

/// The primes below [`SMALL_PRIME_BOUND`] (sieve of Eratosthenes, once).
fn small_primes() -> &'static [u32] {
    static PRIMES: OnceLock<Vec<u32>> = OnceLock::new();
    PRIMES.get_or_init(|| {
        let n = SMALL_PRIME_BOUND as usize;
        let mut composite = vec![false; n];
        let mut primes = Vec::new();
        for i in 2..n {
            if !composite[i] {
                primes.push(i as u32);
                let mut j = i * i;
                while j < n {
                    composite[j] = true;
                    j += i;
                }
            }
        }
        primes
    })
}

/// `numerators[i] / den`, each in lowest terms with a positive denominator (`den ≠ 0`).
pub fn reduce_over(numerators: Vec<BigInt>, den: &BigInt) -> Vec<Rational> {
    debug_assert!(!den.is_zero());
    if let Some(reduced) = reduce_in_words(&numerators, den) {
        return reduced;
    }
    if den.bits() * (numerators.len() as u64) < COMMON_FACTOR_WORK {
        return numerators
            .into_iter()
            .map(|n| reduced_ratio(n, den.clone()))
            .collect();
    }
    let (numerators, den) = if den.is_negative() {
        (numerators.into_iter().map(|n| -n).collect(), -den)
    } else {
        (numerators, den.clone())
    };
    let limbs = numerators
        .iter()
        .map(|n| n.magnitude().iter_u64_digits().len())
        .max()
        .unwrap_or(0);
    let parts = DenominatorParts::of(&den, limbs);
    let DenominatorParts {
        rest,
        montgomery,
        smooth,
        smooth_word,
        ..
    } = &*parts;
    let residues = montgomery.as_ref().map(|m| Residues::new(&numerators, m));
    let g = match (montgomery, &residues) {
        (Some(m), Some(residues)) => gcd_bigint(&BigInt::from(product_modulo(residues, m)), rest),
        _ => BigInt::one(),
    };
    let rough = (!g.is_one()).then(|| part_made_of(rest, &g));
    numerators
        .into_par_iter()
        .enumerate()
        .map_init(Vec::new, |quotients, (i, n)| {
            if n.is_zero() {
                return Rational::from_integer(BigInt::zero());
            }
            let (mut n, mut common) = smooth.divide_out(n);
            if residues.as_ref().is_some_and(|r| r.get(i).is_none()) {
                n /= rest;
                common = common.times(rest);
            } else if let Some(part) = &rough {
                let c = gcd_bigint(&n.mod_floor(part), part);
                if !c.is_one() {
                    n /= &c;
                    common = common.times(&c);
                }
            }
            let reduced = match (&common, *smooth_word) {
                (CommonFactor::Word(1), _) => den.clone(),
                // `d / c = B · (S / c)` for a factor `c` of a word-sized `S`: a product by a
                // word, where the quotient of `d` is a serial division.
                (CommonFactor::Word(c), Some(s)) => {
                    BigInt::from(times_word(rest.magnitude(), s / c))
                }
                _ => reduced_denominator(&den, common, quotients),
            };
            Rational::new_raw(n, reduced)
        })
        .collect()
}

/// What [`reduce_over`] derives from the denominator alone: its smooth part (ready to divide
/// values by), the rest and its Montgomery form. Remembered for the last few denominators: the
/// frames of a drag keep theirs while the anchors move by steps of the same denominator, and
/// this is a division of the 5 700-bit primorial and a GCD per solution otherwise.
struct DenominatorParts {
    den: BigInt,
    /// The values' length the smooth part's remainders are prepared for.
    limbs: usize,
    smooth: SmoothPart,
    /// `S = d / B` when it fits a word (the usual case: a few small primes).
    smooth_word: Option<u64>,
    rest: BigInt,
    /// `None` when the rest is 1 (a smooth denominator: nothing to test).
    montgomery: Option<Montgomery>,
}

/// How many denominators [`DenominatorParts::of`] remembers.
const DENOMINATOR_MEMO: usize = 4;

impl DenominatorParts {
    /// The parts of `den > 0` for values of at most `limbs` limbs, remembered.
    fn of(den: &BigInt, limbs: usize) -> Arc<Self> {
        static MEMO: Mutex<Vec<Arc<DenominatorParts>>> = Mutex::new(Vec::new());
        let remembered = MEMO.lock().ok().and_then(|memo| {
            memo.iter()
                .find(|p| p.den == *den && p.limbs >= limbs)
                .cloned()
        });
        if let Some(parts) = remembered {
            return parts;
        }
        let (smooth, rest) = split_smooth(den.magnitude());
        // The rest is odd (2 is a small prime): Montgomery residues, zero exactly for the
        // values that are multiples of `rest` (those with small reduced denominators, such as
        // parameters the constraints leave at their hints), which would make the product
        // vanish.
        let smooth_word = smooth.iter().try_fold(1u64, |acc, &(p, e)| {
            (0..e).try_fold(acc, |acc, _| acc.checked_mul(u64::from(p)))
        });
        let parts = Arc::new(DenominatorParts {
            den: den.clone(),
            limbs,
            smooth: SmoothPart::new(&smooth, limbs),
            smooth_word,
            montgomery: Montgomery::new(&rest),
            rest: BigInt::from(rest),
        });
        if let Ok(mut memo) = MEMO.lock() {
            if memo.len() == DENOMINATOR_MEMO {
                memo.remove(0);
            }
            memo.push(Arc::clone(&parts));
        }
        parts
    }
}

/// How many distinct common factors [`reduced_denominator`] remembers per worker.
const QUOTIENT_MEMO: usize = 16;

/// The common factor of a value and the denominator: a word while it fits (no allocation for
/// the usual factors, products of small primes), else a big integer.
#[derive(Debug, Clone, PartialEq, Eq)]
enum CommonFactor {
    Word(u64),
    Long(BigInt),
}

impl CommonFactor {
    /// `self · f`.
    fn times(self, f: &BigInt) -> Self {
        CommonFactor::Long(match self {
            CommonFactor::Word(w) => f * w,
            CommonFactor::Long(c) => c * f,
        })
    }

    /// `x / self` for a multiple `x` of `self`.
    fn divide(&self, x: BigInt) -> BigInt {
        match self {
            CommonFactor::Word(w) => exact_word_quotient(x, *w),
            CommonFactor::Long(c) => exact_quotient(x, c),
        }
    }
}

/// `den / common`, remembered in `quotients`: the values of one solution share few distinct
/// common factors with its denominator (powers of the same small primes), so most values
/// take a denominator already divided.
fn reduced_denominator(
    den: &BigInt,
    common: CommonFactor,
    quotients: &mut Vec<(CommonFactor, BigInt)>,
) -> BigInt {
    if let Some((_, quotient)) = quotients.iter().find(|(c, _)| *c == common) {
        return quotient.clone();
    }
    let quotient = common.divide(den.clone());
    if quotients.len() < QUOTIENT_MEMO {
        quotients.push((common, quotient.clone()));
    }
    quotient
}

/// `x · w`, in place in one copy of `x` when the product has `x`'s length, else in one
/// allocation of its own length (`num-bigint`'s product of a copy by a word reallocates when
/// the carry takes a limb more).
fn times_word(x: &BigUint, w: u64) -> BigUint {
    if w == 1 {
        return x.clone();
    }
    let limbs = x.iter_u64_digits().len() as u64;
    if x.bits() + u64::from(64 - w.leading_zeros()) <= 64 * limbs {
        return x.clone() * w;
    }
    thread_local! {
        static PRODUCT: std::cell::RefCell<Vec<u64>> = const { std::cell::RefCell::new(Vec::new()) };
    }
    PRODUCT.with_borrow_mut(|product| {
        product.clear();
        let mut carry = 0u64;
        for limb in x.iter_u64_digits() {
            let t = u128::from(limb) * u128::from(w) + u128::from(carry);
            product.push(t as u64);
            carry = (t >> 64) as u64;
        }
        product.push(carry);
        from_limbs(product)
    })
}

/// [`reduce_over`] by [`crate::reduce_words`] when the denominator and every value fit an `i128`.
fn reduce_in_words(numerators: &[BigInt], den: &BigInt) -> Option<Vec<Rational>> {
    let words = all_fit(
        numerators.len(),
        numerators.iter().map(ToPrimitive::to_i128),
    )?;
    let reduced = crate::reduce_words::reduce_words(&words, den.to_i128()?)?;
    Some(
        reduced
            .into_iter()
            .map(|(n, d)| {
                Rational::new_raw(
                    crate::ring::bigint_from_i128(n),
                    crate::ring::bigint_from_i128(d),
                )
            })
            .collect(),
    )
}

/// The product of the primes below [`SMALL_PRIME_BOUND`] (once; about 5 700 bits).
fn primorial() -> &'static BigUint {
    static PRODUCT: OnceLock<BigUint> = OnceLock::new();
    PRODUCT.get_or_init(|| {
        small_primes()
            .iter()
            .fold(BigUint::one(), |product, &p| product * p)
    })
}

/// `d = Π pᵉ · rest` over the primes `p` below [`SMALL_PRIME_BOUND`]: the `(p, e)` with `e > 0`
/// and `rest`. The primes are those of `gcd(d, Π p)`, one GCD with the primorial (a division
/// and a Lehmer GCD of `d`'s length) where trial division took a pass over `d`'s limbs per
/// group of primes, ~190 passes of hardware divisions; then each of them divides `d` out.
fn split_smooth(d: &BigUint) -> (Vec<(u32, u32)>, BigUint) {
    // gcd(d, P) = gcd(d, P mod d): the division brings the primorial down to d's length
    // before the GCD (which would otherwise take the long way for operands this unequal).
    let mut shared = gcd_biguint(d, &(primorial() % d));
    let mut rest = d.clone();
    let mut factors = Vec::new();
    for &p in small_primes() {
        if shared.is_one() {
            break;
        }
        if !(&shared % p).is_zero() {
            continue;
        }
        shared /= p;
        let mut e = 0;
        if p == 2 {
            let zeros = rest.trailing_zeros().unwrap_or(0);
            rest >>= zeros;
            e = zeros as u32;
        } else {
            while (&rest % p).is_zero() {
                rest /= p;
                e += 1;
            }
        }
        factors.push((p, e));
    }
    (factors, rest)
}

/// A prime `p` of the smooth part with its exponent `e` in `d` (`pᵉ < 2^32`).
#[derive(Debug, Clone, Copy)]
struct PrimePower {
    p: u32,
    e: u32,
    /// `p⁻¹ mod 2^64` for an odd `p` (`0` for 2).
    inverse: u64,
    /// `(2^64 − 1) / p`.
    limit: u64,
}

impl PrimePower {
    fn new(p: u32, e: u32) -> Self {
        let inverse = if p % 2 == 1 {
            word_inverse(u64::from(p))
        } else {
            0
        };
        PrimePower {
            p,
            e,
            inverse,
            limit: u64::MAX / u64::from(p),
        }
    }

    /// `min(v_p(n), e)` read on `r ≡ n (mod pᵉ)`: the exponent of `p` in `r` (all of `e` for
    /// `r = 0`). For an odd `p`, `r` is a multiple of `p` exactly when `r · p⁻¹ mod 2^64` is at
    /// most `(2^64 − 1) / p`, and that product is then `r / p` (Granlund and Montgomery 1994):
    /// a multiplication per factor instead of a division.
    fn exponent_in(&self, mut r: u64) -> u32 {
        if r == 0 {
            return self.e;
        }
        if self.p == 2 {
            return r.trailing_zeros().min(self.e);
        }
        let mut v = 0;
        while v < self.e {
            let q = r.wrapping_mul(self.inverse);
            if q > self.limit {
                break;
            }
            r = q;
            v += 1;
        }
        v
    }
}

/// The smooth part's primes: those whose power `pᵉ` fits a word, in groups whose product fits
/// a word (one pass over a numerator's limbs per group gives its remainder modulo every power
/// in the group), and the others as `(p, e)`, divided out one factor at a time.
#[derive(Debug, Default)]
struct SmoothPart {
    groups: Vec<(WordRemainder, Vec<PrimePower>)>,
    large: Vec<(u32, u32)>,
}

impl SmoothPart {
    /// For values of about `limbs` limbs.
    fn new(smooth: &[(u32, u32)], limbs: usize) -> Self {
        let mut groups: Vec<(u64, Vec<PrimePower>)> = Vec::new();
        let mut large = Vec::new();
        for &(p, e) in smooth {
            let power = (0..e).try_fold(1u64, |acc, _| {
                acc.checked_mul(u64::from(p)).filter(|v| *v < 1 << 32)
            });
            let Some(power) = power else {
                large.push((p, e));
                continue;
            };
            let pp = PrimePower::new(p, e);
            match groups.last_mut() {
                Some((product, members)) if *product * power < 1 << 32 => {
                    *product *= power;
                    members.push(pp);
                }
                _ => groups.push((power, vec![pp])),
            }
        }
        SmoothPart {
            groups: groups
                .into_iter()
                .map(|(product, members)| {
                    // Below 2^32 by construction.
                    (WordRemainder::new(product as u32, limbs), members)
                })
                .collect(),
            large,
        }
    }

    /// `n / c` and `c = gcd(n, S)`: for each word-sized power `pᵉ`, the exponent of `p` in
    /// `n mod pᵉ` (all of `e` when the remainder is zero) read on words, one division of `n` by
    /// their product; then the large powers a factor at a time.
    fn divide_out(&self, n: BigInt) -> (BigInt, CommonFactor) {
        // The factor found so far: `long · word`, `long` only once `word` would overflow.
        let mut long: Option<BigUint> = None;
        let mut word: u64 = 1;
        let mut push = |p: u32| match word.checked_mul(u64::from(p)) {
            Some(w) => word = w,
            None => {
                *long.get_or_insert_with(BigUint::one) *= word;
                word = u64::from(p);
            }
        };
        for (product, members) in &self.groups {
            let remainder = product.of(n.magnitude());
            for pp in members {
                // `remainder` is modulo a multiple of `pᵉ`.
                for _ in 0..pp.exponent_in(remainder) {
                    push(pp.p);
                }
            }
        }
        let common = match long {
            None => CommonFactor::Word(word),
            Some(long) => CommonFactor::Long(BigInt::from(long * word)),
        };
        let mut n = if common == CommonFactor::Word(1) {
            n
        } else {
            common.divide(n)
        };
        let mut extra: Option<BigInt> = None;
        for &(p, e) in &self.large {
            for _ in 0..e {
                if !(n.magnitude() % p).is_zero() {
                    break;
                }
                n /= p;
                *extra.get_or_insert_with(BigInt::one) *= p;
            }
        }
        let common = match extra {
            None => common,
            Some(extra) => common.times(&extra),
        };
        (n, common)
    }
}

/// `Π rᵢ` over the nonzero residues, times a power of `2^−64`, modulo `m` (in parallel chains):
/// shares its primes with `m` exactly as the product of the values does.
fn product_modulo(residues: &Residues, m: &Montgomery) -> BigUint {
    let one = || vec![1u64];
    let chunk = if m.has_lanes() { LANE_CHAIN } else { CHAIN };
    let chain = |first: usize| -> Limbs {
        let nonzero =
            || (first..(first + chunk).min(residues.len())).filter_map(|i| residues.get(i));
        m.lane_product(nonzero())
            .unwrap_or_else(|| m.chain_product(nonzero()))
    };
    let product = (0..residues.len())
        .into_par_iter()
        .step_by(chunk)
        .map(chain)
        .reduce(one, |mut a, b| {
            m.mul_assign(&mut a, &b, &mut Vec::new());
            a
        });
    from_limbs(&product)
}

/// The values' residues modulo the rest ([`Montgomery::residue_into`]), `k` limbs each in one
/// buffer (no allocation per value), with which of them are zero.
struct Residues {
    limbs: Vec<u64>,
    k: usize,
    nonzero: Vec<bool>,
}

impl Residues {
    fn new(numerators: &[BigInt], m: &Montgomery) -> Self {
        let k = m.limbs();
        let mut limbs = vec![0u64; numerators.len() * k];
        limbs
            .par_chunks_mut(k)
            .zip(numerators)
            .for_each_init(Vec::new, |scratch, (out, n)| {
                m.residue_into(n.magnitude(), out, scratch);
            });
        let nonzero = limbs.chunks(k).map(|r| r.iter().any(|l| *l != 0)).collect();
        Residues { limbs, k, nonzero }
    }

    fn len(&self) -> usize {
        self.nonzero.len()
    }

    /// Value `i`'s residue, `None` when it is zero (the value a multiple of the rest).
    fn get(&self, i: usize) -> Option<&[u64]> {
        self.nonzero[i].then(|| &self.limbs[i * self.k..(i + 1) * self.k])
    }
}

/// The largest divisor of `d` whose primes all divide `g` (`g` a divisor of `d`).
fn part_made_of(d: &BigInt, g: &BigInt) -> BigInt {
    let mut part = BigInt::one();
    let mut rest = d.clone();
    let mut factor = g.clone();
    loop {
        let c = gcd_bigint(&rest, &factor);
        if c.is_one() {
            return part;
        }
        rest /= &c;
        part *= &c;
        factor = c;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A Mersenne prime above the trial-division bound.
    fn large_prime() -> BigInt {
        (BigInt::one() << 127) - 1
    }

    /// Large enough for the common-factor path; `3^700 · 2^90 · 7^3 · 11^2 · extra` (powers
    /// beyond a word and within one), times the large prime when asked.
    fn big_denominator(extra: &BigInt, with_large_prime: bool) -> BigInt {
        let d = BigInt::from(3).pow(700u32)
            * BigInt::from(2).pow(90u32)
            * BigInt::from(7 * 7 * 7 * 11 * 11)
            * extra;
        if with_large_prime {
            d * large_prime()
        } else {
            d
        }
    }

    proptest! {
        /// The same fractions as `Rational::new`, on every path: factors shared through the
        /// smooth part, values with small reduced denominators (multiples of the rest), a large
        /// shared prime (found through `g`), and coprime values.
        #[test]
        fn equals_reducing_each_value(
            values in prop::collection::vec(-1_000_000i64..1_000_000, 1..200),
            extra in 1i64..10_000,
            negative in any::<bool>(),
            with_large_prime in any::<bool>(),
        ) {
            let extra = BigInt::from(extra);
            let den = big_denominator(&extra, with_large_prime);
            let sixth = &den / 6;
            reduces_like_each_value(&values, den, negative, |kind, v| match kind {
                0 => v * BigInt::from(3).pow(5u32) * 49,
                1 => v * &extra,
                2 => v * &sixth,
                3 => v * large_prime() + 1,
                _ => v * large_prime(),
            })?;
        }
    }

    /// [`reduce_over`] of the values `make(i mod 5, vᵢ)` over `den` (negated when asked) is
    /// `Rational::new` of each.
    fn reduces_like_each_value(
        values: &[i64],
        den: BigInt,
        negative: bool,
        make: impl Fn(usize, BigInt) -> BigInt,
    ) -> Result<(), TestCaseError> {
        let den = if negative { -den } else { den };
        let numerators: Vec<BigInt> = values
            .iter()
            .enumerate()
            .map(|(i, v)| make(i % 5, BigInt::from(*v)))
            .collect();
        let expected: Vec<Rational> = numerators
            .iter()
            .map(|n| Rational::new(n.clone(), den.clone()))
            .collect();
        prop_assert_eq!(reduce_over(numerators, &den), expected);
        Ok(())
    }

    proptest! {
        /// With a smooth part that fits a word, the reduced denominators are the rest times the
        /// smooth part's cofactor: the same fractions as `Rational::new` for factors shared
        /// through the smooth part, through one of the rest's primes and through all of it.
        #[test]
        fn word_sized_smooth_parts_reduce_like_each_value(
            values in prop::collection::vec(-1_000_000i64..1_000_000, 100..200),
            twos in 0u32..20,
            threes in 0u32..12,
            divisor in prop::sample::select(vec![1i64, 2, 6, 49, 11 * 7 * 3, 2 * 3 * 5 * 7 * 11]),
            negative in any::<bool>(),
        ) {
            let smooth = BigInt::from(2).pow(twos) * BigInt::from(3).pow(threes) * (5 * 7 * 7 * 11 * 11);
            let mersenne = (BigInt::one() << 521) - 1;
            let rest = &mersenne * large_prime();
            reduces_like_each_value(&values, &smooth * &rest, negative, |kind, v| match kind {
                0 => v * divisor,
                1 => v * divisor * &mersenne,
                2 => v * divisor * &rest,
                3 => v * &rest + divisor,
                _ => v,
            })?;
        }
    }

    /// A value times a word: as `num-bigint` multiplies, when the product keeps the value's
    /// length and when the carry takes a limb more.
    #[test]
    fn products_by_a_word() {
        let values = [
            BigUint::from(7u32),
            (BigUint::one() << 100) - 1u32,
            (BigUint::one() << 640) + 12345u32,
            (BigUint::one() << 704) - 1u32,
        ];
        for x in &values {
            for w in [1u64, 2, 3, 1 << 20, u64::MAX] {
                assert_eq!(times_word(x, w), x * w, "{x} · {w}");
            }
        }
    }

    proptest! {
        /// `min(v_p(r), e)` as repeated division finds it, for 2, odd primes and `r = 0`.
        #[test]
        fn exponents_by_inverses(
            p in prop::sample::select(vec![2u32, 3, 5, 17, 4093]),
            e in 1u32..32,
            factors in 0u32..40,
            cofactor in any::<u64>(),
        ) {
            let pp = PrimePower::new(p, e);
            let r = (0..factors).fold(cofactor, |r, _| r.wrapping_mul(u64::from(p)));
            let mut expected = 0;
            let mut rest = r;
            while rest != 0 && expected < e && rest % u64::from(p) == 0 {
                rest /= u64::from(p);
                expected += 1;
            }
            if r == 0 {
                expected = e;
            }
            prop_assert_eq!(pp.exponent_in(r), expected);
        }
    }

    proptest! {
        /// The chains' product shares its primes with the modulus exactly as the values'
        /// product does, by eight lanes (where the processor has IFMA) and by the scalar chain:
        /// a modulus `p · q · r` with Mersenne primes `p = 2^61 − 1`, `q = 2^89 − 1`, values
        /// some of which are multiples of `p` or `q`, enough of them for several chunks.
        #[test]
        fn product_chains_find_the_shared_primes(
            values in prop::collection::vec(prop::collection::vec(any::<u64>(), 0..12), 0..700),
            cofactor in prop::collection::vec(any::<u64>(), 0..8),
            multiples in prop::collection::vec(0usize..700, 0..3),
        ) {
            let p: BigInt = (BigInt::one() << 61u32) - 1;
            let q: BigInt = (BigInt::one() << 89u32) - 1;
            let r = BigInt::from(from_limbs(&cofactor)) * 2 + 1;
            let modulus: BigInt = &p * &q * &r;
            let values: Vec<BigInt> = values
                .iter()
                .enumerate()
                .map(|(i, v)| {
                    let v = BigInt::from(from_limbs(v));
                    match multiples.iter().position(|&m| m == i) {
                        Some(0) => v * &p,
                        Some(_) => v * &q,
                        None => v,
                    }
                })
                .collect();
            let with_lanes = Montgomery::new(modulus.magnitude()).expect("odd");
            for m in [with_lanes.clone(), with_lanes.without_lanes()] {
                // Multiples of the modulus (zero residues) are left out of the chain, as
                // `reduce_over` divides them separately.
                let residues = Residues::new(&values, &m);
                let product: BigInt = values
                    .iter()
                    .enumerate()
                    .filter(|(i, _)| residues.get(*i).is_some())
                    .map(|(_, v)| v)
                    .product();
                let g = gcd_bigint(&BigInt::from(product_modulo(&residues, &m)), &modulus);
                prop_assert_eq!(g, gcd_bigint(&product, &modulus));
            }
        }
    }

    /// A remembered denominator serves later solutions over it, longer values included (its
    /// parts are prepared again for them), with the same fractions as `Rational::new`.
    #[test]
    fn remembered_denominators_reduce_like_fresh_ones() {
        let den = big_denominator(&BigInt::from(13), true);
        for (round, length) in [(1i64, 1u32), (2, 1), (3, 40)] {
            let numerators: Vec<BigInt> = (1..300)
                .map(|i| {
                    let v = BigInt::from(i * round) * BigInt::from(3).pow(length * 30) + i;
                    if i % 7 == 0 {
                        v * &den / BigInt::from(7 * 7 * 7)
                    } else {
                        v
                    }
                })
                .collect();
            let expected: Vec<Rational> = numerators
                .iter()
                .map(|n| Rational::new(n.clone(), den.clone()))
                .collect();
            assert_eq!(reduce_over(numerators, &den), expected, "round {round}");
        }
    }

    /// Coprime numerators take the fast path and come back unchanged over the denominator.
    #[test]
    fn coprime_values_keep_their_denominator() {
        let den = BigInt::from(2).pow(4000u32) + 1;
        let numerators: Vec<BigInt> = (1..50).map(|i| BigInt::from(2).pow(i)).collect();
        let reduced = reduce_over(numerators.clone(), &den);
        for (r, n) in reduced.iter().zip(&numerators) {
            assert_eq!(r.numer(), n);
            assert_eq!(r.denom(), &den);
        }
    }
}
