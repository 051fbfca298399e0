//! Saving an editing session, and its autosave.
//!
//! * **Save** writes the session as a run file beside the run being edited (its sources,
//!   settings and outputs as written, and every committed edit in order, see
//!   [`Session::session_run_file`]), then runs that file as `ecles run` does and writes what
//!   `ecles run` would write for it (the outputs and `report.json`, in `<name>.out`) with
//!   `values.json`, every parameter's exact value. The run must reach exactly the editor's
//!   values, or the save fails: a saved session is proved reproducible when it is written.
//!   A failed save leaves the session file as it was; its output directory follows
//!   `ecles run`'s rule: all or nothing, and the previous `report.json` is removed before the
//!   outputs are written, so a failed save leaves no report that could be taken for its own.
//! * **Autosave** writes the same run file (without running it) to `<stem>.autosave.ron` beside
//!   the run after every commit, undo, redo and resume, atomically: killing the editor loses
//!   at most the drag under way. On start, an autosave with edits is offered for resuming
//!   ([`Session::resume`]); the first new commit replaces it.

use crate::commands::{default_out_dir, PreparedRun};
use crate::error::RunError;
use crate::outputs::{self, write_atomically};
use crate::session::Session;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// Longest file name a save may be given.
const MAX_NAME: usize = 100;

/// The file of exact values a save writes beside the outputs.
pub const VALUES_FILE: &str = "values.json";

/// The autosave of `run`: `<stem>.autosave.ron` in the same directory.
pub fn autosave_path(run: &Path) -> PathBuf {
    run.with_file_name(format!("{}.autosave.ron", stem(run)))
}

/// The name a save takes when none is given: `<stem>.session.ron`.
pub fn default_save_name(run: &Path) -> String {
    format!("{}.session.ron", stem(run))
}

fn stem(run: &Path) -> String {
    run.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "run".into())
}

/// The first lines of a saved run file.
fn comment(session: &Session, what: &str) -> String {
    format!(
        "{what} by `ecles edit` from {}: its sources, settings and outputs,\n\
         with the {} edits committed in the editor, in order. `ecles run` on this file repeats\n\
         them and reaches the editor's exact values.",
        session.run_path.display(),
        session.committed_count()
    )
}

/// Writes the autosave of the session's current state.
pub fn autosave(session: &Session, path: &Path) -> Result<(), RunError> {
    write_atomically(
        path,
        session
            .session_run_file(&comment(session, "Autosaved"))
            .as_bytes(),
    )
}

/// The number of edits in the autosave at `path`, when there is one worth offering (a
/// readable run file with at least one edit).
pub fn autosave_offer(path: &Path, limit: u64) -> Option<usize> {
    let saved = crate::runfile::read(path, limit).ok()?;
    (!saved.edits.is_empty()).then_some(saved.edits.len())
}

/// Checks the name of a save: a plain `.ron` file name (no directory), not the run file, its
/// autosave or any input of the run.
fn save_path(session: &Session, name: &str) -> Result<PathBuf, String> {
    let allowed = |c: char| c.is_ascii_alphanumeric() || "._-".contains(c);
    if name.len() > MAX_NAME
        || !name.ends_with(".ron")
        || name.starts_with('.')
        || !name.chars().all(allowed)
    {
        return Err(format!(
            "{name:?} is not a name to save under: letters, digits, '.', '_' and '-', ending in .ron, at most {MAX_NAME} characters"
        ));
    }
    let run = &session.run_path;
    let path = run.with_file_name(name);
    // Compared as files, not as text: on a case-insensitive file system `Worm.ron` is
    // `worm.ron`.
    let same_file = |a: &Path, b: &Path| match (std::fs::canonicalize(a), std::fs::canonicalize(b))
    {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    };
    let autosave = autosave_path(run);
    if same_file(&path, run) || same_file(&path, &autosave) {
        return Err(format!(
            "{name:?} is the run file or its autosave; choose another name"
        ));
    }
    if let Some(input) = session.inputs().iter().find(|i| same_file(&path, i)) {
        return Err(format!(
            "{name:?} is {}, an input of the run; choose another name",
            input.display()
        ));
    }
    Ok(path)
}

/// Saves the session as `name` (default [`default_save_name`]) beside the run file and writes
/// what `ecles run` writes for it, after checking that running it gives the editor's values.
/// Returns what was written.
pub fn save(session: &Session, name: Option<&str>, limit: u64) -> Result<Value, RunError> {
    let name = name.map_or_else(|| default_save_name(&session.run_path), str::to_string);
    let path = save_path(session, &name).map_err(RunError::input)?;
    let text = session.session_run_file(&comment(session, "Saved"));
    let previous = std::fs::read(&path).ok();
    write_atomically(&path, text.as_bytes())?;
    let written = run_saved(session, &path, limit);
    if written.is_err() {
        // A failed save leaves the file as it was.
        let _ = match &previous {
            Some(bytes) => write_atomically(&path, bytes),
            None => std::fs::remove_file(&path).map_err(|e| RunError::environment(e.to_string())),
        };
    }
    written
}

/// Runs the saved file at `path` as `ecles run` does and writes its outputs, report and
/// `values.json`; refused when its values are not the session's.
fn run_saved(session: &Session, path: &Path, limit: u64) -> Result<Value, RunError> {
    let out_dir = default_out_dir(path);
    let prepared = PreparedRun::prepare(path, limit)?;
    let mut files = prepared.outputs.files.clone();
    files.push(VALUES_FILE.to_string());
    outputs::check_targets(&out_dir, &files, &prepared.outputs.inputs)?;
    let executed = prepared.execute(|| {})?;
    if executed.report.summary.failed > 0 || executed.values != *session.values() {
        return Err(RunError::environment(format!(
            "running the saved session {} does not reach the editor's values; nothing was saved",
            path.display()
        )));
    }
    let system = session.system();
    let values: Vec<Value> = system
        .params()
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let exact: Vec<String> = session
                .values()
                .get(api::ParamId(i as u32))
                .iter()
                .map(api::format_rational)
                .collect();
            json!({ "name": p.name, "exact": exact })
        })
        .collect();
    let values_json = serde_json::to_string_pretty(&json!({
        "run": path.display().to_string(),
        "values": values,
    }))
    .map_err(|e| RunError::environment(format!("cannot encode the values: {e}")))?
        + "\n";
    outputs::remove_stale_report(&out_dir)?;
    executed.write(
        &out_dir,
        vec![(VALUES_FILE.to_string(), values_json.into_bytes())],
    )?;
    Ok(json!({
        "run": path.display().to_string(),
        "out": out_dir.display().to_string(),
        "files": files,
        "edits": session.committed_count(),
    }))
}
