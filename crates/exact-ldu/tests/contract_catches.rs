//! The backend contract is not vacuous: a backend that gets one answer wrong fails the test of
//! that answer.

use api::{
    BackendError, Factorization, IntMatrix, LinearBackend, Rational, Redundancy, RhsFamily,
    SolveError, StrongFailure,
};
use backend_contract::{suite, Contract};
use exact_ldu::{ExactFactorization, ExactLdu};

/// Which answer [`Broken`] gets wrong.
#[derive(Clone, Copy)]
enum Flaw {
    /// Every solution is off by one in its first entry.
    Solve,
    /// Every redundancy coefficient is doubled.
    Redundancies,
    /// The last null-space vector is dropped.
    NullSpace,
    /// Strong consistency always passes.
    Strong,
}

/// The exact backend with one flaw.
struct Broken(Flaw);

/// Its factorization: the exact one, with the flaw applied.
struct BrokenFactorization(ExactFactorization, Flaw);

impl LinearBackend for Broken {
    type Factorization = BrokenFactorization;
    fn name(&self) -> &'static str {
        "broken exact-ldu"
    }
    fn factor(&self, matrix: &IntMatrix) -> Result<BrokenFactorization, BackendError> {
        Ok(BrokenFactorization(
            ExactLdu::default().factor(matrix)?,
            self.0,
        ))
    }
}

impl Factorization for BrokenFactorization {
    type Scalar = Rational;
    type LeastSquares = <ExactFactorization as Factorization>::LeastSquares;
    fn rows(&self) -> usize {
        self.0.rows()
    }
    fn cols(&self) -> usize {
        self.0.cols()
    }
    fn rank(&self) -> usize {
        self.0.rank()
    }
    fn independent_rows(&self) -> Vec<usize> {
        self.0.independent_rows()
    }
    fn redundancies(&self) -> Vec<Redundancy<Rational>> {
        let mut reds = self.0.redundancies();
        if let Flaw::Redundancies = self.1 {
            for red in &mut reds {
                for (_, w) in &mut red.combination {
                    *w = w.clone() * Rational::from_integer(2.into());
                }
            }
        }
        reds
    }
    fn solve(&self, rhs: &[Rational]) -> Result<Vec<Rational>, SolveError<Rational>> {
        let mut x = self.0.solve(rhs)?;
        if let (Flaw::Solve, Some(first)) = (self.1, x.first_mut()) {
            *first += Rational::from_integer(1.into());
        }
        Ok(x)
    }
    fn check_consistent(&self, rhs: &[Rational]) -> Result<(), SolveError<Rational>> {
        self.0.check_consistent(rhs)
    }
    fn check_strongly_consistent(
        &self,
        family: &RhsFamily,
    ) -> Result<Result<(), StrongFailure<Rational>>, BackendError> {
        let verdict = self.0.check_strongly_consistent(family)?;
        Ok(match self.1 {
            Flaw::Strong => Ok(()),
            _ => verdict,
        })
    }
    fn null_space(&self) -> Vec<Vec<Rational>> {
        let mut basis = self.0.null_space();
        if let Flaw::NullSpace = self.1 {
            basis.pop();
        }
        basis
    }
    fn prepare_least_squares(
        &self,
        family: &RhsFamily,
        weights: &[Rational],
    ) -> Result<Self::LeastSquares, BackendError> {
        self.0.prepare_least_squares(family, weights)
    }
}

#[test]
#[should_panic(expected = "broken exact-ldu / solve")]
fn a_wrong_solution_fails_solve() {
    suite::solve(&Broken(Flaw::Solve), &Contract::exact());
}

#[test]
#[should_panic(expected = "broken exact-ldu / redundancies")]
fn a_wrong_combination_fails_redundancies() {
    suite::redundancies(&Broken(Flaw::Redundancies), &Contract::exact());
}

#[test]
#[should_panic(expected = "broken exact-ldu / null_space")]
fn a_missing_kernel_vector_fails_null_space() {
    suite::null_space(&Broken(Flaw::NullSpace), &Contract::exact());
}

#[test]
#[should_panic(expected = "broken exact-ldu / check_strongly_consistent")]
fn a_lenient_strong_check_fails() {
    suite::check_strongly_consistent(&Broken(Flaw::Strong), &Contract::exact());
}
