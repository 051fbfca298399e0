//! The `c2` constraint source, a dynamic plugin: makes a `spline2d` deformation `C²`.
//!
//! A `spline2d` source of smoothness 1 declares its control points and `C¹` conditions. A `c2`
//! source built after it finds it among the earlier sources ([`api::BuildRequest::sources`]),
//! re-reads its mesh from its configuration text (paths resolved against
//! [`api::BuildRequest::base_dir`], parsed exactly as `spline2d` does with
//! [`spline2d::config::spline_from_config`]), builds the degree-`d` spline with
//! smoothness 2 and contributes **only the order-2 conditions**, as vector rows of dimension 2
//! on the existing control points `{spline}.{point name}`. The two sources together carry the
//! full `C²` system: its rank is `control points − dim S²_d` (Schumaker's formula, exact for
//! `d ≥ 8`).
//!
//! # Configuration (RON)
//! ```ron
//! (
//!     spline: "phi",              // the spline2d source (built earlier in the run)
//!     allow_low_degree: false,    // default false: refuse degree d < 9
//! )
//! ```
//! `C²` needs `d ≥ 3r + 2 = 8` for the dimension formula and `d ≥ 9` for local control (a
//! control point moved changes the spline near it only), so a spline of degree below
//! [`MIN_DEGREE`] is refused unless `allow_low_degree: true` (then it is a warning).
//!
//! Rows are labelled `{name}: {spline} C2 edge a-b #j` (origin: this source, item
//! `{spline} C2 edge a-b #j`). The summary counts `conditions`, `degree` and `interior_edges`.
//! The source has no operations and no outputs: edit and render through the spline's source.
//!
//! Built as a `cdylib` (`cargo build --release -p plugins-c2` gives
//! `target/release/libplugins_c2.so` on Linux), it is loaded by path from a run file:
//! ```ron
//! (name: "smooth", plugin: "../target/release/libplugins_c2.so", config: (spline: "phi")),
//! ```

use api::{
    BuildRequest, ConstraintRow, ConstraintSource, Contribution, Integer, OperationCheckRequest,
    OperationPlan, Origin, OutputCheck, OutputCheckRequest, OutputFile, ParamId, PlanRequest,
    RenderRequest, RowBody, SourceError, SummaryItem,
};
use serde::Deserialize;
use spline2d::config::spline_from_config_text;
use spline2d::spline::Spline;
use std::collections::HashMap;

/// Smallest degree accepted without `allow_low_degree`: `C²` splines have local control from
/// degree 9 on (`d ≥ 3r + 3`).
pub const MIN_DEGREE: usize = 9;

/// Smallest degree for which Schumaker's dimension formula of `S²_d` is exact (`d ≥ 3r + 2`).
pub const FORMULA_DEGREE: usize = 8;

/// The plugin kind, as reported to hosts.
pub const KIND: &str = "c2";

/// The configuration, as written in a run file: `(spline: "phi", allow_low_degree: false)`.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct C2Config {
    /// Name of the `spline2d` source whose control points get the `C²` conditions.
    pub spline: String,
    /// Accept a spline of degree below [`MIN_DEGREE`] (with a warning) instead of refusing it.
    #[serde(default)]
    pub allow_low_degree: bool,
}

