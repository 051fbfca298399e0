//! The row rank of a large sparse matrix in `f64`: a sparse QR of `A` by Givens rotations
//! (George and Heath, "Solution of sparse linear least squares problems using Givens
//! rotations", Linear Algebra Appl. 34, 1980) with a row-oriented rank test, for the
//! whole-system cross-check of meshes whose dense QR would not fit.
//!
//! The columns of `A` are ordered to keep `R` sparse (approximate minimum degree on the pattern
//! of `Aᵀ A`, whose Cholesky factor has the pattern of `R`). The rows of `A`, scaled to unit
//! length, are rotated into `R` one at a time, in the order of their first column: while the
//! row's first column holds a row of `R`, a rotation of the two zeroes that entry; at the first
//! free column `k` what is left, `x`, becomes row `k` of `R`. In exact arithmetic a row in the
//! span of the rows before it is rotated to `x = 0` (a nonzero combination of the rows of `R`
//! starts in an occupied column); in `f64` rounding leaves entries at the level of the unit
//! roundoff, and one of them at a free column must not take that column. So, Heath's rule, a
//! new diagonal entry `|x_k|` must exceed the tolerance (the rows have unit length, like the
//! dense QR's diagonal test on unit rows); a smaller one is set to zero and the rotations go on.
//! A row is independent when it takes a column, dependent when nothing of it is left; the
//! margin reports the smallest diagonal entry kept and the largest one set to zero.
//!
//! Like every rank test in `f64` without pivoting this is a heuristic: a row independent only
//! by less than the tolerance is dropped, and a row processed early is never revisited. The
//! float answer is a cross-check, never a verdict.
//!
//! Why our own kernel: faer's sparse QR does not reveal rank (no pivoting, `R` not exposed) and
//! SuiteSparseQR is GPL with no maintained Rust binding; the rotations are a short loop over
//! sorted sparse rows. Every operation is a plain `f64` operation in a fixed order, so the
//! answer is the same on every machine.

use crate::column_order::{column_order, RowPattern};
use crate::convert::{local_column, local_columns, matrix_rows, part_row};
use api::{BackendError, IntMatrix, RankMargin};

/// The float row rank of a sparse matrix (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct SparseRowRank {
    /// Rows kept as independent.
    pub rank: usize,
    /// The independent rows, increasing.
    pub independent: Vec<usize>,
    /// How far the kept and dropped diagonal magnitudes were from the threshold.
    pub margin: RankMargin,
}

/// A sparse row of `R` or a vector being rotated in: `(position, value)`, positions increasing.
pub(crate) type SparseVector = Vec<(u32, f64)>;

/// The rank of `matrix` by the sparse Givens QR of `A` with relative `tolerance`.
pub fn sparse_row_rank(matrix: &IntMatrix, tolerance: f64) -> Result<SparseRowRank, BackendError> {
    let n = matrix.cols();
    u32::try_from(n).map_err(|_| BackendError::Numerical("too many columns".into()))?;
    let rows = matrix_rows(matrix, "matrix")?;
    let position = positions(&column_order(&RowPattern::of_rows(&rows, n)?));
    let scaled = rows
        .iter()
        .enumerate()
        .map(|(i, row)| (i, scaled_row(row, &position)))
        .collect();
    drop(rows);
    Ok(rank_of_scaled(scaled, n, tolerance))
}

/// [`sparse_row_rank`] of the submatrix of `matrix` with rows `rows` and columns `cols`
/// (increasing; every column those rows use, such as a connected component's), read straight
/// from `matrix`: no integer copy of the submatrix, and its rows are made in `f64` only after
/// the column order, from the pattern alone (at a whole mesh, AMD's workspace and the `f64` rows
/// together were the cross-check's peak of memory). Row `k` of the result is `rows[k]`.
pub fn sparse_part_row_rank(
    matrix: &IntMatrix,
    rows: &[usize],
    cols: &[usize],
    tolerance: f64,
) -> Result<SparseRowRank, BackendError> {
    let n = cols.len();
    u32::try_from(n).map_err(|_| BackendError::Numerical("too many columns".into()))?;
    let local = local_columns(matrix.cols(), cols);
    let mut pattern = RowPattern::with_capacity(rows.len(), n)?;
    for &i in rows {
        for (j, _) in matrix.row(i) {
            pattern.push(local_column(&local, i, *j, "matrix")?)?;
        }
        pattern.end_row();
    }
    let position = positions(&column_order(&pattern));
    drop(pattern);
    let scaled = rows
        .iter()
        .enumerate()
        .map(|(k, &i)| {
            Ok((
                k,
                scaled_row(&part_row(matrix, i, &local, "matrix")?, &position),
            ))
        })
        .collect::<Result<Vec<_>, BackendError>>()?;
    Ok(rank_of_scaled(scaled, n, tolerance))
}

/// The position of each column in `order`.
fn positions(order: &[usize]) -> Vec<u32> {
    let mut position = vec![0u32; order.len()];
    for (k, &c) in order.iter().enumerate() {
        position[c] = k as u32;
    }
    position
}

/// A row of `A` at unit length over the column positions, sorted (zeros left out).
fn scaled_row(row: &[(usize, f64)], position: &[u32]) -> SparseVector {
    let norm = row.iter().map(|(_, v)| v * v).sum::<f64>().sqrt();
    let mut x: SparseVector = row
        .iter()
        .filter(|(_, v)| *v != 0.0)
        .map(|(c, v)| (position[*c], v / norm))
        .collect();
    x.sort_unstable_by_key(|(k, _)| *k);
    x
}

