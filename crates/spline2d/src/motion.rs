//! Exact rational motions of the plane: the soft rotations and scalings of 2DSD
//! ([`crate::edit::Operation::Rotate`], [`crate::edit::Operation::Scale`]).
//!
//! Coordinates never pass through `f64`: a moved point is `c + M (p − c)` computed in exact
//! rationals, where `M` is an exact rational matrix chosen close to the requested motion.
//!
//! * **Rotation** by `φ` degrees: `φ` is reduced exactly modulo 360 into `(−180, 180]`;
//!   exactly 0 is the identity (the point is returned unchanged), exactly 180 the half turn
//!   `−I`. Otherwise a half turn is factored out when `|φ| > 90`, leaving `φ'` in `[−90, 90]`;
//!   `φ' = ±90` is the exact quarter turn. For other angles `τ = tan(φ'/2)` is rounded to the
//!   grid `1/precision` (so `|τ| ≤ 1`) and `cos = (1 − τ²)/(1 + τ²)`, `sin = 2τ/(1 + τ²)`: an
//!   exact rotation (`cos² + sin² = 1` exactly, so distances to the centre are preserved
//!   exactly). The angle of the exact rotation differs from `φ` by at most
//!   [`rotation_angle_error_bound`]`(precision) = (1 + 1/32)/precision` radians.
//! * **Scaling** by `factor^t`: `t = 0` is the identity, `t = 1` the exact factor. Otherwise
//!   `factor^t` (irrational in general) is replaced by an exact rational `f̃ = m̃·2^e` with `e`
//!   an integer and `m̃` a multiple of `1/precision` in `[1, 2]`, of relative error below
//!   [`scale_relative_error_bound`]`(precision) < 1/precision`. The logarithm is taken from the
//!   bit lengths and top bits of the factor's numerator and denominator, and the integer part
//!   of `t · log2 factor` is exact, so any positive rational factor (`1e300`, `1e-300`,
//!   `1e5000`) works.
//!
//! # Floating point
//! The only floats are `tan` of a half angle `|φ'/2| < 45°` (rotation) and `log2`/`exp2` of
//! numbers in `[1, 2]` (scaling). Each has a stated error bound ([`TAN_ERROR`],
//! [`SCALE_LOG_ERROR`]), and every motion checks that the bound is far below the rounding grid
//! before using the float; when it is not, the motion is refused with a [`MotionError`] rather
//! than returning a wrong value. [`MAX_PRECISION`] is the largest precision for which the
//! checks always pass for rotations and for scalings with `|t| ≤ 1` (the 2DSD fractions).

use api::{Integer, Rational};
use num_bigint::BigUint;
use num_traits::{One, Signed, ToPrimitive, Zero};

/// The largest accepted `precision` (denominator of the rounding grid): `10^12`.
///
/// It keeps the float errors far below the grid: `MAX_PRECISION · (TAN_ERROR + 2^-53) ≤ 1/64`
/// (rotation) and `MAX_PRECISION · 3 · SCALE_LOG_ERROR ≤ 1/8` (scaling with `|t| ≤ 1`); both
/// are checked at compile time.
pub const MAX_PRECISION: u64 = 1_000_000_000_000;

/// Bound on the absolute error of the computed `tan(φ'/2)` for `|φ'/2| < 45°`: `2^-46`.
///
/// Its parts: the rational half angle in degrees converted to `f64` (relative error `≤ 2^-52`,
/// so `≤ 45·2^-52` degrees), the conversion to radians (`≤ 3·2^-53` relative), both amplified
/// by `tan' = 1 + tan² ≤ 2`, plus the error of `f64::tan` itself (assumed a few ulp, `≤ 2^-51`
/// on `[−1, 1]`): together about `1.3·10^-15`, ten times below this bound.
pub const TAN_ERROR: f64 = 64.0 * f64::EPSILON;

