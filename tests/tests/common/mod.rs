//! Helpers shared by the end-to-end tests: building the `ecles` binary and the plugin libraries
//! once per test binary, running the binary, reading its reports.
//!
//! Each test file includes this with `mod common;` and uses what it needs.

#![allow(dead_code)] // every test binary compiles the module and uses a subset of it

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

/// The packages [`build`] builds: the binary and every plugin library the tests load.
const PACKAGES: &[&str] = &[
    "host",
    "plugins-spline2d-dylib",
    "plugins-linear-dylib",
    "plugins-terrain-dylib",
    "plugins-c2",
    "plugins-align",
];

/// The workspace root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from(".."))
}

/// `target/<profile>` of this test binary (`target/<profile>/deps/<test>`).
pub fn profile_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("test binary path");
    exe.parent()
        .and_then(Path::parent)
        .map(Path::to_path_buf)
        .expect("target/<profile>/deps")
}

/// Builds the `ecles` binary and the plugin libraries ([`PACKAGES`]), once, with this
/// test's profile.
pub fn build() -> &'static PathBuf {
    static BUILT: OnceLock<PathBuf> = OnceLock::new();
    BUILT.get_or_init(|| {
        let dir = profile_dir();
        let profile = dir
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let target = dir.parent().map(Path::to_path_buf).expect("target dir");
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let mut cmd = Command::new(cargo);
        cmd.current_dir(root()).arg("build");
        for package in PACKAGES {
            cmd.args(["-p", package]);
        }
        cmd.arg("--target-dir").arg(&target);
        match profile.as_str() {
            "debug" => {}
            "release" => {
                cmd.arg("--release");
            }
            other => {
                cmd.args(["--profile", other]);
            }
        }
        let status = cmd.status().expect("cargo runs");
        assert!(status.success(), "building the binary and plugins failed");
        dir
    })
}

pub fn ecles(args: &[&str]) -> Output {
    let bin = build().join(format!("ecles{}", std::env::consts::EXE_SUFFIX));
    Command::new(bin)
        .current_dir(root())
        .args(args)
        .output()
        .expect("ecles runs")
}

pub fn library(stem: &str) -> PathBuf {
    build().join(plugin_abi::library_file_name(stem))
}

pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

pub fn read_report(dir: &Path) -> Value {
    let text = std::fs::read_to_string(dir.join("report.json")).expect("report written");
    serde_json::from_str(&text).expect("valid JSON")
}

pub fn temp() -> tempfile::TempDir {
    tempfile::tempdir().expect("temporary directory")
}

/// Writes `text` as a run file next to copies of nothing; returns (dir, run path, out dir).
pub fn run_file(text: &str) -> (tempfile::TempDir, PathBuf, PathBuf) {
    let dir = temp();
    let path = dir.path().join("run.ron");
    std::fs::write(&path, text).expect("write run file");
    let out = dir.path().join("out");
    (dir, path, out)
}

/// `ecles run PATH --quiet --out OUT`.
pub fn run_quietly(path: &Path, out: &Path) -> Output {
    ecles(&[
        "run",
        &path.display().to_string(),
        "--quiet",
        "--out",
        &out.display().to_string(),
    ])
}

/// Runs the run-file text `text` (written in a temporary directory) with `--quiet`; asserts it
/// succeeds and returns its report.
pub fn run_text_ok(text: &str) -> Value {
    let (_dir, path, out) = run_file(text);
    let o = run_quietly(&path, &out);
    assert!(o.status.success(), "{text}\n{}", stderr(&o));
    read_report(&out)
}

/// A bundled example's text with its relative paths into `dirs` (`"meshes/"`, …) made
/// absolute, to run from anywhere.
pub fn example_text(name: &str, dirs: &[&str]) -> String {
    let examples = root().join("examples").display().to_string();
    let text = std::fs::read_to_string(root().join("examples").join(name)).expect("an example");
    dirs.iter().fold(text, |t, dir| {
        t.replace(&format!("\"{dir}"), &format!("\"{examples}/{dir}"))
    })
}

pub fn expect_bad_input(text: &str, needles: &[&str]) {
    let (_dir, path, out) = run_file(text);
    let o = run_quietly(&path, &out);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{text}\n{err}");
    for needle in needles {
        assert!(err.contains(needle), "expected {needle:?} in {err:?}");
    }
    assert!(
        !out.join("report.json").exists(),
        "no report may be left behind after bad input"
    );
}

/// A report without what depends on where things were loaded from (the plugin paths, the run
/// file's name), so the static and dynamic paths can be compared.
pub fn without_origin(mut report: Value) -> Value {
    for source in report["sources"].as_array_mut().expect("sources") {
        source["loaded_from"] = Value::Null;
    }
    report["run"] = Value::Null;
    report
}

/// Compiles a dependency-free plugin fixture (`crates/plugin-abi/tests/fixtures/FILE`) with
/// `rustc` into `dir` as the library `name`, with `cfg` (e.g. `variant="old_abi"`) if given.
pub fn compile_fixture(dir: &Path, file: &str, name: &str, cfg: Option<&str>) -> PathBuf {
    let fixture = root().join("crates/plugin-abi/tests/fixtures").join(file);
    let library = dir.join(plugin_abi::library_file_name(name));
    let rustc = std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let mut command = Command::new(rustc);
    command.args([
        "--edition",
        "2021",
        "--crate-type",
        "cdylib",
        "--crate-name",
        name,
    ]);
    if let Some(cfg) = cfg {
        command.args(["--cfg", cfg]);
    }
    let status = command
        .arg("-o")
        .arg(&library)
        .arg(&fixture)
        .status()
        .expect("rustc runs");
    assert!(status.success(), "compiling the fixture {file} failed");
    library
}
