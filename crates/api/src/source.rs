//! Constraint sources: the plugins that contribute parameters and integer rows.
//!
//! A source is built once from its configuration (RON text, its own schema) and contributes
//! new parameters with initial values and rows, possibly on parameters of earlier sources
//! (looked up by name in [`BuildRequest::system`]). It may then plan source-specific edits
//! (a spline's soft translation, say) as ECLES edits, and render outputs (pictures, deformed
//! models) as bytes for the host to write. Sources do no file I/O beyond reading the inputs their
//! configuration names, and never print.
//!
//! Every request and answer is plain serialisable data, so the same trait works in process and
//! across the C ABI of dynamic plugins (which exchange these types as JSON).

use crate::config::TextPosition;
use crate::exact::Rational;
use crate::system::{ConstraintRow, ConstraintSystem, ParamId, Values};
use crate::view::{SourceView, ViewRequest};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// The version of the JSON payloads (requests and answers) exchanged with sources, in process
/// and across the plugin ABI. It changes whenever a request or answer type changes its
/// serialised form (the golden fixtures of `plugin-abi` fail until it does); plugins refuse
/// requests of a newer schema than they know, naming both. History: 1, the first payloads;
/// 2, input limits, the checks before the first edit, error positions, source inputs. Fields
/// added since with serde defaults, which older plugins ignore and whose absence newer ones
/// read as the default, keep 2: the view's outputs and models ([`crate::view`]), and the
/// models' relative heights (absent from the JSON when empty, so planar views serialise as
/// before). The `prisms` view kind came within 2 too: it is an answer only the terrain source
/// gives, so no request changes and every earlier view reads as before; a host built before
/// it cannot decode a prism view and reports that one answer as malformed, naming the plugin
/// (its editor shows that error in place of the view and draws nothing of the source), while
/// every other payload is unchanged.
pub const SCHEMA_VERSION: u32 = 2;

fn schema_v1() -> u32 {
    1
}

/// An earlier source of the same run, for sources that build on another one.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SourceInfo {
    /// Instance name (unique in the run).
    pub name: String,
    /// Plugin kind (`"spline2d"`, `"linear"`, ...).
    pub kind: String,
    /// Its configuration text.
    pub config: String,
}

/// What a source is built from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BuildRequest {
    /// The payload schema the host speaks ([`SCHEMA_VERSION`]; 1 when absent, from hosts
    /// before the field existed).
    #[serde(default = "schema_v1")]
    pub schema: u32,
    /// Instance name: the prefix of the source's parameter names and row labels.
    pub name: String,
    /// Configuration as RON text.
    pub config: String,
    /// Directory relative paths in the configuration are resolved against (the run file's).
    pub base_dir: PathBuf,
    /// The system as built by the earlier sources.
    pub system: ConstraintSystem,
    /// Current values of the earlier sources' parameters.
    pub values: Values,
    /// The earlier sources.
    pub sources: Vec<SourceInfo>,
    /// Largest input file the source may read, in bytes (see [`crate::input`]).
    #[serde(default = "default_input_limit")]
    pub input_limit: u64,
}

fn default_input_limit() -> u64 {
    crate::input::DEFAULT_MAX_INPUT_BYTES
}

/// A new parameter with its initial value (its dimension is the value's length).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct NewParameter {
    /// Unique name.
    pub name: String,
    /// Initial exact value.
    pub value: Vec<Rational>,
}

/// A count or fact for the run report (`"control_points"`, 121).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SummaryItem {
    /// Stable field name.
    pub key: String,
    /// Value.
    pub value: u64,
}

impl SummaryItem {
    /// Summary items from `(key, count)` pairs, sorted by key: the order reports list a
    /// contribution's facts in, whatever order a source gathers them.
    pub fn sorted<'a>(pairs: impl IntoIterator<Item = (&'a str, usize)>) -> Vec<SummaryItem> {
        let mut pairs: Vec<(&str, usize)> = pairs.into_iter().collect();
        pairs.sort();
        pairs
            .into_iter()
            .map(|(key, value)| SummaryItem {
                key: key.to_string(),
                value: value as u64,
            })
            .collect()
    }
}

/// What a source adds to the system.
///
/// Rows refer to existing parameters by their ids and to new ones by
/// `ParamId(existing + k)` for the `k`-th entry of `parameters`, where `existing` is the number
/// of parameters in [`BuildRequest::system`].
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Contribution {
    /// New parameters, in id order.
    pub parameters: Vec<NewParameter>,
    /// New rows.
    pub rows: Vec<ConstraintRow>,
    /// Counts for the report.
    pub summary: Vec<SummaryItem>,
    /// Non-fatal remarks (an unused mesh vertex, a flipped triangle), for the report.
    pub warnings: Vec<String>,
    /// The files the source read (meshes, say), so the host never lets an output overwrite
    /// them. Optional in the JSON exchanged with dynamic plugins.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub inputs: Vec<PathBuf>,
}

