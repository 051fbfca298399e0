//! The conformance checks every plugin should pass (see `conformance`), run twice: on the
//! source linked statically and on this crate's own dynamic library loaded through the ABI
//! (Cargo builds the `cdylib` next to this test, see `plugin_abi::library_beside_test`).
//!
//! Copy this file with the template: only the samples are specific to a plugin.

use api::{BuildRequest, ConstraintSystem, ParamId, Values};
use conformance::{check_source, request, Samples};
use plugin_example::ExampleSource;

/// Good and bad configurations, one operation and one output (the example plugin refuses both).
fn samples() -> Samples {
    let mut system = ConstraintSystem::new();
    system.add_parameter("earlier", 1).expect("fresh name");
    let on_earlier = BuildRequest {
        values: Values::zeros(&system),
        system,
        ..request("ex", r#"(value: "-0.125")"#)
    };
    Samples {
        good: vec![request("ex", r#"(value: "7/3")"#), on_earlier],
        bad: ["(value: \"x\")", "(valu: \"1\")", "(", "(value: 0.5)"]
            .iter()
            .map(|c| request("ex", c))
            .collect(),
        operations: vec!["(move: 1)".into()],
        outputs: vec!["(picture: \"ex.svg\")".into()],
    }
}

#[test]
fn passes_the_conformance_checks_statically_and_loaded() {
    let samples = samples();
    let linked = check_source(&mut || Box::new(ExampleSource::default()), &samples)
        .unwrap_or_else(|e| panic!("statically linked: {e}"));
    // The new parameter of the second sample comes after the earlier source's one.
    assert_eq!(linked[1].rows[0].body.params(), vec![ParamId(1)]);

    let path = plugin_abi::library_beside_test("plugin-example").expect("test executable path");
    let plugin = plugin_abi::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(plugin.kind, "example");
    let loaded = check_source(&mut || Box::new(plugin.instantiate()), &samples)
        .unwrap_or_else(|e| panic!("loaded from {}: {e}", path.display()));
    assert_eq!(loaded, linked);
}
