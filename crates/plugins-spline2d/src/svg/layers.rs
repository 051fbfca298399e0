//! One function per layer of a [`Picture`]: what each kind of element (meshes, conditions,
//! control net and points, groups, anchors, derived points, labels, a model) draws, in world
//! coordinates, with its style. The picture calls them in drawing order.

use super::scene::{escape, finite, StyledGroup, SvgElement};
use super::{Group, Picture, SvgError};
use api::exact::rational_to_f64;
use spline2d::eval::FloatSpline;
use spline2d::model::Model;
use spline2d::net::ControlNet;
use std::collections::BTreeMap;

impl Picture<'_> {
    /// The reference mesh: thin grey straight edges.
    pub(super) fn reference_mesh_layer(&self) -> Result<StyledGroup, SvgError> {
        let vertices: Vec<[f64; 2]> = self
            .spline
            .mesh()
            .vertices()
            .iter()
            .map(|p| [rational_to_f64(&p[0]), rational_to_f64(&p[1])])
            .collect();
        let mut shapes = Vec::new();
        for e in &self.spline.topology().edges {
            let (a, b) = (vertices[e.a], vertices[e.b]);
            if !(finite(&a) && finite(&b)) {
                return Err(SvgError::NotFinite {
                    what: format!("mesh edge {}-{}", e.a, e.b),
                });
            }
            shapes.push(SvgElement::Line(a, b));
        }
        Ok(StyledGroup::new(
            "reference-mesh",
            r##"fill="none" stroke="#b0b0b0" stroke-width="0.6""##,
            shapes,
        ))
    }

    /// The selected conditions: translucent grey polygons through their control points.
    pub(super) fn conditions_layer(&self, current: &[[f64; 2]]) -> Result<StyledGroup, SvgError> {
        Ok(StyledGroup::new(
            "conditions",
            r##"fill="#808080" fill-opacity="0.35" stroke="#606060" stroke-width="0.5" stroke-linejoin="round""##,
            self.condition_polygons(&self.conditions, current)?,
        ))
    }

    /// The deformed mesh: each edge's image under `φ`, sampled, from the triangle first on it.
    pub(super) fn deformed_mesh_layer(&self) -> Result<StyledGroup, SvgError> {
        let spline = self.spline;
        let mesh = spline.mesh();
        let topology = spline.topology();
        let nominal;
        let positions = match self.positions {
            Some(p) => p,
            None => {
                nominal = spline
                    .nominals()
                    .iter()
                    .map(|p| p.to_vec())
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
            shapes.push(SvgElement::Polyline(line));
        }
        Ok(StyledGroup::new(
            "deformed-mesh",
            r##"fill="none" stroke="#202020" stroke-width="1.2" stroke-linejoin="round""##,
            shapes,
        ))
    }

    /// The global control net, dotted, at the current positions.
    pub(super) fn control_net_layer(&self, current: &[[f64; 2]]) -> StyledGroup {
        let net = ControlNet::new(self.spline);
        let shapes = net
            .edges()
            .iter()
            .map(|&(a, b)| SvgElement::Line(current[a], current[b]))
            .collect();
        StyledGroup::new(
            "control-net",
            r##"fill="none" stroke="#707070" stroke-width="0.6" stroke-dasharray="2 2""##,
            shapes,
        )
    }

    /// A group's conditions and points in its colour: up to two layers, `{class}-conditions`
    /// and `{class}-points`, each only when it has something to draw.
    pub(super) fn group_layers(
        &self,
        group: &Group,
        current: &[[f64; 2]],
    ) -> Result<Vec<StyledGroup>, SvgError> {
        let mut layers = Vec::new();
        let polygons = self.condition_polygons(&group.conditions, current)?;
        let colour = escape(&group.colour);
        if !polygons.is_empty() {
            layers.push(StyledGroup::new(
                &format!("{}-conditions", escape(&group.class)),
                &format!(
                    r#"fill="{colour}" fill-opacity="0.3" stroke="{colour}" stroke-width="0.5""#
                ),
                polygons,
            ));
        }
        let circles = self.point_circles(&group.points, current, 2.6)?;
        if !circles.is_empty() {
            layers.push(StyledGroup::new(
                &format!("{}-points", escape(&group.class)),
                &format!(r#"fill="{colour}""#),
                circles,
            ));
        }
        Ok(layers)
    }

    /// The derived points of an edit: filled black dots.
    pub(super) fn derived_layer(&self, current: &[[f64; 2]]) -> Result<StyledGroup, SvgError> {
        Ok(StyledGroup::new(
            "derived",
            r#"fill="black""#,
            self.point_circles(&self.derived, current, 3.5)?,
        ))
    }

    /// The anchors of an edit: open bold circles.
    pub(super) fn anchors_layer(&self, current: &[[f64; 2]]) -> Result<StyledGroup, SvgError> {
        Ok(StyledGroup::new(
            "anchors",
            r#"fill="none" stroke="black" stroke-width="2""#,
            self.point_circles(&self.anchors, current, 5.0)?,
        ))
    }

    /// The text labels, next to their control points, in the order added.
    pub(super) fn labels_layer(&self, current: &[[f64; 2]]) -> Result<StyledGroup, SvgError> {
        let shapes = self
            .labels
            .iter()
            .map(|(p, text)| {
                Ok(SvgElement::Text(
                    current[self.check_point(*p)?],
                    text.clone(),
                ))
            })
            .collect::<Result<_, SvgError>>()?;
        Ok(StyledGroup::new(
            "labels",
            r#"font-family="sans-serif" font-size="11" fill="black""#,
            shapes,
        ))
    }

    /// One polygon per condition (an index into the spline's conditions) through its control
    /// points at `current`, ordered around their centroid.
    fn condition_polygons(
        &self,
        conditions: &[usize],
        current: &[[f64; 2]],
    ) -> Result<Vec<SvgElement>, SvgError> {
        let all = self.spline.conditions();
        let mut polygons = Vec::with_capacity(conditions.len());
        for &c in conditions {
            let condition = all.get(c).ok_or(SvgError::NoSuchCondition {
                condition: c,
                count: all.len(),
            })?;
            let points: Vec<[f64; 2]> = condition.terms.iter().map(|(p, _)| current[*p]).collect();
            polygons.push(SvgElement::Polygon(around_centroid(points)));
        }
        Ok(polygons)
    }

    /// A circle of `radius` pixels at each of `points` (control point ids) at `current`.
    fn point_circles(
        &self,
        points: &[usize],
        current: &[[f64; 2]],
        radius: f64,
    ) -> Result<Vec<SvgElement>, SvgError> {
        points
            .iter()
            .map(|&p| Ok(SvgElement::Circle(current[self.check_point(p)?], radius)))
            .collect()
    }
}

/// Most model edges a picture draws one by one. A model with more is drawn by its outline in
/// the picture's plane — its boundary edges and its silhouette, the edges between a face seen
/// from above and one seen from below (and edges of more than two faces) — so that a picture of a
/// real model (a scanned statue of 100 000 triangles) stays a drawing of a few megabytes that a
/// browser renders at once, not a solid blob.
pub const MODEL_EDGE_BUDGET: usize = 50_000;

/// A model's triangle edges (each once), thin blue; beyond [`MODEL_EDGE_BUDGET`] edges, its
/// outline only (group `model-outline`).
pub(super) fn model_edges_layer(model: &Model) -> Result<StyledGroup, SvgError> {
    let count = model.positions.len();
    let xy = |v: usize| [model.positions[v][0], model.positions[v][1]];
    // Per edge: its faces and the sides (sign of the area in the plane) they are seen from.
    let mut edges: BTreeMap<(usize, usize), (usize, i8, bool)> = BTreeMap::new();
    for tri in &model.triangles {
        if let Some(&v) = tri.iter().find(|&&v| v >= count) {
            return Err(SvgError::NoSuchPoint { point: v, count });
        }
        let [a, b, c] = tri.map(xy);
        let area = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        let side: i8 = if area > 0.0 {
            1
        } else if area < 0.0 {
            -1
        } else {
            0
        };
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            if a != b {
                let entry = edges
                    .entry((a.min(b), a.max(b)))
                    .or_insert((0, side, false));
                entry.0 += 1;
                entry.2 |= entry.1 != side;
            }
        }
    }
    let outline = edges.len() > MODEL_EDGE_BUDGET;
    let mut shapes = Vec::new();
    for ((a, b), (faces, _, sides_differ)) in edges {
        if outline && faces == 2 && !sides_differ {
            continue;
        }
        let (pa, pb) = (xy(a), xy(b));
        if !(finite(&pa) && finite(&pb)) {
            return Err(SvgError::NotFinite {
                what: format!("model edge {a}-{b}"),
            });
        }
        shapes.push(SvgElement::Line(pa, pb));
    }
    Ok(StyledGroup::new(
        if outline {
            "model-outline"
        } else {
            "model-edges"
        },
        r##"fill="none" stroke="#4a7fb5" stroke-width="0.5""##,
        shapes,
    ))
}

