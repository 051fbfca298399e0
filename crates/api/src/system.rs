//! Parameters, integer constraint rows and the constraint system they form.
//!
//! A parameter is a scalar (`dim = 1`) or a vector of `dim` coordinates (a point of the plane
//! is one parameter with `dim = 2`, as in the thesis, section 4.4). A constraint row is either
//!
//! * a **vector row** `Σ c_j p_j = q` over vector parameters of one dimension `d`: it holds for
//!   each of the `d` coordinates with the same coefficients (the spline smoothness conditions
//!   treat x and y alike), so `q` has `d` components; or
//! * a **scalar row** `Σ c_j p_j[k_j] = q` over single coordinates (alignment constraints mix
//!   coordinates, and scalar parameters are their own single coordinate).
//!
//! Coefficients and right-hand sides are integers: sources scale rational data to integers
//! ([`crate::exact::coprime_integers`]).

use crate::exact::{Integer, Rational};
use crate::matrix::IntMatrix;
use crate::name_index::NameIndex;
use num_traits::Zero;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::sync::Arc;

/// Index of a parameter in a [`ConstraintSystem`].
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize, Default,
)]
pub struct ParamId(pub u32);

impl ParamId {
    /// The index as `usize`.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl fmt::Display for ParamId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#{}", self.0)
    }
}

/// Index of a constraint row in a [`ConstraintSystem`].
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize, Default,
)]
pub struct RowId(pub u32);

impl RowId {
    /// The index as `usize`.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// One coordinate of a parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Coord {
    /// The parameter.
    pub param: ParamId,
    /// Which coordinate (`0` for a scalar parameter).
    pub component: usize,
}

/// A declared parameter.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Parameter {
    /// Unique name (sources prefix their names, e.g. `"mesh.q_0_3_2@u"`), shared: reports
    /// name the parameters of every edit, and a copy of the name is a reference count.
    pub name: Arc<str>,
    /// Number of coordinates: 1 for a scalar, 2 for a point of the plane.
    pub dim: usize,
}

/// Where a constraint row comes from: the source that emitted it and the item inside it.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
pub struct Origin {
    /// Name of the constraint source (e.g. `"spline2d"`, `"linear"`).
    pub source: String,
    /// The item inside the source (an edge, an equation number, ...).
    pub item: String,
}

/// The equation of a constraint row.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub enum RowBody {
    /// `Σ c_j p_j = q`, holding coordinate by coordinate for parameters of dimension
    /// `rhs.len()`.
    Vector {
        /// Coefficients per parameter.
        terms: Vec<(ParamId, Integer)>,
        /// Right-hand side, one integer per coordinate.
        rhs: Vec<Integer>,
    },
    /// `Σ c_j p_j[k_j] = q` over single coordinates.
    Scalar {
        /// Coefficients per coordinate.
        terms: Vec<(Coord, Integer)>,
        /// Right-hand side.
        rhs: Integer,
    },
}

impl RowBody {
    /// The distinct parameters the row involves, increasing.
    pub fn params(&self) -> Vec<ParamId> {
        let mut out: Vec<ParamId> = match self {
            RowBody::Vector { terms, .. } => terms.iter().map(|(p, _)| *p).collect(),
            RowBody::Scalar { terms, .. } => terms.iter().map(|(c, _)| c.param).collect(),
        };
        out.sort();
        out.dedup();
        out
    }

    /// The parameter of every term, in the row's order; a parameter appears once per term
    /// (a scalar row may name several coordinates of one parameter). No allocation, unlike
    /// [`RowBody::params`].
    pub fn term_params(&self) -> impl Iterator<Item = ParamId> + '_ {
        let (vector, scalar) = match self {
            RowBody::Vector { terms, .. } => (Some(terms.iter().map(|(p, _)| *p)), None),
            RowBody::Scalar { terms, .. } => (None, Some(terms.iter().map(|(c, _)| c.param))),
        };
        vector
            .into_iter()
            .flatten()
            .chain(scalar.into_iter().flatten())
    }

    /// Number of scalar equations the row stands for.
    pub fn scalar_rows(&self) -> usize {
        match self {
            RowBody::Vector { rhs, .. } => rhs.len(),
            RowBody::Scalar { .. } => 1,
        }
    }

    /// The row as scalar equations over single coordinates, borrowed: a vector row of
    /// dimension `d` stands for `d` equations (`component: Some(k)`), a scalar row for one
    /// (`component: None`). The one place where rows are split per coordinate; nothing is
    /// copied (a small edit's analyses split their rows at every edit).
    pub fn scalar_equations(&self) -> impl ExactSizeIterator<Item = ScalarEquation<'_>> + '_ {
        (0..self.scalar_rows()).map(move |k| ScalarEquation { body: self, k })
    }
}

/// One scalar equation `Σ c_j x_j = q` over coordinates of a row, from
/// [`RowBody::scalar_equations`] (borrowed from the row).
#[derive(Debug, Clone, Copy)]
pub struct ScalarEquation<'a> {
    body: &'a RowBody,
    /// The coordinate, for a vector row; `0` for a scalar row.
    k: usize,
}

impl<'a> ScalarEquation<'a> {
    /// The coordinate, for equations split from a vector row.
    pub fn component(&self) -> Option<usize> {
        match self.body {
            RowBody::Vector { .. } => Some(self.k),
            RowBody::Scalar { .. } => None,
        }
    }

