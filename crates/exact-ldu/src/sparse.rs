//! Exact rank, independent rows, redundancies and consistency of large sparse systems.
//!
//! The fraction-free LDU stores dense rows: fine for the relevant subsystem of an edit, hopeless
//! for the whole C1 system of a 1 000-triangle spline (7 040 × 12 321 per coordinate). This is
//! the same fraction-free elimination on sparse rows, with a pivot order chosen to keep rows
//! short (Markowitz: the column with the fewest live entries, then its shortest row, then the
//! smallest magnitude, ties on original indices). Rows are kept primitive (divided by the GCD of
//! their entries and right-hand sides), so numbers stay small on mesh-like systems.
//!
//! A row that is eliminated to zero is redundant; if its right-hand side is not zero the system
//! is inconsistent. Every elimination step `t ← (a·t − b·p)/g` is logged (target, pivot row and
//! the three integers), so the combination of independent rows equal to a redundant row is
//! recovered exactly by walking the log backwards from the step that zeroed it — reverse
//! accumulation, touching only the steps its zero depends on, whatever their number (a cycle of
//! 10⁵ equalities closed by one row gives that row's 10⁵-term combination in linear time) — and
//! verified against the original rows.

use crate::ring::{gcd_all, Int, Ring};
use api::{IntMatrix, Rational};
use num_traits::Zero;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// A redundant row and its exact combination of independent rows.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SparseRedundancy {
    /// The redundant row.
    pub row: usize,
    /// `(independent row, coefficient)` with `A[row] = Σ coefficient · A[independent row]`,
    /// by increasing row; `None` when combinations were not asked for ([`Combinations::Skip`]).
    pub combination: Option<Vec<(usize, Rational)>>,
    /// Right-hand-side columns in which the row's value differs from the same combination of
    /// right-hand sides: the system is inconsistent in those columns.
    pub inconsistent_columns: Vec<usize>,
}

/// The outcome of a sparse exact elimination.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SparseElimination {
    /// The rank.
    pub rank: usize,
    /// Pivot `(row, column)` pairs in elimination order; the rows are independent.
    pub pivots: Vec<(usize, usize)>,
    /// Every other row (ordered by row index).
    pub redundant: Vec<SparseRedundancy>,
}

impl SparseElimination {
    /// True when every right-hand-side column is consistent.
    pub fn consistent(&self) -> bool {
        self.redundant
            .iter()
            .all(|r| r.inconsistent_columns.is_empty())
    }
}

/// Whether an elimination recovers the combination of each redundant row (it then logs every
/// step: memory in proportion to the steps) or only finds rank, pivots and consistency.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Combinations {
    /// Every redundant row's exact combination of independent rows.
    Exact,
    /// Rank, pivots, redundant rows and consistency only.
    Skip,
}

/// No step: a row as it was given (after its initial division by its content).
const INITIAL: u32 = u32::MAX;

/// A sparse row with right-hand sides.
#[derive(Debug, Clone)]
struct Row {
    entries: Vec<(usize, Int)>,
    rhs: Vec<Int>,
    active: bool,
    /// The last logged step that changed this row ([`INITIAL`] if none).
    last_step: u32,
}

/// One elimination step: `target ← (a · target − b · pivot) / g`, where `target` is the row as
/// left by step `previous` and `pivot` the pivot row as it was when it became a pivot (its
/// `last_step` then, which never changes afterwards).
#[derive(Debug, Clone)]
struct Step {
    target: u32,
    previous: u32,
    pivot: u32,
    pivot_step: u32,
    a: Int,
    b: Int,
    g: Int,
}

