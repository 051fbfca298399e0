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
//! is inconsistent. The combination of independent rows equal to a redundant row is recovered
//! exactly from the rows that took part in eliminating it (solving a small dense system with
//! the fraction-free LDU), and verified.

use crate::factorization::ExactFactorization;
use crate::ldu::Simplification;
use crate::ring::{gcd_all, Int, Ring};
use api::{Factorization, IntMatrix, Rational, SolveError};
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// A redundant row and its exact combination of independent rows.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SparseRedundancy {
    /// The redundant row.
    pub row: usize,
    /// `(independent row, coefficient)` with `A[row] = Σ coefficient · A[independent row]`;
    /// `None` when the rows involved were too many to solve for it densely (see
    /// [`SparseElimination::combination_limit`]).
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
    /// Largest number of independent rows a combination was solved over.
    pub combination_limit: usize,
}

impl SparseElimination {
    /// True when every right-hand-side column is consistent.
    pub fn consistent(&self) -> bool {
        self.redundant
            .iter()
            .all(|r| r.inconsistent_columns.is_empty())
    }
}

/// A sparse row with right-hand sides and the set of pivot rows that modified it.
#[derive(Debug, Clone)]
struct Row {
    entries: Vec<(usize, Int)>,
    rhs: Vec<Int>,
    support: Vec<usize>,
    active: bool,
}

/// `(a · x − b · y) / g` of two sparse rows (and right-hand sides), made primitive.
fn combine(a: &Int, x: &Row, b: &Int, y: &Row, pivot_col: usize) -> (Vec<(usize, Int)>, Vec<Int>) {
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
        return (out, rhs);
    }
    (
        out.into_iter().map(|(c, v)| (c, v.div_exact(&g))).collect(),
        rhs.iter().map(|v| v.div_exact(&g)).collect(),
    )
}

/// The entry of `row` in column `c` (which the caller knows is present).
fn entry(row: &Row, c: usize) -> &Int {
    let k = row.entries.binary_search_by_key(&c, |e| e.0).unwrap_or(0);
    &row.entries[k].1
}

fn merge_support(a: &[usize], b: &[usize], extra: usize) -> Vec<usize> {
    let mut out = Vec::with_capacity(a.len() + b.len() + 1);
    out.extend_from_slice(a);
    out.extend_from_slice(b);
    out.push(extra);
    out.sort_unstable();
    out.dedup();
    out
}

/// Eliminates `matrix` exactly, with right-hand-side columns `rhs` (each of length `rows`).
/// Combinations of redundant rows are solved over at most `combination_limit` independent rows.
pub fn eliminate(
    matrix: &IntMatrix,
    rhs: &[Vec<api::Integer>],
    combination_limit: usize,
) -> SparseElimination {
    let (m, n) = (matrix.rows(), matrix.cols());
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
                (entries, rhs_i)
            } else {
                (
                    entries
                        .into_iter()
                        .map(|(c, v)| (c, v.div_exact(&g)))
                        .collect(),
                    rhs_i.iter().map(|v| v.div_exact(&g)).collect(),
                )
            };
            Row {
                entries,
                rhs: rhs_i,
                support: Vec::new(),
                active: true,
            }
        })
        .collect();
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
        let pivot_row = rows[p].clone();
        let piv = entry(&pivot_row, c).clone();
        for &t in live.iter().filter(|&&t| t != p) {
            let utc = entry(&rows[t], c).clone();
            let h = piv.gcd(&utc);
            let (a, b) = (piv.div_exact(&h), utc.div_exact(&h));
            let before: Vec<usize> = rows[t].entries.iter().map(|e| e.0).collect();
            let (entries, rhs_t) = combine(&a, &rows[t], &b, &pivot_row, c);
            let support = merge_support(&rows[t].support, &pivot_row.support, p);
            let row = &mut rows[t];
            row.entries = entries;
            row.rhs = rhs_t;
            row.support = support;
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
    }
    zeroed.sort_unstable();
    let redundant = zeroed
        .into_iter()
        .map(|t| {
            let inconsistent_columns: Vec<usize> = rows[t]
                .rhs
                .iter()
                .enumerate()
                .filter(|(_, v)| !v.is_zero())
                .map(|(k, _)| k)
                .collect();
            SparseRedundancy {
                row: t,
                combination: combination(matrix, t, &rows[t].support, combination_limit),
                inconsistent_columns,
            }
        })
        .collect();
    SparseElimination {
        rank: pivots.len(),
        pivots,
        redundant,
        combination_limit,
    }
}

/// [`eliminate`] per connected component of the matrix's bipartite graph; components that are
/// the same matrix with the same right-hand sides (up to renumbering) are eliminated once.
/// Identical answers up to the order of pivots.
pub fn eliminate_blockwise(
    matrix: &IntMatrix,
    rhs: &[Vec<api::Integer>],
    combination_limit: usize,
) -> SparseElimination {
    type Key = (
        Vec<Vec<(usize, api::Integer)>>,
        Vec<Vec<api::Integer>>,
        usize,
    );
    let mut cache: std::collections::HashMap<Key, SparseElimination> =
        std::collections::HashMap::new();
    let mut pivots = Vec::new();
    let mut redundant = Vec::new();
    for (rows, cols, local) in crate::blocks::component_matrices(matrix) {
        if rows.is_empty() {
            continue;
        }
        let local_rhs: Vec<Vec<api::Integer>> = rhs
            .iter()
            .map(|col| rows.iter().map(|&i| col[i].clone()).collect())
            .collect();
        let key: Key = (
            local.row_iter().map(|r| r.to_vec()).collect(),
            local_rhs.clone(),
            local.cols(),
        );
        let result = cache
            .entry(key)
            .or_insert_with(|| eliminate(&local, &local_rhs, combination_limit));
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
        combination_limit,
    }
}

/// The exact `w` with `A[t] = Σ w_k A[support_k]`, solved densely over the support rows and
/// verified; `None` if the support is larger than `limit`.
fn combination(
    matrix: &IntMatrix,
    t: usize,
    support: &[usize],
    limit: usize,
) -> Option<Vec<(usize, Rational)>> {
    if support.len() > limit {
        return None;
    }
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
    // Columns as rows: (Aᵀ restricted) w = A[t]ᵀ.
    let transposed = matrix.select(support, &cols).transpose();
    let target: Vec<Rational> = cols
        .iter()
        .map(|&c| Rational::from_integer(matrix.get(t, c)))
        .collect();
    let f = ExactFactorization::<Int>::new(&transposed, Simplification::Gcd);
    match f.solve(&target) {
        Ok(w) => Some(
            support
                .iter()
                .copied()
                .zip(w)
                .filter(|(_, v)| *v != Rational::from_integer(0.into()))
                .collect(),
        ),
        Err(SolveError::Inconsistent(_)) | Err(SolveError::Input(_)) => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ExactLdu;
    use api::LinearBackend;
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
            let e = eliminate(&matrix, &[good.clone(), bad.clone()], 64);
            let b = eliminate_blockwise(&matrix, &[good.clone(), bad.clone()], 64);
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
                let combo = red.combination.clone().expect("small supports");
                for c in 0..n {
                    let s: Rational = combo.iter().map(|(i, w)| w * Rational::from_integer(matrix.get(*i, c))).sum();
                    prop_assert_eq!(s, Rational::from_integer(matrix.get(red.row, c)));
                }
                prop_assert!(combo.iter().all(|(i, _)| independent.contains(i)));
            }
        }
    }
}
