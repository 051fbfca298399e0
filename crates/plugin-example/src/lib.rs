//! A tiny constraint source of kind `"example"`, exported as a dynamic plugin.
//!
//! It is the template for plugin authors: copy the crate, rename it, replace the body of
//! [`ExampleSource`]. What makes it a plugin is only
//!
//! * `crate-type = ["cdylib", "rlib"]` in `Cargo.toml` (the `cdylib` is what a host loads);
//! * an implementation of [`api::ConstraintSource`];
//! * the last line, [`plugin_abi::export_source!`], which generates the C symbols. Plugin code
//!   needs no `unsafe` of its own.
//!
//! Its configuration (RON) is `(value: "7/3")`: the source declares one scalar parameter
//! `{name}.x` with that exact value (decimal or fraction text, read by
//! [`api::parse_rational`]) and one row fixing it, scaled to integers: `3·x = 7`.
//!
//! Rules for sources (see the workspace's architecture notes): do no file I/O beyond the inputs
//! the configuration names, never print, say where an error is (source name, field), and
//! prefix parameter names and row labels with the instance name.

use api::{
    parse_rational, BuildRequest, ConstraintRow, ConstraintSource, Contribution, NewParameter,
    OperationCheckRequest, OperationPlan, Origin, OutputCheck, OutputCheckRequest, OutputFile,
    ParamId, PlanRequest, RenderRequest, RowBody, SourceError, SummaryItem,
};
use serde::Deserialize;

/// The configuration, as written in a run file: `(value: "7/3")`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Config {
    /// Exact value of `x`: `"3"`, `"-2.5"`, `"7/3"`.
    value: String,
    /// Test hook, not for real runs: `(value: "1", test_panic: true)` makes `build` panic, so
    /// tests can check that a panicking plugin becomes an error and not a crash.
    #[serde(default)]
    test_panic: bool,
}

/// The example source. Its state is what `build` learned, kept for `plan` and `render`.
#[derive(Debug, Default)]
pub struct ExampleSource {
    /// Instance name, once built.
    name: Option<String>,
}

impl ExampleSource {
    fn name(&self) -> &str {
        self.name.as_deref().unwrap_or("example (not built)")
    }
}

impl ConstraintSource for ExampleSource {
    fn kind(&self) -> &str {
        "example"
    }

    fn version(&self) -> &str {
        env!("CARGO_PKG_VERSION")
    }

    fn build(&mut self, request: &BuildRequest) -> Result<Contribution, SourceError> {
        let name = &request.name;
        // Positioned errors: the host shows them at the right line of the run file.
        let config: Config = api::config::from_ron(&request.config, &format!("{name} config"))?;
        if config.test_panic {
            panic!("{name}: test_panic is set, panicking on purpose");
        }
        let value = parse_rational(&config.value)
            .map_err(|e| SourceError::new(format!("{name} config: value: {e}")))?;

        // New parameters get the ids after the existing ones, in order.
        let x_name = format!("{name}.x");
        if request.system.param_id(&x_name).is_some() {
            return Err(SourceError::new(format!(
                "{name}: {x_name:?} already exists"
            )));
        }
        let x = u32::try_from(request.system.params().len())
            .map(ParamId)
            .map_err(|_| SourceError::new(format!("{name}: too many parameters")))?;

        // Rows have integer coefficients: x = n/d becomes d·x = n (d > 0, n/d reduced).
        let row = ConstraintRow {
            label: format!("{name}: x = {}", config.value.trim()),
            origin: Origin {
                source: name.clone(),
                item: "x".into(),
            },
            body: RowBody::Vector {
                terms: vec![(x, value.denom().clone())],
                rhs: vec![value.numer().clone()],
            },
        };
        self.name = Some(name.clone());
        Ok(Contribution {
            inputs: Vec::new(),
            parameters: vec![NewParameter {
                name: x_name,
                value: vec![value],
            }],
            rows: vec![row],
            summary: vec![SummaryItem {
                key: "parameters".into(),
                value: 1,
            }],
            warnings: vec![],
        })
    }

    fn plan(&self, request: &PlanRequest) -> Result<OperationPlan, SourceError> {
        Err(SourceError::new(format!(
            "{}: example sources have no operations (asked for {:?})",
            self.name(),
            request.operation
        )))
    }

    fn render(&self, request: &RenderRequest) -> Result<Vec<OutputFile>, SourceError> {
        Err(SourceError::new(format!(
            "{}: example sources have no outputs (asked for {:?})",
            self.name(),
            request.output
        )))
    }

    // The checks run before the first edit of a run; a source without operations or outputs
    // refuses them there, so a run file asking for one fails before any work is done.
    fn check_operation(&self, request: &OperationCheckRequest) -> Result<(), SourceError> {
        Err(SourceError::new(format!(
            "{}: example sources have no operations (asked for {:?})",
            self.name(),
            request.operation
        )))
    }

    fn check_output(&self, request: &OutputCheckRequest) -> Result<OutputCheck, SourceError> {
        Err(SourceError::new(format!(
            "{}: example sources have no outputs (asked for {:?})",
            self.name(),
            request.output
        )))
    }
}

// The C ABI: `ecles_plugin_abi_version`, `ecles_plugin_entry_v1`, header and vtable.
plugin_abi::export_source!(ExampleSource::default);

#[cfg(test)]
mod tests {
    use super::*;
    use api::{ConstraintSystem, Values};

    fn build(config: &str) -> Result<Contribution, SourceError> {
        let mut system = ConstraintSystem::new();
        system.add_parameter("earlier", 1).expect("fresh name");
        ExampleSource::default().build(&BuildRequest {
            schema: api::SCHEMA_VERSION,
            input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
            name: "ex".into(),
            config: config.into(),
            base_dir: ".".into(),
            values: Values::zeros(&system),
            system,
            sources: vec![],
        })
    }

    #[test]
    fn a_fraction_becomes_an_integer_row() {
        let c = build(r#"(value: "7/3")"#).expect("valid");
        assert_eq!(c.parameters[0].name, "ex.x");
        assert_eq!(
            c.parameters[0].value,
            vec![parse_rational("7/3").expect("7/3")]
        );
        assert_eq!(
            c.rows[0].body,
            RowBody::Vector {
                terms: vec![(ParamId(1), 3.into())],
                rhs: vec![7.into()]
            }
        );
    }

    #[test]
    fn bad_configs_are_refused_with_the_instance_name() {
        for config in [r#"(value: "x")"#, "(valu: \"1\")", "("] {
            let error = build(config).expect_err(config);
            assert!(error.message.starts_with("ex config"), "{}", error.message);
        }
    }
}
