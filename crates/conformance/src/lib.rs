//! Conformance checks for constraint sources: what every plugin's tests should verify.
//!
//! The checks take sources as `&mut dyn ConstraintSource`, so they run the same on a source
//! linked statically and on a dynamic plugin loaded with `plugin_abi::load(..)?.instantiate()`
//! (a `DynamicSource` implements the same trait). They verify the rules of
//! [`api::source`] that a host relies on:
//!
//! * **builds answer** and **never panic**: a good configuration gives a contribution, a bad one
//!   an error (with a message naming the instance), and neither unwinds;
//! * **determinism**: two fresh instances given the same request give identical contributions
//!   (reports are byte-identical across runs);
//! * **contributions apply cleanly** to the system of the request
//!   ([`Contribution::apply_to`]: new names unique, ids and dimensions valid);
//! * **names are prefixed by the instance name**: new parameters are `{name}.…`, row labels
//!   start with `{name}:` and row origins name the instance;
//! * **summary keys are stable `snake_case`** (`control_points`), each given once;
//! * **checks, plan and render answer or refuse gracefully**: an answer is well formed
//!   ([`OperationPlan::validate`]: anchors and derived parameters exist, one positive weight per
//!   derived parameter, step sizes match; rendered files are the ones the output's check
//!   announced), a refusal has a message, and nothing panics.
//!
//! [`check_source`] runs everything on a set of [`Samples`]; the single checks are public for
//! tests that need only one.
//!
//! ```
//! use conformance::Samples;
//! use api::{
//!     BuildRequest, ConstraintSource, Contribution, NewParameter, OperationCheckRequest,
//!     OperationPlan, OutputCheck, OutputCheckRequest, OutputFile, PlanRequest, RenderRequest,
//!     SourceError, SummaryItem,
//! };
//!
//! /// Declares one scalar parameter `{name}.x = 0`; its configuration must be `()`.
//! #[derive(Default)]
//! struct Zero;
//!
//! impl ConstraintSource for Zero {
//!     fn kind(&self) -> &str { "zero" }
//!     fn version(&self) -> &str { "1.0.0" }
//!     fn build(&mut self, request: &BuildRequest) -> Result<Contribution, SourceError> {
//!         if request.config.trim() != "()" {
//!             return Err(SourceError::new(format!("{} config: expected ()", request.name)));
//!         }
//!         Ok(Contribution {
//!             parameters: vec![NewParameter {
//!                 name: format!("{}.x", request.name),
//!                 value: vec![api::Rational::from_integer(0.into())],
//!             }],
//!             summary: vec![SummaryItem { key: "parameters".into(), value: 1 }],
//!             ..Contribution::default()
//!         })
//!     }
//!     fn plan(&self, _: &PlanRequest) -> Result<OperationPlan, SourceError> {
//!         Err(SourceError::new("zero: no operations"))
//!     }
//!     fn render(&self, _: &RenderRequest) -> Result<Vec<OutputFile>, SourceError> {
//!         Err(SourceError::new("zero: no outputs"))
//!     }
//!     fn check_operation(&self, _: &OperationCheckRequest) -> Result<(), SourceError> {
//!         Err(SourceError::new("zero: no operations"))
//!     }
//!     fn check_output(&self, _: &OutputCheckRequest) -> Result<OutputCheck, SourceError> {
//!         Err(SourceError::new("zero: no outputs"))
//!     }
//! }
//!
//! let samples = Samples {
//!     good: vec![conformance::request("z", "()")],
//!     bad: vec![conformance::request("z", "(x: 1)")],
//!     operations: vec!["(anchors: [])".into()],
//!     outputs: vec!["(picture: \"z.svg\")".into()],
//! };
//! conformance::check_source(&mut || Box::new(Zero), &samples)?;
//! # Ok::<(), conformance::ConformanceError>(())
//! ```

