//! Pictures of a spline deformation as SVG text, for people to look at: the reference mesh,
//! the deformed mesh with curved edges, the control net, anchors and derived points of an
//! edit, selected smoothness conditions (drawn as translucent quadrilaterals, as in the thesis
//! figures 14.3 and 18.8) and a deformed model.
//!
//! Output is deterministic: coordinates are printed with two decimals in a fixed element
//! order, with no timestamps, so pictures can be compared as text. The y axis points up (the
//! picture is flipped), and the view box is fitted to the drawn data with a margin.
//!
//! ```no_run
//! # use plugins_spline2d::svg::Picture;
//! # use spline2d::spline::Spline;
//! # fn show(spline: &Spline, positions: &[Vec<api::Rational>]) -> Result<(), Box<dyn std::error::Error>> {
//! let svg = Picture::new(spline)
//!     .positions(positions)
//!     .control_net(true)
//!     .anchors(&[0])
//!     .title("after the edit")
//!     .to_svg()?;
//! std::fs::write("edit.svg", svg)?;
//! # Ok(()) }
//! ```

mod layers;
pub mod raster;
mod scene;

use api::exact::rational_to_f64;
use api::Rational;
use layers::{control_points_layer, model_edges_layer, model_vertices_layer};
use scene::{finite, header, scale_for, Scene};
use spline2d::eval::{check_positions, EvalError};
use spline2d::model::Model;
use spline2d::spline::Spline;

/// Why a picture could not be drawn.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SvgError {
    /// The positions do not fit the spline.
    #[error("positions: {0}")]
    Positions(#[from] EvalError),
    /// Pictures show deformations of the plane: positions need 2 coordinates.
    #[error("pictures need control point positions with 2 coordinates, got {0}")]
    NotPlanar(usize),
    /// An anchor, derived point or label refers to a missing control point.
    #[error("control point {point} does not exist (the spline has {count})")]
    NoSuchPoint {
        /// The id given.
        point: usize,
        /// Control points of the spline.
        count: usize,
    },
    /// A selected condition does not exist.
    #[error("condition {condition} does not exist (the spline has {count})")]
    NoSuchCondition {
        /// The index given.
        condition: usize,
        /// Conditions of the spline.
        count: usize,
    },
    /// A coordinate is too large for `f64` or not a number.
    #[error("{what} has a coordinate that cannot be drawn (not finite)")]
    NotFinite {
        /// What was being drawn.
        what: String,
    },
}

/// A picture of one state of a spline deformation, configured with builder methods and drawn
/// by [`Picture::to_svg`] (or two side by side by [`before_after`]).
///
/// By default it shows the reference mesh and the deformed mesh; everything else is opt-in.
#[derive(Debug, Clone)]
pub struct Picture<'a> {
    spline: &'a Spline,
    positions: Option<&'a [Vec<Rational>]>,
    title: Option<String>,
    reference_mesh: bool,
    deformed_mesh: bool,
    control_points: bool,
    control_net: bool,
    anchors: Vec<usize>,
    derived: Vec<usize>,
    conditions: Vec<usize>,
    labels: Vec<(usize, String)>,
    groups: Vec<Group>,
    model: Option<&'a Model>,
    model_vertices: bool,
    model_edges: bool,
    samples: usize,
    size: f64,
}

/// Points and conditions drawn in one colour (a Dulmage–Mendelsohn part, say).
#[derive(Debug, Clone)]
struct Group {
    class: String,
    colour: String,
    points: Vec<usize>,
    conditions: Vec<usize>,
}

/// Margin around the data, in pixels.
const MARGIN: f64 = 16.0;
/// Height reserved for a title, in pixels.
const TITLE_HEIGHT: f64 = 24.0;
/// Gap between the panels of [`before_after`], in pixels.
const GAP: f64 = 24.0;

impl<'a> Picture<'a> {
    /// A picture of `spline` at its nominal positions (the identity deformation), showing the
    /// reference and deformed meshes, 16 segments per curved edge, 600 pixels on the longer
    /// side.
    pub fn new(spline: &'a Spline) -> Self {
        Picture {
            spline,
            positions: None,
            title: None,
            reference_mesh: true,
            deformed_mesh: true,
            control_points: false,
            control_net: false,
            anchors: Vec::new(),
            derived: Vec::new(),
            conditions: Vec::new(),
            labels: Vec::new(),
            groups: Vec::new(),
            model: None,
            model_vertices: false,
            model_edges: false,
            samples: 16,
            size: 600.0,
        }
    }

    /// Current control point positions (one per control point, 2 coordinates each); control
    /// points, the net, conditions and the deformed mesh are drawn there.
    pub fn positions(mut self, positions: &'a [Vec<Rational>]) -> Self {
        self.positions = Some(positions);
        self
    }

