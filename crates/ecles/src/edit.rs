//! ECLES.Initialize and ECLES.Update (thesis, algorithms 1, 3, 4, 5).

use crate::error::{Conflict, ConflictingRow, EditError};
use crate::hint_columns::HintColumn;
use crate::reduce::{reduce, ReducedSystem};
use crate::relevant::{extract_relevant, Relevant};
use crate::substitute::Substitution;
use api::Value;
use api::{
    ConstraintSystem, Factorization, Fraction, Inconsistency, LinearBackend, ParamId,
    PreparedLeastSquares, Rational, RowId, SolveError, StrongFailure, Values,
};
use num_traits::{One, Signed};
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::Arc;

/// A row of `R_ED` and its combination of independent rows (indices into `R_ED`).
type Combination<S> = (usize, Vec<(usize, S)>);

/// The coordinates of a vector-layout update are solved on separate threads when `R_ED` has
/// at least this many columns (below, waking a thread costs more than a column's solve).
const PARALLEL_COLUMNS_ABOVE: usize = 128;

/// What the user asks for: anchors `A`, derived parameters `D` with weights, and whether strong
/// solvability must be checked at initialisation.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct EditSpec {
    /// `A`: parameters whose new values are given (at least one).
    pub anchors: Vec<ParamId>,
    /// `D`: parameters that may change to keep the constraints (disjoint from `A`).
    pub derived: Vec<ParamId>,
    /// One positive weight per derived parameter (all 1 when `None`): how strongly its hint is
    /// honoured.
    pub weights: Option<Vec<Rational>>,
    /// Check at initialisation that every anchor value is reachable (algorithm 3).
    pub strong: bool,
}

impl EditSpec {
    /// An edit with unit weights and no strong check.
    pub fn new(anchors: Vec<ParamId>, derived: Vec<ParamId>) -> Self {
        EditSpec {
            anchors,
            derived,
            weights: None,
            strong: false,
        }
    }

    /// Sets one weight per derived parameter.
    pub fn with_weights(mut self, weights: Vec<Rational>) -> Self {
        self.weights = Some(weights);
        self
    }

    /// Requests the strong-solvability check.
    pub fn strong(mut self) -> Self {
        self.strong = true;
        self
    }
}

/// How the reduced system is laid out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// All relevant rows are vector rows of dimension `dim` over parameters of that dimension:
    /// one unknown per parameter and `dim` right-hand sides sharing one factorization.
    Vector {
        /// The common dimension.
        dim: usize,
    },
    /// One unknown per coordinate (vector rows are split into one scalar row per coordinate).
    Scalar,
}

/// A row of the reduced system: a constraint and, when a vector row was split, the coordinate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct RowRef {
    /// The constraint.
    pub row: RowId,
    /// The coordinate of a split vector row (`None` for scalar rows and vector layouts).
    pub component: Option<usize>,
}

/// What initialisation found out about an edit.
#[derive(Debug, Clone, PartialEq)]
pub struct InitReport<S> {
    /// Name of the backend.
    pub backend: &'static str,
    /// `E`, the relevant constraints.
    pub relevant: Vec<RowId>,
    /// `F'`, the fixed relevant parameters.
    pub fixed_relevant: Vec<ParamId>,
    /// The layout of the reduced system.
    pub layout: Layout,
    /// Equations of the reduced system (rows of `R_ED`).
    pub equations: usize,
    /// Unknowns of the reduced system (columns of `R_ED`).
    pub unknowns: usize,
    /// Rank of `R_ED`.
    pub rank: usize,
    /// Rows kept as independent.
    pub independent: Vec<RowRef>,
    /// Each redundant row with the combination of independent rows equal to it.
    pub redundant: Vec<(RowRef, Vec<(RowRef, S)>)>,
    /// `Some(true)` when strong solvability was checked (it failed otherwise), `None` when not
    /// asked.
    pub strongly_solvable: Option<bool>,
}

/// The outcome of one update: new values of the anchors (as given) and of the derived parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct UpdateResult<S> {
    /// Anchors with their required values.
    pub anchors: Vec<(ParamId, Vec<Rational>)>,
    /// Derived parameters with their computed values.
    pub derived: Vec<(ParamId, Vec<S>)>,
}

impl UpdateResult<Rational> {
    /// Writes the anchors' and derived parameters' values into `values` (the commit of an
    /// edit: [`Edit::apply`], and hosts that keep the result of an update to commit later).
    pub fn write_into(&self, values: &mut Values) {
        values.replace_all(self.anchors.iter().chain(&self.derived).cloned());
    }
}

/// What a snapped update ([`Edit::update_snapped`]) committed instead of the optimum.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SnapSummary {
    /// Free values are multiples of `2^−grid_bits`.
    pub grid_bits: u32,
    /// Every derived value is within this distance of the least-squares optimum's (an upper
    /// bound, proved exactly and rounded up).
    pub distance_bound: f64,
    /// Right-hand-side columns that could not be snapped and hold the optimum itself.
    pub optimum_columns: usize,
}

