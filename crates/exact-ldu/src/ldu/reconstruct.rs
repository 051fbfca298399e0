//! The factors as matrices, and the product they reconstruct (invariant I1, thesis (4.1)).
//!
//! ```text
//! A[row_perm[k]][col_perm[c]] = Σ_{j ≤ min(k, r−1)} L[k][j] · U[j][c] / D[j]
//! ```

use super::Ldu;
use crate::ring::Ring;
use api::Rational as BigRational;
use num_bigint::BigInt;
use num_traits::Zero;

impl<R: Ring> Ldu<R> {
    /// Largest bit size among the entries of `L`, `D` and `U` (the quantity of thesis figures
    /// 7.1–7.4).
    pub fn max_entry_bits(&self) -> u64 {
        self.l
            .iter()
            .flatten()
            .chain(self.d.iter())
            .chain(self.u.iter().flatten())
            .map(Ring::bits)
            .max()
            .unwrap_or(0)
    }

    /// `Π_R L D⁻¹ U Π_C` computed with rationals: equals `A` exactly (invariant I1).
    ///
    /// # Complexity
    /// `O(m r n)` rational operations.
    pub fn reconstruct(&self) -> Vec<Vec<BigRational>> {
        let mut out = vec![vec![BigRational::zero(); self.cols]; self.rows];
        for k in 0..self.rows {
            for (j, lkj) in self.l[k].iter().enumerate() {
                if lkj.is_zero() {
                    continue;
                }
                let coeff = BigRational::new(lkj.to_bigint(), self.d[j].to_bigint());
                for c in 0..self.cols {
                    let ujc = &self.u[j][c];
                    if !ujc.is_zero() {
                        out[self.row_perm[k]][self.col_perm[c]] +=
                            &coeff * BigRational::from_integer(ujc.to_bigint());
                    }
                }
            }
        }
        out
    }

    /// Dense `L` (`m × r`), `D` (diagonal) and `U` (`r × n`) as big integers, rows of `L` in
    /// `Π_R` order and columns of `U` in `Π_C` order, as printed in the thesis.
    pub fn dense_factors(&self) -> (Vec<Vec<BigInt>>, Vec<BigInt>, Vec<Vec<BigInt>>) {
        let l = self
            .l
            .iter()
            .map(|row| {
                let mut dense = vec![BigInt::from(0); self.rank];
                for (j, v) in row.iter().enumerate() {
                    dense[j] = v.to_bigint();
                }
                dense
            })
            .collect();
        let d = self.d.iter().map(Ring::to_bigint).collect();
        let u = self
            .u
            .iter()
            .map(|row| row.iter().map(Ring::to_bigint).collect())
            .collect();
        (l, d, u)
    }
}

#[cfg(test)]
mod tests {
    use super::super::factor::tests::matrix_4_3;
    use super::super::Simplification;
    use super::*;
    use api::Rational;

    #[test]
    fn the_factors_of_4_3_reconstruct_it() {
        let a = backend_contract::thesis::matrix_4_3().to_dense();
        let a: Vec<Vec<Rational>> = a
            .into_iter()
            .map(|r| r.into_iter().map(Rational::from_integer).collect())
            .collect();
        let (rows, cols) = matrix_4_3();
        let ldu = Ldu::factor(rows, cols, Simplification::Turner).expect("rectangular");
        assert_eq!(ldu.reconstruct(), a);
        let (l, d, u) = ldu.dense_factors();
        assert_eq!(
            (l.len(), l[0].len(), d.len(), u.len(), u[0].len()),
            (5, 3, 3, 3, 4)
        );
        // The largest entry of the printed factors is −164 (8 bits).
        assert_eq!(ldu.max_entry_bits(), 8);
        let bits = l
            .iter()
            .flatten()
            .chain(&d)
            .chain(u.iter().flatten())
            .map(BigInt::bits)
            .max();
        assert_eq!(bits, Some(ldu.max_entry_bits()));
    }
}
