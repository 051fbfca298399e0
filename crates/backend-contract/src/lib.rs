//! The backend contract: what every [`api::LinearBackend`] must answer, checked the same way
//! for all of them.
//!
//! * [`thesis`]: the worked examples of the thesis with the answers it prints — (4.3) and its
//!   factoring, (8.17) and its solution, (9.9)–(9.14) least squares, Turner's example of 7.1–7.3
//!   stage by stage — the one copy of those matrices in the workspace;
//! * [`fixtures`]: named fixtures (the thesis examples and edge shapes) with the questions
//!   asked about them; [`cases`]: random fixtures of the same form (proptest);
//! * [`oracle`]: an independent rational Gauss–Jordan elimination that decides ranks,
//!   consistency and kernels;
//! * [`checks`]: the defining equation of every answer (`A x = b`, `yᵀA = 0 ≠ yᵀb`,
//!   `A N = 0`, `W (x − h) ⟂ ker A`, …), exactly or within a [`Tolerance`];
//! * [`suite`]: one generic test body per function of the traits (`rank`, `independent_rows`,
//!   `redundancies`, `rank_margin`, `solve`, `check_consistent`, `check_strongly_consistent`,
//!   `null_space`, `least_squares`, `prepare_least_squares` with `check`, `solve` and
//!   `solve_approx`, and the typed input errors), each run on every named fixture and on
//!   random ones;
//! * [`analysis`]: the rank, redundancy and consistency part for analyses that are not full
//!   backends (the sparse elimination).
//!
//! # Adding a backend
//!
//! One line in a test file of the backend's crate (with this crate as a dev-dependency) gives
//! it the whole suite, as a module of `#[test]`s:
//!
//! ```ignore
//! use backend_contract::{backend_tests, Contract};
//! backend_tests!(my_backend: MyBackend::new(), Contract::exact());
//! // A floating-point backend compares within a relative tolerance:
//! backend_tests!(my_float_backend: MyFloatBackend::default(), Contract::float(1e-8));
//! ```
//!
//! [`Contract::exact`] also checks the promises only an exact backend makes (primitive integer
//! certificates on a minimal conflicting set, a primitive integer null space);
//! [`Contract::max_dim`] bounds the random matrices for backends whose cost explodes.

pub mod analysis;
pub mod cases;
pub mod checks;
pub mod fixtures;
pub mod oracle;
pub mod suite;
pub mod thesis;
mod tolerance;

pub use tolerance::{Contract, Tolerance, Violation};

/// The whole [`suite`] for one backend, as a module `$module` of `#[test]` functions named
/// after the trait functions they check.
///
/// `backend_tests!(name: backend_expression, contract_expression);` — the expressions are
/// evaluated inside the module, which sees the names of the enclosing one.
#[macro_export]
macro_rules! backend_tests {
    ($module:ident: $backend:expr, $contract:expr $(,)?) => {
        mod $module {
            #[allow(unused_imports)]
            use super::*;
            $crate::backend_tests!(@each $backend, $contract;
                factor_shape rank independent_rows redundancies rank_margin solve
                check_consistent check_strongly_consistent null_space least_squares
                prepared_check prepared_solve prepared_solve_approx input_errors);
        }
    };
    (@each $backend:expr, $contract:expr; $($test:ident)*) => {
        $(
            #[test]
            fn $test() {
                $crate::suite::$test(&$backend, &$contract);
            }
        )*
    };
}

/// The [`analysis`] part of the contract for one [`analysis::RankAnalysis`], as a module of
/// `#[test]` functions: `analysis_tests!(name: analysis_expression, contract_expression);`.
#[macro_export]
macro_rules! analysis_tests {
    ($module:ident: $analysis:expr, $contract:expr $(,)?) => {
        mod $module {
            #[allow(unused_imports)]
            use super::*;
            $crate::analysis_tests!(@each $analysis, $contract;
                rank independent_rows redundancies consistency);
        }
    };
    (@each $analysis:expr, $contract:expr; $($test:ident)*) => {
        $(
            #[test]
            fn $test() {
                $crate::analysis::$test(&$analysis, &$contract);
            }
        )*
    };
}
