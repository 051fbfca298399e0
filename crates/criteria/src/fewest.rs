//! Fewest changed parameters (Brenner, eq. 21, the exact-fitting problem): the smallest set
//! of groups (a group: the unknowns of one parameter) whose columns span every right-hand side
//! of `M y = t_k`, exactly.
//!
//! A set `U` of groups can carry the change iff every `t_k` lies in the span of `M`'s columns
//! in `U`; when it cannot, exact elimination gives a certificate `z` with `zᵀ M_U = 0` and
//! `zᵀ t_k ≠ 0`, and then *every* set that carries the change contains a group where `zᵀ M`
//! is not zero (else `zᵀ M_S = 0` would contradict `zᵀ t_k ≠ 0`): a **cut**. The search is an
//! implicit hitting-set method:
//!
//! 1. **Determined unknowns.** A Gauss–Jordan row equal to a unit vector with a nonzero
//!    right-hand side fixes its unknown to a nonzero change: its group is in every support.
//! 2. **Smallest hitting set.** Find a smallest set of groups meeting every cut so far (branch
//!    and bound: branch on the smallest unhit cut, bound by pairwise disjoint unhit cuts) and
//!    test it: if it carries the change it is a minimum support (every support meets every
//!    cut, so none is smaller); otherwise its certificate is a new cut. Each round removes the
//!    set just tested, so the rounds end.
//! 3. **Ties.** Every hitting set of that size is tested too (new cuts only remove
//!    candidates); those that carry the change are the ties.
//! 4. **Beyond the budget** ([`crate::FEWEST_EXACT_WORK`] matrix entries of rank tests, or two million
//!    branch-and-bound nodes), a heuristic: start from the union of the least-absolute-change
//!    supports (L1, the convex relaxation of counting; a vertex changes at most `rank M`
//!    unknowns) and drop groups one by one, smallest change first, while the rest still
//!    carries the change. The result is minimal under inclusion, not proven minimal in size.
//!
//! With a support fixed, the change is the least weighted-squares one inside it; for a support
//! of minimum size its columns are independent, so that change is the only one. Among ties
//! the smallest weighted squared change is chosen, then the first in lexicographic order.

use crate::dense::{augmented, least_norm, reduce_rows, weighted_squares, Matrix};
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
    /// Whether no smaller support exists (the exact search finished).
    pub(crate) proven_minimal: bool,
    /// Whether every support of that size was found (the tie search finished).
    pub(crate) ties_complete: bool,
    /// Rank tests made.
    pub(crate) rank_tests: usize,
}

/// Most tie supports kept in a result (their number is still counted).
pub(crate) const LISTED_TIES: usize = 32;