use api::{
    BuildRequest, ConstraintSource, Contribution, OperationCheckRequest, OperationPlan,
    OutputCheckRequest, PlanRequest, RenderRequest,
};
use api::{ConstraintSystem, SystemError, Values};
use std::collections::BTreeSet;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// A rule a source broke. The message says which rule, which call and which item.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ConformanceError {
    /// A call unwound instead of answering.
    #[error("{call} panicked: {message}")]
    Panicked {
        /// The call (`build of "phi"`, `plan of "phi"`).
        call: String,
        /// The panic message.
        message: String,
    },
    /// A sample configuration that should build was refused.
    #[error("build of {name:?} refused a good configuration: {message}")]
    Refused {
        /// The instance name.
        name: String,
        /// The source's error.
        message: String,
    },
    /// A sample configuration that should be refused was built.
    #[error("build of {name:?} accepted a bad configuration: {config}")]
    AcceptedBadConfig {
        /// The instance name.
        name: String,
        /// The configuration text.
        config: String,
    },
    /// An error without a usable message.
    #[error("{call} returned an error that {problem}: {message:?}")]
    PoorError {
        /// The call.
        call: String,
        /// What is wrong with the message.
        problem: String,
        /// The message.
        message: String,
    },
    /// The contribution does not apply to the system of the request.
    #[error("the contribution of {name:?} does not apply to the request's system: {error}")]
    DoesNotApply {
        /// The instance name.
        name: String,
        /// Why the system refused it.
        error: SystemError,
    },
    /// A parameter name, row label or row origin does not name the instance.
    #[error(
        "{what} {found:?} of {name:?} is not prefixed by the instance name (expected {expected})"
    )]
    Unprefixed {
        /// The instance name.
        name: String,
        /// `"parameter"`, `"row label"` or `"row origin"`.
        what: String,
        /// The offending text.
        found: String,
        /// What it should look like.
        expected: String,
    },
    /// A summary key that is not stable `snake_case`, or given twice.
    #[error("summary key {key:?} of {name:?} {problem}")]
    SummaryKey {
        /// The instance name.
        name: String,
        /// The key.
        key: String,
        /// What is wrong with it.
        problem: String,
    },
    /// Two instances built the same request differently.
    #[error("two instances built {name:?} differently: {difference}")]
    NotDeterministic {
        /// The instance name.
        name: String,
        /// The first difference found.
        difference: String,
    },
    /// Kind or version empty, or different between two instances.
    #[error("identity: {problem}")]
    Identity {
        /// What is wrong.
        problem: String,
    },
    /// A plan that refers to unknown parameters or has inconsistent sizes.
    #[error("plan of {name:?} for {operation:?} is malformed: {problem}")]
    BadPlan {
        /// The instance name.
        name: String,
        /// The operation text.
        operation: String,
        /// What is wrong.
        problem: String,
    },
    /// Render answered with an unusable file name.
    #[error("render of {name:?} for {output:?} produced the file name {file:?}, which is not a plain file name")]
    BadFileName {
        /// The instance name.
        name: String,
        /// The output text.
        output: String,
        /// The file name.
        file: String,
    },
    /// Render wrote other files than the output's check announced.
    #[error("render of {name:?} for {output:?} wrote {rendered:?}, but its check announced {announced:?}")]
    UnannouncedFiles {
        /// The instance name.
        name: String,
        /// The output text.
        output: String,
        /// The names the check announced.
        announced: Vec<String>,
        /// The names render produced.
        rendered: Vec<String>,
    },
    /// Render attached a note that is blank or spans several lines (the host prints each note
    /// on one line of its summary).
    #[error("render of {name:?} for {output:?} attached the note {note:?} to {file:?}; notes must be one non-blank line")]
    BadNote {
        /// The instance name.
        name: String,
        /// The output text.
        output: String,
        /// The file name.
        file: String,
        /// The note.
        note: String,
    },
    /// The source's view does not pass [`api::SourceView::validate`] on the system it built.
    #[error("view of {name:?} cannot be drawn: {problem}")]
    BadView {
        /// Instance name.
        name: String,
        /// What is wrong.
        problem: String,
    },
}

/// Sample inputs for [`check_source`].
#[derive(Debug, Clone, Default)]
pub struct Samples {
    /// Requests the source must build (each on fresh instances).
    pub good: Vec<BuildRequest>,
    /// Requests the source must refuse with an error (each on a fresh instance).
    pub bad: Vec<BuildRequest>,
    /// Operation texts planned after each good build; a plan or a refusal is fine.
    pub operations: Vec<String>,
    /// Output texts rendered after each good build; files or a refusal are fine.
    pub outputs: Vec<String>,
}

/// A build request on an empty system with no earlier sources, relative paths resolved against
/// the current directory.
pub fn request(name: &str, config: &str) -> BuildRequest {
    BuildRequest {
        schema: api::SCHEMA_VERSION,
        name: name.to_string(),
        config: config.to_string(),
        base_dir: ".".into(),
        system: ConstraintSystem::new(),
        values: Values::default(),
        sources: Vec::new(),
        input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
    }
}

