//! The c2 source against the spline2d source it builds on: the combined rank is
//! `control points − dim S²_d`, configuration errors are clear, and the conformance checks pass.

use api::{format_rational, ConstraintSystem, IntMatrix, Rational, SourceInfo, Values};
use api::{BuildRequest, ConstraintSource, Integer, RowBody};
use conformance::{self, Samples};
use plugins_c2::*;
use plugins_spline2d::plugin::Spline2dSource;
use spline2d::mesh::{grid, Mesh};
use spline2d::mesh_io::{from_points, MeshOptions};
use spline2d::spline::Spline;
use std::path::PathBuf;

/// The inline `spline2d` configuration of a mesh.
fn spline_config(mesh: &Mesh, degree: usize, smoothness: usize) -> String {
    let vertices: Vec<String> = mesh
        .vertices()
        .iter()
        .map(|[x, y]| format!("({:?}, {:?})", format_rational(x), format_rational(y)))
        .collect();
    let triangles: Vec<String> = mesh
        .triangles()
        .iter()
        .map(|[a, b, c]| format!("({a}, {b}, {c})"))
        .collect();
    format!(
        "(mesh: (vertices: [{}], triangles: [{}]), degree: {degree}, smoothness: {smoothness})",
        vertices.join(", "),
        triangles.join(", ")
    )
}

fn mesh(points: &[(i64, i64)], triangles: &[[usize; 3]]) -> Mesh {
    let vertices = points
        .iter()
        .map(|&(x, y)| {
            [
                Rational::from_integer(x.into()),
                Rational::from_integer(y.into()),
            ]
        })
        .collect();
    from_points(vertices, triangles.to_vec(), &MeshOptions::default())
        .expect("valid mesh")
        .mesh
}

/// A wheel of `n` triangles around the origin, rim radii alternating 100 and 40.
fn wheel(n: usize) -> Mesh {
    let mut points = vec![(0, 0)];
    for k in 0..n {
        let angle = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
        let radius = if k % 2 == 0 { 100.0 } else { 40.0 };
        points.push((
            (radius * angle.cos()).round() as i64,
            (radius * angle.sin()).round() as i64,
        ));
    }
    let triangles: Vec<[usize; 3]> = (0..n).map(|k| [0, 1 + k, 1 + (k + 1) % n]).collect();
    mesh(&points, &triangles)
}

/// The square split by both diagonals: the centre's four edges lie on two lines.
fn cross() -> Mesh {
    mesh(
        &[(0, 0), (20, 0), (20, 20), (0, 20), (10, 10)],
        &[[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]],
    )
}

/// The system after a spline2d source `phi` built from `config`, and the earlier-source list a
/// later source sees.
fn spline_system(config: &str, base_dir: PathBuf) -> (ConstraintSystem, Values, Vec<SourceInfo>) {
    let request = BuildRequest {
        base_dir,
        ..conformance::request("phi", config)
    };
    let contribution = Spline2dSource::default()
        .build(&request)
        .unwrap_or_else(|e| panic!("spline2d builds: {e}"));
    let mut system = ConstraintSystem::new();
    let mut values = Values::default();
    contribution
        .apply_to(&mut system, &mut values)
        .expect("applies");
    let sources = vec![SourceInfo {
        name: "phi".into(),
        kind: "spline2d".into(),
        config: config.into(),
    }];
    (system, values, sources)
}

/// A c2 build request named `smooth` after the spline of `spline_config`.
fn c2_request(spline_config: &str, config: &str) -> BuildRequest {
    let (system, values, sources) = spline_system(spline_config, ".".into());
    BuildRequest {
        system,
        values,
        sources,
        ..conformance::request("smooth", config)
    }
}

/// Rank of the whole system at the parameter level (every row is a vector row of dimension 2).
fn rank(system: &ConstraintSystem) -> usize {
    let rows: Vec<Vec<(usize, Integer)>> = system
        .rows()
        .iter()
        .map(|r| match &r.body {
            RowBody::Vector { terms, .. } => {
                terms.iter().map(|(p, c)| (p.index(), c.clone())).collect()
            }
            RowBody::Scalar { .. } => panic!("only vector rows expected"),
        })
        .collect();
    let zeros = vec![vec![Integer::from(0); rows.len()]];
    let matrix = IntMatrix::from_sparse(system.params().len(), rows).expect("ids in range");
    exact_ldu::sparse::eliminate(&matrix, &zeros, exact_ldu::sparse::Combinations::Skip).rank
}

