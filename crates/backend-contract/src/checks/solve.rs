//! Solutions, certificates of inconsistency, and weak and strong consistency verdicts.
//!
//! ```text
//! A x = b,   or   yᵀA = 0,  yᵀb = δ ≠ 0
//! ```

use super::{gcd, left_product, residuals_vanish, zero, Check};
use crate::oracle;
use crate::tolerance::{ensure, with_numbers, Num, Tolerance, Violation};
use api::{
    BackendError, Inconsistency, IntMatrix, Integer, Rational, RhsFamily, SolveError,
    StrongFailure, Value,
};

/// `A x = b`.
pub fn solution<S: Value>(a: &IntMatrix, b: &[Rational], x: &[S], tol: Tolerance) -> Check {
    solution_near(a, b, x, 0.0, tol)
}

/// `A x = b` for an `x` computed from inputs of size `extra` (hints).
pub(super) fn solution_near<S: Value>(
    a: &IntMatrix,
    b: &[Rational],
    x: &[S],
    extra: f64,
    tol: Tolerance,
) -> Check {
    ensure(x.len() == a.cols(), || {
        format!("{} entries for {} unknowns", x.len(), a.cols())
    })?;
    with_numbers!(x, tol, |x| residuals_vanish(a, &x, b, extra, tol))
}

/// `x` equals the known answer `want`.
pub fn equals<S: Value>(x: &[S], want: &[Rational], tol: Tolerance) -> Check {
    ensure(x.len() == want.len(), || {
        format!("{} entries, expected {}", x.len(), want.len())
    })?;
    with_numbers!(x, tol, |x| equal_entries(&x, want, tol))
}

fn equal_entries<N: Num>(x: &[N], want: &[Rational], tol: Tolerance) -> Check {
    for (k, (got, w)) in x.iter().zip(want).enumerate() {
        let w = N::of_rational(w);
        ensure(tol.is_zero(&got.minus(&w), w.size().max(1.0)), || {
            format!("entry {k} is {got:?}, expected {w:?}")
        })?;
    }
    Ok(())
}

/// A valid proof that `A x = b` has no solution: rows increasing, `yᵀA = 0`,
/// `yᵀb = discrepancy ≠ 0`; for exact backends `y` is a primitive integer vector without zero
/// entries whose rows form a circuit (rank one less than their number).
pub fn certificate<S: Value>(
    a: &IntMatrix,
    b: &[Rational],
    c: &Inconsistency<S>,
    tol: Tolerance,
) -> Check {
    ensure(!c.rows.is_empty(), || {
        "the certificate names no rows".into()
    })?;
    ensure(c.rows.windows(2).all(|w| w[0] < w[1]), || {
        format!("rows {:?} are not increasing", c.rows)
    })?;
    ensure(c.rows.iter().all(|&i| i < a.rows()), || {
        format!("rows {:?} beyond {}", c.rows, a.rows())
    })?;
    ensure(c.certificate.len() == c.rows.len(), || {
        format!("{} values for {} rows", c.certificate.len(), c.rows.len())
    })?;
    let mut values = c.certificate.clone();
    values.push(c.discrepancy.clone());
    with_numbers!(&values, tol, |v| certificate_equations(
        a, b, &c.rows, &v, tol
    ))?;
    if tol == Tolerance::Exact {
        let y: Vec<Rational> = c.certificate.iter().filter_map(Value::to_exact).collect();
        ensure(
            y.iter().all(|v| v.is_integer() && *v.numer() != zero()),
            || format!("certificate {y:?} is not a nonzero integer vector"),
        )?;
        let g = y.iter().fold(zero(), |g, v| gcd(g, v.numer().clone()));
        ensure(g == Integer::from(1), || {
            format!("certificate {y:?} is not primitive")
        })?;
        let dense = oracle::dense(a);
        let support: Vec<Vec<Rational>> = c.rows.iter().map(|&i| dense[i].clone()).collect();
        ensure(oracle::rank(&support) + 1 == support.len(), || {
            format!("rows {:?} are not a minimal conflicting set", c.rows)
        })?;
    }
    Ok(())
}

