//! Control points and smoothness conditions of a degree-`d` triangular Bézier spline on a
//! reference mesh (thesis chapter 12 and 13).
//!
//! * One control point per nominal position (`C⁰` by sharing, thesis 12.2.1 and 17.5): a mesh
//!   with `V` vertices, `E` edges and `F` triangles has `V + (d−1)E + (d−1)(d−2)/2·F` points.
//! * For each interior edge shared by triangles `u` and `v` and each order `ρ = 1..=r` the
//!   `C^ρ` conditions (the quadrilateral conditions (12.7) for `ρ = 1`):
//!   `c^v_{ρ,j,k} = Σ_{ν+μ+κ=ρ} c^u_{ν, j+μ, k+κ} B^ρ_{ν,μ,κ}(β)` for `j + k = d − ρ`, where `β`
//!   are the barycentric coordinates of `v`'s opposite vertex relative to `u`. The coefficients
//!   are rational; each row is scaled to coprime integers.

use crate::mesh::{difference_in_words, Mesh, Point, Topology};
use api::{Integer, Rational};
use num_integer::Integer as _;
use num_traits::{One, Zero};

/// Where a control point lies, as classified in thesis figure 14.5 (by its multi-index
/// `(i, j, k)` in any triangle containing it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PointType {
    /// At a mesh vertex (`i = d` or `j = d` or `k = d`).
    Corner,
    /// On an edge, next to a corner (one index 0, another 1).
    EdgeCorner,
    /// On an edge, elsewhere.
    Edge,
    /// Inside a triangle, two indices equal to 1.
    InnerCorner,
    /// Inside a triangle, one index equal to 1.
    InnerEdge,
    /// All indices at least 2: in no `C¹` condition.
    Interior,
}

impl PointType {
    /// The type of multi-index `(i, j, k)` of degree `d`.
    pub fn of(idx: [usize; 3], d: usize) -> PointType {
        let [i, j, k] = idx;
        if i == d || j == d || k == d {
            PointType::Corner
        } else if (i == 0 && (j == 1 || k == 1))
            || (j == 0 && (i == 1 || k == 1))
            || (k == 0 && (i == 1 || j == 1))
        {
            PointType::EdgeCorner
        } else if i == 0 || j == 0 || k == 0 {
            PointType::Edge
        } else if idx.iter().filter(|&&x| x == 1).count() >= 2 {
            PointType::InnerCorner
        } else if i == 1 || j == 1 || k == 1 {
            PointType::InnerEdge
        } else {
            PointType::Interior
        }
    }

    /// A short lowercase name for reports.
    pub fn name(self) -> &'static str {
        match self {
            PointType::Corner => "corner",
            PointType::EdgeCorner => "edge corner",
            PointType::Edge => "edge",
            PointType::InnerCorner => "inner corner",
            PointType::InnerEdge => "inner edge",
            PointType::Interior => "interior",
        }
    }
}

/// A Bézier control point shared by every triangle whose net contains its nominal position.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ControlPoint {
    /// Stable name: `v{a}` at vertex `a`, `e{a}-{b}:{i}` on edge `a < b` with weight `i` on
    /// `a`, `t{t}:{i},{j},{k}` inside triangle `t`.
    pub name: String,
    /// Classification (figure 14.5).
    pub kind: PointType,
}

/// One smoothness condition `Σ c_s q_s = 0` with coprime integer coefficients.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Condition {
    /// The interior edge (index into [`Topology::edges`]).
    pub edge: usize,
    /// Smoothness order `ρ` (1 for the quadrilateral conditions).
    pub order: usize,
    /// Index `j` of the condition along the edge (`0 ..= d − ρ`).
    pub index: usize,
    /// `(control point, coefficient)`, nonzero coefficients.
    pub terms: Vec<(usize, Integer)>,
    /// Label naming edge, order and index.
    pub label: String,
}

/// Why a spline could not be built.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SplineError {
    /// Degree 0 has no deformation to speak of.
    #[error("degree must be at least 1, got {0}")]
    Degree(usize),
    /// A degree above [`MAX_DEGREE`].
    #[error("degree {degree} is above the limit of {max}")]
    DegreeTooHigh {
        /// Requested degree.
        degree: usize,
        /// [`MAX_DEGREE`].
        max: usize,
    },
    /// The spline would have more control points or conditions than the limits allow
    /// ([`MAX_CONTROL_POINTS`], [`MAX_CONDITIONS`]); checked before anything is allocated.
    #[error("degree {degree} and C^{smoothness} on {triangles} triangles give {count} {what}, more than the limit of {max}")]
    TooLarge {
        /// `"control points"` or `"conditions"`.
        what: &'static str,
        /// How many there would be (saturated at `u64::MAX`).
        count: u64,
        /// The limit.
        max: u64,
        /// Degree.
        degree: usize,
        /// Smoothness.
        smoothness: usize,
        /// Triangles of the mesh.
        triangles: usize,
    },
    /// Smoothness of order `r ≥ d` cannot hold with local control (and is meaningless).
    #[error("smoothness C^{smoothness} needs degree above {smoothness}, got degree {degree}")]
    SmoothnessTooHigh {
        /// Requested order.
        smoothness: usize,
        /// Degree.
        degree: usize,
    },
}