/// `(a · x − b · y) / g` of two sparse rows (and right-hand sides), made primitive: the entries,
/// the right-hand sides and `g`.
fn combine(
    a: &Int,
    x: &Row,
    b: &Int,
    y: &Row,
    pivot_col: usize,
) -> (Vec<(usize, Int)>, Vec<Int>, Int) {
    let mut out = Vec::with_capacity(x.entries.len() + y.entries.len());
    let (mut i, mut j) = (0, 0);
    while i < x.entries.len() || j < y.entries.len() {
        let cx = x.entries.get(i).map_or(usize::MAX, |e| e.0);
        let cy = y.entries.get(j).map_or(usize::MAX, |e| e.0);
        let (c, v) = if cx < cy {
            i += 1;
            (cx, a.mul(&x.entries[i - 1].1))
        } else if cy < cx {
            j += 1;
            (cy, b.mul(&y.entries[j - 1].1).neg())
        } else {
            i += 1;
            j += 1;
            (
                cx,
                Int::mul_sub(a, &x.entries[i - 1].1, b, &y.entries[j - 1].1),
            )
        };
        if c != pivot_col && !v.is_zero() {
            out.push((c, v));
        }
    }
    let rhs: Vec<Int> = x
        .rhs
        .iter()
        .zip(&y.rhs)
        .map(|(p, q)| Int::mul_sub(a, p, b, q))
        .collect();
    let values: Vec<Int> = out
        .iter()
        .map(|(_, v)| v.clone())
        .chain(rhs.iter().cloned())
        .collect();
    let g = gcd_all(&values);
    if g.is_zero() || g.is_one() {
        return (out, rhs, Int::one());
    }
    (
        out.into_iter().map(|(c, v)| (c, v.div_exact(&g))).collect(),
        rhs.iter().map(|v| v.div_exact(&g)).collect(),
        g,
    )
}

/// The entry of `row` in column `c` (which the caller knows is present).
fn entry(row: &Row, c: usize) -> &Int {
    let k = row.entries.binary_search_by_key(&c, |e| e.0).unwrap_or(0);
    &row.entries[k].1
}

/// Eliminates `matrix` exactly, with right-hand-side columns `rhs` (each of length `rows`), and
/// recovers the combination of every redundant row when asked.
pub fn eliminate(
    matrix: &IntMatrix,
    rhs: &[Vec<api::Integer>],
    combinations: Combinations,
) -> SparseElimination {
    let run = run(matrix, rhs, combinations);
    let redundant = run
        .zeroed
        .iter()
        .map(|&t| {
            let inconsistent_columns: Vec<usize> = run.rows[t]
                .rhs
                .iter()
                .enumerate()
                .filter(|(_, v)| !v.is_zero())
                .map(|(k, _)| k)
                .collect();
            SparseRedundancy {
                row: t,
                combination: (combinations == Combinations::Exact).then(|| {
                    combination(matrix, &run.steps, &run.contents, t, run.rows[t].last_step)
                }),
                inconsistent_columns,
            }
        })
        .collect();
    SparseElimination {
        rank: run.pivots.len(),
        pivots: run.pivots,
        redundant,
    }
}

/// What an elimination leaves: the rows as eliminated, the log, the rows' contents, the pivots
/// and the rows eliminated to zero (increasing).
struct Run {
    rows: Vec<Row>,
    steps: Vec<Step>,
    contents: Vec<Int>,
    pivots: Vec<(usize, usize)>,
    zeroed: Vec<usize>,
}

