//! Change criteria for an exactly constrained edit (Brenner, section 3.1).
//!
//! An edit leaves a family of possible changes: every `y` with `M y = t_k`, one system per
//! right-hand side `k` (one per coordinate of vector parameters, all sharing `M`). ECLES picks
//! the one of least weighted squares. Brenner shows why that is not always what a user
//! expects — least squares "tends to change many variables by a small amount" — and lays out
//! the alternatives. This crate decides each of them exactly, over the rationals:
//!
//! * [`Measure::L2`]: least `Σ w_j y_j²` (ECLES' own criterion);
//! * [`Measure::L1`]: least `Σ w_j |y_j|`, an exact rational linear program
//!   ([`least_absolute`](crate::least_absolute)), with the dimension of the set of optima;
//! * [`Measure::Fewest`]: fewest changed parameters (groups of unknowns), by branch over
//!   supports with exact rank tests (implicit hitting sets) up to [`FEWEST_EXACT_WORK`], a
//!   flagged heuristic beyond.
//!
//! Each can be restricted to **primary** unknowns ([`Problem::primary`]): the measure is then
//! minimised over the primary unknowns only, the others left free; among those optima the
//! secondary unknowns take their least weighted-squares change (lexicographic, Brenner figure
//! 3(b)). The secondary unknowns are eliminated exactly first (the rows of the Gauss–Jordan
//! form that no longer involve them are what the primary unknowns must satisfy), so the first
//! stage is the same problem on fewer unknowns.
//!
//! The routines are dense and exact; problems beyond [`DENSE_LIMIT`] matrix entries are
//! refused before any work.

mod dense;
mod fewest;
mod least_absolute;
mod simplex;

use api::Rational;
use dense::{eliminate, least_norm, times, Matrix};
use num_traits::{Signed, Zero};

/// Most entries (rows × unknowns) of a problem the criteria accept: dense exact elimination
/// and simplex pivots cost about `rows × unknowns` rational operations each.
pub const DENSE_LIMIT: usize = 250_000;

/// The work of the exact search for the fewest changed parameters, in matrix entries its rank
/// tests eliminate (a test costs the entries of its matrix): beyond it the search falls back to
/// its heuristic (the tie search stops there too). About a second on spline edits.
pub const FEWEST_EXACT_WORK: usize = 20_000_000;

/// What is minimised.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Measure {
    /// The weighted sum of squared changes.
    L2,
    /// The weighted sum of absolute changes.
    L1,
    /// The number of changed groups (unweighted).
    Fewest,
}

/// The family of changes: `y` with `matrix · y = rhs[k]` for every `k`.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// `M`, row by row.
    pub matrix: Vec<Vec<Rational>>,
    /// The right-hand sides, each of `matrix.len()` values.
    pub rhs: Vec<Vec<Rational>>,
    /// One positive weight per unknown.
    pub weights: Vec<Rational>,
    /// The group (parameter) of each unknown, numbered from 0: what [`Measure::Fewest`]
    /// counts.
    pub groups: Vec<usize>,
    /// Which unknowns are primary; `None`: all.
    pub primary: Option<Vec<bool>>,
}

/// A chosen change and what is known of its optimality.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// The change, one vector of unknowns per right-hand side.
    pub changes: Vec<Vec<Rational>>,
    /// The measure of the change over the primary unknowns (all unknowns without a primary
    /// set): `Σ w y²`, `Σ w |y|` or the number of changed groups.
    pub measure: Rational,
    /// For L1: the dimension of the set of optimal changes of the primary unknowns (0: the
    /// optimum is unique).
    pub optimal_face_dimension: Option<usize>,
    /// For Fewest: the supports.
    pub supports: Option<Supports>,
    /// Simplex pivots made (L1, and Fewest's heuristic).
    pub pivots: usize,
}

