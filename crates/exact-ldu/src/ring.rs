//! Integer arithmetic for the factoring: the [`Ring`] trait and the machine-integer fast path.
//!
//! [`Int`] keeps a value in an `i64` while it fits and moves it to a [`BigInt`] only when a
//! result overflows (products and differences are formed in `i128` first, so `a·b − c·d` of
//! machine integers never overflows on the way). Values are kept normalised: a big value that
//! fits an `i64` again (after a division or a GCD) moves back. The algorithms are generic over
//! [`Ring`], so the same code runs on plain [`BigInt`] (the fast path forced off) and must give
//! identical results.

use num_bigint::{BigInt, BigUint, Sign};
use num_traits::{One, Signed, ToPrimitive, Zero};
use std::cmp::Ordering;
use std::fmt;

/// The integer operations the fraction-free algorithms need.
pub trait Ring: Clone + fmt::Debug + PartialEq + Eq + Send + Sync + 'static {
    /// 0.
    fn zero() -> Self;
    /// 1.
    fn one() -> Self;
    /// From a machine integer.
    fn from_i64(v: i64) -> Self;
    /// From an arbitrary-precision integer.
    fn from_bigint(v: &BigInt) -> Self;
    /// To an arbitrary-precision integer.
    fn to_bigint(&self) -> BigInt;
    /// The value as an `i64`, when it fits.
    fn to_i64(&self) -> Option<i64>;
    /// `self == 0`.
    fn is_zero(&self) -> bool;
    /// `self == 1`.
    fn is_one(&self) -> bool;
    /// `self < 0`.
    fn is_negative(&self) -> bool;
    /// `self + other`.
    fn add(&self, other: &Self) -> Self;
    /// `self − other`.
    fn sub(&self, other: &Self) -> Self;
    /// `self · other`.
    fn mul(&self, other: &Self) -> Self;
    /// `−self`.
    fn neg(&self) -> Self;
    /// `|self|`.
    fn abs(&self) -> Self {
        if self.is_negative() {
            self.neg()
        } else {
            self.clone()
        }
    }
    /// `a·b − c·d`, the cross-multiplication of the fraction-free elimination.
    fn mul_sub(a: &Self, b: &Self, c: &Self, d: &Self) -> Self {
        a.mul(b).sub(&c.mul(d))
    }
    /// `self += a · b` (in place where the representation allows).
    fn add_mul(&mut self, a: &Self, b: &Self) {
        *self = self.add(&a.mul(b));
    }
    /// `self / other` where the division is known to be exact.
    fn div_exact(&self, other: &Self) -> Self;
    /// Greatest common divisor, non-negative (`gcd(0, 0) = 0`).
    fn gcd(&self, other: &Self) -> Self;
    /// Compares absolute values.
    fn abs_cmp(&self, other: &Self) -> Ordering;
    /// Compares values.
    fn cmp_value(&self, other: &Self) -> Ordering;
    /// Number of bits of `|self|` (0 for 0).
    fn bits(&self) -> u64;
}

impl Ring for BigInt {
    fn zero() -> Self {
        Zero::zero()
    }
    fn one() -> Self {
        One::one()
    }
    fn from_i64(v: i64) -> Self {
        BigInt::from(v)
    }
    fn from_bigint(v: &BigInt) -> Self {
        v.clone()
    }
    fn to_bigint(&self) -> BigInt {
        self.clone()
    }
    fn to_i64(&self) -> Option<i64> {
        ToPrimitive::to_i64(self)
    }
    fn is_zero(&self) -> bool {
        Zero::is_zero(self)
    }
    fn is_one(&self) -> bool {
        One::is_one(self)
    }
    fn is_negative(&self) -> bool {
        self.sign() == Sign::Minus
    }
    fn add(&self, other: &Self) -> Self {
        self + other
    }
    fn sub(&self, other: &Self) -> Self {
        self - other
    }
    fn mul(&self, other: &Self) -> Self {
        self * other
    }
    fn neg(&self) -> Self {
        -self
    }
    fn add_mul(&mut self, a: &Self, b: &Self) {
        *self += a * b;
    }
    fn div_exact(&self, other: &Self) -> Self {
        debug_assert!(Zero::is_zero(&(self % other)), "inexact division");
        self / other
    }
    fn gcd(&self, other: &Self) -> Self {
        crate::gcd::gcd_bigint(self, other)
    }
    fn abs_cmp(&self, other: &Self) -> Ordering {
        self.magnitude().cmp(other.magnitude())
    }
    fn cmp_value(&self, other: &Self) -> Ordering {
        self.cmp(other)
    }
    fn bits(&self) -> u64 {
        BigInt::bits(self)
    }
}

