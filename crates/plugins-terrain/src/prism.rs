//! The prism mesh `P` (thesis 17.2): one layer of triangular prisms over the reference mesh
//! `T`, with flat bottom `z = a` and top `z = b`, and the exact coordinates of a point in it.
//!
//! A point `p = (x, y, z)` of the prism over triangle `u` has the barycentric coordinates
//! `β0, β1, β2` of `(x, y)` in `u` and the vertical coordinates (17.2.1)
//! `α0 = (b − z)/(b − a)`, `α1 = (z − a)/(b − a)`, so that `α0 + α1 = 1`,
//! `Σ βk·vk = (x, y)` and `α0·a + α1·b = z` ([`PrismCoordinates::point`]). The 2.5D
//! deformation (17.1) is `ψ(p) = (φ(x, y), α0·σ0(x, y) + α1·σ1(x, y))` ([`psi_exact`]); the fast
//! float version for models is [`crate::deform::Psi`].

use api::Rational;
use num_traits::Zero;
use spline2d::eval::{evaluate_in_triangle, locate_exact};
use spline2d::mesh::Mesh;
use spline2d::spline::Spline;

/// Why a layer cannot be built.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LayerError {
    /// The bottom is not below the top.
    #[error("the bottom a = {bottom} must be below the top b = {top}")]
    Empty {
        /// `a`, as `p` or `p/q`.
        bottom: String,
        /// `b`, as `p` or `p/q`.
        top: String,
    },
}

/// The vertical extent `[a, b]` of the prisms, exact, `a < b`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PrismLayer {
    bottom: Rational,
    top: Rational,
}

impl PrismLayer {
    /// The layer between `bottom` (`a`) and `top` (`b`).
    pub fn new(bottom: Rational, top: Rational) -> Result<PrismLayer, LayerError> {
        if bottom >= top {
            return Err(LayerError::Empty {
                bottom: api::format_rational(&bottom),
                top: api::format_rational(&top),
            });
        }
        Ok(PrismLayer { bottom, top })
    }

    /// `a`.
    pub fn bottom(&self) -> &Rational {
        &self.bottom
    }

    /// `b`.
    pub fn top(&self) -> &Rational {
        &self.top
    }

    /// The vertical coordinates `[α0, α1] = [(b − z)/(b − a), (z − a)/(b − a)]` of height `z`
    /// (17.2.1); both in `[0, 1]` exactly when `a ≤ z ≤ b`.
    pub fn vertical(&self, z: &Rational) -> [Rational; 2] {
        let height = &self.top - &self.bottom;
        [(&self.top - z) / &height, (z - &self.bottom) / &height]
    }

    /// True when `a ≤ z ≤ b`.
    pub fn contains(&self, z: &Rational) -> bool {
        *z >= self.bottom && *z <= self.top
    }
}

/// Where a point lies in the prism mesh, exactly.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PrismCoordinates {
    /// The triangle of `T` under the point (the lowest-numbered one on shared edges).
    pub triangle: usize,
    /// Barycentric coordinates of `(x, y)` in the triangle.
    pub beta: [Rational; 3],
    /// Vertical coordinates `[α0, α1]`.
    pub alpha: [Rational; 2],
}

impl PrismCoordinates {
    /// The point these coordinates describe: `(Σ βk·vk, α0·a + α1·b)`.
    pub fn point(&self, mesh: &Mesh, layer: &PrismLayer) -> [Rational; 3] {
        let tri = mesh.triangles()[self.triangle];
        let mut xy = [Rational::zero(), Rational::zero()];
        for (v, b) in tri.iter().zip(&self.beta) {
            for (c, coordinate) in xy.iter_mut().enumerate() {
                *coordinate += b * &mesh.vertices()[*v][c];
            }
        }
        let [x, y] = xy;
        let z = &self.alpha[0] * layer.bottom() + &self.alpha[1] * layer.top();
        [x, y, z]
    }
}

/// The prism containing `p` and `p`'s coordinates in it, exactly; `None` when `(x, y)` is
/// outside `T` or `z` outside `[a, b]`. A linear scan over the triangles: for exact checks.
pub fn locate_in_prisms(
    mesh: &Mesh,
    layer: &PrismLayer,
    p: &[Rational; 3],
) -> Option<PrismCoordinates> {
    if !layer.contains(&p[2]) {
        return None;
    }
    let (triangle, beta) = locate_exact(mesh, &[p[0].clone(), p[1].clone()])?;
    Some(PrismCoordinates {
        triangle,
        beta,
        alpha: layer.vertical(&p[2]),
    })
}

