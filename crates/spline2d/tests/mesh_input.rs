//! Reading reference meshes from OBJ files and checking their topology; robustness of the
//! readers on arbitrary input.

use api::Rational;
use proptest::prelude::*;
use spline2d::mesh::twice_area;
use spline2d::mesh_io::{
    from_points, parse_obj, read_obj, MeshError, MeshErrorKind, MeshOptions, MeshRead, MeshWarning,
    OrientationPolicy,
};
use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("data")
        .join(name)
}

fn read(name: &str, options: &MeshOptions) -> MeshRead {
    match read_obj(&data(name), options, api::input::DEFAULT_MAX_INPUT_BYTES) {
        Ok(read) => read,
        Err(e) => panic!("{name}: {e}"),
    }
}

fn q(n: i64, d: i64) -> Rational {
    Rational::new(n.into(), d.into())
}

/// Every triangle counter-clockwise, every edge in one or two triangles.
fn assert_valid(read: &MeshRead) {
    let mesh = &read.mesh;
    for t in mesh.triangles() {
        let v = mesh.vertices();
        assert!(twice_area(&v[t[0]], &v[t[1]], &v[t[2]]) > q(0, 1));
    }
    for e in mesh.topology().edges {
        assert!((1..=2).contains(&e.faces.len()));
    }
}

#[test]
fn square() {
    let read = read("square.obj", &MeshOptions::default());
    assert_valid(&read);
    assert!(read.warnings.is_empty());
    assert_eq!(read.mesh.vertices().len(), 4);
    assert_eq!(read.mesh.triangles(), &[[0, 1, 2], [0, 2, 3]]);
    let topology = read.mesh.topology();
    assert_eq!(topology.edges.len(), 5);
    assert_eq!(topology.interior_edges(), 1);
    assert_eq!(topology.interior_vertices(), 0);
}

#[test]
fn strip_of_six_triangles() {
    let read = read("strip.obj", &MeshOptions::default());
    assert_valid(&read);
    assert_eq!(read.mesh.vertices().len(), 8);
    assert_eq!(read.mesh.triangles().len(), 6);
    // The last face is clockwise in the file (line 18) and is flipped.
    assert_eq!(
        read.warnings,
        vec![MeshWarning::Flipped {
            triangle: 5,
            line: Some(18)
        }]
    );
    let topology = read.mesh.topology();
    assert_eq!(topology.edges.len(), 13);
    assert_eq!(topology.interior_edges(), 5);
    assert_eq!(topology.interior_vertices(), 0);

    let reject = MeshOptions {
        orientation: OrientationPolicy::Reject,
        ..MeshOptions::default()
    };
    let e = match read_obj(
        &data("strip.obj"),
        &reject,
        api::input::DEFAULT_MAX_INPUT_BYTES,
    ) {
        Ok(_) => panic!("clockwise triangle accepted"),
        Err(e) => e,
    };
    assert!(matches!(e.kind, MeshErrorKind::Clockwise { .. }));
    assert!(e.to_string().ends_with(
        "strip.obj:18: triangle 5 is clockwise (vertices 2, 6, 7); \
         the orientation policy rejects clockwise triangles"
    ));
}

#[test]
fn starfish_wheel_of_ten_triangles() {
    let read = read("starfish.obj", &MeshOptions::default());
    assert_valid(&read);
    assert!(read.warnings.is_empty());
    assert_eq!(read.mesh.vertices().len(), 11);
    assert_eq!(read.mesh.triangles().len(), 10);
    assert_eq!(
        read.mesh.vertices()[2],
        [q(323_607, 1_000_000), q(235_114, 1_000_000)]
    );
    let topology = read.mesh.topology();
    assert_eq!(topology.edges.len(), 20);
    assert_eq!(topology.interior_edges(), 10);
    assert_eq!(topology.interior_vertices(), 1);
    assert!(topology.interior_vertex[0]);
}

