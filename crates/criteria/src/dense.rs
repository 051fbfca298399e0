//! Dense exact linear algebra over the rationals, for the small systems the criteria work on:
//! Gauss–Jordan reduction with a choice of pivot columns, the weighted least-norm solution,
//! and the projection that eliminates some unknowns.
//!
//! Dense and plain on purpose: the criteria refuse systems beyond [`crate::DENSE_LIMIT`]
//! entries, and every routine here must be easy to check by reading (the simplex and the
//! support search rest on it).

use api::Rational;
use num_traits::Zero;

/// A dense matrix, row by row.
pub(crate) type Matrix = Vec<Vec<Rational>>;

/// Gauss–Jordan reduction of `m` in place, pivots taken only in `pivot_columns` (in that order
/// of preference): returns the pivot column of each of the first rows. Afterwards each pivot
/// column is a unit vector (1 in its row), and the rows after the pivot rows are zero in every
/// column of `pivot_columns`. Other columns are carried along (right-hand sides, or columns
/// that are only eliminated into).
pub(crate) fn reduce_rows(m: &mut Matrix, pivot_columns: &[usize]) -> Vec<usize> {
    let mut pivots = Vec::new();
    for &col in pivot_columns {
        let rank = pivots.len();
        let Some(found) = (rank..m.len()).find(|&r| !m[r][col].is_zero()) else {
            continue;
        };
        m.swap(rank, found);
        let inverse = m[rank][col].recip();
        for value in m[rank].iter_mut() {
            if !value.is_zero() {
                *value *= &inverse;
            }
        }
        let pivot_row = m[rank].clone();
        for (r, row) in m.iter_mut().enumerate() {
            if r == rank || row[col].is_zero() {
                continue;
            }
            let factor = row[col].clone();
            for (value, p) in row.iter_mut().zip(&pivot_row) {
                if !p.is_zero() {
                    *value -= &factor * p;
                }
            }
        }
        pivots.push(col);
        if pivots.len() == m.len() {
            break;
        }
    }
    pivots
}

/// The rank of the columns `cols` of `m`.
pub(crate) fn rank_of_columns(m: &Matrix, cols: &[usize]) -> usize {
    let mut sub: Matrix = m
        .iter()
        .map(|row| cols.iter().map(|&c| row[c].clone()).collect())
        .collect();
    let all: Vec<usize> = (0..cols.len()).collect();
    reduce_rows(&mut sub, &all).len()
}

/// The system `m y = t` with only independent rows: `m` reduced over all its columns; `None`
/// when it has no solution.
pub(crate) fn independent_rows(m: &Matrix, t: &[Rational]) -> Option<(Matrix, Vec<Rational>)> {
    let n = m.first().map_or(0, Vec::len);
    let mut a: Matrix = m
        .iter()
        .zip(t)
        .map(|(row, t)| row.iter().cloned().chain([t.clone()]).collect())
        .collect();
    let all: Vec<usize> = (0..n).collect();
    let rank = reduce_rows(&mut a, &all).len();
    if a[rank..].iter().any(|row| !row[n].is_zero()) {
        return None;
    }
    a.truncate(rank);
    let rhs = a
        .iter_mut()
        .map(|row| row.pop().unwrap_or_default())
        .collect();
    Some((a, rhs))
}

/// The solution of `m y = t` of least `Σ w_j y_j²` (`w` positive), the other columns of `cols`
/// zero: `y = W⁻¹ Mᵀ λ` with `(M W⁻¹ Mᵀ) λ = t` over independent rows. `None` when there is no
/// solution with support in `cols`. Returns a full-length vector (`m`'s width).
pub(crate) fn least_norm(
    m: &Matrix,
    t: &[Rational],
    weights: &[Rational],
    cols: &[usize],
) -> Option<Vec<Rational>> {
    let width = weights.len();
    let sub: Matrix = m
        .iter()
        .map(|row| cols.iter().map(|&c| row[c].clone()).collect())
        .collect();
    let (rows, rhs) = independent_rows(&sub, t)?;
    let r = rows.len();
    let inverse_weights: Vec<Rational> = cols.iter().map(|&c| weights[c].recip()).collect();
    // [G | t] with G = M W⁻¹ Mᵀ, symmetric positive definite (independent rows).
    let mut gram: Matrix = (0..r)
        .map(|i| {
            (0..r)
                .map(|k| {
                    let mut sum = Rational::zero();
                    for ((a, b), w) in rows[i].iter().zip(&rows[k]).zip(&inverse_weights) {
                        if !a.is_zero() && !b.is_zero() {
                            sum += a * b * w;
                        }
                    }
                    sum
                })
                .chain([rhs[i].clone()])
                .collect()
        })
        .collect();
    let all: Vec<usize> = (0..r).collect();
    let rank = reduce_rows(&mut gram, &all).len();
    debug_assert_eq!(rank, r, "independent rows give a regular Gram matrix");
    let lambda: Vec<Rational> = gram.iter().map(|row| row[r].clone()).collect();
    let mut y = vec![Rational::zero(); width];
    for (j, &c) in cols.iter().enumerate() {
        let mut sum = Rational::zero();
        for (row, l) in rows.iter().zip(&lambda) {
            if !row[j].is_zero() {
                sum += &row[j] * l;
            }
        }
        y[c] = sum * &inverse_weights[j];
    }
    Some(y)
}

