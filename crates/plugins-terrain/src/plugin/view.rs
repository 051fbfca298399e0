//! The terrain source's view for an interactive editor ([`api::Prisms`]): the reference mesh,
//! the layer `[a, b]`, per triangle the parameters of `σ0`, `σ1` and (with `xy: true`) `φ` in
//! multi-index order, and the models the request's outputs deform, each vertex placed where
//! the render's `ψ` evaluates it ([`PrismLocator`]) with its relative height in the layer.

use super::{Built, TerrainSource};
use crate::deform::PrismLocator;
use api::{ParamId, Prisms, SourceError, SourceView, ViewModel, ViewModels, ViewRequest};
use spline2d::params::SplineParams;
use spline2d::spline::Spline;

impl TerrainSource {
    /// The prisms of the built source and the models `request.outputs` deform
    /// ([`view_models`]).
    pub(super) fn prisms_view(&self, request: &ViewRequest) -> Result<SourceView, SourceError> {
        let built = self.built()?;
        let spline = &built.spline;
        let mesh = spline.mesh();
        Ok(SourceView::Prisms(Prisms {
            degree: spline.degree(),
            smoothness: spline.smoothness(),
            vertices: mesh.vertices().to_vec(),
            triangles: mesh.triangles().to_vec(),
            bottom: patches(spline, &built.bottom),
            top: patches(spline, &built.top),
            xy: built.xy.as_ref().map(|xy| patches(spline, xy)),
            reference_bottom: built.layer.bottom().clone(),
            reference_top: built.layer.top().clone(),
            models: view_models(self, built, &request.outputs)?,
        }))
    }
}

/// Per triangle of `spline`'s mesh, the parameters of its control points (of the surface whose
/// parameters are `params`) in the spline's order of a triangle's points, which is the
/// view's multi-index order `(d,0,0), (d−1,1,0), …, (0,0,d)` (as spline2d's view).
fn patches(spline: &Spline, params: &SplineParams) -> Vec<Vec<ParamId>> {
    (0..spline.mesh().triangles().len())
        .map(|t| {
            spline
                .triangle_points(t)
                .iter()
                .map(|&p| params.ids[p])
                .collect()
        })
        .collect()
}

/// The models that `outputs` (output texts of the source, in run-file order) deform, for an
/// editor's view: each read and checked exactly as render reads it (`check_output_text`: the
/// same readers — `.asc` grids, OBJ models, plain grids — and limits; paths against the
/// build's base directory, which is the run file's, as render's), with its vertices and the
/// triangles its deformed OBJ has (a height field's two triangles per grid cell, an OBJ's
/// polygons fan-triangulated), each vertex placed where the render's `ψ` evaluates it (one
/// [`PrismLocator::locate`], the location [`crate::deform::Psi::map`] makes: `None` for a
/// vertex outside the mesh or the layer, which `ψ` leaves in place) and its relative height
/// `(z − a)/(b − a)` as `ψ` computes it. At most [`MAX_VIEW_MODEL_VERTICES`] vertices in
/// all, counted before each model is placed; errors name the model file.
fn view_models(
    source: &TerrainSource,
    built: &Built,
    outputs: &[String],
) -> Result<Vec<ViewModel>, SourceError> {
    let mut models = ViewModels::default();
    let mut locator = None;
    for text in outputs {
        let checked = source.check_output_text(text, &built.base_dir, built.input_limit)?;
        let (name, model) = (checked.model_name, checked.model);
        let error = |message: String| {
            SourceError::new(format!("{} view: model {name:?}: {message}", built.name))
        };
        models.reserve(model.positions.len()).map_err(error)?;
        let locator =
            locator.get_or_insert_with(|| PrismLocator::new(built.spline.mesh(), &built.layer));
        let embedding: Vec<_> = model
            .positions
            .iter()
            .map(|&p| locator.locate(p).ok().map(|(t, beta, _)| (t, beta)))
            .collect();
        let relative_height = model
            .positions
            .iter()
            .map(|p| locator.relative_height(p[2]))
            .collect();
        models
            .push(
                name.clone(),
                model.positions,
                &model.triangles,
                embedding,
                relative_height,
            )
            .map_err(error)?;
    }
    Ok(models.into_models())
}