/// The minimum supports of a Fewest change.
#[derive(Debug, Clone, PartialEq)]
pub struct Supports {
    /// Primary groups changed by the chosen change (ascending).
    pub chosen: Vec<usize>,
    /// Other supports of the same size, each as primary groups (at most 31 listed).
    pub ties: Vec<Vec<usize>>,
    /// The supports of that size found (the chosen one included): all of them when
    /// `ties_complete`.
    pub count: usize,
    /// Whether every support of that size was found (the tie search stayed within its
    /// budget).
    pub ties_complete: bool,
    /// Whether no support is smaller: false when the search exceeded
    /// [`FEWEST_EXACT_WORK`] and the heuristic answered.
    pub proven_minimal: bool,
    /// Exact rank tests made.
    pub rank_tests: usize,
}

/// Why a criterion gave no change.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CriterionError {
    /// The problem's parts do not fit together.
    #[error("malformed change problem: {0}")]
    Shape(String),
    /// A weight is zero or negative.
    #[error("weight {index} is {weight}; weights must be positive")]
    Weight {
        /// The unknown.
        index: usize,
        /// Its weight, as text.
        weight: String,
    },
    /// Too many entries for the dense exact methods.
    #[error("the change problem has {rows} rows and {unknowns} unknowns, more than the {limit} entries the exact criteria work on; use L2")]
    TooLarge {
        /// Rows of `M`.
        rows: usize,
        /// Unknowns.
        unknowns: usize,
        /// [`DENSE_LIMIT`].
        limit: usize,
    },
    /// A right-hand side is not reachable.
    #[error("right-hand side {0} is not in the span of the matrix: no change satisfies every row")]
    Inconsistent(usize),
}

/// The change of `problem` that minimises `measure` (see the crate documentation).
pub fn solve(problem: &Problem, measure: Measure) -> Result<Solution, CriterionError> {
    validate(problem)?;
    let n = problem.weights.len();
    let primary: Vec<usize> = (0..n).filter(|&j| is_primary(problem, j)).collect();
    let secondary: Vec<usize> = (0..n).filter(|&j| !is_primary(problem, j)).collect();
    let matrix: &Matrix = &problem.matrix;
    for (k, t) in problem.rhs.iter().enumerate() {
        if dense::independent_rows(matrix, t).is_none() {
            return Err(CriterionError::Inconsistent(k));
        }
    }
    // Stage 1: the primary unknowns, the secondary ones eliminated.
    let (projected, projected_rhs) = eliminate(matrix, &problem.rhs, &secondary, &primary);
    let weights: Vec<Rational> = primary
        .iter()
        .map(|&j| problem.weights[j].clone())
        .collect();
    let all: Vec<usize> = (0..primary.len()).collect();
    let inconsistent = CriterionError::Inconsistent;
    let mut optimal_face_dimension = None;
    let mut supports = None;
    let mut pivots = 0;
    let primary_changes: Vec<Vec<Rational>> = match measure {
        Measure::L2 => projected_rhs
            .iter()
            .enumerate()
            .map(|(k, t)| least_norm(&projected, t, &weights, &all).ok_or(inconsistent(k)))
            .collect::<Result<_, _>>()?,
        Measure::L1 => {
            let mut dimension = 0;
            let mut changes = Vec::with_capacity(projected_rhs.len());
            for (k, t) in projected_rhs.iter().enumerate() {
                let l1 = least_absolute::least_absolute_change(&projected, t, &weights)
                    .ok_or(inconsistent(k))?;
                dimension += l1.face_dimension;
                pivots += l1.pivots;
                changes.push(l1.y);
            }
            optimal_face_dimension = Some(dimension);
            changes
        }
        Measure::Fewest => {
            // Groups renumbered over the primary unknowns (in order of first appearance).
            let mut numbering: Vec<Option<usize>> = vec![None; n];
            let mut original = Vec::new();
            let groups: Vec<usize> = primary
                .iter()
                .map(|&j| {
                    let g = problem.groups[j];
                    *numbering[g].get_or_insert_with(|| {
                        original.push(g);
                        original.len() - 1
                    })
                })
                .collect();
            let (found, count) = fewest::fewest_changed(
                &projected,
                &projected_rhs,
                &weights,
                &groups,
                FEWEST_EXACT_WORK,
            )
            .ok_or(inconsistent(0))?;
            let rename = |set: &Vec<usize>| -> Vec<usize> {
                let mut set: Vec<usize> = set.iter().map(|&g| original[g]).collect();
                set.sort_unstable();
                set
            };
            let mut listed = found.supports.iter().map(rename);
            supports = Some(Supports {
                chosen: listed.next().unwrap_or_default(),
                ties: listed.collect(),
                count,
                ties_complete: found.ties_complete,
                proven_minimal: found.proven_minimal,
                rank_tests: found.rank_tests,
            });
            found.y
        }
    };
    // Stage 2: the secondary unknowns, least squares for what the primary ones leave.
    let mut changes = vec![vec![Rational::zero(); n]; problem.rhs.len()];
    for (k, (change, primary_change)) in changes.iter_mut().zip(&primary_changes).enumerate() {
        for (&j, y) in primary.iter().zip(primary_change) {
            change[j] = y.clone();
        }
        if secondary.is_empty() {
            continue;
        }
        let carried = times(matrix, change);
        let rest: Vec<Rational> = problem.rhs[k]
            .iter()
            .zip(&carried)
            .map(|(t, c)| t - c)
            .collect();
        let secondary_change =
            least_norm(matrix, &rest, &problem.weights, &secondary).ok_or(inconsistent(k))?;
        for &j in &secondary {
            change[j] = secondary_change[j].clone();
        }
    }
    let measure_value = measure_of(problem, measure, &primary, &changes);
    Ok(Solution {
        changes,
        measure: measure_value,
        optimal_face_dimension,
        supports,
        pivots,
    })
}