/// The control points and conditions of a `C^r` spline of degree `d` on a mesh.
///
/// The conditions are made when first asked for ([`Spline::conditions`]); a source that only
/// declares them streams them into its rows ([`Spline::for_each_condition`]), so a whole mesh's
/// conditions are not held twice.
#[derive(Debug, Clone)]
pub struct Spline {
    mesh: Mesh,
    topology: Topology,
    degree: usize,
    smoothness: usize,
    points: Vec<ControlPoint>,
    /// Per triangle, the control point of each multi-index (see [`Spline::local_index`]).
    triangle_points: Vec<Vec<usize>>,
    /// Nominal positions, made when first asked for ([`Spline::nominals`]).
    nominal: std::sync::OnceLock<Vec<Point>>,
    conditions: std::sync::OnceLock<Vec<Condition>>,
}

/// Two splines are equal when their meshes, degrees, smoothness and control points are (the
/// nominal positions and conditions follow from those, whether made yet or not).
impl PartialEq for Spline {
    fn eq(&self, other: &Self) -> bool {
        self.mesh == other.mesh
            && self.degree == other.degree
            && self.smoothness == other.smoothness
            && self.points == other.points
            && self.triangle_points == other.triangle_points
    }
}

impl Eq for Spline {}

/// All multi-indices `(i, j, k)` with `i + j + k = d`, in lexicographic order of `(i, j, k)`
/// descending: `(d,0,0), (d−1,1,0), (d−1,0,1), …, (0,0,d)`.
pub fn multi_indices(d: usize) -> Vec<[usize; 3]> {
    let mut out = Vec::with_capacity((d + 1) * (d + 2) / 2);
    for i in (0..=d).rev() {
        for j in (0..=d - i).rev() {
            out.push([i, j, d - i - j]);
        }
    }
    out
}

fn factorial(n: usize) -> Integer {
    (1..=n).fold(Integer::one(), |acc, k| acc * Integer::from(k))
}

/// The multinomial coefficients `d!/(i! j! k!)` in [`multi_indices`] order.
pub fn multinomials(d: usize) -> Vec<Integer> {
    let fd = factorial(d);
    multi_indices(d)
        .into_iter()
        .map(|[i, j, k]| &fd / (factorial(i) * factorial(j) * factorial(k)))
        .collect()
}

/// The highest degree a spline may have. The thesis works with `d = 5`; `C²` needs `d ≥ 9`;
/// beyond 40 every triangle carries more than 800 control points, which no edit needs.
pub const MAX_DEGREE: usize = 40;

/// The most control points a spline may have (each is a parameter of the system).
pub const MAX_CONTROL_POINTS: u64 = 20_000_000;

/// The most smoothness conditions a spline may have (each is a row of the system).
pub const MAX_CONDITIONS: u64 = 40_000_000;

/// Control points and conditions a spline of this size would have, in checked arithmetic
/// (saturating at `u64::MAX`): `V + E(d − 1) + T(d − 1)(d − 2)/2` points, and for every
/// interior edge `Σ_{m=1..r} (d + 1 − m)` conditions.
fn size_of(
    vertices: usize,
    edges: usize,
    interior_edges: usize,
    triangles: usize,
    degree: usize,
    smoothness: usize,
) -> (u64, u64) {
    let n = |x: usize| x as u64;
    let d = n(degree);
    let points = n(vertices)
        .saturating_add(n(edges).saturating_mul(d.saturating_sub(1)))
        .saturating_add(
            n(triangles)
                .saturating_mul(d.saturating_sub(1).saturating_mul(d.saturating_sub(2)) / 2),
        );
    let per_edge: u64 = (1..=n(smoothness)).map(|m| (d + 1).saturating_sub(m)).sum();
    (points, n(interior_edges).saturating_mul(per_edge))
}

/// The mesh's vertex coordinates over their least common denominator: `(common, scaled)` with
/// vertex `v` at `scaled[v] / common`.
fn scaled_vertices(mesh: &Mesh) -> (Integer, Vec<[Integer; 2]>) {
    let common = mesh
        .vertices()
        .iter()
        .flatten()
        .fold(Integer::one(), |acc, c| {
            if c.denom().is_one() {
                acc
            } else {
                acc.lcm(c.denom())
            }
        });
    let scaled = mesh
        .vertices()
        .iter()
        .map(|p| {
            let s = |c: &Rational| c.numer() * (&common / c.denom());
            [s(&p[0]), s(&p[1])]
        })
        .collect();
    (common, scaled)
}

