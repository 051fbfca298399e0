//! C^r triangular Bézier spline deformations of the plane (thesis part II, chapters 10–14): the
//! library under the `spline2d` constraint source, shared with the terrain and c2 sources.
//!
//! * [`mesh`] / [`mesh_io`]: the reference mesh with exact coordinates, read from OBJ or an
//!   inline form and validated.
//! * [`spline`]: control points (shared per nominal position) and the `C^r` conditions.
//! * [`net`]: the global Bézier control net and distances on it.
//! * [`eval`]: evaluating the spline at points, exactly and fast in `f64` (point location grid,
//!   allocation-free evaluation).
//! * [`model`]: loading OBJ models and point clouds, deforming them, writing them back.
//!   Both OBJ readers (the exact mesh reader and the float model reader) share their lexical
//!   layer: statements, tokens with columns and face corners (`obj_text.rs`).
//! * [`params`]: declaring control points and conditions in a shared constraint system.
//! * [`edit`]: the 2DSD operations: selection, ExpandDerived, relative magnitudes, soft
//!   translation / rotation / scaling turned into ECLES edits.
//! * [`motion`]: exact rational rotations and scalings of the plane (no float on coordinates).
//! * [`config`]: the RON configuration of a spline and building the spline it describes.
//! * [`operation`]: the parts of a 2DSD operation as a run file writes them, checked.

pub mod config;
pub mod edit;
pub mod eval;
pub mod image;
pub mod mesh;
pub mod mesh_io;
pub mod model;
pub mod motion;
pub mod net;
mod obj_text;
pub mod operation;
pub mod params;
pub mod spline;
