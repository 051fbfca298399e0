//! Weighted least squares with constraints in `f64` for large sparse systems, the float twin of
//! an edit whose `R_ED` is too large for the dense QR (thousands of rows on a real mesh).
//!
//! The independent rows `Â` come from the sparse rank test ([`crate::sparse_row_rank`]). With
//! `V = W⁻¹`, the minimiser of `Σ w_s (x_s − h_s)²` subject to `Â x = b̂` is
//! `x = h − V Âᵀ λ`, `G λ = Â h − b̂`, `G = Â V Âᵀ`. `G = Rᵀ R` is formed as the Givens QR of
//! `M = (Â V^{1/2})ᵀ` — its rows are the columns of `Â` scaled by `sqrt(v_s)`, rotated in one at a
//! time in an approximate-minimum-degree order of `G`'s pattern — never as `G` itself, so the
//! conditioning is that of `Â V^{1/2}`, as in the dense backend. Each solve is two sparse
//! triangular solves. Weak consistency is decided on every row of `A` with the dense backend's
//! test: `|a_i·x − b_i| ≤ tolerance · (‖a_i‖ ‖x‖ + |b_i|)`.

use crate::column_order::{column_order, RowPattern};
use crate::convert::matrix_rows;
use crate::sparse_rank::{rotate_in, sparse_row_rank, SparseRowRank, SparseVector};
use api::{BackendError, IntMatrix};

/// Prepared weighted least squares (see the module documentation).
#[derive(Debug, Clone)]
pub struct SparseLeastSquares {
    /// Every row of `A`, by rows.
    rows: Vec<Vec<(usize, f64)>>,
    /// `‖a_i‖₂` per row.
    row_norms: Vec<f64>,
    /// The independent rows (indices into `A`), in the order of `R`'s columns.
    kept: Vec<usize>,
    /// `V = W⁻¹`, per unknown.
    v: Vec<f64>,
    /// `R` by rows: row `k` starts at column `k`.
    r: Vec<SparseVector>,
    tolerance: f64,
}

/// Why a float solve failed: row `row` is not satisfied by the least-squares solution within
/// the tolerance (the constraints are inconsistent for this right-hand side).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unsatisfied {
    /// The failing row of `A`.
    pub row: usize,
}

impl SparseLeastSquares {
    /// Prepares `A` (`matrix`) with weights `weights` (positive, one per column) and relative
    /// `tolerance` for rank and consistency; also returns the rank test's answer.
    pub fn new(
        matrix: &IntMatrix,
        weights: &[f64],
        tolerance: f64,
    ) -> Result<(Self, SparseRowRank), BackendError> {
        if weights.len() != matrix.cols() || weights.iter().any(|w| !(*w > 0.0 && w.is_finite())) {
            return Err(BackendError::Numerical(
                "weights must be positive and finite, one per column".into(),
            ));
        }
        let rank = sparse_row_rank(matrix, tolerance)?;
        let rows = matrix_rows(matrix, "matrix")?;
        let row_norms: Vec<f64> = rows
            .iter()
            .map(|r| r.iter().map(|(_, v)| v * v).sum::<f64>().sqrt())
            .collect();
        let v: Vec<f64> = weights.iter().map(|w| 1.0 / w).collect();
        // M's rows: the columns of Â scaled by sqrt(v_s), over the positions of Â's rows.
        let mut columns: Vec<Vec<(usize, f64)>> = vec![Vec::new(); matrix.cols()];
        for (k, &i) in rank.independent.iter().enumerate() {
            for (s, a) in &rows[i] {
                columns[*s].push((k, a * v[*s].sqrt()));
            }
        }
        let r_count = rank.independent.len();
        let order = column_order(&RowPattern::of_rows(&columns, r_count)?);
        let mut position = vec![0u32; r_count];
        for (p, &k) in order.iter().enumerate() {
            position[k] = p as u32;
        }
        let mut factor: Vec<SparseVector> = vec![Vec::new(); r_count];
        let mut scratch = (Vec::new(), Vec::new());
        let mut dropped = 0.0;
        let mut vectors: Vec<SparseVector> = columns
            .into_iter()
            .map(|c| {
                let mut x: SparseVector = c.into_iter().map(|(k, v)| (position[k], v)).collect();
                x.sort_unstable_by_key(|(p, _)| *p);
                x
            })
            .collect();
        vectors.sort_by_key(|x| x.first().map_or(u32::MAX, |(p, _)| *p));
        for x in vectors {
            // Â has independent rows, so every column of R gets a diagonal: nothing is dropped
            // at a tolerance of zero.
            if let Some((k, rest)) = rotate_in(&mut factor, x, 0.0, &mut dropped, &mut scratch) {
                factor[k] = rest;
            }
        }
        if factor
            .iter()
            .enumerate()
            .any(|(k, row)| row.first().is_none_or(|(p, _)| *p as usize != k))
        {
            return Err(BackendError::Numerical(
                "the independent rows are too close to dependent for f64".into(),
            ));
        }
        let kept: Vec<usize> = order.iter().map(|&k| rank.independent[k]).collect();
        Ok((
            SparseLeastSquares {
                rows,
                row_norms,
                kept,
                v,
                r: factor,
                tolerance,
            },
            rank,
        ))
    }

