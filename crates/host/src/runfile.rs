//! The RON run file: which sources to load, which backend settings, which edits to run and
//! which outputs to write. Unknown fields are errors; every error names the file and the line
//! and column.
//!
//! ```ron
//! (
//!     sources: [
//!         (name: "phi", plugin: "spline2d", config: (mesh: "meshes/worm.obj", degree: 5)),
//!         (name: "eq", plugin: "linear", config: (parameters: {"a": "1"}, equations: [])),
//!         (name: "c2", plugin: "plugins/plugins_c2", config: (spline: "phi")), // libplugins_c2.so on Linux
//!     ],
//!     backend: (simplify: Gcd),             // Gcd (default), Turner or None
//!     cross_check: (tolerance: 1e-10),      // default; None turns the float backend off
//!     edits: [
//!         Ecles(anchors: {"eq.a": "2"}, derived: ["eq.b"]),
//!         Source(source: "phi", operation: (anchors: ["v4"], translate: ("1", "0"))),
//!     ],
//!     outputs: [(source: "phi", output: (picture: "worm.svg"))],
//! )
//! ```

use api::exact::Exact;
use ron::value::RawValue;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

/// A whole run file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunFile {
    /// Constraint sources, built in this order (a later source may constrain an earlier one's
    /// parameters).
    pub sources: Vec<SourceEntry>,
    /// Exact backend settings.
    #[serde(default)]
    pub backend: BackendConfig,
    /// Float cross-check settings; `None` turns it off.
    #[serde(default = "default_cross_check")]
    pub cross_check: Option<CrossCheckConfig>,
    /// Edits, run in order.
    #[serde(default)]
    pub edits: Vec<EditEntry>,
    /// Outputs rendered by sources after the edits.
    #[serde(default)]
    pub outputs: Vec<OutputEntry>,
}

/// One constraint source.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SourceEntry {
    /// Instance name, unique in the run: prefix of its parameter names and row labels.
    pub name: String,
    /// A built-in kind (`"linear"`, `"spline2d"`) or the path of a dynamic plugin library
    /// (relative to the run file; without an extension, the platform's library file name,
    /// see [`crate::registry::library_path`]).
    pub plugin: String,
    /// The plugin's configuration (its own schema), kept as the text written in the run file.
    #[serde(default = "empty_config")]
    pub config: Box<RawValue>,
}

fn empty_config() -> Box<RawValue> {
    RawValue::from_boxed_ron("()".into()).unwrap_or_else(|_| unreachable!("\"()\" is RON"))
}

/// Simplification method of the exact factoring.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
pub enum Simplify {
    /// GCD simplification (default).
    #[default]
    Gcd,
    /// Turner's GCD-free simplification.
    Turner,
    /// No simplification (exponential growth; for comparison only).
    None,
}

/// Exact backend settings.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BackendConfig {
    /// Simplification method.
    #[serde(default)]
    pub simplify: Simplify,
}

/// Float cross-check settings.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrossCheckConfig {
    /// Relative tolerance of the float backend's rank decisions and of value comparisons.
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
}

fn default_tolerance() -> f64 {
    float_qr::DEFAULT_TOLERANCE
}

fn default_cross_check() -> Option<CrossCheckConfig> {
    Some(CrossCheckConfig {
        tolerance: default_tolerance(),
    })
}

/// A value of a parameter: one number for a scalar, a list for a vector parameter.
#[derive(Debug, Clone)]
pub enum ValueText {
    /// A scalar.
    Scalar(Exact),
    /// A vector.
    Vector(Vec<Exact>),
}

