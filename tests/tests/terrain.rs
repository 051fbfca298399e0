//! End-to-end tests of the `terrain` source through the real `ecles` binary: the bundled
//! terrain example (report section, pictures, deformed models, determinism), the dynamic plugin
//! library against the built-in source, and malformed terrain inputs.

mod common;

use common::{ecles, expect_bad_input, read_report, root, run_file, stderr, temp, without_origin};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The terrain plugin library (built with the binary by the shared helper).
fn terrain_library() -> PathBuf {
    common::library("plugins_terrain_dylib")
}

fn run(run_file: &Path, out: &Path) {
    let o = ecles(&[
        "run",
        &run_file.display().to_string(),
        "--quiet",
        "--out",
        &out.display().to_string(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

fn lines_starting(text: &str, prefix: &str) -> usize {
    text.lines().filter(|l| l.starts_with(prefix)).count()
}

#[test]
fn the_bundled_terrain_example_raises_a_hill_and_shifts_a_ridge() {
    let (a, b) = (temp(), temp());
    let example = root().join("examples/terrain.ron");
    run(&example, a.path());
    run(&example, b.path());
    let report = read_report(a.path());
    let source = &report["sources"][0];
    assert_eq!(source["plugin"], "terrain");
    let counts = &source["counts"];
    for (key, value) in [
        ("vertices", 9),
        ("triangles", 8),
        ("surfaces", 3),
        ("control_points_per_surface", 121),
        ("conditions_per_surface", 40),
    ] {
        assert_eq!(counts[key], value, "{key}");
    }
    // 121 + 121 scalar and 121 planar control points; 40 rows per surface.
    assert_eq!(source["parameters"], 363);
    assert_eq!(source["rows"], 120);
    assert_eq!(report["consistent"], Value::Bool(true));
    let edits = report["edits"].as_array().expect("edits");
    assert_eq!(edits.len(), 2);
    for edit in edits {
        assert_eq!(edit["solvable"], Value::Bool(true), "{edit}");
        assert_eq!(edit["max_residual"], "0");
        assert_eq!(edit["float_agrees"], Value::Bool(true), "{edit}");
        assert!(edit["plan"]["initial_derived"]
            .as_u64()
            .is_some_and(|n| n > 0));
    }
    // The hill edit moves the top surface, the ridge edit phi.
    let names = |edit: &Value| -> Vec<String> {
        edit["anchors"]
            .as_array()
            .expect("anchors")
            .iter()
            .map(|a| a.as_str().unwrap_or_default().to_string())
            .collect()
    };
    assert_eq!(names(&edits[0]), ["terrain.top.v4"]);
    assert_eq!(names(&edits[1]), ["terrain.xy.e4-5:2", "terrain.xy.e4-5:3"]);
    let files = [
        "hills-deformed.obj",
        "hills-deformed.asc",
        "hills-before.png",
        "hills-after.png",
        "tower-deformed.obj",
    ];
    assert_eq!(report["outputs"], serde_json::json!(files));
    for file in files {
        let bytes = std::fs::read(a.path().join(file)).expect(file);
        assert_eq!(
            bytes,
            std::fs::read(b.path().join(file)).expect(file),
            "{file} differs between runs"
        );
        if file.ends_with(".png") {
            assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"), "{file}");
        }
    }
    assert_eq!(
        std::fs::read(a.path().join("report.json")).expect("report"),
        std::fs::read(b.path().join("report.json")).expect("report")
    );
    // The terrain keeps its topology (thesis Table 19.2: 1 089 vertices, 2 048 triangles), every
    // vertex lies inside the prisms, and the hill rose.
    let obj = std::fs::read_to_string(a.path().join("hills-deformed.obj")).expect("obj");
    assert_eq!(lines_starting(&obj, "v "), 1089);
    assert_eq!(lines_starting(&obj, "f "), 2048);
    assert!(!obj.contains("left in place"), "{}", &obj[..200]);
    let highest = |text: &str| {
        text.lines()
            .filter_map(|l| l.strip_prefix("v "))
            .filter_map(|l| l.split_whitespace().nth(2)?.parse::<f64>().ok())
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let original =
        std::fs::read_to_string(root().join("examples/terrains/hills.asc")).expect("asc");
    let original_top = original
        .lines()
        .skip(6)
        .flat_map(str::split_whitespace)
        .filter_map(|v| v.parse::<f64>().ok())
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(
        highest(&obj) > original_top + 5.0,
        "{} vs {original_top}",
        highest(&obj)
    );
    let tower = std::fs::read_to_string(a.path().join("tower-deformed.obj")).expect("tower");
    assert_eq!(
        (lines_starting(&tower, "v "), lines_starting(&tower, "f ")),
        (8, 12)
    );
}

#[test]
fn the_terrain_plugin_library_gives_the_same_results_as_the_builtin() {
    let library = terrain_library().display().to_string();
    let terrains = root().join("examples/terrains");
    let mesh = terrains.join("reference.obj").display().to_string();
    let hills = terrains.join("hills.asc").display().to_string();
    let results = ["terrain", library.as_str()].map(|plugin| {
        let text = format!(
            r#"(
                sources: [(name: "t", plugin: {plugin:?}, config: (spline: (mesh: {mesh:?}), top: "20", xy: true))],
                edits: [
                    Source(source: "t", operation: (mode: "z0", anchors: ["v4"], neighborhood: 2, dz: "-3")),
                    Source(source: "t", operation: (mode: "xy", anchors: ["v4"], neighborhood: 2, translate: ("2", "1"))),
                ],
                outputs: [(source: "t", output: (model: {hills:?}, picture: "h.png", size: 96))],
            )"#
        );
        let (dir, path, out) = run_file(&text);
        run(&path, &out);
        let png = std::fs::read(out.join("h-after.png")).expect("picture");
        (without_origin(read_report(&out)), png, dir)
    });
    assert_eq!(results[0].0, results[1].0);
    assert_eq!(results[0].1, results[1].1);
    assert_eq!(results[0].0["sources"][0]["counts"]["surfaces"], 3);
    let o = ecles(&["plugins", "--path", &library]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("terrain"));
}

#[test]
fn malformed_terrain_inputs_exit_2_with_located_messages() {
    let mesh = root()
        .join("examples/terrains/reference.obj")
        .display()
        .to_string();
    expect_bad_input(
        &format!(
            r#"(sources: [(name: "t", plugin: "terrain", config: (spline: (mesh: {mesh:?}), top: "5", bottom: "5"))])"#
        ),
        &["t config", "the bottom a = 5 must be below the top b = 5"],
    );
    expect_bad_input(
        &format!(
            r#"(sources: [(name: "t", plugin: "terrain", config: (spline: (mesh: {mesh:?}), top: "5", colour: 1))])"#
        ),
        &["t config", "colour"],
    );
    // A height field with a typo in its data: the message names file, line and column.
    let dir = temp();
    let grid = dir.path().join("bad.asc");
    std::fs::write(
        &grid,
        "ncols 2\nnrows 2\nxllcenter 0\nyllcenter 0\ncellsize 40\n1 2\n3 4,5\n",
    )
    .expect("write grid");
    let text = format!(
        r#"(sources: [(name: "t", plugin: "terrain", config: (spline: (mesh: {mesh:?}), top: "5"))],
            outputs: [(source: "t", output: (model: {:?}))])"#,
        grid.display().to_string()
    );
    expect_bad_input(&text, &["t output", "bad.asc:7:4: invalid number \"4,5\""]);
}