/// The rank of the rows `scaled` (`(row, unit row over the column positions)`) over `n`
/// columns (see the module documentation).
fn rank_of_scaled(
    mut scaled: Vec<(usize, SparseVector)>,
    n: usize,
    tolerance: f64,
) -> SparseRowRank {
    scaled.sort_by_key(|(i, x)| (x.first().map_or(u32::MAX, |(k, _)| *k), *i));
    let mut r: Vec<SparseVector> = vec![Vec::new(); n];
    let mut scratch = (Vec::new(), Vec::new());
    let mut independent = Vec::new();
    let (mut smallest_kept, mut largest_dropped) = (1.0_f64, 0.0_f64);
    for (i, x) in scaled {
        let landed = rotate_in(&mut r, x, tolerance, &mut largest_dropped, &mut scratch);
        if let Some((k, rest)) = landed {
            smallest_kept = smallest_kept.min(rest[0].1.abs());
            r[k] = rest;
            independent.push(i);
        }
    }
    independent.sort_unstable();
    SparseRowRank {
        rank: independent.len(),
        independent,
        margin: RankMargin {
            smallest_kept,
            largest_dropped,
            tolerance,
        },
    }
}

/// Rotates the row `x` into `R` (George–Heath): while its first position `k` holds a row of
/// `R`, a Givens rotation of that row and `x` zeroes `x_k`. At a free position `k`, `x` becomes
/// row `k` of `R` if `|x_k| > tolerance` (returned, for the caller to install); a smaller `x_k`
/// is rounding left by the rotations (Heath's rule: it is set to zero, `largest_dropped`
/// records it) and the rotations go on. `None` when nothing of `x` is left: it depends on the
/// rows before it.
pub(crate) fn rotate_in(
    r: &mut [SparseVector],
    mut x: SparseVector,
    tolerance: f64,
    largest_dropped: &mut f64,
    scratch: &mut (SparseVector, SparseVector),
) -> Option<(usize, SparseVector)> {
    let mut start = 0;
    while let Some(&(k, xk)) = x.get(start) {
        let row = &mut r[k as usize];
        let Some(&(_, rkk)) = row.first() else {
            if xk.abs() > tolerance {
                x.drain(..start);
                return Some((k as usize, x));
            }
            *largest_dropped = largest_dropped.max(xk.abs());
            start += 1;
            continue;
        };
        let rho = rkk.hypot(xk);
        let (c, s) = (rkk / rho, xk / rho);
        let (new_row, new_x) = scratch;
        new_row.clear();
        new_x.clear();
        let (mut i, mut j) = (0, start);
        while i < row.len() || j < x.len() {
            let pi = row.get(i).map_or(u32::MAX, |e| e.0);
            let pj = x.get(j).map_or(u32::MAX, |e| e.0);
            let (p, a, b) = if pi < pj {
                i += 1;
                (pi, row[i - 1].1, 0.0)
            } else if pj < pi {
                j += 1;
                (pj, 0.0, x[j - 1].1)
            } else {
                i += 1;
                j += 1;
                (pi, row[i - 1].1, x[j - 1].1)
            };
            if p == k {
                new_row.push((p, rho));
                continue;
            }
            let (u, w) = (c * a + s * b, c * b - s * a);
            if u != 0.0 {
                new_row.push((p, u));
            }
            if w != 0.0 {
                new_x.push((p, w));
            }
        }
        std::mem::swap(row, new_row);
        std::mem::swap(&mut x, new_x);
        start = 0;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn matrix(cols: usize, rows: &[&[(usize, i64)]]) -> IntMatrix {
        IntMatrix::from_sparse(
            cols,
            rows.iter()
                .map(|r| r.iter().map(|(c, v)| (*c, (*v).into())).collect())
                .collect(),
        )
        .expect("in range")
    }

    /// Exact dependencies are dropped with a wide margin, and the kept rows are independent.
    #[test]
    fn dependent_rows_are_dropped_with_a_wide_margin() {
        // r2 = r0 + 2 r1, r4 = r3 − r0; r5 zero.
        let a = matrix(
            5,
            &[
                &[(0, 1), (1, 2)],
                &[(1, 1), (2, -3)],
                &[(0, 1), (1, 4), (2, -6)],
                &[(3, 2), (4, 5)],
                &[(0, -1), (1, -2), (3, 2), (4, 5)],
                &[],
            ],
        );
        let rank = sparse_row_rank(&a, 1e-10).expect("finite");
        assert_eq!(rank.rank, 3);
        assert!(rank.margin.smallest_kept > 1e-3, "{:?}", rank.margin);
        assert!(rank.margin.largest_dropped < 1e-14, "{:?}", rank.margin);
        let dense = crate::FloatQr::default();
        let f = api::LinearBackend::factor(&dense, &a).expect("factor");
        assert_eq!(api::Factorization::rank(&f), 3);
    }

    /// The rank of a long banded system with a cycle agrees with the dense QR.
    #[test]
    fn a_cycle_of_equalities_loses_one_rank() {
        let n = 300;
        let rows: Vec<Vec<(usize, i64)>> =
            (0..n).map(|i| vec![(i, 3), ((i + 1) % n, -3)]).collect();
        let refs: Vec<&[(usize, i64)]> = rows.iter().map(Vec::as_slice).collect();
        let rank = sparse_row_rank(&matrix(n, &refs), 1e-10).expect("finite");
        assert_eq!(rank.rank, n - 1);
        assert_eq!(rank.independent.len(), n - 1);
    }
}
