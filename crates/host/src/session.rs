//! A run: sources built into one system, edits executed with the exact backend and checked
//! against the float backend, outputs rendered.

use crate::analysis::{self, label, max_residual};
use crate::registry::{self, Origin};
use crate::report::{EditReport, Report, SourceReport, Summary, ValueReport};
use crate::runfile::{self, EditEntry, RunFile, Simplify};
use api::{
    format_rational, BuildRequest, ConstraintSource, ConstraintSystem, Factorization, Highlight,
    LinearBackend, OutputFile, ParamId, PlanRequest, PlannedStep, Rational, RenderRequest,
    SourceInfo, Value, Values,
};
use ecles::{Edit, EditError, EditSpec, UpdateResult};
use exact_ldu::{ExactLdu, Simplification};
use float_qr::FloatQr;
use num_traits::One;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Bad input: the run cannot start or continue (exit code 2).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

/// A built source.
struct Loaded {
    name: String,
    kind: String,
    source: Box<dyn ConstraintSource>,
    report: SourceReport,
}

/// The state of a run.
pub struct Session {
    /// Run file path as given.
    pub run_path: PathBuf,
    base_dir: PathBuf,
    run: RunFile,
    sources: Vec<Loaded>,
    system: ConstraintSystem,
    initial: Values,
    values: Values,
    exact: ExactLdu,
    tolerance: Option<f64>,
    last_highlight: BTreeMap<String, Highlight>,
}

impl Session {
    /// Reads the run file and builds every source, in order.
    pub fn build(run_path: &Path) -> Result<Session, InputError> {
        let run = runfile::read(run_path).map_err(|e| InputError(e.to_string()))?;
        let base_dir = run_path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_else(|| PathBuf::from("."));
        let method = match run.backend.simplify {
            Simplify::Gcd => Simplification::Gcd,
            Simplify::Turner => Simplification::Turner,
            Simplify::None => Simplification::None,
        };
        let mut session = Session {
            run_path: run_path.to_path_buf(),
            base_dir,
            tolerance: run.cross_check.map(|c| c.tolerance),
            run,
            sources: Vec::new(),
            system: ConstraintSystem::new(),
            initial: Values::default(),
            values: Values::default(),
            exact: ExactLdu::new(method),
            last_highlight: BTreeMap::new(),
        };
        let entries = session.run.sources.clone();
        for entry in &entries {
            session.build_source(entry)?;
        }
        session.initial = session.values.clone();
        Ok(session)
    }

    fn build_source(&mut self, entry: &runfile::SourceEntry) -> Result<(), InputError> {
        let (mut source, origin) =
            registry::instantiate(&entry.plugin, &self.base_dir).map_err(|e| {
                InputError(format!(
                    "{}: source {:?}: {e}",
                    self.run_path.display(),
                    entry.name
                ))
            })?;
        let config = runfile::to_ron_text(&entry.config);
        let request = BuildRequest {
            name: entry.name.clone(),
            config,
            base_dir: self.base_dir.clone(),
            system: self.system.clone(),
            values: self.values.clone(),
            sources: self
                .sources
                .iter()
                .zip(&self.run.sources)
                .map(|(s, e)| SourceInfo {
                    name: s.name.clone(),
                    kind: s.kind.clone(),
                    config: runfile::to_ron_text(&e.config),
                })
                .collect(),
        };
        let contribution = source.build(&request).map_err(|e| {
            InputError(format!(
                "{}: source {:?} (plugin {}): {}",
                self.run_path.display(),
                entry.name,
                entry.plugin,
                e.message
            ))
        })?;
        contribution
            .apply_to(&mut self.system, &mut self.values)
            .map_err(|e| {
                InputError(format!(
                    "{}: source {:?} (plugin {}) contributed invalid data: {e}",
                    self.run_path.display(),
                    entry.name,
                    entry.plugin
                ))
            })?;
        let report = SourceReport {
            name: entry.name.clone(),
            plugin: source.kind().to_string(),
            version: source.version().to_string(),
            loaded_from: match origin {
                Origin::Builtin => "builtin".to_string(),
                Origin::Library(path) => path,
            },
            parameters: contribution.parameters.len(),
            rows: contribution.rows.len(),
            counts: contribution
                .summary
                .iter()
                .map(|s| (s.key.clone(), s.value))
                .collect(),
            warnings: contribution.warnings.clone(),
        };
        self.sources.push(Loaded {
            name: entry.name.clone(),
            kind: source.kind().to_string(),
            source,
            report,
        });
        Ok(())
    }

