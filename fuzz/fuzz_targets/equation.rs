//! The linear-equation parser, directly and through a `linear` source's configuration.
#![no_main]

use api::ConstraintSource;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Err(e) = plugins_linear::equation::parse_equation(text) {
        assert!(e.column >= 1);
    }
    // The same text as an equation over two declared parameters.
    let config = format!(
        "(parameters: {{\"a\": \"1\", \"b\": \"2\"}}, equations: [{:?}])",
        text
    );
    let request = conformance::request("fz", &config);
    let _ = plugins_linear::LinearSource::new().build(&request);
});