/// Whether unknown `j` is primary.
fn is_primary(problem: &Problem, j: usize) -> bool {
    problem.primary.as_ref().is_none_or(|p| p[j])
}

/// The measure of `changes` over the unknowns `primary`.
fn measure_of(
    problem: &Problem,
    measure: Measure,
    primary: &[usize],
    changes: &[Vec<Rational>],
) -> Rational {
    let mut total = Rational::zero();
    match measure {
        Measure::L2 | Measure::L1 => {
            for change in changes {
                for &j in primary {
                    let y = &change[j];
                    if y.is_zero() {
                        continue;
                    }
                    let size = if measure == Measure::L2 {
                        y * y
                    } else {
                        y.abs()
                    };
                    total += size * &problem.weights[j];
                }
            }
        }
        Measure::Fewest => {
            let mut changed: Vec<usize> = primary
                .iter()
                .filter(|&&j| changes.iter().any(|c| !c[j].is_zero()))
                .map(|&j| problem.groups[j])
                .collect();
            changed.sort_unstable();
            changed.dedup();
            total = Rational::from_integer(changed.len().into());
        }
    }
    total
}

/// Checks shapes, weights and the size bound before any work.
fn validate(problem: &Problem) -> Result<(), CriterionError> {
    let n = problem.weights.len();
    let rows = problem.matrix.len();
    let shape = |message: String| Err(CriterionError::Shape(message));
    if let Some(row) = problem.matrix.iter().position(|r| r.len() != n) {
        return shape(format!(
            "row {row} has {} entries for {n} unknowns",
            problem.matrix[row].len()
        ));
    }
    if let Some(k) = problem.rhs.iter().position(|t| t.len() != rows) {
        return shape(format!(
            "right-hand side {k} has {} values for {rows} rows",
            problem.rhs[k].len()
        ));
    }
    if problem.groups.len() != n {
        return shape(format!("{} groups for {n} unknowns", problem.groups.len()));
    }
    if problem.groups.iter().any(|&g| g >= n) {
        return shape("a group number is not below the number of unknowns".into());
    }
    if let Some(primary) = &problem.primary {
        if primary.len() != n {
            return shape(format!("{} primary flags for {n} unknowns", primary.len()));
        }
    }
    if let Some(index) = problem.weights.iter().position(|w| !w.is_positive()) {
        return Err(CriterionError::Weight {
            index,
            weight: problem.weights[index].to_string(),
        });
    }
    if rows.saturating_mul(n) > DENSE_LIMIT {
        return Err(CriterionError::TooLarge {
            rows,
            unknowns: n,
            limit: DENSE_LIMIT,
        });
    }
    Ok(())
}
