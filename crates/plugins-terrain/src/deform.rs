//! The 2.5D deformation `ψ` in floating point, for models with millions of vertices
//! (thesis 17.2–17.3).
//!
//! [`Psi`] keeps the point locator of the reference mesh and the three splines as one
//! [`FloatSpline`] whose control values are `(σ0, σ1)` or `(φx, φy, σ0, σ1)`, so mapping a vertex
//! is one point location and one evaluation, without allocation:
//! locate `(x, y)` in `T` (triangle `u`, barycentric `β`), take `α0 = (b − z)/(b − a)`,
//! `α1 = (z − a)/(b − a)`, and return `(φ(x, y), α0·σ0(x, y) + α1·σ1(x, y))`. Without `φ`
//! (the identity) `x` and `y` are returned unchanged. Vertices outside the prisms keep their
//! position and are listed ([`DeformedModel`]); the topology is kept.
//!
//! [`Psi::jacobian_in`] gives `ψ` and its derivatives on one prism, for normals and for
//! checking smoothness across the walls of neighbouring prisms.

use crate::prism::{Layer, Surfaces};
use api::exact::rational_to_f64;
use api::Rational;
use plugins_spline2d::eval::{check_positions, EvalError, FloatSpline, Locator};
use plugins_spline2d::model::Model;
use plugins_spline2d::spline::Spline;

/// Relative tolerance on `z` (in units of `b − a`): points that far above the top or below the
/// bottom still count as inside, so vertices on the faces are deformed despite rounding.
pub const LAYER_TOLERANCE: f64 = 1e-9;

/// Why the control values cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DeformError {
    /// A surface's values do not fit the spline.
    #[error("{surface}: {source}")]
    Values {
        /// `"phi"`, `"bottom"` or `"top"`.
        surface: &'static str,
        /// What is wrong.
        source: EvalError,
    },
    /// A surface has the wrong number of coordinates.
    #[error("{surface} needs {expected} coordinates per control point, got {found}")]
    Dimension {
        /// `"phi"`, `"bottom"` or `"top"`.
        surface: &'static str,
        /// Coordinates it needs.
        expected: usize,
        /// Coordinates given.
        found: usize,
    },
}

/// Why a point was not deformed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outside {
    /// `(x, y)` is outside the reference mesh (or not finite).
    Mesh,
    /// `z` is below the bottom or above the top of the prisms (or not finite).
    Layer,
}

/// A deformed model and the vertices left in place.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DeformedModel {
    /// Same vertex numbering and triangles as the input; vertices inside the prisms mapped by
    /// `ψ`, the others unchanged.
    pub model: Model,
    /// Vertices whose `(x, y)` is outside the reference mesh (ascending).
    pub outside_mesh: Vec<usize>,
    /// Vertices inside the mesh but outside `[a, b]` in `z` (ascending).
    pub outside_layer: Vec<usize>,
}

impl DeformedModel {
    /// Every vertex left in place, ascending.
    pub fn outside(&self) -> Vec<usize> {
        let mut all: Vec<usize> = self
            .outside_mesh
            .iter()
            .chain(&self.outside_layer)
            .copied()
            .collect();
        all.sort_unstable();
        all
    }
}

/// `ψ` ready to map points.
#[derive(Debug, Clone)]
pub struct Psi {
    locator: Locator,
    /// Values `(σ0, σ1)` or `(φx, φy, σ0, σ1)`.
    spline: FloatSpline,
    xy: bool,
    bottom: f64,
    top: f64,
    /// Per triangle, its corners.
    corners: Vec<[[f64; 2]; 3]>,
    /// Per triangle, `∂βk/∂x` and `∂βk/∂y`.
    gradients: Vec<[[f64; 2]; 3]>,
}