/// Runs `f`, turning a panic into [`ConformanceError::Panicked`].
fn no_panic<T>(call: String, f: impl FnOnce() -> T) -> Result<T, ConformanceError> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|payload| {
        let message = if let Some(s) = payload.downcast_ref::<&str>() {
            (*s).to_string()
        } else if let Some(s) = payload.downcast_ref::<String>() {
            s.clone()
        } else {
            "a panic with a non-string payload".to_string()
        };
        ConformanceError::Panicked { call, message }
    })
}

/// Checks an error message: non-empty, and naming the instance when `name` is given.
fn check_message(call: &str, name: Option<&str>, message: &str) -> Result<(), ConformanceError> {
    let poor = |problem: &str| ConformanceError::PoorError {
        call: call.to_string(),
        problem: problem.to_string(),
        message: message.to_string(),
    };
    if message.trim().is_empty() {
        return Err(poor("is empty"));
    }
    if let Some(name) = name {
        if !message.contains(name) {
            return Err(poor(&format!("does not name the instance {name:?}")));
        }
    }
    Ok(())
}

/// True for stable report keys: `snake_case` ASCII, starting with a letter.
fn is_snake_case(key: &str) -> bool {
    let mut chars = key.chars();
    chars.next().is_some_and(|c| c.is_ascii_lowercase())
        && chars.all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
        && !key.ends_with('_')
        && !key.contains("__")
}

/// Checks the contribution of instance `name` against the rules that need no second build:
/// it applies to `system`/`values`, names are prefixed, summary keys are stable `snake_case`.
/// Returns the system and values with the contribution applied.
pub fn check_contribution(
    name: &str,
    contribution: &Contribution,
    system: &ConstraintSystem,
    values: &Values,
) -> Result<(ConstraintSystem, Values), ConformanceError> {
    let unprefixed = |what: &str, found: &str, expected: String| ConformanceError::Unprefixed {
        name: name.to_string(),
        what: what.to_string(),
        found: found.to_string(),
        expected,
    };
    let param_prefix = format!("{name}.");
    for p in &contribution.parameters {
        if !p.name.starts_with(&param_prefix) || p.name.len() == param_prefix.len() {
            return Err(unprefixed("parameter", &p.name, format!("\"{name}.…\"")));
        }
    }
    let label_prefix = format!("{name}:");
    for row in &contribution.rows {
        if !row.label.starts_with(&label_prefix) {
            return Err(unprefixed(
                "row label",
                &row.label,
                format!("\"{name}: …\""),
            ));
        }
        if row.origin.source != name {
            return Err(unprefixed(
                "row origin",
                &row.origin.source,
                format!("origin.source == {name:?}"),
            ));
        }
    }
    let mut keys = BTreeSet::new();
    for item in &contribution.summary {
        let bad = |problem: &str| ConformanceError::SummaryKey {
            name: name.to_string(),
            key: item.key.clone(),
            problem: problem.to_string(),
        };
        if !is_snake_case(&item.key) {
            return Err(bad(
                "is not snake_case (lowercase letters, digits, single underscores)",
            ));
        }
        if !keys.insert(item.key.as_str()) {
            return Err(bad("is given twice"));
        }
    }
    let mut system = system.clone();
    let mut values = values.clone();
    contribution
        .apply_to(&mut system, &mut values)
        .map_err(|error| ConformanceError::DoesNotApply {
            name: name.to_string(),
            error,
        })?;
    Ok((system, values))
}

/// Builds `request` once (no panic, no refusal) and checks the contribution with
/// [`check_contribution`]. Returns the contribution.
pub fn check_build(
    source: &mut dyn ConstraintSource,
    request: &BuildRequest,
) -> Result<Contribution, ConformanceError> {
    let name = &request.name;
    let contribution =
        no_panic(format!("build of {name:?}"), || source.build(request))?.map_err(|e| {
            ConformanceError::Refused {
                name: name.clone(),
                message: e.message,
            }
        })?;
    check_contribution(name, &contribution, &request.system, &request.values)?;
    Ok(contribution)
}

