//! Running run files in process for the host's unit tests: most host behaviour is tested this
//! way, without spawning the binary.

use crate::commands::PreparedRun;
use crate::error::RunError;
use crate::report::Report;
use crate::session::{Planning, Session};
use std::path::{Path, PathBuf};

/// The bundled examples directory.
pub fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// A temporary directory that sees the bundled meshes, models and terrains, with `run_text`
/// as `run.ron`; returns the directory (keep it alive) and the run file's path.
pub fn beside_examples(run_text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("temporary directory");
    #[cfg(unix)]
    for sub in ["meshes", "models", "terrains"] {
        std::os::unix::fs::symlink(examples().join(sub), dir.path().join(sub)).expect("link");
    }
    let run = dir.path().join("run.ron");
    std::fs::write(&run, run_text).expect("write the run file");
    (dir, run)
}

/// Checks, analyses and runs `run_text` as `ecles run` does (nothing is written); the report.
pub fn check(run_text: &str) -> Result<Report, RunError> {
    let (_dir, run) = beside_examples(run_text);
    let prepared = PreparedRun::prepare(&run, api::input::DEFAULT_MAX_INPUT_BYTES)?;
    Ok(prepared.execute(|| {})?.report)
}

/// The session of `run_text`, built and checked (keep the directory alive).
pub fn session(run_text: &str) -> (tempfile::TempDir, Session) {
    let (dir, run) = beside_examples(run_text);
    let session =
        Session::build(&run, api::input::DEFAULT_MAX_INPUT_BYTES).expect("the session builds");
    session
        .check()
        .expect("every edit and output is well formed");
    (dir, session)
}

/// The text of a bundled run file.
pub fn example(name: &str) -> String {
    std::fs::read_to_string(examples().join(name)).expect("bundled run file")
}

/// Commits `operation` (RON text) of source `source` as the editor does: planned, initialised,
/// committed under the run's policy and recorded as a `Source(...)` entry.
pub fn commit_operation(session: &mut Session, source: &str, operation: &str) {
    let Planning::Planned(plan) = session.plan_operation(source, operation).expect("plans") else {
        panic!("refused: {operation}");
    };
    let edit = session.initialize(&plan).expect("initialises");
    let step = plan.steps.last().expect("a step");
    let result = session.committed_update(&edit, step).expect("solvable");
    let entry = format!("Source(source: {source:?}, operation: {operation})");
    session.apply(&edit, &result, entry).expect("applies");
}
