//! Evaluating a spline exactly: barycentric coordinates in rationals, locating a point by a
//! linear scan, and the Bernstein sum `Σ d!/(i! j! k!) β0^i β1^j β2^k q_{ijk}` in rationals.
//! The oracle for tests and for small numbers of points.

use super::check_positions;
use crate::mesh::{twice_area, Mesh, Point};
use crate::spline::{multi_indices, multinomials, Spline};
use api::Rational;
use num_traits::{One, Zero};

/// Exact barycentric coordinates of `p` relative to triangle `t` of `mesh` (ratios of twice
/// areas; they sum to 1 and are all nonnegative exactly when `p` lies in the closed triangle).
///
/// # Panics
/// If `t` is not a triangle of `mesh` (like slice indexing).
pub fn barycentric(mesh: &Mesh, t: usize, p: &Point) -> [Rational; 3] {
    let [a, b, c] = mesh.triangles()[t];
    let v = mesh.vertices();
    let (a, b, c) = (&v[a], &v[b], &v[c]);
    // Valid meshes have nonzero area (see `Mesh`), so the divisions are safe.
    let area = twice_area(a, b, c);
    [
        twice_area(p, b, c) / &area,
        twice_area(a, p, c) / &area,
        twice_area(a, b, p) / &area,
    ]
}

/// The triangle containing `p` (all barycentric coordinates `≥ 0`, exactly) and `p`'s
/// barycentric coordinates in it; `None` when `p` lies outside the mesh. A point on an edge or
/// vertex shared by several triangles gets the lowest-numbered one, so the answer is
/// deterministic. A linear scan: meant for exact checks, not for many points (see
/// [`Locator`](super::Locator)).
pub fn locate_exact(mesh: &Mesh, p: &Point) -> Option<(usize, [Rational; 3])> {
    let zero = Rational::zero();
    (0..mesh.triangles().len()).find_map(|t| {
        let beta = barycentric(mesh, t, p);
        beta.iter().all(|b| *b >= zero).then_some((t, beta))
    })
}

/// `φ` on triangle `t` at barycentric coordinates `beta`, exactly. `None` when the positions
/// do not fit the spline (see [`check_positions`]) or `t` is not a triangle.
pub fn evaluate_in_triangle(
    spline: &Spline,
    positions: &[Vec<Rational>],
    t: usize,
    beta: &[Rational; 3],
) -> Option<Vec<Rational>> {
    let dim = check_positions(spline, positions).ok()?;
    if t >= spline.mesh().triangles().len() {
        return None;
    }
    let d = spline.degree();
    let powers: Vec<Vec<Rational>> = beta
        .iter()
        .map(|b| {
            let mut row = Vec::with_capacity(d + 1);
            let mut acc = Rational::one();
            for _ in 0..=d {
                row.push(acc.clone());
                acc *= b;
            }
            row
        })
        .collect();
    let points = spline.triangle_points(t);
    let mut out = vec![Rational::zero(); dim];
    for ((l, [i, j, k]), m) in multi_indices(d)
        .into_iter()
        .enumerate()
        .zip(multinomials(d))
    {
        let w = Rational::from_integer(m) * &powers[0][i] * &powers[1][j] * &powers[2][k];
        if w.is_zero() {
            continue;
        }
        for (o, q) in out.iter_mut().zip(&positions[points[l]]) {
            *o += &w * q;
        }
    }
    Some(out)
}

/// `φ(p)`, exactly: the spline with control points at `positions` evaluated in the triangle
/// containing `p` ([`locate_exact`]). `None` when `p` is outside the mesh or the positions do
/// not fit the spline (use [`check_positions`] to tell the two apart). With the nominal
/// positions (the identity deformation) `φ(p) = p`.
pub fn evaluate_exact(
    spline: &Spline,
    positions: &[Vec<Rational>],
    p: &Point,
) -> Option<Vec<Rational>> {
    check_positions(spline, positions).ok()?;
    let (t, beta) = locate_exact(spline.mesh(), p)?;
    evaluate_in_triangle(spline, positions, t, &beta)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::test_support::*;
    use crate::eval::Locator;
    use crate::spline::tests::{grid, q};

    #[test]
    fn exact_location_prefers_the_lowest_triangle() {
        let mesh = grid(1, false);
        // The diagonal (0,0)-(10,10) is shared by triangles 0 and 1.
        let (t, beta) = locate_exact(&mesh, &[q(5), q(5)]).expect("inside");
        assert_eq!(t, 0);
        assert_eq!(beta.iter().sum::<Rational>(), q(1));
        assert!(locate_exact(&mesh, &[q(11), q(5)]).is_none());
        assert!(locate_exact(&mesh, &[frac(-1, 1000), q(5)]).is_none());
        let locator = Locator::new(&mesh);
        assert!(locator.locate([5.0, 5.0]).is_some());
        assert!(locator.locate([10.0, 10.0]).is_some());
        assert!(locator.locate([10.001, 5.0]).is_none());
        assert!(locator.locate([f64::NAN, 5.0]).is_none());
    }
}
