//! The global Bézier control net `G` (thesis 12.1): control points joined as in each triangle's
//! local triangular grid, and hop distances on it (breadth-first searches over a `petgraph`
//! compressed sparse row graph, settled only as far as an edit needs them).

use crate::spline::{multi_indices, Spline};
use petgraph::csr::Csr;
use petgraph::Directed;
use std::collections::BTreeSet;

/// The control net: one node per control point (node `i` is control point `i`).
#[derive(Debug, Clone)]
pub struct ControlNet {
    /// Every edge in both directions, so a point's neighbours are one slice.
    graph: Csr<(), (), Directed, u32>,
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
        let mut both_ways: Vec<(u32, u32)> = edges
            .iter()
            .flat_map(|&(a, b)| [(a as u32, b as u32), (b as u32, a as u32)])
            .collect();
        both_ways.sort_unstable();
        let mut graph = Csr::from_sorted_edges(&both_ways)
            .expect("sorted, and unique: `edges` is a set of pairs `a < b`");
        // Points after the last one with an edge (none in a mesh's net, where every point lies
        // in a triangle of degree ≥ 1) are nodes too.
        while graph.node_count() < spline.points().len() {
            graph.add_node(());
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

    /// The control points joined to `p`.
    fn neighbors(&self, p: usize) -> impl Iterator<Item = usize> + '_ {
        self.graph
            .neighbors_slice(p as u32)
            .iter()
            .map(|&w| w as usize)
    }

    /// Hop distances from the nearest of `sources` (every edge is one hop), settled lazily:
    /// see [`Distances`].
    pub fn distances_from(&self, sources: &[usize]) -> Distances<'_> {
        Distances::new(self, sources)
    }

    /// For each point of `region` (in its order), the hop distance to the nearest control point
    /// outside it (`None` when the region holds its whole connected component).
    ///
    /// A shortest path from a point of the region to the nearest outside point runs inside the
    /// region until its last hop (an earlier outside point would be nearer), so the search
    /// starts from the region's points next to an outside one, at distance 1, and never leaves
    /// the region: it visits the region and its edges, not the whole net (only the zeroed
    /// lookup array from a point to its place in `region` has the net's size).
    pub fn distances_out_of(&self, region: &[usize]) -> Vec<Option<u32>> {
        // `slot[p]` is `1 +` the position of `p` in `region`, `0` outside it.
        let mut slot = vec![0u32; self.len()];
        for (i, &p) in region.iter().enumerate() {
            if p < slot.len() {
                slot[p] = i as u32 + 1;
            }
        }
        let mut distance: Vec<Option<u32>> = vec![None; region.len()];
        let mut frontier: Vec<usize> = Vec::new();
        for (i, &p) in region.iter().enumerate() {
            if p < slot.len() && self.neighbors(p).any(|w| slot[w] == 0) {
                distance[i] = Some(1);
                frontier.push(p);
            }
        }
        let mut level = 1;
        while !frontier.is_empty() {
            level += 1;
            let mut next = Vec::new();
            for &v in &frontier {
                for w in self.neighbors(v) {
                    let i = slot[w] as usize;
                    if i > 0 && distance[i - 1].is_none() {
                        distance[i - 1] = Some(level);
                        next.push(w);
                    }
                }
            }
            frontier = next;
        }
        distance
    }
}

/// Hop distances on a [`ControlNet`] from the nearest of a set of sources, found by a
/// breadth-first search that settles one level at a time and only as far as it is asked: an
/// edit with `δ_max = 3` looks at its neighbourhood, not the whole net (a whole-net search for
/// every Select was two thirds of a δ_max = 3 Select + Initialize on the 968-triangle grid).
#[derive(Debug, Clone)]
pub struct Distances<'a> {
    net: &'a ControlNet,
    /// Settled distance of each point, [`Distances::UNSETTLED`] until then.
    distance: Vec<u32>,
    /// The points at distance `level`, whose neighbours are the next level.
    frontier: Vec<usize>,
    level: u32,
    /// Every settled point, in the order settled (non-decreasing distance).
    settled: Vec<usize>,
}

impl<'a> Distances<'a> {
    const UNSETTLED: u32 = u32::MAX;

    fn new(net: &'a ControlNet, sources: &[usize]) -> Self {
        let mut distance = vec![Self::UNSETTLED; net.len()];
        let mut frontier = Vec::new();
        for &s in sources {
            if s < distance.len() && distance[s] == Self::UNSETTLED {
                distance[s] = 0;
                frontier.push(s);
            }
        }
        Distances {
            net,
            distance,
            settled: frontier.clone(),
            frontier,
            level: 0,
        }
    }

    /// Settles the next level; false when nothing was left to settle.
    fn settle_level(&mut self) -> bool {
        if self.frontier.is_empty() {
            return false;
        }
        let next_level = self.level + 1;
        let mut next = Vec::new();
        for &v in &self.frontier {
            for w in self.net.neighbors(v) {
                if self.distance[w] == Self::UNSETTLED {
                    self.distance[w] = next_level;
                    next.push(w);
                }
            }
        }
        self.settled.extend_from_slice(&next);
        self.frontier = next;
        self.level = next_level;
        true
    }

