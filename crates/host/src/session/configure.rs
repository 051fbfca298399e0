//! A source rebuilt with another configuration in the middle of a session: a `Configure(...)`
//! edit of a run file, or the editor's continuity switch and "load reference mesh".
//!
//! What becomes of the values is the mathematically plain choice, written here once:
//! a parameter the new system shares with the old one (same name, dimension and initial value:
//! the same control point of the same reference mesh) keeps its current value, any other
//! starts at its new initial value; if the values so made break rows of the new system (a C0
//! deformation made C1), they are *projected*: the least change (unit weights, exact least
//! squares) of the parameters connected to the broken rows after which every row holds, the
//! nearest state of the new system. A C1 deformation made C0 is therefore kept as it is, and a
//! C0 one made C1 becomes the nearest smooth one.

use super::{Built, ConfigPlace, Session, Step};
use crate::analysis::max_residual;
use crate::error::RunError;
use crate::report::EditReport;
use api::{ParamId, Values};
use ecles::Edit;
use std::collections::BTreeMap;

/// What [`Session::configure`] did with the values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Configured {
    /// Parameters that kept their current values.
    pub carried: usize,
    /// Parameters that start at their new initial values (new, or not the same as before).
    pub restarted: usize,
    /// Parameters moved by the projection onto the new rows (0: none was needed).
    pub projected: usize,
}

impl Session {
    /// The configuration source `name` is built with now (RON text): the run file's, or the
    /// last `Configure(...)`'s in force.
    pub fn source_config(&self, name: &str) -> Result<&str, RunError> {
        Ok(&self.loaded(name)?.config)
    }

    /// Rebuilds every source in run-file order, `source` with `config` (RON text in its
    /// schema) and the others with the configurations they have now, and makes the result the
    /// current system and values as the module describes: committed like an edit (`entry` is
    /// its run-file text; [`Session::undo`] puts the old sources, system and values back).
    /// Refused with nothing changed when a source refuses its configuration (`place` says
    /// where the configuration is written, for the message) or the projection fails.
    pub(super) fn configure_placed(
        &mut self,
        source: &str,
        config: &str,
        place: ConfigPlace,
        entry: String,
    ) -> Result<Configured, RunError> {
        let mut fresh = self.rebuilt(source, config, &place)?;
        let (mut values, mut configured) = self.carry_values(&fresh);
        let broken: Vec<api::RowId> = fresh
            .system
            .violations(&values)
            .into_iter()
            .map(|(row, _, _)| row)
            .collect();
        if !broken.is_empty() {
            let derived = connected_parameters(&fresh.system, &broken);
            configured.projected = derived.len();
            let projection = Edit::projection(&self.exact, &fresh.system, &values, derived)
                .map_err(|e| RunError::input(format!("source {source:?}: the values cannot be carried into the new configuration: {e}")))?;
            projection
                .project(&values)
                .map_err(|e| RunError::input(format!("source {source:?}: the values cannot be carried into the new configuration: {e}")))?
                .write_into(&mut values);
        }
        self.inputs.extend(fresh.inputs.iter().cloned());
        let mut built = Built {
            sources: std::mem::take(&mut fresh.sources),
            system: std::mem::take(&mut fresh.system),
            initial: std::mem::take(&mut fresh.values),
            graph: std::cell::OnceCell::new(),
        };
        self.swap_build(&mut built);
        self.undone.clear();
        self.history.push(Step {
            values: std::mem::replace(&mut self.values, values),
            highlight: std::mem::take(&mut self.last_highlight),
            entry,
            build: Some(built),
        });
        self.generation += 1;
        Ok(configured)
    }

    /// A session of this run with every source built again in run-file order, `source` with
    /// `config` and the others with the configurations they have now; its values are the new
    /// initial values. Nothing of `self` changes.
    pub(super) fn rebuilt(
        &self,
        source: &str,
        config: &str,
        place: &ConfigPlace,
    ) -> Result<Session, RunError> {
        self.loaded(source)?;
        let mut fresh = Session::empty(&self.run_path, self.run.clone(), self.input_limit);
        for (entry, loaded) in self.run.sources.iter().zip(&self.sources) {
            if entry.name == source {
                fresh.build_source(entry, config, place)?;
            } else {
                fresh.build_source(entry, &loaded.config, &ConfigPlace::Unplaced)?;
            }
        }
        fresh.initial = fresh.values.clone();
        Ok(fresh)
    }

