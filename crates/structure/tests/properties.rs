//! Property tests on random sparse patterns: the matching is maximum (against a plain
//! augmenting-path reference), the Dulmage–Mendelsohn parts partition the graph in block
//! triangular form and do not depend on the matching, blocks are exactly the strongly
//! connected components in a valid solve order, and explanations exist for every unknown.

use proptest::prelude::*;
use std::collections::VecDeque;
use structure::{
    components, dulmage_mendelsohn, explain, explain_rows, maximum_matching, Bipartite,
    DmDecomposition, Matching, PartKind,
};

/// Reference maximum matching: one breadth-first augmenting-path search per row.
fn reference_matching(g: &Bipartite) -> Matching {
    let (m, n) = (g.rows(), g.cols());
    let mut row_to_col = vec![None; m];
    let mut col_to_row: Vec<Option<usize>> = vec![None; n];
    let mut size = 0;
    for s in 0..m {
        let mut prev_row = vec![usize::MAX; n];
        let mut queue = VecDeque::from([s]);
        let mut end = None;
        'search: while let Some(r) = queue.pop_front() {
            for &c in g.row(r) {
                if prev_row[c] != usize::MAX {
                    continue;
                }
                prev_row[c] = r;
                match col_to_row[c] {
                    None => {
                        end = Some(c);
                        break 'search;
                    }
                    Some(r2) => queue.push_back(r2),
                }
            }
        }
        let Some(mut c) = end else { continue };
        loop {
            let r = prev_row[c];
            let old: Option<usize> = row_to_col[r];
            row_to_col[r] = Some(c);
            col_to_row[c] = Some(r);
            match old {
                Some(o) => c = o,
                None => break,
            }
        }
        size += 1;
    }
    Matching {
        row_to_col,
        col_to_row,
        size,
    }
}

fn arb_pattern() -> impl Strategy<Value = (usize, Vec<Vec<usize>>)> {
    prop_oneof![
        (0usize..14, 0usize..14, 0.0f64..0.5),
        // Larger and sparser: several blocks and all three parts at once.
        (0usize..60, 0usize..60, 0.0f64..0.08),
    ]
    .prop_flat_map(|(m, n, density)| {
        let row = proptest::collection::vec(proptest::bool::weighted(density.max(0.01)), n)
            .prop_map(|bits| {
                bits.iter()
                    .enumerate()
                    .filter(|(_, b)| **b)
                    .map(|(j, _)| j)
                    .collect::<Vec<usize>>()
            });
        (Just(n), proptest::collection::vec(row, m))
    })
}

fn parts(dm: &DmDecomposition) -> [(PartKind, &structure::Part); 3] {
    [
        (PartKind::Over, &dm.over),
        (PartKind::Well, &dm.well),
        (PartKind::Under, &dm.under),
    ]
}

