//! Random small integer matrices: the float backend against the exact backend (the oracle),
//! through the same traits.

use api::exact::rational_to_f64;
use api::{Factorization, IntMatrix, LinearBackend, Rational, SolveError};
use exact_ldu::ExactLdu;
use float_qr::FloatQr;
use proptest::prelude::*;

/// A random case: the matrix (`m × n`, both up to 8), a solution `x0`, hints and weights.
#[derive(Debug, Clone)]
struct Case {
    cols: usize,
    rows: Vec<Vec<i64>>,
    x0: Vec<i64>,
    hints: Vec<i64>,
    weights: Vec<(i64, i64)>,
}

fn product(left: &[Vec<i64>], right: &[Vec<i64>], cols: usize) -> Vec<Vec<i64>> {
    left.iter()
        .map(|l| {
            (0..cols)
                .map(|j| l.iter().zip(right).map(|(a, r)| a * r[j]).sum())
                .collect()
        })
        .collect()
}

/// Dense matrices with entries in −9..=9, or (half of the time) products of an `m × k` and a
/// `k × n` matrix with entries in −3..=3, which have rank at most `k`.
fn arb_case() -> impl Strategy<Value = Case> {
    (0usize..=8, 0usize..=8, 0usize..=8).prop_flat_map(|(m, n, k)| {
        let row = |len: usize, bound: i64| prop::collection::vec(-bound..=bound, len);
        (
            any::<bool>(),
            prop::collection::vec(row(n, 9), m),
            prop::collection::vec(row(k, 3), m),
            prop::collection::vec(row(n, 3), k),
            row(n, 5),
            row(n, 5),
            prop::collection::vec((1i64..=5, 1i64..=3), n),
        )
            .prop_map(move |(low, dense, left, right, x0, hints, weights)| Case {
                cols: n,
                rows: if low {
                    product(&left, &right, n)
                } else {
                    dense
                },
                x0,
                hints,
                weights,
            })
    })
}

fn q(v: i64) -> Rational {
    Rational::from_integer(v.into())
}

fn max_abs(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(0.0, |acc, v| acc.max(v.abs()))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn float_agrees_with_exact(case in arb_case()) {
        let a = IntMatrix::from_dense(case.cols, &case.rows).expect("matrix");
        let (m, n) = (case.rows.len(), case.cols);
        let exact = ExactLdu::default().factor(&a).expect("exact factor");
        let float = FloatQr::default().factor(&a).expect("float factor");
        let r = exact.rank();
        let a_f = |i: usize, j: usize| case.rows[i][j] as f64;
        let a_norm = max_abs(case.rows.iter().flatten().map(|&v| v as f64)).max(1.0);

        // Rank, and the float's independent rows are independent by the exact oracle.
        prop_assert_eq!(float.rank(), r);
        let ind = float.independent_rows();
        let all: Vec<usize> = (0..n).collect();
        let sub = ExactLdu::default().factor(&a.select(&ind, &all)).expect("factor");
        prop_assert_eq!(sub.rank(), r);
        let margin = float.rank_margin().expect("margin");
        prop_assert!(margin.largest_dropped <= margin.tolerance);
        prop_assert!(margin.smallest_kept > margin.tolerance || r == 0);

        // Redundancies reproduce their rows.
        let reds = float.redundancies();
        prop_assert_eq!(reds.len(), m - r);
        for red in &reds {
            for j in 0..n {
                let s: f64 = red.combination.iter().map(|(k, w)| w * a_f(*k, j)).sum();
                let scale: f64 = red.combination.iter().map(|(k, w)| (w * a_f(*k, j)).abs()).sum();
                prop_assert!((s - a_f(red.row, j)).abs() <= 1e-9 * (1.0 + scale), "{:?}", red);
            }
        }

        // A consistent right-hand side b = A x0.
        let b: Vec<i64> = case
            .rows
            .iter()
            .map(|row| row.iter().zip(&case.x0).map(|(a, x)| a * x).sum())
            .collect();
        let b_q: Vec<Rational> = b.iter().map(|&v| q(v)).collect();
        let x = float.solve(&b_q).expect("b = A x0 is consistent");
        for (i, row) in case.rows.iter().enumerate() {
            let ax: f64 = row.iter().zip(&x).map(|(a, x)| *a as f64 * x).sum();
            prop_assert!((ax - b[i] as f64).abs() <= 1e-9 * a_norm * (1.0 + max_abs(x.iter().copied())));
        }

        // Weighted least squares agrees with the exact answer.
        let hints: Vec<Rational> = case.hints.iter().map(|&v| q(v)).collect();
        let weights: Vec<Rational> = case
            .weights
            .iter()
            .map(|&(p, d)| Rational::new(p.into(), d.into()))
            .collect();
        let want = exact.least_squares(&b_q, &hints, &weights).expect("exact least squares");
        let got = float.least_squares(&b_q, &hints, &weights).expect("float least squares");
        let want: Vec<f64> = want.iter().map(rational_to_f64).collect();
        let tol = 1e-8 * (1.0 + max_abs(want.iter().copied()));
        for (g, w) in got.iter().zip(&want) {
            prop_assert!((g - w).abs() <= tol, "float {:?} exact {:?}", got, want);
        }

        // Null space: n − r orthonormal vectors with A N ≈ 0.
        let null = float.null_space();
        prop_assert_eq!(null.len(), n - r);
        for (k, v) in null.iter().enumerate() {
            prop_assert_eq!(v.len(), n);
            for i in 0..m {
                let s: f64 = (0..n).map(|j| a_f(i, j) * v[j]).sum();
                prop_assert!(s.abs() <= 1e-10 * a_norm * n as f64);
            }
            for (l, u) in null.iter().enumerate() {
                let d: f64 = v.iter().zip(u).map(|(a, b)| a * b).sum();
                let want = if k == l { 1.0 } else { 0.0 };
                prop_assert!((d - want).abs() <= 1e-12);
            }
        }

        // Perturbing one row of b: both backends give the same verdict.
        if m > 0 {
            let mut b2 = b_q.clone();
            b2[0] += q(1);
            let exact_ok = exact.check_consistent(&b2).is_ok();
            match float.check_consistent(&b2) {
                Ok(()) => prop_assert!(exact_ok, "float says consistent, exact does not"),
                Err(SolveError::Inconsistent(c)) => {
                    prop_assert!(!exact_ok, "float says inconsistent, exact does not: {:?}", c);
                    prop_assert!(c.rows.contains(&0));
                    for j in 0..n {
                        let s: f64 = c.rows.iter().zip(&c.certificate).map(|(&i, y)| y * a_f(i, j)).sum();
                        prop_assert!(s.abs() <= 1e-9 * a_norm * max_abs(c.certificate.iter().copied()));
                    }
                    prop_assert!(c.discrepancy.abs() > 1e-6);
                }
                Err(e) => prop_assert!(false, "unexpected error {:?}", e),
            }
        }
    }
}