/// An integer that stays in an `i64` while it fits and becomes a [`BigInt`] only on overflow.
///
/// Invariant: the `Big` variant never holds a value that fits an `i64`, so equal values have
/// equal representations.
#[derive(Clone, PartialEq, Eq, Hash)]
pub enum Int {
    /// A value that fits an `i64`.
    Small(i64),
    /// A value outside the `i64` range.
    Big(Box<BigInt>),
}

impl fmt::Debug for Int {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Int::Small(v) => write!(f, "{v}"),
            Int::Big(v) => write!(f, "{v}"),
        }
    }
}

impl fmt::Display for Int {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self, f)
    }
}

impl Int {
    #[inline]
    fn from_i128(v: i128) -> Int {
        match i64::try_from(v) {
            Ok(s) => Int::Small(s),
            Err(_) => Int::boxed_i128(v),
        }
    }

    /// The rare overflow of [`Int::from_i128`], kept out of line so that the machine-word path
    /// of every operation inlines into the elimination loops.
    #[cold]
    #[inline(never)]
    fn boxed_i128(v: i128) -> Int {
        Int::Big(Box::new(BigInt::from(v)))
    }

    fn from_big(v: BigInt) -> Int {
        match ToPrimitive::to_i64(&v) {
            Some(s) => Int::Small(s),
            None => Int::Big(Box::new(v)),
        }
    }

    fn big(&self) -> BigInt {
        match self {
            Int::Small(v) => BigInt::from(*v),
            Int::Big(b) => (**b).clone(),
        }
    }

    /// True when the value is held in a machine integer.
    pub fn is_small(&self) -> bool {
        matches!(self, Int::Small(_))
    }
}

/// `v` as a big integer, through `i64` when it fits: num-bigint (0.4.8) builds an `i128` digit
/// by digit in a loop of 128-bit shifts (a call per value), an `i64` in one step (one digit is
/// kept inline, no allocation) — a tenth of a small exact drag frame, which converts every
/// value.
pub(crate) fn bigint_from_i128(v: i128) -> BigInt {
    match i64::try_from(v) {
        Ok(w) => BigInt::from(w),
        Err(_) => BigInt::from(v),
    }
}

/// `a · b` as a plain big integer (no intermediate boxing).
fn product(a: &Int, b: &Int) -> BigInt {
    match (a, b) {
        (Int::Small(x), Int::Small(y)) => bigint_from_i128(*x as i128 * *y as i128),
        (Int::Small(x), Int::Big(y)) | (Int::Big(y), Int::Small(x)) => &**y * *x,
        (Int::Big(x), Int::Big(y)) => &**x * &**y,
    }
}

/// Binary (Stein) GCD of two machine words.
pub(crate) fn binary_gcd(mut a: u64, mut b: u64) -> u64 {
    if a == 0 {
        return b;
    }
    if b == 0 {
        return a;
    }
    let shift = (a | b).trailing_zeros();
    a >>= a.trailing_zeros();
    loop {
        b >>= b.trailing_zeros();
        if a > b {
            std::mem::swap(&mut a, &mut b);
        }
        b -= a;
        if b == 0 {
            return a << shift;
        }
    }
}

