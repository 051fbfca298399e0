//! The RON run file: which sources to load, which backend settings, which edits to run and
//! which outputs to write. Unknown fields and duplicate keys are errors at every level; every
//! error names the file and the line and column *of the run file*, also for errors a source
//! finds in its own fragment (see [`Fragment`]).
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
//!         // Another change criterion (L2 by default, L1, Fewest), on primary parameters first.
//!         Ecles(anchors: {"eq.a": "3"}, derived: ["eq.b"], criterion: L1, primary: ["eq.b"]),
//!         Source(source: "phi", operation: (anchors: ["v4"], translate: ("1", "0"))),
//!         // From here on, "phi" is built with this configuration (C0); values carried over.
//!         Configure(source: "phi", config: (mesh: "meshes/worm.obj", degree: 5, smoothness: 0)),
//!     ],
//!     outputs: [(source: "phi", output: (picture: "worm.svg"))],
//!     editor: (image: (file: "photo.png", opacity: "1/2")), // for `ecles edit`, optional
//! )
//! ```
//!
//! Reading happens in two passes over one text: the file is parsed with every source entry,
//! edit and output kept as a borrowed [`RawValue`] slice of the text, then each of those is
//! parsed on its own. A slice's offset in the text gives its position, so errors inside it,
//! and errors a source reports inside its configuration, operation or output fragment, are
//! translated into run-file coordinates.

use api::config::{from_ron, ron_options, unique_map, TextPosition};
use api::exact::Exact;
use api::input::{read_text_file, InputFileError};
use api::Rational;
use api::SourceError;
use ron::value::RawValue;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

/// Most edits a run file may hold (each is validated and run in turn).
pub const MAX_EDITS: usize = 100_000;

/// Most outputs a run file may hold.
pub const MAX_OUTPUTS: usize = 1_000;

/// Most sources a run file may hold.
pub const MAX_SOURCES: usize = 1_000;

/// A piece of the run file forwarded to a source as written (a configuration, an operation,
/// an output request), with where it is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Fragment {
    /// The RON text, exactly as in the run file (leading whitespace and comments included).
    text: String,
    /// Position of the text's first character in the run file.
    origin: TextPosition,
}

impl Fragment {
    /// A fragment starting at `origin` of its file.
    pub fn new(text: impl Into<String>, origin: TextPosition) -> Self {
        Fragment {
            text: text.into(),
            origin,
        }
    }

    /// The RON text forwarded to the source.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// Where the fragment's value begins in the run file (after leading whitespace).
    pub fn start(&self) -> TextPosition {
        let skipped = self.text.len() - self.text.trim_start().len();
        TextPosition::after(&self.text[..skipped]).within(self.origin)
    }

    /// A position inside the fragment's text as a run-file position; the fragment's start
    /// when the source gave none.
    pub fn locate(&self, inner: Option<TextPosition>) -> TextPosition {
        match inner {
            Some(at) => at.within(self.origin),
            None => self.start(),
        }
    }
}

/// A whole run file.
#[derive(Debug, Clone)]
pub struct RunFile {
    /// Constraint sources, built in this order (a later source may constrain an earlier one's
    /// parameters).
    pub sources: Vec<SourceEntry>,
    /// Exact backend settings.
    pub backend: BackendConfig,
    /// Float cross-check settings; `None` turns it off.
    pub cross_check: Option<CrossCheckConfig>,
    /// What an edit commits, when the run file says: the exact least-squares optimum or a
    /// snapped point ([`RunFile::commit_policy`] is what applies).
    pub commit: Option<CommitPolicy>,
    /// Edits, run in order.
    pub edits: Vec<EditEntry>,
    /// Outputs rendered by sources after the edits.
    pub outputs: Vec<OutputEntry>,
    /// Settings of the interactive editor (`ecles edit`), with their text as written.
    pub editor: Option<(EditorConfig, String)>,
}

/// What `ecles edit` shows besides the sources (`editor: (image: (file: "photo.png"))`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EditorConfig {
    /// A target image drawn behind the sources.
    #[serde(default)]
    pub image: Option<TargetImage>,
}

