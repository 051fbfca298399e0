//! The `linear` constraint source: hand-written linear systems over named scalar parameters.
//!
//! A `linear` source declares scalar parameters with exact initial values and integer linear
//! equations over them, or over parameters of earlier sources. Its configuration (RON) takes
//! one of two forms.
//!
//! # Equations form
//!
//! ```ron
//! (
//!     // name -> exact initial value: a string read exactly ("3", "-2.5", "7/3", "1e-3")
//!     // or a RON integer. Ids follow the order written here.
//!     parameters: { "p1": "3", "p2": "-2.5", "p3": "7/3", "p4": 0 },
//!     equations: [ "p1 + p2 - p3 = 0", "3 p3 - 5 p4 = 7" ],
//! )
//! ```
//!
//! Both fields are optional (a source may only add equations on earlier parameters).
//!
//! An equation is a sum of terms on each side of exactly one `=`. A term is
//! `[sign] [integer coefficient] [*] name` or an integer constant; both sides may hold terms
//! and constants (`2 p1 = p2 + 3`), a name may appear several times (the coefficients are
//! summed), whitespace is free (`3*x+4-2y=-7+z`), integers have any size. Coefficients are
//! integers: `0.5 p1` or `p1 / 2` is an error ("coefficients must be integers; multiply the
//! equation through").
//!
//! A name is resolved as
//! 1. a parameter of this source (its short name as declared, or its full name
//!    `{source}.{name}`), otherwise
//! 2. the full name of a parameter declared by an earlier source (`other.x`), which is how a
//!    later source adds constraints to earlier ones. Such a parameter must be scalar.
//!
//! # Matrix form
//!
//! For generated systems, `matrix · p = rhs`:
//!
//! ```ron
//! (
//!     matrix: [[1, 1, -1], [0, 2, 1]],
//!     rhs: [0, 5],
//!     names: ["a", "b", "c"],        // optional; default p0..p{n-1}
//!     values: ["1", "2", "3"],       // optional initial values; default all 0
//! )
//! ```
//!
//! Every matrix row has one entry per parameter; matrix and `rhs` entries are RON integers or
//! strings holding integers (`"123456789012345678901234567890"`), values are as in the
//! equations form. Without `names` and `values` the number of parameters is the length of the
//! first row. The matrix form declares its own parameters only.
//!
//! # What the source contributes
//!
//! * One scalar parameter (dimension 1) per declared name, named `{source}.{name}` where
//!   `{source}` is [`BuildRequest::name`], with ids in declaration order after the existing
//!   parameters.
//! * One [`RowBody::Scalar`] row per equation over coordinate 0 of the parameters, with the
//!   terms moved left (merged, zero coefficients dropped, ordered by parameter id) and the
//!   constants moved right. Its label is the trimmed equation text (matrix form: `row {i}`);
//!   its origin is `{ source: {source}, item: "equation {i}" }` (matrix form: `"row {i}"`).
//!   Equations and rows are numbered from 1.
//! * An equation whose coefficients all cancel (`p1 - p1 = 3`) is kept when its constant is
//!   nonzero, so that the host reports the inconsistency `0 = 3`, with a warning; a `0 = 0`
//!   equation is dropped with a warning.
//! * Summary items `parameters` (new parameters) and `equations` (rows contributed).
//!
//! # Errors
//!
//! Every error names what it is about:
//!
//! * RON errors give the line and column in the configuration: ``config 3:12: Unexpected
//!   field named `equatoins` in `LinearConfig`, expected one of `parameters`, ...``;
//! * floats are refused, since they are not exact: `parameter "p1": 0.1 is a floating-point
//!   number, which is not exact; quote it ("0.1") to have it read exactly ...`;
//! * equation errors give the equation number and the 1-based column (in characters):
//!   `equation 2, column 7: expected a parameter name or a number, found '*'`,
//!   `equation 1, column 6: unknown parameter 'q' ...`;
//! * matrix shape errors name the row: `matrix row 2 has 2 entries, expected 3 (the length of
//!   row 1)`.
//!
//! # Example
//!
//! ```
//! use api::{BuildRequest, ConstraintSource, ConstraintSystem, Values};
//! use plugins_linear::LinearSource;
//!
//! let request = BuildRequest {
//!     name: "pump".into(),
//!     config: r#"(
//!         parameters: { "p1": "1", "p2": "2", "p3": "3", "p4": "8" },
//!         equations: [ "p1 + p2 - p3 = 0", "p4 - p3 = 5" ],
//!     )"#
//!     .into(),
//!     base_dir: ".".into(),
//!     system: ConstraintSystem::new(),
//!     values: Values::default(),
//!     sources: vec![],
//!     input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
//!     schema: api::SCHEMA_VERSION,
//! };
//! let contribution = LinearSource::new().build(&request).unwrap();
//! let (mut system, mut values) = (ConstraintSystem::new(), Values::default());
//! contribution.apply_to(&mut system, &mut values).unwrap();
//! assert_eq!(&*system.params()[3].name, "pump.p4");
//! assert_eq!(system.rows()[1].label, "p4 - p3 = 5");
//! assert!(system.violations(&values).is_empty());
//! ```