impl Ring for Int {
    fn zero() -> Self {
        Int::Small(0)
    }
    fn one() -> Self {
        Int::Small(1)
    }
    fn from_i64(v: i64) -> Self {
        Int::Small(v)
    }
    fn from_bigint(v: &BigInt) -> Self {
        Int::from_big(v.clone())
    }
    fn to_bigint(&self) -> BigInt {
        self.big()
    }
    fn to_i64(&self) -> Option<i64> {
        match self {
            Int::Small(v) => Some(*v),
            Int::Big(_) => None,
        }
    }
    fn is_zero(&self) -> bool {
        matches!(self, Int::Small(0))
    }
    fn is_one(&self) -> bool {
        matches!(self, Int::Small(1))
    }
    fn is_negative(&self) -> bool {
        match self {
            Int::Small(v) => *v < 0,
            Int::Big(b) => b.sign() == Sign::Minus,
        }
    }
    #[inline]
    fn add(&self, other: &Self) -> Self {
        if let (Int::Small(a), Int::Small(b)) = (self, other) {
            return Int::from_i128(*a as i128 + *b as i128);
        }
        big_sum(self, other)
    }
    #[inline]
    fn sub(&self, other: &Self) -> Self {
        if let (Int::Small(a), Int::Small(b)) = (self, other) {
            return Int::from_i128(*a as i128 - *b as i128);
        }
        big_difference(self, other)
    }
    #[inline]
    fn mul(&self, other: &Self) -> Self {
        if let (Int::Small(a), Int::Small(b)) = (self, other) {
            return Int::from_i128(*a as i128 * *b as i128);
        }
        big_product(self, other)
    }
    #[inline]
    fn neg(&self) -> Self {
        match self {
            Int::Small(v) => Int::from_i128(-(*v as i128)),
            Int::Big(b) => Int::from_big(-&**b),
        }
    }
    fn add_mul(&mut self, a: &Self, b: &Self) {
        match (&mut *self, a, b) {
            (_, Int::Small(0), _) | (_, _, Int::Small(0)) => {}
            (Int::Small(s), Int::Small(x), Int::Small(y)) => {
                // |x·y| ≤ 2^126 and |s| < 2^63: the sum fits an i128.
                *self = Int::from_i128(*s as i128 + *x as i128 * *y as i128);
            }
            (Int::Big(acc), Int::Big(x), Int::Small(y))
            | (Int::Big(acc), Int::Small(y), Int::Big(x)) => {
                **acc += &**x * *y;
                if let Some(v) = ToPrimitive::to_i64(&**acc) {
                    *self = Int::Small(v);
                }
            }
            (Int::Big(acc), Int::Big(x), Int::Big(y)) => {
                **acc += &**x * &**y;
                if let Some(v) = ToPrimitive::to_i64(&**acc) {
                    *self = Int::Small(v);
                }
            }
            _ => *self = self.add(&a.mul(b)),
        }
    }
    #[inline]
    fn mul_sub(a: &Self, b: &Self, c: &Self, d: &Self) -> Self {
        if let (Int::Small(a), Int::Small(b), Int::Small(c), Int::Small(d)) = (a, b, c, d) {
            // |a·b|, |c·d| ≤ 2^126, so the difference fits an i128.
            return Int::from_i128(*a as i128 * *b as i128 - *c as i128 * *d as i128);
        }
        big_cross_difference(a, b, c, d)
    }
    #[inline]
    fn div_exact(&self, other: &Self) -> Self {
        if let (Int::Small(a), Int::Small(b)) = (self, other) {
            return word_quotient(*a, *b);
        }
        big_quotient(self, other)
    }
    #[inline]
    fn gcd(&self, other: &Self) -> Self {
        if let (Int::Small(a), Int::Small(b)) = (self, other) {
            return word_gcd(*a, *b);
        }
        big_gcd(self, other)
    }
    #[inline]
    fn abs_cmp(&self, other: &Self) -> Ordering {
        if let (Int::Small(a), Int::Small(b)) = (self, other) {
            return a.unsigned_abs().cmp(&b.unsigned_abs());
        }
        big_abs_cmp(self, other)
    }
    fn cmp_value(&self, other: &Self) -> Ordering {
        match (self, other) {
            (Int::Small(a), Int::Small(b)) => a.cmp(b),
            (Int::Small(_), Int::Big(b)) => {
                if b.sign() == Sign::Minus {
                    Ordering::Greater
                } else {
                    Ordering::Less
                }
            }
            (Int::Big(a), Int::Small(_)) => {
                if a.sign() == Sign::Minus {
                    Ordering::Less
                } else {
                    Ordering::Greater
                }
            }
            (Int::Big(a), Int::Big(b)) => a.cmp(b),
        }
    }
    fn bits(&self) -> u64 {
        match self {
            Int::Small(v) => 64 - v.unsigned_abs().leading_zeros() as u64,
            Int::Big(b) => b.bits(),
        }
    }
}