/// Bound on the relative error, per unit of `|t| + 2`, of the computed `2^frac(t·log2 factor)`
/// before rounding: `2^-45`, so the float part of a scaling has relative error at most
/// `(|t| + 2)·2^-45`.
///
/// Its parts: `log2` of the numerator's and denominator's top 64 bits normalised to `[1, 2)`
/// (conversion `≤ 2^-52`, `f64::log2` assumed `≤ 2^-51`, together taken as `≤ 2^-48` each),
/// `t` and the exact fractional part of `t·(bits(num) − bits(den))` converted to `f64`
/// (relative `≤ 2^-52`), the float products and sums, and `f64::exp2` (assumed `≤ 2^-50`
/// relative on `[0, 1]`).
pub const SCALE_LOG_ERROR: f64 = 128.0 * f64::EPSILON;

/// The float error of a rotation must stay below this fraction of the grid `1/precision`.
const ROTATION_GRID_MARGIN: f64 = 1.0 / 64.0;

/// The float error of a scaling must stay below this fraction of the grid `1/precision`.
const SCALE_GRID_MARGIN: f64 = 1.0 / 8.0;

/// `2^-53`: the unit roundoff of `f64`.
const UNIT_ROUNDOFF: f64 = f64::EPSILON / 2.0;

// The documented limit keeps the float errors far below the rounding grid.
const _: () = assert!(
    (MAX_PRECISION as f64) * (TAN_ERROR + (1.0 + TAN_ERROR) * UNIT_ROUNDOFF)
        <= ROTATION_GRID_MARGIN
);
const _: () = assert!((MAX_PRECISION as f64) * 3.0 * SCALE_LOG_ERROR <= SCALE_GRID_MARGIN);
// Every precision is exactly representable in `f64`.
const _: () = assert!(MAX_PRECISION < (1 << 53));

/// Why a motion was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MotionError {
    /// The precision is outside `1..=MAX_PRECISION`.
    #[error("precision {0} must be between 1 and {max}", max = MAX_PRECISION)]
    Precision(u64),
    /// The scale factor is zero or negative.
    #[error("scale factor {0} must be positive")]
    NonPositiveFactor(String),
    /// The float error bound would not be far below the rounding grid.
    #[error(
        "{what}: the floating-point error bound {bound:e} is not below {margin} of the rounding grid 1/{precision}; use a smaller precision"
    )]
    FloatError {
        /// The quantity computed in floating point.
        what: &'static str,
        /// Its error bound, absolute for the rotation's tan and relative for a scaling.
        bound: f64,
        /// The fraction of the grid it must stay below.
        margin: f64,
        /// The requested precision.
        precision: u64,
    },
    /// A value is outside the range the motion handles (an exponent or fraction too large).
    #[error("{0} is out of range")]
    OutOfRange(&'static str),
}

/// Checks `1 ≤ precision ≤ MAX_PRECISION`.
pub fn check_precision(precision: u64) -> Result<(), MotionError> {
    if (1..=MAX_PRECISION).contains(&precision) {
        Ok(())
    } else {
        Err(MotionError::Precision(precision))
    }
}

/// Bound, in radians, on the difference between the angle of [`Rotation::new`]`(degrees,
/// precision)` and `degrees`: `(1 + 1/32)/precision`.
///
/// `τ` is within `(1/2 + 1/64)/precision` of `tan(φ'/2)` (half a grid step plus the checked
/// float error), and `2·atan` has derivative at most 2.
pub fn rotation_angle_error_bound(precision: u64) -> f64 {
    (1.0 + 2.0 * ROTATION_GRID_MARGIN) / precision as f64
}

/// Bound on the relative error `|f̃ / factor^t − 1|` of [`scale_power`]:
/// `(1/2)(1 + 10^-12)/precision + (1/8)/precision < 0.63/precision`.
///
/// Half a grid step on a mantissa in `[1, 2]` plus the checked float error.
pub fn scale_relative_error_bound(precision: u64) -> f64 {
    (0.5 * (1.0 + 1e-12) + SCALE_GRID_MARGIN) / precision as f64
}

