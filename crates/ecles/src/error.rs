//! Why an edit could not be set up or updated.

use crate::edit::RowRef;
use api::{BackendError, RowId};
use std::fmt;

/// One constraint taking part in a conflict, with its multiplier in the certificate.
#[derive(Debug, Clone, PartialEq)]
pub struct ConflictingRow<S> {
    /// The constraint (and coordinate, for vector rows split into scalar rows).
    pub row: RowRef,
    /// Its label, for messages.
    pub label: String,
    /// Its multiplier `y_i` in the certificate `yᵀ R_ED = 0`, `yᵀ b ≠ 0`.
    pub multiplier: S,
}

/// A set of constraints that cannot hold together, with the proof.
#[derive(Debug, Clone, PartialEq)]
pub struct Conflict<S> {
    /// The coordinate of a vector edit (dimension > 1) in which the conflict arises; `None` for
    /// scalar edits.
    pub coordinate: Option<usize>,
    /// The conflicting constraints (a minimal set for the exact backend).
    pub rows: Vec<ConflictingRow<S>>,
    /// `yᵀ b`, nonzero.
    pub discrepancy: S,
}

impl<S> Conflict<S> {
    /// The distinct rows involved.
    pub fn row_ids(&self) -> Vec<RowId> {
        let mut ids: Vec<RowId> = self.rows.iter().map(|r| r.row.row).collect();
        ids.dedup();
        ids
    }

    /// The labels of the conflicting rows, in certificate order.
    pub fn labels(&self) -> Vec<&str> {
        self.rows.iter().map(|r| r.label.as_str()).collect()
    }
}

impl<S> fmt::Display for Conflict<S> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<String> = self
            .rows
            .iter()
            .map(|r| match r.row.component {
                Some(k) => format!("{:?}[{k}]", r.label),
                None => format!("{:?}", r.label),
            })
            .collect();
        write!(f, "{}", names.join(", "))?;
        if let Some(k) = self.coordinate {
            write!(f, " (coordinate {k})")?;
        }
        Ok(())
    }
}

/// Why an edit was refused. Nothing is changed when any of these is returned.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EditError<S: fmt::Debug> {
    /// An editing action needs at least one anchor.
    #[error("an edit needs at least one anchor parameter")]
    NoAnchors,
    /// An id does not name a parameter of the system.
    #[error("parameter id {0} does not exist")]
    UnknownParameter(api::ParamId),
    /// A parameter is listed twice among anchors and derived parameters.
    #[error("parameter {name:?} is listed more than once")]
    Duplicate {
        /// The parameter's name.
        name: String,
    },
    /// A parameter is both anchor and derived.
    #[error("parameter {name:?} is both an anchor and derived")]
    AnchorAlsoDerived {
        /// The parameter's name.
        name: String,
    },
    /// The number of weights differs from the number of derived parameters.
    #[error("{found} weights given for {expected} derived parameters")]
    WeightCount {
        /// Derived parameters.
        expected: usize,
        /// Weights given.
        found: usize,
    },
    /// A weight is not positive.
    #[error("weight of {name:?} is {weight}; weights must be positive")]
    NonPositiveWeight {
        /// The parameter's name.
        name: String,
        /// The weight as text.
        weight: String,
    },
    /// The number of anchor values or hints differs from the edit's.
    #[error("{found} {what} given, the edit has {expected}")]
    Count {
        /// "anchor values" or "hints".
        what: &'static str,
        /// Expected count.
        expected: usize,
        /// Given count.
        found: usize,
    },
    /// A value has the wrong number of coordinates.
    #[error("value for {name:?} has {found} coordinates, expected {expected}")]
    ValueDimension {
        /// The parameter's name.
        name: String,
        /// Coordinates expected.
        expected: usize,
        /// Coordinates given.
        found: usize,
    },
    /// The backend refused the data.
    #[error(transparent)]
    Backend(#[from] BackendError),
    /// The current values of the fixed relevant parameters already violate the relevant
    /// constraints for every choice of the derived parameters.
    #[error("the current values violate constraints that no derived parameter can repair: {0}")]
    CurrentStateInconsistent(Box<Conflict<S>>),
    /// Strong solvability fails: moving the named anchor coordinate alone breaks the constraints.
    #[error("not strongly solvable: moving {anchor:?}{} conflicts with {conflict}",
        .component.map(|k| format!("[{k}]")).unwrap_or_default())]
    NotStronglySolvable {
        /// The anchor parameter.
        anchor: String,
        /// Its coordinate, for scalar edits of vector parameters.
        component: Option<usize>,
        /// The constraints that block it.
        conflict: Box<Conflict<S>>,
    },
    /// A requested move of the anchors is impossible: the rows of the certificate tie the
    /// anchors to fixed parameters (or to each other) in the direction of the move (see
    /// [`crate::check_moves`]).
    #[error("the requested move of the anchors conflicts with {0}")]
    MoveBlocked(Box<Conflict<S>>),
    /// Weak solvability fails for these anchor values: the anchors contradict the constraints.
    #[error("the anchor values conflict with constraints {0}")]
    Conflict(Box<Conflict<S>>),
    /// The change criterion could not choose (the edit is too large for it).
    #[error("change criterion: {0}")]
    Criterion(criteria::CriterionError),
}

impl<S: fmt::Debug> EditError<S> {
    /// The conflicting rows behind the refusal, when there are some: for conflicts, blocked
    /// moves, failed strong checks and inconsistent current states.
    pub fn conflict(&self) -> Option<&Conflict<S>> {
        match self {
            EditError::Conflict(c)
            | EditError::CurrentStateInconsistent(c)
            | EditError::MoveBlocked(c) => Some(c),
            EditError::NotStronglySolvable { conflict, .. } => Some(conflict),
            _ => None,
        }
    }
}