fn certificate_equations<N: Num>(
    a: &IntMatrix,
    b: &[Rational],
    rows: &[usize],
    values: &[N],
    tol: Tolerance,
) -> Check {
    let (y, discrepancy) = values.split_at(values.len() - 1);
    let discrepancy = &discrepancy[0];
    for (j, (s, scale)) in left_product(a, rows, y).iter().enumerate() {
        ensure(tol.is_zero(s, *scale), || {
            format!("yᵀA is {s:?} in column {j}")
        })?;
    }
    let magnitude = super::norm_inf(y);
    let mut yb = N::zero();
    let mut scale = 0.0;
    for (&i, yi) in rows.iter().zip(y) {
        let bi = N::of_rational(&b[i]);
        scale += bi.size() * magnitude;
        yb = yb.plus(&yi.times(&bi));
    }
    ensure(
        tol.is_zero(&yb.minus(discrepancy), scale + discrepancy.size()),
        || format!("yᵀb = {yb:?}, but the discrepancy is {discrepancy:?}"),
    )?;
    ensure(tol.is_nonzero(discrepancy, scale), || {
        format!("the discrepancy {discrepancy:?} is zero")
    })
}

/// The verdict of a solve: a solution of a consistent system, a valid certificate for an
/// inconsistent one.
pub fn solve_answer<S: Value>(
    a: &IntMatrix,
    b: &[Rational],
    answer: &Result<Vec<S>, SolveError<S>>,
    tol: Tolerance,
) -> Check {
    match answer {
        Ok(x) => {
            ensure(is_consistent(a, b), || {
                "solved an inconsistent system".into()
            })?;
            solution(a, b, x, tol)
        }
        Err(e) => refusal(a, b, e, tol),
    }
}

/// The verdict of a weak-consistency check.
pub fn consistency_answer<S: Value>(
    a: &IntMatrix,
    b: &[Rational],
    answer: &Result<(), SolveError<S>>,
    tol: Tolerance,
) -> Check {
    match answer {
        Ok(()) => ensure(is_consistent(a, b), || {
            "an inconsistent system passed the check".into()
        }),
        Err(e) => refusal(a, b, e, tol),
    }
}

/// A refusal of a valid question is a certificate for an inconsistent system.
pub(super) fn refusal<S: Value>(
    a: &IntMatrix,
    b: &[Rational],
    e: &SolveError<S>,
    tol: Tolerance,
) -> Check {
    match e {
        SolveError::Inconsistent(c) => {
            ensure(!is_consistent(a, b), || {
                format!("a consistent system refused with {c:?}")
            })?;
            certificate(a, b, c, tol)
        }
        SolveError::Input(e) => Err(Violation(format!("a valid question refused: {e}"))),
    }
}

pub(super) fn is_consistent(a: &IntMatrix, b: &[Rational]) -> bool {
    oracle::is_consistent(&oracle::dense(a), b)
}

/// The verdict of a strong-consistency check: `Ok` exactly when every column of `K` and every
/// constant is in the range of `A`; a direction failure names a column of `K` out of range, a
/// constant failure (only when every direction is in range) a constant out of range, each with
/// a valid certificate.
pub fn strong_answer<S: Value>(
    a: &IntMatrix,
    family: &RhsFamily,
    answer: &Result<Result<(), StrongFailure<S>>, BackendError>,
    tol: Tolerance,
) -> Check {
    let k = &family.coefficients;
    let directions: Vec<Vec<Rational>> = (0..k.cols()).map(|p| oracle::column(k, p)).collect();
    let direction_ok: Vec<bool> = directions.iter().map(|d| is_consistent(a, d)).collect();
    let constant_ok: Vec<bool> = family
        .constant
        .iter()
        .map(|c| is_consistent(a, c))
        .collect();
    match answer {
        Err(e) => Err(Violation(format!("a valid family refused: {e}"))),
        Ok(Ok(())) => ensure(
            direction_ok.iter().chain(&constant_ok).all(|&ok| ok),
            || format!("passed with directions {direction_ok:?}, constants {constant_ok:?}"),
        ),
        Ok(Err(StrongFailure::Direction {
            parameter,
            inconsistency,
        })) => {
            ensure(direction_ok.get(*parameter) == Some(&false), || {
                format!("direction {parameter} blamed; in range: {direction_ok:?}")
            })?;
            certificate(a, &directions[*parameter], inconsistency, tol)
        }
        Ok(Err(StrongFailure::Constant {
            column,
            inconsistency,
        })) => {
            ensure(direction_ok.iter().all(|&ok| ok), || {
                format!("a constant blamed while directions {direction_ok:?} fail")
            })?;
            ensure(constant_ok.get(*column) == Some(&false), || {
                format!("constant {column} blamed; in range: {constant_ok:?}")
            })?;
            certificate(a, &family.constant[*column], inconsistency, tol)
        }
    }
}
