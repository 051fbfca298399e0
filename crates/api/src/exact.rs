//! Exact values: arbitrary-precision integers and rationals, and the exact reading of decimal text.
//!
//! Decimal text such as `0.1` is read as the rational `1/10`, never through `f64`, so a value a
//! user typed is the value the solver sees.

use num_bigint::BigInt;
use num_integer::Integer as _;
use num_rational::BigRational;
use num_traits::{One, Zero};
use serde::de::{self, Deserializer, Visitor};
use serde::Deserialize;
use std::fmt;

/// Arbitrary-precision integer: constraint coefficients and right-hand sides.
pub type Integer = BigInt;

/// Arbitrary-precision rational: parameter values, hints, weights and solutions.
pub type Rational = BigRational;

/// Why a text could not be read as an exact rational.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{message} at column {column} of {text:?}")]
pub struct ParseRationalError {
    /// The text that was being read.
    pub text: String,
    /// 1-based column (in characters) of the first offending character.
    pub column: usize,
    /// What was expected there.
    pub message: String,
}

impl ParseRationalError {
    fn at(text: &str, byte: usize, message: impl Into<String>) -> Self {
        ParseRationalError {
            text: text.to_string(),
            column: text[..byte.min(text.len())].chars().count() + 1,
            message: message.into(),
        }
    }
}

/// Reads an exact rational from text.
///
/// Accepted forms (surrounding whitespace is ignored):
/// * integers: `3`, `-12`, `+7`;
/// * decimals with optional exponent: `-2.5`, `.25`, `1e-3`, `6.02E23`;
/// * fractions of integers: `7/3`, `-4/6` (the result is reduced; the denominator must be nonzero).
///
/// Every form is converted exactly: `0.1` becomes `1/10`.
pub fn parse_rational(text: &str) -> Result<Rational, ParseRationalError> {
    let trimmed_start = text.len() - text.trim_start().len();
    let body = text.trim();
    if body.is_empty() {
        return Err(ParseRationalError::at(text, 0, "expected a number"));
    }
    if let Some(slash) = body.find('/') {
        let numer = parse_integer(text, trimmed_start, &body[..slash])?;
        let denom_text = &body[slash + 1..];
        let denom = parse_integer(text, trimmed_start + slash + 1, denom_text)?;
        if denom.is_zero() {
            return Err(ParseRationalError::at(
                text,
                trimmed_start + slash + 1,
                "denominator must be nonzero",
            ));
        }
        return Ok(Rational::new(numer, denom));
    }
    parse_decimal(text, trimmed_start, body)
}

/// Parses a signed integer occupying `part`, which starts at byte `offset` of `full`.
fn parse_integer(full: &str, offset: usize, part: &str) -> Result<Integer, ParseRationalError> {
    let (negative, digits, digits_offset) = split_sign(part);
    if digits.is_empty() {
        return Err(ParseRationalError::at(
            full,
            offset + digits_offset,
            "expected digits",
        ));
    }
    if let Some((i, _)) = digits.char_indices().find(|(_, c)| !c.is_ascii_digit()) {
        return Err(ParseRationalError::at(
            full,
            offset + digits_offset + i,
            "expected a digit",
        ));
    }
    let value: Integer = digits
        .parse()
        .map_err(|_| ParseRationalError::at(full, offset, "expected an integer"))?;
    Ok(if negative { -value } else { value })
}

fn split_sign(part: &str) -> (bool, &str, usize) {
    match part.as_bytes().first() {
        Some(b'-') => (true, &part[1..], 1),
        Some(b'+') => (false, &part[1..], 1),
        _ => (false, part, 0),
    }
}

