//! Locating points of the reference mesh in `f64`: a uniform grid of triangle buckets, for
//! drawing and for deforming models with up to millions of vertices.

use super::float_vertices;
use crate::mesh::Mesh;

/// Default tolerance of [`Locator::locate`], in barycentric units: a point whose smallest
/// barycentric coordinate is at least `-LOCATE_TOLERANCE` counts as inside.
pub const LOCATE_TOLERANCE: f64 = 1e-9;

/// Grid cells per triangle of a [`Locator`] (more cells: fewer candidates per lookup).
const CELLS_PER_TRIANGLE: f64 = 2.0;

/// Largest number of grid cells along one axis of a [`Locator`].
const MAX_CELLS_PER_AXIS: usize = 2048;

/// Fast point location in the reference mesh, in `f64`.
///
/// Triangles are bucketed in a uniform grid over the mesh's bounding box (about two cells per
/// triangle); each triangle is listed in every cell its slightly enlarged bounding box meets.
/// Each triangle keeps its corners (rounded to the nearest `f64`) and the inverse of twice its
/// area, so its barycentric coordinates cost a few multiplications.
#[derive(Debug, Clone)]
pub struct Locator {
    /// Per triangle: corners `x0 y0 x1 y1 x2 y2` and `1 / twice area`.
    triangles: Vec<[f64; 7]>,
    origin: [f64; 2],
    /// Cells per unit length along x and y.
    inv_cell: [f64; 2],
    cells: [usize; 2],
    /// CSR layout: the triangles of cell `c` are `items[starts[c]..starts[c + 1]]`, ascending.
    starts: Vec<usize>,
    items: Vec<u32>,
    tolerance: f64,
}

impl Locator {
    /// Builds the locator of a mesh with the default tolerance [`LOCATE_TOLERANCE`].
    /// Triangles whose corners collapse in `f64` (zero or non-finite area after rounding) are
    /// never found.
    pub fn new(mesh: &Mesh) -> Self {
        Self::with_tolerance(mesh, LOCATE_TOLERANCE)
    }

    /// Builds the locator with a tolerance in barycentric units (negative or NaN values are
    /// treated as 0): points that far outside a triangle still count as inside it, so points
    /// on shared edges and mesh borders are found despite rounding.
    pub fn with_tolerance(mesh: &Mesh, tolerance: f64) -> Self {
        let tolerance = if tolerance > 0.0 { tolerance } else { 0.0 };
        let vertices = float_vertices(mesh);
        let mut triangles = Vec::with_capacity(mesh.triangles().len());
        let mut boxes = Vec::with_capacity(mesh.triangles().len());
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for tri in mesh.triangles() {
            let [a, b, c] = tri.map(|v| vertices[v]);
            let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            let inv = 1.0 / area;
            let usable =
                area != 0.0 && inv.is_finite() && [a, b, c].iter().flatten().all(|x| x.is_finite());
            triangles.push(if usable {
                [a[0], a[1], b[0], b[1], c[0], c[1], inv]
            } else {
                [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, f64::NAN]
            });
            if !usable {
                boxes.push(None);
                continue;
            }
            let mut bl = [a[0].min(b[0]).min(c[0]), a[1].min(b[1]).min(c[1])];
            let mut bh = [a[0].max(b[0]).max(c[0]), a[1].max(b[1]).max(c[1])];
            // Enlarge by the tolerance (a point at barycentric distance `tol` is at most
            // `tol · size` away) plus rounding slack.
            let pad = (tolerance * 2.0 + 1e-12) * (bh[0] - bl[0]).max(bh[1] - bl[1]);
            for axis in 0..2 {
                bl[axis] -= pad;
                bh[axis] += pad;
                lo[axis] = lo[axis].min(bl[axis]);
                hi[axis] = hi[axis].max(bh[axis]);
            }
            boxes.push(Some((bl, bh)));
        }
        let count = boxes.iter().flatten().count();
        let size = [hi[0] - lo[0], hi[1] - lo[1]];
        let usable_size = size.iter().all(|s| *s > 0.0 && s.is_finite());
        let cells = if count == 0 || !usable_size {
            [1, 1]
        } else {
            // About CELLS_PER_TRIANGLE cells per triangle, square-ish cells.
            let target = count as f64 * CELLS_PER_TRIANGLE;
            let nx = (target * size[0] / size[1]).sqrt().ceil();
            let ny = (target * size[1] / size[0]).sqrt().ceil();
            [
                (nx as usize).clamp(1, MAX_CELLS_PER_AXIS),
                (ny as usize).clamp(1, MAX_CELLS_PER_AXIS),
            ]
        };
        let inv_cell = if count == 0 || !usable_size {
            [0.0, 0.0]
        } else {
            [cells[0] as f64 / size[0], cells[1] as f64 / size[1]]
        };
        let origin = if count == 0 { [0.0, 0.0] } else { lo };
        let cell_of = |x: f64, axis: usize| -> usize {
            let c = ((x - origin[axis]) * inv_cell[axis]).floor();
            if c.is_nan() || c < 0.0 {
                0
            } else {
                (c as usize).min(cells[axis] - 1)
            }
        };
        let ranges: Vec<Option<([usize; 2], [usize; 2])>> = boxes
            .iter()
            .map(|b| {
                b.map(|(bl, bh)| {
                    (
                        [cell_of(bl[0], 0), cell_of(bl[1], 1)],
                        [cell_of(bh[0], 0), cell_of(bh[1], 1)],
                    )
                })
            })
            .collect();
        let mut starts = vec![0usize; cells[0] * cells[1] + 1];
        for (l, h) in ranges.iter().flatten() {
            for y in l[1]..=h[1] {
                for x in l[0]..=h[0] {
                    starts[y * cells[0] + x + 1] += 1;
                }
            }
        }
        for c in 1..starts.len() {
            starts[c] += starts[c - 1];
        }
        let mut fill = starts.clone();
        let mut items = vec![0u32; starts[starts.len() - 1]];
        for (t, range) in ranges.iter().enumerate() {
            if let Some((l, h)) = range {
                for y in l[1]..=h[1] {
                    for x in l[0]..=h[0] {
                        let c = y * cells[0] + x;
                        items[fill[c]] = t as u32;
                        fill[c] += 1;
                    }
                }
            }
        }
        Locator {
            triangles,
            origin,
            inv_cell,
            cells,
            starts,
            items,
            tolerance,
        }
    }

