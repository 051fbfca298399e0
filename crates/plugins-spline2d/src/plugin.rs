//! The `spline2d` constraint source as a plugin: configuration, build, planned operations and
//! rendered outputs.
//!
//! # Configuration (RON)
//! ```ron
//! (
//!     mesh: "meshes/worm.obj",     // OBJ file relative to the run file, or inline:
//!     // mesh: (vertices: [("0", "0"), ("10", "0"), ("0", "10")], triangles: [(0, 1, 2)]),
//!     degree: 5,                   // default 5
//!     smoothness: 1,               // C^r, default 1
//!     snap: "1/1000",              // optional: round coordinates to this grid
//!     orientation: "fix",          // "fix" (default) flips clockwise triangles, "reject" refuses
//! )
//! ```
//! Numbers that must be exact are written as strings (`"0.1"` is exactly 1/10) or integers;
//! floating-point literals are refused.
//!
//! # Operations (RON)
//! ```ron
//! (
//!     anchors: ["v4", "e4-5:2"],   // control point names (see `ControlPoint::name`)
//!     neighborhood: 3,             // δ_max on the control net, or "all"
//!     translate: ("3/2", "-1"),    // or rotate: (center: ("0", "0"), degrees: "30", precision: 1000)
//!                                  // or scale: (center: ("0", "0"), factor: "3/2", precision: 1000)
//!                                  // precision: 1..=10^12, default 10^6 (see `crate::motion`)
//!     steps: 4,                    // default 1
//! )
//! ```
//!
//! # Outputs (RON)
//! ```ron
//! (
//!     picture: "worm.svg",               // before/after picture with the last edit highlighted
//!     model: "models/worm-model.obj",    // optional: deform this model, write <stem>-deformed.obj
//!     parts: false,                      // colour by Dulmage–Mendelsohn part
//! )
//! ```

use crate::edit::{Neighborhood, Operation, SelectError, SplineEditor};
use crate::eval::{FloatSpline, Locator};
use crate::mesh_io::{self, MeshOptions, OrientationPolicy};
use crate::model::{deform_model, load_model, write_obj};
use crate::net::ControlNet;
use crate::source::SplineParams;
use crate::spline::Spline;
use crate::svg::{before_after, Picture};
use api::exact::Exact;
use api::{
    BuildRequest, ConstraintSource, Contribution, OperationPlan, OutputFile, PlanRequest,
    PlannedStep, Rational, RenderRequest, SourceError, SummaryItem,
};
use num_traits::One;
use serde::{Deserialize, Deserializer};
use std::path::Path;

/// Vertices and triangles written in the configuration.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct InlineMesh {
    vertices: Vec<(Exact, Exact)>,
    triangles: Vec<[usize; 3]>,
}

/// Deserialises a present field as `Some` (RON values carry no `Some(..)` wrapper here).
fn some<'de, D: Deserializer<'de>, T: Deserialize<'de>>(d: D) -> Result<Option<T>, D::Error> {
    T::deserialize(d).map(Some)
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct Config {
    /// A path (string) or an inline mesh; told apart after parsing for precise errors.
    mesh: ron::Value,
    #[serde(default = "default_degree")]
    degree: usize,
    #[serde(default = "default_smoothness")]
    smoothness: usize,
    #[serde(default, deserialize_with = "some")]
    snap: Option<Exact>,
    #[serde(default, deserialize_with = "some")]
    orientation: Option<String>,
}

fn default_degree() -> usize {
    5
}

