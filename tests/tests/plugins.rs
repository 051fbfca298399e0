//! New constraint types as external plugins, end to end: the bundled `c2` and `align` example
//! runs through the real binary with the plugins loaded from their dynamic libraries, and a
//! plugin of another ABI version refused with both versions named; the editor's views of the
//! spline2d and terrain plugin libraries equal the built-in sources' ones.

mod common;

use common::{ecles, expect_bad_input, library, read_report, root, stderr, temp};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Output;

/// Runs the bundled example `examples/{name}.ron` with its plugin libraries taken from this
/// test's build (the example names `../target/release/<stem>`; the copy names the library
/// built for this test's profile). Meshes and models are read from the examples directory.
fn run_example(name: &str, stems: &[&str]) -> (tempfile::TempDir, Output, PathBuf) {
    let examples = root().join("examples");
    let mut text =
        std::fs::read_to_string(examples.join(format!("{name}.ron"))).expect("bundled example");
    for stem in stems {
        let written = format!("\"../target/release/{stem}\"");
        assert!(text.contains(&written), "{name}.ron loads {stem}");
        text = text.replace(
            &written,
            &format!("{:?}", library(stem).display().to_string()),
        );
    }
    for dir in ["meshes", "models"] {
        let absolute = format!("\"{}/", examples.join(dir).display());
        text = text.replace(&format!("\"{dir}/"), &absolute);
    }
    let dir = temp();
    let run = dir.path().join(format!("{name}.ron"));
    std::fs::write(&run, text).expect("write run file");
    let out = dir.path().join("out");
    let o = ecles(&[
        "run",
        &run.display().to_string(),
        "--quiet",
        "--out",
        &out.display().to_string(),
    ]);
    (dir, o, out)
}

/// The exact values of every parameter an edit changed, the later edit winning.
fn final_values(report: &Value) -> BTreeMap<String, Vec<String>> {
    let mut values = BTreeMap::new();
    for edit in report["edits"].as_array().expect("edits") {
        for v in edit["values"].as_array().expect("values") {
            let exact = v["exact"]
                .as_array()
                .expect("exact coordinates")
                .iter()
                .map(|c| c.as_str().expect("rational text").to_string())
                .collect();
            values.insert(v["name"].as_str().expect("name").to_string(), exact);
        }
    }
    values
}

fn labels(list: &Value) -> Vec<String> {
    list.as_array()
        .expect("labels")
        .iter()
        .map(|l| l.as_str().expect("label").to_string())
        .collect()
}

