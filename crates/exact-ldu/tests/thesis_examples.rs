//! The worked examples of the thesis, reproduced exactly.

// Matrix checks index rows and columns explicitly, as the thesis writes them.
#![allow(clippy::needless_range_loop)]

use api::{Factorization, IntMatrix, LinearBackend, Rational};
use exact_ldu::{ExactLdu, Int, Ldu, Pivoting, Ring, Simplification};
use num_bigint::BigInt;

fn q(n: i64, d: i64) -> Rational {
    Rational::new(n.into(), d.into())
}

fn ints(rows: &[&[i64]]) -> Vec<Vec<BigInt>> {
    rows.iter()
        .map(|r| r.iter().map(|&v| BigInt::from(v)).collect())
        .collect()
}

fn matrix_4_3() -> IntMatrix {
    IntMatrix::from_dense(
        4,
        &[
            vec![4, 9, 16, 29],
            vec![-1, -6, -19, -16],
            vec![1, 5, 15, 19],
            vec![5, 6, -1, -12],
            vec![5, 10, 15, 20],
        ],
    )
    .expect("matrix (4.3)")
}

fn rhs_8_17() -> Vec<Rational> {
    [142, 42, 40, -128, 50].iter().map(|&v| q(v, 1)).collect()
}

const ALL_METHODS: [Simplification; 3] = [
    Simplification::None,
    Simplification::Gcd,
    Simplification::Turner,
];

/// Matrix (4.3): rank 3, the permutations, L, D and U exactly as printed (the printed factors
/// are those of Turner's method with the corrected D update).
#[test]
fn factoring_of_matrix_4_3() {
    let f = ExactLdu::new(Simplification::Turner)
        .factor(&matrix_4_3())
        .expect("factor");
    let ldu = f.ldu();
    assert_eq!(ldu.rank(), 3);
    assert_eq!(ldu.row_perm(), &[1, 2, 0, 3, 4]);
    assert_eq!(ldu.col_perm(), &[0, 1, 3, 2]);
    let (l, d, u) = ldu.dense_factors();
    assert_eq!(
        l,
        ints(&[
            &[-1, 0, 0],
            &[1, 1, 0],
            &[4, 15, -80],
            &[5, 24, -164],
            &[5, 20, -120]
        ])
    );
    assert_eq!(
        d,
        vec![BigInt::from(-1), BigInt::from(-1), BigInt::from(-80)]
    );
    assert_eq!(
        u,
        ints(&[&[-1, -6, -16, -19], &[0, 1, -3, 4], &[0, 0, -80, 0]])
    );
    // Â, the first r rows of Π_R⁻¹ A (4.6).
    assert_eq!(f.independent_rows(), vec![1, 2, 0]);
    // Every method finds the same rank and permutations, and satisfies the invariant.
    for method in ALL_METHODS {
        let f = ExactLdu::new(method).factor(&matrix_4_3()).expect("factor");
        assert_eq!(f.rank(), 3, "{method:?}");
        assert_eq!(f.ldu().row_perm(), &[1, 2, 0, 3, 4], "{method:?}");
        assert_eq!(f.ldu().col_perm(), &[0, 1, 3, 2], "{method:?}");
        let a = matrix_4_3().to_dense();
        let back = f.ldu().reconstruct();
        for (i, row) in a.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                assert_eq!(back[i][j], Rational::from_integer(v.clone()), "{method:?}");
            }
        }
    }
}

/// The GCD method on (4.3) divides the third row of U down to (0, 0, 1, 0).
#[test]
fn gcd_factoring_of_matrix_4_3() {
    let f = ExactLdu::new(Simplification::Gcd)
        .factor(&matrix_4_3())
        .expect("factor");
    let (_, _, u) = f.ldu().dense_factors();
    assert_eq!(
        u,
        ints(&[&[-1, -6, -16, -19], &[0, 1, -3, 4], &[0, 0, 1, 0]])
    );
}