    /// Right-hand side.
    pub fn rhs(&self) -> &'a Integer {
        match self.body {
            RowBody::Vector { rhs, .. } => &rhs[self.k],
            RowBody::Scalar { rhs, .. } => rhs,
        }
    }

    /// Coefficients per coordinate, in the row's order.
    pub fn terms(&self) -> impl Iterator<Item = (Coord, &'a Integer)> + 'a {
        let k = self.k;
        let (vector, scalar) = match self.body {
            RowBody::Vector { terms, .. } => (
                Some(terms.iter().map(move |(p, c)| {
                    (
                        Coord {
                            param: *p,
                            component: k,
                        },
                        c,
                    )
                })),
                None,
            ),
            RowBody::Scalar { terms, .. } => (None, Some(terms.iter().map(|(c, v)| (*c, v)))),
        };
        vector
            .into_iter()
            .flatten()
            .chain(scalar.into_iter().flatten())
    }
}

/// A labelled constraint row.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ConstraintRow {
    /// Human-readable label, unique enough to name the row in messages.
    pub label: String,
    /// Which source and item produced it.
    pub origin: Origin,
    /// The equation.
    pub body: RowBody,
}

/// Why a parameter, a row or a value was rejected.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SystemError {
    /// Two parameters with one name.
    #[error("parameter {name:?} is declared twice")]
    DuplicateParameter {
        /// The name.
        name: String,
    },
    /// A parameter with no coordinates.
    #[error("parameter {name:?} has dimension 0")]
    ZeroDimension {
        /// The name.
        name: String,
    },
    /// A row names a parameter that does not exist.
    #[error("row {label:?} refers to parameter {param}, but only {count} parameters exist")]
    UnknownParameter {
        /// The row's label.
        label: String,
        /// The offending id.
        param: ParamId,
        /// Number of declared parameters.
        count: usize,
    },
    /// A vector row over a parameter of another dimension.
    #[error(
        "row {label:?} is a {row_dim}-dimensional vector row but parameter {name:?} has dimension {param_dim}"
    )]
    DimensionMismatch {
        /// The row's label.
        label: String,
        /// The parameter's name.
        name: String,
        /// Dimension of the row.
        row_dim: usize,
        /// Dimension of the parameter.
        param_dim: usize,
    },
    /// A vector row with an empty right-hand side.
    #[error("vector row {label:?} has an empty right-hand side")]
    EmptyVectorRow {
        /// The row's label.
        label: String,
    },
    /// A scalar row names a coordinate a parameter does not have.
    #[error("row {label:?} uses coordinate {component} of {name:?}, which has dimension {dim}")]
    ComponentOutOfRange {
        /// The row's label.
        label: String,
        /// The parameter's name.
        name: String,
        /// The coordinate asked for.
        component: usize,
        /// The parameter's dimension.
        dim: usize,
    },
    /// A value vector of the wrong length.
    #[error("value for {name:?} has {found} coordinates, expected {expected}")]
    WrongValueDimension {
        /// The parameter's name.
        name: String,
        /// Coordinates given.
        found: usize,
        /// Coordinates expected.
        expected: usize,
    },
}

/// Parameters and constraint rows from all sources: one parameter space, global ids.
///
/// Serialises as its parameters and rows; deserialising re-validates every row.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(try_from = "SystemData", into = "SystemData")]
pub struct ConstraintSystem {
    params: Vec<Parameter>,
    /// Parameter ids by name (the names themselves are in `params`).
    by_name: NameIndex,
    rows: Vec<ConstraintRow>,
    /// For each parameter, the rows that involve it (increasing).
    incidence: Vec<Vec<RowId>>,
}

/// Two systems are equal when their parameters and rows are (the name index and the incidence
/// lists are derived from them).
impl PartialEq for ConstraintSystem {
    fn eq(&self, other: &Self) -> bool {
        self.params == other.params && self.rows == other.rows
    }
}

impl Eq for ConstraintSystem {}

impl ConstraintSystem {
    /// An empty system.
    pub fn new() -> Self {
        Self::default()
    }

    /// Declares a parameter; names are unique.
    pub fn add_parameter(
        &mut self,
        name: impl Into<Arc<str>>,
        dim: usize,
    ) -> Result<ParamId, SystemError> {
        let name = name.into();
        if dim == 0 {
            return Err(SystemError::ZeroDimension {
                name: name.to_string(),
            });
        }
        if self.by_name.get(&self.params, &name).is_some() {
            return Err(SystemError::DuplicateParameter {
                name: name.to_string(),
            });
        }
        let id = ParamId(self.params.len() as u32);
        self.params.push(Parameter { name, dim });
        self.by_name.insert(&self.params, id);
        self.incidence.push(Vec::new());
        Ok(id)
    }

    /// Adds a row after checking every id and dimension. Repeated terms are summed and zero
    /// coefficients dropped.
    pub fn add_row(&mut self, mut row: ConstraintRow) -> Result<RowId, SystemError> {
        self.check_row(&mut row)?;
        let id = RowId(self.rows.len() as u32);
        record_incidence(&mut self.incidence, &row.body, id);
        self.rows.push(row);
        Ok(id)
    }

    /// [`ConstraintSystem::add_row`] for many rows, all or nothing: every row is checked before
    /// any is added. Rows added to a system without rows are adopted as they are (the vector
    /// of a million rows is not copied).
    pub(crate) fn add_rows(&mut self, mut rows: Vec<ConstraintRow>) -> Result<(), SystemError> {
        for row in &mut rows {
            self.check_row(row)?;
        }
        let first = self.rows.len();
        if first == 0 {
            self.rows = rows;
        } else {
            self.rows.reserve_exact(rows.len());
            self.rows.extend(rows);
        }
        for (k, row) in self.rows.iter().enumerate().skip(first) {
            record_incidence(&mut self.incidence, &row.body, RowId(k as u32));
        }
        Ok(())
    }

