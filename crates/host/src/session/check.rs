//! Checking every edit and output of a run before the first edit runs.

use super::render::check_file_name;
use super::Session;
use crate::error::RunError;
use crate::runfile::{self, EditKind, GenericEdit};
use api::{format_rational, OperationCheckRequest, OutputCheckRequest, ParamId, Rational};
use num_traits::Zero;
use std::collections::BTreeSet;
use std::path::PathBuf;

/// What the outputs of a run will write and read, known before the first edit.
#[derive(Debug, Clone, Default)]
pub struct OutputsPlan {
    /// File names, in output order.
    pub files: Vec<String>,
    /// Every input of the run: the run file, the sources' inputs, the outputs' models, the
    /// plugin libraries.
    pub inputs: Vec<PathBuf>,
    /// Per output, the files its check announced (`None` from plugins built before checks
    /// existed: their files are checked when rendered).
    pub announced: Vec<Option<Vec<String>>>,
}

impl Session {
    /// Checks `edits`, read from `file` (named in messages), against this run's parameters and
    /// sources: generic edits here, source operations by their sources.
    pub(super) fn check_edits(
        &self,
        file: &str,
        edits: &[runfile::EditEntry],
    ) -> Result<(), RunError> {
        self.check_edits_from(file, edits, 0)
    }

    /// [`Session::check_edits`] of `edits`, the run's edits from number `first` on. After a
    /// `Configure(...)` the rest is checked against the system it builds (built here: a
    /// configuration a source refuses is found before the first edit runs).
    fn check_edits_from(
        &self,
        file: &str,
        edits: &[runfile::EditEntry],
        first: usize,
    ) -> Result<(), RunError> {
        for (k, edit) in edits.iter().enumerate() {
            let i = first + k;
            self.check_primary(&edit.criterion.primary)
                .map_err(|message| {
                    RunError::input(format!("{file}:{}: edit {i}: {message}", edit.at))
                })?;
            match &edit.kind {
                EditKind::Configure { source, config } => {
                    let place = super::ConfigPlace::At(file.to_string(), config.clone());
                    let rebuilt = self.rebuilt(source, config.text(), &place)?;
                    return rebuilt.check_edits_from(file, &edits[k + 1..], i + 1);
                }
                EditKind::Ecles(generic) => {
                    let hinted = !generic.hints.is_empty()
                        && matches!(
                            edit.criterion.measure,
                            runfile::MeasureName::L1 | runfile::MeasureName::Fewest
                        );
                    let checked = if hinted {
                        Err("hints belong to least squares: L1 and Fewest measure the change from the current values".to_string())
                    } else {
                        self.check_generic(generic)
                    };
                    checked.map_err(|message| {
                        RunError::input(format!("{file}:{}: edit {i}: {message}", edit.at))
                    })?
                }
                EditKind::Source { source, operation } => {
                    let loaded = self.loaded(source)?;
                    loaded
                        .source
                        .check_operation(&OperationCheckRequest {
                            schema: api::SCHEMA_VERSION,
                            operation: operation.text().to_string(),
                        })
                        .map_err(|e| {
                            RunError::input(runfile::located_source_error(
                                file,
                                operation,
                                &format!("edit {i} (source {source:?})"),
                                &e,
                            ))
                        })?;
                }
            }
        }
        Ok(())
    }

    /// Checks every edit and every output before the first edit runs: generic edits here
    /// (names, dimensions, weights, overlaps), source operations and outputs by their sources
    /// (schemas, names, numbers and limits; outputs read and validate their models). Returns
    /// what the outputs will write and read.
    pub fn check(&self) -> Result<OutputsPlan, RunError> {
        self.check_edits(&self.run_name(), &self.run.edits)?;
        let image = self.target_image()?;
        let mut plan = OutputsPlan {
            files: Vec::new(),
            inputs: self.inputs.clone(),
            announced: Vec::new(),
        };
        // The target image is an input too: no output may overwrite it.
        plan.inputs.extend(image.map(|image| image.path));
        for (i, out) in self.run.outputs.iter().enumerate() {
            let loaded = self.loaded(&out.source)?;
            let context = format!("output {i} (source {:?})", out.source);
            let check = loaded
                .source
                .check_output(&OutputCheckRequest {
                    schema: api::SCHEMA_VERSION,
                    output: out.output.text().to_string(),
                    base_dir: self.base_dir.clone(),
                    input_limit: self.input_limit,
                })
                .map_err(|e| self.source_error(&out.output, &context, &e))?;
            for name in &check.files {
                check_file_name(name)
                    .map_err(|m| self.at(out.at, format!("{context} would write {name:?}: {m}")))?;
                if plan.files.contains(name) {
                    return Err(self.at(out.at, format!("{context}: two outputs write {name:?}")));
                }
                plan.files.push(name.clone());
            }
            plan.announced
                .push(check.checked.then(|| check.files.clone()));
            plan.inputs.extend(check.inputs);
        }
        Ok(plan)
    }

    /// Checks an edit's primary parameters: each a parameter, none twice. (Those that are not
    /// derived by the edit have no change to minimise; the report counts the derived ones.)
    fn check_primary(&self, primary: &[String]) -> Result<(), String> {
        let mut seen = BTreeSet::new();
        for name in primary {
            self.param(name).map_err(|e| format!("primary: {e}"))?;
            if !seen.insert(name) {
                return Err(format!("primary parameter {name:?} is listed twice"));
            }
        }
        Ok(())
    }

    /// Checks a generic edit: at least one anchor; every name a parameter; values of the right
    /// dimension; derived parameters distinct and not anchors; hints and weights only for
    /// derived parameters, weights positive.
    pub(super) fn check_generic(&self, edit: &GenericEdit) -> Result<(), String> {
        if edit.anchors.is_empty() {
            return Err("anchors is empty: an edit needs at least one anchor".into());
        }
        let param = |name: &str, role: &str| -> Result<ParamId, String> {
            self.system.param_id(name).ok_or_else(|| {
                format!("{role} {name:?} is not a parameter of the run (parameters are named source.name, e.g. \"worm.v3\")")
            })
        };
        let dimension = |name: &str, id: ParamId, role: &str, value: &runfile::ValueText| {
            let dim = self.system.params()[id.index()].dim;
            let given = value.coordinates().len();
            if given == dim {
                Ok(())
            } else {
                Err(format!(
                    "the {role} of {name:?} has {given} coordinates, but the parameter has {dim}"
                ))
            }
        };
        for (name, value) in &edit.anchors {
            let id = param(name, "anchor")?;
            dimension(name, id, "value", value)?;
        }
        let mut derived = BTreeSet::new();
        for name in &edit.derived {
            param(name, "derived parameter")?;
            if edit.anchors.contains_key(name) {
                return Err(format!("{name:?} is both an anchor and derived"));
            }
            if !derived.insert(name.as_str()) {
                return Err(format!("{name:?} is listed twice in derived"));
            }
        }
        for (name, value) in &edit.hints {
            let id = param(name, "hinted parameter")?;
            if !derived.contains(name.as_str()) {
                return Err(format!("{name:?} has a hint but is not derived"));
            }
            dimension(name, id, "hint", value)?;
        }
        for (name, weight) in &edit.weights {
            param(name, "weighted parameter")?;
            if !derived.contains(name.as_str()) {
                return Err(format!("{name:?} has a weight but is not derived"));
            }
            if weight.0 <= Rational::zero() {
                return Err(format!(
                    "the weight of {name:?} is {}; weights must be positive",
                    format_rational(&weight.0)
                ));
            }
        }
        Ok(())
    }
}
