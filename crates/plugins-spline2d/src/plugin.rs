//! The `spline2d` constraint source as a plugin: configuration, build, planned operations and
//! rendered outputs.
//!
//! # Configuration (RON)
//! The schema of [`spline2d::config::SplineConfig`]: `mesh` (an OBJ file relative to the run
//! file, or inline vertices and triangles), `degree` (default 5), `smoothness` (`C^r`, default
//! 1), `snap` and `orientation`.
//!
//! # Operations (RON)
//! ```ron
//! (
//!     anchors: ["v4", "e4-5:2"],   // control point names (see `ControlPoint::name`)
//!     neighborhood: 3,             // δ_max on the control net, or "all"
//!     translate: ("3/2", "-1"),    // or rotate: (center: ("0", "0"), degrees: "30", precision: 1000)
//!                                  // or scale: (center: ("0", "0"), factor: "3/2", precision: 1000)
//!                                  // precision: 1..=10^12, default 10^6 (see `spline2d::motion`)
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
//! Checked and rendered in `output.rs`.

use crate::output;
use api::config::from_ron;
use api::{
    BezierTriangles, BuildRequest, ConstraintSource, Contribution, OperationCheckRequest,
    OperationPlan, OutputCheck, OutputCheckRequest, OutputFile, ParamId, PlanRequest,
    RenderRequest, RowId, SourceError, SourceView, SummaryItem, ViewRequest,
};
use serde::Deserialize;
use spline2d::config::{spline_from_config_text, SplineRead};
use spline2d::edit::{Neighborhood, Operation, SelectError, SplineEditor};
use spline2d::net::ControlNet;
use spline2d::operation::{
    checked_steps, default_steps, find_anchors, motion, operation_plan, ExactList,
    NeighborhoodConfig, RotateConfig, ScaleConfig,
};
use spline2d::params::SplineParams;
use spline2d::spline::Spline;

/// A `spline2d` operation as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct OperationConfig {
    anchors: Vec<String>,
    #[serde(default)]
    neighborhood: Option<NeighborhoodConfig>,
    #[serde(default)]
    translate: Option<ExactList>,
    #[serde(default)]
    rotate: Option<RotateConfig>,
    #[serde(default)]
    scale: Option<ScaleConfig>,
    #[serde(default = "default_steps")]
    steps: u64,
}

/// An operation checked against the built spline.
struct CheckedOperation {
    anchors: Vec<usize>,
    neighborhood: Neighborhood,
    operation: Operation,
    steps: usize,
}

/// What a built source keeps.
#[derive(Debug, Clone)]
pub(crate) struct Built {
    /// The source's name (prefix of its parameters and rows).
    pub(crate) name: String,
    pub(crate) spline: Spline,
    /// The control net, built at the first operation planned (analyses never need it).
    net: std::sync::OnceLock<ControlNet>,
    /// Where the control points live in the system.
    pub(crate) params: SplineParams,
    /// Id of the row of the first condition (conditions are consecutive rows).
    first_row: usize,
    /// The build request's base directory: what the view resolves its outputs' model paths
    /// against (a view request carries none; render's base directory is the same run file's).
    pub(crate) base_dir: std::path::PathBuf,
    /// The build request's input limit, which the view's model reads keep too.
    pub(crate) input_limit: u64,
}

impl Built {
    /// The control points among `ids` (parameters of other sources are left out).
    pub(crate) fn points_of(&self, ids: &[ParamId]) -> Vec<usize> {
        ids.iter()
            .filter_map(|id| self.params.point_of(*id))
            .collect()
    }

    /// The conditions (indices into the spline's conditions) among `rows` (rows of other
    /// sources are left out).
    pub(crate) fn conditions_of(&self, rows: &[RowId]) -> Vec<usize> {
        rows.iter()
            .filter_map(|r| r.index().checked_sub(self.first_row))
            .filter(|&c| c < self.spline.conditions().len())
            .collect()
    }
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

