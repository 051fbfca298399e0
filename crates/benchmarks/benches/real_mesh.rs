//! The exact path on a real-looking irregular mesh: `data/figure.obj` (588 vertices, 1 052
//! triangles, coordinates on a 0.5 lattice, made by `tools/make_figure_mesh.py`), degree 5, C1.
//! A soft translation of the vertex `v255` near the middle by (20, 60) with neighbourhoods
//! δ_max = 8, 12 and 16, as a mouse-down (Select + ExpandDerived + Initialize), one Update (the
//! first and a repeated one), an exact drag frame (the Update unreduced), its float preview, and
//! the commit (Update written into the values), exact and float backends.
//!
//! `cargo bench -p benchmarks --bench real_mesh`

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

use api::{ConstraintSystem, Factorization, LinearBackend, Rational, Values};
/// The `benchmarks` library declares the `ecles` binary's allocator (mimalloc); a bench links
/// it only when it uses the library, and would otherwise measure with the system's allocator.
use benchmarks as _;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use ecles::Edit;
use exact_ldu::ExactLdu;
use float_qr::FloatQr;
use spline2d::edit::{Neighborhood, Operation, SplineEditor};
use spline2d::mesh_io::{parse_obj, MeshOptions};
use spline2d::net::ControlNet;
use spline2d::spline::Spline;
use std::hint::black_box;

mod common;

fn figure_spline() -> Spline {
    let text = include_str!("../data/figure.obj");
    let read = parse_obj(text, "figure.obj", &MeshOptions::default()).expect("valid mesh");
    Spline::new(read.mesh, 5, 1).expect("valid spline")
}

/// The figure spline declared as one source, with its editor parts.
struct Fixture {
    spline: Spline,
    net: ControlNet,
    system: ConstraintSystem,
    values: Values,
    params: spline2d::params::SplineParams,
    anchor: usize,
}

impl Fixture {
    fn new() -> Self {
        let spline = figure_spline();
        let net = ControlNet::new(&spline);
        let mut system = ConstraintSystem::new();
        let mut values = Values::default();
        let params = spline
            .declare(&mut system, &mut values, "fig", spline.identity_positions())
            .expect("fresh system");
        let anchor = spline
            .points()
            .iter()
            .position(|p| &*p.name == "v255")
            .expect("vertex 255");
        Fixture {
            spline,
            net,
            system,
            values,
            params,
            anchor,
        }
    }

    /// Select + ExpandDerived for the translation by (20, 60), then ECLES Initialize.
    fn mouse_down<B: LinearBackend>(
        &self,
        backend: &B,
        radius: u32,
    ) -> (spline2d::edit::Plan, Edit<B::Factorization>) {
        let editor = SplineEditor {
            spline: &self.spline,
            net: &self.net,
            params: &self.params,
        };
        let operation = Operation::Translate {
            by: vec![
                Rational::from_integer(20.into()),
                Rational::from_integer(60.into()),
            ],
        };
        let (_, plan) = editor
            .plan_operation(
                &self.system,
                &self.values,
                &[self.anchor],
                Neighborhood::Radius(radius),
                &operation,
                1,
            )
            .expect("plan");
        let edit =
            Edit::initialize(backend, &self.system, &self.values, &plan.spec).expect("initialize");
        (plan, edit)
    }
}

fn edits_with<B: LinearBackend>(c: &mut Criterion, name: &str, backend: &B)
where
    <B::Factorization as Factorization>::Scalar: std::fmt::Debug,
    Edit<B::Factorization>: Clone,
{
    let fixture = Fixture::new();
    let mut group = c.benchmark_group("real-mesh-edit");
    group.sample_size(10);
    for radius in [8u32, 12, 16] {
        let label = format!("{name}-delta{radius}");
        // A first mouse-down on this derived set (nothing remembered), and a repeated one (the
        // same anchor and neighbourhood again: `R_ED` depends on the mesh and the sets only, so
        // the exact backend's memo of the last factoring answers).
        group.bench_function(BenchmarkId::new("mouse-down", &label), |b| {
            b.iter(|| {
                exact_ldu::forget_last_factoring();
                black_box(fixture.mouse_down(backend, radius).1.report().rank)
            })
        });
        group.bench_function(BenchmarkId::new("mouse-down-again", &label), |b| {
            b.iter(|| black_box(fixture.mouse_down(backend, radius).1.report().rank))
        });
        let (plan, edit) = fixture.mouse_down(backend, radius);
        common::update_and_preview(&mut group, &label, &edit, &plan);
    }
    group.finish();
}

