//! Workloads for the benchmarks: random dense integer matrices (thesis chapter 7) and banded
//! sparse constraint systems shaped like spline smoothness conditions (four nonzeros per row,
//! small coefficients, each parameter in a few neighbouring rows).
//!
//! Everything is generated from a seed, so every run measures the same inputs.

/// Every benchmark measures with the allocator the `ecles` binary uses (see `host`'s feature
/// `mimalloc`): exact arithmetic allocates a great many small blocks, so the allocator is part
/// of what an exact edit costs.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

use api::{ConstraintRow, ConstraintSystem, IntMatrix, Origin, ParamId, Rational, RowBody, Values};
use num_bigint::BigInt;

/// A small deterministic generator (xorshift64*).
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a nonzero seed (0 is replaced by a fixed constant).
    pub fn new(seed: u64) -> Self {
        Rng(if seed == 0 {
            0x9e37_79b9_7f4a_7c15
        } else {
            seed
        })
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in `lo..=hi`.
    pub fn range(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next_u64() % ((hi - lo + 1) as u64)) as i64
    }
}

/// A dense `rows × cols` matrix of signed `bits`-bit integers (`−2^(bits−1) ..= 2^(bits−1) − 1`).
pub fn random_dense(rows: usize, cols: usize, bits: u32, seed: u64) -> IntMatrix {
    let mut rng = Rng::new(seed);
    let half = 1i64 << (bits - 1);
    let data: Vec<Vec<i64>> = (0..rows)
        .map(|_| (0..cols).map(|_| rng.range(-half, half - 1)).collect())
        .collect();
    IntMatrix::from_dense(cols, &data).expect("rectangular by construction")
}

/// A banded system over `n` scalar parameters `p0 … p{n−1}`: row `i` involves parameters
/// `2i … 2i+3` with nonzero coefficients in `−12..=12` (like the barycentric ratios of C1
/// conditions), so each parameter occurs in about two rows. The current values are small
/// integers and the right-hand sides are chosen so that they satisfy every row.
pub fn banded_system(n: usize, seed: u64) -> (ConstraintSystem, Vec<ParamId>, Values) {
    let mut rng = Rng::new(seed);
    let mut system = ConstraintSystem::new();
    let params: Vec<ParamId> = (0..n)
        .map(|i| {
            system
                .add_parameter(format!("p{i}"), 1)
                .expect("names are distinct")
        })
        .collect();
    let current: Vec<i64> = (0..n).map(|_| rng.range(-50, 50)).collect();
    let mut i = 0;
    while 2 * i + 3 < n {
        let terms: Vec<(ParamId, BigInt)> = (0..4)
            .map(|k| {
                let mut c = 0;
                while c == 0 {
                    c = rng.range(-12, 12);
                }
                (params[2 * i + k], BigInt::from(c))
            })
            .collect();
        let rhs: BigInt = terms
            .iter()
            .map(|(p, c)| c * BigInt::from(current[p.index()]))
            .sum();
        system
            .add_row(ConstraintRow {
                label: format!("band{i}"),
                origin: Origin {
                    source: "benchmarks".into(),
                    item: format!("row {i}"),
                },
                body: RowBody::Vector {
                    terms,
                    rhs: vec![rhs],
                },
            })
            .expect("valid row");
        i += 1;
    }
    let values = Values::from_vecs(
        &system,
        current
            .iter()
            .map(|&v| vec![Rational::from_integer(v.into())])
            .collect(),
    )
    .expect("one value per parameter");
    (system, params, values)
}

/// A reference mesh of `n × n` squares of side 10, each split by its rising diagonal, interior
/// vertices displaced by up to 2 units: `2 n²` triangles, `(n + 1)²` vertices.
pub fn perturbed_grid(n: usize) -> spline2d::mesh::Mesh {
    spline2d::mesh::grid(n, 10, true)
}

/// Anchor and derived sets for an edit of a banded system: the anchor is the middle parameter of
/// a window of `width + 1` parameters, the other `width` are derived.
pub fn window_edit(params: &[ParamId], width: usize) -> (Vec<ParamId>, Vec<ParamId>) {
    let start = params.len() / 2 - width / 2;
    let window = &params[start..=start + width];
    let anchor = window[width / 2];
    let derived = window.iter().copied().filter(|p| *p != anchor).collect();
    (vec![anchor], derived)
}

/// The linear point systems of `tools/peer_bench.py` (SolveSpace and kiwisolver run the same
/// ones): 2D points with scalar parameters `x<p>`, `y<p>` and scalar rows, as the `linear`
/// source builds them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointSystem {
    /// `n` points `(i, 0)`; each inner point is the midpoint of its neighbours.
    Chain,
    /// `k × k` points `(j, i)`, `k²` closest to `n`; rows horizontal, columns vertical.
    Grid,
    /// A strip of `n / 2` parallelograms `a_i = (2i, 0)`, `b_i = (2i + 2, 2)` with
    /// `a_{i+1} − a_i = b_{i+1} − b_i`, plus the midpoint of the last pair.
    Parallelograms,
}

