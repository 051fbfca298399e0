//! The sparse integer matrix a backend factors.

use crate::exact::Integer;
use num_traits::Zero;

/// An `rows × cols` integer matrix stored by rows; each row lists its nonzero entries by
/// increasing column.
///
/// Constraint rows are short (a C1 condition has four nonzeros), so rows are sparse; backends
/// copy the matrix into whatever layout they factor in.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
pub struct IntMatrix {
    rows: Vec<Vec<(usize, Integer)>>,
    cols: usize,
}

/// Why a matrix could not be built.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum MatrixError {
    /// A row of a dense literal has the wrong length.
    #[error("row {row} has {found} entries, expected {expected}")]
    RaggedRow {
        /// Index of the row.
        row: usize,
        /// Entries found.
        found: usize,
        /// Entries expected.
        expected: usize,
    },
    /// A sparse entry names a column outside the matrix.
    #[error("row {row} has an entry in column {col}, but the matrix has {cols} columns")]
    ColumnOutOfRange {
        /// Index of the row.
        row: usize,
        /// The offending column.
        col: usize,
        /// Number of columns.
        cols: usize,
    },
}

impl IntMatrix {
    /// The `rows × cols` zero matrix.
    pub fn zeros(rows: usize, cols: usize) -> Self {
        IntMatrix {
            rows: vec![Vec::new(); rows],
            cols,
        }
    }

    /// Builds a matrix from dense rows of any integer type; all rows must have `cols` entries.
    pub fn from_dense<T: Clone + Into<Integer>>(
        cols: usize,
        rows: &[Vec<T>],
    ) -> Result<Self, MatrixError> {
        let mut out = IntMatrix::zeros(0, cols);
        for (i, row) in rows.iter().enumerate() {
            if row.len() != cols {
                return Err(MatrixError::RaggedRow {
                    row: i,
                    found: row.len(),
                    expected: cols,
                });
            }
            out.rows.push(
                row.iter()
                    .enumerate()
                    .map(|(j, v)| (j, v.clone().into()))
                    .filter(|(_, v)| !v.is_zero())
                    .collect(),
            );
        }
        Ok(out)
    }

    /// Builds a matrix from sparse rows `(column, value)`; entries of a row are summed per
    /// column and zeros dropped.
    pub fn from_sparse(cols: usize, rows: Vec<Vec<(usize, Integer)>>) -> Result<Self, MatrixError> {
        let mut out = IntMatrix {
            rows: Vec::with_capacity(rows.len()),
            cols,
        };
        for (i, mut row) in rows.into_iter().enumerate() {
            if let Some((col, _)) = row.iter().find(|(c, _)| *c >= cols) {
                return Err(MatrixError::ColumnOutOfRange {
                    row: i,
                    col: *col,
                    cols,
                });
            }
            // Sorted and merged in place: the rows given are the rows kept, not copied.
            row.sort_by_key(|(c, _)| *c);
            row.dedup_by(|later, kept| {
                let same = later.0 == kept.0;
                if same {
                    kept.1 += std::mem::take(&mut later.1);
                }
                same
            });
            row.retain(|(_, v)| !v.is_zero());
            out.rows.push(row);
        }
        Ok(out)
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.rows.len()
    }

    /// Number of columns.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// The nonzero entries of row `i`, by increasing column.
    pub fn row(&self, i: usize) -> &[(usize, Integer)] {
        &self.rows[i]
    }

    /// Iterates over the rows.
    pub fn row_iter(&self) -> impl Iterator<Item = &[(usize, Integer)]> {
        self.rows.iter().map(|r| r.as_slice())
    }

    /// Entry `(i, j)` (zero when not stored).
    pub fn get(&self, i: usize, j: usize) -> Integer {
        self.rows[i]
            .binary_search_by_key(&j, |(c, _)| *c)
            .map(|k| self.rows[i][k].1.clone())
            .unwrap_or_else(|_| Integer::zero())
    }

    /// Number of stored nonzeros.
    pub fn nnz(&self) -> usize {
        self.rows.iter().map(Vec::len).sum()
    }