impl Contribution {
    /// Adds the parameters and rows to `system` and `values`, all or nothing: on any error
    /// both are left unchanged. See [`Contribution::apply_into`], which moves them.
    pub fn apply_to(
        &self,
        system: &mut ConstraintSystem,
        values: &mut Values,
    ) -> Result<(), crate::system::SystemError> {
        self.clone().apply_into(system, values)
    }

    /// [`Contribution::apply_to`] moving the parameters and rows in: nothing of the system is
    /// copied (a failure truncates what was added), so a source that adds a million rows costs
    /// one copy of them, not three.
    pub fn apply_into(
        self,
        system: &mut ConstraintSystem,
        values: &mut Values,
    ) -> Result<(), crate::system::SystemError> {
        let (params, rows) = (system.params().len(), system.rows().len());
        system.reserve_exact(self.parameters.len());
        values.reserve_exact(self.parameters.len());
        let added = (|| {
            for p in self.parameters {
                let id = system.add_parameter(p.name, p.value.len())?;
                values.push(system, id, p.value)?;
            }
            system.add_rows(self.rows)
        })();
        if added.is_err() {
            system.truncate(params, rows);
            values.truncate(params);
        }
        added
    }
}

/// A source-specific edit to plan (the operation as RON text in the source's own schema).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanRequest {
    /// The payload schema the host speaks ([`SCHEMA_VERSION`]; 1 when absent, from hosts
    /// before the field existed).
    #[serde(default = "schema_v1")]
    pub schema: u32,
    /// The operation.
    pub operation: String,
    /// The whole system.
    pub system: ConstraintSystem,
    /// Current values.
    pub values: Values,
}

/// Anchor values and hints of one step of a planned edit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlannedStep {
    /// New values of the anchors, in [`OperationPlan::anchors`] order.
    pub anchors: Vec<Vec<Rational>>,
    /// Hints of the derived parameters, in [`OperationPlan::derived`] order.
    pub hints: Vec<Vec<Rational>>,
}

/// An ECLES edit planned by a source.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OperationPlan {
    /// Anchor parameters.
    pub anchors: Vec<ParamId>,
    /// Derived parameters.
    pub derived: Vec<ParamId>,
    /// One positive weight per derived parameter.
    pub weights: Vec<Rational>,
    /// Whether the host should run the strong-solvability check.
    pub strong: bool,
    /// Steps of the drag, each from the state at initialisation.
    pub steps: Vec<PlannedStep>,
    /// Facts about the planning (points added to the derived set, ...), for the report.
    pub summary: Vec<SummaryItem>,
}

impl OperationPlan {
    /// Checks the plan against `system` before the host uses it: at least one anchor, every id
    /// a parameter of `system`, no parameter twice (nor both anchor and derived), one positive
    /// weight per derived parameter, at least one step, and every step giving one value of the
    /// right dimension per anchor and one hint per derived parameter. A plugin's answer is
    /// data from outside the host: nothing indexes with its ids before this passes.
    pub fn validate(&self, system: &ConstraintSystem) -> Result<(), String> {
        if self.anchors.is_empty() {
            return Err("the plan has no anchors".into());
        }
        let mut seen = std::collections::BTreeSet::new();
        let mut dims = |ids: &[ParamId]| -> Result<Vec<usize>, String> {
            ids.iter()
                .map(|id| {
                    let param = system.param(*id).ok_or_else(|| {
                        format!("the plan names parameter {id}, which does not exist")
                    })?;
                    if !seen.insert(*id) {
                        return Err(format!("the plan names {:?} twice", param.name));
                    }
                    Ok(param.dim)
                })
                .collect()
        };
        let anchor_dims = dims(&self.anchors)?;
        let derived_dims = dims(&self.derived)?;
        if self.weights.len() != self.derived.len() {
            return Err(format!(
                "{} weights for {} derived parameters",
                self.weights.len(),
                self.derived.len()
            ));
        }
        if let Some(w) = self
            .weights
            .iter()
            .find(|w| **w <= Rational::from_integer(0.into()))
        {
            return Err(format!(
                "weight {} is not positive",
                crate::exact::format_rational(w)
            ));
        }
        if self.steps.is_empty() {
            return Err("the plan has no steps".into());
        }
        for (k, step) in self.steps.iter().enumerate() {
            let sizes =
                |values: &[Vec<Rational>]| -> Vec<usize> { values.iter().map(Vec::len).collect() };
            if sizes(&step.anchors) != anchor_dims || sizes(&step.hints) != derived_dims {
                return Err(format!(
                    "step {k} does not give one value of the right dimension per anchor and derived parameter"
                ));
            }
        }
        Ok(())
    }
}

