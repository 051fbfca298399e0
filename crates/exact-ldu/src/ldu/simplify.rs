//! Algorithms 9–13 (thesis 6.4, chapter 7): removing common factors during the factoring.
//!
//! ```text
//! L_tt U_t = (L_tt g) (U_t / g)          rows of U   (algorithms 9, 11, 13)
//! L_ti / D_ii = (L_ti / g) / (D_ii / g)  columns of L (algorithms 10, 12)
//! ```
//!
//! Each step rewrites a product that invariant I1 contains without changing it. `None` removes
//! nothing (plain fraction-free elimination, thesis 7.1: entries double in size every stage);
//! `Gcd` divides each new row of `U` by its content and each column of `L` with `D_ii` by
//! theirs (7.2); `Turner` divides each new row by the previous pivot, which Bareiss and Turner
//! showed divides it exactly, and the common `D_tt` with it (7.3).

use super::Simplification;
use crate::ring::{gcd_all, Ring};

/// Algorithm 9 (`LinSys.SimplifyURow`, thesis 6.4): removes common factors from the new row
/// `t` (its entries after the pivot column, `tail`) with the chosen method:
///
/// * `None`: nothing (the None step: plain fraction-free elimination, thesis 7.1);
/// * `Gcd`: [`simplify_u_row_gcd`] (algorithm 11);
/// * `Turner`: [`simplify_u_row_turner`] (algorithm 13) by `previous_pivot` `U_{i−1,i−1}`,
///   from the second stage on (`None` at the first).
///
/// The factoring's GCD method eliminates and simplifies in one pass
/// ([`super::eliminate::eliminate_variable_gcd`]); this dispatch is what that pass equals.
#[inline]
pub(super) fn simplify_u_row<R: Ring>(
    method: Simplification,
    tail: &mut [R],
    l_tt: &mut R,
    previous_pivot: Option<&R>,
) {
    match method {
        Simplification::None => {}
        Simplification::Gcd => {
            simplify_u_row_gcd(tail, l_tt);
        }
        Simplification::Turner => {
            if let Some(divisor) = previous_pivot {
                simplify_u_row_turner(tail, divisor);
            }
        }
    }
}

/// Algorithm 10 (`LinSys.SimplifyLColumn`, thesis 6.4): with the GCD method,
/// [`simplify_l_column_gcd`] on column `i` of `L` (rows `l_rows`, from row `i` on) and `D_ii`;
/// nothing with `None` and `Turner`.
#[inline]
pub(super) fn simplify_l_column<R: Ring>(
    method: Simplification,
    l_rows: &mut [Vec<R>],
    i: usize,
    d_ii: &mut R,
) {
    if method == Simplification::Gcd {
        simplify_l_column_gcd(l_rows, i, d_ii);
    }
}

/// Algorithm 11 (`LinSys.SimplifyURowGCD`, thesis 7.2): divides the row `tail` by the GCD of
/// its entries and multiplies that factor into `L_tt`, so `L_tt U_t` is unchanged.
///
/// # Returns
/// Whether the row is nonzero (and now primitive).
///
/// # Complexity
/// One GCD pass and, when the GCD is not 1, one exact division per entry.
pub(super) fn simplify_u_row_gcd<R: Ring>(tail: &mut [R], l_tt: &mut R) -> bool {
    let g = divide_out_content(tail);
    if g.is_zero() {
        return false;
    }
    if !g.is_one() {
        *l_tt = l_tt.mul(&g);
    }
    true
}

/// Divides `values` by their content `g = gcd(values) ≥ 0` (nothing when `g` is 0 or 1) and
/// returns `g`: the division step of algorithm 11, shared with the fused GCD elimination.
#[inline]
pub(super) fn divide_out_content<R: Ring>(values: &mut [R]) -> R {
    let g = gcd_all(values);
    if !g.is_zero() && !g.is_one() {
        for v in values.iter_mut().filter(|v| !v.is_zero()) {
            *v = v.div_exact(&g);
        }
    }
    g
}

/// Algorithm 11 applied to every row before the first stage (the GCD method; the thesis'
/// algorithm 6 step 7 simplifies only the first pivot row there, and every other row after its
/// first elimination). Starting from primitive rows makes the pivots chosen inside one connected
/// component independent of the other components, so block-wise factoring equals one
/// factoring (ARCHITECTURE.md, "Decisions"); the thesis' examples come out unchanged.
///
/// `primitive[t]` becomes true for every nonzero row.
pub(super) fn make_rows_primitive<R: Ring>(
    u: &mut [Vec<R>],
    l_diag: &mut [R],
    primitive: &mut [bool],
) {
    for ((row, l_tt), is_primitive) in u.iter_mut().zip(l_diag).zip(primitive) {
        if simplify_u_row_gcd(row, l_tt) {
            *is_primitive = true;
        }
    }
}

