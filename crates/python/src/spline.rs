//! Float evaluation of a source's triangular Bézier view (a `spline2d` source) at the
//! session's current values: `ψ` at points, and models deformed by it. A vertex in a triangle
//! whose control points are exactly those of the identity (`(i·v0 + j·v1 + k·v2)/d`) is
//! returned as given: the float result never moves what the exact deformation leaves in place.

use api::exact::rational_to_f64;
use api::{BezierTriangles, Rational, SourceView};
use host::session::Session;
use pyo3::PyResult;
use spline2d::eval::Locator;
use spline2d::mesh_io::{from_points, MeshOptions};

/// A source's spline at the session's current values, ready to evaluate.
pub(crate) struct Evaluator {
    locator: Locator,
    degree: usize,
    /// Per triangle, its control points in the view's multi-index order.
    patches: Vec<Vec<[f64; 2]>>,
    /// Per triangle, whether its patch is exactly the identity.
    identity: Vec<bool>,
}

impl Evaluator {
    /// The evaluator of source `name`, which must draw itself as triangular Bézier patches.
    pub(crate) fn of(session: &Session, name: &str) -> PyResult<Evaluator> {
        let view = session.view(name).map_err(crate::input_error)?;
        let Some(SourceView::BezierTriangles(view)) = view else {
            return Err(crate::input_error(format!(
                "source {name:?} is not a triangular Bézier spline (a spline2d source)"
            )));
        };
        Evaluator::of_view(session, &view)
    }

    fn of_view(session: &Session, view: &BezierTriangles) -> PyResult<Evaluator> {
        let mesh = from_points(
            view.vertices.to_vec(),
            view.triangles.clone(),
            &MeshOptions::default(),
        )
        .map_err(crate::input_error)?
        .mesh;
        let d = view.degree;
        let multi_indices: Vec<[usize; 3]> = (0..=d)
            .rev()
            .flat_map(|i| (0..=d - i).rev().map(move |j| [i, j, d - i - j]))
            .collect();
        let mut patches = Vec::with_capacity(view.patches.len());
        let mut identity = Vec::with_capacity(view.patches.len());
        for (t, params) in view.triangles.iter().zip(&view.patches) {
            let mut points = Vec::with_capacity(params.len());
            let mut same = params.len() == multi_indices.len();
            for (id, [i, j, k]) in params.iter().zip(&multi_indices) {
                let value = session.values().get(*id);
                if value.len() != 2 {
                    return Err(crate::input_error(
                        "a control point is not a point of the plane",
                    ));
                }
                points.push([rational_to_f64(&value[0]), rational_to_f64(&value[1])]);
                if same {
                    let weights = [*i, *j, *k];
                    let at = |c: usize| -> Rational {
                        let sum: Rational = (0..3)
                            .map(|v| {
                                &view.vertices[t[v]][c] * Rational::from_integer(weights[v].into())
                            })
                            .sum();
                        sum / Rational::from_integer(d.into())
                    };
                    same = value[0] == at(0) && value[1] == at(1);
                }
            }
            patches.push(points);
            identity.push(same);
        }
        Ok(Evaluator {
            locator: Locator::new(&mesh),
            degree: d,
            patches,
            identity,
        })
    }

    /// `ψ(p)`, with the triangle it lies in; `None` outside the mesh.
    fn at(&self, p: [f64; 2]) -> Option<(usize, [f64; 2])> {
        let (t, beta) = self.locator.locate(p)?;
        let d = self.degree;
        // Σ d!/(i! j! k!) β0^i β1^j β2^k c_ijk, in the view's order.
        let mut out = [0.0; 2];
        let mut n = 0;
        for i in (0..=d).rev() {
            for j in (0..=d - i).rev() {
                let k = d - i - j;
                let weight = multinomial(d, i, j, k)
                    * beta[0].powi(i as i32)
                    * beta[1].powi(j as i32)
                    * beta[2].powi(k as i32);
                let c = self.patches[t][n];
                out[0] += weight * c[0];
                out[1] += weight * c[1];
                n += 1;
            }
        }
        Some((t, out))
    }

    /// `ψ` at each point; `None` outside the mesh.
    pub(crate) fn evaluate(&self, points: &[(f64, f64)]) -> Vec<Option<(f64, f64)>> {
        points
            .iter()
            .map(|&(x, y)| self.at([x, y]).map(|(_, [u, v])| (u, v)))
            .collect()
    }

    /// Vertices `(x, y)` or `(x, y, z)` deformed by `ψ` (z kept); those outside the mesh and
    /// those in identity patches are returned as given. Also the number outside.
    pub(crate) fn deform(&self, vertices: &[Vec<f64>]) -> PyResult<(Vec<Vec<f64>>, usize)> {
        let mut outside = 0;
        let mut out = Vec::with_capacity(vertices.len());
        for (n, v) in vertices.iter().enumerate() {
            if v.len() != 2 && v.len() != 3 {
                return Err(crate::input_error(format!(
                    "vertex {n} has {} coordinates; expected 2 or 3",
                    v.len()
                )));
            }
            match self.at([v[0], v[1]]) {
                Some((t, _)) if self.identity[t] => out.push(v.clone()),
                Some((_, [x, y])) => {
                    let mut moved = v.clone();
                    moved[0] = x;
                    moved[1] = y;
                    out.push(moved);
                }
                None => {
                    outside += 1;
                    out.push(v.clone());
                }
            }
        }
        Ok((out, outside))
    }
}

/// `d! / (i! j! k!)` as a float (degrees are small).
fn multinomial(d: usize, i: usize, j: usize, k: usize) -> f64 {
    let factorial = |n: usize| (1..=n).map(|m| m as f64).product::<f64>();
    factorial(d) / (factorial(i) * factorial(j) * factorial(k))
}
