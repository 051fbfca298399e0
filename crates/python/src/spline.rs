//! Float evaluation of a source's view at the session's current values: `ψ` of a `spline2d`
//! source (triangular Bézier patches) and of a `terrain` source (a layer of prisms), at points
//! and on model vertices. Every patch is evaluated in displacement form, `p + Σ Bᵢ(β)·(cᵢ −
//! idᵢ)`, the displacements of the control points formed exactly before rounding: a patch whose
//! control points did not move has displacements exactly zero, so the float result never moves
//! what the exact deformation leaves in place.

use api::exact::rational_to_f64;
use api::{BezierTriangles, ParamId, Prisms, Rational, SourceView};
use host::session::Session;
use pyo3::PyResult;
use spline2d::eval::Locator;
use spline2d::mesh_io::{from_points, MeshOptions};

/// The locator of a view's reference mesh (validated again: the view comes from a source).
fn locator(vertices: &[[Rational; 2]], triangles: &[[usize; 3]]) -> PyResult<Locator> {
    let mesh = from_points(
        vertices.to_vec(),
        triangles.to_vec(),
        &MeshOptions::default(),
    )
    .map_err(crate::input_error)?
    .mesh;
    Ok(Locator::new(&mesh))
}

/// The multi-indices `(i, j, k)` of degree `d`, lexicographically descending: the order of a
/// view's control points in a patch.
fn multi_indices(d: usize) -> Vec<[usize; 3]> {
    (0..=d)
        .rev()
        .flat_map(|i| (0..=d - i).rev().map(move |j| [i, j, d - i - j]))
        .collect()
}

/// The Bernstein weights `d!/(i! j! k!) β0^i β1^j β2^k` in the order of [`multi_indices`].
fn bernstein(d: usize, beta: [f64; 3]) -> Vec<f64> {
    let factorial = |n: usize| (1..=n).map(|m| m as f64).product::<f64>();
    multi_indices(d)
        .iter()
        .map(|&[i, j, k]| {
            factorial(d) / (factorial(i) * factorial(j) * factorial(k))
                * beta[0].powi(i as i32)
                * beta[1].powi(j as i32)
                * beta[2].powi(k as i32)
        })
        .collect()
}

/// The planar displacements `c − id` of the control points `params` of triangle `t`, where
/// the identity's control point `(i, j, k)` is `(i·v0 + j·v1 + k·v2)/d`; exact, then rounded.
fn planar_displacements(
    session: &Session,
    vertices: &[[Rational; 2]],
    t: &[usize; 3],
    params: &[ParamId],
    d: usize,
) -> PyResult<Vec<[f64; 2]>> {
    params
        .iter()
        .zip(multi_indices(d))
        .map(|(id, w)| {
            let value = session.values().get(*id);
            if value.len() != 2 {
                return Err(crate::input_error(
                    "a control point is not a point of the plane",
                ));
            }
            let mut out = [0.0; 2];
            for (c, slot) in out.iter_mut().enumerate() {
                let identity = (0..3)
                    .map(|v| &vertices[t[v]][c] * Rational::from_integer(w[v].into()))
                    .sum::<Rational>()
                    / Rational::from_integer(d.into());
                *slot = rational_to_f64(&(&value[c] - identity));
            }
            Ok(out)
        })
        .collect()
}

/// `Σ wᵢ·cᵢ` of planar values.
fn planar_sum(weights: &[f64], values: &[[f64; 2]]) -> [f64; 2] {
    let mut out = [0.0; 2];
    for (w, c) in weights.iter().zip(values) {
        out[0] += w * c[0];
        out[1] += w * c[1];
    }
    out
}

/// `Σ wᵢ·cᵢ`.
fn sum(weights: &[f64], values: &[f64]) -> f64 {
    weights.iter().zip(values).map(|(w, c)| w * c).sum()
}

/// A source's deformation at the session's current values.
pub(crate) enum Deformation {
    /// A `spline2d` source: `ψ(x, y) = (x, y) + D(x, y)`.
    Plane {
        locator: Locator,
        degree: usize,
        /// Per triangle, the displacements of its control points.
        displacements: Vec<Vec<[f64; 2]>>,
    },
    /// A `terrain` source: the layer of prisms between `z = a` and `z = b`.
    Prisms {
        locator: Locator,
        degree: usize,
        /// Per triangle, `σ0 − a` and `σ1 − b` at its control points.
        bottom: Vec<Vec<f64>>,
        top: Vec<Vec<f64>>,
        /// Per triangle, the displacements of `φ`'s control points (none: the identity).
        xy: Option<Vec<Vec<[f64; 2]>>>,
        a: f64,
        b: f64,
    },
}

impl Deformation {
    /// The deformation of source `name`.
    pub(crate) fn of(session: &Session, name: &str) -> PyResult<Deformation> {
        match session.deformation_view(name).map_err(crate::input_error)? {
            Some(SourceView::BezierTriangles(view)) => Deformation::plane(session, &view),
            Some(SourceView::Prisms(view)) => Deformation::prisms(session, &view),
            None => Err(crate::input_error(format!(
                "source {name:?} has no deformation to evaluate"
            ))),
        }
    }