/// A random family `b(α) = A x0 − K α` with `K = [A g | v]`: the first direction is always in
/// the range of `A`, the second (`v` random) only sometimes.
#[derive(Debug, Clone)]
struct FamilyCase {
    case: Case,
    g: Vec<i64>,
    v: Vec<i64>,
    alpha: (i64, i64),
}

fn arb_family_case() -> impl Strategy<Value = FamilyCase> {
    arb_case().prop_flat_map(|case| {
        let (m, n) = (case.rows.len(), case.cols);
        (
            Just(case),
            prop::collection::vec(-3i64..=3, n),
            prop::collection::vec(-3i64..=3, m),
            (-4i64..=4, -1i64..=1),
        )
            .prop_map(|(case, g, v, alpha)| FamilyCase { case, g, v, alpha })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn families_agree_with_exact(fc in arb_family_case()) {
        let case = &fc.case;
        let a = IntMatrix::from_dense(case.cols, &case.rows).expect("matrix");
        let exact = ExactLdu::default().factor(&a).expect("exact factor");
        let float = FloatQr::default().factor(&a).expect("float factor");
        let k_rows: Vec<Vec<i64>> = case
            .rows
            .iter()
            .zip(&fc.v)
            .map(|(row, v)| vec![row.iter().zip(&fc.g).map(|(a, g)| a * g).sum(), *v])
            .collect();
        let c: Vec<Rational> = case
            .rows
            .iter()
            .map(|row| q(row.iter().zip(&case.x0).map(|(a, x)| a * x).sum()))
            .collect();
        let family = api::RhsFamily {
            constant: vec![c],
            coefficients: IntMatrix::from_dense(2, &k_rows).expect("K"),
        };

        let want = exact.check_strongly_consistent(&family).expect("valid family");
        let got = float.check_strongly_consistent(&family).expect("valid family");
        match (&want, &got) {
            (Ok(()), Ok(())) => {}
            (
                Err(api::StrongFailure::Direction { parameter: pe, .. }),
                Err(api::StrongFailure::Direction { parameter: pf, .. }),
            ) => prop_assert_eq!((*pe, *pf), (1, 1)),
            _ => prop_assert!(false, "exact {:?} float {:?}", want, got),
        }

        let weights: Vec<Rational> = case
            .weights
            .iter()
            .map(|&(p, d)| Rational::new(p.into(), d.into()))
            .collect();
        let hints: Vec<Rational> = case.hints.iter().map(|&v| q(v)).collect();
        let alpha = [q(fc.alpha.0), q(fc.alpha.1)];
        let pe = exact.prepare_least_squares(&family, &weights).expect("prepare");
        let pf = float.prepare_least_squares(&family, &weights).expect("prepare");
        use api::PreparedLeastSquares;
        match (pe.solve(0, &alpha, &hints), pf.solve(0, &alpha, &hints)) {
            (Ok(xe), Ok(xf)) => {
                let xe: Vec<f64> = xe.iter().map(rational_to_f64).collect();
                let tol = 1e-8 * (1.0 + max_abs(xe.iter().copied()));
                for (g, w) in xf.iter().zip(&xe) {
                    prop_assert!((g - w).abs() <= tol, "float {:?} exact {:?}", xf, xe);
                }
            }
            (Err(SolveError::Inconsistent(ce)), Err(SolveError::Inconsistent(cf))) => {
                prop_assert!(fc.alpha.1 != 0);
                prop_assert!(!ce.rows.is_empty() && !cf.rows.is_empty());
                prop_assert_eq!(pf.check(0, &alpha), Err(SolveError::Inconsistent(cf)));
            }
            (e, f) => prop_assert!(false, "exact {:?} float {:?}", e, f),
        }
    }
}
