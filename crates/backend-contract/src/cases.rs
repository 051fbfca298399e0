//! Random fixtures for the property tests: small integer matrices of every shape and rank,
//! with random right-hand sides, families, hints and weights.
//!
//! Matrices are dense random, sparse, low rank (products of thin factors), zero, or with
//! duplicated and scaled rows, including the shapes `0 × n` and `m × 0`; entries stay small so
//! a float backend decides every rank correctly.

use crate::fixtures::{columns_matrix, FamilyCase, Fixture, LeastSquaresCase};
use crate::oracle;
use api::{IntMatrix, Rational, RhsFamily};
use proptest::prelude::*;

fn dense(m: usize, n: usize, lo: i64, hi: i64) -> impl Strategy<Value = Vec<Vec<i64>>> {
    prop::collection::vec(prop::collection::vec(lo..=hi, n), m)
}

/// A random `m × n` integer matrix with `m, n ≤ max_dim`, as `(n, rows)`.
pub fn matrix(max_dim: usize) -> impl Strategy<Value = (usize, Vec<Vec<i64>>)> {
    (0..=max_dim, 0..=max_dim).prop_flat_map(|(m, n)| {
        let rows = prop_oneof![
            3 => dense(m, n, -9, 9),
            2 => dense(m, n, -2, 2).prop_map(|a| {
                a.into_iter()
                    .map(|row| row.into_iter().map(|v| if v.abs() == 2 { 0 } else { 3 * v }).collect())
                    .collect()
            }),
            3 => (1usize..=3)
                .prop_flat_map(move |k| (dense(m, k, -4, 4), dense(k, n, -4, 4)))
                .prop_map(move |(p, q)| {
                    p.iter()
                        .map(|prow| {
                            (0..n).map(|j| prow.iter().zip(&q).map(|(x, qr)| x * qr[j]).sum()).collect()
                        })
                        .collect()
                }),
            1 => Just(vec![vec![0; n]; m]),
            2 => dense(m.max(1), n, -9, 9).prop_map(|mut a| {
                let first = a[0].clone();
                a.push(first.clone());
                a.push(first.iter().map(|v| -2 * v).collect());
                a
            }),
        ];
        (Just(n), rows)
    })
}

fn rationals(len: usize) -> impl Strategy<Value = Vec<Rational>> {
    prop::collection::vec((-20i64..=20, 1i64..=6), len).prop_map(|v| {
        v.into_iter()
            .map(|(p, q)| Rational::new(p.into(), q.into()))
            .collect()
    })
}

fn integers(len: usize) -> impl Strategy<Value = Vec<Rational>> {
    prop::collection::vec(-3i64..=3, len).prop_map(|v| {
        v.into_iter()
            .map(|x| Rational::from_integer(x.into()))
            .collect()
    })
}

fn positive(len: usize) -> impl Strategy<Value = Vec<Rational>> {
    prop::collection::vec((1i64..=9, 1i64..=4), len).prop_map(|v| {
        v.into_iter()
            .map(|(p, q)| Rational::new(p.into(), q.into()))
            .collect()
    })
}

/// The random parts of a fixture besides the matrix.
#[derive(Debug, Clone)]
struct Vectors {
    x0: Vec<Rational>,
    noise: Vec<Rational>,
    hints: Vec<Rational>,
    weights: Vec<Rational>,
    g: Vec<Rational>,
    v: Vec<Rational>,
    alpha: Vec<Rational>,
}

fn vectors(m: usize, n: usize) -> impl Strategy<Value = Vectors> {
    (
        rationals(n),
        rationals(m),
        rationals(n),
        positive(n),
        integers(n),
        integers(m),
        rationals(2),
    )
        .prop_map(|(x0, noise, hints, weights, g, v, alpha)| Vectors {
            x0,
            noise,
            hints,
            weights,
            g,
            v,
            alpha,
        })
}

/// A random fixture: a [`matrix`] with a consistent right-hand side `A x₀`, a perturbed one
/// `A x₀ + e` (consistent or not), the families `c = A x₀` with `K = [A g | A x₀']` and
/// `K = [A g | v]` (`v` random: in the range or not), evaluated at `α = 0`, a random `α` and
/// `α = (α₁, 0)`, and the least squares of `A x = A x₀` with random hints and weights.
pub fn fixture(max_dim: usize) -> impl Strategy<Value = Fixture> {
    matrix(max_dim).prop_flat_map(|(n, rows)| {
        let m = rows.len();
        (Just((n, rows)), vectors(m, n)).prop_map(|((n, rows), v)| build(n, &rows, v))
    })
}

fn build(n: usize, rows: &[Vec<i64>], v: Vectors) -> Fixture {
    let matrix = IntMatrix::from_dense(n, rows).expect("the strategy builds rectangular matrices");
    let m = matrix.rows();
    let a = oracle::dense(&matrix);
    let b = oracle::mat_vec(&a, &v.x0);
    let perturbed: Vec<Rational> = b.iter().zip(&v.noise).map(|(x, e)| x + e).collect();
    let ag = oracle::mat_vec(&a, &v.g);
    let shifted: Vec<Rational> = v.x0.iter().map(|x| x.floor()).collect();
    let a_shift = oracle::mat_vec(&a, &shifted);
    let zero = Rational::from_integer(0.into());
    let alphas = vec![
        vec![zero.clone(), zero.clone()],
        v.alpha.clone(),
        vec![v.alpha[0].clone(), zero],
    ];
    let family = |columns: &[Vec<Rational>]| FamilyCase {
        family: RhsFamily {
            constant: vec![b.clone(), perturbed.clone()],
            coefficients: columns_matrix(m, columns),
        },
        alphas: alphas.clone(),
        hints: v.hints.clone(),
        weights: v.weights.clone(),
    };
    Fixture {
        name: "random".into(),
        rhs: vec![b.clone(), perturbed.clone()],
        families: vec![family(&[ag.clone(), a_shift]), family(&[ag, v.v.clone()])],
        least_squares: vec![LeastSquaresCase {
            rhs: b,
            hints: v.hints,
            weights: v.weights,
            solution: None,
        }],
        matrix,
    }
}