/// An initialised editing action: call [`Edit::update`] (or [`Edit::apply`]) once per new set of
/// anchor values and hints.
#[derive(Debug, Clone)]
pub struct Edit<F: Factorization> {
    backend: &'static str,
    anchors: Vec<ParamId>,
    anchor_names: Vec<Arc<str>>,
    anchor_dims: Vec<usize>,
    derived: Vec<ParamId>,
    derived_names: Vec<Arc<str>>,
    derived_dims: Vec<usize>,
    relevant: Relevant,
    layout: Layout,
    reduced: ReducedSystem,
    /// Trivial rows solved by substitution (`None` when there are none): the factoring, the
    /// checks and the least squares then work on its inner system.
    substitution: Option<Substitution>,
    /// One weight per unknown of `R_ED`.
    weights: Vec<Rational>,
    factorization: F,
    prepared: F::LeastSquares,
    strongly_solvable: Option<bool>,
    /// The last update's hints by coordinate column (vector layout).
    hint_columns: crate::hint_columns::HintColumns,
}

impl<F: Factorization> Edit<F> {
    /// ECLES.Initialize: validates `spec`, extracts the relevant part of `system`, factors
    /// `R_ED` with `backend`, checks strong solvability if asked, and prepares the
    /// least-squares solve. `values` supplies the current values of the fixed relevant
    /// parameters; they are captured here.
    pub fn initialize<B>(
        backend: &B,
        system: &ConstraintSystem,
        values: &Values,
        spec: &EditSpec,
    ) -> Result<Self, EditError<F::Scalar>>
    where
        B: LinearBackend<Factorization = F>,
    {
        Self::initialize_with(backend, system, values, spec, true)
    }

    /// [`Edit::initialize`], solving trivial rows by substitution or not (the answers are the
    /// same; the tests compare them).
    pub(crate) fn initialize_with<B>(
        backend: &B,
        system: &ConstraintSystem,
        values: &Values,
        spec: &EditSpec,
        substitute: bool,
    ) -> Result<Self, EditError<F::Scalar>>
    where
        B: LinearBackend<Factorization = F>,
    {
        if spec.anchors.is_empty() {
            return Err(EditError::NoAnchors);
        }
        Self::initialize_checked(backend, system, values, spec, substitute)
    }

    /// The projection of `values` onto the constraints: the smallest change of the `derived`
    /// parameters (weighted least squares with unit weights, exact) after which every row
    /// touching them holds, every other parameter fixed. What becomes of a state when rows are
    /// added to its system (a spline made smoother): the nearest state that keeps them. It is
    /// ECLES with no anchors; update it with no anchor values and the current values as hints
    /// ([`Edit::project`] does both).
    pub fn projection<B>(
        backend: &B,
        system: &ConstraintSystem,
        values: &Values,
        derived: Vec<ParamId>,
    ) -> Result<Self, EditError<F::Scalar>>
    where
        B: LinearBackend<Factorization = F>,
    {
        let spec = EditSpec::new(Vec::new(), derived);
        Self::initialize_checked(backend, system, values, &spec, true)
    }

    /// The projected values of [`Edit::projection`]: no anchors, the current values as hints.
    pub fn project(
        &self,
        values: &Values,
    ) -> Result<UpdateResult<F::Scalar>, EditError<F::Scalar>> {
        let hints: Vec<Vec<Rational>> = self
            .derived
            .iter()
            .map(|p| values.get(*p).to_vec())
            .collect();
        self.update(&[], &hints)
    }

