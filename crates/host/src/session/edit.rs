//! Running an edit: planned by the run file or a source, executed on the exact backend and
//! cross-checked on the float one.

use super::{Session, Step};
use crate::analysis::{label, max_residual};
use crate::error::RunError;
use crate::report::{EditReport, SnapReport, ValueReport};
use crate::runfile::{CommitPolicy, EditEntry, EditKind, GenericEdit};
use api::{
    format_rational, ConstraintSystem, Factorization, Highlight, LinearBackend, ParamId,
    PlanRequest, PlannedStep, Rational, Value, Values,
};
use ecles::{Edit, EditError, EditSpec, UpdateResult};
use exact_ldu::ExactFactorization;
use float_qr::FloatQr;
use num_traits::One;
use std::collections::BTreeMap;

impl Session {
    /// Plans edit `index` of the run file: a generic edit from its names and values, a source
    /// operation by its source (whose plan is checked before anything uses it). A source's
    /// refusal at this point is [`Planning::Refused`]; bad input is an error.
    pub fn plan_edit(&self, index: usize) -> Result<Planning, RunError> {
        let entry = self
            .run
            .edits
            .get(index)
            .ok_or_else(|| RunError::input(format!("the run has no edit {index}")))?;
        self.plan_entry(&self.run_name(), entry, index)
    }

    /// Plans `entry`, edit `index` of run file `file` (this run's, or a session being
    /// resumed; named in messages).
    fn plan_entry(
        &self,
        file: &str,
        entry: &EditEntry,
        index: usize,
    ) -> Result<Planning, RunError> {
        let at = |position, message: String| {
            RunError::input(format!("{file}:{position}: edit {index}: {message}"))
        };
        match &entry.kind {
            EditKind::Ecles(generic) => {
                let (spec, steps) = self
                    .generic_plan(generic)
                    .map_err(|e| at(entry.at, e.to_string()))?;
                Ok(Planning::Planned(PlannedEdit {
                    spec,
                    steps,
                    source: None,
                    summary: BTreeMap::new(),
                }))
            }
            EditKind::Source { source, operation } => self
                .plan_operation(source, operation.text())
                .map_err(|e| match e {
                    RunError::Input(message) => at(operation.start(), message),
                    other => other,
                }),
            EditKind::Configure { .. } => Err(at(
                entry.at,
                "a Configure(...) rebuilds a source; it is run, not planned".into(),
            )),
        }
    }

    /// Plans an operation of source `source` (RON text in the source's schema) on the current
    /// values: what an editor calls for every new operation. The plan is checked against the
    /// system ([`api::OperationPlan::validate`]) before it is returned.
    pub fn plan_operation(&self, source: &str, operation: &str) -> Result<Planning, RunError> {
        let loaded = self.loaded(source)?;
        let request = PlanRequest {
            schema: api::SCHEMA_VERSION,
            operation: operation.to_string(),
            system: self.system.clone(),
            values: self.values.clone(),
        };
        match loaded.source.plan(&request) {
            Ok(plan) => {
                // A plugin's answer is outside data: nothing indexes with its ids before they
                // are checked.
                plan.validate(&self.system).map_err(|problem| {
                    RunError::input(format!(
                        "source {source:?} planned an edit that cannot run: {problem}"
                    ))
                })?;
                Ok(Planning::Planned(PlannedEdit {
                    summary: plan
                        .summary
                        .iter()
                        .map(|s| (s.key.clone(), s.value))
                        .collect(),
                    spec: EditSpec {
                        anchors: plan.anchors,
                        derived: plan.derived,
                        weights: Some(plan.weights),
                        strong: plan.strong,
                    },
                    steps: plan.steps,
                    source: Some(source.to_string()),
                }))
            }
            Err(e) => Ok(Planning::Refused(e.message)),
        }
    }

    /// ECLES.Initialize of a planned edit on the current values, with the exact backend.
    pub fn initialize(&self, plan: &PlannedEdit) -> Result<ActiveEdit, EditError<Rational>> {
        let edit = Edit::initialize(&self.exact, &self.system, &self.values, &plan.spec)?;
        Ok(ActiveEdit {
            edit,
            generation: self.generation,
            source: plan.source.clone(),
        })
    }

    /// Commits an update of `edit` (from [`ActiveEdit::update`]): the anchors and derived
    /// parameters take its values, the previous values can be restored with
    /// [`Session::undo`]. Refused when the values changed since the edit was initialised.
    /// `entry` is the edit as a run-file entry (`Source(source: ..., operation: ...)` with
    /// the operation of this result), kept for [`Session::committed_edits`].
    pub fn apply(
        &mut self,
        edit: &ActiveEdit,
        result: &UpdateResult<Rational>,
        entry: String,
    ) -> Result<(), RunError> {
        if edit.generation != self.generation {
            return Err(RunError::input(
                "the edit was initialised on values that have changed since; initialise it again",
            ));
        }
        let report = edit.edit.report();
        let mut independent: Vec<api::RowId> = report.independent.iter().map(|r| r.row).collect();
        independent.sort();
        independent.dedup();
        let highlight = edit.source.clone().map(|source| {
            (
                source,
                Highlight {
                    anchors: edit.edit.anchors().to_vec(),
                    derived: edit.edit.derived().to_vec(),
                    independent_rows: independent,
                },
            )
        });
        let updates = result.anchors.iter().chain(&result.derived).cloned();
        self.commit(updates, highlight, entry);
        Ok(())
    }

