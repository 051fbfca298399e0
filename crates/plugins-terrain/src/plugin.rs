//! The `terrain` constraint source: the three splines of a 2.5D deformation as parameters and
//! integer rows, the z0/z1/xy editing modes of PrisMystic (thesis 18.5–18.6), deformed models
//! and shaded-relief pictures.
//!
//! # Parameters and rows
//! One spline of degree `d` and smoothness `C^r` on the reference mesh `T` gives the control
//! points (named as in `spline2d`: `v3`, `e3-7:2`, `t5:2,2,1`). For every control point the
//! source declares `{name}.bottom.{point}` (a coefficient of `σ0`, initially `a`) and
//! `{name}.top.{point}` (of `σ1`, initially `b`), and with `xy: true` also `{name}.xy.{point}`
//! (a control point of `φ`, two coordinates, initially its nominal position: `φ` is the
//! identity). The `C^r` conditions of each spline are integer rows labelled by surface:
//! `{name}: top C1 edge 3-4 #2`. Without `xy`, `φ` is the identity and has no parameters.
//!
//! # Configuration (RON)
//! ```ron
//! (
//!     spline: (mesh: "terrains/reference.obj", degree: 5, smoothness: 1), // spline2d's schema:
//!                                  // the reference mesh T (path or inline), degree, smoothness,
//!                                  // snap, orientation
//!     top: "20",                   // b: the top of the prisms
//!     bottom: "-20",               // a: the bottom (default −b, as in thesis 18.2); a < b
//!     xy: true,                    // also edit φ (default false: φ is the identity)
//! )
//! ```
//! Numbers that must be exact are strings (`"0.1"` is exactly 1/10) or integers.
//!
//! # Operations (RON)
//! ```ron
//! // z1-mode (z0 for the bottom): the anchors move vertically by dz; derived points follow
//! // by the 2DSD rules on the control net.
//! (mode: "z1", anchors: ["v4"], neighborhood: 3, dz: "12", steps: 2)
//! // xy-mode: spline2d's operations on φ (needs xy: true).
//! (mode: "xy", anchors: ["e4-5:2"], neighborhood: 4, translate: ("-6", "0"))
//! (mode: "xy", anchors: ["v4"], rotate: (center: ("20", "20"), degrees: "15", precision: 1000))
//! (mode: "xy", anchors: ["v4"], scale: (center: ("20", "20"), factor: "3/2", precision: 1000))
//! ```
//! `neighborhood` is `δ_max` on the control net (default 3) or `"all"`; `steps` (default 1)
//! splits the move into a drag. The derived set is expanded until the edit is strongly
//! solvable (verified exactly), so every step succeeds.
//!
//! # Outputs (RON)
//! ```ron
//! (
//!     model: "terrains/hills.asc", // the terrain or model to deform, relative to the run file:
//!                                  // .asc (ESRI ASCII grid), .obj, anything else a plain grid;
//!                                  // written as <stem>-deformed.obj
//!     picture: "hills.png",        // shaded relief before and after: hills-before.png and
//!                                  // hills-after.png, with the reference mesh and the last
//!                                  // edit's anchors (red) and derived points (orange)
//!     size: 640,                   // picture width in pixels (default 640)
//!     reference_mesh: true,        // draw T and φ(T) (default true)
//! )
//! ```
//! Model vertices outside the prisms (outside `T`, or `z` outside `[a, b]`) are left in place
//! and listed, with their counts, in the first lines of the deformed OBJ.

use crate::deform::{DeformedModel, Psi};
use crate::heightfield::HeightField;
use crate::prism::{PrismLayer, Surfaces};
use crate::relief::{self, Marker, Panel, View};
use api::config::{check_output_file_name, from_ron};
use api::exact::{rational_to_f64, Exact};
use api::{
    BuildRequest, ConstraintSource, Contribution, OperationCheckRequest, OperationPlan, Origin,
    OutputCheck, OutputCheckRequest, OutputFile, ParamId, PlanRequest, Rational, RenderRequest,
    SourceError, SummaryItem, Values,
};
use serde::Deserialize;
use spline2d::config::{spline_from_config, SplineConfig, SplineRead};
use spline2d::edit::{Neighborhood, Operation, SelectError, SplineEditor};
use spline2d::model::{deformed_name, load_model, write_obj, Model};
use spline2d::net::ControlNet;
use spline2d::operation::{
    checked_steps, default_steps, find_anchors, motion, operation_plan, ExactList,
    NeighborhoodConfig, RotateConfig, ScaleConfig,
};
use spline2d::params::SplineParams;
use spline2d::spline::Spline;
use std::path::{Path, PathBuf};

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct Config {
    /// A `spline2d` configuration (mesh, degree, smoothness, snap, orientation).
    spline: SplineConfig,
    top: Exact,
    #[serde(default)]
    bottom: Option<Exact>,
    #[serde(default)]
    xy: bool,
}

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
struct CheckedOperation {
    /// [`SURFACES`] index of the edited surface.
    surface: usize,
    anchors: Vec<usize>,
    neighborhood: Neighborhood,
    operation: Operation,
    steps: usize,
}

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
}

