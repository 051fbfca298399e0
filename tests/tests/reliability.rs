//! Hostile but realistic input through the real binary, one test per class of failure: every
//! bad input is a clean error (exit 2, a message with the run file's line and column or the
//! item, nothing written) before any work; the environment failing is exit 3 with nothing
//! left behind; standard output closed or full never panics.

mod common;

use common::{ecles, expect_bad_input, read_report, root, stderr, temp};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A temporary directory that sees the bundled meshes, models and terrains (symbolic links),
/// with `text` as `run.ron`; returns the directory, the run file and the output directory.
fn beside_examples(text: &str) -> (tempfile::TempDir, PathBuf, PathBuf) {
    let dir = temp();
    for sub in ["meshes", "models", "terrains"] {
        #[cfg(unix)]
        std::os::unix::fs::symlink(root().join("examples").join(sub), dir.path().join(sub))
            .expect("link");
    }
    let run = dir.path().join("run.ron");
    std::fs::write(&run, text).expect("write run file");
    let out = dir.path().join("out");
    (dir, run, out)
}

/// Runs `ecles run RUN --quiet --out OUT`.
fn run(run: &Path, out: &Path) -> std::process::Output {
    ecles(&[
        "run",
        &run.display().to_string(),
        "--quiet",
        "--out",
        &out.display().to_string(),
    ])
}

/// The bundled worm run file with `from` replaced by `to` (which must occur).
fn worm_with(from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(root().join("examples/worm.ron")).expect("worm.ron");
    assert!(text.contains(from), "{from:?} not in worm.ron");
    text.replacen(from, to, 1)
}

/// The bundled worm run file as it is.
fn worm() -> String {
    std::fs::read_to_string(root().join("examples/worm.ron")).expect("worm.ron")
}

/// Expects exit code 2 with every needle in the message, and nothing written.
fn refused(text: &str, needles: &[&str]) {
    let (_dir, path, out) = beside_examples(text);
    let o = run(&path, &out);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{text}\n{err}");
    assert!(!err.contains("panicked"), "{err}");
    for needle in needles {
        assert!(err.contains(needle), "expected {needle:?} in {err:?}");
    }
    assert!(!out.exists() || std::fs::read_dir(&out).map_or(0, |d| d.count()) == 0);
}

const WORM_SOURCE: &str = r#"(name: "worm", plugin: "spline2d", config: (mesh: "meshes/worm.obj", degree: 5, smoothness: 1))"#;

/// A run file with the worm source and one edit.
fn worm_edit(edit: &str) -> String {
    format!("(\n  sources: [{WORM_SOURCE}],\n  edits: [\n    {edit},\n  ],\n)\n")
}

#[test]
fn sizes_are_bounded_before_anything_is_allocated() {
    for (from, to, needles) in [
        (
            "degree: 5",
            "degree: 1000000000",
            &["run.ron:5:", "degree 1000000000 is above the limit of 40"][..],
        ),
        (
            "degree: 5",
            "degree: 100000",
            &["degree 100000 is above the limit"][..],
        ),
        (
            "steps: 4",
            "steps: 18446744073709551615",
            &[
                "run.ron:9:",
                "steps is 18446744073709551615, but must be between 1 and 100000",
            ][..],
        ),
        (
            "steps: 4",
            "steps: 1000000000",
            &["between 1 and 100000"][..],
        ),
        (
            "neighborhood: 3",
            "neighborhood: 4294967296",
            &["above the limit"][..],
        ),
    ] {
        refused(&worm_with(from, to), needles);
    }
    // Grid dimensions of a height field: huge and overflowing products.
    for header in [
        "ncols 9223372036854775808\nnrows 2\n",
        "ncols 4294967296\nnrows 4294967296\n",
        "ncols 100000\nnrows 100000\n",
    ] {
        let (dir, _, _) = beside_examples("()");
        std::fs::write(
            dir.path().join("big.asc"),
            format!("{header}xllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3 4\n"),
        )
        .expect("grid");
        let text = std::fs::read_to_string(root().join("examples/terrain.ron"))
            .expect("terrain.ron")
            .replace("terrains/hills.asc", "big.asc");
        std::fs::write(dir.path().join("run.ron"), text).expect("run");
        let out = dir.path().join("out");
        let o = run(&dir.path().join("run.ron"), &out);
        assert_eq!(o.status.code(), Some(2), "{header}: {}", stderr(&o));
        assert!(stderr(&o).contains("big.asc"), "{}", stderr(&o));
        assert!(!out.join("report.json").exists());
    }
    // Picture sizes.
    let text = std::fs::read_to_string(root().join("examples/terrain.ron"))
        .expect("terrain.ron")
        .replace(
            "picture: \"hills.png\"",
            "picture: \"hills.png\", size: 4000000000",
        );
    refused(&text, &["picture width must be between 16 and 8192"]);
}