mod config;
pub mod equation;

use api::{
    BuildRequest, ConstraintRow, ConstraintSource, Contribution, Coord, Integer, NewParameter,
    OperationCheckRequest, OperationPlan, Origin, OutputCheck, OutputCheckRequest, OutputFile,
    ParamId, PlanRequest, Rational, RenderRequest, RowBody, SourceError, SummaryItem,
};
use config::{parse_config, Config};
use equation::parse_equation;
use num_traits::Zero;
use std::collections::HashMap;

/// The `linear` constraint source: named scalar parameters and integer linear equations
/// (see the [crate documentation](crate) for the configuration).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LinearSource;

impl LinearSource {
    /// A new source, to be built once from its configuration.
    pub fn new() -> Self {
        LinearSource
    }
}

/// The new parameters of one build: short names and their ids.
struct Declared<'a> {
    source: &'a str,
    ids: HashMap<&'a str, ParamId>,
}

impl Declared<'_> {
    /// Own parameter by short or full name.
    fn get(&self, name: &str) -> Option<ParamId> {
        self.ids.get(name).copied().or_else(|| {
            name.strip_prefix(self.source)
                .and_then(|rest| rest.strip_prefix('.'))
                .and_then(|short| self.ids.get(short).copied())
        })
    }
}

/// Declares the parameters, refusing names that already exist in the system.
fn declare<'a>(
    request: &'a BuildRequest,
    parameters: &'a [(String, Rational)],
    contribution: &mut Contribution,
) -> Result<Declared<'a>, SourceError> {
    let existing = request.system.params().len();
    let mut ids = HashMap::new();
    for (k, (name, value)) in parameters.iter().enumerate() {
        let full = format!("{}.{name}", request.name);
        if request.system.param_id(&full).is_some() {
            return Err(SourceError::new(format!(
                "parameter {name:?}: an earlier source already declares {full:?}"
            )));
        }
        let id = u32::try_from(existing + k)
            .map(ParamId)
            .map_err(|_| SourceError::new("too many parameters"))?;
        ids.insert(name.as_str(), id);
        contribution.parameters.push(NewParameter {
            name: full,
            value: vec![value.clone()],
        });
    }
    Ok(Declared {
        source: &request.name,
        ids,
    })
}

/// Builds a scalar row from `(param, coefficient)` terms, or `None` (with a warning) for
/// `0 = 0`. `what` names the equation in warnings.
fn make_row(
    terms: Vec<(ParamId, Integer)>,
    rhs: Integer,
    label: String,
    origin: Origin,
    what: &str,
    warnings: &mut Vec<String>,
) -> Option<ConstraintRow> {
    let mut terms = terms;
    terms.sort_by_key(|(p, _)| *p);
    let mut merged: Vec<(ParamId, Integer)> = Vec::with_capacity(terms.len());
    for (p, c) in terms {
        match merged.last_mut() {
            Some((last, sum)) if *last == p => *sum += c,
            _ => merged.push((p, c)),
        }
    }
    merged.retain(|(_, c)| !c.is_zero());
    if merged.is_empty() {
        if rhs.is_zero() {
            warnings.push(format!(
                "{what}: every coefficient cancels (0 = 0); dropped"
            ));
            return None;
        }
        warnings.push(format!(
            "{what}: every coefficient cancels, leaving 0 = {rhs}; kept, so the system is \
             inconsistent"
        ));
    }
    Some(ConstraintRow {
        label,
        origin,
        body: RowBody::Scalar {
            terms: merged
                .into_iter()
                .map(|(param, c)| {
                    (
                        Coord {
                            param,
                            component: 0,
                        },
                        c,
                    )
                })
                .collect(),
            rhs,
        },
    })
}