/// The scaled vertex coordinates and the positions' denominator in machine words, when the
/// coordinates fit an `i64` and the denominator (`common · d`) an `i128`: the nominal
/// positions of a mesh with integer or short decimal coordinates are then sums of three
/// products in `i128` (see [`nominal_in_words`]).
fn nominal_words(
    scaled: &[[Integer; 2]],
    denominator: &Integer,
    degree: usize,
) -> Option<(Vec<[i128; 2]>, i128)> {
    use num_traits::ToPrimitive;
    // Three terms of at most 2^63 · d each must not overflow: d below 2^60 is plenty.
    if degree >= 1 << 60 {
        return None;
    }
    let scaled = scaled
        .iter()
        .map(|[x, y]| Some([i128::from(x.to_i64()?), i128::from(y.to_i64()?)]))
        .collect::<Option<Vec<_>>>()?;
    Some((scaled, denominator.to_i128()?))
}

/// The nominal position `(i a + j b + k c) / d` of the control point with weights `idx` on the
/// corners `tri`, in machine words (checked: `None` if a sum overflows).
fn nominal_in_words(
    tri: &[usize; 3],
    idx: &[usize; 3],
    scaled: &[[i128; 2]],
    denominator: i128,
) -> Option<Point> {
    let mut sums = [0i128; 2];
    for (v, w) in tri.iter().zip(idx) {
        let w = i128::try_from(*w).ok()?;
        for (sum, c) in sums.iter_mut().zip(scaled[*v]) {
            *sum = sum.checked_add(c.checked_mul(w)?)?;
        }
    }
    Some([
        exact_ldu::reduced_small_ratio(sums[0], denominator)?,
        exact_ldu::reduced_small_ratio(sums[1], denominator)?,
    ])
}

impl Spline {
    /// The index of the control point named `name` (see [`ControlPoint::name`]).
    pub fn point_index(&self, name: &str) -> Option<usize> {
        self.points.iter().position(|p| p.name == name)
    }

    /// Builds the control points and the `C^1 … C^r` conditions of a degree-`d` spline, after
    /// checking the degree against [`MAX_DEGREE`] and the sizes against [`MAX_CONTROL_POINTS`]
    /// and [`MAX_CONDITIONS`].
    pub fn new(mesh: Mesh, degree: usize, smoothness: usize) -> Result<Self, SplineError> {
        if degree == 0 {
            return Err(SplineError::Degree(degree));
        }
        if degree > MAX_DEGREE {
            return Err(SplineError::DegreeTooHigh {
                degree,
                max: MAX_DEGREE,
            });
        }
        if smoothness >= degree && smoothness > 0 {
            return Err(SplineError::SmoothnessTooHigh { smoothness, degree });
        }
        let topology = mesh.topology();
        let (point_count, condition_count) = size_of(
            mesh.vertices().len(),
            topology.edges.len(),
            topology.interior_edges(),
            mesh.triangles().len(),
            degree,
            smoothness,
        );
        for (what, count, max) in [
            ("control points", point_count, MAX_CONTROL_POINTS),
            ("conditions", condition_count, MAX_CONDITIONS),
        ] {
            if count > max {
                return Err(SplineError::TooLarge {
                    what,
                    count,
                    max,
                    degree,
                    smoothness,
                    triangles: mesh.triangles().len(),
                });
            }
        }
        let d = degree;
        let indices = multi_indices(d);
        // Shared points found by direct addressing (a hash map of positions was a tenth of a
        // whole-mesh analysis, in cache misses): a vertex's point by the vertex, an edge's
        // `d − 1` points by the edge and the weight on its smaller vertex; points inside a
        // triangle belong to it alone (the mesh has no duplicate triangles).
        let per_edge = d - 1;
        let mut vertex_point = vec![usize::MAX; mesh.vertices().len()];
        let mut edge_point = vec![usize::MAX; topology.edges.len() * per_edge];
        let mut points: Vec<ControlPoint> =
            Vec::with_capacity(usize::try_from(point_count).unwrap_or_default());
        let mut triangle_points = Vec::with_capacity(mesh.triangles().len());
        for (t, tri) in mesh.triangles().iter().enumerate() {
            let mut own = Vec::with_capacity(indices.len());
            for idx in &indices {
                let positive = idx.iter().filter(|w| **w > 0).count();
                let (slot, name) = match positive {
                    1 => {
                        let k = (0..3).find(|&k| idx[k] == d).unwrap_or(0);
                        (Some(&mut vertex_point[tri[k]]), format!("v{}", tri[k]))
                    }
                    2 => {
                        let opposite = (0..3).find(|&k| idx[k] == 0).unwrap_or(0);
                        let e = topology.triangle_edges[t][opposite];
                        let edge = &topology.edges[e];
                        let on_a = (0..3).find(|&k| tri[k] == edge.a).map_or(0, |k| idx[k]);
                        (
                            Some(&mut edge_point[e * per_edge + on_a - 1]),
                            format!("e{}-{}:{on_a}", edge.a, edge.b),
                        )
                    }
                    _ => (None, format!("t{t}:{},{},{}", idx[0], idx[1], idx[2])),
                };
                let id = match slot {
                    Some(known) if *known != usize::MAX => *known,
                    slot => {
                        points.push(ControlPoint {
                            name,
                            kind: PointType::of(*idx, d),
                        });
                        if let Some(slot) = slot {
                            *slot = points.len() - 1;
                        }
                        points.len() - 1
                    }
                };
                own.push(id);
            }
            triangle_points.push(own);
        }
        Ok(Spline {
            mesh,
            topology,
            degree,
            smoothness,
            points,
            triangle_points,
            nominal: std::sync::OnceLock::new(),
            conditions: std::sync::OnceLock::new(),
        })
    }

