//! Shared vocabulary of ecles-rs.
//!
//! Every other crate speaks in these terms:
//!
//! * [`exact`]: exact values ([`Integer`], [`Rational`]) and the exact conversion of decimal text;
//! * [`system`]: parameters (scalar or vector), sparse integer constraint rows `Σ c_j p_j = q`
//!   with a label and an origin, and the merged [`ConstraintSystem`];
//! * [`matrix`]: the sparse integer matrix handed to a backend;
//! * [`config`]: reading the RON fragments a host forwards to sources, with positions;
//! * [`input`]: reading input files (meshes, models, height fields) as bounded regular files;
//! * [`source`]: the [`ConstraintSource`] trait constraint plugins implement;
//! * [`view`]: what an interactive editor draws of a source (optional for sources);
//! * [`words`]: machine-word arithmetic of the exact fast paths;
//! * [`backend`]: the traits a linear-algebra backend implements (factor, rank, independent and
//!   redundant rows, solve, weak and strong consistency, null space, weighted least squares).
//!
//! The crate depends on no backend; backends and the ECLES editor depend on it.

pub mod backend;
pub mod config;
pub mod exact;
pub mod input;
pub mod matrix;
mod name_index;
pub mod source;
pub mod system;
pub mod view;
pub mod words;

pub use backend::{
    BackendError, Factorization, Fraction, Inconsistency, IntegerNullSpace, LinearBackend,
    PreparedLeastSquares, RankMargin, Redundancy, RhsFamily, Snapped, SolveError, StrongFailure,
    Value,
};
pub use exact::{
    coprime_integers, format_rational, identical_rationals, parse_rational, rational_difference,
    rational_over_integer, rational_sum, rational_times_integer, Integer, ParseRationalError,
    Rational,
};
pub use matrix::{IntMatrix, MatrixError};
pub use source::SCHEMA_VERSION;
pub use source::{
    BuildRequest, ConstraintSource, Contribution, Highlight, NewParameter, OperationCheckRequest,
    OperationPlan, OutputCheck, OutputCheckRequest, OutputFile, PlanRequest, PlannedStep,
    RenderRequest, SourceError, SourceInfo, StructureParts, SummaryItem,
};
pub use system::{
    ConstraintRow, ConstraintSystem, Coord, Origin, ParamId, Parameter, RowBody, RowId,
    ScalarEquation, SystemError, Values,
};
pub use view::{
    BezierTriangles, Prisms, SourceView, ViewModel, ViewModels, ViewRequest,
    MAX_VIEW_MODEL_VERTICES,
};
