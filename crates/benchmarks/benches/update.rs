//! ECLES latency: Initialize (extract, factor, prepare) and Update (weak check + weighted least
//! squares) for edits with about 20 and about 60 derived scalar parameters of a banded sparse
//! system shaped like spline smoothness conditions, exact and float backends on the same edit.
//!
//! `cargo bench -p benchmarks --bench update`

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

use api::{Factorization, LinearBackend, Rational};
use benchmarks::{banded_system, window_edit};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use ecles::{Edit, EditSpec};
use exact_ldu::{ExactLdu, Simplification};
use float_qr::FloatQr;
use std::hint::black_box;

fn bench_backend<B: LinearBackend>(c: &mut Criterion, name: &str, backend: &B)
where
    <B::Factorization as Factorization>::Scalar: std::fmt::Debug,
{
    let mut group = c.benchmark_group("ecles");
    for width in [20usize, 60] {
        let (system, params, values) = banded_system(400, 42);
        let (anchors, derived) = window_edit(&params, width);
        let spec = EditSpec::new(anchors.clone(), derived.clone());
        group.bench_function(BenchmarkId::new(format!("initialize-{name}"), width), |b| {
            b.iter(|| black_box(Edit::initialize(backend, &system, &values, &spec).is_ok()))
        });
        let edit = Edit::initialize(backend, &system, &values, &spec).expect("edit initialises");
        // The anchor moves by 7/3; hints move the derived parameters half as far.
        let shift = Rational::new(7.into(), 3.into());
        let half = Rational::new(7.into(), 6.into());
        let anchor_values: Vec<Vec<Rational>> = anchors
            .iter()
            .map(|p| vec![&values.get(*p)[0] + &shift])
            .collect();
        let hints: Vec<Vec<Rational>> = derived
            .iter()
            .map(|p| vec![&values.get(*p)[0] + &half])
            .collect();
        edit.update(&anchor_values, &hints)
            .expect("the window absorbs the move");
        group.bench_function(BenchmarkId::new(format!("update-{name}"), width), |b| {
            b.iter(|| black_box(edit.update(&anchor_values, &hints).is_ok()))
        });
    }
    group.finish();
}

fn updates(c: &mut Criterion) {
    bench_backend(c, "exact", &ExactLdu::new(Simplification::Gcd));
    bench_backend(c, "float", &FloatQr::default());
}

criterion_group!(benches, updates);
criterion_main!(benches);
