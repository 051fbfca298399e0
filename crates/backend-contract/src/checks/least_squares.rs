//! Weighted least squares, prepared families and their approximations.
//!
//! ```text
//! A x = b,   W (x − h) ⟂ ker A        (the Lagrange conditions (9.5))
//! ```

use super::solve::{is_consistent, refusal, solution_near};
use super::Check;
use crate::oracle;
use crate::tolerance::{ensure, with_numbers, Num, Tolerance, Violation};
use api::{IntMatrix, Rational, RhsFamily, SolveError, Value};

/// The weighted least-squares solution: `A x = b` and `W (x − h) ⟂ ker A` (the Lagrange
/// conditions (9.5), which determine `x` uniquely).
pub fn least_squares<S: Value>(
    a: &IntMatrix,
    b: &[Rational],
    hints: &[Rational],
    weights: &[Rational],
    x: &[S],
    tol: Tolerance,
) -> Check {
    let hint_size = super::norm_inf(hints);
    solution_near(a, b, x, hint_size, tol)?;
    let kernel = oracle::kernel(&oracle::dense(a), a.cols());
    with_numbers!(x, tol, |x| optimality(&kernel, &x, hints, weights, tol))
}

fn optimality<N: Num>(
    kernel: &[Vec<Rational>],
    x: &[N],
    hints: &[Rational],
    weights: &[Rational],
    tol: Tolerance,
) -> Check {
    let magnitude = super::norm_inf(x) + super::norm_inf(hints);
    for z in kernel {
        let mut s = N::zero();
        let mut scale = 0.0;
        for ((zs, xs), (hs, ws)) in z.iter().zip(x).zip(hints.iter().zip(weights)) {
            let zw = N::of_rational(&(zs * ws));
            scale += zw.size() * magnitude;
            s = s.plus(&zw.times(&xs.minus(&N::of_rational(hs))));
        }
        ensure(tol.is_zero(&s, scale), || {
            format!("W (x − h) is not orthogonal to the kernel vector {z:?}: {s:?}")
        })?;
    }
    Ok(())
}

/// The verdict of a least-squares solve: the optimal solution of a consistent system, a valid
/// certificate for an inconsistent one.
pub fn least_squares_answer<S: Value>(
    a: &IntMatrix,
    b: &[Rational],
    hints: &[Rational],
    weights: &[Rational],
    answer: &Result<Vec<S>, SolveError<S>>,
    tol: Tolerance,
) -> Check {
    match answer {
        Ok(x) => {
            ensure(is_consistent(a, b), || {
                "solved an inconsistent system".into()
            })?;
            least_squares(a, b, hints, weights, x, tol)
        }
        Err(e) => refusal(a, b, e, tol),
    }
}

/// `b(α) = c_j − K α`.
pub fn family_rhs(family: &RhsFamily, column: usize, alpha: &[Rational]) -> Vec<Rational> {
    family.constant[column]
        .iter()
        .enumerate()
        .map(|(i, c)| {
            family
                .coefficients
                .row(i)
                .iter()
                .fold(c.clone(), |acc, (k, v)| {
                    acc - Rational::from_integer(v.clone()) * &alpha[*k]
                })
        })
        .collect()
}

/// `solve_approx` answers like `solve`: the same verdict, and the same values rounded to `f64`
/// (to within a few roundings).
pub fn approximation<S: Value>(
    exact: &Result<Vec<S>, SolveError<S>>,
    approx: &Result<Vec<f64>, SolveError<S>>,
) -> Check {
    match (exact, approx) {
        (Ok(x), Ok(y)) => {
            ensure(x.len() == y.len(), || {
                format!("{} vs {} entries", x.len(), y.len())
            })?;
            for (k, (x, y)) in x.iter().zip(y).enumerate() {
                let x = x.to_f64();
                ensure((x - y).abs() <= 1e-12 * x.abs(), || {
                    format!("entry {k}: {y} approximates {x}")
                })?;
            }
            Ok(())
        }
        (Err(e), Err(f)) => ensure(e == f, || format!("refused with {f:?}, solve with {e:?}")),
        (e, f) => Err(Violation(format!(
            "solve answered {:?}, solve_approx {:?}",
            e.is_ok(),
            f.is_ok()
        ))),
    }
}
