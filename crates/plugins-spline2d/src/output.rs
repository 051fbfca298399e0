//! The outputs of a `spline2d` source: checking an output request (file names, the model it
//! reads) before any edit runs, and rendering it after the edits: the deformed model as OBJ and
//! the before/after picture.
//!
//! ```ron
//! (
//!     picture: "worm.svg",               // before/after picture with the last edit highlighted
//!     model: "models/worm-model.obj",    // optional: deform this model, write <stem>-deformed.obj
//!     control_net: true,                 // draw the control net (default true)
//!     parts: false,                      // colour by Dulmage–Mendelsohn part
//!     image: (file: "photo.png"),        // optional: deform a raster image, see image_output
//! )
//! ```

use crate::image_output::{check_image, render_image, CheckedImage, ImageConfig};
use crate::plugin::Built;
use crate::svg::{before_after, Picture};
use api::config::{check_output_file_name, from_ron};
use api::{OutputFile, RenderRequest, SourceError, ViewModel, ViewModels};
use serde::Deserialize;
use spline2d::eval::{FloatSpline, Locator};
use spline2d::model::{
    deform_model, deformed_name, left_in_place_note, load_model_with_source, locate_vertices,
    plane_jacobian, Deformed, Model, ModelSource,
};
use std::path::{Path, PathBuf};

/// What to render.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct OutputConfig {
    /// Before/after picture file name: `.svg`, or `.png` (the same drawing rasterised, see
    /// [`crate::svg::raster`]).
    #[serde(default)]
    picture: Option<String>,
    /// A model to deform (OBJ, relative to the run file); written as `<stem>-deformed.obj`.
    #[serde(default)]
    model: Option<String>,
    /// Draw the control net (default true).
    #[serde(default = "default_true")]
    control_net: bool,
    /// Colour the "after" panel by Dulmage–Mendelsohn part: over-determined points and
    /// conditions red, well-determined orange (default false).
    #[serde(default)]
    parts: bool,
    /// A raster image to deform (see [`crate::image_output`]).
    #[serde(default)]
    image: Option<ImageConfig>,
}

fn default_true() -> bool {
    true
}

/// An output checked: the files it writes, in render order, and the model it reads.
pub(crate) struct CheckedOutput {
    config: OutputConfig,
    /// `<stem>-deformed.obj` with the model's full path.
    pub(crate) model: Option<(String, PathBuf)>,
    picture: Option<String>,
    /// The image to deform, read and checked.
    image: Option<CheckedImage>,
}

impl CheckedOutput {
    /// The files it writes, in render order: the deformed model, then the picture.
    pub(crate) fn files(&self) -> Vec<String> {
        self.model
            .iter()
            .map(|(name, _)| name.clone())
            .chain(self.picture.clone())
            .chain(self.image.as_ref().map(|i| i.name.clone()))
            .collect()
    }
}

/// Parses and checks an output of `built`; the model file must be a model.
pub(crate) fn check_output(
    built: &Built,
    text: &str,
    base_dir: &Path,
    limit: u64,
) -> Result<(CheckedOutput, Option<(Model, ModelSource)>), SourceError> {
    let what = format!("{} output", built.name);
    let config: OutputConfig = from_ron(text, &what)?;
    let error = |message: String| SourceError::new(format!("{what}: {message}"));
    if let Some(name) = &config.picture {
        check_output_file_name(name, "picture", "svg")
            .or_else(|_| check_output_file_name(name, "picture", "png"))
            .map_err(|_| {
                error(format!(
                    "picture {name:?} must be a plain file name ending in .svg or .png"
                ))
            })?;
    }
    let (model, loaded) = match &config.model {
        Some(path) => {
            let full = base_dir.join(path);
            let model = load_model_with_source(&full, limit).map_err(|e| error(e.to_string()))?;
            (Some((deformed_name(path), full)), Some(model))
        }
        None => (None, None),
    };
    let image = match &config.image {
        Some(image) => Some(check_image(image, base_dir, limit).map_err(error)?),
        None => None,
    };
    if config.picture.is_none() && model.is_none() && image.is_none() {
        return Err(error(
            "nothing to render; give picture, model and/or image".into(),
        ));
    }
    let checked = CheckedOutput {
        picture: config.picture.clone(),
        config,
        model,
        image,
    };
    let files = checked.files();
    if let Some((k, name)) = files
        .iter()
        .enumerate()
        .find(|(k, name)| files[..*k].contains(name))
    {
        return Err(error(format!(
            "two of its files (the deformed model, the picture, the deformed image) are named {name:?} (file {})",
            k + 1
        )));
    }
    Ok((checked, loaded))
}

