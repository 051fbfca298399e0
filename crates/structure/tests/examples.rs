//! Worked examples: Brenner's system (3), over- and under-determined systems, empty matrices,
//! errors, explanations, and graphs deep enough to overflow any recursive implementation.

use api::IntMatrix;
use structure::{
    components, decompose, dulmage_mendelsohn, explain, explain_rows, maximum_matching, Bipartite,
    Matching, Node, PartKind, StructureError,
};

fn names(prefix: &str, n: usize) -> Vec<String> {
    (1..=n).map(|k| format!("{prefix}{k}")).collect()
}

/// Columns are 1-based as in the paper.
fn pattern(cols: usize, rows: &[&[usize]]) -> Bipartite {
    let rows: Vec<Vec<usize>> = rows
        .iter()
        .map(|r| r.iter().map(|c| c - 1).collect())
        .collect();
    Bipartite::from_pattern(cols, &rows).expect("columns in range")
}

/// Brenner's example (3): f1(x1,x2), f2(x1,x2), f3(x2,x3,x4), f4(x1,x3,x4), f5(x3,x5,x7),
/// f6(x4,x5,x6), f7(x6,x7).
fn brenner() -> Bipartite {
    pattern(
        7,
        &[
            &[1, 2],
            &[1, 2],
            &[2, 3, 4],
            &[1, 3, 4],
            &[3, 5, 7],
            &[4, 5, 6],
            &[6, 7],
        ],
    )
}

#[test]
fn brenner_example_blocks_in_solve_order() {
    let g = brenner();
    assert_eq!((g.rows(), g.cols(), g.nnz()), (7, 7, 18));
    let m = maximum_matching(&g);
    assert_eq!(m.size, 7);
    let dm = dulmage_mendelsohn(&g, &m).unwrap();
    assert!(dm.is_well_constrained());
    assert_eq!(dm.structural_rank, 7);
    assert_eq!(dm.well.rows, (0..7).collect::<Vec<_>>());
    let blocks: Vec<(Vec<usize>, Vec<usize>, Vec<usize>)> = dm
        .blocks
        .iter()
        .map(|b| (b.rows.clone(), b.cols.clone(), b.depends_on.clone()))
        .collect();
    assert_eq!(
        blocks,
        vec![
            (vec![0, 1], vec![0, 1], vec![]),
            (vec![2, 3], vec![2, 3], vec![0]),
            (vec![4, 5, 6], vec![4, 5, 6], vec![1]),
        ]
    );
    assert!(dm.blocks.iter().all(|b| b.over_inputs.is_empty()));
    assert_eq!(dm.block_of_col(5), Some(2));
    assert_eq!(dm.block_of_row(3), Some(1));
    assert_eq!(dm.part_of_row(6), Some(PartKind::Well));
    assert_eq!(dm.part_of_col(7), None);
}

#[test]
fn brenner_example_from_int_matrix() {
    let dense: Vec<Vec<i64>> = vec![
        vec![1, 1, 0, 0, 0, 0, 0],
        vec![2, -1, 0, 0, 0, 0, 0],
        vec![0, 1, 1, 1, 0, 0, 0],
        vec![1, 0, 3, -1, 0, 0, 0],
        vec![0, 0, 1, 0, 1, 0, 1],
        vec![0, 0, 0, 1, 1, 1, 0],
        vec![0, 0, 0, 0, 0, 1, 1],
    ];
    let m = IntMatrix::from_dense(7, &dense).unwrap();
    assert_eq!(Bipartite::from_matrix(&m), brenner());
}

