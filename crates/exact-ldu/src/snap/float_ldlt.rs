//! `P G Pᵀ = L D Lᵀ` in `f64` for the symmetric positive definite normal matrix `G` of a
//! least-squares problem: the approximate optimum that a snapped commit rounds
//! ([`super`]). Nothing exact depends on it: a poor approximation only moves the snapped point
//! farther from the optimum, and the bound reported with it says how far.
//!
//! Same up-looking algorithm and symbolic part as the factoring modulo `p`
//! ([`crate::ldlt_symbolic`]). Every operation is a plain `f64` addition, multiplication or
//! division in a fixed order (no fused multiply-add, no threads), so the result is the same
//! on every IEEE 754 machine: a snapped commit is reproducible.

use crate::ldlt_symbolic::{elimination_tree, fill_reducing_order, RowPatterns};

/// The factors of `P G Pᵀ = L D Lᵀ` in `f64`, `L` by rows and by columns.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FloatLdlt {
    /// Pivot `k` is row and column `order[k]` of `G`.
    order: Vec<usize>,
    row_starts: Vec<usize>,
    row_entries: Vec<(u32, f64)>,
    column_starts: Vec<usize>,
    column_entries: Vec<(u32, f64)>,
    diagonal: Vec<f64>,
}

impl FloatLdlt {
    /// Factors the symmetric `G` (both triangles, sparse rows with increasing columns) in a
    /// fill-reducing order; `None` when a pivot is not positive and finite (`G` too badly
    /// conditioned for `f64`).
    pub(crate) fn factor(rows: &[Vec<(usize, f64)>]) -> Option<Self> {
        let n = rows.len();
        u32::try_from(n).ok()?;
        let order = fill_reducing_order(rows);
        let mut position = vec![0usize; n];
        for (k, &old) in order.iter().enumerate() {
            position[old] = k;
        }
        let (parent, counts) = elimination_tree(rows, &order, &position);
        let mut column_starts = Vec::with_capacity(n + 1);
        column_starts.push(0);
        for c in &counts {
            column_starts.push(column_starts[column_starts.len() - 1] + c);
        }
        let mut column_entries = vec![(0u32, 0f64); column_starts[n]];
        let mut filled = vec![0usize; n];
        let mut row_starts = Vec::with_capacity(n + 1);
        row_starts.push(0);
        let mut row_entries = Vec::with_capacity(column_starts[n]);
        let mut diagonal = Vec::with_capacity(n);
        let mut y = vec![0f64; n];
        let mut walker = RowPatterns::new(n);
        for k in 0..n {
            for &(j, a) in &rows[order[k]] {
                let i = position[j];
                if i <= k {
                    y[i] += a;
                }
            }
            let mut d = y[k];
            y[k] = 0.0;
            for &i in walker.row(&rows[order[k]], k, &position, &parent) {
                let yi = y[i];
                y[i] = 0.0;
                for &(row, l) in &column_entries[column_starts[i]..column_starts[i] + filled[i]] {
                    y[row as usize] -= l * yi;
                }
                let l_ki = yi / diagonal[i];
                d -= l_ki * yi;
                column_entries[column_starts[i] + filled[i]] = (k as u32, l_ki);
                filled[i] += 1;
                row_entries.push((i as u32, l_ki));
            }
            if !(d > 0.0 && d.is_finite()) {
                return None;
            }
            diagonal.push(d);
            let start = row_starts[k];
            row_entries[start..].sort_unstable_by_key(|(i, _)| *i);
            row_starts.push(row_entries.len());
        }
        Some(FloatLdlt {
            order,
            row_starts,
            row_entries,
            column_starts,
            column_entries,
            diagonal,
        })
    }

    /// Solves `G x = b`: `b` (in the order of `G`'s rows) is replaced by `x`.
    pub(crate) fn solve_in_place(&self, b: &mut [f64]) {
        let n = self.order.len();
        let mut z: Vec<f64> = self.order.iter().map(|&old| b[old]).collect();
        for k in 0..n {
            let mut s = 0.0;
            for &(i, l) in &self.row_entries[self.row_starts[k]..self.row_starts[k + 1]] {
                s += l * z[i as usize];
            }
            z[k] -= s;
        }
        for (w, d) in z.iter_mut().zip(&self.diagonal) {
            *w /= d;
        }
        for i in (0..n).rev() {
            let mut s = 0.0;
            for &(k, l) in &self.column_entries[self.column_starts[i]..self.column_starts[i + 1]] {
                s += l * z[k as usize];
            }
            z[i] -= s;
        }
        for (k, &old) in self.order.iter().enumerate() {
            b[old] = z[k];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `G x = b` for a sparse positive definite `G` (a path with chords), to near machine
    /// precision.
    #[test]
    fn the_factors_solve_a_positive_definite_system() {
        let n = 40;
        let mut dense = vec![vec![0f64; n]; n];
        for i in 0..n {
            dense[i][i] = 9.0 + (i % 4) as f64;
            if i + 1 < n {
                dense[i][i + 1] = -3.0;
                dense[i + 1][i] = -3.0;
            }
            if i + 7 < n {
                dense[i][i + 7] = 1.5;
                dense[i + 7][i] = 1.5;
            }
        }
        let rows: Vec<Vec<(usize, f64)>> = dense
            .iter()
            .map(|r| {
                r.iter()
                    .copied()
                    .enumerate()
                    .filter(|(_, v)| *v != 0.0)
                    .collect()
            })
            .collect();
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut b: Vec<f64> = dense
            .iter()
            .map(|r| r.iter().zip(&x).map(|(a, x)| a * x).sum())
            .collect();
        FloatLdlt::factor(&rows)
            .expect("positive definite")
            .solve_in_place(&mut b);
        for (got, want) in b.iter().zip(&x) {
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
    }

    /// An indefinite matrix is refused, not factored.
    #[test]
    fn a_matrix_that_is_not_positive_definite_is_refused() {
        let rows = vec![vec![(0, 1.0), (1, 2.0)], vec![(0, 2.0), (1, 1.0)]];
        assert!(FloatLdlt::factor(&rows).is_none());
    }
}