/// One drag on a point system: the system, its values, the dragged point's two parameters
/// (anchors), every other parameter (derived) and the anchors' targets (moved by (3, −2)).
pub struct PointDrag {
    /// The constraints.
    pub system: ConstraintSystem,
    /// The current (initial) values.
    pub values: Values,
    /// `x` and `y` of the dragged point.
    pub anchors: Vec<ParamId>,
    /// Every other parameter.
    pub derived: Vec<ParamId>,
    /// The anchors' new values.
    pub targets: Vec<Vec<Rational>>,
}

/// Point positions, equations as `(parameter, coefficient)` lists (parameter `2p` is `x` of
/// point `p`, `2p + 1` its `y`) and the dragged point.
type PointLayout = (Vec<(i64, i64)>, Vec<Vec<(usize, i64)>>, usize);

/// The points, equations and dragged point of `kind` with about `n` points, as in
/// `tools/peer_bench.py`.
fn point_layout(kind: PointSystem, n: usize) -> PointLayout {
    match kind {
        PointSystem::Chain => {
            let points = (0..n as i64).map(|i| (i, 0)).collect();
            // Point p has parameters 2p (x) and 2p + 1 (y).
            let eq = (1..n - 1)
                .flat_map(|i| {
                    (0..2).map(move |k| {
                        vec![(2 * i + k, 2), (2 * (i - 1) + k, -1), (2 * (i + 1) + k, -1)]
                    })
                })
                .collect();
            (points, eq, n / 2)
        }
        PointSystem::Grid => {
            let k = (n as f64).sqrt().round() as usize;
            let at = |i: usize, j: usize| i * k + j;
            let points = (0..k * k)
                .map(|p| ((p % k) as i64, (p / k) as i64))
                .collect();
            let mut eq = Vec::new();
            for i in 0..k {
                for j in 1..k {
                    eq.push(vec![(2 * at(i, j) + 1, 1), (2 * at(i, 0) + 1, -1)]);
                    eq.push(vec![(2 * at(j, i), 1), (2 * at(0, i), -1)]);
                }
            }
            (points, eq, at(k / 2, k / 2))
        }
        PointSystem::Parallelograms => {
            let m = n / 2;
            // a_i is point 2i, b_i point 2i + 1, the apex point 2m.
            let mut points: Vec<(i64, i64)> = (0..m as i64)
                .flat_map(|i| [(2 * i, 0), (2 * i + 2, 2)])
                .collect();
            points.push((2 * m as i64 - 1, 1));
            let mut eq = Vec::new();
            for i in 0..m - 1 {
                let (a, b, a1, b1) = (2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3);
                for c in 0..2 {
                    eq.push(vec![
                        (2 * a1 + c, 1),
                        (2 * a + c, -1),
                        (2 * b1 + c, -1),
                        (2 * b + c, 1),
                    ]);
                }
            }
            let (a, b, apex) = (2 * (m - 1), 2 * (m - 1) + 1, 2 * m);
            for c in 0..2 {
                eq.push(vec![(2 * apex + c, 2), (2 * a + c, -1), (2 * b + c, -1)]);
            }
            (points, eq, 2 * (m / 2))
        }
    }
}

/// The name of parameter `q` of a point system: `x<p>` or `y<p>` of point `p = q / 2`.
fn coordinate_name(q: usize) -> String {
    format!("{}{}", ["x", "y"][q % 2], q / 2)
}

/// The system `kind` with about `n` points, as in `tools/peer_bench.py`.
pub fn point_drag(kind: PointSystem, n: usize) -> PointDrag {
    use api::Coord;
    let (points, equations, dragged) = point_layout(kind, n);
    let mut system = ConstraintSystem::new();
    let params: Vec<ParamId> = (0..2 * points.len())
        .map(|q| {
            system
                .add_parameter(coordinate_name(q), 1)
                .expect("distinct names")
        })
        .collect();
    for (i, terms) in equations.iter().enumerate() {
        system
            .add_row(ConstraintRow {
                label: format!("eq{i}"),
                origin: Origin {
                    source: "points".into(),
                    item: format!("{i}"),
                },
                body: RowBody::Scalar {
                    terms: terms
                        .iter()
                        .map(|(q, c)| {
                            (
                                Coord {
                                    param: params[*q],
                                    component: 0,
                                },
                                BigInt::from(*c),
                            )
                        })
                        .collect(),
                    rhs: BigInt::from(0),
                },
            })
            .expect("valid row");
    }
    let values = Values::from_vecs(
        &system,
        points
            .iter()
            .flat_map(|(x, y)| [*x, *y])
            .map(|v| vec![Rational::from_integer(v.into())])
            .collect(),
    )
    .expect("one value per parameter");
    let anchors = vec![params[2 * dragged], params[2 * dragged + 1]];
    let (x, y) = points[dragged];
    let targets = vec![
        vec![Rational::from_integer((x + 3).into())],
        vec![Rational::from_integer((y - 2).into())],
    ];
    let derived = params
        .iter()
        .copied()
        .filter(|p| !anchors.contains(p))
        .collect();
    PointDrag {
        system,
        values,
        anchors,
        derived,
        targets,
    }
}

