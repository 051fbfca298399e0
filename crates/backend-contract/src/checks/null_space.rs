//! The null space.
//!
//! ```text
//! A v = 0 for each of n − r independent vectors v
//! ```

use super::{gcd, residuals_vanish, zero, Check};
use crate::oracle;
use crate::tolerance::{ensure, with_numbers, Tolerance};
use api::{IntMatrix, Integer, Rational, Value};

/// `basis` is a basis of `{x : A x = 0}`: `n − rank A` independent vectors with `A v = 0`;
/// for exact backends primitive integer vectors.
pub fn null_space<S: Value>(a: &IntMatrix, basis: &[Vec<S>], tol: Tolerance) -> Check {
    let dense = oracle::dense(a);
    let n = a.cols();
    let want = n - oracle::rank(&dense);
    ensure(basis.len() == want, || {
        format!(
            "{} null-space vectors, expected n − r = {want}",
            basis.len()
        )
    })?;
    let zeros = vec![Rational::from_integer(zero()); a.rows()];
    for v in basis {
        ensure(v.len() == n, || {
            format!("a vector of length {} for n = {n}", v.len())
        })?;
        with_numbers!(v, tol, |v| residuals_vanish(a, &v, &zeros, 0.0, tol))?;
    }
    match tol {
        Tolerance::Exact => {
            let exact: Vec<Vec<Rational>> = basis
                .iter()
                .map(|v| v.iter().filter_map(Value::to_exact).collect())
                .collect();
            ensure(oracle::rank(&exact) == exact.len(), || {
                "the null-space vectors are dependent".into()
            })?;
            for v in &exact {
                ensure(v.iter().all(Rational::is_integer), || {
                    format!("{v:?} is not an integer vector")
                })?;
                let g = v.iter().fold(zero(), |g, x| gcd(g, x.numer().clone()));
                ensure(g == Integer::from(1), || format!("{v:?} is not primitive"))?;
            }
            Ok(())
        }
        Tolerance::Relative(_) => {
            let floats: Vec<Vec<f64>> = basis
                .iter()
                .map(|v| v.iter().map(Value::to_f64).collect())
                .collect();
            ensure(numerically_independent(floats), || {
                "the null-space vectors are (numerically) dependent".into()
            })
        }
    }
}

/// Modified Gram–Schmidt: every vector keeps at least `1e-6` of its length after the earlier
/// ones are projected out.
fn numerically_independent(mut vectors: Vec<Vec<f64>>) -> bool {
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    for k in 0..vectors.len() {
        let norm = dot(&vectors[k], &vectors[k]).sqrt();
        for l in 0..k {
            let (done, rest) = vectors.split_at_mut(k);
            let p = dot(&rest[0], &done[l]);
            for (x, y) in rest[0].iter_mut().zip(&done[l]) {
                *x -= p * y;
            }
        }
        let left = dot(&vectors[k], &vectors[k]).sqrt();
        if left.is_nan() || left <= 1e-6 * norm {
            return false;
        }
        for x in vectors[k].iter_mut() {
            *x /= left;
        }
    }
    true
}
