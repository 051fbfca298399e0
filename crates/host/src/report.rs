//! The machine-readable report (`report.json`, `ecles analyze --json`).
//!
//! Field names are a stable contract (documented in the README). Exact values are strings
//! `"p"` or `"p/q"`; floats are plain JSON numbers. Everything is ordered deterministically, so
//! the same run file gives a byte-identical report.

use serde::Serialize;
use std::sync::Arc;

/// The whole report.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// Run file name as given on the command line.
    pub run: String,
    /// Number of scalar parameters (coordinates).
    pub parameters: usize,
    /// Number of scalar constraint rows (equations).
    pub constraints: usize,
    /// Exact rank of the constraint matrix, in scalar equations.
    pub rank: usize,
    /// Degrees of freedom `parameters − rank`.
    pub dof: usize,
    /// Whether `R p = q` has a solution.
    pub consistent: bool,
    /// Whether the current (initial) values satisfy every row exactly.
    pub satisfied: bool,
    /// Rows found dependent, each with its exact combination of independent rows.
    pub redundant: Vec<RedundantRow>,
    /// Labels in the inconsistency certificate, when inconsistent.
    pub conflict: Option<Vec<String>>,
    /// Labels of rows the initial values violate.
    pub violated: Vec<String>,
    /// Per source: plugin and counts.
    pub sources: Vec<SourceReport>,
    /// The float backend's view of the whole system.
    pub cross_check: CrossCheckReport,
    /// Components, Dulmage–Mendelsohn parts and blocks, structural against exact rank.
    pub structure: Option<crate::structural::StructureReport>,
    /// Edits, in run order (empty for `analyze`).
    pub edits: Vec<EditReport>,
    /// Files written by outputs.
    pub outputs: Vec<String>,
    /// What the sources said about the files they wrote (model vertices a deformation left
    /// in place, say), in output order.
    pub output_notes: Vec<OutputNote>,
    /// Totals.
    pub summary: Summary,
}

/// A source's note on one of the files it wrote.
#[derive(Debug, Clone, Serialize)]
pub struct OutputNote {
    /// The file name.
    pub file: String,
    /// The note (one line).
    pub note: String,
}

/// A row that depends on the independent rows.
#[derive(Debug, Clone, Serialize)]
pub struct RedundantRow {
    /// Its label (with `[k]` for coordinate `k` of a vector row split per coordinate).
    pub row: String,
    /// How many scalar equations it stands for: a vector row analysed once for all its
    /// coordinates (a spline's x and y) counts its dimension, any other row 1. Counts in the
    /// report (`constraints`, `rank`, an edit's `relevant`, `rank`, `redundant`) are scalar
    /// equations throughout.
    pub equations: usize,
    /// `row = Σ coefficient · independent row`, exact, whatever its length (combinations of
    /// more than `analysis::COMPACT_ABOVE` terms are written compactly).
    pub combination: Option<Vec<Term>>,
}

/// One term of a combination: one row, or a run of consecutive rows (in the system's order)
/// with the same coefficient.
#[derive(Debug, Clone, Serialize)]
pub struct Term {
    /// Row label (the first row of a run).
    pub row: String,
    /// The last row of a run (absent for a single row).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub through: Option<String>,
    /// The number of rows of a run (absent for a single row).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rows: Option<usize>,
    /// Exact coefficient.
    pub coefficient: String,
}

/// A source of the run.
#[derive(Debug, Clone, Serialize)]
pub struct SourceReport {
    /// Instance name.
    pub name: String,
    /// Plugin kind.
    pub plugin: String,
    /// Plugin version.
    pub version: String,
    /// `"builtin"` or the library path.
    pub loaded_from: String,
    /// Parameters the source declared.
    pub parameters: usize,
    /// Rows the source declared.
    pub rows: usize,
    /// The source's own counts (a spline reports vertices, edges, control points, ...).
    pub counts: std::collections::BTreeMap<String, u64>,
    /// Non-fatal remarks.
    pub warnings: Vec<String>,
}

/// Float backend vs exact on the whole system.
#[derive(Debug, Clone, Serialize, Default)]
pub struct CrossCheckReport {
    /// Whether the cross-check ran.
    pub enabled: bool,
    /// Relative tolerance used.
    pub tolerance: Option<f64>,
    /// The float backend's rank.
    pub float_rank: Option<usize>,
    /// Rank and redundant rows agree.
    pub agree: Option<bool>,
    /// Margin of the float rank decision.
    pub margin: Option<Margin>,
    /// What differs, in words.
    pub disagreements: Vec<String>,
    /// Why it was skipped, if it was.
    pub skipped: Option<String>,
    /// How the float rank was found: `"dense QR"` (column-pivoted Householder, every
    /// component small), `"sparse QR"` (Givens rotations with Heath's rank test, every
    /// component large) or both, per connected component.
    pub method: Option<String>,
}

/// Margin of a float rank decision (diagonal magnitudes relative to the largest).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Margin {
    /// Smallest kept.
    pub smallest_kept: f64,
    /// Largest dropped.
    pub largest_dropped: f64,
}