/// Why a `c2` source could not be built. Every message starts with the instance name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum C2Error {
    /// The configuration is not valid RON of the schema.
    #[error("{name} config: {message}")]
    Config {
        /// Instance name.
        name: String,
        /// The parser's message.
        message: String,
        /// Where in the configuration text.
        at: Option<api::config::TextPosition>,
    },
    /// No earlier source has the configured name.
    #[error("{name}: no source named {spline:?} is built before this one (earlier sources: {earlier}); put the spline2d source first")]
    NoSuchSource {
        /// Instance name.
        name: String,
        /// The configured spline name.
        spline: String,
        /// The earlier sources' names, or `none`.
        earlier: String,
    },
    /// The named source is not a `spline2d` source.
    #[error("{name}: source {spline:?} is a {kind:?} source; c2 adds conditions to a \"spline2d\" source")]
    NotASpline {
        /// Instance name.
        name: String,
        /// The configured spline name.
        spline: String,
        /// Its kind.
        kind: String,
    },
    /// The spline's configuration could not be read again (or the spline not built).
    #[error("{name}: reading spline {spline:?}: {message}")]
    Spline {
        /// Instance name.
        name: String,
        /// The configured spline name.
        spline: String,
        /// What went wrong.
        message: String,
    },
    /// The spline has no `C¹` conditions to build on.
    #[error("{name}: spline {spline:?} has smoothness C0; c2 adds the order-2 conditions on top of the C1 conditions (set smoothness: 1 on {spline:?})")]
    NotC1 {
        /// Instance name.
        name: String,
        /// The configured spline name.
        spline: String,
    },
    /// The spline's degree is too low for `C²` with local control.
    #[error("{name}: spline {spline:?} has degree {degree}, but C2 smoothness needs degree d >= 3r + 2 = 8 for the dimension formula of the spline space and d >= 9 for local control; set degree: 9 (or more) on {spline:?}, or allow_low_degree: true to accept degree {degree}")]
    LowDegree {
        /// Instance name.
        name: String,
        /// The configured spline name.
        spline: String,
        /// Its degree.
        degree: usize,
    },
    /// A control point of the spline is not a parameter of the system.
    #[error("{name}: the system has no parameter {param:?}; was {spline:?} built by spline2d from the same configuration?")]
    MissingPoint {
        /// Instance name.
        name: String,
        /// The configured spline name.
        spline: String,
        /// The parameter looked for.
        param: String,
    },
    /// A control point parameter that is not a point of the plane.
    #[error("{name}: parameter {param:?} has dimension {dim}, but the control points of a spline2d deformation have dimension 2")]
    Dimension {
        /// Instance name.
        name: String,
        /// The parameter.
        param: String,
        /// Its dimension.
        dim: usize,
    },
}

impl From<C2Error> for SourceError {
    fn from(e: C2Error) -> Self {
        let at = match &e {
            C2Error::Config { at, .. } => *at,
            _ => None,
        };
        SourceError {
            message: e.to_string(),
            at,
        }
    }
}

/// Parses a configuration (`(spline: "phi")`); errors carry their position in `text`.
pub fn parse_config(name: &str, text: &str) -> Result<C2Config, C2Error> {
    api::config::from_ron(text, "config").map_err(|e| C2Error::Config {
        name: name.to_string(),
        message: e
            .message
            .strip_prefix("config: ")
            .unwrap_or(&e.message)
            .to_string(),
        at: e.at,
    })
}

/// What a built source keeps, for messages.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Built {
    name: String,
    spline: String,
}

/// The `c2` source.
#[derive(Debug, Clone, Default)]
pub struct C2Source {
    built: Option<Built>,
}

impl C2Source {
    fn describe(&self) -> String {
        match &self.built {
            Some(b) => format!("{} (C2 conditions of {:?})", b.name, b.spline),
            None => "c2 (not built)".to_string(),
        }
    }

    /// The refusal of an operation (`operation` as written): the spline is edited through its
    /// own source.
    fn no_operations(&self, operation: &str) -> SourceError {
        SourceError::new(format!(
            "{}: c2 sources have no operations; edit the spline through its own source (asked for {operation:?})",
            self.describe(),
        ))
    }

    /// The refusal of an output (`output` as written): the spline is rendered through its own
    /// source.
    fn no_outputs(&self, output: &str) -> SourceError {
        SourceError::new(format!(
            "{}: c2 sources have no outputs; render the spline through its own source (asked for {output:?})",
            self.describe(),
        ))
    }

