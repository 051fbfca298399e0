//! Files loaded from the page (a reference mesh, a model): a browser hands over a file's bytes
//! and name, never its path, so the editor keeps a copy in `<stem>.inputs/` beside the run file.
//! The session's run file (saved or autosaved) names that copy, and `ecles run` on it finds it
//! again: a session stays reproducible whatever was loaded into it.

use crate::outputs::write_atomically;
use std::path::{Path, PathBuf};

/// Longest name a loaded file may have.
const MAX_NAME: usize = 100;

/// A loaded file, kept.
pub(crate) struct Stored {
    /// Its path as the run file names it (relative to the run file's directory, `/`-separated).
    pub relative: String,
    path: PathBuf,
    /// Written now (a file with the same bytes may have been there already).
    created: bool,
}

/// The directory loaded files of `run` are kept in: `<stem>.inputs` beside it.
fn inputs_dir_name(run: &Path) -> String {
    let stem = run
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "run".into());
    format!("{stem}.inputs")
}

/// Checks a loaded file's name: a plain file name with an extension, no directory.
fn check_name(name: &str) -> Result<(), String> {
    let allowed = |c: char| c.is_ascii_alphanumeric() || "._-".contains(c);
    let has_extension = name
        .rsplit_once('.')
        .is_some_and(|(base, ext)| !base.is_empty() && !ext.is_empty());
    if name.is_empty()
        || name.len() > MAX_NAME
        || name.starts_with('.')
        || !name.chars().all(allowed)
        || !has_extension
    {
        return Err(format!(
            "{name:?}: a loaded file needs a plain name of at most {MAX_NAME} letters, digits, '.', '_' or '-', with an extension (rename it and load it again)"
        ));
    }
    Ok(())
}

/// Keeps `bytes`, loaded as `name`, in the inputs directory of `run`: under `name`, or
/// `base-2.ext`, `base-3.ext`, … when a different file already has that name (a file with the
/// same bytes is used as it is).
pub(crate) fn store(run: &Path, name: &str, bytes: &[u8]) -> Result<Stored, String> {
    check_name(name)?;
    let dir_name = inputs_dir_name(run);
    let dir = run
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
        .join(&dir_name);
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let (base, ext) = name.rsplit_once('.').unwrap_or((name, ""));
    for n in 1..=1000 {
        let file = if n == 1 {
            name.to_string()
        } else {
            format!("{base}-{n}.{ext}")
        };
        let path = dir.join(&file);
        let stored = |created| Stored {
            relative: format!("{dir_name}/{file}"),
            path: path.clone(),
            created,
        };
        match std::fs::read(&path) {
            Ok(existing) if existing == bytes => return Ok(stored(false)),
            Ok(_) => continue,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                write_atomically(&path, bytes).map_err(|e| e.to_string())?;
                return Ok(stored(true));
            }
            Err(e) => return Err(format!("cannot read {}: {e}", path.display())),
        }
    }
    Err(format!(
        "{}: 1000 different files are named like {name:?} already",
        dir.display()
    ))
}

/// Takes back a file the session refused: removed when it was written for it (and its
/// directory when that is left empty), so a refused load leaves nothing behind.
pub(crate) fn discard(stored: &Stored) {
    if stored.created {
        let _ = std::fs::remove_file(&stored.path);
        if let Some(dir) = stored.path.parent() {
            // Fails, as it should, when the directory holds other files.
            let _ = std::fs::remove_dir(dir);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_are_kept_beside_the_run_under_names_that_do_not_clash() {
        let dir = tempfile::tempdir().expect("dir");
        let run = dir.path().join("worm.ron");
        let a = store(&run, "model.obj", b"v 0 0\n").expect("stored");
        assert_eq!(a.relative, "worm.inputs/model.obj");
        let same = store(&run, "model.obj", b"v 0 0\n").expect("the same bytes");
        assert_eq!(same.relative, a.relative);
        assert!(!same.created);
        let b = store(&run, "model.obj", b"v 1 1\n").expect("other bytes");
        assert_eq!(b.relative, "worm.inputs/model-2.obj");
        discard(&b);
        assert!(!dir.path().join("worm.inputs/model-2.obj").exists());
        assert!(dir.path().join("worm.inputs/model.obj").exists());
        discard(&a);
        assert!(
            !dir.path().join("worm.inputs").exists(),
            "nothing left behind"
        );
        for bad in ["../x.obj", "x", ".obj", "a b.obj", "dir/x.obj", ""] {
            assert!(store(&run, bad, b"v 0 0\n").is_err(), "{bad:?}");
        }
    }
}
