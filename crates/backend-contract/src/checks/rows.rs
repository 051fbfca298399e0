//! Rank, independent rows, redundancies and the rank margin.
//!
//! ```text
//! r = rank A,   rank A[I] = r = |I|,   A[t] = Σ_{k∈I} w_k A[k]  (t ∉ I)
//! ```

use super::{left_product, Check};
use crate::oracle;
use crate::tolerance::{ensure, with_numbers, Num, Tolerance, Violation};
use api::{IntMatrix, RankMargin, Rational, Redundancy, Value};

/// `rank = rank A`.
pub fn rank(a: &IntMatrix, rank: usize) -> Check {
    let want = oracle::rank(&oracle::dense(a));
    ensure(rank == want, || {
        format!("rank {rank}, but A has rank {want}")
    })
}

/// `rows` are `rank` distinct rows of `A` that are independent.
pub fn independent_rows(a: &IntMatrix, rank: usize, rows: &[usize]) -> Check {
    ensure(rows.len() == rank, || {
        format!("{} independent rows for rank {rank}", rows.len())
    })?;
    let mut sorted = rows.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    ensure(sorted.len() == rows.len(), || {
        format!("repeated rows in {rows:?}")
    })?;
    ensure(rows.iter().all(|&i| i < a.rows()), || {
        format!("{rows:?} names a row beyond {}", a.rows())
    })?;
    let dense = oracle::dense(a);
    let chosen: Vec<Vec<Rational>> = rows.iter().map(|&i| dense[i].clone()).collect();
    ensure(oracle::rank(&chosen) == rank, || {
        format!("rows {rows:?} are not independent")
    })
}

/// One redundancy per row outside `independent`, each a combination of independent rows with
/// nonzero coefficients that reproduces its row.
pub fn redundancies<S: Value>(
    a: &IntMatrix,
    independent: &[usize],
    redundancies: &[Redundancy<S>],
    tol: Tolerance,
) -> Check {
    let mut rows: Vec<usize> = independent.to_vec();
    rows.extend(redundancies.iter().map(|r| r.row));
    rows.sort_unstable();
    ensure(rows == (0..a.rows()).collect::<Vec<_>>(), || {
        format!("independent and redundant rows {rows:?} are not each row of A once")
    })?;
    for red in redundancies {
        let used: Vec<usize> = red.combination.iter().map(|(k, _)| *k).collect();
        ensure(used.iter().all(|k| independent.contains(k)), || {
            format!(
                "row {} is combined from rows {used:?}, not all independent",
                red.row
            )
        })?;
        let mut distinct = used.clone();
        distinct.sort_unstable();
        distinct.dedup();
        ensure(distinct.len() == used.len(), || {
            format!("row {} repeats a row in {used:?}", red.row)
        })?;
        let w: Vec<S> = red.combination.iter().map(|(_, w)| w.clone()).collect();
        with_numbers!(&w, tol, |w| combination_reproduces(
            a, red.row, &used, &w, tol
        ))?;
    }
    Ok(())
}

fn combination_reproduces<N: Num>(
    a: &IntMatrix,
    row: usize,
    used: &[usize],
    w: &[N],
    tol: Tolerance,
) -> Check {
    ensure(w.iter().all(|v| !v.is_exact_zero()), || {
        format!("row {row}: a coefficient is zero")
    })?;
    let combined = left_product(a, used, w);
    let target: Vec<N> = (0..a.cols())
        .map(|j| N::of_integer(&a.get(row, j)))
        .collect();
    for (j, ((s, scale), t)) in combined.iter().zip(&target).enumerate() {
        ensure(tol.is_zero(&s.minus(t), scale + t.size()), || {
            format!("row {row}, column {j}: the combination gives {s:?}, the row {t:?}")
        })?;
    }
    Ok(())
}

/// Exact backends report no margin; float backends one whose threshold separates the kept and
/// dropped diagonal magnitudes (1 kept when the rank is 0).
pub fn rank_margin(rank: usize, margin: Option<RankMargin>, tol: Tolerance) -> Check {
    match (tol, margin) {
        (Tolerance::Exact, None) => Ok(()),
        (Tolerance::Exact, Some(m)) => Err(Violation(format!(
            "an exact backend decides without a tolerance, but reports {m:?}"
        ))),
        (Tolerance::Relative(_), None) => Err(Violation(
            "a backend deciding with a tolerance must report its margin".into(),
        )),
        (Tolerance::Relative(_), Some(m)) => {
            ensure(m.tolerance > 0.0 && m.tolerance < 1.0, || {
                format!("tolerance {m:?}")
            })?;
            ensure((0.0..=m.tolerance).contains(&m.largest_dropped), || {
                format!("a dropped magnitude above the tolerance: {m:?}")
            })?;
            ensure(m.smallest_kept <= 1.0, || {
                format!("kept magnitude above 1: {m:?}")
            })?;
            if rank == 0 {
                ensure(m.smallest_kept == 1.0, || format!("rank 0 keeps 1: {m:?}"))
            } else {
                ensure(m.smallest_kept > m.tolerance, || {
                    format!("a kept magnitude below the tolerance: {m:?}")
                })
            }
        }
    }
}
