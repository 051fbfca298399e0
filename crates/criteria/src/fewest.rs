//! Fewest changed parameters (Brenner, eq. 21, the exact-fitting problem): the smallest set
//! of groups (a group: the unknowns of one parameter) whose columns span every right-hand side
//! of `M y = t_k`, exactly.
//!
//! A set `U` of groups can carry the change iff every `t_k` lies in the span of `M`'s columns
//! in `U`: one exact rank test. The search:
//!
//! 1. **Determined unknowns.** A Gauss–Jordan row equal to a unit vector fixes its unknown.
//!    A group whose unknowns are all fixed at zero never changes (dropped); a group with a
//!    nonzero fixed unknown always changes.
//! 2. **Necessary groups.** A group without which the others cannot carry the change is in
//!    every support (one test per group).
//! 3. **Branch over supports** of the remaining groups by increasing size, in lexicographic
//!    order; the first size with a feasible support is the minimum, and every feasible support
//!    of that size is a tie. A level is entered only when its tests fit the budget
//!    ([`crate::FEWEST_EXACT_TESTS`] over the whole search).
//! 4. **Beyond the budget**, a heuristic: start from the union of the least-absolute-change
//!    supports (L1, the convex relaxation of counting; a vertex changes at most `rank M`
//!    unknowns) and drop groups one by one, smallest change first, while the rest still
//!    carries the change. The result is minimal under inclusion, not proven minimal in size.
//!
//! With a support fixed, the change is the least weighted-squares one inside it; for a support
//! of minimum size its columns are independent, so that change is the only one. Among ties
//! the smallest weighted squared change is chosen, then the first in lexicographic order.

use crate::dense::{columns_span, least_norm, reduce_rows, weighted_squares, Matrix};
use crate::least_absolute::least_absolute_change;
use api::Rational;
use num_traits::{One, Zero};

/// The result of the search.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FewestChange {
    /// The change, per right-hand side.
    pub(crate) y: Vec<Vec<Rational>>,
    /// The supports of minimum size found (group ids, ascending), the chosen one first; the
    /// chosen one alone when the search was not exact.
    pub(crate) supports: Vec<Vec<usize>>,
    /// Whether no smaller support exists (the branch search finished).
    pub(crate) proven_minimal: bool,
    /// Rank tests made.
    pub(crate) rank_tests: usize,
}

/// Most tie supports kept in a result (their number is still counted).
pub(crate) const LISTED_TIES: usize = 32;