    /// Calls `f(point, nominal position)` once for every control point, computing each position
    /// on the way (nothing is kept): the point with weights `(i, j, k)` on a triangle's corners
    /// `(a, b, c)` sits at `(i a + j b + k c) / d`.
    pub fn for_each_nominal(&self, mut f: impl FnMut(usize, Point)) {
        let d = self.degree;
        // Vertex coordinates over one common denominator, so that a position costs integer
        // sums and a single reduction.
        let (common, scaled) = scaled_vertices(&self.mesh);
        let denominator = &common * Integer::from(d);
        let indices = multi_indices(d);
        let words = nominal_words(&scaled, &denominator, d);
        let mut done = vec![false; self.points.len()];
        for (tri, own) in self.mesh.triangles().iter().zip(&self.triangle_points) {
            for (idx, &point) in indices.iter().zip(own) {
                if std::mem::replace(&mut done[point], true) {
                    continue;
                }
                if let Some(position) = words.as_ref().and_then(|(scaled, denominator)| {
                    nominal_in_words(tri, idx, scaled, *denominator)
                }) {
                    f(point, position);
                    continue;
                }
                let mut sums = [Integer::zero(), Integer::zero()];
                for (v, w) in tri.iter().zip(idx) {
                    if *w > 0 {
                        sums[0] += &scaled[*v][0] * Integer::from(*w);
                        sums[1] += &scaled[*v][1] * Integer::from(*w);
                    }
                }
                let [x, y] = sums;
                f(
                    point,
                    [
                        exact_ldu::reduced_ratio(x, denominator.clone()),
                        exact_ldu::reduced_ratio(y, denominator.clone()),
                    ],
                );
            }
        }
    }

    /// The nominal positions of all control points in the reference mesh (the control points
    /// of the identity deformation), indexed like [`Spline::points`]; computed on the first
    /// call, so a source that only declares the spline never holds them beside its values.
    pub fn nominals(&self) -> &[Point] {
        self.nominal.get_or_init(|| {
            let mut out = vec![[Rational::zero(), Rational::zero()]; self.points.len()];
            self.for_each_nominal(|point, position| out[point] = position);
            out
        })
    }

    /// The nominal position of control point `point` (see [`Spline::nominals`]).
    ///
    /// # Panics
    /// Panics if `point` is not a control point index.
    pub fn nominal(&self, point: usize) -> &Point {
        &self.nominals()[point]
    }

    /// Calls `f` with every smoothness condition, edge by edge, in the order of
    /// [`Spline::conditions`], making each one on the way (nothing is kept).
    pub fn for_each_condition(&self, mut f: impl FnMut(Condition)) {
        let d = self.degree;
        let (_, scaled) = scaled_vertices(&self.mesh);
        // Twice the signed area in the common-denominator integer coordinates: the ratios of
        // these are the barycentric coordinates.
        let area = |a: usize, b: usize, c: usize| -> Integer {
            let (pa, pb, pc) = (&scaled[a], &scaled[b], &scaled[c]);
            (&pb[0] - &pa[0]) * (&pc[1] - &pa[1]) - (&pb[1] - &pa[1]) * (&pc[0] - &pa[0])
        };
        for (e, edge) in self.topology.edges.iter().enumerate() {
            let [(tu, ku), (tv, kv)] = match edge.faces.as_slice() {
                [a, b] => [*a, *b],
                _ => continue,
            };
            let u = self.mesh.triangles()[tu];
            let v = self.mesh.triangles()[tv];
            let (u0, u1, u2) = (u[ku], u[(ku + 1) % 3], u[(ku + 2) % 3]);
            let v0 = v[kv];
            // β = (area(v0, u1, u2), area(u0, v0, u2), area(u0, u1, v0)) / whole; the
            // condition times |whole|^ρ has integer coefficients: |whole|^ρ for the point of v's
            // triangle and −sign(whole)^ρ · multinomial · Π areas^exponent for u's.
            let whole = area(u0, u1, u2);
            let areas = [area(v0, u1, u2), area(u0, v0, u2), area(u0, u1, v0)];
            // The point of triangle `t` (vertices `vs` in any order) with weights `idx` on them.
            let point = |t: usize, vs: [usize; 3], idx: [usize; 3]| -> usize {
                let tri = self.mesh.triangles()[t];
                let mut own = [0usize; 3];
                for (v, w) in vs.iter().zip(idx) {
                    if let Some(k) = (0..3).find(|&k| tri[k] == *v) {
                        own[k] = w;
                    }
                }
                self.triangle_points[t][self.local_index(own)]
            };
            for rho in 1..=self.smoothness {
                let scale = num_traits::pow(num_traits::Signed::abs(&whole), rho);
                let flip = num_traits::Signed::is_negative(&whole) && rho % 2 == 1;
                // The coefficients of B^ρ_{ν,μ,κ}(β) for all ν + μ + κ = ρ, scaled.
                let bernstein: Vec<([usize; 3], Integer)> = multi_indices(rho)
                    .into_iter()
                    .map(|[nu, mu, ka]| {
                        let multinomial =
                            factorial(rho) / (factorial(nu) * factorial(mu) * factorial(ka));
                        let value = multinomial
                            * num_traits::pow(areas[0].clone(), nu)
                            * num_traits::pow(areas[1].clone(), mu)
                            * num_traits::pow(areas[2].clone(), ka);
                        ([nu, mu, ka], if flip { -value } else { value })
                    })
                    .collect();
                for j in 0..=d - rho {
                    let k = d - rho - j;
                    let mut terms: Vec<(usize, Integer)> =
                        vec![(point(tv, [v0, u1, u2], [rho, j, k]), scale.clone())];
                    for ([nu, mu, ka], b) in &bernstein {
                        if b.is_zero() {
                            continue;
                        }
                        terms.push((point(tu, [u0, u1, u2], [*nu, j + mu, k + ka]), -b.clone()));
                    }
                    let terms = integer_row(terms);
                    if terms.is_empty() {
                        continue;
                    }
                    f(Condition {
                        edge: e,
                        order: rho,
                        index: j,
                        terms,
                        label: format!("C{rho} edge {}-{} #{j}", edge.a, edge.b),
                    });
                }
            }
        }
    }