/// A PNG or JPEG drawn behind the sources in the editor, to edit towards.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, try_from = "RawTargetImage")]
pub struct TargetImage {
    /// The image file, relative to the run file.
    pub file: String,
    /// Opacity in [0, 1] (default 1/2).
    pub opacity: Rational,
    /// Model coordinates of the image's top-left corner (default (0, 0)).
    pub position: [Rational; 2],
    /// Model units per image pixel, positive (default 1).
    pub units_per_pixel: Rational,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTargetImage {
    file: String,
    #[serde(default)]
    opacity: Option<Exact>,
    #[serde(default)]
    position: Option<(Exact, Exact)>,
    #[serde(default)]
    units_per_pixel: Option<Exact>,
}

impl TryFrom<RawTargetImage> for TargetImage {
    type Error = String;
    fn try_from(raw: RawTargetImage) -> Result<Self, String> {
        let zero = Rational::from_integer(0.into());
        let one = Rational::from_integer(1.into());
        let opacity = raw
            .opacity
            .map_or_else(|| Rational::new(1.into(), 2.into()), |e| e.0);
        if opacity < zero || opacity > one {
            return Err(format!("image opacity {opacity} must be between 0 and 1"));
        }
        let units_per_pixel = raw.units_per_pixel.map_or(one, |e| e.0);
        if units_per_pixel <= zero {
            return Err(format!(
                "image units_per_pixel {units_per_pixel} must be positive"
            ));
        }
        let position = raw
            .position
            .map_or_else(|| [zero.clone(), zero.clone()], |(x, y)| [x.0, y.0]);
        Ok(TargetImage {
            file: raw.file,
            opacity,
            position,
            units_per_pixel,
        })
    }
}

/// One constraint source.
#[derive(Debug, Clone)]
pub struct SourceEntry {
    /// Instance name, unique in the run: prefix of its parameter names and row labels.
    pub name: String,
    /// A built-in kind (`"linear"`, `"spline2d"`) or the path of a dynamic plugin library
    /// (relative to the run file; without an extension, the platform's library file name,
    /// see [`crate::registry::library_path`]).
    pub plugin: String,
    /// The plugin's configuration (its own schema), as written (`()` when absent).
    pub config: Fragment,
    /// Where the entry starts.
    pub at: TextPosition,
    /// The whole entry's RON text as written (what a saved session repeats).
    pub text: String,
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

/// Largest grid of a snapped commit, in bits below the unit: `2^−256` is far below any
/// meaningful coordinate, and it bounds the size of committed values.
pub const MAX_GRID_BITS: u32 = 256;

/// What an edit commits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(try_from = "RawCommit")]
pub enum CommitPolicy {
    /// The exact least-squares optimum (the thesis' ECLES): its denominators grow with every
    /// edit of a session.
    #[default]
    Optimum,
    /// A point of the constraint set near the optimum with small denominators: free values on
    /// the grid `2^−grid_bits`, the others exact consequences of the constraints; every
    /// constraint holds exactly, the report gives a proved bound on the distance to the
    /// optimum. Sizes stay bounded over long sessions.
    Snapped {
        /// Free values are multiples of `2^−grid_bits` (1 ..= [`MAX_GRID_BITS`]).
        grid_bits: u32,
    },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
enum RawCommit {
    Optimum,
    Snapped { grid_bits: u32 },
}

impl TryFrom<RawCommit> for CommitPolicy {
    type Error = String;
    fn try_from(raw: RawCommit) -> Result<Self, String> {
        match raw {
            RawCommit::Optimum => Ok(CommitPolicy::Optimum),
            RawCommit::Snapped { grid_bits } if (1..=MAX_GRID_BITS).contains(&grid_bits) => {
                Ok(CommitPolicy::Snapped { grid_bits })
            }
            RawCommit::Snapped { grid_bits } => Err(format!(
                "commit grid_bits {grid_bits} must be between 1 and {MAX_GRID_BITS}"
            )),
        }
    }
}

/// Float cross-check settings.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields, try_from = "RawCrossCheck")]
pub struct CrossCheckConfig {
    /// Relative tolerance of the float backend's rank decisions and of value comparisons, in
    /// (0, 1).
    pub tolerance: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCrossCheck {
    #[serde(default = "default_tolerance")]
    tolerance: f64,
}

impl TryFrom<RawCrossCheck> for CrossCheckConfig {
    type Error = String;
    fn try_from(raw: RawCrossCheck) -> Result<Self, String> {
        if raw.tolerance > 0.0 && raw.tolerance < 1.0 {
            Ok(CrossCheckConfig {
                tolerance: raw.tolerance,
            })
        } else {
            Err(format!(
                "cross_check tolerance {} must be between 0 and 1",
                raw.tolerance
            ))
        }
    }
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
            fn visit_i128<E: serde::de::Error>(self, v: i128) -> Result<ValueText, E> {
                Ok(ValueText::Scalar(Exact(api::Rational::from_integer(
                    v.into(),
                ))))
            }
            fn visit_u128<E: serde::de::Error>(self, v: u128) -> Result<ValueText, E> {
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

/// A generic ECLES edit on named parameters.
#[derive(Debug, Clone)]
pub struct GenericEdit {
    /// Anchors and their required new values.
    pub anchors: BTreeMap<String, ValueText>,
    /// Derived parameters.
    pub derived: Vec<String>,
    /// Hints for derived parameters (default: their current values).
    pub hints: BTreeMap<String, ValueText>,
    /// Weights of derived parameters (default 1).
    pub weights: BTreeMap<String, Exact>,
    /// Check strong solvability at initialisation.
    pub strong: bool,
}

/// What an edit does.
#[derive(Debug, Clone)]
pub enum EditKind {
    /// A generic ECLES edit on named parameters.
    Ecles(GenericEdit),
    /// An operation planned by a source (a spline's soft translation, ...).
    Source {
        /// The source instance.
        source: String,
        /// The operation, in the source's own schema.
        operation: Fragment,
    },
    /// From this edit on, a source is built with another configuration (another continuity,
    /// another reference mesh); see [`crate::session::Session::configure`] for what becomes of
    /// the values.
    Configure {
        /// The source instance.
        source: String,
        /// Its new configuration, in the source's own schema.
        config: Fragment,
    },
}

/// What an edit minimises among the changes that keep every constraint (Brenner 3.1; see the
/// `criteria` crate).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, serde::Serialize)]
pub enum MeasureName {
    /// Weighted least squares (ECLES; the default).
    #[default]
    L2,
    /// Weighted sum of absolute changes.
    L1,
    /// Number of changed parameters.
    Fewest,
}

impl MeasureName {
    /// The criterion of this measure over every derived parameter.
    pub fn criterion(self) -> ecles::Criterion {
        ecles::Criterion {
            measure: self.measure(),
            primary: None,
        }
    }

    /// The measure the edit minimises.
    pub fn measure(self) -> ecles::Measure {
        match self {
            MeasureName::L2 => ecles::Measure::L2,
            MeasureName::L1 => ecles::Measure::L1,
            MeasureName::Fewest => ecles::Measure::Fewest,
        }
    }
}

/// The change criterion of an edit: `criterion: L1` and `primary: [...]` in the run file.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct CriterionChoice {
    /// What is minimised.
    pub measure: MeasureName,
    /// Parameters whose change is minimised first (empty: every derived parameter).
    pub primary: Vec<String>,
}

impl CriterionChoice {
    /// ECLES' own criterion (least squares on every derived parameter).
    pub fn is_least_squares(&self) -> bool {
        self.measure == MeasureName::L2 && self.primary.is_empty()
    }
}

/// An edit and where it is written.
#[derive(Debug, Clone)]
pub struct EditEntry {
    /// What it does.
    pub kind: EditKind,
    /// Its change criterion (generic edits and source operations).
    pub criterion: CriterionChoice,
    /// Where it starts in the run file.
    pub at: TextPosition,
    /// The whole entry's RON text as written (what a saved session repeats).
    pub text: String,
}

/// An output rendered by a source.
#[derive(Debug, Clone)]
pub struct OutputEntry {
    /// The source instance.
    pub source: String,
    /// What to render, in the source's own schema.
    pub output: Fragment,
    /// Where the entry starts.
    pub at: TextPosition,
    /// The whole entry's RON text as written (what a saved session repeats).
    pub text: String,
}

/// Why a run file could not be read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RunFileError {
    /// The file could not be read (missing, not a regular file, too large, binary).
    #[error("{0}")]
    Input(#[from] InputFileError),
    /// A syntax, schema or consistency error at a position of the file.
    #[error("{path}:{at}: {message}")]
    At {
        /// The file.
        path: String,
        /// Where.
        at: TextPosition,
        /// What is wrong.
        message: String,
    },
}

/// The top level, with every entry kept as a slice of the text.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRunFile<'a> {
    #[serde(borrow)]
    sources: Vec<&'a RawValue>,
    #[serde(default)]
    backend: BackendConfig,
    #[serde(default = "default_cross_check")]
    cross_check: Option<CrossCheckConfig>,
    #[serde(default)]
    commit: Option<CommitPolicy>,
    #[serde(borrow, default)]
    edits: Vec<&'a RawValue>,
    #[serde(borrow, default)]
    outputs: Vec<&'a RawValue>,
    #[serde(borrow, default)]
    editor: Option<&'a RawValue>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSource<'a> {
    name: String,
    plugin: String,
    #[serde(borrow, default)]
    config: Option<&'a RawValue>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
enum RawEdit<'a> {
    Ecles {
        #[serde(deserialize_with = "unique_map")]
        anchors: BTreeMap<String, ValueText>,
        #[serde(default)]
        derived: Vec<String>,
        #[serde(default, deserialize_with = "unique_map")]
        hints: BTreeMap<String, ValueText>,
        #[serde(default, deserialize_with = "unique_map")]
        weights: BTreeMap<String, Exact>,
        #[serde(default)]
        strong: bool,
        #[serde(default)]
        criterion: MeasureName,
        #[serde(default)]
        primary: Vec<String>,
    },
    Source {
        source: String,
        #[serde(borrow)]
        operation: &'a RawValue,
        #[serde(default)]
        criterion: MeasureName,
        #[serde(default)]
        primary: Vec<String>,
    },
    Configure {
        source: String,
        #[serde(borrow)]
        config: &'a RawValue,
    },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawOutput<'a> {
    source: String,
    #[serde(borrow)]
    output: &'a RawValue,
}

impl RunFile {
    /// What an edit of this run commits: as the run file says, else the exact optimum (the
    /// thesis' ECLES; `ecles edit` chooses its own default, see the editor).
    pub fn commit_policy(&self) -> CommitPolicy {
        self.commit.unwrap_or_default()
    }