#[test]
fn brenner_explanations_trace_back_through_h() {
    let g = brenner();
    let dm = decompose(&g);
    let (f, x) = (names("f", 7), names("x", 7));
    let e = explain(&dm, &g, 2, &f, &x).unwrap();
    assert_eq!(e.part, PartKind::Well);
    assert_eq!(e.block, Some(1));
    assert_eq!(
        e.text,
        vec![
            "x3 is fixed by f3, f4 together with x1, x2 (f3, f4 fix x3 and x4 jointly)",
            "x1 and x2 are fixed by f1, f2",
            "solve order: [f1, f2 → x1, x2] then [f3, f4 → x3, x4]",
        ]
    );
    assert_eq!(e.chain.len(), 2);
    assert_eq!(e.chain[0].block, Some(0));
    assert_eq!(e.chain[1].rows, vec![2, 3]);
    assert_eq!(e.chain[1].inputs, vec![0, 1]);
    assert_eq!(e.chain[1].input_names, vec!["x1", "x2"]);

    let e = explain(&dm, &g, 5, &f, &x).unwrap();
    assert_eq!(
        e.text[..3],
        [
            "x6 is fixed by f5, f6, f7 together with x3, x4 (f5, f6, f7 fix x5, x6 and x7 jointly)",
            "x3 and x4 are fixed by f3, f4 together with x1, x2",
            "x1 and x2 are fixed by f1, f2",
        ]
    );
    assert_eq!(
        e.chain.iter().map(|s| s.block).collect::<Vec<_>>(),
        vec![Some(0), Some(1), Some(2)]
    );

    let e = explain(&dm, &g, 0, &f, &x).unwrap();
    assert_eq!(
        e.text,
        vec!["x1 is fixed by f1, f2 (f1, f2 fix x1 and x2 jointly)"]
    );

    // Labels are optional.
    let e = explain(&dm, &g, 0, &[], &[]).unwrap();
    assert_eq!(
        e.text,
        vec!["column 0 is fixed by row 0, row 1 (row 0, row 1 fix column 0 and column 1 jointly)"]
    );
}

/// f1(x1), f2(x1), f3(x1, x2), f4(x3, x4), plus x5 in no row.
fn mixed() -> Bipartite {
    pattern(5, &[&[1], &[1], &[1, 2], &[3, 4]])
}

#[test]
fn over_well_and_under_parts() {
    let g = mixed();
    let dm = decompose(&g);
    assert_eq!(dm.structural_rank, 3);
    assert!(!dm.is_well_constrained());
    assert_eq!(
        (dm.over.rows.clone(), dm.over.cols.clone()),
        (vec![0, 1], vec![0])
    );
    assert_eq!(
        (dm.well.rows.clone(), dm.well.cols.clone()),
        (vec![2], vec![1])
    );
    assert_eq!(
        (dm.under.rows.clone(), dm.under.cols.clone()),
        (vec![3], vec![2, 3, 4])
    );
    assert_eq!(dm.blocks.len(), 1);
    assert_eq!(dm.blocks[0].over_inputs, vec![0]);
    assert!(dm.blocks[0].depends_on.is_empty());

    let (f, x) = (names("f", 4), names("x", 5));
    let e = explain(&dm, &g, 1, &f, &x).unwrap();
    assert_eq!(
        e.text,
        vec![
            "x2 is fixed by f3 together with x1",
            "x1 is fixed by f1, f2",
            "over-constrained: more constraints than unknowns here: f1, f2 (2 constraints on 1 unknown)",
            "solve order: [f1, f2 → x1] then [f3 → x2]",
        ]
    );
    assert_eq!(e.chain[0].part, PartKind::Over);

    let e = explain(&dm, &g, 0, &f, &x).unwrap();
    assert_eq!(e.part, PartKind::Over);
    assert_eq!(
        e.text,
        vec![
            "x1 is fixed by f1, f2",
            "over-constrained: more constraints than unknowns here: f1, f2 (2 constraints on 1 unknown)",
        ]
    );

    let e = explain(&dm, &g, 2, &f, &x).unwrap();
    assert_eq!(e.part, PartKind::Under);
    assert_eq!(
        e.text,
        vec![
            "x3 is free: not determined by the constraints alone (it lies in the under-determined part with 2 unknowns and 1 constraint)",
            "constraints there: f4; unknowns there: x3, x4",
        ]
    );
    let e = explain(&dm, &g, 4, &f, &x).unwrap();
    assert_eq!(e.text, vec!["x5 is free: no constraint involves it"]);
    assert_eq!(e.chain[0].cols, vec![4]);
}