/// Builds spline2d (C1) + c2 on `mesh` and compares the rank with the dimension formula.
fn check_rank(what: &str, mesh: &Mesh, degree: usize) {
    let spline_config = spline_config(mesh, degree, 1);
    let config = if degree < MIN_DEGREE {
        "(spline: \"phi\", allow_low_degree: true)"
    } else {
        "(spline: \"phi\")"
    };
    let request = c2_request(&spline_config, config);
    let contribution = C2Source::default()
        .build(&request)
        .unwrap_or_else(|e| panic!("{what}: c2 builds: {e}"));
    let mut system = request.system.clone();
    let mut values = request.values.clone();
    contribution
        .apply_to(&mut system, &mut values)
        .expect("applies");
    // The identity deformation is C-infinity: it satisfies every C2 condition.
    assert!(system.violations(&values).is_empty(), "{what}");

    let c2 = Spline::new(mesh.clone(), degree, 2).expect("C2 spline");
    let interior_edges = c2.topology().interior_edges();
    assert_eq!(
        contribution.rows.len(),
        (degree - 1) * interior_edges,
        "{what}: d − 1 order-2 conditions per interior edge"
    );
    let points = c2.points().len();
    assert_eq!(system.params().len(), points, "{what}");
    let dimension = c2.spline_space_dimension();
    assert_eq!(
        rank(&system),
        points - dimension,
        "{what}, degree {degree}: rank of C1 + C2 rows != {points} points − dim S²_d {dimension}"
    );
}

#[test]
fn combined_rank_is_points_minus_the_c2_spline_space_dimension() {
    check_rank("grid", &grid(2, 10, false), 9);
    check_rank("perturbed grid", &grid(3, 10, true), 9);
    check_rank("wheel", &wheel(7), 9);
    check_rank("cross", &cross(), 9);
    check_rank("cross", &cross(), 10);
    // Degree 8 is below local control but the dimension formula still holds.
    check_rank("perturbed grid", &grid(2, 10, true), 8);
}

#[test]
fn rows_are_labelled_and_counted() {
    let request = c2_request(&spline_config(&cross(), 9, 1), "(spline: \"phi\")");
    let c = C2Source::default().build(&request).expect("builds");
    assert!(c.parameters.is_empty());
    assert_eq!(c.rows[0].label, "smooth: phi C2 edge 0-4 #0");
    assert_eq!(c.rows[0].origin.source, "smooth");
    assert_eq!(c.rows[0].origin.item, "phi C2 edge 0-4 #0");
    let count = |key: &str| c.summary.iter().find(|s| s.key == key).map(|s| s.value);
    assert_eq!(count("conditions"), Some(32));
    assert_eq!(count("degree"), Some(9));
    assert_eq!(count("interior_edges"), Some(4));
    assert!(c.warnings.is_empty());
    // The configuration is a struct: anything else is refused with its position.
    let map = BuildRequest {
        config: "{\"spline\": \"phi\"}".into(),
        ..request
    };
    let e = C2Source::default().build(&map).expect_err("map syntax");
    assert!(e.message.starts_with("smooth config: "), "{}", e.message);
    assert_eq!(e.at.map(|p| p.line), Some(1));
}

#[test]
fn the_mesh_path_is_resolved_against_the_run_directory() {
    let examples = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let spline = "(mesh: \"meshes/grid.obj\", degree: 9)";
    let (system, values, sources) = spline_system(spline, examples.clone());
    let request = BuildRequest {
        system,
        values,
        sources,
        base_dir: examples,
        ..conformance::request("smooth", "(spline: \"phi\")")
    };
    let c = C2Source::default().build(&request).expect("builds");
    // The grid has 8 interior edges: 8 order-2 conditions each at degree 9.
    assert_eq!(c.rows.len(), 64);
    let elsewhere = BuildRequest {
        base_dir: "/nonexistent".into(),
        ..request
    };
    let error = C2Source::default().build(&elsewhere).expect_err("no mesh");
    assert!(
        error
            .message
            .starts_with("smooth: reading spline \"phi\": phi: "),
        "{error}"
    );
    assert!(error.message.contains("grid.obj"), "{error}");
}