    /// ECLES.Initialize after the anchor rule (at least one, except for a projection).
    fn initialize_checked<B>(
        backend: &B,
        system: &ConstraintSystem,
        values: &Values,
        spec: &EditSpec,
        substitute: bool,
    ) -> Result<Self, EditError<F::Scalar>>
    where
        B: LinearBackend<Factorization = F>,
    {
        validate_ids_and_weights(system, values, spec)?;
        let relevant = extract_relevant(system, &spec.anchors, &spec.derived);
        let reduced = reduce(system, values, spec, &relevant);

        let dims = |ids: &[ParamId]| -> Vec<usize> {
            ids.iter().map(|p| system.params()[p.index()].dim).collect()
        };
        let names = |ids: &[ParamId]| -> Vec<Arc<str>> {
            ids.iter()
                .map(|p| system.params()[p.index()].name.clone())
                .collect()
        };
        // One weight per unknown of `R_ED` (per coordinate in the scalar layout).
        let mut edit_weights = Vec::with_capacity(reduced.r_ed.cols());
        match &spec.weights {
            None => edit_weights.resize(reduced.r_ed.cols(), Rational::one()),
            Some(weights) => {
                for (w, p) in weights.iter().zip(&spec.derived) {
                    let copies = match reduced.layout {
                        Layout::Vector { .. } => 1,
                        Layout::Scalar => system.params()[p.index()].dim,
                    };
                    edit_weights.extend(std::iter::repeat_n(w.clone(), copies));
                }
            }
        }
        let substitution = substitute
            .then(|| Substitution::new(&reduced, &edit_weights))
            .flatten();
        let factored = substitution.as_ref().map_or(&reduced, Substitution::inner);
        let factorization = backend.factor(&factored.r_ed)?;
        let mut strongly_solvable = None;
        let anchor_names = names(&spec.anchors);
        let anchor_dims = dims(&spec.anchors);
        if spec.strong {
            strong_check(
                &factorization,
                &reduced,
                substitution.as_ref(),
                &anchor_names,
                &anchor_dims,
            )?;
            strongly_solvable = Some(true);
        }
        let factored_weights = match &substitution {
            Some(s) => s.group_weights(),
            None => &edit_weights,
        };
        let prepared = factorization.prepare_least_squares(&factored.family, factored_weights)?;
        Ok(Edit {
            backend: backend.name(),
            anchors: spec.anchors.clone(),
            anchor_names,
            anchor_dims,
            derived: spec.derived.clone(),
            derived_names: names(&spec.derived),
            derived_dims: dims(&spec.derived),
            relevant,
            layout: reduced.layout,
            reduced,
            substitution,
            weights: edit_weights,
            factorization,
            prepared,
            strongly_solvable,
            hint_columns: Default::default(),
        })
    }

    /// Only the strong-solvability test of an edit (algorithm 3), without preparing the least
    /// squares: for choosing derived sets, where an edit is tried and grown until it passes.
    /// `spec.strong` is ignored (the test always runs).
    pub fn check_strongly_solvable<B>(
        backend: &B,
        system: &ConstraintSystem,
        values: &Values,
        spec: &EditSpec,
    ) -> Result<(), EditError<F::Scalar>>
    where
        B: LinearBackend<Factorization = F>,
    {
        validate_spec::<F::Scalar>(system, values, spec)?;
        let relevant = extract_relevant(system, &spec.anchors, &spec.derived);
        let reduced = reduce(system, values, spec, &relevant);
        // Weights only shape the least squares; the substitution needs one per unknown.
        let unit = vec![Rational::one(); reduced.r_ed.cols()];
        let substitution = Substitution::new(&reduced, &unit);
        let factored = substitution.as_ref().map_or(&reduced, Substitution::inner);
        let factorization = backend.factor(&factored.r_ed)?;
        let names: Vec<Arc<str>> = spec
            .anchors
            .iter()
            .map(|p| system.params()[p.index()].name.clone())
            .collect();
        let dims: Vec<usize> = spec
            .anchors
            .iter()
            .map(|p| system.params()[p.index()].dim)
            .collect();
        strong_check(
            &factorization,
            &reduced,
            substitution.as_ref(),
            &names,
            &dims,
        )
    }

    /// The layout of the reduced system.
    pub fn layout(&self) -> Layout {
        self.layout
    }

    /// `E` and `F'`.
    pub fn relevant(&self) -> &Relevant {
        &self.relevant
    }

    /// The reduced system `R_ED x = c − R_EA α` this edit factored.
    pub fn reduced(&self) -> &ReducedSystem {
        &self.reduced
    }

    /// The reduced system, once the edit is done with: what a report describes, without
    /// reducing the edit again ([`crate::reduce_edit`] gives the same system).
    pub fn into_reduced(self) -> ReducedSystem {
        self.reduced
    }

    /// The factorization of `R_ED`.
    pub fn factorization(&self) -> &F {
        &self.factorization
    }

    /// The anchors, in the order their values are passed to [`Edit::update`].
    pub fn anchors(&self) -> &[ParamId] {
        &self.anchors
    }

    /// The weight of each unknown of `R_ED`.
    pub(crate) fn weights(&self) -> &[Rational] {
        &self.weights
    }

    /// The derived parameters, in the order hints are passed and results returned.
    pub fn derived(&self) -> &[ParamId] {
        &self.derived
    }

