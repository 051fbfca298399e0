//! `P A Pᵀ = L D Lᵀ (mod p)` of a sparse symmetric matrix, `P` a fill-reducing symmetric
//! permutation (approximate minimum degree, Amestoy, Davis and Duff 1996, through the `amd`
//! crate), `L` unit lower triangular, `D` diagonal with nonzero entries.
//!
//! The normal matrices `G = Â V Âᵀ` of least squares on a mesh are sparse and symmetric, with
//! the pattern of a 2D neighbourhood graph: a dense factoring costs `r³/3` operations and
//! `r²` per lifting step, this one `O(Σ_j |L_{:,j}|²)` and `2 nnz(L) + r` per step, which on
//! mesh patterns in a minimum-degree order is a few dozen entries per row.
//!
//! The numeric factoring is the up-looking algorithm (row `k` of `L` from a sparse triangular
//! solve with the rows above it, its pattern read off the elimination tree; T. A. Davis,
//! "Algorithm 849: a concise sparse Cholesky factorization package", ACM TOMS 31, 2005),
//! here over the integers modulo `p`. Without pivoting it needs every leading principal minor
//! of `P A Pᵀ` to be nonzero modulo `p`: true over `Q` for a positive definite `A`, so it fails
//! only for primes dividing one of those minors, and the caller then tries another prime.

use super::Modulus;
use crate::ldlt_symbolic::{elimination_tree, RowPatterns};

/// The factors of `P A Pᵀ = L D Lᵀ (mod p)`, `L` kept both by rows and by columns (the forward
/// and the backward substitution each read one of them as a gather).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct SparseLdlt {
    modulus: Modulus,
    /// Pivot `k` is row and column `order[k]` of `A`.
    order: Vec<usize>,
    /// Row `k` of `L` (strictly below the diagonal): `row_entries[row_starts[k]..row_starts[k + 1]]`
    /// as `(column, value)`, columns increasing.
    row_starts: Vec<usize>,
    row_entries: Vec<(u32, u64)>,
    /// Column `i` of `L`: `column_entries[column_starts[i]..column_starts[i + 1]]` as
    /// `(row, value)`, rows increasing.
    column_starts: Vec<usize>,
    column_entries: Vec<(u32, u64)>,
    /// `D⁻¹`.
    inverse_diagonal: Vec<u64>,
}

impl SparseLdlt {
    /// Factors the symmetric `A` (`n × n`, both triangles given, as sparse rows of residues)
    /// in the pivot order `order` (a permutation of `0..n`); `None` when a pivot vanishes modulo
    /// `p` (for a positive definite `A`, when `p` divides a leading principal minor of
    /// `P A Pᵀ`).
    ///
    /// Complexity: `Σ_j |L_{:,j}|²` multiply-adds modulo `p`, `nnz(L)` words twice.
    pub(crate) fn factor(
        rows: &[Vec<(usize, u64)>],
        order: &[usize],
        modulus: Modulus,
    ) -> Option<Self> {
        let n = rows.len();
        debug_assert_eq!(order.len(), n);
        if u32::try_from(n).is_err() {
            return None;
        }
        let mut position = vec![0usize; n];
        for (k, &old) in order.iter().enumerate() {
            position[old] = k;
        }
        let (parent, counts) = elimination_tree(rows, order, &position);
        let mut walker = RowPatterns::new(n);
        let mut column_starts = Vec::with_capacity(n + 1);
        column_starts.push(0);
        for c in &counts {
            column_starts.push(column_starts[column_starts.len() - 1] + c);
        }
        let total = column_starts[n];
        let mut column_entries = vec![(0u32, 0u64); total];
        let mut filled = vec![0usize; n];
        let mut row_starts = Vec::with_capacity(n + 1);
        row_starts.push(0);
        let mut row_entries = Vec::with_capacity(total);
        let mut inverse_diagonal = Vec::with_capacity(n);
        let mut y = vec![0u64; n];
        let p = modulus.prime();
        for k in 0..n {
            for &(j, a) in &rows[order[k]] {
                let i = position[j];
                if i <= k {
                    y[i] = modulus.reduce(y[i] + a);
                }
            }
            // Sparse triangular solve for row k, then its diagonal entry.
            let mut diagonal = y[k];
            y[k] = 0;
            for &i in walker.row(&rows[order[k]], k, &position, &parent) {
                let yi = y[i];
                y[i] = 0;
                let minus_yi = (p - yi) % p;
                for &(row, l) in &column_entries[column_starts[i]..column_starts[i] + filled[i]] {
                    let slot = &mut y[row as usize];
                    *slot = modulus.reduce(*slot + l * minus_yi);
                }
                let l_ki = modulus.mul(yi, inverse_diagonal[i]);
                diagonal = modulus.reduce(diagonal + (p - l_ki) * yi);
                column_entries[column_starts[i] + filled[i]] = (k as u32, l_ki);
                filled[i] += 1;
                row_entries.push((i as u32, l_ki));
            }
            if diagonal == 0 {
                return None;
            }
            inverse_diagonal.push(modulus.inverse(diagonal));
            // Rows of L are read in increasing column order by the forward substitution.
            let start = row_starts[k];
            row_entries[start..].sort_unstable_by_key(|(i, _)| *i);
            row_starts.push(row_entries.len());
        }
        Some(SparseLdlt {
            modulus,
            order: order.to_vec(),
            row_starts,
            row_entries,
            column_starts,
            column_entries,
            inverse_diagonal,
        })
    }

