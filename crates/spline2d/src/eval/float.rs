//! The float spline: a spline's control values in `f64`, laid out per triangle as a reference
//! function plus pre-multiplied displacements (see [`FloatSpline`]) and built from exact
//! positions; evaluating it is in `float/evaluate.rs`.

mod evaluate;

use super::{check_positions, float_vertices, EvalError};
use crate::spline::{multinomials, Spline};
use api::exact::rational_to_f64_nearest;
use api::{Integer, Rational};

/// `w·(q − r)` (`w·q` without `r`) rounded to the nearest `f64`. The fraction is not reduced:
/// the rounding does not need it, and the greatest common divisors would dominate the cost of
/// converting a spline.
fn scaled_difference(q: &Rational, r: Option<&Rational>, w: &Integer) -> f64 {
    let (numerator, denominator) = match r {
        None => (q.numer() * w, q.denom().clone()),
        Some(r) if r.denom() == q.denom() => ((q.numer() - r.numer()) * w, q.denom().clone()),
        Some(r) => (
            (q.numer() * r.denom() - r.numer() * q.denom()) * w,
            q.denom() * r.denom(),
        ),
    };
    // Denominators of reduced rationals are positive, and so is their product.
    rational_to_f64_nearest(&Rational::new_raw(numerator, denominator))
}

/// What one coordinate of a [`FloatSpline`]'s values is measured from: a function `r` whose
/// Bernstein coefficients `r_i` are known exactly. The spline is stored as `r` plus the
/// displacement `Σ B_i(β)·(q_i − r_i)`, so where every `q_i = r_i` the float value is `r`
/// itself and elsewhere the rounding error scales with the displacement, not with `r`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Reference {
    /// The zero function: the control values are stored as they are.
    Zero,
    /// Coordinate `axis` (0 for `x`, 1 for `y`) of the identity map of the plane; its
    /// coefficient at a control point is that coordinate of the point's nominal position
    /// ([`crate::spline::ControlPoint::nominal`]).
    Identity(usize),
    /// A constant function (every coefficient equal to it): a flat surface such as `z = a`.
    Constant(Rational),
}

/// A [`Reference`] in `f64`.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Base {
    Zero,
    Identity(usize),
    Constant(f64),
}

/// A spline with its control points in `f64`, laid out per triangle for fast evaluation, as a
/// reference function plus a displacement.
///
/// Every coordinate `c` of the values has a [`Reference`] `r_c` (the identity for a
/// deformation of the plane, a constant for a surface, or zero). For each control point `i`
/// the exact displacement `δ_i = q_i − r_i`, multiplied by the point's multinomial coefficient
/// `w_i = d!/(i! j! k!)`, is rounded to the nearest `f64` once
/// ([`api::exact::rational_to_f64_nearest`]); triangle `t`'s values are stored contiguously in
/// [`multi_indices`](crate::spline::multi_indices) order. Then `φ_c = r_c + D_c` with
/// `D_c(β) = Σ β0^i β1^j β2^k · stored_{ijk}`, and the identity reference is evaluated at the
/// point itself ([`FloatSpline::evaluate_point_into`]) or as `Σ βk·vk`
/// ([`FloatSpline::evaluate_into`]). A triangle whose displacements are all zero is marked
/// ([`FloatSpline::is_displaced`]) and not evaluated: a point there comes back bit-identical.
///
/// # Error bound
/// Let `u = 2^-53`, `N = (d+1)(d+2)/2` and, for a point `p` in triangle `t` (or within the
/// locator's tolerance of it), `M_c` the largest `|δ_i|` of coordinate `c` over the control
/// points of `t` (for a point on or within rounding of an edge or vertex shared with another
/// triangle, of both triangles). If the float barycentric coordinates are off by at most `δ_β`
/// each, the computed displacement satisfies
///
/// `|D̂_c − D_c(p)| ≤ K·M_c` with `K = (N + d + 5)·u + 9·d·δ_β` ([`displacement_error_factor`]),
///
/// and the value at the point, `x̂' = fl(x + D̂_x)` for an identity reference, satisfies
/// `|x̂' − x'| ≤ u·|x'| + 1.01·K·M_x`, where `x' = x + D_x(p)` is the exact value at the
/// rational value of the `f64` input. For the barycentric coordinates of
/// [`Locator`](super::Locator) (corners rounded to nearest, `p` inside `t`),
/// `δ_β ≤ 7u·h(2L + 3h)/A` ([`barycentric_error_bound`]), with `h` the longest edge of
/// `t`, `A` twice its area and `L` the largest magnitude of a coordinate of `p` or of `t`'s
/// corners: for well-shaped triangles whose size is that of the coordinates, `K` is a few
/// hundred `u` at degree 5. In particular `M_c = 0` gives the reference value exactly.
#[derive(Debug, Clone, PartialEq)]
pub struct FloatSpline {
    degree: usize,
    dim: usize,
    /// `(d+1)(d+2)/2 · dim` values per triangle.
    stride: usize,
    /// Per triangle, the rounded `w_i·δ_i`.
    coefficients: Vec<f64>,
    /// Per triangle: some displacement is nonzero.
    displaced: Vec<bool>,
    references: Vec<Reference>,
    bases: Vec<Base>,
    /// Per triangle, its corners (rounded to nearest), when some reference is the identity;
    /// empty otherwise.
    corners: Vec<[[f64; 2]; 3]>,
}

