//! `P A = L U (mod p)` of a dense nonsingular square matrix: the general "cheap inverse" of
//! Dixon's lifting, used when the matrix is not symmetric or when the sparse symmetric
//! factoring ([`super::ldlt`]) meets a zero pivot for every prime it tries.

use super::Modulus;

/// `P A = L U (mod p)` of a nonsingular square matrix, stored densely row by row: `L` strictly
/// below the diagonal (unit diagonal implied), `U` on and above it, and for each row of the
/// factors the row of `A` it came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct ModularLu {
    n: usize,
    modulus: Modulus,
    factors: Vec<u64>,
    /// `U`'s diagonal inverted, for the backward substitution.
    inverse_diagonal: Vec<u64>,
    /// Row `i` of the factors is row `rows[i]` of `A`.
    rows: Vec<usize>,
}

impl ModularLu {
    /// Factors `A` (`n × n`, given by sparse rows of residues) modulo `modulus`; `None` when
    /// `p` divides `det A` (in particular when `A` is singular).
    ///
    /// Complexity: `n³/3` multiply-adds modulo `p`, `n²` words.
    pub(crate) fn factor(n: usize, rows: &[Vec<(usize, u64)>], modulus: Modulus) -> Option<Self> {
        let mut a = vec![0u64; n * n];
        for (i, row) in rows.iter().enumerate() {
            for &(j, v) in row {
                a[i * n + j] = v;
            }
        }
        let mut perm: Vec<usize> = (0..n).collect();
        let mut inverse_diagonal = Vec::with_capacity(n);
        let p = modulus.prime();
        for k in 0..n {
            let pivot = (k..n).find(|&i| a[i * n + k] != 0)?;
            if pivot != k {
                for j in 0..n {
                    a.swap(k * n + j, pivot * n + j);
                }
                perm.swap(k, pivot);
            }
            let inv = modulus.inverse(a[k * n + k]);
            inverse_diagonal.push(inv);
            let (upper, lower) = a.split_at_mut((k + 1) * n);
            let pivot_row = &upper[k * n..(k + 1) * n];
            for row in lower.chunks_exact_mut(n) {
                if row[k] == 0 {
                    continue;
                }
                let l = modulus.mul(row[k], inv);
                row[k] = l;
                let minus_l = p - l;
                for j in k + 1..n {
                    if pivot_row[j] != 0 {
                        row[j] = modulus.reduce(row[j] + minus_l * pivot_row[j]);
                    }
                }
            }
        }
        Some(ModularLu {
            n,
            modulus,
            factors: a,
            inverse_diagonal,
            rows: perm,
        })
    }

    /// The modulus of the factoring.
    pub(crate) fn modulus(&self) -> Modulus {
        self.modulus
    }

    /// Solves `A x = b (mod p)`: `b` (residues, in the order of `A`'s rows) is replaced by `x`.
    pub(crate) fn solve_in_place(&self, b: &mut [u64], scratch: &mut Vec<u64>) {
        let n = self.n;
        let m = &self.modulus;
        let p = m.prime();
        scratch.clear();
        scratch.extend(self.rows.iter().map(|&r| b[r]));
        // Forward: L y = P b.
        for i in 0..n {
            let row = &self.factors[i * n..i * n + i];
            let mut acc: u128 = 0;
            for (l, y) in row.iter().zip(scratch.iter()) {
                acc += u128::from(l * y);
            }
            let s = m.reduce_wide(acc);
            scratch[i] = m.reduce(scratch[i] + p - s);
        }
        // Backward: U x = y.
        for i in (0..n).rev() {
            let row = &self.factors[i * n + i + 1..(i + 1) * n];
            let mut acc: u128 = 0;
            for (u, x) in row.iter().zip(scratch[i + 1..].iter()) {
                acc += u128::from(u * x);
            }
            let s = m.reduce_wide(acc);
            scratch[i] = m.mul(m.reduce(scratch[i] + p - s), self.inverse_diagonal[i]);
        }
        b.copy_from_slice(scratch);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The defining equation `P A = L U (mod p)`, through solving: `A x = b` for the solution.
    #[test]
    fn the_factors_solve_the_system_modulo_p() {
        let m = Modulus::new(101);
        let a = [[0u64, 2, 3], [4, 5, 6], [7, 8, 10]];
        let rows: Vec<Vec<(usize, u64)>> = a
            .iter()
            .map(|r| {
                r.iter()
                    .copied()
                    .enumerate()
                    .filter(|(_, v)| *v != 0)
                    .collect()
            })
            .collect();
        let lu = ModularLu::factor(3, &rows, m).expect("nonsingular");
        let x = [5u64, 17, 99];
        let mut b: Vec<u64> = a
            .iter()
            .map(|r| r.iter().zip(&x).map(|(u, v)| u * v).sum::<u64>() % 101)
            .collect();
        lu.solve_in_place(&mut b, &mut Vec::new());
        assert_eq!(b, x);
        // det A = -5: singular modulo 5, refused.
        assert!(ModularLu::factor(3, &rows, Modulus::new(5)).is_none());
    }
}
