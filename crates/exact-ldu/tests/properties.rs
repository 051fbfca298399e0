//! Algebraic invariants of the exact backend on random matrices of every shape and rank.
//!
//! An independent oracle (plain rational Gauss–Jordan elimination written here) decides ranks
//! and consistency, so the backend is never checked against itself.

// Matrix code below indexes rows and columns explicitly; iterators would hide the algebra.
#![allow(clippy::needless_range_loop)]

use api::{
    Factorization, IntMatrix, LinearBackend, PreparedLeastSquares, Rational, RhsFamily, SolveError,
    StrongFailure,
};
use exact_ldu::{ExactLdu, Simplification};
use num_bigint::BigInt;
use num_traits::{One, Zero};
use proptest::prelude::*;

const METHODS: [Simplification; 3] = [
    Simplification::None,
    Simplification::Gcd,
    Simplification::Turner,
];

fn r(v: i64) -> Rational {
    Rational::from_integer(v.into())
}

/// Rank of a rational matrix by Gauss–Jordan elimination (the oracle).
fn oracle_rank(rows: &[Vec<Rational>]) -> usize {
    let mut m: Vec<Vec<Rational>> = rows.to_vec();
    let cols = m.first().map_or(0, Vec::len);
    let mut rank = 0;
    for c in 0..cols {
        let Some(p) = (rank..m.len()).find(|&i| !m[i][c].is_zero()) else {
            continue;
        };
        m.swap(rank, p);
        let pivot = m[rank][c].clone();
        for i in 0..m.len() {
            if i != rank && !m[i][c].is_zero() {
                let f = &m[i][c] / &pivot;
                for j in c..cols {
                    let delta = &f * &m[rank][j];
                    m[i][j] -= delta;
                }
            }
        }
        rank += 1;
    }
    rank
}

fn to_rational(a: &[Vec<i64>]) -> Vec<Vec<Rational>> {
    a.iter()
        .map(|row| row.iter().map(|&v| r(v)).collect())
        .collect()
}

fn with_column(a: &[Vec<Rational>], b: &[Rational]) -> Vec<Vec<Rational>> {
    a.iter()
        .zip(b)
        .map(|(row, v)| {
            let mut row = row.clone();
            row.push(v.clone());
            row
        })
        .collect()
}

fn mat_vec(a: &[Vec<i64>], x: &[Rational]) -> Vec<Rational> {
    a.iter()
        .map(|row| row.iter().zip(x).map(|(&v, xi)| r(v) * xi).sum())
        .collect()
}

fn int_matrix(a: &[Vec<i64>], cols: usize) -> IntMatrix {
    IntMatrix::from_dense(cols, a).expect("rectangular")
}

/// A matrix with its column count (needed when it has no rows).
#[derive(Debug, Clone)]
struct Case {
    cols: usize,
    a: Vec<Vec<i64>>,
}

fn dense(m: usize, n: usize, lo: i64, hi: i64) -> impl Strategy<Value = Vec<Vec<i64>>> {
    prop::collection::vec(prop::collection::vec(lo..=hi, n), m)
}

/// Matrices of every kind: random, sparse, low rank (product of thin factors), zero,
/// duplicated rows, and the degenerate shapes 0 × n and m × 0.
fn case() -> impl Strategy<Value = Case> {
    (0usize..=7, 0usize..=7).prop_flat_map(|(m, n)| {
        prop_oneof![
            3 => dense(m, n, -9, 9).prop_map(move |a| Case { cols: n, a }),
            2 => dense(m, n, -2, 2).prop_map(move |a| Case {
                cols: n,
                a: a.into_iter()
                    .map(|row| row.into_iter().map(|v| if v.abs() == 2 { 0 } else { v * 3 }).collect())
                    .collect(),
            }),
            3 => (1usize..=3).prop_flat_map(move |k| (dense(m, k, -4, 4), dense(k, n, -4, 4)))
                .prop_map(move |(p, q)| Case {
                    cols: n,
                    a: p.iter()
                        .map(|prow| (0..n).map(|j| prow.iter().zip(&q).map(|(x, qr)| x * qr[j]).sum()).collect())
                        .collect(),
                }),
            1 => Just(Case { cols: n, a: vec![vec![0; n]; m] }),
            2 => dense(m.max(1), n, -9, 9).prop_map(move |mut a| {
                let first = a[0].clone();
                a.push(first.clone());
                a.push(first.iter().map(|v| -2 * v).collect());
                Case { cols: n, a }
            }),
        ]
    })
}

