//! Built-in constraint sources and the dynamic loader.

use api::ConstraintSource;
use plugin_abi::{library_file_name, load, LoadError};
use plugins_linear::LinearSource;
use plugins_spline2d::plugin::Spline2dSource;
use plugins_terrain::plugin::TerrainSource;
use std::path::{Path, PathBuf};

/// A built-in source kind with its constructor.
pub struct Builtin {
    /// Kind, as named in run files.
    pub kind: &'static str,
    /// Constructor.
    pub make: fn() -> Box<dyn ConstraintSource>,
}

/// The sources compiled into the host.
pub fn builtins() -> Vec<Builtin> {
    vec![
        Builtin {
            kind: "linear",
            make: || Box::new(LinearSource::new()),
        },
        Builtin {
            kind: "spline2d",
            make: || Box::new(Spline2dSource::default()),
        },
        Builtin {
            kind: "terrain",
            make: || Box::new(TerrainSource::default()),
        },
    ]
}

/// Where an instantiated source came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LoadedFrom {
    /// Compiled in.
    Builtin,
    /// Loaded from this library.
    Library(String),
}

/// True when a run file's `plugin` names a library rather than a built-in kind.
pub fn is_library(plugin: &str) -> bool {
    plugin.contains('/')
        || plugin.contains('\\')
        || [".so", ".dylib", ".dll"]
            .iter()
            .any(|ext| plugin.ends_with(ext))
}

/// Why a plugin could not be instantiated.
#[derive(Debug, thiserror::Error)]
pub enum RegistryError {
    /// Neither a built-in kind nor a library path.
    #[error("unknown plugin {plugin:?}: built-in plugins are {known}; a dynamic plugin is given by the path of its library")]
    Unknown {
        /// The name given.
        plugin: String,
        /// The built-in kinds.
        known: String,
    },
    /// The library could not be loaded.
    #[error(transparent)]
    Load(#[from] LoadError),
}

/// The file a run file's library path names, relative to `base_dir`. A path whose file name has
/// no extension names a library portably: `"../target/release/plugins_c2"` is
/// `libplugins_c2.so` on Linux, `libplugins_c2.dylib` on macOS and `plugins_c2.dll` on Windows.
pub fn library_path(plugin: &str, base_dir: &Path) -> PathBuf {
    let path = base_dir.join(plugin);
    match (path.extension(), path.file_name()) {
        (None, Some(stem)) => path.with_file_name(library_file_name(&stem.to_string_lossy())),
        _ => path,
    }
}

/// Instantiates the source named by a run file's `plugin` field (library paths are relative
/// to `base_dir`, see [`library_path`]).
pub fn instantiate(
    plugin: &str,
    base_dir: &Path,
) -> Result<(Box<dyn ConstraintSource>, LoadedFrom), RegistryError> {
    if is_library(plugin) {
        let path = library_path(plugin, base_dir);
        let loaded = load(&path)?;
        return Ok((
            Box::new(loaded.instantiate()),
            LoadedFrom::Library(path.display().to_string()),
        ));
    }
    builtins()
        .into_iter()
        .find(|b| b.kind == plugin)
        .map(|b| ((b.make)(), LoadedFrom::Builtin))
        .ok_or_else(|| RegistryError::Unknown {
            plugin: plugin.to_string(),
            known: builtins()
                .iter()
                .map(|b| format!("{:?}", b.kind))
                .collect::<Vec<_>>()
                .join(", "),
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tells_libraries_from_kinds() {
        assert!(is_library("plugins/libc2.so"));
        assert!(is_library("c2.dll"));
        assert!(!is_library("spline2d"));
        let err = instantiate("nope", Path::new(".")).err().expect("unknown");
        assert!(err.to_string().contains("\"linear\""), "{err}");
        let (source, origin) = instantiate("linear", Path::new(".")).expect("builtin");
        assert_eq!(source.kind(), "linear");
        assert_eq!(origin, LoadedFrom::Builtin);
    }

    #[test]
    fn library_paths_without_extension_follow_the_platform() {
        let base = Path::new("runs");
        assert_eq!(
            library_path("../lib/plugins_c2", base),
            base.join("../lib").join(library_file_name("plugins_c2"))
        );
        assert_eq!(
            library_path("lib/libc2.so", base),
            base.join("lib/libc2.so")
        );
    }
}