    /// Checks a row's ids and dimensions against the parameters, and merges its terms.
    fn check_row(&self, row: &mut ConstraintRow) -> Result<(), SystemError> {
        match &mut row.body {
            RowBody::Vector { terms, rhs } => {
                if rhs.is_empty() {
                    return Err(SystemError::EmptyVectorRow {
                        label: row.label.clone(),
                    });
                }
                for (p, _) in terms.iter() {
                    let param = self.checked_param(&row.label, *p)?;
                    if param.dim != rhs.len() {
                        return Err(SystemError::DimensionMismatch {
                            label: row.label.clone(),
                            name: param.name.to_string(),
                            row_dim: rhs.len(),
                            param_dim: param.dim,
                        });
                    }
                }
                merge_terms(terms);
            }
            RowBody::Scalar { terms, .. } => {
                for (c, _) in terms.iter() {
                    let param = self.checked_param(&row.label, c.param)?;
                    if c.component >= param.dim {
                        return Err(SystemError::ComponentOutOfRange {
                            label: row.label.clone(),
                            name: param.name.to_string(),
                            component: c.component,
                            dim: param.dim,
                        });
                    }
                }
                merge_terms(terms);
            }
        }
        Ok(())
    }

    /// Makes room for `params` more parameters, exactly: a source that adds a million
    /// parameters does not leave the doubling slack of a growing vector behind (its rows are
    /// adopted or reserved exactly by [`ConstraintSystem::add_rows`]).
    pub(crate) fn reserve_exact(&mut self, params: usize) {
        self.params.reserve_exact(params);
        self.by_name.reserve(&self.params, params);
        self.incidence.reserve_exact(params);
    }

    /// Drops every parameter from `params` on and every row from `rows` on (the rows dropped
    /// must be all those involving the parameters dropped): undoes additions that failed part
    /// way.
    pub(crate) fn truncate(&mut self, params: usize, rows: usize) {
        for row in self.rows.drain(rows..) {
            for p in row.body.params() {
                if let Some(list) = self.incidence.get_mut(p.index()) {
                    list.retain(|r| r.index() < rows);
                }
            }
        }
        for id in params..self.params.len() {
            self.by_name.remove(&self.params, ParamId(id as u32));
        }
        self.params.truncate(params);
        self.incidence.truncate(params);
    }

    fn checked_param(&self, label: &str, id: ParamId) -> Result<&Parameter, SystemError> {
        self.params
            .get(id.index())
            .ok_or_else(|| SystemError::UnknownParameter {
                label: label.to_string(),
                param: id,
                count: self.params.len(),
            })
    }

    /// The parameters and the rows, taken out of the system (for a caller that has no further
    /// use for it and wants them without a copy).
    pub fn into_parts(self) -> (Vec<Parameter>, Vec<ConstraintRow>) {
        (self.params, self.rows)
    }

    /// All parameters, indexed by [`ParamId`].
    pub fn params(&self) -> &[Parameter] {
        &self.params
    }

    /// One parameter, if the id exists.
    pub fn param(&self, id: ParamId) -> Option<&Parameter> {
        self.params.get(id.index())
    }

    /// The rows in which a parameter has a nonzero coefficient, increasing.
    ///
    /// # Panics
    /// Panics if `id` is not a parameter of this system.
    pub fn rows_of(&self, id: ParamId) -> &[RowId] {
        &self.incidence[id.index()]
    }

    /// Looks a parameter up by name.
    pub fn param_id(&self, name: &str) -> Option<ParamId> {
        self.by_name.get(&self.params, name)
    }

    /// All rows, indexed by [`RowId`].
    pub fn rows(&self) -> &[ConstraintRow] {
        &self.rows
    }

    /// One row, if the id exists.
    pub fn row(&self, id: RowId) -> Option<&ConstraintRow> {
        self.rows.get(id.index())
    }

    /// Total number of scalar coordinates (columns of the scalar matrix).
    pub fn coordinate_count(&self) -> usize {
        self.params.iter().map(|p| p.dim).sum()
    }

    /// Column of each parameter's first coordinate in the scalar matrix.
    pub fn coordinate_offsets(&self) -> Vec<usize> {
        let mut offsets = Vec::with_capacity(self.params.len());
        let mut next = 0;
        for p in &self.params {
            offsets.push(next);
            next += p.dim;
        }
        offsets
    }

    /// The whole system over scalar coordinates: a vector row of dimension `d` becomes `d`
    /// scalar rows. Returns the matrix, the right-hand side and, for each scalar row, the row it
    /// comes from and the coordinate.
    pub fn scalar_matrix(&self) -> (IntMatrix, Vec<Integer>, Vec<(RowId, usize)>) {
        let offsets = self.coordinate_offsets();
        let mut sparse = Vec::new();
        let mut rhs_out = Vec::new();
        let mut origin = Vec::new();
        for (i, row) in self.rows.iter().enumerate() {
            for equation in row.body.scalar_equations() {
                sparse.push(
                    equation
                        .terms()
                        .map(|(c, v)| (offsets[c.param.index()] + c.component, v.clone()))
                        .collect(),
                );
                rhs_out.push(equation.rhs().clone());
                origin.push((RowId(i as u32), equation.component().unwrap_or(0)));
            }
        }
        let matrix = IntMatrix::from_sparse(self.coordinate_count(), sparse)
            .expect("coordinates were validated when the rows were added");
        (matrix, rhs_out, origin)
    }

    /// Residual `Σ c_j p_j − q` of every scalar equation that the values violate, as
    /// `(row, coordinate, residual)`, in row order. Empty when every constraint holds exactly.
    /// Large systems are checked in parallel (after an edit on a real mesh each row sums values
    /// of thousands of digits: half a second for the 15 000 rows of the figure mesh at δ = 40).
    pub fn violations(&self, values: &Values) -> Vec<(RowId, usize, Rational)> {
        let of_row =
            |(i, row): (usize, &ConstraintRow)| row_violations(RowId(i as u32), row, values);
        if self.rows.len() < PARALLEL_ROWS_FROM {
            self.rows.iter().enumerate().flat_map(of_row).collect()
        } else {
            self.rows
                .par_iter()
                .enumerate()
                .flat_map_iter(of_row)
                .collect()
        }
    }
}