/// Resolves a name of equation `index`: own parameter first, then an earlier full name.
fn resolve(
    request: &BuildRequest,
    declared: &Declared<'_>,
    index: usize,
    name: &str,
    column: usize,
) -> Result<ParamId, SourceError> {
    if let Some(id) = declared.get(name) {
        return Ok(id);
    }
    let Some(id) = request.system.param_id(name) else {
        return Err(SourceError::new(format!(
            "equation {index}, column {column}: unknown parameter '{name}' (neither declared \
             in `parameters` nor the full name of an earlier source's parameter)"
        )));
    };
    match request.system.param(id) {
        Some(param) if param.dim == 1 => Ok(id),
        Some(param) => Err(SourceError::new(format!(
            "equation {index}, column {column}: parameter '{name}' has {} coordinates; \
             linear equations are over scalar parameters",
            param.dim
        ))),
        None => Err(SourceError::new(format!(
            "equation {index}, column {column}: parameter '{name}' is not in the system"
        ))),
    }
}

fn build_equations(
    request: &BuildRequest,
    parameters: &[(String, Rational)],
    equations: &[String],
) -> Result<Contribution, SourceError> {
    let mut contribution = Contribution::default();
    let declared = declare(request, parameters, &mut contribution)?;
    for (i, text) in equations.iter().enumerate() {
        let index = i + 1;
        let parsed = parse_equation(text).map_err(|e| {
            SourceError::new(format!(
                "equation {index}, column {}: {}",
                e.column, e.message
            ))
        })?;
        let terms = parsed
            .terms
            .into_iter()
            .map(|(name, c)| {
                resolve(request, &declared, index, &name.name, name.column).map(|id| (id, c))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let origin = Origin {
            source: request.name.clone(),
            item: format!("equation {index}"),
        };
        let what = format!("equation {index} ({:?})", text.trim());
        if let Some(row) = make_row(
            terms,
            parsed.rhs,
            text.trim().to_string(),
            origin,
            &what,
            &mut contribution.warnings,
        ) {
            contribution.rows.push(row);
        }
    }
    if parameters.is_empty() && equations.is_empty() {
        contribution
            .warnings
            .push("the config declares no parameters and no equations".into());
    }
    Ok(contribution)
}

fn build_matrix(
    request: &BuildRequest,
    parameters: &[(String, Rational)],
    rows: &[Vec<Integer>],
    rhs: &[Integer],
) -> Result<Contribution, SourceError> {
    let mut contribution = Contribution::default();
    let declared = declare(request, parameters, &mut contribution)?;
    let ids: Vec<ParamId> = parameters
        .iter()
        .filter_map(|(name, _)| declared.get(name))
        .collect();
    for (i, (row, q)) in rows.iter().zip(rhs).enumerate() {
        let label = format!("row {}", i + 1);
        let terms = ids.iter().copied().zip(row.iter().cloned()).collect();
        let origin = Origin {
            source: request.name.clone(),
            item: label.clone(),
        };
        let what = format!("matrix {label}");
        if let Some(row) = make_row(
            terms,
            q.clone(),
            label,
            origin,
            &what,
            &mut contribution.warnings,
        ) {
            contribution.rows.push(row);
        }
    }
    Ok(contribution)
}

impl ConstraintSource for LinearSource {
    fn kind(&self) -> &str {
        "linear"
    }

    fn version(&self) -> &str {
        env!("CARGO_PKG_VERSION")
    }

    fn build(&mut self, request: &BuildRequest) -> Result<Contribution, SourceError> {
        let mut contribution = match parse_config(&request.config)? {
            Config::Equations {
                parameters,
                equations,
            } => build_equations(request, &parameters, &equations)?,
            Config::Matrix {
                parameters,
                rows,
                rhs,
            } => build_matrix(request, &parameters, &rows, &rhs)?,
        };
        contribution.summary = vec![
            SummaryItem {
                key: "parameters".into(),
                value: contribution.parameters.len() as u64,
            },
            SummaryItem {
                key: "equations".into(),
                value: contribution.rows.len() as u64,
            },
        ];
        Ok(contribution)
    }

    fn plan(&self, _request: &PlanRequest) -> Result<OperationPlan, SourceError> {
        Err(SourceError::new("the linear source has no operations"))
    }

    fn render(&self, _request: &RenderRequest) -> Result<Vec<OutputFile>, SourceError> {
        Err(SourceError::new("the linear source has no outputs"))
    }

    fn check_operation(&self, _request: &OperationCheckRequest) -> Result<(), SourceError> {
        Err(SourceError::new("the linear source has no operations"))
    }

    fn check_output(&self, _request: &OutputCheckRequest) -> Result<OutputCheck, SourceError> {
        Err(SourceError::new("the linear source has no outputs"))
    }
}

#[cfg(test)]
mod tests;