    /// Relevant and redundant constraints, rank, layout and strong-solvability verdict.
    pub fn report(&self) -> InitReport<F::Scalar> {
        let rows = &self.reduced.rows;
        let (mut independent, redundant): (Vec<usize>, Vec<Combination<F::Scalar>>) = match &self
            .substitution
        {
            None => (
                self.factorization.independent_rows(),
                self.factorization
                    .redundancies()
                    .into_iter()
                    .map(|red| (red.row, red.combination))
                    .collect(),
            ),
            Some(sub) => {
                let mut independent: Vec<usize> = self
                    .factorization
                    .independent_rows()
                    .into_iter()
                    .map(|k| sub.original_row(k))
                    .collect();
                independent.extend(sub.tree_rows());
                let redundant = self
                    .factorization
                    .redundancies()
                    .into_iter()
                    .map(|red| {
                        let t = sub.original_row(red.row);
                        let mut combination: Vec<(usize, F::Scalar)> = red
                            .combination
                            .into_iter()
                            .map(|(k, c)| (sub.original_row(k), c))
                            .collect();
                        // A_t − Σ c A_k, cancelled by the substituted rows.
                        let mut residual = vec![(t, F::Scalar::from_rational(&Rational::one()))];
                        residual.extend(combination.iter().map(|(i, c)| (*i, -c.clone())));
                        combination.extend(sub.complete(&self.reduced.r_ed, &residual));
                        combination.sort_by_key(|(i, _)| *i);
                        (t, combination)
                    })
                    .collect();
                (independent, redundant)
            }
        };
        independent.sort_unstable();
        InitReport {
            backend: self.backend,
            relevant: self.relevant.constraints.clone(),
            fixed_relevant: self.relevant.fixed.clone(),
            layout: self.layout,
            equations: self.reduced.r_ed.rows(),
            unknowns: self.reduced.r_ed.cols(),
            rank: independent.len(),
            independent: independent.into_iter().map(|i| rows[i]).collect(),
            redundant: redundant
                .into_iter()
                .map(|(t, combination)| {
                    (
                        rows[t],
                        combination.into_iter().map(|(i, c)| (rows[i], c)).collect(),
                    )
                })
                .collect(),
            strongly_solvable: self.strongly_solvable,
        }
    }

    /// An inconsistency found on the factored system, over the rows of `R_ED`: inner rows
    /// mapped back and completed by the substituted rows (the same discrepancy).
    fn original_inconsistency(&self, inc: Inconsistency<F::Scalar>) -> Inconsistency<F::Scalar> {
        map_inconsistency(&self.reduced, self.substitution.as_ref(), inc)
    }

    fn check_values(
        &self,
        what: &'static str,
        given: &[Vec<Rational>],
        names: &[Arc<str>],
        dims: &[usize],
    ) -> Result<(), EditError<F::Scalar>> {
        if given.len() != dims.len() {
            return Err(EditError::Count {
                what,
                expected: dims.len(),
                found: given.len(),
            });
        }
        for ((v, name), dim) in given.iter().zip(names).zip(dims) {
            if v.len() != *dim {
                return Err(EditError::ValueDimension {
                    name: name.to_string(),
                    expected: *dim,
                    found: v.len(),
                });
            }
        }
        Ok(())
    }

    /// ECLES.Update: checks that the anchor values are reachable (weak solvability) and returns
    /// the derived values closest to the hints that satisfy every relevant constraint.
    ///
    /// `anchor_values[k]` is the new value of anchor `k`; `hints[k]` the suggested value of
    /// derived parameter `k`. Nothing is modified; see [`Edit::apply`].
    pub fn update(
        &self,
        anchor_values: &[Vec<Rational>],
        hints: &[Vec<Rational>],
    ) -> Result<UpdateResult<F::Scalar>, EditError<F::Scalar>> {
        self.hinted(anchor_values, hints)?.update(anchor_values)
    }

    /// ECLES.Update for drawing: the same exact verdict as [`Edit::update`], the derived values
    /// rounded to `f64`. During a drag every frame needs a picture but only the last position is
    /// committed; an exact backend skips reducing fractions here, the dominant cost of large
    /// exact updates.
    pub fn preview(
        &self,
        anchor_values: &[Vec<Rational>],
        hints: &[Vec<Rational>],
    ) -> Result<Vec<Vec<f64>>, EditError<F::Scalar>> {
        self.hinted(anchor_values, hints)?.preview(anchor_values)
    }

