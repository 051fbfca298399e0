//! The worked examples of the thesis, reproduced exactly: what only the exact LDU factoring
//! shows — the printed factors of (4.3), its basic solution of (8.17), and the working matrix of
//! Turner's example after every stage. The equations every backend satisfies on these
//! examples (rank, solutions, certificates, the least squares of (9.9)) are the backend
//! contract's (`tests/contract.rs`); the matrices and printed answers are `backend_contract::thesis`.

use api::{Factorization, LinearBackend, Rational};
use backend_contract::thesis::{self, Table};
use exact_ldu::{ExactLdu, Int, Ldu, Pivoting, Ring, Simplification};
use num_bigint::BigInt;

const ALL_METHODS: [Simplification; 3] = [
    Simplification::None,
    Simplification::Gcd,
    Simplification::Turner,
];

fn ints(table: &Table) -> Vec<Vec<BigInt>> {
    table
        .iter()
        .map(|r| r.iter().map(|&v| BigInt::from(v)).collect())
        .collect()
}

/// Matrix (4.3): rank 3, the permutations, L, D and U exactly as printed (the printed factors
/// are those of Turner's method with the corrected D update).
#[test]
fn factoring_of_matrix_4_3() {
    let printed = thesis::factors_4_3();
    let f = ExactLdu::new(Simplification::Turner)
        .factor(&thesis::matrix_4_3())
        .expect("factor");
    let ldu = f.ldu().expect("factored fraction-free");
    assert_eq!(ldu.rank(), thesis::RANK_4_3);
    assert_eq!(ldu.row_perm(), printed.row_perm.as_slice());
    assert_eq!(ldu.col_perm(), printed.col_perm.as_slice());
    let (l, d, u) = ldu.dense_factors();
    assert_eq!(l, ints(&printed.l));
    assert_eq!(
        d,
        printed
            .d
            .iter()
            .map(|&v| BigInt::from(v))
            .collect::<Vec<_>>()
    );
    assert_eq!(u, ints(&printed.u));
    // Â, the first r rows of Π_R⁻¹ A (4.6).
    assert_eq!(f.independent_rows(), thesis::independent_rows_4_6());
    // Every method finds the same permutations and satisfies the invariant.
    for method in ALL_METHODS {
        let f = ExactLdu::new(method)
            .factor(&thesis::matrix_4_3())
            .expect("factor");
        assert_eq!(
            f.ldu().expect("factored fraction-free").row_perm(),
            printed.row_perm.as_slice(),
            "{method:?}"
        );
        assert_eq!(
            f.ldu().expect("factored fraction-free").col_perm(),
            printed.col_perm.as_slice(),
            "{method:?}"
        );
        let a: Vec<Vec<Rational>> = thesis::matrix_4_3()
            .to_dense()
            .into_iter()
            .map(|row| row.into_iter().map(Rational::from_integer).collect())
            .collect();
        assert_eq!(
            f.ldu().expect("factored fraction-free").reconstruct(),
            a,
            "{method:?}"
        );
    }
}

/// The GCD method on (4.3) divides the third row of U down to (0, 0, 1, 0).
#[test]
fn gcd_factoring_of_matrix_4_3() {
    let f = ExactLdu::new(Simplification::Gcd)
        .factor(&thesis::matrix_4_3())
        .expect("factor");
    let (_, _, u) = f.ldu().expect("factored fraction-free").dense_factors();
    assert_eq!(u, ints(&thesis::u_4_3_gcd()));
}

/// Solve (8.17)–(8.22): the basic solution (`X̃ = 0`) is `P = Π_C⁻¹ X` with the printed
/// `X = (59, −95/2, 23/2, 0)` (see `backend_contract::thesis` for the printed slip), for every
/// method and without machine integers.
#[test]
fn solve_8_17() {
    let b = thesis::rhs_8_17();
    for method in ALL_METHODS {
        let f = ExactLdu::new(method)
            .factor(&thesis::matrix_4_3())
            .expect("factor");
        let p = f.solve(&b).expect("solvable");
        let x: Vec<Rational> = f
            .ldu()
            .expect("factored fraction-free")
            .col_perm()
            .iter()
            .map(|&c| p[c].clone())
            .collect();
        assert_eq!(x, thesis::x_8_22(), "{method:?}");
        assert_eq!(p, thesis::solution_8_17(), "{method:?}");
    }
    let f = ExactLdu::without_machine_integers(Simplification::Turner)
        .factor(&thesis::matrix_4_3())
        .expect("factor");
    assert_eq!(f.solve(&b).expect("solvable"), thesis::solution_8_17());
}

fn turner_matrix() -> Vec<Vec<Int>> {
    thesis::turner_7_1()
        .to_dense()
        .iter()
        .map(|r| r.iter().map(Int::from_bigint).collect())
        .collect()
}

/// Sections 7.1–7.3: the 4 × 4 example of Turner, U after each stage for the three methods
/// (without exchanges, as worked by hand in the thesis).
#[test]
fn turner_example_stage_by_stage() {
    for (method, printed) in [
        (Simplification::None, thesis::stages_7_1_none()),
        (Simplification::Gcd, thesis::stages_7_2_gcd()),
        (Simplification::Turner, thesis::stages_7_3_turner()),
    ] {
        let (ldu, stages) =
            Ldu::factor_traced(turner_matrix(), 4, method, Pivoting::FirstNonzero).expect("square");
        let printed: Vec<Vec<Vec<BigInt>>> = printed.iter().map(ints).collect();
        assert_eq!(stages, printed, "{method:?}");
        if method == Simplification::Turner {
            // Without exchanges Turner's last pivot is the determinant.
            assert_eq!(ldu.u_row(3)[3], Int::from_i64(thesis::DETERMINANT_7_1));
        }
    }
}