/// Parses `[sign] digits [. digits] [(e|E) [sign] digits]` exactly.
fn parse_decimal(full: &str, offset: usize, body: &str) -> Result<Rational, ParseRationalError> {
    let (negative, rest, sign_len) = split_sign(body);
    let mut mantissa_digits = String::new();
    let mut fraction_len: i64 = 0;
    let mut seen_point = false;
    let mut seen_digit = false;
    let mut exponent_at = None;
    for (i, c) in rest.char_indices() {
        match c {
            '0'..='9' => {
                mantissa_digits.push(c);
                seen_digit = true;
                if seen_point {
                    fraction_len += 1;
                }
            }
            '.' if !seen_point => seen_point = true,
            'e' | 'E' if seen_digit => {
                exponent_at = Some(i);
                break;
            }
            _ => {
                return Err(ParseRationalError::at(
                    full,
                    offset + sign_len + i,
                    "expected a digit, '.', an exponent or '/'",
                ))
            }
        }
    }
    if !seen_digit {
        return Err(ParseRationalError::at(
            full,
            offset + sign_len,
            "expected digits",
        ));
    }
    let mut exponent: i64 = 0;
    if let Some(at) = exponent_at {
        let exp_text = &rest[at + 1..];
        let exp_offset = offset + sign_len + at + 1;
        let value = parse_integer(full, exp_offset, exp_text)?;
        exponent = i64::try_from(&value)
            .ok()
            .filter(|e| e.abs() <= 100_000)
            .ok_or_else(|| ParseRationalError::at(full, exp_offset, "exponent out of range"))?;
    }
    let mantissa: Integer = mantissa_digits
        .parse()
        .map_err(|_| ParseRationalError::at(full, offset, "expected a number"))?;
    let scale = exponent - fraction_len;
    let ten = Integer::from(10);
    let magnitude = if scale >= 0 {
        Rational::from_integer(mantissa * num_traits::pow(ten, scale as usize))
    } else {
        Rational::new(mantissa, num_traits::pow(ten, (-scale) as usize))
    };
    Ok(if negative { -magnitude } else { magnitude })
}

/// Formats a rational as `"p"` or `"p/q"`: the stable text form used in reports.
pub fn format_rational(value: &Rational) -> String {
    DisplayRational(value).to_string()
}

/// Display adapter writing `p` for integers and `p/q` otherwise.
pub struct DisplayRational<'a>(pub &'a Rational);

impl fmt::Display for DisplayRational<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.denom().is_one() {
            write!(f, "{}", self.0.numer())
        } else {
            write!(f, "{}/{}", self.0.numer(), self.0.denom())
        }
    }
}

/// Converts a rational to the nearest-ish `f64` (for pictures and the float backend only).
///
/// Works for numerators and denominators far beyond the `f64` range by scaling both to 64
/// significant bits first.
pub fn rational_to_f64(value: &Rational) -> f64 {
    fraction_to_f64(value.numer(), value.denom())
}

/// [`rational_to_f64`] of `numerator / denominator` (`denominator ≠ 0`, the fraction need not be
/// in lowest terms), without forming the rational: the values of an exact solution over their
/// common denominator, drawn without a copy of that denominator per value.
pub fn fraction_to_f64(numerator: &BigInt, denominator: &BigInt) -> f64 {
    top_bits(numerator).over(top_bits(denominator))
}

/// A number scaled to 64 significant bits: `x >> shift` (rounded towards −∞, as `BigInt`'s
/// shift) as an `f64`, and the shift (0 for a number of at most 64 bits). [`rational_to_f64`]
/// divides two of them; a numerator computed in limbs ([`top_bits_of_limbs`]) is converted
/// without forming a `BigInt`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TopBits {
    value: f64,
    shift: i64,
}

impl TopBits {
    /// `self / denominator` as [`fraction_to_f64`] computes it (`0.0` for a zero numerator).
    pub fn over(self, denominator: TopBits) -> f64 {
        if self.value == 0.0 {
            return 0.0;
        }
        let exp = self.shift - denominator.shift;
        let exp = exp.clamp(i32::MIN as i64, i32::MAX as i64) as i32;
        (self.value / denominator.value) * 2f64.powi(exp)
    }
}

/// [`TopBits`] of `x`, read off its limbs instead of shifting a copy.
pub fn top_bits(x: &BigInt) -> TopBits {
    use num_traits::Signed;
    let magnitude = x.magnitude();
    scaled_limbs(
        x.bits(),
        |i| magnitude.iter_u64_digits().nth(i).unwrap_or(0),
        |shift| magnitude.trailing_zeros().unwrap_or(0) < shift,
        x.is_negative(),
    )
}

/// [`TopBits`] of `±Σ limbs[i] 2^(64 i)` (`-` when `negative`; limbs least significant first,
/// zero limbs on top allowed): the same as [`top_bits`] of that `BigInt`.
pub fn top_bits_of_limbs(limbs: &[u64], negative: bool) -> TopBits {
    top_bits_of_limbs_above(limbs, 0, negative)
}

