//! The loader against real libraries: the example plugin built as a `cdylib`, and the fixture
//! libraries of `fixtures/fake_plugin.rs`.
//!
//! Cargo cannot (on stable) make a dev-dependency's `cdylib` available to a test, so the tests
//! build the libraries themselves: `cargo build -p plugin-example --lib` with the profile and
//! target directory of the running test binary (so a `--release` test run reuses its release
//! artifacts), and `rustc --crate-type cdylib` for the fixtures.

use api::{
    parse_rational, BuildRequest, ConstraintSource, ConstraintSystem, Contribution, PlanRequest,
    RenderRequest, SourceError, SourceInfo, Values,
};
use plugin_abi::abi::ABI_VERSION;
use plugin_abi::{library_file_name, load, DynamicSource, LoadError, LoadedPlugin};
use plugin_example::ExampleSource;
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// Where Cargo put this test binary: `<target>/[<triple>/]<profile>/deps/<binary>`.
struct Layout {
    /// `<target>/[<triple>/]<profile>`: where Cargo puts the libraries it builds.
    profile_dir: PathBuf,
    /// `<target>`.
    target_dir: PathBuf,
    /// `<triple>`, when the run cross-compiles with `--target`.
    triple: Option<OsString>,
    /// `debug`, `release` or a custom profile's name.
    profile: String,
}

fn layout() -> Layout {
    let exe = std::env::current_exe().expect("path of the test binary");
    let profile_dir = exe
        .parent()
        .and_then(Path::parent)
        .expect("the test binary lives in <target>/<profile>/deps")
        .to_path_buf();
    let profile = profile_dir
        .file_name()
        .and_then(|n| n.to_str())
        .expect("profile directory name")
        .to_string();
    let parent = profile_dir
        .parent()
        .expect("target directory")
        .to_path_buf();
    // Cargo marks its target directory's root with CACHEDIR.TAG; a directory without one between
    // the root and the profile is a `--target` triple.
    let (target_dir, triple) = match parent.parent() {
        Some(root)
            if !parent.join("CACHEDIR.TAG").exists() && root.join("CACHEDIR.TAG").exists() =>
        {
            (root.to_path_buf(), parent.file_name().map(OsString::from))
        }
        _ => (parent, None),
    };
    Layout {
        profile_dir,
        target_dir,
        triple,
        profile,
    }
}

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Runs a command; panics with its output if it fails.
fn run(mut command: Command) {
    let output = command
        .output()
        .unwrap_or_else(|e| panic!("cannot run {command:?}: {e}"));
    assert!(
        output.status.success(),
        "{command:?} failed ({}):\n{}\n{}",
        output.status,
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
}

/// The example plugin's `cdylib`, built once per test binary.
fn example_library() -> &'static Path {
    static LIBRARY: OnceLock<PathBuf> = OnceLock::new();
    LIBRARY.get_or_init(|| {
        let layout = layout();
        let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        let mut command = Command::new(cargo);
        command
            .current_dir(workspace_root())
            .args(["build", "--quiet", "-p", "plugin-example", "--lib"])
            .arg("--target-dir")
            .arg(&layout.target_dir);
        match layout.profile.as_str() {
            "debug" => {}
            "release" => {
                command.arg("--release");
            }
            other => {
                command.args(["--profile", other]);
            }
        }
        if let Some(triple) = &layout.triple {
            command.arg("--target").arg(triple);
        }
        run(command);
        let path = layout.profile_dir.join(library_file_name("plugin_example"));
        assert!(path.is_file(), "cargo did not produce {}", path.display());
        path
    })
}

/// A fixture library compiled from `fixtures/fake_plugin.rs` with `variant`.
fn fixture_library(variant: &str) -> PathBuf {
    let dir = layout().profile_dir.join("plugin-abi-fixtures");
    std::fs::create_dir_all(&dir).expect("fixture directory");
    let path = dir.join(library_file_name(&format!("fake_{variant}")));
    let rustc = std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let mut command = Command::new(rustc);
    command
        .current_dir(workspace_root())
        .args(["--edition", "2021", "--crate-type", "cdylib"])
        .args(["--crate-name", &format!("fake_{variant}")])
        .args(["--cfg", &format!("variant=\"{variant}\"")])
        .arg("-o")
        .arg(&path)
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/fake_plugin.rs"));
    run(command);
    path
}

