//! The Dulmage–Mendelsohn decomposition: the over-, well- and under-determined parts of the
//! constraint graph, and the irreducible blocks of the well-determined part in an order in
//! which they can be solved (Brenner 2.1, figure 1(c)–(d)).

use crate::bipartite::Bipartite;
use crate::error::StructureError;
use crate::matching::{maximum_matching, Matching};
use petgraph::algo::kosaraju_scc;
use petgraph::graph::{DiGraph, NodeIndex};
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
///   the pair of column `c` for every other well column `c` of row `r`, found with petgraph's
///   `kosaraju_scc` (iterative: its two passes use `DfsPostOrder` and `Dfs`, whose `next` pop
///   and push an explicit `Vec` stack), ordered topologically.
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
    let mut g: DiGraph<(), ()> = DiGraph::with_capacity(well_rows.len(), 0);
    for _ in well_rows {
        g.add_node(());
    }
    for (k, &r) in well_rows.iter().enumerate() {
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
                    g.add_edge(NodeIndex::new(k), NodeIndex::new(target), ());
                }
            }
        }
    }

    // kosaraju_scc (petgraph 0.8.3, src/algo/scc/kosaraju_scc.rs) is iterative: both passes
    // drive `DfsPostOrder::next` / `Dfs::next`, which loop over an explicit `Vec` stack.
    let sccs = kosaraju_scc(&g);
    let mut scc_of = vec![0usize; well_rows.len()];
    for (s, members) in sccs.iter().enumerate() {
        for v in members {
            scc_of[v.index()] = s;
        }
    }
    let count = sccs.len();
    // Dependencies between components (edges of the collapsed graph H).
    let mut deps: Vec<Vec<usize>> = vec![Vec::new(); count];
    for e in g.raw_edges() {
        let (a, b) = (scc_of[e.source().index()], scc_of[e.target().index()]);
        if a != b {
            deps[a].push(b);
        }
    }
    for d in &mut deps {
        d.sort_unstable();
        d.dedup();
    }
    // Smallest row of each component: the tie-break of the solve order. Nodes are numbered by
    // increasing row, so the smallest node index gives the smallest row.
    let mut first_row = vec![usize::MAX; count];
    for (k, &r) in well_rows.iter().enumerate() {
        let s = scc_of[k];
        first_row[s] = first_row[s].min(r);
    }

    // Kahn's algorithm: a component becomes ready when all it depends on is placed.
    let mut waiting: Vec<usize> = deps.iter().map(Vec::len).collect();
    let mut dependents: Vec<Vec<usize>> = vec![Vec::new(); count];
    for (a, d) in deps.iter().enumerate() {
        for &b in d {
            dependents[b].push(a);
        }
    }
    let mut ready: BinaryHeap<Reverse<(usize, usize)>> = (0..count)
        .filter(|&s| waiting[s] == 0)
        .map(|s| Reverse((first_row[s], s)))
        .collect();
    let mut position = vec![usize::MAX; count];
    let mut order = Vec::with_capacity(count);
    while let Some(Reverse((_, s))) = ready.pop() {
        position[s] = order.len();
        order.push(s);
        for &a in &dependents[s] {
            waiting[a] -= 1;
            if waiting[a] == 0 {
                ready.push(Reverse((first_row[a], a)));
            }
        }
    }
    // The collapsed graph is acyclic, so every component is placed.
    debug_assert_eq!(order.len(), count);

    let mut blocks: Vec<Block> = vec![Block::default(); count];
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
    for (s, d) in deps.iter().enumerate() {
        let b = position[s];
        let mut mapped: Vec<usize> = d.iter().map(|&t| position[t]).collect();
        mapped.sort_unstable();
        blocks[b].depends_on = mapped;
    }
    for block in &mut blocks {
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