    /// The whole-system report without edits.
    pub fn analyze(&self) -> Report {
        let a = analysis::analyse(&self.system, &self.initial, self.tolerance);
        Report {
            run: self.run_path.display().to_string(),
            parameters: a.parameters,
            constraints: a.constraints,
            rank: a.rank,
            dof: a.parameters - a.rank,
            consistent: a.consistent,
            satisfied: a.violated.is_empty(),
            redundant: a.redundant,
            conflict: a.conflict,
            violated: a.violated,
            sources: self.sources.iter().map(|s| s.report.clone()).collect(),
            cross_check: a.cross_check,
            structure: a.structure,
            edits: Vec::new(),
            outputs: Vec::new(),
            output_notes: Vec::new(),
            summary: Summary::default(),
        }
    }

    /// Why the parameter (or coordinate `name[k]`) is fixed, limited or free, in lines of text;
    /// `None` when no such parameter exists.
    pub fn explain(&self, name: &str) -> Option<Vec<String>> {
        let shape = analysis::shape(&self.system);
        crate::structural::explain_parameter(&shape, name)
    }

    /// Number of edits in the run file.
    pub fn edit_count(&self) -> usize {
        self.run.edits.len()
    }

    /// Checks every name used by generic edits before anything runs.
    pub fn validate_edits(&self) -> Result<(), InputError> {
        for (i, edit) in self.run.edits.iter().enumerate() {
            if let EditEntry::Ecles {
                anchors,
                derived,
                hints,
                weights,
                ..
            } = edit
            {
                for name in anchors
                    .keys()
                    .chain(derived)
                    .chain(hints.keys())
                    .chain(weights.keys())
                {
                    self.param(i, name)?;
                }
                for name in hints.keys().chain(weights.keys()) {
                    if !derived.contains(name) {
                        return Err(InputError(format!(
                            "edit {i}: {name:?} has a hint or weight but is not derived"
                        )));
                    }
                }
            }
        }
        Ok(())
    }

    fn param(&self, edit: usize, name: &str) -> Result<ParamId, InputError> {
        self.system
            .param_id(name)
            .ok_or_else(|| InputError(format!("edit {edit}: unknown parameter {name:?}")))
    }

    fn name(&self, id: ParamId) -> String {
        self.system.params()[id.index()].name.clone()
    }