    /// Number of triangles of the mesh it was built from.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The tolerance in barycentric units.
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// Barycentric coordinates of `p` in triangle `t` (`NaN` for a triangle that collapsed in
    /// `f64`). `None` if `t` is not a triangle.
    pub fn barycentric(&self, t: usize, p: [f64; 2]) -> Option<[f64; 3]> {
        self.triangles.get(t).map(|tri| Self::beta(tri, p))
    }

    #[inline]
    fn beta(tri: &[f64; 7], p: [f64; 2]) -> [f64; 3] {
        let [x0, y0, x1, y1, x2, y2, inv] = *tri;
        let (x, y) = (p[0], p[1]);
        [
            ((x1 - x) * (y2 - y) - (y1 - y) * (x2 - x)) * inv,
            ((x2 - x) * (y0 - y) - (y2 - y) * (x0 - x)) * inv,
            ((x0 - x) * (y1 - y) - (y0 - y) * (x1 - x)) * inv,
        ]
    }

    /// The triangle containing `p` and `p`'s barycentric coordinates in it, or `None` when `p`
    /// is outside the mesh (or not finite). A triangle with all coordinates `≥ 0` wins (the
    /// lowest-numbered one); otherwise the triangle whose smallest coordinate is largest, if
    /// that is at least `-tolerance`. Coordinates are returned unclamped (a point just outside
    /// is extrapolated, which is the more accurate value).
    pub fn locate(&self, p: [f64; 2]) -> Option<(usize, [f64; 3])> {
        if !(p[0].is_finite() && p[1].is_finite()) || self.items.is_empty() {
            return None;
        }
        let mut cell = [0usize; 2];
        for axis in 0..2 {
            let c = ((p[axis] - self.origin[axis]) * self.inv_cell[axis]).floor();
            // Points outside the enlarged bounding box of all triangles are outside the mesh;
            // the last cell is closed on the right.
            if c < 0.0 || c > self.cells[axis] as f64 {
                return None;
            }
            cell[axis] = (c as usize).min(self.cells[axis] - 1);
        }
        let c = cell[1] * self.cells[0] + cell[0];
        let mut best: Option<(usize, [f64; 3], f64)> = None;
        for &t in &self.items[self.starts[c]..self.starts[c + 1]] {
            let t = t as usize;
            let beta = Self::beta(&self.triangles[t], p);
            let min = beta[0].min(beta[1]).min(beta[2]);
            if min >= 0.0 {
                return Some((t, beta));
            }
            if min >= -self.tolerance && best.is_none_or(|(_, _, m)| min > m) {
                best = Some((t, beta, min));
            }
        }
        best.map(|(t, beta, _)| (t, beta))
    }
}
