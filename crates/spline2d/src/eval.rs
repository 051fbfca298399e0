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

use crate::mesh::{twice_area, Mesh, Point};
use crate::spline::{multi_indices, Spline};
use api::exact::rational_to_f64_nearest;
use api::{Integer, Rational};
use num_traits::{One, Zero};

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
/// [`Locator`]).
pub fn locate_exact(mesh: &Mesh, p: &Point) -> Option<(usize, [Rational; 3])> {
    let zero = Rational::zero();
    (0..mesh.triangles().len()).find_map(|t| {
        let beta = barycentric(mesh, t, p);
        beta.iter().all(|b| *b >= zero).then_some((t, beta))
    })
}

fn factorial(n: usize) -> Integer {
    (1..=n).fold(Integer::one(), |acc, k| acc * Integer::from(k))
}

/// The multinomial coefficients `d!/(i! j! k!)` in [`multi_indices`] order.
fn multinomials(d: usize) -> Vec<Integer> {
    let fd = factorial(d);
    multi_indices(d)
        .into_iter()
        .map(|[i, j, k]| &fd / (factorial(i) * factorial(j) * factorial(k)))
        .collect()
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
        let vertices: Vec<[f64; 2]> = mesh
            .vertices()
            .iter()
            .map(|p| {
                [
                    rational_to_f64_nearest(&p[0]),
                    rational_to_f64_nearest(&p[1]),
                ]
            })
            .collect();
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

/// Degrees up to this use a stack buffer for the powers of `β` in evaluation.
const STACK_DEGREE: usize = 31;
/// Degrees up to this use a smaller stack buffer.
const SMALL_DEGREE: usize = 7;

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
/// [`multi_indices`] order. Then `φ_c = r_c + D_c` with
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
/// `|D̂_c − D_c(p)| ≤ K·M_c` with `K = (N + d + 5)·u + 9·d·δ_β`,
///
/// and the value at the point, `x̂' = fl(x + D̂_x)` for an identity reference, satisfies
/// `|x̂' − x'| ≤ u·|x'| + 1.01·K·M_x`, where `x' = x + D_x(p)` is the exact value at the
/// rational value of the `f64` input. For the barycentric coordinates of [`Locator`] (corners
/// rounded to nearest, `p` inside `t`), `δ_β ≤ 7u·h(2L + 3h)/A`, with `h` the longest edge of
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
            let nominal = &spline.points()[point].nominal;
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

    /// Reference `c` on triangle `t` at `beta` (the identity as `Σ βk·vk`).
    #[inline]
    fn base_at(&self, t: usize, beta: [f64; 3], c: usize) -> f64 {
        match self.bases[c] {
            Base::Zero => 0.0,
            Base::Constant(v) => v,
            Base::Identity(axis) => {
                let k = &self.corners[t];
                beta[0] * k[0][axis] + beta[1] * k[1][axis] + beta[2] * k[2][axis]
            }
        }
    }

    /// Reference `c` at the point `p` (the identity is `p` itself).
    #[inline]
    fn base_at_point(&self, p: [f64; 2], c: usize) -> f64 {
        match self.bases[c] {
            Base::Zero => 0.0,
            Base::Constant(v) => v,
            Base::Identity(axis) => p[axis],
        }
    }

    /// `φ` on triangle `t` at barycentric coordinates `beta`; `None` if `t` is not a triangle.
    pub fn evaluate(&self, t: usize, beta: [f64; 3]) -> Option<Vec<f64>> {
        if t >= self.triangle_count() {
            return None;
        }
        let mut out = vec![0.0; self.dim];
        self.evaluate_into(t, beta, &mut out);
        Some(out)
    }

    /// `φ` on triangle `t` at `beta`, written to `out` without allocating (for degrees up to
    /// 31): the reference at `beta` (the identity as `Σ βk·vk` from the rounded corners) plus
    /// the displacement. For drawing; to map a point use
    /// [`FloatSpline::evaluate_point_into`], which takes the identity from the point itself.
    ///
    /// # Panics
    /// If `t` is not a triangle or `out.len()` differs from [`FloatSpline::dim`].
    pub fn evaluate_into(&self, t: usize, beta: [f64; 3], out: &mut [f64]) {
        self.displacement_into(t, beta, out);
        let moved = self.displaced[t];
        for (c, o) in out.iter_mut().enumerate() {
            let base = self.base_at(t, beta, c);
            *o = if moved { base + *o } else { base };
        }
    }

    /// The displacement `D(β) = Σ B_i(β)·δ_i` from the references on triangle `t` at `beta`,
    /// written to `out` without allocating (zeros where [`FloatSpline::is_displaced`] is
    /// false). The hot path for deforming large models: the value is the reference plus this.
    /// Error bound: see [`FloatSpline`].
    ///
    /// # Panics
    /// If `t` is not a triangle or `out.len()` differs from [`FloatSpline::dim`].
    #[inline]
    pub fn displacement_into(&self, t: usize, beta: [f64; 3], out: &mut [f64]) {
        assert_eq!(
            out.len(),
            self.dim,
            "output has the wrong number of coordinates"
        );
        if !self.displaced[t] {
            out.fill(0.0);
            return;
        }
        let coefficients = &self.coefficients[t * self.stride..(t + 1) * self.stride];
        match self.dim {
            1 => {
                let mut o = [0.0; 1];
                self.sum::<1>(coefficients, beta, &mut o);
                out.copy_from_slice(&o);
            }
            2 => {
                let mut o = [0.0; 2];
                self.sum::<2>(coefficients, beta, &mut o);
                out.copy_from_slice(&o);
            }
            3 => {
                let mut o = [0.0; 3];
                self.sum::<3>(coefficients, beta, &mut o);
                out.copy_from_slice(&o);
            }
            4 => {
                let mut o = [0.0; 4];
                self.sum::<4>(coefficients, beta, &mut o);
                out.copy_from_slice(&o);
            }
            _ => self.sum_dyn(coefficients, beta, out),
        }
    }

    /// Fills `powers[a * (d + 1) + e] = beta[a]^e`.
    #[inline]
    fn powers(d: usize, beta: [f64; 3], powers: &mut [f64]) {
        for (a, b) in beta.iter().enumerate() {
            let row = &mut powers[a * (d + 1)..(a + 1) * (d + 1)];
            let mut acc = 1.0;
            for p in row.iter_mut() {
                *p = acc;
                acc *= b;
            }
        }
    }

    #[inline]
    fn with_powers<R>(&self, beta: [f64; 3], f: impl FnOnce(&[f64]) -> R) -> R {
        let d = self.degree;
        let n = 3 * (d + 1);
        if d <= SMALL_DEGREE {
            // Common degrees: a small buffer is cheaper to initialise.
            let mut stack = [0.0f64; 3 * (SMALL_DEGREE + 1)];
            Self::powers(d, beta, &mut stack[..n]);
            f(&stack[..n])
        } else if d <= STACK_DEGREE {
            let mut stack = [0.0f64; 3 * (STACK_DEGREE + 1)];
            Self::powers(d, beta, &mut stack[..n]);
            f(&stack[..n])
        } else {
            let mut heap = vec![0.0f64; n];
            Self::powers(d, beta, &mut heap);
            f(&heap)
        }
    }

    #[inline]
    fn sum<const K: usize>(&self, coefficients: &[f64], beta: [f64; 3], out: &mut [f64; K]) {
        let d = self.degree;
        self.with_powers(beta, |pw| {
            let (p0, rest) = pw.split_at(d + 1);
            let (p1, p2) = rest.split_at(d + 1);
            let mut chunks = coefficients.chunks_exact(K);
            for i in (0..=d).rev() {
                let a = p0[i];
                for j in (0..=d - i).rev() {
                    let w = a * p1[j] * p2[d - i - j];
                    if let Some(q) = chunks.next() {
                        for c in 0..K {
                            out[c] += w * q[c];
                        }
                    }
                }
            }
        });
    }

    fn sum_dyn(&self, coefficients: &[f64], beta: [f64; 3], out: &mut [f64]) {
        let d = self.degree;
        out.iter_mut().for_each(|o| *o = 0.0);
        self.with_powers(beta, |pw| {
            let (p0, rest) = pw.split_at(d + 1);
            let (p1, p2) = rest.split_at(d + 1);
            let mut chunks = coefficients.chunks_exact(self.dim);
            for i in (0..=d).rev() {
                for j in (0..=d - i).rev() {
                    let w = p0[i] * p1[j] * p2[d - i - j];
                    if let Some(q) = chunks.next() {
                        for (o, x) in out.iter_mut().zip(q) {
                            *o += w * x;
                        }
                    }
                }
            }
        });
    }

    /// The displacement `D` on triangle `t` at `beta` with its partial derivatives with
    /// respect to the three barycentric coordinates, taken as independent variables of the
    /// Bernstein form: `∂D/∂β0 = Σ_{i ≥ 1} i · β0^(i−1) β1^j β2^k · stored_{ijk}` and likewise
    /// for `β1`, `β2`. The derivative along a direction `u` of the plane is
    /// `Σ_a ∂D/∂β_a · ∂β_a/∂u` (the `∂β_a/∂u` of a triangle sum to zero, so a term common to
    /// the three partials does not matter). Returns the displacement (bit-identical to
    /// [`FloatSpline::displacement_into`]) and the three partials (each with
    /// [`FloatSpline::dim`] coordinates; all zero where [`FloatSpline::is_displaced`] is
    /// false); `None` if `t` is not a triangle.
    pub fn displacement_with_derivatives(
        &self,
        t: usize,
        beta: [f64; 3],
    ) -> Option<(Vec<f64>, [Vec<f64>; 3])> {
        if t >= self.triangle_count() {
            return None;
        }
        let d = self.degree;
        let dim = self.dim;
        let mut value = vec![0.0; dim];
        let mut partials = [vec![0.0; dim], vec![0.0; dim], vec![0.0; dim]];
        if !self.displaced[t] {
            return Some((value, partials));
        }
        let coefficients = &self.coefficients[t * self.stride..(t + 1) * self.stride];
        self.with_powers(beta, |pw| {
            let (p0, rest) = pw.split_at(d + 1);
            let (p1, p2) = rest.split_at(d + 1);
            // β^e and e·β^(e−1) for one coordinate.
            let power = |p: &[f64], e: usize| p[e];
            let derivative = |p: &[f64], e: usize| if e == 0 { 0.0 } else { e as f64 * p[e - 1] };
            let mut chunks = coefficients.chunks_exact(dim);
            for i in (0..=d).rev() {
                for j in (0..=d - i).rev() {
                    let k = d - i - j;
                    let Some(q) = chunks.next() else { return };
                    let (a, b, c) = (power(p0, i), power(p1, j), power(p2, k));
                    let weights = [
                        a * b * c,
                        derivative(p0, i) * b * c,
                        a * derivative(p1, j) * c,
                        a * b * derivative(p2, k),
                    ];
                    for (coordinate, x) in q.iter().enumerate() {
                        value[coordinate] += weights[0] * x;
                        for (partial, w) in partials.iter_mut().zip(&weights[1..]) {
                            partial[coordinate] += w * x;
                        }
                    }
                }
            }
        });
        Some((value, partials))
    }

    /// `φ` on triangle `t` at `beta` with its partial derivatives with respect to the three
    /// barycentric coordinates: the reference plus [`FloatSpline::displacement_with_derivatives`],
    /// the reference differentiated as the linear function `Σ βa·ra` (for the identity
    /// `∂/∂βa = va`, the corner; a constant has none). Partials of the degree-`d` Bernstein
    /// form differ from these by a term common to the three, so directional derivatives
    /// `Σ_a ∂φ/∂β_a · ∂β_a/∂u` are the same. The value is bit-identical to
    /// [`FloatSpline::evaluate`]; `None` if `t` is not a triangle.
    pub fn evaluate_with_derivatives(
        &self,
        t: usize,
        beta: [f64; 3],
    ) -> Option<(Vec<f64>, [Vec<f64>; 3])> {
        let (mut value, mut partials) = self.displacement_with_derivatives(t, beta)?;
        let moved = self.displaced[t];
        for (c, v) in value.iter_mut().enumerate() {
            let base = self.base_at(t, beta, c);
            *v = if moved { base + *v } else { base };
            if let Base::Identity(axis) = self.bases[c] {
                for (a, partial) in partials.iter_mut().enumerate() {
                    partial[c] += self.corners[t][a][axis];
                }
            }
        }
        Some((value, partials))
    }

    /// `φ(p)`: locates `p` with `locator` (built from the same mesh) and evaluates. `None` when
    /// `p` is outside the mesh or the locator belongs to a mesh with other triangles.
    pub fn evaluate_point(&self, locator: &Locator, p: [f64; 2]) -> Option<Vec<f64>> {
        let mut out = vec![0.0; self.dim];
        self.evaluate_point_into(locator, p, &mut out)
            .then_some(out)
    }

    /// Like [`FloatSpline::evaluate_point`] without allocating: writes `φ(p)` to `out` and
    /// returns `true`, or returns `false` (leaving `out` unchanged) when `p` is outside, the
    /// locator's triangle is not one of this spline's, or `out` has the wrong length.
    ///
    /// The value is the reference at `p` plus the displacement: an identity coordinate is
    /// `fl(x + D̂_x)` with `x` the input itself, so a point in a triangle that is not
    /// displaced ([`FloatSpline::is_displaced`]) comes back bit-identical and a displaced one
    /// is within the bound stated at [`FloatSpline`].
    pub fn evaluate_point_into(&self, locator: &Locator, p: [f64; 2], out: &mut [f64]) -> bool {
        if out.len() != self.dim {
            return false;
        }
        match locator.locate(p) {
            Some((t, beta)) if t < self.triangle_count() => {
                self.displacement_into(t, beta, out);
                let moved = self.displaced[t];
                for (c, o) in out.iter_mut().enumerate() {
                    let base = self.base_at_point(p, c);
                    *o = if moved { base + *o } else { base };
                }
                true
            }
            _ => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spline::tests::{grid, q, star, strip};
    use api::exact::rational_to_f64;

    fn frac(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    fn nominal(spline: &Spline) -> Vec<Vec<Rational>> {
        spline.points().iter().map(|p| p.nominal.to_vec()).collect()
    }

    /// A small deterministic generator (xorshift) for sample points.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }
        fn below(&mut self, n: i64) -> i64 {
            (self.next() % n as u64) as i64
        }
    }

    /// A random point of triangle `t` with rational barycentric coordinates.
    fn random_point(mesh: &Mesh, t: usize, rng: &mut Rng) -> Point {
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
    fn corners_reproduce_control_points() {
        let spline = Spline::new(grid(2, true), 4, 1).expect("spline");
        // Arbitrary positions, three coordinates.
        let positions: Vec<Vec<Rational>> = (0..spline.points().len() as i64)
            .map(|i| vec![frac(i * 7 % 11, 3), q(i), frac(-i, 5)])
            .collect();
        let float = FloatSpline::new(&spline, &positions).expect("float");
        let d = spline.degree();
        for (t, tri) in spline.mesh().triangles().iter().enumerate() {
            for (corner, idx) in [[d, 0, 0], [0, d, 0], [0, 0, d]].into_iter().enumerate() {
                let point = spline.triangle_points(t)[spline.local_index(idx)];
                let mut beta = [q(0), q(0), q(0)];
                beta[corner] = q(1);
                let exact = evaluate_in_triangle(&spline, &positions, t, &beta).expect("value");
                assert_eq!(exact, positions[point]);
                let v = &spline.mesh().vertices()[tri[corner]];
                assert_eq!(
                    evaluate_exact(&spline, &positions, v).expect("inside"),
                    positions[point]
                );
                let mut bf = [0.0; 3];
                bf[corner] = 1.0;
                let f = float.evaluate(t, bf).expect("triangle");
                let expected: Vec<f64> = positions[point].iter().map(rational_to_f64).collect();
                assert_eq!(f, expected);
            }
        }
    }

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

    #[test]
    fn float_agrees_with_exact_on_random_points() {
        let spline = Spline::new(grid(3, true), 5, 1).expect("spline");
        let mut rng = Rng(12345);
        let positions: Vec<Vec<Rational>> = spline
            .points()
            .iter()
            .map(|p| {
                vec![
                    &p.nominal[0] + frac(rng.below(200) - 100, 37),
                    &p.nominal[1] + frac(rng.below(200) - 100, 41),
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

    #[test]
    fn derivatives_match_the_identity_and_finite_differences() {
        let spline = Spline::new(grid(2, true), 5, 1).expect("spline");
        let identity = FloatSpline::new(&spline, &nominal(&spline)).expect("float");
        let mut rng = Rng(77);
        let positions: Vec<Vec<Rational>> = spline
            .points()
            .iter()
            .map(|_| vec![frac(rng.below(200) - 100, 7)])
            .collect();
        let bumpy = FloatSpline::new(&spline, &positions).expect("float");
        assert!(identity
            .evaluate_with_derivatives(99, [1.0, 0.0, 0.0])
            .is_none());
        for t in 0..spline.mesh().triangles().len() {
            let beta = [0.2, 0.5, 0.3];
            // Identity: the x coordinate changes by the change of x along any direction.
            let (value, partials) = identity.evaluate_with_derivatives(t, beta).expect("t");
            assert_eq!(Some(value.clone()), identity.evaluate(t, beta));
            let corners = spline.mesh().triangles()[t]
                .map(|v| spline.mesh().vertices()[v].clone())
                .map(|p| [rational_to_f64(&p[0]), rational_to_f64(&p[1])]);
            for c in 0..2 {
                // Moving from corner 0 to corner 1 is d/dβ1 − d/dβ0.
                let along = partials[1][c] - partials[0][c];
                let expected = corners[1][c] - corners[0][c];
                assert!((along - expected).abs() < 1e-9, "{along} vs {expected}");
            }
            // Arbitrary scalar values: central differences in barycentric directions.
            let (_, partials) = bumpy.evaluate_with_derivatives(t, beta).expect("t");
            let h = 1e-6;
            for (from, to) in [(0, 1), (1, 2), (2, 0)] {
                let mut plus = beta;
                let mut minus = beta;
                plus[to] += h;
                plus[from] -= h;
                minus[to] -= h;
                minus[from] += h;
                let f = |b: [f64; 3]| bumpy.evaluate(t, b).expect("t")[0];
                let numeric = (f(plus) - f(minus)) / (2.0 * h);
                let analytic = partials[to][0] - partials[from][0];
                assert!(
                    (numeric - analytic).abs() < 1e-5 * (1.0 + analytic.abs()),
                    "{numeric} vs {analytic}"
                );
            }
        }
    }

    #[test]
    fn high_degrees_and_many_coordinates_use_the_general_path() {
        let spline = Spline::new(strip(1), 33, 0).expect("spline");
        let positions: Vec<Vec<Rational>> = spline
            .points()
            .iter()
            .map(|p| vec![p.nominal[0].clone(), p.nominal[1].clone(), q(2), q(-1)])
            .collect();
        let float = FloatSpline::new(&spline, &positions).expect("float");
        let v = float.evaluate(0, [0.25, 0.25, 0.5]).expect("triangle");
        let x = |corner: usize| {
            let vertex = spline.mesh().triangles()[0][corner];
            rational_to_f64(&spline.mesh().vertices()[vertex][0])
        };
        let expected = 0.25 * x(0) + 0.25 * x(1) + 0.5 * x(2);
        assert!((v[0] - expected).abs() < 1e-9, "{} vs {expected}", v[0]);
        assert!((v[2] - 2.0).abs() < 1e-9 && (v[3] + 1.0).abs() < 1e-9);
    }
}