/// Rows from which [`ConstraintSystem::violations`] runs in parallel (below, handing the rows
/// to other threads costs about what checking them does).
const PARALLEL_ROWS_FROM: usize = 1024;

/// The violated scalar equations of one row, as in [`ConstraintSystem::violations`].
fn row_violations(
    id: RowId,
    row: &ConstraintRow,
    values: &Values,
) -> Vec<(RowId, usize, Rational)> {
    match &row.body {
        RowBody::Vector { terms, rhs } => rhs
            .iter()
            .enumerate()
            .filter_map(|(k, q)| {
                exact_residual(terms.iter().map(|(p, c)| (&values.get(*p)[k], c)), q)
                    .map(|r| (id, k, r))
            })
            .collect(),
        RowBody::Scalar { terms, rhs } => exact_residual(
            terms
                .iter()
                .map(|(c, v)| (&values.get(c.param)[c.component], v)),
            rhs,
        )
        .map(|r| (id, 0, r))
        .into_iter()
        .collect(),
    }
}

/// `Σ c_j x_j − q`, or `None` when it is zero, without reducing a fraction on the way: the terms
/// are summed pairwise as unreduced fractions (equal denominators added directly), and only a
/// nonzero residual is reduced once. Edits on real meshes leave values with thousands of digits;
/// reducing after every addition (what `Ratio`'s `+=` does) costs a big GCD per term.
fn exact_residual<'a>(
    terms: impl Iterator<Item = (&'a Rational, &'a Integer)> + Clone,
    q: &Integer,
) -> Option<Rational> {
    if let Some(small) = word_residual(terms.clone(), q) {
        return small;
    }
    let mut parts: Vec<(Integer, Integer)> = terms
        .filter(|(_, c)| !c.is_zero())
        .map(|(x, c)| (x.numer() * c, x.denom().clone()))
        .collect();
    parts.push((-q, Integer::from(1)));
    while parts.len() > 1 {
        let mut next = Vec::with_capacity(parts.len().div_ceil(2));
        let mut pairs = parts.into_iter();
        while let Some((a, b)) = pairs.next() {
            match pairs.next() {
                None => next.push((a, b)),
                Some((c, d)) if b == d => next.push((a + c, b)),
                Some((c, d)) => match shared_factor(&b, &d) {
                    // Over lcm(b, d) = b · (d / g): the denominators of one solution share
                    // almost all their factors, so this keeps the sums at their size.
                    Some(g) => {
                        let (fb, fd) = (&d / &g, &b / &g);
                        next.push((a * &fb + c * fd, b * fb));
                    }
                    None => next.push((a * &d + c * &b, b * d)),
                },
            }
        }
        parts = next;
    }
    let (numer, denom) = parts.pop()?;
    (!numer.is_zero()).then(|| Rational::new(numer, denom))
}

/// [`exact_residual`] in machine words: `Some(residual)` when every coefficient, numerator and
/// denominator fits an `i64` and every step of the sum an `i128` (checked), `None` to say
/// the big-integer path must answer. A freshly built mesh's rows over its nominal positions
/// (denominators dividing the degree) are all answered here, one pass without allocation;
/// checking them in big integers was a seventh of a whole-mesh `ecles analyze`.
fn word_residual<'a>(
    terms: impl Iterator<Item = (&'a Rational, &'a Integer)>,
    q: &Integer,
) -> Option<Option<Rational>> {
    use crate::words::checked_mul_i128;
    use num_integer::Integer as _;
    use num_traits::ToPrimitive;
    // The running sum `numer / denom`, `denom > 0`.
    let (mut numer, mut denom) = (-i128::from(q.to_i64()?), 1i128);
    for (x, c) in terms {
        let c = i128::from(c.to_i64()?);
        if c == 0 {
            continue;
        }
        let a = i128::from(x.numer().to_i64()?);
        let b = i128::from(x.denom().to_i64()?);
        // Two `i64`s: their product fits.
        let term = c * a;
        if b == denom {
            numer = numer.checked_add(term)?;
        } else {
            // Both denominators are positive; a GCD and quotients of words when both fit one
            // (a division of `i128`s is a library call).
            let (fd, fb) = match (u64::try_from(denom), u64::try_from(b)) {
                (Ok(x), Ok(y)) => {
                    let g = x.gcd(&y);
                    (i128::from(y / g), i128::from(x / g))
                }
                _ => {
                    let g = denom.gcd(&b);
                    (b / g, denom / g)
                }
            };
            numer = checked_mul_i128(numer, fd)?.checked_add(checked_mul_i128(term, fb)?)?;
            denom = checked_mul_i128(denom, fd)?;
        }
    }
    Some((numer != 0).then(|| Rational::new(Integer::from(numer), Integer::from(denom))))
}

/// Euclid steps [`shared_factor`] takes before giving up.
const SHARED_FACTOR_STEPS: usize = 24;

/// `gcd(a, b)` of positive `a`, `b` when Euclid's algorithm ends within [`SHARED_FACTOR_STEPS`] steps, else `None`.
/// Denominators such as `D / 6` and `D / 10` (the reduced values of one exact solution over a
/// common `D`) end in a few steps of small quotients, each a single pass over the numbers,
/// where a general GCD of numbers with thousands of digits would cost far more.
fn shared_factor(a: &Integer, b: &Integer) -> Option<Integer> {
    use num_integer::Integer as _;
    let (mut x, mut y) = (a.clone(), b.clone());
    for _ in 0..SHARED_FACTOR_STEPS {
        if y.is_zero() {
            return Some(x);
        }
        let r = x.mod_floor(&y);
        x = std::mem::replace(&mut y, r);
    }
    None
}

