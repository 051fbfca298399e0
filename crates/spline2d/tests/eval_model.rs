//! Evaluating splines (exact and float) and deforming models, from the public API.

use api::exact::rational_to_f64;
use api::{Factorization, IntMatrix, LinearBackend, Rational};
use exact_ldu::ExactLdu;
use spline2d::eval::{evaluate_exact, evaluate_in_triangle, locate_exact, FloatSpline, Locator};
use spline2d::mesh::{Mesh, Point};
use spline2d::mesh_io::{from_points, MeshOptions};
use spline2d::model::{
    deform_model, load_model, parse_model, plane_jacobian, write_obj, Model, ModelError,
};
use spline2d::spline::Spline;
use std::path::PathBuf;
use std::time::Instant;

/// The default input limit.
const LIMIT: u64 = api::input::DEFAULT_MAX_INPUT_BYTES;

fn q(n: i64) -> Rational {
    Rational::from_integer(n.into())
}

fn frac(n: i64, d: i64) -> Rational {
    Rational::new(n.into(), d.into())
}

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("data")
        .join(name)
}

/// `(n+1)²` vertices `cell` apart, interior ones optionally displaced.
fn grid(n: usize, cell: i64, perturb: bool) -> Mesh {
    spline2d::mesh::grid(n, cell, perturb)
}

fn nominal(spline: &Spline) -> Vec<Vec<Rational>> {
    spline.nominals().iter().map(|p| p.to_vec()).collect()
}

fn to_f64(p: &Point) -> [f64; 2] {
    [rational_to_f64(&p[0]), rational_to_f64(&p[1])]
}

/// xorshift64, deterministic.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: i64) -> i64 {
        (self.next() % n as u64) as i64
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The point with barycentric coordinates `beta` in triangle `t`.
fn point_in(mesh: &Mesh, t: usize, beta: &[Rational; 3]) -> Point {
    let mut p = [q(0), q(0)];
    for (v, w) in mesh.triangles()[t].iter().zip(beta) {
        p[0] += &mesh.vertices()[*v][0] * w;
        p[1] += &mesh.vertices()[*v][1] * w;
    }
    p
}

fn random_beta(rng: &mut Rng) -> [Rational; 3] {
    let (a, b) = (rng.below(997), rng.below(997));
    let (a, b) = if a + b > 997 {
        (997 - a, 997 - b)
    } else {
        (a, b)
    };
    [frac(997 - a - b, 997), frac(a, 997), frac(b, 997)]
}

#[test]
fn a_quadratic_on_one_triangle_by_hand() {
    let mesh = from_points(
        vec![[q(0), q(0)], [q(1), q(0)], [q(0), q(1)]],
        vec![[0, 1, 2]],
        &MeshOptions::default(),
    )
    .expect("mesh")
    .mesh;
    let spline = Spline::new(mesh, 2, 0).expect("spline");
    // q200 = 1, q110 = 2, q101 = 3, q020 = 4, q011 = 5, q002 = 6 (scalar spline).
    let mut positions = vec![Vec::new(); spline.points().len()];
    for (idx, value) in [
        ([2, 0, 0], 1),
        ([1, 1, 0], 2),
        ([1, 0, 1], 3),
        ([0, 2, 0], 4),
        ([0, 1, 1], 5),
        ([0, 0, 2], 6),
    ] {
        positions[spline.triangle_points(0)[spline.local_index(idx)]] = vec![q(value)];
    }
    // β = (1/2, 1/4, 1/4), p = (1/4, 1/4):
    // 1·1/4 + 2·2·1/8 + 2·3·1/8 + 4·1/16 + 2·5·1/16 + 6·1/16 = 11/4.
    let p = [frac(1, 4), frac(1, 4)];
    assert_eq!(
        evaluate_exact(&spline, &positions, &p),
        Some(vec![frac(11, 4)])
    );
    // Edge midpoint of (1,0)-(0,1): β = (0, 1/2, 1/2): 4/4 + 2·5/4 + 6/4 = 5.
    assert_eq!(
        evaluate_exact(&spline, &positions, &[frac(1, 2), frac(1, 2)]),
        Some(vec![q(5)])
    );
    let float = FloatSpline::new(&spline, &positions).expect("float");
    let locator = Locator::new(spline.mesh());
    let v = float
        .evaluate_point(&locator, [0.25, 0.25])
        .expect("inside");
    assert!((v[0] - 2.75).abs() < 1e-14);
    assert!(evaluate_exact(&spline, &positions, &[frac(3, 4), frac(1, 2)]).is_none());
    assert!(float.evaluate_point(&locator, [0.75, 0.5]).is_none());
    assert!(float.evaluate_point(&locator, [-0.01, 0.5]).is_none());
}

