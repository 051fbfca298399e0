//! Change criteria (Brenner 3.1) against ECLES' own least-squares Update on the same edits:
//! windows of about 20 and 60 derived scalar parameters of the banded spline-like system of
//! the `update` bench, exact backend. `update_by` runs the least-squares Update first (its
//! verdict), then the criterion on the dense exact problem.
//!
//! `cargo bench -p benchmarks --bench criteria`

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

use api::Rational;
use benchmarks::{banded_system, window_edit};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use ecles::{Edit, EditSpec, Measure};
use exact_ldu::{ExactLdu, Simplification};
use std::hint::black_box;

fn criteria(c: &mut Criterion) {
    let backend = ExactLdu::new(Simplification::Gcd);
    let mut group = c.benchmark_group("criteria");
    group.sample_size(20);
    for width in [20usize, 60] {
        let (system, params, values) = banded_system(400, 42);
        let (anchors, derived) = window_edit(&params, width);
        let spec = EditSpec::new(anchors.clone(), derived.clone());
        let edit = Edit::initialize(&backend, &system, &values, &spec).expect("edit initialises");
        let shift = Rational::new(7.into(), 3.into());
        let anchor_values: Vec<Vec<Rational>> = anchors
            .iter()
            .map(|p| vec![&values.get(*p)[0] + &shift])
            .collect();
        // Changes measured from the current values (what L1 and Fewest use).
        let hints: Vec<Vec<Rational>> = derived.iter().map(|p| values.get(*p).to_vec()).collect();
        group.bench_function(BenchmarkId::new("update-L2", width), |b| {
            b.iter(|| black_box(edit.update(&anchor_values, &hints).is_ok()))
        });
        // The half of the derived parameters nearest the anchors primary.
        let primary: Vec<_> = derived[..derived.len() / 2].to_vec();
        let cases = [
            ("L2-primary-half", Measure::L2, Some(primary)),
            ("L1", Measure::L1, None),
            ("Fewest", Measure::Fewest, None),
        ];
        for (name, measure, primary) in cases {
            let criterion = ecles::Criterion { measure, primary };
            let (_, chosen) = edit
                .update_by(&criterion, &anchor_values, &hints)
                .expect("the window absorbs the move");
            // What the criterion chose, next to its time.
            println!(
                "{name}/{width}: measure {}, {} changed, face {:?}, supports {:?}",
                chosen.value,
                chosen.changed.len(),
                chosen.optimal_face_dimension,
                chosen.supports.as_ref().map(|s| (
                    s.proven_minimal,
                    s.count,
                    s.ties_complete,
                    s.rank_tests
                ))
            );
            group.bench_function(BenchmarkId::new(name, width), |b| {
                b.iter(|| black_box(edit.update_by(&criterion, &anchor_values, &hints).is_ok()))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, criteria);
criterion_main!(benches);