fn rationals(len: usize) -> impl Strategy<Value = Vec<Rational>> {
    prop::collection::vec((-20i64..=20, 1i64..=6), len).prop_map(|v| {
        v.into_iter()
            .map(|(p, q)| Rational::new(p.into(), q.into()))
            .collect()
    })
}

fn positive_weights(len: usize) -> impl Strategy<Value = Vec<Rational>> {
    prop::collection::vec((1i64..=9, 1i64..=4), len).prop_map(|v| {
        v.into_iter()
            .map(|(p, q)| Rational::new(p.into(), q.into()))
            .collect()
    })
}

fn case_with_vectors() -> impl Strategy<
    Value = (
        Case,
        Vec<Rational>,
        Vec<Rational>,
        Vec<Rational>,
        Vec<Rational>,
    ),
> {
    case().prop_flat_map(|c| {
        let n = c.cols;
        let m = c.a.len();
        (
            Just(c),
            rationals(n),
            rationals(n),
            positive_weights(n),
            rationals(m),
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 160, ..ProptestConfig::default() })]

    /// A = Π_R L D⁻¹ U Π_C exactly; rank as the oracle; independent rows independent; every
    /// method and both integer types agree on rank and permutation-independent answers.
    #[test]
    fn factoring_invariants(c in case()) {
        let ar = to_rational(&c.a);
        let rank = oracle_rank(&ar);
        let matrix = int_matrix(&c.a, c.cols);
        for method in METHODS {
            let f = ExactLdu::new(method).factor(&matrix).expect("factor");
            prop_assert_eq!(f.rank(), rank);
            let back = f.ldu().reconstruct();
            prop_assert_eq!(&back, &ar);
            let independent = f.independent_rows();
            let chosen: Vec<Vec<Rational>> = independent.iter().map(|&i| ar[i].clone()).collect();
            prop_assert_eq!(oracle_rank(&chosen), rank);
            // The same algorithm over plain big integers gives bit-identical factors.
            let big = ExactLdu::without_machine_integers(method).factor(&matrix).expect("factor");
            prop_assert_eq!(big.ldu().dense_factors(), f.ldu().dense_factors());
            prop_assert_eq!(big.ldu().row_perm(), f.ldu().row_perm());
            prop_assert_eq!(big.ldu().col_perm(), f.ldu().col_perm());
            // Redundant rows are the stated combinations of independent rows.
            let redundancies = f.redundancies();
            prop_assert_eq!(redundancies.len(), c.a.len() - rank);
            for red in redundancies {
                let mut combo = vec![Rational::zero(); c.cols];
                for (i, w) in &red.combination {
                    prop_assert!(independent.contains(i));
                    for (j, v) in combo.iter_mut().enumerate() {
                        *v += w * &ar[*i][j];
                    }
                }
                prop_assert_eq!(&combo, &ar[red.row]);
            }
        }
    }

    /// Null space: n − r primitive integer vectors, independent, with A N = 0.
    #[test]
    fn null_space(c in case()) {
        let ar = to_rational(&c.a);
        let rank = oracle_rank(&ar);
        for method in METHODS {
            let f = ExactLdu::new(method).factor(&int_matrix(&c.a, c.cols)).expect("factor");
            let basis = f.null_space();
            prop_assert_eq!(basis.len(), c.cols - rank);
            for v in &basis {
                prop_assert!(v.iter().all(|x| x.is_integer()));
                let g = v.iter().fold(BigInt::zero(), |g, x| num_integer::Integer::gcd(&g, x.numer()));
                prop_assert!(g.is_one());
                prop_assert!(mat_vec(&c.a, v).iter().all(Zero::is_zero));
            }
            prop_assert_eq!(oracle_rank(&basis), basis.len());
        }
    }

    /// Solutions satisfy the equations exactly; a unique solution is the same for every method;
    /// an inconsistent right-hand side yields a valid, minimal certificate.
    #[test]
    fn solve_and_certificates((c, x0, _h, _w, noise) in case_with_vectors()) {
        let ar = to_rational(&c.a);
        let rank = oracle_rank(&ar);
        let consistent = mat_vec(&c.a, &x0);
        let mut perturbed = consistent.clone();
        for (p, e) in perturbed.iter_mut().zip(&noise) {
            *p += e;
        }
        let perturbed_consistent = oracle_rank(&with_column(&ar, &perturbed)) == rank;
        let mut unique: Option<Vec<Rational>> = None;
        for method in METHODS {
            let f = ExactLdu::new(method).factor(&int_matrix(&c.a, c.cols)).expect("factor");
            let x = f.solve(&consistent).expect("consistent by construction");
            prop_assert_eq!(mat_vec(&c.a, &x), consistent.clone());
            if rank == c.cols {
                prop_assert_eq!(&x, &x0);
                if let Some(u) = &unique { prop_assert_eq!(u, &x); }
                unique = Some(x);
            }
            match f.solve(&perturbed) {
                Ok(x) => {
                    prop_assert!(perturbed_consistent);
                    prop_assert_eq!(mat_vec(&c.a, &x), perturbed.clone());
                }
                Err(SolveError::Inconsistent(cert)) => {
                    prop_assert!(!perturbed_consistent);
                    prop_assert!(f.check_consistent(&perturbed).is_err());
                    // yᵀA = 0, yᵀb = discrepancy ≠ 0, y integer and primitive.
                    for j in 0..c.cols {
                        let s: Rational = cert.rows.iter().zip(&cert.certificate)
                            .map(|(&i, y)| y * &ar[i][j]).sum();
                        prop_assert!(s.is_zero());
                    }
                    let yb: Rational = cert.rows.iter().zip(&cert.certificate)
                        .map(|(&i, y)| y * &perturbed[i]).sum();
                    prop_assert_eq!(&yb, &cert.discrepancy);
                    prop_assert!(!yb.is_zero());
                    prop_assert!(cert.certificate.iter().all(|y| y.is_integer() && !y.is_zero()));
                    // Minimal: the support is a circuit (rank |S| − 1).
                    let support: Vec<Vec<Rational>> = cert.rows.iter().map(|&i| ar[i].clone()).collect();
                    prop_assert_eq!(oracle_rank(&support), support.len() - 1);
                }
                Err(e) => prop_assert!(false, "unexpected error {e:?}"),
            }
        }
    }

    /// Weighted least squares: A x = b and W (x − h) ⟂ null(A); the minimiser is unique, so all
    /// methods and both integer types return the same x.
    #[test]
    fn least_squares_optimality((c, x0, h, w, _noise) in case_with_vectors()) {
        let b = mat_vec(&c.a, &x0);
        let mut first: Option<Vec<Rational>> = None;
        for method in METHODS {
            let matrix = int_matrix(&c.a, c.cols);
            let f = ExactLdu::new(method).factor(&matrix).expect("factor");
            let x = f.least_squares(&b, &h, &w).expect("consistent");
            prop_assert_eq!(mat_vec(&c.a, &x), b.clone());
            for v in f.null_space() {
                let s: Rational = v.iter().zip(&x).zip(&h).zip(&w)
                    .map(|(((vi, xi), hi), wi)| vi * wi * (xi - hi)).sum();
                prop_assert!(s.is_zero());
            }
            let big = ExactLdu::without_machine_integers(method).factor(&matrix).expect("factor");
            prop_assert_eq!(big.least_squares(&b, &h, &w).expect("consistent"), x.clone());
            if let Some(f0) = &first { prop_assert_eq!(f0, &x); }
            first = Some(x);
        }
    }

    /// Strong consistency agrees with the oracle rank test rank [A | c | K] = rank A, and a
    /// prepared family solves every α it accepts.
    #[test]
    fn strong_consistency_and_families(
        (c, x0, h, w, _noise) in case_with_vectors(),
        k_in_range in any::<bool>(),
        seed in 0i64..1000,
    ) {
        let ar = to_rational(&c.a);
        let m = c.a.len();
        let rank = oracle_rank(&ar);
        // K: two columns, in the range of A or arbitrary.
        let k_cols: Vec<Vec<Rational>> = (0..2i64)
            .map(|t| {
                if k_in_range {
                    let x: Vec<Rational> = (0..c.cols as i64).map(|j| r((seed + 3 * j + t) % 5 - 2)).collect();
                    mat_vec(&c.a, &x)
                } else {
                    (0..m as i64).map(|i| r((seed * (i + 1) + t) % 7 - 3)).collect()
                }
            })
            .collect();
        let k = IntMatrix::from_dense(
            2,
            &(0..m).map(|i| k_cols.iter().map(|col| col[i].numer().clone()).collect::<Vec<BigInt>>()).collect::<Vec<_>>(),
        ).expect("K");
        let constant = mat_vec(&c.a, &x0);
        let family = RhsFamily { constant: vec![constant.clone()], coefficients: k };
        let mut augmented = ar.clone();
        for col in &k_cols {
            augmented = with_column(&augmented, col);
        }
        let strongly = oracle_rank(&augmented) == rank;
        let f = ExactLdu::default().factor(&int_matrix(&c.a, c.cols)).expect("factor");
        match f.check_strongly_consistent(&family).expect("valid family") {
            Ok(()) => prop_assert!(strongly),
            Err(StrongFailure::Direction { parameter, .. }) => {
                prop_assert!(!strongly);
                prop_assert!(oracle_rank(&with_column(&ar, &k_cols[parameter])) > rank);
            }
            Err(StrongFailure::Constant { .. }) => prop_assert!(false, "constant is in the range"),
        }
        let prepared = f.prepare_least_squares(&family, &w).expect("prepare");
        let alpha = vec![Rational::new(seed.into(), 7.into()), r(1)];
        let b: Vec<Rational> = (0..m)
            .map(|i| &constant[i] - &k_cols[0][i] * &alpha[0] - &k_cols[1][i] * &alpha[1])
            .collect();
        let weakly = oracle_rank(&with_column(&ar, &b)) == rank;
        match prepared.solve(0, &alpha, &h) {
            Ok(x) => {
                prop_assert!(weakly);
                prop_assert_eq!(mat_vec(&c.a, &x), b.clone());
                prop_assert_eq!(f.least_squares(&b, &h, &w).expect("consistent"), x);
            }
            Err(SolveError::Inconsistent(cert)) => {
                prop_assert!(!weakly);
                let yb: Rational = cert.rows.iter().zip(&cert.certificate).map(|(&i, y)| y * &b[i]).sum();
                prop_assert_eq!(yb, cert.discrepancy);
            }
            Err(e) => prop_assert!(false, "unexpected error {e:?}"),
        }
        prop_assert_eq!(prepared.check(0, &alpha).is_ok(), weakly);
    }
}

#[test]
fn bad_arguments_are_typed_errors() {
    let a = IntMatrix::from_dense(2, &[vec![1, 2], vec![2, 4]]).expect("matrix");
    let f = ExactLdu::default().factor(&a).expect("factor");
    assert!(matches!(f.solve(&[r(1)]), Err(SolveError::Input(_))));
    assert!(matches!(
        f.least_squares(&[r(1), r(2)], &[r(0)], &[r(1), r(1)]),
        Err(SolveError::Input(_))
    ));
    assert!(matches!(
        f.least_squares(&[r(1), r(2)], &[r(0), r(0)], &[r(1), r(-1)]),
        Err(SolveError::Input(api::BackendError::NonPositiveWeight {
            index: 1,
            ..
        }))
    ));
    let family = RhsFamily::single(vec![r(1), r(2)]);
    let prepared = f
        .prepare_least_squares(&family, &[r(1), r(1)])
        .expect("prepare");
    assert!(matches!(
        prepared.solve(1, &[], &[r(0), r(0)]),
        Err(SolveError::Input(api::BackendError::NoSuchColumn { .. }))
    ));
    assert!(matches!(
        prepared.solve(0, &[r(1)], &[r(0), r(0)]),
        Err(SolveError::Input(_))
    ));
}