/// The search over the system `m y = t_k` (`rhs[k] = t_k`), `groups[j]` the group of column
/// `j`, with at most `budget` rank tests in the exact branch search; `None` when some `t_k`
/// is not in the column span of `m`.
pub(crate) fn fewest_changed(
    m: &Matrix,
    rhs: &[Vec<Rational>],
    weights: &[Rational],
    groups: &[usize],
    budget: usize,
) -> Option<(FewestChange, usize)> {
    let n = weights.len();
    let group_count = groups.iter().map(|g| g + 1).max().unwrap_or(0);
    // [M | t_0 … t_K] in Gauss–Jordan form; dependent rows must have zero right-hand sides.
    let mut a: Matrix = m
        .iter()
        .enumerate()
        .map(|(i, row)| {
            row.iter()
                .cloned()
                .chain(rhs.iter().map(|t| t[i].clone()))
                .collect()
        })
        .collect();
    let all: Vec<usize> = (0..n).collect();
    let pivots = reduce_rows(&mut a, &all);
    if a[pivots.len()..]
        .iter()
        .any(|row| row[n..].iter().any(|v| !v.is_zero()))
    {
        return None;
    }
    a.truncate(pivots.len());
    let rows: Matrix = a.iter().map(|row| row[..n].to_vec()).collect();
    let reduced_rhs: Vec<Vec<Rational>> = (0..rhs.len())
        .map(|k| a.iter().map(|row| row[n + k].clone()).collect())
        .collect();
    let columns_of = |set: &[usize]| -> Vec<usize> {
        (0..n)
            .filter(|&j| set.binary_search(&groups[j]).is_ok())
            .collect()
    };
    let tests = std::cell::Cell::new(0usize);
    let carries = |set: &[usize]| {
        tests.set(tests.get() + 1);
        columns_span(&rows, &columns_of(set), &reduced_rhs)
    };

    // 1. Determined unknowns: a reduced row that is a unit vector.
    let mut fixed_zero = vec![false; n];
    let mut fixed_nonzero = vec![false; n];
    for (i, row) in rows.iter().enumerate() {
        let pivot = pivots[i];
        let unit = row
            .iter()
            .enumerate()
            .all(|(j, v)| if j == pivot { v.is_one() } else { v.is_zero() });
        if unit {
            if reduced_rhs.iter().all(|t| t[i].is_zero()) {
                fixed_zero[pivot] = true;
            } else {
                fixed_nonzero[pivot] = true;
            }
        }
    }
    let mut candidates = Vec::new();
    let mut necessary = Vec::new();
    for g in 0..group_count {
        let cols: Vec<usize> = (0..n).filter(|&j| groups[j] == g).collect();
        let useless = cols
            .iter()
            .all(|&j| fixed_zero[j] || rows.iter().all(|row| row[j].is_zero()));
        if cols.iter().any(|&j| fixed_nonzero[j]) {
            necessary.push(g);
        } else if !useless {
            candidates.push(g);
        }
    }
    // 2. Necessary groups among the candidates.
    let mut optional = Vec::new();
    for (i, &g) in candidates.iter().enumerate() {
        let mut others: Vec<usize> = necessary.clone();
        others.extend(candidates[..i].iter().chain(&candidates[i + 1..]));
        others.sort_unstable();
        if carries(&others) {
            optional.push(g);
        } else {
            necessary.push(g);
        }
    }
    necessary.sort_unstable();

    // 3. Supports by increasing size.
    let mut found: Vec<Vec<usize>> = Vec::new();
    let mut exact = true;
    for k in 0..=optional.len() {
        if binomial(optional.len(), k).saturating_add(tests.get()) > budget {
            exact = false;
            break;
        }
        let mut combination: Vec<usize> = (0..k).collect();
        loop {
            let mut set = necessary.clone();
            set.extend(combination.iter().map(|&i| optional[i]));
            set.sort_unstable();
            if carries(&set) {
                found.push(set);
            }
            if !next_combination(&mut combination, optional.len()) {
                break;
            }
        }
        if !found.is_empty() {
            break;
        }
    }

    // 4. Beyond the budget: from the L1 supports, drop what is not needed.
    if !exact {
        let mut start = vec![false; group_count];
        for t in &reduced_rhs {
            let l1 = least_absolute_change(&rows, t, weights)?;
            for (j, y) in l1.y.iter().enumerate() {
                start[groups[j]] |= !y.is_zero();
            }
        }
        for &g in &necessary {
            start[g] = true;
        }
        let mut set: Vec<usize> = (0..group_count).filter(|&g| start[g]).collect();
        // Smallest change first: the least-norm change inside the start set, per group.
        let cols = columns_of(&set);
        let mut size = vec![Rational::zero(); group_count];
        for t in &reduced_rhs {
            let y = least_norm(&rows, t, weights, &cols)?;
            for (j, y) in y.iter().enumerate() {
                if !y.is_zero() {
                    size[groups[j]] += y * y * &weights[j];
                }
            }
        }
        let mut order: Vec<usize> = set
            .iter()
            .copied()
            .filter(|g| necessary.binary_search(g).is_err())
            .collect();
        order.sort_by(|a, b| size[*a].cmp(&size[*b]).then(a.cmp(b)));
        for g in order {
            let without: Vec<usize> = set.iter().copied().filter(|&h| h != g).collect();
            if carries(&without) {
                set = without;
            }
        }
        found = vec![set];
    }
    let rank_tests = tests.get();

    // The change inside each support; the smallest weighted squares first, then order.
    let mut best: Option<(Rational, usize, Vec<Vec<Rational>>)> = None;
    for (i, set) in found.iter().enumerate() {
        let cols = columns_of(set);
        let mut changes = Vec::with_capacity(reduced_rhs.len());
        let mut squares = Rational::zero();
        for t in &reduced_rhs {
            let y = least_norm(&rows, t, weights, &cols)?;
            squares += weighted_squares(&y, weights);
            changes.push(y);
        }
        if best.as_ref().is_none_or(|(s, _, _)| squares < *s) {
            best = Some((squares, i, changes));
        }
    }
    let (_, chosen, y) = best?;
    let tie_total = found.len();
    let chosen_support = found.remove(chosen);
    found.insert(0, chosen_support);
    found.truncate(LISTED_TIES);
    Some((
        FewestChange {
            y,
            supports: found,
            proven_minimal: exact,
            rank_tests,
        },
        tie_total,
    ))
}