    /// What an edit commits in this run: the optimum or a snapped point.
    pub fn commit_policy(&self) -> CommitPolicy {
        self.run.commit_policy()
    }

    /// Makes `policy` this run's commit policy unless the run file states one: what `ecles
    /// edit` does before the first edit (its sessions commit snapped points unless told).
    pub fn default_commit_policy(&mut self, policy: CommitPolicy) {
        self.run.commit.get_or_insert(policy);
    }

    /// The update a commit of `edit` takes for `step`, under the run's commit policy (the
    /// optimum, or a snapped point): what [`Session::run_edit`] commits for the same step.
    pub fn committed_update(
        &self,
        edit: &ActiveEdit,
        step: &PlannedStep,
    ) -> Result<UpdateResult<Rational>, EditError<Rational>> {
        match self.run.commit_policy() {
            CommitPolicy::Optimum => edit.update(step),
            CommitPolicy::Snapped { grid_bits } => edit
                .update_snapped(step, grid_bits)
                .map(|(result, _)| result),
        }
    }

    /// Restores the state before the last committed edit (exactly: the state itself was
    /// kept, and after a `Configure(...)` the sources and system too); `false` when there is
    /// none. [`Session::redo`] takes it back.
    pub fn undo(&mut self) -> bool {
        self.step_back(true)
    }

    /// Commits again the last edit undone; `false` when there is none (a commit since the undo
    /// forgets what was undone).
    pub fn redo(&mut self) -> bool {
        self.step_back(false)
    }

    /// Undo (`true`) and redo: the state on top of the history (or of the undone edits)
    /// becomes current, the current one goes on the other stack with the same edit.
    fn step_back(&mut self, undo: bool) -> bool {
        let popped = if undo {
            self.history.pop()
        } else {
            self.undone.pop()
        };
        let Some(mut step) = popped else {
            return false;
        };
        if let Some(built) = step.build.as_mut() {
            self.swap_build(built);
        }
        let back = Step {
            values: std::mem::replace(&mut self.values, step.values),
            highlight: std::mem::replace(&mut self.last_highlight, step.highlight),
            entry: step.entry,
            build: step.build,
        };
        if undo {
            self.undone.push(back);
        } else {
            self.history.push(back);
        }
        self.generation += 1;
        true
    }

    /// Writes a result's values (its anchors' and derived parameters') into the values, keeping
    /// the previous state and the edit (`entry`, its run-file text) for [`Session::undo`] and
    /// [`Session::committed_edits`].
    fn commit(
        &mut self,
        updates: impl IntoIterator<Item = (ParamId, Vec<Rational>)>,
        highlight: Option<(String, Highlight)>,
        entry: String,
    ) {
        self.undone.clear();
        self.history.push(Step {
            values: self.values.clone(),
            highlight: self.last_highlight.clone(),
            entry,
            build: None,
        });
        self.values.replace_all(updates);
        if let Some((source, highlight)) = highlight {
            self.last_highlight.insert(source, highlight);
        }
        self.generation += 1;
    }

    /// The committed edits in force (undone ones excluded), in order, as run-file entries.
    pub fn committed_edits(&self) -> impl Iterator<Item = &str> {
        self.history.iter().map(|step| step.entry.as_str())
    }

    /// Runs edit `index`; the report says whether it was solvable. Values change only when
    /// every step succeeded.
    pub fn run_edit(&mut self, index: usize) -> Result<EditReport, RunError> {
        let entry = self
            .run
            .edits
            .get(index)
            .ok_or_else(|| RunError::input(format!("the run has no edit {index}")))?
            .clone();
        self.run_entry(&self.run_name(), &entry, index)
    }