/// [`top_bits_of_limbs`] of the number whose limbs are `zeros` zero limbs, then `limbs`: a number
/// known only from its top limbs, as exactly as if the zeros were written out.
pub fn top_bits_of_limbs_above(limbs: &[u64], zeros: usize, negative: bool) -> TopBits {
    let used = limbs.iter().rposition(|l| *l != 0).map_or(0, |i| i + 1);
    let limbs = &limbs[..used];
    let Some(top) = limbs.last() else {
        return TopBits {
            value: 0.0,
            shift: 0,
        };
    };
    let bits = 64 * ((zeros + limbs.len()) as u64 - 1) + u64::from(64 - top.leading_zeros());
    let limb = |i: usize| {
        i.checked_sub(zeros)
            .and_then(|i| limbs.get(i))
            .copied()
            .unwrap_or(0)
    };
    scaled_limbs(
        bits,
        limb,
        |shift| {
            let whole = (shift / 64) as usize;
            let part = shift % 64;
            (zeros..whole).any(|i| limb(i) != 0)
                || (part > 0 && limb(whole) & ((1u64 << part) - 1) != 0)
        },
        negative,
    )
}

/// [`TopBits`] of a number of `bits` bits with limbs `limb(i)`, which has ones below bit `s`
/// when `ones_below(s)`.
fn scaled_limbs(
    bits: u64,
    limb: impl Fn(usize) -> u64,
    ones_below: impl FnOnce(u64) -> bool,
    negative: bool,
) -> TopBits {
    let sign = |v: f64| if negative { -v } else { v };
    if bits <= 64 {
        return TopBits {
            value: sign(limb(0) as f64),
            shift: 0,
        };
    }
    let shift = bits - 64;
    let offset = shift % 64;
    let index = usize::try_from(shift / 64).unwrap_or(usize::MAX);
    let low = limb(index);
    let top = if offset == 0 {
        low
    } else {
        (low >> offset) | (limb(index.saturating_add(1)) << (64 - offset))
    };
    let value = if negative && ones_below(shift) {
        // Rounded towards −∞: one unit further from zero.
        -((u128::from(top) + 1) as f64)
    } else {
        sign(top as f64)
    };
    TopBits {
        value,
        shift: shift as i64,
    }
}

/// Converts a rational to the nearest `f64`, correctly rounded (ties to even), with gradual
/// underflow to subnormals and `±∞` beyond the largest finite `f64`. Unlike
/// [`rational_to_f64`] (up to three roundings), a value that is an `f64` comes back exactly
/// and any other value is off by at most half a unit in the last place: `|x̂ − x| ≤ 2^-53·|x|`
/// for results in the normal range. For values that feed exact-sensitive float evaluation
/// (displacements, coordinates written for a user). The fraction need not be in lowest terms
/// (`Rational::new_raw`), which saves the greatest common divisor when converting products.
pub fn rational_to_f64_nearest(value: &Rational) -> f64 {
    use num_traits::{Signed, ToPrimitive};
    if value.is_zero() {
        return 0.0;
    }
    let negative = value.is_negative();
    let signed = |x: f64| if negative { -x } else { x };
    let n = value.numer().abs();
    let d = value.denom().abs();
    // e with 2^e ≤ n/d < 2^(e+1).
    let mut e = n.bits() as i64 - d.bits() as i64;
    let below = if e >= 0 {
        n < (&d << (e as usize))
    } else {
        (&n << ((-e) as usize)) < d
    };
    if below {
        e -= 1;
    }
    if e > 1023 {
        return signed(f64::INFINITY);
    }
    if e < -1076 {
        // Below half the smallest subnormal 2^-1074.
        return signed(0.0);
    }
    // The quantum of the result is 2^(E − 52), E = max(e, −1022): q = round(n/d · 2^(52 − E)).
    let exponent = e.max(-1022);
    let shift = 52 - exponent;
    let (numerator, denominator) = if shift >= 0 {
        (n << (shift as usize), d)
    } else {
        (n, d << ((-shift) as usize))
    };
    let (mut q, r) = num_integer::Integer::div_rem(&numerator, &denominator);
    let twice = r << 1usize;
    if twice > denominator || (twice == denominator && q.bit(0)) {
        q += 1u32;
    }
    // q ≤ 2^53; bits = ((E + 1022) << 52) + q covers normal numbers (q ≥ 2^52, the implicit
    // bit carrying into the exponent field), subnormals (E = −1022, q < 2^52) and a rounding
    // up to the next power of two (q = 2^53).
    let Some(q) = q.to_u64() else {
        return signed(f64::INFINITY);
    };
    let bits = (((exponent + 1022) as u64) << 52) + q;
    if bits >= f64::INFINITY.to_bits() {
        return signed(f64::INFINITY);
    }
    signed(f64::from_bits(bits))
}

/// The exact rational equal to a finite `f64` (used to feed float results back into exact checks).
pub fn rational_from_f64(value: f64) -> Option<Rational> {
    Rational::from_float(value)
}