    /// The editor's `Configure(...)`: [`Session::configure_placed`] with the entry made from
    /// `config`; errors name the source, not a place in a file.
    pub fn configure(&mut self, source: &str, config: &str) -> Result<Configured, RunError> {
        let entry = format!(
            "Configure(source: {}, config: {})",
            ron_string(source),
            config.trim()
        );
        self.configure_placed(source, config, ConfigPlace::Unplaced, entry)
    }

    /// The report of a `Configure(...)` edit of a run file.
    pub(super) fn configure_report(
        &self,
        index: usize,
        source: &str,
        outcome: Configured,
    ) -> EditReport {
        EditReport {
            index,
            kind: "configure".into(),
            source: Some(source.to_string()),
            solvable: true,
            plan: BTreeMap::from([
                ("carried".to_string(), outcome.carried as u64),
                ("restarted".to_string(), outcome.restarted as u64),
                ("projected".to_string(), outcome.projected as u64),
            ]),
            max_residual: max_residual(&self.system, &self.values),
            ..EditReport::default()
        }
    }

    /// The values of `fresh`'s system: the current value of each parameter this system has
    /// too with the same dimension and initial value, the fresh initial value otherwise.
    fn carry_values(&self, fresh: &Session) -> (Values, Configured) {
        let mut values = fresh.values.clone();
        let mut configured = Configured::default();
        for (i, param) in fresh.system.params().iter().enumerate() {
            let id = ParamId(i as u32);
            let same = self.system.param_id(&param.name).filter(|&old| {
                self.system.params()[old.index()].dim == param.dim
                    && self.initial.get(old) == fresh.values.get(id)
            });
            match same {
                Some(old) => {
                    if values
                        .set(&fresh.system, id, self.values.get(old).to_vec())
                        .is_ok()
                    {
                        configured.carried += 1;
                    } else {
                        configured.restarted += 1;
                    }
                }
                None => configured.restarted += 1,
            }
        }
        (values, configured)
    }
}

/// The parameters joined to `rows` through rows of `system` (the connected parts of its
/// parameter–row graph that hold them), increasing: the only parameters the least-squares
/// projection onto the rows moves.
fn connected_parameters(system: &api::ConstraintSystem, rows: &[api::RowId]) -> Vec<ParamId> {
    let mut row_seen = vec![false; system.rows().len()];
    let mut param_seen = vec![false; system.params().len()];
    let mut queue: Vec<api::RowId> = Vec::new();
    for &row in rows {
        if !row_seen[row.index()] {
            row_seen[row.index()] = true;
            queue.push(row);
        }
    }
    while let Some(row) = queue.pop() {
        for p in system.rows()[row.index()].body.params() {
            if param_seen[p.index()] {
                continue;
            }
            param_seen[p.index()] = true;
            for &next in system.rows_of(p) {
                if !row_seen[next.index()] {
                    row_seen[next.index()] = true;
                    queue.push(next);
                }
            }
        }
    }
    param_seen
        .iter()
        .enumerate()
        .filter(|(_, &seen)| seen)
        .map(|(i, _)| ParamId(i as u32))
        .collect()
}