    /// The edit with `hints` fixed (checked and gathered once): what the frames of a drag
    /// share, whose hints are the values at mouse-down while the anchors move. Each
    /// [`HintedEdit::update`], [`HintedEdit::preview`] or [`HintedEdit::frame`] then costs the
    /// solve alone — [`Edit::update`] recognises unchanged hints too, but by comparing every
    /// number with the last ones, which on a small exact frame costs a fifth of it.
    pub fn with_hints(
        &self,
        hints: &[Vec<Rational>],
    ) -> Result<HintedEdit<'_, F>, EditError<F::Scalar>> {
        self.check_values("hints", hints, &self.derived_names, &self.derived_dims)?;
        let hints = match self.layout {
            Layout::Vector { dim } => {
                GatheredHints::ByColumn(self.hint_columns.by_column(hints, dim))
            }
            Layout::Scalar => GatheredHints::Flat(self.hint_columns.flattened(hints)),
        };
        Ok(HintedEdit { edit: self, hints })
    }

    /// The update's result: the anchors at `anchor_values`, the derived parameters at
    /// `derived_values`.
    fn result(
        &self,
        anchor_values: &[Vec<Rational>],
        derived_values: Vec<Vec<F::Scalar>>,
    ) -> UpdateResult<F::Scalar> {
        UpdateResult {
            anchors: self
                .anchors
                .iter()
                .copied()
                .zip(anchor_values.iter().cloned())
                .collect(),
            derived: self.derived.iter().copied().zip(derived_values).collect(),
        }
    }

    /// [`Edit::with_hints`] for one update at `anchor_values`, checked first (the errors of a
    /// call with both wrong name the anchor values, as they always have).
    fn hinted(
        &self,
        anchor_values: &[Vec<Rational>],
        hints: &[Vec<Rational>],
    ) -> Result<HintedEdit<'_, F>, EditError<F::Scalar>> {
        self.check_anchor_values(anchor_values)?;
        self.with_hints(hints)
    }

    fn check_anchor_values(
        &self,
        anchor_values: &[Vec<Rational>],
    ) -> Result<(), EditError<F::Scalar>> {
        self.check_values(
            "anchor values",
            anchor_values,
            &self.anchor_names,
            &self.anchor_dims,
        )
    }

    /// One coordinate column of the update in the backend's values: the prepared least squares
    /// on the inner system, mapped back through the substitution when there is one. (Takes the
    /// edit's parts, not the edit: columns run on threads, and a factorization need not be
    /// `Sync`.)
    fn solve_column(
        prepared: &F::LeastSquares,
        reduced: &ReducedSystem,
        substitution: Option<&Substitution>,
        weights: &[Rational],
        column: usize,
        alpha: &[Rational],
        hints: &HintColumn,
    ) -> Result<Vec<F::Scalar>, SolveError<F::Scalar>> {
        through_substitution(
            substitution,
            reduced,
            weights,
            column,
            alpha,
            hints,
            |h| prepared.solve(column, alpha, h),
            F::Scalar::from_rational,
            |a, b| a + b,
            |a| -a,
        )
    }

    fn solve_error(&self, e: SolveError<F::Scalar>, column: usize) -> EditError<F::Scalar> {
        match e {
            SolveError::Input(e) => EditError::Backend(e),
            SolveError::Inconsistent(inc) => EditError::Conflict(Box::new(conflict(
                &self.reduced.rows,
                &self.reduced.labels,
                self.layout,
                column,
                self.original_inconsistency(inc),
            ))),
        }
    }
}

impl<F: Factorization<Scalar = Rational>> Edit<F> {
    /// ECLES.Update as an exact drag frame (see [`HintedEdit::frame`]).
    pub fn frame(
        &self,
        anchor_values: &[Vec<Rational>],
        hints: &[Vec<Rational>],
    ) -> Result<Vec<Vec<Fraction>>, EditError<Rational>> {
        self.hinted(anchor_values, hints)?.frame(anchor_values)
    }

    /// ECLES.Update committed as a snapped point (see [`HintedEdit::update_snapped`]).
    pub fn update_snapped(
        &self,
        anchor_values: &[Vec<Rational>],
        hints: &[Vec<Rational>],
        grid_bits: u32,
    ) -> Result<(UpdateResult<Rational>, SnapSummary), EditError<Rational>> {
        self.hinted(anchor_values, hints)?
            .update_snapped(anchor_values, grid_bits)
    }

    /// Runs [`Edit::update`] and, only if it succeeds, writes the anchor and derived values into
    /// `values`. On any error `values` is left exactly as it was.
    pub fn apply(
        &self,
        system: &ConstraintSystem,
        values: &mut Values,
        anchor_values: &[Vec<Rational>],
        hints: &[Vec<Rational>],
    ) -> Result<UpdateResult<Rational>, EditError<Rational>> {
        if values.len() != system.params().len() {
            return Err(EditError::Count {
                what: "parameter values",
                expected: system.params().len(),
                found: values.len(),
            });
        }
        let result = self.update(anchor_values, hints)?;
        result.write_into(values);
        Ok(result)
    }
}

/// Hints checked against an edit's derived parameters and gathered the way its solve reads
/// them.
#[derive(Debug, Clone)]
enum GatheredHints {
    /// Vector layout: coordinate `j` of every derived parameter, per column `j`.
    ByColumn(Vec<HintColumn>),
    /// Scalar layout: every coordinate of every derived parameter in one column.
    Flat(HintColumn),
}

/// An edit with its hints fixed ([`Edit::with_hints`]): ECLES.Update for any anchor values, the
/// hints already checked and gathered, so that the memos of the steps that follow recognise
/// them by identity. What a drag's frames share.
pub struct HintedEdit<'e, F: Factorization> {
    edit: &'e Edit<F>,
    hints: GatheredHints,
}

