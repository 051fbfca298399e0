//! terrain: applying the 2.5D deformation ψ to models of 10⁴, 10⁵ and 10⁶ vertices in random
//! order (with and without the planar map φ) and to a 1000 × 1000 height field in row order,
//! and a z1-mode edit with δ_max = 3 (2DSD Select + ECLES
//! Initialize, and one Update) through the `terrain` source on a 968-triangle reference mesh,
//! exact and float backends.
//!
//! `cargo bench -p benchmarks --bench terrain`

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

use api::{
    BuildRequest, ConstraintSource, ConstraintSystem, Factorization, LinearBackend, PlanRequest,
    Rational, Values,
};
use benchmarks::{perturbed_grid, Rng};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use ecles::{Edit, EditSpec};
use exact_ldu::ExactLdu;
use float_qr::FloatQr;
use plugins_terrain::deform::Psi;
use plugins_terrain::plugin::TerrainSource;
use plugins_terrain::prism::{PrismLayer, Surfaces};
use spline2d::model::Model;
use spline2d::spline::Spline;
use std::hint::black_box;

/// Squares per side of the reference mesh: 2 · 22² = 968 triangles over [0, 220]².
const GRID: usize = 22;

fn q(n: i64, d: i64) -> Rational {
    Rational::new(n.into(), d.into())
}

/// `count` points spread over the prisms `[0, 220]² × [−15, 15]`.
fn model(count: usize, rng: &mut Rng) -> Model {
    let mut unit = || rng.range(0, 1_000_000) as f64 / 1_000_000.0;
    Model {
        positions: (0..count)
            .map(|_| [220.0 * unit(), 220.0 * unit(), 30.0 * unit() - 15.0])
            .collect(),
        triangles: Vec::new(),
    }
}

/// A `side × side` height field over `[0, 220]²` in row order (as a terrain is stored), heights
/// in `[−15, 15]`.
fn height_field(side: usize) -> Model {
    let step = 220.0 / (side - 1) as f64;
    Model {
        positions: (0..side * side)
            .map(|k| {
                let (x, y) = ((k % side) as f64 * step, (k / side) as f64 * step);
                [x, y, 10.0 * (x / 17.0).sin() * (y / 23.0).cos()]
            })
            .collect(),
        triangles: Vec::new(),
    }
}

fn psi(c: &mut Criterion) {
    let spline = Spline::new(perturbed_grid(GRID), 5, 1).expect("valid mesh");
    let layer = PrismLayer::new(q(-20, 1), q(20, 1)).expect("a < b");
    let mut rng = Rng::new(17);
    // Control values off the identity (evaluation costs the same for any values).
    let mut noise = |scale: i64| q(rng.range(-scale, scale), 100);
    let bottom: Vec<Vec<Rational>> = (0..spline.points().len())
        .map(|_| vec![q(-20, 1) + noise(300)])
        .collect();
    let top: Vec<Vec<Rational>> = (0..spline.points().len())
        .map(|_| vec![q(20, 1) + noise(300)])
        .collect();
    let phi: Vec<Vec<Rational>> = spline
        .nominals()
        .iter()
        .map(|p| vec![&p[0] + noise(50), &p[1] + noise(50)])
        .collect();
    let with_phi = Psi::new(
        &spline,
        &layer,
        Surfaces {
            phi: Some(&phi),
            bottom: &bottom,
            top: &top,
        },
    )
    .expect("values fit");
    let without_phi = Psi::new(
        &spline,
        &layer,
        Surfaces {
            phi: None,
            bottom: &bottom,
            top: &top,
        },
    )
    .expect("values fit");
    let mut rng = Rng::new(42);
    let mut group = c.benchmark_group("terrain-psi");
    group.sample_size(10);
    for count in [10_000usize, 100_000, 1_000_000] {
        let points = model(count, &mut rng);
        group.throughput(Throughput::Elements(count as u64));
        group.bench_function(BenchmarkId::new("xyz", count), |b| {
            b.iter(|| black_box(with_phi.deform(&points).outside_mesh.len()))
        });
        if count == 1_000_000 {
            group.bench_function(BenchmarkId::new("z-only", count), |b| {
                b.iter(|| black_box(without_phi.deform(&points).outside_mesh.len()))
            });
            let grid = height_field(1000);
            group.bench_function(BenchmarkId::new("xyz-grid-order", count), |b| {
                b.iter(|| black_box(with_phi.deform(&grid).outside_mesh.len()))
            });
        }
    }
    group.finish();
}