/// The unit roundoff `u = 2^-53` of `f64` arithmetic, the unit of [`FloatSpline`]'s error
/// bound.
pub const UNIT_ROUNDOFF: f64 = 1.0 / 9_007_199_254_740_992.0;

/// `δ_β` of [`FloatSpline`]'s error bound: how far the float barycentric coordinates of the
/// [`Locator`](super::Locator) may be off for `p` in the triangle with these corners (rounded
/// to nearest), `7u·h(2L + 3h)/A` with `h` the longest edge, `A` twice the area and `L` the
/// largest magnitude of a coordinate of `p` or of a corner.
pub fn barycentric_error_bound(corners: [[f64; 2]; 3], p: [f64; 2]) -> f64 {
    let [a, b, c] = corners;
    let length = |u: [f64; 2], v: [f64; 2]| (u[0] - v[0]).hypot(u[1] - v[1]);
    let h = length(a, b).max(length(b, c)).max(length(c, a));
    let area = ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs();
    let l = corners
        .iter()
        .chain(std::iter::once(&p))
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    7.0 * UNIT_ROUNDOFF * h * (2.0 * l + 3.0 * h) / area
}

/// `K = (N + d + 5)·u + 9·d·δ_β` of [`FloatSpline`]'s error bound for degree `d`
/// (`N = (d+1)(d+2)/2`) and barycentric error `delta` ([`barycentric_error_bound`]): the
/// computed displacement is within `K·M_c` of the exact one.
pub fn displacement_error_factor(degree: usize, delta: f64) -> f64 {
    let n = (degree + 1) * (degree + 2) / 2;
    (n + degree + 5) as f64 * UNIT_ROUNDOFF + 9.0 * degree as f64 * delta
}

impl FloatSpline {
    /// Converts a spline with control points at `positions` (one per control point, all with
    /// the same number of coordinates; see [`check_positions`]). Values with two coordinates
    /// are a deformation of the plane and are measured from the identity
    /// (`[Reference::Identity(0), Reference::Identity(1)]`), so the nominal positions give the
    /// identity exactly; other values are measured from zero. See
    /// [`FloatSpline::with_references`] to choose.
    pub fn new(spline: &Spline, positions: &[Vec<Rational>]) -> Result<Self, EvalError> {
        let dim = check_positions(spline, positions)?;
        let references = if dim == 2 {
            vec![Reference::Identity(0), Reference::Identity(1)]
        } else {
            vec![Reference::Zero; dim]
        };
        Self::with_references(spline, positions, &references)
    }

