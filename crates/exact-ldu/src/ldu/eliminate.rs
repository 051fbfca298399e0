//! Algorithm 8 (`LinSys.EliminateVariable`, thesis 6.3): row `t` of `U` loses its entry in the
//! pivot column `i`.
//!
//! ```text
//! L_ti ← L_tt U_ti,   D_tt ← D_tt U_ii,   U_ts ← U_ii U_ts − U_ti U_is  (s > i),   U_ti ← 0
//! ```
//!
//! Row `t` of `Π_R⁻¹ A Π_C⁻¹` is `Σ_{k<i} L_tk U_k / D_kk + L_tt U_t / D_tt` before; after, the
//! new terms `L_ti U_i / D_ii + L_tt (U_ii U_t − U_ti U_i) / (D_tt U_ii)` add up to the old
//! `L_tt U_t / D_tt` because `D_ii = D_tt U_ii` (step 9 of algorithm 6 scaled the common value):
//! invariant I1 holds row by row. `D_tt` is shared by every uneliminated row, so the caller
//! multiplies it once per stage.

use super::simplify::divide_out_content;
use crate::ring::Ring;

/// Algorithm 8 (`LinSys.EliminateVariable`, thesis 6.3) on working row `row` with the pivot row
/// `pivot_row` of stage `i`, without simplification: `L_ti ← L_tt U_ti` is appended to `l_row`,
/// `U_ts ← U_ii U_ts − U_ti U_is` for `s > i`, `U_ti ← 0`. Step 3, `D_tt ← D_tt U_ii`, is the
/// caller's (one value for all rows).
///
/// # Complexity
/// `n − i − 1` cross multiplications.
#[inline]
pub(super) fn eliminate_variable<R: Ring>(
    row: &mut [R],
    pivot_row: &[R],
    pivot: &R,
    i: usize,
    l_row: &mut Vec<R>,
    l_tt: &R,
) {
    let uti = std::mem::replace(&mut row[i], R::zero());
    l_row.push(l_tt.mul(&uti));
    for s in i + 1..row.len() {
        row[s] = R::mul_sub(pivot, &row[s], &uti, &pivot_row[s]);
    }
}

/// Algorithm 8 followed by algorithm 11 (`LinSys.SimplifyURowGCD`), in one pass: the GCD
/// method's elimination of column `i` from `row`, with the same results as
/// [`eliminate_variable`] then [`super::simplify::simplify_u_row_gcd`] (unit tested) and two
/// shortcuts:
///
/// * the multipliers are divided by `h = gcd(U_ii, U_ti)` first,
///   `U_ts ← (U_ii/h) U_ts − (U_ti/h) U_is`, and `h` goes into `L_tt` together with the row's
///   GCD (the row GCD of the plain step would contain `h` anyway);
/// * a row with `U_ti = 0` that is already primitive (`primitive`, kept by the GCD method:
///   every row starts primitive) is only negated when `U_ii < 0`, and `L_tt ← L_tt |U_ii|`,
///   instead of being multiplied by `U_ii` and divided back.
///
/// Afterwards `primitive` tells whether the new row is primitive (false only for a zero row).
///
/// `negated` says that `row` is stored as its negative (the value is `−row`): a row that is not
/// eliminated and only changes sign under a negative pivot has its flag flipped instead of every
/// entry rewritten, so a stage costs nothing for the many rows a sparse pivot column misses.
/// A stored-negated row that must be eliminated is first turned back ([`materialize`]).
///
/// # Complexity
/// `n − i − 1` cross multiplications and one GCD pass over the new row; `O(1)` for a primitive
/// row with `U_ti = 0`.
#[inline]
#[allow(clippy::too_many_arguments)]
pub(super) fn eliminate_variable_gcd<R: Ring>(
    row: &mut [R],
    pivot_row: &[R],
    pivot: &R,
    i: usize,
    l_row: &mut Vec<R>,
    l_tt: &mut R,
    primitive: &mut bool,
    negated: &mut bool,
) {
    if !row[i].is_zero() {
        materialize(row, negated);
    }
    let uti = std::mem::replace(&mut row[i], R::zero());
    l_row.push(l_tt.mul(&uti));
    let tail = &mut row[i + 1..];
    if uti.is_zero() {
        if *primitive {
            if pivot.is_negative() {
                *negated = !*negated;
            }
            *l_tt = l_tt.mul(&pivot.abs());
            return;
        }
        let g = divide_out_content(tail);
        if g.is_zero() {
            return;
        }
        if pivot.is_negative() {
            *negated = !*negated;
        }
        *l_tt = l_tt.mul(&pivot.abs().mul(&g));
        *primitive = true;
        return;
    }
    let h = pivot.gcd(&uti);
    let a = pivot.div_exact(&h);
    let b = uti.div_exact(&h);
    for (v, p) in tail.iter_mut().zip(&pivot_row[i + 1..]) {
        // Where the pivot row is zero the entry is only scaled by `a` (often 1, and most
        // entries of a constraint row are zero).
        if p.is_zero() {
            if !v.is_zero() && !a.is_one() {
                *v = v.mul(&a);
            }
        } else {
            *v = R::mul_sub(&a, v, &b, p);
        }
    }
    let g = divide_out_content(tail);
    if g.is_zero() {
        *primitive = false;
        return;
    }
    *l_tt = l_tt.mul(&h.mul(&g));
    *primitive = true;
}

/// Stores a row flagged as negated ([`eliminate_variable_gcd`]) with its true entries.
pub(super) fn materialize<R: Ring>(row: &mut [R], negated: &mut bool) {
    if *negated {
        negate_nonzero(row);
        *negated = false;
    }
}