/// Solve (8.17)–(8.22): the system is consistent (8.19) and X = Π_C P = (59, −95/2, 23/2, 0).
///
/// The thesis prints this X as the final P, but (8.9) says P = Π_C⁻¹ X, which swaps the last two
/// entries (Π_C exchanges columns 3 and 4): P = (59, −95/2, 0, 23/2). Only that P satisfies
/// A P = B (the first row gives 142 with it and −7.5 with the printed vector).
#[test]
fn solve_8_17() {
    let a = matrix_4_3().to_dense();
    for method in ALL_METHODS {
        let f = ExactLdu::new(method).factor(&matrix_4_3()).expect("factor");
        f.check_consistent(&rhs_8_17()).expect("consistent");
        let p = f.solve(&rhs_8_17()).expect("solvable");
        let x: Vec<Rational> = f.ldu().col_perm().iter().map(|&c| p[c].clone()).collect();
        assert_eq!(
            x,
            vec![q(59, 1), q(-95, 2), q(23, 2), q(0, 1)],
            "{method:?}"
        );
        assert_eq!(
            p,
            vec![q(59, 1), q(-95, 2), q(0, 1), q(23, 2)],
            "{method:?}"
        );
        for (row, b) in a.iter().zip(rhs_8_17()) {
            let s: Rational = row
                .iter()
                .zip(&p)
                .map(|(aij, pj)| Rational::from_integer(aij.clone()) * pj)
                .sum();
            assert_eq!(s, b);
        }
    }
    // Without machine integers the answer is identical.
    let f = ExactLdu::without_machine_integers(Simplification::Turner)
        .factor(&matrix_4_3())
        .expect("factor");
    assert_eq!(
        f.solve(&rhs_8_17()).expect("solvable"),
        vec![q(59, 1), q(-95, 2), q(0, 1), q(23, 2)]
    );
}

/// Least squares (9.9)–(9.14) with M = 2I and P' = (1, 1, 1, 1): P'' = (3/2, −3/2, −23/2, 23/2).
#[test]
fn least_squares_9_9() {
    let hints = vec![q(1, 1); 4];
    let weights = vec![q(1, 1); 4];
    for method in ALL_METHODS {
        let f = ExactLdu::new(method).factor(&matrix_4_3()).expect("factor");
        let p = f
            .least_squares(&rhs_8_17(), &hints, &weights)
            .expect("solvable");
        assert_eq!(
            p,
            vec![q(3, 2), q(-3, 2), q(-23, 2), q(23, 2)],
            "{method:?}"
        );
    }
}

fn turner_matrix() -> Vec<Vec<Int>> {
    [[8, 7, 4, 1], [4, 6, 7, 3], [6, 3, 4, 6], [4, 5, 8, 2]]
        .iter()
        .map(|r| r.iter().map(|&v| Int::from_i64(v)).collect())
        .collect()
}

