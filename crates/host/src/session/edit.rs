//! Running an edit: planned by the run file or a source, executed on the exact backend and
//! cross-checked on the float one.

use super::Session;
use crate::analysis::{label, max_residual};
use crate::error::RunError;
use crate::report::{EditReport, ValueReport};
use crate::runfile::{EditKind, GenericEdit};
use api::{
    format_rational, ConstraintSystem, Factorization, Highlight, LinearBackend, ParamId,
    PlanRequest, PlannedStep, Rational, Value, Values,
};
use ecles::{Edit, EditError, EditSpec, UpdateResult};
use float_qr::FloatQr;
use num_traits::One;

impl Session {
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
