//! The `align` constraint source, a dynamic plugin: geometric constraints a user declares on
//! points of other sources (a spline's control points, say), as exact scalar rows.
//!
//! # Configuration (RON)
//! ```ron
//! (constraints: [
//!     SameX(["phi.v3", "phi.v7"]),                       // equal x: phi.v3 x = phi.v7 x
//!     SameY(["phi.v0", "phi.v1", "phi.v2"]),             // equal y (each against the first)
//!     OnLine(points: ["phi.v2"], through: (("0", "0"), ("10", "5"))),
//!     Fixed(point: "phi.v4", at: ("3", "7/2")),          // x = 3 and y = 7/2
//!     Offset(point: "phi.v5", from: "phi.v4", by: ("1", "0")),  // phi.v5 = phi.v4 + (1, 0)
//! ])
//! ```
//! Points are parameters of dimension 2 of earlier sources, by full name; numbers are exact
//! (strings such as `"7/2"`, `"0.1"`, or integers; floating-point literals are refused).
//!
//! # Rows
//! Every constraint becomes **scalar** rows ([`api::RowBody::Scalar`]) over single coordinates
//! (x is coordinate 0, y coordinate 1), with rational data scaled to coprime integers:
//!
//! | constraint | rows | label (source named `align`) |
//! | --- | --- | --- |
//! | `SameX([p, q, …])` | `p.x − q.x = 0`, … | `align: p x = q x` |
//! | `SameY([p, q, …])` | `p.y − q.y = 0`, … | `align: p y = q y` |
//! | `OnLine(points, through: (a, b))` | `(b−a) × (p−a) = 0` per point | `align: p on the line through (0, 0) and (10, 5)` |
//! | `Fixed(point, at)` | `p.x = x`, `p.y = y` | `align: p x = 3`, `align: p y = 7/2` |
//! | `Offset(point, from, by)` | `p.x − f.x = dx`, `p.y − f.y = dy` | `align: p x = f x + 1`, `align: p y = f y` |
//!
//! Row origins are `{ source: name, item: "constraint k (Kind)" }`, `k` counted from 1. The
//! summary counts `constraints`, `rows` and each kind (`same_x`, `same_y`, `on_line`, `fixed`,
//! `offset`).
//!
//! These rows mix coordinates, so a system holding them and a spline's vector rows is analysed
//! and edited per coordinate (the host and ECLES switch layouts on their own). The constraints
//! must hold for the current values (the host refuses a run whose initial values violate a
//! row): align the reference geometry, then edit.
//!
//! Built as a `cdylib` (`cargo build --release -p plugins-align` gives
//! `target/release/libplugins_align.so` on Linux), it is loaded by path from a run file.

use api::exact::{format_rational, Exact};
use api::{
    coprime_integers, BuildRequest, ConstraintRow, ConstraintSource, ConstraintSystem,
    Contribution, Coord, Integer, OperationCheckRequest, OperationPlan, Origin, OutputCheck,
    OutputCheckRequest, OutputFile, ParamId, PlanRequest, Rational, RenderRequest, RowBody,
    SourceError, SummaryItem,
};
use num_traits::{One, Signed, Zero};
use serde::Deserialize;

/// The plugin kind, as reported to hosts.
pub const KIND: &str = "align";

/// The configuration: `(constraints: [...])`.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AlignConfig {
    /// The constraints, in order.
    pub constraints: Vec<Alignment>,
}

/// An exact point `(x, y)` written in a configuration.
pub type ExactPoint = (Exact, Exact);

/// One declared constraint.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Alignment {
    /// The points share their x coordinate (a vertical line): at least two points.
    SameX(Vec<String>),
    /// The points share their y coordinate (a horizontal line): at least two points.
    SameY(Vec<String>),
    /// The points lie on the fixed line through two distinct points.
    OnLine {
        /// The points kept on the line (at least one).
        points: Vec<String>,
        /// Two distinct points of the line.
        through: (ExactPoint, ExactPoint),
    },
    /// The point stays at the given position.
    Fixed {
        /// The point.
        point: String,
        /// Its position.
        at: ExactPoint,
    },
    /// The point stays at a fixed offset from another point.
    Offset {
        /// The point.
        point: String,
        /// The point it follows.
        from: String,
        /// `point − from`.
        by: ExactPoint,
    },
}