/// Asks a built source for its editor view twice, with no outputs and with `outputs` (output
/// texts the source's `check_output` accepted, as a host sends them), and checks the answers:
/// no panic and no refusal; a view asked without outputs has no models (models come only from
/// outputs); the outputs change nothing but the models (not the kind either); the view passes
/// [`api::SourceView::validate`] on the system the source was built into (models included).
/// Views of every kind are checked alike ([`api::SourceView::models`]: Bézier triangles,
/// prisms). Sources without a view pass. Returns the view with `outputs`, so that a plugin loaded
/// through the ABI can be compared with the same source linked statically.
pub fn check_view(
    source: &dyn ConstraintSource,
    name: &str,
    system: &api::ConstraintSystem,
    outputs: &[String],
) -> Result<Option<api::SourceView>, ConformanceError> {
    let bad = |problem: String| ConformanceError::BadView {
        name: name.to_string(),
        problem,
    };
    let ask = |outputs: &[String]| {
        let request = api::ViewRequest {
            schema: api::SCHEMA_VERSION,
            outputs: outputs.to_vec(),
        };
        no_panic(format!("view of {name:?}"), || source.view(&request))?
            .map_err(|e| bad(format!("refused: {}", e.message)))
    };
    let plain = ask(&[])?;
    let with_outputs = ask(outputs)?;
    match (plain, &with_outputs) {
        (None, None) => return Ok(None),
        // Any kind (Bézier triangles, prisms): models only from outputs, and the rest of the
        // view (its kind included) the same with and without them.
        (Some(plain), Some(view)) => {
            if !plain.models().is_empty() {
                return Err(bad(format!(
                    "it has models ({}) although the request names no outputs",
                    plain.models().len()
                )));
            }
            let mut rest = view.clone();
            rest.models_mut().clear();
            if rest != plain {
                return Err(bad(format!(
                    "the outputs {outputs:?} change more than its models"
                )));
            }
        }
        (Some(_), None) => {
            return Err(bad(format!(
                "it has a view without outputs but none with the outputs {outputs:?}"
            )))
        }
        (None, Some(_)) => {
            return Err(bad(format!(
                "it has a view with the outputs {outputs:?} but none without"
            )))
        }
    }
    if let Some(view) = &with_outputs {
        view.validate(system).map_err(bad)?;
    }
    Ok(with_outputs)
}

/// The outputs of `outputs` that `source` accepts in its check (`check_output` answers with
/// files), checked with the build request's base directory and input limit, as a host checks
/// the outputs it later names in a view request.
fn accepted_outputs(
    source: &dyn ConstraintSource,
    request: &BuildRequest,
    outputs: &[String],
) -> Result<Vec<String>, ConformanceError> {
    let mut accepted = Vec::new();
    for output in outputs {
        let check = OutputCheckRequest {
            schema: api::SCHEMA_VERSION,
            output: output.clone(),
            base_dir: request.base_dir.clone(),
            input_limit: request.input_limit,
        };
        let call = format!("check of {:?} for the output {output:?}", request.name);
        if no_panic(call, || source.check_output(&check))?.is_ok() {
            accepted.push(output.clone());
        }
    }
    Ok(accepted)
}

/// Builds `request` on two fresh instances and checks both contributions
/// ([`check_build`]) and that they are identical.
pub fn check_deterministic(
    first: &mut dyn ConstraintSource,
    second: &mut dyn ConstraintSource,
    request: &BuildRequest,
) -> Result<Contribution, ConformanceError> {
    let a = check_build(first, request)?;
    let b = check_build(second, request)?;
    if let Some(difference) = first_difference(&a, &b) {
        return Err(ConformanceError::NotDeterministic {
            name: request.name.clone(),
            difference,
        });
    }
    Ok(a)
}

/// The first place two contributions differ, in words.
fn first_difference(a: &Contribution, b: &Contribution) -> Option<String> {
    if a == b {
        return None;
    }
    fn list<T: PartialEq + std::fmt::Debug>(what: &str, a: &[T], b: &[T]) -> Option<String> {
        if a.len() != b.len() {
            return Some(format!("{} vs {} {what}", a.len(), b.len()));
        }
        a.iter()
            .zip(b)
            .position(|(x, y)| x != y)
            .map(|i| format!("{what} #{i}: {:?} vs {:?}", a[i], b[i]))
    }
    list("parameters", &a.parameters, &b.parameters)
        .or_else(|| list("rows", &a.rows, &b.rows))
        .or_else(|| list("summary items", &a.summary, &b.summary))
        .or_else(|| list("warnings", &a.warnings, &b.warnings))
}