#[test]
fn special_files_are_refused_without_reading_them() {
    // A run file that is a device or a directory.
    for path in ["/dev/zero", "/dev/urandom", "/tmp"] {
        let o = ecles(&[
            "run",
            path,
            "--quiet",
            "--out",
            &temp().path().display().to_string(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{path}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("must be a regular file"),
            "{}",
            stderr(&o)
        );
    }
    // Devices as mesh and model.
    refused(
        &worm_with("meshes/worm.obj", "/dev/zero"),
        &[
            "/dev/zero",
            "must be a regular file, but this is a character device",
        ],
    );
    refused(
        &worm_with("models/worm-model.obj", "/dev/urandom"),
        &["/dev/urandom", "character device"],
    );
    // A FIFO is refused at once instead of blocking forever.
    let (dir, _, _) = beside_examples("()");
    let fifo = dir.path().join("mesh.obj");
    let status = Command::new("mkfifo").arg(&fifo).status().expect("mkfifo");
    assert!(status.success());
    let text = worm_with("meshes/worm.obj", "mesh.obj");
    std::fs::write(dir.path().join("run.ron"), text).expect("run");
    let bin = common::build().join(format!("ecles{}", std::env::consts::EXE_SUFFIX));
    let mut child = Command::new(bin)
        .args(["run", "run.ron", "--quiet"])
        .current_dir(dir.path())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if start.elapsed() > Duration::from_secs(30) {
            let _ = child.kill();
            panic!("ecles blocked on a FIFO");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    assert_eq!(status.code(), Some(2));
    // Files over the limit, and binary files.
    let (dir, path, out) = beside_examples(&worm_with("meshes/worm.obj", "junk.obj"));
    std::fs::write(
        dir.path().join("junk.obj"),
        b"v 1 2\n\x00\x01\x02\xff binary",
    )
    .expect("junk");
    let o = run(&path, &out);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("junk.obj:2:1"), "{}", stderr(&o));
    assert!(stderr(&o).contains("not a text file"), "{}", stderr(&o));
    let o = ecles(&[
        "--max-input-bytes",
        "100",
        "run",
        &path.display().to_string(),
        "--quiet",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("more than the limit of 100 bytes"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn closed_or_full_standard_output_never_panics() {
    let bin = common::build().join(format!("ecles{}", std::env::consts::EXE_SUFFIX));
    // A reader that goes away after one byte: the command ends quietly.
    let mut child = Command::new(&bin)
        .args(["analyze", "examples/worm.ron", "--json"])
        .current_dir(root())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    {
        use std::io::Read;
        let mut stdout = child.stdout.take().expect("stdout");
        let mut one = [0u8; 1];
        stdout.read_exact(&mut one).expect("one byte");
    }
    let o = child.wait_with_output().expect("wait");
    assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // A full device: an error message and exit code 3, nothing written.
    #[cfg(target_os = "linux")]
    {
        let out = temp();
        let full = std::fs::File::create("/dev/full").expect("/dev/full");
        let o = Command::new(&bin)
            .args(["run", "examples/worm.ron", "--out"])
            .arg(out.path())
            .current_dir(root())
            .stdout(full)
            .output()
            .expect("run");
        assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
        assert!(
            stderr(&o).contains("cannot write to standard output"),
            "{}",
            stderr(&o)
        );
        assert!(!stderr(&o).contains("panicked"));
        assert!(!out.path().join("report.json").exists());
    }
}

#[test]
fn unknown_fields_and_duplicate_keys_are_located_errors() {
    let linear = r#"(name: "eq", plugin: "linear", config: (parameters: {"a": "1", "b": "1"}, equations: ["a - b = 0"]))"#;
    let with =
        |edit: &str| format!("(\n  sources: [{linear}],\n  edits: [\n    {edit},\n  ],\n)\n");
    expect_bad_input(
        &with(r#"Ecles(anchors: {"eq.a": "2"}, derived: ["eq.b"], wieghts: {"eq.b": "1"})"#),
        &["run.ron:4:", "wieghts"],
    );
    expect_bad_input(
        &with(r#"Ecles(anchors: {"eq.a": "5", "eq.a": "6"}, derived: ["eq.b"])"#),
        &["run.ron:4:", "\"eq.a\" is given twice"],
    );
    refused(
        &worm_edit(
            r#"Source(source: "worm", operation: (anchors: ["v3"], translate: ("0", "1")), extra: 3)"#,
        ),
        &["run.ron:4:", "extra"],
    );
    // A plugin's own configuration error, at its run-file position (not "config 1:40").
    expect_bad_input(
        "(\n  sources: [\n    (name: \"eq\", plugin: \"linear\", config: (\n      parameters: {\"a\": \"1\", \"a\": \"2\"},\n    )),\n  ],\n)\n",
        &["run.ron:4:", "\"a\" is declared twice"],
    );
    refused(
        "(\n  sources: [(name: \"worm\", plugin: \"spline2d\", config: (mesh: \"meshes/worm.obj\",\n    degre: 5))],\n)\n",
        &["run.ron:3:", "degre"],
    );
    refused(
        &worm_edit(
            r#"Source(source: "worm", operation: (anchors: ["v3"], translate: ("0", "1"), wieghts: 2))"#,
        ),
        &["run.ron:4:", "wieghts"],
    );
    refused(
        &format!("(\n  sources: [{WORM_SOURCE}],\n  outputs: [\n    (source: \"worm\", output: (picture: \"w.svg\", colour: true)),\n  ],\n)\n"),
        &["run.ron:4:", "colour"],
    );
}

#[test]
fn malformed_edits_are_refused_before_the_first_edit_runs() {
    let linear = r#"(name: "eq", plugin: "linear", config: (parameters: {"a": "1", "b": "1"}, equations: ["a - b = 0"]))"#;
    // A good edit first: it must not run (no report) when a later one is malformed.
    let generic = |edit: &str| {
        format!("(\n  sources: [{linear}],\n  edits: [\n    Ecles(anchors: {{\"eq.a\": \"2\"}}, derived: [\"eq.b\"]),\n    {edit},\n  ],\n)\n")
    };
    for (edit, needle) in [
        (
            r#"Ecles(anchors: {"eq.a": "2"}, derived: ["eq.b"], weights: {"eq.b": "0"})"#,
            "weights must be positive",
        ),
        (
            r#"Ecles(anchors: {"eq.a": "2"}, derived: ["eq.b"], weights: {"eq.b": "-1"})"#,
            "weights must be positive",
        ),
        (r#"Ecles(anchors: {})"#, "anchors is empty"),
        (
            r#"Ecles(anchors: {"eq.a": "2"}, derived: ["eq.a"])"#,
            "both an anchor and derived",
        ),
        (
            r#"Ecles(anchors: {"eq.a": "2"}, derived: ["eq.b", "eq.b"])"#,
            "listed twice",
        ),
        (
            r#"Ecles(anchors: {"eq.z": "2"})"#,
            "\"eq.z\" is not a parameter",
        ),
        (
            r#"Ecles(anchors: {"eq.a": ("1", "2")})"#,
            "has 2 coordinates, but the parameter has 1",
        ),
        (
            r#"Ecles(anchors: {"eq.a": "2"}, hints: {"eq.b": "1"})"#,
            "has a hint but is not derived",
        ),
    ] {
        expect_bad_input(&generic(edit), &["run.ron:5:", "edit 1: ", needle]);
    }
    let source = |op: &str| worm_edit(&format!("Source(source: \"worm\", operation: {op})"));
    for (op, needle) in [
        (
            r#"(anchors: ["v99"], translate: ("0", "1"))"#,
            "no control point named \"v99\"",
        ),
        (
            r#"(anchors: [], translate: ("0", "1"))"#,
            "anchors is empty",
        ),
        (
            r#"(anchors: ["v3"], translate: ("0", "1", "2"))"#,
            "3 coordinates",
        ),
        (
            r#"(anchors: ["v3"], translate: ("0", "1"), steps: 0)"#,
            "steps is 0",
        ),
        (
            r#"(anchors: ["v3"], rotate: (center: ("0", "0"), degrees: "5", precision: 0))"#,
            "precision",
        ),
        (
            r#"(anchors: ["v3"], scale: (center: ("0", "0"), factor: "0"))"#,
            "must be positive",
        ),
        (
            r#"(anchors: ["v3"], translate: ("0", "1"), neighborhood: -1)"#,
            "neighborhood -1 is negative",
        ),
    ] {
        refused(
            &source(op),
            &["run.ron:4:", "edit 0 (source \"worm\")", needle],
        );
    }
    let terrain = |op: &str| {
        std::fs::read_to_string(root().join("examples/terrain.ron"))
            .expect("terrain.ron")
            .replacen(
                r#"operation: (mode: "z1", anchors: ["v4"], neighborhood: 3, dz: "16", steps: 2)"#,
                &format!("operation: {op}"),
                1,
            )
    };
    refused(
        &terrain(r#"(mode: "z3", anchors: ["v4"], dz: "1")"#),
        &["run.ron:", "mode must be"],
    );
    refused(
        &terrain(r#"(mode: "xy", anchors: ["v4"], translate: ("1", "0"))"#)
            .replace("xy: true,", ""),
        &["needs `xy: true`"],
    );
}

#[test]
fn failed_runs_leave_no_stale_or_partial_output() {
    let (_dir, path, out) = beside_examples(&worm());
    let o = run(&path, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.join("report.json").exists());
    // The same directory, bad input: the old report is gone.
    std::fs::write(&path, worm_with("degree: 5", "degree: 0")).expect("rewrite");
    let o = run(&path, &out);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        !out.join("report.json").exists(),
        "stale report left behind"
    );
    // An output that cannot be written (its name is taken by a directory): exit 3, and
    // neither the report nor any of this run's files or temporary files remain.
    std::fs::write(&path, worm()).expect("rewrite");
    std::fs::remove_dir_all(&out).expect("clean");
    std::fs::create_dir_all(out.join("worm.svg")).expect("blocker");
    let o = run(&path, &out);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("worm.svg"), "{}", stderr(&o));
    let left: Vec<String> = std::fs::read_dir(&out)
        .expect("out")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(left, ["worm.svg"], "only the blocking directory remains");
}

#[test]
fn concurrent_runs_into_one_directory_never_collide() {
    let (_dir, path, out) = beside_examples(&worm());
    let bin = common::build().join(format!("ecles{}", std::env::consts::EXE_SUFFIX));
    let children: Vec<_> = (0..4)
        .map(|_| {
            Command::new(&bin)
                .args(["run", &path.display().to_string(), "--quiet", "--out"])
                .arg(&out)
                .stderr(Stdio::piped())
                .spawn()
                .expect("spawn")
        })
        .collect();
    for child in children {
        let o = child.wait_with_output().expect("wait");
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let report = read_report(&out);
    assert_eq!(report["summary"]["failed"], 0);
    for entry in std::fs::read_dir(&out).expect("out") {
        let name = entry
            .expect("entry")
            .file_name()
            .to_string_lossy()
            .into_owned();
        assert!(
            !name.ends_with(".partial"),
            "temporary file {name} left behind"
        );
    }
}

#[test]
fn files_that_are_not_models_or_would_be_overwritten_are_refused() {
    for (model, needle) in [
        ("/etc/passwd", "is not an OBJ statement"),
        ("run.ron", "is not an OBJ statement"),
        ("random.bin", "not a text file"),
        ("empty.obj", "has no vertices"),
    ] {
        let (dir, path, out) = beside_examples(&worm_with("models/worm-model.obj", model));
        std::fs::write(dir.path().join("random.bin"), [7u8, 0, 200, 13, 0, 255]).expect("junk");
        std::fs::write(dir.path().join("empty.obj"), "# nothing\n").expect("empty");
        let o = run(&path, &out);
        assert_eq!(o.status.code(), Some(2), "{model}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{model}: {}", stderr(&o));
        assert!(!out.join("report.json").exists());
    }
    // A picture named .gif, and an output that would overwrite the run file.
    refused(
        &worm_with("worm.svg", "worm.gif"),
        &["ending in .svg or .png"],
    );
    refused(
        &worm_with("worm.svg", "run.ron"),
        &["ending in .svg or .png"],
    );
    // The mesh itself (an OBJ named .svg) as the picture, written into its own directory.
    let (dir, path, _) = beside_examples(
        &worm_with("meshes/worm.obj", "mesh.svg").replace("\"worm.svg\"", "\"mesh.svg\""),
    );
    std::fs::copy(
        root().join("examples/meshes/worm.obj"),
        dir.path().join("mesh.svg"),
    )
    .expect("copy");
    let o = run(&path, dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("an input of this run"),
        "{}",
        stderr(&o)
    );
    let mesh = std::fs::read(dir.path().join("mesh.svg")).expect("mesh");
    assert_eq!(
        mesh,
        std::fs::read(root().join("examples/meshes/worm.obj")).expect("worm.obj")
    );
}

#[test]
fn small_ones_explain_coordinates_bom_plugin_paths_and_exit_codes() {
    // explain on one coordinate of a vector parameter, and out of range.
    let o = ecles(&["explain", "examples/worm.ron", "worm.v3[1]"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("worm.v3[1] is constrained as worm.v3 is"),
        "{text}"
    );
    let o = ecles(&["explain", "examples/worm.ron", "worm.v3[2]"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("coordinate 2 is out of range"),
        "{}",
        stderr(&o)
    );
    let o = ecles(&["explain", "examples/worm.ron", "worm.nope"]);
    assert_eq!(o.status.code(), Some(2));
    // A run file starting with a UTF-8 byte order mark.
    let (_dir, path, out) = beside_examples(&format!("\u{feff}{}", worm()));
    let o = run(&path, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    // plugins --path takes the extension-less form run files take.
    common::build();
    let stem = common::profile_dir().join("plugins_align");
    let o = ecles(&["plugins", "--path", &stem.display().to_string()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("plugin align"));
    // An output directory that cannot be created is the environment's failure: exit 3.
    let blocker = temp();
    let file = blocker.path().join("a-file");
    std::fs::write(&file, b"x").expect("file");
    let o = ecles(&[
        "run",
        "examples/worm.ron",
        "--quiet",
        "--out",
        &file.join("sub").display().to_string(),
    ]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
}

#[test]
fn contradicting_rows_are_conflicts_not_redundancies_and_analyze_exits_2() {
    let text = "(sources: [(name: \"eq\", plugin: \"linear\", config: (parameters: {\"x\": \"0\"}, equations: [\"x = 0\", \"x = 1\"]))])";
    let (_dir, path, _) = beside_examples(text);
    let o = ecles(&["analyze", &path.display().to_string(), "--json"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let report: Value = serde_json::from_slice(&o.stdout).expect("the JSON is printed first");
    assert_eq!(report["consistent"], Value::Bool(false));
    assert_eq!(report["redundant"], Value::Array(vec![]));
    let conflict: Vec<&str> = report["conflict"]
        .as_array()
        .expect("conflict")
        .iter()
        .filter_map(Value::as_str)
        .collect();
    assert_eq!(conflict.len(), 2, "{conflict:?}");
    assert!(stderr(&o).contains("contradict"), "{}", stderr(&o));
    // A consistent redundant row is still listed with its combination.
    let text = "(sources: [(name: \"eq\", plugin: \"linear\", config: (parameters: {\"x\": \"0\"}, equations: [\"x = 0\", \"2 x = 0\"]))])";
    let (_dir, path, _) = beside_examples(text);
    let o = ecles(&["analyze", &path.display().to_string(), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report: Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(report["redundant"].as_array().map(Vec::len), Some(1));
}

#[test]
fn a_plan_naming_an_unknown_parameter_is_refused_not_a_panic() {
    let dir = temp();
    let library = common::compile_fixture(dir.path(), "bad_plan_plugin.rs", "bad_plan", None);
    expect_bad_input(
        &format!(
            "(\n  sources: [(name: \"bad\", plugin: {:?})],\n  edits: [Source(source: \"bad\", operation: ())],\n)",
            library.display().to_string()
        ),
        &["planned an edit that cannot run", "#999999"],
    );
}

/// Runs `text` (one edit of `worm.v3`); the report and `worm.v3`'s new value.
fn v3_after(text: &str) -> (Value, Value) {
    let (_dir, path, out) = beside_examples(text);
    let o = run(&path, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let report = read_report(&out);
    let v3 = report["edits"][0]["values"]
        .as_array()
        .expect("values")
        .iter()
        .find(|v| v["name"] == "worm.v3")
        .expect("v3")
        .clone();
    (report, v3)
}

#[test]
fn rotations_and_scales_are_exact_whatever_the_numbers() {
    // 3.6e401 degrees is an exact multiple of 360: the anchor stays exactly where it was.
    let text = worm_edit(
        r#"Source(source: "worm", operation: (anchors: ["v3"], neighborhood: 2, rotate: (center: ("0", "0"), degrees: "3.6e401")))"#,
    );
    let (_, v3) = v3_after(&text);
    assert_eq!(v3["exact"], serde_json::json!(["36", "17"]));
    // A quarter turn about the origin is exact: v3 = (36, 17) goes to (-17, 36).
    let text = worm_edit(
        r#"Source(source: "worm", operation: (anchors: ["v3"], neighborhood: 2, rotate: (center: ("0", "0"), degrees: "-270")))"#,
    );
    let (_, v3) = v3_after(&text);
    assert_eq!(v3["exact"], serde_json::json!(["-17", "36"]));
    // Scaling by 1e300 about v0 = (0, 0): the anchor lands exactly at 1e300 · (36, 17).
    let text = worm_edit(
        r#"Source(source: "worm", operation: (anchors: ["v3"], neighborhood: 2, scale: (center: ("0", "0"), factor: "1e300")))"#,
    );
    let (report, v3) = v3_after(&text);
    let big = |k: u32| format!("{k}{}", "0".repeat(300));
    assert_eq!(v3["exact"], serde_json::json!([big(36), big(17)]));
    assert_eq!(report["edits"][0]["max_residual"], "0");
}

#[test]
fn refusals_name_the_rows_that_block_the_requested_move() {
    let align = common::library("plugins_align");
    let text = format!(
        "(\n  sources: [\n    {WORM_SOURCE},\n    (name: \"al\", plugin: {:?}, config: (constraints: [OnLine(points: [\"worm.v0\"], through: ((\"0\", \"0\"), (\"0\", \"10\")))])),\n  ],\n  edits: [\n    Source(source: \"worm\", operation: (anchors: [\"v0\"], neighborhood: 2, translate: (\"0\", \"1\"))),\n    Source(source: \"worm\", operation: (anchors: [\"v0\"], neighborhood: 2, translate: (\"1\", \"0\"))),\n  ],\n)\n",
        align.display().to_string()
    );
    let (_dir, path, out) = beside_examples(&text);
    let o = run(&path, &out);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let report = read_report(&out);
    // Along y the pin in x does not block anything.
    let first = &report["edits"][0];
    assert_eq!(first["solvable"], Value::Bool(true), "{first}");
    assert_eq!(first["max_residual"], "0");
    // Along x it does, and the report names exactly that row, with an explanation.
    let second = &report["edits"][1];
    assert_eq!(second["solvable"], Value::Bool(false), "{second}");
    let conflict: Vec<&str> = second["conflict"]
        .as_array()
        .expect("conflict filled")
        .iter()
        .filter_map(Value::as_str)
        .collect();
    assert_eq!(conflict.len(), 1, "{conflict:?}");
    assert!(conflict[0].starts_with("al row 1: worm.v0"), "{conflict:?}");
    assert!(!second["explanation"]
        .as_array()
        .expect("explanation")
        .is_empty());
    assert_eq!(second["plan"]["expansion_blocked"], 1);
}

#[test]
fn terrain_heights_stay_exactly_where_nothing_was_edited() {
    let text = std::fs::read_to_string(root().join("examples/terrain.ron")).expect("terrain.ron");
    let start = text.find("edits: [").expect("edits");
    let end = start + text[start..].find("\n    ],").expect("end of edits") + "\n    ],".len();
    let no_edits = format!("{}edits: [],{}", &text[..start], &text[end..]);
    let (_dir, path, out) = beside_examples(&no_edits);
    let o = run(&path, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let heights: Vec<f64> = std::fs::read_to_string(root().join("examples/terrains/hills.asc"))
        .expect("hills.asc")
        .lines()
        .skip(6)
        .flat_map(|l| {
            l.split_whitespace()
                .map(|t| t.parse::<f64>().expect("height"))
                .collect::<Vec<_>>()
        })
        .collect();
    let deformed = std::fs::read_to_string(out.join("hills-deformed.obj")).expect("deformed");
    let mut zs: Vec<f64> = deformed
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            l.split_whitespace()
                .nth(2)
                .expect("z")
                .parse::<f64>()
                .expect("z")
        })
        .collect();
    let mut expected = heights.clone();
    zs.sort_by(f64::total_cmp);
    expected.sort_by(f64::total_cmp);
    assert_eq!(zs, expected, "every height comes out exactly as it went in");
}

#[test]
fn a_plugin_path_that_is_not_a_file_is_refused_without_blocking() {
    let dir = temp();
    let fifo = dir.path().join("fifo.so");
    let status = Command::new("mkfifo").arg(&fifo).status().expect("mkfifo");
    assert!(status.success());
    let start = Instant::now();
    expect_bad_input(
        &format!(
            "(sources: [(name: \"p\", plugin: {:?})])",
            fifo.display().to_string()
        ),
        &["not a regular file"],
    );
    assert!(start.elapsed() < Duration::from_secs(20));
}