impl Alignment {
    /// The variant's name as written in configurations (`"SameX"`).
    pub fn kind(&self) -> &'static str {
        match self {
            Alignment::SameX(_) => "SameX",
            Alignment::SameY(_) => "SameY",
            Alignment::OnLine { .. } => "OnLine",
            Alignment::Fixed { .. } => "Fixed",
            Alignment::Offset { .. } => "Offset",
        }
    }

    /// The summary key counting this kind (`"same_x"`).
    fn key(&self) -> &'static str {
        match self {
            Alignment::SameX(_) => "same_x",
            Alignment::SameY(_) => "same_y",
            Alignment::OnLine { .. } => "on_line",
            Alignment::Fixed { .. } => "fixed",
            Alignment::Offset { .. } => "offset",
        }
    }
}

/// Why an `align` source could not be built. Every message starts with the instance name and
/// names the constraint (counted from 1) and the point.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum AlignError {
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
    /// A point that is not a parameter of the system.
    #[error("{name}: constraint {index} ({kind}): no parameter named {param:?} (points are named by source and point, e.g. \"phi.v3\")")]
    UnknownPoint {
        /// Instance name.
        name: String,
        /// The constraint, counted from 1.
        index: usize,
        /// Its kind.
        kind: &'static str,
        /// The name given.
        param: String,
    },
    /// A parameter that is not a point of the plane.
    #[error("{name}: constraint {index} ({kind}): {param:?} has dimension {dim}, but align works on points of the plane (dimension 2)")]
    NotAPoint {
        /// Instance name.
        name: String,
        /// The constraint, counted from 1.
        index: usize,
        /// Its kind.
        kind: &'static str,
        /// The parameter.
        param: String,
        /// Its dimension.
        dim: usize,
    },
    /// Too few points for the constraint to say anything.
    #[error("{name}: constraint {index} ({kind}) needs at least {needed} point(s), got {found}")]
    TooFewPoints {
        /// Instance name.
        name: String,
        /// The constraint, counted from 1.
        index: usize,
        /// Its kind.
        kind: &'static str,
        /// The least number of points.
        needed: usize,
        /// The number given.
        found: usize,
    },
    /// A point named twice in one constraint (its row would read `0 = 0`).
    #[error("{name}: constraint {index} ({kind}) names {param:?} twice")]
    Repeated {
        /// Instance name.
        name: String,
        /// The constraint, counted from 1.
        index: usize,
        /// Its kind.
        kind: &'static str,
        /// The point.
        param: String,
    },
    /// `OnLine` through two equal points.
    #[error("{name}: constraint {index} (OnLine): the two points the line goes through are equal")]
    DegenerateLine {
        /// Instance name.
        name: String,
        /// The constraint, counted from 1.
        index: usize,
    },
}

impl From<AlignError> for SourceError {
    fn from(e: AlignError) -> Self {
        let at = match &e {
            AlignError::Config { at, .. } => *at,
            _ => None,
        };
        SourceError {
            message: e.to_string(),
            at,
        }
    }
}

/// Parses a configuration (RON, struct and enum syntax as in the module documentation).
pub fn parse_config(name: &str, text: &str) -> Result<AlignConfig, AlignError> {
    api::config::from_ron(text, "config").map_err(|e| AlignError::Config {
        name: name.to_string(),
        message: e
            .message
            .strip_prefix("config: ")
            .unwrap_or(&e.message)
            .to_string(),
        at: e.at,
    })
}