fn default_size() -> u32 {
    640
}

fn default_true() -> bool {
    true
}

/// An output checked: the model read, and the files it writes.
struct CheckedOutput {
    config: OutputConfig,
    model: Model,
    model_path: PathBuf,
    /// `<stem>-deformed.obj`.
    model_file: String,
    /// `<picture stem>` of `<stem>-before.png` and `<stem>-after.png`.
    picture: Option<String>,
}

impl CheckedOutput {
    fn files(&self) -> Vec<String> {
        let mut files = vec![self.model_file.clone()];
        if let Some(stem) = &self.picture {
            files.push(format!("{stem}-before.png"));
            files.push(format!("{stem}-after.png"));
        }
        files
    }
}

/// The three surfaces, in parameter order.
const SURFACES: [&str; 3] = ["bottom", "top", "xy"];

/// What a built source keeps.
#[derive(Debug, Clone)]
struct Built {
    name: String,
    spline: Spline,
    net: ControlNet,
    layer: PrismLayer,
    bottom: SplineParams,
    top: SplineParams,
    xy: Option<SplineParams>,
}

impl Built {
    /// The parameters of each surface, in [`SURFACES`] order (`None` for `φ` without `xy`).
    fn surfaces(&self) -> [Option<&SplineParams>; 3] {
        [Some(&self.bottom), Some(&self.top), self.xy.as_ref()]
    }

    /// `ψ` for the control values in `values`.
    fn psi(&self, values: &Values) -> Result<Psi, SourceError> {
        let last = self
            .surfaces()
            .iter()
            .flatten()
            .flat_map(|p| p.ids.last())
            .map(|id| id.index())
            .max()
            .unwrap_or(0);
        if values.len() <= last {
            return Err(SourceError::new(format!(
                "{}: the values given have {} parameters, the source's go up to #{last}",
                self.name,
                values.len()
            )));
        }
        let bottom = self.bottom.positions(values);
        let top = self.top.positions(values);
        let xy = self.xy.as_ref().map(|p| p.positions(values));
        Psi::new(
            &self.spline,
            &self.layer,
            Surfaces {
                phi: xy.as_deref(),
                bottom: &bottom,
                top: &top,
            },
        )
        .map_err(|e| SourceError::new(format!("{}: {e}", self.name)))
    }

    /// The surface ([`SURFACES`] index) and control point of a parameter of this source.
    fn point_of(&self, id: ParamId) -> Option<(usize, usize)> {
        self.surfaces()
            .iter()
            .enumerate()
            .find_map(|(s, params)| params.and_then(|p| p.point_of(id)).map(|point| (s, point)))
    }
}

/// The `terrain` source.
#[derive(Debug, Clone, Default)]
pub struct TerrainSource {
    built: Option<Built>,
}

impl TerrainSource {
    /// The spline (shared by the surfaces), once built.
    pub fn spline(&self) -> Option<&Spline> {
        self.built.as_ref().map(|b| &b.spline)
    }

    fn built(&self) -> Result<&Built, SourceError> {
        self.built
            .as_ref()
            .ok_or_else(|| SourceError::new("terrain: the source has not been built"))
    }
}

/// Reads the terrain or model to deform, of at most `limit` bytes: an ESRI grid (`.asc`), an
/// OBJ model (`.obj`) or a plain grid (anything else).
pub fn load_terrain(path: &Path, limit: u64) -> Result<Model, String> {
    let is_obj = path
        .extension()
        .is_some_and(|e| e.to_string_lossy().eq_ignore_ascii_case("obj"));
    if is_obj {
        load_model(path, limit).map_err(|e| e.to_string())
    } else {
        HeightField::read(path, limit)
            .map(|field| field.to_model())
            .map_err(|e| e.to_string())
    }
}