/// Algorithm 12 (`LinSys.SimplifyLColumnGCD`, thesis 7.2): divides column `i` of `L` (rows
/// `l_rows`, from row `i` on) and `D_ii` by their GCD, so every `L_ti / D_ii` is unchanged.
/// The GCD search stops as soon as it reaches 1.
///
/// # Complexity
/// At most `m − i` GCDs and divisions.
pub(super) fn simplify_l_column_gcd<R: Ring>(l_rows: &mut [Vec<R>], i: usize, d_ii: &mut R) {
    let mut g = d_ii.abs();
    for row in l_rows.iter() {
        if g.is_one() {
            break;
        }
        g = g.gcd(&row[i]);
    }
    if !g.is_one() && !g.is_zero() {
        *d_ii = d_ii.div_exact(&g);
        for row in l_rows.iter_mut() {
            row[i] = row[i].div_exact(&g);
        }
    }
}

/// Algorithm 13 (`LinSys.SimplifyURowTurner`, thesis 7.3), steps 2–4: divides the new row
/// `tail` exactly by the previous pivot `U_{i−1,i−1}` (Bareiss: after eliminating column `i`
/// every entry of the remaining rows is a multiple of it). Step 5 is [`simplify_d_turner`].
///
/// # Complexity
/// One exact division per entry.
#[inline]
pub(super) fn simplify_u_row_turner<R: Ring>(tail: &mut [R], previous_pivot: &R) {
    for v in tail.iter_mut() {
        *v = v.div_exact(previous_pivot);
    }
}

/// Algorithm 13 step 5, corrected: `D_tt ← D_tt / U_{i−1,i−1}`, so that `L_tt U_t / D_tt` is
/// unchanged when the row was divided by `U_{i−1,i−1}`. The thesis prints
/// `D_tt ← U_tt / U_{i−1,i−1}`, a slip (ARCHITECTURE.md, "Decisions"; the seeds' README). The
/// factoring applies it once per stage to the `D_tt` all uneliminated rows share; afterwards
/// that value is the pivot `U_ii` (Bareiss), which is how the printed `D` of (4.3) comes out.
#[inline]
pub(super) fn simplify_d_turner<R: Ring>(d_tt: &R, previous_pivot: &R) -> R {
    d_tt.div_exact(previous_pivot)
}

#[cfg(test)]
mod tests {
    use super::super::factor::tests::{ints, matrix_4_3, turner_matrix};
    use super::super::factor::WorkingFactors;
    use super::super::Pivoting;
    use super::*;
    use crate::ring::Int;
    use api::Rational;
    use proptest::prelude::*;

    fn int(v: i64) -> Int {
        Int::from_i64(v)
    }

    /// `l_tt · row` entry by entry.
    fn scaled(l_tt: &Int, row: &[Int]) -> Vec<Int> {
        row.iter().map(|v| v.mul(l_tt)).collect()
    }

    #[test]
    fn the_gcd_rows_of_the_first_stage_of_turners_example() {
        // Thesis 7.2: the rows of the first stage (7.1) divided by their GCDs 20, 2 and 12.
        let stage = ints(&[vec![20, 40, 20], vec![-18, 8, 42], vec![12, 48, 12]]);
        let want = ints(&[vec![1, 2, 1], vec![-9, 4, 21], vec![1, 4, 1]]);
        for ((row, want), g) in stage.into_iter().zip(want).zip([20, 2, 12]) {
            let mut row = row;
            let mut l_tt = int(1);
            assert!(simplify_u_row_gcd(&mut row, &mut l_tt));
            assert_eq!((row, l_tt), (want, int(g)));
        }
        let mut zero = ints(&[vec![0, 0]]).remove(0);
        let mut l_tt = int(3);
        assert!(!simplify_u_row_gcd(&mut zero, &mut l_tt));
        assert_eq!(l_tt, int(3));
    }

    #[test]
    fn the_turner_rows_of_the_second_stage_of_turners_example() {
        // Thesis 7.3: (880, 1200) and (480, 0) divided by the previous pivot 8.
        let mut rows = ints(&[vec![880, 1200], vec![480, 0]]);
        for row in rows.iter_mut() {
            simplify_u_row_turner(row, &int(8));
        }
        assert_eq!(rows, ints(&[vec![110, 150], vec![60, 0]]));
        assert_eq!(simplify_d_turner(&int(160), &int(8)), int(20));
    }

    #[test]
    fn the_none_step_and_the_dispatch() {
        let row = ints(&[vec![4, 6]]).remove(0);
        let mut none = row.clone();
        let mut l_tt = int(1);
        simplify_u_row(Simplification::None, &mut none, &mut l_tt, Some(&int(2)));
        assert_eq!((&none, &l_tt), (&row, &int(1)));
        let mut turner = row.clone();
        simplify_u_row(Simplification::Turner, &mut turner, &mut l_tt, None);
        assert_eq!(turner, row, "no division at the first stage");
        simplify_u_row(
            Simplification::Turner,
            &mut turner,
            &mut l_tt,
            Some(&int(2)),
        );
        assert_eq!((turner, &l_tt), (ints(&[vec![2, 3]]).remove(0), &int(1)));
        let mut gcd = row.clone();
        simplify_u_row(Simplification::Gcd, &mut gcd, &mut l_tt, None);
        assert_eq!((gcd, l_tt), (ints(&[vec![2, 3]]).remove(0), int(2)));

        let mut l = vec![ints(&[vec![4]]).remove(0), ints(&[vec![6]]).remove(0)];
        let mut d = int(8);
        for method in [Simplification::None, Simplification::Turner] {
            simplify_l_column(method, &mut l, 0, &mut d);
            assert_eq!(
                (l[0][0].clone(), l[1][0].clone(), d.clone()),
                (int(4), int(6), int(8))
            );
        }
        simplify_l_column(Simplification::Gcd, &mut l, 0, &mut d);
        assert_eq!(
            (l[0][0].clone(), l[1][0].clone(), d),
            (int(2), int(3), int(4))
        );
    }

