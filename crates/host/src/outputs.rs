//! Writing a run's files: all or nothing, report last.
//!
//! * At the start of a run the previous `report.json` of the output directory is removed, so a
//!   run that fails leaves no report that could be taken for its own.
//! * Every file is first written to a temporary file of a unique name in the output directory
//!   (`.worm.svg.XXXXXX.partial`, so concurrent runs into one directory never share one) and
//!   synced; only when all are written are they renamed into place, `report.json` last. A
//!   rename is atomic, so a reader sees an old file or a complete new one, never a truncated
//!   one, and the presence of `report.json` means the run completed.
//! * When anything fails (a full disk, a missing permission), the temporary files and the
//!   files this run already renamed into place are removed, and the error names the file.
//! * No output may overwrite an input of the run (the run file, a mesh, a model, a plugin):
//!   [`check_targets`] refuses that before the first edit runs.

use crate::error::RunError;
use std::collections::BTreeSet;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The name of the run report in the output directory.
pub const REPORT: &str = "report.json";

/// Removes the report a previous run left in `dir` (nothing to do when there is none).
pub fn remove_stale_report(dir: &Path) -> Result<(), RunError> {
    let path = dir.join(REPORT);
    match std::fs::remove_file(&path) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) if path.is_dir() => Err(RunError::input(format!(
            "{} is a directory, where the run report belongs: {e}",
            path.display()
        ))),
        Err(e) => Err(RunError::environment(format!(
            "cannot remove the previous report {}: {e}",
            path.display()
        ))),
    }
}

/// Checks that no output file of `names` (with `report.json`) in `dir` is one of `inputs`:
/// existing targets are compared with the inputs by their canonical paths (so links and `..`
/// do not hide a collision).
pub fn check_targets(dir: &Path, names: &[String], inputs: &[PathBuf]) -> Result<(), RunError> {
    let canonical_inputs: BTreeSet<PathBuf> = inputs
        .iter()
        .filter_map(|p| std::fs::canonicalize(p).ok())
        .collect();
    for name in names.iter().map(String::as_str).chain([REPORT]) {
        let target = dir.join(name);
        if let Ok(canonical) = std::fs::canonicalize(&target) {
            if canonical_inputs.contains(&canonical) {
                return Err(RunError::input(format!(
                    "the output {} would overwrite {}, an input of this run; choose another name or output directory (--out)",
                    target.display(),
                    canonical.display()
                )));
            }
        }
    }
    Ok(())
}

/// Creates `dir` (and its parents) if needed.
pub fn create_dir(dir: &Path) -> Result<(), RunError> {
    std::fs::create_dir_all(dir).map_err(|e| {
        RunError::environment(format!(
            "cannot create the output directory {}: {e}",
            dir.display()
        ))
    })
}

/// A file staged in the output directory under a temporary name.
struct Staged {
    temp: tempfile::NamedTempFile,
    target: PathBuf,
}

/// Writes `files` (name and contents) and then the report as `report.json` into `dir`, all or
/// nothing (see the module documentation). `report` streams the report's bytes into its
/// temporary file: a large optimum's report holds hundreds of megabytes of digits, which are
/// not gathered in memory first.
pub fn write_all(
    dir: &Path,
    files: &[(&str, &[u8])],
    report: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), RunError> {
    let mut staged = Vec::with_capacity(files.len() + 1);
    for &(name, bytes) in files {
        staged.push(stage(dir, name, |out| out.write_all(bytes))?);
    }
    staged.push(stage(dir, REPORT, report)?);
    let mut placed: Vec<PathBuf> = Vec::with_capacity(staged.len());
    for Staged { temp, target } in staged {
        match temp.persist(&target) {
            Ok(_) => placed.push(target),
            Err(e) => {
                // The remaining temporary files are removed when dropped.
                for path in &placed {
                    let _ = std::fs::remove_file(path);
                }
                return Err(RunError::environment(format!(
                    "cannot write {}: {}",
                    target.display(),
                    e.error
                )));
            }
        }
    }
    Ok(())
}

/// Writes one file atomically: through a synced temporary file in the same directory and a
/// rename, so a reader sees the old file or the whole new one.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), RunError> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let Staged { temp, target } = stage(dir, &name, |out| out.write_all(bytes))?;
    temp.persist(&target).map_err(|e| {
        RunError::environment(format!("cannot write {}: {}", target.display(), e.error))
    })?;
    Ok(())
}

