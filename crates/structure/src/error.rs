//! Why a structural computation refused its input.

/// Why a structural computation refused its input.
///
/// The graph itself is always valid once built; errors come from inputs that were made
/// elsewhere (a sparsity pattern, a matching, an index asked about) and do not fit the graph.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum StructureError {
    /// A sparsity pattern names a column outside the matrix.
    #[error("row {row} has an entry in column {col}, but the matrix has {cols} columns")]
    ColumnOutOfRange {
        /// Index of the row.
        row: usize,
        /// The offending column.
        col: usize,
        /// Number of columns.
        cols: usize,
    },
    /// A row index asked about is not a row of the graph.
    #[error("row {row} does not exist: the graph has {rows} rows")]
    NoSuchRow {
        /// The offending row.
        row: usize,
        /// Number of rows.
        rows: usize,
    },
    /// A column index asked about is not a column of the graph.
    #[error("column {col} does not exist: the graph has {cols} columns")]
    NoSuchColumn {
        /// The offending column.
        col: usize,
        /// Number of columns.
        cols: usize,
    },
    /// A matching was computed for a graph of another size.
    #[error("the matching is for a {matching_rows}×{matching_cols} graph, not {rows}×{cols}")]
    MatchingSize {
        /// Rows of the graph.
        rows: usize,
        /// Columns of the graph.
        cols: usize,
        /// Rows the matching covers.
        matching_rows: usize,
        /// Columns the matching covers.
        matching_cols: usize,
    },
    /// A matching pairs a row and a column that share no entry, or its two directions (and
    /// its size) disagree.
    #[error("the matching is not a matching of this graph (row {row})")]
    MatchingInvalid {
        /// The first row where the matching does not fit the graph (or the number of rows
        /// when only the columns' side or the size disagree).
        row: usize,
    },
    /// An augmenting path exists: the matching is not maximum, so the Dulmage–Mendelsohn parts
    /// would overlap.
    #[error(
        "the matching is not maximum: unmatched row {row} reaches unmatched column {col} by an alternating path"
    )]
    MatchingNotMaximum {
        /// An unmatched row at one end of the augmenting path.
        row: usize,
        /// The unmatched column at its other end.
        col: usize,
    },
}
