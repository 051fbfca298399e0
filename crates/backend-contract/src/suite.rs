//! The generic test bodies: one per function of the backend traits, run on every named fixture
//! and on random fixtures, against any [`LinearBackend`].
//!
//! Each `pub fn` here is one test of [`crate::backend_tests!`]; a failure panics with the
//! backend, the test, the fixture (the shrunk random case for random fixtures) and the broken
//! equation.

use crate::cases;
use crate::checks::{self, Check};
use crate::fixtures::{self, Fixture};
use crate::tolerance::{ensure, Contract, Violation};
use api::{
    BackendError, Factorization, LinearBackend, PreparedLeastSquares, Rational, RhsFamily,
    SolveError,
};
use proptest::test_runner::{Config, TestCaseError, TestRunner};

/// A test body on one fixture.
type Body<B> = fn(&B, &Fixture, &Contract) -> Check;

/// Runs `body` on every named fixture, then on `contract.cases` random fixtures.
fn run<B: LinearBackend>(backend: &B, contract: &Contract, test: &str, body: Body<B>) {
    for fixture in fixtures::all() {
        if let Err(v) = body(backend, &fixture, contract) {
            panic!("{} / {test} / {}: {v}", backend.name(), fixture.name);
        }
    }
    let mut runner = TestRunner::new(Config {
        cases: contract.cases,
        failure_persistence: None,
        ..Config::default()
    });
    let result = runner.run(&cases::fixture(contract.max_dim), |fixture| {
        body(backend, &fixture, contract).map_err(|v| TestCaseError::fail(v.0))
    });
    if let Err(e) = result {
        panic!("{} / {test} / random: {e}", backend.name());
    }
}

fn factor<B: LinearBackend>(backend: &B, f: &Fixture) -> Result<B::Factorization, Violation> {
    backend
        .factor(&f.matrix)
        .map_err(|e| Violation(format!("factor refused the matrix: {e}")))
}

/// `LinearBackend::factor` accepts every shape; `rows`, `cols` are `m`, `n`; `name` is set.
pub fn factor_shape<B: LinearBackend>(backend: &B, contract: &Contract) {
    run(backend, contract, "factor_shape", |backend, f, _| {
        ensure(!backend.name().is_empty(), || {
            "the backend has no name".into()
        })?;
        let fz = factor(backend, f)?;
        ensure(
            (fz.rows(), fz.cols()) == (f.matrix.rows(), f.matrix.cols()),
            || {
                format!(
                    "{} × {} for an {} × {} matrix",
                    fz.rows(),
                    fz.cols(),
                    f.matrix.rows(),
                    f.matrix.cols()
                )
            },
        )
    });
}

/// `Factorization::rank` is the rank.
pub fn rank<B: LinearBackend>(backend: &B, contract: &Contract) {
    run(backend, contract, "rank", |backend, f, _| {
        checks::rank(&f.matrix, factor(backend, f)?.rank())
    });
}

/// `Factorization::independent_rows`: `r` independent rows.
pub fn independent_rows<B: LinearBackend>(backend: &B, contract: &Contract) {
    run(backend, contract, "independent_rows", |backend, f, _| {
        let fz = factor(backend, f)?;
        checks::independent_rows(&f.matrix, fz.rank(), &fz.independent_rows())
    });
}

/// `Factorization::redundancies`: every other row as a combination of the independent rows.
pub fn redundancies<B: LinearBackend>(backend: &B, contract: &Contract) {
    run(backend, contract, "redundancies", |backend, f, c| {
        let fz = factor(backend, f)?;
        checks::redundancies(
            &f.matrix,
            &fz.independent_rows(),
            &fz.redundancies(),
            c.tolerance,
        )
    });
}

/// `Factorization::rank_margin`: none for exact backends, a separating threshold otherwise.
pub fn rank_margin<B: LinearBackend>(backend: &B, contract: &Contract) {
    run(backend, contract, "rank_margin", |backend, f, c| {
        let fz = factor(backend, f)?;
        checks::rank_margin(fz.rank(), fz.rank_margin(), c.tolerance)
    });
}

/// `Factorization::solve`: `A x = b`, or a valid certificate.
pub fn solve<B: LinearBackend>(backend: &B, contract: &Contract) {
    run(backend, contract, "solve", |backend, f, c| {
        let fz = factor(backend, f)?;
        for b in &f.rhs {
            checks::solve_answer(&f.matrix, b, &fz.solve(b), c.tolerance)?;
        }
        Ok(())
    });
}