impl<F: Factorization> HintedEdit<'_, F> {
    /// ECLES.Update with these hints (see [`Edit::update`]).
    pub fn update(
        &self,
        anchor_values: &[Vec<Rational>],
    ) -> Result<UpdateResult<F::Scalar>, EditError<F::Scalar>> {
        let edit = self.edit;
        let (prepared, reduced, substitution, weights) = (
            &edit.prepared,
            &edit.reduced,
            edit.substitution.as_ref(),
            &edit.weights,
        );
        let derived_values = self.solve_with(anchor_values, |column, alpha, h| {
            Edit::<F>::solve_column(prepared, reduced, substitution, weights, column, alpha, h)
        })?;
        Ok(edit.result(anchor_values, derived_values))
    }

    /// ECLES.Update for drawing with these hints (see [`Edit::preview`]): the exact verdict,
    /// the derived values rounded to `f64`.
    pub fn preview(
        &self,
        anchor_values: &[Vec<Rational>],
    ) -> Result<Vec<Vec<f64>>, EditError<F::Scalar>> {
        let edit = self.edit;
        let (prepared, reduced, substitution, weights) = (
            &edit.prepared,
            &edit.reduced,
            edit.substitution.as_ref(),
            &edit.weights,
        );
        self.solve_with(anchor_values, |column, alpha, h| {
            if substitution.is_none() {
                return prepared.solve_approx(column, alpha, h);
            }
            // The offsets are added in the backend's values and the sum rounded once, so the
            // preview stays the update rounded (the inner system is small by construction).
            Edit::<F>::solve_column(prepared, reduced, substitution, weights, column, alpha, h)
                .map(|x| x.iter().map(Value::to_f64).collect())
        })
    }

    /// Validates the anchor values, then solves per column (vector layout, the columns in
    /// parallel: on large exact edits each is a lifted solve of its own) or once (scalar
    /// layout). The first failing column in order gives the error, as a sequential loop would.
    fn solve_with<T>(
        &self,
        anchor_values: &[Vec<Rational>],
        solve: impl Fn(usize, &[Rational], &HintColumn) -> Result<Vec<T>, SolveError<F::Scalar>> + Sync,
    ) -> Result<Vec<Vec<T>>, EditError<F::Scalar>>
    where
        T: Clone + Send,
    {
        let edit = self.edit;
        edit.check_anchor_values(anchor_values)?;
        match &self.hints {
            GatheredHints::ByColumn(hint_columns) => {
                let dim = hint_columns.len();
                let column = |j: usize| {
                    let alpha: Vec<Rational> = anchor_values.iter().map(|v| v[j].clone()).collect();
                    solve(j, &alpha, &hint_columns[j])
                };
                // Threads pay off only when a column is real work.
                let columns: Vec<Result<Vec<T>, SolveError<F::Scalar>>> =
                    if edit.reduced.r_ed.cols() >= PARALLEL_COLUMNS_ABOVE {
                        (0..dim).into_par_iter().map(column).collect()
                    } else {
                        (0..dim).map(column).collect()
                    };
                // (Not `vec![Vec::with_capacity(dim); n]`: clones of a vector drop its capacity.)
                let mut out: Vec<Vec<T>> = (0..edit.derived.len())
                    .map(|_| Vec::with_capacity(dim))
                    .collect();
                for (j, column) in columns.into_iter().enumerate() {
                    let x = column.map_err(|e| edit.solve_error(e, j))?;
                    for (slot, value) in out.iter_mut().zip(x) {
                        slot.push(value);
                    }
                }
                Ok(out)
            }
            GatheredHints::Flat(h) => {
                let alpha: Vec<Rational> = anchor_values.iter().flatten().cloned().collect();
                let mut x = solve(0, &alpha, h)
                    .map_err(|e| edit.solve_error(e, 0))?
                    .into_iter();
                Ok(edit
                    .derived_dims
                    .iter()
                    .map(|&dim| x.by_ref().take(dim).collect())
                    .collect())
            }
        }
    }
}