#[test]
fn noisy_coordinates_are_exact_unless_snapped() {
    let plain = read("noisy.obj", &MeshOptions::default());
    assert_eq!(
        plain.mesh.vertices()[2][0],
        q(30_000_000_000_000_004, 100_000_000_000_000_000)
    );
    assert_eq!(
        plain.warnings,
        vec![MeshWarning::UnusedVertex {
            vertex: 4,
            line: Some(6)
        }]
    );
    let snapped = read(
        "noisy.obj",
        &MeshOptions {
            snap: Some(q(1, 1000)),
            ..MeshOptions::default()
        },
    );
    assert_eq!(snapped.mesh.vertices()[2], [q(3, 10), q(6, 5)]);
    assert_eq!(snapped.mesh.vertices()[0], [q(1, 10), q(1, 5)]);
}

#[test]
fn missing_file_names_the_file() {
    let e = match read_obj(
        &data("no-such-mesh.obj"),
        &MeshOptions::default(),
        api::input::DEFAULT_MAX_INPUT_BYTES,
    ) {
        Ok(_) => panic!("missing file read"),
        Err(e) => e,
    };
    assert!(matches!(e.kind, MeshErrorKind::Io(_)));
    assert!(e.source.ends_with("no-such-mesh.obj"));
}

/// Checks the promises of a successful read; an error must be displayable.
fn check(result: Result<MeshRead, MeshError>) {
    match result {
        Ok(read) => {
            assert_valid(&read);
            for w in &read.warnings {
                assert!(!w.to_string().is_empty());
            }
        }
        Err(e) => assert!(!e.to_string().is_empty()),
    }
}

fn token() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("v".to_string()),
        Just("f".to_string()),
        Just("vn".to_string()),
        Just("#".to_string()),
        Just("\n".to_string()),
        Just("\n".to_string()),
        Just("/".to_string()),
        Just("//".to_string()),
        (-6i64..8).prop_map(|i| i.to_string()),
        (-6i64..8).prop_map(|i| i.to_string()),
        (-20i64..20, 1i64..5).prop_map(|(n, d)| format!("{n}/{d}")),
        (-20i64..20).prop_map(|n| format!("{}.{}", n / 10, n.rem_euclid(10))),
        "[0-9eE.+-]{1,4}",
        "[ -~]{0,3}",
    ]
}

fn any_options() -> impl Strategy<Value = MeshOptions> {
    (
        prop_oneof![
            Just(None),
            Just(Some(q(1, 2))),
            Just(Some(q(0, 1))),
            Just(Some(q(-1, 3)))
        ],
        any::<bool>(),
    )
        .prop_map(|(snap, reject)| MeshOptions {
            snap,
            orientation: if reject {
                OrientationPolicy::Reject
            } else {
                OrientationPolicy::Fix
            },
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn printable_text_never_panics(text in "[ -~\t\n\r]{0,200}", options in any_options()) {
        check(parse_obj(&text, "fuzz.obj", &options));
    }

    #[test]
    fn obj_token_soup_never_panics(
        tokens in prop::collection::vec(token(), 0..80),
        options in any_options(),
    ) {
        check(parse_obj(&tokens.join(" "), "soup.obj", &options));
    }

    #[test]
    fn structured_obj_never_panics(
        vertices in prop::collection::vec((-3i64..4, -3i64..4), 0..7),
        faces in prop::collection::vec(prop::collection::vec(-8i64..9, 0..6), 0..8),
        options in any_options(),
    ) {
        let mut text = String::new();
        for (x, y) in &vertices {
            text.push_str(&format!("v {x} {y}\n"));
        }
        for face in &faces {
            let corners: Vec<String> = face.iter().map(i64::to_string).collect();
            text.push_str(&format!("f {}\n", corners.join(" ")));
        }
        check(parse_obj(&text, "structured.obj", &options));
    }

    #[test]
    fn random_points_never_panic(
        vertices in prop::collection::vec((-3i64..4, -3i64..4), 0..7),
        triangles in prop::collection::vec([0usize..8, 0usize..8, 0usize..8], 0..8),
        options in any_options(),
    ) {
        let points = vertices.iter().map(|&(x, y)| [q(x, 1), q(y, 1)]).collect();
        check(from_points(points, triangles, &options));
    }
}