    /// The matrix as dense rows.
    pub fn to_dense(&self) -> Vec<Vec<Integer>> {
        self.rows
            .iter()
            .map(|row| {
                let mut dense = vec![Integer::zero(); self.cols];
                for (c, v) in row {
                    dense[*c] = v.clone();
                }
                dense
            })
            .collect()
    }

    /// The transpose.
    pub fn transpose(&self) -> IntMatrix {
        let mut rows = vec![Vec::new(); self.cols];
        for (i, row) in self.rows.iter().enumerate() {
            for (c, v) in row {
                rows[*c].push((i, v.clone()));
            }
        }
        IntMatrix {
            rows,
            cols: self.rows.len(),
        }
    }

    /// The sub-matrix of the given rows and columns, in the given orders.
    ///
    /// # Panics
    /// Panics if an index is out of range (callers pass indices they computed themselves).
    pub fn select(&self, rows: &[usize], cols: &[usize]) -> IntMatrix {
        // A few columns of a wide matrix (a redundant row's neighbourhood in a whole mesh): a
        // map, so the cost follows the selection and not the width.
        let position: Box<dyn Fn(usize) -> Option<usize>> = if cols.len() * 16 < self.cols {
            let map: std::collections::HashMap<usize, usize> =
                cols.iter().enumerate().map(|(k, c)| (*c, k)).collect();
            Box::new(move |c| map.get(&c).copied())
        } else {
            let mut dense = vec![usize::MAX; self.cols];
            for (k, c) in cols.iter().enumerate() {
                dense[*c] = k;
            }
            Box::new(move |c| Some(dense[c]).filter(|&k| k != usize::MAX))
        };
        let rows = rows
            .iter()
            .map(|&i| {
                let mut row: Vec<(usize, Integer)> = self.rows[i]
                    .iter()
                    .filter_map(|(c, v)| position(*c).map(|k| (k, v.clone())))
                    .collect();
                row.sort_by_key(|(c, _)| *c);
                row
            })
            .collect();
        IntMatrix {
            rows,
            cols: cols.len(),
        }
    }

    /// Appends a sparse row (entries must be in range; zeros are dropped, columns merged).
    pub fn push_row(&mut self, row: Vec<(usize, Integer)>) -> Result<(), MatrixError> {
        let index = self.rows.len();
        let single = IntMatrix::from_sparse(self.cols, vec![row]).map_err(|e| match e {
            MatrixError::ColumnOutOfRange { col, cols, .. } => MatrixError::ColumnOutOfRange {
                row: index,
                col,
                cols,
            },
            other => other,
        })?;
        self.rows.extend(single.rows);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dense_and_sparse_round_trip() {
        let m = IntMatrix::from_dense(3, &[vec![1, 0, -2], vec![0, 0, 0]]).unwrap();
        assert_eq!(m.rows(), 2);
        assert_eq!(m.nnz(), 2);
        assert_eq!(m.get(0, 2), Integer::from(-2));
        assert_eq!(m.get(1, 1), Integer::from(0));
        let t = m.transpose();
        assert_eq!(t.get(2, 0), Integer::from(-2));
        let s = m.select(&[0], &[2, 0]);
        assert_eq!(
            s.to_dense(),
            vec![vec![Integer::from(-2), Integer::from(1)]]
        );
    }

    #[test]
    fn sparse_rows_merge_and_validate() {
        let m = IntMatrix::from_sparse(
            2,
            vec![vec![(1, 3.into()), (0, 1.into()), (1, (-3).into())]],
        )
        .unwrap();
        assert_eq!(m.row(0), &[(0, Integer::from(1))]);
        assert!(matches!(
            IntMatrix::from_sparse(2, vec![vec![(2, 1.into())]]),
            Err(MatrixError::ColumnOutOfRange { col: 2, .. })
        ));
        assert!(matches!(
            IntMatrix::from_dense(2, &[vec![1]]),
            Err(MatrixError::RaggedRow { .. })
        ));
    }
}
