//! Workloads for the benchmarks: random dense integer matrices (thesis chapter 7) and banded
//! sparse constraint systems shaped like spline smoothness conditions (four nonzeros per row,
//! small coefficients, each parameter in a few neighbouring rows).
//!
//! Everything is generated from a seed, so every run measures the same inputs.

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

#[cfg(test)]
mod tests {
    use super::*;

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
