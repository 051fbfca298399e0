//! A matrix with the sparsity structure of the C1 conditions of a degree-`d` triangular Bézier
//! spline on a grid of `n × n` squares, each split by its diagonal (the meshes of the spline
//! benches), built here so that this crate does not depend on spline2d.
//!
//! Control points sit at nominal positions `(i a + j b + k c) / d`, `i + j + k = d`, of each
//! triangle `(a, b, c)` and are shared between triangles (vertices, `d − 1` per edge,
//! `(d − 1)(d − 2) / 2` inside each triangle). Each interior edge between triangles `u` and
//! `v` gives `d` rows of four nonzeros, the quadrilateral conditions
//! `c^v_{1jk} − β0 c^u_{1jk} − β1 c^u_{0,j+1,k} − β2 c^u_{0,j,k+1}`, `j + k = d − 1`, where
//! index 0 is the vertex opposite the edge; the coefficients used are 1, −1, −1, 1 (only the
//! structure matters).

use api::IntMatrix;
use std::collections::HashMap;

/// The C1 condition matrix of the `n × n` grid for degree `d` (one coordinate).
pub fn c1_grid_matrix(n: usize, d: usize) -> IntMatrix {
    let side = n + 1;
    let vertex = |x: usize, y: usize| y * side + x;
    let position = |v: usize| ((v % side) as i64, (v / side) as i64);
    let mut triangles: Vec<[usize; 3]> = Vec::with_capacity(2 * n * n);
    for y in 0..n {
        for x in 0..n {
            let (v00, v10, v01, v11) = (
                vertex(x, y),
                vertex(x + 1, y),
                vertex(x, y + 1),
                vertex(x + 1, y + 1),
            );
            triangles.push([v00, v10, v11]);
            triangles.push([v00, v11, v01]);
        }
    }
    // Control point of triangle (p0, p1, p2) with barycentric indices (i, j, k): keyed by its
    // position scaled by d, unique across the mesh.
    let mut points: HashMap<(i64, i64), usize> = HashMap::new();
    let mut point = |p: [usize; 3], i: usize, j: usize, k: usize| -> usize {
        let (a, b, c) = (position(p[0]), position(p[1]), position(p[2]));
        let key = (
            i as i64 * a.0 + j as i64 * b.0 + k as i64 * c.0,
            i as i64 * a.1 + j as i64 * b.1 + k as i64 * c.1,
        );
        let next = points.len();
        *points.entry(key).or_insert(next)
    };
    for &t in &triangles {
        for i in 0..=d {
            for j in 0..=d - i {
                point(t, i, j, d - i - j);
            }
        }
    }
    // Interior edges: the two triangles on each edge, with their opposite vertices.
    let mut edges: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    for t in &triangles {
        for e in 0..3 {
            let (a, b) = (t[(e + 1) % 3], t[(e + 2) % 3]);
            edges.entry((a.min(b), a.max(b))).or_default().push(t[e]);
        }
    }
    let mut interior: Vec<(usize, usize, usize, usize)> = edges
        .iter()
        .filter(|(_, opposite)| opposite.len() == 2)
        .map(|(&(a, b), opposite)| (a, b, opposite[0], opposite[1]))
        .collect();
    interior.sort_unstable();
    let mut rows = Vec::with_capacity(interior.len() * d);
    for (a, b, ou, ov) in interior {
        let (u, v) = ([ou, a, b], [ov, a, b]);
        for j in 0..d {
            let k = d - 1 - j;
            rows.push(vec![
                (point(v, 1, j, k), 1.into()),
                (point(u, 1, j, k), (-1).into()),
                (point(u, 0, j + 1, k), (-1).into()),
                (point(u, 0, j, k + 1), 1.into()),
            ]);
        }
    }
    let cols = points.len();
    match IntMatrix::from_sparse(cols, rows) {
        Ok(m) => m,
        Err(e) => panic!("control point indices are in range by construction: {e}"),
    }
}