    /// An upper bound on the number of conditions (a condition whose coefficients all vanish is
    /// left out), for reserving.
    pub fn condition_bound(&self) -> usize {
        let (_, bound) = size_of(
            self.mesh.vertices().len(),
            self.topology.edges.len(),
            self.topology.interior_edges(),
            self.mesh.triangles().len(),
            self.degree,
            self.smoothness,
        );
        usize::try_from(bound).unwrap_or(usize::MAX)
    }

    /// The reference mesh.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// Edges and interior vertices of the mesh.
    pub fn topology(&self) -> &Topology {
        &self.topology
    }

    /// The degree `d`.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The smoothness order `r`.
    pub fn smoothness(&self) -> usize {
        self.smoothness
    }

    /// All control points.
    pub fn points(&self) -> &[ControlPoint] {
        &self.points
    }

    /// The control points of triangle `t`, in the order of [`multi_indices`].
    pub fn triangle_points(&self, t: usize) -> &[usize] {
        &self.triangle_points[t]
    }

    /// Position of multi-index `(i, j, k)` in [`multi_indices`] order.
    pub fn local_index(&self, idx: [usize; 3]) -> usize {
        let d = self.degree;
        let i = idx[0];
        // Rows with first index above i hold Σ_{i' > i} (d − i' + 1) entries.
        let before: usize = (i + 1..=d).map(|ip| d - ip + 1).sum();
        before + (d - i - idx[1])
    }

    /// All smoothness conditions, made on the first call.
    pub fn conditions(&self) -> &[Condition] {
        self.conditions.get_or_init(|| {
            let mut out = Vec::with_capacity(self.condition_bound());
            self.for_each_condition(|c| out.push(c));
            out
        })
    }

    /// The expected number of control points `V + (d−1)E + (d−1)(d−2)/2·F` over the vertices
    /// used by triangles.
    pub fn expected_point_count(&self) -> usize {
        let d = self.degree;
        let used = self
            .mesh
            .triangles()
            .iter()
            .flatten()
            .collect::<std::collections::BTreeSet<_>>()
            .len();
        used + (d - 1) * self.topology.edges.len()
            + (d - 1) * (d.saturating_sub(2)) / 2 * self.mesh.triangles().len()
    }

    /// Schumaker's dimension of `S^r_d` on this triangulation:
    /// `C(d+2,2) + C(d−r+1,2)·E_I − [C(d+2,2) − C(r+2,2)]·V_I + σ` with
    /// `σ = Σ_v Σ_{j=1}^{d−r} (r + j + 1 − j·e_v)₊`, `e_v` the number of distinct edge slopes
    /// at interior vertex `v`. Exact for `d ≥ 3r + 2` (Hong 1991) on a triangulated polygon
    /// (connected, simply connected).
    pub fn spline_space_dimension(&self) -> usize {
        let (d, r) = (self.degree as i64, self.smoothness as i64);
        let c2 = |n: i64| if n < 2 { 0 } else { n * (n - 1) / 2 };
        let e_i = self.topology.interior_edges() as i64;
        let v_i = self.topology.interior_vertices() as i64;
        // The neighbours of every vertex, from one pass over the edges.
        let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); self.mesh.vertices().len()];
        for e in &self.topology.edges {
            neighbours[e.a].push(e.b);
            neighbours[e.b].push(e.a);
        }
        let mut sigma = 0i64;
        for (v, interior) in self.topology.interior_vertex.iter().enumerate() {
            if !*interior {
                continue;
            }
            let e_v = self.slopes_towards(v, &neighbours[v]) as i64;
            for j in 1..=(d - r) {
                sigma += (r + j + 1 - j * e_v).max(0);
            }
        }
        (c2(d + 2) + c2(d - r + 1) * e_i - (c2(d + 2) - c2(r + 2)) * v_i + sigma) as usize
    }

    /// Number of distinct lines through vertex `v` among its edges.
    pub fn distinct_slopes(&self, v: usize) -> usize {
        let neighbours: Vec<usize> = self
            .topology
            .edges
            .iter()
            .filter_map(|e| match (e.a == v, e.b == v) {
                (true, _) => Some(e.b),
                (_, true) => Some(e.a),
                _ => None,
            })
            .collect();
        self.slopes_towards(v, &neighbours)
    }

    /// Number of distinct lines through vertex `v` and one of `neighbours`.
    fn slopes_towards(&self, v: usize, neighbours: &[usize]) -> usize {
        let vertices = self.mesh.vertices();
        let p = &vertices[v];
        let others = || neighbours.iter().map(|&q| &vertices[q]);
        slopes_in_words(p, others()).unwrap_or_else(|| slopes_by_division(p, others()))
    }
}