    /// This run file's text with `edits` (whole entries, RON text) in place of its own edits:
    /// the same sources, backend, cross-check, commit policy and outputs, as written, after
    /// `comment` (lines of text, each written as a `//` comment). What an editor saves: reading
    /// the text back gives this run file with those edits.
    pub fn with_edits<'e>(
        &self,
        comment: &str,
        edits: impl IntoIterator<Item = &'e str>,
    ) -> String {
        // An entry as written may end in a `//` comment: its comma then goes on a line of its
        // own.
        let entry = |text: &str| {
            let last_line = text.lines().last().unwrap_or_default();
            if last_line.contains("//") {
                format!("        {text}\n        ,\n")
            } else {
                format!("        {text},\n")
            }
        };
        let mut out = String::new();
        for line in comment.lines() {
            out.push_str("// ");
            out.push_str(line);
            out.push('\n');
        }
        out.push_str("(\n    sources: [\n");
        for source in &self.sources {
            out.push_str(&entry(&source.text));
        }
        out.push_str("    ],\n");
        let simplify = match self.backend.simplify {
            Simplify::Gcd => "Gcd",
            Simplify::Turner => "Turner",
            Simplify::None => "None",
        };
        out.push_str(&format!("    backend: (simplify: {simplify}),\n"));
        match self.cross_check {
            // `{:?}` of an f64 is the shortest text that reads back as the same number.
            Some(c) => out.push_str(&format!(
                "    cross_check: (tolerance: {:?}),\n",
                c.tolerance
            )),
            None => out.push_str("    cross_check: None,\n"),
        }
        match self.commit_policy() {
            CommitPolicy::Optimum => out.push_str("    commit: Optimum,\n"),
            CommitPolicy::Snapped { grid_bits } => {
                out.push_str(&format!("    commit: Snapped(grid_bits: {grid_bits}),\n"))
            }
        }
        out.push_str("    edits: [\n");
        for edit in edits {
            out.push_str(&entry(edit));
        }
        out.push_str("    ],\n    outputs: [\n");
        for output in &self.outputs {
            out.push_str(&entry(&output.text));
        }
        out.push_str("    ],\n");
        if let Some((_, text)) = &self.editor {
            out.push_str(&format!("    editor: {}", entry(text).trim_start()));
        }
        out.push_str(")\n");
        out
    }
}

/// Reads and checks a run file of at most `limit` bytes.
pub fn read(path: &Path, limit: u64) -> Result<RunFile, RunFileError> {
    let text = read_text_file(path, "run file", limit)?;
    parse(&text, &path.display().to_string())
}

/// Parses and checks run-file text (`name` is used in messages). A UTF-8 byte order mark is
/// ignored.
pub fn parse(text: &str, name: &str) -> Result<RunFile, RunFileError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let reader = Reader { text, name };
    let raw: RawRunFile = ron_options().from_str(text).map_err(|e| RunFileError::At {
        path: name.to_string(),
        at: TextPosition {
            line: e.position.line,
            column: e.position.col,
        },
        message: e.code.to_string(),
    })?;
    for (what, count, max) in [
        ("sources", raw.sources.len(), MAX_SOURCES),
        ("edits", raw.edits.len(), MAX_EDITS),
        ("outputs", raw.outputs.len(), MAX_OUTPUTS),
    ] {
        if count > max {
            return Err(reader.error(
                TextPosition::START,
                format!("{count} {what}, more than the limit of {max}"),
            ));
        }
    }
    let mut sources: Vec<SourceEntry> = Vec::with_capacity(raw.sources.len());
    for value in &raw.sources {
        let entry: RawSource = reader.element(value)?;
        let at = reader.fragment(value).start();
        if entry.name.is_empty()
            || !entry
                .name
                .chars()
                .all(|c| c.is_alphanumeric() || "_-".contains(c))
        {
            return Err(reader.error(
                at,
                format!(
                    "source name {:?} must be non-empty and made of letters, digits, '_' and '-'",
                    entry.name
                ),
            ));
        }
        if sources.iter().any(|s| s.name == entry.name) {
            return Err(reader.error(at, format!("two sources are named {:?}", entry.name)));
        }
        let config = match entry.config {
            Some(config) => reader.fragment(config),
            None => Fragment::new("()", at),
        };
        sources.push(SourceEntry {
            name: entry.name,
            plugin: entry.plugin,
            config,
            at,
            text: value.get_ron().trim().to_string(),
        });
    }
    let known = |source: &str| sources.iter().any(|s| s.name == source);
    let mut edits = Vec::with_capacity(raw.edits.len());
    for (i, value) in raw.edits.iter().enumerate() {
        let at = reader.fragment(value).start();
        let mut criterion = CriterionChoice::default();
        let kind = match reader.element::<RawEdit>(value)? {
            RawEdit::Ecles {
                anchors,
                derived,
                hints,
                weights,
                strong,
                criterion: measure,
                primary,
            } => {
                criterion = CriterionChoice { measure, primary };
                EditKind::Ecles(GenericEdit {
                    anchors,
                    derived,
                    hints,
                    weights,
                    strong,
                })
            }
            RawEdit::Source {
                source,
                operation,
                criterion: measure,
                primary,
            } => {
                criterion = CriterionChoice { measure, primary };
                if !known(&source) {
                    return Err(
                        reader.error(at, format!("edit {i} names unknown source {source:?}"))
                    );
                }
                EditKind::Source {
                    source,
                    operation: reader.fragment(operation),
                }
            }
            RawEdit::Configure { source, config } => {
                if !known(&source) {
                    return Err(
                        reader.error(at, format!("edit {i} names unknown source {source:?}"))
                    );
                }
                EditKind::Configure {
                    source,
                    config: reader.fragment(config),
                }
            }
        };
        edits.push(EditEntry {
            kind,
            criterion,
            at,
            text: value.get_ron().trim().to_string(),
        });
    }
    let mut outputs = Vec::with_capacity(raw.outputs.len());
    for (i, value) in raw.outputs.iter().enumerate() {
        let at = reader.fragment(value).start();
        let entry: RawOutput = reader.element(value)?;
        if !known(&entry.source) {
            return Err(reader.error(
                at,
                format!("output {i} names unknown source {:?}", entry.source),
            ));
        }
        outputs.push(OutputEntry {
            source: entry.source,
            output: reader.fragment(entry.output),
            at,
            text: value.get_ron().trim().to_string(),
        });
    }
    let editor = match raw.editor {
        Some(value) => Some((
            reader.element::<EditorConfig>(value)?,
            value.get_ron().trim().to_string(),
        )),
        None => None,
    };
    Ok(RunFile {
        sources,
        backend: raw.backend,
        cross_check: raw.cross_check,
        commit: raw.commit,
        edits,
        outputs,
        editor,
    })
}

/// The text being read, for positions of its slices.
struct Reader<'t> {
    text: &'t str,
    name: &'t str,
}

impl<'t> Reader<'t> {
    /// `value` (a slice of the text) as a fragment with its position.
    fn fragment(&self, value: &RawValue) -> Fragment {
        let part = value.get_ron();
        let base = self.text.as_ptr() as usize;
        let start = part.as_ptr() as usize;
        // Every RawValue here borrows from `self.text`; a slice from anywhere else (which the
        // deserializer never produces) is placed at the start rather than mis-indexed.
        let origin = match start.checked_sub(base) {
            Some(offset) if offset + part.len() <= self.text.len() => {
                TextPosition::after(&self.text[..offset])
            }
            _ => TextPosition::START,
        };
        Fragment::new(part, origin)
    }