impl Psi {
    /// Converts the splines of a deformation on `spline`'s mesh to floating point.
    pub fn new(spline: &Spline, layer: &Layer, surfaces: Surfaces<'_>) -> Result<Psi, DeformError> {
        let check = |surface: &'static str, values: &[Vec<Rational>], expected: usize| {
            let found = check_positions(spline, values)
                .map_err(|source| DeformError::Values { surface, source })?;
            if found == expected {
                Ok(())
            } else {
                Err(DeformError::Dimension {
                    surface,
                    expected,
                    found,
                })
            }
        };
        check("bottom", surfaces.bottom, 1)?;
        check("top", surfaces.top, 1)?;
        if let Some(phi) = surfaces.phi {
            check("phi", phi, 2)?;
        }
        let combined: Vec<Vec<Rational>> = (0..spline.points().len())
            .map(|p| {
                let mut v = surfaces.phi.map(|phi| phi[p].clone()).unwrap_or_default();
                v.push(surfaces.bottom[p][0].clone());
                v.push(surfaces.top[p][0].clone());
                v
            })
            .collect();
        let float = FloatSpline::new(spline, &combined).map_err(|source| DeformError::Values {
            surface: "bottom",
            source,
        })?;
        let vertices: Vec<[f64; 2]> = spline
            .mesh()
            .vertices()
            .iter()
            .map(|p| [rational_to_f64(&p[0]), rational_to_f64(&p[1])])
            .collect();
        let corners: Vec<[[f64; 2]; 3]> = spline
            .mesh()
            .triangles()
            .iter()
            .map(|tri| tri.map(|v| vertices[v]))
            .collect();
        let gradients = corners
            .iter()
            .map(|&[[x0, y0], [x1, y1], [x2, y2]]| {
                let area = (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0);
                [
                    [(y1 - y2) / area, (x2 - x1) / area],
                    [(y2 - y0) / area, (x0 - x2) / area],
                    [(y0 - y1) / area, (x1 - x0) / area],
                ]
            })
            .collect();
        Ok(Psi {
            locator: Locator::new(spline.mesh()),
            spline: float,
            xy: surfaces.phi.is_some(),
            bottom: rational_to_f64(layer.bottom()),
            top: rational_to_f64(layer.top()),
            corners,
            gradients,
        })
    }

    /// Whether `φ` is part of the deformation (otherwise it is the identity).
    pub fn has_phi(&self) -> bool {
        self.xy
    }

    /// The prism of `p`: triangle, barycentric coordinates `β` and vertical coordinates `α`.
    pub fn locate(&self, p: [f64; 3]) -> Result<(usize, [f64; 3], [f64; 2]), Outside> {
        let (t, beta) = self.locator.locate([p[0], p[1]]).ok_or(Outside::Mesh)?;
        let height = self.top - self.bottom;
        let slack = LAYER_TOLERANCE * height;
        let z = p[2];
        if !(z >= self.bottom - slack && z <= self.top + slack) {
            return Err(Outside::Layer);
        }
        Ok((
            t,
            beta,
            [(self.top - z) / height, (z - self.bottom) / height],
        ))
    }

    /// `ψ(p)`, or why `p` is outside the prisms.
    #[inline]
    pub fn map(&self, p: [f64; 3]) -> Result<[f64; 3], Outside> {
        let (t, beta, [a0, a1]) = self.locate(p)?;
        let mut values = [0.0; 4];
        if self.xy {
            self.spline.evaluate_into(t, beta, &mut values);
            Ok([values[0], values[1], a0 * values[2] + a1 * values[3]])
        } else {
            self.spline.evaluate_into(t, beta, &mut values[..2]);
            Ok([p[0], p[1], a0 * values[0] + a1 * values[1]])
        }
    }

    /// `φ` on triangle `t` at barycentric coordinates `beta` (the point `Σ βk·vk` itself when
    /// `φ` is the identity); `None` if `t` is not a triangle. For drawing the deformed
    /// reference mesh.
    pub fn phi_in(&self, t: usize, beta: [f64; 3]) -> Option<[f64; 2]> {
        if self.xy {
            let v = self.spline.evaluate(t, beta)?;
            Some([v[0], v[1]])
        } else {
            let corners = self.corners.get(t)?;
            let at = |axis: usize| (0..3).map(|k| beta[k] * corners[k][axis]).sum();
            Some([at(0), at(1)])
        }
    }

    /// `ψ` and its Jacobian `∂ψ_r/∂(x, y, z)_c` on the prism over triangle `t` at `p`,
    /// evaluating that prism's polynomial pieces (also just outside the triangle, so the two
    /// sides of a shared wall can be compared). `None` if `t` is not a triangle.
    pub fn jacobian_in(&self, t: usize, p: [f64; 3]) -> Option<([f64; 3], [[f64; 3]; 3])> {
        let beta = self.locator.barycentric(t, [p[0], p[1]])?;
        let g = self.gradients.get(t)?;
        let (value, partials) = self.spline.evaluate_with_derivatives(t, beta)?;
        // Derivative of value coordinate `c` along x (axis 0) or y (axis 1).
        let along =
            |c: usize, axis: usize| -> f64 { (0..3).map(|k| partials[k][c] * g[k][axis]).sum() };
        let height = self.top - self.bottom;
        let (a0, a1) = ((self.top - p[2]) / height, (p[2] - self.bottom) / height);
        let s = if self.xy { 2 } else { 0 };
        let (s0, s1) = (value[s], value[s + 1]);
        let z = a0 * s0 + a1 * s1;
        let dz = [
            a0 * along(s, 0) + a1 * along(s + 1, 0),
            a0 * along(s, 1) + a1 * along(s + 1, 1),
            (s1 - s0) / height,
        ];
        if self.xy {
            Some((
                [value[0], value[1], z],
                [
                    [along(0, 0), along(0, 1), 0.0],
                    [along(1, 0), along(1, 1), 0.0],
                    dz,
                ],
            ))
        } else {
            Some(([p[0], p[1], z], [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], dz]))
        }
    }

    /// Maps every vertex of `model` by `ψ`; vertices outside the prisms keep their position and
    /// are listed. Allocates only the output.
    pub fn deform(&self, model: &Model) -> DeformedModel {
        let mut positions = Vec::with_capacity(model.positions.len());
        let mut outside_mesh = Vec::new();
        let mut outside_layer = Vec::new();
        for (v, p) in model.positions.iter().enumerate() {
            match self.map(*p) {
                Ok(q) => positions.push(q),
                Err(reason) => {
                    positions.push(*p);
                    match reason {
                        Outside::Mesh => outside_mesh.push(v),
                        Outside::Layer => outside_layer.push(v),
                    }
                }
            }
        }
        DeformedModel {
            model: Model {
                positions,
                triangles: model.triangles.clone(),
            },
            outside_mesh,
            outside_layer,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prism::psi_exact;
    use api::exact::rational_from_f64;
    use plugins_spline2d::mesh::grid;

    fn q(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    /// Points spread over `[−5, 45]² × [−6, 14]`: some outside the mesh `[0, 40]²` or the layer
    /// `[−7/2, 12]`.
    fn points() -> Vec<[f64; 3]> {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % 1_000_000) as f64 / 1_000_000.0
        };
        (0..2000)
            .map(|_| {
                [
                    next() * 50.0 - 5.0,
                    next() * 50.0 - 5.0,
                    next() * 20.0 - 6.0,
                ]
            })
            .collect()
    }

    #[test]
    fn the_undeformed_map_returns_every_vertex() {
        let spline = Spline::new(grid(2, 20, true), 5, 1).expect("spline");
        let layer = Layer::new(q(-7, 2), q(12, 1)).expect("layer");
        let phi = spline.identity_positions();
        let bottom = spline.constant_positions(layer.bottom());
        let top = spline.constant_positions(layer.top());
        let model = Model {
            positions: points(),
            triangles: vec![[0, 1, 2], [3, 4, 5]],
        };
        for with_phi in [false, true] {
            let surfaces = Surfaces {
                phi: with_phi.then_some(phi.as_slice()),
                bottom: &bottom,
                top: &top,
            };
            let psi = Psi::new(&spline, &layer, surfaces).expect("psi");
            let deformed = psi.deform(&model);
            assert_eq!(deformed.model.triangles, model.triangles);
            assert!(!deformed.outside_mesh.is_empty() && !deformed.outside_layer.is_empty());
            for (v, (p, image)) in model
                .positions
                .iter()
                .zip(&deformed.model.positions)
                .enumerate()
            {
                let inside = (0.0..=40.0).contains(&p[0])
                    && (0.0..=40.0).contains(&p[1])
                    && (-3.5..=12.0).contains(&p[2]);
                assert_eq!(
                    deformed.outside().binary_search(&v).is_err(),
                    inside,
                    "vertex {v} at {p:?}"
                );
                if !inside {
                    assert_eq!(image, p, "outside vertices stay in place");
                    continue;
                }
                for c in 0..3 {
                    assert!(
                        (image[c] - p[c]).abs() <= 1e-13 * (1.0 + p[c].abs()),
                        "{image:?} vs {p:?}"
                    );
                }
                if !with_phi {
                    assert_eq!([image[0], image[1]], [p[0], p[1]], "x and y untouched");
                }
                if v % 50 != 0 {
                    continue;
                }
                // The exact map agrees (checked on a sample: f64 values make long fractions):
                // it is the identity on the exact value of p.
                let exact = p.map(|c| rational_from_f64(c).expect("finite"));
                assert_eq!(
                    psi_exact(&spline, &layer, surfaces, &exact),
                    Some(exact.clone())
                );
            }
        }
    }

    #[test]
    fn bad_values_are_reported_by_surface() {
        let spline = Spline::new(grid(1, 20, false), 5, 1).expect("spline");
        let layer = Layer::new(q(0, 1), q(1, 1)).expect("layer");
        let flat = spline.constant_positions(&q(0, 1));
        let plane = spline.identity_positions();
        let short = &flat[1..];
        let error =
            |phi: Option<&[Vec<Rational>]>, bottom: &[Vec<Rational>], top: &[Vec<Rational>]| {
                Psi::new(&spline, &layer, Surfaces { phi, bottom, top })
                    .expect_err("bad values")
                    .to_string()
            };
        assert!(error(None, short, &flat).starts_with("bottom: expected 36 control point"));
        assert!(error(None, &flat, &plane)
            .starts_with("top needs 1 coordinates per control point, got 2"));
        assert!(error(Some(&flat), &flat, &flat).starts_with("phi needs 2"));
        let psi = Psi::new(
            &spline,
            &layer,
            Surfaces {
                phi: None,
                bottom: &flat,
                top: &flat,
            },
        )
        .expect("psi");
        assert_eq!(psi.map([f64::NAN, 1.0, 0.5]), Err(Outside::Mesh));
        assert_eq!(psi.map([1.0, 1.0, f64::NAN]), Err(Outside::Layer));
        assert_eq!(psi.map([1.0, 1.0, 1.0 + 1e-12]), Ok([1.0, 1.0, 0.0]));
        assert!(psi.jacobian_in(2, [1.0, 1.0, 0.5]).is_none());
        assert!(psi.phi_in(2, [1.0, 0.0, 0.0]).is_none());
    }
}