/// The search over the system `m y = t_k` (`rhs[k] = t_k`), `groups[j]` the group of column
/// `j`, with at most `budget` matrix entries of rank tests in the exact search; `None` when some `t_k`
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
    let mut a = augmented(m, rhs);
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
    let work = std::cell::Cell::new(0usize);
    // Why a set of groups cannot carry the change: `z` over the reduced rows with
    // `zᵀ M_U = 0` and `zᵀ t_k ≠ 0` for some `k`; `None` when it carries it.
    let certificate = |set: &[usize]| -> Option<Vec<Rational>> {
        tests.set(tests.get() + 1);
        let cols = columns_of(set);
        // Only rows touching the set or with a right-hand side matter.
        let touched: Vec<usize> = (0..rows.len())
            .filter(|&i| {
                cols.iter().any(|&j| !rows[i][j].is_zero())
                    || reduced_rhs.iter().any(|t| !t[i].is_zero())
            })
            .collect();
        let (c, k) = (cols.len(), reduced_rhs.len());
        work.set(work.get() + touched.len() * (c + k + touched.len()));
        let mut a: Matrix = touched
            .iter()
            .enumerate()
            .map(|(local, &i)| {
                cols.iter()
                    .map(|&j| rows[i][j].clone())
                    .chain(reduced_rhs.iter().map(|t| t[i].clone()))
                    .chain((0..touched.len()).map(|l| Rational::from_integer((l == local).into())))
                    .collect()
            })
            .collect();
        let pivot_columns: Vec<usize> = (0..c).collect();
        let rank = reduce_rows(&mut a, &pivot_columns).len();
        let row = a[rank..]
            .iter()
            .find(|row| row[c..c + k].iter().any(|v| !v.is_zero()))?;
        let mut z = vec![Rational::zero(); rows.len()];
        for (local, &i) in touched.iter().enumerate() {
            z[i] = row[c + k + local].clone();
        }
        Some(z)
    };
    // The groups a certificate says every carrying set must contain one of: those where
    // `zᵀ M` is not zero.
    let cut = |z: &[Rational]| -> Vec<usize> {
        let mut cut: Vec<usize> = (0..n)
            .filter(|&j| {
                let mut sum = Rational::zero();
                for (zi, row) in z.iter().zip(&rows) {
                    if !zi.is_zero() && !row[j].is_zero() {
                        sum += zi * &row[j];
                    }
                }
                !sum.is_zero()
            })
            .map(|j| groups[j])
            .collect();
        cut.sort_unstable();
        cut.dedup();
        cut
    };

    // 1. Determined unknowns: a reduced row that is a unit vector.
    let mut fixed_nonzero = vec![false; n];
    for (i, row) in rows.iter().enumerate() {
        let pivot = pivots[i];
        let unit = row
            .iter()
            .enumerate()
            .all(|(j, v)| if j == pivot { v.is_one() } else { v.is_zero() });
        if unit && reduced_rhs.iter().any(|t| !t[i].is_zero()) {
            fixed_nonzero[pivot] = true;
        }
    }
    let mut necessary: Vec<usize> = (0..n)
        .filter(|&j| fixed_nonzero[j])
        .map(|j| groups[j])
        .collect();
    necessary.sort_unstable();
    necessary.dedup();
    // Groups with a nonzero column: the only ones that can help carry the change.
    let mut live: Vec<usize> = (0..n)
        .filter(|&j| rows.iter().any(|row| !row[j].is_zero()))
        .map(|j| groups[j])
        .collect();
    live.sort_unstable();
    live.dedup();
    let with_necessary = |extra: &[usize]| -> Vec<usize> {
        let mut set: Vec<usize> = necessary.iter().chain(extra).copied().collect();
        set.sort_unstable();
        set.dedup();
        set
    };

    // The cut of a set that cannot carry the change (certificate `z`), grown first to a
    // maximal such set: a short cut.
    let maximal_cut = |set: Vec<usize>, z: Vec<Rational>| -> Vec<usize> {
        let rest: Vec<usize> = live
            .iter()
            .copied()
            .filter(|g| set.binary_search(g).is_err())
            .collect();
        let (_, z) = grow(set, &rest, z, &certificate);
        cut(&z)
    };

    // 2. Implicit hitting sets: a smallest set hitting every cut so far; carried → minimum;
    //    else its certificate is a new cut.
    let mut cuts: Vec<Vec<usize>> = Vec::new();
    let mut nodes = 0usize;
    let mut found: Vec<Vec<usize>> = Vec::new();
    let mut exact = true;
    let mut ties_complete = true;
    let minimum = loop {
        if work.get() >= budget {
            exact = false;
            break None;
        }
        let Some(hitting) = minimum_hitting_set(&cuts, &mut nodes) else {
            exact = false;
            break None;
        };
        let set = with_necessary(&hitting);
        match certificate(&set) {
            None => break Some(hitting.len()),
            Some(z) => {
                let new = maximal_cut(set, z);
                if new.is_empty() || new.iter().all(|g| necessary.binary_search(g).is_ok()) {
                    // No set can carry it: the system was inconsistent.
                    return None;
                }
                cuts.push(new);
            }
        }
    };
    // 3. Ties: every hitting set of that size that carries the change.
    if let Some(size) = minimum {
        let mut candidates = Vec::new();
        ties_complete = hitting_sets_of_size(&cuts, size, &mut nodes, &mut candidates);
        for hitting in candidates {
            if !cuts
                .iter()
                .all(|c| c.iter().any(|g| hitting.binary_search(g).is_ok()))
            {
                continue;
            }
            if work.get() >= budget {
                ties_complete = false;
                break;
            }
            let set = with_necessary(&hitting);
            match certificate(&set) {
                None => found.push(set),
                Some(z) => cuts.push(maximal_cut(set, z)),
            }
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
            if certificate(&without).is_none() {
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
            ties_complete: exact && ties_complete,
            rank_tests,
        },
        tie_total,
    ))
}

/// Grows `base`, a set that cannot carry the change (certificate `z`), by the groups of `rest`
/// while it still cannot — all of `rest` at once if possible, else each half in turn — to a
/// maximal such set; returns it and its certificate. The cut of a maximal set is small (every
/// group outside it would make it carry the change), which is what makes the hitting-set
/// rounds few: `O(cut · log |rest|)` tests each.
fn grow(
    base: Vec<usize>,
    rest: &[usize],
    z: Vec<Rational>,
    certificate: &dyn Fn(&[usize]) -> Option<Vec<Rational>>,
) -> (Vec<usize>, Vec<Rational>) {
    if rest.is_empty() {
        return (base, z);
    }
    let mut all: Vec<usize> = base.iter().chain(rest).copied().collect();
    all.sort_unstable();
    all.dedup();
    if let Some(z_all) = certificate(&all) {
        return (all, z_all);
    }
    if rest.len() == 1 {
        return (base, z);
    }
    let (first, second) = rest.split_at(rest.len() / 2);
    let (base, z) = grow(base, first, z, certificate);
    grow(base, second, z, certificate)
}