/// `degrees` reduced exactly modulo 360 into `(−180, 180]`.
pub fn reduce_degrees(degrees: &Rational) -> Rational {
    let full = Rational::from_integer(360.into());
    let half = Rational::from_integer(180.into());
    let turns = (degrees / &full).floor();
    let reduced = degrees - &full * turns; // in [0, 360)
    if reduced > half {
        reduced - full
    } else {
        reduced
    }
}

/// An exact rotation of the plane: `cos² + sin² = 1` exactly.
#[derive(Debug, Clone, PartialEq)]
pub struct Rotation {
    cos: Rational,
    sin: Rational,
}

impl Rotation {
    /// The identity.
    pub fn identity() -> Rotation {
        Rotation {
            cos: Rational::one(),
            sin: Rational::zero(),
        }
    }

    /// An exact rotation by about `degrees` counter-clockwise (construction in the module
    /// documentation): exactly the requested one for multiples of 90 degrees, otherwise within
    /// [`rotation_angle_error_bound`]`(precision)` radians of it. Refused only for a precision
    /// outside `1..=MAX_PRECISION`.
    pub fn new(degrees: &Rational, precision: u64) -> Result<Rotation, MotionError> {
        check_precision(precision)?;
        let reduced = reduce_degrees(degrees);
        if reduced.is_zero() {
            return Ok(Rotation::identity());
        }
        let half = Rational::from_integer(180.into());
        if reduced == half {
            return Ok(Rotation {
                cos: -Rational::one(),
                sin: Rational::zero(),
            });
        }
        let quarter = Rational::from_integer(90.into());
        let (half_turn, rest) = if reduced > quarter {
            (true, reduced - half)
        } else if reduced < -&quarter {
            (true, reduced + half)
        } else {
            (false, reduced)
        };
        // rest ∈ [−90, 90] and nonzero.
        let tau = if rest == quarter {
            Rational::one()
        } else if rest == -&quarter {
            -Rational::one()
        } else {
            tan_half_on_grid(&rest, precision)?
        };
        let tau2 = &tau * &tau;
        let denom = Rational::one() + &tau2;
        let mut cos = (Rational::one() - tau2) / &denom;
        let mut sin = (Rational::from_integer(2.into()) * tau) / denom;
        if half_turn {
            cos = -cos;
            sin = -sin;
        }
        Ok(Rotation { cos, sin })
    }

    /// The exact cosine.
    pub fn cos(&self) -> &Rational {
        &self.cos
    }

    /// The exact sine.
    pub fn sin(&self) -> &Rational {
        &self.sin
    }

    /// Whether this is the identity.
    pub fn is_identity(&self) -> bool {
        self.cos.is_one() && self.sin.is_zero()
    }

    /// `center + R (p − center)`, exactly; the identity returns `p` unchanged.
    pub fn apply(&self, center: &[Rational; 2], p: &[Rational; 2]) -> [Rational; 2] {
        if self.is_identity() {
            return p.clone();
        }
        let dx = &p[0] - &center[0];
        let dy = &p[1] - &center[1];
        [
            &center[0] + &self.cos * &dx - &self.sin * &dy,
            &center[1] + &self.sin * &dx + &self.cos * &dy,
        ]
    }
}

/// `p` rotated about `center` by `degrees · t` (see [`Rotation::new`]); `t = 0` and multiples
/// of 360 degrees return `p` unchanged.
pub fn rotate_point(
    center: &[Rational; 2],
    p: &[Rational; 2],
    degrees: &Rational,
    t: &Rational,
    precision: u64,
) -> Result<[Rational; 2], MotionError> {
    Ok(Rotation::new(&(degrees * t), precision)?.apply(center, p))
}