#[test]
fn identity_and_corners() {
    let spline = Spline::new(grid(3, 10, true), 4, 1).expect("spline");
    let mesh = spline.mesh();
    let identity = nominal(&spline);
    let float = FloatSpline::new(&spline, &identity).expect("float");
    let locator = Locator::new(mesh);
    let mut rng = Rng(7);
    for t in 0..mesh.triangles().len() {
        let p = point_in(mesh, t, &random_beta(&mut rng));
        assert_eq!(evaluate_exact(&spline, &identity, &p), Some(p.to_vec()));
        let pf = to_f64(&p);
        let v = float.evaluate_point(&locator, pf).expect("inside");
        assert!((v[0] - pf[0]).abs() < 1e-12 && (v[1] - pf[1]).abs() < 1e-12);
    }
    // Every mesh vertex (corner control point), found by the locator too.
    let moved: Vec<Vec<Rational>> = identity
        .iter()
        .enumerate()
        .map(|(i, p)| vec![&p[0] + frac(i as i64 % 7, 3), &p[1] - q(i as i64 % 5)])
        .collect();
    let float = FloatSpline::new(&spline, &moved).expect("float");
    for (v, p) in mesh.vertices().iter().enumerate() {
        let point = spline
            .points()
            .iter()
            .position(|c| c.name == format!("v{v}"))
            .expect("corner point");
        assert_eq!(
            evaluate_exact(&spline, &moved, p),
            Some(moved[point].clone())
        );
        let f = float
            .evaluate_point(&locator, to_f64(p))
            .expect("corner found");
        let e: Vec<f64> = moved[point].iter().map(rational_to_f64).collect();
        assert!((f[0] - e[0]).abs() < 1e-12 && (f[1] - e[1]).abs() < 1e-12);
    }
}

/// Blossom of the quadratic map `P_c(p) = pᵀ A_c p + b_c · p` (`d ≥ 2`) at the multiset of
/// `d` points: `[Sᵀ A S − Σ uᵀ A u] / (d(d−1)) + b · S / d` with `S = Σ u`.
fn blossom(args: &[Point], a: &[[Rational; 3]; 2], b: &[[Rational; 2]; 2]) -> Vec<Rational> {
    let d = Rational::from_integer(args.len().into());
    let quad = |u: &Point, v: &Point, m: &[Rational; 3]| -> Rational {
        // m = (a11, a12, a22), symmetric.
        &m[0] * &u[0] * &v[0] + &m[1] * (&u[0] * &v[1] + &u[1] * &v[0]) + &m[2] * &u[1] * &v[1]
    };
    let mut s = [q(0), q(0)];
    for u in args {
        s[0] += &u[0];
        s[1] += &u[1];
    }
    (0..2)
        .map(|c| {
            let diag: Rational = args.iter().map(|u| quad(u, u, &a[c])).sum();
            (quad(&s, &s, &a[c]) - diag) / (&d * (&d - q(1)))
                + (&b[c][0] * &s[0] + &b[c][1] * &s[1]) / &d
        })
        .collect()
}

