//! spline2d: building control points, conditions and the control net for meshes of about 10,
//! 1 000 and 10 000 triangles; 2DSD Select + ECLES Initialize and one Update for a single-anchor
//! soft translation with δ_max = 3 and 8 on the 1 000-triangle mesh, exact and float backends;
//! the exact Update snapped and as an unreduced drag frame.
//!
//! `cargo bench -p benchmarks --bench spline`

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

use api::{ConstraintSystem, Factorization, LinearBackend, Values};
use benchmarks::perturbed_grid;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use ecles::Edit;
use exact_ldu::ExactLdu;
use float_qr::FloatQr;
use spline2d::edit::{Neighborhood, Operation, Plan, SplineEditor};
use spline2d::net::ControlNet;
use spline2d::spline::Spline;
use std::hint::black_box;

mod common;

fn build(c: &mut Criterion) {
    let mut group = c.benchmark_group("spline-build");
    group.sample_size(10);
    // n × n squares, two triangles each: 8, 968 and 9 800 triangles.
    for n in [2usize, 22, 70] {
        let mesh = perturbed_grid(n);
        let triangles = mesh.triangles().len();
        group.bench_function(BenchmarkId::new("rows+net", triangles), |b| {
            b.iter(|| {
                let spline = Spline::new(mesh.clone(), 5, 1).expect("valid mesh");
                let net = ControlNet::new(&spline);
                black_box((spline.conditions().len(), net.edges().len()))
            })
        });
    }
    group.finish();
}

/// Whole-system exact rank of the scalar C1 system (x and y rows are two identical connected
/// components): one elimination of the whole matrix against one per distinct component.
fn rank(c: &mut Criterion) {
    let mut group = c.benchmark_group("spline-rank");
    group.sample_size(10);
    for n in [3usize, 22] {
        let spline = Spline::new(perturbed_grid(n), 5, 1).expect("valid mesh");
        let mut system = ConstraintSystem::new();
        let mut values = Values::default();
        spline
            .declare(&mut system, &mut values, "phi", spline.identity_positions())
            .expect("fresh system");
        let (matrix, _, _) = system.scalar_matrix();
        let triangles = 2 * n * n;
        group.bench_function(BenchmarkId::new("sparse-monolithic", triangles), |b| {
            b.iter(|| {
                black_box(
                    exact_ldu::sparse::eliminate(
                        &matrix,
                        &[],
                        exact_ldu::sparse::Combinations::Skip,
                    )
                    .rank,
                )
            })
        });
        group.bench_function(BenchmarkId::new("sparse-blockwise", triangles), |b| {
            b.iter(|| {
                black_box(
                    exact_ldu::sparse::eliminate_blockwise(
                        &matrix,
                        &[],
                        exact_ldu::sparse::Combinations::Skip,
                    )
                    .rank,
                )
            })
        });
        if n <= 3 {
            // The dense LDU (the one edits use) is only feasible on small systems.
            group.bench_function(BenchmarkId::new("dense-monolithic", triangles), |b| {
                b.iter(|| black_box(ExactLdu::default().factor(&matrix).map(|f| f.rank())))
            });
            group.bench_function(BenchmarkId::new("dense-blockwise", triangles), |b| {
                b.iter(|| {
                    black_box(
                        exact_ldu::BlockwiseLdu::default()
                            .factor(&matrix)
                            .map(|f| f.rank()),
                    )
                })
            });
        }
    }
    group.finish();
}

/// The degree-5 C1 spline on the 968-triangle perturbed grid, declared as one source, and the
/// edge point in the middle of the mesh that the edit benches drag.
struct GridFixture {
    spline: Spline,
    net: ControlNet,
    system: ConstraintSystem,
    values: Values,
    params: spline2d::params::SplineParams,
    anchor: usize,
}

impl GridFixture {
    fn new() -> Self {
        let spline = Spline::new(perturbed_grid(22), 5, 1).expect("valid mesh");
        let net = ControlNet::new(&spline);
        let mut system = ConstraintSystem::new();
        let mut values = Values::default();
        let params = spline
            .declare(&mut system, &mut values, "phi", spline.identity_positions())
            .expect("fresh system");
        let anchor = spline
            .points()
            .iter()
            .position(|p| &*p.name == "e264-265:2")
            .expect("middle edge point");
        GridFixture {
            spline,
            net,
            system,
            values,
            params,
            anchor,
        }
    }

    fn editor(&self) -> SplineEditor<'_> {
        SplineEditor {
            spline: &self.spline,
            net: &self.net,
            params: &self.params,
        }
    }

    /// 2DSD Select and the plan of a one-step translation of the anchor by `by` within
    /// `radius`.
    fn translation(&self, radius: u32, by: Vec<api::Rational>) -> Plan {
        let editor = self.editor();
        let sel = editor
            .select(
                &self.system,
                &self.values,
                &[self.anchor],
                Neighborhood::Radius(radius),
            )
            .expect("select");
        editor
            .plan(&sel, &self.values, &Operation::Translate { by }, 1)
            .expect("plan")
    }
}

/// The translation the Select + Initialize benches plan: by (3, 3).
fn by_three() -> Vec<api::Rational> {
    vec![api::Rational::from_integer(3.into()); 2]
}

/// The translation of the Update benches: by (7/3, −5/4).
fn by_fractions() -> Vec<api::Rational> {
    vec![
        api::Rational::new(7.into(), 3.into()),
        api::Rational::new((-5).into(), 4.into()),
    ]
}