    /// Runs `entry` as edit `index` of run file `file` (see [`Session::run_edit`]).
    pub(super) fn run_entry(
        &mut self,
        file: &str,
        entry: &EditEntry,
        index: usize,
    ) -> Result<EditReport, RunError> {
        let mut report = EditReport {
            index,
            ..EditReport::default()
        };
        if let EditKind::Configure { source, config } = &entry.kind {
            let place = super::ConfigPlace::At(file.to_string(), config.clone());
            let outcome =
                self.configure_placed(source, config.text(), place, entry.text.clone())?;
            return Ok(self.configure_report(index, source, outcome));
        }
        let planned = self.plan_entry(file, entry, index)?;
        report.kind = match &entry.kind {
            EditKind::Source { source, .. } => {
                report.source = Some(source.clone());
                "source".into()
            }
            _ => "ecles".into(),
        };
        let plan = match planned {
            Planning::Planned(plan) => plan,
            Planning::Refused(message) => {
                report.solvable = false;
                report.error = Some(format!("planning failed: {message}"));
                report.max_residual = max_residual(&self.system, &self.values);
                return Ok(report);
            }
        };
        report.plan = plan.summary.clone();
        let (spec, steps) = (&plan.spec, &plan.steps);
        report.anchors = spec.anchors.iter().map(|p| self.name(*p)).collect();
        report.derived = spec.derived.iter().map(|p| self.name(*p)).collect();
        report.steps = steps.len();
        report.propagation = steps
            .last()
            .map(|last| self.edit_propagation(&spec.anchors, &last.anchors));
        let commit = self.run.commit_policy();
        let snapped = std::cell::Cell::new(None::<ecles::SnapSummary>);
        let criterion = self.criterion(&entry.criterion)?;
        let chosen = std::cell::RefCell::new(None::<ecles::CriterionSummary>);
        let exact = execute(
            &self.exact,
            &self.system,
            &self.values,
            spec,
            steps,
            |edit, step| match commit {
                // Another criterion commits its exact choice: snapping would move it off its
                // optimum (and off the parameters it leaves in place).
                _ if !criterion.is_least_squares() => {
                    let hints = self.criterion_hints(&criterion, spec, step);
                    let (result, summary) = edit.update_by(&criterion, &step.anchors, &hints)?;
                    *chosen.borrow_mut() = Some(summary);
                    Ok(result)
                }
                CommitPolicy::Optimum => edit.update(&step.anchors, &step.hints),
                CommitPolicy::Snapped { grid_bits } => {
                    let (result, summary) =
                        edit.update_snapped(&step.anchors, &step.hints, grid_bits)?;
                    snapped.set(Some(summary));
                    Ok(result)
                }
            },
        );
        report.snap = snapped.get().map(SnapReport::from);
        report.criterion = chosen
            .into_inner()
            .map(|summary| self.criterion_report(&summary));
        // The initialised edit's reduced system; reduced again only when Initialize refused
        // the edit (a conflict's report still describes its structure).
        report.structure = match exact.init.as_ref() {
            Some(InitFacts {
                reduced: Some(reduced),
                independent_rows,
                ..
            }) => Some(crate::structural::edit_structure(
                &self.system,
                reduced,
                *independent_rows,
            )),
            _ => ecles::reduce_edit::<Rational>(&self.system, &self.values, spec)
                .ok()
                .map(|(_, reduced)| {
                    crate::structural::edit_structure(&self.system, &reduced, false)
                }),
        };
        if let Some(init) = &exact.init {
            report.relevant = init.relevant;
            report.fixed_relevant = init.fixed.iter().map(|p| self.name(*p)).collect();
            report.rank = init.rank;
            report.redundant = init.redundant;
        }
        // The float run starts from the same state as the exact one; it solves least squares,
        // so under another criterion only its verdict and rank are compared.
        if let Some(tol) = self.tolerance {
            self.cross_check_edit(
                &mut report,
                spec,
                steps,
                &exact,
                tol,
                criterion.is_least_squares(),
            );
        }
        match exact.outcome {
            Ok(mut results) => {
                report.solvable = true;
                if let Some(last) = results.pop() {
                    let entries: Vec<&(ParamId, Vec<Rational>)> =
                        last.anchors.iter().chain(&last.derived).collect();
                    // Decimal text of values with thousands of digits: on all cores, each
                    // distinct denominator once.
                    let values: Vec<&[Rational]> =
                        entries.iter().map(|(_, v)| v.as_slice()).collect();
                    let texts = super::value_text::value_texts(&values);
                    report.values = entries
                        .iter()
                        .zip(texts)
                        .map(|((id, v), exact)| ValueReport {
                            name: self.name(*id),
                            exact,
                            approx: v.iter().map(Value::to_f64).collect(),
                        })
                        .collect();
                    let highlight = plan.source.clone().map(|source| {
                        (
                            source,
                            Highlight {
                                anchors: spec.anchors.clone(),
                                derived: spec.derived.clone(),
                                independent_rows: exact
                                    .init
                                    .as_ref()
                                    .map(|i| i.independent.clone())
                                    .unwrap_or_default(),
                            },
                        )
                    });
                    let updates = last.anchors.into_iter().chain(last.derived);
                    self.commit(updates, highlight, entry.text.clone());
                }
            }
            Err(e) => {
                report.solvable = false;
                report.error = Some(e.to_string());
                report.conflict = conflict_labels(&self.system, &e);
                report.explanation = self.explain_conflict(spec, &e);
            }
        }
        report.max_residual = max_residual(&self.system, &self.values);
        Ok(report)
    }

