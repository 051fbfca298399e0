//! The reference mesh `T`: exact vertex coordinates and counter-clockwise triangles, with the
//! edge topology the spline needs.
//!
//! A [`Mesh`] is always valid: readers ([`crate::mesh_io`]) check every triangle (indices in
//! range, nonzero area, consistent orientation, no duplicates, at most two triangles per edge)
//! before building one.

use api::Rational;
use num_traits::Zero;
use std::collections::HashMap;

/// A point of the plane with exact coordinates.
pub type Point = [Rational; 2];

/// Twice the signed area of the triangle `a b c` (positive when counter-clockwise).
pub fn twice_area(a: &Point, b: &Point, c: &Point) -> Rational {
    if let Some((numer, denom)) = twice_area_in_words(a, b, c) {
        return Rational::new(numer.into(), denom.into());
    }
    (&b[0] - &a[0]) * (&c[1] - &a[1]) - (&b[1] - &a[1]) * (&c[0] - &a[0])
}

/// The sign of [`twice_area`]: `Greater` when `a b c` turn counter-clockwise, `Equal` when they
/// are collinear. Without building the area as a fraction when the words suffice (the mesh
/// checks and the count of lines through each vertex ask only this).
pub fn orientation(a: &Point, b: &Point, c: &Point) -> std::cmp::Ordering {
    match twice_area_in_words(a, b, c) {
        Some((numer, _)) => numer.cmp(&0),
        None => twice_area(a, b, c).cmp(&Rational::zero()),
    }
}

/// [`twice_area`] in `i128` as an unreduced fraction with a positive denominator, when every
/// coordinate's numerator and denominator fits an `i64` and no step overflows (checked);
/// `None` otherwise. Meshes with integer or short decimal coordinates (a whole mesh's hundred
/// thousand triangles) take this path instead of a dozen reduced big-rational operations per
/// triangle.
fn twice_area_in_words(a: &Point, b: &Point, c: &Point) -> Option<(i128, i128)> {
    let (un, ud) = difference_in_words(&b[0], &a[0])?;
    let (vn, vd) = difference_in_words(&c[1], &a[1])?;
    let (wn, wd) = difference_in_words(&b[1], &a[1])?;
    let (xn, xd) = difference_in_words(&c[0], &a[0])?;
    let (left, left_d) = (un.checked_mul(vn)?, ud.checked_mul(vd)?);
    let (right, right_d) = (wn.checked_mul(xn)?, wd.checked_mul(xd)?);
    let (numer, denom) = if left_d == right_d {
        (left.checked_sub(right)?, left_d)
    } else {
        (
            left.checked_mul(right_d)?
                .checked_sub(right.checked_mul(left_d)?)?,
            left_d.checked_mul(right_d)?,
        )
    };
    Some((numer, denom))
}

/// `p − q` as an unreduced fraction `(numerator, denominator)` in `i128`, the denominator
/// positive, when both numerators and denominators fit an `i64` (then no step overflows);
/// `None` otherwise.
pub(crate) fn difference_in_words(p: &Rational, q: &Rational) -> Option<(i128, i128)> {
    use num_traits::ToPrimitive;
    let word = |x: &Rational| -> Option<(i128, i128)> {
        Some((x.numer().to_i64()?.into(), x.denom().to_i64()?.into()))
    };
    let ((pn, pd), (qn, qd)) = (word(p)?, word(q)?);
    if pd == qd {
        return Some((pn - qn, pd));
    }
    Some((pn * qd - qn * pd, pd * qd))
}

/// A validated triangle mesh of the plane.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mesh {
    vertices: Vec<Point>,
    triangles: Vec<[usize; 3]>,
}

/// An edge of the mesh, `a < b`, with the triangles on it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Edge {
    /// Smaller vertex index.
    pub a: usize,
    /// Larger vertex index.
    pub b: usize,
    /// `(triangle, k)` for each triangle containing the edge, where the edge is opposite the
    /// triangle's `k`-th vertex. One entry on the border, two inside.
    pub faces: Vec<(usize, usize)>,
}