/// Outputs to render for the current state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RenderRequest {
    /// The payload schema the host speaks ([`SCHEMA_VERSION`]; 1 when absent, from hosts
    /// before the field existed).
    #[serde(default = "schema_v1")]
    pub schema: u32,
    /// What to render, as RON text in the source's own schema.
    pub output: String,
    /// Directory relative paths in the request are resolved against.
    pub base_dir: PathBuf,
    /// The whole system.
    pub system: ConstraintSystem,
    /// Values before the edits of the run.
    pub initial: Values,
    /// Current values.
    pub values: Values,
    /// Parameters and rows of the last edit, to highlight.
    pub highlight: Option<Highlight>,
    /// The Dulmage–Mendelsohn parts of the whole system, for pictures coloured by part.
    pub structure: Option<StructureParts>,
    /// Largest input file the source may read, in bytes (see [`crate::input`]).
    #[serde(default = "default_input_limit")]
    pub input_limit: u64,
}

/// An operation to check before the first edit of a run runs: everything about it that does
/// not depend on the values at its turn (its schema, the anchors it names, its numbers and
/// their limits).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct OperationCheckRequest {
    /// The payload schema the host speaks ([`SCHEMA_VERSION`]; 1 when absent, from hosts
    /// before the field existed).
    #[serde(default = "schema_v1")]
    pub schema: u32,
    /// The operation, as RON text in the source's own schema.
    pub operation: String,
}

/// An output to check before the first edit of a run runs: its schema, and the files it
/// reads (which are read and validated now) and writes.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct OutputCheckRequest {
    /// The payload schema the host speaks ([`SCHEMA_VERSION`]; 1 when absent, from hosts
    /// before the field existed).
    #[serde(default = "schema_v1")]
    pub schema: u32,
    /// What to render, as RON text in the source's own schema.
    pub output: String,
    /// Directory relative paths in the request are resolved against.
    pub base_dir: PathBuf,
    /// Largest input file the source may read, in bytes (see [`crate::input`]).
    #[serde(default = "default_input_limit")]
    pub input_limit: u64,
}

/// What a checked output will do.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct OutputCheck {
    /// Whether the source checked the output. `false` only from plugins built before checks
    /// existed (their outputs are checked when rendered); then the lists are empty.
    #[serde(default)]
    pub checked: bool,
    /// Names of the files rendering will produce, in order.
    #[serde(default)]
    pub files: Vec<String>,
    /// Input files rendering will read (resolved against the base directory).
    #[serde(default)]
    pub inputs: Vec<PathBuf>,
}

impl OutputCheck {
    /// A checked output writing `files` and reading `inputs`.
    pub fn new(files: Vec<String>, inputs: Vec<PathBuf>) -> Self {
        OutputCheck {
            checked: true,
            files,
            inputs,
        }
    }
}

/// Parameters and rows by Dulmage–Mendelsohn part (a parameter is in the part of any of its
/// coordinates, the more constrained part winning).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct StructureParts {
    /// Parameters in the over-determined part.
    pub over: Vec<ParamId>,
    /// Parameters in the well-determined part.
    pub well: Vec<ParamId>,
    /// Rows in the over-determined part.
    pub over_rows: Vec<crate::system::RowId>,
    /// Rows in the well-determined part.
    pub well_rows: Vec<crate::system::RowId>,
}

/// What the last edit touched.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Highlight {
    /// Anchors.
    pub anchors: Vec<ParamId>,
    /// Derived parameters.
    pub derived: Vec<ParamId>,
    /// Relevant rows kept as independent.
    pub independent_rows: Vec<crate::system::RowId>,
}

/// A file produced by a source; the host decides where and whether it is written.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct OutputFile {
    /// File name (no directories).
    pub name: String,
    /// Contents.
    pub bytes: Vec<u8>,
    /// What a person should know about the file that its contents alone do not make obvious
    /// (model vertices left in place because they lie outside the deformed region, say). The
    /// host puts them in the run report and prints them. Optional in the JSON exchanged with
    /// dynamic plugins, so plugins built before the field existed still load.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
}

impl OutputFile {
    /// A file without notes.
    pub fn new(name: impl Into<String>, bytes: Vec<u8>) -> Self {
        OutputFile {
            name: name.into(),
            bytes,
            notes: Vec::new(),
        }
    }

    /// The same file with one more note.
    pub fn with_note(mut self, note: impl Into<String>) -> Self {
        self.notes.push(note.into());
        self
    }
}