    /// Converts a spline with control points at `positions`, coordinate `c` measured from
    /// `references[c]` (one reference per coordinate; identity axes 0 or 1).
    pub fn with_references(
        spline: &Spline,
        positions: &[Vec<Rational>],
        references: &[Reference],
    ) -> Result<Self, EvalError> {
        let dim = check_positions(spline, positions)?;
        if references.len() != dim {
            return Err(EvalError::ReferenceCount {
                expected: dim,
                found: references.len(),
            });
        }
        if let Some((coordinate, axis)) =
            references
                .iter()
                .enumerate()
                .find_map(|(coordinate, r)| match r {
                    Reference::Identity(axis) if *axis > 1 => Some((coordinate, *axis)),
                    _ => None,
                })
        {
            return Err(EvalError::IdentityAxis { coordinate, axis });
        }
        let d = spline.degree();
        let weights = multinomials(d);
        let stride = weights.len() * dim;
        let triangles = spline.mesh().triangles().len();
        // `w·δ` of a control point, rounded once.
        let displacement = |point: usize, w: &Integer| -> Vec<f64> {
            let nominal = spline.nominal(point);
            positions[point]
                .iter()
                .zip(references)
                .map(|(q, r)| {
                    let r = match r {
                        Reference::Zero => None,
                        Reference::Identity(axis) => Some(&nominal[*axis]),
                        Reference::Constant(c) => Some(c),
                    };
                    scaled_difference(q, r, w)
                })
                .collect()
        };
        // A control point has the same multinomial in every triangle containing it (they are
        // symmetric in the multi-index), so each is converted once; the weight's local index
        // is kept to check.
        let mut converted: Vec<Option<(usize, Vec<f64>)>> = vec![None; positions.len()];
        let mut coefficients = Vec::with_capacity(stride * triangles);
        let mut displaced = Vec::with_capacity(triangles);
        for t in 0..triangles {
            let mut moved = false;
            for (l, &point) in spline.triangle_points(t).iter().enumerate() {
                let stale = match &converted[point] {
                    Some((k, _)) => weights[*k] != weights[l],
                    None => true,
                };
                if stale {
                    converted[point] = Some((l, displacement(point, &weights[l])));
                }
                if let Some((_, values)) = &converted[point] {
                    moved |= values.iter().any(|x| *x != 0.0);
                    coefficients.extend_from_slice(values);
                }
            }
            displaced.push(moved);
        }
        let bases: Vec<Base> = references
            .iter()
            .map(|r| match r {
                Reference::Zero => Base::Zero,
                Reference::Identity(axis) => Base::Identity(*axis),
                Reference::Constant(c) => Base::Constant(rational_to_f64_nearest(c)),
            })
            .collect();
        let corners = if bases.iter().any(|b| matches!(b, Base::Identity(_))) {
            let vertices = float_vertices(spline.mesh());
            spline
                .mesh()
                .triangles()
                .iter()
                .map(|tri| tri.map(|v| vertices[v]))
                .collect()
        } else {
            Vec::new()
        };
        Ok(FloatSpline {
            degree: d,
            dim,
            stride,
            coefficients,
            displaced,
            references: references.to_vec(),
            bases,
            corners,
        })
    }

