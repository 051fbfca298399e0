//! Deforming a model (a triangle mesh or point cloud in `f64`) by a spline deformation `φ` of
//! the plane: every vertex `(x, y, z)` becomes `(φ(x, y), z)`.
//!
//! Models are read from Wavefront OBJ ([`load_model`], [`parse_model`]); a deformed model is
//! written back as the same file with its moved vertices and their normals changed
//! ([`ObjSource::write_deformed`]), or as a plain triangle mesh ([`write_obj`]). The reader is a small one of its
//! own rather than `tobj`: `tobj` rejects 2D vertices (`v x y`), drops vertices used by no
//! face (so point clouds come back empty), renumbers vertices, and stores `f32` unless its
//! `use_f64` feature is on; a model's vertex numbers must survive the round trip so that
//! vertices reported outside the reference mesh can be found in the user's file.
//!
//! Reading is in `read.rs`, deforming (and the report note on vertices left in place) in
//! `deform.rs`, writing (and the name of a deformed model's file) in `write.rs`; their items are
//! re-exported here.

mod deform;
mod gltf_source;
mod matrix3;
mod obj_source;
mod ply_source;
mod read;
mod stl_source;
mod write;

pub use deform::{deform_model, left_in_place_note, locate_vertices, plane_jacobian};
pub use gltf_source::GltfSource;
pub use obj_source::ObjSource;
pub use ply_source::PlySource;
pub use read::{load_model, load_model_with_source, parse_model, ModelSource};
pub use stl_source::StlSource;
pub use write::{deformed_name, write_obj};

use std::path::PathBuf;

/// A model: vertex positions and triangles (0-based, possibly none for a point cloud).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Model {
    /// Vertex positions `(x, y, z)`; 2D files have `z = 0`.
    pub positions: Vec<[f64; 3]>,
    /// Triangles as vertex indices (polygons of the file fan-triangulated).
    pub triangles: Vec<[usize; 3]>,
}

/// A deformed model and the vertices that could not be deformed.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Deformed {
    /// The model with `(x, y)` of every vertex inside the reference mesh replaced by `φ(x, y)`;
    /// same vertex numbering and triangles.
    pub model: Model,
    /// Vertices outside the reference mesh (ascending). They keep their position; callers
    /// should report them rather than ship a silently half-deformed model.
    pub outside: Vec<usize>,
}

/// Why a model could not be read or deformed. Errors about files name the file.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// The file could not be read: missing, not a regular file, or too large.
    #[error("{path}: the model {reason}")]
    Input {
        /// The file.
        path: PathBuf,
        /// Why it was not read.
        reason: String,
    },
    /// The file has no vertices: it is not a model.
    #[error("{file}: the model has no vertices (no `v` lines)")]
    Empty {
        /// The file (or the name given to [`parse_model`]).
        file: String,
    },
    /// The OBJ text is malformed.
    #[error("{file}:{line}:{column}: {message}")]
    Parse {
        /// The file (or the name given to [`parse_model`]).
        file: String,
        /// 1-based line number.
        line: usize,
        /// 1-based column (in characters) of the offending item (1 for a whole line).
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// [`deform_model`] needs a deformation of the plane (values with 2 coordinates).
    #[error("a model can only be deformed by a spline with 2 coordinates, this one has {dim}")]
    NotAPlaneDeformation {
        /// Coordinates of the spline's values.
        dim: usize,
    },
    /// The locator and the spline were built from meshes with different triangle counts.
    #[error(
        "the locator has {locator} triangles but the spline has {spline}: build both from the same mesh"
    )]
    MeshMismatch {
        /// Triangles of the locator.
        locator: usize,
        /// Triangles of the spline.
        spline: usize,
    },
}
