//! The 2.5D deformation `ψ` in floating point, for models with millions of vertices
//! (thesis 17.2–17.3).
//!
//! [`Psi`] keeps the point locator of the reference mesh and the three splines as one
//! [`FloatSpline`] whose control values are `(σ0, σ1)` or `(φx, φy, σ0, σ1)`, stored as
//! displacements from the undeformed state (`σ0 = a`, `σ1 = b`, `φ` the identity), so mapping a
//! vertex is one point location and one evaluation, without allocation: locate `(x, y)` in `T`
//! (triangle `u`, barycentric `β`), take `α0 = (b − z)/(b − a)`, `α1 = (z − a)/(b − a)`, and
//! return `(x + Dx, y + Dy, z + α0·D0 + α1·D1)`, where `Dx, Dy, D0, D1` are the displacements
//! `Σ B_i(β)·δ_i` of `φx − x`, `φy − y`, `σ0 − a` and `σ1 − b`. This is `ψ` exactly
//! (`α0·a + α1·b = z`), and in floating point a vertex in a prism whose control values are
//! all unchanged comes back bit-identical (that prism is not even evaluated), while a moved
//! one is off by an amount proportional to its displacement (bound at [`Psi::map`]). Without
//! `φ` (the identity) `x` and `y` are returned unchanged. Vertices outside the prisms keep
//! their position and are listed ([`DeformedModel`]); the topology is kept.
//!
//! [`Psi::jacobian_in`] gives `ψ` and its derivatives on one prism, for normals and for
//! checking smoothness across the walls of neighbouring prisms. The location alone (triangle,
//! `β`, `α`, or why a point is outside) is [`PrismLocator`], which the source's view shares so
//! an editor evaluates `ψ` where the render does.

use crate::prism::{PrismLayer, Surfaces};
use api::exact::rational_to_f64_nearest;
use api::Rational;
use spline2d::eval::{check_positions, EvalError, FloatSpline, Locator, Reference};
use spline2d::mesh::Mesh;
use spline2d::model::Model;
use spline2d::spline::Spline;

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
    PrismLayer,
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

/// Where points lie in the prism layer, in floating point: the location [`Psi::map`] makes
/// before it evaluates, on its own so that an editor's view places a model's vertices exactly
/// where the render deforms them (the terrain source's view uses it), without the splines.
#[derive(Debug, Clone)]
pub struct PrismLocator {
    locator: Locator,
    /// `a` and `b`, the nearest `f64`s.
    bottom: f64,
    top: f64,
}

impl PrismLocator {
    /// The locator of the prisms of `layer` over `mesh`.
    pub fn new(mesh: &Mesh, layer: &PrismLayer) -> PrismLocator {
        PrismLocator {
            locator: Locator::new(mesh),
            bottom: rational_to_f64_nearest(layer.bottom()),
            top: rational_to_f64_nearest(layer.top()),
        }
    }

    /// The prism of `p`: triangle, barycentric coordinates `β` of `(x, y)` (one
    /// [`Locator::locate`]) and vertical coordinates `[α0, α1]` (from `z`, each computed from
    /// `z` itself, not one from the other), or why `p` is outside the prisms: `(x, y)` outside
    /// the mesh, or `z` more than [`LAYER_TOLERANCE`]`·(b − a)` below the bottom or above the
    /// top.
    pub fn locate(&self, p: [f64; 3]) -> Result<(usize, [f64; 3], [f64; 2]), Outside> {
        let (t, beta) = self.locator.locate([p[0], p[1]]).ok_or(Outside::Mesh)?;
        let height = self.top - self.bottom;
        let slack = LAYER_TOLERANCE * height;
        let z = p[2];
        if !(z >= self.bottom - slack && z <= self.top + slack) {
            return Err(Outside::PrismLayer);
        }
        Ok((t, beta, [(self.top - z) / height, self.relative_height(z)]))
    }