/// Renders a checked output of `built` after the edits: the deformed model (when the output
/// names one), then the picture (when it names one).
pub(crate) fn render(
    built: &Built,
    request: &RenderRequest,
) -> Result<Vec<OutputFile>, SourceError> {
    let what = format!("{} output", built.name);
    let (checked, model) = check_output(
        built,
        &request.output,
        &request.base_dir,
        request.input_limit,
    )?;
    let error = |e: &dyn std::fmt::Display| SourceError::new(format!("{what}: {e}"));
    let after = built.params.positions(&request.values);
    let mut files = Vec::new();
    let (model, source) = match model {
        Some((model, source)) => (Some(model), Some(source)),
        None => (None, None),
    };
    let deformed = match &model {
        Some(model) => {
            let spline = FloatSpline::new(&built.spline, &after).map_err(|e| error(&e))?;
            let locator = Locator::new(built.spline.mesh());
            let deformed = deform_model(model, &spline, &locator).map_err(|e| error(&e))?;
            if let (Some((name, _)), Some(source)) = (&checked.model, &source) {
                let bytes = source
                    .write_deformed(model, &deformed.model, |v| {
                        let p = model.positions[v];
                        plane_jacobian(&spline, &locator, [p[0], p[1]])
                    })
                    .map_err(|e| error(&e))?;
                files.push(deformed_file(name, bytes, &deformed));
            }
            Some(deformed)
        }
        None => None,
    };
    if let Some(name) = &checked.config.picture {
        let svg = picture(
            built,
            request,
            &checked.config,
            &after,
            model.as_ref(),
            deformed.as_ref(),
        )
        .map_err(|e| error(&e))?;
        let file = if is_png(name) {
            let mut file = OutputFile::new(
                name.clone(),
                crate::svg::raster::svg_to_png(&svg).map_err(|e| error(&e))?,
            );
            file.notes.extend(crate::svg::raster::missing_fonts_note());
            file
        } else {
            OutputFile::new(name.clone(), svg.into_bytes())
        };
        files.push(file);
    }
    if let Some(image) = &checked.image {
        let spline = FloatSpline::new(&built.spline, &after).map_err(|e| error(&e))?;
        files.push(render_image(image, &built.spline, &spline).map_err(|e| error(&e))?);
    }
    if files.is_empty() {
        return Err(SourceError::new(format!(
            "{what}: nothing to render; give picture, model and/or image"
        )));
    }
    Ok(files)
}

/// The models that `outputs` (output texts of `built`, in run-file order) deform, for an
/// editor's view: each read and checked exactly as render reads it ([`check_output`]: the same
/// reader and limits; paths against the build's base directory, which is the run file's, as
/// render's), with its vertices, its triangles, and where render's deformation evaluates each
/// vertex ([`locate_vertices`] with the locator render builds). Outputs without a model add
/// nothing. At most [`MAX_VIEW_MODEL_VERTICES`] vertices in all, counted before each model is
/// placed; errors name the model file.
pub(crate) fn view_models(
    built: &Built,
    outputs: &[String],
) -> Result<Vec<ViewModel>, SourceError> {
    let mut models = ViewModels::default();
    let mut locator = None;
    for text in outputs {
        let (checked, model) = check_output(built, text, &built.base_dir, built.input_limit)?;
        let (Some(name), Some((model, _))) = (checked.config.model, model) else {
            continue;
        };
        let error = |message: String| {
            SourceError::new(format!("{} view: model {name:?}: {message}", built.name))
        };
        models.reserve(model.positions.len()).map_err(error)?;
        let locator = locator.get_or_insert_with(|| Locator::new(built.spline.mesh()));
        let embedding = locate_vertices(&model, locator);
        // A plane deformation has no layer: no relative heights.
        models
            .push(
                name.clone(),
                model.positions,
                &model.triangles,
                embedding,
                Vec::new(),
            )
            .map_err(error)?;
    }
    Ok(models.into_models())
}

/// The deformed model as an OBJ file named `name` (`bytes`: the model's own file with what
/// moved written again), with a note for the report on the vertices left in place outside the
/// reference mesh.
fn deformed_file(name: &str, bytes: Vec<u8>, deformed: &Deformed) -> OutputFile {
    let mut file = OutputFile::new(name.to_string(), bytes);
    file.notes.extend(left_in_place_note(
        &deformed.outside,
        "outside the reference mesh",
    ));
    file
}

/// Whether a picture is written as PNG (its name ends in `.png`, any case).
fn is_png(name: &str) -> bool {
    Path::new(name)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
}

/// The before/after picture: the spline at its initial and its current (`after`) positions,
/// the last edit's anchors, derived points and independent conditions highlighted on the
/// right, optionally its Dulmage–Mendelsohn parts, and the model before and after.
fn picture(
    built: &Built,
    request: &RenderRequest,
    config: &OutputConfig,
    after: &[Vec<api::Rational>],
    model: Option<&Model>,
    deformed: Option<&Deformed>,
) -> Result<String, crate::svg::SvgError> {
    let before = built.params.positions(&request.initial);
    let highlight = request.highlight.clone().unwrap_or_default();
    let anchors = built.points_of(&highlight.anchors);
    let derived = built.points_of(&highlight.derived);
    let conditions = built.conditions_of(&highlight.independent_rows);
    let mut before_picture = Picture::new(&built.spline)
        .positions(&before)
        .title(format!("{}: before", built.name))
        .reference_mesh(true)
        .deformed_mesh(true)
        .control_points(true)
        .control_net(config.control_net);
    let mut after_picture = Picture::new(&built.spline)
        .positions(after)
        .title(format!("{}: after", built.name))
        .reference_mesh(true)
        .deformed_mesh(true)
        .control_points(true)
        .control_net(config.control_net)
        .anchors(&anchors)
        .derived(&derived)
        .conditions(&conditions);
    if let (true, Some(parts)) = (config.parts, &request.structure) {
        after_picture = after_picture
            .group(
                "well-determined",
                "#ff7f0e",
                &built.points_of(&parts.well),
                &built.conditions_of(&parts.well_rows),
            )
            .group(
                "over-determined",
                "#d62728",
                &built.points_of(&parts.over),
                &built.conditions_of(&parts.over_rows),
            );
    }
    if let Some(model) = model {
        before_picture = before_picture.model(model, false, true);
    }
    if let Some(deformed) = deformed {
        after_picture = after_picture.model(&deformed.model, false, true);
    }
    before_after(&before_picture, &after_picture)
}