#[test]
fn the_c2_plugin_makes_the_worm_c2_and_its_edits_keep_every_condition() {
    let (_dir, o, out) = run_example("c2", &["plugins_c2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report = read_report(&out);
    let c2 = &report["sources"][1];
    assert_eq!(c2["plugin"], "c2");
    assert!(c2["loaded_from"].is_string(), "{c2}");
    // Degree 9 on the worm (6 triangles in a strip, 5 interior edges, no interior vertex):
    // dim S^2_9 = C(11, 2) + 5·C(8, 2) = 55 + 140 = 195 (Schumaker), and the system has one
    // independent row per coordinate per lost degree of freedom.
    let points = report["sources"][0]["counts"]["control_points"]
        .as_u64()
        .expect("count");
    assert_eq!(points, 280);
    assert_eq!(c2["counts"]["conditions"], 5 * 8);
    assert_eq!(report["rank"], 2 * (points - 195));
    assert_eq!(report["redundant"].as_array().map(Vec::len), Some(0));
    for edit in report["edits"].as_array().expect("edits") {
        assert_eq!(edit["solvable"], true, "{edit}");
        assert_eq!(edit["max_residual"], "0");
        assert_eq!(edit["float_agrees"], true, "{edit}");
        assert!(
            edit["rank"].as_u64() > Some(0),
            "the C2 rows take part: {edit}"
        );
    }
    assert!(out.join("c2-worm.svg").is_file());
    assert!(out.join("worm-model-deformed.obj").is_file());
}

#[test]
fn an_alignment_that_over_constrains_the_spline_is_named_and_edits_breaking_it_are_refused() {
    let (_dir, o, out) = run_example("align", &["plugins_align"]);
    // One edit is refused on purpose: exit status 1, report still written.
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let report = read_report(&out);
    assert_eq!(report["consistent"], true);

    // The pinned bump: four pinned points and the C1 condition tying them — structurally
    // over-determined (10 rows on 8 coordinates), with labels from both plugins.
    let over = &report["structure"]["over"];
    assert_eq!(
        (over["rows"].as_u64(), over["columns"].as_u64()),
        (Some(10), Some(8))
    );
    let over_rows = labels(&over["row_labels"]);
    assert!(
        over_rows.contains(&"worm row 1: C1 edge 1-2 #0[0]".to_string()),
        "{over_rows:?}"
    );
    assert!(
        over_rows.contains(&"align row 5: worm.v1 x = 12".to_string()),
        "{over_rows:?}"
    );
    // ... and exactly: one redundant row per coordinate, each an exact combination of rows of
    // both sources.
    let redundant = report["redundant"].as_array().expect("redundant rows");
    assert_eq!(redundant.len(), 2);
    for r in redundant {
        let rows: Vec<&str> = r["combination"]
            .as_array()
            .expect("combination")
            .iter()
            .map(|t| t["row"].as_str().expect("row label"))
            .chain([r["row"].as_str().expect("row label")])
            .collect();
        assert!(
            rows.iter()
                .any(|l| l.starts_with("worm row ") && l.contains(": C1 edge")),
            "{rows:?}"
        );
        assert!(rows.iter().any(|l| l.starts_with("align row ")), "{rows:?}");
    }

    let edits = report["edits"].as_array().expect("edits");
    for edit in &edits[..2] {
        assert_eq!(edit["solvable"], true, "{edit}");
        assert_eq!(edit["max_residual"], "0");
    }
    let refused = &edits[2];
    assert_eq!(refused["solvable"], false);
    let message = refused["error"].as_str().expect("reason");
    assert!(message.contains("align row 5: worm.v1 x = 12"), "{message}");

    // Every alignment holds exactly after the edits.
    let values = final_values(&report);
    let at = |name: &str, initial: [&str; 2]| -> Vec<String> {
        values
            .get(name)
            .cloned()
            .unwrap_or_else(|| initial.iter().map(|c| c.to_string()).collect())
    };
    let (v0, v4) = (at("worm.v0", ["0", "0"]), at("worm.v4", ["48", "0"]));
    assert_eq!(v0[1], v4[1], "SameY(v0, v4)");
    let (v5, v7) = (at("worm.v5", ["60", "11"]), at("worm.v7", ["84", "11"]));
    assert_ne!(v7, ["84", "11"], "the tail moved");
    assert_eq!(v5[1], v7[1], "Offset(v7, v5, (24, 0)) in y");
    assert_eq!(at("worm.v1", ["12", "17"]), ["12", "17"], "Fixed(v1)");
    assert!(out.join("align-worm.svg").is_file());
}

#[test]
fn a_plugin_of_another_abi_version_is_refused_naming_both_versions() {
    // A library whose probe answers ABI version 999 (its entry aborts if ever called).
    let dir = temp();
    let library = common::compile_fixture(
        dir.path(),
        "fake_plugin.rs",
        "fake_old_abi",
        Some("variant=\"old_abi\""),
    );
    let expected = format!("version {}", plugin_abi::abi::ABI_VERSION);
    expect_bad_input(
        &format!(
            r#"(sources: [(name: "old", plugin: {:?}, config: ())])"#,
            library.display().to_string()
        ),
        &["version 999", &expected, &library.display().to_string()],
    );
    // `ecles plugins --path` says the same.
    let o = ecles(&["plugins", "--path", &library.display().to_string()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("version 999"), "{}", stderr(&o));
}

#[test]
fn a_missing_plugin_library_is_named() {
    let missing: &Path = Path::new("no/such/plugins_c2");
    expect_bad_input(
        &format!(
            r#"(sources: [(name: "c", plugin: {:?}, config: ())])"#,
            missing
        ),
        &[&plugin_abi::library_file_name("plugins_c2"), "not found"],
    );
}

/// The view of source `name` built from `config` (base directory `examples/`), asked with
/// `outputs`, from the plugin library `library` and from the built-in source `fixed`: both
/// pass the conformance check of views and are equal, floats included (they cross the
/// boundary bit for bit). Returns the view.
fn view_across_the_boundary(
    library_name: &str,
    mut fixed: impl api::ConstraintSource,
    name: &str,
    config: &str,
    outputs: &[String],
) -> api::SourceView {
    use api::{ConstraintSource, ConstraintSystem, Values};
    let request = api::BuildRequest {
        schema: api::SCHEMA_VERSION,
        input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
        name: name.into(),
        config: config.into(),
        base_dir: root().join("examples"),
        system: ConstraintSystem::new(),
        values: Values::default(),
        sources: Vec::new(),
    };
    let plugin = plugin_abi::load(&library(library_name)).expect("loads");
    let mut dynamic = plugin.instantiate();
    let contribution = dynamic.build(&request).expect("dynamic build");
    fixed.build(&request).expect("static build");
    let mut system = ConstraintSystem::new();
    let mut values = Values::default();
    contribution
        .apply_to(&mut system, &mut values)
        .expect("applies");
    let view = conformance::check_view(&dynamic, name, &system, outputs)
        .expect("a conforming view")
        .expect("the source draws");
    assert_eq!(
        Some(view.clone()),
        conformance::check_view(&fixed, name, &system, outputs).expect("static view")
    );
    view
}

/// The editor's view of the worm (method 6 of the plugin ABI), with the model the output of
/// examples/worm.ron deforms, is the same from the spline2d plugin library as from the
/// built-in source, and passes the conformance check of views (no models without outputs,
/// outputs change only the models, the host's validation).
#[test]
fn the_spline_view_crosses_the_plugin_boundary_unchanged() {
    use api::SourceView;
    // The output of examples/worm.ron, as written there.
    let run = std::fs::read_to_string(root().join("examples/worm.ron")).expect("worm.ron");
    let output = r#"(picture: "worm.svg", model: "models/worm-model.obj")"#;
    assert!(run.contains(output), "examples/worm.ron names its model");
    let view = view_across_the_boundary(
        "plugins_spline2d_dylib",
        plugins_spline2d::plugin::Spline2dSource::default(),
        "worm",
        r#"(mesh: "meshes/worm.obj", degree: 5, smoothness: 1)"#,
        &[output.to_string()],
    );
    let SourceView::BezierTriangles(view) = view else {
        panic!("spline2d draws Bézier triangles")
    };
    // The worm: 6 triangles, degree 5 (21 control points each), and its model.
    assert_eq!((view.triangles.len(), view.degree), (6, 5));
    assert!(view.patches.iter().all(|p| p.len() == 21));
    assert_eq!(view.models.len(), 1);
    let model = &view.models[0];
    assert_eq!(model.name, "models/worm-model.obj");
    assert_eq!((model.vertices.len(), model.faces.len()), (341, 600));
    assert!(model.embedding.iter().filter(|e| e.is_some()).count() > 300);
}

/// The editor's view of the terrain (a prism view), with the models the outputs of
/// examples/terrain.ron deform, is the same from the terrain plugin library as from the
/// built-in source, and passes the conformance check of views.
#[test]
fn the_terrain_view_crosses_the_plugin_boundary_unchanged() {
    use api::SourceView;
    // The source and outputs of examples/terrain.ron, as written there.
    let run = std::fs::read_to_string(root().join("examples/terrain.ron")).expect("terrain.ron");
    let outputs: Vec<String> = [
        r#"(model: "terrains/hills.asc", picture: "hills.png")"#,
        r#"(model: "terrains/tower.obj")"#,
    ]
    .map(String::from)
    .to_vec();
    for output in &outputs {
        assert!(
            run.contains(output.as_str()),
            "examples/terrain.ron has {output}"
        );
    }
    assert!(run.contains(r#"spline: (mesh: "terrains/reference.obj", degree: 5, smoothness: 1),"#));
    let view = view_across_the_boundary(
        "plugins_terrain_dylib",
        plugins_terrain::plugin::TerrainSource::default(),
        "terrain",
        r#"(spline: (mesh: "terrains/reference.obj", degree: 5, smoothness: 1),
            top: "20", xy: true)"#,
        &outputs,
    );
    let SourceView::Prisms(view) = view else {
        panic!("the terrain draws prisms")
    };
    // The reference mesh of 8 triangles, degree 5 (21 control points per patch and surface),
    // φ edited, the layer between -20 and 20, and the two models.
    assert_eq!((view.triangles.len(), view.degree), (8, 5));
    let xy = view.xy.as_ref().expect("xy: true");
    assert!([&view.bottom, &view.top, xy]
        .iter()
        .all(|surface| surface.len() == 8 && surface.iter().all(|p| p.len() == 21)));
    let q = |n: i64| api::Rational::from_integer(n.into());
    assert_eq!((view.reference_bottom, view.reference_top), (q(-20), q(20)));
    let names: Vec<&str> = view.models.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["terrains/hills.asc", "terrains/tower.obj"]);
    let hills = &view.models[0];
    assert_eq!(
        (hills.vertices.len(), hills.faces.len()),
        (33 * 33, 2 * 32 * 32)
    );
    assert_eq!(hills.relative_height.len(), hills.vertices.len());
    assert!(hills.embedding.iter().all(Option::is_some));
}
