//! Structural analysis of the C1 condition systems of degree-5 splines on grids of 968 and
//! 9 800 triangles (n = 22 and 70 squares per side): building the graph, Hopcroft–Karp
//! matching, the Dulmage–Mendelsohn decomposition with its blocks, and both together.
//!
//! The condition system alone is entirely under-determined (every row matched, 5/3 as many
//! unknowns as rows), so it has no blocks. The `fixed` variant adds one row fixing each unknown
//! that a maximum matching leaves free (as anchored or fixed parameters would): a square,
//! structurally well-constrained system whose whole graph goes through the block computation.
//!
//! `cargo bench -p structure`

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

#[path = "support/spline_pattern.rs"]
mod spline_pattern;

use api::IntMatrix;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use spline_pattern::c1_grid_matrix;
use std::hint::black_box;
use structure::{decompose, dulmage_mendelsohn, maximum_matching, Bipartite};

/// The matrix plus a unit row for every column that a maximum matching leaves unmatched.
fn fix_free_unknowns(matrix: &IntMatrix) -> IntMatrix {
    let matching = maximum_matching(&Bipartite::from_matrix(matrix));
    let mut fixed = matrix.clone();
    for (col, row) in matching.col_to_row.iter().enumerate() {
        if row.is_none() {
            if let Err(e) = fixed.push_row(vec![(col, 1.into())]) {
                panic!("column {col} is in range: {e}");
            }
        }
    }
    fixed
}

fn structure(c: &mut Criterion) {
    let mut group = c.benchmark_group("structure");
    group.sample_size(10);
    for (n, variant) in [(22usize, ""), (22, "fixed"), (70, ""), (70, "fixed")] {
        let conditions = c1_grid_matrix(n, 5);
        let matrix = if variant == "fixed" {
            fix_free_unknowns(&conditions)
        } else {
            conditions
        };
        let graph = Bipartite::from_matrix(&matrix);
        let matching = maximum_matching(&graph);
        let dm = match dulmage_mendelsohn(&graph, &matching) {
            Ok(dm) => dm,
            Err(e) => panic!("{e}"),
        };
        let triangles = 2 * n * n;
        let id = if variant.is_empty() {
            triangles.to_string()
        } else {
            format!("{triangles}-{variant}")
        };
        let suffix = if variant.is_empty() {
            String::new()
        } else {
            format!(" ({variant})")
        };
        println!(
            "n = {n}{suffix}: {triangles} triangles, {} rows × {} unknowns, {} nonzeros; structural rank {}; \
             over {}×{}, well {}×{} in {} blocks, under {}×{}",
            graph.rows(),
            graph.cols(),
            graph.nnz(),
            dm.structural_rank,
            dm.over.rows.len(),
            dm.over.cols.len(),
            dm.well.rows.len(),
            dm.well.cols.len(),
            dm.blocks.len(),
            dm.under.rows.len(),
            dm.under.cols.len(),
        );
        group.bench_with_input(BenchmarkId::new("graph", &id), &matrix, |b, m| {
            b.iter(|| Bipartite::from_matrix(black_box(m)))
        });
        group.bench_with_input(BenchmarkId::new("matching", &id), &graph, |b, g| {
            b.iter(|| maximum_matching(black_box(g)))
        });
        group.bench_with_input(
            BenchmarkId::new("dm+blocks", &id),
            &(&graph, &matching),
            |b, (g, m)| b.iter(|| dulmage_mendelsohn(black_box(g), black_box(m))),
        );
        group.bench_with_input(
            BenchmarkId::new("matching+dm+blocks", &id),
            &graph,
            |b, g| b.iter(|| decompose(black_box(g))),
        );
    }
    group.finish();
}

criterion_group!(benches, structure);
criterion_main!(benches);