#[test]
fn a_global_quadratic_map_is_reproduced_exactly() {
    let spline = Spline::new(grid(3, 10, true), 3, 2).expect("spline");
    let mesh = spline.mesh();
    let a = [
        [frac(1, 30), frac(-1, 50), q(0)],
        [q(0), frac(1, 40), frac(1, 20)],
    ];
    let b = [[q(1), frac(1, 5)], [frac(-1, 7), q(1)]];
    let mut positions = vec![Vec::new(); spline.points().len()];
    for (t, tri) in mesh.triangles().iter().enumerate() {
        for idx in spline2d::spline::multi_indices(3) {
            let mut args = Vec::new();
            for (v, count) in tri.iter().zip(idx) {
                args.extend(std::iter::repeat_n(mesh.vertices()[*v].clone(), count));
            }
            positions[spline.triangle_points(t)[spline.local_index(idx)]] = blossom(&args, &a, &b);
        }
    }
    // Positions from one global polynomial satisfy every C^r condition exactly.
    for c in spline.conditions() {
        for coord in [0, 1] {
            let sum: Rational = c
                .terms
                .iter()
                .map(|(p, v)| Rational::from_integer(v.clone()) * &positions[*p][coord])
                .sum();
            assert_eq!(sum, q(0), "{}", c.label);
        }
    }
    let mut rng = Rng(99);
    for t in 0..mesh.triangles().len() {
        let p = point_in(mesh, t, &random_beta(&mut rng));
        let expected = blossom(&[p.clone(), p.clone()], &a, &b);
        assert_eq!(evaluate_exact(&spline, &positions, &p), Some(expected));
    }
}

/// Positions of a random `C^1` spline: integer combinations of the null space of the
/// condition matrix, one per coordinate.
fn random_smooth(spline: &Spline, rng: &mut Rng) -> Vec<Vec<Rational>> {
    let rows = spline
        .conditions()
        .iter()
        .map(|c| c.terms.clone())
        .collect();
    let matrix = IntMatrix::from_sparse(spline.points().len(), rows).expect("matrix");
    let basis = ExactLdu::default()
        .factor(&matrix)
        .expect("factor")
        .null_space();
    let mut positions = vec![vec![q(0), q(0)]; spline.points().len()];
    for coord in 0..2 {
        for v in &basis {
            let w = q(rng.below(21) - 10);
            for (p, x) in positions.iter_mut().zip(v) {
                p[coord] += &w * x;
            }
        }
    }
    positions
}

/// Largest jump of the derivative across interior edges (normal direction, second-order
/// one-sided differences) and of the value, relative to the derivative's size.
fn jumps(spline: &Spline, float: &FloatSpline, locator: &Locator) -> (f64, f64) {
    let mesh = spline.mesh();
    let verts: Vec<[f64; 2]> = mesh.vertices().iter().map(to_f64).collect();
    let (mut value_jump, mut slope_jump) = (0.0f64, 0.0f64);
    for e in &spline.topology().edges {
        let [(tu, ku), (tv, _)] = match e.faces.as_slice() {
            [x, y] => [*x, *y],
            _ => continue,
        };
        let opposite = verts[mesh.triangles()[tu][ku]];
        for s in [0.3, 0.5, 0.8] {
            let m = [
                (1.0 - s) * verts[e.a][0] + s * verts[e.b][0],
                (1.0 - s) * verts[e.a][1] + s * verts[e.b][1],
            ];
            let n = [opposite[0] - m[0], opposite[1] - m[1]];
            // Truncation error ∝ h² (checked: 1e-1, 1e-3, 1e-5, 1e-7 relative for h = 1e-2 … 1e-5
            // on the C1 spline below); rounding is still far below at 1e-5.
            let h = 1e-5;
            let f = |t: usize, k: f64| -> Vec<f64> {
                let p = [m[0] + k * h * n[0], m[1] + k * h * n[1]];
                let beta = locator.barycentric(t, p).expect("triangle");
                float.evaluate(t, beta).expect("triangle")
            };
            let (u0, u1, u2) = (f(tu, 0.0), f(tu, 1.0), f(tu, 2.0));
            let (v0, v1, v2) = (f(tv, 0.0), f(tv, -1.0), f(tv, -2.0));
            for c in 0..2 {
                let du = (-3.0 * u0[c] + 4.0 * u1[c] - u2[c]) / (2.0 * h);
                let dv = (3.0 * v0[c] - 4.0 * v1[c] + v2[c]) / (2.0 * h);
                let scale = du.abs().max(dv.abs()).max(1.0);
                slope_jump = slope_jump.max((du - dv).abs() / scale);
                value_jump = value_jump.max((u0[c] - v0[c]).abs() / scale);
            }
        }
    }
    (value_jump, slope_jump)
}

