//! An exact primal simplex over the rationals, dense tableau, Bland's rule.
//!
//! The problem is `min cᵀx` subject to `A x = b`, `x ≥ 0`, started from a feasible basis the
//! caller gives (the tableau already in canonical form for it: each basic column a unit
//! vector, `b ≥ 0`). Every decision — the entering column (a negative reduced cost), the
//! leaving row (the ratio test) — is an exact comparison of rationals, so optimality is
//! proved, not estimated. Bland's rule (the lowest-numbered improving column enters; among
//! rows tied in the ratio test the lowest-numbered basic variable leaves) cannot cycle, so the
//! method ends after finitely many pivots even on degenerate problems (the L1 problems of
//! edits are highly degenerate: most changes are zero).
//!
//! Why our own: the L1 criterion needs the final tableau itself (reduced costs for the optimal
//! face, warm restarts over that face), starts from a basis it builds without a phase 1, and
//! must stay exact; no maintained Rust crate offers an exact simplex with that access (the
//! ones we found are float-based or record every tableau for teaching).

use api::Rational;
use num_traits::{Signed, Zero};

/// A tableau in canonical form for its basis.
#[derive(Debug, Clone)]
pub(crate) struct Tableau {
    /// `B⁻¹A`, one row per constraint.
    rows: Vec<Vec<Rational>>,
    /// `B⁻¹b`, the values of the basic variables (never negative).
    values: Vec<Rational>,
    /// The basic variable of each row.
    basis: Vec<usize>,
    /// The costs of the current objective.
    costs: Vec<Rational>,
    /// `c − (c_B)ᵀ B⁻¹A`: zero on basic columns.
    reduced: Vec<Rational>,
    /// Pivots made, over every run (reported).
    pivots: usize,
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Outcome {
    /// No allowed column has a negative reduced cost: the basis is optimal.
    Optimal,
    /// The column can grow without bound, the objective decreasing.
    Unbounded(usize),
}

impl Tableau {
    /// A tableau from rows already in canonical form for `basis` (`rows[i][basis[i]] = 1`,
    /// zero in the other rows) with `values ≥ 0`, and objective `costs`.
    pub(crate) fn new(
        rows: Vec<Vec<Rational>>,
        values: Vec<Rational>,
        basis: Vec<usize>,
        costs: Vec<Rational>,
    ) -> Self {
        debug_assert!(values.iter().all(|v| !v.is_negative()));
        debug_assert!(basis.iter().enumerate().all(|(i, &j)| rows
            .iter()
            .enumerate()
            .all(|(r, row)| row[j] == Rational::from_integer((r == i).into()))));
        let mut tableau = Tableau {
            reduced: Vec::new(),
            rows,
            values,
            basis,
            costs: Vec::new(),
            pivots: 0,
        };
        tableau.set_costs(costs);
        tableau
    }

    /// Replaces the objective (the basis stays: it is still feasible).
    pub(crate) fn set_costs(&mut self, costs: Vec<Rational>) {
        let mut reduced = costs.clone();
        for (row, &j) in self.rows.iter().zip(&self.basis) {
            let cost = &costs[j];
            if cost.is_zero() {
                continue;
            }
            for (r, a) in reduced.iter_mut().zip(row) {
                if !a.is_zero() {
                    *r -= cost * a;
                }
            }
        }
        self.costs = costs;
        self.reduced = reduced;
    }

    /// Pivots until no column with `allowed[j]` has a negative reduced cost (Bland's rule).
    pub(crate) fn minimize(&mut self, allowed: &[bool]) -> Outcome {
        loop {
            let entering =
                (0..self.reduced.len()).find(|&j| allowed[j] && self.reduced[j].is_negative());
            let Some(entering) = entering else {
                return Outcome::Optimal;
            };
            // The ratio test; ties to the lowest-numbered basic variable.
            let mut leaving: Option<(usize, Rational)> = None;
            for (i, row) in self.rows.iter().enumerate() {
                let a = &row[entering];
                if !a.is_positive() {
                    continue;
                }
                let ratio = &self.values[i] / a;
                let better = match &leaving {
                    None => true,
                    Some((l, best)) => {
                        ratio < *best || (ratio == *best && self.basis[i] < self.basis[*l])
                    }
                };
                if better {
                    leaving = Some((i, ratio));
                }
            }
            let Some((row, _)) = leaving else {
                return Outcome::Unbounded(entering);
            };
            self.pivot(row, entering);
        }
    }