impl Edge {
    /// True when two triangles share this edge.
    pub fn is_interior(&self) -> bool {
        self.faces.len() == 2
    }
}

/// Edges and vertex classification of a mesh.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Topology {
    /// All edges, sorted by `(a, b)`.
    pub edges: Vec<Edge>,
    /// For each triangle, the index of the edge opposite each of its vertices.
    pub triangle_edges: Vec<[usize; 3]>,
    /// For each vertex, whether it is interior (on no border edge and in some triangle).
    pub interior_vertex: Vec<bool>,
}

impl Topology {
    /// Number of edges shared by two triangles.
    pub fn interior_edges(&self) -> usize {
        self.edges.iter().filter(|e| e.is_interior()).count()
    }

    /// Number of interior vertices.
    pub fn interior_vertices(&self) -> usize {
        self.interior_vertex.iter().filter(|v| **v).count()
    }
}

impl Mesh {
    /// A mesh from data the caller has validated: every triangle counter-clockwise with
    /// nonzero area, indices in range, no duplicate triangle, no edge in more than two
    /// triangles, and consistent orientation across shared edges.
    pub(crate) fn from_validated(vertices: Vec<Point>, triangles: Vec<[usize; 3]>) -> Self {
        debug_assert!(triangles.iter().all(|t| {
            t.iter().all(|&v| v < vertices.len())
                && twice_area(&vertices[t[0]], &vertices[t[1]], &vertices[t[2]]) > Rational::zero()
        }));
        Mesh {
            vertices,
            triangles,
        }
    }

    /// The vertices.
    pub fn vertices(&self) -> &[Point] {
        &self.vertices
    }

    /// The triangles, counter-clockwise.
    pub fn triangles(&self) -> &[[usize; 3]] {
        &self.triangles
    }

    /// Edges, their triangles, and which vertices are interior.
    pub fn topology(&self) -> Topology {
        let mut index: HashMap<(usize, usize), usize> = HashMap::new();
        let mut edges: Vec<Edge> = Vec::new();
        let mut triangle_edges = Vec::with_capacity(self.triangles.len());
        for (t, tri) in self.triangles.iter().enumerate() {
            let mut own = [0usize; 3];
            for (k, slot) in own.iter_mut().enumerate() {
                let (p, q) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
                let key = (p.min(q), p.max(q));
                let e = *index.entry(key).or_insert_with(|| {
                    edges.push(Edge {
                        a: key.0,
                        b: key.1,
                        faces: Vec::new(),
                    });
                    edges.len() - 1
                });
                edges[e].faces.push((t, k));
                *slot = e;
            }
            triangle_edges.push(own);
        }
        // Sort edges by (a, b) for deterministic numbering; remap triangle references.
        let mut order: Vec<usize> = (0..edges.len()).collect();
        order.sort_by_key(|&e| (edges[e].a, edges[e].b));
        let mut new_index = vec![0; edges.len()];
        for (new, &old) in order.iter().enumerate() {
            new_index[old] = new;
        }
        let edges: Vec<Edge> = order.iter().map(|&old| edges[old].clone()).collect();
        for own in triangle_edges.iter_mut() {
            for e in own.iter_mut() {
                *e = new_index[*e];
            }
        }
        let mut used = vec![false; self.vertices.len()];
        for tri in &self.triangles {
            for &v in tri {
                used[v] = true;
            }
        }
        let mut interior_vertex = used;
        for e in &edges {
            if !e.is_interior() {
                interior_vertex[e.a] = false;
                interior_vertex[e.b] = false;
            }
        }
        Topology {
            edges,
            triangle_edges,
            interior_vertex,
        }
    }
}