fn default_smoothness() -> usize {
    1
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct RotateConfig {
    center: (Exact, Exact),
    degrees: Exact,
    #[serde(default = "default_precision")]
    precision: u64,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct ScaleConfig {
    center: (Exact, Exact),
    factor: Exact,
    #[serde(default = "default_precision")]
    precision: u64,
}

fn default_precision() -> u64 {
    1_000_000
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct OperationConfig {
    anchors: Vec<String>,
    /// `3` or `"all"`.
    #[serde(default, deserialize_with = "some")]
    neighborhood: Option<ron::Value>,
    #[serde(default, deserialize_with = "some")]
    translate: Option<Vec<Exact>>,
    #[serde(default, deserialize_with = "some")]
    rotate: Option<RotateConfig>,
    #[serde(default, deserialize_with = "some")]
    scale: Option<ScaleConfig>,
    #[serde(default = "default_steps")]
    steps: usize,
}

fn default_steps() -> usize {
    1
}

/// Parses RON text into `T` through `ron::Value`, so both struct syntax `(a: 1)` and the map
/// syntax the host forwards (`{"a": 1}`) are accepted.
pub(crate) fn from_ron<T: serde::de::DeserializeOwned>(
    text: &str,
    what: &str,
) -> Result<T, SourceError> {
    let value: ron::Value =
        ron::from_str(text).map_err(|e| SourceError::new(format!("{what}: {e}")))?;
    value
        .into_rust()
        .map_err(|e| SourceError::new(format!("{what}: {e}")))
}

/// What a built source keeps.
#[derive(Debug, Clone)]
struct Built {
    name: String,
    spline: Spline,
    net: ControlNet,
    params: SplineParams,
    /// Id of the row of the first condition (conditions are consecutive rows).
    first_row: usize,
}

/// What to render.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct OutputConfig {
    /// Before/after picture file name (`.svg`).
    #[serde(default, deserialize_with = "some")]
    picture: Option<String>,
    /// A model to deform (OBJ, relative to the run file); written as `<stem>-deformed.obj`.
    #[serde(default, deserialize_with = "some")]
    model: Option<String>,
    /// Draw the control net (default true).
    #[serde(default = "default_true")]
    control_net: bool,
    /// Colour the "after" panel by Dulmage–Mendelsohn part: over-determined points and
    /// conditions red, well-determined orange (default false).
    #[serde(default)]
    parts: bool,
}

fn default_true() -> bool {
    true
}

/// The `spline2d` source.
#[derive(Debug, Clone, Default)]
pub struct Spline2dSource {
    built: Option<Built>,
}

impl Spline2dSource {
    /// The spline, once built.
    pub fn spline(&self) -> Option<&Spline> {
        self.built.as_ref().map(|b| &b.spline)
    }

    fn built(&self) -> Result<&Built, SourceError> {
        self.built
            .as_ref()
            .ok_or_else(|| SourceError::new("spline2d: the source has not been built"))
    }
}

fn read_mesh(
    config: &Config,
    name: &str,
    base_dir: &Path,
) -> Result<mesh_io::MeshRead, SourceError> {
    let orientation = match config.orientation.as_deref() {
        None | Some("fix") => OrientationPolicy::Fix,
        Some("reject") => OrientationPolicy::Reject,
        Some(other) => {
            return Err(SourceError::new(format!(
                "{name}: orientation must be \"fix\" or \"reject\", not {other:?}"
            )))
        }
    };
    let options = MeshOptions {
        snap: config.snap.as_ref().map(|s| s.0.clone()),
        orientation,
    };
    let read = match &config.mesh {
        ron::Value::String(path) => mesh_io::read_obj(&base_dir.join(path), &options),
        other => {
            let inline: InlineMesh = other.clone().into_rust().map_err(|e| {
                SourceError::new(format!(
                    "{name}: mesh must be an OBJ path or (vertices: [...], triangles: [...]): {e}"
                ))
            })?;
            mesh_io::from_points(
                inline
                    .vertices
                    .iter()
                    .map(|(x, y)| [x.0.clone(), y.0.clone()])
                    .collect(),
                inline.triangles,
                &options,
            )
        }
    };
    read.map_err(|e| SourceError::new(format!("{name}: {e}")))
}

/// Reads a `spline2d` configuration exactly as [`Spline2dSource::build`] does: parses the RON
/// text, reads the mesh (an OBJ path is resolved against `base_dir`) and builds the spline of
/// the configured degree and smoothness. Errors are prefixed with `name` as the source's own
/// errors are.
///
/// For plugins that build on a `spline2d` source of the same run: its name and configuration
/// text are in [`api::BuildRequest::sources`], and its control points are the parameters
/// `{name}.{point name}` (see [`crate::spline::ControlPoint::name`]).
pub fn spline_from_config(
    name: &str,
    config: &str,
    base_dir: &Path,
) -> Result<(Spline, Vec<mesh_io::MeshWarning>), SourceError> {
    let config: Config = from_ron(config, &format!("{name} config"))?;
    let read = read_mesh(&config, name, base_dir)?;
    let spline = Spline::new(read.mesh, config.degree, config.smoothness)
        .map_err(|e| SourceError::new(format!("{name}: {e}")))?;
    Ok((spline, read.warnings))
}

impl ConstraintSource for Spline2dSource {
    fn kind(&self) -> &str {
        "spline2d"
    }

    fn version(&self) -> &str {
        env!("CARGO_PKG_VERSION")
    }

    fn build(&mut self, request: &BuildRequest) -> Result<Contribution, SourceError> {
        let (spline, warnings) =
            spline_from_config(&request.name, &request.config, &request.base_dir)?;
        let (mut contribution, params) = spline.contribution(
            &request.name,
            2,
            request.system.params().len(),
            spline.identity_positions(),
        );
        let topology = spline.topology();
        let mut summary = vec![
            ("vertices", spline.mesh().vertices().len()),
            ("edges", topology.edges.len()),
            ("interior_edges", topology.interior_edges()),
            ("interior_vertices", topology.interior_vertices()),
            ("triangles", spline.mesh().triangles().len()),
            ("degree", spline.degree()),
            ("smoothness", spline.smoothness()),
            ("control_points", spline.points().len()),
            ("conditions", spline.conditions().len()),
            ("spline_space_dimension", spline.spline_space_dimension()),
        ];
        summary.sort();
        contribution.summary = summary
            .into_iter()
            .map(|(key, value)| SummaryItem {
                key: key.to_string(),
                value: value as u64,
            })
            .collect();
        contribution.warnings = warnings.iter().map(|w| w.to_string()).collect();
        let net = ControlNet::new(&spline);
        self.built = Some(Built {
            name: request.name.clone(),
            spline,
            net,
            params,
            first_row: request.system.rows().len(),
        });
        Ok(contribution)
    }

    fn plan(&self, request: &PlanRequest) -> Result<OperationPlan, SourceError> {
        let built = self.built()?;
        let what = format!("{} operation", built.name);
        let op: OperationConfig = from_ron(&request.operation, &what)?;
        let anchors = op
            .anchors
            .iter()
            .map(|name| {
                built
                    .spline
                    .points()
                    .iter()
                    .position(|p| p.name == *name)
                    .ok_or_else(|| {
                        SourceError::new(format!(
                            "{what}: no control point named {name:?} (names look like \"v3\", \"e3-7:2\", \"t5:2,2,1\")"
                        ))
                    })
            })
            .collect::<Result<Vec<usize>, _>>()?;
        let neighborhood = match op.neighborhood {
            None => Neighborhood::Radius(3),
            Some(ron::Value::String(k)) if k == "all" => Neighborhood::All,
            Some(value) => match value.clone().into_rust::<u32>() {
                Ok(r) => Neighborhood::Radius(r),
                Err(_) => {
                    return Err(SourceError::new(format!(
                        "{what}: neighborhood must be a number of steps or \"all\", not {value:?}"
                    )))
                }
            },
        };
        let operation = match (&op.translate, &op.rotate, &op.scale) {
            (Some(by), None, None) => Operation::Translate {
                by: by.iter().map(|e| e.0.clone()).collect(),
            },
            (None, Some(r), None) => Operation::Rotate {
                center: [r.center.0 .0.clone(), r.center.1 .0.clone()],
                degrees: r.degrees.0.clone(),
                precision: r.precision,
            },
            (None, None, Some(s)) => Operation::Scale {
                center: [s.center.0 .0.clone(), s.center.1 .0.clone()],
                factor: s.factor.0.clone(),
                precision: s.precision,
            },
            _ => {
                return Err(SourceError::new(format!(
                    "{what}: give exactly one of translate, rotate or scale"
                )))
            }
        };
        let editor = SplineEditor {
            spline: &built.spline,
            net: &built.net,
            params: &built.params,
        };
        let error = |e: SelectError| SourceError::new(format!("{what}: {e}"));
        // Refuse a bad precision, factor or vector before the (expensive) selection.
        operation.validate(built.params.dim).map_err(error)?;
        let selection = editor
            .select(&request.system, &request.values, &anchors, neighborhood)
            .map_err(error)?;
        let plan = editor
            .plan(&selection, &request.values, &operation, op.steps)
            .map_err(error)?;
        let summary = vec![
            SummaryItem {
                key: "initial_derived".into(),
                value: selection.initial.len() as u64,
            },
            SummaryItem {
                key: "added_by_expansion".into(),
                value: selection.added.len() as u64,
            },
            SummaryItem {
                key: "solvability_checks".into(),
                value: selection.checks as u64,
            },
        ];
        Ok(OperationPlan {
            weights: vec![Rational::one(); plan.spec.derived.len()],
            anchors: plan.spec.anchors,
            derived: plan.spec.derived,
            strong: false,
            steps: plan
                .steps
                .into_iter()
                .map(|s| PlannedStep {
                    anchors: s.anchors,
                    hints: s.hints,
                })
                .collect(),
            summary,
        })
    }

    fn render(&self, request: &RenderRequest) -> Result<Vec<OutputFile>, SourceError> {
        let built = self.built()?;
        let what = format!("{} output", built.name);
        let config: OutputConfig = from_ron(&request.output, &what)?;
        let error = |e: &dyn std::fmt::Display| SourceError::new(format!("{what}: {e}"));
        let before = built.params.positions(&request.initial);
        let after = built.params.positions(&request.values);
        let mut files = Vec::new();
        let model = match &config.model {
            Some(path) => {
                let full = request.base_dir.join(path);
                Some(load_model(&full).map_err(|e| error(&e))?)
            }
            None => None,
        };
        let deformed = match &model {
            Some(model) => {
                let spline = FloatSpline::new(&built.spline, &after).map_err(|e| error(&e))?;
                let locator = Locator::new(built.spline.mesh());
                Some(deform_model(model, &spline, &locator).map_err(|e| error(&e))?)
            }
            None => None,
        };
        if let (Some(path), Some(deformed)) = (&config.model, &deformed) {
            let stem = std::path::Path::new(path)
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "model".into());
            let mut bytes = Vec::new();
            if !deformed.outside.is_empty() {
                bytes.extend(
                    format!(
                        "# {} vertices lie outside the reference mesh and were left in place: {:?}\n",
                        deformed.outside.len(),
                        deformed.outside
                    )
                    .into_bytes(),
                );
            }
            write_obj(&deformed.model, &mut bytes).map_err(|e| error(&e))?;
            let mut file = OutputFile::new(format!("{stem}-deformed.obj"), bytes);
            file.notes.extend(crate::model::left_in_place_note(
                &deformed.outside,
                "outside the reference mesh",
            ));
            files.push(file);
        }
        if let Some(name) = &config.picture {
            let highlight = request.highlight.clone().unwrap_or_default();
            let points = |ids: &[api::ParamId]| -> Vec<usize> {
                ids.iter()
                    .filter_map(|id| built.params.point_of(*id))
                    .collect()
            };
            let anchors = points(&highlight.anchors);
            let derived = points(&highlight.derived);
            let conditions: Vec<usize> = highlight
                .independent_rows
                .iter()
                .filter_map(|r| r.index().checked_sub(built.first_row))
                .filter(|&c| c < built.spline.conditions().len())
                .collect();
            let mut before_picture = Picture::new(&built.spline)
                .positions(&before)
                .title(format!("{}: before", built.name))
                .reference_mesh(true)
                .deformed_mesh(true)
                .control_points(true)
                .control_net(config.control_net);
            let mut after_picture = Picture::new(&built.spline)
                .positions(&after)
                .title(format!("{}: after", built.name))
                .reference_mesh(true)
                .deformed_mesh(true)
                .control_points(true)
                .control_net(config.control_net)
                .anchors(&anchors)
                .derived(&derived)
                .conditions(&conditions);
            if let (true, Some(parts)) = (config.parts, &request.structure) {
                let over_points = points(&parts.over);
                let well_points = points(&parts.well);
                let conditions_of = |rows: &[api::RowId]| -> Vec<usize> {
                    rows.iter()
                        .filter_map(|r| r.index().checked_sub(built.first_row))
                        .filter(|&c| c < built.spline.conditions().len())
                        .collect()
                };
                after_picture = after_picture
                    .group(
                        "well-determined",
                        "#ff7f0e",
                        &well_points,
                        &conditions_of(&parts.well_rows),
                    )
                    .group(
                        "over-determined",
                        "#d62728",
                        &over_points,
                        &conditions_of(&parts.over_rows),
                    );
            }
            if let Some(model) = &model {
                before_picture = before_picture.model(model, false, true);
            }
            if let Some(deformed) = &deformed {
                after_picture = after_picture.model(&deformed.model, false, true);
            }
            let svg = before_after(&before_picture, &after_picture).map_err(|e| error(&e))?;
            files.push(OutputFile::new(name.clone(), svg.into_bytes()));
        }
        if files.is_empty() {
            return Err(SourceError::new(format!(
                "{what}: nothing to render; give picture and/or model"
            )));
        }
        Ok(files)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::{ConstraintSystem, Values};
    use std::path::PathBuf;

    fn request(config: &str) -> BuildRequest {
        BuildRequest {
            name: "phi".into(),
            config: config.into(),
            base_dir: PathBuf::from("."),
            system: ConstraintSystem::new(),
            values: Values::default(),
            sources: vec![],
        }
    }

    const SQUARE: &str = r#"(mesh: (vertices: [("0", "0"), ("10", "0"), ("10", "10"), ("0", "10"), ("5", "4")],
        triangles: [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)]), degree: 5)"#;

    #[test]
    fn builds_and_plans_a_translation() {
        let mut source = Spline2dSource::default();
        let contribution = source.build(&request(SQUARE)).expect("build");
        let mut system = ConstraintSystem::new();
        let mut values = Values::default();
        contribution
            .apply_to(&mut system, &mut values)
            .expect("apply");
        assert!(system.violations(&values).is_empty());
        let count = |k: &str| {
            contribution
                .summary
                .iter()
                .find(|s| s.key == k)
                .map(|s| s.value)
        };
        assert_eq!(count("triangles"), Some(4));
        assert_eq!(count("interior_vertices"), Some(1));
        let plan = source
            .plan(&PlanRequest {
                operation:
                    r#"(anchors: ["v4"], neighborhood: 2, translate: ("1", "1/2"), steps: 2)"#
                        .into(),
                system: system.clone(),
                values: values.clone(),
            })
            .expect("plan");
        assert_eq!(plan.anchors.len(), 1);
        assert_eq!(plan.steps.len(), 2);
        assert_eq!(plan.weights.len(), plan.derived.len());
    }

    #[test]
    fn configuration_errors_are_clear() {
        let mut source = Spline2dSource::default();
        let err = source
            .build(&request(r#"(mesh: "missing.obj")"#))
            .expect_err("missing file");
        assert!(err.message.contains("missing.obj"), "{}", err.message);
        let err = source
            .build(&request(r#"(mesh: "x.obj", degre: 5)"#))
            .expect_err("unknown field");
        assert!(err.message.contains("degre"), "{}", err.message);
        let err = source
            .build(&request(
                r#"(mesh: (vertices: [(0.5, "0"), ("1", "0"), ("0", "1")], triangles: [(0, 1, 2)]))"#,
            ))
            .expect_err("float");
        assert!(err.message.contains("floating-point"), "{}", err.message);
        source.build(&request(SQUARE)).expect("build");
        let plan = |op: &str| {
            source.plan(&PlanRequest {
                operation: op.into(),
                system: ConstraintSystem::new(),
                values: Values::default(),
            })
        };
        assert!(plan(r#"(anchors: ["v9"], translate: ("1", "0"))"#)
            .expect_err("unknown point")
            .message
            .contains("v9"));
        assert!(plan(r#"(anchors: ["v4"])"#)
            .expect_err("no operation")
            .message
            .contains("exactly one"));
        // Limits are checked before the selection runs.
        let err =
            plan(r#"(anchors: ["v4"], rotate: (center: ("0", "0"), degrees: "30", precision: 0))"#)
                .expect_err("precision 0");
        assert!(
            err.message
                .contains("precision 0 must be between 1 and 1000000000000"),
            "{}",
            err.message
        );
        let err = plan(r#"(anchors: ["v4"], scale: (center: ("0", "0"), factor: "-2"))"#)
            .expect_err("negative factor");
        assert!(
            err.message.contains("scale factor -2 must be positive"),
            "{}",
            err.message
        );
    }
}