/// Most nodes the hitting-set searches visit in one problem.
const HITTING_NODES: usize = 2_000_000;

/// The unhit cut with the fewest groups, if any (the branch with the fewest choices).
fn smallest_unhit<'a>(cuts: &'a [Vec<usize>], chosen: &[usize]) -> Option<&'a Vec<usize>> {
    cuts.iter()
        .filter(|c| !c.iter().any(|g| chosen.contains(g)))
        .min_by_key(|c| c.len())
}

/// A lower bound on the groups still needed: unhit cuts taken greedily pairwise disjoint.
fn disjoint_unhit(cuts: &[Vec<usize>], chosen: &[usize]) -> usize {
    let mut used: Vec<usize> = Vec::new();
    let mut count = 0;
    for c in cuts {
        if c.iter().any(|g| chosen.contains(g) || used.contains(g)) {
            continue;
        }
        used.extend(c);
        count += 1;
    }
    count
}

/// A smallest set of groups meeting every cut (ascending), by branch and bound: branch on the
/// groups of the smallest unhit cut, bound by disjoint unhit cuts. `None` beyond
/// [`HITTING_NODES`] nodes (over the whole problem, counted in `nodes`).
fn minimum_hitting_set(cuts: &[Vec<usize>], nodes: &mut usize) -> Option<Vec<usize>> {
    fn search(
        cuts: &[Vec<usize>],
        chosen: &mut Vec<usize>,
        best: &mut Option<Vec<usize>>,
        nodes: &mut usize,
    ) -> bool {
        *nodes += 1;
        if *nodes > HITTING_NODES {
            return false;
        }
        let Some(cut) = smallest_unhit(cuts, chosen) else {
            if best.as_ref().is_none_or(|b| chosen.len() < b.len()) {
                let mut found = chosen.clone();
                found.sort_unstable();
                *best = Some(found);
            }
            return true;
        };
        let bound = chosen.len() + disjoint_unhit(cuts, chosen);
        if best.as_ref().is_some_and(|b| bound >= b.len()) {
            return true;
        }
        for &g in cut {
            chosen.push(g);
            let finished = search(cuts, chosen, best, nodes);
            chosen.pop();
            if !finished {
                return false;
            }
        }
        true
    }
    let mut best = None;
    search(cuts, &mut Vec::new(), &mut best, nodes).then_some(best)?
}

/// Every set of `size` groups meeting every cut, ascending each and in lexicographic order,
/// into `out` (when `size` is the smallest such size these are exactly the minimal ones,
/// reached by branching on the smallest unhit cut); `false` when [`HITTING_NODES`] ran out.
fn hitting_sets_of_size(
    cuts: &[Vec<usize>],
    size: usize,
    nodes: &mut usize,
    out: &mut Vec<Vec<usize>>,
) -> bool {
    fn search(
        cuts: &[Vec<usize>],
        size: usize,
        chosen: &mut Vec<usize>,
        found: &mut std::collections::BTreeSet<Vec<usize>>,
        nodes: &mut usize,
    ) -> bool {
        *nodes += 1;
        if *nodes > HITTING_NODES {
            return false;
        }
        let Some(cut) = smallest_unhit(cuts, chosen) else {
            if chosen.len() == size {
                let mut set = chosen.clone();
                set.sort_unstable();
                found.insert(set);
            }
            return true;
        };
        if chosen.len() + disjoint_unhit(cuts, chosen) > size {
            return true;
        }
        for &g in cut {
            chosen.push(g);
            let finished = search(cuts, size, chosen, found, nodes);
            chosen.pop();
            if !finished {
                return false;
            }
        }
        true
    }
    let mut found = std::collections::BTreeSet::new();
    let complete = search(cuts, size, &mut Vec::new(), &mut found, nodes);
    out.extend(found);
    complete
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64) -> Rational {
        Rational::from_integer(n.into())
    }

    #[test]
    fn hitting_sets_are_smallest_and_all_are_listed() {
        let cuts = vec![vec![0, 1], vec![1, 2], vec![2, 3]];
        let mut nodes = 0;
        let best = minimum_hitting_set(&cuts, &mut nodes).expect("within the budget");
        assert_eq!(best.len(), 2);
        let mut all = Vec::new();
        assert!(hitting_sets_of_size(&cuts, 2, &mut nodes, &mut all));
        assert_eq!(all, vec![vec![0, 2], vec![1, 2], vec![1, 3]]);
        // No cuts: the empty set.
        assert_eq!(minimum_hitting_set(&[], &mut nodes), Some(vec![]));
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
            fewest_changed(&m, &[vec![q(4)]], &vec![q(1); 4], &[0, 1, 2, 3], 1).expect("solvable");
        assert!(!r.proven_minimal);
        assert_eq!(r.supports.len(), 1);
        assert_eq!(r.supports[0].len(), 1);
        let sum: Rational = r.y[0].iter().sum();
        assert_eq!(sum, q(4));
    }
}