/// The serialised form of a [`ConstraintSystem`].
#[derive(Serialize, Deserialize)]
struct SystemData {
    params: Vec<Parameter>,
    rows: Vec<ConstraintRow>,
}

impl From<ConstraintSystem> for SystemData {
    fn from(s: ConstraintSystem) -> Self {
        SystemData {
            params: s.params,
            rows: s.rows,
        }
    }
}

impl TryFrom<SystemData> for ConstraintSystem {
    type Error = SystemError;
    fn try_from(data: SystemData) -> Result<Self, SystemError> {
        let mut system = ConstraintSystem::new();
        for p in data.params {
            system.add_parameter(p.name, p.dim)?;
        }
        for row in data.rows {
            system.add_row(row)?;
        }
        Ok(system)
    }
}

/// Records row `id` in the incidence lists of the parameters its (merged) body involves: terms
/// are sorted by parameter (by coordinate for scalar rows), so each parameter is recorded once.
fn record_incidence(incidence: &mut [Vec<RowId>], body: &RowBody, id: RowId) {
    let mut last = None;
    let mut record = |p: ParamId| {
        if last != Some(p) {
            incidence[p.index()].push(id);
            last = Some(p);
        }
    };
    match body {
        RowBody::Vector { terms, .. } => terms.iter().for_each(|(p, _)| record(*p)),
        RowBody::Scalar { terms, .. } => terms.iter().for_each(|(c, _)| record(c.param)),
    }
}

/// Sorts terms by key, sums repeated keys and drops zero coefficients, in place (terms already
/// in that form, as sources give them, are only looked at).
fn merge_terms<K: Ord + Copy>(terms: &mut Vec<(K, Integer)>) {
    let merged = terms.windows(2).all(|pair| pair[0].0 < pair[1].0)
        && terms.iter().all(|(_, v)| !v.is_zero());
    if merged {
        return;
    }
    terms.sort_by_key(|(k, _)| *k);
    let mut out: Vec<(K, Integer)> = Vec::with_capacity(terms.len());
    for (k, v) in terms.drain(..) {
        match out.last_mut() {
            Some((lk, lv)) if *lk == k => *lv += v,
            _ => out.push((k, v)),
        }
    }
    out.retain(|(_, v)| !v.is_zero());
    *terms = out;
}

/// Current exact values of all parameters of a system: the state being edited.
///
/// Copies share their data until one of them changes (copy on write): a session keeps the
/// initial values, the current ones and one state per undo step, which for a whole mesh are a
/// million parameters each.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Values {
    data: std::sync::Arc<Vec<Vec<Rational>>>,
}

impl Values {
    /// All parameters of `system` at zero.
    pub fn zeros(system: &ConstraintSystem) -> Self {
        Values {
            data: std::sync::Arc::new(
                system
                    .params()
                    .iter()
                    .map(|p| vec![Rational::zero(); p.dim])
                    .collect(),
            ),
        }
    }

    /// Values given per parameter; each vector must have the parameter's dimension.
    pub fn from_vecs(
        system: &ConstraintSystem,
        data: Vec<Vec<Rational>>,
    ) -> Result<Self, SystemError> {
        let mut values = Values::zeros(system);
        for (i, v) in data.into_iter().enumerate() {
            values.set(system, ParamId(i as u32), v)?;
        }
        Ok(values)
    }

    /// The value of one parameter.
    ///
    /// # Panics
    /// Panics if `id` is not a parameter of the system these values belong to.
    pub fn get(&self, id: ParamId) -> &[Rational] {
        &self.data[id.index()]
    }

    /// Sets one parameter after checking its dimension.
    pub fn set(
        &mut self,
        system: &ConstraintSystem,
        id: ParamId,
        value: Vec<Rational>,
    ) -> Result<(), SystemError> {
        let param = system.param(id).ok_or(SystemError::UnknownParameter {
            label: "value".into(),
            param: id,
            count: system.params().len(),
        })?;
        if value.len() != param.dim {
            return Err(SystemError::WrongValueDimension {
                name: param.name.to_string(),
                found: value.len(),
                expected: param.dim,
            });
        }
        let data = std::sync::Arc::make_mut(&mut self.data);
        if data.len() < system.params().len() {
            data.resize_with(system.params().len(), Vec::new);
        }
        data[id.index()] = value;
        Ok(())
    }

    /// Number of parameters.
    pub fn len(&self) -> usize {
        self.data.len()
    }

    /// True when there are no parameters.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// Appends the value of a parameter just added to `system` (its id must be the next one).
    pub fn push(
        &mut self,
        system: &ConstraintSystem,
        id: ParamId,
        value: Vec<Rational>,
    ) -> Result<(), SystemError> {
        let param = system
            .param(id)
            .filter(|_| id.index() == self.data.len())
            .ok_or(SystemError::UnknownParameter {
                label: "value".into(),
                param: id,
                count: self.data.len(),
            })?;
        if value.len() != param.dim {
            return Err(SystemError::WrongValueDimension {
                name: param.name.to_string(),
                found: value.len(),
                expected: param.dim,
            });
        }
        std::sync::Arc::make_mut(&mut self.data).push(value);
        Ok(())
    }

    /// Makes room for `params` more values, exactly.
    /// Makes room for `params` more parameters, exactly: a source that adds a million
    /// parameters does not leave the doubling slack of a growing vector behind (its rows are
    /// adopted or reserved exactly by [`ConstraintSystem::add_rows`]).
    pub(crate) fn reserve_exact(&mut self, params: usize) {
        std::sync::Arc::make_mut(&mut self.data).reserve_exact(params);
    }

