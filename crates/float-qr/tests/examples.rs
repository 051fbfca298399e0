//! Worked examples with the values the float backend gives: the thesis matrix (4.3), edge
//! shapes, duplicate rows and badly scaled matrices whose rank margin it reports. The equations
//! every answer satisfies are the backend contract's (`tests/contract.rs`).

use api::{Factorization, IntMatrix, LinearBackend, Rational, RhsFamily, SolveError};
use backend_contract::thesis;
use exact_ldu::ExactLdu;
use float_qr::{FloatFactorization, FloatQr};

fn q(n: i64) -> Rational {
    Rational::from_integer(n.into())
}

fn qs(values: &[i64]) -> Vec<Rational> {
    values.iter().map(|&v| q(v)).collect()
}

fn factor(cols: usize, rows: &[Vec<i64>]) -> FloatFactorization {
    let a = IntMatrix::from_dense(cols, rows).expect("matrix");
    FloatQr::default().factor(&a).expect("factor")
}

/// The matrix (4.3) of the thesis as dense rows.
fn matrix_4_3() -> Vec<Vec<i64>> {
    thesis::matrix_4_3()
        .to_dense()
        .iter()
        .map(|row| {
            row.iter()
                .map(|v| i64::try_from(v).expect("small"))
                .collect()
        })
        .collect()
}

fn residual(a: &[Vec<i64>], x: &[f64], b: &[i64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(row, bi)| {
            let ax: f64 = row.iter().zip(x).map(|(aij, xj)| *aij as f64 * xj).sum();
            (ax - *bi as f64).abs()
        })
        .fold(0.0, f64::max)
}

/// (4.3): the rank decision has a wide margin, the inconsistent right-hand side of (8.17) with
/// `b₅ = 51` gets a certificate of the same size as the exact one, and the null vector has
/// unit length. (Solutions, certificates, families and the least squares of (9.9) are checked
/// by the backend contract, `tests/contract.rs`.)
#[test]
fn thesis_matrix_4_3() {
    let a = matrix_4_3();
    let f = factor(4, &a);
    assert_eq!(f.rank(), 3);
    let margin = f.rank_margin().expect("float backends report a margin");
    assert!(margin.smallest_kept > 1e-3, "{margin:?}");
    assert!(margin.largest_dropped < 1e-14, "{margin:?}");

    let mut bad = thesis::rhs_8_17();
    bad[4] = q(51);
    let Err(SolveError::Inconsistent(c)) = f.solve(&bad) else {
        panic!("b₅ = 51 is inconsistent")
    };
    assert!(c.rows.contains(&4), "{c:?}");
    // The exact backend finds the system inconsistent too (its certificate may name another
    // circuit through row 4: the two backends pick different independent rows).
    let exact = ExactLdu::default()
        .factor(&thesis::matrix_4_3())
        .expect("factor");
    let Err(SolveError::Inconsistent(e)) = exact.solve(&bad) else {
        panic!("the exact backend must agree")
    };
    assert!(e.rows.contains(&4));
    assert_eq!(e.rows.len(), c.rows.len());

    let null = f.null_space();
    assert_eq!(null.len(), 1);
    let norm: f64 = null[0].iter().map(|v| v * v).sum::<f64>().sqrt();
    assert!((norm - 1.0).abs() < 1e-12);
    assert!(residual(&a, &null[0], &[0; 5]) < 1e-12);
}

#[test]
fn no_rows() {
    let f = factor(3, &[]);
    assert_eq!((f.rows(), f.cols(), f.rank()), (0, 3, 0));
    assert!(f.independent_rows().is_empty());
    assert!(f.redundancies().is_empty());
    let margin = f.rank_margin().expect("margin");
    assert_eq!((margin.smallest_kept, margin.largest_dropped), (1.0, 0.0));
    assert_eq!(f.solve(&[]).expect("trivially consistent"), vec![0.0; 3]);
    let null = f.null_space();
    assert_eq!(null.len(), 3);
    for (k, v) in null.iter().enumerate() {
        for (j, x) in v.iter().enumerate() {
            assert!((x.abs() - f64::from(u8::from(j == k))).abs() < 1e-15);
        }
    }
    let x = f
        .least_squares(&[], &qs(&[1, 2, 3]), &qs(&[1, 1, 1]))
        .expect("hints are feasible");
    assert_eq!(x, vec![1.0, 2.0, 3.0]);
    assert_eq!(
        f.check_strongly_consistent(&RhsFamily::single(vec![])),
        Ok(Ok(()))
    );
}

#[test]
fn no_columns() {
    let f = factor(0, &[vec![], vec![], vec![]]);
    assert_eq!((f.rows(), f.cols(), f.rank()), (3, 0, 0));
    let reds = f.redundancies();
    assert_eq!(reds.len(), 3);
    assert!(reds.iter().all(|r| r.combination.is_empty()));
    assert_eq!(
        f.solve(&qs(&[0, 0, 0])).expect("zero rhs"),
        Vec::<f64>::new()
    );
    let Err(SolveError::Inconsistent(c)) = f.solve(&qs(&[0, 7, 0])) else {
        panic!("0 = 7 is inconsistent")
    };
    assert_eq!(c.rows, vec![1]);
    assert_eq!(c.certificate, vec![1.0]);
    assert_eq!(c.discrepancy, 7.0);
    assert!(f.null_space().is_empty());
    assert_eq!(
        f.least_squares(&qs(&[0, 0, 0]), &[], &[]).expect("empty"),
        Vec::<f64>::new()
    );
    let empty = factor(0, &[]);
    assert_eq!(empty.rank(), 0);
    assert_eq!(empty.solve(&[]).expect("empty"), Vec::<f64>::new());
    assert!(empty.null_space().is_empty());
}