    /// Runs edit `index`; the report says whether it was solvable. Values change only when
    /// every step succeeded.
    pub fn run_edit(&mut self, index: usize) -> Result<EditReport, InputError> {
        let entry = self.run.edits[index].clone();
        let mut report = EditReport {
            index,
            ..EditReport::default()
        };
        let (spec, steps) = match &entry {
            EditEntry::Ecles {
                anchors,
                derived,
                hints,
                weights,
                strong,
            } => {
                report.kind = "ecles".into();
                self.generic_plan(index, anchors, derived, hints, weights, *strong)?
            }
            EditEntry::Source { source, operation } => {
                report.kind = "source".into();
                report.source = Some(source.clone());
                let Some(loaded) = self.sources.iter().find(|s| &s.name == source) else {
                    return Err(InputError(format!(
                        "edit {index}: unknown source {source:?}"
                    )));
                };
                let request = PlanRequest {
                    operation: runfile::to_ron_text(operation),
                    system: self.system.clone(),
                    values: self.values.clone(),
                };
                match loaded.source.plan(&request) {
                    Ok(plan) => {
                        report.plan = plan
                            .summary
                            .iter()
                            .map(|s| (s.key.clone(), s.value))
                            .collect();
                        let spec = EditSpec {
                            anchors: plan.anchors,
                            derived: plan.derived,
                            weights: Some(plan.weights),
                            strong: plan.strong,
                        };
                        (spec, plan.steps)
                    }
                    Err(e) => {
                        report.solvable = false;
                        report.error = Some(format!("planning failed: {}", e.message));
                        report.max_residual = max_residual(&self.system, &self.values);
                        return Ok(report);
                    }
                }
            }
        };
        report.anchors = spec.anchors.iter().map(|p| self.name(*p)).collect();
        report.derived = spec.derived.iter().map(|p| self.name(*p)).collect();
        report.steps = steps.len();
        let exact = execute(&self.exact, &self.system, &self.values, &spec, &steps);
        let relevant = ecles::extract_relevant(&self.system, &spec.anchors, &spec.derived);
        report.structure = Some(crate::structural::edit_structure(
            &self.system,
            &relevant.constraints,
            &spec.derived,
        ));
        if let Some(init) = &exact.init {
            report.relevant = init.relevant;
            report.fixed_relevant = init.fixed.iter().map(|p| self.name(*p)).collect();
            report.rank = init.rank;
            report.redundant = init.redundant;
        }
        // The float run starts from the same state as the exact one.
        if let Some(tol) = self.tolerance {
            self.cross_check_edit(&mut report, &spec, &steps, &exact, tol);
        }
        match &exact.outcome {
            Ok(results) => {
                report.solvable = true;
                if let Some(last) = results.last() {
                    let mut updates = last.anchors.clone();
                    updates.extend(last.derived.iter().cloned());
                    report.values = updates
                        .iter()
                        .map(|(id, v)| ValueReport {
                            name: self.name(*id),
                            exact: v.iter().map(format_rational).collect(),
                            approx: v.iter().map(Value::to_f64).collect(),
                        })
                        .collect();
                    self.values.replace_all(updates);
                }
                if let EditEntry::Source { source, .. } = &entry {
                    self.last_highlight.insert(
                        source.clone(),
                        Highlight {
                            anchors: spec.anchors.clone(),
                            derived: spec.derived.clone(),
                            independent_rows: exact
                                .init
                                .as_ref()
                                .map(|i| i.independent.clone())
                                .unwrap_or_default(),
                        },
                    );
                }
            }
            Err(e) => {
                report.solvable = false;
                report.error = Some(e.to_string());
                report.conflict = conflict_labels(&self.system, e);
                report.explanation = self.explain_conflict(&spec, e);
            }
        }
        report.max_residual = max_residual(&self.system, &self.values);
        Ok(report)
    }

    /// Which anchors and constraints clash in a refused edit, in words: the conflicting rows,
    /// the anchors they contain, and the fixed and derived parameters they tie them to.
    fn explain_conflict<S: std::fmt::Debug>(
        &self,
        spec: &EditSpec,
        e: &EditError<S>,
    ) -> Vec<String> {
        let conflict = match e {
            EditError::Conflict(c) | EditError::CurrentStateInconsistent(c) => c,
            EditError::NotStronglySolvable { conflict, .. } => conflict,
            _ => return Vec::new(),
        };
        let rows: std::collections::BTreeSet<api::RowId> =
            conflict.rows.iter().map(|r| r.row.row).collect();
        let mut anchors = std::collections::BTreeSet::new();
        let mut derived = std::collections::BTreeSet::new();
        let mut fixed = std::collections::BTreeSet::new();
        for row in &rows {
            for p in self.system.rows()[row.index()].body.params() {
                if spec.anchors.contains(&p) {
                    anchors.insert(self.name(p));
                } else if spec.derived.contains(&p) {
                    derived.insert(self.name(p));
                } else {
                    fixed.insert(self.name(p));
                }
            }
        }
        let list = |set: &std::collections::BTreeSet<String>| {
            set.iter().cloned().collect::<Vec<_>>().join(", ")
        };
        let labels: Vec<String> = rows
            .iter()
            .map(|r| self.system.rows()[r.index()].label.clone())
            .collect();
        let mut lines = vec![format!(
            "the constraints {} cannot all hold with the requested anchor values",
            labels.join("; ")
        )];
        let structure = crate::structural::edit_structure(
            &self.system,
            &ecles::extract_relevant(&self.system, &spec.anchors, &spec.derived).constraints,
            &spec.derived,
        );
        if !structure.over_determined.is_empty() {
            lines.push(format!(
                "structurally over-determined: {} (more constraints than the derived parameters in them can satisfy)",
                structure.over_determined.join("; ")
            ));
        }
        if !anchors.is_empty() {
            lines.push(format!("anchors involved: {}", list(&anchors)));
        }
        if !fixed.is_empty() {
            lines.push(format!(
                "they tie the anchors to fixed parameters: {} (make some of them derived to let them follow)",
                list(&fixed)
            ));
        }
        if !derived.is_empty() {
            lines.push(format!(
                "the derived parameters {} cannot absorb the move on their own",
                list(&derived)
            ));
        }
        lines
    }

