//! The worked examples of the thesis, with the answers it prints.
//!
//! * (4.3): a `5 × 4` matrix of rank 3 and its printed factoring `Π_R L D⁻¹ U Π_C` (the
//!   factors of Turner's method with the corrected `D` update), the independent rows (4.6);
//! * (8.17)–(8.22): the right-hand side `B`, the intermediate `Y` (8.20) and the solution. The
//!   thesis prints `X = Π_C P = (59, −95/2, 23/2, 0)` as the final `P`; (8.9) says
//!   `P = Π_C⁻¹ X`, which swaps the last two entries: `P = (59, −95/2, 0, 23/2)` is the vector
//!   with `A P = B` (the first row gives 142 with it, −7.5 with the printed one);
//! * (9.9)–(9.14): least squares with `M = 2I` (unit weights) and hints `P' = (1, 1, 1, 1)`:
//!   `P'' = (3/2, −3/2, −23/2, 23/2)`, the unique minimiser;
//! * 7.1–7.3: Turner's `4 × 4` example and the working matrix `U` after every stage of the
//!   three simplification methods, worked by hand without exchanges. In the GCD stages (7.2)
//!   the thesis prints the last entry as 1; the row `(0, 0, 0, −15)` divided by its GCD 15 is
//!   `(0, 0, 0, −1)`: the printed sign is a slip, corrected here.
//!
//! Matrices are [`IntMatrix`]; printed integer tables are `i64`.

use api::{IntMatrix, Rational};

/// An integer table as printed.
pub type Table = Vec<Vec<i64>>;

fn matrix(cols: usize, rows: &[&[i64]]) -> IntMatrix {
    let rows: Table = rows.iter().map(|r| r.to_vec()).collect();
    IntMatrix::from_dense(cols, &rows).expect("the printed matrices are rectangular")
}

fn table(rows: &[&[i64]]) -> Table {
    rows.iter().map(|r| r.to_vec()).collect()
}

fn q(n: i64, d: i64) -> Rational {
    Rational::new(n.into(), d.into())
}

fn integers(values: &[i64]) -> Vec<Rational> {
    values.iter().map(|&v| q(v, 1)).collect()
}

/// The matrix `A` of (4.3), (8.17) and (9.9): `5 × 4`, rank 3.
pub fn matrix_4_3() -> IntMatrix {
    matrix(
        4,
        &[
            &[4, 9, 16, 29],
            &[-1, -6, -19, -16],
            &[1, 5, 15, 19],
            &[5, 6, -1, -12],
            &[5, 10, 15, 20],
        ],
    )
}

/// The rank of (4.3).
pub const RANK_4_3: usize = 3;

/// A factoring `A = Π_R L D⁻¹ U Π_C` as the thesis prints it: `Π_R`, `Π_C` as vectors (position
/// `k` holds row / column `row_perm[k]` / `col_perm[k]` of `A`), `L` with its rows in `Π_R`
/// order, `U` with its columns in `Π_C` order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PrintedFactors {
    /// `Π_R`.
    pub row_perm: Vec<usize>,
    /// `L` (`m × r`).
    pub l: Table,
    /// The diagonal of `D`.
    pub d: Vec<i64>,
    /// `U` (`r × n`).
    pub u: Table,
    /// `Π_C`.
    pub col_perm: Vec<usize>,
}

/// The factoring of (4.3) printed in 4.1 and 8.3 (full pivoting, Turner's simplification).
pub fn factors_4_3() -> PrintedFactors {
    PrintedFactors {
        row_perm: vec![1, 2, 0, 3, 4],
        l: table(&[
            &[-1, 0, 0],
            &[1, 1, 0],
            &[4, 15, -80],
            &[5, 24, -164],
            &[5, 20, -120],
        ]),
        d: vec![-1, -1, -80],
        u: table(&[&[-1, -6, -16, -19], &[0, 1, -3, 4], &[0, 0, -80, 0]]),
        col_perm: vec![0, 1, 3, 2],
    }
}

/// `U` of (4.3) with the GCD method: the third row `(0, 0, −80, 0)` divided down to
/// `(0, 0, 1, 0)`.
pub fn u_4_3_gcd() -> Table {
    table(&[&[-1, -6, -16, -19], &[0, 1, -3, 4], &[0, 0, 1, 0]])
}

/// `Â` of (4.6): the independent rows of (4.3), as rows of `A`.
pub fn independent_rows_4_6() -> Vec<usize> {
    vec![1, 2, 0]
}

/// `B` of (8.17) and (9.9).
pub fn rhs_8_17() -> Vec<Rational> {
    integers(&[142, 42, 40, -128, 50])
}

/// `Y = D L̂⁻¹ B̂` of (8.20).
pub fn y_8_20() -> Vec<Rational> {
    integers(&[42, -82, -920])
}

/// `X = Π_C P` of (8.21)–(8.22), printed there as `P`.
pub fn x_8_22() -> Vec<Rational> {
    vec![q(59, 1), q(-95, 2), q(23, 2), q(0, 1)]
}

/// The basic solution `P = Π_C⁻¹ X` of (8.17) (`X̃ = 0`): `A P = B`.
pub fn solution_8_17() -> Vec<Rational> {
    vec![q(59, 1), q(-95, 2), q(0, 1), q(23, 2)]
}

/// The hints `P'` of (9.11).
pub fn hints_9_11() -> Vec<Rational> {
    integers(&[1, 1, 1, 1])
}