impl<'de> Deserialize<'de> for ValueText {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ValueVisitor;
        impl<'de> serde::de::Visitor<'de> for ValueVisitor {
            type Value = ValueText;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("an exact number (\"7/3\", \"0.1\", 3) or a list of them")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<ValueText, E> {
                api::parse_rational(v)
                    .map(|r| ValueText::Scalar(Exact(r)))
                    .map_err(E::custom)
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<ValueText, E> {
                Ok(ValueText::Scalar(Exact(api::Rational::from_integer(
                    v.into(),
                ))))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<ValueText, E> {
                Ok(ValueText::Scalar(Exact(api::Rational::from_integer(
                    v.into(),
                ))))
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<ValueText, E> {
                Err(E::custom(format!(
                    "{v} is a floating-point literal; write exact numbers as strings, e.g. \"{v}\""
                )))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<ValueText, A::Error> {
                let mut out = Vec::new();
                while let Some(e) = seq.next_element::<Exact>()? {
                    out.push(e);
                }
                Ok(ValueText::Vector(out))
            }
        }
        deserializer.deserialize_any(ValueVisitor)
    }
}

impl ValueText {
    /// The coordinates.
    pub fn coordinates(&self) -> Vec<api::Rational> {
        match self {
            ValueText::Scalar(e) => vec![e.0.clone()],
            ValueText::Vector(v) => v.iter().map(|e| e.0.clone()).collect(),
        }
    }
}

/// An edit.
#[derive(Debug, Clone, Deserialize)]
pub enum EditEntry {
    /// A generic ECLES edit on named parameters.
    Ecles {
        /// Anchors and their required new values.
        anchors: BTreeMap<String, ValueText>,
        /// Derived parameters.
        #[serde(default)]
        derived: Vec<String>,
        /// Hints for derived parameters (default: their current values).
        #[serde(default)]
        hints: BTreeMap<String, ValueText>,
        /// Weights of derived parameters (default 1).
        #[serde(default)]
        weights: BTreeMap<String, Exact>,
        /// Check strong solvability at initialisation.
        #[serde(default)]
        strong: bool,
    },
    /// An operation planned by a source (a spline's soft translation, ...).
    Source {
        /// The source instance.
        source: String,
        /// The operation, in the source's own schema (text as written).
        operation: Box<RawValue>,
    },
}

/// An output rendered by a source.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputEntry {
    /// The source instance.
    pub source: String,
    /// What to render, in the source's own schema (text as written).
    pub output: Box<RawValue>,
}

/// Why a run file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum RunFileError {
    /// The file could not be read.
    #[error("{path}: cannot read the run file: {message}")]
    Io {
        /// The file.
        path: String,
        /// The I/O error.
        message: String,
    },
    /// RON syntax or schema error with its position.
    #[error("{path}:{line}:{column}: {message}")]
    Syntax {
        /// The file.
        path: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The parser's message.
        message: String,
    },
    /// The file parsed but is inconsistent (duplicate source name, unknown source...).
    #[error("{path}: {message}")]
    Invalid {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
}

/// RON options for run files: `Some(..)` may be omitted around present optional values.
fn ron_options() -> ron::Options {
    ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
}

/// Reads and checks a run file.
pub fn read(path: &Path) -> Result<RunFile, RunFileError> {
    let text = std::fs::read_to_string(path).map_err(|e| RunFileError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    parse(&text, &path.display().to_string())
}

/// Parses and checks run-file text (`name` is used in messages).
pub fn parse(text: &str, name: &str) -> Result<RunFile, RunFileError> {
    let run: RunFile = ron_options()
        .from_str(text)
        .map_err(|e| RunFileError::Syntax {
            path: name.to_string(),
            line: e.position.line,
            column: e.position.col,
            message: e.code.to_string(),
        })?;
    let invalid = |message: String| RunFileError::Invalid {
        path: name.to_string(),
        message,
    };
    let mut seen = std::collections::BTreeSet::new();
    for s in &run.sources {
        if s.name.is_empty() || s.name.contains(char::is_whitespace) {
            return Err(invalid(format!(
                "source name {:?} must be non-empty and without spaces",
                s.name
            )));
        }
        if !seen.insert(s.name.clone()) {
            return Err(invalid(format!("two sources are named {:?}", s.name)));
        }
    }
    let known = |source: &str| seen.contains(source);
    for (i, edit) in run.edits.iter().enumerate() {
        if let EditEntry::Source { source, .. } = edit {
            if !known(source) {
                return Err(invalid(format!("edit {i} names unknown source {source:?}")));
            }
        }
    }
    for (i, out) in run.outputs.iter().enumerate() {
        if !known(&out.source) {
            return Err(invalid(format!(
                "output {i} names unknown source {:?}",
                out.source
            )));
        }
    }
    if let Some(cc) = &run.cross_check {
        if !(cc.tolerance > 0.0 && cc.tolerance < 1.0) {
            return Err(invalid(format!(
                "cross_check tolerance {} must be between 0 and 1",
                cc.tolerance
            )));
        }
    }
    Ok(run)
}

/// The RON text of a plugin configuration, operation or output, as written in the run file:
/// sources parse it with their own schema.
pub fn to_ron_text(value: &RawValue) -> String {
    value.trim().get_ron().to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_full_run_file() {
        let run = parse(
            r#"(
                sources: [(name: "eq", plugin: "linear", config: (parameters: {"a": "1"}))],
                backend: (simplify: Turner),
                cross_check: (tolerance: 1e-8),
                edits: [
                    Ecles(anchors: {"eq.a": "2"}, derived: ["eq.b"], weights: {"eq.b": "1/2"}),
                    Source(source: "eq", operation: (anything: 1)),
                ],
                outputs: [(source: "eq", output: (picture: "x.svg"))],
            )"#,
            "run.ron",
        )
        .expect("valid");
        assert_eq!(run.backend.simplify, Simplify::Turner);
        assert_eq!(run.cross_check.map(|c| c.tolerance), Some(1e-8));
        assert_eq!(run.edits.len(), 2);
        let off = parse(r#"(sources: [], cross_check: None)"#, "run.ron").expect("valid");
        assert!(off.cross_check.is_none());
        let default = parse(r#"(sources: [])"#, "run.ron").expect("valid");
        assert!(default.cross_check.is_some());
    }

    #[test]
    fn errors_name_the_position() {
        let err = parse("(\n  sources: [],\n  edist: [],\n)", "run.ron").expect_err("typo");
        let text = err.to_string();
        assert!(text.starts_with("run.ron:3:"), "{text}");
        assert!(text.contains("edist"), "{text}");
        let err = parse(
            "(sources: [(name: \"a\", plugin: \"linear\"), (name: \"a\", plugin: \"linear\")])",
            "r.ron",
        )
        .expect_err("duplicate");
        assert!(err.to_string().contains("two sources"), "{err}");
        let err = parse(
            "(sources: [], edits: [Source(source: \"zz\", operation: ())])",
            "r.ron",
        )
        .expect_err("unknown source");
        assert!(err.to_string().contains("zz"), "{err}");
        let err = parse(
            "(sources: [], edits: [Ecles(anchors: {\"a\": 0.1})])",
            "r.ron",
        )
        .expect_err("float value");
        assert!(err.to_string().contains("r.ron:1:"), "{err}");
    }
}
