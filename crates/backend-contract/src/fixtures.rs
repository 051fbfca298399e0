//! Named fixtures: a matrix with the questions the suite asks about it.
//!
//! [`all`] is the set every backend is run on: the thesis' worked examples ([`crate::thesis`])
//! with the answers it prints, and the edge shapes a backend must survive (no rows, no
//! columns, a zero matrix, duplicated and scaled rows, full column rank, a nearly singular
//! block). Random fixtures ([`crate::cases`]) have the same form.

use crate::{oracle, thesis};
use api::{IntMatrix, Rational, RhsFamily};

/// A family `b(α) = c_j − K α` with the parameter values it is evaluated at, and hints and
/// weights for its prepared least squares.
#[derive(Debug, Clone, PartialEq)]
pub struct FamilyCase {
    /// The family.
    pub family: RhsFamily,
    /// Values of `α` (each of length `K.cols()`).
    pub alphas: Vec<Vec<Rational>>,
    /// Hints `h` (length `n`).
    pub hints: Vec<Rational>,
    /// Positive weights (length `n`).
    pub weights: Vec<Rational>,
}

/// A weighted least-squares problem: minimise `Σ w_s (x_s − h_s)²` subject to `A x = b`.
#[derive(Debug, Clone, PartialEq)]
pub struct LeastSquaresCase {
    /// `b`.
    pub rhs: Vec<Rational>,
    /// `h`.
    pub hints: Vec<Rational>,
    /// `w`, positive.
    pub weights: Vec<Rational>,
    /// The minimiser, when the source prints it.
    pub solution: Option<Vec<Rational>>,
}

/// A matrix and the questions asked about it. Verdicts are not stored: the suite decides them
/// with the [`oracle`].
#[derive(Debug, Clone, PartialEq)]
pub struct Fixture {
    /// Where the matrix comes from (`"thesis (4.3)"`, `"duplicate rows"`, `"random"`).
    pub name: String,
    /// `A`.
    pub matrix: IntMatrix,
    /// Right-hand sides to solve and check, consistent and not.
    pub rhs: Vec<Vec<Rational>>,
    /// Families for strong consistency and prepared least squares.
    pub families: Vec<FamilyCase>,
    /// Least-squares problems.
    pub least_squares: Vec<LeastSquaresCase>,
}

fn q(n: i64, d: i64) -> Rational {
    Rational::new(n.into(), d.into())
}

fn dense(cols: usize, rows: &[&[i64]]) -> IntMatrix {
    let rows: Vec<Vec<i64>> = rows.iter().map(|r| r.to_vec()).collect();
    IntMatrix::from_dense(cols, &rows).expect("the fixture matrices are rectangular")
}

/// `K` from its columns (each of length `m`), integer entries.
pub(crate) fn columns_matrix(m: usize, columns: &[Vec<Rational>]) -> IntMatrix {
    let rows: Vec<Vec<(usize, api::Integer)>> = (0..m)
        .map(|i| {
            columns
                .iter()
                .enumerate()
                .filter(|(_, col)| *col[i].numer() != 0.into())
                .map(|(k, col)| (k, col[i].to_integer()))
                .collect()
        })
        .collect();
    IntMatrix::from_sparse(columns.len(), rows).expect("columns index the matrix")
}

/// The unit vector `e_t` of length `m`.
fn unit(m: usize, t: usize) -> Vec<Rational> {
    (0..m).map(|i| q(i64::from(i == t), 1)).collect()
}

/// The first row `t` whose perturbation `b + e_t` makes `A x = b + e_t` inconsistent (a row
/// that depends on the others), if any.
fn dependent_row(a: &[Vec<Rational>], b: &[Rational]) -> Option<usize> {
    (0..b.len()).find(|&t| {
        let mut bad = b.to_vec();
        bad[t] += q(1, 1);
        !oracle::is_consistent(a, &bad)
    })
}

/// The questions every fixture asks, derived from the matrix alone: a consistent right-hand
/// side `A x₀` with fractions, the zero right-hand side, an inconsistent one where a row
/// depends on the others; families with directions in the range of `A` and (when `A` has
/// dependent rows) one out of it, and an inconsistent constant; a weighted least-squares
/// problem.
pub fn derived(name: &str, matrix: IntMatrix) -> Fixture {
    let (m, n) = (matrix.rows(), matrix.cols());
    let a = oracle::dense(&matrix);
    let x0: Vec<Rational> = (0..n as i64).map(|j| q(j % 5 - 2, 1 + j % 3)).collect();
    let b = oracle::mat_vec(&a, &x0);
    let hints: Vec<Rational> = (0..n as i64).map(|j| q(j - 1, 1)).collect();
    let weights: Vec<Rational> = (0..n as i64).map(|j| q(1 + j % 3, 2)).collect();
    let g1: Vec<Rational> = (0..n as i64).map(|j| q(1 - j % 2 * 2, 1)).collect();
    let g2: Vec<Rational> = (0..n as i64).map(|j| q(j % 3 - 1, 1)).collect();
    let in_range = vec![oracle::mat_vec(&a, &g1), oracle::mat_vec(&a, &g2)];
    let alphas = vec![
        vec![q(0, 1), q(0, 1)],
        vec![q(1, 2), q(-3, 1)],
        vec![q(5, 1), q(0, 1)],
    ];
    let case = |constant: Vec<Rational>, columns: &[Vec<Rational>]| FamilyCase {
        family: RhsFamily {
            constant: vec![constant],
            coefficients: columns_matrix(m, columns),
        },
        alphas: alphas.clone(),
        hints: hints.clone(),
        weights: weights.clone(),
    };
    let mut rhs = vec![b.clone(), vec![q(0, 1); m]];
    let mut families = vec![case(b.clone(), &in_range)];
    if let Some(t) = dependent_row(&a, &b) {
        let mut bad = b.clone();
        bad[t] += q(1, 1);
        rhs.push(bad.clone());
        families.push(case(b.clone(), &[in_range[0].clone(), unit(m, t)]));
        families.push(case(bad, &in_range));
    }
    Fixture {
        name: name.to_string(),
        matrix,
        rhs,
        families,
        least_squares: vec![LeastSquaresCase {
            rhs: b,
            hints,
            weights,
            solution: None,
        }],
    }
}