/// The weights of (9.11): `M = 2W = 2I`.
pub fn weights_9_11() -> Vec<Rational> {
    integers(&[1, 1, 1, 1])
}

/// The least-squares solution `P''` of (9.13)–(9.14).
pub fn solution_9_13() -> Vec<Rational> {
    vec![q(3, 2), q(-3, 2), q(-23, 2), q(23, 2)]
}

/// Turner's `4 × 4` example of 7.1–7.3 (full rank).
pub fn turner_7_1() -> IntMatrix {
    matrix(
        4,
        &[&[8, 7, 4, 1], &[4, 6, 7, 3], &[6, 3, 4, 6], &[4, 5, 8, 2]],
    )
}

/// `U` after each of the four stages without simplification (7.1).
pub fn stages_7_1_none() -> Vec<Table> {
    let stage3 = table(&[
        &[8, 7, 4, 1],
        &[0, 20, 40, 20],
        &[0, 0, 880, 1200],
        &[0, 0, 0, -576000],
    ]);
    vec![
        table(&[
            &[8, 7, 4, 1],
            &[0, 20, 40, 20],
            &[0, -18, 8, 42],
            &[0, 12, 48, 12],
        ]),
        table(&[
            &[8, 7, 4, 1],
            &[0, 20, 40, 20],
            &[0, 0, 880, 1200],
            &[0, 0, 480, 0],
        ]),
        stage3.clone(),
        stage3,
    ]
}

/// `U` after each stage with GCD simplification (7.2; the sign slip of the last entry
/// corrected, see the module notes).
pub fn stages_7_2_gcd() -> Vec<Table> {
    let stage3 = table(&[
        &[8, 7, 4, 1],
        &[0, 1, 2, 1],
        &[0, 0, 11, 15],
        &[0, 0, 0, -1],
    ]);
    vec![
        table(&[&[8, 7, 4, 1], &[0, 1, 2, 1], &[0, -9, 4, 21], &[0, 1, 4, 1]]),
        table(&[&[8, 7, 4, 1], &[0, 1, 2, 1], &[0, 0, 11, 15], &[0, 0, 1, 0]]),
        stage3.clone(),
        stage3,
    ]
}

/// `U` after each stage with Turner's simplification (7.3).
pub fn stages_7_3_turner() -> Vec<Table> {
    let stage3 = table(&[
        &[8, 7, 4, 1],
        &[0, 20, 40, 20],
        &[0, 0, 110, 150],
        &[0, 0, 0, -450],
    ]);
    vec![
        table(&[
            &[8, 7, 4, 1],
            &[0, 20, 40, 20],
            &[0, -18, 8, 42],
            &[0, 12, 48, 12],
        ]),
        table(&[
            &[8, 7, 4, 1],
            &[0, 20, 40, 20],
            &[0, 0, 110, 150],
            &[0, 0, 60, 0],
        ]),
        stage3.clone(),
        stage3,
    ]
}

/// The last pivot of Turner's method on 7.1 (without exchanges): the determinant, −450.
pub const DETERMINANT_7_1: i64 = -450;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::oracle;

    fn product(a: &IntMatrix, x: &[Rational]) -> Vec<Rational> {
        oracle::mat_vec(&oracle::dense(a), x)
    }

    /// The printed factors multiply back to (4.3).
    #[test]
    fn the_printed_factoring_of_4_3_is_a_factoring() {
        let a = oracle::dense(&matrix_4_3());
        let f = factors_4_3();
        for (k, l_row) in f.l.iter().enumerate() {
            for c in 0..4 {
                let s: Rational = (0..RANK_4_3).map(|j| q(l_row[j] * f.u[j][c], f.d[j])).sum();
                assert_eq!(s, a[f.row_perm[k]][f.col_perm[c]]);
            }
        }
        assert_eq!(oracle::rank(&a), RANK_4_3);
        let chosen: Vec<Vec<Rational>> = independent_rows_4_6()
            .iter()
            .map(|&i| a[i].clone())
            .collect();
        assert_eq!(oracle::rank(&chosen), RANK_4_3);
    }

    #[test]
    fn the_solutions_of_8_17_and_9_9_satisfy_the_system() {
        let a = matrix_4_3();
        assert_eq!(product(&a, &solution_8_17()), rhs_8_17());
        assert_ne!(product(&a, &x_8_22()), rhs_8_17(), "the printed X is Π_C P");
        let p = solution_8_17();
        let perm = factors_4_3().col_perm;
        let x: Vec<Rational> = perm.iter().map(|&c| p[c].clone()).collect();
        assert_eq!(x, x_8_22());
        assert_eq!(product(&a, &solution_9_13()), rhs_8_17());
        // Optimality: W (P'' − P') is orthogonal to the null space of A.
        let dense = oracle::dense(&a);
        for z in oracle::kernel(&dense, 4) {
            let s: Rational = z
                .iter()
                .zip(solution_9_13().iter().zip(hints_9_11()))
                .map(|(zi, (x, h))| zi * (x - h))
                .sum();
            assert_eq!(s, q(0, 1));
        }
    }

    #[test]
    fn turners_example_has_full_rank() {
        assert_eq!(oracle::rank(&oracle::dense(&turner_7_1())), 4);
        for stages in [stages_7_1_none(), stages_7_2_gcd(), stages_7_3_turner()] {
            assert_eq!(stages.len(), 4);
        }
        assert_eq!(stages_7_3_turner()[3][3][3], DETERMINANT_7_1);
    }
}
