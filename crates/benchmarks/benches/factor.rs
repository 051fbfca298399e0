//! Factoring dense random 10-bit square matrices (thesis chapter 7): exact LDU with each
//! simplification method, with and without the machine-integer fast path, against the float QR
//! backend on the same inputs.
//!
//! `cargo bench -p benchmarks --bench factor`

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

use api::LinearBackend;
use benchmarks::random_dense;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use exact_ldu::{ExactLdu, Simplification};
use float_qr::FloatQr;
use std::hint::black_box;

fn factor(c: &mut Criterion) {
    let mut group = c.benchmark_group("factor");
    group.sample_size(10);
    for n in [10usize, 20, 40, 80] {
        let a = random_dense(n, n, 10, 1000 + n as u64);
        for (name, method) in [
            ("gcd", Simplification::Gcd),
            ("turner", Simplification::Turner),
            ("none", Simplification::None),
        ] {
            // Without simplification entries double in size at every step (about 10·2^(r−1)
            // bits): beyond n = 10 a single factoring takes minutes.
            if method == Simplification::None && n > 10 {
                continue;
            }
            group.bench_with_input(BenchmarkId::new(format!("exact-{name}"), n), &a, |b, a| {
                let backend = ExactLdu::new(method);
                b.iter(|| black_box(backend.factor(a)))
            });
            group.bench_with_input(
                BenchmarkId::new(format!("exact-{name}-bigint-only"), n),
                &a,
                |b, a| {
                    let backend = ExactLdu::without_machine_integers(method);
                    b.iter(|| black_box(backend.factor(a)))
                },
            );
        }
        group.bench_with_input(BenchmarkId::new("float-qr", n), &a, |b, a| {
            let backend = FloatQr::default();
            b.iter(|| black_box(backend.factor(a)))
        });
    }
    group.finish();
}

criterion_group!(benches, factor);
criterion_main!(benches);
