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
//!
//! # View
//! An editor's view is an [`api::Prisms`]: `T`, the layer `[a, b]`, per triangle the
//! parameters of `σ0`, `σ1` and (with `xy: true`) `φ` in multi-index order, and the models the
//! requested outputs deform, each vertex placed where `ψ` evaluates it, with its relative
//! height `(z − a)/(b − a)` (`view`). A drag of one of its points is an operation above: mode
//! `z0`, `z1` or `xy` after the point's surface, the anchor the parameter's name without
//! `{name}.{surface}.`.

mod operation;
mod output;
mod view;

use crate::deform::Psi;
use crate::heightfield::HeightField;
use crate::prism::{PrismLayer, Surfaces};
use api::config::from_ron;
use api::exact::Exact;
use api::{
    BuildRequest, ConstraintSource, Contribution, OperationCheckRequest, OperationPlan, Origin,
    OutputCheck, OutputCheckRequest, OutputFile, ParamId, PlanRequest, Rational, RenderRequest,
    SourceError, SourceView, SummaryItem, Values, ViewRequest,
};
use serde::Deserialize;
use spline2d::config::{spline_from_config, SplineConfig, SplineRead};
use spline2d::edit::{SelectError, SplineEditor};
use spline2d::model::{load_model_with_source, Model, ModelSource};
use spline2d::net::ControlNet;
use spline2d::operation::operation_plan;
use spline2d::params::SplineParams;
use spline2d::spline::Spline;
use std::path::Path;

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
/// The three surfaces, in parameter order.
const SURFACES: [&str; 3] = ["bottom", "top", "xy"];

/// What a built source keeps.
#[derive(Debug, Clone)]
struct Built {
    name: String,
    spline: Spline,
    /// The control net, built at the first operation planned (analyses never need it).
    net: std::sync::OnceLock<ControlNet>,
    layer: PrismLayer,
    bottom: SplineParams,
    top: SplineParams,
    xy: Option<SplineParams>,
    /// The build request's base directory: what the view resolves its outputs' model paths
    /// against (a view request carries none; render's base directory is the same run file's).
    base_dir: std::path::PathBuf,
    /// The build request's input limit, which the view's model reads keep too.
    input_limit: u64,
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
/// OBJ, STL, PLY or glTF model (`.obj`, `.stl`, `.ply`, `.gltf`, `.glb`) or a plain grid
/// (anything else).
pub fn load_terrain(path: &Path, limit: u64) -> Result<Model, String> {
    load_terrain_with_source(path, limit).map(|(model, _)| model)
}

/// A terrain or model file as read, for writing the deformed one back.
#[derive(Debug, Clone, PartialEq)]
pub enum TerrainFile {
    /// An OBJ, STL, PLY or glTF model, written back as the same file.
    Model(ModelSource),
    /// A height field (a GeoTIFF, an ESRI grid or a plain grid), written as a new OBJ (and a
    /// GeoTIFF or ESRI grid back as the same kind of grid when the terrain has no φ, see the
    /// output's documentation).
    Grid(Box<HeightField>),
}

/// [`load_terrain`] with the file itself (to write the deformed model back as the same file, in
/// its format).
pub fn load_terrain_with_source(path: &Path, limit: u64) -> Result<(Model, TerrainFile), String> {
    let is_model = path.extension().is_some_and(|e| {
        let e = e.to_string_lossy();
        ["obj", "stl", "ply", "gltf", "glb"]
            .iter()
            .any(|model| e.eq_ignore_ascii_case(model))
    });
    if is_model {
        load_model_with_source(path, limit)
            .map(|(model, source)| (model, TerrainFile::Model(source)))
            .map_err(|e| e.to_string())
    } else {
        HeightField::read(path, limit)
            .map(|field| (field.to_model(), TerrainFile::Grid(Box::new(field))))
            .map_err(|e| e.to_string())
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
    for row in &mut contribution.rows {
        let item = format!("{label} {}", row.origin.item);
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
            // Every surface has the same rows: one per condition.
            ("conditions_per_surface", contribution.rows.len() / surfaces),
        ]);
        contribution.summary = SummaryItem::sorted(summary);
        contribution.warnings = spline2d::mesh_io::summarize_warnings(&warnings);
        contribution.inputs = file.into_iter().collect();
        self.built = Some(Built {
            name: name.clone(),
            spline,
            net: std::sync::OnceLock::new(),
            layer,
            bottom,
            top,
            xy,
            base_dir: request.base_dir.clone(),
            input_limit: request.input_limit,
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
            net: built.net.get_or_init(|| ControlNet::new(&built.spline)),
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
        self.render_output(request)
    }

    /// The prisms: the reference mesh, the layer, per triangle the parameters of `σ0`, `σ1`
    /// and `φ` (with `xy: true`), and the models the request's outputs deform, placed where
    /// `ψ` evaluates them, with their relative heights (`view`).
    fn view(&self, request: &ViewRequest) -> Result<Option<SourceView>, SourceError> {
        self.prisms_view(request).map(Some)
    }
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod view_tests;