/// Eliminates the unknowns `eliminated` from `m y = t_k` (one system per right-hand side):
/// the rows of the reduced system that no longer involve them, `m' y' = t'_k` over the other
/// columns `kept` (in that order). A `y'` solves it iff some values of the eliminated unknowns
/// complete it to a solution of the whole system.
pub(crate) fn eliminate(
    m: &Matrix,
    rhs: &[Vec<Rational>],
    eliminated: &[usize],
    kept: &[usize],
) -> (Matrix, Vec<Vec<Rational>>) {
    let width = m.first().map_or(0, Vec::len);
    let mut a = augmented(m, rhs);
    let rank = reduce_rows(&mut a, eliminated).len();
    let rest = &a[rank..];
    let projected = rest
        .iter()
        .map(|row| kept.iter().map(|&c| row[c].clone()).collect())
        .collect();
    let projected_rhs = (0..rhs.len())
        .map(|k| rest.iter().map(|row| row[width + k].clone()).collect())
        .collect();
    (projected, projected_rhs)
}

/// `[m | t_0 … t_K]`: `m` with the right-hand sides as extra columns.
pub(crate) fn augmented(m: &Matrix, rhs: &[Vec<Rational>]) -> Matrix {
    m.iter()
        .enumerate()
        .map(|(i, row)| {
            row.iter()
                .cloned()
                .chain(rhs.iter().map(|column| column[i].clone()))
                .collect()
        })
        .collect()
}

/// `m y` for one right-hand side.
pub(crate) fn times(m: &Matrix, y: &[Rational]) -> Vec<Rational> {
    m.iter()
        .map(|row| {
            let mut sum = Rational::zero();
            for (a, x) in row.iter().zip(y) {
                if !a.is_zero() && !x.is_zero() {
                    sum += a * x;
                }
            }
            sum
        })
        .collect()
}

/// `Σ w_j y_j²`.
pub(crate) fn weighted_squares(y: &[Rational], weights: &[Rational]) -> Rational {
    y.iter()
        .zip(weights)
        .filter(|(y, _)| !y.is_zero())
        .map(|(y, w)| y * y * w)
        .fold(Rational::zero(), |sum, term| sum + term)
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_traits::One;

    fn one() -> Rational {
        Rational::one()
    }

    fn q(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    fn matrix(rows: &[&[i64]]) -> Matrix {
        rows.iter()
            .map(|row| row.iter().map(|&v| q(v, 1)).collect())
            .collect()
    }

    #[test]
    fn reduction_finds_the_rank_and_unit_pivot_columns() {
        let mut m = matrix(&[&[1, 2, 3], &[2, 4, 6], &[1, 0, 1]]);
        let pivots = reduce_rows(&mut m, &[0, 1, 2]);
        assert_eq!(pivots, vec![0, 1]);
        assert_eq!(m[0], vec![q(1, 1), q(0, 1), q(1, 1)]);
        assert_eq!(m[1], vec![q(0, 1), q(1, 1), q(1, 1)]);
        assert!(m[2].iter().all(Zero::is_zero));
    }

    #[test]
    fn the_least_norm_solution_is_weighted() {
        // y0 + y1 = 3 with weights 1 and 2: y = (2, 1) (y_j ∝ 1/w_j).
        let m = matrix(&[&[1, 1]]);
        let y = least_norm(&m, &[q(3, 1)], &[q(1, 1), q(2, 1)], &[0, 1]).expect("solvable");
        assert_eq!(y, vec![q(2, 1), q(1, 1)]);
        // Restricted to column 1: y = (0, 3).
        let y = least_norm(&m, &[q(3, 1)], &[q(1, 1), q(2, 1)], &[1]).expect("solvable");
        assert_eq!(y, vec![q(0, 1), q(3, 1)]);
        // Inconsistent.
        let m = matrix(&[&[1, 1], &[2, 2]]);
        assert!(least_norm(&m, &[q(1, 1), q(3, 1)], &[one(), one()], &[0, 1]).is_none());
    }

    #[test]
    fn elimination_keeps_what_the_other_unknowns_must_satisfy() {
        // y0 + y2 = 1, y1 + y2 = 2: eliminating y2 leaves y1 − y0 = 1 (up to scale).
        let m = matrix(&[&[1, 0, 1], &[0, 1, 1]]);
        let (p, t) = eliminate(&m, &[vec![q(1, 1), q(2, 1)]], &[2], &[0, 1]);
        assert_eq!(p.len(), 1);
        assert_eq!(&p[0][1] * q(1, 1) + &p[0][0], q(0, 1));
        assert_eq!(&t[0][0], &p[0][1]);
        assert_eq!(rank_of_columns(&m, &[0, 1, 2]), 2);
    }
}