/// Writes a fresh temporary file next to `dir/name` through `write` (buffered) and syncs it.
fn stage(
    dir: &Path,
    name: &str,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<Staged, RunError> {
    let target = dir.join(name);
    let fail = |e: std::io::Error| {
        RunError::environment(format!("cannot write {}: {e}", target.display()))
    };
    let mut temp = tempfile::Builder::new()
        .prefix(&format!(".{name}."))
        .suffix(".partial")
        .tempfile_in(dir)
        .map_err(fail)?;
    let mut out = std::io::BufWriter::with_capacity(STAGING_BUFFER, &mut temp);
    write(&mut out).map_err(fail)?;
    out.flush().map_err(fail)?;
    drop(out);
    temp.as_file().sync_all().map_err(fail)?;
    Ok(Staged { temp, target })
}

/// Bytes gathered before each write to a staged file.
const STAGING_BUFFER: usize = 1 << 20;

#[cfg(test)]
mod tests {
    use super::*;

    fn listing(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .expect("dir")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn writes_everything_and_the_report_last() {
        let dir = tempfile::tempdir().expect("dir");
        write_all(dir.path(), &[("a.svg", b"<svg/>")], |out| {
            out.write_all(b"{}\n")
        })
        .expect("write");
        assert_eq!(listing(dir.path()), ["a.svg", "report.json"]);
        assert_eq!(
            std::fs::read(dir.path().join("a.svg")).expect("read"),
            b"<svg/>"
        );
    }

    #[test]
    fn a_failure_leaves_nothing_of_the_run() {
        let dir = tempfile::tempdir().expect("dir");
        // `b.obj` cannot replace a directory: the second rename fails.
        std::fs::create_dir(dir.path().join("b.obj")).expect("dir");
        std::fs::write(dir.path().join("b.obj").join("keep"), b"x").expect("write");
        let error = write_all(
            dir.path(),
            &[("a.svg", b"a".as_slice()), ("b.obj", b"b".as_slice())],
            |out| out.write_all(b"{}"),
        )
        .expect_err("cannot replace a directory");
        assert_eq!(error.exit_code(), crate::error::EXIT_ENVIRONMENT);
        assert!(error.to_string().contains("b.obj"), "{error}");
        assert_eq!(listing(dir.path()), ["b.obj"]);
    }

    /// A report that fails while it is streamed (after more than the staging buffer's worth of
    /// bytes) fails the run with its name, and no file of the run is left, staged or placed.
    #[test]
    fn a_report_failing_midway_leaves_nothing() {
        let dir = tempfile::tempdir().expect("dir");
        let error = write_all(dir.path(), &[("a.svg", b"<svg/>".as_slice())], |out| {
            out.write_all(&vec![b' '; 3 * STAGING_BUFFER])?;
            Err(std::io::Error::other("the report cannot be encoded"))
        })
        .expect_err("the report fails");
        assert_eq!(error.exit_code(), crate::error::EXIT_ENVIRONMENT);
        let message = error.to_string();
        assert!(message.contains(REPORT), "{message}");
        assert!(message.contains("cannot be encoded"), "{message}");
        assert!(listing(dir.path()).is_empty());
    }

    #[test]
    fn stale_reports_are_removed_and_inputs_protected() {
        let dir = tempfile::tempdir().expect("dir");
        remove_stale_report(dir.path()).expect("nothing to remove");
        std::fs::write(dir.path().join(REPORT), b"old").expect("write");
        remove_stale_report(dir.path()).expect("remove");
        assert!(listing(dir.path()).is_empty());
        let run = dir.path().join("self.ron");
        std::fs::write(&run, b"()").expect("write");
        let error = check_targets(dir.path(), &["self.ron".into()], std::slice::from_ref(&run))
            .expect_err("would overwrite the run file");
        assert_eq!(error.exit_code(), crate::error::EXIT_INPUT);
        assert!(
            error.to_string().contains("an input of this run"),
            "{error}"
        );
        check_targets(dir.path(), &["other.svg".into()], &[run]).expect("no collision");
    }
}
