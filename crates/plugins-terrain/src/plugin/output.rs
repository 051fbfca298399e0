//! Outputs of the terrain source: checking them (the model read and validated, the files
//! announced), rendering the deformed model and the shaded-relief pictures.

use super::{load_terrain_with_source, Built, TerrainFile, TerrainSource};
use crate::deform::{DeformedModel, Psi};
use crate::relief::{self, Marker, Panel, Shading, View};
use api::config::{check_output_file_name, from_ron};
use api::exact::rational_to_f64;
use api::{OutputFile, ParamId, RenderRequest, SourceError, Values};
use serde::Deserialize;
use spline2d::model::{deformed_name, write_obj, Model};
use std::path::{Path, PathBuf};

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct OutputConfig {
    #[serde(default)]
    model: Option<String>,
    #[serde(default)]
    picture: Option<String>,
    #[serde(default = "default_size")]
    size: u32,
    #[serde(default = "default_true")]
    reference_mesh: bool,
    /// Vertical exaggeration of the relief's light (default 1).
    #[serde(default)]
    exaggeration: Option<api::exact::Exact>,
    /// `"same"` (default: positions in the heights' unit) or `"degrees"` (a geographic grid:
    /// positions in degrees of longitude and latitude, heights in metres).
    #[serde(default)]
    horizontal_units: Option<String>,
}

impl OutputConfig {
    /// How the pictures light the surface; `Err` for an exaggeration that is not positive or
    /// units other than `"same"` and `"degrees"`.
    fn shading(&self) -> Result<Shading, String> {
        let exaggeration = match &self.exaggeration {
            Some(e) if e.0 > api::Rational::from_integer(0.into()) => {
                api::exact::rational_to_f64(&e.0)
            }
            Some(e) => {
                return Err(format!(
                    "exaggeration {} must be positive",
                    api::format_rational(&e.0)
                ))
            }
            None => 1.0,
        };
        let degrees = match self.horizontal_units.as_deref() {
            None | Some("same") => false,
            Some("degrees") => true,
            Some(other) => {
                return Err(format!(
                    "horizontal_units {other:?} must be \"same\" or \"degrees\""
                ))
            }
        };
        Ok(Shading {
            exaggeration,
            degrees,
        })
    }
}

fn default_size() -> u32 {
    640
}

fn default_true() -> bool {
    true
}

/// An output checked: the model read, and the files it writes.
pub(super) struct CheckedOutput {
    config: OutputConfig,
    pub(super) model: Model,
    /// The model's or grid's file.
    source: TerrainFile,
    /// `<stem>-deformed.asc` (`.tif`): an ESRI grid (a GeoTIFF) is also written back as the
    /// same grid with its new heights — with φ, the deformed surface sampled on the grid again
    /// ([`crate::resample`]).
    grid_file: Option<String>,
    /// The model file as the output names it (relative to the run file, as written).
    pub(super) model_name: String,
    pub(super) model_path: PathBuf,
    /// `<stem>-deformed.obj`.
    pub(super) model_file: String,
    /// `<picture stem>` of `<stem>-before.png` and `<stem>-after.png`.
    pub(super) picture: Option<String>,
}

impl CheckedOutput {
    pub(super) fn files(&self) -> Vec<String> {
        let mut files = vec![self.model_file.clone()];
        files.extend(self.grid_file.clone());
        if let Some(stem) = &self.picture {
            files.push(format!("{stem}-before.png"));
            files.push(format!("{stem}-after.png"));
        }
        files
    }
}