/// A rational written in a configuration file as text (`"7/3"`, `"0.1"`, read exactly) or as
/// an integer. Floating-point literals are refused with a message asking to quote them: a
/// binary float is not the number the user typed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Exact(pub Rational);

impl<'de> Deserialize<'de> for Exact {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ExactVisitor;
        impl Visitor<'_> for ExactVisitor {
            type Value = Exact;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("an exact number as a string (\"7/3\", \"0.1\") or an integer")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Exact, E> {
                parse_rational(v).map(Exact).map_err(E::custom)
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Exact, E> {
                Ok(Exact(Rational::from_integer(v.into())))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Exact, E> {
                Ok(Exact(Rational::from_integer(v.into())))
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Exact, E> {
                Err(E::custom(format!(
                    "{v} is a floating-point literal; write exact numbers as strings, e.g. \"{v}\""
                )))
            }
        }
        deserializer.deserialize_any(ExactVisitor)
    }
}

/// True when `a` and `b` hold the same numerators and denominators, entry by entry: a cheap
/// key comparison for memos (no cross-multiplication as in `Rational`'s `==`). Equal results
/// mean equal values; values built unreduced may compare different although equal, which costs
/// a memo a recomputation, never a wrong answer.
pub fn identical_rationals(a: &[Rational], b: &[Rational]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            identical_integers(x.numer(), y.numer()) && identical_integers(x.denom(), y.denom())
        })
}

/// `a == b`, digit by digit in line: the values compared by the memos are mostly one or two
/// digits long, where a call to `memcmp` per integer costs more than the comparison.
fn identical_integers(a: &Integer, b: &Integer) -> bool {
    let (x, y) = (a.iter_u64_digits(), b.iter_u64_digits());
    a.sign() == b.sign() && x.len() == y.len() && x.eq(y)
}

/// `a + b` in lowest terms, by Henrici's addition (Knuth, TAOCP vol. 2, 4.5.1): with
/// `g = gcd(b.den, a.den)`, `t = a.num·(b.den/g) + b.num·(a.den/g)`, the sum is
/// `(t/h) / ((a.den/g)·(b.den/h))` with `h = gcd(t, g)`, already reduced because both operands
/// are. The only GCDs are of the denominators and of `t` with `g`, never of the full sum:
/// adding a small step to a value with thousands of digits (a hint `p + θ·d`, a drag frame's
/// step) costs a division by a small number instead of a GCD of two huge ones, which is what
/// `Rational`'s `+` pays. Two integers are added as integers.
pub fn rational_sum(a: &Rational, b: &Rational) -> Rational {
    if a.is_integer() && b.is_integer() {
        return Rational::from_integer(a.numer() + b.numer());
    }
    if a.is_zero() {
        return b.clone();
    }
    if b.is_zero() {
        return a.clone();
    }
    let (p, q) = (a.denom(), b.denom());
    let g = denominator_gcd(p, q);
    if g.is_one() {
        // Coprime denominators: `a.num·q + b.num·p` is prime to `p·q`.
        return Rational::new_raw(a.numer() * q + b.numer() * p, p * q);
    }
    let (p_g, q_g) = (p / &g, q / &g);
    let t = a.numer() * &q_g + b.numer() * &p_g;
    if t.is_zero() {
        return Rational::zero();
    }
    let h = denominator_gcd(&g, &t);
    if h.is_one() {
        Rational::new_raw(t, p_g * q)
    } else {
        Rational::new_raw(t / &h, p_g * (q / h))
    }
}

/// `gcd(|x|, |y|)`, the smaller operand first reducing the larger by one division (the
/// binary GCD of `num-bigint` would subtract the small number from the huge one bit by bit).
fn denominator_gcd(x: &Integer, y: &Integer) -> Integer {
    let (x, y) = (x.magnitude(), y.magnitude());
    let (big, small) = if x.bits() >= y.bits() { (x, y) } else { (y, x) };
    if small.is_zero() {
        return Integer::from(big.clone());
    }
    if big.bits() > 2 * small.bits() + 64 {
        Integer::from((big % small).gcd(small))
    } else {
        Integer::from(big.gcd(small))
    }
}

/// `a − b` in lowest terms (see [`rational_sum`]).
pub fn rational_difference(a: &Rational, b: &Rational) -> Rational {
    if a.is_integer() && b.is_integer() {
        Rational::from_integer(a.numer() - b.numer())
    } else {
        rational_sum(a, &-b)
    }
}