/// (4.3) with the questions of (8.17) and (9.9): `B`, `B` with `b₅ = 51` (inconsistent), the
/// families `c = B` with `K` = column 0 of `A` (in range) and `[column 0 | e₅]`, and the least
/// squares of (9.9)–(9.14) with its printed solution.
pub fn thesis_4_3() -> Fixture {
    let matrix = thesis::matrix_4_3();
    let mut f = derived("thesis (4.3), (8.17), (9.9)", matrix.clone());
    let b = thesis::rhs_8_17();
    let mut bad = b.clone();
    bad[4] = q(51, 1);
    f.rhs.splice(0..0, [b.clone(), bad]);
    let column0 = oracle::column(&matrix, 0);
    let alphas = vec![
        vec![q(0, 1), q(0, 1)],
        vec![q(2, 1), q(0, 1)],
        vec![q(5, 1), q(1, 1)],
    ];
    for columns in [
        vec![column0.clone(), vec![q(0, 1); 5]],
        vec![column0, unit(5, 4)],
    ] {
        f.families.push(FamilyCase {
            family: RhsFamily {
                constant: vec![b.clone()],
                coefficients: columns_matrix(5, &columns),
            },
            alphas: alphas.clone(),
            hints: thesis::hints_9_11(),
            weights: thesis::weights_9_11(),
        });
    }
    f.least_squares.insert(
        0,
        LeastSquaresCase {
            rhs: b,
            hints: thesis::hints_9_11(),
            weights: thesis::weights_9_11(),
            solution: Some(thesis::solution_9_13()),
        },
    );
    f
}

/// Every named fixture.
pub fn all() -> Vec<Fixture> {
    let big = 1_000_000;
    let nearly = 1000;
    vec![
        thesis_4_3(),
        derived("thesis 7.1 (Turner's example)", thesis::turner_7_1()),
        derived("no rows (0 × 3)", IntMatrix::zeros(0, 3)),
        derived("no columns (3 × 0)", IntMatrix::zeros(3, 0)),
        derived("empty (0 × 0)", IntMatrix::zeros(0, 0)),
        derived("zero (2 × 3)", IntMatrix::zeros(2, 3)),
        derived(
            "duplicate rows",
            dense(3, &[&[1, -1, 0], &[1, -1, 0], &[0, 1, -1], &[1, -1, 0]]),
        ),
        derived(
            "full column rank",
            dense(3, &[&[2, 1, 0], &[0, 1, 1], &[1, 0, 3], &[3, 2, 4]]),
        ),
        derived(
            "a copy scaled by 10⁶",
            dense(3, &[&[1, 2, 3], &[big, 2 * big, 3 * big], &[0, 1, 0]]),
        ),
        derived(
            "nearly singular [[K, K+1], [K+1, K+2]], K = 1000",
            dense(2, &[&[nearly, nearly + 1], &[nearly + 1, nearly + 2]]),
        ),
    ]
}

/// The fixture named `name` (panics on an unknown name: fixtures are test data).
pub fn named(name: &str) -> Fixture {
    all()
        .into_iter()
        .find(|f| f.name == name)
        .unwrap_or_else(|| panic!("no fixture named {name:?}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_fixture_is_well_formed() {
        for f in all() {
            let (m, n) = (f.matrix.rows(), f.matrix.cols());
            assert!(f.rhs.iter().all(|b| b.len() == m), "{}", f.name);
            for c in &f.families {
                assert_eq!(c.family.coefficients.rows(), m, "{}", f.name);
                assert!(c.family.constant.iter().all(|b| b.len() == m));
                assert!(c
                    .alphas
                    .iter()
                    .all(|a| a.len() == c.family.coefficients.cols()));
                assert_eq!((c.hints.len(), c.weights.len()), (n, n));
            }
            for l in &f.least_squares {
                assert_eq!((l.rhs.len(), l.hints.len(), l.weights.len()), (m, n, n));
                assert!(oracle::is_consistent(&oracle::dense(&f.matrix), &l.rhs));
            }
        }
        let f = named("thesis (4.3), (8.17), (9.9)");
        let a = oracle::dense(&f.matrix);
        assert!(oracle::is_consistent(&a, &f.rhs[0]));
        assert!(!oracle::is_consistent(&a, &f.rhs[1]));
    }
}