    /// Parses and checks an operation: schema, anchors, neighbourhood, move and steps.
    fn check(&self, text: &str) -> Result<CheckedOperation, SourceError> {
        let built = self.built()?;
        let what = format!("{} operation", built.name);
        let op: OperationConfig = from_ron(text, &what)?;
        let error = |message: String| SourceError::new(format!("{what}: {message}"));
        let anchors = find_anchors(&built.spline, &op.anchors).map_err(error)?;
        let operation = motion(
            op.translate.as_ref(),
            op.rotate.as_ref(),
            op.scale.as_ref(),
            built.params.dim,
        )
        .map_err(error)?;
        let steps = checked_steps(op.steps, built.spline.points().len()).map_err(error)?;
        Ok(CheckedOperation {
            anchors,
            neighborhood: op.neighborhood.map_or(Neighborhood::Radius(3), |n| n.0),
            operation,
            steps,
        })
    }
}

impl ConstraintSource for Spline2dSource {
    fn kind(&self) -> &str {
        "spline2d"
    }

    fn version(&self) -> &str {
        env!("CARGO_PKG_VERSION")
    }

    fn build(&mut self, request: &BuildRequest) -> Result<Contribution, SourceError> {
        let SplineRead {
            spline,
            warnings,
            file,
        } = spline_from_config_text(
            &request.name,
            &request.config,
            &request.base_dir,
            request.input_limit,
        )?;
        let (mut contribution, params) = spline.contribution(
            &request.name,
            2,
            request.system.params().len(),
            spline.identity_positions(),
        );
        let mut summary = spline.summary_counts();
        summary.extend([
            ("control_points", spline.points().len()),
            // One row per condition (counted from the rows, which are the conditions made once).
            ("conditions", contribution.rows.len()),
        ]);
        contribution.summary = SummaryItem::sorted(summary);
        contribution.warnings = spline2d::mesh_io::summarize_warnings(&warnings);
        contribution.inputs = file.into_iter().collect();
        self.built = Some(Built {
            name: request.name.clone(),
            spline,
            net: std::sync::OnceLock::new(),
            params,
            first_row: request.system.rows().len(),
            base_dir: request.base_dir.clone(),
            input_limit: request.input_limit,
        });
        Ok(contribution)
    }

    fn check_operation(&self, request: &OperationCheckRequest) -> Result<(), SourceError> {
        self.check(&request.operation).map(|_| ())
    }

    fn check_output(&self, request: &OutputCheckRequest) -> Result<OutputCheck, SourceError> {
        let (checked, _) = output::check_output(
            self.built()?,
            &request.output,
            &request.base_dir,
            request.input_limit,
        )?;
        Ok(OutputCheck::new(
            checked.files(),
            checked.model.iter().map(|(_, path)| path.clone()).collect(),
        ))
    }

    fn plan(&self, request: &PlanRequest) -> Result<OperationPlan, SourceError> {
        let built = self.built()?;
        let what = format!("{} operation", built.name);
        let op = self.check(&request.operation)?;
        let editor = SplineEditor {
            spline: &built.spline,
            net: built.net.get_or_init(|| ControlNet::new(&built.spline)),
            params: &built.params,
        };
        let error = |e: SelectError| SourceError::new(format!("{what}: {e}"));
        let (selection, plan) = editor
            .plan_operation(
                &request.system,
                &request.values,
                &op.anchors,
                op.neighborhood,
                &op.operation,
                op.steps,
            )
            .map_err(error)?;
        Ok(operation_plan(&selection, plan))
    }

    fn render(&self, request: &RenderRequest) -> Result<Vec<OutputFile>, SourceError> {
        output::render(self.built()?, request)
    }