impl TerrainSource {
    /// Parses and checks an operation: schema, mode, anchors, neighbourhood, move and steps.
    fn check(&self, text: &str) -> Result<CheckedOperation, SourceError> {
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

    /// Parses and checks an output, reading the model (which must be a terrain or a model).
    fn check_output_text(
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
        let full = base_dir.join(&model_path);
        let model = load_terrain(&full, limit).map_err(|e| error(&e))?;
        let checked = CheckedOutput {
            model_file: deformed_name(&model_path),
            config,
            model,
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
}

/// Declares the spline as surface `surface` (`SURFACES` index) of source `name`: parameters
/// `{name}.{surface}.{point}`, rows labelled `{name}: {surface} {condition}`.
fn surface_contribution(
    spline: &Spline,
    name: &str,
    surface: usize,
    existing: usize,
    initial: Vec<Vec<Rational>>,
) -> (Contribution, SplineParams) {
    let label = SURFACES[surface];
    let dim = initial.first().map_or(1, Vec::len);
    let (mut contribution, params) =
        spline.contribution(&format!("{name}.{label}"), dim, existing, initial);
    for (row, condition) in contribution.rows.iter_mut().zip(spline.conditions()) {
        let item = format!("{label} {}", condition.label);
        row.label = format!("{name}: {item}");
        row.origin = Origin {
            source: name.to_string(),
            item,
        };
    }
    (contribution, params)
}

impl ConstraintSource for TerrainSource {
    fn kind(&self) -> &str {
        "terrain"
    }

    fn version(&self) -> &str {
        env!("CARGO_PKG_VERSION")
    }

    fn build(&mut self, request: &BuildRequest) -> Result<Contribution, SourceError> {
        let name = &request.name;
        let config: Config = from_ron(&request.config, &format!("{name} config"))?;
        let top = config.top.0;
        let bottom = config.bottom.map_or_else(|| -top.clone(), |b| b.0);
        let layer = PrismLayer::new(bottom, top)
            .map_err(|e| SourceError::new(format!("{name} config: {e}")))?;
        let SplineRead {
            spline,
            warnings,
            file,
        } = spline_from_config(
            &format!("{name} spline"),
            &config.spline,
            &request.base_dir,
            request.input_limit,
        )?;
        let n = spline.points().len();
        let existing = request.system.params().len();
        let (mut contribution, bottom) = surface_contribution(
            &spline,
            name,
            0,
            existing,
            spline.constant_positions(layer.bottom()),
        );
        let (upper, top) = surface_contribution(
            &spline,
            name,
            1,
            existing + n,
            spline.constant_positions(layer.top()),
        );
        let mut parts = vec![upper];
        let xy = if config.xy {
            let (plane, xy) = surface_contribution(
                &spline,
                name,
                2,
                existing + 2 * n,
                spline.identity_positions(),
            );
            parts.push(plane);
            Some(xy)
        } else {
            None
        };
        for part in parts {
            contribution.parameters.extend(part.parameters);
            contribution.rows.extend(part.rows);
        }
        let surfaces = if config.xy { 3 } else { 2 };
        let mut summary = spline.summary_counts();
        summary.extend([
            ("surfaces", surfaces),
            ("control_points_per_surface", n),
            ("conditions_per_surface", spline.conditions().len()),
        ]);
        contribution.summary = SummaryItem::sorted(summary);
        contribution.warnings = warnings.iter().map(|w| w.to_string()).collect();
        contribution.inputs = file.into_iter().collect();
        let net = ControlNet::new(&spline);
        self.built = Some(Built {
            name: name.clone(),
            spline,
            net,
            layer,
            bottom,
            top,
            xy,
        });
        Ok(contribution)
    }

    fn check_operation(&self, request: &OperationCheckRequest) -> Result<(), SourceError> {
        self.check(&request.operation).map(|_| ())
    }

    fn check_output(&self, request: &OutputCheckRequest) -> Result<OutputCheck, SourceError> {
        let checked =
            self.check_output_text(&request.output, &request.base_dir, request.input_limit)?;
        Ok(OutputCheck::new(checked.files(), vec![checked.model_path]))
    }

    fn plan(&self, request: &PlanRequest) -> Result<OperationPlan, SourceError> {
        let built = self.built()?;
        let what = format!("{} operation", built.name);
        let error = |message: String| SourceError::new(format!("{what}: {message}"));
        let op = self.check(&request.operation)?;
        let Some(params) = built.surfaces()[op.surface] else {
            return Err(error("the surface has no parameters".into()));
        };
        let (anchors, neighborhood, operation) = (&op.anchors, op.neighborhood, &op.operation);
        let editor = SplineEditor {
            spline: &built.spline,
            net: &built.net,
            params,
        };
        let refused = |e: SelectError| error(e.to_string());
        let (selection, plan) = editor
            .plan_operation(
                &request.system,
                &request.values,
                anchors,
                neighborhood,
                operation,
                op.steps,
            )
            .map_err(refused)?;
        Ok(operation_plan(&selection, plan))
    }

    fn render(&self, request: &RenderRequest) -> Result<Vec<OutputFile>, SourceError> {
        let built = self.built()?;
        let what = format!("{} output", built.name);
        let error = |e: &dyn std::fmt::Display| SourceError::new(format!("{what}: {e}"));
        let checked =
            self.check_output_text(&request.output, &request.base_dir, request.input_limit)?;
        let (config, model, picture_stem) = (&checked.config, &checked.model, &checked.picture);
        let before = built.psi(&request.initial)?;
        let after = built.psi(&request.values)?;
        let deformed = after.deform(model);
        let mut model_file = OutputFile::new(
            checked.model_file.clone(),
            deformed_obj(built, &deformed).map_err(|e| error(&e))?,
        );
        model_file.notes.extend(
            outside_lists(&deformed)
                .into_iter()
                .filter_map(|(list, place)| spline2d::model::left_in_place_note(list, place)),
        );
        let mut files = vec![model_file];
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
            let view = View::fit(&panels, config.size).map_err(|e| error(&e))?;
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

/// The deformed model as OBJ, with a header naming the vertices left in place.
fn deformed_obj(built: &Built, deformed: &DeformedModel) -> std::io::Result<Vec<u8>> {
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
        let nominal = &built.spline.points()[point].nominal;
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

#[cfg(test)]
mod tests {
    use super::*;
    use api::conformance::{self, Samples};
    use api::{ConstraintSystem, Factorization, IntMatrix, LinearBackend, RowBody};
    use ecles::{Edit, EditSpec};
    use exact_ldu::{ExactFactorization, ExactLdu};
    use std::path::PathBuf;

    /// The reference mesh of thesis Table 19.2 (a 2 × 2 grid of squares split by diagonals, 9
    /// vertices and 8 triangles), with the centre moved off the grid lines.
    const GRID: &str = r#"(mesh: (vertices: [("0", "0"), ("20", "0"), ("40", "0"), ("0", "20"), ("21", "19"),
        ("40", "20"), ("0", "40"), ("20", "40"), ("40", "40")],
        triangles: [(0, 1, 4), (0, 4, 3), (1, 2, 5), (1, 5, 4), (3, 4, 7), (3, 7, 6), (4, 5, 8), (4, 8, 7)]))"#;

    fn config(xy: bool) -> String {
        format!(r#"(spline: {GRID}, top: "20", xy: {xy})"#)
    }

    fn request(config: &str) -> BuildRequest {
        BuildRequest {
            base_dir: PathBuf::from("."),
            ..conformance::request("hills", config)
        }
    }

    /// A built source with its system and values.
    fn built(xy: bool) -> (TerrainSource, ConstraintSystem, Values) {
        let mut source = TerrainSource::default();
        let contribution = source.build(&request(&config(xy))).expect("build");
        let mut system = ConstraintSystem::new();
        let mut values = Values::default();
        contribution
            .apply_to(&mut system, &mut values)
            .expect("contribution applies");
        (source, system, values)
    }

    /// Plans `operation` and applies its last step exactly.
    fn edit(
        source: &TerrainSource,
        system: &ConstraintSystem,
        values: &mut Values,
        operation: &str,
    ) {
        let plan = source
            .plan(&PlanRequest {
                schema: api::SCHEMA_VERSION,
                operation: operation.into(),
                system: system.clone(),
                values: values.clone(),
            })
            .expect("plan");
        let spec = EditSpec::new(plan.anchors.clone(), plan.derived.clone());
        let edit: Edit<ExactFactorization> =
            Edit::initialize(&ExactLdu::default(), system, values, &spec).expect("initialize");
        let last = plan.steps.last().expect("a step");
        edit.apply(system, values, &last.anchors, &last.hints)
            .expect("strongly solvable edits succeed");
        assert!(system.violations(values).is_empty());
    }

    #[test]
    fn declares_two_surfaces_or_three_with_their_conditions() {
        for xy in [false, true] {
            let (source, system, values) = built(xy);
            let spline = source.spline().expect("built");
            let (n, conditions) = (spline.points().len(), spline.conditions().len());
            assert_eq!(
                (n, conditions),
                (121, 40),
                "thesis Table 19.2 (rows swapped back)"
            );
            let surfaces = if xy { 3 } else { 2 };
            assert_eq!(system.params().len(), surfaces * n);
            assert_eq!(system.rows().len(), surfaces * conditions);
            assert!(system.violations(&values).is_empty());
            let names: Vec<&str> = system.params().iter().map(|p| p.name.as_str()).collect();
            assert_eq!(names[0], "hills.bottom.v0");
            assert_eq!(names[n], "hills.top.v0");
            assert_eq!(
                values.get(ParamId(0)),
                &[Rational::from_integer((-20).into())]
            );
            assert_eq!(
                values.get(ParamId(n as u32)),
                &[Rational::from_integer(20.into())]
            );
            if xy {
                assert_eq!(names[2 * n], "hills.xy.v0");
                assert!(names.contains(&"hills.xy.v4"));
                assert_eq!(system.params()[2 * n].dim, 2);
            }
            for (s, surface) in SURFACES.iter().take(surfaces).enumerate() {
                let rows = &system.rows()[s * conditions..(s + 1) * conditions];
                assert!(rows
                    .iter()
                    .all(|r| r.label.starts_with(&format!("hills: {surface} C1 edge"))));
                assert!(rows.iter().all(|r| r.origin.source == "hills"));
                // The rank of each surface's system is points − dim S^r_d.
                let first = (s * n) as u32;
                let sparse: Vec<Vec<(usize, api::Integer)>> = rows
                    .iter()
                    .map(|r| match &r.body {
                        RowBody::Vector { terms, .. } => terms
                            .iter()
                            .map(|(id, c)| ((id.0 - first) as usize, c.clone()))
                            .collect(),
                        RowBody::Scalar { .. } => panic!("spline rows are vector rows"),
                    })
                    .collect();
                let matrix = IntMatrix::from_sparse(n, sparse).expect("in range");
                let rank = ExactLdu::default().factor(&matrix).expect("factor").rank();
                assert_eq!(rank, n - spline.spline_space_dimension(), "{surface}");
                // The 8 conditions around the interior vertex carry 2 dependencies.
                assert_eq!(rank, 38);
            }
        }
    }

    #[test]
    fn passes_the_conformance_checks() {
        let dir = tempfile::tempdir().expect("temporary directory");
        let terrain = dir.path().join("t.txt");
        std::fs::write(&terrain, "0 1 2\n1 2 3\n2 3 4\n").expect("write");
        let mut earlier = ConstraintSystem::new();
        earlier.add_parameter("earlier", 1).expect("fresh name");
        let on_earlier = BuildRequest {
            values: Values::zeros(&earlier),
            system: earlier,
            ..request(&config(true))
        };
        let samples = Samples {
            good: vec![request(&config(false)), on_earlier],
            bad: [
                r#"(spline: (mesh: "missing.obj"), top: "1")"#.to_string(),
                format!(r#"(spline: {GRID}, top: "1", bottom: "1")"#),
                format!(r#"(spline: {GRID}, top: 0.5)"#),
                format!(r#"(spline: {GRID}, top: "1", colour: 3)"#),
                format!(r#"(spline: {GRID})"#),
                "(".into(),
            ]
            .iter()
            .map(|c| request(c))
            .collect(),
            operations: vec![
                r#"(mode: "z1", anchors: ["v4"], dz: "3")"#.into(),
                r#"(mode: "xy", anchors: ["v4"], translate: ("1", "0"))"#.into(),
                r#"(mode: "z2", anchors: ["v4"], dz: "3")"#.into(),
            ],
            outputs: vec![
                r#"(picture: "x.png")"#.into(),
                format!(
                    r#"(model: {:?}, picture: "x.png", size: 32)"#,
                    terrain.display().to_string()
                ),
            ],
        };
        let contributions =
            conformance::check_source(&mut || Box::new(TerrainSource::default()), &samples)
                .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(contributions[1].parameters[0].name, "hills.bottom.v0");
    }

    #[test]
    fn bad_operations_and_outputs_say_what_is_wrong() {
        let (source, system, values) = built(false);
        let plan = |op: &str| {
            source
                .plan(&PlanRequest {
                    schema: api::SCHEMA_VERSION,
                    operation: op.into(),
                    system: system.clone(),
                    values: values.clone(),
                })
                .expect_err(op)
                .message
        };
        for (op, needle) in [
            (
                r#"(mode: "xy", anchors: ["v4"], translate: ("1", "0"))"#,
                "needs `xy: true`",
            ),
            (
                r#"(mode: "z1", anchors: ["v4"], translate: ("1", "0"))"#,
                "give dz",
            ),
            (r#"(mode: "z3", anchors: ["v4"], dz: "1")"#, "mode must be"),
            (
                r#"(mode: "z0", anchors: ["v99"], dz: "1")"#,
                "no control point named \"v99\"",
            ),
            (
                r#"(mode: "z0", anchors: ["v4"], dz: 1.5)"#,
                "floating-point",
            ),
            (
                r#"(mode: "z0", anchors: ["v4"], dz: "1", neighborhood: "some")"#,
                "neighborhood",
            ),
            (r#"(mode: "z0", anchors: [], dz: "1")"#, "anchors is empty"),
        ] {
            let message = plan(op);
            assert!(message.starts_with("hills operation: "), "{message}");
            assert!(message.contains(needle), "{needle}: {message}");
        }
        let (source, system, values) = built(true);
        let message = source
            .plan(&PlanRequest {
                schema: api::SCHEMA_VERSION,
                operation: r#"(mode: "xy", anchors: ["v4"], dz: "1")"#.into(),
                system,
                values: values.clone(),
            })
            .expect_err("dz in xy")
            .message;
        assert!(message.contains("exactly one of translate"), "{message}");
        let render = |output: &str| {
            source
                .render(&RenderRequest {
                    schema: api::SCHEMA_VERSION,
                    input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
                    output: output.into(),
                    base_dir: PathBuf::from("."),
                    system: ConstraintSystem::new(),
                    initial: values.clone(),
                    values: values.clone(),
                    highlight: None,
                    structure: None,
                })
                .expect_err(output)
                .message
        };
        assert!(render("(picture: \"x.png\")").contains("give the model"));
        assert!(render("(model: \"t.asc\", picture: \"x.svg\")").contains("must end in .png"));
        assert!(render("(model: \"t.asc\", picture: \"d/x.png\")").contains("no directories"));
        assert!(render("(model: \"no/such.asc\")")
            .contains("no/such.asc: the height field cannot be read"));
        assert!(render("(model: \"/dev/zero\")").contains("character device"));
        assert!(render("(model: \"t.asc\", size: 100000)").contains("picture width"));
        let message = TerrainSource::default()
            .render(&RenderRequest {
                schema: api::SCHEMA_VERSION,
                input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
                output: "(model: \"t.asc\")".into(),
                base_dir: PathBuf::from("."),
                system: ConstraintSystem::new(),
                initial: Values::default(),
                values: Values::default(),
                highlight: None,
                structure: None,
            })
            .expect_err("not built")
            .message;
        assert!(message.contains("not been built"), "{message}");
    }

    /// A smooth terrain inside the layer [−20, 20] and its gradient.
    fn terrain(p: [f64; 2]) -> (f64, [f64; 2]) {
        let (x, y) = (p[0] / 6.0, p[1] / 9.0);
        (
            4.0 + 3.0 * x.sin() * y.cos(),
            [0.5 * x.cos() * y.cos(), -(3.0 / 9.0) * x.sin() * y.sin()],
        )
    }

    /// After a z edit and an xy edit the deformed terrain `S(x, y) = ψ(x, y, h(x, y))` of a
    /// smooth `h` is C1 across every interior edge of the reference mesh: evaluated with the
    /// polynomial pieces of the two triangles, value and gradient agree to rounding.
    #[test]
    fn deformed_terrains_are_c1_across_triangle_edges() {
        let (source, system, mut values) = built(true);
        let initial = values.clone();
        edit(
            &source,
            &system,
            &mut values,
            r#"(mode: "z1", anchors: ["v4"], neighborhood: 3, dz: "12", steps: 2)"#,
        );
        edit(
            &source,
            &system,
            &mut values,
            r#"(mode: "z0", anchors: ["e1-4:2"], neighborhood: 2, dz: "-5")"#,
        );
        edit(
            &source,
            &system,
            &mut values,
            r#"(mode: "xy", anchors: ["e4-5:2", "e4-5:3"], neighborhood: 4, translate: ("-6", "3/2"))"#,
        );
        let built = source.built().expect("built");
        let psi = built.psi(&values).expect("psi");
        let before = built.psi(&initial).expect("psi");
        let mut moved = [0.0f64; 3];
        let mut checked = 0;
        let vertices = built.spline.mesh().vertices();
        for edge in built
            .spline
            .topology()
            .edges
            .iter()
            .filter(|e| e.is_interior())
        {
            let [a, b] = [edge.a, edge.b].map(|v| vertices[v].clone().map(|c| rational_to_f64(&c)));
            for s in 1..8 {
                let u = f64::from(s) / 8.0;
                let p = [a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1])];
                let (h, dh) = terrain(p);
                let sides: Vec<([f64; 3], [[f64; 3]; 2])> = edge
                    .faces
                    .iter()
                    .map(|&(t, _)| {
                        let (value, j) = psi.jacobian_in(t, [p[0], p[1], h]).expect("triangle");
                        // Chain rule: ∂S/∂x = ∂ψ/∂x + ∂ψ/∂z · ∂h/∂x.
                        let grad =
                            [0, 1].map(|axis| [0, 1, 2].map(|r| j[r][axis] + j[r][2] * dh[axis]));
                        (value, grad)
                    })
                    .collect();
                let ((v0, g0), (v1, g1)) = (sides[0], sides[1]);
                let scale = v0
                    .iter()
                    .chain(g0.iter().flatten())
                    .fold(1.0f64, |m, x| m.max(x.abs()));
                for (x, y) in v0
                    .iter()
                    .zip(&v1)
                    .chain(g0.iter().flatten().zip(g1.iter().flatten()))
                {
                    assert!(
                        (x - y).abs() <= 1e-9 * scale,
                        "edge {}-{} at {p:?}: {x} vs {y}",
                        edge.a,
                        edge.b
                    );
                }
                // The edits changed the terrain here (at least somewhere).
                let old = before.map([p[0], p[1], h]).expect("inside");
                for c in 0..3 {
                    moved[c] = moved[c].max((v0[c] - old[c]).abs());
                }
                // The float map agrees with its own pieces.
                let mapped = psi.map([p[0], p[1], h]).expect("inside");
                for c in 0..3 {
                    assert!((mapped[c] - v0[c]).abs() <= 1e-9 * scale);
                }
                checked += 1;
            }
        }
        assert_eq!(checked, 8 * 7);
        // The derivatives are those of ψ: central differences inside each triangle agree.
        for t in 0..built.spline.mesh().triangles().len() {
            let corners = built.spline.mesh().triangles()[t]
                .map(|v| vertices[v].clone().map(|c| rational_to_f64(&c)));
            let p = [0, 1].map(|c| 0.3 * corners[0][c] + 0.3 * corners[1][c] + 0.4 * corners[2][c]);
            let at = [p[0], p[1], terrain(p).0];
            let (_, j) = psi.jacobian_in(t, at).expect("triangle");
            let step = 1e-5;
            for axis in 0..3 {
                let (mut plus, mut minus) = (at, at);
                plus[axis] += step;
                minus[axis] -= step;
                let (f, g) = (
                    psi.map(plus).expect("inside"),
                    psi.map(minus).expect("inside"),
                );
                for r in 0..3 {
                    let numeric = (f[r] - g[r]) / (2.0 * step);
                    assert!(
                        (numeric - j[r][axis]).abs() < 1e-5 * (1.0 + numeric.abs()),
                        "{numeric} vs {}",
                        j[r][axis]
                    );
                }
            }
        }
        assert!(moved.iter().all(|m| *m > 0.1), "{moved:?}");
    }

    /// The bundled terrain example's source (`examples/terrain.ron`) and the bundled height
    /// field `examples/terrains/hills.asc`.
    fn example() -> (TerrainSource, ConstraintSystem, Values, Model) {
        let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
        let config = r#"(spline: (mesh: "terrains/reference.obj", degree: 5, smoothness: 1),
            top: "20", xy: true)"#;
        let mut source = TerrainSource::default();
        let contribution = source
            .build(&BuildRequest {
                base_dir: examples.clone(),
                ..conformance::request("terrain", config)
            })
            .expect("build");
        let mut system = ConstraintSystem::new();
        let mut values = Values::default();
        contribution
            .apply_to(&mut system, &mut values)
            .expect("contribution applies");
        let hills = load_terrain(
            &examples.join("terrains/hills.asc"),
            api::input::DEFAULT_MAX_INPUT_BYTES,
        )
        .expect("hills.asc");
        (source, system, values, hills)
    }

    /// Without an edit the bundled terrain comes back bit-identical (x, y and z of every
    /// vertex; `α0·σ0 + α1·σ1` used to round heights such as 4.531 to 4.530999999999998).
    #[test]
    fn the_undeformed_example_terrain_is_returned_bit_identical() {
        let (source, _, values, hills) = example();
        let built = source.built().expect("built");
        let deformed = built.psi(&values).expect("psi").deform(&hills);
        assert_eq!(deformed.model.triangles, hills.triangles);
        assert_eq!(deformed.model.positions.len(), 33 * 33);
        for (image, p) in deformed.model.positions.iter().zip(&hills.positions) {
            assert_eq!(image.map(f64::to_bits), p.map(f64::to_bits), "{p:?}");
        }
        // Every sample is inside the prisms (cell centres on [0, 40]²), so all went through ψ.
        assert!(deformed.outside().is_empty());
    }

    /// Local edits of the bundled terrain (the top and bottom raised near vertex 0, φ moved
    /// near vertex 2, by awkward amounts): vertices over prisms whose control values did not
    /// change are bit-identical, the others agree with the exact `ψ` within the bound of
    /// [`Psi::map`].
    #[test]
    fn local_edits_of_the_example_terrain_leave_far_vertices_bit_identical() {
        let (source, system, mut values, hills) = example();
        for operation in [
            r#"(mode: "z1", anchors: ["v0"], neighborhood: 2, dz: "7/3")"#,
            r#"(mode: "z0", anchors: ["v0"], neighborhood: 2, dz: "-1/3")"#,
            r#"(mode: "xy", anchors: ["v2"], neighborhood: 2, translate: ("1/3", "-2/7"))"#,
        ] {
            edit(&source, &system, &mut values, operation);
        }
        let built = source.built().expect("built");
        let bottom = built.bottom.positions(&values);
        let top = built.top.positions(&values);
        let xy = built.xy.as_ref().expect("xy").positions(&values);
        let surfaces = Surfaces {
            phi: Some(&xy),
            bottom: &bottom,
            top: &top,
        };
        let checked = crate::deform::tests::check_against_exact(
            &built.spline,
            &built.layer,
            surfaces,
            &hills.positions,
        );
        assert!(
            checked.unchanged > 100 && checked.moved > 100,
            "{checked:?}"
        );
        // Samples on the walls between changed and unchanged prisms, where the exact ψ leaves
        // them in place, stay in place in floats too (their barycentric coordinate across the
        // wall is exactly 0, so only the wall's unchanged control values contribute).
        assert!(checked.exactly_in_place > 0, "{checked:?}");
        assert_eq!(checked.moved_in_floats_only, 0, "{checked:?}");
        eprintln!("{checked:?}");
    }

    #[test]
    fn renders_the_deformed_model_and_pictures() {
        let dir = tempfile::tempdir().expect("temporary directory");
        // A 9 × 9 height field over [0, 40]², one sample beyond the mesh and one above the top.
        let mut text = String::from("ncols 9\nnrows 9\nxllcenter 0\nyllcenter 0\ncellsize 5\n");
        for r in 0..9 {
            let row: Vec<String> = (0..9)
                .map(|c| match (r, c) {
                    (0, 0) => "25".to_string(),
                    _ => format!("{}", (r * c) % 7),
                })
                .collect();
            text.push_str(&row.join(" "));
            text.push('\n');
        }
        std::fs::write(dir.path().join("t.asc"), text).expect("write");
        std::fs::write(
            dir.path().join("m.obj"),
            "v 1 1 0\nv 50 1 0\nv 1 30 2\nf 1 2 3\n",
        )
        .expect("write");
        let (source, system, mut values) = built(true);
        let initial = values.clone();
        edit(
            &source,
            &system,
            &mut values,
            r#"(mode: "z1", anchors: ["v4"], dz: "10")"#,
        );
        let built = source.built().expect("built");
        let highlight = api::Highlight {
            anchors: vec![built.top.ids[4]],
            derived: vec![built.top.ids[5], built.top.ids[6]],
            independent_rows: vec![],
        };
        let render = |output: &str| {
            source.render(&RenderRequest {
                schema: api::SCHEMA_VERSION,
                input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
                output: output.into(),
                base_dir: dir.path().to_path_buf(),
                system: system.clone(),
                initial: initial.clone(),
                values: values.clone(),
                highlight: Some(highlight.clone()),
                structure: None,
            })
        };
        let files = render(r#"(model: "t.asc", picture: "t.png", size: 64)"#).expect("render");
        let names: Vec<&str> = files.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(names, ["t-deformed.obj", "t-before.png", "t-after.png"]);
        let obj = String::from_utf8(files[0].bytes.clone()).expect("utf8");
        assert!(obj.starts_with(
            "# hills: deformed by the 2.5D map psi (prisms between z = -20 and z = 20)\n"
        ));
        // The sample at height 25 (north-west corner, vertex 72) is above the top.
        assert!(
            obj.contains(
                "# 1 vertices below the bottom or above the top were left in place (0-based): [72]"
            ),
            "{obj}"
        );
        assert_eq!(
            files[0].notes,
            ["1 model vertex below the bottom or above the top left in place (0-based): 72"]
        );
        assert!(files[1..].iter().all(|f| f.notes.is_empty()));
        assert!(obj.contains("81 vertices, 128 triangles"));
        assert!(files[1..].iter().all(|f| f.bytes.starts_with(b"\x89PNG")));
        assert_ne!(files[1].bytes, files[2].bytes);
        // Deterministic.
        assert_eq!(
            render(r#"(model: "t.asc", picture: "t.png", size: 64)"#).expect("again"),
            files
        );
        let files = render(r#"(model: "m.obj")"#).expect("render");
        let obj = String::from_utf8(files[0].bytes.clone()).expect("utf8");
        assert!(
            obj.contains(
                "# 1 vertices outside the reference mesh were left in place (0-based): [1]"
            ),
            "{obj}"
        );
        assert_eq!(
            files[0].notes,
            ["1 model vertex outside the reference mesh left in place (0-based): 1"]
        );
        assert!(obj.contains("\nv 50 1 0\n"));
    }
}