impl<F: Factorization<Scalar = Rational>> HintedEdit<'_, F> {
    /// ECLES.Update as an exact drag frame: the same verdict and the same values as
    /// [`Edit::update`] (`derived[k][j]` for derived parameter `k`, coordinate `j`), as fractions
    /// over the solution's common denominator, not reduced — what a frame needs that is drawn
    /// (`Fraction::to_f64`) or inspected exactly and then replaced by the next one. Reducing,
    /// the largest cost of an exact update on real meshes, is left to the commit
    /// ([`Edit::apply`]). Backends without an unreduced form answer through [`Edit::update`].
    pub fn frame(
        &self,
        anchor_values: &[Vec<Rational>],
    ) -> Result<Vec<Vec<Fraction>>, EditError<Rational>> {
        let edit = self.edit;
        let prepared = &edit.prepared;
        let (reduced, substitution, weights) =
            (&edit.reduced, edit.substitution.as_ref(), &edit.weights);
        self.solve_with(anchor_values, |column, alpha, h| {
            // The groups' values unreduced, the offsets added as fractions.
            let unreduced = |h: &[Rational]| match prepared.solve_unreduced(column, alpha, h)? {
                Some(x) => Ok(x),
                None => Ok(prepared
                    .solve(column, alpha, h)?
                    .into_iter()
                    .map(Fraction::from)
                    .collect()),
            };
            through_substitution(
                substitution,
                reduced,
                weights,
                column,
                alpha,
                h,
                unreduced,
                |r: &Rational| Fraction::from(r.clone()),
                |a, b| a + b,
                |a| -a,
            )
        })
    }

    /// ECLES.Update committed as a snapped point (see [`api::PreparedLeastSquares::solve_snapped`]):
    /// the same verdict as [`Edit::update`], derived values that satisfy every relevant
    /// constraint exactly with small denominators (free values on the grid `2^−grid_bits`),
    /// and how far they may be from the least-squares optimum. What long editing sessions
    /// commit: the optimum's denominators grow with every edit, these stay bounded.
    pub fn update_snapped(
        &self,
        anchor_values: &[Vec<Rational>],
        grid_bits: u32,
    ) -> Result<(UpdateResult<Rational>, SnapSummary), EditError<Rational>> {
        let edit = self.edit;
        let prepared = &edit.prepared;
        let (reduced, substitution, weights) =
            (&edit.reduced, edit.substitution.as_ref(), &edit.weights);
        let summary = std::sync::Mutex::new(SnapSummary {
            grid_bits,
            distance_bound: 0.0,
            optimum_columns: 0,
        });
        let derived = self.solve_with(anchor_values, |column, alpha, h| {
            // Each unknown differs from its group's value by ±1 times it plus an exact offset:
            // the groups' distance bound is the unknowns'.
            through_substitution(
                substitution,
                reduced,
                weights,
                column,
                alpha,
                h,
                |h| {
                    let snapped = prepared.solve_snapped(column, alpha, h, grid_bits)?;
                    if let Ok(mut s) = summary.lock() {
                        s.distance_bound = s.distance_bound.max(snapped.distance_bound);
                        s.optimum_columns += usize::from(snapped.optimum);
                    }
                    Ok(snapped.values)
                },
                Rational::clone,
                |a, b| a + b,
                |a| -a,
            )
        })?;
        let summary = summary
            .into_inner()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        Ok((edit.result(anchor_values, derived), summary))
    }
}

/// Solves one right-hand-side column through `substitution` of `reduced`, if any: the hints of
/// the groups from those of the unknowns (`weights` per unknown), `solve` on the factored
/// system, the unknowns from the groups' values and the anchor values `alpha`.
#[allow(clippy::too_many_arguments)]
fn through_substitution<T: Clone, E>(
    substitution: Option<&Substitution>,
    reduced: &ReducedSystem,
    weights: &[Rational],
    column: usize,
    alpha: &[Rational],
    hints: &HintColumn,
    solve: impl Fn(&[Rational]) -> Result<Vec<T>, E>,
    from_rational: impl Fn(&Rational) -> T,
    plus: impl Fn(T, T) -> T,
    negate: impl Fn(T) -> T,
) -> Result<Vec<T>, E> {
    match substitution {
        None => solve(hints),
        Some(sub) => {
            let inner_hints = sub.group_hints(weights, hints, column);
            let y = solve(&inner_hints)?;
            Ok(sub.expand(
                &y,
                column,
                alpha,
                &reduced.family.coefficients,
                from_rational,
                plus,
                negate,
            ))
        }
    }
}

/// An inconsistency of the factored system (the inner one of `substitution`, or `reduced`
/// itself) over the rows of `reduced`: the certificate's inner rows mapped back and completed by
/// the substituted rows, which cancel what the inner rows leave on substituted unknowns. The
/// discrepancy `yᵀ b` is unchanged (module documentation of [`crate::substitute`]).
fn map_inconsistency<S: api::Value>(
    reduced: &ReducedSystem,
    substitution: Option<&Substitution>,
    inc: Inconsistency<S>,
) -> Inconsistency<S> {
    let Some(sub) = substitution else {
        return inc;
    };
    let mut combination: Vec<(usize, S)> = inc
        .rows
        .iter()
        .zip(inc.certificate)
        .map(|(&k, y)| (sub.original_row(k), y))
        .collect();
    let completion = sub.complete(&reduced.r_ed, &combination);
    combination.extend(completion.into_iter().map(|(i, f)| (i, -f)));
    combination.sort_by_key(|(i, _)| *i);
    Inconsistency {
        rows: combination.iter().map(|(i, _)| *i).collect(),
        certificate: combination.into_iter().map(|(_, y)| y).collect(),
        discrepancy: inc.discrepancy,
    }
}

