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

/// A terrain source's `ψ` (a [`Prisms`](api::Prisms) view) at the session's current values,
/// in the displacement form the source renders with: `(x + Dx, y + Dy, z + (1 − α)·(σ0 − a) +
/// α·(σ1 − b))`, each displacement's control values formed exactly before rounding, so a
/// prism whose values did not move leaves its vertices exactly in place.
pub(crate) struct PrismsEvaluator {
    locator: Locator,
    degree: usize,
    bottom: Vec<Vec<f64>>,
    top: Vec<Vec<f64>>,
    xy: Option<Vec<Vec<[f64; 2]>>>,
    /// `a` and `b`, the reference layer's bottom and top.
    a: f64,
    b: f64,
}

impl PrismsEvaluator {
    /// The evaluator of terrain source `name`.
    pub(crate) fn of(session: &Session, name: &str) -> PyResult<PrismsEvaluator> {
        let view = session.view(name).map_err(crate::input_error)?;
        let Some(SourceView::Prisms(view)) = view else {
            return Err(crate::input_error(format!(
                "source {name:?} is not a layer of prisms (a terrain source)"
            )));
        };
        let mesh = from_points(
            view.vertices.to_vec(),
            view.triangles.clone(),
            &MeshOptions::default(),
        )
        .map_err(crate::input_error)?
        .mesh;
        let d = view.degree;
        let scalar = |patches: &[Vec<api::ParamId>], reference: &Rational| -> Vec<Vec<f64>> {
            patches
                .iter()
                .map(|p| {
                    p.iter()
                        .map(|id| rational_to_f64(&(&session.values().get(*id)[0] - reference)))
                        .collect()
                })
                .collect()
        };
        let multi_indices: Vec<[usize; 3]> = (0..=d)
            .rev()
            .flat_map(|i| (0..=d - i).rev().map(move |j| [i, j, d - i - j]))
            .collect();
        let xy = view.xy.as_ref().map(|patches| {
            patches
                .iter()
                .zip(&view.triangles)
                .map(|(p, t)| {
                    p.iter()
                        .zip(&multi_indices)
                        .map(|(id, w)| {
                            let value = session.values().get(*id);
                            let mut out = [0.0; 2];
                            for (c, slot) in out.iter_mut().enumerate() {
                                let identity: Rational = (0..3)
                                    .map(|v| {
                                        &view.vertices[t[v]][c]
                                            * Rational::from_integer(w[v].into())
                                    })
                                    .sum::<Rational>()
                                    / Rational::from_integer(d.into());
                                *slot = rational_to_f64(&(&value[c] - identity));
                            }
                            out
                        })
                        .collect()
                })
                .collect()
        });
        let (a, b) = (
            rational_to_f64(&view.reference_bottom),
            rational_to_f64(&view.reference_top),
        );
        Ok(PrismsEvaluator {
            locator: Locator::new(&mesh),
            degree: d,
            bottom: scalar(&view.bottom, &view.reference_bottom),
            top: scalar(&view.top, &view.reference_top),
            xy,
            a,
            b,
        })
    }

    /// The Bernstein weights of degree `d` at `beta`, in the view's multi-index order.
    fn weights(&self, beta: [f64; 3]) -> Vec<f64> {
        let d = self.degree;
        let mut out = Vec::new();
        for i in (0..=d).rev() {
            for j in (0..=d - i).rev() {
                let k = d - i - j;
                out.push(
                    multinomial(d, i, j, k)
                        * beta[0].powi(i as i32)
                        * beta[1].powi(j as i32)
                        * beta[2].powi(k as i32),
                );
            }
        }
        out
    }

    /// The bottom and top heights `σ0`, `σ1` at each point; `None` outside the mesh.
    pub(crate) fn heights(&self, points: &[(f64, f64)]) -> Vec<Option<(f64, f64)>> {
        points
            .iter()
            .map(|&(x, y)| {
                let (t, beta) = self.locator.locate([x, y])?;
                let w = self.weights(beta);
                let dot = |c: &[f64]| -> f64 { w.iter().zip(c).map(|(w, c)| w * c).sum() };
                Some((self.a + dot(&self.bottom[t]), self.b + dot(&self.top[t])))
            })
            .collect()
    }

    /// Vertices `(x, y, z)` deformed by `ψ`; those outside the mesh or the layer `[a, b]` are
    /// returned as given. Also how many were left so.
    pub(crate) fn deform(&self, vertices: &[Vec<f64>]) -> PyResult<(Vec<Vec<f64>>, usize)> {
        let (a, b) = (self.a, self.b);
        let slack = 1e-9 * (b - a);
        let mut outside = 0;
        let mut out = Vec::with_capacity(vertices.len());
        for (n, v) in vertices.iter().enumerate() {
            if v.len() != 3 {
                return Err(crate::input_error(format!(
                    "vertex {n} has {} coordinates; a terrain deforms (x, y, z)",
                    v.len()
                )));
            }
            let z = v[2];
            let located = self.locator.locate([v[0], v[1]]);
            let Some((t, beta)) = located.filter(|_| z >= a - slack && z <= b + slack) else {
                outside += 1;
                out.push(v.clone());
                continue;
            };
            let w = self.weights(beta);
            let dot = |c: &[f64]| -> f64 { w.iter().zip(c).map(|(w, c)| w * c).sum() };
            let (below, above) = ((b - z) / (b - a), (z - a) / (b - a));
            let mut moved = v.clone();
            moved[2] = z + below * dot(&self.bottom[t]) + above * dot(&self.top[t]);
            if let Some(xy) = &self.xy {
                let dx: f64 = w.iter().zip(&xy[t]).map(|(w, c)| w * c[0]).sum();
                let dy: f64 = w.iter().zip(&xy[t]).map(|(w, c)| w * c[1]).sum();
                moved[0] += dx;
                moved[1] += dy;
            }
            out.push(moved);
        }
        Ok((out, outside))
    }
}