/// Builds `request` expecting a refusal: an error whose message names the instance, and no
/// panic. Returns the message.
pub fn check_refuses(
    source: &mut dyn ConstraintSource,
    request: &BuildRequest,
) -> Result<String, ConformanceError> {
    let call = format!("build of {:?}", request.name);
    match no_panic(call.clone(), || source.build(request))? {
        Ok(_) => Err(ConformanceError::AcceptedBadConfig {
            name: request.name.clone(),
            config: request.config.clone(),
        }),
        Err(e) => {
            check_message(&call, Some(&request.name), &e.message)?;
            Ok(e.message)
        }
    }
}

/// Plans each operation and renders each output on a built source over `system`/`values` (the
/// system with its contribution applied). Answers must be well formed, refusals must have a
/// message, and nothing may panic.
pub fn check_plan_and_render(
    source: &dyn ConstraintSource,
    name: &str,
    system: &ConstraintSystem,
    values: &Values,
    operations: &[String],
    outputs: &[String],
) -> Result<(), ConformanceError> {
    for operation in operations {
        let call = format!("check of {name:?} for the operation {operation:?}");
        let check = OperationCheckRequest {
            schema: api::SCHEMA_VERSION,
            operation: operation.clone(),
        };
        if let Err(e) = no_panic(call.clone(), || source.check_operation(&check))? {
            check_message(&call, None, &e.message)?;
        }
        let call = format!("plan of {name:?} for {operation:?}");
        let request = PlanRequest {
            schema: api::SCHEMA_VERSION,
            operation: operation.clone(),
            system: system.clone(),
            values: values.clone(),
        };
        match no_panic(call.clone(), || source.plan(&request))? {
            Ok(plan) => check_plan(name, operation, system, &plan)?,
            Err(e) => check_message(&call, None, &e.message)?,
        }
    }
    for output in outputs {
        let call = format!("check of {name:?} for the output {output:?}");
        let check = OutputCheckRequest {
            schema: api::SCHEMA_VERSION,
            output: output.clone(),
            base_dir: ".".into(),
            input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
        };
        let announced = match no_panic(call.clone(), || source.check_output(&check))? {
            Ok(check) => check.checked.then_some(check.files),
            Err(e) => {
                check_message(&call, None, &e.message)?;
                None
            }
        };
        let call = format!("render of {name:?} for {output:?}");
        let request = RenderRequest {
            schema: api::SCHEMA_VERSION,
            output: output.clone(),
            base_dir: ".".into(),
            system: system.clone(),
            initial: values.clone(),
            values: values.clone(),
            highlight: None,
            structure: None,
            input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
        };
        match no_panic(call.clone(), || source.render(&request))? {
            Ok(files) => {
                let names: Vec<String> = files.iter().map(|f| f.name.clone()).collect();
                for file in files {
                    if file.name.is_empty()
                        || file.name.contains(['/', '\\'])
                        || file.name.starts_with('.')
                    {
                        return Err(ConformanceError::BadFileName {
                            name: name.to_string(),
                            output: output.clone(),
                            file: file.name,
                        });
                    }
                    if let Some(note) = file
                        .notes
                        .iter()
                        .find(|n| n.trim().is_empty() || n.contains(['\n', '\r']))
                    {
                        return Err(ConformanceError::BadNote {
                            name: name.to_string(),
                            output: output.clone(),
                            file: file.name.clone(),
                            note: note.clone(),
                        });
                    }
                }
                if let Some(announced) = announced.filter(|a| *a != names) {
                    return Err(ConformanceError::UnannouncedFiles {
                        name: name.to_string(),
                        output: output.clone(),
                        announced,
                        rendered: names,
                    });
                }
            }
            Err(e) => check_message(&call, None, &e.message)?,
        }
    }
    Ok(())
}

fn check_plan(
    name: &str,
    operation: &str,
    system: &ConstraintSystem,
    plan: &OperationPlan,
) -> Result<(), ConformanceError> {
    plan.validate(system)
        .map_err(|problem| ConformanceError::BadPlan {
            name: name.to_string(),
            operation: operation.to_string(),
            problem,
        })
}