/// `Factorization::check_consistent`: the verdict of the oracle, with a valid certificate.
pub fn check_consistent<B: LinearBackend>(backend: &B, contract: &Contract) {
    run(backend, contract, "check_consistent", |backend, f, c| {
        let fz = factor(backend, f)?;
        for b in &f.rhs {
            checks::consistency_answer(&f.matrix, b, &fz.check_consistent(b), c.tolerance)?;
        }
        Ok(())
    });
}

/// `Factorization::check_strongly_consistent`: `Ok` exactly when every direction and constant
/// is in the range, failures blamed on one that is not, directions first.
pub fn check_strongly_consistent<B: LinearBackend>(backend: &B, contract: &Contract) {
    run(
        backend,
        contract,
        "check_strongly_consistent",
        |backend, f, c| {
            let fz = factor(backend, f)?;
            for case in &f.families {
                let answer = fz.check_strongly_consistent(&case.family);
                checks::strong_answer(&f.matrix, &case.family, &answer, c.tolerance)?;
            }
            Ok(())
        },
    );
}

/// `Factorization::null_space`: a basis of the kernel.
pub fn null_space<B: LinearBackend>(backend: &B, contract: &Contract) {
    run(backend, contract, "null_space", |backend, f, c| {
        checks::null_space(&f.matrix, &factor(backend, f)?.null_space(), c.tolerance)
    });
}

/// `Factorization::least_squares`: the constrained minimiser (the printed one where the thesis
/// prints it), or a valid certificate for an inconsistent right-hand side.
pub fn least_squares<B: LinearBackend>(backend: &B, contract: &Contract) {
    run(backend, contract, "least_squares", |backend, f, c| {
        let fz = factor(backend, f)?;
        for l in &f.least_squares {
            let answer = fz.least_squares(&l.rhs, &l.hints, &l.weights);
            checks::least_squares_answer(
                &f.matrix,
                &l.rhs,
                &l.hints,
                &l.weights,
                &answer,
                c.tolerance,
            )?;
            if let (Some(want), Ok(x)) = (&l.solution, &answer) {
                checks::equals(x, want, c.tolerance)?;
            }
        }
        let Some(first) = f.least_squares.first() else {
            return Ok(());
        };
        for b in &f.rhs {
            let answer = fz.least_squares(b, &first.hints, &first.weights);
            checks::least_squares_answer(
                &f.matrix,
                b,
                &first.hints,
                &first.weights,
                &answer,
                c.tolerance,
            )?;
        }
        Ok(())
    });
}

/// Every `(column, α)` of every family of `f`, with `b(α) = c_j − K α`.
fn evaluations(f: &Fixture) -> Vec<(usize, usize, Vec<Rational>, Vec<Rational>)> {
    let mut out = Vec::new();
    for (k, case) in f.families.iter().enumerate() {
        for column in 0..case.family.constant.len() {
            for alpha in &case.alphas {
                let b = checks::family_rhs(&case.family, column, alpha);
                out.push((k, column, alpha.clone(), b));
            }
        }
    }
    out
}

fn prepare<F: Factorization>(fz: &F, f: &Fixture) -> Result<Vec<F::LeastSquares>, Violation> {
    f.families
        .iter()
        .map(|case| {
            fz.prepare_least_squares(&case.family, &case.weights)
                .map_err(|e| Violation(format!("a valid family refused: {e}")))
        })
        .collect()
}

/// `Factorization::prepare_least_squares` and `PreparedLeastSquares::check`: the weak
/// consistency of `A x = c_j − K α`.
pub fn prepared_check<B: LinearBackend>(backend: &B, contract: &Contract) {
    run(backend, contract, "prepared_check", |backend, f, c| {
        let fz = factor(backend, f)?;
        let prepared = prepare(&fz, f)?;
        for (k, column, alpha, b) in evaluations(f) {
            checks::consistency_answer(
                &f.matrix,
                &b,
                &prepared[k].check(column, &alpha),
                c.tolerance,
            )?;
        }
        Ok(())
    });
}

/// `PreparedLeastSquares::solve`: the minimiser for `b(α)`, or a valid certificate.
pub fn prepared_solve<B: LinearBackend>(backend: &B, contract: &Contract) {
    run(backend, contract, "prepared_solve", |backend, f, c| {
        let fz = factor(backend, f)?;
        let prepared = prepare(&fz, f)?;
        for (k, column, alpha, b) in evaluations(f) {
            let case = &f.families[k];
            let answer = prepared[k].solve(column, &alpha, &case.hints);
            checks::least_squares_answer(
                &f.matrix,
                &b,
                &case.hints,
                &case.weights,
                &answer,
                c.tolerance,
            )?;
        }
        Ok(())
    });
}

