//! Conversion of the exact input data (integers, rationals) to `f64`, refusing values that do
//! not fit.

use api::exact::rational_to_f64;
use api::{BackendError, IntMatrix, Integer, Rational};
use num_traits::ToPrimitive;

/// A sparse row in `f64`: `(column, value)` by increasing column.
pub(crate) type FloatRow = Vec<(usize, f64)>;

/// The rows of an integer matrix in `f64`; `what` names the matrix in the error.
pub(crate) fn matrix_rows(matrix: &IntMatrix, what: &str) -> Result<Vec<FloatRow>, BackendError> {
    matrix
        .row_iter()
        .enumerate()
        .map(|(i, row)| {
            row.iter()
                .map(|(j, v)| Ok((*j, entry_to_f64(v, i, *j, what)?)))
                .collect()
        })
        .collect()
}

/// The local index of each column of a matrix `width` wide for a part with columns `cols`
/// (increasing): column `cols[k]` is `k`, the others `usize::MAX`.
pub(crate) fn local_columns(width: usize, cols: &[usize]) -> Vec<usize> {
    let mut local = vec![usize::MAX; width];
    for (k, &c) in cols.iter().enumerate() {
        local[c] = k;
    }
    local
}

/// Row `i` of `matrix` in `f64` over the local columns `local` (see [`local_columns`]): a row
/// of a submatrix without an integer copy of it. Errors name entries of `matrix`, including one
/// outside the part's columns.
pub(crate) fn part_row(
    matrix: &IntMatrix,
    i: usize,
    local: &[usize],
    what: &str,
) -> Result<FloatRow, BackendError> {
    matrix
        .row(i)
        .iter()
        .map(|(j, v)| {
            Ok((
                local_column(local, i, *j, what)?,
                entry_to_f64(v, i, *j, what)?,
            ))
        })
        .collect()
}

/// The local index of column `j` (of row `i`), refused if it is outside the part.
pub(crate) fn local_column(
    local: &[usize],
    i: usize,
    j: usize,
    what: &str,
) -> Result<usize, BackendError> {
    match local[j] {
        usize::MAX => Err(BackendError::Numerical(format!(
            "entry ({i}, {j}) of the {what} is outside the given columns"
        ))),
        k => Ok(k),
    }
}

/// Entry `(i, j)` of an integer matrix in `f64`, refused if it does not fit.
fn entry_to_f64(v: &Integer, i: usize, j: usize, what: &str) -> Result<f64, BackendError> {
    v.to_f64()
        .filter(|f| f.is_finite())
        .or_else(|| {
            Some(rational_to_f64(&Rational::from_integer(v.clone()))).filter(|f| f.is_finite())
        })
        .ok_or_else(|| {
            BackendError::Numerical(format!(
                "entry ({i}, {j}) of the {what} does not fit in f64"
            ))
        })
}

/// A vector of rationals in `f64`; `what` names the vector in the error.
pub(crate) fn rationals(values: &[Rational], what: &str) -> Result<Vec<f64>, BackendError> {
    values
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let f = rational_to_f64(v);
            if f.is_finite() {
                Ok(f)
            } else {
                Err(BackendError::Numerical(format!(
                    "entry {i} of the {what} does not fit in f64"
                )))
            }
        })
        .collect()
}

/// `Σ row_j x_j` and `Σ |row_j| |x_j|` (the magnitude its rounding error is proportional to).
pub(crate) fn dot_with_magnitude(row: &[(usize, f64)], x: &[f64]) -> (f64, f64) {
    row.iter().fold((0.0, 0.0), |(s, m), (j, v)| {
        (s + v * x[*j], m + (v * x[*j]).abs())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::Integer;

    #[test]
    fn huge_values_are_refused() {
        let huge = Integer::from(10).pow(400u32);
        let a = IntMatrix::from_sparse(2, vec![vec![(1, huge.clone())]]).expect("matrix");
        assert!(matches!(
            matrix_rows(&a, "matrix"),
            Err(BackendError::Numerical(_))
        ));
        let v = [
            Rational::from_integer(1.into()),
            Rational::from_integer(huge),
        ];
        assert!(matches!(
            rationals(&v, "right-hand side"),
            Err(BackendError::Numerical(_))
        ));
        let small = Rational::new(1.into(), Integer::from(10).pow(400u32));
        assert_eq!(
            rationals(&[small], "hints").expect("tiny is zero"),
            vec![0.0]
        );
    }

    #[test]
    fn ordinary_values_convert() {
        let a = IntMatrix::from_dense(2, &[vec![3, -4]]).expect("matrix");
        assert_eq!(
            matrix_rows(&a, "matrix").expect("fits"),
            vec![vec![(0, 3.0), (1, -4.0)]]
        );
        let v = [Rational::new(1.into(), 4.into())];
        assert_eq!(rationals(&v, "hints").expect("fits"), vec![0.25]);
        assert_eq!(
            dot_with_magnitude(&[(0, 3.0), (1, -4.0)], &[1.0, 1.0]),
            (-1.0, 7.0)
        );
    }
}