    /// With the corrected step 5 the common `D_tt` equals the pivot after every Turner stage,
    /// and `D_ii = U_{i−1,i−1} U_ii`: the printed `D = diag(−1, −1, −80)` of (4.3).
    #[test]
    fn turners_d_is_the_product_of_consecutive_pivots() {
        for (rows, cols) in [matrix_4_3(), turner_matrix()] {
            let mut w = WorkingFactors::new(rows, cols);
            let a = w.product();
            while w.i < w.rows() && w.pivot(Pivoting::SmallestMagnitude) {
                w.take_pivot();
                w.eliminate_below_pivot(Simplification::Turner);
                let i = w.i;
                assert_eq!(w.pending_d, w.u[i][i]);
                let previous = if i == 0 {
                    int(1)
                } else {
                    w.u[i - 1][i - 1].clone()
                };
                assert_eq!(w.d[i], previous.mul(&w.u[i][i]));
                assert_eq!(w.product(), a);
                w.i += 1;
            }
        }
        let (rows, cols) = matrix_4_3();
        let ldu = super::super::factor::ldu_factor(
            rows,
            cols,
            Simplification::Turner,
            Pivoting::SmallestMagnitude,
            None,
        );
        assert_eq!(ldu.d(), &[int(-1), int(-1), int(-80)]);
    }

    fn row() -> impl Strategy<Value = Vec<i64>> {
        prop::collection::vec(prop_oneof![-30i64..=30, Just(0)], 0..=6)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        /// Algorithm 11: `L_tt U_t` unchanged, the row primitive (or zero).
        #[test]
        fn the_gcd_row_step_keeps_l_tt_times_the_row(values in row(), l_tt in -5i64..=5) {
            let before = ints(&[values]).remove(0);
            let mut row = before.clone();
            let mut l = int(l_tt);
            let nonzero = simplify_u_row_gcd(&mut row, &mut l);
            prop_assert_eq!(scaled(&l, &row), scaled(&int(l_tt), &before));
            prop_assert_eq!(nonzero, before.iter().any(|v| !v.is_zero()));
            let g = gcd_all(&row);
            let reduced = if nonzero { g.is_one() } else { g.is_zero() };
            prop_assert!(reduced);
        }

        /// Algorithm 11 on every row: flags tell exactly the nonzero rows.
        #[test]
        fn making_rows_primitive(rows in prop::collection::vec(row(), 0..=4)) {
            let mut u = ints(&rows);
            let mut l_diag = vec![int(1); u.len()];
            let mut primitive = vec![false; u.len()];
            make_rows_primitive(&mut u, &mut l_diag, &mut primitive);
            for (k, original) in ints(&rows).iter().enumerate() {
                prop_assert_eq!(scaled(&l_diag[k], &u[k]), original.clone());
                prop_assert_eq!(primitive[k], gcd_all(&u[k]).is_one());
            }
        }

        /// Algorithm 12: every `L_ti / D_ii` unchanged, and no common factor is left.
        #[test]
        fn the_gcd_column_step_keeps_the_ratios(
            column in prop::collection::vec(-40i64..=40, 1..=5),
            d in prop_oneof![-60i64..=-1, 1i64..=60],
        ) {
            let mut l: Vec<Vec<Int>> = column.iter().map(|&v| vec![int(0), int(v)]).collect();
            let mut d_ii = int(d);
            simplify_l_column_gcd(&mut l, 1, &mut d_ii);
            let ratio = |num: &Int, den: &Int| Rational::new(num.to_bigint(), den.to_bigint());
            for (row, &v) in l.iter().zip(&column) {
                prop_assert_eq!(ratio(&row[1], &d_ii), ratio(&int(v), &int(d)));
                prop_assert!(row[0].is_zero());
            }
            let g = l.iter().fold(d_ii.abs(), |g, row| g.gcd(&row[1]));
            prop_assert!(g.is_one());
        }

        /// Algorithm 13: the row times the previous pivot is the row before.
        #[test]
        fn the_turner_row_step_divides_exactly(values in row(), divisor in prop_oneof![-9i64..=-1, 1i64..=9]) {
            let before: Vec<Int> = ints(&[values]).remove(0).iter().map(|v| v.mul(&int(divisor))).collect();
            let mut row = before.clone();
            simplify_u_row_turner(&mut row, &int(divisor));
            prop_assert_eq!(scaled(&int(divisor), &row), before);
        }
    }
}
