//! The `spline2d` constraint source: smooth deformations of the plane given by degree-`d`
//! triangular Bézier splines on a reference mesh (thesis part II, chapters 10–14), as a plugin
//! of the host.
//!
//! The mathematics (meshes, splines, evaluation, models, the 2DSD editor) is the [`spline2d`]
//! library; this crate is the glue around it:
//!
//! * [`plugin`]: the [`api::ConstraintSource`] implementation (configuration, build, checks,
//!   plan), with its outputs (checking and rendering the deformed model and the picture) in
//!   `output.rs`;
//! * [`svg`]: deterministic SVG pictures (meshes, control net, anchors, conditions, models,
//!   before/after), the source's picture output.

mod image_output;
mod output;
pub mod plugin;
pub mod svg;