fn check_decomposition(g: &Bipartite, m: &Matching, dm: &DmDecomposition) {
    let (rows, cols) = (g.rows(), g.cols());
    assert_eq!(dm.structural_rank, m.size);

    // Partition of rows and columns; lookups agree with the lists.
    let mut row_seen = vec![0; rows];
    let mut col_seen = vec![0; cols];
    for (kind, part) in parts(dm) {
        assert!(part.rows.windows(2).all(|w| w[0] < w[1]));
        assert!(part.cols.windows(2).all(|w| w[0] < w[1]));
        for &r in &part.rows {
            row_seen[r] += 1;
            assert_eq!(dm.part_of_row(r), Some(kind));
        }
        for &c in &part.cols {
            col_seen[c] += 1;
            assert_eq!(dm.part_of_col(c), Some(kind));
        }
    }
    assert!(row_seen.iter().all(|&k| k == 1));
    assert!(col_seen.iter().all(|&k| k == 1));

    // Sizes: over has more rows than columns, under more columns than rows (when not empty);
    // the well part is square and perfectly matched within itself.
    if !dm.over.rows.is_empty() {
        assert!(dm.over.rows.len() > dm.over.cols.len());
    }
    if !dm.under.cols.is_empty() {
        assert!(dm.under.cols.len() > dm.under.rows.len());
    }
    assert_eq!(dm.well.rows.len(), dm.well.cols.len());
    for &r in &dm.well.rows {
        let c = m.row_to_col[r].expect("well rows are matched");
        assert_eq!(dm.part_of_col(c), Some(PartKind::Well));
    }
    assert_eq!(
        dm.structural_rank,
        dm.over.cols.len() + dm.well.cols.len() + dm.under.rows.len()
    );

    // Block triangular form.
    for &r in &dm.over.rows {
        assert!(g
            .row(r)
            .iter()
            .all(|&c| dm.part_of_col(c) == Some(PartKind::Over)));
    }
    for &r in &dm.well.rows {
        assert!(g
            .row(r)
            .iter()
            .all(|&c| dm.part_of_col(c) != Some(PartKind::Under)));
    }

    // Blocks: partition of the well part, square, matched inside, dependencies earlier and
    // exactly the blocks of the other well columns of their rows.
    let mut row_block = vec![usize::MAX; rows];
    let mut col_block = vec![usize::MAX; cols];
    for (b, block) in dm.blocks.iter().enumerate() {
        assert_eq!(block.rows.len(), block.cols.len());
        assert!(!block.rows.is_empty());
        for &r in &block.rows {
            assert_eq!(row_block[r], usize::MAX);
            row_block[r] = b;
            assert_eq!(dm.block_of_row(r), Some(b));
        }
        for &c in &block.cols {
            col_block[c] = b;
            assert_eq!(dm.block_of_col(c), Some(b));
        }
    }
    let mut well_rows: Vec<usize> = dm.blocks.iter().flat_map(|b| b.rows.clone()).collect();
    well_rows.sort_unstable();
    assert_eq!(well_rows, dm.well.rows);
    for (b, block) in dm.blocks.iter().enumerate() {
        for &r in &block.rows {
            let mate = m.row_to_col[r].expect("matched");
            assert_eq!(col_block[mate], b);
        }
        assert!(block.depends_on.iter().all(|&d| d < b));
        // The solve order's tie-break: of the blocks ready when `b` is placed (all they depend
        // on placed before), `b` has the smallest first row.
        for later in &dm.blocks[b + 1..] {
            if later.depends_on.iter().all(|&d| d < b) {
                assert!(
                    block.rows[0] < later.rows[0],
                    "block {b} placed before a block ready with a smaller first row"
                );
            }
        }
        let mut expected: Vec<usize> = block
            .rows
            .iter()
            .flat_map(|&r| g.row(r).iter().copied())
            .filter(|&c| dm.part_of_col(c) == Some(PartKind::Well) && col_block[c] != b)
            .map(|c| col_block[c])
            .collect();
        expected.sort_unstable();
        expected.dedup();
        assert_eq!(block.depends_on, expected);
        let mut over_inputs: Vec<usize> = block
            .rows
            .iter()
            .flat_map(|&r| g.row(r).iter().copied())
            .filter(|&c| dm.part_of_col(c) == Some(PartKind::Over))
            .collect();
        over_inputs.sort_unstable();
        over_inputs.dedup();
        assert_eq!(block.over_inputs, over_inputs);

        // Strongly connected inside: from the first pair every pair of the block is reachable
        // (edges to other blocks only go earlier, so with this the blocks are exactly the
        // strongly connected components), and backwards too.
        for forward in [true, false] {
            let mut reached = vec![false; rows];
            let mut stack = vec![block.rows[0]];
            reached[block.rows[0]] = true;
            while let Some(r) = stack.pop() {
                let next: Vec<usize> = if forward {
                    g.row(r)
                        .iter()
                        .filter(|&&c| col_block[c] == b)
                        .filter_map(|&c| m.col_to_row[c])
                        .collect()
                } else {
                    let mate = m.row_to_col[r].expect("matched");
                    g.col(mate)
                        .iter()
                        .copied()
                        .filter(|&r2| row_block[r2] == b)
                        .collect()
                };
                for r2 in next {
                    if !reached[r2] {
                        reached[r2] = true;
                        stack.push(r2);
                    }
                }
            }
            assert!(block.rows.iter().all(|&r| reached[r]));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn decomposition_is_consistent((n, rows) in arb_pattern()) {
        let g = Bipartite::from_pattern(n, &rows).unwrap();
        let m = maximum_matching(&g);
        m.validate(&g).unwrap();
        let reference = reference_matching(&g);
        reference.validate(&g).unwrap();
        prop_assert_eq!(m.size, reference.size);

        let dm = dulmage_mendelsohn(&g, &m).unwrap();
        check_decomposition(&g, &m, &dm);

        // The coarse parts do not depend on the maximum matching chosen; blocks neither (up to
        // order, which here is also the same because it depends only on the block graph).
        let dm2 = dulmage_mendelsohn(&g, &reference).unwrap();
        check_decomposition(&g, &reference, &dm2);
        prop_assert_eq!(&dm.over, &dm2.over);
        prop_assert_eq!(&dm.well, &dm2.well);
        prop_assert_eq!(&dm.under, &dm2.under);
        prop_assert_eq!(&dm.blocks, &dm2.blocks);

        // Components agree with petgraph's count and partition the graph.
        let c = components(&g);
        prop_assert_eq!(c.len(), petgraph::algo::connected_components(&g.to_petgraph()));
        prop_assert_eq!(c.components.iter().map(|k| k.rows.len()).sum::<usize>(), g.rows());
        prop_assert_eq!(c.components.iter().map(|k| k.cols.len()).sum::<usize>(), g.cols());
        for i in 0..g.rows() {
            for &j in g.row(i) {
                prop_assert_eq!(c.of_row(i), c.of_col(j));
            }
        }

        // Every unknown has an explanation whose last step holds it (free ones: the piece).
        for col in 0..g.cols() {
            let e = explain(&dm, &g, col, &[], &[]).unwrap();
            prop_assert_eq!(Some(e.part), dm.part_of_col(col));
            prop_assert!(!e.text.is_empty());
            let last = e.chain.last().expect("a step");
            prop_assert!(last.cols.contains(&col));
            for s in &e.chain {
                prop_assert!(s.rows.iter().all(|&r| dm.part_of_row(r) == Some(s.part)));
            }
        }
        let all: Vec<usize> = (0..g.rows()).collect();
        let r = explain_rows(&dm, &g, &all, &[], &[]).unwrap();
        prop_assert_eq!(r.structural_rank, m.size);
        prop_assert_eq!(r.structurally_dependent, m.size < g.rows());
    }

    /// Over- and under-determined parts are also characterised without a matching: deleting
    /// an over row keeps the structural rank, deleting an under column keeps it too, and
    /// deleting a well row or a column of the well or over part lowers it.
    #[test]
    fn parts_match_rank_deletion((n, rows) in arb_pattern()) {
        let g = Bipartite::from_pattern(n, &rows).unwrap();
        let dm = structure::decompose(&g);
        let rank = dm.structural_rank;
        for r in 0..g.rows() {
            let mut fewer = rows.clone();
            fewer.remove(r);
            let h = Bipartite::from_pattern(n, &fewer).unwrap();
            let k = maximum_matching(&h).size;
            prop_assert_eq!(k == rank, dm.part_of_row(r) == Some(PartKind::Over), "row {}", r);
        }
        for c in 0..g.cols() {
            let without: Vec<Vec<usize>> =
                rows.iter().map(|row| row.iter().copied().filter(|&j| j != c).collect()).collect();
            let h = Bipartite::from_pattern(n, &without).unwrap();
            let k = maximum_matching(&h).size;
            prop_assert_eq!(k == rank, dm.part_of_col(c) == Some(PartKind::Under), "column {}", c);
        }
    }
}