    /// The distance of `p` (`None` when no source reaches it or `p` is not a point of the
    /// net), settling levels until `p` is reached or the search is exhausted.
    pub fn get(&mut self, p: usize) -> Option<u32> {
        if p >= self.distance.len() {
            return None;
        }
        while self.distance[p] == Self::UNSETTLED {
            if !self.settle_level() {
                return None;
            }
        }
        Some(self.distance[p])
    }

    /// The points at distance at most `radius` from the sources (the sources included), in
    /// the order settled.
    pub fn within(&mut self, radius: u32) -> &[usize] {
        while self.level < radius && self.settle_level() {}
        let end = self
            .settled
            .partition_point(|&p| self.distance[p] <= radius);
        &self.settled[..end]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spline::tests::grid;
    use std::collections::VecDeque;

    /// Whole-net breadth-first search, the plain way: what the lazy searches must agree with.
    fn reference_distances(net: &ControlNet, sources: &[usize]) -> Vec<Option<u32>> {
        let mut distance = vec![None; net.len()];
        let mut queue = VecDeque::new();
        for &s in sources {
            if distance[s].is_none() {
                distance[s] = Some(0);
                queue.push_back(s);
            }
        }
        while let Some(v) = queue.pop_front() {
            let next = distance[v].map(|d: u32| d + 1);
            for &(a, b) in net.edges() {
                let w = if a == v {
                    b
                } else if b == v {
                    a
                } else {
                    continue;
                };
                if distance[w].is_none() {
                    distance[w] = next;
                    queue.push_back(w);
                }
            }
        }
        distance
    }

    #[test]
    fn a_single_triangle_net_is_its_local_grid() {
        let spline = Spline::new(crate::spline::tests::strip(1), 3, 1).expect("spline");
        let net = ControlNet::new(&spline);
        // 10 points, 3 · (1 + 2 + 3) = 18 edges in a degree-3 triangular grid.
        assert_eq!(net.len(), 10);
        assert_eq!(net.edges().len(), 18);
        let corner = spline.triangle_points(0)[spline.local_index([3, 0, 0])];
        let far = spline.triangle_points(0)[spline.local_index([0, 3, 0])];
        let mut d = net.distances_from(&[corner]);
        assert_eq!(d.get(corner), Some(0));
        assert_eq!(d.get(far), Some(3));
        assert_eq!(d.get(net.len()), None);
    }

    #[test]
    fn shared_points_join_the_local_nets() {
        let spline = Spline::new(grid(2, false), 5, 1).expect("spline");
        let net = ControlNet::new(&spline);
        let mut d = net.distances_from(&[0]);
        assert!((0..net.len()).all(|p| d.get(p).is_some()));
        // Opposite grid corner: 2 squares · 5 steps along each axis, diagonals shorten it.
        let far = spline
            .points()
            .iter()
            .position(|p| &*p.name == "v8")
            .expect("vertex 8");
        assert_eq!(d.get(far), Some(10));
    }

    #[test]
    fn lazy_distances_agree_with_a_whole_search() {
        let spline = Spline::new(grid(4, true), 4, 1).expect("spline");
        let net = ControlNet::new(&spline);
        let sources = [17, 3, 17, 40];
        let expected = reference_distances(&net, &sources);
        let farthest = expected.iter().flatten().copied().max().expect("reached");
        assert!(farthest > 4, "the net is larger than the radii below");
        for radius in [0, 1, 3, farthest, farthest + 2] {
            let mut lazy = net.distances_from(&sources);
            let mut within = lazy.within(radius).to_vec();
            within.sort_unstable();
            let want: Vec<usize> = (0..net.len())
                .filter(|&p| expected[p].is_some_and(|d| d <= radius))
                .collect();
            assert_eq!(within, want, "radius {radius}");
            // Asked in an order that jumps back and forth between levels.
            for p in (0..net.len()).rev().step_by(7).chain(0..net.len()) {
                assert_eq!(lazy.get(p), expected[p], "point {p}");
            }
        }
    }

    #[test]
    fn distances_out_of_a_region_stay_inside_it() {
        let spline = Spline::new(grid(4, true), 4, 1).expect("spline");
        let net = ControlNet::new(&spline);
        let mut around = net.distances_from(&[20]);
        let region: Vec<usize> = around.within(3).iter().rev().copied().collect();
        let inside: BTreeSet<usize> = region.iter().copied().collect();
        let outside: Vec<usize> = (0..net.len()).filter(|p| !inside.contains(p)).collect();
        let expected = reference_distances(&net, &outside);
        let got = net.distances_out_of(&region);
        for (i, &p) in region.iter().enumerate() {
            assert_eq!(got[i], expected[p], "point {p}");
        }
        assert!(got.contains(&Some(4)), "the centre is 4 hops out");
        // A region holding the whole net has no outside point.
        let everything: Vec<usize> = (0..net.len()).collect();
        assert!(net
            .distances_out_of(&everything)
            .iter()
            .all(Option::is_none));
    }
}