    /// A refused edit of `spec` for a person: the labels of the conflicting rows (empty when
    /// the refusal has no certificate) and the explanation in lines of text.
    pub fn conflict_details(
        &self,
        spec: &EditSpec,
        e: &EditError<Rational>,
    ) -> (Vec<String>, Vec<String>) {
        (
            conflict_labels(&self.system, e).unwrap_or_default(),
            self.explain_conflict(spec, e),
        )
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
        let list = |set: &std::collections::BTreeSet<std::sync::Arc<str>>| {
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
            .map(|(_, reduced)| crate::structural::edit_structure(&self.system, &reduced, false))
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

    /// The ECLES criterion of a run file's choice (its primary names resolved).
    pub fn criterion(
        &self,
        choice: &crate::runfile::CriterionChoice,
    ) -> Result<ecles::Criterion, RunError> {
        Ok(ecles::Criterion {
            measure: choice.measure.measure(),
            primary: if choice.primary.is_empty() {
                None
            } else {
                Some(
                    choice
                        .primary
                        .iter()
                        .map(|n| self.param(n))
                        .collect::<Result<_, _>>()?,
                )
            },
        })
    }

    /// Plans a generic edit given by a library caller: checked as a run file's edit is (names,
    /// dimensions, weights, overlaps), then planned on the current values.
    pub fn plan_generic(&self, edit: &GenericEdit) -> Result<PlannedEdit, RunError> {
        self.check_generic(edit).map_err(RunError::input)?;
        let (spec, steps) = self.generic_plan(edit)?;
        Ok(PlannedEdit {
            spec,
            steps,
            source: None,
            summary: BTreeMap::new(),
        })
    }

    /// What `criterion` measures changes from in `step`: the step's hints for least squares
    /// (ECLES: as close to the hints as the constraints allow, primary parameters first), the
    /// current values for L1 and Fewest (what moves: hints are a least-squares notion; a
    /// source's soft hints would otherwise count points that follow them as unchanged).
    pub fn criterion_hints(
        &self,
        criterion: &ecles::Criterion,
        spec: &EditSpec,
        step: &PlannedStep,
    ) -> Vec<Vec<Rational>> {
        match criterion.measure {
            ecles::Measure::L2 => step.hints.clone(),
            ecles::Measure::L1 | ecles::Measure::Fewest => spec
                .derived
                .iter()
                .map(|id| self.values.get(*id).to_vec())
                .collect(),
        }
    }

    /// The report of what a criterion chose (report.json's `criterion`; the editor's frames
    /// carry it too).
    pub fn criterion_report(
        &self,
        summary: &ecles::CriterionSummary,
    ) -> crate::report::CriterionReport {
        let names = |ids: &[ParamId]| -> Vec<String> {
            ids.iter().map(|p| self.name(*p).to_string()).collect()
        };
        let supports = summary.supports.as_ref();
        crate::report::CriterionReport {
            measure: format!("{:?}", summary.measure),
            primary: names(&summary.primary),
            value: format_rational(&summary.value),
            changed: names(&summary.changed),
            unique: summary.optimal_face_dimension.map(|d| d == 0),
            optimal_face_dimension: summary.optimal_face_dimension,
            proven_minimal: supports.map(|s| s.proven_minimal),
            minimum_sets: supports.map(|s| s.count),
            ties_complete: supports.map(|s| s.ties_complete),
            ties: supports
                .map(|s| s.ties.iter().map(|t| names(t)).collect())
                .unwrap_or_default(),
            rank_tests: supports.map(|s| s.rank_tests),
        }
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
        compare_values: bool,
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
        let large = ecles::reduce_edit::<f64>(&self.system, &self.values, spec)
            .map(|(_, reduced)| {
                reduced.r_ed().rows().saturating_mul(reduced.r_ed().cols())
                    > super::float_twin::DENSE_EDIT_LIMIT
            })
            .unwrap_or(false);
        report.float_method = Some(if large { "sparse QR" } else { "dense QR" }.to_string());
        let float = if large {
            super::float_twin::execute_sparse(&self.system, &self.values, spec, steps, tolerance)
        } else {
            execute(
                &backend,
                &self.system,
                &self.values,
                spec,
                steps,
                |edit, step| edit.update(&step.anchors, &step.hints),
            )
        };
        if let (Some(e), Some(f)) = (&exact.init, &float.init) {
            if e.rank != f.rank {
                report
                    .disagreements
                    .push(format!("rank of R_ED: exact {}, float {}", e.rank, f.rank));
            }
        }
        match (&exact.outcome, &float.outcome) {
            (Ok(_), Ok(_)) if !compare_values => {}
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
                // A snapped commit may differ from the optimum by its proved distance.
                let snapped = report.snap.as_ref().map_or(0.0, |s| s.distance_bound);
                let bound = tolerance.sqrt().max(1e-6) + snapped;
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
}

/// An edit ready to initialise: the ECLES spec, the anchor values and hints of each step, and
/// what the source's planning found.
#[derive(Debug, Clone)]
pub struct PlannedEdit {
    /// Anchors, derived parameters, weights, strong check.
    pub spec: EditSpec,
    /// Anchor values and hints per step of the drag (each from the state at initialisation).
    pub steps: Vec<PlannedStep>,
    /// The source that planned it (`None` for generic edits).
    pub source: Option<String>,
    /// The source's facts about the planning (for the report).
    pub summary: BTreeMap<String, u64>,
}

/// The outcome of planning.
#[derive(Debug, Clone)]
pub enum Planning {
    /// An edit to run.
    Planned(PlannedEdit),
    /// The source refused the operation at its turn (its message).
    Refused(String),
}

/// An initialised edit on the exact backend: update and preview as often as needed (a drag),
/// then [`Session::apply`] the result to commit it.
pub struct ActiveEdit {
    edit: Edit<ExactFactorization>,
    /// The session's generation at initialisation: applying is refused once values changed.
    generation: u64,
    source: Option<String>,
}

impl ActiveEdit {
    /// ECLES.Update: exact values of the anchors and derived parameters for one step.
    pub fn update(
        &self,
        step: &PlannedStep,
    ) -> Result<UpdateResult<Rational>, EditError<Rational>> {
        self.edit.update(&step.anchors, &step.hints)
    }

    /// ECLES.Update committed as a snapped point (free values on the grid `2^−grid_bits`, every
    /// constraint exact, a proved bound on the distance to the optimum): what a long editing
    /// session commits so that its values stay small.
    pub fn update_snapped(
        &self,
        step: &PlannedStep,
        grid_bits: u32,
    ) -> Result<(UpdateResult<Rational>, ecles::SnapSummary), EditError<Rational>> {
        self.edit
            .update_snapped(&step.anchors, &step.hints, grid_bits)
    }

    /// [`ActiveEdit::update`] under `criterion`, measuring changes from `hints` (see
    /// [`Edit::update_by`] and [`Session::criterion_hints`]).
    pub fn update_by(
        &self,
        criterion: &ecles::Criterion,
        step: &PlannedStep,
        hints: &[Vec<Rational>],
    ) -> Result<(UpdateResult<Rational>, ecles::CriterionSummary), EditError<Rational>> {
        self.edit.update_by(criterion, &step.anchors, hints)
    }

    /// The same verdict as [`ActiveEdit::update`] with the derived values as `f64`, cheaper
    /// (for drag frames).
    pub fn preview(&self, step: &PlannedStep) -> Result<Vec<Vec<f64>>, EditError<Rational>> {
        self.edit.preview(&step.anchors, &step.hints)
    }

    /// The ECLES edit (its report, reduced system, factorization).
    pub fn edit(&self) -> &Edit<ExactFactorization> {
        &self.edit
    }
}

/// An initialised edit's relevant rows, rank and redundant rows in scalar equations (the unit
/// of every count in reports): a vector row stands for one equation per coordinate, and so do
/// the rank and redundant rows of an edit factored once for all coordinates (vector layout).
pub fn equation_counts<S>(
    system: &ConstraintSystem,
    report: &ecles::InitReport<S>,
) -> (usize, usize, usize) {
    let copies = match report.layout {
        ecles::Layout::Vector { dim } => dim,
        ecles::Layout::Scalar => 1,
    };
    let relevant = report
        .relevant
        .iter()
        .map(|r| match &system.rows()[r.index()].body {
            api::RowBody::Vector { rhs, .. } => rhs.len(),
            api::RowBody::Scalar { .. } => 1,
        })
        .sum();
    (
        relevant,
        report.rank * copies,
        report.redundant.len() * copies,
    )
}

/// What initialising an edit found.
pub(super) struct InitFacts {
    pub(super) relevant: usize,
    pub(super) fixed: Vec<ParamId>,
    pub(super) rank: usize,
    pub(super) redundant: usize,
    pub(super) independent: Vec<api::RowId>,
    /// Whether the exact factoring found every row of `R_ED` independent.
    pub(super) independent_rows: bool,
    /// The reduced system the edit factored (`ecles::reduce_edit`'s), for the report's
    /// structure; `None` where the run did not go through [`ecles::Edit`].
    pub(super) reduced: Option<ecles::ReducedSystem>,
}

/// One backend's run of an edit.
pub(super) struct Execution<S: api::Value> {
    pub(super) init: Option<InitFacts>,
    pub(super) outcome: Result<Vec<UpdateResult<S>>, EditError<S>>,
}

/// Initialises `spec` on `backend` and runs every step through `update` (the optimum, or a
/// snapped point for the exact backend).
#[allow(clippy::type_complexity)]
pub(super) fn execute<B: LinearBackend>(
    backend: &B,
    system: &ConstraintSystem,
    values: &Values,
    spec: &EditSpec,
    steps: &[PlannedStep],
    update: impl Fn(
        &Edit<B::Factorization>,
        &PlannedStep,
    ) -> Result<
        UpdateResult<<B::Factorization as Factorization>::Scalar>,
        EditError<<B::Factorization as Factorization>::Scalar>,
    >,
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
    let (relevant, rank, redundant) = equation_counts(system, &report);
    let outcome = steps
        .iter()
        .map(|s| update(&edit, s))
        .collect::<Result<Vec<_>, _>>();
    let init = InitFacts {
        relevant,
        fixed: report.fixed_relevant.clone(),
        rank,
        redundant,
        independent: {
            let mut rows: Vec<api::RowId> = report.independent.iter().map(|r| r.row).collect();
            rows.sort();
            rows.dedup();
            rows
        },
        independent_rows: report.rank == report.equations,
        reduced: Some(edit.into_reduced()),
    };
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::{check, example, session};

    const WORM: &str =
        r#"(sources: [(name: "worm", plugin: "spline2d", config: (mesh: "meshes/worm.obj"))])"#;

    /// A session from run text: built like a run file's; text over the input limit is refused
    /// before it is read. The deformation view is the view without the outputs' models.
    #[test]
    fn run_text_builds_a_session_within_the_input_limit() {
        let text = r#"(sources: [(name: "eq", plugin: "linear", config: (parameters: {"a": "1"}, equations: ["a = 1"]))])"#;
        let session = Session::build_text(text, "run text", std::path::Path::new("."), 1 << 20)
            .expect("built");
        assert_eq!(session.system().params().len(), 1);
        let refused = Session::build_text(text, "run text", std::path::Path::new("."), 10)
            .err()
            .expect("over the limit");
        assert!(refused.to_string().starts_with("run text: "), "{refused}");
        assert!(
            refused.to_string().contains("input limit of 10"),
            "{refused}"
        );
    }

    /// An editor draws a spline source from its view and the current values: every patch's
    /// points are parameters of the system; other sources draw nothing; unknown ones are named.
    #[test]
    fn an_editor_gets_the_view_of_a_spline_and_nothing_from_a_linear_source() {
        let run = r#"(sources: [
            (name: "worm", plugin: "spline2d", config: (mesh: "meshes/worm.obj", degree: 3)),
            (name: "eq", plugin: "linear", config: (parameters: {"a": "1"}, equations: ["a = 1"])),
        ])"#;
        let (_dir, session) = session(run);
        let Some(api::SourceView::BezierTriangles(view)) = session.view("worm").expect("view")
        else {
            panic!("spline2d draws Bézier triangles");
        };
        assert_eq!((view.degree, view.patches.len()), (3, 6));
        assert!(view
            .patches
            .iter()
            .flatten()
            .all(|p| session.system.params()[p.index()].name.starts_with("worm.")));
        assert_eq!(session.view("eq").expect("no view"), None);
        let unknown = session.view("nope").expect_err("unknown source");
        assert!(unknown.to_string().contains("\"nope\""), "{unknown}");
        // Without outputs, the view has no models.
        assert!(view.models.is_empty());
    }

    /// The view carries the models of the run file's outputs of that source, in run-file
    /// order (another source's outputs are not its own), placed in the reference mesh.
    #[test]
    fn the_view_carries_the_models_of_the_sources_outputs() {
        let run = r#"(sources: [
            (name: "worm", plugin: "spline2d", config: (mesh: "meshes/worm.obj", degree: 3)),
            (name: "star", plugin: "spline2d", config: (mesh: "meshes/starfish.obj", degree: 2)),
        ], outputs: [
            (source: "star", output: (model: "models/starfish-model.obj")),
            (source: "worm", output: (picture: "worm.svg")),
            (source: "worm", output: (picture: "w.svg", model: "models/worm-model.obj")),
        ])"#;
        let (_dir, session) = session(run);
        for (name, degree, model) in [("worm", 3, "worm"), ("star", 2, "starfish")] {
            let Some(api::SourceView::BezierTriangles(view)) = session.view(name).expect("view")
            else {
                panic!("spline2d draws Bézier triangles");
            };
            assert_eq!(view.degree, degree);
            assert_eq!(view.models.len(), 1, "{name}");
            let placed = &view.models[0];
            assert_eq!(placed.embedding.len(), placed.vertices.len());
            assert!(placed.embedding.iter().any(Option::is_some));
            assert_eq!(placed.name, format!("models/{model}-model.obj"));
            // The deformation view is the same spline without the models.
            let Some(api::SourceView::BezierTriangles(alone)) =
                session.deformation_view(name).expect("view")
            else {
                panic!("spline2d draws Bézier triangles");
            };
            assert!(alone.models.is_empty());
            assert_eq!(
                (alone.patches, alone.vertices),
                (view.patches, view.vertices)
            );
        }
    }