    /// The Bézier patches over the reference mesh, each control point as its parameter, and
    /// the models the request's outputs deform, placed in the mesh (`output::view_models`).
    fn view(&self, request: &ViewRequest) -> Result<Option<SourceView>, SourceError> {
        let built = self.built()?;
        let spline = &built.spline;
        let mesh = spline.mesh();
        Ok(Some(SourceView::BezierTriangles(BezierTriangles {
            degree: spline.degree(),
            smoothness: spline.smoothness(),
            vertices: mesh.vertices().to_vec(),
            triangles: mesh.triangles().to_vec(),
            patches: (0..mesh.triangles().len())
                .map(|t| {
                    spline
                        .triangle_points(t)
                        .iter()
                        .map(|&p| built.params.ids[p])
                        .collect()
                })
                .collect(),
            models: output::view_models(built, &request.outputs)?,
        })))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::{ConstraintSystem, Values};

    fn request(config: &str) -> BuildRequest {
        conformance::request("phi", config)
    }

    const SQUARE: &str = r#"(mesh: (vertices: [("0", "0"), ("10", "0"), ("10", "10"), ("0", "10"), ("5", "4")],
        triangles: [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)]), degree: 5)"#;

    /// The source built on [`SQUARE`], its contribution, and the system and values it makes.
    fn built_square() -> (Spline2dSource, Contribution, ConstraintSystem, Values) {
        let mut source = Spline2dSource::default();
        let contribution = source.build(&request(SQUARE)).expect("build");
        let mut system = ConstraintSystem::new();
        let mut values = Values::default();
        contribution
            .apply_to(&mut system, &mut values)
            .expect("apply");
        (source, contribution, system, values)
    }

    #[test]
    fn builds_and_plans_a_translation() {
        let (source, contribution, system, values) = built_square();
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
                schema: api::SCHEMA_VERSION,
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

    /// The view's contract: patch `t` lists the control points of triangle `t` in multi-index
    /// order, so at the identity deformation (the initial values) control point `(i, j, k)` is
    /// the domain point `(i A + j B + k C) / d` of the triangle's vertices `A, B, C`.
    #[test]
    fn the_view_lists_each_triangles_control_points_in_multi_index_order() {
        let (source, _, system, values) = built_square();
        let view = source
            .view(&ViewRequest {
                schema: api::SCHEMA_VERSION,
                outputs: Vec::new(),
            })
            .expect("view")
            .expect("spline2d has a view");
        view.validate(&system).expect("valid");
        let SourceView::BezierTriangles(view) = view else {
            panic!("spline2d draws Bézier triangles")
        };
        assert_eq!((view.degree, view.smoothness), (5, 1));
        // A request that names no outputs gets no models.
        assert!(view.models.is_empty());
        assert_eq!(view.triangles.len(), 4);
        let d = view.degree;
        let q = |n: usize| api::Rational::from_integer(n.into());
        for (tri, patch) in view.triangles.iter().zip(&view.patches) {
            assert_eq!(patch.len(), 21);
            let mut at = 0;
            for i in (0..=d).rev() {
                for j in (0..=d - i).rev() {
                    let k = d - i - j;
                    let weights = [q(i), q(j), q(k)];
                    for c in 0..2 {
                        let expected = (0..3)
                            .map(|v| &weights[v] * &view.vertices[tri[v]][c])
                            .fold(q(0), |a, b| a + b)
                            / q(d);
                        assert_eq!(values.get(patch[at])[c], expected, "({i},{j},{k})");
                    }
                    at += 1;
                }
            }
            // Corners are the vertices' points, shared by every patch around the vertex.
            let name = |id: ParamId| system.params()[id.index()].name.clone();
            assert_eq!(&*name(patch[0]), format!("phi.v{}", tri[0]));
            assert_eq!(&*name(patch[20]), format!("phi.v{}", tri[2]));
        }
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
                schema: api::SCHEMA_VERSION,
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

    #[test]
    fn sizes_are_checked_before_anything_is_allocated() {
        let mut source = Spline2dSource::default();
        for (degree, needle) in [
            ("1000000000", "degree 1000000000 is above the limit of 40"),
            ("100000", "degree 100000 is above the limit of 40"),
            ("18446744073709551615", "above the limit"),
        ] {
            let config = SQUARE.replace("degree: 5", &format!("degree: {degree}"));
            let err = source.build(&request(&config)).expect_err(degree);
            assert!(err.message.contains(needle), "{}", err.message);
        }
        let config = SQUARE.replace("degree: 5", "degree: 5, smoothness: 9");
        let err = source.build(&request(&config)).expect_err("smoothness");
        assert!(
            err.message.contains("needs degree above 9"),
            "{}",
            err.message
        );
        let err = source
            .build(&request(&SQUARE.replace("degree: 5", "degree: -1")))
            .expect_err("negative");
        assert!(err.at.is_some(), "{}", err.message);
    }

    #[test]
    fn operations_and_outputs_are_checked_before_any_edit() {
        let mut source = Spline2dSource::default();
        source.build(&request(SQUARE)).expect("build");
        let op = |text: &str| {
            source
                .check_operation(&OperationCheckRequest {
                    schema: api::SCHEMA_VERSION,
                    operation: text.into(),
                })
                .map_err(|e| e.message)
        };
        assert_eq!(op(r#"(anchors: ["v4"], translate: ("1", "0"))"#), Ok(()));
        for (text, needle) in [
            (
                r#"(anchors: [], translate: ("1", "0"))"#,
                "anchors is empty",
            ),
            (
                r#"(anchors: ["v4", "v4"], translate: ("1", "0"))"#,
                "named twice",
            ),
            (
                r#"(anchors: ["v9"], translate: ("1", "0"))"#,
                "no control point named \"v9\"",
            ),
            (
                r#"(anchors: ["v4"], translate: ("1", "0", "2"))"#,
                "3 coordinates",
            ),
            (
                r#"(anchors: ["v4"], translate: ("1", "0"), steps: 0)"#,
                "steps is 0",
            ),
            (
                r#"(anchors: ["v4"], translate: ("1", "0"), steps: 18446744073709551615)"#,
                "between 1 and 100000",
            ),
            (
                r#"(anchors: ["v4"], translate: ("1", "0"), neighborhood: -1)"#,
                "negative",
            ),
            (
                r#"(anchors: ["v4"], scale: (center: ("0", "0"), factor: "-2"))"#,
                "must be positive",
            ),
            (
                r#"(anchors: ["v4"], translate: ("1", "0"), wieghts: 1)"#,
                "wieghts",
            ),
            (r#"(anchors: ["v4"])"#, "exactly one"),
        ] {
            let message = op(text).expect_err(text);
            assert!(message.contains(needle), "{text}: {message}");
            assert!(message.starts_with("phi operation: "), "{message}");
        }
        let out = |text: &str| {
            source
                .check_output(&OutputCheckRequest {
                    schema: api::SCHEMA_VERSION,
                    output: text.into(),
                    base_dir: ".".into(),
                    input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
                })
                .map_err(|e| e.message)
        };
        assert_eq!(
            out(r#"(picture: "a.svg")"#).map(|c| c.files),
            Ok(vec!["a.svg".to_string()])
        );
        assert_eq!(
            out(r#"(picture: "a.PNG")"#).map(|c| c.files),
            Ok(vec!["a.PNG".to_string()])
        );
        for (text, needle) in [
            (r#"(picture: "a.gif")"#, "ending in .svg or .png"),
            (r#"(picture: "../a.svg")"#, "plain file name"),
            (r#"(picture: ".svg")"#, "plain file name"),
            (r#"(model: "/etc/passwd")"#, "is not an OBJ statement"),
            (r#"(model: "/dev/zero")"#, "character device"),
            (r#"(model: "no/such.obj")"#, "no/such.obj"),
            (r#"()"#, "nothing to render"),
        ] {
            let message = out(text).expect_err(text);
            assert!(message.contains(needle), "{text}: {message}");
        }
    }
}