    fn generic_plan(
        &self,
        index: usize,
        anchors: &BTreeMap<String, runfile::ValueText>,
        derived: &[String],
        hints: &BTreeMap<String, runfile::ValueText>,
        weights: &BTreeMap<String, api::exact::Exact>,
        strong: bool,
    ) -> Result<(EditSpec, Vec<PlannedStep>), InputError> {
        let anchor_ids: Vec<ParamId> = anchors
            .keys()
            .map(|n| self.param(index, n))
            .collect::<Result<_, _>>()?;
        let derived_ids: Vec<ParamId> = derived
            .iter()
            .map(|n| self.param(index, n))
            .collect::<Result<_, _>>()?;
        let anchor_values: Vec<Vec<Rational>> = anchors.values().map(|v| v.coordinates()).collect();
        let hint_values: Vec<Vec<Rational>> = derived
            .iter()
            .zip(&derived_ids)
            .map(|(n, id)| {
                hints
                    .get(n)
                    .map(|v| v.coordinates())
                    .unwrap_or_else(|| self.values.get(*id).to_vec())
            })
            .collect();
        let weight_values: Vec<Rational> = derived
            .iter()
            .map(|n| {
                weights
                    .get(n)
                    .map(|w| w.0.clone())
                    .unwrap_or_else(Rational::one)
            })
            .collect();
        Ok((
            EditSpec {
                anchors: anchor_ids,
                derived: derived_ids,
                weights: Some(weight_values),
                strong,
            },
            vec![PlannedStep {
                anchors: anchor_values,
                hints: hint_values,
            }],
        ))
    }

    fn cross_check_edit(
        &self,
        report: &mut EditReport,
        spec: &EditSpec,
        steps: &[PlannedStep],
        exact: &Execution<Rational>,
        tolerance: f64,
    ) {
        let backend = match FloatQr::new(tolerance) {
            Ok(b) => b,
            Err(e) => {
                report
                    .disagreements
                    .push(format!("float backend unavailable: {e}"));
                report.float_agrees = Some(false);
                return;
            }
        };
        let float = execute(&backend, &self.system, &self.values, spec, steps);
        if let (Some(e), Some(f)) = (&exact.init, &float.init) {
            if e.rank != f.rank {
                report
                    .disagreements
                    .push(format!("rank of R_ED: exact {}, float {}", e.rank, f.rank));
            }
        }
        match (&exact.outcome, &float.outcome) {
            (Ok(e), Ok(f)) => {
                let mut deviation = 0f64;
                for (es, fs) in e.iter().zip(f) {
                    for ((_, ev), (_, fv)) in es.derived.iter().zip(&fs.derived) {
                        for (x, y) in ev.iter().zip(fv) {
                            let x = x.to_f64();
                            deviation = deviation.max((x - y).abs() / (1.0 + x.abs()));
                        }
                    }
                }
                report.float_deviation = Some(deviation);
                let bound = tolerance.sqrt().max(1e-6);
                if deviation > bound {
                    report.disagreements.push(format!(
                        "float values deviate by {deviation:e} (relative), above {bound:e}"
                    ));
                }
            }
            (Err(_), Err(_)) => {}
            (Ok(_), Err(e)) => report
                .disagreements
                .push(format!("exact solved the edit, float refused it: {e}")),
            (Err(_), Ok(_)) => report
                .disagreements
                .push("float solved the edit, exact proved it unsolvable".to_string()),
        }
        report.float_agrees = Some(report.disagreements.is_empty());
    }

