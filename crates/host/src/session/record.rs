//! A session as a run file, and back: the run's own sources, backend, commit policy and
//! outputs with the edits committed so far (what an editor saves and autosaves; `ecles run`
//! on it repeats every edit and reaches the same exact values), and resuming such a file.

use super::Session;
use crate::error::RunError;
use crate::runfile;
use std::path::Path;

impl Session {
    /// The run file of the current state: this run's sources, settings and outputs as written,
    /// and the committed edits in force (undone ones left out) in order, after `comment`.
    pub fn session_run_file(&self, comment: &str) -> String {
        self.run.with_edits(comment, self.committed_edits())
    }

    /// Number of committed edits in force.
    pub fn committed_count(&self) -> usize {
        self.history.len()
    }

    /// Repeats the edits of `path`, a session saved from this run ([`Session::session_run_file`]),
    /// on the initial values: each becomes a committed edit (undoable one by one), and its
    /// outputs become the session's (they name the model loaded in an editor). Refused,
    /// with nothing changed, once an edit was committed here, when the file's sources or
    /// settings are not this run's, when an edit is bad input, or when an edit cannot be
    /// repeated (its refusal named with the file, line and column). Returns the number of
    /// edits repeated.
    pub fn resume(&mut self, path: &Path) -> Result<usize, RunError> {
        let file = path.display().to_string();
        if !self.history.is_empty() || !self.undone.is_empty() {
            return Err(RunError::input(format!(
                "{file}: a saved session is resumed before the first edit, not after"
            )));
        }
        let saved =
            runfile::read(path, self.input_limit).map_err(|e| RunError::input(e.to_string()))?;
        self.check_same_run(&file, &saved)?;
        self.check_edits(&file, &saved.edits)?;
        // The session's outputs (a model loaded in the editor) come with it.
        let outputs = std::mem::replace(&mut self.run.outputs, saved.outputs);
        if let Err(e) = self.check() {
            self.run.outputs = outputs;
            return Err(e);
        }
        for (index, entry) in saved.edits.iter().enumerate() {
            let outcome = self.run_entry(&file, entry, index);
            let failure = match outcome {
                Ok(report) if report.solvable => None,
                Ok(report) => Some(RunError::input(format!(
                    "{file}:{}: edit {index} cannot be repeated: {}",
                    entry.at,
                    report.error.unwrap_or_default()
                ))),
                Err(e) => Some(e),
            };
            if let Some(e) = failure {
                // Back to the state before the first repeated edit (configurations too).
                while self.undo() {}
                self.undone.clear();
                self.run.outputs = outputs;
                return Err(e);
            }
        }
        Ok(saved.edits.len())
    }