/// Section 7.1–7.3: the 4 × 4 example of Turner, U after each stage for the three methods
/// (without exchanges, as worked by hand in the thesis).
#[test]
fn turner_example_stage_by_stage() {
    let (_, none) = Ldu::factor_traced(
        turner_matrix(),
        4,
        Simplification::None,
        Pivoting::FirstNonzero,
    )
    .expect("square");
    assert_eq!(
        none,
        vec![
            ints(&[
                &[8, 7, 4, 1],
                &[0, 20, 40, 20],
                &[0, -18, 8, 42],
                &[0, 12, 48, 12]
            ]),
            ints(&[
                &[8, 7, 4, 1],
                &[0, 20, 40, 20],
                &[0, 0, 880, 1200],
                &[0, 0, 480, 0]
            ]),
            ints(&[
                &[8, 7, 4, 1],
                &[0, 20, 40, 20],
                &[0, 0, 880, 1200],
                &[0, 0, 0, -576000]
            ]),
            ints(&[
                &[8, 7, 4, 1],
                &[0, 20, 40, 20],
                &[0, 0, 880, 1200],
                &[0, 0, 0, -576000]
            ]),
        ]
    );

    let (turner_ldu, turner) = Ldu::factor_traced(
        turner_matrix(),
        4,
        Simplification::Turner,
        Pivoting::FirstNonzero,
    )
    .expect("square");
    assert_eq!(
        turner,
        vec![
            ints(&[
                &[8, 7, 4, 1],
                &[0, 20, 40, 20],
                &[0, -18, 8, 42],
                &[0, 12, 48, 12]
            ]),
            ints(&[
                &[8, 7, 4, 1],
                &[0, 20, 40, 20],
                &[0, 0, 110, 150],
                &[0, 0, 60, 0]
            ]),
            ints(&[
                &[8, 7, 4, 1],
                &[0, 20, 40, 20],
                &[0, 0, 110, 150],
                &[0, 0, 0, -450]
            ]),
            ints(&[
                &[8, 7, 4, 1],
                &[0, 20, 40, 20],
                &[0, 0, 110, 150],
                &[0, 0, 0, -450]
            ]),
        ]
    );
    // Turner's last pivot is the determinant (det = -450 · sign of no exchanges = -450 ... up to
    // the scale of the first row: det(A) = U_44 here).
    assert_eq!(turner_ldu.u_row(3)[3], Int::from_i64(-450));

    // GCD (7.2). The thesis prints the last entry as 1; the row (0, 0, 0, −15) divided by its
    // GCD 15 is (0, 0, 0, −1): the printed sign is a slip.
    let (_, gcd) = Ldu::factor_traced(
        turner_matrix(),
        4,
        Simplification::Gcd,
        Pivoting::FirstNonzero,
    )
    .expect("square");
    assert_eq!(
        gcd,
        vec![
            ints(&[&[8, 7, 4, 1], &[0, 1, 2, 1], &[0, -9, 4, 21], &[0, 1, 4, 1]]),
            ints(&[&[8, 7, 4, 1], &[0, 1, 2, 1], &[0, 0, 11, 15], &[0, 0, 1, 0]]),
            ints(&[
                &[8, 7, 4, 1],
                &[0, 1, 2, 1],
                &[0, 0, 11, 15],
                &[0, 0, 0, -1]
            ]),
            ints(&[
                &[8, 7, 4, 1],
                &[0, 1, 2, 1],
                &[0, 0, 11, 15],
                &[0, 0, 0, -1]
            ]),
        ]
    );
}

/// An inconsistent right-hand side for (4.3) is rejected with a certificate naming the rows
/// that conflict.
#[test]
fn inconsistent_rhs_gets_a_certificate() {
    let mut b = rhs_8_17();
    b[4] = q(51, 1);
    let f = ExactLdu::default().factor(&matrix_4_3()).expect("factor");
    let err = f.solve(&b).expect_err("inconsistent");
    let api::SolveError::Inconsistent(c) = err else {
        panic!("expected an inconsistency, got {err:?}")
    };
    assert!(c.rows.contains(&4));
    // yᵀA = 0 and yᵀb ≠ 0.
    let a = matrix_4_3().to_dense();
    for j in 0..4 {
        let s: Rational = c
            .rows
            .iter()
            .zip(&c.certificate)
            .map(|(&i, y)| y * Rational::from_integer(a[i][j].clone()))
            .sum();
        assert_eq!(s, q(0, 1));
    }
    let yb: Rational = c
        .rows
        .iter()
        .zip(&c.certificate)
        .map(|(&i, y)| y * &b[i])
        .sum();
    assert_eq!(yb, c.discrepancy);
    assert_ne!(yb, q(0, 1));
    assert!(c.certificate.iter().all(|y| y.is_integer()));
}

/// A ragged matrix is a typed error, not a panic.
#[test]
fn ragged_rows_are_rejected() {
    let rows = vec![
        vec![Int::from_i64(1), Int::from_i64(2)],
        vec![Int::from_i64(3)],
    ];
    assert!(matches!(
        Ldu::factor(rows, 2, Simplification::Gcd),
        Err(api::BackendError::DimensionMismatch { .. })
    ));
}