/// The elimination itself (see [`eliminate`]); the log only with [`Combinations::Exact`].
fn run(matrix: &IntMatrix, rhs: &[Vec<api::Integer>], combinations: Combinations) -> Run {
    let (m, n) = (matrix.rows(), matrix.cols());
    let mut contents: Vec<Int> = Vec::with_capacity(m);
    let mut rows: Vec<Row> = matrix
        .row_iter()
        .enumerate()
        .map(|(i, r)| {
            let entries: Vec<(usize, Int)> =
                r.iter().map(|(c, v)| (*c, Int::from_bigint(v))).collect();
            let rhs_i: Vec<Int> = rhs.iter().map(|col| Int::from_bigint(&col[i])).collect();
            let values: Vec<Int> = entries
                .iter()
                .map(|(_, v)| v.clone())
                .chain(rhs_i.iter().cloned())
                .collect();
            let g = gcd_all(&values);
            let (entries, rhs_i) = if g.is_zero() || g.is_one() {
                contents.push(Int::one());
                (entries, rhs_i)
            } else {
                let parts = (
                    entries
                        .into_iter()
                        .map(|(c, v)| (c, v.div_exact(&g)))
                        .collect(),
                    rhs_i.iter().map(|v| v.div_exact(&g)).collect(),
                );
                contents.push(g);
                parts
            };
            Row {
                entries,
                rhs: rhs_i,
                active: true,
                last_step: INITIAL,
            }
        })
        .collect();
    let mut steps: Vec<Step> = Vec::new();
    let mut col_rows: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (i, r) in rows.iter().enumerate() {
        for (c, _) in &r.entries {
            col_rows[*c].push(i);
        }
    }
    let mut heap: BinaryHeap<Reverse<(usize, usize)>> = col_rows
        .iter()
        .enumerate()
        .filter(|(_, l)| !l.is_empty())
        .map(|(c, l)| Reverse((l.len(), c)))
        .collect();
    let mut pivoted = vec![false; n];
    let mut pivots = Vec::new();
    let mut zeroed: Vec<usize> = (0..m).filter(|&i| rows[i].entries.is_empty()).collect();
    for &i in &zeroed {
        rows[i].active = false;
    }
    while let Some(Reverse((count, c))) = heap.pop() {
        if pivoted[c] {
            continue;
        }
        // Live rows still holding column c.
        let live: Vec<usize> = {
            let list = &mut col_rows[c];
            list.retain(|&i| {
                rows[i].active && rows[i].entries.binary_search_by_key(&c, |e| e.0).is_ok()
            });
            list.sort_unstable();
            list.dedup();
            list.clone()
        };
        if live.is_empty() {
            continue;
        }
        if live.len() != count {
            heap.push(Reverse((live.len(), c)));
            continue;
        }
        let p = live
            .iter()
            .copied()
            .min_by(|&x, &y| {
                rows[x]
                    .entries
                    .len()
                    .cmp(&rows[y].entries.len())
                    .then_with(|| entry(&rows[x], c).abs_cmp(entry(&rows[y], c)))
                    .then(x.cmp(&y))
            })
            .unwrap_or(live[0]);
        pivoted[c] = true;
        pivots.push((p, c));
        rows[p].active = false;
        let pivot_row = std::mem::take(&mut rows[p].entries);
        let pivot = Row {
            entries: pivot_row,
            rhs: rows[p].rhs.clone(),
            active: false,
            last_step: rows[p].last_step,
        };
        let piv = entry(&pivot, c).clone();
        for &t in live.iter().filter(|&&t| t != p) {
            let utc = entry(&rows[t], c).clone();
            let h = piv.gcd(&utc);
            let (a, b) = (piv.div_exact(&h), utc.div_exact(&h));
            let before: Vec<usize> = rows[t].entries.iter().map(|e| e.0).collect();
            let (entries, rhs_t, g) = combine(&a, &rows[t], &b, &pivot, c);
            let row = &mut rows[t];
            if combinations == Combinations::Exact {
                steps.push(Step {
                    target: t as u32,
                    previous: row.last_step,
                    pivot: p as u32,
                    pivot_step: pivot.last_step,
                    a,
                    b,
                    g,
                });
                row.last_step = (steps.len() - 1) as u32;
            }
            row.entries = entries;
            row.rhs = rhs_t;
            if row.entries.is_empty() {
                row.active = false;
                zeroed.push(t);
                continue;
            }
            for (col, _) in &row.entries {
                if before.binary_search(col).is_err() {
                    col_rows[*col].push(t);
                    heap.push(Reverse((col_rows[*col].len(), *col)));
                }
            }
        }
        rows[p].entries = pivot.entries;
    }
    zeroed.sort_unstable();
    Run {
        rows,
        steps,
        contents,
        pivots,
        zeroed,
    }
}

