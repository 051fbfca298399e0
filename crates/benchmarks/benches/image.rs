//! Deforming a 1 000 × 1 000-pixel image with a spline deformation (`spline2d::image`): over
//! the 968-triangle benchmark mesh (a perturbed 22 × 22 grid of 20-unit cells, 440 × 440
//! units, 0.44 unit per pixel), degree 5, with (a) one soft translation at δ_max = 3 (a local
//! edit: most triangles not displaced) and (b) every control point displaced by a smooth swirl
//! (every triangle displaced: the worst case). One core.
//!
//! `cargo bench -p benchmarks --bench image`

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

use api::Rational;
use benchmarks::perturbed_grid;
use criterion::{criterion_group, criterion_main, Criterion};
use spline2d::eval::FloatSpline;
use spline2d::image::{deform_image, reference_triangles, Placement, Rgba};
use spline2d::spline::Spline;
use std::hint::black_box;

/// A rational close to `x` (a multiple of 2^−20).
fn rational(x: f64) -> Rational {
    Rational::new(((x * 1048576.0).round() as i64).into(), 1048576.into())
}

fn image(c: &mut Criterion) {
    let spline = Spline::new(perturbed_grid(22), 5, 1).expect("valid mesh");
    let nominal: Vec<Vec<Rational>> = spline.nominals().iter().map(|p| p.to_vec()).collect();
    let size = 1000;
    let pixels: Vec<u8> = (0..size * size)
        .flat_map(|k| {
            let (i, j) = (k % size, k / size);
            [
                (i % 256) as u8,
                (j % 256) as u8,
                ((i / 7 + j / 7) % 2 * 255) as u8,
                255,
            ]
        })
        .collect();
    let picture = Rgba {
        width: size,
        height: size,
        pixels,
    };
    let placement = Placement {
        left: 0.0,
        top: 440.0,
        units_per_pixel: 0.44,
    };
    let triangles = reference_triangles(&spline);
    // (a) A local edit: the points within 30 units of the centre pushed by up to 6 units.
    let local: Vec<Vec<Rational>> = nominal
        .iter()
        .map(|p| {
            let (x, y) = (
                api::exact::rational_to_f64(&p[0]),
                api::exact::rational_to_f64(&p[1]),
            );
            let d = (x - 220.0).hypot(y - 220.0);
            let w = (1.0 - d / 30.0).max(0.0);
            vec![&p[0] + rational(6.0 * w * w), &p[1] + rational(4.0 * w * w)]
        })
        .collect();
    // (b) A swirl of every point.
    let swirl: Vec<Vec<Rational>> = nominal
        .iter()
        .map(|p| {
            let (x, y) = (
                api::exact::rational_to_f64(&p[0]),
                api::exact::rational_to_f64(&p[1]),
            );
            let a = 0.3 * (-((x - 220.0).powi(2) + (y - 220.0).powi(2)) / 20000.0).exp();
            let (dx, dy) = (x - 220.0, y - 220.0);
            vec![
                rational(220.0 + dx * a.cos() - dy * a.sin()),
                rational(220.0 + dx * a.sin() + dy * a.cos()),
            ]
        })
        .collect();
    let mut group = c.benchmark_group("image-1000x1000");
    group.sample_size(10);
    for (name, positions) in [("local-edit", &local), ("every-triangle", &swirl)] {
        let float = FloatSpline::new(&spline, positions).expect("float twin");
        group.bench_function(name, |b| {
            b.iter(|| {
                black_box(
                    deform_image(&float, &triangles, &picture, placement, [0; 4])
                        .expect("deformed")
                        .pixels
                        .len(),
                )
            })
        });
    }
    group.finish();
}

criterion_group!(benches, image);
criterion_main!(benches);
