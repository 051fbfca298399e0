//! The constraint graph: constraint rows on one side, unknowns (columns) on the other, an edge
//! wherever a row has a nonzero coefficient.

use crate::error::StructureError;
use api::IntMatrix;
use petgraph::graph::UnGraph;
use serde::Serialize;

/// A node of the petgraph view of a [`Bipartite`] graph.
///
/// Kept as the node weight so that results of petgraph algorithms can be read back without
/// remembering the numbering convention.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub enum Node {
    /// Constraint row `i` of the matrix.
    Row(usize),
    /// Unknown (column) `j` of the matrix.
    Col(usize),
}

/// The bipartite constraint graph of a sparse matrix, with adjacency both ways.
///
/// Rows and columns keep the matrix's numbering. Adjacency is stored in compressed form (one
/// offset array and one index array per side), both sides sorted, because every algorithm here
/// walks rows to columns (matching, over-determined part, block dependencies) and columns to
/// rows (under-determined part), and a spline system has 10^5 nodes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Bipartite {
    rows: usize,
    cols: usize,
    row_start: Vec<usize>,
    row_cols: Vec<usize>,
    col_start: Vec<usize>,
    col_rows: Vec<usize>,
}

impl Bipartite {
    /// The graph of an integer matrix: an edge for every stored (hence nonzero) entry.
    ///
    /// Coefficients are dropped; only the pattern matters for structure.
    pub fn from_matrix(matrix: &IntMatrix) -> Self {
        let mut row_start = Vec::with_capacity(matrix.rows() + 1);
        let mut row_cols = Vec::with_capacity(matrix.nnz());
        row_start.push(0);
        for row in matrix.row_iter() {
            // IntMatrix rows are sorted by column, merged and free of zeros.
            row_cols.extend(row.iter().map(|(c, _)| *c));
            row_start.push(row_cols.len());
        }
        Self::from_compressed_rows(matrix.cols(), row_start, row_cols)
    }

    /// The graph of a sparsity pattern: `rows[i]` lists the columns where row `i` has an entry.
    ///
    /// Useful when the coefficients are not integers or not at hand. Repeated columns in a row
    /// count once.
    ///
    /// # Errors
    /// [`StructureError::ColumnOutOfRange`] if a row names a column `>= cols`.
    pub fn from_pattern(cols: usize, rows: &[Vec<usize>]) -> Result<Self, StructureError> {
        let mut row_start = Vec::with_capacity(rows.len() + 1);
        let mut row_cols = Vec::with_capacity(rows.iter().map(Vec::len).sum());
        row_start.push(0);
        for (i, row) in rows.iter().enumerate() {
            if let Some(&col) = row.iter().find(|&&c| c >= cols) {
                return Err(StructureError::ColumnOutOfRange { row: i, col, cols });
            }
            let begin = row_cols.len();
            row_cols.extend_from_slice(row);
            row_cols[begin..].sort_unstable();
            // Remove repeats within this row only.
            let mut write = begin;
            for read in begin..row_cols.len() {
                if write == begin || row_cols[write - 1] != row_cols[read] {
                    row_cols[write] = row_cols[read];
                    write += 1;
                }
            }
            row_cols.truncate(write);
            row_start.push(row_cols.len());
        }
        Ok(Self::from_compressed_rows(cols, row_start, row_cols))
    }

    /// Builds the column side by counting sort (columns' rows come out sorted).
    fn from_compressed_rows(cols: usize, row_start: Vec<usize>, row_cols: Vec<usize>) -> Self {
        let rows = row_start.len().saturating_sub(1);
        let mut col_start = vec![0usize; cols + 1];
        for &c in &row_cols {
            col_start[c + 1] += 1;
        }
        for j in 0..cols {
            col_start[j + 1] += col_start[j];
        }
        let mut next = col_start.clone();
        let mut col_rows = vec![0usize; row_cols.len()];
        for i in 0..rows {
            for &c in &row_cols[row_start[i]..row_start[i + 1]] {
                col_rows[next[c]] = i;
                next[c] += 1;
            }
        }
        Bipartite {
            rows,
            cols,
            row_start,
            row_cols,
            col_start,
            col_rows,
        }
    }

    /// Number of constraint rows.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of unknowns (columns).
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// Number of edges (nonzero entries).
    pub fn nnz(&self) -> usize {
        self.row_cols.len()
    }

    /// The columns of row `i`, increasing.
    ///
    /// # Panics
    /// Panics if `i >= self.rows()`.
    pub fn row(&self, i: usize) -> &[usize] {
        &self.row_cols[self.row_start[i]..self.row_start[i + 1]]
    }

    /// The rows of column `j`, increasing.
    ///
    /// # Panics
    /// Panics if `j >= self.cols()`.
    pub fn col(&self, j: usize) -> &[usize] {
        &self.col_rows[self.col_start[j]..self.col_start[j + 1]]
    }

    /// Whether row `i` has an entry in column `j` (false for indices out of range).
    pub fn has_edge(&self, i: usize, j: usize) -> bool {
        i < self.rows && j < self.cols && self.row(i).binary_search(&j).is_ok()
    }

    /// The same graph as a petgraph undirected graph, for users who want petgraph's
    /// algorithms.
    ///
    /// Node `i` (for `i < rows`) is [`Node::Row`]`(i)`, node `rows + j` is [`Node::Col`]`(j)`;
    /// edges are listed row by row, by increasing column.
    pub fn to_petgraph(&self) -> UnGraph<Node, ()> {
        let mut g = UnGraph::with_capacity(self.rows + self.cols, self.nnz());
        for i in 0..self.rows {
            g.add_node(Node::Row(i));
        }
        for j in 0..self.cols {
            g.add_node(Node::Col(j));
        }
        for i in 0..self.rows {
            for &j in self.row(i) {
                g.add_edge(
                    petgraph::graph::NodeIndex::new(i),
                    petgraph::graph::NodeIndex::new(self.rows + j),
                    (),
                );
            }
        }
        g
    }

    /// Checks that `row` is a row of the graph.
    pub(crate) fn check_row(&self, row: usize) -> Result<(), StructureError> {
        if row < self.rows {
            Ok(())
        } else {
            Err(StructureError::NoSuchRow {
                row,
                rows: self.rows,
            })
        }
    }

    /// Checks that `col` is a column of the graph.
    pub(crate) fn check_col(&self, col: usize) -> Result<(), StructureError> {
        if col < self.cols {
            Ok(())
        } else {
            Err(StructureError::NoSuchColumn {
                col,
                cols: self.cols,
            })
        }
    }
}
