//! The configuration of a spline as a run file writes it (the RON schema of a `spline2d`
//! source, also the `spline` field of a terrain and what the c2 plugin reads of its spline2d
//! source) and building the spline it describes.
//!
//! ```ron
//! (
//!     mesh: "meshes/worm.obj",     // OBJ file relative to the run file, or inline:
//!     // mesh: (vertices: [("0", "0"), ("10", "0"), ("0", "10")], triangles: [(0, 1, 2)]),
//!     degree: 5,                   // default 5
//!     smoothness: 1,               // C^r, default 1
//!     snap: "1/1000",              // optional: round coordinates to this grid
//!     orientation: "fix",          // "fix" (default) flips clockwise triangles, "reject" refuses
//! )
//! ```
//! Numbers that must be exact are written as strings (`"0.1"` is exactly 1/10) or integers;
//! floating-point literals are refused.
//!
//! It lives in the library, not in the plugin, so that every source reading a spline2d
//! configuration reads it with one schema and one set of messages.

use crate::mesh_io::{self, MeshOptions, OrientationPolicy};
use crate::spline::Spline;
use api::config::from_ron;
use api::exact::Exact;
use api::SourceError;
use serde::de::{self, Deserializer, MapAccess, Visitor};
use serde::Deserialize;
use std::fmt;
use std::path::{Path, PathBuf};

/// Vertices and triangles written in the configuration.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InlineMesh {
    /// Exact vertex coordinates.
    pub vertices: Vec<(Exact, Exact)>,
    /// Triangles as 0-based vertex indices.
    pub triangles: Vec<[usize; 3]>,
}

/// Where the reference mesh comes from: an OBJ file (relative to the run file) or
/// `(vertices: [...], triangles: [...])` written inline.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MeshSpec {
    /// An OBJ file.
    File(String),
    /// Inline data.
    Inline(InlineMesh),
}

impl<'de> Deserialize<'de> for MeshSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct MeshVisitor;
        impl<'de> Visitor<'de> for MeshVisitor {
            type Value = MeshSpec;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("an OBJ path or (vertices: [...], triangles: [...])")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<MeshSpec, E> {
                Ok(MeshSpec::File(v.to_string()))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<MeshSpec, A::Error> {
                const FIELDS: &[&str] = &["vertices", "triangles"];
                let (mut vertices, mut triangles) = (None, None);
                while let Some(key) = map.next_key::<String>()? {
                    match key.as_str() {
                        "vertices" if vertices.is_none() => vertices = Some(map.next_value()?),
                        "triangles" if triangles.is_none() => triangles = Some(map.next_value()?),
                        "vertices" | "triangles" => {
                            return Err(de::Error::custom(format!("{key} is given twice")))
                        }
                        other => return Err(de::Error::unknown_field(other, FIELDS)),
                    }
                }
                Ok(MeshSpec::Inline(InlineMesh {
                    vertices: vertices.ok_or_else(|| de::Error::missing_field("vertices"))?,
                    triangles: triangles.ok_or_else(|| de::Error::missing_field("triangles"))?,
                }))
            }
        }
        deserializer.deserialize_any(MeshVisitor)
    }
}

/// The configuration of a `spline2d` source (and of the reference spline of a terrain).
#[derive(Debug, Clone, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SplineConfig {
    /// The reference mesh.
    pub mesh: MeshSpec,
    /// Degree `d` (default 5; at most [`crate::spline::MAX_DEGREE`]).
    #[serde(default = "default_degree")]
    pub degree: usize,
    /// Smoothness `C^r` (default 1; below the degree).
    #[serde(default = "default_smoothness")]
    pub smoothness: usize,
    /// Round coordinates to this grid.
    #[serde(default)]
    pub snap: Option<Exact>,
    /// `"fix"` (default) flips clockwise triangles, `"reject"` refuses them.
    #[serde(default)]
    pub orientation: Option<String>,
}

fn default_degree() -> usize {
    5
}

fn default_smoothness() -> usize {
    1
}

/// Reads the mesh of a configuration (an OBJ path is resolved against `base_dir` and read
/// with at most `limit` bytes); returns it with the file read, if any.
fn read_mesh(
    config: &SplineConfig,
    name: &str,
    base_dir: &Path,
    limit: u64,
) -> Result<(mesh_io::MeshRead, Option<PathBuf>), SourceError> {
    let orientation = match config.orientation.as_deref() {
        None | Some("fix") => OrientationPolicy::Fix,
        Some("reject") => OrientationPolicy::Reject,
        Some(other) => {
            return Err(SourceError::new(format!(
                "{name}: orientation must be \"fix\" or \"reject\", not {other:?}"
            )))
        }
    };
    let options = MeshOptions {
        snap: config.snap.as_ref().map(|s| s.0.clone()),
        orientation,
    };
    let (read, file) = match &config.mesh {
        MeshSpec::File(path) => {
            let full = base_dir.join(path);
            (mesh_io::read_obj(&full, &options, limit), Some(full))
        }
        MeshSpec::Inline(inline) => (
            mesh_io::from_points(
                inline
                    .vertices
                    .iter()
                    .map(|(x, y)| [x.0.clone(), y.0.clone()])
                    .collect(),
                inline.triangles.clone(),
                &options,
            ),
            None,
        ),
    };
    let read = read.map_err(|e| SourceError::new(format!("{name}: {e}")))?;
    Ok((read, file))
}

/// A spline as a configuration describes it, with the mesh warnings and the mesh file read.
#[derive(Debug, Clone)]
pub struct SplineRead {
    /// The spline.
    pub spline: Spline,
    /// What the mesh reader repaired or found odd.
    pub warnings: Vec<mesh_io::MeshWarning>,
    /// The OBJ file read, if the mesh is not inline.
    pub file: Option<PathBuf>,
}

/// Builds the spline a `spline2d` configuration describes, as the `spline2d` source does:
/// reads the mesh (an OBJ path is resolved against `base_dir`, at most `limit` bytes) and builds
/// the spline of the configured degree and smoothness. Errors are prefixed with `name`.
pub fn spline_from_config(
    name: &str,
    config: &SplineConfig,
    base_dir: &Path,
    limit: u64,
) -> Result<SplineRead, SourceError> {
    let (read, file) = read_mesh(config, name, base_dir, limit)?;
    let spline = Spline::new(read.mesh, config.degree, config.smoothness)
        .map_err(|e| SourceError::new(format!("{name}: {e}")))?;
    Ok(SplineRead {
        spline,
        warnings: read.warnings,
        file,
    })
}

/// [`spline_from_config`] from the configuration's RON text, for plugins that build on a
/// `spline2d` source of the same run: its name and configuration text are in
/// [`api::BuildRequest::sources`], and its control points are the parameters
/// `{name}.{point name}` (see [`crate::spline::ControlPoint::name`]).
pub fn spline_from_config_text(
    name: &str,
    config: &str,
    base_dir: &Path,
    limit: u64,
) -> Result<SplineRead, SourceError> {
    let config: SplineConfig = from_ron(config, &format!("{name} config"))?;
    spline_from_config(name, &config, base_dir, limit)
}