/// `row ← −row`, touching only the nonzero entries (rows of constraint systems are mostly zero,
/// and a negative pivot negates every row it does not eliminate).
fn negate_nonzero<R: Ring>(row: &mut [R]) {
    for v in row.iter_mut().filter(|v| !v.is_zero()) {
        *v = v.neg();
    }
}

#[cfg(test)]
mod tests {
    use super::super::factor::tests::{ints, matrix_4_3, turner_matrix};
    use super::super::factor::WorkingFactors;
    use super::super::simplify::{make_rows_primitive, simplify_u_row_gcd};
    use super::super::Pivoting;
    use super::*;
    use crate::ring::{gcd_all, Int};
    use proptest::prelude::*;

    /// Stage 0 of `rows` up to step 9, then [`eliminate_variable`] on row `t` alone: the row is
    /// zero in the pivot column and I1 holds with `D_tt · U_ii` for that row.
    fn eliminate_one_row(rows: Vec<Vec<Int>>, cols: usize, t: usize) {
        let mut w = WorkingFactors::new(rows, cols);
        let a = w.product();
        if !w.pivot(Pivoting::SmallestMagnitude) || t == 0 || t >= w.rows() {
            return;
        }
        w.take_pivot();
        let pivot = w.u[0][0].clone();
        let (head, tail) = w.u.split_at_mut(1);
        eliminate_variable(
            &mut tail[t - 1],
            &head[0],
            &pivot,
            0,
            &mut w.l[t],
            &w.l_diag[t],
        );
        assert!(w.u[t][0].is_zero());
        let d_t = w.pending_d.mul(&pivot);
        let product = w.product_with(|k| {
            if k == t {
                d_t.clone()
            } else {
                w.pending_d.clone()
            }
        });
        assert_eq!(product, a);
    }

    #[test]
    fn eliminating_a_row_of_the_thesis_matrices_keeps_the_factoring() {
        for t in 1..5 {
            let (rows, cols) = matrix_4_3();
            eliminate_one_row(rows, cols, t);
        }
        for t in 1..4 {
            let (rows, cols) = turner_matrix();
            eliminate_one_row(rows, cols, t);
        }
    }

    #[test]
    fn the_first_stage_of_turners_example_is_plain_elimination() {
        // Thesis 7.1: row (4, 6, 7, 3) against the pivot row (8, 7, 4, 1) becomes (0, 20, 40, 20).
        let pivot_row = ints(&[vec![8, 7, 4, 1]]).remove(0);
        let mut row = ints(&[vec![4, 6, 7, 3]]).remove(0);
        let mut l_row = Vec::new();
        eliminate_variable(
            &mut row,
            &pivot_row,
            &Int::from_i64(8),
            0,
            &mut l_row,
            &Int::from_i64(1),
        );
        assert_eq!(row, ints(&[vec![0, 20, 40, 20]]).remove(0));
        assert_eq!(l_row, vec![Int::from_i64(4)]);
    }

    fn row_pair() -> impl Strategy<Value = (Vec<i64>, Vec<i64>, bool)> {
        (1usize..=6).prop_flat_map(|n| {
            (
                prop::collection::vec(prop_oneof![-12i64..=12, Just(0)], n),
                prop::collection::vec(prop_oneof![-12i64..=12, Just(0)], n),
                any::<bool>(),
            )
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        /// I1 row by row on random matrices.
        #[test]
        fn elimination_keeps_the_factoring(
            rows in prop::collection::vec(prop::collection::vec(-5i64..=5, 4), 1..=5),
            t in 1usize..5,
        ) {
            eliminate_one_row(ints(&rows), 4, t);
        }

        /// The fused GCD step equals algorithm 8 followed by algorithm 11 (row, `L_ti`, `L_tt`),
        /// for primitive rows (as the GCD method keeps them) and others.
        #[test]
        fn the_gcd_shortcuts_equal_the_plain_steps(
            (pivot_row, row, make_primitive) in row_pair(),
            l_tt in 1i64..=6,
        ) {
            let mut pivot_row = ints(&[pivot_row]).remove(0);
            if pivot_row[0].is_zero() {
                pivot_row[0] = Int::from_i64(-3);
            }
            let mut rows = vec![ints(&[row]).remove(0)];
            let mut l_diag = vec![Int::from_i64(l_tt)];
            let mut primitive = vec![false];
            if make_primitive {
                make_rows_primitive(&mut rows, &mut l_diag, &mut primitive);
            }
            let pivot = pivot_row[0].clone();

            let mut plain = rows[0].clone();
            let mut plain_l = Vec::new();
            let mut plain_l_tt = l_diag[0].clone();
            eliminate_variable(&mut plain, &pivot_row, &pivot, 0, &mut plain_l, &plain_l_tt);
            let plain_primitive = simplify_u_row_gcd(&mut plain[1..], &mut plain_l_tt);

            let mut fused = rows[0].clone();
            let mut fused_l = Vec::new();
            let mut fused_l_tt = l_diag[0].clone();
            let mut fused_primitive = primitive[0];
            let mut fused_negated = false;
            eliminate_variable_gcd(&mut fused, &pivot_row, &pivot, 0, &mut fused_l, &mut fused_l_tt, &mut fused_primitive, &mut fused_negated);
            materialize(&mut fused, &mut fused_negated);

            prop_assert_eq!(&fused, &plain);
            prop_assert_eq!(&fused_l, &plain_l);
            prop_assert_eq!(&fused_l_tt, &plain_l_tt);
            prop_assert_eq!(fused_primitive, plain_primitive);
            let g = gcd_all(&fused[1..]);
            prop_assert!(g.is_zero() || g.is_one());
        }
    }
}