/// The `terrain` source on the 968-triangle mesh (no φ parameters): its system and values.
fn terrain_source() -> (TerrainSource, ConstraintSystem, Values) {
    let mesh = perturbed_grid(GRID);
    let vertices: Vec<String> = mesh
        .vertices()
        .iter()
        .map(|p| format!("(\"{}\", \"{}\")", p[0], p[1]))
        .collect();
    let triangles: Vec<String> = mesh
        .triangles()
        .iter()
        .map(|t| format!("({}, {}, {})", t[0], t[1], t[2]))
        .collect();
    let config = format!(
        "(spline: (mesh: (vertices: [{}], triangles: [{}])), top: \"20\")",
        vertices.join(", "),
        triangles.join(", ")
    );
    let mut source = TerrainSource::default();
    let contribution = source
        .build(&BuildRequest {
            schema: api::SCHEMA_VERSION,
            input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
            name: "t".into(),
            config,
            base_dir: ".".into(),
            system: ConstraintSystem::new(),
            values: Values::default(),
            sources: Vec::new(),
        })
        .expect("valid configuration");
    let mut system = ConstraintSystem::new();
    let mut values = Values::default();
    contribution
        .apply_to(&mut system, &mut values)
        .expect("fresh system");
    (source, system, values)
}

fn z_edit_with<B: LinearBackend>(
    c: &mut Criterion,
    name: &str,
    backend: &B,
    source: &TerrainSource,
    request: &PlanRequest,
) where
    <B::Factorization as Factorization>::Scalar: std::fmt::Debug,
{
    let mut group = c.benchmark_group("terrain-z-edit");
    group.sample_size(20);
    let label = format!("{name}-delta3");
    let spec =
        |plan: &api::OperationPlan| EditSpec::new(plan.anchors.clone(), plan.derived.clone());
    group.bench_function(BenchmarkId::new("select+initialize", &label), |b| {
        b.iter(|| {
            let plan = source.plan(request).expect("plan");
            black_box(
                Edit::initialize(backend, &request.system, &request.values, &spec(&plan)).is_ok(),
            )
        })
    });
    let plan = source.plan(request).expect("plan");
    let edit = Edit::initialize(backend, &request.system, &request.values, &spec(&plan))
        .expect("initialize");
    let step = &plan.steps[0];
    edit.update(&step.anchors, &step.hints)
        .expect("strongly solvable");
    let report = edit.report();
    eprintln!(
        "{label}: 1 anchor, {} derived points, {} equations, rank {}",
        plan.derived.len(),
        report.equations,
        report.rank
    );
    group.bench_function(BenchmarkId::new("update", &label), |b| {
        b.iter(|| black_box(edit.update(&step.anchors, &step.hints).is_ok()))
    });
    group.finish();
}

fn z_edit(c: &mut Criterion) {
    let (source, system, values) = terrain_source();
    // The top surface's control point at the middle vertex of the grid.
    let middle = (GRID / 2) * (GRID + 1) + GRID / 2;
    let request = PlanRequest {
        schema: api::SCHEMA_VERSION,
        operation: format!(r#"(mode: "z1", anchors: ["v{middle}"], neighborhood: 3, dz: "7/2")"#),
        system,
        values,
    };
    z_edit_with(c, "exact", &ExactLdu::default(), &source, &request);
    z_edit_with(c, "float", &FloatQr::default(), &source, &request);
}

criterion_group!(benches, psi, z_edit);
criterion_main!(benches);