/// `tan(rest/2)` (`rest` in degrees, `|rest| < 90`) rounded to the grid `1/precision`, clamped
/// to `[−1, 1]`; within `(1/2 + 1/64)/precision` of the true value.
fn tan_half_on_grid(rest: &Rational, precision: u64) -> Result<Rational, MotionError> {
    let p = precision as f64; // exact: precision < 2^53
                              // Error of tan plus the rounding of the product by `p`, in grid units.
    let bound = p * TAN_ERROR + p * (1.0 + TAN_ERROR) * UNIT_ROUNDOFF;
    if bound.is_nan() || bound > ROTATION_GRID_MARGIN {
        return Err(MotionError::FloatError {
            what: "tan of the half angle",
            bound: bound / p,
            margin: ROTATION_GRID_MARGIN,
            precision,
        });
    }
    let half_angle = rest / Rational::from_integer(2.into());
    let degrees = to_f64_bounded(&half_angle).ok_or(MotionError::OutOfRange("the half angle"))?;
    let tan = (degrees * (std::f64::consts::PI / 180.0)).tan();
    let n = (tan * p)
        .round()
        .to_i64()
        .ok_or(MotionError::OutOfRange("tan of the half angle"))?;
    let limit = i64::try_from(precision).map_err(|_| MotionError::Precision(precision))?;
    Ok(Rational::new(
        n.clamp(-limit, limit).into(),
        Integer::from(precision),
    ))
}

/// `factor^t` as an exact rational `f̃ = m̃·2^e` (`m̃` a multiple of `1/precision` in `[1, 2]`,
/// `e` an integer) with `|f̃/factor^t − 1| ≤ `[`scale_relative_error_bound`]`(precision)`;
/// exactly 1 for `t = 0` and exactly `factor` for `t = 1`.
///
/// Refused when `factor ≤ 0`, when the precision is outside `1..=MAX_PRECISION`, and when the
/// float error bound `(|t| + 2)·SCALE_LOG_ERROR` exceeds `1/(8·precision)` (never for
/// `|t| ≤ 1`).
pub fn scale_power(
    factor: &Rational,
    t: &Rational,
    precision: u64,
) -> Result<Rational, MotionError> {
    check_precision(precision)?;
    if !factor.is_positive() {
        return Err(MotionError::NonPositiveFactor(api::format_rational(factor)));
    }
    if t.is_zero() {
        return Ok(Rational::one());
    }
    if t.is_one() {
        return Ok(factor.clone());
    }
    let p = precision as f64; // exact: precision < 2^53
    let t_f = to_f64_bounded(t).ok_or(MotionError::OutOfRange("the scale fraction"))?;
    let bound = (t_f.abs() + 2.0) * SCALE_LOG_ERROR;
    if bound.is_nan() || bound * p > SCALE_GRID_MARGIN {
        return Err(MotionError::FloatError {
            what: "the scale factor power",
            bound,
            margin: SCALE_GRID_MARGIN,
            precision,
        });
    }
    // log2 factor = (e_n + l_n) − (e_d + l_d), e exact integers, l ∈ [0, 1] floats.
    let (e_n, l_n) = log2_parts(factor.numer().magnitude())?;
    let (e_d, l_d) = log2_parts(factor.denom().magnitude())?;
    // t·log2 factor = floor(k) + frac(k) + t·(l_n − l_d), the first part exact.
    let k = t * Rational::from_integer(Integer::from(e_n) - Integer::from(e_d));
    let k_floor = k.floor();
    let k_frac = to_f64_bounded(&(&k - &k_floor)).ok_or(MotionError::OutOfRange("frac"))?;
    let g = k_frac + t_f * (l_n - l_d);
    let g_int = g.floor();
    let g_frac = g - g_int; // in [0, 1]
    let n = (g_frac.exp2() * p)
        .round()
        .to_i64()
        .ok_or(MotionError::OutOfRange("the scale mantissa"))?;
    let g_int = g_int
        .to_i64()
        .ok_or(MotionError::OutOfRange("the scale exponent"))?;
    let e = k_floor.to_integer() + Integer::from(g_int);
    let mantissa = Rational::new(n.into(), Integer::from(precision));
    Ok(mantissa * pow2_rational(&e)?)
}

