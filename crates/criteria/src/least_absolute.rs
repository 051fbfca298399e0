//! The least absolute change (L1): `min Σ w_j |y_j|` subject to `M y = t`, exactly.
//!
//! Split `y = u − v` with `u, v ≥ 0` and minimise `Σ w_j (u_j + v_j)`: a linear program in
//! standard form. Its starting basis needs no phase 1: the Gauss–Jordan form of `[M | t]`
//! has a unit pivot column per independent row; the row's pivot variable is `u_p` when its
//! right-hand side is not negative, else `v_p` after the row is negated. The simplex then ends
//! at an optimal vertex (Bland's rule, see [`crate::simplex`]).
//!
//! **Which optimum.** L1 optima are often not unique (Brenner, figure 3(g)). The one returned
//! is the vertex the simplex ends at from that starting basis with the columns in the
//! problem's order (`u_0 … u_{n−1}, v_0 … v_{n−1}`): a function of the problem alone,
//! reproducible. A vertex is also the sparsest kind of optimum: at most `rank M` changes are
//! nonzero.
//!
//! **How many optima.** The set of optima is the optimal face. With the final reduced costs,
//! a feasible `(u, v)` is optimal exactly when it is zero on every column of positive reduced
//! cost (complementary slackness holds with the final dual for any optimal point, so this is
//! the whole face, not part of it). The columns that can be positive somewhere on the face are
//! found by maximising each remaining one over the face, each time from the current basis
//! (still feasible: the face is the problem with the other columns fixed at zero); an
//! unbounded column is positive on a ray of the face. With `J` the unknowns that can change
//! on the face, there is a point of the face where all of them change at once (an average of
//! points), so the face's affine hull is `{M y = t, y_j = 0 off J}` and its dimension is
//! `|J| − rank M_J`.

use crate::dense::{independent_rows, rank_of_columns, Matrix};
use crate::simplex::{Outcome, Tableau};
use api::Rational;
use num_traits::{Signed, Zero};

/// The least absolute change for one right-hand side.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LeastAbsolute {
    /// The change.
    pub(crate) y: Vec<Rational>,
    /// `Σ w_j |y_j|`.
    pub(crate) objective: Rational,
    /// Dimension of the set of optima (0: unique).
    pub(crate) face_dimension: usize,
    /// Simplex pivots, the optimum and the face together.
    pub(crate) pivots: usize,
}

/// The least absolute change solving `m y = t` with weights `weights` (positive), or `None`
/// when `m y = t` has no solution.
pub(crate) fn least_absolute_change(
    m: &Matrix,
    t: &[Rational],
    weights: &[Rational],
) -> Option<LeastAbsolute> {
    let n = weights.len();
    let (rows, rhs) = independent_rows(m, t)?;
    // The pivot of each reduced row is its first nonzero entry (columns were taken in order).
    let mut tableau_rows = Vec::with_capacity(rows.len());
    let mut values = Vec::with_capacity(rows.len());
    let mut basis = Vec::with_capacity(rows.len());
    for (row, t) in rows.iter().zip(rhs) {
        let pivot = row.iter().position(|a| !a.is_zero())?;
        let negate = t.is_negative();
        let sign = |a: &Rational| if negate { -a } else { a.clone() };
        let mut tableau_row: Vec<Rational> = row.iter().map(sign).collect();
        tableau_row.extend(row.iter().map(|a| -sign(a)));
        tableau_rows.push(tableau_row);
        basis.push(if negate { n + pivot } else { pivot });
        values.push(t.abs());
    }
    let costs: Vec<Rational> = weights.iter().chain(weights).cloned().collect();
    let mut tableau = Tableau::new(tableau_rows, values, basis, costs);
    let everything = vec![true; 2 * n];
    // Bounded below by zero: the simplex ends at an optimum.
    if tableau.minimize(&everything) != Outcome::Optimal {
        return None;
    }
    let x = tableau.solution();
    let objective = tableau.objective();
    let y: Vec<Rational> = (0..n).map(|j| &x[j] - &x[n + j]).collect();

    // The optimal face: the columns of zero reduced cost, and which of them can be positive.
    let tight: Vec<bool> = tableau
        .reduced_costs()
        .iter()
        .map(|r| r.is_zero())
        .collect();
    let mut can_be_positive: Vec<bool> = x.iter().map(|v| v.is_positive()).collect();
    for j in 0..2 * n {
        if !tight[j] || can_be_positive[j] {
            continue;
        }
        let mut costs = vec![Rational::zero(); 2 * n];
        costs[j] = -Rational::from_integer(1.into());
        tableau.set_costs(costs);
        match tableau.minimize(&tight) {
            Outcome::Unbounded(_) => can_be_positive[j] = true,
            Outcome::Optimal => {
                for (slot, value) in can_be_positive.iter_mut().zip(tableau.solution()) {
                    *slot |= value.is_positive();
                }
            }
        }
    }
    let changing: Vec<usize> = (0..n)
        .filter(|&j| can_be_positive[j] || can_be_positive[n + j])
        .collect();
    let face_dimension = changing.len() - rank_of_columns(&rows, &changing);
    Some(LeastAbsolute {
        y,
        objective,
        face_dimension,
        pivots: tableau.pivots(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64) -> Rational {
        Rational::from_integer(n.into())
    }

    #[test]
    fn one_equation_moves_the_cheapest_unknown() {
        // y0 + y1 + y2 = 6, weights 3, 1, 2: all of it on y1.
        let m = vec![vec![q(1), q(1), q(1)]];
        let r = least_absolute_change(&m, &[q(6)], &[q(3), q(1), q(2)]).expect("solvable");
        assert_eq!(r.y, vec![q(0), q(6), q(0)]);
        assert_eq!(r.objective, q(6));
        assert_eq!(r.face_dimension, 0);
    }

    #[test]
    fn ties_make_a_face() {
        // y0 + y1 = 1 with equal weights: every split with both ≥ 0 is optimal (a segment).
        let m = vec![vec![q(1), q(1)]];
        let r = least_absolute_change(&m, &[q(1)], &[q(1), q(1)]).expect("solvable");
        assert_eq!(r.objective, q(1));
        assert_eq!(r.face_dimension, 1);
        // A negative right-hand side starts from the negated row.
        let r = least_absolute_change(&m, &[q(-2)], &[q(1), q(1)]).expect("solvable");
        assert_eq!(r.objective, q(2));
        assert_eq!(&r.y[0] + &r.y[1], q(-2));
        assert_eq!(r.face_dimension, 1);
    }

    #[test]
    fn no_solution_is_none() {
        let m = vec![vec![q(1), q(1)], vec![q(2), q(2)]];
        assert!(least_absolute_change(&m, &[q(1), q(1)], &[q(1), q(1)]).is_none());
    }
}