impl TerrainSource {
    /// Parses and checks an output, reading the model (which must be a terrain or a model).
    pub(super) fn check_output_text(
        &self,
        text: &str,
        base_dir: &Path,
        limit: u64,
    ) -> Result<CheckedOutput, SourceError> {
        let built = self.built()?;
        let what = format!("{} output", built.name);
        let error = |e: &dyn std::fmt::Display| SourceError::new(format!("{what}: {e}"));
        let config: OutputConfig = from_ron(text, &what)?;
        let Some(model_path) = config.model.clone() else {
            return Err(error(
                &"give the model (terrain) to deform: model: \"terrain.asc\" (or .obj, or a plain grid)",
            ));
        };
        let picture = match &config.picture {
            Some(name) => {
                check_output_file_name(name, "picture", "png").map_err(|e| error(&e))?;
                let stem = Path::new(name)
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default();
                Some(stem)
            }
            None => None,
        };
        relief::check_width(config.size).map_err(|e| error(&e))?;
        config.shading().map_err(|e| error(&e))?;
        let full = base_dir.join(&model_path);
        let (model, source) = load_terrain_with_source(&full, limit).map_err(|e| error(&e))?;
        // An ESRI grid or a GeoTIFF is also written back in its own format.
        let grid_extension = match &source {
            TerrainFile::Grid(_) if crate::heightfield::is_esri(&full) => Some("asc"),
            TerrainFile::Grid(_) if crate::geotiff::is_geotiff(&full) => Some("tif"),
            _ => None,
        };
        let grid_file = grid_extension.map(|extension| {
            let stem = Path::new(&model_path)
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "terrain".into());
            format!("{stem}-deformed.{extension}")
        });
        let checked = CheckedOutput {
            model_file: deformed_name(&model_path),
            config,
            model,
            source,
            grid_file,
            model_name: model_path,
            model_path: full,
            picture,
        };
        let files = checked.files();
        if let Some(name) = files.iter().skip(1).find(|f| **f == files[0]) {
            return Err(error(&format!(
                "the deformed model and a picture are both named {name:?}"
            )));
        }
        Ok(checked)
    }

    /// Renders an output: the deformed model and, if asked, the relief pictures.
    pub(super) fn render_output(
        &self,
        request: &RenderRequest,
    ) -> Result<Vec<OutputFile>, SourceError> {
        let built = self.built()?;
        let what = format!("{} output", built.name);
        let error = |e: &dyn std::fmt::Display| SourceError::new(format!("{what}: {e}"));
        let checked =
            self.check_output_text(&request.output, &request.base_dir, request.input_limit)?;
        let (config, model, picture_stem) = (&checked.config, &checked.model, &checked.picture);
        let before = built.psi(&request.initial)?;
        let after = built.psi(&request.values)?;
        let deformed = after.deform(model);
        let bytes = match &checked.source {
            // The model's own file with what moved written again, normals by ψ's Jacobian.
            TerrainFile::Model(source) => source
                .write_deformed(model, &deformed.model, |v| {
                    let p = model.positions[v];
                    let (t, _, _) = after.locate(p).ok()?;
                    after.jacobian_in(t, p).map(|(_, j)| j)
                })
                .map_err(|e| error(&e))?,
            TerrainFile::Grid(_) => deformed_grid_obj(built, &deformed).map_err(|e| error(&e))?,
        };
        let mut model_file = OutputFile::new(checked.model_file.clone(), bytes);
        model_file.notes.extend(
            outside_lists(&deformed)
                .into_iter()
                .filter_map(|(list, place)| spline2d::model::left_in_place_note(list, place)),
        );
        let mut files = vec![model_file];
        if let (Some(name), TerrainFile::Grid(field)) = (&checked.grid_file, &checked.source) {
            let heights: Vec<Option<f64>> = if built.xy.is_none() {
                // The samples stay on their grid. The model numbers the samples with data row
                // by row from the south-west.
                let mut vertex = 0;
                field
                    .heights
                    .iter()
                    .map(|h| {
                        h.map(|_| {
                            vertex += 1;
                            deformed.model.positions[vertex - 1][2]
                        })
                    })
                    .collect()
            } else {
                // φ moves the samples: the deformed surface sampled on the grid again.
                crate::resample::resample(field, &deformed.model)
            };
            let bytes = match field.write_geotiff(&heights) {
                Some(written) => written.map_err(|e| error(&e))?,
                None => field
                    .write_esri(&heights)
                    .ok_or_else(|| error(&"the deformed heights do not fit the grid"))?
                    .into_bytes(),
            };
            files.push(OutputFile::new(name.clone(), bytes));
        }
        if let Some(picture) = picture_stem {
            let initial = before.deform(model).model;
            let lines = |psi: &Psi| {
                if config.reference_mesh {
                    mesh_lines(built, psi)
                } else {
                    Vec::new()
                }
            };
            let (lines_before, lines_after) = (lines(&before), lines(&after));
            let highlight = request.highlight.clone().unwrap_or_default();
            let markers_before = markers(built, &before, &request.initial, &highlight.anchors, &[]);
            let markers_after = markers(
                built,
                &after,
                &request.values,
                &highlight.anchors,
                &highlight.derived,
            );
            let panels = [
                Panel {
                    model: &initial,
                    lines: &lines_before,
                    markers: &markers_before,
                },
                Panel {
                    model: &deformed.model,
                    lines: &lines_after,
                    markers: &markers_after,
                },
            ];
            let shading = config.shading().map_err(|e| error(&e))?;
            let view = View::fit(&panels, config.size)
                .map_err(|e| error(&e))?
                .with_shading(shading);
            for (panel, when) in panels.iter().zip(["before", "after"]) {
                files.push(OutputFile::new(
                    format!("{picture}-{when}.png"),
                    relief::render(panel, &view).map_err(|e| error(&e))?,
                ));
            }
        }
        Ok(files)
    }
}

