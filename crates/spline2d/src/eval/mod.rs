//! Evaluating a spline `φ` at points of the reference mesh, exactly and in floating point.
//!
//! On triangle `t` with barycentric coordinates `β = (β0, β1, β2)` of `p`,
//! `φ(p) = Σ_{i+j+k=d} d!/(i! j! k!) β0^i β1^j β2^k q_{ijk}`, where `q_{ijk}` is the current
//! position of the control point with multi-index `(i, j, k)` in `t`
//! ([`Spline::triangle_points`], [`Spline::local_index`]). Positions are given per control
//! point id as `&[Vec<Rational>]`, every entry with the same number `k ≥ 1` of coordinates
//! (`k = 2` for a deformation of the plane, `k = 1` for a scalar spline such as a height).
//!
//! * Exact path ([`barycentric`], [`locate_exact`], [`evaluate_exact`]): rationals throughout;
//!   the oracle for tests and for small numbers of points. Locating is a linear scan.
//! * Float path ([`Locator`], [`FloatSpline`]): for drawing and for deforming models with up
//!   to millions of vertices. The locator buckets triangles in a uniform grid and keeps each
//!   triangle's corners in `f64`; the float spline keeps every triangle's displacements from a
//!   reference (the identity for a deformation of the plane), pre-multiplied by their
//!   multinomial coefficients and rounded once, contiguously, so evaluating a point allocates
//!   nothing ([`FloatSpline::evaluate_point_into`]) and a point where nothing moved comes back
//!   bit-identical.
//!
//! Each path has its own file (`exact.rs`, `locate.rs`, `float.rs` with `float/evaluate.rs`);
//! their items are re-exported here.

mod exact;
mod float;
mod locate;

pub use exact::{barycentric, evaluate_exact, evaluate_in_triangle, locate_exact};
pub use float::{
    barycentric_error_bound, displacement_error_factor, FloatSpline, Reference, UNIT_ROUNDOFF,
};
pub use locate::{Locator, LOCATE_TOLERANCE};

use crate::mesh::Mesh;
use crate::spline::Spline;
use api::exact::rational_to_f64_nearest;
use api::Rational;

/// Why positions cannot be used with a spline.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum EvalError {
    /// The number of positions differs from the number of control points.
    #[error("expected {expected} control point positions (one per control point), got {found}")]
    PositionCount {
        /// Control points of the spline.
        expected: usize,
        /// Positions given.
        found: usize,
    },
    /// Positions have no coordinates.
    #[error("control point positions need at least one coordinate")]
    ZeroDimension,
    /// [`FloatSpline::with_references`] needs one reference per coordinate.
    #[error("expected one reference per coordinate ({expected}), got {found}")]
    ReferenceCount {
        /// Coordinates of the positions.
        expected: usize,
        /// References given.
        found: usize,
    },
    /// An identity reference names an axis the plane does not have.
    #[error(
        "reference of coordinate {coordinate}: the identity has axes 0 (x) and 1 (y), not {axis}"
    )]
    IdentityAxis {
        /// The coordinate.
        coordinate: usize,
        /// The axis given.
        axis: usize,
    },
    /// A position has a different number of coordinates than the first one.
    #[error("control point {point} has {found} coordinates, the first one has {expected}")]
    Dimension {
        /// The control point.
        point: usize,
        /// Coordinates of control point 0.
        expected: usize,
        /// Coordinates of this control point.
        found: usize,
    },
}

/// Checks that `positions` has one entry per control point of `spline`, all with the same
/// number `k ≥ 1` of coordinates, and returns `k`.
pub fn check_positions(spline: &Spline, positions: &[Vec<Rational>]) -> Result<usize, EvalError> {
    let expected = spline.points().len();
    if positions.len() != expected {
        return Err(EvalError::PositionCount {
            expected,
            found: positions.len(),
        });
    }
    let dim = positions.first().map_or(0, Vec::len);
    if dim == 0 {
        return Err(EvalError::ZeroDimension);
    }
    match positions.iter().position(|p| p.len() != dim) {
        Some(point) => Err(EvalError::Dimension {
            point,
            expected: dim,
            found: positions[point].len(),
        }),
        None => Ok(dim),
    }
}

/// The vertices of `mesh` rounded to the nearest `f64`: the corners the float path (the
/// locator's triangles, the identity reference of a float spline) computes with.
fn float_vertices(mesh: &Mesh) -> Vec<[f64; 2]> {
    mesh.vertices()
        .iter()
        .map(|p| {
            [
                rational_to_f64_nearest(&p[0]),
                rational_to_f64_nearest(&p[1]),
            ]
        })
        .collect()
}

#[cfg(test)]
mod test_support {
    //! What the evaluation tests share: exact fractions, nominal positions, random points.
    use crate::mesh::{Mesh, Point};
    use crate::spline::tests::q;
    use crate::spline::Spline;
    use api::Rational;

    pub(super) fn frac(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    pub(super) fn nominal(spline: &Spline) -> Vec<Vec<Rational>> {
        spline.nominals().iter().map(|p| p.to_vec()).collect()
    }

    /// A small deterministic generator (xorshift) for sample points.
    pub(super) struct Rng(pub(super) u64);
    impl Rng {
        pub(super) fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }
        pub(super) fn below(&mut self, n: i64) -> i64 {
            (self.next() % n as u64) as i64
        }
    }

    /// A random point of triangle `t` with rational barycentric coordinates.
    pub(super) fn random_point(mesh: &Mesh, t: usize, rng: &mut Rng) -> Point {
        let (a, b) = (rng.below(1000), rng.below(1000));
        let (a, b) = if a + b > 1000 {
            (1000 - a, 1000 - b)
        } else {
            (a, b)
        };
        let beta = [frac(1000 - a - b, 1000), frac(a, 1000), frac(b, 1000)];
        let tri = mesh.triangles()[t];
        let mut p = [q(0), q(0)];
        for (v, w) in tri.iter().zip(&beta) {
            p[0] += &mesh.vertices()[*v][0] * w;
            p[1] += &mesh.vertices()[*v][1] * w;
        }
        p
    }
}
