//! Operations of the terrain source as written (the z0/z1/xy modes), checked before any edit.

use super::TerrainSource;
use api::config::from_ron;
use api::exact::Exact;
use api::SourceError;
use serde::Deserialize;
use spline2d::edit::{Neighborhood, Operation};
use spline2d::operation::{
    checked_steps, default_steps, find_anchors, motion, ExactList, NeighborhoodConfig,
    RotateConfig, ScaleConfig,
};

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct OperationConfig {
    /// `"z0"`, `"z1"` or `"xy"`.
    mode: String,
    anchors: Vec<String>,
    #[serde(default)]
    neighborhood: Option<NeighborhoodConfig>,
    #[serde(default)]
    dz: Option<Exact>,
    #[serde(default)]
    translate: Option<ExactList>,
    #[serde(default)]
    rotate: Option<RotateConfig>,
    #[serde(default)]
    scale: Option<ScaleConfig>,
    #[serde(default = "default_steps")]
    steps: u64,
}

/// An operation checked against the built terrain.
pub(super) struct CheckedOperation {
    /// [`SURFACES`] index of the edited surface.
    pub(super) surface: usize,
    pub(super) anchors: Vec<usize>,
    pub(super) neighborhood: Neighborhood,
    pub(super) operation: Operation,
    pub(super) steps: usize,
}
impl TerrainSource {
    /// Parses and checks an operation: schema, mode, anchors, neighbourhood, move and steps.
    pub(super) fn check(&self, text: &str) -> Result<CheckedOperation, SourceError> {
        let built = self.built()?;
        let what = format!("{} operation", built.name);
        let error = |message: String| SourceError::new(format!("{what}: {message}"));
        let op: OperationConfig = from_ron(text, &what)?;
        let surface = match op.mode.as_str() {
            "z0" => 0,
            "z1" => 1,
            "xy" if built.xy.is_some() => 2,
            "xy" => {
                return Err(error(
                    "mode \"xy\" needs `xy: true` in the source configuration".into(),
                ))
            }
            other => {
                return Err(error(format!(
                    "mode must be \"z0\" (bottom), \"z1\" (top) or \"xy\", not {other:?}"
                )))
            }
        };
        let anchors = find_anchors(&built.spline, &op.anchors).map_err(error)?;
        let operation = if surface == 2 {
            if op.dz.is_some() {
                return Err(error(
                    "mode \"xy\": give exactly one of translate, rotate or scale (dz is for z0/z1)"
                        .into(),
                ));
            }
            motion(
                op.translate.as_ref(),
                op.rotate.as_ref(),
                op.scale.as_ref(),
                2,
            )
            .map_err(|e| error(format!("mode \"xy\": {e}")))?
        } else {
            match (&op.dz, &op.translate, &op.rotate, &op.scale) {
                (Some(dz), None, None, None) => Operation::Translate {
                    by: vec![dz.0.clone()],
                },
                _ => {
                    return Err(error(format!(
                        "mode {:?} moves the anchors vertically: give dz (and no translate, rotate or scale)",
                        op.mode
                    )))
                }
            }
        };
        let steps = checked_steps(op.steps, built.spline.points().len()).map_err(error)?;
        Ok(CheckedOperation {
            surface,
            anchors,
            neighborhood: op.neighborhood.map_or(Neighborhood::Radius(3), |n| n.0),
            operation,
            steps,
        })
    }
}