/// A model's vertices as small blue dots.
pub(super) fn model_vertices_layer(model: &Model) -> Result<StyledGroup, SvgError> {
    let mut shapes = Vec::with_capacity(model.positions.len());
    for (v, p) in model.positions.iter().enumerate() {
        let xy = [p[0], p[1]];
        if !finite(&xy) {
            return Err(SvgError::NotFinite {
                what: format!("model vertex {v}"),
            });
        }
        shapes.push(SvgElement::Circle(xy, 1.0));
    }
    Ok(StyledGroup::new(
        "model-vertices",
        r##"fill="#4a7fb5""##,
        shapes,
    ))
}

/// Every control point as a small dark dot at `current`.
pub(super) fn control_points_layer(current: &[[f64; 2]]) -> StyledGroup {
    let shapes = current
        .iter()
        .map(|p| SvgElement::Circle(*p, 1.8))
        .collect();
    StyledGroup::new("control-points", r##"fill="#404040""##, shapes)
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

#[cfg(test)]
mod tests {
    use super::super::scene::num;
    use super::*;

    #[test]
    fn polygons_through_four_points_do_not_cross() {
        let p = around_centroid(vec![[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]]);
        assert_eq!(p, vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        assert_eq!(num(-0.001), "0.00");
        assert_eq!(num(2.5), "2.50");
    }
}

#[cfg(test)]
mod model_tests {
    use super::*;

    /// A model too large to draw edge by edge is drawn by its outline: for a flat grid of
    /// triangles, its border.
    #[test]
    fn large_models_are_outlined() {
        let n = 170; // 170 × 170 squares: 86 870 edges, beyond the budget.
        let at = |i: usize, j: usize| j * (n + 1) + i;
        let positions: Vec<[f64; 3]> = (0..=n)
            .flat_map(|j| (0..=n).map(move |i| [i as f64, j as f64, 0.0]))
            .collect();
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        let big = Model {
            positions,
            triangles,
        };
        let layer = model_edges_layer(&big).expect("drawn");
        assert_eq!(layer.name(), "model-outline");
        assert_eq!(layer.len(), 4 * n, "the border only");
        // A small model is drawn edge by edge.
        let small = Model {
            positions: big.positions[..].to_vec(),
            triangles: big.triangles[..2].to_vec(),
        };
        let layer = model_edges_layer(&small).expect("drawn");
        assert_eq!((layer.name(), layer.len()), ("model-edges", 5));
    }
}