/// Why a source refused a request.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, thiserror::Error)]
#[error("{message}")]
pub struct SourceError {
    /// What went wrong, naming the file (and line/column) or the item.
    pub message: String,
    /// Where in the request's RON text (configuration, operation or output) the error is, when
    /// the source knows: the host turns it into a run-file position. Optional in the JSON
    /// exchanged with dynamic plugins, so plugins built before the field existed still load.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<TextPosition>,
}

impl SourceError {
    /// An error with a message and no position.
    pub fn new(message: impl Into<String>) -> Self {
        SourceError {
            message: message.into(),
            at: None,
        }
    }

    /// The same error at a position of the request's text.
    pub fn with_position(mut self, at: TextPosition) -> Self {
        self.at = Some(at);
        self
    }
}

/// A plugin that contributes parameters and constraints.
pub trait ConstraintSource {
    /// Plugin kind, as named in run files (`"spline2d"`).
    fn kind(&self) -> &str;
    /// Plugin version.
    fn version(&self) -> &str;
    /// Reads the configuration and contributes parameters and rows. Called once.
    fn build(&mut self, request: &BuildRequest) -> Result<Contribution, SourceError>;
    /// Plans a source-specific edit. Sources without operations refuse every request.
    fn plan(&self, request: &PlanRequest) -> Result<OperationPlan, SourceError>;
    /// Renders outputs for the current state. Sources without outputs refuse every request.
    /// The files are the ones [`ConstraintSource::check_output`] announced, in that order.
    fn render(&self, request: &RenderRequest) -> Result<Vec<OutputFile>, SourceError>;
    /// Checks an operation before the first edit of the run: `Ok` means [`plan`] will not
    /// refuse its schema, names or numbers (it may still find the edit unsolvable at its turn).
    /// Sources without operations refuse every request.
    ///
    /// [`plan`]: ConstraintSource::plan
    fn check_operation(&self, request: &OperationCheckRequest) -> Result<(), SourceError>;
    /// Checks an output before the first edit of the run, reading and validating the files it
    /// needs, and says which files it will write. Sources without outputs refuse every request.
    fn check_output(&self, request: &OutputCheckRequest) -> Result<OutputCheck, SourceError>;
    /// The source's geometry for an interactive editor ([`crate::view`]), asked once after
    /// [`ConstraintSource::build`], with the models the request's outputs deform; `None` when
    /// the source has nothing to draw (the default).
    fn view(&self, request: &ViewRequest) -> Result<Option<SourceView>, SourceError> {
        let _ = request;
        Ok(None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::{Origin, RowBody};

    fn r(n: i64) -> Rational {
        Rational::from_integer(n.into())
    }

    #[test]
    fn contributions_apply_atomically_and_round_trip() {
        let mut system = ConstraintSystem::new();
        let mut values = Values::default();
        let first = Contribution {
            parameters: vec![
                NewParameter {
                    name: "a".into(),
                    value: vec![r(1)],
                },
                NewParameter {
                    name: "b".into(),
                    value: vec![r(1)],
                },
            ],
            rows: vec![ConstraintRow {
                label: "a=b".into(),
                origin: Origin::default(),
                body: RowBody::Vector {
                    terms: vec![(ParamId(0), 1.into()), (ParamId(1), (-1).into())],
                    rhs: vec![0.into()],
                },
            }],
            ..Contribution::default()
        };
        first.apply_to(&mut system, &mut values).expect("valid");
        assert_eq!(system.params().len(), 2);
        assert!(system.violations(&values).is_empty());
        // A bad row leaves everything as it was, including the parameters before it.
        let bad = Contribution {
            parameters: vec![NewParameter {
                name: "c".into(),
                value: vec![r(2)],
            }],
            // A good row on an existing parameter and the new one, then a broken row: the
            // good row's incidence entries must go too.
            rows: vec![
                ConstraintRow {
                    label: "good".into(),
                    origin: Origin::default(),
                    body: RowBody::Vector {
                        terms: vec![(ParamId(0), 1.into()), (ParamId(2), (-1).into())],
                        rhs: vec![0.into()],
                    },
                },
                ConstraintRow {
                    label: "broken".into(),
                    origin: Origin::default(),
                    body: RowBody::Vector {
                        terms: vec![(ParamId(9), 1.into())],
                        rhs: vec![0.into()],
                    },
                },
            ],
            ..Contribution::default()
        };
        assert_eq!(system.params().len(), 2, "the new parameter gets id 2");
        let before = (system.clone(), values.clone());
        assert!(bad.apply_to(&mut system, &mut values).is_err());
        assert_eq!((system.clone(), values.clone()), before);
        // Systems survive serialisation (rows re-validated on the way back).
        let json = serde_json::to_string(&system).expect("serialise");
        let back: ConstraintSystem = serde_json::from_str(&json).expect("deserialise");
        assert_eq!(back, system);
        assert_eq!(back.rows_of(ParamId(1)), &[crate::system::RowId(0)]);
    }
}
