//! Change criteria for an edit (Brenner 3.1): which of the derived values that keep every
//! relevant constraint an Update returns.
//!
//! ECLES returns the derived values of least weighted squared distance to the hints
//! ([`Measure::L2`] on every derived parameter, the default). [`Edit::update_by`] offers the
//! others of the `criteria` crate — least squares on primary parameters first, least absolute
//! change, fewest changed parameters — on the same edit: the change `y = x_D − h` from the
//! hints `h` ranges over `R_ED y = b(α) − R_ED h`, exactly the family the least-squares update
//! chooses from. The least-squares update runs first: it gives the verdict (a refused move
//! keeps today's conflict certificate) and one exact solution `x*`, whose `R_ED (x* − h)` is
//! the right-hand side, so no right-hand side is formed twice.

use crate::edit::{Edit, Layout, UpdateResult};
use crate::error::EditError;
use api::{Factorization, ParamId, Rational};
pub use criteria::Measure;
use num_traits::Zero;

/// How an Update chooses among the derived values that keep every constraint.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Criterion {
    /// What is minimised over the change from the hints.
    pub measure: Measure,
    /// The primary parameters: the measure is minimised over those among the derived ones
    /// first, the others then take their least weighted-squares change. `None`: every derived
    /// parameter is primary.
    pub primary: Option<Vec<ParamId>>,
}

impl Default for Criterion {
    fn default() -> Self {
        Criterion {
            measure: Measure::L2,
            primary: None,
        }
    }
}

impl Criterion {
    /// ECLES' own criterion: least weighted squares over every derived parameter.
    pub fn is_least_squares(&self) -> bool {
        self.measure == Measure::L2 && self.primary.is_none()
    }
}

/// What an Update under a criterion chose, beside the values.
#[derive(Debug, Clone, PartialEq)]
pub struct CriterionSummary {
    /// The measure minimised.
    pub measure: Measure,
    /// Derived parameters that were primary (all of them without a primary set), in edit
    /// order.
    pub primary: Vec<ParamId>,
    /// The measure of the change over the primary parameters.
    pub value: Rational,
    /// Derived parameters that changed (differ from their hints), in edit order.
    pub changed: Vec<ParamId>,
    /// L1: dimension of the set of optimal changes (0: unique).
    pub optimal_face_dimension: Option<usize>,
    /// Fewest: the minimum supports.
    pub supports: Option<SupportSummary>,
}

/// The minimum supports of a Fewest change, as parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct SupportSummary {
    /// Other sets of primary parameters of the same size that could carry the change (at most
    /// 31 listed).
    pub ties: Vec<Vec<ParamId>>,
    /// Minimum supports found, the chosen one included (all of them when `ties_complete`).
    pub count: usize,
    /// Whether every minimum support was found.
    pub ties_complete: bool,
    /// False when the exact search was over its budget and a heuristic answered.
    pub proven_minimal: bool,
    /// Exact rank tests made.
    pub rank_tests: usize,
}

