//! Pieces shared by the edit benches (included with `mod common;`).

use api::Factorization;
use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, BenchmarkId};
use ecles::Edit;
use spline2d::edit::Plan;
use std::hint::black_box;

/// Prints the size of the edit, then benches its first step's exact-or-float Update (the
/// reduced result) and Preview (the same solution rounded to `f64`): the first Update after
/// Initialize (on a fresh copy of the edit, so it includes what the edit works out once per set
/// of hints), then repeated ones.
pub fn update_and_preview<F: Factorization>(
    group: &mut BenchmarkGroup<'_, WallTime>,
    label: &str,
    edit: &Edit<F>,
    plan: &Plan,
) where
    F::Scalar: std::fmt::Debug,
    Edit<F>: Clone,
{
    let step = &plan.steps[0];
    let report = edit.report();
    eprintln!(
        "{label}: {} anchors, {} derived points, {} equations, rank {}",
        plan.spec.anchors.len(),
        plan.spec.derived.len(),
        report.equations,
        report.rank
    );
    group.bench_function(BenchmarkId::new("first-update", label), |b| {
        b.iter(|| black_box(edit.clone().update(&step.anchors, &step.hints).is_ok()))
    });
    group.bench_function(BenchmarkId::new("update", label), |b| {
        b.iter(|| black_box(edit.update(&step.anchors, &step.hints).is_ok()))
    });
    group.bench_function(BenchmarkId::new("preview", label), |b| {
        b.iter(|| black_box(edit.preview(&step.anchors, &step.hints).is_ok()))
    });
}
