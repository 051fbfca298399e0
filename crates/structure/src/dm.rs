//! The Dulmage–Mendelsohn decomposition: the over-, well- and under-determined parts of the
//! constraint graph, and the irreducible blocks of the well-determined part in an order in
//! which they can be solved (Brenner 2.1, figure 1(c)–(d)).

use crate::bipartite::Bipartite;
use crate::error::StructureError;
use crate::matching::{maximum_matching, Matching};
use serde::Serialize;
use std::cmp::Reverse;
use std::collections::{BinaryHeap, VecDeque};

/// Which coarse part of the decomposition a row or column lies in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PartKind {
    /// Over-determined: every maximum matching leaves some of these rows unmatched; the rows
    /// involve only columns of this part and outnumber them.
    Over,
    /// Well-determined: as many rows as columns, perfectly matched; solvable block by block.
    Well,
    /// Under-determined: every maximum matching leaves some of these columns unmatched; the
    /// columns outnumber the rows, so some unknowns stay free.
    Under,
}

/// A coarse part: its rows and columns, each increasing.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize)]
pub struct Part {
    /// Constraint rows of the part, increasing.
    pub rows: Vec<usize>,
    /// Unknowns of the part, increasing.
    pub cols: Vec<usize>,
}

/// An irreducible block of the well-determined part: as many rows as columns, and no proper
/// subset of its rows involves as few unknowns of the block as it has rows (Brenner's
/// irreducible subgraph).
///
/// Once the blocks listed in `depends_on` (and the columns in `over_inputs`) are known, the
/// block's rows fix its columns; it cannot be split further by structure alone.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize)]
pub struct Block {
    /// Constraint rows of the block, increasing.
    pub rows: Vec<usize>,
    /// Unknowns the block determines, increasing (as many as rows).
    pub cols: Vec<usize>,
    /// Blocks whose columns appear in this block's rows (the edges of the collapsed graph `H`),
    /// increasing; every one of them comes earlier in the solve order.
    pub depends_on: Vec<usize>,
    /// Columns of the over-determined part that appear in this block's rows, increasing: the
    /// over-determined part is solved before any block.
    pub over_inputs: Vec<usize>,
}

/// The Dulmage–Mendelsohn decomposition of a constraint graph.
///
/// Block triangular form: rows of the over part have entries only in over columns; rows of the
/// well part have entries only in well and over columns; rows of the under part may have
/// entries anywhere. Solving goes over part, then the well blocks in order, then the under
/// part (which leaves free unknowns).
///
/// This is structure only: it holds for generic values of the nonzero coefficients. Actual
/// values can lower the rank (a well block whose submatrix is singular), which only the exact
/// backend decides.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize)]
pub struct DmDecomposition {
    /// Size of a maximum matching: the rank of the matrix for generic coefficient values, an
    /// upper bound on its actual rank.
    pub structural_rank: usize,
    /// The over-determined part (rows and columns reachable from unmatched rows by
    /// alternating paths).
    pub over: Part,
    /// The well-determined part (perfectly matched).
    pub well: Part,
    /// The under-determined part (rows and columns reachable from unmatched columns by
    /// alternating paths).
    pub under: Part,
    /// The irreducible blocks of the well part in solve order: each comes after the blocks it
    /// depends on; among blocks ready at the same time, the one with the smaller first row
    /// comes first.
    pub blocks: Vec<Block>,
    #[serde(skip)]
    row_part: Vec<PartKind>,
    #[serde(skip)]
    col_part: Vec<PartKind>,
    #[serde(skip)]
    row_block: Vec<Option<usize>>,
    #[serde(skip)]
    col_block: Vec<Option<usize>>,
}

impl DmDecomposition {
    /// Whether the graph is structurally well-constrained: no over- or under-determined part.
    pub fn is_well_constrained(&self) -> bool {
        self.over.rows.is_empty()
            && self.over.cols.is_empty()
            && self.under.rows.is_empty()
            && self.under.cols.is_empty()
    }

    /// Number of rows of the decomposed graph.
    pub fn rows(&self) -> usize {
        self.row_part.len()
    }

    /// Number of columns of the decomposed graph.
    pub fn cols(&self) -> usize {
        self.col_part.len()
    }

    /// The part holding row `i` (`None` if out of range).
    pub fn part_of_row(&self, i: usize) -> Option<PartKind> {
        self.row_part.get(i).copied()
    }

    /// The part holding column `j` (`None` if out of range).
    pub fn part_of_col(&self, j: usize) -> Option<PartKind> {
        self.col_part.get(j).copied()
    }

    /// The block (index into [`DmDecomposition::blocks`]) holding row `i`, if the row is in
    /// the well part.
    pub fn block_of_row(&self, i: usize) -> Option<usize> {
        self.row_block.get(i).copied().flatten()
    }

