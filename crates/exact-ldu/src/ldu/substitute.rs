//! Forward and backward substitution on a factoring (thesis 8.1, algorithm 14 steps 2–3).
//!
//! ```text
//! A x = b  ⇔  L D⁻¹ y = Π_R⁻¹ b,  U (Π_C x) = y
//! L̂ z = b̂,   y = D z   (8.5);    b̃ − L̃ z = 0   (8.10);    Û x̂ = y − Ũ x̃   (8.7)
//! ```
//!
//! Every vector is a [`QVec`]: integer numerators over one common denominator, so the
//! substitutions run on integers and divide each new entry only once.

use super::Ldu;
use crate::qvec::QVec;
use crate::ring::Ring;

impl<R: Ring> Ldu<R> {
    /// Forward substitution on a right-hand side given in `Π_R` order (length `m`): afterwards
    /// entries `0..r` hold `z = L̂⁻¹ b̂` and entries `r..m` the residuals `b̃ − L̃ z`, all over
    /// the common denominator. The system is consistent exactly when the residuals vanish
    /// (weak solvability, thesis (8.10)); `D z` is the `Y` of (8.5).
    ///
    /// # Complexity
    /// `O(m r)` ring operations.
    pub fn forward(&self, b: &mut QVec<R>) {
        debug_assert_eq!(b.num.len(), self.rows);
        for k in 0..self.rank {
            let row = &self.l[k];
            let mut s = b.num[k].clone();
            for (j, lkj) in row.iter().enumerate().take(k) {
                if !lkj.is_zero() && !b.num[j].is_zero() {
                    s = s.sub(&lkj.mul(&b.num[j]));
                }
            }
            b.divide_entry(k, s, &row[k]);
        }
        for t in self.rank..self.rows {
            let mut s = b.num[t].clone();
            for (j, ltj) in self.l[t].iter().enumerate() {
                if !ltj.is_zero() && !b.num[j].is_zero() {
                    s = s.sub(&ltj.mul(&b.num[j]));
                }
            }
            b.num[t] = s;
        }
    }

    /// Back substitution `Û x̂ = y` in place (`y` of length `r`, permuted column order): step 3
    /// of algorithm 14, (8.8).
    ///
    /// # Complexity
    /// `O(r²)` ring operations.
    pub fn backward(&self, y: &mut QVec<R>) {
        debug_assert_eq!(y.num.len(), self.rank);
        for k in (0..self.rank).rev() {
            let row = &self.u[k];
            let mut s = y.num[k].clone();
            for (j, ukj) in row.iter().enumerate().take(self.rank).skip(k + 1) {
                if !ukj.is_zero() && !y.num[j].is_zero() {
                    s = s.sub(&ukj.mul(&y.num[j]));
                }
            }
            y.divide_entry(k, s, &row[k]);
        }
    }

    /// The coefficients `w` with `row t of Π_R⁻¹A = Σ_k w_k · row k` for a redundant position
    /// `t ≥ r`, i.e. row `t` of `L̃ L̂⁻¹` (thesis 4.3, (8.10)), over a common denominator:
    /// the solution of `L̂ᵀ w = l_t`.
    ///
    /// Solved column by column of `L̂ᵀ` (row by row of `L̂`, from the last unknown to the
    /// first): once `w_k` is known, row `k` of `L̂` is subtracted from the pending entries, and an
    /// unknown that stays zero costs nothing. A dependency involves few rows, so this touches
    /// only those, where a dot product per unknown would read the whole triangle.
    ///
    /// # Complexity
    /// `O(Σ_{k: w_k ≠ 0} |row k of L̂|)` ring operations plus the rescaling of nonzero entries.
    pub fn redundancy_weights(&self, t: usize) -> QVec<R> {
        debug_assert!(t >= self.rank && t < self.rows);
        let mut w = QVec::from_integers(self.l[t].clone());
        for k in (0..self.rank).rev() {
            if w.num[k].is_zero() {
                continue;
            }
            let s = w.num[k].clone();
            w.divide_entry(k, s, &self.l[k][k]);
            let wk = w.num[k].clone();
            for (j, lkj) in self.l[k][..k].iter().enumerate() {
                if !lkj.is_zero() {
                    w.num[j] = w.num[j].sub(&lkj.mul(&wk));
                }
            }
        }
        w
    }
}

#[cfg(test)]
mod tests {
    use super::super::factor::tests::{ints, matrix_4_3};
    use super::super::Simplification;
    use super::*;
    use crate::ring::Int;
    use api::Rational;
    use proptest::prelude::*;