    /// The `x` with `Â x = b̂` closest to `hints` in the weighted norm, `b` given for every row of
    /// `A` (with `magnitudes`, per row, the size of the terms that formed `b_i`); `Err` with the
    /// first row the solution does not satisfy within the tolerance.
    pub fn solve(
        &self,
        b: &[f64],
        magnitudes: &[f64],
        hints: &[f64],
    ) -> Result<Vec<f64>, Unsatisfied> {
        let dot = |row: &[(usize, f64)], x: &[f64]| row.iter().map(|(c, a)| a * x[*c]).sum::<f64>();
        // ρ = Â h − b̂ in R's column order.
        let mut z: Vec<f64> = self
            .kept
            .iter()
            .map(|&i| dot(&self.rows[i], hints) - b[i])
            .collect();
        // Rᵀ z' = ρ, then R λ = z'.
        for k in 0..z.len() {
            let row = &self.r[k];
            z[k] /= row[0].1;
            let zk = z[k];
            for (p, rkp) in &row[1..] {
                z[*p as usize] -= rkp * zk;
            }
        }
        for k in (0..z.len()).rev() {
            let row = &self.r[k];
            let s: f64 = row[1..].iter().map(|(p, rkp)| rkp * z[*p as usize]).sum();
            z[k] = (z[k] - s) / row[0].1;
        }
        // x = h − V Âᵀ λ.
        let mut x = hints.to_vec();
        for (&i, lambda) in self.kept.iter().zip(&z) {
            for (s, a) in &self.rows[i] {
                x[*s] -= self.v[*s] * a * lambda;
            }
        }
        let x_norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
        for (i, row) in self.rows.iter().enumerate() {
            let residual = (dot(row, &x) - b[i]).abs();
            if residual > self.tolerance.sqrt() * (self.row_norms[i] * x_norm + magnitudes[i]) {
                return Err(Unsatisfied { row: i });
            }
        }
        Ok(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The constrained least-squares solution of a small system with a redundant row, checked
    /// against the optimality conditions; an inconsistent right-hand side is refused.
    #[test]
    fn solves_and_refuses_like_the_definition() {
        // x0 + x1 = 2, x1 − x2 = 1, x0 + 2 x1 − x2 = 3 (the sum of the two).
        let a = IntMatrix::from_dense(3, &[vec![1, 1, 0], vec![0, 1, -1], vec![1, 2, -1]])
            .expect("matrix");
        let (lsq, rank) = SparseLeastSquares::new(&a, &[1.0, 2.0, 4.0], 1e-10).expect("prepared");
        assert_eq!(rank.rank, 2);
        let hints = [0.5, 0.25, -1.0];
        let x = lsq
            .solve(&[2.0, 1.0, 3.0], &[2.0, 1.0, 3.0], &hints)
            .expect("consistent");
        assert!((x[0] + x[1] - 2.0).abs() < 1e-12 && (x[1] - x[2] - 1.0).abs() < 1e-12);
        // Optimality: W (x − h) is in the row space: with w = (1, 2, 4) and the kernel
        // direction (−1, 1, 1), Σ w_s (x_s − h_s) k_s = 0.
        let g: f64 = [1.0, 2.0, 4.0]
            .iter()
            .zip(x.iter().zip(&hints))
            .zip([-1.0, 1.0, 1.0])
            .map(|((w, (x, h)), k)| w * (x - h) * k)
            .sum();
        assert!(g.abs() < 1e-12, "{g}");
        assert!(lsq
            .solve(&[2.0, 1.0, 4.0], &[2.0, 1.0, 4.0], &hints)
            .is_err());
    }
}
