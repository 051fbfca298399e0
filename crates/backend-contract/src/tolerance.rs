//! How a backend's answers are compared with the equations: exactly, or within a relative
//! tolerance; and what a broken equation is reported as.

use api::{Integer, Rational, Value};
use std::fmt;

/// How the equations are checked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tolerance {
    /// Exactly, in rationals. The backend must answer in exact values ([`Value::to_exact`]),
    /// and the promises only an exact backend makes are checked too: certificates are primitive
    /// integer vectors on a minimal conflicting set, null-space vectors are primitive integers.
    Exact,
    /// In `f64`: a residual passes when its magnitude is at most this factor times the
    /// magnitude of the terms it was computed from.
    Relative(f64),
}

impl Tolerance {
    /// Whether `value`, computed from terms of total magnitude `scale`, counts as zero.
    pub(crate) fn is_zero<N: Num>(self, value: &N, scale: f64) -> bool {
        match self {
            Tolerance::Exact => value.is_exact_zero(),
            Tolerance::Relative(r) => value.size() <= r * scale,
        }
    }

    /// Whether `value` (of terms of magnitude `scale`) is clearly nonzero.
    pub(crate) fn is_nonzero<N: Num>(self, value: &N, scale: f64) -> bool {
        match self {
            Tolerance::Exact => !value.is_exact_zero(),
            Tolerance::Relative(r) => value.size() > r * scale.max(1.0),
        }
    }
}

/// What the suite runs and how it compares.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contract {
    /// How answers are compared with the equations.
    pub tolerance: Tolerance,
    /// Largest number of rows and of columns of the random matrices.
    pub max_dim: usize,
    /// Random cases per property.
    pub cases: u32,
}

impl Contract {
    /// An exact backend: exact comparisons, random matrices up to `7 × 7`.
    pub const fn exact() -> Self {
        Contract {
            tolerance: Tolerance::Exact,
            max_dim: 7,
            cases: 64,
        }
    }

    /// A floating-point backend: comparisons within `relative`, random matrices up to `7 × 7`.
    pub const fn float(relative: f64) -> Self {
        Contract {
            tolerance: Tolerance::Relative(relative),
            max_dim: 7,
            cases: 64,
        }
    }

    /// The same contract on random matrices of at most `max_dim` rows and columns (for
    /// backends whose cost explodes with the size, such as elimination without simplification).
    pub const fn max_dim(self, max_dim: usize) -> Self {
        Contract { max_dim, ..self }
    }

    /// The same contract with `cases` random cases per property.
    pub const fn cases(self, cases: u32) -> Self {
        Contract { cases, ..self }
    }
}

/// An equation or promise of the backend traits that an answer breaks.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Violation(pub String);

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Violation {}

/// `Ok` when `condition` holds, else the violation `message()`.
pub(crate) fn ensure(condition: bool, message: impl FnOnce() -> String) -> Result<(), Violation> {
    if condition {
        Ok(())
    } else {
        Err(Violation(message()))
    }
}

/// The arithmetic the equations are evaluated in: [`Rational`] (exact) or `f64`.
pub(crate) trait Num: Clone + fmt::Debug {
    fn of_integer(v: &Integer) -> Self;
    fn of_rational(v: &Rational) -> Self;
    fn zero() -> Self;
    fn plus(&self, other: &Self) -> Self;
    fn minus(&self, other: &Self) -> Self;
    fn times(&self, other: &Self) -> Self;
    /// `|self|` as `f64`.
    fn size(&self) -> f64;
    fn is_exact_zero(&self) -> bool;
}

impl Num for Rational {
    fn of_integer(v: &Integer) -> Self {
        Rational::from_integer(v.clone())
    }
    fn of_rational(v: &Rational) -> Self {
        v.clone()
    }
    fn zero() -> Self {
        Rational::from_integer(0.into())
    }
    fn plus(&self, other: &Self) -> Self {
        self + other
    }
    fn minus(&self, other: &Self) -> Self {
        self - other
    }
    fn times(&self, other: &Self) -> Self {
        self * other
    }
    fn size(&self) -> f64 {
        Value::to_f64(self).abs()
    }
    fn is_exact_zero(&self) -> bool {
        *self == Self::zero()
    }
}

impl Num for f64 {
    fn of_integer(v: &Integer) -> Self {
        Value::to_f64(&Rational::from_integer(v.clone()))
    }
    fn of_rational(v: &Rational) -> Self {
        Value::to_f64(v)
    }
    fn zero() -> Self {
        0.0
    }
    fn plus(&self, other: &Self) -> Self {
        self + other
    }
    fn minus(&self, other: &Self) -> Self {
        self - other
    }
    fn times(&self, other: &Self) -> Self {
        self * other
    }
    fn size(&self) -> f64 {
        self.abs()
    }
    fn is_exact_zero(&self) -> bool {
        *self == 0.0
    }
}

/// A backend's answer lifted into the arithmetic its tolerance asks for.
pub(crate) enum Numbers {
    Exact(Vec<Rational>),
    Float(Vec<f64>),
}

/// Lifts `values`: exact rationals under [`Tolerance::Exact`] (a value without an exact form
/// is a violation), `f64` otherwise.
pub(crate) fn numbers<S: Value>(values: &[S], tolerance: Tolerance) -> Result<Numbers, Violation> {
    match tolerance {
        Tolerance::Exact => values
            .iter()
            .map(|v| {
                v.to_exact()
                    .ok_or_else(|| Violation(format!("{v:?} is not an exact value")))
            })
            .collect::<Result<Vec<_>, _>>()
            .map(Numbers::Exact),
        Tolerance::Relative(_) => Ok(Numbers::Float(values.iter().map(Value::to_f64).collect())),
    }
}

/// Runs `$body` with `$x` bound to `$values` lifted by [`numbers`], in either arithmetic.
macro_rules! with_numbers {
    ($values:expr, $tolerance:expr, |$x:ident| $body:expr) => {
        match $crate::tolerance::numbers($values, $tolerance)? {
            $crate::tolerance::Numbers::Exact($x) => $body,
            $crate::tolerance::Numbers::Float($x) => $body,
        }
    };
}
pub(crate) use with_numbers;