    /// Parses one element (a source entry, an edit, an output) with run-file positions.
    fn element<T: Deserialize<'t>>(&self, value: &'t RawValue) -> Result<T, RunFileError> {
        let fragment = self.fragment(value);
        ron_options()
            .from_str(value.get_ron())
            .map_err(|e| RunFileError::At {
                path: self.name.to_string(),
                at: fragment.locate(Some(TextPosition {
                    line: e.position.line,
                    column: e.position.col,
                })),
                message: e.code.to_string(),
            })
    }

    fn error(&self, at: TextPosition, message: String) -> RunFileError {
        RunFileError::At {
            path: self.name.to_string(),
            at,
            message,
        }
    }
}

/// A source's refusal of one of its fragments, as a run-file error message:
/// `run.ron:LINE:COL: {context}: {message}` at the position the source gave, or at the
/// fragment's start.
pub fn located_source_error(
    run: &str,
    fragment: &Fragment,
    context: &str,
    error: &SourceError,
) -> String {
    format!(
        "{run}:{}: {context}: {}",
        fragment.locate(error.at),
        error.message
    )
}

/// Parses a fragment's text into `T` with errors in run-file coordinates (for host-side
/// schemas inside fragments).
pub fn parse_fragment<T: serde::de::DeserializeOwned>(
    run: &str,
    fragment: &Fragment,
    context: &str,
) -> Result<T, String> {
    from_ron(fragment.text(), context)
        .map_err(|e| format!("{run}:{}: {}", fragment.locate(e.at), e.message))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The run file of a saved session reads back to the same entries, also when entries end
    /// in line comments (their commas go on lines of their own) and with an editor section.
    #[test]
    fn a_run_file_with_other_edits_reads_back_to_the_same_entries() {
        let text = r#"(
            sources: [
                (name: "a", plugin: "linear", config: (parameters: {"x": "1"}, equations: [])) // first
            ],
            cross_check: (tolerance: 1e-8),
            commit: Snapped(grid_bits: 12),
            outputs: [],
            editor: (image: (file: "p.png", opacity: "1/4")), // behind
        )"#;
        let run = parse(text, "run.ron").expect("parses");
        let edit = r#"Ecles(anchors: {"a.x": "2"}) // moved"#;
        let saved = run.with_edits("two lines\nof comment", [edit, edit]);
        let again = parse(&saved, "saved.ron").expect("the saved text parses");
        assert_eq!(again.edits.len(), 2, "{saved}");
        assert!(again.edits.iter().all(|e| e.text == edit), "{saved}");
        assert_eq!(again.sources[0].text, run.sources[0].text);
        assert_eq!(
            again.commit_policy(),
            CommitPolicy::Snapped { grid_bits: 12 }
        );
        assert_eq!(again.cross_check.map(|c| c.tolerance), Some(1e-8));
        assert_eq!(again.editor, run.editor);
        assert!(
            saved.starts_with("// two lines\n// of comment\n("),
            "{saved}"
        );
    }

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
                    Configure(source: "eq", config: (parameters: {"a": "3"})),
                ],
                outputs: [(source: "eq", output: (picture: "x.svg"))],
            )"#,
            "run.ron",
        )
        .expect("valid");
        assert_eq!(run.backend.simplify, Simplify::Turner);
        assert_eq!(run.cross_check.map(|c| c.tolerance), Some(1e-8));
        assert_eq!(run.edits.len(), 3);
        let EditKind::Configure { source, config } = &run.edits[2].kind else {
            panic!("a configuration");
        };
        assert_eq!(
            (source.as_str(), config.text()),
            ("eq", " (parameters: {\"a\": \"3\"})")
        );
        assert_eq!(
            run.edits[1].at,
            TextPosition {
                line: 7,
                column: 21
            }
        );
        let EditKind::Source { operation, .. } = &run.edits[1].kind else {
            panic!("a source edit");
        };
        assert_eq!(operation.text(), " (anything: 1)");
        assert_eq!(
            operation.start(),
            TextPosition {
                line: 7,
                column: 53
            }
        );
        let off = parse(r#"(sources: [], cross_check: None)"#, "run.ron").expect("valid");
        assert!(off.cross_check.is_none());
        let default = parse(r#"(sources: [])"#, "run.ron").expect("valid");
        assert!(default.cross_check.is_some());
    }

    fn error(text: &str) -> String {
        parse(text, "r.ron").expect_err(text).to_string()
    }

    #[test]
    fn errors_name_the_position() {
        let text = error("(\n  sources: [],\n  edist: [],\n)");
        assert!(text.starts_with("r.ron:3:"), "{text}");
        assert!(text.contains("edist"), "{text}");
        let text = error(
            "(sources: [(name: \"a\", plugin: \"linear\"),\n (name: \"a\", plugin: \"linear\")])",
        );
        assert!(text.starts_with("r.ron:2:2: two sources"), "{text}");
        let text = error("(sources: [], edits: [Source(source: \"zz\", operation: ())])");
        assert!(text.contains("zz"), "{text}");
        let text = error("(sources: [],\n edits: [Configure(source: \"zz\", config: ())])");
        assert!(
            text.starts_with("r.ron:2:10: edit 0 names unknown source \"zz\""),
            "{text}"
        );
        let text = error("(sources: [], edits: [Ecles(anchors: {\"a\": 0.1})])");
        assert!(text.starts_with("r.ron:1:"), "{text}");
        let text = error("(sources: [], cross_check: (tolerance: 2.0))");
        assert!(text.contains("between 0 and 1"), "{text}");
    }

    #[test]
    fn unknown_fields_and_duplicate_keys_are_errors_at_every_level() {
        let text =
            error("(sources: [],\n edits: [\n  Ecles(anchors: {\"a\": \"1\"}, wieghts: {})])");
        assert!(text.starts_with("r.ron:3:"), "{text}");
        assert!(text.contains("wieghts"), "{text}");
        let text = error(
            "(sources: [(name: \"s\", plugin: \"linear\")],\n edits: [Source(source: \"s\", operation: (), extra: 3)])",
        );
        assert!(text.starts_with("r.ron:2:"), "{text}");
        assert!(text.contains("extra"), "{text}");
        let text = error(
            "(sources: [],\n edits: [Ecles(anchors: {\"eq.a\": \"5\",\n  \"eq.a\": \"6\"})])",
        );
        assert!(text.starts_with("r.ron:3:"), "{text}");
        assert!(text.contains("\"eq.a\" is given twice"), "{text}");
        let text = error("(sources: [(name: \"s\", plugin: \"linear\", colour: 1)])");
        assert!(text.contains("colour"), "{text}");
        let text = error("(sources: [(name: \"s\", plugin: \"linear\")], outputs: [(source: \"s\", output: (), x: 1)])");
        assert!(text.contains("`x`"), "{text}");
    }

    #[test]
    fn a_byte_order_mark_is_ignored() {
        let run = parse("\u{feff}(sources: [])", "r.ron").expect("BOM");
        assert!(run.sources.is_empty());
    }

    #[test]
    fn source_positions_translate_into_the_run_file() {
        let run = parse(
            "(sources: [\n  (name: \"phi\", plugin: \"spline2d\",\n   config: (\n     degree: 5,\n     degre: 4))])",
            "r.ron",
        )
        .expect("valid");
        let config = &run.sources[0].config;
        let err = from_ron::<BTreeMap<String, u32>>("{\"a\": x}", "c").expect_err("x");
        let inner = err.at.expect("position");
        assert_eq!(inner.line, 1);
        // A position on the fragment's third line keeps its column.
        let third = TextPosition { line: 3, column: 6 };
        assert_eq!(
            config.locate(Some(third)),
            TextPosition { line: 5, column: 6 }
        );
        assert_eq!(
            config.start(),
            TextPosition {
                line: 3,
                column: 12
            }
        );
        let message = located_source_error(
            "r.ron",
            config,
            "source \"phi\"",
            &SourceError::new("no mesh").with_position(third),
        );
        assert_eq!(message, "r.ron:5:6: source \"phi\": no mesh");
    }
}
