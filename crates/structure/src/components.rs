//! Connected components of the constraint graph: parts of the system that cannot influence
//! each other (Brenner 3.2: "unconnected components of the constraint graph cannot influence
//! O").

use crate::bipartite::Bipartite;
use petgraph::unionfind::UnionFind;
use serde::Serialize;

/// One connected component: its rows and columns, each sorted increasingly.
///
/// An empty row (no entries) or an unknown that no row mentions is a component on its own,
/// with the other side empty.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Component {
    /// Constraint rows of the component, increasing.
    pub rows: Vec<usize>,
    /// Unknowns of the component, increasing.
    pub cols: Vec<usize>,
}

/// The connected components of a [`Bipartite`] graph, with lookups from rows and columns.
///
/// Components are ordered by their smallest row; components without rows (isolated unknowns)
/// come after all others, by their column. The order depends only on the graph.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Components {
    /// The components in deterministic order.
    pub components: Vec<Component>,
    #[serde(skip)]
    row_component: Vec<usize>,
    #[serde(skip)]
    col_component: Vec<usize>,
}

impl Components {
    /// Number of components.
    pub fn len(&self) -> usize {
        self.components.len()
    }

    /// Whether there are no components (the graph has no rows and no columns).
    pub fn is_empty(&self) -> bool {
        self.components.is_empty()
    }

    /// Index (into [`Components::components`]) of the component holding row `i`, if it exists.
    pub fn of_row(&self, i: usize) -> Option<usize> {
        self.row_component.get(i).copied()
    }

    /// Index of the component holding column `j`, if it exists.
    pub fn of_col(&self, j: usize) -> Option<usize> {
        self.col_component.get(j).copied()
    }
}

/// Connected components of the constraint graph, by union–find over its edges.
///
/// Time `O((rows + cols + nnz) α)`; no recursion (petgraph 0.8.3's `UnionFind::union` and
/// `into_labeling` find roots with a path-halving loop, despite the helper's name
/// `find_mut_recursive`).
pub fn components(graph: &Bipartite) -> Components {
    let (m, n) = (graph.rows(), graph.cols());
    // Nodes: rows 0..m, columns m..m+n.
    let mut uf = UnionFind::<usize>::new(m + n);
    for i in 0..m {
        for &j in graph.row(i) {
            uf.union(i, m + j);
        }
    }
    let labels = uf.into_labeling();
    // Number the components in the required order: first appearance scanning rows, then
    // columns. Scanning rows in increasing order meets each component at its smallest row;
    // components without rows are met while scanning columns, at their (only) column.
    let mut number = vec![usize::MAX; m + n];
    let mut out: Vec<Component> = Vec::new();
    let mut row_component = vec![0usize; m];
    let mut col_component = vec![0usize; n];
    for (node, &root) in labels.iter().enumerate() {
        if number[root] == usize::MAX {
            number[root] = out.len();
            out.push(Component {
                rows: Vec::new(),
                cols: Vec::new(),
            });
        }
        let k = number[root];
        if node < m {
            out[k].rows.push(node);
            row_component[node] = k;
        } else {
            out[k].cols.push(node - m);
            col_component[node - m] = k;
        }
    }
    // Rows and columns were pushed in increasing order, so each list is already sorted.
    Components {
        components: out,
        row_component,
        col_component,
    }
}