/// A generated mesh: `(n + 1)²` vertices `cell` apart, each square split by its rising diagonal
/// (`2 n²` counter-clockwise triangles). With `perturb`, interior vertices are displaced by up
/// to 2 units in a fixed pattern, so that no two edges at a vertex are collinear by accident —
/// the generic case of the spline-space dimension formula. Used by tests, benchmarks and as a
/// starting mesh. `cell` must exceed 4 when perturbing (so triangles stay counter-clockwise).
pub fn grid(n: usize, cell: i64, perturb: bool) -> Mesh {
    let mut vertices = Vec::with_capacity((n + 1) * (n + 1));
    for y in 0..=n as i64 {
        for x in 0..=n as i64 {
            let inner = x > 0 && y > 0 && x < n as i64 && y < n as i64;
            let (dx, dy) = if perturb && inner {
                ((x * 7 + y * 3) % 5 - 2, (x * 2 + y * 5) % 5 - 2)
            } else {
                (0, 0)
            };
            vertices.push([
                Rational::from_integer((cell * x + dx).into()),
                Rational::from_integer((cell * y + dy).into()),
            ]);
        }
    }
    let at = |x: usize, y: usize| y * (n + 1) + x;
    let mut triangles = Vec::with_capacity(2 * n * n);
    for y in 0..n {
        for x in 0..n {
            triangles.push([at(x, y), at(x + 1, y), at(x + 1, y + 1)]);
            triangles.push([at(x, y), at(x + 1, y + 1), at(x, y + 1)]);
        }
    }
    Mesh::from_validated(vertices, triangles)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    pub(crate) fn q(n: i64) -> Rational {
        Rational::from_integer(n.into())
    }

    proptest::proptest! {
        /// The word-size area, when it answers, is the big-rational one; coordinates up to
        /// `i64::MAX` make it decline, and the area is still exact.
        #[test]
        fn twice_area_in_words_is_exact_or_declines(
            coordinates in proptest::collection::vec(
                (
                    proptest::prop_oneof![-10_000i64..10_000, proptest::num::i64::ANY],
                    proptest::prop_oneof![1i64..20, 1i64..i64::MAX],
                ),
                6,
            ),
        ) {
            let x: Vec<Rational> = coordinates
                .iter()
                .map(|(n, d)| Rational::new((*n).into(), (*d).into()))
                .collect();
            let (a, b, c) = ([x[0].clone(), x[1].clone()], [x[2].clone(), x[3].clone()], [x[4].clone(), x[5].clone()]);
            let exact = (&b[0] - &a[0]) * (&c[1] - &a[1]) - (&b[1] - &a[1]) * (&c[0] - &a[0]);
            if let Some((numer, denom)) = twice_area_in_words(&a, &b, &c) {
                proptest::prop_assert!(denom > 0);
                proptest::prop_assert_eq!(&Rational::new(numer.into(), denom.into()), &exact);
            }
            proptest::prop_assert_eq!(orientation(&a, &b, &c), exact.cmp(&Rational::zero()));
            proptest::prop_assert_eq!(twice_area(&a, &b, &c), exact);
        }
    }

    /// Two triangles sharing the diagonal of the unit square.
    pub(crate) fn square() -> Mesh {
        Mesh::from_validated(
            vec![[q(0), q(0)], [q(1), q(0)], [q(1), q(1)], [q(0), q(1)]],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    #[test]
    fn topology_of_a_square() {
        let t = square().topology();
        assert_eq!(t.edges.len(), 5);
        assert_eq!(t.interior_edges(), 1);
        let diagonal = t
            .edges
            .iter()
            .find(|e| (e.a, e.b) == (0, 2))
            .expect("diagonal");
        assert_eq!(diagonal.faces, vec![(0, 1), (1, 2)]);
        assert_eq!(t.interior_vertices(), 0);
        assert_eq!(
            twice_area(&[q(0), q(0)], &[q(1), q(0)], &[q(0), q(1)]),
            q(1)
        );
    }
}