fn edits(c: &mut Criterion) {
    edits_with(c, "exact", &ExactLdu::default());
    edits_with(c, "float", &FloatQr::default());
}

/// An exact drag frame (`Edit::frame`): the exact Update over its common denominator, not
/// reduced (the reduction waits for the commit).
fn frames(c: &mut Criterion) {
    let fixture = Fixture::new();
    let mut group = c.benchmark_group("real-mesh-edit");
    group.sample_size(10);
    for radius in [8u32, 12, 16] {
        let (plan, edit) = fixture.mouse_down(&ExactLdu::default(), radius);
        let step = &plan.steps[0];
        edit.update(&step.anchors, &step.hints).expect("solvable");
        group.bench_function(
            BenchmarkId::new("exact-frame", format!("exact-delta{radius}")),
            |b| b.iter(|| black_box(edit.frame(&step.anchors, &step.hints).is_ok())),
        );
        // A snapped Update as a drag frame (every constraint exact, small values), after the
        // first one prepared the peeled basis and the f64 factoring.
        edit.update_snapped(&step.anchors, &step.hints, 24)
            .expect("solvable");
        group.bench_function(
            BenchmarkId::new("snapped-frame", format!("exact-delta{radius}")),
            |b| b.iter(|| black_box(edit.update_snapped(&step.anchors, &step.hints, 24).is_ok())),
        );
    }
    group.finish();
}

/// The commit at mouse-up: the exact Update written into a copy of the values (`Edit::apply`),
/// and the snapped commit (`Edit::update_snapped` on the grid `2^−24`, written the same way;
/// its first call on an edit also peels the basis and factors `G` in `f64`, so each sample
/// starts from a fresh Initialize taken out of the timing).
fn commits(c: &mut Criterion) {
    let fixture = Fixture::new();
    let mut group = c.benchmark_group("real-mesh-commit");
    group.sample_size(10);
    for radius in [8u32, 12, 16] {
        let (plan, edit) = fixture.mouse_down(&ExactLdu::default(), radius);
        let step = &plan.steps[0];
        group.bench_function(
            BenchmarkId::new("apply", format!("exact-delta{radius}")),
            |b| {
                b.iter(|| {
                    let mut values = fixture.values.clone();
                    black_box(
                        edit.apply(&fixture.system, &mut values, &step.anchors, &step.hints)
                            .is_ok(),
                    )
                })
            },
        );
    }
    for radius in [8u32, 16, 40] {
        let (plan, edit) = fixture.mouse_down(&ExactLdu::default(), radius);
        let step = &plan.steps[0];
        group.bench_function(
            BenchmarkId::new("snapped", format!("exact-delta{radius}")),
            |b| {
                b.iter_batched(
                    || (edit.clone(), fixture.values.clone()),
                    |(edit, mut values)| {
                        let (result, summary) = edit
                            .update_snapped(&step.anchors, &step.hints, 24)
                            .expect("solvable");
                        result.write_into(&mut values);
                        black_box(summary.distance_bound)
                    },
                    criterion::BatchSize::LargeInput,
                )
            },
        );
    }
    group.finish();
}

/// The whole edit at δ_max = 40 with a snapped commit: mouse-down (cold) and the commit.
fn big_neighbourhood(c: &mut Criterion) {
    let fixture = Fixture::new();
    let mut group = c.benchmark_group("real-mesh-delta40");
    group.sample_size(10);
    group.bench_function("mouse-down-and-snapped-commit", |b| {
        b.iter(|| {
            exact_ldu::forget_last_factoring();
            let (plan, edit) = fixture.mouse_down(&ExactLdu::default(), 40);
            let step = &plan.steps[0];
            let mut values = fixture.values.clone();
            let (result, summary) = edit
                .update_snapped(&step.anchors, &step.hints, 24)
                .expect("solvable");
            result.write_into(&mut values);
            black_box(summary.distance_bound)
        })
    });
    group.finish();
}

criterion_group!(benches, edits, frames, commits, big_neighbourhood);
criterion_main!(benches);