    /// The relative height `α1 = (z − a)/(b − a)` of height `z` in the layer, as
    /// [`PrismLocator::locate`] computes it (outside `[0, 1]` for `z` outside the layer).
    pub fn relative_height(&self, z: f64) -> f64 {
        (z - self.bottom) / (self.top - self.bottom)
    }
}

/// `ψ` ready to map points.
#[derive(Debug, Clone)]
pub struct Psi {
    /// The location of points in the prisms, with `a` and `b` in `f64`.
    prisms: PrismLocator,
    /// Values `(σ0, σ1)` or `(φx, φy, σ0, σ1)`, measured from `(a, b)` or `(x, y, a, b)`.
    spline: FloatSpline,
    xy: bool,
    /// Per triangle, its corners.
    corners: Vec<[[f64; 2]; 3]>,
    /// Per triangle, `∂βk/∂x` and `∂βk/∂y`.
    gradients: Vec<[[f64; 2]; 3]>,
}

impl Psi {
    /// Converts the splines of a deformation on `spline`'s mesh to floating point.
    pub fn new(
        spline: &Spline,
        layer: &PrismLayer,
        surfaces: Surfaces<'_>,
    ) -> Result<Psi, DeformError> {
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
        let mut references = if surfaces.phi.is_some() {
            vec![Reference::Identity(0), Reference::Identity(1)]
        } else {
            Vec::new()
        };
        references.push(Reference::Constant(layer.bottom().clone()));
        references.push(Reference::Constant(layer.top().clone()));
        let float =
            FloatSpline::with_references(spline, &combined, &references).map_err(|source| {
                DeformError::Values {
                    surface: "bottom",
                    source,
                }
            })?;
        let vertices: Vec<[f64; 2]> = spline
            .mesh()
            .vertices()
            .iter()
            .map(|p| {
                [
                    rational_to_f64_nearest(&p[0]),
                    rational_to_f64_nearest(&p[1]),
                ]
            })
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
            prisms: PrismLocator::new(spline.mesh(), layer),
            spline: float,
            xy: surfaces.phi.is_some(),
            corners,
            gradients,
        })
    }

    /// Whether `φ` is part of the deformation (otherwise it is the identity).
    pub fn has_phi(&self) -> bool {
        self.xy
    }

    /// The prism of `p`: triangle, barycentric coordinates `β` and vertical coordinates `α`
    /// ([`PrismLocator::locate`]).
    pub fn locate(&self, p: [f64; 3]) -> Result<(usize, [f64; 3], [f64; 2]), Outside> {
        self.prisms.locate(p)
    }

    /// Whether some control value of the prism over triangle `t` differs from the undeformed
    /// state (`φ` the identity, `σ0 = a`, `σ1 = b`); `false` if `t` is not a triangle.
    /// [`Psi::map`] returns the points of the other prisms unchanged.
    pub fn is_displaced(&self, t: usize) -> bool {
        self.spline.is_displaced(t)
    }

    /// `ψ(p)`, or why `p` is outside the prisms, as the identity plus a displacement:
    /// `(x + D̂x, y + D̂y, z + (α̂0·D̂0 + α̂1·D̂1))`.
    ///
    /// # Error bound
    /// A point in a prism whose control values are all unchanged ([`Psi::is_displaced`] is
    /// false) is returned bit-identical. Otherwise, with `u = 2^-53`, `x' y' z'` the exact `ψ`
    /// at the rational value of the `f64` input (exact `a`, `b` and control values), `M_c` the
    /// largest exact displacement `|δ_i|` of coordinate `c` (`φx − x`, `φy − y`, `σ0 − a`,
    /// `σ1 − b`) over the control points of the triangle (of both triangles for a point on or
    /// within rounding of a shared edge or vertex) and `K` the factor stated at
    /// [`FloatSpline`] (`K = (N + d + 5)·u + 9·d·δ_β`, `N = (d+1)(d+2)/2`, `δ_β` the error
    /// of the barycentric coordinates, `≤ 7u·h(2L + 3h)/A`):
    ///
    /// * `|x̂' − x'| ≤ u·|x'| + 1.01·K·Mx`, and likewise for `y`;
    /// * `|ẑ' − z'| ≤ u·|z'| + 1.01·(K + η)·(M0 + M1)` with
    ///   `η = 5u + 2u·(|a| + |b|)/(b − a)` (the error of the float `α0`, `α1`).
    ///
    /// So the error is one rounding of the result plus a small multiple of `u` times the
    /// displacement, not `u` times `|a|`, `|b|` or `|x|`.
    #[inline]
    pub fn map(&self, p: [f64; 3]) -> Result<[f64; 3], Outside> {
        let (t, beta, [a0, a1]) = self.locate(p)?;
        if !self.spline.is_displaced(t) {
            return Ok(p);
        }
        if self.xy {
            let mut d = [0.0; 4];
            self.spline.displacement_into(t, beta, &mut d);
            Ok([p[0] + d[0], p[1] + d[1], p[2] + (a0 * d[2] + a1 * d[3])])
        } else {
            let mut d = [0.0; 2];
            self.spline.displacement_into(t, beta, &mut d);
            Ok([p[0], p[1], p[2] + (a0 * d[0] + a1 * d[1])])
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
    ///
    /// As in [`Psi::map`], `ψ` is the identity plus the displacements, so the Jacobian is
    /// `I` plus their derivatives: `∂x'/∂x = 1 + ∂Dx/∂x`, `∂z'/∂x = α0·∂D0/∂x + α1·∂D1/∂x`,
    /// `∂z'/∂z = 1 + (D1 − D0)/(b − a)`. The value is [`Psi::map`]'s on `t`.
    pub fn jacobian_in(&self, t: usize, p: [f64; 3]) -> Option<([f64; 3], [[f64; 3]; 3])> {
        let beta = self.prisms.locator.barycentric(t, [p[0], p[1]])?;
        let g = self.gradients.get(t)?;
        let (d, partials) = self.spline.displacement_with_derivatives(t, beta)?;
        // Derivative of displacement coordinate `c` along x (axis 0) or y (axis 1).
        let along =
            |c: usize, axis: usize| -> f64 { (0..3).map(|k| partials[k][c] * g[k][axis]).sum() };
        let (bottom, top) = (self.prisms.bottom, self.prisms.top);
        let height = top - bottom;
        let (a0, a1) = ((top - p[2]) / height, (p[2] - bottom) / height);
        let s = if self.xy { 2 } else { 0 };
        let (d0, d1) = (d[s], d[s + 1]);
        let z = p[2] + (a0 * d0 + a1 * d1);
        let dz = [
            a0 * along(s, 0) + a1 * along(s + 1, 0),
            a0 * along(s, 1) + a1 * along(s + 1, 1),
            1.0 + (d1 - d0) / height,
        ];
        if self.xy {
            Some((
                [p[0] + d[0], p[1] + d[1], z],
                [
                    [1.0 + along(0, 0), along(0, 1), 0.0],
                    [along(1, 0), 1.0 + along(1, 1), 0.0],
                    dz,
                ],
            ))
        } else {
            Some(([p[0], p[1], z], [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], dz]))
        }
    }

    /// Maps every vertex of `model` by `ψ`; vertices outside the prisms keep their position and
    /// are listed. Vertices are mapped in parallel (rayon, chunks of consecutive vertices so
    /// neighbours share the locator's cache lines); the result does not depend on the number of
    /// threads (each vertex's image is computed on its own).
    pub fn deform(&self, model: &Model) -> DeformedModel {
        use rayon::prelude::*;
        let mapped: Vec<Result<[f64; 3], Outside>> = model
            .positions
            .par_iter()
            .with_min_len(4096)
            .map(|p| self.map(*p))
            .collect();
        let mut positions = Vec::with_capacity(model.positions.len());
        let mut outside_mesh = Vec::new();
        let mut outside_layer = Vec::new();
        for (v, (p, image)) in model.positions.iter().zip(mapped).enumerate() {
            match image {
                Ok(q) => positions.push(q),
                Err(reason) => {
                    positions.push(*p);
                    match reason {
                        Outside::Mesh => outside_mesh.push(v),
                        Outside::PrismLayer => outside_layer.push(v),
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
pub(crate) mod tests {
    use super::*;
    use crate::prism::psi_exact;
    use api::exact::{rational_from_f64, rational_to_f64};
    use spline2d::eval::{
        barycentric_error_bound, displacement_error_factor, locate_exact, UNIT_ROUNDOFF as U,
    };
    use spline2d::mesh::grid;

    /// What [`check_against_exact`] found.
    #[derive(Debug, Default)]
    pub(crate) struct Checked {
        /// Vertices in prisms with unchanged control values (bit-identical).
        pub unchanged: usize,
        /// Vertices in prisms with changed control values (within the bound).
        pub moved: usize,
        /// Vertices the float map leaves in place (outside the prisms).
        pub outside: usize,
        /// The largest error / bound over the moved vertices and coordinates.
        pub worst: f64,
        /// The largest error in units of `u·(|exact| + M)` (`M` the displacement budget of the
        /// coordinate: `Mx`, `My` or `M0 + M1`), for the record.
        pub relative: f64,
        /// Vertices in changed prisms that the exact `ψ` leaves in place.
        pub exactly_in_place: usize,
        /// Of those, the vertices the float map moves.
        pub moved_in_floats_only: usize,
    }

    /// Maps `points` with the float `ψ` of `surfaces` and checks every vertex inside the
    /// prisms: bit-identical where the prism's control values are those of the undeformed
    /// state (checked exactly), otherwise within the bound stated at [`Psi::map`] of the exact
    /// `ψ` ([`psi_exact`]) at the rational value of the `f64` vertex.
    pub(crate) fn check_against_exact(
        spline: &Spline,
        layer: &PrismLayer,
        surfaces: Surfaces<'_>,
        points: &[[f64; 3]],
    ) -> Checked {
        let psi = Psi::new(spline, layer, surfaces).expect("psi");
        let deformed = psi.deform(&Model {
            positions: points.to_vec(),
            triangles: Vec::new(),
        });
        // Exact displacements per control point: (φx − x, φy − y, σ0 − a, σ1 − b).
        let displacements: Vec<[Rational; 4]> = spline
            .nominals()
            .iter()
            .enumerate()
            .map(|(i, nominal)| {
                let (dx, dy) = match surfaces.phi {
                    Some(phi) => (&phi[i][0] - &nominal[0], &phi[i][1] - &nominal[1]),
                    None => (
                        Rational::from_integer(0.into()),
                        Rational::from_integer(0.into()),
                    ),
                };
                [
                    dx,
                    dy,
                    &surfaces.bottom[i][0] - layer.bottom(),
                    &surfaces.top[i][0] - layer.top(),
                ]
            })
            .collect();
        let zero = Rational::from_integer(0.into());
        let unchanged = |t: usize| {
            spline
                .triangle_points(t)
                .iter()
                .all(|&i| displacements[i].iter().all(|d| *d == zero))
        };
        let corners = |t: usize| {
            spline.mesh().triangles()[t].map(|v| {
                let p = &spline.mesh().vertices()[v];
                [rational_to_f64(&p[0]), rational_to_f64(&p[1])]
            })
        };
        let (a, b) = (
            rational_to_f64(layer.bottom()),
            rational_to_f64(layer.top()),
        );
        let eta = 5.0 * U + 2.0 * U * (a.abs() + b.abs()) / (b - a);
        let d = spline.degree();
        let mut checked = Checked::default();
        for (p, image) in points.iter().zip(&deformed.model.positions) {
            let Ok((t, _, _)) = psi.locate(*p) else {
                assert_eq!(image.map(f64::to_bits), p.map(f64::to_bits));
                checked.outside += 1;
                continue;
            };
            assert_eq!(psi.is_displaced(t), !unchanged(t), "triangle {t}");
            if unchanged(t) {
                assert_eq!(image.map(f64::to_bits), p.map(f64::to_bits), "{p:?}");
                checked.unchanged += 1;
                continue;
            }
            let exact_p = p.map(|c| rational_from_f64(c).expect("finite"));
            let (Some(exact), Some((te, _))) = (
                psi_exact(spline, layer, surfaces, &exact_p),
                locate_exact(spline.mesh(), &[exact_p[0].clone(), exact_p[1].clone()]),
            ) else {
                // Inside only by the float tolerance; not a vertex of the tests.
                panic!("{p:?} is inside the prisms in floats but not exactly");
            };
            checked.moved += 1;
            if exact == exact_p {
                checked.exactly_in_place += 1;
                if image != p {
                    checked.moved_in_floats_only += 1;
                }
            }
            let (mut m, mut delta) = ([0.0f64; 4], 0.0f64);
            for s in [t, te] {
                for &i in spline.triangle_points(s) {
                    for (mc, dc) in m.iter_mut().zip(&displacements[i]) {
                        *mc = mc.max(rational_to_f64(dc).abs());
                    }
                }
                delta = delta.max(barycentric_error_bound(corners(s), [p[0], p[1]]));
            }
            let k = displacement_error_factor(d, delta);
            let budgets = [k * m[0], k * m[1], (k + eta) * (m[2] + m[3])];
            for c in 0..3 {
                let error = rational_from_f64(image[c]).expect("finite") - &exact[c];
                let error = rational_to_f64(&error).abs();
                let bound =
                    (U * rational_to_f64(&exact[c]).abs() + 1.01 * budgets[c]) * (1.0 + 1e-9);
                assert!(
                    error <= bound,
                    "{p:?} coordinate {c}: error {error:e} > bound {bound:e}"
                );
                checked.worst = checked.worst.max(error / bound);
                let scale = rational_to_f64(&exact[c]).abs() + [m[0], m[1], m[2] + m[3]][c];
                checked.relative = checked.relative.max(error / (U * scale));
            }
        }
        checked
    }

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
        let layer = PrismLayer::new(q(-7, 2), q(12, 1)).expect("layer");
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
                // Identity plus zero displacements: bit for bit.
                assert_eq!(image.map(f64::to_bits), p.map(f64::to_bits), "{p:?}");
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

    /// A layer and a mesh whose numbers are not `f64`s (a = −1/10, b = 123/7, nominal positions
    /// with denominator 5): the undeformed map still returns every vertex bit-identical.
    #[test]
    fn awkward_layers_leave_undeformed_vertices_bit_identical() {
        let spline = Spline::new(grid(2, 20, true), 5, 1).expect("spline");
        let layer = PrismLayer::new(q(-1, 10), q(123, 7)).expect("layer");
        let phi = spline.identity_positions();
        let bottom = spline.constant_positions(layer.bottom());
        let top = spline.constant_positions(layer.top());
        let mut points = points();
        for x in [0.1, 4.531, 1e-7, 39.999999999999, 1.0 / 3.0] {
            for z in [-0.1, 4.531, 17.571428571428573, 0.0, 1e-300, 12.345678] {
                points.push([x, 40.0 - x, z]);
            }
        }
        for with_phi in [false, true] {
            let surfaces = Surfaces {
                phi: with_phi.then_some(phi.as_slice()),
                bottom: &bottom,
                top: &top,
            };
            let checked = check_against_exact(&spline, &layer, surfaces, &points);
            assert_eq!(checked.moved, 0);
            assert!(checked.unchanged > 900, "{checked:?}");
        }
    }

    /// Control values moved near the corner (0, 0) by awkward amounts, in all four
    /// coordinates: vertices over unchanged prisms come back bit-identical, the others agree
    /// with the exact `ψ` within the bound of [`Psi::map`]; the Jacobian is that of the
    /// identity plus the displacements.
    #[test]
    fn local_edits_move_only_their_prisms_within_the_bound() {
        let spline = Spline::new(grid(2, 20, true), 5, 1).expect("spline");
        let layer = PrismLayer::new(q(-7, 2), q(12, 1)).expect("layer");
        let near = |i: usize| {
            let [x, y] = spline.nominal(i);
            x + y < q(20, 1)
        };
        let shift = |i: usize, salt: i64, d: i64| q(((i as i64) * salt % 17) - 8, d);
        let phi: Vec<Vec<Rational>> = spline
            .nominals()
            .iter()
            .enumerate()
            .map(|(i, p)| {
                if near(i) {
                    vec![&p[0] + shift(i, 7, 9), &p[1] + shift(i, 5, 13)]
                } else {
                    p.to_vec()
                }
            })
            .collect();
        let surface = |level: &Rational, salt: i64| -> Vec<Vec<Rational>> {
            (0..spline.points().len())
                .map(|i| {
                    if near(i) {
                        vec![level + shift(i, salt, 3)]
                    } else {
                        vec![level.clone()]
                    }
                })
                .collect()
        };
        let bottom = surface(layer.bottom(), 3);
        let top = surface(layer.top(), 11);
        let mut points = points();
        for x in [0.1, 4.531, 1e-7, 24.5, 1.0 / 3.0, 20.0] {
            for z in [-3.5, 4.531, 12.0, 0.0, 1e-300] {
                points.push([x, x, z]);
                points.push([x, 40.0 - x, z]);
            }
        }
        for with_phi in [false, true] {
            let surfaces = Surfaces {
                phi: with_phi.then_some(phi.as_slice()),
                bottom: &bottom,
                top: &top,
            };
            let checked = check_against_exact(&spline, &layer, surfaces, &points);
            assert!(
                checked.unchanged > 200 && checked.moved > 200,
                "{checked:?}"
            );
            eprintln!("with φ: {with_phi}: {checked:?}");
            // Jacobian: central differences of the map inside a moved prism.
            let psi = Psi::new(&spline, &layer, surfaces).expect("psi");
            let at = [3.0, 4.0, 1.5];
            let (t, _, _) = psi.locate(at).expect("inside");
            assert!(psi.is_displaced(t));
            let (value, j) = psi.jacobian_in(t, at).expect("triangle");
            assert_eq!(Ok(value), psi.map(at));
            let step = 1e-5;
            for axis in 0..3 {
                let (mut plus, mut minus) = (at, at);
                plus[axis] += step;
                minus[axis] -= step;
                let (f, g) = (psi.map(plus).expect("in"), psi.map(minus).expect("in"));
                for r in 0..3 {
                    let numeric = (f[r] - g[r]) / (2.0 * step);
                    assert!(
                        (numeric - j[r][axis]).abs() < 1e-6 * (1.0 + numeric.abs()),
                        "∂{r}/∂{axis}: {numeric} vs {}",
                        j[r][axis]
                    );
                }
            }
            // Far away the Jacobian is the identity's.
            let far = [35.0, 36.0, 2.0];
            let (t, _, _) = psi.locate(far).expect("inside");
            assert!(!psi.is_displaced(t));
            let (value, j) = psi.jacobian_in(t, far).expect("triangle");
            assert_eq!(value, far);
            assert_eq!(j, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        }
    }

    #[test]
    fn bad_values_are_reported_by_surface() {
        let spline = Spline::new(grid(1, 20, false), 5, 1).expect("spline");
        let layer = PrismLayer::new(q(0, 1), q(1, 1)).expect("layer");
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
        assert_eq!(psi.map([1.0, 1.0, f64::NAN]), Err(Outside::PrismLayer));
        // Just above the top (within the tolerance): both surfaces are flattened to 0, a
        // displacement of −1 for the top, so z' is 0 up to a few units of 2^-53 (the bound of
        // `Psi::map` with M1 = 1).
        let [x, y, z] = psi.map([1.0, 1.0, 1.0 + 1e-12]).expect("inside");
        assert_eq!([x, y], [1.0, 1.0]);
        assert!(z.abs() <= 1e-15, "{z}");
        assert!(psi.jacobian_in(2, [1.0, 1.0, 0.5]).is_none());
        assert!(psi.phi_in(2, [1.0, 0.0, 0.0]).is_none());
    }
}