/// The number of distinct lines through `p` and each of `neighbours`, in rationals: each
/// direction normalised to `(1, dy / dx)` or `(0, 1)`.
fn slopes_by_division<'a>(p: &Point, neighbours: impl Iterator<Item = &'a Point>) -> usize {
    let mut directions: Vec<(Rational, Rational)> = Vec::new();
    for q in neighbours {
        let (dx, dy) = (&q[0] - &p[0], &q[1] - &p[1]);
        let dir = if dx.is_zero() {
            (Rational::zero(), Rational::one())
        } else {
            (Rational::one(), dy / dx)
        };
        if !directions.contains(&dir) {
            directions.push(dir);
        }
    }
    directions.len()
}

/// The number of distinct lines through `p` and each of `neighbours`, in machine words: each
/// direction `q − p` becomes its primitive integer vector with a positive first nonzero entry
/// (a line, not a ray), compared exactly. `None` when a coordinate's numerator or denominator
/// does not fit an `i64` or a step overflows (checked); the caller then divides rationals.
fn slopes_in_words<'a>(p: &Point, neighbours: impl Iterator<Item = &'a Point>) -> Option<usize> {
    let mut lines: Vec<(i128, i128)> = Vec::new();
    for q in neighbours {
        let (xn, xd) = difference_in_words(&q[0], &p[0])?;
        let (yn, yd) = difference_in_words(&q[1], &p[1])?;
        // The direction over the common denominator xd · yd (positive), then primitive.
        let (mut x, mut y) = (xn.checked_mul(yd)?, yn.checked_mul(xd)?);
        let g = num_integer::gcd(x, y);
        if g != 0 {
            (x, y) = (x / g, y / g);
        }
        if x < 0 || (x == 0 && y < 0) {
            (x, y) = (x.checked_neg()?, y.checked_neg()?);
        }
        if !lines.contains(&(x, y)) {
            lines.push((x, y));
        }
    }
    Some(lines.len())
}