#[test]
fn explain_rows_tells_structural_from_numerical_dependency() {
    let g = mixed();
    let dm = decompose(&g);
    let (f, x) = (names("f", 4), names("x", 5));
    let r = explain_rows(&dm, &g, &[1, 0, 1], &f, &x).unwrap();
    assert_eq!(r.rows, vec![0, 1]);
    assert_eq!(r.cols, vec![0]);
    assert_eq!(r.structural_rank, 1);
    assert!(r.structurally_dependent);
    assert_eq!(
        r.text,
        vec![
            "f1, f2 involve 1 unknown: x1",
            "structurally dependent: these 2 constraints can be matched with only 1 distinct unknown, so they are dependent whatever the coefficients",
            "f1, f2 lie in the over-determined part (2 constraints on 1 unknown in all)",
            "x1 lies in the over-determined part (2 constraints on 1 unknown in all)",
        ]
    );

    let g = brenner();
    let dm = decompose(&g);
    let (f, x) = (names("f", 7), names("x", 7));
    let r = explain_rows(&dm, &g, &[2, 0, 1], &f, &x).unwrap();
    assert!(!r.structurally_dependent);
    assert_eq!(r.structural_rank, 3);
    assert_eq!(r.row_groups.len(), 2);
    assert_eq!(r.row_groups[0].block, Some(0));
    assert_eq!(r.row_groups[1].names, vec!["f3"]);
    assert_eq!(
        r.text[1..],
        [
            "structurally independent: each constraint can be paired with an unknown of its own, so any dependency among them comes from the values of the coefficients",
            "f1, f2 lie in block 0 of the solve order (f1, f2 fix x1 and x2)",
            "f3 lies in block 1 of the solve order (f3, f4 fix x3 and x4)",
            "x1, x2 lie in block 0 of the solve order (f1, f2 fix x1 and x2)",
            "x3, x4 lie in block 1 of the solve order (f3, f4 fix x3 and x4)",
        ]
    );
    assert!(matches!(
        explain_rows(&dm, &g, &[7], &f, &x),
        Err(StructureError::NoSuchRow { row: 7, rows: 7 })
    ));
}

#[test]
fn empty_matrices() {
    // 0 × 3: every unknown is free.
    let g = Bipartite::from_matrix(&IntMatrix::zeros(0, 3));
    let dm = decompose(&g);
    assert_eq!(dm.structural_rank, 0);
    assert_eq!(dm.under.cols, vec![0, 1, 2]);
    assert!(dm.over.rows.is_empty() && dm.well.cols.is_empty() && dm.blocks.is_empty());
    let e = explain(&dm, &g, 1, &[], &[]).unwrap();
    assert_eq!(e.part, PartKind::Under);
    assert_eq!(components(&g).len(), 3);

    // 2 × 0: the rows (0 = q) are over-determined.
    let g = Bipartite::from_matrix(&IntMatrix::zeros(2, 0));
    let dm = decompose(&g);
    assert_eq!(dm.over.rows, vec![0, 1]);
    assert!(dm.over.cols.is_empty() && dm.under.rows.is_empty());
    assert!(matches!(
        explain(&dm, &g, 0, &[], &[]),
        Err(StructureError::NoSuchColumn { col: 0, cols: 0 })
    ));
    let r = explain_rows(&dm, &g, &[0, 1], &[], &[]).unwrap();
    assert!(r.structurally_dependent);
    assert_eq!(components(&g).len(), 2);

    // 0 × 0.
    let g = Bipartite::from_matrix(&IntMatrix::zeros(0, 0));
    let dm = decompose(&g);
    assert!(dm.is_well_constrained() && dm.blocks.is_empty());
    assert!(components(&g).is_empty());
    assert_eq!(g.to_petgraph().node_count(), 0);
}

#[test]
fn components_are_ordered_and_sorted() {
    // Row 1 is empty, column 5 is in no row.
    let g = pattern(6, &[&[3, 4], &[], &[1, 2], &[4, 2], &[6]]);
    let c = components(&g);
    let got: Vec<(Vec<usize>, Vec<usize>)> = c
        .components
        .iter()
        .map(|k| (k.rows.clone(), k.cols.clone()))
        .collect();
    assert_eq!(
        got,
        vec![
            (vec![0, 2, 3], vec![0, 1, 2, 3]),
            (vec![1], vec![]),
            (vec![4], vec![5]),
            (vec![], vec![4]),
        ]
    );
    assert_eq!(c.of_row(3), Some(0));
    assert_eq!(c.of_col(4), Some(3));
    assert_eq!(c.of_col(6), None);
    let pg = g.to_petgraph();
    assert_eq!(pg.node_count(), 5 + 6);
    assert_eq!(pg.edge_count(), g.nnz());
    assert_eq!(petgraph::algo::connected_components(&pg), c.len());
    assert_eq!(pg[petgraph::graph::NodeIndex::new(5 + 2)], Node::Col(2));
}