/// A deformed grid as OBJ, with a header naming the vertices left in place.
fn deformed_grid_obj(built: &Built, deformed: &DeformedModel) -> std::io::Result<Vec<u8>> {
    let mut bytes = format!(
        "# {}: deformed by the 2.5D map psi (prisms between z = {} and z = {})\n",
        built.name,
        api::format_rational(built.layer.bottom()),
        api::format_rational(built.layer.top())
    )
    .into_bytes();
    for (list, place) in outside_lists(deformed) {
        if !list.is_empty() {
            // 0-based vertex numbers, as in the reports.
            bytes.extend(
                format!(
                    "# {} vertices {place} were left in place (0-based): {list:?}\n",
                    list.len()
                )
                .into_bytes(),
            );
        }
    }
    write_obj(&deformed.model, &mut bytes)?;
    Ok(bytes)
}

/// The model vertices `ψ` left in place, with where they lie.
fn outside_lists(deformed: &DeformedModel) -> [(&[usize], &'static str); 2] {
    [
        (&deformed.outside_mesh, "outside the reference mesh"),
        (&deformed.outside_layer, "below the bottom or above the top"),
    ]
}

/// The edges of the reference mesh mapped by `φ`, as polylines.
fn mesh_lines(built: &Built, psi: &Psi) -> Vec<Vec<[f64; 2]>> {
    let samples = if psi.has_phi() { 16 } else { 1 };
    built
        .spline
        .topology()
        .edges
        .iter()
        .filter_map(|edge| {
            let &(t, k) = edge.faces.first()?;
            // The edge opposite corner k runs from corner k+1 to corner k+2.
            let (from, to) = ((k + 1) % 3, (k + 2) % 3);
            (0..=samples)
                .map(|s| {
                    let u = s as f64 / samples as f64;
                    let mut beta = [0.0; 3];
                    beta[from] = 1.0 - u;
                    beta[to] = u;
                    psi.phi_in(t, beta)
                })
                .collect::<Option<Vec<_>>>()
        })
        .collect()
}

/// Discs for the anchors (red) and derived points (orange) of the last edit of this source:
/// control points of `φ` where they are, points of `σ0`/`σ1` at the image of their nominal
/// position.
fn markers(
    built: &Built,
    psi: &Psi,
    values: &Values,
    anchors: &[ParamId],
    derived: &[ParamId],
) -> Vec<Marker> {
    let place = |id: ParamId| -> Option<[f64; 2]> {
        let (surface, point) = built.point_of(id)?;
        if surface == 2 {
            let v = values.get(id);
            return Some([rational_to_f64(v.first()?), rational_to_f64(v.get(1)?)]);
        }
        let nominal = built.spline.nominal(point);
        let z = rational_to_f64(built.layer.bottom());
        let image = psi
            .map([
                rational_to_f64(&nominal[0]),
                rational_to_f64(&nominal[1]),
                z,
            ])
            .ok()?;
        Some([image[0], image[1]])
    };
    let disc = |ids: &[ParamId], colour: [u8; 3], radius: f64| -> Vec<Marker> {
        ids.iter()
            .filter_map(|&id| place(id))
            .map(|at| Marker { at, colour, radius })
            .collect()
    };
    let mut out = disc(derived, [255, 127, 14], 2.5);
    out.extend(disc(anchors, [214, 39, 40], 4.5));
    out
}