    /// Renders every output; nothing is written here.
    pub fn render_outputs(&self) -> Result<Vec<OutputFile>, InputError> {
        let mut files: Vec<OutputFile> = Vec::new();
        let parts = if self.run.outputs.is_empty() {
            None
        } else {
            Some(crate::structural::parts(
                &self.system,
                &analysis::shape(&self.system),
            ))
        };
        for (i, out) in self.run.outputs.iter().enumerate() {
            let Some(loaded) = self.sources.iter().find(|s| s.name == out.source) else {
                return Err(InputError(format!(
                    "output {i}: unknown source {:?}",
                    out.source
                )));
            };
            let request = RenderRequest {
                output: runfile::to_ron_text(&out.output),
                base_dir: self.base_dir.clone(),
                system: self.system.clone(),
                initial: self.initial.clone(),
                values: self.values.clone(),
                highlight: self.last_highlight.get(&out.source).cloned(),
                structure: parts.clone(),
            };
            let rendered = loaded.source.render(&request).map_err(|e| {
                InputError(format!(
                    "output {i} (source {:?}): {}",
                    out.source, e.message
                ))
            })?;
            for file in rendered {
                if file.name.is_empty()
                    || file.name.contains(['/', '\\'])
                    || file.name == "report.json"
                    || file.name.starts_with('.')
                {
                    return Err(InputError(format!(
                        "output {i}: source {:?} produced an invalid file name {:?}",
                        out.source, file.name
                    )));
                }
                if files.iter().any(|f| f.name == file.name) {
                    return Err(InputError(format!(
                        "output {i}: two outputs write {:?}",
                        file.name
                    )));
                }
                files.push(file);
            }
        }
        Ok(files)
    }
}

/// What initialising an edit found.
struct InitFacts {
    relevant: usize,
    fixed: Vec<ParamId>,
    rank: usize,
    redundant: usize,
    independent: Vec<api::RowId>,
}

/// One backend's run of an edit.
struct Execution<S: api::Value> {
    init: Option<InitFacts>,
    outcome: Result<Vec<UpdateResult<S>>, EditError<S>>,
}

fn execute<B: LinearBackend>(
    backend: &B,
    system: &ConstraintSystem,
    values: &Values,
    spec: &EditSpec,
    steps: &[PlannedStep],
) -> Execution<<B::Factorization as Factorization>::Scalar> {
    let edit = match Edit::initialize(backend, system, values, spec) {
        Ok(edit) => edit,
        Err(e) => {
            return Execution {
                init: None,
                outcome: Err(e),
            }
        }
    };
    let report = edit.report();
    let init = InitFacts {
        relevant: report.relevant.len(),
        fixed: report.fixed_relevant.clone(),
        rank: report.rank,
        redundant: report.redundant.len(),
        independent: {
            let mut rows: Vec<api::RowId> = report.independent.iter().map(|r| r.row).collect();
            rows.sort();
            rows.dedup();
            rows
        },
    };
    let outcome = steps
        .iter()
        .map(|s| edit.update(&s.anchors, &s.hints))
        .collect::<Result<Vec<_>, _>>();
    Execution {
        init: Some(init),
        outcome,
    }
}

fn conflict_labels<S: std::fmt::Debug>(
    system: &ConstraintSystem,
    e: &EditError<S>,
) -> Option<Vec<String>> {
    let conflict = match e {
        EditError::Conflict(c) | EditError::CurrentStateInconsistent(c) => c,
        EditError::NotStronglySolvable { conflict, .. } => conflict,
        _ => return None,
    };
    Some(
        conflict
            .rows
            .iter()
            .map(|r| label(system, r.row.row, r.row.component))
            .collect(),
    )
}

/// A one-line description of a system report.
pub fn describe(report: &Report) -> String {
    format!(
        "{} parameters, {} constraints, rank {}, {} redundant, {}",
        report.parameters,
        report.constraints,
        report.rank,
        report.redundant.len(),
        if report.consistent {
            "consistent".to_string()
        } else {
            format!(
                "INCONSISTENT ({})",
                report.conflict.clone().unwrap_or_default().join(", ")
            )
        }
    )
}