    #[test]
    fn an_editor_plans_initialises_drags_applies_and_undoes() {
        let (_dir, mut session) = session(WORM);
        let before = session.values.clone();
        let Planning::Planned(plan) = session
            .plan_operation(
                "worm",
                r#"(anchors: ["v3"], neighborhood: 2, translate: ("0", "6"), steps: 3)"#,
            )
            .expect("plans")
        else {
            panic!("refused");
        };
        assert_eq!(plan.steps.len(), 3);
        let edit = session.initialize(&plan).expect("initialises");
        // Drag frames: previews agree with the exact updates.
        for step in &plan.steps {
            let exact = edit.update(step).expect("solvable");
            let preview = edit.preview(step).expect("solvable");
            for ((_, e), p) in exact.derived.iter().zip(&preview) {
                for (x, y) in e.iter().zip(p) {
                    assert!((api::exact::rational_to_f64(x) - y).abs() < 1e-9);
                }
            }
        }
        let last = edit
            .update(plan.steps.last().expect("steps"))
            .expect("solvable");
        let entry = "Source(source: \"worm\", operation: ())".to_string();
        session.apply(&edit, &last, entry.clone()).expect("applies");
        assert!(session.system.violations(&session.values).is_empty());
        assert_ne!(session.values, before);
        // The edit is stale now: applying it again is refused.
        assert!(session.apply(&edit, &last, entry.clone()).is_err());
        let after = session.values.clone();
        assert!(session.undo());
        assert_eq!(session.values, before);
        assert!(!session.undo());
        // Redo restores the committed values exactly; a new commit forgets what was undone.
        assert_eq!(session.can_undo_redo(), (false, true));
        assert!(session.redo());
        assert_eq!(session.values, after);
        assert!(!session.redo());
        assert!(session.undo());
        let again = session.initialize(&plan).expect("initialises");
        let first = again.update(&plan.steps[0]).expect("solvable");
        session.apply(&again, &first, entry).expect("applies");
        assert_eq!(session.can_undo_redo(), (true, false));
    }