    /// The modulus of the factoring.
    pub(crate) fn modulus(&self) -> Modulus {
        self.modulus
    }

    /// Entries of `L` below the diagonal.
    #[cfg(test)]
    fn nonzeros(&self) -> usize {
        self.row_entries.len()
    }

    /// Solves `A x = b (mod p)`: `b` (residues, in the order of `A`'s rows) is replaced by `x`.
    pub(crate) fn solve_in_place(&self, b: &mut [u64], scratch: &mut Vec<u64>) {
        let n = self.order.len();
        let m = &self.modulus;
        let p = m.prime();
        scratch.clear();
        scratch.extend(self.order.iter().map(|&old| b[old]));
        // Forward: L z = P b, then w = D⁻¹ z.
        for k in 0..n {
            let mut acc: u128 = 0;
            for &(i, l) in &self.row_entries[self.row_starts[k]..self.row_starts[k + 1]] {
                acc += u128::from(l * scratch[i as usize]);
            }
            let s = m.reduce_wide(acc);
            scratch[k] = m.reduce(scratch[k] + p - s);
        }
        for (w, d) in scratch.iter_mut().zip(&self.inverse_diagonal) {
            *w = m.mul(*w, *d);
        }
        // Backward: Lᵀ y = w.
        for i in (0..n).rev() {
            let mut acc: u128 = 0;
            for &(k, l) in &self.column_entries[self.column_starts[i]..self.column_starts[i + 1]] {
                acc += u128::from(l * scratch[k as usize]);
            }
            let s = m.reduce_wide(acc);
            scratch[i] = m.reduce(scratch[i] + p - s);
        }
        for (k, &old) in self.order.iter().enumerate() {
            b[old] = scratch[k];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ldlt_symbolic::fill_reducing_order;

    /// A symmetric positive definite matrix with the pattern of a path plus a few chords.
    fn sample(n: usize) -> Vec<Vec<i64>> {
        let mut a = vec![vec![0i64; n]; n];
        for i in 0..n {
            a[i][i] = 10 + (i as i64 % 3);
            if i + 1 < n {
                a[i][i + 1] = -3;
                a[i + 1][i] = -3;
            }
            if i + 5 < n && i % 2 == 0 {
                a[i][i + 5] = 2;
                a[i + 5][i] = 2;
            }
        }
        a
    }

    fn residues(a: &[Vec<i64>], m: &Modulus) -> Vec<Vec<(usize, u64)>> {
        a.iter()
            .map(|row| {
                row.iter()
                    .enumerate()
                    .filter(|(_, v)| **v != 0)
                    .map(|(j, v)| (j, m.residue_i128(i128::from(*v))))
                    .collect()
            })
            .collect()
    }

    /// The defining equation, through solving: `A x = b (mod p)` for the computed `x`, in the
    /// fill-reducing order and in the identity order.
    #[test]
    fn the_factors_solve_the_system_modulo_p() {
        let m = Modulus::new(2_147_483_629);
        let a = sample(23);
        let rows = residues(&a, &m);
        let n = a.len();
        let x: Vec<u64> = (0..n as u64).map(|i| (i * 7919 + 3) % m.prime()).collect();
        let b: Vec<u64> = a
            .iter()
            .map(|row| {
                let s: i128 = row
                    .iter()
                    .zip(&x)
                    .map(|(v, xi)| i128::from(*v) * i128::from(*xi))
                    .sum();
                m.residue_i128(s)
            })
            .collect();
        let amd = fill_reducing_order(&rows);
        let mut sorted = amd.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n).collect::<Vec<_>>(), "a permutation");
        for order in [amd, (0..n).collect()] {
            let f = SparseLdlt::factor(&rows, &order, m).expect("positive definite");
            let mut got = b.clone();
            f.solve_in_place(&mut got, &mut Vec::new());
            assert_eq!(got, x);
        }
    }

    /// A minimum-degree order keeps an arrow matrix (dense first row and column) free of fill,
    /// where the identity order fills `L` completely.
    #[test]
    fn a_fill_reducing_order_avoids_fill() {
        let n = 30;
        let a: Vec<Vec<i64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| match (i, j) {
                        _ if i == j => 100,
                        (0, _) | (_, 0) => 1,
                        _ => 0,
                    })
                    .collect()
            })
            .collect();
        let m = Modulus::new(1_000_003);
        let rows = residues(&a, &m);
        let identity: Vec<usize> = (0..n).collect();
        let filled = SparseLdlt::factor(&rows, &identity, m).expect("nonsingular");
        assert_eq!(filled.nonzeros(), n * (n - 1) / 2);
        let ordered =
            SparseLdlt::factor(&rows, &fill_reducing_order(&rows), m).expect("nonsingular");
        assert_eq!(ordered.nonzeros(), n - 1);
    }

    /// A vanishing pivot modulo `p` is reported, not divided by: `[[1, 1], [1, 1 + p]]` is
    /// positive definite over `Q` and singular modulo `p`.
    #[test]
    fn a_zero_pivot_is_refused() {
        let m = Modulus::new(101);
        let a = vec![vec![1i64, 1], vec![1, 102]];
        let rows = residues(&a, &m);
        assert!(SparseLdlt::factor(&rows, &[0, 1], m).is_none());
        let other = Modulus::new(103);
        assert!(SparseLdlt::factor(&residues(&a, &other), &[0, 1], other).is_some());
    }
}