/// `a · k` in lowest terms; an integer `a` is multiplied as an integer, and `k = ±1` is a copy
/// or a negation (see [`rational_sum`]).
pub fn rational_times_integer(a: &Rational, k: &Integer) -> Rational {
    if k.is_one() {
        a.clone()
    } else if k.sign() == num_bigint::Sign::Minus && k.magnitude().is_one() {
        -a
    } else if a.is_integer() {
        Rational::from_integer(a.numer() * k)
    } else {
        a * k
    }
}

/// `a / k` in lowest terms for a positive integer `k` (a group's weight, a count): one GCD of
/// the numerator with `k`, in machine words when both fit in a `u64` (`Rational`'s `/` reduces
/// twice, in big integers, and checks for a zero divisor).
///
/// # Panics
/// When `k` is not positive.
pub fn rational_over_integer(a: &Rational, k: &Integer) -> Rational {
    assert!(
        k.sign() == num_bigint::Sign::Plus,
        "division by a non-positive integer"
    );
    if k.is_one() {
        return a.clone();
    }
    use num_traits::ToPrimitive;
    if let (Some(n), Some(d)) = (a.numer().magnitude().to_u64(), k.to_u64()) {
        let g = n.gcd(&d);
        let numer = Integer::from_biguint(a.numer().sign(), (n / g).into());
        let denom = a.denom() * Integer::from(d / g);
        // numer / g and d / g are coprime, numer and a's denominator already were.
        return Rational::new_raw(numer, denom);
    }
    // `a.num` is prime to `a.den`: only the GCD with `k` (one division of the big numerator by
    // `k` first, see [`denominator_gcd`]) is left to cancel.
    let g = denominator_gcd(a.numer(), k);
    if g.is_one() {
        Rational::new_raw(a.numer().clone(), a.denom() * k)
    } else {
        Rational::new_raw(a.numer() / &g, a.denom() * (k / g))
    }
}