/// Combinations over at most this many rows are solved densely over those rows (the
/// fraction-free LDU of a small system, faster than rational accumulation on large entries);
/// longer ones (a cycle of equalities) by reverse accumulation over the log.
const DENSE_COMBINATION: usize = 256;

/// The exact `w` with `A[t] = Σ w_k A[k]` over the independent rows `k` that row `t`'s zero
/// was built from (found by walking the log from step `last`, without arithmetic): solved
/// densely when they are few, by reverse accumulation otherwise. Verified against the rows.
fn combination(
    matrix: &IntMatrix,
    steps: &[Step],
    contents: &[Int],
    t: usize,
    last: u32,
) -> Vec<(usize, Rational)> {
    let support = support(steps, t, last);
    let w = if support.len() <= DENSE_COMBINATION {
        solve_over(matrix, t, &support)
    } else {
        None
    };
    let w = w.unwrap_or_else(|| accumulate(steps, contents, t, last));
    debug_assert!(verified(matrix, t, &w), "combination of row {t}");
    w
}

/// The rows other than `t` whose original form the zero of row `t` (made at step `last`) was
/// built from, increasing.
fn support(steps: &[Step], t: usize, last: u32) -> Vec<usize> {
    let mut seen_steps = std::collections::HashSet::new();
    let mut rows = std::collections::BTreeSet::new();
    let mut stack = vec![(t as u32, last)];
    while let Some((row, step)) = stack.pop() {
        if step == INITIAL {
            if row as usize != t {
                rows.insert(row as usize);
            }
            continue;
        }
        if !seen_steps.insert(step) {
            continue;
        }
        let s = &steps[step as usize];
        stack.push((s.target, s.previous));
        stack.push((s.pivot, s.pivot_step));
    }
    rows.into_iter().collect()
}

/// `A[t] = Σ w_k A[support_k]` solved densely over the support rows (`Aᵀ` restricted to them
/// by the fraction-free LDU); `None` if `A[t]` is not in their span (which the log rules out).
fn solve_over(matrix: &IntMatrix, t: usize, support: &[usize]) -> Option<Vec<(usize, Rational)>> {
    use api::Factorization;
    if support.is_empty() {
        return Some(Vec::new());
    }
    let mut cols: Vec<usize> = support
        .iter()
        .chain(std::iter::once(&t))
        .flat_map(|&i| matrix.row(i).iter().map(|(c, _)| *c))
        .collect();
    cols.sort_unstable();
    cols.dedup();
    let transposed = matrix.select(support, &cols).transpose();
    let target: Vec<Rational> = cols
        .iter()
        .map(|&c| Rational::from_integer(matrix.get(t, c)))
        .collect();
    let f = crate::ExactFactorization::<Int>::new(&transposed, crate::Simplification::Gcd);
    let w = f.solve(&target).ok()?;
    Some(
        support
            .iter()
            .copied()
            .zip(w)
            .filter(|(_, v)| !v.is_zero())
            .collect(),
    )
}