    /// A title above the picture (escaped).
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }

    /// Whether to draw the reference mesh (thin grey straight edges).
    pub fn reference_mesh(mut self, on: bool) -> Self {
        self.reference_mesh = on;
        self
    }

    /// Whether to draw the deformed mesh (each edge's image under `φ`, sampled).
    pub fn deformed_mesh(mut self, on: bool) -> Self {
        self.deformed_mesh = on;
        self
    }

    /// Whether to draw every control point as a small dot.
    pub fn control_points(mut self, on: bool) -> Self {
        self.control_points = on;
        self
    }

    /// Whether to draw the global control net (dotted), see
    /// [`ControlNet`](spline2d::net::ControlNet).
    pub fn control_net(mut self, on: bool) -> Self {
        self.control_net = on;
        self
    }

    /// Draws `points` and `conditions` in `colour` (an SVG colour such as `"#d62728"`), in a
    /// group of class `class` (for example the over-determined part of the system).
    pub fn group(
        mut self,
        class: &str,
        colour: &str,
        points: &[usize],
        conditions: &[usize],
    ) -> Self {
        self.groups.push(Group {
            class: class.to_string(),
            colour: colour.to_string(),
            points: points.to_vec(),
            conditions: conditions.to_vec(),
        });
        self
    }

    /// Anchors of an edit (open bold circles), by control point id.
    pub fn anchors(mut self, points: &[usize]) -> Self {
        self.anchors = points.to_vec();
        self
    }

    /// Derived points of an edit (filled black dots), by control point id.
    pub fn derived(mut self, points: &[usize]) -> Self {
        self.derived = points.to_vec();
        self
    }

    /// Conditions to show (indices into [`Spline::conditions`]), each as a translucent polygon
    /// through its control points.
    pub fn conditions(mut self, conditions: &[usize]) -> Self {
        self.conditions = conditions.to_vec();
        self
    }

    /// Adds a text label next to a control point (escaped; drawn in the order added).
    pub fn label(mut self, point: usize, text: impl Into<String>) -> Self {
        self.labels.push((point, text.into()));
        self
    }

    /// A model to draw as given (pass the deformed model to show the deformation), with its
    /// vertices as dots and/or its triangle edges, using `x` and `y`.
    pub fn model(mut self, model: &'a Model, vertices: bool, edges: bool) -> Self {
        self.model = Some(model);
        self.model_vertices = vertices;
        self.model_edges = edges;
        self
    }

    /// Segments per curved edge of the deformed mesh (at least 1).
    pub fn samples_per_edge(mut self, samples: usize) -> Self {
        self.samples = samples.max(1);
        self
    }

    /// Size in pixels of the longer side of the data area (at least 16; default 600).
    pub fn size(mut self, pixels: f64) -> Self {
        self.size = if pixels.is_finite() {
            pixels.max(16.0)
        } else {
            600.0
        };
        self
    }

    /// The picture as a standalone SVG document.
    pub fn to_svg(&self) -> Result<String, SvgError> {
        let scene = self.scene()?;
        let bounds = scene.bounds();
        let scale = scale_for(&bounds, self.size);
        let (w, h) = scene.panel_size(&bounds, scale);
        let mut out = header(w, h);
        scene.render(&mut out, &bounds, scale, [0.0, 0.0], w);
        out.push_str("</svg>\n");
        Ok(out)
    }

    /// Control point positions in `f64`, checked.
    fn current(&self) -> Result<Vec<[f64; 2]>, SvgError> {
        let points = self.spline.points();
        let converted: Vec<[f64; 2]> = match self.positions {
            Some(positions) => {
                let dim = check_positions(self.spline, positions)?;
                if dim != 2 {
                    return Err(SvgError::NotPlanar(dim));
                }
                positions
                    .iter()
                    .map(|p| [rational_to_f64(&p[0]), rational_to_f64(&p[1])])
                    .collect()
            }
            None => self
                .spline
                .nominals()
                .iter()
                .map(|p| [rational_to_f64(&p[0]), rational_to_f64(&p[1])])
                .collect(),
        };
        if let Some(i) = converted.iter().position(|p| !finite(p)) {
            return Err(SvgError::NotFinite {
                what: format!("control point {i} ({})", points[i].name),
            });
        }
        Ok(converted)
    }

    fn check_point(&self, point: usize) -> Result<usize, SvgError> {
        let count = self.spline.points().len();
        if point < count {
            Ok(point)
        } else {
            Err(SvgError::NoSuchPoint { point, count })
        }
    }

    /// Everything to draw, in world coordinates, in drawing order: one layer per kind of
    /// element (see `layers.rs`), empty ones included (they are not written).
    fn scene(&self) -> Result<Scene, SvgError> {
        let current = self.current()?;
        let mut layers = Vec::new();
        if self.reference_mesh {
            layers.push(self.reference_mesh_layer()?);
        }
        if !self.conditions.is_empty() {
            layers.push(self.conditions_layer(&current)?);
        }
        if let (Some(model), true) = (self.model, self.model_edges) {
            layers.push(model_edges_layer(model)?);
        }
        if self.deformed_mesh {
            layers.push(self.deformed_mesh_layer()?);
        }
        if self.control_net {
            layers.push(self.control_net_layer(&current));
        }
        if let (Some(model), true) = (self.model, self.model_vertices) {
            layers.push(model_vertices_layer(model)?);
        }
        if self.control_points {
            layers.push(control_points_layer(&current));
        }
        for group in &self.groups {
            layers.extend(self.group_layers(group, &current)?);
        }
        if !self.derived.is_empty() {
            layers.push(self.derived_layer(&current)?);
        }
        if !self.anchors.is_empty() {
            layers.push(self.anchors_layer(&current)?);
        }
        if !self.labels.is_empty() {
            layers.push(self.labels_layer(&current)?);
        }
        Ok(Scene {
            layers,
            title: self.title.clone(),
        })
    }
}