    /// Refuses a saved session whose sources, backend or commit policy differ from this run's:
    /// its edits were made on another system, or another way.
    fn check_same_run(&self, file: &str, saved: &runfile::RunFile) -> Result<(), RunError> {
        let run = self.run_name();
        if saved.sources.len() != self.run.sources.len() {
            return Err(RunError::input(format!(
                "{file}: it has {} sources, {run} has {}: it was saved from another run file, or the run file changed since",
                saved.sources.len(),
                self.run.sources.len()
            )));
        }
        for (theirs, ours) in saved.sources.iter().zip(&self.run.sources) {
            let same = theirs.name == ours.name
                && theirs.plugin == ours.plugin
                && theirs.config.text().trim() == ours.config.text().trim();
            if !same {
                return Err(RunError::input(format!(
                    "{file}:{}: source {:?} is not the one of {run}: it was saved from another run file, or the run file changed since",
                    theirs.at, theirs.name
                )));
            }
        }
        if saved.backend.simplify != self.run.backend.simplify
            || saved.commit_policy() != self.run.commit_policy()
        {
            return Err(RunError::input(format!(
                "{file}: its backend or commit policy is not the one of {run}"
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::session;

    const WORM: &str = r#"(sources: [(name: "worm", plugin: "spline2d", config: (mesh: "meshes/worm.obj", degree: 3))],
        outputs: [(source: "worm", output: (picture: "worm.svg"))])"#;

    /// Commits `operation` of the worm as the editor does.
    fn commit(session: &mut Session, operation: &str) {
        crate::testutil::commit_operation(session, "worm", operation);
    }

    /// The run file of a session repeats its edits in force: read back into a fresh session
    /// of the same run, it gives the same values exactly, edit by edit undoable; undone edits
    /// are left out.
    #[test]
    fn a_saved_session_resumes_to_the_same_exact_values() {
        let (dir, mut session) = session(WORM);
        commit(
            &mut session,
            r#"(anchors: ["v3"], neighborhood: 2, translate: ("1/3", "6"), steps: 1)"#,
        );
        commit(
            &mut session,
            r#"(anchors: ["v5"], neighborhood: 3, translate: ("-2", "0.5"), steps: 1)"#,
        );
        commit(
            &mut session,
            r#"(anchors: ["v0"], neighborhood: 1, translate: ("7", "7"), steps: 1)"#,
        );
        assert!(session.undo());
        let text = session.session_run_file("Saved for a test");
        assert!(text.starts_with("// Saved for a test\n"), "{text}");
        assert_eq!(text.matches("Source(source:").count(), 2, "{text}");
        assert!(
            text.contains(r#"(source: "worm", output: (picture: "worm.svg"))"#),
            "{text}"
        );
        let saved = dir.path().join("saved.ron");
        std::fs::write(&saved, &text).expect("write");

        let (_again_dir, mut fresh) = crate::testutil::session(WORM);
        assert_eq!(fresh.resume(&saved).expect("resumes"), 2);
        assert_eq!(fresh.values, session.values);
        assert_eq!(fresh.committed_count(), 2);
        assert_eq!(fresh.session_run_file("x"), session.session_run_file("x"));
        assert!(fresh.undo() && fresh.undo() && !fresh.undo());
        assert_eq!(fresh.values, fresh.initial);
        // Once an edit was undone or committed here, resuming is refused.
        let late = fresh.resume(&saved).expect_err("too late");
        assert!(late.to_string().contains("before the first edit"), "{late}");
    }

    /// A saved session of another run, or one whose edit cannot be repeated, is refused with
    /// its file and position, and changes nothing.
    #[test]
    fn a_foreign_or_unrepeatable_session_is_refused_and_changes_nothing() {
        let (dir, mut session) = session(WORM);
        let other = dir.path().join("other.ron");
        std::fs::write(
            &other,
            WORM.replace("degree: 3", "degree: 5").replace(
                "outputs:",
                r#"edits: [Source(source: "worm", operation: (anchors: ["v3"], translate: ("1", "0")))], outputs:"#,
            ),
        )
        .expect("write");
        let error = session.resume(&other).expect_err("another run");
        assert!(error.to_string().contains("other.ron:1:"), "{error}");
        assert!(error.to_string().contains("another run file"), "{error}");

        // Two pins that contradict each other once v3 moves: the second edit cannot be
        // repeated, the first is rolled back.
        let bad = dir.path().join("bad.ron");
        let edits = r#"edits: [
            Source(source: "worm", operation: (anchors: ["v3"], neighborhood: 1, translate: ("1", "0"))),
            Ecles(anchors: {"worm.v3": ["0", "0"], "worm.v4": ["0", "0"]}, derived: []),
        ], outputs:"#;
        std::fs::write(&bad, WORM.replace("outputs:", edits)).expect("write");
        let before = session.values.clone();
        let error = session.resume(&bad).expect_err("unrepeatable");
        assert!(error.to_string().contains("bad.ron:4:13:"), "{error}");
        assert!(
            error.to_string().contains("edit 1 cannot be repeated"),
            "{error}"
        );
        assert_eq!(session.values, before);
        assert_eq!(session.committed_count(), 0);
        assert_eq!(session.can_undo_redo(), (false, false));
    }
}