    /// Keeps the first `params` values (undoes [`Values::push`]es).
    pub(crate) fn truncate(&mut self, params: usize) {
        std::sync::Arc::make_mut(&mut self.data).truncate(params);
    }

    /// Replaces several parameters at once; used to commit an edit atomically after it has been
    /// fully computed. Values shared with another copy (a session's undo history holds the
    /// previous ones) are copied only where they are not replaced.
    pub fn replace_all(&mut self, updates: impl IntoIterator<Item = (ParamId, Vec<Rational>)>) {
        if let Some(data) = std::sync::Arc::get_mut(&mut self.data) {
            for (id, value) in updates {
                data[id.index()] = value;
            }
            return;
        }
        let mut replaced: Vec<Option<Vec<Rational>>> = vec![None; self.data.len()];
        for (id, value) in updates {
            replaced[id.index()] = Some(value);
        }
        let data = self
            .data
            .iter()
            .zip(replaced)
            .map(|(old, new)| new.unwrap_or_else(|| old.clone()))
            .collect();
        self.data = std::sync::Arc::new(data);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Replacing values shared with a copy leaves the copy as it was and copies the others
    /// over; unshared values are replaced in place; a parameter named twice takes the last.
    #[test]
    fn replacing_shared_values_leaves_the_copy_alone() {
        let mut system = ConstraintSystem::new();
        let ids: Vec<ParamId> = (0..4)
            .map(|k| {
                system
                    .add_parameter(format!("p{k}"), 1 + k % 2)
                    .expect("parameter")
            })
            .collect();
        let q = |n: i64, d: i64| Rational::new(n.into(), d.into());
        let data = vec![
            vec![q(1, 2)],
            vec![q(3, 1), q(-4, 3)],
            vec![q(5, 7)],
            vec![q(0, 1), q(9, 4)],
        ];
        let mut values = Values::from_vecs(&system, data.clone()).expect("values");
        let before = values.clone();
        let updates = vec![
            (ids[1], vec![q(6, 5), q(1, 1)]),
            (ids[2], vec![q(2, 3)]),
            (ids[1], vec![q(7, 5), q(-1, 1)]),
        ];
        values.replace_all(updates.clone());
        for (k, id) in ids.iter().enumerate() {
            assert_eq!(before.get(*id), data[k].as_slice(), "the copy, p{k}");
        }
        let expected = [
            data[0].clone(),
            vec![q(7, 5), q(-1, 1)],
            vec![q(2, 3)],
            data[3].clone(),
        ];
        for (k, id) in ids.iter().enumerate() {
            assert_eq!(values.get(*id), expected[k].as_slice(), "replaced, p{k}");
        }
        drop(before);
        let mut unshared = Values::from_vecs(&system, data).expect("values");
        unshared.replace_all(updates);
        for (k, id) in ids.iter().enumerate() {
            assert_eq!(unshared.get(*id), expected[k].as_slice(), "in place, p{k}");
        }
    }

    /// Residuals of values over denominators that share almost all their factors (`D / 6`,
    /// `D / 10`, `D`), through the short Euclid, and over coprime ones, through the product.
    #[test]
    fn residuals_over_related_and_unrelated_denominators() {
        let d = Integer::from(2).pow(300u32) * Integer::from(3).pow(90u32) * Integer::from(5);
        let q = |n: i64, den: &Integer| Rational::new(Integer::from(n), den.clone());
        let terms = [Integer::from(1), Integer::from(1), Integer::from(-1)];
        let sum = |values: [Rational; 3]| {
            exact_residual(values.iter().zip(terms.iter()), &Integer::from(0))
        };
        let (sixth, tenth) = (&d / 6, &d / 10);
        assert_eq!(sum([q(1, &sixth), q(1, &tenth), q(16, &d)]), None);
        assert_eq!(
            sum([q(1, &sixth), q(1, &tenth), q(17, &d)]),
            Some(q(-1, &d))
        );
        let p = Integer::from(2).pow(127u32) - 1;
        assert_eq!(
            sum([q(1, &p), q(1, &d), Rational::new(&p + &d, &p * &d)]),
            None
        );
    }

    fn r(n: i64) -> Rational {
        Rational::from_integer(n.into())
    }

    /// `term_params` names each term's parameter in order, repeats included; `params` is the
    /// same set sorted without repeats.
    #[test]
    fn term_params_follow_the_terms() {
        let vector = RowBody::Vector {
            terms: vec![(ParamId(4), 1.into()), (ParamId(2), (-1).into())],
            rhs: vec![0.into(), 0.into()],
        };
        assert_eq!(
            vector.term_params().collect::<Vec<_>>(),
            [ParamId(4), ParamId(2)]
        );
        assert_eq!(vector.params(), [ParamId(2), ParamId(4)]);
        let coord = |p: u32, component: usize| Coord {
            param: ParamId(p),
            component,
        };
        let scalar = RowBody::Scalar {
            terms: vec![
                (coord(3, 1), 2.into()),
                (coord(1, 0), 1.into()),
                (coord(3, 0), 1.into()),
            ],
            rhs: 5.into(),
        };
        assert_eq!(
            scalar.term_params().collect::<Vec<_>>(),
            [ParamId(3), ParamId(1), ParamId(3)]
        );
        assert_eq!(scalar.params(), [ParamId(1), ParamId(3)]);
    }

    #[test]
    fn vector_rows_expand_per_coordinate() {
        let mut s = ConstraintSystem::new();
        let a = s.add_parameter("a", 2).unwrap();
        let b = s.add_parameter("b", 2).unwrap();
        let t = s.add_parameter("t", 1).unwrap();
        s.add_row(ConstraintRow {
            label: "a=b".into(),
            origin: Origin::default(),
            body: RowBody::Vector {
                terms: vec![(a, 1.into()), (b, (-1).into())],
                rhs: vec![0.into(), 1.into()],
            },
        })
        .unwrap();
        s.add_row(ConstraintRow {
            label: "ax=t".into(),
            origin: Origin::default(),
            body: RowBody::Scalar {
                terms: vec![
                    (
                        Coord {
                            param: a,
                            component: 0,
                        },
                        1.into(),
                    ),
                    (
                        Coord {
                            param: t,
                            component: 0,
                        },
                        (-1).into(),
                    ),
                ],
                rhs: 0.into(),
            },
        })
        .unwrap();
        let (m, q, origin) = s.scalar_matrix();
        assert_eq!(m.rows(), 3);
        assert_eq!(m.cols(), 5);
        assert_eq!(m.get(1, 1), Integer::from(1));
        assert_eq!(m.get(1, 3), Integer::from(-1));
        assert_eq!(m.get(2, 4), Integer::from(-1));
        assert_eq!(q[1], Integer::from(1));
        assert_eq!(origin[1], (RowId(0), 1));

        let values =
            Values::from_vecs(&s, vec![vec![r(1), r(2)], vec![r(1), r(1)], vec![r(1)]]).unwrap();
        assert!(s.violations(&values).is_empty());
        let values =
            Values::from_vecs(&s, vec![vec![r(1), r(2)], vec![r(1), r(2)], vec![r(1)]]).unwrap();
        assert_eq!(s.violations(&values), vec![(RowId(0), 1, r(-1))]);
    }

    /// A chain `p_{i+1} − p_i = (1, 0)` long enough to be checked in parallel, at `p_i = (i, 1/3)`
    /// with three points moved by `(0, 1/7)`: exactly the rows at those points are reported, in
    /// row order, with their residuals.
    #[test]
    fn large_systems_report_every_violation_in_row_order() {
        let n = 3 * PARALLEL_ROWS_FROM;
        let mut s = ConstraintSystem::new();
        let points: Vec<ParamId> = (0..=n)
            .map(|i| s.add_parameter(format!("p{i}"), 2).unwrap())
            .collect();
        for i in 0..n {
            s.add_row(ConstraintRow {
                label: format!("step {i}"),
                origin: Origin::default(),
                body: RowBody::Vector {
                    terms: vec![(points[i + 1], 1.into()), (points[i], (-1).into())],
                    rhs: vec![1.into(), 0.into()],
                },
            })
            .unwrap();
        }
        let third = Rational::new(1.into(), 3.into());
        let seventh = Rational::new(1.into(), 7.into());
        let moved = [5usize, PARALLEL_ROWS_FROM + 3, n];
        let at = |moved: &[usize]| {
            let columns = (0..=n)
                .map(|i| {
                    let y = if moved.contains(&i) {
                        &third + &seventh
                    } else {
                        third.clone()
                    };
                    vec![r(i as i64), y]
                })
                .collect();
            Values::from_vecs(&s, columns).unwrap()
        };
        assert!(s.violations(&at(&[])).is_empty());
        // Row i reads y_{i+1} − y_i: −1/7 after a moved point, 1/7 before one.
        let expected = vec![
            (RowId(4), 1, seventh.clone()),
            (RowId(5), 1, -&seventh),
            (RowId(PARALLEL_ROWS_FROM as u32 + 2), 1, seventh.clone()),
            (RowId(PARALLEL_ROWS_FROM as u32 + 3), 1, -&seventh),
            (RowId(n as u32 - 1), 1, seventh.clone()),
        ];
        assert_eq!(s.violations(&at(&moved)), expected);
    }

    /// The residual summed as unreduced fractions equals the one summed with `Ratio`'s reducing
    /// additions, for equal, different and coprime denominators.
    #[test]
    fn residuals_are_exact_sums_without_reducing_on_the_way() {
        let q = |n: i64, d: i64| Rational::new(n.into(), d.into());
        let cases: Vec<(Vec<(Rational, i64)>, i64)> = vec![
            (vec![(q(1, 3), 3), (q(2, 3), -3)], -1),
            (vec![(q(1, 6), 6), (q(1, 10), 10), (q(5, 7), 7)], 7),
            (vec![(q(1, 6), 6), (q(1, 10), 10), (q(5, 7), 7)], 6),
            (vec![(q(-7, 12), 5), (q(7, 12), 5), (q(1, 2), 0)], 0),
            (vec![], 4),
        ];
        for (terms, rhs) in cases {
            let expected = terms.iter().fold(-r(rhs), |acc, (x, c)| acc + x * r(*c));
            let coefficients: Vec<Integer> = terms.iter().map(|(_, c)| (*c).into()).collect();
            let got = exact_residual(terms.iter().map(|(x, _)| x).zip(&coefficients), &rhs.into());
            assert_eq!(got, (!expected.is_zero()).then_some(expected));
        }
    }

    proptest::proptest! {
        /// The word-size residual, when it answers, is the exact one; when the terms overflow
        /// (numerators and denominators up to `i64::MAX`) it declines and the big-integer path
        /// answers, also exactly.
        #[test]
        fn word_residuals_are_exact_or_decline(
            terms in proptest::collection::vec(
                (
                    proptest::prop_oneof![-1000i64..1000, proptest::num::i64::ANY],
                    proptest::prop_oneof![1i64..60, 1i64..i64::MAX],
                    proptest::prop_oneof![-6i64..7, proptest::num::i64::ANY],
                ),
                0..8,
            ),
            rhs in proptest::prop_oneof![-100i64..100, proptest::num::i64::ANY],
        ) {
            let values: Vec<Rational> =
                terms.iter().map(|(n, d, _)| Rational::new((*n).into(), (*d).into())).collect();
            let coefficients: Vec<Integer> = terms.iter().map(|(_, _, c)| (*c).into()).collect();
            let expected = values
                .iter()
                .zip(&coefficients)
                .fold(Rational::from_integer((-rhs).into()), |acc, (x, c)| {
                    acc + x * Rational::from_integer(c.clone())
                });
            let expected = (!expected.is_zero()).then_some(expected);
            let rhs = Integer::from(rhs);
            if let Some(word) = word_residual(values.iter().zip(&coefficients), &rhs) {
                proptest::prop_assert_eq!(&word, &expected);
            }
            proptest::prop_assert_eq!(exact_residual(values.iter().zip(&coefficients), &rhs), expected);
        }
    }

    /// Rows added at once (adopted by an empty system, appended to a non-empty one) give the
    /// system of rows added one by one: merged terms, incidence lists; a bad row adds nothing.
    #[test]
    fn rows_added_at_once_equal_rows_added_one_by_one() {
        let params = |s: &mut ConstraintSystem| -> Vec<ParamId> {
            (0..4)
                .map(|k| s.add_parameter(format!("p{k}"), 1 + k % 2).unwrap())
                .collect()
        };
        let scalar = |p: ParamId, c: i64| {
            (
                Coord {
                    param: p,
                    component: 0,
                },
                Integer::from(c),
            )
        };
        let rows = |p: &[ParamId]| {
            vec![
                ConstraintRow {
                    label: "vector, unsorted, repeated".into(),
                    origin: Origin::default(),
                    body: RowBody::Vector {
                        terms: vec![(p[3], 2.into()), (p[1], 1.into()), (p[3], (-2).into())],
                        rhs: vec![0.into(), 1.into()],
                    },
                },
                ConstraintRow {
                    label: "scalar, merged".into(),
                    origin: Origin::default(),
                    body: RowBody::Scalar {
                        terms: vec![scalar(p[0], 1), scalar(p[1], -1), scalar(p[2], 3)],
                        rhs: 4.into(),
                    },
                },
                ConstraintRow {
                    label: "scalar, repeated parameter".into(),
                    origin: Origin::default(),
                    body: RowBody::Scalar {
                        terms: vec![
                            scalar(p[2], 1),
                            (
                                Coord {
                                    param: p[1],
                                    component: 1,
                                },
                                Integer::from(5),
                            ),
                            scalar(p[1], 1),
                        ],
                        rhs: 0.into(),
                    },
                },
            ]
        };
        let mut one_by_one = ConstraintSystem::new();
        let p = params(&mut one_by_one);
        for _ in 0..2 {
            for row in rows(&p) {
                one_by_one.add_row(row).unwrap();
            }
        }
        let mut at_once = ConstraintSystem::new();
        params(&mut at_once);
        at_once.add_rows(rows(&p)).unwrap();
        at_once.add_rows(rows(&p)).unwrap();
        assert_eq!(at_once, one_by_one);
        assert_eq!(at_once.incidence, one_by_one.incidence);
        assert_eq!(
            at_once.incidence[p[1].index()],
            vec![RowId(0), RowId(1), RowId(2), RowId(3), RowId(4), RowId(5)]
        );
        assert!(matches!(
            &at_once.rows()[0].body,
            RowBody::Vector { terms, .. } if terms == &vec![(p[1], Integer::from(1))]
        ));

        let mut bad = rows(&p);
        bad.push(ConstraintRow {
            label: "unknown parameter".into(),
            origin: Origin::default(),
            body: RowBody::Scalar {
                terms: vec![scalar(ParamId(9), 1)],
                rhs: 0.into(),
            },
        });
        let mut empty = ConstraintSystem::new();
        params(&mut empty);
        let before = empty.clone();
        assert!(matches!(
            empty.add_rows(bad),
            Err(SystemError::UnknownParameter { .. })
        ));
        assert_eq!(empty, before);
        assert!(empty.incidence.iter().all(Vec::is_empty));
    }

    #[test]
    fn rejects_bad_rows_and_names() {
        let mut s = ConstraintSystem::new();
        let a = s.add_parameter("a", 2).unwrap();
        assert!(matches!(
            s.add_parameter("a", 1),
            Err(SystemError::DuplicateParameter { .. })
        ));
        assert!(matches!(
            s.add_parameter("z", 0),
            Err(SystemError::ZeroDimension { .. })
        ));
        let bad_dim = ConstraintRow {
            label: "x".into(),
            origin: Origin::default(),
            body: RowBody::Vector {
                terms: vec![(a, 1.into())],
                rhs: vec![0.into()],
            },
        };
        assert!(matches!(
            s.add_row(bad_dim),
            Err(SystemError::DimensionMismatch { .. })
        ));
        let bad_id = ConstraintRow {
            label: "y".into(),
            origin: Origin::default(),
            body: RowBody::Scalar {
                terms: vec![(
                    Coord {
                        param: ParamId(7),
                        component: 0,
                    },
                    1.into(),
                )],
                rhs: 0.into(),
            },
        };
        assert!(matches!(
            s.add_row(bad_id),
            Err(SystemError::UnknownParameter { .. })
        ));
        let bad_component = ConstraintRow {
            label: "z".into(),
            origin: Origin::default(),
            body: RowBody::Scalar {
                terms: vec![(
                    Coord {
                        param: a,
                        component: 2,
                    },
                    1.into(),
                )],
                rhs: 0.into(),
            },
        };
        assert!(matches!(
            s.add_row(bad_component),
            Err(SystemError::ComponentOutOfRange { .. })
        ));
        assert!(matches!(
            Values::from_vecs(&s, vec![vec![r(1)]]),
            Err(SystemError::WrongValueDimension { .. })
        ));
    }
}
