//! Generic edits on linear point systems (`benchmarks::point_drag`, the systems of
//! `tools/peer_bench.py`, which times SolveSpace and kiwisolver on them): one point dragged by
//! (3, −2), every other parameter derived with unit weights. Per system and size: the whole
//! edit (Initialize + one Update) and a drag frame (a further Update), exact and float, and the
//! exact frame unreduced (`Edit::frame`).
//!
//! `cargo bench -p benchmarks --bench points`

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

use api::LinearBackend;
use benchmarks::{point_drag, PointSystem};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use ecles::{Edit, EditSpec};
use exact_ldu::ExactLdu;
use float_qr::FloatQr;
use std::hint::black_box;

/// One benchmark case: the system's label, its size, the drag, its edit spec and hints.
type Case = (
    &'static str,
    usize,
    benchmarks::PointDrag,
    EditSpec,
    Vec<Vec<api::Rational>>,
);

/// Every system at every size (parallelograms with one point more: `2m + 1` corners), with the
/// edit spec and hints of its drag.
fn cases(sizes: &[usize]) -> Vec<Case> {
    let mut out = Vec::new();
    for (kind, label) in [
        (PointSystem::Chain, "chain"),
        (PointSystem::Grid, "grid"),
        (PointSystem::Parallelograms, "parallelograms"),
    ] {
        for &n in sizes {
            let n = if kind == PointSystem::Parallelograms {
                n + 1
            } else {
                n
            };
            let drag = point_drag(kind, n);
            let spec = EditSpec::new(drag.anchors.clone(), drag.derived.clone());
            let hints = drag
                .derived
                .iter()
                .map(|p| drag.values.get(*p).to_vec())
                .collect();
            out.push((label, n, drag, spec, hints));
        }
    }
    out
}

fn drags_with<B: LinearBackend>(c: &mut Criterion, name: &str, backend: &B, sizes: &[usize])
where
    <B::Factorization as api::Factorization>::Scalar: std::fmt::Debug,
{
    let mut group = c.benchmark_group("point-drag");
    group.sample_size(10);
    for (label, n, drag, spec, hints) in cases(sizes) {
        let id = format!("{name}-{label}{n}");
        group.bench_function(BenchmarkId::new("edit", &id), |b| {
            b.iter(|| {
                exact_ldu::forget_last_factoring();
                let edit = Edit::initialize(backend, &drag.system, &drag.values, &spec)
                    .expect("initialize");
                black_box(edit.update(&drag.targets, &hints).is_ok())
            })
        });
        let edit =
            Edit::initialize(backend, &drag.system, &drag.values, &spec).expect("initialize");
        edit.update(&drag.targets, &hints).expect("solvable");
        group.bench_function(BenchmarkId::new("frame", &id), |b| {
            b.iter(|| black_box(edit.update(&drag.targets, &hints).is_ok()))
        });
    }
    group.finish();
}

/// The exact drag frame as an editor draws it (`Edit::frame`): the values of
/// [`Edit::update`] exactly, as fractions over the solution's common denominator, not reduced;
/// given the hints every frame (`unreduced-frame`) and with the hints fixed for the drag
/// (`drag-frame`, [`ecles::HintedEdit::frame`]).
fn exact_frames(c: &mut Criterion, sizes: &[usize]) {
    let mut group = c.benchmark_group("point-drag");
    group.sample_size(10);
    for (label, n, drag, spec, hints) in cases(sizes) {
        let edit = Edit::initialize(&ExactLdu::default(), &drag.system, &drag.values, &spec)
            .expect("initialize");
        let frame = edit.frame(&drag.targets, &hints).expect("solvable");
        let update = edit.update(&drag.targets, &hints).expect("solvable");
        // The frame is the update, unreduced.
        for (f, (_, u)) in frame.iter().zip(&update.derived) {
            for (a, b) in f.iter().zip(u) {
                assert_eq!(a.reduced(), *b);
            }
        }
        group.bench_function(
            BenchmarkId::new("unreduced-frame", format!("exact-{label}{n}")),
            |b| b.iter(|| black_box(edit.frame(&drag.targets, &hints).is_ok())),
        );
        // A drag: the hints (the values at mouse-down) fixed once, only the anchors move, as
        // kiwisolver's edit variable is added once and then only suggested.
        let hinted = edit.with_hints(&hints).expect("hints");
        assert_eq!(hinted.frame(&drag.targets).expect("solvable"), frame);
        group.bench_function(
            BenchmarkId::new("drag-frame", format!("exact-{label}{n}")),
            |b| b.iter(|| black_box(hinted.frame(&drag.targets).is_ok())),
        );
    }
    group.finish();
}

fn drags(c: &mut Criterion) {
    exact_frames(c, &[10, 100, 1000]);
    drags_with(c, "exact", &ExactLdu::default(), &[10, 100, 1000]);
    // The dense float QR of a 1 000-point system takes seconds: the float twin is compared on
    // the smaller ones.
    drags_with(c, "float", &FloatQr::default(), &[10, 100]);
}

criterion_group!(benches, drags);
criterion_main!(benches);