/// `C(n, k)`, saturating.
fn binomial(n: usize, k: usize) -> usize {
    let k = k.min(n - k.min(n));
    let mut result: usize = 1;
    for i in 0..k {
        result = match result.checked_mul(n - i) {
            Some(v) => v / (i + 1),
            None => return usize::MAX,
        };
    }
    result
}

/// The next `k`-combination of `0..n` in lexicographic order; `false` after the last.
fn next_combination(c: &mut [usize], n: usize) -> bool {
    let k = c.len();
    for i in (0..k).rev() {
        if c[i] < n - k + i {
            c[i] += 1;
            for j in i + 1..k {
                c[j] = c[j - 1] + 1;
            }
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64) -> Rational {
        Rational::from_integer(n.into())
    }

    #[test]
    fn combinations_and_binomials() {
        let mut c = vec![0, 1];
        let mut seen = vec![c.clone()];
        while next_combination(&mut c, 4) {
            seen.push(c.clone());
        }
        assert_eq!(seen.len(), binomial(4, 2));
        assert_eq!(seen.last(), Some(&vec![2, 3]));
        assert!(!next_combination(&mut [], 3));
        assert_eq!(binomial(5, 0), 1);
        assert_eq!(binomial(3, 5), 1);
        assert_eq!(binomial(usize::MAX, 3), usize::MAX);
    }

    #[test]
    fn two_ways_to_carry_one_change_are_a_tie() {
        // y0 − y1 = 0 and y1 + y2 = 1: {y2} (y = (0, 0, 1)) is the only support of size one
        // ({y0, y1} carries it too, with two changes).
        let m = vec![vec![q(1), q(-1), q(0)], vec![q(0), q(1), q(1)]];
        let (r, ties) = fewest_changed(
            &m,
            &[vec![q(0), q(1)]],
            &[q(1), q(1), q(1)],
            &[0, 1, 2],
            1000,
        )
        .expect("solvable");
        assert_eq!(r.supports, vec![vec![2]]);
        assert_eq!((ties, r.proven_minimal), (1, true));
        assert_eq!(r.y, vec![vec![q(0), q(0), q(1)]]);
        // y0 + y1 = 1: two supports of size one; the cheaper (weight 1 < 2) is chosen.
        let m = vec![vec![q(1), q(1)]];
        let (r, ties) =
            fewest_changed(&m, &[vec![q(1)]], &[q(2), q(1)], &[0, 1], 1000).expect("solvable");
        assert_eq!(r.supports, vec![vec![1], vec![0]]);
        assert_eq!(ties, 2);
        assert_eq!(r.y, vec![vec![q(0), q(1)]]);
    }

    #[test]
    fn a_group_changes_when_any_of_its_unknowns_does() {
        // Two parameters of two coordinates each; the change needs both coordinates of one.
        let m = vec![vec![q(1), q(0), q(1), q(0)], vec![q(0), q(1), q(0), q(1)]];
        let (r, ties) = fewest_changed(
            &m,
            &[vec![q(1), q(1)]],
            &[q(1), q(1), q(1), q(1)],
            &[0, 0, 1, 1],
            1000,
        )
        .expect("solvable");
        assert_eq!(r.supports.len(), 2);
        assert_eq!(ties, 2);
        assert_eq!(r.supports[0], vec![0]);
    }

    #[test]
    fn beyond_the_budget_the_heuristic_says_so() {
        let m = vec![vec![q(1), q(1), q(1), q(1)]];
        let (r, _) =
            fewest_changed(&m, &[vec![q(4)]], &vec![q(1); 4], &[0, 1, 2, 3], 2).expect("solvable");
        assert!(!r.proven_minimal);
        assert_eq!(r.supports.len(), 1);
        assert_eq!(r.supports[0].len(), 1);
        let sum: Rational = r.y[0].iter().sum();
        assert_eq!(sum, q(4));
    }
}