/// `PreparedLeastSquares::solve_approx`: the verdict and (rounded) values of `solve`.
pub fn prepared_solve_approx<B: LinearBackend>(backend: &B, contract: &Contract) {
    run(
        backend,
        contract,
        "prepared_solve_approx",
        |backend, f, _| {
            let fz = factor(backend, f)?;
            let prepared = prepare(&fz, f)?;
            for (k, column, alpha, _) in evaluations(f) {
                let hints = &f.families[k].hints;
                checks::approximation(
                    &prepared[k].solve(column, &alpha, hints),
                    &prepared[k].solve_approx(column, &alpha, hints),
                )?;
            }
            Ok(())
        },
    );
}

fn is_dimension_mismatch<S: std::fmt::Debug>(
    r: &Result<impl std::fmt::Debug, SolveError<S>>,
) -> bool {
    matches!(
        r,
        Err(SolveError::Input(BackendError::DimensionMismatch { .. }))
    )
}

/// Malformed questions are typed errors, never panics or answers: wrong lengths, non-positive
/// weights, a family of the wrong height, a column or `α` the family does not have.
pub fn input_errors<B: LinearBackend>(backend: &B, contract: &Contract) {
    run(backend, contract, "input_errors", |backend, f, _| {
        let fz = factor(backend, f)?;
        let (m, n) = (f.matrix.rows(), f.matrix.cols());
        let zero = Rational::from_integer(0.into());
        let one = Rational::from_integer(1.into());
        let long_rhs = vec![zero.clone(); m + 1];
        ensure(
            matches!(
                fz.solve(&long_rhs),
                Err(SolveError::Input(BackendError::DimensionMismatch { expected, found, .. }))
                    if expected == m && found == m + 1
            ),
            || "solve accepted a right-hand side of length m + 1".into(),
        )?;
        ensure(
            is_dimension_mismatch(&fz.check_consistent(&long_rhs)),
            || "check_consistent accepted a right-hand side of length m + 1".into(),
        )?;
        let b = vec![zero.clone(); m];
        let ones = vec![one.clone(); n];
        ensure(
            is_dimension_mismatch(&fz.least_squares(&b, &vec![zero.clone(); n + 1], &ones)),
            || "least_squares accepted n + 1 hints".into(),
        )?;
        ensure(
            is_dimension_mismatch(&fz.least_squares(&b, &ones, &vec![one.clone(); n + 1])),
            || "least_squares accepted n + 1 weights".into(),
        )?;
        if n > 0 {
            let mut weights = ones.clone();
            weights[n - 1] = zero.clone();
            ensure(
                matches!(
                    fz.least_squares(&b, &ones, &weights),
                    Err(SolveError::Input(BackendError::NonPositiveWeight { index, .. })) if index == n - 1
                ),
                || "least_squares accepted a zero weight".into(),
            )?;
            weights[n - 1] = one.clone();
            weights[0] = -one.clone();
            ensure(
                matches!(
                    fz.prepare_least_squares(&RhsFamily::single(b.clone()), &weights),
                    Err(BackendError::NonPositiveWeight { index: 0, .. })
                ),
                || "prepare_least_squares accepted a negative weight".into(),
            )?;
        }
        let tall = RhsFamily::single(long_rhs);
        ensure(
            matches!(
                fz.check_strongly_consistent(&tall),
                Err(BackendError::DimensionMismatch { .. })
            ),
            || "check_strongly_consistent accepted a family of m + 1 rows".into(),
        )?;
        ensure(
            matches!(
                fz.prepare_least_squares(&tall, &ones),
                Err(BackendError::DimensionMismatch { .. })
            ),
            || "prepare_least_squares accepted a family of m + 1 rows".into(),
        )?;
        let prepared = fz
            .prepare_least_squares(&RhsFamily::single(b), &ones)
            .map_err(|e| Violation(format!("a valid family refused: {e}")))?;
        ensure(
            matches!(
                prepared.solve(1, &[], &ones),
                Err(SolveError::Input(BackendError::NoSuchColumn {
                    column: 1,
                    columns: 1
                }))
            ),
            || "a prepared solve accepted column 1 of a one-column family".into(),
        )?;
        ensure(
            matches!(
                prepared.check(1, &[]),
                Err(SolveError::Input(BackendError::NoSuchColumn { .. }))
            ),
            || "a prepared check accepted column 1 of a one-column family".into(),
        )?;
        ensure(
            is_dimension_mismatch(&prepared.solve(0, &[one], &ones)),
            || "a prepared solve accepted α for a family without parameters".into(),
        )?;
        ensure(
            is_dimension_mismatch(&prepared.solve(0, &[], &vec![zero; n + 1])),
            || "a prepared solve accepted n + 1 hints".into(),
        )
    });
}
