//! Maximum matching of the constraint graph (Hopcroft–Karp): the structural rank, and the
//! pairing of rows with the unknowns they can be solved for.

use crate::bipartite::Bipartite;
use crate::error::StructureError;
use serde::Serialize;
use std::collections::VecDeque;

/// A matching: pairs (row, column) sharing an entry, no row or column used twice.
///
/// Both directions are stored because the Dulmage–Mendelsohn decomposition walks alternating
/// paths from either side.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize)]
pub struct Matching {
    /// For every row, the column it is matched with.
    pub row_to_col: Vec<Option<usize>>,
    /// For every column, the row it is matched with.
    pub col_to_row: Vec<Option<usize>>,
    /// Number of matched pairs.
    pub size: usize,
}

impl Matching {
    /// Checks that this is a matching of `graph`: sizes fit, both directions agree, `size` is
    /// the number of pairs, and every pair is an edge. (Maximality is checked where it
    /// matters, by [`crate::dulmage_mendelsohn`].)
    ///
    /// # Errors
    /// [`StructureError::MatchingSize`] or [`StructureError::MatchingInvalid`].
    pub fn validate(&self, graph: &Bipartite) -> Result<(), StructureError> {
        if self.row_to_col.len() != graph.rows() || self.col_to_row.len() != graph.cols() {
            return Err(StructureError::MatchingSize {
                rows: graph.rows(),
                cols: graph.cols(),
                matching_rows: self.row_to_col.len(),
                matching_cols: self.col_to_row.len(),
            });
        }
        let mut pairs = 0usize;
        for (row, mate) in self.row_to_col.iter().enumerate() {
            if let Some(col) = *mate {
                let back = self.col_to_row.get(col).copied().flatten();
                if back != Some(row) || !graph.has_edge(row, col) {
                    return Err(StructureError::MatchingInvalid { row });
                }
                pairs += 1;
            }
        }
        let col_pairs = self.col_to_row.iter().filter(|m| m.is_some()).count();
        if col_pairs != pairs || self.size != pairs {
            return Err(StructureError::MatchingInvalid { row: graph.rows() });
        }
        Ok(())
    }
}

const INF: usize = usize::MAX;

/// A maximum matching of the constraint graph by Hopcroft–Karp; its size is the structural
/// rank (the rank of the matrix for generic values of its nonzero coefficients).
///
/// Time `O(nnz · sqrt(rows + cols))`. Entirely iterative: the breadth-first phase uses a queue
/// and the depth-first phase an explicit stack with a per-row cursor into its adjacency, so
/// graphs with 10^6 nodes cannot overflow the call stack. A greedy pass seeds the matching.
/// The result is deterministic (it depends only on the graph).
pub fn maximum_matching(graph: &Bipartite) -> Matching {
    let (m, n) = (graph.rows(), graph.cols());
    let mut row_to_col: Vec<Option<usize>> = vec![None; m];
    let mut col_to_row: Vec<Option<usize>> = vec![None; n];
    let mut size = 0usize;

    // Greedy start: each row takes its first free column.
    for (i, mate) in row_to_col.iter_mut().enumerate() {
        if let Some(&j) = graph.row(i).iter().find(|&&j| col_to_row[j].is_none()) {
            *mate = Some(j);
            col_to_row[j] = Some(i);
            size += 1;
        }
    }

    let mut dist = vec![INF; m];
    let mut queue: VecDeque<usize> = VecDeque::with_capacity(m);
    // Depth-first phase state: the path of rows from a free row, and per row the position of
    // the next column to try (a row that runs out is dead for this phase).
    let mut cursor = vec![0usize; m];
    // Row `path[k + 1]` is the current mate of the column through which it was reached from
    // `path[k]`, so augmenting only needs the rows.
    let mut path: Vec<usize> = Vec::new();

    loop {
        // Breadth-first phase: layer rows by the length of the shortest alternating path from
        // a free row; `limit` is the layer from which a free column is first reached.
        queue.clear();
        for i in 0..m {
            if row_to_col[i].is_none() && !graph.row(i).is_empty() {
                dist[i] = 0;
                queue.push_back(i);
            } else {
                dist[i] = INF;
            }
        }
        let mut limit = INF;
        while let Some(i) = queue.pop_front() {
            if dist[i] >= limit {
                continue;
            }
            for &j in graph.row(i) {
                match col_to_row[j] {
                    None => {
                        if limit == INF {
                            limit = dist[i];
                        }
                    }
                    Some(k) => {
                        if dist[k] == INF {
                            dist[k] = dist[i] + 1;
                            queue.push_back(k);
                        }
                    }
                }
            }
        }
        if limit == INF {
            break;
        }

        // Depth-first phase: vertex-disjoint shortest augmenting paths along the layers.
        cursor.fill(0);
        for start in 0..m {
            if row_to_col[start].is_some() || dist[start] != 0 {
                continue;
            }
            path.clear();
            path.push(start);
            while let Some(&i) = path.last() {
                let adj = graph.row(i);
                if cursor[i] >= adj.len() {
                    // Dead end: no augmenting path through `i` in this phase.
                    dist[i] = INF;
                    path.pop();
                    continue;
                }
                let j = adj[cursor[i]];
                cursor[i] += 1;
                match col_to_row[j] {
                    None if dist[i] == limit => {
                        // Augment: the last row takes `j`, every earlier row takes the column
                        // that led to the next row on the path.
                        let mut col = j;
                        for k in (0..path.len()).rev() {
                            let row = path[k];
                            let previous = row_to_col[row];
                            row_to_col[row] = Some(col);
                            col_to_row[col] = Some(row);
                            if let Some(p) = previous {
                                col = p;
                            }
                        }
                        size += 1;
                        // Rows of the path are now matched: keep them out of this phase.
                        for &row in &path {
                            dist[row] = INF;
                        }
                        break;
                    }
                    Some(k) if dist[i] < limit && dist[k] == dist[i] + 1 => {
                        path.push(k);
                    }
                    _ => {}
                }
            }
        }
    }
    debug_assert!(size <= m.min(n));
    Matching {
        row_to_col,
        col_to_row,
        size,
    }
}