/// The primitive row of integer coefficients (merging repeated control points, dropping zeros,
/// divided by their greatest common divisor: the same row [`api::coprime_integers`] gives for
/// any positive multiple), sorted by control point.
fn integer_row(terms: Vec<(usize, Integer)>) -> Vec<(usize, Integer)> {
    let mut merged: Vec<(usize, Integer)> = Vec::with_capacity(terms.len());
    for (p, c) in terms {
        match merged.iter_mut().find(|(q, _)| *q == p) {
            Some((_, acc)) => *acc += c,
            None => merged.push((p, c)),
        }
    }
    merged.retain(|(_, c)| !c.is_zero());
    let gcd = merged
        .iter()
        .fold(Integer::zero(), |g, (_, c)| exact_ldu::gcd_bigint(&g, c));
    if !gcd.is_zero() && !gcd.is_one() {
        for (_, c) in &mut merged {
            *c = &*c / &gcd;
        }
    }
    merged.sort_by_key(|(p, _)| *p);
    merged
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::mesh::twice_area;
    use api::{Factorization, IntMatrix, LinearBackend};
    use exact_ldu::ExactLdu;

    pub(crate) fn q(n: i64) -> Rational {
        Rational::from_integer(n.into())
    }

    /// Builds a mesh after orienting every triangle counter-clockwise.
    pub(crate) fn mesh(points: &[(i64, i64)], triangles: &[[usize; 3]]) -> Mesh {
        let vertices: Vec<Point> = points.iter().map(|&(x, y)| [q(x), q(y)]).collect();
        let triangles = triangles
            .iter()
            .map(|t| {
                if twice_area(&vertices[t[0]], &vertices[t[1]], &vertices[t[2]]) > Rational::zero()
                {
                    *t
                } else {
                    [t[0], t[2], t[1]]
                }
            })
            .collect();
        Mesh::from_validated(vertices, triangles)
    }

    /// A zigzag strip of `n` triangles `(i, i+1, i+2)` over alternating bottom and top
    /// vertices: `n + 2` vertices, `n − 1` interior edges.
    pub(crate) fn strip(n: usize) -> Mesh {
        let points: Vec<(i64, i64)> = (0..n as i64 + 2)
            .map(|i| if i % 2 == 0 { (3 * i, 0) } else { (3 * i, 5) })
            .collect();
        let tris: Vec<[usize; 3]> = (0..n).map(|i| [i, i + 1, i + 2]).collect();
        mesh(&points, &tris)
    }

    /// A wheel of `n` triangles around a centre, rim radii alternating long and short (a star).
    pub(crate) fn star(n: usize) -> Mesh {
        let mut points = vec![(0, 0)];
        for k in 0..n {
            let angle = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            let radius = if k % 2 == 0 { 100.0 } else { 40.0 };
            points.push((
                (radius * angle.cos()).round() as i64,
                (radius * angle.sin()).round() as i64,
            ));
        }
        let tris: Vec<[usize; 3]> = (0..n).map(|k| [0, 1 + k, 1 + (k + 1) % n]).collect();
        mesh(&points, &tris)
    }

    /// A grid of `n × n` squares of side 10 (see [`crate::mesh::grid`]).
    pub(crate) fn grid(n: usize, perturb: bool) -> Mesh {
        crate::mesh::grid(n, 10, perturb)
    }

    /// The square split by both diagonals: the centre's four edges lie on two lines.
    fn cross() -> Mesh {
        mesh(
            &[(0, 0), (2, 0), (2, 2), (0, 2), (1, 1)],
            &[[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]],
        )
    }

    proptest::proptest! {
        /// Lines counted in machine words are the lines counted by dividing rationals, for
        /// neighbours on a few lines through `p` (both sides of it, short and 18-digit
        /// coordinates, so the words path also declines).
        #[test]
        fn slopes_in_words_are_the_slopes_by_division(
            centre in (-50i64..50, -50i64..50, 1i64..4),
            steps in proptest::collection::vec((0usize..4, -3i64..4, 1i64..3), 1..8),
            huge in proptest::bool::ANY,
        ) {
            let scale: i64 = if huge { 1_000_000_000_000_000_000 } else { 1 };
            let (cx, cy, cd) = centre;
            let p: Point = [
                Rational::new(Integer::from(cx) * scale, cd.into()),
                Rational::new(Integer::from(cy) * scale, cd.into()),
            ];
            let lines = [(1i64, 0i64), (0, 1), (2, 3), (-1, 5)];
            let neighbours: Vec<Point> = steps
                .iter()
                .filter(|(_, t, _)| *t != 0)
                .map(|&(l, t, d)| {
                    let (dx, dy) = lines[l];
                    [
                        &p[0] + Rational::new((dx * t).into(), d.into()),
                        &p[1] + Rational::new((dy * t).into(), d.into()),
                    ]
                })
                .collect();
            let expected = slopes_by_division(&p, neighbours.iter());
            if let Some(words) = slopes_in_words(&p, neighbours.iter()) {
                proptest::prop_assert_eq!(words, expected);
            }
        }
    }

    /// A hexagon around a centre with six distinct edge slopes.
    fn hexagon() -> Mesh {
        mesh(
            &[
                (0, 0),
                (10, 1),
                (6, 9),
                (-4, 8),
                (-11, -1),
                (-5, -9),
                (4, -8),
            ],
            &(0..6)
                .map(|k| [0, 1 + k, 1 + (k + 1) % 6])
                .collect::<Vec<_>>(),
        )
    }

    fn rank(spline: &Spline) -> usize {
        let rows = spline
            .conditions()
            .iter()
            .map(|c| c.terms.clone())
            .collect::<Vec<_>>();
        let matrix = IntMatrix::from_sparse(spline.points().len(), rows).expect("in range");
        ExactLdu::default().factor(&matrix).expect("factor").rank()
    }

    fn check_dimension(mesh: Mesh, d: usize, r: usize) -> (usize, usize, usize) {
        let spline = Spline::new(mesh, d, r).expect("spline");
        assert_eq!(spline.points().len(), spline.expected_point_count());
        let dim = spline.spline_space_dimension();
        let rank = rank(&spline);
        assert_eq!(
            rank + dim,
            spline.points().len(),
            "d={d} r={r}: rank {rank} + dim {dim} != {} points",
            spline.points().len()
        );
        (spline.points().len(), spline.conditions().len(), rank)
    }

    #[test]
    fn thesis_table_19_counts() {
        // Table 19.1: strips of 6, 7, 8 triangles and a 10-triangle wheel; Table 19.2: a grid
        // of 9 vertices and 8 triangles (with its two rows swapped back).
        assert_eq!(check_dimension(strip(6), 5, 1).0, 96);
        assert_eq!(
            Spline::new(strip(6), 5, 1)
                .expect("spline")
                .conditions()
                .len(),
            25
        );
        let (cp, cond, _) = check_dimension(strip(7), 5, 1);
        assert_eq!((cp, cond), (111, 30));
        let (cp, cond, _) = check_dimension(strip(8), 5, 1);
        assert_eq!((cp, cond), (126, 35));
        let (cp, cond, _) = check_dimension(star(10), 5, 1);
        assert_eq!((cp, cond), (151, 50));
        let (cp, cond, rank) = check_dimension(grid(2, false), 5, 1);
        assert_eq!((cp, cond), (121, 40));
        // The centre has edges on three lines: two of its 40 conditions are redundant.
        assert_eq!(rank, 38);
    }

    #[test]
    fn rank_matches_the_dimension_formula() {
        for d in [5, 6] {
            check_dimension(cross(), d, 1);
            check_dimension(hexagon(), d, 1);
            check_dimension(grid(3, false), d, 1);
            check_dimension(grid(3, true), d, 1);
            check_dimension(star(7), d, 1);
        }
        // C0 (no conditions) and C2 with d = 9 ≥ 3r + 2.
        check_dimension(grid(2, true), 5, 0);
        check_dimension(cross(), 9, 2);
        check_dimension(hexagon(), 9, 2);
        check_dimension(grid(2, false), 9, 2);
    }

    #[test]
    fn vertices_on_two_lines_carry_one_more_degree_of_freedom() {
        let s = Spline::new(cross(), 5, 1).expect("spline");
        assert_eq!(s.distinct_slopes(4), 2);
        // 4 interior edges × 5 conditions, one dependency at the two-line vertex beyond the
        // generic count.
        let generic = 21 + 10 * 4 - 18;
        assert_eq!(s.spline_space_dimension(), generic + 1);
    }

    #[test]
    fn quadrilateral_conditions_are_affine_combinations() {
        let s = Spline::new(grid(2, true), 5, 1).expect("spline");
        for c in s.conditions() {
            assert_eq!(c.terms.len(), 4, "{}", c.label);
            // Coefficients sum to zero: the identity deformation (nominal positions) satisfies
            // every condition, and so does any constant.
            let sum: Integer = c.terms.iter().map(|(_, v)| v.clone()).sum();
            assert!(sum.is_zero(), "{}", c.label);
            for coord in 0..2 {
                let value: Rational = c
                    .terms
                    .iter()
                    .map(|(p, v)| Rational::from_integer(v.clone()) * &s.nominal(*p)[coord])
                    .sum();
                assert!(value.is_zero(), "{}", c.label);
            }
        }
    }

    /// Nominal positions and conditions made on demand: every point's position once, at the
    /// weighted mean of its triangle's corners (a vertex's point on the vertex), the stream of
    /// conditions equal to the kept list, and equality blind to what was made already.
    #[test]
    fn nominal_positions_and_conditions_are_made_once_on_demand() {
        let s = Spline::new(grid(3, true), 4, 2).expect("spline");
        let fresh = s.clone();
        let mut seen = vec![0usize; s.points().len()];
        s.for_each_nominal(|point, position| {
            seen[point] += 1;
            assert_eq!(&position, s.nominal(point));
        });
        assert!(seen.iter().all(|&n| n == 1));
        for (v, vertex) in s.mesh().vertices().iter().enumerate() {
            let name = format!("v{v}");
            let point = s.point_index(&name).expect("vertex point");
            assert_eq!(s.nominal(point), vertex, "{name}");
        }
        let mut streamed = Vec::new();
        s.for_each_condition(|c| streamed.push(c));
        assert_eq!(streamed.as_slice(), s.conditions());
        assert!(streamed.len() <= s.condition_bound());
        assert!(streamed.iter().any(|c| c.order == 2));
        assert_eq!(fresh, s);
        assert_eq!(
            s.identity_positions(),
            s.nominals().iter().map(|p| p.to_vec()).collect::<Vec<_>>()
        );
    }

    #[test]
    fn point_types_follow_figure_14_5() {
        let d = 6;
        let count = |t: PointType| {
            multi_indices(d)
                .iter()
                .filter(|i| PointType::of(**i, d) == t)
                .count()
        };
        assert_eq!(count(PointType::Corner), 3);
        assert_eq!(count(PointType::EdgeCorner), 6);
        assert_eq!(count(PointType::Edge), 3 * (d - 3));
        assert_eq!(count(PointType::InnerCorner), 3);
        assert_eq!(count(PointType::Interior), multi_indices(d - 6).len());
        let s = Spline::new(grid(1, false), 5, 1).expect("spline");
        for (t, _) in s.mesh().triangles().iter().enumerate() {
            for idx in multi_indices(5) {
                assert_eq!(multi_indices(5)[s.local_index(idx)], idx);
                let p = s.triangle_points(t)[s.local_index(idx)];
                assert_eq!(s.points()[p].kind, PointType::of(idx, 5));
            }
        }
    }

    #[test]
    fn bad_degrees_are_rejected() {
        assert!(matches!(
            Spline::new(grid(1, false), 0, 0),
            Err(SplineError::Degree(0))
        ));
        assert!(matches!(
            Spline::new(grid(1, false), 2, 2),
            Err(SplineError::SmoothnessTooHigh { .. })
        ));
    }
}
