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

use api::exact::rational_to_f64;
use api::Rational;
use spline2d::eval::{check_positions, EvalError, FloatSpline};
use spline2d::model::Model;
use spline2d::net::ControlNet;
use spline2d::spline::Spline;
use std::collections::BTreeSet;
use std::fmt::Write as _;

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

    /// Whether to draw the global control net (dotted), see [`ControlNet`].
    pub fn control_net(mut self, on: bool) -> Self {
        self.control_net = on;
        self
    }

    /// Anchors of an edit (open bold circles), by control point id.
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

    /// Marks anchor points (open bold circles).
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
            None => points
                .iter()
                .map(|p| {
                    [
                        rational_to_f64(&p.nominal[0]),
                        rational_to_f64(&p.nominal[1]),
                    ]
                })
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

    /// Everything to draw, in world coordinates, in drawing order.
    fn scene(&self) -> Result<Scene, SvgError> {
        let spline = self.spline;
        let mesh = spline.mesh();
        let topology = spline.topology();
        let current = self.current()?;
        let vertices: Vec<[f64; 2]> = mesh
            .vertices()
            .iter()
            .map(|p| [rational_to_f64(&p[0]), rational_to_f64(&p[1])])
            .collect();
        let mut layers = Vec::new();

        if self.reference_mesh {
            let mut shapes = Vec::new();
            for e in &topology.edges {
                let (a, b) = (vertices[e.a], vertices[e.b]);
                if !(finite(&a) && finite(&b)) {
                    return Err(SvgError::NotFinite {
                        what: format!("mesh edge {}-{}", e.a, e.b),
                    });
                }
                shapes.push(Shape::Line(a, b));
            }
            layers.push(Layer::new(
                "reference-mesh",
                r##"fill="none" stroke="#b0b0b0" stroke-width="0.6""##,
                shapes,
            ));
        }

        if !self.conditions.is_empty() {
            let count = spline.conditions().len();
            let mut shapes = Vec::new();
            for &c in &self.conditions {
                let condition = spline
                    .conditions()
                    .get(c)
                    .ok_or(SvgError::NoSuchCondition {
                        condition: c,
                        count,
                    })?;
                let points: Vec<[f64; 2]> =
                    condition.terms.iter().map(|(p, _)| current[*p]).collect();
                shapes.push(Shape::Polygon(around_centroid(points)));
            }
            layers.push(Layer::new(
                "conditions",
                r##"fill="#808080" fill-opacity="0.35" stroke="#606060" stroke-width="0.5" stroke-linejoin="round""##,
                shapes,
            ));
        }

        if let (Some(model), true) = (self.model, self.model_edges) {
            let count = model.positions.len();
            let mut edges = BTreeSet::new();
            for tri in &model.triangles {
                for k in 0..3 {
                    let (a, b) = (tri[k], tri[(k + 1) % 3]);
                    if a.max(b) >= count {
                        return Err(SvgError::NoSuchPoint {
                            point: a.max(b),
                            count,
                        });
                    }
                    if a != b {
                        edges.insert((a.min(b), a.max(b)));
                    }
                }
            }
            let xy = |v: usize| [model.positions[v][0], model.positions[v][1]];
            let mut shapes = Vec::with_capacity(edges.len());
            for (a, b) in edges {
                let (pa, pb) = (xy(a), xy(b));
                if !(finite(&pa) && finite(&pb)) {
                    return Err(SvgError::NotFinite {
                        what: format!("model edge {a}-{b}"),
                    });
                }
                shapes.push(Shape::Line(pa, pb));
            }
            layers.push(Layer::new(
                "model-edges",
                r##"fill="none" stroke="#4a7fb5" stroke-width="0.5""##,
                shapes,
            ));
        }

        if self.deformed_mesh {
            let nominal;
            let positions = match self.positions {
                Some(p) => p,
                None => {
                    nominal = spline
                        .points()
                        .iter()
                        .map(|p| p.nominal.to_vec())
                        .collect::<Vec<_>>();
                    &nominal
                }
            };
            let float = FloatSpline::new(spline, positions)?;
            let mut shapes = Vec::with_capacity(topology.edges.len());
            let mut value = [0.0; 2];
            for e in &topology.edges {
                let Some(&(t, k)) = e.faces.first() else {
                    continue;
                };
                let tri = mesh.triangles()[t];
                let (ia, ib) = ((k + 1) % 3, (k + 2) % 3);
                let (ia, ib) = if tri[ia] == e.a { (ia, ib) } else { (ib, ia) };
                let mut line = Vec::with_capacity(self.samples + 1);
                for s in 0..=self.samples {
                    let u = s as f64 / self.samples as f64;
                    let mut beta = [0.0; 3];
                    beta[ia] = 1.0 - u;
                    beta[ib] = u;
                    float.evaluate_into(t, beta, &mut value);
                    if !finite(&value) {
                        return Err(SvgError::NotFinite {
                            what: format!("deformed edge {}-{}", e.a, e.b),
                        });
                    }
                    line.push(value);
                }
                shapes.push(Shape::Polyline(line));
            }
            layers.push(Layer::new(
                "deformed-mesh",
                r##"fill="none" stroke="#202020" stroke-width="1.2" stroke-linejoin="round""##,
                shapes,
            ));
        }

        if self.control_net {
            let net = ControlNet::new(spline);
            let shapes = net
                .edges()
                .iter()
                .map(|&(a, b)| Shape::Line(current[a], current[b]))
                .collect();
            layers.push(Layer::new(
                "control-net",
                r##"fill="none" stroke="#707070" stroke-width="0.6" stroke-dasharray="2 2""##,
                shapes,
            ));
        }

        if let (Some(model), true) = (self.model, self.model_vertices) {
            let mut shapes = Vec::with_capacity(model.positions.len());
            for (v, p) in model.positions.iter().enumerate() {
                let xy = [p[0], p[1]];
                if !finite(&xy) {
                    return Err(SvgError::NotFinite {
                        what: format!("model vertex {v}"),
                    });
                }
                shapes.push(Shape::Circle(xy, 1.0));
            }
            layers.push(Layer::new("model-vertices", r##"fill="#4a7fb5""##, shapes));
        }

        if self.control_points {
            let shapes = current.iter().map(|p| Shape::Circle(*p, 1.8)).collect();
            layers.push(Layer::new("control-points", r##"fill="#404040""##, shapes));
        }

        for group in &self.groups {
            let count = spline.conditions().len();
            let mut polygons = Vec::with_capacity(group.conditions.len());
            for &c in &group.conditions {
                let condition = spline
                    .conditions()
                    .get(c)
                    .ok_or(SvgError::NoSuchCondition {
                        condition: c,
                        count,
                    })?;
                let points: Vec<[f64; 2]> =
                    condition.terms.iter().map(|(p, _)| current[*p]).collect();
                polygons.push(Shape::Polygon(around_centroid(points)));
            }
            let colour = escape(&group.colour);
            if !polygons.is_empty() {
                layers.push(Layer::new(
                    &format!("{}-conditions", escape(&group.class)),
                    &format!(
                        r#"fill="{colour}" fill-opacity="0.3" stroke="{colour}" stroke-width="0.5""#
                    ),
                    polygons,
                ));
            }
            let circles = group
                .points
                .iter()
                .map(|&p| Ok(Shape::Circle(current[self.check_point(p)?], 2.6)))
                .collect::<Result<Vec<_>, SvgError>>()?;
            if !circles.is_empty() {
                layers.push(Layer::new(
                    &format!("{}-points", escape(&group.class)),
                    &format!(r#"fill="{colour}""#),
                    circles,
                ));
            }
        }

        if !self.derived.is_empty() {
            let shapes = self
                .derived
                .iter()
                .map(|&p| Ok(Shape::Circle(current[self.check_point(p)?], 3.5)))
                .collect::<Result<_, SvgError>>()?;
            layers.push(Layer::new("derived", r#"fill="black""#, shapes));
        }

        if !self.anchors.is_empty() {
            let shapes = self
                .anchors
                .iter()
                .map(|&p| Ok(Shape::Circle(current[self.check_point(p)?], 5.0)))
                .collect::<Result<_, SvgError>>()?;
            layers.push(Layer::new(
                "anchors",
                r#"fill="none" stroke="black" stroke-width="2""#,
                shapes,
            ));
        }

        if !self.labels.is_empty() {
            let shapes = self
                .labels
                .iter()
                .map(|(p, text)| Ok(Shape::Text(current[self.check_point(*p)?], text.clone())))
                .collect::<Result<_, SvgError>>()?;
            layers.push(Layer::new(
                "labels",
                r#"font-family="sans-serif" font-size="11" fill="black""#,
                shapes,
            ));
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

fn finite(p: &[f64; 2]) -> bool {
    p[0].is_finite() && p[1].is_finite()
}

/// Orders points by angle around their centroid (ties by the original order), so the polygon
/// through them does not cross itself when they are in convex position.
fn around_centroid(points: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    let n = points.len().max(1) as f64;
    let c = [
        points.iter().map(|p| p[0]).sum::<f64>() / n,
        points.iter().map(|p| p[1]).sum::<f64>() / n,
    ];
    let mut keyed: Vec<(f64, usize, [f64; 2])> = points
        .into_iter()
        .enumerate()
        .map(|(i, p)| ((p[1] - c[1]).atan2(p[0] - c[0]), i, p))
        .collect();
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    keyed.into_iter().map(|(_, _, p)| p).collect()
}

/// Something to draw, in world coordinates (radii in pixels).
#[derive(Debug, Clone)]
enum Shape {
    Line([f64; 2], [f64; 2]),
    Polyline(Vec<[f64; 2]>),
    Polygon(Vec<[f64; 2]>),
    Circle([f64; 2], f64),
    Text([f64; 2], String),
}

impl Shape {
    /// Calls `f` with every point of the shape (for bounds).
    fn each_point(&self, mut f: impl FnMut(&[f64; 2])) {
        match self {
            Shape::Line(a, b) => {
                f(a);
                f(b);
            }
            Shape::Polyline(p) | Shape::Polygon(p) => p.iter().for_each(f),
            Shape::Circle(c, _) | Shape::Text(c, _) => f(c),
        }
    }
}

/// One group of shapes sharing a style.
#[derive(Debug, Clone)]
struct Layer {
    class: String,
    style: String,
    shapes: Vec<Shape>,
}

impl Layer {
    fn new(class: &str, style: &str, shapes: Vec<Shape>) -> Self {
        Layer {
            class: class.to_string(),
            style: style.to_string(),
            shapes,
        }
    }
}

/// Axis-aligned bounds of world coordinates; empty when `lo > hi`.
#[derive(Debug, Clone, Copy)]
struct Bounds {
    lo: [f64; 2],
    hi: [f64; 2],
}

impl Bounds {
    fn empty() -> Self {
        Bounds {
            lo: [f64::INFINITY; 2],
            hi: [f64::NEG_INFINITY; 2],
        }
    }

    fn add(&mut self, p: &[f64; 2]) {
        for ((lo, hi), x) in self.lo.iter_mut().zip(self.hi.iter_mut()).zip(p) {
            *lo = lo.min(*x);
            *hi = hi.max(*x);
        }
    }

    fn union(&self, other: &Bounds) -> Bounds {
        Bounds {
            lo: [self.lo[0].min(other.lo[0]), self.lo[1].min(other.lo[1])],
            hi: [self.hi[0].max(other.hi[0]), self.hi[1].max(other.hi[1])],
        }
    }

    /// The bounds, or the unit square at the origin when nothing was added.
    fn or_unit(self) -> Bounds {
        if self.lo[0] <= self.hi[0] && self.lo[1] <= self.hi[1] {
            self
        } else {
            Bounds {
                lo: [0.0, 0.0],
                hi: [1.0, 1.0],
            }
        }
    }

    fn extent(&self) -> [f64; 2] {
        [self.hi[0] - self.lo[0], self.hi[1] - self.lo[1]]
    }
}

/// Pixels per world unit so that the longer side of `bounds` is `size` pixels.
fn scale_for(bounds: &Bounds, size: f64) -> f64 {
    let [w, h] = bounds.extent();
    let longest = w.max(h);
    if longest > 0.0 && longest.is_finite() {
        size / longest
    } else {
        1.0
    }
}

/// Drawn content of one panel.
#[derive(Debug, Clone)]
struct Scene {
    layers: Vec<Layer>,
    title: Option<String>,
}

impl Scene {
    fn bounds(&self) -> Bounds {
        let mut b = Bounds::empty();
        for layer in &self.layers {
            for shape in &layer.shapes {
                shape.each_point(|p| b.add(p));
            }
        }
        b.or_unit()
    }

    fn title_height(&self) -> f64 {
        if self.title.is_some() {
            TITLE_HEIGHT
        } else {
            0.0
        }
    }

    fn panel_size(&self, bounds: &Bounds, scale: f64) -> (f64, f64) {
        let [w, h] = bounds.extent();
        (
            w * scale + 2.0 * MARGIN,
            h * scale + 2.0 * MARGIN + self.title_height(),
        )
    }

    /// Writes the panel with its top left corner at `offset`; `width` is the panel's width.
    fn render(&self, out: &mut String, bounds: &Bounds, scale: f64, offset: [f64; 2], width: f64) {
        let top = offset[1] + self.title_height() + MARGIN;
        let to_screen = |p: &[f64; 2]| -> [f64; 2] {
            [
                offset[0] + MARGIN + (p[0] - bounds.lo[0]) * scale,
                top + (bounds.hi[1] - p[1]) * scale,
            ]
        };
        if let Some(title) = &self.title {
            let _ = writeln!(
                out,
                r#"<text class="title" x="{}" y="{}" font-family="sans-serif" font-size="14" text-anchor="middle">{}</text>"#,
                num(offset[0] + width / 2.0),
                num(offset[1] + 17.0),
                escape(title)
            );
        }
        for layer in &self.layers {
            if layer.shapes.is_empty() {
                continue;
            }
            let _ = writeln!(out, r#"<g class="{}" {}>"#, layer.class, layer.style);
            for shape in &layer.shapes {
                match shape {
                    Shape::Line(a, b) => {
                        let (a, b) = (to_screen(a), to_screen(b));
                        let _ = writeln!(
                            out,
                            r#"<line x1="{}" y1="{}" x2="{}" y2="{}"/>"#,
                            num(a[0]),
                            num(a[1]),
                            num(b[0]),
                            num(b[1])
                        );
                    }
                    Shape::Polyline(points) | Shape::Polygon(points) => {
                        let tag = if matches!(shape, Shape::Polygon(_)) {
                            "polygon"
                        } else {
                            "polyline"
                        };
                        let _ = write!(out, r#"<{tag} points=""#);
                        for (i, p) in points.iter().enumerate() {
                            let s = to_screen(p);
                            if i > 0 {
                                out.push(' ');
                            }
                            let _ = write!(out, "{},{}", num(s[0]), num(s[1]));
                        }
                        out.push_str("\"/>\n");
                    }
                    Shape::Circle(c, r) => {
                        let c = to_screen(c);
                        let _ = writeln!(
                            out,
                            r#"<circle cx="{}" cy="{}" r="{}"/>"#,
                            num(c[0]),
                            num(c[1]),
                            num(*r)
                        );
                    }
                    Shape::Text(p, text) => {
                        let p = to_screen(p);
                        let _ = writeln!(
                            out,
                            r#"<text x="{}" y="{}">{}</text>"#,
                            num(p[0] + 6.0),
                            num(p[1] - 6.0),
                            escape(text)
                        );
                    }
                }
            }
            out.push_str("</g>\n");
        }
    }
}

fn header(width: f64, height: f64) -> String {
    let (w, h) = (num(width), num(height));
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n<rect width=\"{w}\" height=\"{h}\" fill=\"white\"/>\n"
    )
}

/// A coordinate with two decimals; `-0.00` is written `0.00`.
fn num(x: f64) -> String {
    let s = format!("{x:.2}");
    if s == "-0.00" {
        "0.00".to_string()
    } else {
        s
    }
}

/// Escapes text for SVG content and attribute values.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // Control characters other than tab and newlines are not allowed in XML 1.0.
            c if c.is_control() && !matches!(c, '\t' | '\n' | '\r') => out.push('\u{fffd}'),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use spline2d::mesh::Mesh;

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
    fn polygons_through_four_points_do_not_cross() {
        let p = around_centroid(vec![[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]]);
        assert_eq!(p, vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        assert_eq!(num(-0.001), "0.00");
        assert_eq!(num(2.5), "2.50");
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