/// The same by reverse accumulation over the log (module documentation): the zero that row `t`
/// became at step `last` is `Σ γ_i · A[i] / content_i` over the rows it was built from, so
/// `A[t] = −Σ_{i ≠ t} (γ_i content_t / (γ_t content_i)) A[i]`.
fn accumulate(steps: &[Step], contents: &[Int], t: usize, last: u32) -> Vec<(usize, Rational)> {
    // The coefficient of the version of a row each step produced (a step makes one version of
    // one row), and of each row as given.
    let mut at_step: Vec<Option<Rational>> = vec![None; steps.len()];
    let mut at_start: Vec<Option<Rational>> = vec![None; contents.len()];
    let mut pending: BinaryHeap<u32> = BinaryHeap::new();
    let mut credit = |row: u32,
                      step: u32,
                      value: Rational,
                      at_step: &mut Vec<Option<Rational>>,
                      pending: &mut BinaryHeap<u32>| {
        let slot = if step == INITIAL {
            &mut at_start[row as usize]
        } else {
            let slot = &mut at_step[step as usize];
            if slot.is_none() {
                pending.push(step);
            }
            slot
        };
        match slot {
            Some(c) => *c += value,
            None => *slot = Some(value),
        }
    };
    // `x · k` for a small integer `k` without building a rational from it when `k = ±1`.
    let times = |x: &Rational, k: &Int| match k.to_i64() {
        Some(1) => x.clone(),
        Some(-1) => -x.clone(),
        _ => x * Rational::from_integer(k.to_bigint()),
    };
    credit(
        t as u32,
        last,
        Rational::from_integer(1.into()),
        &mut at_step,
        &mut pending,
    );
    while let Some(k) = pending.pop() {
        let step = &steps[k as usize];
        let Some(c) = at_step[k as usize].take() else {
            continue;
        };
        if c.is_zero() {
            continue;
        }
        let over_g = if step.g.is_one() {
            c
        } else {
            c / Rational::from_integer(step.g.to_bigint())
        };
        credit(
            step.target,
            step.previous,
            times(&over_g, &step.a),
            &mut at_step,
            &mut pending,
        );
        credit(
            step.pivot,
            step.pivot_step,
            -times(&over_g, &step.b),
            &mut at_step,
            &mut pending,
        );
    }
    // γ_i / content_i per original row.
    let scaled = |row: usize, gamma: &Rational| {
        if contents[row].is_one() {
            gamma.clone()
        } else {
            gamma / Rational::from_integer(contents[row].to_bigint())
        }
    };
    let own = at_start[t]
        .as_ref()
        .map(|g| scaled(t, g))
        .unwrap_or_else(Rational::zero);
    at_start
        .iter()
        .enumerate()
        .filter_map(|(row, gamma)| {
            let gamma = gamma.as_ref()?;
            (row != t && !gamma.is_zero()).then(|| (row, -(scaled(row, gamma) / &own)))
        })
        .collect()
}

/// Whether `A[t] = Σ w_k A[k]` exactly.
fn verified(matrix: &IntMatrix, t: usize, w: &[(usize, Rational)]) -> bool {
    let mut sum: std::collections::BTreeMap<usize, Rational> = Default::default();
    for (k, wk) in w {
        for (c, v) in matrix.row(*k) {
            *sum.entry(*c).or_insert_with(Rational::zero) += wk * Rational::from_integer(v.clone());
        }
    }
    for (c, v) in matrix.row(t) {
        *sum.entry(*c).or_insert_with(Rational::zero) -= Rational::from_integer(v.clone());
    }
    sum.values().all(Zero::is_zero)
}

/// [`eliminate`] per connected component of the matrix's bipartite graph; components that are
/// the same matrix with the same right-hand sides (up to renumbering) are eliminated once.
/// Identical answers up to the order of pivots, which are listed component by component.
pub fn eliminate_blockwise(
    matrix: &IntMatrix,
    rhs: &[Vec<api::Integer>],
    combinations: Combinations,
) -> SparseElimination {
    let parts = crate::blocks::components(matrix);
    // A component holding more than half of the rows (a whole mesh) has no identical twin, so
    // sharing cannot save its work: the whole matrix is then eliminated at once, without copying
    // any component. Pivots never cross components, the pivot order inside a component does not
    // depend on the others and renumbering is monotone, so each component gets the pivots of
    // its own elimination (property tested against [`eliminate_by_components`]).
    if !parts.iter().any(|(rows, _)| 2 * rows.len() > matrix.rows()) {
        return eliminate_by_components(matrix, rhs, combinations, parts);
    }
    let mut component_of_row = vec![0usize; matrix.rows()];
    for (k, (rows, _)) in parts.iter().enumerate() {
        for &i in rows {
            component_of_row[i] = k;
        }
    }
    let mut whole = eliminate(matrix, rhs, combinations);
    whole.pivots.sort_by_key(|(row, _)| component_of_row[*row]);
    whole.redundant.sort_by_key(|r| r.row);
    whole
}