impl<F: Factorization<Scalar = Rational>> Edit<F> {
    /// ECLES.Update under `criterion`: the same verdict as [`Edit::update`], the derived values
    /// chosen by the criterion (see the module documentation). Every relevant constraint
    /// holds exactly, as for [`Edit::update`].
    pub fn update_by(
        &self,
        criterion: &Criterion,
        anchor_values: &[Vec<Rational>],
        hints: &[Vec<Rational>],
    ) -> Result<(UpdateResult<Rational>, CriterionSummary), EditError<Rational>> {
        let optimum = self.update(anchor_values, hints)?;
        let derived = self.derived();
        let r_ed = self.reduced().r_ed();
        let (rows, unknowns) = (r_ed.rows(), r_ed.cols());
        if rows.saturating_mul(unknowns) > criteria::DENSE_LIMIT {
            return Err(EditError::Criterion(criteria::CriterionError::TooLarge {
                rows,
                unknowns,
                limit: criteria::DENSE_LIMIT,
            }));
        }
        let is_primary = |p: &ParamId| {
            criterion
                .primary
                .as_ref()
                .is_none_or(|primary| primary.contains(p))
        };
        // Unknowns: parameters (vector layout, one right-hand side per coordinate) or their
        // coordinates (scalar layout, one right-hand side); the group of an unknown is its
        // parameter.
        let (groups, columns): (Vec<usize>, usize) = match self.layout() {
            Layout::Vector { dim } => ((0..derived.len()).collect(), dim),
            Layout::Scalar => (
                hints
                    .iter()
                    .enumerate()
                    .flat_map(|(k, h)| std::iter::repeat_n(k, h.len()))
                    .collect(),
                1,
            ),
        };
        // The least-squares change from the hints, per right-hand side.
        let optimum_values: Vec<&Vec<Rational>> = optimum.derived.iter().map(|(_, v)| v).collect();
        let changes: Vec<Vec<Rational>> = match self.layout() {
            Layout::Vector { .. } => (0..columns)
                .map(|k| {
                    optimum_values
                        .iter()
                        .zip(hints)
                        .map(|(x, h)| &x[k] - &h[k])
                        .collect()
                })
                .collect(),
            Layout::Scalar => vec![optimum_values
                .iter()
                .copied()
                .flatten()
                .zip(hints.iter().flatten())
                .map(|(x, h)| x - h)
                .collect()],
        };
        let matrix: Vec<Vec<Rational>> = r_ed
            .to_dense()
            .into_iter()
            .map(|row| row.into_iter().map(Rational::from_integer).collect())
            .collect();
        let rhs: Vec<Vec<Rational>> = changes
            .iter()
            .map(|change| {
                matrix
                    .iter()
                    .map(|row| {
                        row.iter()
                            .zip(change)
                            .filter(|(a, y)| !a.is_zero() && !y.is_zero())
                            .map(|(a, y)| a * y)
                            .sum()
                    })
                    .collect()
            })
            .collect();
        let problem = criteria::Problem {
            matrix,
            rhs,
            weights: self.weights().to_vec(),
            primary: criterion
                .primary
                .as_ref()
                .map(|_| groups.iter().map(|&g| is_primary(&derived[g])).collect()),
            groups,
        };
        let solution =
            criteria::solve(&problem, criterion.measure).map_err(EditError::Criterion)?;
        // x = h + y, per parameter.
        let mut values: Vec<Vec<Rational>> = hints.to_vec();
        match self.layout() {
            Layout::Vector { .. } => {
                for (k, change) in solution.changes.iter().enumerate() {
                    for (value, y) in values.iter_mut().zip(change) {
                        value[k] += y;
                    }
                }
            }
            Layout::Scalar => {
                let mut change = solution.changes[0].iter();
                for value in values.iter_mut() {
                    for (v, y) in value.iter_mut().zip(change.by_ref()) {
                        *v += y;
                    }
                }
            }
        }
        let changed: Vec<ParamId> = derived
            .iter()
            .zip(values.iter().zip(hints))
            .filter(|(_, (v, h))| v != h)
            .map(|(p, _)| *p)
            .collect();
        let as_params =
            |set: &Vec<usize>| -> Vec<ParamId> { set.iter().map(|&g| derived[g]).collect() };
        let summary = CriterionSummary {
            measure: criterion.measure,
            primary: derived.iter().copied().filter(|p| is_primary(p)).collect(),
            value: solution.measure,
            changed,
            optimal_face_dimension: solution.optimal_face_dimension,
            supports: solution.supports.map(|s| SupportSummary {
                ties: s.ties.iter().map(as_params).collect(),
                count: s.count,
                ties_complete: s.ties_complete,
                proven_minimal: s.proven_minimal,
                rank_tests: s.rank_tests,
            }),
        };
        Ok((
            UpdateResult {
                anchors: optimum.anchors,
                derived: derived.iter().copied().zip(values).collect(),
            },
            summary,
        ))
    }
}