/// The exact strong-solvability check of a reduced system (algorithm 3): `Ok` when every
/// anchor value can be absorbed by the derived parameters.
fn strong_check<F: Factorization>(
    factorization: &F,
    reduced: &ReducedSystem,
    substitution: Option<&Substitution>,
    anchor_names: &[Arc<str>],
    anchor_dims: &[usize],
) -> Result<(), EditError<F::Scalar>> {
    let factored = substitution.map_or(reduced, Substitution::inner);
    match factorization.check_strongly_consistent(&factored.family)? {
        Ok(()) => Ok(()),
        Err(StrongFailure::Constant {
            column,
            inconsistency,
        }) => Err(state_inconsistent(
            reduced,
            column,
            map_inconsistency(reduced, substitution, inconsistency),
        )),
        Err(StrongFailure::Direction {
            parameter,
            inconsistency,
        }) => {
            let inconsistency = map_inconsistency(reduced, substitution, inconsistency);
            let (anchor, component) = match reduced.layout {
                Layout::Vector { .. } => (anchor_names[parameter].to_string(), None),
                Layout::Scalar => {
                    let mut offset = 0;
                    let mut found = (String::new(), None);
                    for (name, dim) in anchor_names.iter().zip(anchor_dims) {
                        if parameter < offset + dim {
                            let k = parameter - offset;
                            found = (name.to_string(), (*dim > 1).then_some(k));
                            break;
                        }
                        offset += dim;
                    }
                    found
                }
            };
            Err(EditError::NotStronglySolvable {
                anchor,
                component,
                conflict: Box::new(conflict(
                    &reduced.rows,
                    &reduced.labels,
                    Layout::Scalar,
                    0,
                    inconsistency,
                )),
            })
        }
    }
}

/// The current values contradict the relevant rows whatever the anchors (a failed constant part
/// of a strong or directed check).
pub(crate) fn state_inconsistent<S: Clone + std::fmt::Debug>(
    reduced: &ReducedSystem,
    column: usize,
    inconsistency: Inconsistency<S>,
) -> EditError<S> {
    EditError::CurrentStateInconsistent(Box::new(conflict(
        &reduced.rows,
        &reduced.labels,
        reduced.layout,
        column,
        inconsistency,
    )))
}

pub(crate) fn conflict<S: Clone>(
    rows: &[RowRef],
    labels: &[String],
    layout: Layout,
    column: usize,
    inc: Inconsistency<S>,
) -> Conflict<S> {
    Conflict {
        coordinate: match layout {
            Layout::Vector { dim } if dim > 1 => Some(column),
            _ => None,
        },
        rows: inc
            .rows
            .iter()
            .zip(inc.certificate)
            .map(|(&i, multiplier)| ConflictingRow {
                row: rows[i],
                label: labels[i].clone(),
                multiplier,
            })
            .collect(),
        discrepancy: inc.discrepancy,
    }
}

/// Checks ids, overlaps and weights (one positive weight per derived parameter, if given).
pub(crate) fn validate_spec<S: std::fmt::Debug>(
    system: &ConstraintSystem,
    values: &Values,
    spec: &EditSpec,
) -> Result<(), EditError<S>> {
    if spec.anchors.is_empty() {
        return Err(EditError::NoAnchors);
    }
    validate_ids_and_weights(system, values, spec)
}

/// [`validate_spec`] without the rule that an edit has anchors (a projection has none).
fn validate_ids_and_weights<S: std::fmt::Debug>(
    system: &ConstraintSystem,
    values: &Values,
    spec: &EditSpec,
) -> Result<(), EditError<S>> {
    // foldhash: SipHash's set-up and rounds were a visible part of initialising small edits.
    let mut seen: HashMap<ParamId, bool, foldhash::fast::RandomState> =
        HashMap::with_capacity_and_hasher(
            spec.anchors.len() + spec.derived.len(),
            Default::default(),
        );
    for (p, is_anchor) in spec
        .anchors
        .iter()
        .map(|p| (p, true))
        .chain(spec.derived.iter().map(|p| (p, false)))
    {
        let Some(param) = system.param(*p) else {
            return Err(EditError::UnknownParameter(*p));
        };
        if let Some(&was_anchor) = seen.get(p) {
            let name = param.name.to_string();
            return Err(if was_anchor != is_anchor {
                EditError::AnchorAlsoDerived { name }
            } else {
                EditError::Duplicate { name }
            });
        }
        seen.insert(*p, is_anchor);
    }
    if values.len() != system.params().len() {
        return Err(EditError::Count {
            what: "parameter values",
            expected: system.params().len(),
            found: values.len(),
        });
    }
    if let Some(w) = &spec.weights {
        if w.len() != spec.derived.len() {
            return Err(EditError::WeightCount {
                expected: spec.derived.len(),
                found: w.len(),
            });
        }
        for (wi, p) in w.iter().zip(&spec.derived) {
            // A sign test, not a comparison of fractions (which multiplies across).
            if !wi.is_positive() {
                return Err(EditError::NonPositiveWeight {
                    name: system.params()[p.index()].name.to_string(),
                    weight: api::format_rational(wi),
                });
            }
        }
    }
    Ok(())
}