/// One edit.
#[derive(Debug, Clone, Serialize, Default)]
pub struct EditReport {
    /// Position in the run file.
    pub index: usize,
    /// `"ecles"` or `"source"`.
    pub kind: String,
    /// The source for source operations.
    pub source: Option<String>,
    /// Anchor names.
    pub anchors: Vec<Arc<str>>,
    /// Derived names.
    pub derived: Vec<Arc<str>>,
    /// Number of relevant constraints, in scalar equations.
    pub relevant: usize,
    /// Names of the fixed relevant parameters.
    pub fixed_relevant: Vec<Arc<str>>,
    /// Rank of `R_ED`, in scalar equations.
    pub rank: usize,
    /// Redundant relevant equations (scalar).
    pub redundant: usize,
    /// Whether every step was solvable.
    pub solvable: bool,
    /// Steps run.
    pub steps: usize,
    /// Error message when not solvable.
    pub error: Option<String>,
    /// Conflicting constraints when a step was not solvable.
    pub conflict: Option<Vec<String>>,
    /// Which anchors and constraints clash, in words (empty when solvable).
    pub explanation: Vec<String>,
    /// Dulmage–Mendelsohn view of the relevant subsystem `R_ED`.
    pub structure: Option<crate::structural::EditStructure>,
    /// Final values of anchors and derived parameters (unchanged when not solvable).
    pub values: Vec<ValueReport>,
    /// Largest exact residual over all rows after the edit (`"0"`).
    pub max_residual: String,
    /// Largest difference between float and exact values, relative to `1 + |exact|`.
    pub float_deviation: Option<f64>,
    /// Whether the float backend agreed (verdicts, rank, values within tolerance).
    pub float_agrees: Option<bool>,
    /// How the float cross-check solved the edit: `"dense QR"` (the float backend's own ECLES
    /// edit, for the smallest `R_ED`) or `"sparse QR"` (the sparse twin); absent without a
    /// cross-check.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub float_method: Option<String>,
    /// What differs, in words.
    pub disagreements: Vec<String>,
    /// Facts from the source's planning.
    pub plan: std::collections::BTreeMap<String, u64>,
    /// What a snapped commit wrote instead of the optimum (absent for the default commit of
    /// the optimum).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub snap: Option<SnapReport>,
    /// How the anchors' move propagates (as `ecles explain --move --json` gives it), or why it
    /// was not analysed (`{"skipped": …}`: a component too large).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub propagation: Option<crate::session::EditPropagation>,
    /// The change criterion, when the edit names one other than least squares on every
    /// derived parameter.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub criterion: Option<CriterionReport>,
}

/// What an edit's change criterion chose (Brenner 3.1).
#[derive(Debug, Clone, Serialize)]
pub struct CriterionReport {
    /// `"L2"`, `"L1"` or `"Fewest"`.
    pub measure: String,
    /// Derived parameters that were primary (the measure was minimised over them first); all
    /// of them when the edit names no primary parameters.
    pub primary: Vec<String>,
    /// The measure of the change over the primary parameters, exact: `Σ w·Δ²`, `Σ w·|Δ|` or
    /// the number of changed parameters. Changes are from the hints (the current values
    /// unless hints are given).
    pub value: String,
    /// Derived parameters that changed.
    pub changed: Vec<String>,
    /// L1: whether the optimum is unique, and the dimension of the set of optima (Brenner
    /// figure 3(g)); the values are the vertex the exact simplex reaches.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unique: Option<bool>,
    /// L1: dimension of the set of optimal changes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub optimal_face_dimension: Option<usize>,
    /// Fewest: whether no smaller set of changed parameters exists (false: the exact search
    /// was over its budget and a heuristic answered).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub proven_minimal: Option<bool>,
    /// Fewest: the number of sets of that size that could carry the change (1: no tie).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub minimum_sets: Option<usize>,
    /// Fewest: whether every such set was found (false: `minimum_sets` is a lower bound, the
    /// tie search was over its budget).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ties_complete: Option<bool>,
    /// Fewest: the other sets (at most 31 listed).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub ties: Vec<Vec<String>>,
    /// Fewest: exact rank tests made.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rank_tests: Option<usize>,
}

/// A snapped commit: the values satisfy every constraint exactly (`max_residual` is `"0"`)
/// and lie near the exact least-squares optimum.
#[derive(Debug, Clone, Serialize)]
pub struct SnapReport {
    /// Free values are multiples of `2^−grid_bits`.
    pub grid_bits: u32,
    /// Every derived value is within this distance of the optimum's value (proved exactly by
    /// weak duality, rounded up).
    pub distance_bound: f64,
    /// Right-hand-side columns that could not be snapped and hold the optimum itself.
    pub optimum_columns: usize,
}

impl From<ecles::SnapSummary> for SnapReport {
    fn from(s: ecles::SnapSummary) -> Self {
        SnapReport {
            grid_bits: s.grid_bits,
            distance_bound: s.distance_bound,
            optimum_columns: s.optimum_columns,
        }
    }
}

/// A parameter value.
#[derive(Debug, Clone, Serialize)]
pub struct ValueReport {
    /// Parameter name (the system's, shared).
    pub name: Arc<str>,
    /// Exact coordinates.
    pub exact: Vec<String>,
    /// Float approximations of the exact coordinates.
    pub approx: Vec<f64>,
}

/// Totals.
#[derive(Debug, Clone, Serialize, Default)]
pub struct Summary {
    /// Edits run.
    pub edits: usize,
    /// Edits that were not solvable.
    pub failed: usize,
    /// Places where the float backend disagreed with the exact one.
    pub disagreements: usize,
}