/// `a / b` in machine words, for a division known to be exact.
#[inline]
fn word_quotient(a: i64, b: i64) -> Int {
    debug_assert!(b != 0 && a % b == 0, "inexact division");
    // The processor's 64-bit division (a 128-bit one is a library call several times slower);
    // only a / −1 can leave the i64 range (for i64::MIN).
    if b == -1 {
        Int::from_i128(-(a as i128))
    } else {
        Int::Small(a / b)
    }
}

/// `gcd(a, b)` of two machine words (`2^63` for `gcd(i64::MIN, i64::MIN)` leaves the range).
#[inline]
fn word_gcd(a: i64, b: i64) -> Int {
    Int::from_i128(binary_gcd(a.unsigned_abs(), b.unsigned_abs()) as i128)
}

// The operations of `Int` with a big operand, out of line (see `Int::boxed_i128`). Each also
// takes two machine words (the quotient and the GCD through the word functions above).

#[inline(never)]
fn big_sum(a: &Int, b: &Int) -> Int {
    match (a, b) {
        (Int::Small(a), Int::Small(b)) => Int::from_i128(*a as i128 + *b as i128),
        (Int::Small(a), Int::Big(b)) | (Int::Big(b), Int::Small(a)) => Int::from_big(&**b + *a),
        (Int::Big(a), Int::Big(b)) => Int::from_big(&**a + &**b),
    }
}

#[inline(never)]
fn big_difference(a: &Int, b: &Int) -> Int {
    match (a, b) {
        (Int::Small(a), Int::Small(b)) => Int::from_i128(*a as i128 - *b as i128),
        (Int::Small(a), Int::Big(b)) => Int::from_big(*a - &**b),
        (Int::Big(a), Int::Small(b)) => Int::from_big(&**a - *b),
        (Int::Big(a), Int::Big(b)) => Int::from_big(&**a - &**b),
    }
}

#[inline(never)]
fn big_product(a: &Int, b: &Int) -> Int {
    match (a, b) {
        (Int::Small(a), Int::Small(b)) => Int::from_i128(*a as i128 * *b as i128),
        (Int::Small(0), _) | (_, Int::Small(0)) => Int::Small(0),
        (Int::Small(a), Int::Big(b)) | (Int::Big(b), Int::Small(a)) => Int::from_big(&**b * *a),
        (Int::Big(a), Int::Big(b)) => Int::from_big(&**a * &**b),
    }
}

#[inline(never)]
fn big_cross_difference(a: &Int, b: &Int, c: &Int, d: &Int) -> Int {
    Int::from_big(product(a, b) - product(c, d))
}

#[inline(never)]
fn big_quotient(a: &Int, b: &Int) -> Int {
    match (a, b) {
        (Int::Small(a), Int::Small(b)) => word_quotient(*a, *b),
        (Int::Big(a), Int::Small(b)) => {
            debug_assert!(Zero::is_zero(&(&**a % *b)), "inexact division");
            Int::from_big(&**a / *b)
        }
        (Int::Big(a), Int::Big(b)) => {
            debug_assert!(Zero::is_zero(&(&**a % &**b)), "inexact division");
            Int::from_big(&**a / &**b)
        }
        // |a| ≤ 2^63 ≤ |b|: the exact quotient is 0, or ±1 for a = i64::MIN, |b| = 2^63.
        (Int::Small(a), Int::Big(b)) => {
            debug_assert!(
                Zero::is_zero(&(BigInt::from(*a) % &**b)),
                "inexact division"
            );
            Int::from_big(BigInt::from(*a) / &**b)
        }
    }
}