#[test]
fn low_degrees_and_wrong_sources_are_refused_clearly() {
    let five = spline_config(&cross(), 5, 1);
    let error = C2Source::default()
        .build(&c2_request(&five, "(spline: \"phi\")"))
        .expect_err("degree 5");
    for needle in [
        "smooth: spline \"phi\" has degree 5",
        "d >= 9",
        "d >= 3r + 2 = 8",
        "allow_low_degree",
    ] {
        assert!(error.message.contains(needle), "{needle}: {error}");
    }
    // Allowed on request, with a warning.
    let c = C2Source::default()
        .build(&c2_request(
            &five,
            "(spline: \"phi\", allow_low_degree: true)",
        ))
        .expect("allowed");
    assert_eq!(c.rows.len(), 4 * 4);
    assert!(c.warnings[0].contains("degree 5 < 9"), "{:?}", c.warnings);
    // Degree 2 cannot carry C2 at all.
    let error = C2Source::default()
        .build(&c2_request(
            &spline_config(&cross(), 2, 1),
            "(spline: \"phi\", allow_low_degree: true)",
        ))
        .expect_err("degree 2");
    assert!(error.message.contains("needs degree above 2"), "{error}");
    // A C0 spline.
    let error = C2Source::default()
        .build(&c2_request(
            &spline_config(&cross(), 9, 0),
            "(spline: \"phi\")",
        ))
        .expect_err("C0");
    assert!(error.message.contains("smoothness C0"), "{error}");
    // A C2 spline: the rows are redundant, and the warning says so.
    let c = C2Source::default()
        .build(&c2_request(
            &spline_config(&cross(), 9, 2),
            "(spline: \"phi\")",
        ))
        .expect("C2 spline");
    assert!(
        c.warnings[0].contains("already has smoothness C2"),
        "{:?}",
        c.warnings
    );

    let nine = spline_config(&cross(), 9, 1);
    let error = C2Source::default()
        .build(&c2_request(&nine, "(spline: \"psi\")"))
        .expect_err("unknown source");
    assert!(
        error.message.contains("no source named \"psi\"") && error.message.contains("\"phi\""),
        "{error}"
    );
    let mut request = c2_request(&nine, "(spline: \"phi\")");
    request.sources[0].kind = "linear".into();
    let error = C2Source::default()
        .build(&request)
        .expect_err("not a spline");
    assert!(error.message.contains("is a \"linear\" source"), "{error}");
    // The spline's parameters must be in the system.
    let mut request = c2_request(&nine, "(spline: \"phi\")");
    request.system = ConstraintSystem::new();
    request.values = Values::default();
    let error = C2Source::default().build(&request).expect_err("no points");
    assert!(error.message.contains("no parameter \"phi."), "{error}");
    // Configuration errors name the field.
    let error = C2Source::default()
        .build(&c2_request(&nine, "(spline: \"phi\", allow_low: true)"))
        .expect_err("unknown field");
    assert!(error.message.starts_with("smooth config: "), "{error}");
    assert!(error.message.contains("allow_low"), "{error}");
}

#[test]
fn passes_the_conformance_checks() {
    let nine = spline_config(&wheel(5), 9, 1);
    let good = c2_request(&nine, "(spline: \"phi\")");
    let bad_configs = [
        "(spline: \"psi\")",
        "(spline: 3)",
        "(splines: \"phi\")",
        "(",
        "()",
    ];
    let mut bad: Vec<BuildRequest> = bad_configs
        .iter()
        .map(|config| BuildRequest {
            config: config.to_string(),
            ..good.clone()
        })
        .collect();
    bad.push(c2_request(
        &spline_config(&wheel(5), 6, 1),
        "(spline: \"phi\")",
    ));
    bad.push(BuildRequest {
        sources: vec![],
        ..good.clone()
    });
    let samples = Samples {
        good: vec![
            good,
            c2_request(
                &spline_config(&grid(1, 10, false), 7, 1),
                "(spline: \"phi\", allow_low_degree: true)",
            ),
        ],
        bad,
        operations: vec!["(anchors: [\"v0\"], translate: (\"1\", \"0\"))".into()],
        outputs: vec!["(picture: \"c2.svg\")".into()],
    };
    let contributions = conformance::check_source(&mut || Box::new(C2Source::default()), &samples)
        .unwrap_or_else(|e| panic!("statically linked: {e}"));
    // The same checks on the crate's own dynamic library, loaded through the ABI: identical
    // contributions.
    let path = plugin_abi::library_beside_test("plugins-c2").expect("test executable path");
    let plugin = plugin_abi::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(plugin.kind, KIND);
    let loaded = conformance::check_source(&mut || Box::new(plugin.instantiate()), &samples)
        .unwrap_or_else(|e| panic!("loaded from {}: {e}", path.display()));
    assert_eq!(loaded, contributions);
    assert_eq!(contributions[0].rows.len(), 8 * 5);
}