/// [`eliminate`] on a copy of each of `parts` (the [`crate::blocks::components`] of `matrix`),
/// eliminating identical components once.
fn eliminate_by_components(
    matrix: &IntMatrix,
    rhs: &[Vec<api::Integer>],
    combinations: Combinations,
    parts: Vec<(Vec<usize>, Vec<usize>)>,
) -> SparseElimination {
    // Identical components (the coordinates of a split vector system) are eliminated once; the
    // component itself is the key, so no copy is made for it.
    type Key = (IntMatrix, Vec<Vec<api::Integer>>);
    let mut cache: std::collections::HashMap<Key, SparseElimination> =
        std::collections::HashMap::new();
    let mut pivots = Vec::new();
    let mut redundant = Vec::new();
    for (rows, cols, local) in crate::blocks::submatrices(matrix, parts) {
        if rows.is_empty() {
            continue;
        }
        let local_rhs: Vec<Vec<api::Integer>> = rhs
            .iter()
            .map(|col| rows.iter().map(|&i| col[i].clone()).collect())
            .collect();
        let result = match cache.entry((local, local_rhs)) {
            std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
            std::collections::hash_map::Entry::Vacant(v) => {
                let (local, local_rhs) = v.key();
                let result = eliminate(local, local_rhs, combinations);
                v.insert(result)
            }
        };
        pivots.extend(result.pivots.iter().map(|(r, c)| (rows[*r], cols[*c])));
        redundant.extend(result.redundant.iter().map(|red| {
            SparseRedundancy {
                row: rows[red.row],
                combination: red
                    .combination
                    .as_ref()
                    .map(|w| w.iter().map(|(i, v)| (rows[*i], v.clone())).collect()),
                inconsistent_columns: red.inconsistent_columns.clone(),
            }
        }));
    }
    redundant.sort_by_key(|r| r.row);
    SparseElimination {
        rank: pivots.len(),
        pivots,
        redundant,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ExactLdu;
    use api::{Factorization, LinearBackend};
    use proptest::prelude::*;

    fn sparse_case() -> impl Strategy<Value = (usize, Vec<Vec<(usize, i64)>>)> {
        (1usize..=12, 1usize..=10).prop_flat_map(|(n, m)| {
            let row = prop::collection::vec((0..n, prop_oneof![-3i64..=-1, 1i64..=3]), 0..=4);
            (Just(n), prop::collection::vec(row, m)).prop_map(|(n, mut rows)| {
                // Duplicate a combination of two rows to force redundancies.
                if rows.len() >= 2 {
                    let mut combo = rows[0].clone();
                    combo.extend(rows[1].iter().map(|(c, v)| (*c, 2 * v)));
                    rows.push(combo);
                }
                (n, rows)
            })
        })
    }

    /// A cycle of equalities `x_i − x_{i+1} = 0` closed by `x_{n−1} − x_0 = 0`: the closing
    /// row is the negated sum of all the others, found by reverse accumulation over the log
    /// (one step per row), and a row of the chain that is not in the cycle has none.
    #[test]
    fn a_long_cycle_gets_its_whole_combination() {
        let n = 5000;
        let rows: Vec<Vec<(usize, api::Integer)>> = (0..n)
            .map(|i| vec![(i, 1.into()), ((i + 1) % n, (-1).into())])
            .collect();
        let matrix = IntMatrix::from_sparse(n, rows).expect("in range");
        let e = eliminate(&matrix, &[], Combinations::Exact);
        assert_eq!(e.rank, n - 1);
        assert_eq!(e.redundant.len(), 1);
        let red = &e.redundant[0];
        let combo = red.combination.as_ref().expect("asked for");
        assert_eq!(combo.len(), n - 1);
        let minus_one = Rational::from_integer((-1).into());
        assert!(combo.iter().all(|(i, w)| *i != red.row && *w == minus_one));
        assert!(verified(&matrix, red.row, combo));
        let skipped = eliminate(&matrix, &[], Combinations::Skip);
        assert_eq!(skipped.rank, n - 1);
        assert!(skipped.redundant[0].combination.is_none());
    }

    proptest! {
        #[test]
        fn agrees_with_the_dense_factoring((n, rows) in sparse_case(), shift in -3i64..=3) {
            let matrix = IntMatrix::from_sparse(
                n,
                rows.iter().map(|r| r.iter().map(|(c, v)| (*c, (*v).into())).collect()).collect(),
            ).expect("in range");
            // A consistent right-hand side (A·x for x = 1..n) and a perturbed one.
            let good: Vec<api::Integer> = matrix.row_iter()
                .map(|r| r.iter().map(|(c, v)| v * api::Integer::from(*c as i64 + 1)).sum())
                .collect();
            let mut bad = good.clone();
            if let Some(last) = bad.last_mut() {
                *last += api::Integer::from(shift);
            }
            let e = eliminate(&matrix, &[good.clone(), bad.clone()], Combinations::Exact);
            let b = eliminate_blockwise(&matrix, &[good.clone(), bad.clone()], Combinations::Exact);
            // Eliminating the whole matrix at once (when one component has most rows) gives
            // exactly what eliminating a copy of each component does, pivot order included.
            let by_components = eliminate_by_components(
                &matrix,
                &[good.clone(), bad.clone()],
                Combinations::Exact,
                crate::blocks::components(&matrix),
            );
            prop_assert_eq!(&b, &by_components);
            prop_assert_eq!(b.rank, e.rank);
            prop_assert_eq!(b.consistent(), e.consistent());
            prop_assert_eq!(b.redundant.len(), e.redundant.len());
            let dense = ExactLdu::default().factor(&matrix).expect("factor");
            prop_assert_eq!(e.rank, dense.rank());
            prop_assert!(e.redundant.iter().all(|r| r.inconsistent_columns.iter().all(|&k| k == 1)));
            let rational = |v: &[api::Integer]| -> Vec<Rational> { v.iter().cloned().map(Rational::from_integer).collect() };
            prop_assert_eq!(e.consistent(), dense.check_consistent(&rational(&bad)).is_ok());
            // Independent rows are independent; combinations reproduce redundant rows.
            let independent: Vec<usize> = e.pivots.iter().map(|(r, _)| *r).collect();
            let all: Vec<usize> = (0..n).collect();
            let sub = ExactLdu::default().factor(&matrix.select(&independent, &all)).expect("factor");
            prop_assert_eq!(sub.rank(), independent.len());
            for red in &e.redundant {
                let combo = red.combination.clone().expect("asked for");
                for c in 0..n {
                    let s: Rational = combo.iter().map(|(i, w)| w * Rational::from_integer(matrix.get(*i, c))).sum();
                    prop_assert_eq!(s, Rational::from_integer(matrix.get(red.row, c)));
                }
                prop_assert!(combo.iter().all(|(i, _)| independent.contains(i)));
            }
            // Both ways of recovering a combination (dense over the support, reverse
            // accumulation over the log) give the same, unique, combination.
            let logged = run(&matrix, &[], Combinations::Exact);
            for &t in &logged.zeroed {
                let last = logged.rows[t].last_step;
                let dense = solve_over(&matrix, t, &support(&logged.steps, t, last));
                prop_assert_eq!(dense, Some(accumulate(&logged.steps, &logged.contents, t, last)));
            }
        }
    }
}