#[test]
fn a_c1_spline_is_smooth_across_edges() {
    let spline = Spline::new(grid(2, 10, true), 5, 1).expect("spline");
    let locator = Locator::new(spline.mesh());
    let mut rng = Rng(2024);
    let smooth = random_smooth(&spline, &mut rng);
    let float = FloatSpline::new(&spline, &smooth).expect("float");
    let (value, slope) = jumps(&spline, &float, &locator);
    assert!(value < 1e-12, "value jump {value}");
    assert!(slope < 1e-5, "slope jump {slope}");
    // The same check does see the kink of a spline that is only C0.
    let rough: Vec<Vec<Rational>> = nominal(&spline)
        .into_iter()
        .map(|p| {
            vec![
                &p[0] + frac(rng.below(100), 50),
                &p[1] + frac(rng.below(100), 50),
            ]
        })
        .collect();
    let float = FloatSpline::new(&spline, &rough).expect("float");
    let (value, slope) = jumps(&spline, &float, &locator);
    assert!(value < 1e-12, "value jump {value}");
    assert!(slope > 1e-2, "slope jump {slope}");
}

#[test]
fn float_and_exact_agree_on_shared_edges_and_outside() {
    let spline = Spline::new(grid(2, 10, false), 3, 1).expect("spline");
    let positions = nominal(&spline);
    let float = FloatSpline::new(&spline, &positions).expect("float");
    let locator = Locator::new(spline.mesh());
    // On the diagonal shared by triangles 0 and 1: exact picks 0.
    let p = [q(5), q(5)];
    let (t, _) = locate_exact(spline.mesh(), &p).expect("inside");
    assert_eq!(t, 0);
    let v = float.evaluate_point(&locator, [5.0, 5.0]).expect("inside");
    assert!((v[0] - 5.0).abs() < 1e-12);
    // Just outside, beyond tolerance.
    for p in [
        [-1e-6, 5.0],
        [20.0 + 1e-6, 5.0],
        [5.0, 21.0],
        [f64::INFINITY, 0.0],
    ] {
        assert!(locator.locate(p).is_none(), "{p:?}");
    }
    // Exactly on the border, and within rounding of it.
    assert!(locator.locate([20.0, 20.0]).is_some());
    assert!(locator.locate([0.1 + 0.2 - 0.3, 7.0]).is_some());
    assert!(evaluate_in_triangle(&spline, &positions, 99, &[q(1), q(0), q(0)]).is_none());
}

