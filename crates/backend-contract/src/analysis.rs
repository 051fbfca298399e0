//! The part of the contract a whole-system analysis answers without a factorization: rank,
//! independent rows, redundancies and the consistency of right-hand sides (the sparse
//! elimination of `exact-ldu` is one).
//!
//! A [`RankAnalysis`] is checked with the same equations as the full backends
//! ([`crate::checks`]), on the same fixtures; [`crate::analysis_tests!`] generates the tests.

use crate::cases;
use crate::checks::{self, Check};
use crate::fixtures::{self, Fixture};
use crate::tolerance::{ensure, Contract};
use api::{IntMatrix, Rational, Redundancy, Value};
use proptest::test_runner::{Config, TestCaseError, TestRunner};

/// What a [`RankAnalysis`] answers about a matrix and some right-hand sides.
#[derive(Debug, Clone, PartialEq)]
pub struct Analysis<S> {
    /// The rank `r`.
    pub rank: usize,
    /// `r` independent rows.
    pub independent_rows: Vec<usize>,
    /// Every other row, with its combination of the independent rows.
    pub redundancies: Vec<Redundancy<S>>,
    /// Per right-hand side: whether `A x = b` has a solution.
    pub consistent: Vec<bool>,
}

/// An analysis that answers rank, redundancy and consistency questions.
pub trait RankAnalysis {
    /// Number type of the combinations.
    type Scalar: Value;
    /// Short name for failures.
    fn name(&self) -> &'static str;
    /// Analyses `matrix` with the right-hand sides `rhs` (each of length `m`).
    fn analyse(&self, matrix: &IntMatrix, rhs: &[Vec<Rational>]) -> Analysis<Self::Scalar>;
}

type Body<A> = fn(&A, &Fixture, &Contract) -> Check;

fn run<A: RankAnalysis>(analysis: &A, contract: &Contract, test: &str, body: Body<A>) {
    for fixture in fixtures::all() {
        if let Err(v) = body(analysis, &fixture, contract) {
            panic!("{} / {test} / {}: {v}", analysis.name(), fixture.name);
        }
    }
    let mut runner = TestRunner::new(Config {
        cases: contract.cases,
        failure_persistence: None,
        ..Config::default()
    });
    let result = runner.run(&cases::fixture(contract.max_dim), |fixture| {
        body(analysis, &fixture, contract).map_err(|v| TestCaseError::fail(v.0))
    });
    if let Err(e) = result {
        panic!("{} / {test} / random: {e}", analysis.name());
    }
}

/// The rank.
pub fn rank<A: RankAnalysis>(analysis: &A, contract: &Contract) {
    run(analysis, contract, "rank", |analysis, f, _| {
        checks::rank(&f.matrix, analysis.analyse(&f.matrix, &f.rhs).rank)
    });
}

/// `r` independent rows.
pub fn independent_rows<A: RankAnalysis>(analysis: &A, contract: &Contract) {
    run(analysis, contract, "independent_rows", |analysis, f, _| {
        let answer = analysis.analyse(&f.matrix, &f.rhs);
        checks::independent_rows(&f.matrix, answer.rank, &answer.independent_rows)
    });
}

/// Every other row as a combination of the independent rows.
pub fn redundancies<A: RankAnalysis>(analysis: &A, contract: &Contract) {
    run(analysis, contract, "redundancies", |analysis, f, c| {
        let answer = analysis.analyse(&f.matrix, &f.rhs);
        checks::redundancies(
            &f.matrix,
            &answer.independent_rows,
            &answer.redundancies,
            c.tolerance,
        )
    });
}

/// One verdict per right-hand side, the oracle's.
pub fn consistency<A: RankAnalysis>(analysis: &A, contract: &Contract) {
    run(analysis, contract, "consistency", |analysis, f, _| {
        let answer = analysis.analyse(&f.matrix, &f.rhs);
        ensure(answer.consistent.len() == f.rhs.len(), || {
            format!(
                "{} verdicts for {} right-hand sides",
                answer.consistent.len(),
                f.rhs.len()
            )
        })?;
        let a = crate::oracle::dense(&f.matrix);
        for (k, (b, &verdict)) in f.rhs.iter().zip(&answer.consistent).enumerate() {
            let want = crate::oracle::is_consistent(&a, b);
            ensure(verdict == want, || {
                format!("right-hand side {k}: consistent {verdict}, the oracle says {want}")
            })?;
        }
        Ok(())
    });
}
