//! The `spline2d` constraint source: smooth deformations of the plane given by degree-`d`
//! triangular Bézier splines on a reference mesh (thesis part II, chapters 10–14).
//!
//! * [`mesh`] / [`mesh_io`]: the reference mesh with exact coordinates, read from OBJ or an
//!   inline form and validated.
//! * [`spline`]: control points (shared per nominal position) and the `C^r` conditions.
//! * [`net`]: the global Bézier control net and distances on it.
//! * [`eval`]: evaluating the spline at points, exactly and fast in `f64` (point location grid,
//!   allocation-free evaluation).
//! * [`model`]: loading OBJ models and point clouds, deforming them, writing them back.
//! * [`svg`]: deterministic SVG pictures (meshes, control net, anchors, conditions, models,
//!   before/after).
//! * [`source`]: declaring control points and conditions in a shared constraint system.
//! * [`edit`]: the 2DSD operations: selection, ExpandDerived, relative magnitudes, soft
//!   translation / rotation / scaling turned into ECLES edits.
//! * [`motion`]: exact rational rotations and scalings of the plane (no float on coordinates).
//! * [`plugin`]: the [`api::ConstraintSource`] implementation (configuration, build, plan,
//!   render).

pub mod edit;
pub mod eval;
pub mod mesh;
pub mod mesh_io;
pub mod model;
pub mod motion;
pub mod net;
pub mod operation;
pub mod plugin;
pub mod source;
pub mod spline;
pub mod svg;