    /// The block holding column `j`, if the column is in the well part.
    pub fn block_of_col(&self, j: usize) -> Option<usize> {
        self.col_block.get(j).copied().flatten()
    }

    /// The part a [`PartKind`] names.
    pub fn part(&self, kind: PartKind) -> &Part {
        match kind {
            PartKind::Over => &self.over,
            PartKind::Well => &self.well,
            PartKind::Under => &self.under,
        }
    }
}

/// Matching, then decomposition: the usual entry point.
///
/// Cannot fail, because [`maximum_matching`] returns a maximum matching of the same graph.
pub fn decompose(graph: &Bipartite) -> DmDecomposition {
    let matching = maximum_matching(graph);
    match dulmage_mendelsohn(graph, &matching) {
        Ok(dm) => dm,
        // Not reachable: the matching was made for this graph and Hopcroft–Karp stops only
        // when no augmenting path is left.
        Err(e) => unreachable!("Hopcroft–Karp produced an invalid matching: {e}"),
    }
}

/// The Dulmage–Mendelsohn decomposition of `graph` from a maximum matching of it.
///
/// * over-determined part: rows reachable from unmatched rows by alternating paths (row to
///   column by any edge, column to row by the matching), with the columns on those paths;
/// * under-determined part: columns reachable from unmatched columns by alternating paths
///   (column to row by any edge, row to column by the matching), with the rows on those paths;
/// * well-determined part: the rest, perfectly matched; its fine blocks are the strongly
///   connected components of the graph on matched pairs where the pair of row `r` depends on
///   the pair of column `c` for every other well column `c` of row `r`, found by Tarjan's
///   algorithm (iterative, an explicit stack), ordered topologically.
///
/// The parts do not depend on which maximum matching is given. Time
/// `O(rows + cols + nnz)` plus a heap over the blocks; no recursion.
///
/// # Errors
/// [`StructureError::MatchingSize`] / [`StructureError::MatchingInvalid`] if `matching` is not
/// a matching of `graph`, [`StructureError::MatchingNotMaximum`] if it is not maximum.
pub fn dulmage_mendelsohn(
    graph: &Bipartite,
    matching: &Matching,
) -> Result<DmDecomposition, StructureError> {
    matching.validate(graph)?;
    let (m, n) = (graph.rows(), graph.cols());
    let row_to_col = &matching.row_to_col;
    let col_to_row = &matching.col_to_row;

    let mut row_part = vec![PartKind::Well; m];
    let mut col_part = vec![PartKind::Well; n];
    let mut queue: VecDeque<usize> = VecDeque::new();

    // Over-determined part: alternating search from unmatched rows. `origin` remembers the
    // unmatched row each row was reached from, to name an augmenting path if one shows up.
    let mut origin = vec![usize::MAX; m];
    for i in 0..m {
        if row_to_col[i].is_none() {
            row_part[i] = PartKind::Over;
            origin[i] = i;
            queue.push_back(i);
        }
    }
    while let Some(i) = queue.pop_front() {
        for &j in graph.row(i) {
            if col_part[j] == PartKind::Over {
                continue;
            }
            col_part[j] = PartKind::Over;
            match col_to_row[j] {
                None => {
                    return Err(StructureError::MatchingNotMaximum {
                        row: origin[i],
                        col: j,
                    })
                }
                Some(k) => {
                    if row_part[k] != PartKind::Over {
                        row_part[k] = PartKind::Over;
                        origin[k] = origin[i];
                        queue.push_back(k);
                    }
                }
            }
        }
    }

    // Under-determined part: alternating search from unmatched columns. With a maximum
    // matching it cannot meet the over part (that would be an augmenting path).
    let mut col_origin = vec![usize::MAX; n];
    for j in 0..n {
        if col_to_row[j].is_none() {
            col_part[j] = PartKind::Under;
            col_origin[j] = j;
            queue.push_back(j);
        }
    }
    while let Some(j) = queue.pop_front() {
        for &i in graph.col(j) {
            match row_part[i] {
                PartKind::Under => continue,
                PartKind::Over => {
                    return Err(StructureError::MatchingNotMaximum {
                        row: origin[i],
                        col: col_origin[j],
                    })
                }
                PartKind::Well => {}
            }
            row_part[i] = PartKind::Under;
            match row_to_col[i] {
                None => {
                    return Err(StructureError::MatchingNotMaximum {
                        row: i,
                        col: col_origin[j],
                    })
                }
                Some(k) => match col_part[k] {
                    PartKind::Under => {}
                    PartKind::Over => {
                        return Err(StructureError::MatchingNotMaximum {
                            row: origin[i],
                            col: col_origin[j],
                        })
                    }
                    PartKind::Well => {
                        col_part[k] = PartKind::Under;
                        col_origin[k] = col_origin[j];
                        queue.push_back(k);
                    }
                },
            }
        }
    }

    let collect = |parts: &[PartKind], kind: PartKind| -> Vec<usize> {
        parts
            .iter()
            .enumerate()
            .filter(|(_, p)| **p == kind)
            .map(|(k, _)| k)
            .collect()
    };
    let over = Part {
        rows: collect(&row_part, PartKind::Over),
        cols: collect(&col_part, PartKind::Over),
    };
    let well = Part {
        rows: collect(&row_part, PartKind::Well),
        cols: collect(&col_part, PartKind::Well),
    };
    let under = Part {
        rows: collect(&row_part, PartKind::Under),
        cols: collect(&col_part, PartKind::Under),
    };

    let (blocks, row_block, col_block) =
        fine_blocks(graph, matching, &well.rows, &row_part, &col_part);

    Ok(DmDecomposition {
        structural_rank: matching.size,
        over,
        well,
        under,
        blocks,
        row_part,
        col_part,
        row_block,
        col_block,
    })
}