#[inline(never)]
fn big_gcd(a: &Int, b: &Int) -> Int {
    match (a, b) {
        (Int::Small(a), Int::Small(b)) => word_gcd(*a, *b),
        (Int::Small(a), Int::Big(b)) | (Int::Big(b), Int::Small(a)) if *a != 0 => {
            // gcd(big, small) = gcd(small, big mod small): one bignum division.
            let rem = ToPrimitive::to_i64(&(&**b % BigInt::from(*a))).unwrap_or(0);
            Int::from_i128(binary_gcd(a.unsigned_abs(), rem.unsigned_abs()) as i128)
        }
        (Int::Big(a), Int::Big(b)) => Int::from_big(crate::gcd::gcd_bigint(a, b)),
        (Int::Small(_), Int::Big(b)) | (Int::Big(b), Int::Small(_)) => {
            Int::from_big(Signed::abs(&**b))
        }
    }
}

#[inline(never)]
fn big_abs_cmp(a: &Int, b: &Int) -> Ordering {
    match (a, b) {
        (Int::Small(a), Int::Small(b)) => a.unsigned_abs().cmp(&b.unsigned_abs()),
        // A big value has |b| ≥ 2^63 ≥ |a|, equal only for a = i64::MIN.
        (Int::Small(a), Int::Big(b)) => BigUint::from(a.unsigned_abs()).cmp(b.magnitude()),
        (Int::Big(b), Int::Small(a)) => b.magnitude().cmp(&BigUint::from(a.unsigned_abs())),
        (Int::Big(a), Int::Big(b)) => a.magnitude().cmp(b.magnitude()),
    }
}

/// `gcd` of a slice (non-negative; 0 for an empty or all-zero slice). Stops early at 1.
pub fn gcd_all<R: Ring>(values: &[R]) -> R {
    let mut g = R::zero();
    for v in values {
        if v.is_zero() {
            continue;
        }
        g = g.gcd(v);
        if g.is_one() {
            break;
        }
    }
    g
}