/// `p` scaled about `center` by `factor^t` ([`scale_power`]); `t = 0` returns `p` unchanged.
pub fn scale_point(
    center: &[Rational; 2],
    p: &[Rational; 2],
    factor: &Rational,
    t: &Rational,
    precision: u64,
) -> Result<[Rational; 2], MotionError> {
    let f = scale_power(factor, t, precision)?;
    if t.is_zero() {
        return Ok(p.clone());
    }
    Ok([
        &center[0] + &f * (&p[0] - &center[0]),
        &center[1] + &f * (&p[1] - &center[1]),
    ])
}

/// `2^e` exactly.
fn pow2_rational(e: &Integer) -> Result<Rational, MotionError> {
    let shift = e
        .magnitude()
        .to_usize()
        .ok_or(MotionError::OutOfRange("the scale exponent"))?;
    let power = Integer::one() << shift;
    Ok(if e.is_negative() {
        Rational::new(Integer::one(), power)
    } else {
        Rational::from_integer(power)
    })
}

/// `log2 x = e + l` for `x > 0`: `e = bits(x) − 1` exactly and `l ∈ [0, 1]` in `f64` with
/// absolute error `≤ 2^-50` (taken as `≤ 2^-48` in [`SCALE_LOG_ERROR`]): the top 64 bits
/// (truncation `< 2^-63` relative), rounded to `f64` (`≤ 2^-53`) and scaled exactly into
/// `[1, 2]`, then `f64::log2`.
fn log2_parts(x: &BigUint) -> Result<(u64, f64), MotionError> {
    let bits = x.bits();
    if bits == 0 {
        return Err(MotionError::OutOfRange("log2 of zero"));
    }
    let shift = bits.saturating_sub(64);
    let top = (x >> shift)
        .to_u64()
        .ok_or(MotionError::OutOfRange("the top bits"))?;
    let top_bits = i64::try_from(bits - shift).map_err(|_| MotionError::OutOfRange("bits"))?;
    // Rounds to nearest; the product by a power of two is exact.
    let mantissa = top as f64 * pow2(1 - top_bits);
    Ok((bits - 1, mantissa.log2()))
}

/// `x` in `f64` with `|result − x| ≤ 2^-52·|x| + 2^-999`; `None` when `|x| ≥ 2^1000`.
///
/// Never converts the numerator or denominator alone (they may be far beyond the `f64`
/// range): the quotient's top 64 bits are computed exactly in integers (truncation `< 2^-63`
/// relative), rounded to `f64` (`≤ 2^-53`) and scaled by exact powers of two.
fn to_f64_bounded(x: &Rational) -> Option<f64> {
    if x.is_zero() {
        return Some(0.0);
    }
    let n = x.numer().magnitude();
    let d = x.denom().magnitude();
    // |x| ∈ (2^(e0 − 1), 2^(e0 + 1)).
    let e0 = i64::try_from(n.bits()).ok()? - i64::try_from(d.bits()).ok()?;
    if e0 > 1000 {
        return None;
    }
    if e0 < -1000 {
        return Some(0.0);
    }
    // |x|·2^k ∈ (2^63, 2^65), k ∈ [−936, 1064].
    let k = 64 - e0;
    let q = if k >= 0 {
        (n << u64::try_from(k).ok()?) / d
    } else {
        n / (d << u64::try_from(-k).ok()?)
    };
    let q = q.to_u128()?;
    let h = k / 2;
    // Both factors are normal (|h|, |k − h| ≤ 532) and so is the result (> 2^-1001).
    let v = q as f64 * pow2(-h) * pow2(h - k);
    Some(if x.is_negative() { -v } else { v })
}