    /// Makes `column` basic in `row`.
    fn pivot(&mut self, row: usize, column: usize) {
        let inverse = self.rows[row][column].recip();
        for value in self.rows[row].iter_mut() {
            if !value.is_zero() {
                *value *= &inverse;
            }
        }
        self.values[row] *= &inverse;
        let pivot_row = self.rows[row].clone();
        let pivot_value = self.values[row].clone();
        for (r, other) in self.rows.iter_mut().enumerate() {
            if r == row || other[column].is_zero() {
                continue;
            }
            let factor = other[column].clone();
            for (value, p) in other.iter_mut().zip(&pivot_row) {
                if !p.is_zero() {
                    *value -= &factor * p;
                }
            }
            self.values[r] -= &factor * &pivot_value;
        }
        let factor = self.reduced[column].clone();
        for (value, p) in self.reduced.iter_mut().zip(&pivot_row) {
            if !p.is_zero() {
                *value -= &factor * p;
            }
        }
        self.basis[row] = column;
        self.pivots += 1;
    }

    /// The value of every variable at the current basis.
    pub(crate) fn solution(&self) -> Vec<Rational> {
        let mut x = vec![Rational::zero(); self.reduced.len()];
        for (value, &j) in self.values.iter().zip(&self.basis) {
            x[j] = value.clone();
        }
        x
    }

    /// The objective at the current basis.
    pub(crate) fn objective(&self) -> Rational {
        self.values
            .iter()
            .zip(&self.basis)
            .map(|(v, &j)| v * &self.costs[j])
            .fold(Rational::zero(), |sum, term| sum + term)
    }

    /// The reduced costs of the current objective.
    pub(crate) fn reduced_costs(&self) -> &[Rational] {
        &self.reduced
    }

    /// Pivots made so far.
    pub(crate) fn pivots(&self) -> usize {
        self.pivots
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64) -> Rational {
        Rational::from_integer(n.into())
    }

    #[test]
    fn a_small_program_reaches_its_optimum() {
        // min −x0 − x1 s.t. x0 + x2 = 2, x1 + x3 = 3, x0 + x1 + x4 = 4 (slacks x2..x4).
        let rows = vec![
            vec![q(1), q(0), q(1), q(0), q(0)],
            vec![q(0), q(1), q(0), q(1), q(0)],
            vec![q(1), q(1), q(0), q(0), q(1)],
        ];
        let mut t = Tableau::new(
            rows,
            vec![q(2), q(3), q(4)],
            vec![2, 3, 4],
            vec![q(-1), q(-1), q(0), q(0), q(0)],
        );
        assert_eq!(t.minimize(&[true; 5]), Outcome::Optimal);
        assert_eq!(t.objective(), q(-4));
        let x = t.solution();
        assert_eq!(&x[0] + &x[1], q(4));
        assert!(t.reduced_costs().iter().all(|r| !r.is_negative()));
        assert!(t.pivots() >= 2);
    }

    #[test]
    fn an_unbounded_column_is_named() {
        // min −x0 s.t. x0 − x1 + x2 = 1: x0 grows with x1.
        let rows = vec![vec![q(1), q(-1), q(1)]];
        let mut t = Tableau::new(rows, vec![q(1)], vec![2], vec![q(-1), q(0), q(0)]);
        assert_eq!(t.minimize(&[true; 3]), Outcome::Unbounded(1));
    }
}