    fn contribute(&self, request: &BuildRequest) -> Result<(Contribution, Built), C2Error> {
        let name = request.name.clone();
        let config = parse_config(&name, &request.config)?;
        let spline_name = config.spline.clone();
        let info = request
            .sources
            .iter()
            .find(|s| s.name == spline_name)
            .ok_or_else(|| C2Error::NoSuchSource {
                name: name.clone(),
                spline: spline_name.clone(),
                earlier: if request.sources.is_empty() {
                    "none".to_string()
                } else {
                    request
                        .sources
                        .iter()
                        .map(|s| format!("{:?}", s.name))
                        .collect::<Vec<_>>()
                        .join(", ")
                },
            })?;
        if info.kind != "spline2d" {
            return Err(C2Error::NotASpline {
                name,
                spline: spline_name,
                kind: info.kind.clone(),
            });
        }
        let spline_error = |message: String| C2Error::Spline {
            name: name.clone(),
            spline: spline_name.clone(),
            message,
        };
        let c1 = spline_from_config_text(
            &info.name,
            &info.config,
            &request.base_dir,
            request.input_limit,
        )
        .map_err(|e| spline_error(e.message))?
        .spline;
        let degree = c1.degree();
        if c1.smoothness() == 0 {
            return Err(C2Error::NotC1 {
                name,
                spline: spline_name,
            });
        }
        let mut warnings = Vec::new();
        if degree < MIN_DEGREE {
            if !config.allow_low_degree {
                return Err(C2Error::LowDegree {
                    name,
                    spline: spline_name,
                    degree,
                });
            }
            warnings.push(format!(
                "spline {spline_name:?} has degree {degree} < {MIN_DEGREE}: accepted with allow_low_degree, but C2 splines of this degree lack local control{}",
                if degree < FORMULA_DEGREE {
                    " and the dimension formula of the spline space may not hold"
                } else {
                    ""
                }
            ));
        }
        if c1.smoothness() >= 2 {
            warnings.push(format!(
                "spline {spline_name:?} already has smoothness C{}: it declares the C2 conditions itself, so these rows are redundant",
                c1.smoothness()
            ));
        }
        let spline =
            Spline::new(c1.mesh().clone(), degree, 2).map_err(|e| spline_error(e.to_string()))?;
        let mut ids: HashMap<usize, ParamId> = HashMap::new();
        let mut lookup = |point: usize| -> Result<ParamId, C2Error> {
            if let Some(found) = ids.get(&point) {
                return Ok(*found);
            }
            let param = format!("{spline_name}.{}", spline.points()[point].name);
            let id = request
                .system
                .param_id(&param)
                .ok_or_else(|| C2Error::MissingPoint {
                    name: name.clone(),
                    spline: spline_name.clone(),
                    param: param.clone(),
                })?;
            let dim = request.system.param(id).map_or(0, |p| p.dim);
            if dim != 2 {
                return Err(C2Error::Dimension {
                    name: name.clone(),
                    param,
                    dim,
                });
            }
            ids.insert(point, id);
            Ok(id)
        };
        let mut rows = Vec::new();
        for condition in spline.conditions().iter().filter(|c| c.order == 2) {
            let terms = condition
                .terms
                .iter()
                .map(|(point, coefficient)| Ok((lookup(*point)?, coefficient.clone())))
                .collect::<Result<Vec<_>, C2Error>>()?;
            let item = format!("{spline_name} {}", condition.label);
            rows.push(ConstraintRow {
                label: format!("{name}: {item}"),
                origin: Origin {
                    source: name.clone(),
                    item,
                },
                body: RowBody::Vector {
                    terms,
                    rhs: vec![Integer::from(0); 2],
                },
            });
        }
        let summary = vec![
            SummaryItem {
                key: "conditions".into(),
                value: rows.len() as u64,
            },
            SummaryItem {
                key: "degree".into(),
                value: degree as u64,
            },
            SummaryItem {
                key: "interior_edges".into(),
                value: spline.topology().interior_edges() as u64,
            },
        ];
        Ok((
            Contribution {
                inputs: Vec::new(),
                parameters: Vec::new(),
                rows,
                summary,
                warnings,
            },
            Built {
                name,
                spline: spline_name,
            },
        ))
    }
}

impl ConstraintSource for C2Source {
    fn kind(&self) -> &str {
        KIND
    }

    fn version(&self) -> &str {
        env!("CARGO_PKG_VERSION")
    }

    fn build(&mut self, request: &BuildRequest) -> Result<Contribution, SourceError> {
        let (contribution, built) = self.contribute(request)?;
        self.built = Some(built);
        Ok(contribution)
    }

    fn plan(&self, request: &PlanRequest) -> Result<OperationPlan, SourceError> {
        Err(self.no_operations(&request.operation))
    }

    fn render(&self, request: &RenderRequest) -> Result<Vec<OutputFile>, SourceError> {
        Err(self.no_outputs(&request.output))
    }

    fn check_operation(&self, request: &OperationCheckRequest) -> Result<(), SourceError> {
        Err(self.no_operations(&request.operation))
    }

    fn check_output(&self, request: &OutputCheckRequest) -> Result<OutputCheck, SourceError> {
        Err(self.no_outputs(&request.output))
    }
}

// The C ABI: `ecles_plugin_abi_version`, `ecles_plugin_entry_v1`, header and vtable.
plugin_abi::export_source!(C2Source::default);
