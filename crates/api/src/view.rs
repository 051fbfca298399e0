//! What an interactive editor draws of a source: which parameters are points to draw and drag,
//! and how they make up the picture (method 6 of the plugin ABI, optional).
//!
//! A view holds structure, not positions: the positions of the points are the parameters'
//! values, which the host keeps exactly. So an editor asks for a view once, draws it from the
//! current values, and during a drag only the moved points travel — the page redraws the
//! pieces that use them.

use crate::exact::Rational;
use crate::system::{ConstraintSystem, ParamId};
use serde::{Deserialize, Serialize};

/// The largest degree a [`BezierTriangles`] view may have (a patch has `(d + 1)(d + 2) / 2`
/// control points; spline2d's own limit is far below).
pub const MAX_VIEW_DEGREE: usize = 64;

/// A request for a source's view ([`crate::ConstraintSource::view`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ViewRequest {
    /// The payload schema the host speaks ([`crate::SCHEMA_VERSION`]).
    pub schema: u32,
}

/// A source's geometry for an editor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SourceView {
    /// A deformation of the plane by triangular Bézier patches over a reference mesh
    /// (spline2d).
    BezierTriangles(BezierTriangles),
}

/// A piecewise polynomial map of degree `d` over a planar triangulation, given per triangle
/// by its Bézier control points: the image of the point with barycentric coordinates
/// `(u, v, w)` in triangle `t` is `Σ d!/(i! j! k!) uⁱ vʲ wᵏ c_ijk` over the control points
/// `c_ijk` of `patches[t]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BezierTriangles {
    /// Polynomial degree `d` (at least 1).
    pub degree: usize,
    /// Smoothness `r` the source's conditions enforce across interior edges (`C^r`).
    pub smoothness: usize,
    /// The reference mesh's vertices, exact.
    pub vertices: Vec<[Rational; 2]>,
    /// The reference mesh's triangles (vertex indices, as the source numbers them).
    pub triangles: Vec<[usize; 3]>,
    /// Per triangle, the parameters (of dimension 2) holding its control points, in the order
    /// of the multi-indices `(i, j, k)` (weights on the triangle's first, second and third
    /// vertex) lexicographically descending: `(d,0,0), (d−1,1,0), (d−1,0,1), …, (0,0,d)`.
    /// Points on a shared edge or vertex are the same parameter in every patch.
    pub patches: Vec<Vec<ParamId>>,
}

impl SourceView {
    /// Checks a view against the system before a host uses it (a plugin's answer is outside
    /// data): indices in range, every patch complete, every point a parameter of dimension 2.
    pub fn validate(&self, system: &ConstraintSystem) -> Result<(), String> {
        match self {
            SourceView::BezierTriangles(view) => view.validate(system),
        }
    }
}

impl BezierTriangles {
    /// Control points per patch: `(d + 1)(d + 2) / 2`.
    pub fn points_per_patch(&self) -> usize {
        (self.degree + 1) * (self.degree + 2) / 2
    }

    fn validate(&self, system: &ConstraintSystem) -> Result<(), String> {
        if !(1..=MAX_VIEW_DEGREE).contains(&self.degree) {
            return Err(format!(
                "the view's degree {} is not between 1 and {MAX_VIEW_DEGREE}",
                self.degree
            ));
        }
        if self.patches.len() != self.triangles.len() {
            return Err(format!(
                "the view has {} patches for {} triangles",
                self.patches.len(),
                self.triangles.len()
            ));
        }
        let vertices = self.vertices.len();
        if let Some((t, tri)) = self
            .triangles
            .iter()
            .enumerate()
            .find(|(_, tri)| tri.iter().any(|&v| v >= vertices))
        {
            return Err(format!(
                "the view's triangle {t} {tri:?} names a vertex beyond its {vertices}"
            ));
        }
        let expected = self.points_per_patch();
        for (t, patch) in self.patches.iter().enumerate() {
            if patch.len() != expected {
                return Err(format!(
                    "the view's patch {t} has {} control points, degree {} needs {expected}",
                    patch.len(),
                    self.degree
                ));
            }
            for id in patch {
                match system.param(*id) {
                    None => {
                        return Err(format!(
                            "the view's patch {t} names parameter {id}, which does not exist"
                        ))
                    }
                    Some(p) if p.dim != 2 => {
                        return Err(format!(
                            "the view's patch {t} names {:?} of dimension {}, not a point",
                            p.name, p.dim
                        ))
                    }
                    Some(_) => {}
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn system() -> (ConstraintSystem, Vec<ParamId>) {
        let mut s = ConstraintSystem::new();
        let points = (0..3)
            .map(|i| s.add_parameter(format!("v{i}"), 2).expect("fresh"))
            .collect();
        s.add_parameter("h", 1).expect("fresh");
        (s, points)
    }

    fn view(patches: Vec<Vec<ParamId>>) -> SourceView {
        let q = |n: i64| Rational::from_integer(n.into());
        SourceView::BezierTriangles(BezierTriangles {
            degree: 1,
            smoothness: 0,
            vertices: vec![[q(0), q(0)], [q(1), q(0)], [q(0), q(1)]],
            triangles: vec![[0, 1, 2]],
            patches,
        })
    }

    #[test]
    fn a_complete_view_passes_and_broken_ones_are_named() {
        let (s, p) = system();
        assert_eq!(view(vec![p.clone()]).validate(&s), Ok(()));
        let short = view(vec![p[..2].to_vec()]).validate(&s).expect_err("short");
        assert!(short.contains("has 2 control points"), "{short}");
        let scalar = view(vec![vec![p[0], p[1], ParamId(3)]])
            .validate(&s)
            .expect_err("scalar");
        assert!(scalar.contains("\"h\" of dimension 1"), "{scalar}");
        let missing = view(vec![vec![p[0], p[1], ParamId(9)]])
            .validate(&s)
            .expect_err("missing");
        assert!(missing.contains("does not exist"), "{missing}");
        let SourceView::BezierTriangles(mut bad) = view(vec![p.clone()]);
        bad.triangles[0] = [0, 1, 5];
        let beyond = SourceView::BezierTriangles(bad.clone())
            .validate(&s)
            .expect_err("vertex");
        assert!(beyond.contains("beyond its 3"), "{beyond}");
        bad.triangles.clear();
        let count = SourceView::BezierTriangles(bad)
            .validate(&s)
            .expect_err("count");
        assert!(count.contains("1 patches for 0 triangles"), "{count}");
    }

    #[test]
    fn views_round_trip_through_json() {
        let (_, p) = system();
        let v = view(vec![p]);
        let text = serde_json::to_string(&v).expect("serialise");
        assert!(text.contains("\"kind\":\"bezier_triangles\""), "{text}");
        assert_eq!(serde_json::from_str::<SourceView>(&text).expect("parse"), v);
    }
}
