//! The `terrain` constraint source: 2.5D deformations of terrains and 3D models (thesis part
//! III, chapters 17–19, the PrisMystic editor).
//!
//! A model inside a layer of prisms over the reference mesh `T` (bottom `z = a`, top `z = b`)
//! is deformed by `ψ(x, y, z) = (φ(x, y), α0·σ0(x, y) + α1·σ1(x, y))`, where `φ` is a planar
//! spline deformation (as in `spline2d`), `σ0` and `σ1` are scalar splines (the bottom and top
//! surfaces), and `α0 = (b − z)/(b − a)`, `α1 = (z − a)/(b − a)` (17.2.1). The three splines
//! share one reference mesh, degree and smoothness; their control values are the parameters
//! and their `C^r` conditions the rows.
//!
//! * [`heightfield`]: terrains as height fields (ESRI ASCII grids and plain grids), read exactly
//!   and triangulated into models.
//! * [`prism`]: the prism layer, exact prism coordinates and `ψ` in exact arithmetic.
//! * [`deform`]: `ψ` in floating point for large models, with derivatives.
//! * [`relief`]: shaded-relief PNG pictures.
//! * [`plugin`]: the [`api::ConstraintSource`] (configuration, build, the z0/z1/xy modes,
//!   rendered outputs, the editor's view of the prisms).

pub mod deform;
pub mod geotiff;
pub mod heightfield;
pub mod plugin;
pub mod prism;
pub mod relief;
pub mod resample;