fn example_plugin() -> LoadedPlugin {
    load(example_library()).expect("the example plugin loads")
}

/// A request on a system that already holds one parameter, so ids are offset.
fn build_request(config: &str) -> BuildRequest {
    let mut system = ConstraintSystem::new();
    system.add_parameter("earlier", 2).expect("fresh name");
    BuildRequest {
        schema: api::SCHEMA_VERSION,
        input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
        name: "ex".into(),
        config: config.into(),
        base_dir: "/some/run/dir".into(),
        values: Values::zeros(&system),
        system,
        sources: vec![SourceInfo {
            name: "earlier".into(),
            kind: "linear".into(),
            config: "()".into(),
        }],
    }
}

#[test]
fn the_example_plugin_loads_and_reports_its_identity() {
    let plugin = example_plugin();
    assert_eq!(plugin.kind, "example");
    assert_eq!(plugin.version, ExampleSource::default().version());
    assert_eq!(plugin.abi_version, ABI_VERSION);
    assert_eq!(plugin.path, example_library());
    let source = plugin.instantiate();
    assert_eq!(source.kind(), "example");
    assert_eq!(source.version(), ExampleSource::default().version());
    // Loading again reuses the (never unloaded) library.
    assert_eq!(example_plugin().kind, "example");
}

#[test]
fn dynamic_and_static_builds_agree() {
    let plugin = example_plugin();
    for config in [
        r#"(value: "7/3")"#,
        r#"(value: "-0.125")"#,
        r#"(value: "3")"#,
    ] {
        let request = build_request(config);
        let mut dynamic = plugin.instantiate();
        let mut fixed = ExampleSource::default();
        let from_plugin: Contribution = dynamic.build(&request).expect("dynamic build");
        let in_process = fixed.build(&request).expect("static build");
        assert_eq!(from_plugin, in_process, "{config}");

        // And the contribution is what the example promises.
        let mut system = request.system.clone();
        let mut values = request.values.clone();
        from_plugin
            .apply_to(&mut system, &mut values)
            .expect("applies");
        let x = system.param_id("ex.x").expect("ex.x declared");
        assert_eq!(x.index(), 1);
        assert!(system.violations(&values).is_empty());
        // The example draws nothing: its view (method 6) is `None` across the boundary too.
        let view = api::ViewRequest {
            schema: api::SCHEMA_VERSION,
            outputs: vec!["(picture: \"ex.svg\")".into()],
        };
        assert_eq!(dynamic.view(&view), Ok(None));
        assert_eq!(fixed.view(&view), Ok(None));
    }
    let c = plugin
        .instantiate()
        .build(&build_request(r#"(value: "7/3")"#))
        .expect("build");
    assert_eq!(
        c.parameters[0].value,
        vec![parse_rational("7/3").expect("7/3")]
    );
    assert_eq!(
        format!("{:?}", c.rows[0].body),
        format!(
            "{:?}",
            api::RowBody::Vector {
                terms: vec![(api::ParamId(1), 3.into())],
                rhs: vec![7.into()],
            }
        )
    );
}

#[test]
fn refusals_cross_the_boundary_unchanged() {
    let plugin = example_plugin();
    let mut dynamic = plugin.instantiate();
    let mut fixed = ExampleSource::default();
    let bad = build_request(r#"(value: "7/0")"#);
    let error = dynamic.build(&bad).expect_err("division by zero");
    assert_eq!(Err(error.clone()), fixed.build(&bad).map(|_| ()));
    assert!(error.message.starts_with("ex config: value:"), "{error}");

    let good = build_request(r#"(value: "1")"#);
    dynamic.build(&good).expect("build");
    fixed.build(&good).expect("build");
    let plan = PlanRequest {
        schema: api::SCHEMA_VERSION,
        operation: "(move: 1)".into(),
        system: good.system.clone(),
        values: good.values.clone(),
    };
    let render = RenderRequest {
        schema: api::SCHEMA_VERSION,
        input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
        output: "(svg: true)".into(),
        base_dir: ".".into(),
        system: good.system.clone(),
        initial: good.values.clone(),
        values: good.values.clone(),
        highlight: None,
        structure: None,
    };
    let plan_error = dynamic.plan(&plan).expect_err("no operations");
    assert_eq!(Err(plan_error.clone()), fixed.plan(&plan).map(|_| ()));
    assert!(plan_error.message.starts_with("ex: "), "{plan_error}");
    let render_error = dynamic.render(&render).expect_err("no outputs");
    assert_eq!(Err(render_error), fixed.render(&render).map(|_| ()));
}

#[test]
fn a_panicking_plugin_is_an_error_not_a_crash() {
    let plugin = example_plugin();
    let mut source: DynamicSource = plugin.instantiate();
    let error: SourceError = source
        .build(&build_request(r#"(value: "1", test_panic: true)"#))
        .expect_err("panics");
    assert!(
        error.message.starts_with(&format!(
            "plugin \"example\" {} ({}): build panicked: ",
            ExampleSource::default().version(),
            example_library().display()
        )),
        "{error}"
    );
    assert!(
        error
            .message
            .ends_with("ex: test_panic is set, panicking on purpose"),
        "{error}"
    );
    // The instance and the process are still fine.
    let c = source
        .build(&build_request(r#"(value: "2")"#))
        .expect("works after a panic");
    assert_eq!(c.parameters.len(), 1);
}

#[test]
fn a_missing_file_is_not_found() {
    let path = layout()
        .profile_dir
        .join(library_file_name("no_such_plugin"));
    let error = load(&path).expect_err("missing");
    assert_eq!(error, LoadError::NotFound { path: path.clone() });
    assert!(error.to_string().contains(&path.display().to_string()));
}

#[test]
fn a_file_that_is_not_a_library_cannot_be_opened() {
    let dir = layout().profile_dir.join("plugin-abi-fixtures");
    std::fs::create_dir_all(&dir).expect("fixture directory");
    let path = dir.join(library_file_name("not_a_library"));
    std::fs::write(&path, "this is text, not machine code\n").expect("write");
    match load(&path) {
        Err(error @ LoadError::Open { .. }) => {
            let LoadError::Open { path: p, message } = &error else {
                unreachable!()
            };
            assert_eq!(p, &path);
            assert!(!message.is_empty());
            assert!(error.to_string().contains(&path.display().to_string()));
        }
        other => panic!("expected an open error, got {other:?}"),
    }
}

#[test]
fn a_library_without_the_probe_is_not_a_plugin() {
    let path = fixture_library("no_probe");
    let error = load(&path).expect_err("no probe");
    assert_eq!(
        error,
        LoadError::MissingSymbol {
            path: path.clone(),
            symbol: "ecles_plugin_abi_version".into()
        }
    );
    assert!(error.to_string().contains(&path.display().to_string()));
}

#[test]
fn a_library_without_the_entry_is_not_a_plugin() {
    let path = fixture_library("no_entry");
    assert_eq!(
        load(&path).expect_err("no entry"),
        LoadError::MissingSymbol {
            path,
            symbol: "ecles_plugin_entry_v1".into()
        }
    );
}

#[test]
fn another_abi_version_is_refused_at_the_probe() {
    // The fixture's entry symbol aborts the process if called: the host must stop at the probe.
    let path = fixture_library("old_abi");
    let error = load(&path).expect_err("ABI 999");
    assert_eq!(
        error,
        LoadError::AbiMismatch {
            path: path.clone(),
            found: 999,
            expected: ABI_VERSION
        }
    );
    let message = error.to_string();
    assert!(message.contains("version 999"), "{message}");
    assert!(
        message.contains(&format!("version {ABI_VERSION}")),
        "{message}"
    );
    assert!(message.contains(&path.display().to_string()), "{message}");
}