/// Blocks of the well part in solve order, and the row and column lookups into them.
type FineBlocks = (Vec<Block>, Vec<Option<usize>>, Vec<Option<usize>>);

/// The irreducible blocks of the well part: strongly connected components of the dependency
/// graph on matched pairs, collapsed and ordered topologically.
///
/// The graphs live in flat arrays (compressed adjacency lists): on the small systems of a
/// generic edit, where this runs once per edit for the report, a vector per node or component
/// (what a general graph type and its component lists hold) cost more than the search.
fn fine_blocks(
    graph: &Bipartite,
    matching: &Matching,
    well_rows: &[usize],
    row_part: &[PartKind],
    col_part: &[PartKind],
) -> FineBlocks {
    let (m, n) = (graph.rows(), graph.cols());
    // Node k stands for the pair (well_rows[k], its mate).
    let mut node_of_row = vec![usize::MAX; m];
    for (k, &r) in well_rows.iter().enumerate() {
        node_of_row[r] = k;
    }
    // The pair of row `r` depends on the pair of each other well column `c` of row `r`.
    let mut dependencies = Adjacency::with_nodes(well_rows.len());
    for &r in well_rows {
        let mate = matching.row_to_col[r];
        for &c in graph.row(r) {
            if col_part[c] != PartKind::Well || Some(c) == mate {
                continue;
            }
            // A well column is matched with a well row (the parts are closed under the
            // matching), so this lookup always succeeds.
            if let Some(r2) = matching.col_to_row[c] {
                let target = node_of_row[r2];
                if target != usize::MAX {
                    dependencies.push_edge(target);
                }
            }
        }
        dependencies.end_node();
    }
    let (scc_of, count) = strongly_connected_components(&dependencies);

    // Dependencies between components (edges of the collapsed graph H), without repeats.
    let mut edges: Vec<(usize, usize)> = (0..well_rows.len())
        .flat_map(|k| dependencies.targets(k).iter().map(move |&t| (k, t)))
        .map(|(k, t)| (scc_of[k], scc_of[t]))
        .filter(|(a, b)| a != b)
        .collect();
    edges.sort_unstable();
    edges.dedup();
    // Smallest row of each component: the tie-break of the solve order. Nodes are numbered by
    // increasing row, so the smallest node index gives the smallest row.
    let mut first_row = vec![usize::MAX; count];
    for (k, &r) in well_rows.iter().enumerate() {
        let s = scc_of[k];
        first_row[s] = first_row[s].min(r);
    }

    // Kahn's algorithm: a component becomes ready when all it depends on is placed.
    let mut waiting = vec![0usize; count];
    let mut dependents = Adjacency::with_nodes(count);
    let mut by_dependency = edges.clone();
    by_dependency.sort_unstable_by_key(|&(_, b)| b);
    let mut next = by_dependency.iter().peekable();
    for b in 0..count {
        while let Some(&(a, _)) = next.next_if(|(_, t)| *t == b) {
            dependents.push_edge(a);
            waiting[a] += 1;
        }
        dependents.end_node();
    }
    let mut ready: BinaryHeap<Reverse<(usize, usize)>> = (0..count)
        .filter(|&s| waiting[s] == 0)
        .map(|s| Reverse((first_row[s], s)))
        .collect();
    let mut position = vec![usize::MAX; count];
    let mut placed = 0;
    while let Some(Reverse((_, s))) = ready.pop() {
        position[s] = placed;
        placed += 1;
        for &a in dependents.targets(s) {
            waiting[a] -= 1;
            if waiting[a] == 0 {
                ready.push(Reverse((first_row[a], a)));
            }
        }
    }
    // The collapsed graph is acyclic, so every component is placed.
    debug_assert_eq!(placed, count);

    // Each block's rows, sized before they are filled.
    let mut sizes = vec![0usize; count];
    for &s in &scc_of {
        sizes[position[s]] += 1;
    }
    let mut blocks: Vec<Block> = sizes
        .iter()
        .map(|&size| Block {
            rows: Vec::with_capacity(size),
            cols: Vec::with_capacity(size),
            ..Block::default()
        })
        .collect();
    let mut row_block = vec![None; m];
    let mut col_block = vec![None; n];
    for (k, &r) in well_rows.iter().enumerate() {
        let b = position[scc_of[k]];
        blocks[b].rows.push(r);
        row_block[r] = Some(b);
        if let Some(c) = matching.row_to_col[r] {
            blocks[b].cols.push(c);
            col_block[c] = Some(b);
        }
    }
    for &(a, b) in &edges {
        blocks[position[a]].depends_on.push(position[b]);
    }
    for block in &mut blocks {
        block.depends_on.sort_unstable();
        // Rows were pushed increasing; columns follow the rows' mates.
        block.cols.sort_unstable();
        let mut inputs: Vec<usize> = block
            .rows
            .iter()
            .flat_map(|&r| graph.row(r).iter().copied())
            .filter(|&c| col_part[c] == PartKind::Over)
            .collect();
        inputs.sort_unstable();
        inputs.dedup();
        block.over_inputs = inputs;
    }
    debug_assert!(row_part
        .iter()
        .enumerate()
        .all(|(r, p)| (*p == PartKind::Well) == row_block[r].is_some()));
    (blocks, row_block, col_block)
}