#[test]
fn refuses_bad_inputs() {
    assert_eq!(
        Bipartite::from_pattern(2, &[vec![0], vec![1, 2]]),
        Err(StructureError::ColumnOutOfRange {
            row: 1,
            col: 2,
            cols: 2
        })
    );
    // Repeats count once.
    let g = Bipartite::from_pattern(3, &[vec![2, 0, 2]]).unwrap();
    assert_eq!(g.row(0), &[0, 2]);

    let g = brenner();
    let empty = Matching {
        row_to_col: vec![None; 7],
        col_to_row: vec![None; 7],
        size: 0,
    };
    assert!(matches!(
        dulmage_mendelsohn(&g, &empty),
        Err(StructureError::MatchingNotMaximum { .. })
    ));
    let wrong_size = Matching {
        row_to_col: vec![None; 6],
        col_to_row: vec![None; 7],
        size: 0,
    };
    assert!(matches!(
        dulmage_mendelsohn(&g, &wrong_size),
        Err(StructureError::MatchingSize { .. })
    ));
    // f1 does not involve x3.
    let mut not_an_edge = maximum_matching(&g);
    not_an_edge.row_to_col[0] = Some(2);
    assert!(matches!(
        dulmage_mendelsohn(&g, &not_an_edge),
        Err(StructureError::MatchingInvalid { row: 0 })
    ));
    let dm = decompose(&mixed());
    assert!(matches!(
        explain(&dm, &g, 0, &[], &[]),
        Err(StructureError::MatchingSize { .. })
    ));
}

#[test]
fn results_serialise_without_lookup_tables() {
    let g = brenner();
    let dm = decompose(&g);
    let json = serde_json::to_value(&dm).unwrap();
    assert_eq!(json["structural_rank"], 7);
    assert_eq!(json["blocks"][2]["depends_on"], serde_json::json!([1]));
    assert!(json.get("row_part").is_none());
    let e = explain(&dm, &g, 2, &[], &[]).unwrap();
    let json = serde_json::to_value(&e).unwrap();
    assert_eq!(json["part"], "well");
    assert_eq!(json["chain"][1]["rows"], serde_json::json!([2, 3]));
    let m = serde_json::to_value(maximum_matching(&g)).unwrap();
    assert_eq!(m["size"], 7);
    let c = serde_json::to_value(components(&g)).unwrap();
    assert_eq!(c["components"][0]["cols"].as_array().unwrap().len(), 7);
}

/// A graph whose only augmenting path after the greedy start has length `n`, and whose block
/// graph is a chain of `n` blocks: recursion would need `n` stack frames.
#[test]
fn deep_paths_do_not_recurse() {
    let n = 1_000_000;
    // Row i (i < n − 1) involves x_i and x_{i+1}; the last row only x_0. Greedy gives row i
    // column i; the last row must augment through all of them.
    let mut rows: Vec<Vec<usize>> = (0..n - 1).map(|i| vec![i, i + 1]).collect();
    rows.push(vec![0]);
    let g = Bipartite::from_pattern(n, &rows).unwrap();
    let m = maximum_matching(&g);
    assert_eq!(m.size, n);
    let dm = dulmage_mendelsohn(&g, &m).unwrap();
    assert!(dm.is_well_constrained());
    assert_eq!(dm.blocks.len(), n);
    assert_eq!(components(&g).len(), 1);
    // The last row fixes x_0 first, then each row the next unknown.
    assert_eq!(dm.blocks[0].rows, vec![n - 1]);
    assert_eq!(dm.blocks[n - 1].cols, vec![n - 1]);
    assert!(dm.blocks[1..].iter().all(|b| b.depends_on.len() == 1));

    // One cycle through every pair: a single irreducible block of n rows.
    let mut rows: Vec<Vec<usize>> = (0..n - 1).map(|i| vec![i, i + 1]).collect();
    rows.push(vec![0, n - 1]);
    let g = Bipartite::from_pattern(n, &rows).unwrap();
    let dm = decompose(&g);
    assert_eq!(dm.blocks.len(), 1);
    assert_eq!(dm.blocks[0].rows.len(), n);
}

#[test]
fn long_explanation_chain() {
    let n = 100_000;
    let mut rows: Vec<Vec<usize>> = vec![vec![0]];
    rows.extend((1..n).map(|i| vec![i - 1, i]));
    let g = Bipartite::from_pattern(n, &rows).unwrap();
    let dm = decompose(&g);
    let e = explain(&dm, &g, n - 1, &[], &[]).unwrap();
    assert_eq!(e.chain.len(), n);
    assert_eq!(
        e.text[0],
        format!(
            "column {} is fixed by row {} together with column {}",
            n - 1,
            n - 1,
            n - 2
        )
    );
    assert_eq!(e.text[n - 1], "column 0 is fixed by row 0");
}