fn edits_with<B: LinearBackend>(c: &mut Criterion, name: &str, backend: &B)
where
    <B::Factorization as Factorization>::Scalar: std::fmt::Debug,
    Edit<B::Factorization>: Clone,
{
    let fixture = GridFixture::new();
    let (system, values) = (&fixture.system, &fixture.values);
    let mut group = c.benchmark_group("spline-edit");
    group.sample_size(20);
    for radius in [3u32, 8] {
        let label = format!("{name}-delta{radius}");
        group.bench_function(BenchmarkId::new("select+initialize", &label), |b| {
            b.iter(|| {
                let plan = fixture.translation(radius, by_three());
                black_box(Edit::initialize(backend, system, values, &plan.spec).is_ok())
            })
        });
        let plan = fixture.translation(radius, by_fractions());
        let edit = Edit::initialize(backend, system, values, &plan.spec).expect("initialize");
        let step = &plan.steps[0];
        edit.update(&step.anchors, &step.hints)
            .expect("strongly solvable");
        common::update_and_preview(&mut group, &label, &edit, &plan);
        // The drag from the current positions to the step: two updates once, then one linear
        // interpolation per frame.
        let here = |ids: &[api::ParamId]| -> Vec<Vec<api::Rational>> {
            ids.iter().map(|p| values.get(*p).to_vec()).collect()
        };
        let drag = edit
            .drag(
                &here(&plan.spec.anchors),
                &here(&plan.spec.derived),
                &step.anchors,
                &step.hints,
            )
            .expect("strongly solvable");
        group.bench_function(BenchmarkId::new("drag-frame", &label), |b| {
            b.iter(|| black_box(drag.preview(0.37)))
        });
    }
    group.finish();
}

fn edits(c: &mut Criterion) {
    edits_with(c, "exact", &ExactLdu::default());
    edits_with(c, "float", &FloatQr::default());
}

/// The two float cross-checks of an edit, on the same edits: the float backend's own
/// Initialize and Update (dense QR of `R_ED`), against the host's sparse twin's work (the
/// reduced system, the sparse rank test and QR of `R_ED`, one least-squares solve): where the
/// sparse one becomes the faster is where the host switches.
fn float_cross_checks(c: &mut Criterion) {
    let fixture = GridFixture::new();
    let (system, values) = (&fixture.system, &fixture.values);
    let mut group = c.benchmark_group("float-cross-check");
    group.sample_size(10);
    for radius in [1u32, 2, 3, 5, 8] {
        let plan = fixture.translation(radius, by_three());
        let step = &plan.steps[0];
        let (_, reduced) =
            ecles::reduce_edit::<f64>(system, values, &plan.spec).expect("a valid edit");
        let entries = reduced.r_ed().rows() * reduced.r_ed().cols();
        let label = format!("delta{radius}-{entries}-entries");
        group.bench_function(BenchmarkId::new("dense", &label), |b| {
            b.iter(|| {
                let edit = Edit::initialize(&FloatQr::default(), system, values, &plan.spec)
                    .expect("initialize");
                black_box(edit.update(&step.anchors, &step.hints).is_ok())
            })
        });
        group.bench_function(BenchmarkId::new("sparse", &label), |b| {
            b.iter(|| {
                let (_, reduced) =
                    ecles::reduce_edit::<f64>(system, values, &plan.spec).expect("a valid edit");
                let r_ed = reduced.r_ed();
                let weights = vec![1.0; r_ed.cols()];
                let (lsq, _) =
                    float_qr::SparseLeastSquares::new(r_ed, &weights, 1e-10).expect("prepared");
                let b = vec![0.0; r_ed.rows()];
                black_box(lsq.solve(&b, &b, &weights).is_ok())
            })
        });
    }
    group.finish();
}

/// A snapped Update (`Edit::update_snapped` on the grid `2^−24`) on the same edits, after the
/// first one: what an editor committing snapped points draws per frame; and the exact drag
/// frame (`Edit::frame`: the values of `Edit::update` over the solution's common denominator,
/// not reduced), what an editor committing the exact optimum draws per frame.
fn exact_frames(c: &mut Criterion) {
    let fixture = GridFixture::new();
    let (system, values) = (&fixture.system, &fixture.values);
    let mut group = c.benchmark_group("spline-edit");
    group.sample_size(20);
    for radius in [3u32, 8] {
        let plan = fixture.translation(radius, by_fractions());
        let edit =
            Edit::initialize(&ExactLdu::default(), system, values, &plan.spec).expect("initialize");
        let step = &plan.steps[0];
        edit.update_snapped(&step.anchors, &step.hints, 24)
            .expect("solvable");
        group.bench_function(
            BenchmarkId::new("snapped-update", format!("exact-delta{radius}")),
            |b| b.iter(|| black_box(edit.update_snapped(&step.anchors, &step.hints, 24).is_ok())),
        );
        // The frame is the update, unreduced.
        let frame = edit.frame(&step.anchors, &step.hints).expect("solvable");
        let update = edit.update(&step.anchors, &step.hints).expect("solvable");
        for (f, (_, u)) in frame.iter().zip(&update.derived) {
            for (a, b) in f.iter().zip(u) {
                assert_eq!(a.reduced(), *b);
            }
        }
        group.bench_function(
            BenchmarkId::new("unreduced-frame", format!("exact-delta{radius}")),
            |b| b.iter(|| black_box(edit.frame(&step.anchors, &step.hints).is_ok())),
        );
    }
    group.finish();
}

criterion_group!(
    benches,
    build,
    rank,
    edits,
    float_cross_checks,
    exact_frames
);
criterion_main!(benches);
