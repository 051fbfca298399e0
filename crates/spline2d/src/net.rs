//! The global Bézier control net `G` (thesis 12.1): control points joined as in each triangle's
//! local triangular grid, and hop distances on it (breadth-first search over a `petgraph`
//! graph).

use crate::spline::{multi_indices, Spline};
use petgraph::graph::{NodeIndex, UnGraph};
use std::collections::BTreeSet;

/// The control net: one node per control point (node `i` is control point `i`).
#[derive(Debug, Clone)]
pub struct ControlNet {
    graph: UnGraph<(), u32>,
    edges: Vec<(usize, usize)>,
}

impl ControlNet {
    /// Builds the net of a spline: in every triangle, `(i, j, k)` is joined to `(i−1, j+1, k)`,
    /// `(i−1, j, k+1)` and `(i, j−1, k+1)`; shared points make the local nets one graph.
    pub fn new(spline: &Spline) -> Self {
        let d = spline.degree();
        let mut set: BTreeSet<(usize, usize)> = BTreeSet::new();
        for t in 0..spline.mesh().triangles().len() {
            let pts = spline.triangle_points(t);
            for [i, j, k] in multi_indices(d) {
                let here = pts[spline.local_index([i, j, k])];
                let mut link = |other: [usize; 3]| {
                    let there = pts[spline.local_index(other)];
                    set.insert((here.min(there), here.max(there)));
                };
                if i > 0 {
                    link([i - 1, j + 1, k]);
                    link([i - 1, j, k + 1]);
                }
                if j > 0 {
                    link([i, j - 1, k + 1]);
                }
            }
        }
        let edges: Vec<(usize, usize)> = set.into_iter().collect();
        let mut graph = UnGraph::with_capacity(spline.points().len() + 1, edges.len());
        for _ in 0..spline.points().len() {
            graph.add_node(());
        }
        for &(a, b) in &edges {
            graph.add_edge(NodeIndex::new(a), NodeIndex::new(b), 1);
        }
        ControlNet { graph, edges }
    }

    /// The net's edges `(a, b)` with `a < b`, sorted.
    pub fn edges(&self) -> &[(usize, usize)] {
        &self.edges
    }

    /// Number of control points.
    pub fn len(&self) -> usize {
        self.graph.node_count()
    }

    /// True for an empty net.
    pub fn is_empty(&self) -> bool {
        self.graph.node_count() == 0
    }

    /// Hop distance from the nearest of `sources` to every control point (`None` where
    /// unreachable), by a breadth-first search from all sources at once (every edge is one
    /// hop): `O(points + edges)`, without copying the net.
    pub fn distances_from(&self, sources: &[usize]) -> Vec<Option<u32>> {
        let mut distance: Vec<Option<u32>> = vec![None; self.len()];
        let mut queue = std::collections::VecDeque::new();
        for &s in sources {
            if s < distance.len() && distance[s].is_none() {
                distance[s] = Some(0);
                queue.push_back(s);
            }
        }
        while let Some(v) = queue.pop_front() {
            let next = distance[v].map_or(0, |d| d + 1);
            for w in self.graph.neighbors(NodeIndex::new(v)) {
                let w = w.index();
                if distance[w].is_none() {
                    distance[w] = Some(next);
                    queue.push_back(w);
                }
            }
        }
        distance
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spline::tests::grid;

    #[test]
    fn a_single_triangle_net_is_its_local_grid() {
        let spline = Spline::new(crate::spline::tests::strip(1), 3, 1).expect("spline");
        let net = ControlNet::new(&spline);
        // 10 points, 3 · (1 + 2 + 3) = 18 edges in a degree-3 triangular grid.
        assert_eq!(net.len(), 10);
        assert_eq!(net.edges().len(), 18);
        let corner = spline.triangle_points(0)[spline.local_index([3, 0, 0])];
        let far = spline.triangle_points(0)[spline.local_index([0, 3, 0])];
        let d = net.distances_from(&[corner]);
        assert_eq!(d[corner], Some(0));
        assert_eq!(d[far], Some(3));
    }

    #[test]
    fn shared_points_join_the_local_nets() {
        let spline = Spline::new(grid(2, false), 5, 1).expect("spline");
        let net = ControlNet::new(&spline);
        let d = net.distances_from(&[0]);
        assert!(d.iter().all(Option::is_some));
        // Opposite grid corner: 2 squares · 5 steps along each axis, diagonals shorten it.
        let far = spline
            .points()
            .iter()
            .position(|p| p.name == "v8")
            .expect("vertex 8");
        assert_eq!(d[far], Some(10));
    }
}