/// Least common multiple of two positive values.
pub fn lcm<R: Ring>(a: &R, b: &R) -> R {
    if a == b {
        return a.clone();
    }
    let g = a.gcd(b);
    a.div_exact(&g).mul(b).abs()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The conversion through `i64` is the plain one on both sides of every boundary.
    #[test]
    fn i128_values_convert_to_the_same_big_integers() {
        let edges = [
            0i128,
            1,
            -1,
            i64::MAX as i128,
            i64::MAX as i128 + 1,
            i64::MIN as i128,
        ];
        for v in edges.into_iter().chain([
            i64::MIN as i128 - 1,
            u64::MAX as i128 + 1,
            i128::MAX,
            i128::MIN,
        ]) {
            assert_eq!(bigint_from_i128(v), BigInt::from(v), "{v}");
        }
    }

    /// `i64::MIN` is small but `2^63` is big: quotients and comparisons across the boundary
    /// (they arise as products of powers of two when elimination runs without simplification).
    #[test]
    fn the_boundary_between_small_and_big_values() {
        let min = Int::Small(i64::MIN);
        let two_63 = Int::from_bigint(&(BigInt::from(1) << 63));
        assert!(!two_63.is_small());
        assert_eq!(min.div_exact(&two_63), Int::Small(-1));
        assert_eq!(min.div_exact(&two_63.neg()), Int::Small(1));
        assert_eq!(Int::Small(0).div_exact(&two_63), Int::Small(0));
        // The one small quotient of small values that is not small.
        assert_eq!(min.div_exact(&Int::Small(-1)), two_63);
        assert_eq!(min.div_exact(&Int::Small(1)), min);
        assert_eq!(Int::Small(-12).div_exact(&Int::Small(-4)), Int::Small(3));
        assert_eq!(min.abs_cmp(&two_63), Ordering::Equal);
        assert_eq!(two_63.abs_cmp(&min), Ordering::Equal);
        assert_eq!(Int::Small(i64::MAX).abs_cmp(&two_63), Ordering::Less);
        assert_eq!(two_63.abs_cmp(&Int::Small(5)), Ordering::Greater);
    }

    fn interesting() -> impl Strategy<Value = i64> {
        prop_oneof![
            any::<i64>(),
            -1000i64..1000,
            Just(i64::MIN),
            Just(i64::MAX),
            Just(i64::MIN + 1),
            Just(0),
        ]
    }

    fn both(v: &BigInt) -> (Int, BigInt) {
        (Int::from_bigint(v), v.clone())
    }

    fn check_normal(v: &Int) {
        if let Int::Big(b) = v {
            assert!(ToPrimitive::to_i64(&**b).is_none(), "unnormalised big {b}");
        }
    }

    proptest! {
        #[test]
        fn int_matches_bigint(a in interesting(), b in interesting(), c in interesting(), d in interesting(), scale in 0u32..3) {
            // Lift some operands beyond i64 to exercise the big paths.
            let lift = |x: i64| BigInt::from(x) * BigInt::from(3).pow(scale * 30);
            let (ia, ba) = both(&lift(a));
            let (ib, bb) = both(&BigInt::from(b));
            let (ic, bc) = both(&lift(c));
            let (id, bd) = both(&BigInt::from(d));
            for (x, y) in [
                (ia.add(&ib), Ring::add(&ba, &bb)),
                (ia.sub(&ib), Ring::sub(&ba, &bb)),
                (ia.mul(&ib), Ring::mul(&ba, &bb)),
                (ia.neg(), Ring::neg(&ba)),
                (Int::mul_sub(&ia, &ib, &ic, &id), BigInt::mul_sub(&ba, &bb, &bc, &bd)),
                (ia.gcd(&ib), Ring::gcd(&ba, &bb)),
                (ia.gcd(&ic), Ring::gcd(&ba, &bc)),
                (ia.abs(), Ring::abs(&ba)),
                ({ let mut acc = ic.clone(); acc.add_mul(&ia, &ib); acc }, { let mut acc = bc.clone(); acc.add_mul(&ba, &bb); acc }),
                ({ let mut acc = ia.clone(); acc.add_mul(&ic, &id); acc }, { let mut acc = ba.clone(); acc.add_mul(&bc, &bd); acc }),
                ({ let mut acc = ia.clone(); acc.add_mul(&ic, &ia); acc }, { let mut acc = ba.clone(); acc.add_mul(&bc, &ba); acc }),
            ] {
                check_normal(&x);
                prop_assert_eq!(x.to_bigint(), y);
            }
            prop_assert_eq!(ia.abs_cmp(&ib), ba.abs_cmp(&bb));
            prop_assert_eq!(ia.cmp_value(&ic), ba.cmp_value(&bc));
            prop_assert_eq!(ia.bits(), Ring::bits(&ba));
            if b != 0 {
                let prod = ia.mul(&ib);
                let q = prod.div_exact(&ib);
                check_normal(&q);
                prop_assert_eq!(q.to_bigint(), ba.clone());
            }
        }
    }

    #[test]
    fn overflow_moves_to_big_and_back() {
        let a = Int::Small(i64::MAX);
        let sum = a.add(&Int::Small(1));
        assert!(!sum.is_small());
        let back = sum.sub(&Int::Small(1));
        assert!(back.is_small());
        assert_eq!(
            Int::Small(i64::MIN).neg().to_bigint(),
            -BigInt::from(i64::MIN)
        );
        assert_eq!(
            Int::Small(i64::MIN).gcd(&Int::Small(0)).to_bigint(),
            BigInt::from(2u64.pow(63))
        );
        assert_eq!(
            gcd_all(&[Int::Small(0), Int::Small(6), Int::Small(-4)]),
            Int::Small(2)
        );
        assert_eq!(lcm(&Int::Small(4), &Int::Small(6)), Int::Small(12));
    }
}