/// `2^j` exactly, for `|j| ≤ 1022` (callers stay within `±532`).
fn pow2(j: i64) -> f64 {
    debug_assert!((-1022..=1023).contains(&j));
    // The biased exponent j + 1023 is in 1..=2046: a normal power of two.
    f64::from_bits(((j + 1023) as u64) << 52)
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::parse_rational;
    use proptest::prelude::*;

    fn q(text: &str) -> Rational {
        parse_rational(text).expect("rational")
    }

    fn pt(x: &str, y: &str) -> [Rational; 2] {
        [q(x), q(y)]
    }

    fn f(x: &Rational) -> f64 {
        to_f64_bounded(x).expect("in range")
    }

    #[test]
    fn conversion_to_f64_is_accurate_far_beyond_the_f64_range() {
        assert_eq!(f(&q("3/4")), 0.75);
        assert_eq!(f(&q("-1e300")), -1e300);
        assert_eq!(f(&q("1e-300")), 1e-300);
        let huge = q("1e5000") / q("3e4999");
        assert!((f(&huge) - 10.0 / 3.0).abs() < 1e-15);
        assert_eq!(to_f64_bounded(&q("1e400")), None);
        assert_eq!(f(&q("1e-400")), 0.0);
        let (e, l) = log2_parts(q("1e300").numer().magnitude()).expect("log2");
        assert!((e as f64 + l - 300.0 * 10f64.log2()).abs() < 1e-12);
        let (e, l) = log2_parts(q("1e5000").numer().magnitude()).expect("log2");
        assert!((e as f64 + l - 5000.0 * 10f64.log2()).abs() < 1e-10);
        assert_eq!(log2_parts(&BigUint::one()).expect("log2"), (0, 0.0));
    }

    #[test]
    fn a_huge_multiple_of_a_full_turn_leaves_the_point_in_place() {
        let p = pt("7/3", "-5");
        let c = pt("1", "2");
        let degrees = q("3.6e401");
        for t in ["1", "1/2", "1/4"] {
            let moved = rotate_point(&c, &p, &degrees, &q(t), 1_000_000).expect("rotate");
            assert_eq!(moved, p, "t = {t}");
        }
        // Zero angle: identity, exactly.
        let moved = rotate_point(&c, &p, &q("30"), &Rational::zero(), 1000).expect("rotate");
        assert_eq!(moved, p);
    }

    #[test]
    fn quarter_and_half_turns_are_exact() {
        let c = pt("1/2", "-3");
        let p = pt("7/3", "5/7");
        let (dx, dy) = (&p[0] - &c[0], &p[1] - &c[1]);
        let quarter = [&c[0] - &dy, &c[1] + &dx];
        let half = [&c[0] - &dx, &c[1] - &dy];
        let three_quarters = [&c[0] + &dy, &c[1] - &dx];
        let big = q("360e50");
        for (degrees, expected) in [
            (q("90"), &quarter),
            (q("180"), &half),
            (q("270"), &three_quarters),
            (q("-90"), &three_quarters),
            (q("-180"), &half),
            (q("-270"), &quarter),
            (&big + q("90"), &quarter),
            (-&big - q("90"), &three_quarters),
            (&big * q("7") + q("180"), &half),
        ] {
            for precision in [1, 1000, MAX_PRECISION] {
                let moved =
                    rotate_point(&c, &p, &degrees, &Rational::one(), precision).expect("rotate");
                assert_eq!(&moved, expected, "{degrees} degrees, precision {precision}");
            }
        }
        // A half of 180 at t = 1/2 is a quarter turn too.
        let moved = rotate_point(&c, &p, &q("180"), &q("1/2"), 10).expect("rotate");
        assert_eq!(moved, quarter);
    }

    #[test]
    fn reduction_lands_in_the_half_open_interval() {
        for (input, expected) in [
            ("0", "0"),
            ("180", "180"),
            ("-180", "180"),
            ("540", "180"),
            ("181", "-179"),
            ("-181", "179"),
            ("720.5", "1/2"),
            ("-1/3", "-1/3"),
        ] {
            assert_eq!(reduce_degrees(&q(input)), q(expected), "{input}");
        }
    }

    #[test]
    fn thirty_degrees_on_huge_coordinates_matches_floating_point() {
        let c = pt("12345/7", "-1e20");
        let p = pt("1.234567e33", "-7.654321e32");
        for (precision, tolerance) in [(MAX_PRECISION, 1e-9), (1_000_000, 2e-6)] {
            let moved = rotate_point(&c, &p, &q("30"), &Rational::one(), precision).expect("rot");
            let (s, co) = 30f64.to_radians().sin_cos();
            let (cx, cy) = (f(&c[0]), f(&c[1]));
            let (dx, dy) = (f(&p[0]) - cx, f(&p[1]) - cy);
            let expected = [cx + co * dx - s * dy, cy + s * dx + co * dy];
            let norm = expected[0].hypot(expected[1]);
            let err = (f(&moved[0]) - expected[0]).hypot(f(&moved[1]) - expected[1]);
            assert!(
                err <= tolerance * norm,
                "precision {precision}: {err} vs {norm}"
            );
            // The distance to the centre is preserved exactly.
            let d2 = |a: &[Rational; 2]| {
                let (x, y) = (&a[0] - &c[0], &a[1] - &c[1]);
                &x * &x + &y * &y
            };
            assert_eq!(d2(&moved), d2(&p));
        }
    }

    #[test]
    fn scaling_by_1e300_is_exact_at_the_anchor_and_relative_elsewhere() {
        let c = pt("3", "-1/7");
        let p = pt("5/2", "11");
        for factor in [q("1e300"), q("1e-300"), q("1e5000"), q("3/2"), q("7e-4000")] {
            let full = scale_point(&c, &p, &factor, &Rational::one(), 1000).expect("scale");
            assert_eq!(
                full,
                [
                    &c[0] + &factor * (&p[0] - &c[0]),
                    &c[1] + &factor * (&p[1] - &c[1])
                ]
            );
            let none = scale_point(&c, &p, &factor, &Rational::zero(), 1000).expect("scale");
            assert_eq!(none, p);
            for precision in [1, 10, 1_000_000, MAX_PRECISION] {
                let root = scale_power(&factor, &q("1/2"), precision).expect("root");
                let ratio = &root * &root / &factor;
                let slack = Rational::new(3.into(), precision.into());
                assert!(
                    ratio > Rational::one() - &slack && ratio < Rational::one() + &slack,
                    "factor {factor}, precision {precision}: ratio {}",
                    f(&ratio)
                );
                let half = scale_point(&c, &p, &factor, &q("1/2"), precision).expect("scale");
                assert_eq!(half[0], &c[0] + &root * (&p[0] - &c[0]));
            }
        }
        assert_eq!(
            scale_power(&q("1"), &q("1/3"), 1000).expect("one"),
            Rational::one()
        );
        assert_eq!(
            scale_power(&q("4"), &q("1/2"), 1000).expect("two"),
            q("2"),
            "exact powers of two stay exact"
        );
    }

    #[test]
    fn refusals_name_the_limit() {
        let c = pt("0", "0");
        let p = pt("1", "1");
        for precision in [0, MAX_PRECISION + 1] {
            let err =
                rotate_point(&c, &p, &q("30"), &Rational::one(), precision).expect_err("refused");
            assert_eq!(
                err.to_string(),
                format!("precision {precision} must be between 1 and 1000000000000")
            );
            assert!(scale_power(&q("2"), &q("1/2"), precision).is_err());
        }
        let err = scale_power(&q("-2"), &q("1/2"), 10).expect_err("negative");
        assert_eq!(err.to_string(), "scale factor -2 must be positive");
        assert!(scale_power(&Rational::zero(), &q("1/2"), 10).is_err());
        // A fraction far outside [0, 1] at the largest precision: the float error bound is too
        // large, and the motion says so instead of returning a wrong value.
        let err = scale_power(&q("2"), &q("1001/2"), MAX_PRECISION).expect_err("too large");
        assert!(matches!(err, MotionError::FloatError { .. }), "{err}");
        assert!(scale_power(&q("2"), &q("1001/2"), 1000).is_ok());
    }

    fn rational(max: i64) -> impl Strategy<Value = Rational> {
        (-max..=max, 1i64..=1000).prop_map(|(n, d)| Rational::new(n.into(), d.into()))
    }

    fn precision() -> impl Strategy<Value = u64> {
        prop_oneof![
            Just(1u64),
            Just(10),
            Just(1000),
            Just(1_000_000),
            Just(MAX_PRECISION),
            1u64..=MAX_PRECISION,
        ]
    }

    /// `a − b` wrapped into `(−π, π]`.
    fn angle_difference(a: f64, b: f64) -> f64 {
        let tau = std::f64::consts::TAU;
        let d = (a - b).rem_euclid(tau);
        if d > std::f64::consts::PI {
            d - tau
        } else {
            d
        }
    }

    proptest! {
        #[test]
        fn rotations_preserve_distances_exactly_and_the_angle_closely(
            c in [rational(10_000), rational(10_000)],
            p in [rational(10_000), rational(10_000)],
            degrees in rational(1_000_000),
            t_num in 0i64..=12,
            precision in precision(),
        ) {
            let t = Rational::new(t_num.into(), 12.into());
            let moved = rotate_point(&c, &p, &degrees, &t, precision).expect("rotate");
            let d2 = |a: &[Rational; 2]| {
                let (x, y) = (&a[0] - &c[0], &a[1] - &c[1]);
                &x * &x + &y * &y
            };
            prop_assert_eq!(d2(&moved), d2(&p));
            let rotation = Rotation::new(&(&degrees * &t), precision).expect("rotation");
            prop_assert_eq!(
                rotation.cos() * rotation.cos() + rotation.sin() * rotation.sin(),
                Rational::one()
            );
            let requested = f(&reduce_degrees(&(&degrees * &t))).to_radians();
            let actual = f(rotation.sin()).atan2(f(rotation.cos()));
            let bound = rotation_angle_error_bound(precision) + 1e-14;
            prop_assert!(angle_difference(actual, requested).abs() <= bound);
            // The same through the moved point, when it is not the centre.
            if d2(&p) > Rational::new(1.into(), 100.into()) {
                let before = f(&(&p[1] - &c[1])).atan2(f(&(&p[0] - &c[0])));
                let after = f(&(&moved[1] - &c[1])).atan2(f(&(&moved[0] - &c[0])));
                prop_assert!(
                    angle_difference(after - before, requested).abs() <= bound + 1e-9
                );
            }
        }

        #[test]
        fn scale_powers_have_small_relative_error(
            mantissa in 1i64..=1_000_000,
            exponent in -400i32..=400,
            t_num in 1i64..=4,
            t_den in 1i64..=5,
            precision in precision(),
        ) {
            let factor = Rational::new(mantissa.into(), 1000.into())
                * Rational::from_integer(10.into()).pow(exponent);
            let t = Rational::new(t_num.into(), t_den.into());
            let power = match scale_power(&factor, &t, precision) {
                Ok(power) => power,
                Err(err) => {
                    // Only fractions beyond the 2DSD range [0, 1] may be refused, and only
                    // when their float error bound is too large for the grid.
                    let t_f = f(&t);
                    prop_assert!(t_f > 1.0, "{}", err);
                    prop_assert!(matches!(err, MotionError::FloatError { .. }), "{}", err);
                    prop_assert!((t_f + 2.0) * SCALE_LOG_ERROR * precision as f64 > 1.0 / 8.0);
                    return Ok(());
                }
            };
            // power^den / factor^num ∈ ((1 − ε)^den, (1 + ε)^den) with ε = 1/precision.
            let t_num = t.numer().to_usize().expect("small");
            let t_den = t.denom().to_usize().expect("small");
            let ratio = num_traits::pow(power.clone(), t_den) / num_traits::pow(factor.clone(), t_num);
            let eps = Rational::new(1.into(), precision.into());
            let low = num_traits::pow(Rational::one() - &eps, t_den);
            let high = num_traits::pow(Rational::one() + &eps, t_den);
            prop_assert!(ratio > low && ratio < high, "ratio {}", f(&ratio));
            // The stated (tighter) bound, checked in floating point on the logarithm.
            let err = (f(&ratio).ln() / t_den as f64).abs();
            prop_assert!(err <= scale_relative_error_bound(precision) * 1.01 + 1e-15);
        }
    }
}