#[test]
fn all_zero_matrix() {
    let f = factor(3, &[vec![0, 0, 0], vec![0, 0, 0]]);
    assert_eq!(f.rank(), 0);
    let margin = f.rank_margin().expect("margin");
    assert_eq!((margin.smallest_kept, margin.largest_dropped), (1.0, 0.0));
    assert_eq!(f.null_space().len(), 3);
    assert_eq!(f.solve(&qs(&[0, 0])).expect("zero rhs"), vec![0.0; 3]);
    let Err(SolveError::Inconsistent(c)) = f.solve(&qs(&[0, -2])) else {
        panic!("0 = -2 is inconsistent")
    };
    assert_eq!((c.rows, c.discrepancy), (vec![1], -2.0));
    let x = f
        .least_squares(&qs(&[0, 0]), &qs(&[4, 5, 6]), &qs(&[1, 2, 3]))
        .expect("rank 0");
    assert_eq!(x, vec![4.0, 5.0, 6.0]);
}

#[test]
fn full_column_rank() {
    // r = n: the solution is unique, least squares ignores hints, the null space is empty.
    let a = vec![vec![2, 1, 0], vec![0, 1, 1], vec![1, 0, 3], vec![3, 2, 4]];
    let f = factor(3, &a);
    assert_eq!(f.rank(), 3);
    assert!(f.null_space().is_empty());
    let b = [3, 2, 4, 9]; // x = (1, 1, 1)
    let x = f.solve(&qs(&b)).expect("consistent");
    for v in &x {
        assert!((v - 1.0).abs() < 1e-12, "{x:?}");
    }
    let y = f
        .least_squares(&qs(&b), &qs(&[9, -9, 9]), &qs(&[1, 5, 2]))
        .expect("consistent");
    for v in &y {
        assert!((v - 1.0).abs() < 1e-12, "{y:?}");
    }
    assert!(f.solve(&qs(&[3, 2, 4, 10])).is_err());
}

#[test]
fn duplicate_rows() {
    let a = vec![
        vec![1, -1, 0],
        vec![1, -1, 0],
        vec![0, 1, -1],
        vec![1, -1, 0],
    ];
    let f = factor(3, &a);
    assert_eq!(f.rank(), 2);
    let reds = f.redundancies();
    assert_eq!(reds.len(), 2);
    for r in &reds {
        assert_eq!(r.combination.len(), 1, "{r:?}");
        assert!((r.combination[0].1 - 1.0).abs() < 1e-12);
        assert_eq!(a[r.combination[0].0], a[r.row]);
    }
    f.check_consistent(&qs(&[5, 5, 1, 5]))
        .expect("equal copies");
    let Err(SolveError::Inconsistent(c)) = f.check_consistent(&qs(&[5, 5, 1, 6])) else {
        panic!("copies disagree")
    };
    assert_eq!(c.rows.len(), 2);
    assert!(c.rows.contains(&3));
    assert!((c.discrepancy.abs() - 1.0).abs() < 1e-12);
}

/// Rows of very different scale: a copy scaled by 10⁶ is still found redundant, and a nearly
/// singular block shows up in the rank margin.
#[test]
fn scaled_rows_and_rank_margin() {
    let big = 1_000_000;
    let f = factor(
        3,
        &[vec![1, 2, 3], vec![big, 2 * big, 3 * big], vec![0, 1, 0]],
    );
    assert_eq!(f.rank(), 2);
    let reds = f.redundancies();
    assert_eq!(reds.len(), 1);
    let scale = if reds[0].row == 0 { 1e-6 } else { 1e6 };
    assert!(
        (reds[0].combination[0].1 / scale - 1.0).abs() < 1e-9,
        "{reds:?}"
    );

    // [[K, K+1], [K+1, K+2]] has determinant −1: exactly rank 2 for every K, but its smallest
    // relative diagonal is about 1/(4K²).
    let nearly = |k: i64| vec![vec![k, k + 1], vec![k + 1, k + 2]];
    let f = factor(2, &nearly(1000));
    assert_eq!(f.rank(), 2);
    let margin = f.rank_margin().expect("margin");
    assert!(
        margin.smallest_kept > 1e-8 && margin.smallest_kept < 1e-5,
        "{margin:?}"
    );
    assert_eq!(margin.largest_dropped, 0.0);
    assert_eq!(margin.tolerance, float_qr::DEFAULT_TOLERANCE);

    // For K = 10⁸ the determinant is below f64 resolution: the float backend drops the row
    // (the exact backend keeps it), and the margin shows the decision was at rounding level.
    let a = IntMatrix::from_dense(2, &nearly(100_000_000)).expect("matrix");
    let f = FloatQr::default().factor(&a).expect("factor");
    let exact = ExactLdu::default().factor(&a).expect("factor");
    assert_eq!(exact.rank(), 2);
    assert_eq!(f.rank(), 1);
    let margin = f.rank_margin().expect("margin");
    assert_eq!(margin.smallest_kept, 1.0);
    assert!(margin.largest_dropped < 1e-14, "{margin:?}");
}