/// Scales `Σ c_j x_j = q` with rational data to coprime integers ([`api::coprime_integers`]),
/// dropping zero coefficients, with a positive first coefficient.
fn integer_row(terms: Vec<(Coord, Rational)>, rhs: Rational) -> (Vec<(Coord, Integer)>, Integer) {
    let terms: Vec<(Coord, Rational)> = terms.into_iter().filter(|(_, v)| !v.is_zero()).collect();
    let mut ints = coprime_integers(terms.iter().map(|(_, v)| v).chain(std::iter::once(&rhs)));
    if !terms.is_empty() && ints[0].is_negative() {
        for v in ints.iter_mut() {
            *v = -&*v;
        }
    }
    let q = ints.pop().unwrap_or_default();
    (terms.into_iter().map(|(c, _)| c).zip(ints).collect(), q)
}

/// Text of an exact number in labels.
fn text(value: &Rational) -> String {
    format_rational(value)
}

/// `" + 3/2"`, `" - 1"` or `""`: an offset in a label.
fn plus(value: &Rational) -> String {
    if value.is_zero() {
        String::new()
    } else if value.is_negative() {
        format!(" - {}", text(&-value))
    } else {
        format!(" + {}", text(value))
    }
}

const AXES: [&str; 2] = ["x", "y"];

/// Turns the configured constraints into scalar rows on the parameters of `system`.
pub fn alignment_rows(
    name: &str,
    config: &AlignConfig,
    system: &ConstraintSystem,
) -> Result<Vec<ConstraintRow>, AlignError> {
    let mut rows = Vec::new();
    for (i, constraint) in config.constraints.iter().enumerate() {
        let index = i + 1;
        let kind = constraint.kind();
        let point = |param: &str| -> Result<ParamId, AlignError> {
            let id = system
                .param_id(param)
                .ok_or_else(|| AlignError::UnknownPoint {
                    name: name.to_string(),
                    index,
                    kind,
                    param: param.to_string(),
                })?;
            let dim = system.param(id).map_or(0, |p| p.dim);
            if dim != 2 {
                return Err(AlignError::NotAPoint {
                    name: name.to_string(),
                    index,
                    kind,
                    param: param.to_string(),
                    dim,
                });
            }
            Ok(id)
        };
        let distinct = |points: &[&String], needed: usize| -> Result<Vec<ParamId>, AlignError> {
            if points.len() < needed {
                return Err(AlignError::TooFewPoints {
                    name: name.to_string(),
                    index,
                    kind,
                    needed,
                    found: points.len(),
                });
            }
            let mut ids: Vec<ParamId> = Vec::with_capacity(points.len());
            for p in points {
                let id = point(p)?;
                if ids.contains(&id) {
                    return Err(AlignError::Repeated {
                        name: name.to_string(),
                        index,
                        kind,
                        param: p.to_string(),
                    });
                }
                ids.push(id);
            }
            Ok(ids)
        };
        let mut push = |label: String, terms: Vec<(Coord, Rational)>, rhs: Rational| {
            let (terms, rhs) = integer_row(terms, rhs);
            rows.push(ConstraintRow {
                label: format!("{name}: {label}"),
                origin: Origin {
                    source: name.to_string(),
                    item: format!("constraint {index} ({kind})"),
                },
                body: RowBody::Scalar { terms, rhs },
            });
        };
        let at = |param: ParamId, component: usize| Coord { param, component };
        let one = Rational::one;
        match constraint {
            Alignment::SameX(points) | Alignment::SameY(points) => {
                let k = usize::from(matches!(constraint, Alignment::SameY(_)));
                let names: Vec<&String> = points.iter().collect();
                let ids = distinct(&names, 2)?;
                for (other, id) in names.iter().zip(&ids).skip(1) {
                    push(
                        format!("{} {axis} = {other} {axis}", names[0], axis = AXES[k]),
                        vec![(at(ids[0], k), one()), (at(*id, k), -one())],
                        Rational::zero(),
                    );
                }
            }
            Alignment::OnLine { points, through } => {
                let ((ax, ay), (bx, by)) = through;
                let (ax, ay, bx, by) = (&ax.0, &ay.0, &bx.0, &by.0);
                let (dx, dy) = (bx - ax, by - ay);
                if dx.is_zero() && dy.is_zero() {
                    return Err(AlignError::DegenerateLine {
                        name: name.to_string(),
                        index,
                    });
                }
                let names: Vec<&String> = points.iter().collect();
                let ids = distinct(&names, 1)?;
                // (b − a) × (p − a) = 0:  dy·p.x − dx·p.y = dy·a.x − dx·a.y.
                for (p, id) in names.iter().zip(&ids) {
                    push(
                        format!(
                            "{p} on the line through ({}, {}) and ({}, {})",
                            text(ax),
                            text(ay),
                            text(bx),
                            text(by)
                        ),
                        vec![(at(*id, 0), dy.clone()), (at(*id, 1), -dx.clone())],
                        &dy * ax - &dx * ay,
                    );
                }
            }
            Alignment::Fixed {
                point: p,
                at: (x, y),
            } => {
                let id = point(p)?;
                for (k, value) in [&x.0, &y.0].into_iter().enumerate() {
                    push(
                        format!("{p} {} = {}", AXES[k], text(value)),
                        vec![(at(id, k), one())],
                        value.clone(),
                    );
                }
            }
            Alignment::Offset {
                point: p,
                from,
                by: (dx, dy),
            } => {
                let names = [p, from];
                let ids = distinct(&names, 2)?;
                for (k, value) in [&dx.0, &dy.0].into_iter().enumerate() {
                    push(
                        format!("{p} {axis} = {from} {axis}{}", plus(value), axis = AXES[k]),
                        vec![(at(ids[0], k), one()), (at(ids[1], k), -one())],
                        value.clone(),
                    );
                }
            }
        }
    }
    Ok(rows)
}