/// `text` as a RON string literal.
fn ron_string(text: &str) -> String {
    serde_json::to_string(text).unwrap_or_else(|_| format!("{text:?}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::session;

    const WORM: &str = r#"(sources: [(name: "worm", plugin: "spline2d", config: (mesh: "meshes/worm.obj", degree: 5, smoothness: 1))],
        outputs: [(source: "worm", output: (picture: "worm.svg"))])"#;

    /// Commits `operation` of the worm as the editor does.
    fn commit(session: &mut Session, operation: &str) {
        crate::testutil::commit_operation(session, "worm", operation);
    }

    fn config(session: &Session, smoothness: &str) -> String {
        crate::config_text::set_field(
            session.source_config("worm").expect("worm"),
            "smoothness",
            smoothness,
            "mesh",
        )
        .expect("set")
    }

    /// C1 → C0 keeps the deformation as it is; an edit under C0 breaks smoothness; C0 → C1
    /// projects it onto the nearest smooth deformation, exactly; undo puts back each system
    /// with its values, and the session's run file repeats all of it.
    #[test]
    fn continuity_switches_keep_or_project_the_values_and_undo_exactly() {
        let (dir, mut session) = session(WORM);
        let c1_rows = session.system().rows().len();
        commit(
            &mut session,
            r#"(anchors: ["v3"], neighborhood: 3, translate: ("0", "6"), steps: 1)"#,
        );
        let smooth = session.values().clone();

        let c0 = config(&session, "0");
        let done = session.configure("worm", &c0).expect("C0");
        assert_eq!(
            session.system().rows().len(),
            0,
            "C0 has no smoothness rows"
        );
        assert!(c1_rows > 0);
        assert_eq!((done.restarted, done.projected), (0, 0));
        assert_eq!(done.carried, session.system().params().len());
        assert_eq!(session.values(), &smooth, "a C1 deformation is a C0 one");

        // Under C0 one control point moves alone: the deformation is no longer C1.
        commit(
            &mut session,
            r#"(anchors: ["v5"], neighborhood: 0, translate: ("3", "0"), steps: 1)"#,
        );
        let rough = session.values().clone();
        let c1 = config(&session, "1");
        let done = session.configure("worm", &c1).expect("C1");
        assert!(done.projected > 0, "{done:?}");
        assert_eq!(session.system().rows().len(), c1_rows);
        assert!(session.system().violations(session.values()).is_empty());
        assert_ne!(session.values(), &rough);

        let projected = session.values().clone();
        let text = session.session_run_file("continuity");
        assert_eq!(
            text.matches("Configure(source: \"worm\"").count(),
            2,
            "{text}"
        );
        let saved = dir.path().join("saved.ron");
        std::fs::write(&saved, &text).expect("write");
        let (_again, mut fresh) = crate::testutil::session(WORM);
        assert_eq!(fresh.resume(&saved).expect("resumes"), 4);
        assert_eq!(fresh.values(), &projected);
        assert_eq!(fresh.system().rows().len(), c1_rows);

        assert!(session.undo());
        assert_eq!(session.system().rows().len(), 0);
        assert_eq!(session.values(), &rough);
        assert!(session.undo() && session.undo());
        assert_eq!(session.values(), &smooth);
        assert_eq!(session.system().rows().len(), c1_rows);
        assert!(session.redo() && session.redo() && session.redo());
        assert_eq!(session.values(), &projected);
        assert_eq!(session.system().rows().len(), c1_rows);
    }

    /// Another reference mesh starts from its own identity wherever its control points differ;
    /// a configuration the source refuses changes nothing and is reported with the source.
    #[test]
    fn another_mesh_restarts_what_differs_and_a_refused_configuration_changes_nothing() {
        let (_dir, mut session) = session(WORM);
        commit(
            &mut session,
            r#"(anchors: ["v3"], neighborhood: 3, translate: ("0", "6"), steps: 1)"#,
        );
        let before = session.values().clone();
        let bad = crate::config_text::set_field(
            session.source_config("worm").expect("worm"),
            "smoothness",
            "5",
            "mesh",
        )
        .expect("set");
        let error = session.configure("worm", &bad).expect_err("C5 of degree 5");
        assert!(error.to_string().contains("source \"worm\""), "{error}");
        assert!(error.to_string().contains("C^5"), "{error}");
        assert_eq!(session.values(), &before);
        assert_eq!(session.committed_count(), 1);

        let inline = r#"(mesh: (vertices: [("0", "0"), ("10", "0"), ("0", "10")], triangles: [(0, 1, 2)]), degree: 5, smoothness: 1)"#;
        let done = session.configure("worm", inline).expect("another mesh");
        assert_eq!(
            done.carried + done.restarted,
            session.system().params().len()
        );
        assert!(done.restarted > 0, "{done:?}");
        assert!(session.system().violations(session.values()).is_empty());
        assert!(session.undo());
        assert_eq!(session.values(), &before);
    }

    /// A run file with `Configure(...)` runs it in order; a configuration its source refuses is
    /// found before the first edit runs, at its line and column.
    #[test]
    fn run_files_configure_in_order_and_bad_configurations_are_found_first() {
        let run = WORM.replace(
            "outputs:",
            r#"edits: [
                Configure(source: "worm", config: (mesh: "meshes/worm.obj", degree: 5, smoothness: 0)),
                Source(source: "worm", operation: (anchors: ["v5"], neighborhood: 0, translate: ("3", "0"))),
            ], outputs:"#,
        );
        let report = crate::testutil::check(&run).expect("runs");
        assert_eq!(report.edits[0].kind, "configure");
        assert_eq!(report.edits[0].plan.get("projected"), Some(&0));
        assert!(report.edits[1].solvable);
        assert_eq!(report.edits[1].derived.len(), 0, "C0: nothing follows");
        let bad = run.replace("smoothness: 0)", "smoothness: 7)");
        let error = crate::testutil::check(&bad).expect_err("refused");
        assert!(error.to_string().contains("run.ron:3:"), "{error}");
    }
}