    /// The same session of overlapping edits committed as optima and as snapped points: both
    /// satisfy every row exactly; the snapped values stay small while the optima grow, each
    /// snapped edit reports a bound, and the float cross-check agrees within it.
    #[test]
    fn snapped_commits_keep_values_small_and_every_row_exact() {
        let edits = r#"edits: [
            Source(source: "worm", operation: (anchors: ["v3"], neighborhood: 3, translate: ("1/3", "6"))),
            Source(source: "worm", operation: (anchors: ["v4"], neighborhood: 3, translate: ("-2", "1/7"))),
            Source(source: "worm", operation: (anchors: ["v2"], neighborhood: 3, translate: ("5/11", "-3"))),
            Source(source: "worm", operation: (anchors: ["v3"], neighborhood: 3, translate: ("1", "1/13"))),
        ]"#;
        let run = |commit: &str| {
            check(&format!(
                "(sources: [(name: \"worm\", plugin: \"spline2d\", config: (mesh: \"meshes/worm.obj\"))],\n{commit} {edits})"
            ))
            .expect("runs")
        };
        let largest_denominator = |report: &crate::report::Report| {
            report
                .edits
                .last()
                .expect("edits")
                .values
                .iter()
                .flat_map(|v| &v.exact)
                .map(|x| x.split('/').nth(1).map_or(0, str::len))
                .max()
                .unwrap_or(0)
        };
        let optimum = run("");
        let snapped = run("commit: Snapped(grid_bits: 16),");
        for report in [&optimum, &snapped] {
            assert_eq!(report.summary.failed, 0);
            assert_eq!(report.summary.disagreements, 0, "{:?}", report.edits);
            assert!(report.edits.iter().all(|e| e.max_residual == "0"));
        }
        assert!(optimum.edits.iter().all(|e| e.snap.is_none()));
        for e in &snapped.edits {
            let snap = e.snap.as_ref().expect("a snapped commit is reported");
            assert_eq!(snap.grid_bits, 16);
            assert_eq!(snap.optimum_columns, 0);
            assert!(
                snap.distance_bound > 0.0 && snap.distance_bound < 1e-2,
                "{snap:?}"
            );
        }
        assert!(
            largest_denominator(&snapped) * 3 < largest_denominator(&optimum),
            "snapped {} digits, optimum {} digits",
            largest_denominator(&snapped),
            largest_denominator(&optimum)
        );
        let error =
            check("(sources: [],\n commit: Snapped(grid_bits: 0))").expect_err("grid out of range");
        assert!(
            error.to_string().contains(":2:") && error.to_string().contains("grid_bits 0"),
            "{error}"
        );
    }

    /// Identical equations, in one source and in two, get labels that tell them apart: the
    /// source, the row's index in it, then the source's own text.
    #[test]
    fn every_row_has_a_label_of_its_own() {
        let (_dir, session) = session(
            r#"(sources: [
                (name: "s", plugin: "linear", config: (parameters: {"x": "1"}, equations: ["x = 1", "x = 1"])),
                (name: "t", plugin: "linear", config: (parameters: {"x": "1"}, equations: ["x = 1"])),
            ])"#,
        );
        let labels: Vec<&str> = session
            .system
            .rows()
            .iter()
            .map(|r| r.label.as_str())
            .collect();
        assert_eq!(
            labels,
            ["s row 1: x = 1", "s row 2: x = 1", "t row 1: x = 1"]
        );
        assert_eq!(
            crate::session::unique_label("worm", 4, "worm: C1 edge 1-2 #0"),
            "worm row 5: C1 edge 1-2 #0"
        );
    }

    /// The report's structure of an edit: independent rows of `R_ED` take no matching (the
    /// structural rank is the number of equations, nothing over-determined); dependent rows
    /// are decomposed (four equations over two unknowns, consistent: rank 2, all four rows
    /// over-determined).
    #[test]
    fn the_structure_of_an_edit_with_and_without_independent_rows() {
        let dependent = check(
            r#"(sources: [(name: "c", plugin: "linear", config: (
                parameters: {"x": "1", "y": "1", "w": "1"},
                equations: ["x + y = 2", "x - y = 0", "y = 1", "w - x = 0"],
            ))], cross_check: None, edits: [
                Ecles(anchors: {"c.w": "1"}, derived: ["c.x", "c.y"]),
            ])"#,
        )
        .expect("runs");
        let edit = &dependent.edits[0];
        assert!(edit.solvable, "{:?}", edit.error);
        let s = edit.structure.as_ref().expect("a structure");
        assert_eq!((s.equations, s.unknowns, s.structural_rank), (4, 2, 2));
        assert_eq!(s.over_determined.len(), 4);
        assert_eq!(edit.rank, 2);
        let independent = check(
            r#"(sources: [(name: "c", plugin: "linear", config: (
                parameters: {"x": "1", "y": "1", "z": "1"},
                equations: ["x + y + z = 3", "x - y = 0"],
            ))], cross_check: None, edits: [
                Ecles(anchors: {"c.z": "2"}, derived: ["c.x", "c.y"]),
            ])"#,
        )
        .expect("runs");
        let edit = &independent.edits[0];
        assert!(edit.solvable, "{:?}", edit.error);
        let s = edit.structure.as_ref().expect("a structure");
        assert_eq!((s.equations, s.unknowns, s.structural_rank), (2, 2, 2));
        assert!(s.over_determined.is_empty());
        assert_eq!(edit.rank, 2);
    }

    /// A redundant row whose combination runs over hundreds of rows is given exactly, runs of
    /// consecutive rows with one coefficient as one term.
    #[test]
    fn long_combinations_are_given_compactly() {
        let n = 400;
        let parameters: Vec<String> = (0..n).map(|i| format!("\"x{i}\": \"0\"")).collect();
        let equations: Vec<String> = (0..n)
            .map(|i| format!("\"x{i} - x{} = 0\"", (i + 1) % n))
            .collect();
        let report = check(&format!(
            "(sources: [(name: \"c\", plugin: \"linear\", config: (parameters: {{{}}}, equations: [{}]))], cross_check: None)",
            parameters.join(", "),
            equations.join(", ")
        ))
        .expect("runs");
        assert_eq!(report.redundant.len(), 1);
        let terms = report.redundant[0].combination.as_ref().expect("exact");
        assert_eq!(terms.len(), 1, "{terms:?}");
        assert_eq!(terms[0].row, "c row 1: x0 - x1 = 0");
        assert_eq!(
            terms[0].through.as_deref(),
            Some("c row 399: x398 - x399 = 0")
        );
        assert_eq!(terms[0].rows, Some(399));
        assert_eq!(terms[0].coefficient, "-1");
    }

    #[test]
    fn runs_report_solutions_refusals_and_located_errors() {
        let report = check(&example("worm.ron")).expect("runs");
        assert_eq!(report.edits.len(), 3);
        assert!(report
            .edits
            .iter()
            .all(|e| e.solvable && e.max_residual == "0"));
        assert_eq!(report.summary.failed, 0);
        let report = check(&example("pumps.ron")).expect("runs");
        assert_eq!(report.summary.failed, 1);
        assert_eq!(
            report.edits[1].conflict.as_deref(),
            Some(&["pump row 2: p4 - p3 = 5".to_string()][..])
        );
        let error = check(
            "(\n  sources: [(name: \"worm\", plugin: \"spline2d\", config: (mesh: \"meshes/worm.obj\"))],\n  edits: [Ecles(anchors: {\"worm.v99\": (\"1\", \"2\")})],\n)",
        )
        .expect_err("unknown parameter");
        assert!(
            error
                .to_string()
                .contains(":3:11: edit 0: anchor \"worm.v99\" is not a parameter"),
            "{error}"
        );
    }
}