/// Rational values scaled by one positive factor to coprime integers: multiplied by the least
/// common multiple of their denominators, then divided by the greatest common divisor of the
/// products. Signs, zeros and the ratios between the values are kept, so the data of a row
/// `Σ c_j x_j = q` becomes that of an equivalent integer row (see [`crate::system`]); values
/// that are all zero come back as zeros. The values are read twice, hence the `Clone`
/// iterator.
pub fn coprime_integers<'a, I>(values: I) -> Vec<Integer>
where
    I: IntoIterator<Item = &'a Rational>,
    I::IntoIter: Clone,
{
    let values = values.into_iter();
    let lcm = values.clone().fold(Integer::one(), |acc, v| {
        if v.denom().is_one() {
            acc
        } else {
            acc.lcm(v.denom())
        }
    });
    let mut ints: Vec<Integer> = values.map(|v| v.numer() * (&lcm / v.denom())).collect();
    let gcd = ints.iter().fold(Integer::zero(), |acc, v| acc.gcd(v));
    if !gcd.is_zero() && !gcd.is_one() {
        for v in &mut ints {
            *v = &*v / &gcd;
        }
    }
    ints
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    #[test]
    fn identical_rationals_compare_numerators_and_denominators() {
        assert!(identical_rationals(
            &[q(1, 2), q(-3, 4)],
            &[q(2, 4), q(-3, 4)]
        ));
        assert!(!identical_rationals(&[q(1, 2)], &[q(1, 3)]));
        assert!(!identical_rationals(&[q(1, 2)], &[q(1, 2), q(0, 1)]));
        // Signs, lengths and high digits all count.
        assert!(!identical_rationals(&[q(1, 2)], &[q(-1, 2)]));
        let big = |e: u32, plus: i64| Rational::from_integer((BigInt::from(1) << e) + plus);
        assert!(identical_rationals(
            &[big(64, 1), big(200, -7)],
            &[big(64, 1), big(200, -7)]
        ));
        assert!(!identical_rationals(&[big(64, 1)], &[big(65, 1)]));
        assert!(!identical_rationals(&[big(64, 1)], &[q(1, 1)]));
        assert!(!identical_rationals(&[big(200, -7)], &[big(200, -9)]));
        // Unreduced, equal in value: different keys (a memo recomputes), never the reverse.
        let unreduced = Rational::new_raw(2.into(), 4.into());
        assert!(!identical_rationals(&[unreduced], &[q(1, 2)]));
    }

    #[test]
    fn parses_integers_decimals_and_fractions_exactly() {
        assert_eq!(parse_rational("3").unwrap(), q(3, 1));
        assert_eq!(parse_rational(" -2.5 ").unwrap(), q(-5, 2));
        assert_eq!(parse_rational("0.1").unwrap(), q(1, 10));
        assert_eq!(parse_rational(".25").unwrap(), q(1, 4));
        assert_eq!(parse_rational("7/3").unwrap(), q(7, 3));
        assert_eq!(parse_rational("-4/6").unwrap(), q(-2, 3));
        assert_eq!(parse_rational("1e-3").unwrap(), q(1, 1000));
        assert_eq!(parse_rational("+1.5E2").unwrap(), q(150, 1));
        assert_eq!(parse_rational("5.").unwrap(), q(5, 1));
    }

    #[test]
    fn reports_the_offending_column() {
        let e = parse_rational("12x4").unwrap_err();
        assert_eq!(e.column, 3);
        let e = parse_rational("1/0").unwrap_err();
        assert_eq!(e.column, 3);
        let e = parse_rational("  ").unwrap_err();
        assert_eq!(e.column, 1);
        let e = parse_rational("1/2.5").unwrap_err();
        assert_eq!(e.column, 4);
        let e = parse_rational("1e").unwrap_err();
        assert_eq!(e.column, 3);
        let e = parse_rational("--1").unwrap_err();
        assert_eq!(e.column, 2);
        assert!(parse_rational("1e999999").is_err());
        assert!(parse_rational(".").is_err());
    }

    #[test]
    fn formats_reports_stably() {
        assert_eq!(format_rational(&q(-95, 2)), "-95/2");
        assert_eq!(format_rational(&q(59, 1)), "59");
    }

    #[test]
    fn nearest_conversion_is_correctly_rounded() {
        // Decimal text: Rust's parser rounds correctly, so both must agree bit for bit.
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let mut texts: Vec<String> = [
            "4.531",
            "0.1",
            "0.3",
            "246.5",
            "1e-7",
            "12345.678",
            "-20",
            "9007199254740993",
            "9007199254740995",
            "1e308",
            "1.7976931348623157e308",
            "1.7976931348623159e308",
            "2e308",
            "4.9406564584124654e-324",
            "2.4703282292062328e-324",
            "2.4703282292062327e-324",
            "2.2250738585072011e-308",
            "1e-400",
            "123456789e-330",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        for _ in 0..3000 {
            let digits = next() % 10_u64.pow((next() % 17 + 1) as u32);
            let exponent = (next() % 700) as i64 - 350;
            texts.push(format!("{digits}e{exponent}"));
            texts.push(format!("-{}.{:03}", next() % 100_000, next() % 1000));
        }
        for text in &texts {
            let exact = parse_rational(text).expect("number");
            let expected: f64 = text.parse().expect("float");
            assert_eq!(
                rational_to_f64_nearest(&exact).to_bits(),
                expected.to_bits(),
                "{text}"
            );
        }
        // Every finite f64 (normal or subnormal) comes back exactly.
        for _ in 0..3000 {
            let x = f64::from_bits(next());
            if x.is_finite() {
                let exact = rational_from_f64(x).expect("finite");
                assert_eq!(
                    rational_to_f64_nearest(&exact).to_bits(),
                    x.to_bits(),
                    "{x:e}"
                );
            }
        }
        // Ties go to even; fractions far beyond 64 bits.
        let two53 = num_traits::pow(BigInt::from(2), 53);
        let tie = Rational::from_integer(&two53 + 1);
        assert_eq!(rational_to_f64_nearest(&tie), 9007199254740992.0);
        let tie = Rational::from_integer(&two53 + 3);
        assert_eq!(rational_to_f64_nearest(&tie), 9007199254740996.0);
        let third = Rational::new(
            num_traits::pow(BigInt::from(10), 400),
            num_traits::pow(BigInt::from(10), 400) * 3,
        );
        assert_eq!(rational_to_f64_nearest(&third), 1.0 / 3.0);
        assert_eq!(rational_to_f64_nearest(&q(-0, 1)).to_bits(), 0);
        let unreduced = Rational::new_raw(BigInt::from(-4531 * 6), BigInt::from(1000 * 6));
        assert_eq!(rational_to_f64_nearest(&unreduced), -4.531);
        let negative_denominator = Rational::new_raw(BigInt::from(1), BigInt::from(-10));
        assert_eq!(rational_to_f64_nearest(&negative_denominator), -0.1);
    }

    #[test]
    fn converts_huge_rationals_to_f64() {
        let big = Rational::new(
            num_traits::pow(BigInt::from(10), 400) * 3,
            num_traits::pow(BigInt::from(10), 400) * 2,
        );
        assert!((rational_to_f64(&big) - 1.5).abs() < 1e-15);
        assert_eq!(rational_to_f64(&q(-95, 2)), -47.5);
        assert_eq!(rational_from_f64(0.5), Some(q(1, 2)));
    }

    #[test]
    fn rationals_scale_to_coprime_integers_keeping_signs_and_zeros() {
        let ints = |values: &[Rational]| coprime_integers(values);
        let i = |v: &[i64]| v.iter().map(|&x| Integer::from(x)).collect::<Vec<_>>();
        assert_eq!(ints(&[q(1, 2), q(-1, 3), q(0, 1)]), i(&[3, -2, 0]));
        assert_eq!(ints(&[q(-4, 1), q(6, 1)]), i(&[-2, 3]));
        assert_eq!(ints(&[q(5, 7)]), i(&[1]));
        assert_eq!(ints(&[q(0, 1), q(0, 1)]), i(&[0, 0]));
        assert!(ints(&[]).is_empty());
    }

    /// What [`rational_to_f64`] computed before it read the top bits off the limbs: both parts
    /// shifted as `BigInt`s (rounding towards −∞).
    fn shifted_to_f64(n: &BigInt, d: &BigInt) -> f64 {
        fn scaled(x: &BigInt) -> (f64, i64) {
            let bits = x.bits() as i64;
            let shift = (bits - 64).max(0);
            let top: BigInt = x >> (shift as usize);
            (num_traits::ToPrimitive::to_f64(&top).unwrap_or(0.0), shift)
        }
        if n.is_zero() {
            return 0.0;
        }
        let (n, ns) = scaled(n);
        let (d, ds) = scaled(d);
        (n / d) * 2f64.powi((ns - ds) as i32)
    }

    /// A big integer from its limbs (least significant first) and sign.
    fn from_limbs(limbs: &[u64], negative: bool) -> BigInt {
        let magnitude = limbs
            .iter()
            .rev()
            .fold(BigInt::zero(), |acc, l| (acc << 64u32) + BigInt::from(*l));
        if negative {
            -magnitude
        } else {
            magnitude
        }
    }

    /// `2^63 + 2^11 + 2^10 − 1`: an `f64` rounds it down, and one more to the even `2^63 + 2^12`.
    const BELOW_A_TIE: u64 = (1 << 63) + (1 << 11) + (1 << 10) - 1;

    #[test]
    fn top_bits_round_negative_values_down() {
        // |x| = BELOW_A_TIE · 2^64 + 1: the ones below the shift make `x >> 64` one unit more
        // negative, which moves the rounded value.
        let x = from_limbs(&[1, BELOW_A_TIE], true);
        let expected = -((1u64 << 63) as f64 + 4096.0);
        assert_eq!(
            top_bits(&x),
            TopBits {
                value: expected,
                shift: 64
            }
        );
        assert_eq!(
            shifted_to_f64(&x, &BigInt::from(1)),
            expected * 2f64.powi(64)
        );
        assert_eq!(
            fraction_to_f64(&x, &BigInt::from(1)),
            expected * 2f64.powi(64)
        );
        // Nothing below the shift: no rounding.
        let exact = from_limbs(&[0, BELOW_A_TIE], true);
        assert_eq!(
            top_bits(&exact),
            TopBits {
                value: -((1u64 << 63) as f64 + 2048.0),
                shift: 64
            }
        );
        // |x| = 2^128 − 1: `x >> 64` is −2^64, beyond a `u64`.
        let x = from_limbs(&[u64::MAX, u64::MAX], true);
        assert_eq!(
            top_bits(&x),
            TopBits {
                value: -(2f64.powi(64)),
                shift: 64
            }
        );
    }

    proptest::proptest! {
        /// The conversion read off the limbs is bit for bit the one by shifted copies, for any
        /// lengths, signs and shifts (limbs of all ones and zeros included).
        #[test]
        fn fractions_convert_as_by_shifted_copies(
            n in proptest::collection::vec(
                proptest::prop_oneof![
                    proptest::num::u64::ANY,
                    proptest::strategy::Just(u64::MAX),
                    proptest::strategy::Just(0u64),
                    proptest::strategy::Just(BELOW_A_TIE),
                ],
                0..6,
            ),
            d in proptest::collection::vec(proptest::num::u64::ANY, 1..6),
            n_negative in proptest::bool::ANY,
            d_negative in proptest::bool::ANY,
            zeros in 0usize..3,
        ) {
            let n = from_limbs(&n, n_negative);
            let d = from_limbs(&d, d_negative);
            proptest::prop_assume!(!d.is_zero());
            let expected = shifted_to_f64(&n, &d);
            let found = fraction_to_f64(&n, &d);
            proptest::prop_assert!(found.to_bits() == expected.to_bits(), "{} against {}", found, expected);
            // The same from the numerator's limbs, with zero limbs on top.
            let mut limbs = n.magnitude().to_u64_digits();
            limbs.extend([0, 0]);
            let from_limbs = if n.is_zero() { 0.0 } else { top_bits_of_limbs(&limbs, n.sign() == num_bigint::Sign::Minus).over(top_bits(&d)) };
            proptest::prop_assert!(from_limbs.to_bits() == expected.to_bits(), "{} against {}", from_limbs, expected);
            // Known from the limbs above `zeros` zero limbs.
            let shifted = &n << (64 * zeros);
            proptest::prop_assert_eq!(
                top_bits_of_limbs_above(&limbs, zeros, n.sign() == num_bigint::Sign::Minus),
                top_bits(&shifted)
            );
        }
    }

    proptest::proptest! {
        /// The shortcuts give the values, in lowest terms, of `Rational`'s own operations.
        #[test]
        fn sum_difference_and_integer_product_are_rationals_own(
            an in -1000i64..1000, ad in 1i64..4, bn in -1000i64..1000, bd in 1i64..4,
            k in -3i64..4,
        ) {
            let (a, b, k) = (q(an, ad), q(bn, bd), Integer::from(k));
            let lowest = |x: &Rational| Rational::new(x.numer().clone(), x.denom().clone());
            let sum = rational_sum(&a, &b);
            proptest::prop_assert_eq!(&sum, &(&a + &b));
            proptest::prop_assert!(identical_rationals(std::slice::from_ref(&sum), &[lowest(&sum)]));
            let difference = rational_difference(&a, &b);
            proptest::prop_assert_eq!(&difference, &(&a - &b));
            proptest::prop_assert!(identical_rationals(std::slice::from_ref(&difference), &[lowest(&difference)]));
            let product = rational_times_integer(&a, &k);
            proptest::prop_assert_eq!(&product, &(&a * &k));
            proptest::prop_assert!(identical_rationals(std::slice::from_ref(&product), &[lowest(&product)]));
        }

        /// Henrici's addition on big values whose denominators share factors (the branches
        /// `g = 1`, `h = 1`, `h > 1`, a zero sum and a huge operand against a small one) gives
        /// `Rational`'s sum in lowest terms.
        #[test]
        fn henrici_sum_of_big_values_is_rationals_own(
            an in -10_000i64..10_000, ad in 1u32..40, bn in -10_000i64..10_000, bd in 1u32..40,
            shared in 0u32..3, a_bits in 0u32..300, b_bits in 0u32..300,
        ) {
            let lowest = |x: &Rational| Rational::new(x.numer().clone(), x.denom().clone());
            // Denominators with a common part `6^shared` and big coprime-ish cofactors.
            let common = num_traits::pow(Integer::from(6), shared as usize);
            let big = |n: i64, d: u32, bits: u32| Rational::new(
                (Integer::from(n) << bits) + Integer::from(n.signum()),
                &common * ((Integer::from(d) << bits) + Integer::from(1)),
            );
            let (a, b) = (big(an, ad, a_bits), big(bn, bd, b_bits));
            for (x, y) in [(&a, &b), (&a, &-&a), (&a, &q(bn, i64::from(bd))), (&q(an, 6), &b)] {
                let sum = rational_sum(x, y);
                proptest::prop_assert_eq!(&sum, &(x + y));
                proptest::prop_assert!(identical_rationals(std::slice::from_ref(&sum), &[lowest(&sum)]));
                let difference = rational_difference(x, y);
                proptest::prop_assert_eq!(&difference, &(x - y));
                proptest::prop_assert!(identical_rationals(std::slice::from_ref(&difference), &[lowest(&difference)]));
            }
        }

        /// Division by a positive integer is `Rational`'s, in lowest terms, in words and beyond.
        #[test]
        fn division_by_a_positive_integer_is_rationals_own(
            an in -1000i64..1000, ad in 1i64..12, k in 1i64..30, big in proptest::bool::ANY,
        ) {
            // Numerators beyond 64 bits take the big-integer path.
            let shift = if big { Integer::from(1u8) << 80 } else { Integer::from(1u8) };
            let a = Rational::new(Integer::from(an) * shift, Integer::from(ad));
            let k = Integer::from(k);
            let quotient = rational_over_integer(&a, &k);
            let lowest = Rational::new(quotient.numer().clone(), quotient.denom().clone());
            proptest::prop_assert_eq!(&quotient, &(&a / Rational::from_integer(k)));
            proptest::prop_assert!(identical_rationals(std::slice::from_ref(&quotient), &[lowest]));
        }
    }
}