/// A directed graph on nodes `0..n` as compressed adjacency lists, built node by node.
struct Adjacency {
    /// The out-edges of node `v` are `targets[start[v]..start[v + 1]]`.
    start: Vec<usize>,
    targets: Vec<usize>,
}

impl Adjacency {
    /// An empty graph to be filled with `nodes` nodes.
    fn with_nodes(nodes: usize) -> Self {
        let mut start = Vec::with_capacity(nodes + 1);
        start.push(0);
        Adjacency {
            start,
            targets: Vec::new(),
        }
    }

    /// An edge from the node being filled to `target`.
    fn push_edge(&mut self, target: usize) {
        self.targets.push(target);
    }

    /// Ends the node being filled: the next edges leave the next node.
    fn end_node(&mut self) {
        self.start.push(self.targets.len());
    }

    /// Number of nodes filled.
    fn nodes(&self) -> usize {
        self.start.len() - 1
    }

    /// The out-neighbours of `v`.
    fn targets(&self, v: usize) -> &[usize] {
        &self.targets[self.start[v]..self.start[v + 1]]
    }
}

/// Tarjan's strongly connected components, iterative (an explicit stack of `(node, next edge)`
/// frames, no recursion): the component of each node and the number of components.
fn strongly_connected_components(graph: &Adjacency) -> (Vec<usize>, usize) {
    const UNSEEN: usize = usize::MAX;
    let nodes = graph.nodes();
    let mut index = vec![UNSEEN; nodes];
    let mut low = vec![0usize; nodes];
    let mut component = vec![UNSEEN; nodes];
    // Visited nodes whose component is not closed yet (Tarjan's stack).
    let mut open = Vec::new();
    let mut frames: Vec<(usize, usize)> = Vec::new();
    let (mut visited, mut count) = (0, 0);
    for root in 0..nodes {
        if index[root] != UNSEEN {
            continue;
        }
        index[root] = visited;
        low[root] = visited;
        visited += 1;
        open.push(root);
        frames.push((root, 0));
        while let Some((v, edge)) = frames.last_mut() {
            let v = *v;
            if let Some(&w) = graph.targets(v).get(*edge) {
                *edge += 1;
                if index[w] == UNSEEN {
                    index[w] = visited;
                    low[w] = visited;
                    visited += 1;
                    open.push(w);
                    frames.push((w, 0));
                } else if component[w] == UNSEEN {
                    // `w` is open: on the path or in a component not closed yet.
                    low[v] = low[v].min(index[w]);
                }
                continue;
            }
            frames.pop();
            if let Some(&(parent, _)) = frames.last() {
                low[parent] = low[parent].min(low[v]);
            }
            if low[v] == index[v] {
                // `v` is the first node of its component: close it.
                while let Some(w) = open.pop() {
                    component[w] = count;
                    if w == v {
                        break;
                    }
                }
                count += 1;
            }
        }
    }
    (component, count)
}