#[test]
fn models_load_deform_and_round_trip() {
    let spline = Spline::new(grid(2, 10, true), 3, 1).expect("spline");
    let locator = Locator::new(spline.mesh());
    let identity = FloatSpline::new(&spline, &nominal(&spline)).expect("float");

    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("eval_model");
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("tetra.obj");
    std::fs::write(
        &path,
        "v 1 1 0\nv 19 1 0\nv 10 18 0\nv 10 8 5\nv 30 30 1\nf 1 2 3\nf 1 2 4\nf 2 3 4\nf 3 1 4 5\n",
    )
    .expect("write");
    let model = load_model(&path, LIMIT).expect("load");
    assert_eq!(model.positions.len(), 5);
    assert_eq!(model.triangles.len(), 5);
    let deformed = deform_model(&model, &identity, &locator).expect("deform");
    assert_eq!(deformed.outside, vec![4]);
    for (a, b) in deformed.model.positions.iter().zip(&model.positions) {
        for c in 0..3 {
            assert!((a[c] - b[c]).abs() <= 1e-12 * (1.0 + b[c].abs()));
        }
    }
    assert_eq!(deformed.model.triangles, model.triangles);

    // A real deformation moves x, y and keeps z.
    let moved: Vec<Vec<Rational>> = nominal(&spline)
        .into_iter()
        .map(|p| vec![&p[0] * frac(3, 2) + &p[1] / q(4), &p[1] - q(2)])
        .collect();
    let affine = FloatSpline::new(&spline, &moved).expect("float");
    let deformed = deform_model(&model, &affine, &locator).expect("deform");
    let [x, y, z] = model.positions[3];
    let got = deformed.model.positions[3];
    assert!((got[0] - (1.5 * x + 0.25 * y)).abs() < 1e-12);
    assert!((got[1] - (y - 2.0)).abs() < 1e-12);
    assert_eq!(got[2], z);
    // Its Jacobian is the linear part, everywhere in the mesh; none outside.
    for p in [[1.0, 1.0], [10.0, 8.0], [19.5, 0.5]] {
        let j = plane_jacobian(&affine, &locator, p).expect("inside");
        let want = [[1.5, 0.25, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        for (row, want_row) in j.iter().zip(want) {
            for (got, want) in row.iter().zip(want_row) {
                assert!((got - want).abs() < 1e-12, "{j:?} at {p:?}");
            }
        }
    }
    assert!(plane_jacobian(&affine, &locator, [30.0, 30.0]).is_none());

    // Round trip through text and through a file.
    let mut text = Vec::new();
    write_obj(&deformed.model, &mut text).expect("write");
    let out = dir.join("tetra_deformed.obj");
    std::fs::write(&out, &text).expect("write file");
    assert_eq!(load_model(&out, LIMIT).expect("reload"), deformed.model);
    let mut again = Vec::new();
    write_obj(&load_model(&out, LIMIT).expect("reload"), &mut again).expect("write");
    assert_eq!(text, again);
}

#[test]
fn models_in_2d_and_point_clouds() {
    let spline = Spline::new(grid(2, 10, false), 2, 1).expect("spline");
    let locator = Locator::new(spline.mesh());
    let identity = FloatSpline::new(&spline, &nominal(&spline)).expect("float");
    let quads = load_model(&data("model_2d_quads.obj"), LIMIT).expect("2D model");
    assert_eq!(quads.positions.len(), 6);
    assert!(quads.positions.iter().all(|p| p[2] == 0.0));
    assert_eq!(
        quads.triangles,
        vec![[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]]
    );
    assert!(deform_model(&quads, &identity, &locator)
        .expect("deform")
        .outside
        .is_empty());
    let cloud = load_model(&data("model_point_cloud.obj"), LIMIT).expect("point cloud");
    assert_eq!(cloud.positions.len(), 4);
    assert!(cloud.triangles.is_empty());
    let deformed = deform_model(&cloud, &identity, &locator).expect("deform");
    assert_eq!(deformed.outside, vec![3]);
    assert_eq!(deformed.model.positions[1][2], -2.0);

    let missing = data("no_such_model.obj");
    let e = load_model(&missing, LIMIT).expect_err("missing");
    assert!(matches!(e, ModelError::Input { .. }));
    assert!(e.to_string().contains("no_such_model.obj"), "{e}");
    // Files that are not models are refused, naming the file and the line.
    let e = parse_model("root:x:0:0:root:/root:/bin/bash\n", "/etc/passwd").expect_err("not OBJ");
    assert!(
        e.to_string().starts_with(
            "/etc/passwd:1:1: \"root:x:0:0:root:/root:/bin/bash\" is not an OBJ statement"
        ),
        "{e}"
    );
    let e = parse_model("(sources: [])\n", "run.ron").expect_err("RON");
    assert!(e.to_string().contains("is not an OBJ statement"), "{e}");
    let e = parse_model("# only a comment\ng group\n", "empty.obj").expect_err("empty");
    assert_eq!(
        e.to_string(),
        "empty.obj: the model has no vertices (no `v` lines)"
    );
    #[cfg(unix)]
    {
        let e = load_model(std::path::Path::new("/dev/urandom"), LIMIT).expect_err("device");
        assert_eq!(
            e.to_string(),
            "/dev/urandom: the model must be a regular file, but this is a character device"
        );
    }
    let e = parse_model("v 1 2\nf 1 2 3\n", "broken.obj").expect_err("bad face");
    assert_eq!(
        e.to_string(),
        "broken.obj:2:5: face refers to vertex 2 but the file defines 1"
    );
}

/// Rough speed of the float path on a 968-triangle mesh (printed, not asserted; run with
/// `--release -- --nocapture`).
#[test]
fn float_path_speed() {
    let spline = Spline::new(grid(22, 10, true), 5, 1).expect("spline");
    let mut rng = Rng(31337);
    let positions: Vec<Vec<Rational>> = nominal(&spline)
        .into_iter()
        .map(|p| {
            vec![
                &p[0] + frac(rng.below(20), 10),
                &p[1] - frac(rng.below(20), 10),
            ]
        })
        .collect();
    let start = Instant::now();
    let locator = Locator::new(spline.mesh());
    let float = FloatSpline::new(&spline, &positions).expect("float");
    let build = start.elapsed();
    let count = 1_000_000;
    let points: Vec<[f64; 2]> = (0..count)
        .map(|_| [rng.unit() * 240.0 - 10.0, rng.unit() * 240.0 - 10.0])
        .collect();
    let start = Instant::now();
    let mut found = 0usize;
    for p in &points {
        if let Some((t, beta)) = locator.locate(*p) {
            found += t + (beta[0] > 2.0) as usize;
        }
    }
    let locate = start.elapsed();
    let start = Instant::now();
    let mut out = [0.0; 2];
    let mut sum = 0.0;
    let mut inside = 0;
    for p in &points {
        if float.evaluate_point_into(&locator, *p, &mut out) {
            sum += out[0] + out[1];
            inside += 1;
        }
    }
    let both = start.elapsed();
    let model = Model {
        positions: points.iter().map(|p| [p[0], p[1], 0.0]).collect(),
        triangles: Vec::new(),
    };
    let start = Instant::now();
    let deformed = deform_model(&model, &float, &locator).expect("deform");
    let deform = start.elapsed();
    println!(
        "{} triangles, degree 5: build {:?}; {count} points ({inside} inside): locate {:.1} ns/point, locate + evaluate {:.1} ns/point, deform_model {:?} ({} outside) [checksums {found} {sum:.3}]",
        spline.mesh().triangles().len(),
        build,
        locate.as_nanos() as f64 / count as f64,
        both.as_nanos() as f64 / count as f64,
        deform,
        deformed.outside.len(),
    );
    assert_eq!(inside + deformed.outside.len(), count);
}

/// One rule for both OBJ readers (the exact reference-mesh reader and the model reader): bytes
/// that are not UTF-8 are accepted in comments and refused in numbers, with the line and the
/// column.
#[test]
fn both_obj_readers_take_latin1_comments_and_refuse_it_in_numbers() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("latin1");
    std::fs::create_dir_all(&dir).expect("temp dir");
    let good = dir.join("good.obj");
    std::fs::write(
        &good,
        b"# caf\xe9\nv 0 0\nv 10 0\nv 0 10 # \xe9t\xe9\nf 1 2 3\n",
    )
    .expect("write");
    let bad = dir.join("bad.obj");
    std::fs::write(&bad, b"# caf\xe9\nv 0 0\nv 1\xe9 0\nv 0 10\nf 1 2 3\n").expect("write");
    let options = spline2d::mesh_io::MeshOptions::default();
    assert!(spline2d::mesh_io::read_obj(&good, &options, LIMIT).is_ok());
    assert_eq!(load_model(&good, LIMIT).expect("model").positions.len(), 3);
    let mesh = spline2d::mesh_io::read_obj(&bad, &options, LIMIT).expect_err("mesh");
    let model = load_model(&bad, LIMIT).expect_err("model");
    for e in [mesh.to_string(), model.to_string()] {
        assert!(e.contains("bad.obj:3:4:"), "{e}");
    }
}