/// Runs every check on the samples, with fresh instances from `make`:
///
/// * kind and version are non-empty and the same for every instance;
/// * each good request builds identically on two instances ([`check_deterministic`]), and the
///   first instance then plans [`Samples::operations`] and renders [`Samples::outputs`]
///   ([`check_plan_and_render`]) and gives a view that can be drawn, if any, asked without
///   outputs and with the sample outputs its `check_output` accepts ([`check_view`]);
/// * each bad request is refused ([`check_refuses`]).
///
/// Returns the contributions of the good requests, in order. For a dynamic plugin, `make` is
/// `|| Box::new(plugin.instantiate())`.
pub fn check_source(
    make: &mut dyn FnMut() -> Box<dyn ConstraintSource>,
    samples: &Samples,
) -> Result<Vec<Contribution>, ConformanceError> {
    let mut make = {
        let constructor = make;
        move || no_panic("the constructor".to_string(), &mut *constructor)
    };
    let reference = make()?;
    let (kind, version) = (
        reference.kind().to_string(),
        reference.version().to_string(),
    );
    if kind.trim().is_empty() || version.trim().is_empty() {
        return Err(ConformanceError::Identity {
            problem: format!("kind {kind:?} and version {version:?} must not be empty"),
        });
    }
    let same_identity = |source: &dyn ConstraintSource| {
        if source.kind() == kind && source.version() == version {
            Ok(())
        } else {
            Err(ConformanceError::Identity {
                problem: format!(
                    "one instance is {kind:?} {version:?}, another {:?} {:?}",
                    source.kind(),
                    source.version()
                ),
            })
        }
    };
    let mut contributions = Vec::with_capacity(samples.good.len());
    for request in &samples.good {
        let mut first = make()?;
        let mut second = make()?;
        same_identity(first.as_ref())?;
        same_identity(second.as_ref())?;
        let contribution = check_deterministic(first.as_mut(), second.as_mut(), request)?;
        let (system, values) = check_contribution(
            &request.name,
            &contribution,
            &request.system,
            &request.values,
        )?;
        check_plan_and_render(
            first.as_ref(),
            &request.name,
            &system,
            &values,
            &samples.operations,
            &samples.outputs,
        )?;
        let outputs = accepted_outputs(first.as_ref(), request, &samples.outputs)?;
        check_view(first.as_ref(), &request.name, &system, &outputs)?;
        contributions.push(contribution);
    }
    for request in &samples.bad {
        let mut source = make()?;
        same_identity(source.as_ref())?;
        check_refuses(source.as_mut(), request)?;
    }
    Ok(contributions)
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::{ConstraintRow, Origin, ParamId, RowBody};
    use api::{NewParameter, OutputCheck, OutputFile, SourceError, SummaryItem};

    /// A source whose misbehaviour is chosen by its configuration text.
    #[derive(Default)]
    struct Fixture {
        calls: usize,
        /// Built with `"view"`: gives a view whose point is the scalar `f.x`; with `"stray"`
        /// that view has a model even when no outputs are named; with `"shifty"` its
        /// smoothness depends on the outputs. With `"prisms"`: a valid prism view whose
        /// heights are `f.x`; `"upside"` the same with its layer upside down; `"switch"` a
        /// Bézier view without outputs and a prism view with them.
        view: String,
    }

    impl ConstraintSource for Fixture {
        fn kind(&self) -> &str {
            "fixture"
        }
        fn version(&self) -> &str {
            "0.1.0"
        }
        fn build(&mut self, request: &BuildRequest) -> Result<Contribution, SourceError> {
            self.calls += 1;
            let name = &request.name;
            let param = |n: &str| NewParameter {
                name: n.to_string(),
                value: vec![api::exact::Rational::from_integer(0.into())],
            };
            let row = |label: String, source: &str, id: u32| ConstraintRow {
                label,
                origin: Origin {
                    source: source.to_string(),
                    item: "x".into(),
                },
                body: RowBody::Vector {
                    terms: vec![(ParamId(id), 1.into())],
                    rhs: vec![0.into()],
                },
            };
            let good = Contribution {
                parameters: vec![param(&format!("{name}.x"))],
                rows: vec![row(format!("{name}: x = 0"), name, 0)],
                summary: vec![SummaryItem {
                    key: "rows".into(),
                    value: 1,
                }],
                ..Contribution::default()
            };
            self.view = request.config.clone();
            match request.config.as_str() {
                "good" | "view" | "stray" | "shifty" | "prisms" | "upside" | "switch" => Ok(good),
                "panic" => panic!("fixture panics"),
                "refuse" => Err(SourceError::new(format!("{name}: refused"))),
                "mute" => Err(SourceError::new("")),
                "unprefixed" => Ok(Contribution {
                    parameters: vec![param("x")],
                    ..good
                }),
                "label" => Ok(Contribution {
                    rows: vec![row("x = 0".into(), name, 0)],
                    ..good
                }),
                "origin" => Ok(Contribution {
                    rows: vec![row(format!("{name}: x = 0"), "other", 0)],
                    ..good
                }),
                "key" => Ok(Contribution {
                    summary: vec![SummaryItem {
                        key: "Control Points".into(),
                        value: 1,
                    }],
                    ..good
                }),
                "twice" => Ok(Contribution {
                    summary: vec![good.summary[0].clone(), good.summary[0].clone()],
                    ..good
                }),
                "dangling" => Ok(Contribution {
                    rows: vec![row(format!("{name}: x = 0"), name, 7)],
                    ..good
                }),
                "counter" => Ok(Contribution {
                    summary: vec![SummaryItem {
                        key: "calls".into(),
                        value: COUNTER.fetch_add(1, std::sync::atomic::Ordering::SeqCst),
                    }],
                    ..good
                }),
                _ => Err(SourceError::new(format!("{name}: unknown test config"))),
            }
        }
        fn plan(&self, request: &PlanRequest) -> Result<OperationPlan, SourceError> {
            match request.operation.as_str() {
                "panic" => panic!("plan panics"),
                "dangling" => Ok(OperationPlan {
                    anchors: vec![ParamId(9)],
                    derived: vec![],
                    weights: vec![],
                    strong: false,
                    steps: vec![],
                    summary: vec![],
                }),
                _ => Err(SourceError::new("fixture: no operations")),
            }
        }
        fn render(&self, request: &RenderRequest) -> Result<Vec<OutputFile>, SourceError> {
            match request.output.as_str() {
                "escape" => Ok(vec![OutputFile::new("../x.svg", vec![])]),
                "note" => Ok(vec![
                    OutputFile::new("x.svg", vec![]).with_note("two\nlines")
                ]),
                "other" => Ok(vec![OutputFile::new("y.svg", vec![])]),
                _ => Ok(vec![OutputFile::new("x.svg", vec![]).with_note("fine")]),
            }
        }
        fn check_operation(&self, request: &OperationCheckRequest) -> Result<(), SourceError> {
            match request.operation.as_str() {
                "check panics" => panic!("check panics"),
                _ => Err(SourceError::new("fixture: no operations")),
            }
        }
        fn check_output(&self, _: &OutputCheckRequest) -> Result<OutputCheck, SourceError> {
            Ok(OutputCheck::new(vec!["x.svg".into()], vec![]))
        }
        fn view(&self, request: &api::ViewRequest) -> Result<Option<api::SourceView>, SourceError> {
            let q = |n: i64| api::Rational::from_integer(n.into());
            let mode = self.view.as_str();
            if !["view", "stray", "shifty", "prisms", "upside", "switch"].contains(&mode) {
                return Ok(None);
            }
            let prisms = matches!(mode, "prisms" | "upside")
                || (mode == "switch" && !request.outputs.is_empty());
            let models = if mode == "stray" || !request.outputs.is_empty() {
                vec![api::ViewModel {
                    name: "m.obj".into(),
                    vertices: vec![[0.0; 3]],
                    faces: Vec::new(),
                    embedding: vec![None],
                    relative_height: if prisms { vec![0.5] } else { Vec::new() },
                }]
            } else {
                Vec::new()
            };
            if prisms {
                let (bottom, top) = if mode == "upside" { (1, -1) } else { (-1, 1) };
                return Ok(Some(api::SourceView::Prisms(api::Prisms {
                    degree: 1,
                    smoothness: 0,
                    vertices: vec![[q(0), q(0)], [q(1), q(0)], [q(0), q(1)]],
                    triangles: vec![[0, 1, 2]],
                    bottom: vec![vec![ParamId(0); 3]],
                    top: vec![vec![ParamId(0); 3]],
                    xy: None,
                    reference_bottom: q(bottom),
                    reference_top: q(top),
                    models,
                })));
            }
            Ok(Some(api::SourceView::BezierTriangles(
                api::BezierTriangles {
                    degree: 1,
                    smoothness: usize::from(mode == "shifty" && !request.outputs.is_empty()),
                    vertices: vec![[q(0), q(0)], [q(1), q(0)], [q(0), q(1)]],
                    triangles: vec![[0, 1, 2]],
                    patches: vec![vec![ParamId(0); 3]],
                    models,
                },
            )))
        }
    }

    static COUNTER: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

    fn samples(good: &[&str], bad: &[&str]) -> Samples {
        Samples {
            good: good.iter().map(|c| request("f", c)).collect(),
            bad: bad.iter().map(|c| request("f", c)).collect(),
            operations: vec!["(move: 1)".into()],
            outputs: vec!["(picture: \"x.svg\")".into()],
        }
    }

    fn check(good: &[&str], bad: &[&str]) -> Result<Vec<Contribution>, ConformanceError> {
        check_source(&mut || Box::new(Fixture::default()), &samples(good, bad))
    }

    #[test]
    fn a_conforming_prism_view_passes() {
        check(&["prisms"], &[]).expect("a prism view of heights conforms");
    }

    #[test]
    fn a_conforming_source_passes() {
        let contributions = check(&["good"], &["refuse", "whatever"]).expect("conforms");
        assert_eq!(contributions.len(), 1);
        assert_eq!(contributions[0].parameters[0].name, "f.x");
    }

    #[test]
    fn each_broken_rule_is_named() {
        let cases: &[(&[&str], &[&str], &str)] = &[
            (&["panic"], &[], "panicked: fixture panics"),
            (
                &["view"],
                &[],
                "view of \"f\" cannot be drawn: the view's patch 0 names \"f.x\" of dimension 1",
            ),
            (
                &["stray"],
                &[],
                "view of \"f\" cannot be drawn: it has models (1) although the request names no outputs",
            ),
            (
                &["shifty"],
                &[],
                "view of \"f\" cannot be drawn: the outputs [\"(picture: \\\"x.svg\\\")\"] change more than its models",
            ),
            (
                &["switch"],
                &[],
                "view of \"f\" cannot be drawn: the outputs [\"(picture: \\\"x.svg\\\")\"] change more than its models",
            ),
            (
                &["upside"],
                &[],
                "view of \"f\" cannot be drawn: the view's reference layer is empty: its bottom 1 is not below its top -1",
            ),
            (&[], &["panic"], "panicked"),
            (&["refuse"], &[], "refused a good configuration"),
            (&[], &["good"], "accepted a bad configuration"),
            (&[], &["mute"], "is empty"),
            (&["unprefixed"], &[], "parameter \"x\""),
            (&["label"], &[], "row label"),
            (&["origin"], &[], "row origin"),
            (&["key"], &[], "not snake_case"),
            (&["twice"], &[], "given twice"),
            (&["dangling"], &[], "does not apply"),
            (&["counter"], &[], "differently: summary items #0"),
        ];
        for (good, bad, needle) in cases {
            let error = check(good, bad).expect_err(needle).to_string();
            assert!(error.contains(needle), "{needle}: {error}");
        }
        // Plan and render answers are checked too.
        let mut source = Fixture::default();
        let built = check_build(&mut source, &request("f", "good")).expect("builds");
        let (system, values) =
            check_contribution("f", &built, &ConstraintSystem::new(), &Values::default())
                .expect("applies");
        for (operation, output, needle) in [
            ("panic", "x", "plan of \"f\" for \"panic\" panicked"),
            ("dangling", "x", "which does not exist"),
            (
                "check panics",
                "x",
                "check of \"f\" for the operation \"check panics\" panicked",
            ),
            ("x", "other", "but its check announced [\"x.svg\"]"),
            ("x", "escape", "\"../x.svg\""),
            ("x", "note", "notes must be one non-blank line"),
        ] {
            let error = check_plan_and_render(
                &source,
                "f",
                &system,
                &values,
                &[operation.into()],
                &[output.into()],
            )
            .expect_err(needle)
            .to_string();
            assert!(error.contains(needle), "{needle}: {error}");
        }
    }

    #[test]
    fn snake_case_keys() {
        for good in ["control_points", "c2_conditions", "x"] {
            assert!(is_snake_case(good), "{good}");
        }
        for bad in [
            "",
            "Control",
            "control-points",
            "_x",
            "x_",
            "a__b",
            "2d",
            "a b",
        ] {
            assert!(!is_snake_case(bad), "{bad}");
        }
    }
}