    const METHODS: [Simplification; 3] = [
        Simplification::None,
        Simplification::Gcd,
        Simplification::Turner,
    ];

    fn rationals(v: &QVec<Int>) -> Vec<Rational> {
        v.num
            .iter()
            .map(|n| Rational::new(n.to_bigint(), v.den.to_bigint()))
            .collect()
    }

    fn l_entry(ldu: &Ldu<Int>, k: usize, j: usize) -> Rational {
        ldu.l_row(k)
            .get(j)
            .map_or(Rational::from_integer(0.into()), |v| {
                Rational::from_integer(v.to_bigint())
            })
    }

    /// `L̂ z = b̂` on the first `r` entries and `b̃ − L̃ z` on the rest.
    fn check_forward(ldu: &Ldu<Int>, b: &[i64]) {
        let mut v = QVec::from_integers(b.iter().map(|&x| Int::from_i64(x)).collect());
        ldu.forward(&mut v);
        let z = rationals(&v);
        let r = ldu.rank();
        for (k, &bk) in b.iter().enumerate() {
            let lz: Rational = (0..r.min(k + 1)).map(|j| l_entry(ldu, k, j) * &z[j]).sum();
            let want = Rational::from_integer(bk.into());
            if k < r {
                assert_eq!(lz, want, "row {k} of L̂ z = b̂");
            } else {
                assert_eq!(&z[k], &(want - lz), "residual of row {k}");
            }
        }
    }

    /// `Û x̂ = y`.
    fn check_backward(ldu: &Ldu<Int>, y: &[i64]) {
        let mut v = QVec::from_integers(y.iter().map(|&x| Int::from_i64(x)).collect());
        ldu.backward(&mut v);
        let x = rationals(&v);
        for (k, &yk) in y.iter().enumerate() {
            let ux: Rational = (k..ldu.rank())
                .map(|j| Rational::from_integer(ldu.u_row(k)[j].to_bigint()) * &x[j])
                .sum();
            assert_eq!(ux, Rational::from_integer(yk.into()));
        }
    }

    /// Row `t` of `L` is `Σ_k w_k` row `k` of `L̂` (so the same holds for the rows of `A`).
    fn check_weights(ldu: &Ldu<Int>) {
        for t in ldu.rank()..ldu.rows() {
            let w = rationals(&ldu.redundancy_weights(t));
            for j in 0..ldu.rank() {
                let combined: Rational = (0..ldu.rank()).map(|k| &w[k] * l_entry(ldu, k, j)).sum();
                assert_eq!(combined, l_entry(ldu, t, j));
            }
        }
    }

    fn small(values: &[Rational]) -> Vec<i64> {
        values
            .iter()
            .map(|v| i64::try_from(v.to_integer()).expect("small integers"))
            .collect()
    }

    #[test]
    fn substitutions_on_the_factoring_of_4_3() {
        let b = small(&backend_contract::thesis::rhs_8_17());
        for method in METHODS {
            let (rows, cols) = matrix_4_3();
            let ldu = Ldu::factor(rows, cols, method).expect("rectangular");
            // (8.18): Π_R⁻¹ B of (8.17); both residuals vanish (8.19).
            let permuted: Vec<i64> = ldu.row_perm().iter().map(|&i| b[i]).collect();
            check_forward(&ldu, &permuted);
            let mut v = QVec::from_integers(permuted.iter().map(|&x| Int::from_i64(x)).collect());
            ldu.forward(&mut v);
            assert!(v.num[3].is_zero() && v.num[4].is_zero());
            // (8.20)–(8.21): Û X̂ = Y.
            check_backward(&ldu, &small(&backend_contract::thesis::y_8_20()));
            check_weights(&ldu);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]

        #[test]
        fn substitutions_solve_their_triangular_systems(
            (cols, rows) in (0usize..=5, 0usize..=5).prop_flat_map(|(m, n)| (
                Just(n),
                prop::collection::vec(prop::collection::vec(-4i64..=4, n), m),
            )),
            rhs in prop::collection::vec(-9i64..=9, 5),
        ) {
            for method in METHODS {
                let ldu = Ldu::factor(ints(&rows), cols, method).expect("rectangular");
                check_forward(&ldu, &rhs[..rows.len()]);
                check_backward(&ldu, &rhs[..ldu.rank()]);
                check_weights(&ldu);
            }
        }
    }
}