    fn plane(session: &Session, view: &BezierTriangles) -> PyResult<Deformation> {
        let displacements = view
            .triangles
            .iter()
            .zip(&view.patches)
            .map(|(t, params)| {
                planar_displacements(session, &view.vertices, t, params, view.degree)
            })
            .collect::<PyResult<_>>()?;
        Ok(Deformation::Plane {
            locator: locator(&view.vertices, &view.triangles)?,
            degree: view.degree,
            displacements,
        })
    }

    fn prisms(session: &Session, view: &Prisms) -> PyResult<Deformation> {
        let heights = |patches: &[Vec<ParamId>], reference: &Rational| -> Vec<Vec<f64>> {
            patches
                .iter()
                .map(|p| {
                    p.iter()
                        .map(|id| rational_to_f64(&(&session.values().get(*id)[0] - reference)))
                        .collect()
                })
                .collect()
        };
        let xy = match &view.xy {
            Some(patches) => Some(
                view.triangles
                    .iter()
                    .zip(patches)
                    .map(|(t, params)| {
                        planar_displacements(session, &view.vertices, t, params, view.degree)
                    })
                    .collect::<PyResult<_>>()?,
            ),
            None => None,
        };
        Ok(Deformation::Prisms {
            locator: locator(&view.vertices, &view.triangles)?,
            degree: view.degree,
            bottom: heights(&view.bottom, &view.reference_bottom),
            top: heights(&view.top, &view.reference_top),
            xy,
            a: rational_to_f64(&view.reference_bottom),
            b: rational_to_f64(&view.reference_top),
        })
    }

    /// A spline's `ψ` at each point; `None` outside the mesh.
    pub(crate) fn evaluate(&self, points: &[(f64, f64)]) -> PyResult<Vec<Option<(f64, f64)>>> {
        let Deformation::Plane {
            locator,
            degree,
            displacements,
        } = self
        else {
            return Err(crate::input_error(
                "evaluate is for a spline2d source; a terrain gives heights",
            ));
        };
        Ok(points
            .iter()
            .map(|&(x, y)| {
                let (t, beta) = locator.locate([x, y])?;
                let [dx, dy] = planar_sum(&bernstein(*degree, beta), &displacements[t]);
                Some((x + dx, y + dy))
            })
            .collect())
    }

    /// A terrain's bottom and top heights at each point; `None` outside the mesh.
    pub(crate) fn heights(&self, points: &[(f64, f64)]) -> PyResult<Vec<Option<(f64, f64)>>> {
        let Deformation::Prisms {
            locator,
            degree,
            bottom,
            top,
            a,
            b,
            ..
        } = self
        else {
            return Err(crate::input_error(
                "heights are for a terrain source; a spline2d source is evaluated",
            ));
        };
        Ok(points
            .iter()
            .map(|&(x, y)| {
                let (t, beta) = locator.locate([x, y])?;
                let w = bernstein(*degree, beta);
                Some((a + sum(&w, &bottom[t]), b + sum(&w, &top[t])))
            })
            .collect())
    }

    /// Model vertices deformed: `(x, y)` or `(x, y, z)` by a spline (z kept), `(x, y, z)` by a
    /// terrain. Vertices outside the mesh (or a terrain's layer, beyond `1e-9·(b − a)`) are
    /// returned as given; also how many.
    pub(crate) fn deform(&self, vertices: &[Vec<f64>]) -> PyResult<(Vec<Vec<f64>>, usize)> {
        let mut outside = 0;
        let mut out = Vec::with_capacity(vertices.len());
        for (n, v) in vertices.iter().enumerate() {
            let moved = match self {
                Deformation::Plane {
                    locator,
                    degree,
                    displacements,
                } => {
                    if v.len() != 2 && v.len() != 3 {
                        return Err(crate::input_error(format!(
                            "vertex {n} has {} coordinates; expected 2 or 3",
                            v.len()
                        )));
                    }
                    locator.locate([v[0], v[1]]).map(|(t, beta)| {
                        let [dx, dy] = planar_sum(&bernstein(*degree, beta), &displacements[t]);
                        let mut moved = v.clone();
                        moved[0] += dx;
                        moved[1] += dy;
                        moved
                    })
                }
                Deformation::Prisms {
                    locator,
                    degree,
                    bottom,
                    top,
                    xy,
                    a,
                    b,
                } => {
                    if v.len() != 3 {
                        return Err(crate::input_error(format!(
                            "vertex {n} has {} coordinates; a terrain deforms (x, y, z)",
                            v.len()
                        )));
                    }
                    let (z, slack) = (v[2], 1e-9 * (b - a));
                    locator
                        .locate([v[0], v[1]])
                        .filter(|_| z >= a - slack && z <= b + slack)
                        .map(|(t, beta)| {
                            let w = bernstein(*degree, beta);
                            let (below, above) = ((b - z) / (b - a), (z - a) / (b - a));
                            let mut moved = v.clone();
                            moved[2] = z + below * sum(&w, &bottom[t]) + above * sum(&w, &top[t]);
                            if let Some(xy) = xy {
                                let [dx, dy] = planar_sum(&w, &xy[t]);
                                moved[0] += dx;
                                moved[1] += dy;
                            }
                            moved
                        })
                }
            };
            out.push(moved.unwrap_or_else(|| {
                outside += 1;
                v.clone()
            }));
        }
        Ok((out, outside))
    }
}
