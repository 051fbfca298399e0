//! A run: sources built into one system, every edit and output checked before the first edit
//! runs, edits executed with the exact backend and checked against the float backend, outputs
//! rendered.

use crate::analysis::{self, label, max_residual};
use crate::error::RunError;
use crate::registry::{self, Origin};
use crate::report::{EditReport, Report, SourceReport, Summary, ValueReport};
use crate::runfile::{self, located_source_error, EditKind, GenericEdit, RunFile, Simplify};
use api::config::TextPosition;
use api::{
    format_rational, BuildRequest, ConstraintSource, ConstraintSystem, Factorization, Highlight,
    LinearBackend, OperationCheckRequest, OutputCheckRequest, OutputFile, ParamId, PlanRequest,
    PlannedStep, Rational, RenderRequest, SourceInfo, Value, Values,
};
use ecles::{Edit, EditError, EditSpec, UpdateResult};
use exact_ldu::{ExactLdu, Simplification};
use float_qr::FloatQr;
use num_traits::{One, Zero};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

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
    input_limit: u64,
    /// Every file the run reads: the run file, source inputs, plugin libraries.
    inputs: Vec<PathBuf>,
    /// The whole system's graph and Dulmage–Mendelsohn decomposition, computed once (the
    /// system does not change after the sources are built).
    graph: std::cell::OnceCell<crate::structural::SystemGraph>,
    last_highlight: BTreeMap<String, Highlight>,
}

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
    /// Reads the run file (at most `input_limit` bytes, the limit every source's inputs get
    /// too) and builds every source, in order.
    pub fn build(run_path: &Path, input_limit: u64) -> Result<Session, RunError> {
        let run =
            runfile::read(run_path, input_limit).map_err(|e| RunError::input(e.to_string()))?;
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
            input_limit,
            inputs: vec![run_path.to_path_buf()],
            graph: std::cell::OnceCell::new(),
            last_highlight: BTreeMap::new(),
        };
        let entries = session.run.sources.clone();
        for entry in &entries {
            session.build_source(entry)?;
        }
        session.initial = session.values.clone();
        Ok(session)
    }

    /// The graph of the whole system, built on first use.
    fn graph(&self) -> &crate::structural::SystemGraph {
        self.graph
            .get_or_init(|| crate::structural::SystemGraph::new(&self.system))
    }

    /// The run file's name in messages.
    fn run_name(&self) -> String {
        self.run_path.display().to_string()
    }

    /// A source's refusal of `fragment`, at its run-file position (see
    /// [`located_source_error`]).
    fn source_error(
        &self,
        fragment: &runfile::Fragment,
        context: &str,
        error: &api::SourceError,
    ) -> RunError {
        RunError::input(located_source_error(
            &self.run_name(),
            fragment,
            context,
            error,
        ))
    }

    /// `run.ron:LINE:COL: message`.
    fn at(&self, at: TextPosition, message: impl std::fmt::Display) -> RunError {
        RunError::input(format!("{}:{at}: {message}", self.run_name()))
    }

    fn build_source(&mut self, entry: &runfile::SourceEntry) -> Result<(), RunError> {
        let (mut source, origin) = registry::instantiate(&entry.plugin, &self.base_dir)
            .map_err(|e| self.at(entry.at, format!("source {:?}: {e}", entry.name)))?;
        let request = BuildRequest {
            name: entry.name.clone(),
            config: entry.config.text().to_string(),
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
                    config: e.config.text().to_string(),
                })
                .collect(),
            input_limit: self.input_limit,
        };
        let context = format!("source {:?} (plugin {})", entry.name, entry.plugin);
        let contribution = source
            .build(&request)
            .map_err(|e| self.source_error(&entry.config, &context, &e))?;
        contribution
            .apply_to(&mut self.system, &mut self.values)
            .map_err(|e| self.at(entry.at, format!("{context} contributed invalid data: {e}")))?;
        self.inputs.extend(contribution.inputs.iter().cloned());
        let report = SourceReport {
            name: entry.name.clone(),
            plugin: source.kind().to_string(),
            version: source.version().to_string(),
            loaded_from: match origin {
                Origin::Builtin => "builtin".to_string(),
                Origin::Library(path) => {
                    self.inputs.push(PathBuf::from(&path));
                    path
                }
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
        let a = analysis::analyze(&self.system, self.graph(), &self.initial, self.tolerance);
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

    /// Why the parameter (or coordinate `name[k]`) is fixed, limited or free, in lines of
    /// text. An unknown parameter, or a coordinate beyond the parameter's dimension, is bad
    /// input.
    pub fn explain(&self, name: &str) -> Result<Vec<String>, RunError> {
        let (base, coordinate) = split_coordinate(name);
        let id = self.system.param_id(base).ok_or_else(|| {
            RunError::input(format!(
                "{}: no parameter named {base:?} (parameters are named source.name, e.g. \"worm.v3\"; one coordinate is name[k])",
                self.run_name()
            ))
        })?;
        let dim = self.system.params()[id.index()].dim;
        if let Some(k) = coordinate {
            if k >= dim {
                return Err(RunError::input(format!(
                    "{}: {name:?}: coordinate {k} is out of range, {base:?} has {dim} coordinate{} (0{})",
                    self.run_name(),
                    if dim == 1 { "" } else { "s" },
                    if dim == 1 { String::new() } else { format!(" to {}", dim - 1) }
                )));
            }
        }
        let shape = &self.graph().shape;
        let mut lines = Vec::new();
        let column = match coordinate {
            // Every row holds per coordinate: the matrix has one column per parameter, and each
            // coordinate is constrained exactly as the whole parameter.
            Some(k) if shape.copies > 1 => {
                lines.push(format!(
                    "every row of this system holds coordinate by coordinate, so {base}[{k}] is constrained as {base} is:"
                ));
                base.to_string()
            }
            Some(_) if dim == 1 => base.to_string(),
            Some(k) => format!("{base}[{k}]"),
            None => base.to_string(),
        };
        lines.extend(
            crate::structural::explain_parameter(self.graph(), &column).unwrap_or_default(),
        );
        Ok(lines)
    }

    /// Number of edits in the run file.
    pub fn edit_count(&self) -> usize {
        self.run.edits.len()
    }

    /// Checks every edit and every output before the first edit runs: generic edits here
    /// (names, dimensions, weights, overlaps), source operations and outputs by their sources
    /// (schemas, names, numbers and limits; outputs read and validate their models). Returns
    /// what the outputs will write and read.
    pub fn check(&self) -> Result<OutputsPlan, RunError> {
        for (i, edit) in self.run.edits.iter().enumerate() {
            match &edit.kind {
                EditKind::Ecles(generic) => self
                    .check_generic(generic)
                    .map_err(|message| self.at(edit.at, format!("edit {i}: {message}")))?,
                EditKind::Source { source, operation } => {
                    let loaded = self.loaded(source)?;
                    loaded
                        .source
                        .check_operation(&OperationCheckRequest {
                            operation: operation.text().to_string(),
                        })
                        .map_err(|e| {
                            self.source_error(
                                operation,
                                &format!("edit {i} (source {source:?})"),
                                &e,
                            )
                        })?;
                }
            }
        }
        let mut plan = OutputsPlan {
            files: Vec::new(),
            inputs: self.inputs.clone(),
            announced: Vec::new(),
        };
        for (i, out) in self.run.outputs.iter().enumerate() {
            let loaded = self.loaded(&out.source)?;
            let context = format!("output {i} (source {:?})", out.source);
            let check = loaded
                .source
                .check_output(&OutputCheckRequest {
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

    /// Checks a generic edit: at least one anchor; every name a parameter; values of the right
    /// dimension; derived parameters distinct and not anchors; hints and weights only for
    /// derived parameters, weights positive.
    fn check_generic(&self, edit: &GenericEdit) -> Result<(), String> {
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

    /// The built source named `name`.
    fn loaded(&self, name: &str) -> Result<&Loaded, RunError> {
        self.sources
            .iter()
            .find(|s| s.name == name)
            .ok_or_else(|| RunError::input(format!("{}: unknown source {name:?}", self.run_name())))
    }

    fn param(&self, name: &str) -> Result<ParamId, RunError> {
        self.system
            .param_id(name)
            .ok_or_else(|| RunError::input(format!("unknown parameter {name:?}")))
    }

    fn name(&self, id: ParamId) -> String {
        self.system.params()[id.index()].name.clone()
    }

    /// Runs edit `index`; the report says whether it was solvable. Values change only when
    /// every step succeeded.
    pub fn run_edit(&mut self, index: usize) -> Result<EditReport, RunError> {
        let entry = self.run.edits[index].clone();
        let mut report = EditReport {
            index,
            ..EditReport::default()
        };
        let (spec, steps) = match &entry.kind {
            EditKind::Ecles(generic) => {
                report.kind = "ecles".into();
                self.generic_plan(generic)
                    .map_err(|e| self.at(entry.at, format!("edit {index}: {e}")))?
            }
            EditKind::Source { source, operation } => {
                report.kind = "source".into();
                report.source = Some(source.clone());
                let loaded = self.loaded(source)?;
                let request = PlanRequest {
                    operation: operation.text().to_string(),
                    system: self.system.clone(),
                    values: self.values.clone(),
                };
                match loaded.source.plan(&request) {
                    Ok(plan) => {
                        // A plugin's answer is outside data: nothing indexes with its ids
                        // before they are checked.
                        plan.validate(&self.system).map_err(|problem| {
                            self.at(
                                operation.start(),
                                format!(
                                    "edit {index}: source {source:?} planned an edit that cannot run: {problem}"
                                ),
                            )
                        })?;
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
        report.structure = ecles::reduce_edit::<Rational>(&self.system, &self.values, &spec)
            .ok()
            .map(|(_, reduced)| crate::structural::edit_structure(&self.system, &reduced));
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
                if let EditKind::Source { source, .. } = &entry.kind {
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
        let Some(conflict) = e.conflict() else {
            return Vec::new();
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
        let structure = ecles::reduce_edit::<Rational>(&self.system, &self.values, spec)
            .ok()
            .map(|(_, reduced)| crate::structural::edit_structure(&self.system, &reduced))
            .unwrap_or_default();
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

    fn generic_plan(&self, edit: &GenericEdit) -> Result<(EditSpec, Vec<PlannedStep>), RunError> {
        let anchor_ids: Vec<ParamId> = edit
            .anchors
            .keys()
            .map(|n| self.param(n))
            .collect::<Result<_, _>>()?;
        let derived_ids: Vec<ParamId> = edit
            .derived
            .iter()
            .map(|n| self.param(n))
            .collect::<Result<_, _>>()?;
        let anchor_values: Vec<Vec<Rational>> =
            edit.anchors.values().map(|v| v.coordinates()).collect();
        let hint_values: Vec<Vec<Rational>> = edit
            .derived
            .iter()
            .zip(&derived_ids)
            .map(|(n, id)| {
                edit.hints
                    .get(n)
                    .map(|v| v.coordinates())
                    .unwrap_or_else(|| self.values.get(*id).to_vec())
            })
            .collect();
        let weight_values: Vec<Rational> = edit
            .derived
            .iter()
            .map(|n| {
                edit.weights
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
                strong: edit.strong,
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

    /// Renders every output; nothing is written here. Each output must produce exactly the
    /// files its check announced (`plan`, from [`Session::check`]).
    pub fn render_outputs(&self, plan: &OutputsPlan) -> Result<Vec<OutputFile>, RunError> {
        let mut files: Vec<OutputFile> = Vec::new();
        let parts = if self.run.outputs.is_empty() {
            None
        } else {
            Some(crate::structural::parts(&self.system, self.graph()))
        };
        for (i, out) in self.run.outputs.iter().enumerate() {
            let loaded = self.loaded(&out.source)?;
            let context = format!("output {i} (source {:?})", out.source);
            let request = RenderRequest {
                output: out.output.text().to_string(),
                base_dir: self.base_dir.clone(),
                system: self.system.clone(),
                initial: self.initial.clone(),
                values: self.values.clone(),
                highlight: self.last_highlight.get(&out.source).cloned(),
                structure: parts.clone(),
                input_limit: self.input_limit,
            };
            let rendered = loaded
                .source
                .render(&request)
                .map_err(|e| self.source_error(&out.output, &context, &e))?;
            let names: Vec<String> = rendered.iter().map(|f| f.name.clone()).collect();
            if let Some(Some(announced)) = plan.announced.get(i) {
                if *announced != names {
                    return Err(self.at(
                        out.at,
                        format!("{context} wrote {names:?}, but its check announced {announced:?}"),
                    ));
                }
            }
            for file in rendered {
                check_file_name(&file.name).map_err(|m| {
                    self.at(
                        out.at,
                        format!("{context} produced the file {:?}: {m}", file.name),
                    )
                })?;
                if files.iter().any(|f| f.name == file.name) {
                    return Err(self.at(
                        out.at,
                        format!("{context}: two outputs write {:?}", file.name),
                    ));
                }
                files.push(file);
            }
        }
        Ok(files)
    }
}

/// `"name[k]"` as `("name", Some(k))`; any other text as `(text, None)`.
fn split_coordinate(name: &str) -> (&str, Option<usize>) {
    if let Some(inner) = name.strip_suffix(']') {
        if let Some((base, k)) = inner.rsplit_once('[') {
            if let Ok(k) = k.parse::<usize>() {
                return (base, Some(k));
            }
        }
    }
    (name, None)
}

/// A file name an output may write: plain (no directories), not hidden, not the report.
fn check_file_name(name: &str) -> Result<(), &'static str> {
    if name.is_empty() || name.contains(['/', '\\']) || name.starts_with('.') {
        Err("not a plain file name")
    } else if name == crate::outputs::REPORT {
        Err("the run report's name")
    } else {
        Ok(())
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
    let conflict = e.conflict()?;
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