/// Two pictures side by side at the same scale (their data bounds joined), e.g. the same
/// spline before and after an edit. Untitled panels are titled "before" and "after". The
/// size of `before` is used.
pub fn before_after(before: &Picture<'_>, after: &Picture<'_>) -> Result<String, SvgError> {
    let mut left = before.scene()?;
    let mut right = after.scene()?;
    left.title.get_or_insert_with(|| "before".to_string());
    right.title.get_or_insert_with(|| "after".to_string());
    let bounds = left.bounds().union(&right.bounds());
    let scale = scale_for(&bounds, before.size);
    let (w, h) = left.panel_size(&bounds, scale);
    let total = 2.0 * w + GAP;
    let mut out = header(total, h);
    left.render(&mut out, &bounds, scale, [0.0, 0.0], w);
    right.render(&mut out, &bounds, scale, [w + GAP, 0.0], w);
    out.push_str("</svg>\n");
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use spline2d::mesh::Mesh;
    use spline2d::net::ControlNet;

    fn q(n: i64) -> Rational {
        Rational::from_integer(n.into())
    }

    /// A grid of `n × n` squares of side 10.
    fn grid(n: usize, perturb: bool) -> Mesh {
        spline2d::mesh::grid(n, 10, perturb)
    }

    #[test]
    fn element_counts_follow_the_options() {
        let spline = Spline::new(grid(1, false), 3, 1).expect("spline");
        let n = spline.points().len();
        let svg = Picture::new(&spline)
            .control_points(true)
            .control_net(true)
            .anchors(&[0, 1])
            .derived(&[2])
            .conditions(&[0, 1])
            .label(0, "a<&>'\"")
            .title("t")
            .to_svg()
            .expect("svg");
        let edges = spline.topology().edges.len();
        assert_eq!(svg.matches("<circle").count(), n + 3);
        assert_eq!(svg.matches("<polygon").count(), 2);
        assert_eq!(svg.matches("<polyline").count(), edges);
        let net = ControlNet::new(&spline).edges().len();
        assert_eq!(svg.matches("<line").count(), edges + net);
        assert!(svg.contains("a&lt;&amp;&gt;&apos;&quot;"));
    }

    #[test]
    fn bad_ids_are_errors() {
        let spline = Spline::new(grid(1, false), 2, 1).expect("spline");
        let n = spline.points().len();
        assert!(matches!(
            Picture::new(&spline).anchors(&[n]).to_svg(),
            Err(SvgError::NoSuchPoint { .. })
        ));
        assert!(matches!(
            Picture::new(&spline).conditions(&[99]).to_svg(),
            Err(SvgError::NoSuchCondition { .. })
        ));
        let scalar = vec![vec![q(1)]; n];
        assert_eq!(
            Picture::new(&spline).positions(&scalar).to_svg(),
            Err(SvgError::NotPlanar(1))
        );
    }

    #[test]
    fn groups_colour_points_and_conditions() {
        let spline = Spline::new(grid(1, false), 3, 1).expect("spline");
        let svg = Picture::new(&spline)
            .control_points(false)
            .group("over-determined", "#d62728", &[0, 1, 2], &[0])
            .to_svg()
            .expect("svg");
        let start = svg
            .find(r#"class="over-determined-points""#)
            .expect("points group");
        let group = &svg[start..svg[start..].find("</g>").map_or(svg.len(), |e| start + e)];
        assert_eq!(group.matches("<circle").count(), 3);
        assert!(svg.contains(r#"class="over-determined-conditions""#));
        assert!(Picture::new(&spline)
            .group("x", "red", &[9999], &[])
            .to_svg()
            .is_err());
    }
}