/// The run file `tools/peer_bench.py` times `ecles run` on, for the drag of [`point_drag`]
/// (byte for byte, but for the order of the grid's equations, interleaved here as in
/// [`point_drag`]):
/// one `linear` source `c` (parameters `x<p>`, `y<p>`, one text equation per row),
/// `cross_check: None` and one generic edit with the dragged point's coordinates as anchors at
/// their targets and every other parameter derived.
pub fn point_run_text(kind: PointSystem, n: usize) -> String {
    let (points, equations, dragged) = point_layout(kind, n);
    let parameters: Vec<String> = points
        .iter()
        .flat_map(|(x, y)| [*x, *y])
        .enumerate()
        .map(|(q, v)| format!("\"{}\": \"{v}\"", coordinate_name(q)))
        .collect();
    let equations: Vec<String> = equations
        .iter()
        .map(|terms| {
            let mut text = String::new();
            for (i, (q, c)) in terms.iter().enumerate() {
                let sign = match (i, *c < 0) {
                    (0, false) => "",
                    (0, true) => "-",
                    (_, false) => " + ",
                    (_, true) => " - ",
                };
                let magnitude = c.unsigned_abs();
                let factor = if magnitude == 1 {
                    String::new()
                } else {
                    format!("{magnitude} ")
                };
                text += &format!("{sign}{factor}{}", coordinate_name(*q));
            }
            format!("\"{text} = 0\"")
        })
        .collect();
    let (x, y) = points[dragged];
    let anchors = format!(
        "\"c.x{dragged}\": \"{}\", \"c.y{dragged}\": \"{}\"",
        x + 3,
        y - 2
    );
    let derived: Vec<String> = (0..2 * points.len())
        .filter(|q| q / 2 != dragged)
        .map(|q| format!("\"c.{}\"", coordinate_name(q)))
        .collect();
    format!(
        "(\n    sources: [(name: \"c\", plugin: \"linear\", config: (\n        parameters: {{{}}},\n        equations: [{}],\n    ))],\n    cross_check: None,\n    edits: [Ecles(anchors: {{{anchors}}}, derived: [{}])],\n)\n",
        parameters.join(", "),
        equations.join(", "),
        derived.join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every point system holds at its initial values, and the sizes are those of the peer
    /// benchmark.
    #[test]
    fn point_systems_hold_initially() {
        for (kind, n, points) in [
            (PointSystem::Chain, 100, 100),
            (PointSystem::Grid, 100, 100),
            (PointSystem::Grid, 1000, 1024),
            (PointSystem::Parallelograms, 101, 101),
        ] {
            let drag = point_drag(kind, n);
            assert_eq!(drag.system.params().len(), 2 * points, "{kind:?}");
            assert!(drag.system.violations(&drag.values).is_empty(), "{kind:?}");
            assert_eq!(drag.derived.len() + 2, 2 * points);
        }
    }

    /// The run file of the smallest chain, as `tools/peer_bench.py` writes it.
    #[test]
    fn point_run_text_is_the_peer_benchmarks_run_file() {
        let expected = concat!(
            "(\n",
            "    sources: [(name: \"c\", plugin: \"linear\", config: (\n",
            "        parameters: {\"x0\": \"0\", \"y0\": \"0\", \"x1\": \"1\", \"y1\": \"0\", ",
            "\"x2\": \"2\", \"y2\": \"0\"},\n",
            "        equations: [\"2 x1 - x0 - x2 = 0\", \"2 y1 - y0 - y2 = 0\"],\n",
            "    ))],\n",
            "    cross_check: None,\n",
            "    edits: [Ecles(anchors: {\"c.x1\": \"4\", \"c.y1\": \"-2\"}, ",
            "derived: [\"c.x0\", \"c.y0\", \"c.x2\", \"c.y2\"])],\n",
            ")\n"
        );
        assert_eq!(point_run_text(PointSystem::Chain, 3), expected);
    }

    #[test]
    fn banded_values_satisfy_the_rows() {
        let (system, params, values) = banded_system(40, 7);
        assert!(system.violations(&values).is_empty());
        assert_eq!(system.rows().len(), 19);
        let (a, d) = window_edit(&params, 20);
        assert_eq!(a.len(), 1);
        assert_eq!(d.len(), 20);
        assert!(!d.contains(&a[0]));
    }

    #[test]
    fn perturbed_grids_have_the_expected_size() {
        let mesh = perturbed_grid(3);
        assert_eq!(mesh.triangles().len(), 18);
        assert_eq!(mesh.vertices().len(), 16);
    }

    #[test]
    fn random_dense_respects_the_bit_size() {
        let m = random_dense(5, 4, 10, 1);
        assert!(m
            .row_iter()
            .flatten()
            .all(|(_, v)| *v >= BigInt::from(-512) && *v <= BigInt::from(511)));
    }
}
