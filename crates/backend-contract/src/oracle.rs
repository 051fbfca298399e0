//! The oracle: plain rational Gauss–Jordan elimination, written here so that no backend is
//! checked against itself.
//!
//! Every answer of the suite is checked against equations whose truth this module decides:
//! ranks, membership in the row or column space, and a basis of the kernel.

use api::{IntMatrix, Rational};

fn zero() -> Rational {
    Rational::from_integer(0.into())
}

/// `matrix` as dense rational rows.
pub fn dense(matrix: &IntMatrix) -> Vec<Vec<Rational>> {
    matrix
        .to_dense()
        .into_iter()
        .map(|row| row.into_iter().map(Rational::from_integer).collect())
        .collect()
}

/// Column `k` of `matrix`.
pub fn column(matrix: &IntMatrix, k: usize) -> Vec<Rational> {
    (0..matrix.rows())
        .map(|i| Rational::from_integer(matrix.get(i, k)))
        .collect()
}

/// `A x`.
pub fn mat_vec(a: &[Vec<Rational>], x: &[Rational]) -> Vec<Rational> {
    a.iter()
        .map(|row| row.iter().zip(x).map(|(v, xi)| v * xi).sum())
        .collect()
}

/// The reduced row echelon form of `rows` (each of length `cols`) and its pivot columns.
fn echelon(rows: &[Vec<Rational>], cols: usize) -> (Vec<Vec<Rational>>, Vec<usize>) {
    let mut m: Vec<Vec<Rational>> = rows.to_vec();
    let mut pivots = Vec::new();
    for c in 0..cols {
        let rank = pivots.len();
        let Some(p) = (rank..m.len()).find(|&i| m[i][c] != zero()) else {
            continue;
        };
        m.swap(rank, p);
        let pivot = m[rank][c].clone();
        for v in m[rank].iter_mut() {
            *v = &*v / &pivot;
        }
        let pivot_row = m[rank].clone();
        for (i, row) in m.iter_mut().enumerate() {
            if i != rank && row[c] != zero() {
                let f = row[c].clone();
                for (v, p) in row.iter_mut().zip(&pivot_row).skip(c) {
                    *v -= &f * p;
                }
            }
        }
        pivots.push(c);
    }
    m.truncate(pivots.len());
    (m, pivots)
}

/// The rank of a rational matrix given by rows.
pub fn rank(rows: &[Vec<Rational>]) -> usize {
    let cols = rows.first().map_or(0, Vec::len);
    echelon(rows, cols).1.len()
}

/// `[A | b]`: `a` with the column `b` appended.
pub fn with_column(a: &[Vec<Rational>], b: &[Rational]) -> Vec<Vec<Rational>> {
    a.iter()
        .zip(b)
        .map(|(row, v)| {
            let mut row = row.clone();
            row.push(v.clone());
            row
        })
        .collect()
}

/// Whether `A x = b` has a solution: `rank [A | b] = rank A`.
pub fn is_consistent(a: &[Vec<Rational>], b: &[Rational]) -> bool {
    rank(&with_column(a, b)) == rank(a)
}

/// A basis of `{x : A x = 0}` (`n` columns): one vector per free column of the echelon form.
pub fn kernel(a: &[Vec<Rational>], n: usize) -> Vec<Vec<Rational>> {
    let (e, pivots) = echelon(a, n);
    (0..n)
        .filter(|c| !pivots.contains(c))
        .map(|free| {
            let mut x = vec![zero(); n];
            x[free] = Rational::from_integer(1.into());
            for (row, &p) in e.iter().zip(&pivots) {
                x[p] = -row[free].clone();
            }
            x
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn r(v: i64) -> Rational {
        Rational::from_integer(v.into())
    }

    #[test]
    fn rank_kernel_and_consistency_of_a_small_matrix() {
        let a = vec![
            vec![r(1), r(2), r(3)],
            vec![r(2), r(4), r(6)],
            vec![r(0), r(1), r(1)],
        ];
        assert_eq!(rank(&a), 2);
        let k = kernel(&a, 3);
        assert_eq!(k.len(), 1);
        assert!(mat_vec(&a, &k[0]).iter().all(|v| *v == r(0)));
        assert!(is_consistent(&a, &[r(1), r(2), r(0)]));
        assert!(!is_consistent(&a, &[r(1), r(3), r(0)]));
        assert_eq!(rank(&[]), 0);
        assert_eq!(kernel(&[], 2).len(), 2);
    }
}