/// What a built source keeps, for messages.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Built {
    name: String,
}

/// The `align` source.
#[derive(Debug, Clone, Default)]
pub struct AlignSource {
    built: Option<Built>,
}

impl AlignSource {
    fn name(&self) -> &str {
        self.built
            .as_ref()
            .map_or("align (not built)", |b| b.name.as_str())
    }

    /// The refusal of an operation (`operation` as written): align sources have none.
    fn no_operations(&self, operation: &str) -> SourceError {
        SourceError::new(format!(
            "{}: align sources have no operations; edit the points through their own source or a generic edit (asked for {operation:?})",
            self.name(),
        ))
    }

    /// The refusal of an output (`output` as written): align sources have none.
    fn no_outputs(&self, output: &str) -> SourceError {
        SourceError::new(format!(
            "{}: align sources have no outputs (asked for {output:?})",
            self.name(),
        ))
    }
}

impl ConstraintSource for AlignSource {
    fn kind(&self) -> &str {
        KIND
    }

    fn version(&self) -> &str {
        env!("CARGO_PKG_VERSION")
    }

    fn build(&mut self, request: &BuildRequest) -> Result<Contribution, SourceError> {
        let name = &request.name;
        let config = parse_config(name, &request.config)?;
        let rows = alignment_rows(name, &config, &request.system)?;
        let mut summary = vec![
            ("constraints", config.constraints.len()),
            ("rows", rows.len()),
        ];
        for key in ["same_x", "same_y", "on_line", "fixed", "offset"] {
            let count = config.constraints.iter().filter(|c| c.key() == key).count();
            summary.push((key, count));
        }
        let warnings = if config.constraints.is_empty() {
            vec!["no constraints declared".to_string()]
        } else {
            Vec::new()
        };
        self.built = Some(Built { name: name.clone() });
        Ok(Contribution {
            inputs: Vec::new(),
            parameters: Vec::new(),
            rows,
            summary: SummaryItem::sorted(summary),
            warnings,
        })
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
plugin_abi::export_source!(AlignSource::default);