    /// The degree `d`.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// Coordinates of a value (`k`).
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.displaced.len()
    }

    /// What each coordinate is measured from.
    pub fn references(&self) -> &[Reference] {
        &self.references
    }

    /// Whether some control value of triangle `t` differs from its reference (as rounded to
    /// `f64`); `false` if `t` is not a triangle. Where it is `false` the spline is its
    /// reference on `t` and [`FloatSpline::evaluate_point_into`] returns the reference value
    /// exactly.
    pub fn is_displaced(&self, t: usize) -> bool {
        self.displaced.get(t).copied().unwrap_or(false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::test_support::*;
    use crate::eval::{check_positions, evaluate_exact, Locator};
    use crate::spline::tests::{grid, q, star, strip};
    use api::exact::rational_to_f64;

    #[test]
    fn identity_reproduces_points_exactly_and_in_floats() {
        for (mesh, d) in [(grid(3, true), 5), (star(7), 3), (strip(4), 2)] {
            let spline = Spline::new(mesh, d, 1).expect("spline");
            let positions = nominal(&spline);
            let float = FloatSpline::new(&spline, &positions).expect("float");
            let locator = Locator::new(spline.mesh());
            let mut rng = Rng(0x9e3779b97f4a7c15);
            for t in 0..spline.mesh().triangles().len() {
                for _ in 0..5 {
                    let p = random_point(spline.mesh(), t, &mut rng);
                    let value = evaluate_exact(&spline, &positions, &p).expect("inside");
                    assert_eq!(value, p.to_vec());
                    let pf = [rational_to_f64(&p[0]), rational_to_f64(&p[1])];
                    // Identity plus a zero displacement: the point itself, bit for bit.
                    let v = float.evaluate_point(&locator, pf).expect("inside");
                    assert_eq!(v, pf.to_vec());
                    assert!((0..spline.mesh().triangles().len()).all(|t| !float.is_displaced(t)));
                    // From the barycentric coordinates (for drawing): to rounding.
                    let (t, beta) = locator.locate(pf).expect("inside");
                    let v = float.evaluate(t, beta).expect("triangle");
                    for c in 0..2 {
                        assert!((v[c] - pf[c]).abs() <= 1e-12 * (1.0 + pf[c].abs()));
                    }
                }
            }
        }
    }

    #[test]
    fn float_agrees_with_exact_on_random_points() {
        let spline = Spline::new(grid(3, true), 5, 1).expect("spline");
        let mut rng = Rng(12345);
        let positions: Vec<Vec<Rational>> = spline
            .nominals()
            .iter()
            .map(|p| {
                vec![
                    &p[0] + frac(rng.below(200) - 100, 37),
                    &p[1] + frac(rng.below(200) - 100, 41),
                ]
            })
            .collect();
        let float = FloatSpline::new(&spline, &positions).expect("float");
        let locator = Locator::new(spline.mesh());
        for t in 0..spline.mesh().triangles().len() {
            for _ in 0..10 {
                let p = random_point(spline.mesh(), t, &mut rng);
                let exact = evaluate_exact(&spline, &positions, &p).expect("inside");
                let pf = [rational_to_f64(&p[0]), rational_to_f64(&p[1])];
                let f = float.evaluate_point(&locator, pf).expect("inside");
                for c in 0..2 {
                    let e = rational_to_f64(&exact[c]);
                    assert!(
                        (f[c] - e).abs() <= 1e-12 * e.abs().max(1.0),
                        "{} vs {e}",
                        f[c]
                    );
                }
            }
        }
    }

    #[test]
    fn bad_positions_are_reported() {
        let spline = Spline::new(strip(1), 2, 1).expect("spline");
        let n = spline.points().len();
        assert!(matches!(
            FloatSpline::new(&spline, &vec![vec![q(0)]; n - 1]),
            Err(EvalError::PositionCount { .. })
        ));
        assert_eq!(
            FloatSpline::new(&spline, &vec![vec![]; n]),
            Err(EvalError::ZeroDimension)
        );
        let mut ragged = vec![vec![q(0), q(1)]; n];
        ragged[3].pop();
        assert!(matches!(
            check_positions(&spline, &ragged),
            Err(EvalError::Dimension { point: 3, .. })
        ));
        assert!(evaluate_exact(&spline, &ragged, &[q(1), q(1)]).is_none());
        let float = FloatSpline::new(&spline, &vec![vec![q(1)]; n]).expect("float");
        assert!(float.evaluate(1, [1.0, 0.0, 0.0]).is_none());
        let mut out = [0.0; 2];
        assert!(!float.evaluate_point_into(&Locator::new(spline.mesh()), [1.0, 1.0], &mut out));
        let values = vec![vec![q(1), q(2)]; n];
        assert_eq!(
            FloatSpline::with_references(&spline, &values, &[Reference::Zero]),
            Err(EvalError::ReferenceCount {
                expected: 2,
                found: 1
            })
        );
        assert_eq!(
            FloatSpline::with_references(
                &spline,
                &values,
                &[Reference::Zero, Reference::Identity(2)]
            ),
            Err(EvalError::IdentityAxis {
                coordinate: 1,
                axis: 2
            })
        );
        // Measured from the constants they equal, values are not displaced and come back as
        // the constants (rounded to nearest), exactly.
        let tenth = frac(1, 10);
        let values = vec![vec![tenth.clone(), q(2)]; n];
        let references = [Reference::Constant(tenth), Reference::Constant(q(2))];
        let flat = FloatSpline::with_references(&spline, &values, &references).expect("float");
        assert_eq!(flat.references(), &references);
        assert!(!flat.is_displaced(0) && !flat.is_displaced(1));
        let (value, partials) = flat
            .evaluate_with_derivatives(0, [0.2, 0.3, 0.5])
            .expect("triangle");
        assert_eq!(value, [0.1, 2.0]);
        assert!(partials.iter().flatten().all(|x| *x == 0.0));
    }
}