/// Control values of the three splines of a 2.5D deformation, per control point of one
/// [`Spline`].
#[derive(Debug, Clone, Copy)]
pub struct Surfaces<'a> {
    /// `φ` (two coordinates per point), or `None` for the identity.
    pub phi: Option<&'a [Vec<Rational>]>,
    /// `σ0`, the bottom surface (one coordinate per point).
    pub bottom: &'a [Vec<Rational>],
    /// `σ1`, the top surface (one coordinate per point).
    pub top: &'a [Vec<Rational>],
}

/// `ψ(p)` exactly (thesis 17.1); `None` when `p` is outside the prisms or the control values do
/// not fit the spline. With `φ` the identity and `σ0 = a`, `σ1 = b` it returns `p`.
pub fn psi_exact(
    spline: &Spline,
    layer: &PrismLayer,
    surfaces: Surfaces<'_>,
    p: &[Rational; 3],
) -> Option<[Rational; 3]> {
    let at = locate_in_prisms(spline.mesh(), layer, p)?;
    let evaluate =
        |values: &[Vec<Rational>]| evaluate_in_triangle(spline, values, at.triangle, &at.beta);
    let s0 = evaluate(surfaces.bottom)?;
    let s1 = evaluate(surfaces.top)?;
    let (x, y) = match surfaces.phi {
        Some(phi) => {
            let xy = evaluate(phi)?;
            (xy.first()?.clone(), xy.get(1)?.clone())
        }
        None => (p[0].clone(), p[1].clone()),
    };
    let z = &at.alpha[0] * s0.first()? + &at.alpha[1] * s1.first()?;
    Some([x, y, z])
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use spline2d::mesh::grid;

    fn q(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    #[test]
    fn layers_are_ordered_and_alphas_sum_to_one() {
        assert!(PrismLayer::new(q(1, 1), q(1, 1)).is_err());
        let error = PrismLayer::new(q(3, 1), q(-1, 2)).expect_err("upside down");
        assert_eq!(
            error.to_string(),
            "the bottom a = 3 must be below the top b = -1/2"
        );
        let layer = PrismLayer::new(q(-20, 1), q(20, 1)).expect("layer");
        assert_eq!(layer.vertical(&q(-20, 1)), [q(1, 1), q(0, 1)]);
        assert_eq!(layer.vertical(&q(20, 1)), [q(0, 1), q(1, 1)]);
        assert_eq!(layer.vertical(&q(10, 1)), [q(1, 4), q(3, 4)]);
        assert!(!layer.contains(&q(41, 2)));
    }

    #[test]
    fn the_undeformed_map_is_the_identity_exactly() {
        let spline = Spline::new(grid(2, 20, true), 5, 1).expect("spline");
        let layer = PrismLayer::new(q(-7, 2), q(12, 1)).expect("layer");
        let phi = spline.identity_positions();
        let bottom = spline.constant_positions(layer.bottom());
        let top = spline.constant_positions(layer.top());
        for with_phi in [false, true] {
            let surfaces = Surfaces {
                phi: with_phi.then_some(phi.as_slice()),
                bottom: &bottom,
                top: &top,
            };
            for p in [
                [q(1, 3), q(5, 7), q(0, 1)],
                [q(40, 1), q(40, 1), q(12, 1)],
                [q(20, 1), q(7, 1), q(-7, 2)],
                [q(399, 10), q(1, 10), q(-1, 9)],
            ] {
                assert_eq!(psi_exact(&spline, &layer, surfaces, &p), Some(p.clone()));
            }
            assert!(psi_exact(&spline, &layer, surfaces, &[q(1, 1), q(1, 1), q(13, 1)]).is_none());
            assert!(psi_exact(&spline, &layer, surfaces, &[q(-1, 1), q(1, 1), q(0, 1)]).is_none());
        }
    }

    proptest! {
        /// Barycentric and vertical coordinates reproduce the point they were computed from,
        /// exactly, and each set sums to one.
        #[test]
        fn coordinates_reproduce_the_point(
            x in 0i64..=4000, y in 0i64..=4000, z in -500i64..=700,
            a in -50i64..=-1, b in 1i64..=70,
        ) {
            let mesh = grid(2, 20, true);
            let layer = PrismLayer::new(q(a, 1), q(b, 1)).expect("a < b");
            let p = [q(x, 100), q(y, 100), q(z, 10)];
            match locate_in_prisms(&mesh, &layer, &p) {
                Some(at) => {
                    prop_assert_eq!(at.point(&mesh, &layer), p.clone());
                    prop_assert_eq!(at.beta.iter().sum::<Rational>(), q(1, 1));
                    prop_assert_eq!(&at.alpha[0] + &at.alpha[1], q(1, 1));
                    prop_assert!(at.alpha.iter().chain(&at.beta).all(|c| *c >= q(0, 1)));
                }
                // The perturbed grid covers [0, 40]², so only z can be outside.
                None => prop_assert!(!layer.contains(&p[2])),
            }
        }
    }
}
