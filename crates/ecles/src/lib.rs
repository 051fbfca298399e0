//! ECLES: Editing by Constrained LEast Squares (thesis, chapter 5).
//!
//! An *editing action* moves a set `A` of anchor parameters to required values; a set `D` of
//! derived parameters follows, as close as possible (weighted least squares) to hints, while every
//! constraint keeps holding exactly; every other parameter stays fixed.
//!
//! * [`extract_relevant`] (algorithm 2) finds the relevant constraints `E` (those that involve
//!   `A ∪ D`) and the fixed relevant parameters `F'`.
//! * [`Edit::initialize`] (algorithm 1) validates the action, factors `R_ED` once, optionally
//!   checks strong solvability (algorithm 3) and prepares the least-squares solve for the family
//!   of right-hand sides `q_E − R_EF' P_F' − R_EA α`.
//! * [`Edit::update`] (algorithm 4) checks weak solvability (algorithm 5) for new anchor values
//!   and solves the least-squares problem for new hints. It is cheap: everything that does not
//!   depend on anchor values and hints was computed by `initialize`.
//! * [`check_moves`]: solvability for the anchor moves actually requested (a translation, a
//!   drag), weaker than strong solvability: what choosing a derived set needs.
//! * [`Edit::update_by`]: the Update under another change criterion (Brenner 3.1: primary
//!   parameters first, least absolute change, fewest changed parameters).
//! * [`Edit::drag`]: a straight drag solved at its two ends; every frame is then an exact
//!   linear interpolation (the solution is affine in the anchor values and hints).
//!
//! Parameters of dimension `d` whose relevant constraints are all vector rows share one
//! factorization for their `d` coordinates ([`Layout::Vector`]); otherwise the edit works on
//! single coordinates ([`Layout::Scalar`]). The crate is generic over the backend and knows
//! nothing about splines.

mod criterion;
mod drag;
mod edit;
mod error;
mod hint_columns;
mod moves;
mod propagation;
mod reduce;
mod relevant;
mod substitute;

pub use criterion::{Criterion, CriterionSummary, Measure, SupportSummary};
pub use drag::Drag;
pub use edit::{Edit, EditSpec, HintedEdit, InitReport, Layout, RowRef, SnapSummary, UpdateResult};
pub use error::{Conflict, ConflictingRow, EditError};
pub use moves::check_moves;
pub use propagation::{
    analyze_propagation, Case, Follows, LostDirection, MoveOutcome, Propagation, PropagationError,
    RowCombination, EXPLAIN_NULL_SPACE_BUDGET, REPORT_NULL_SPACE_BUDGET,
};
pub use reduce::{reduce_edit, ReducedSystem};
pub use relevant::{extract_relevant, Relevant};
