//! `ecles explain RUN PARAM... --move ...`: how a change of the picked parameters propagates
//! ([`ecles::analyze_propagation`], Brenner 3.1), in words and as JSON.

use super::Session;
use crate::error::RunError;
use api::{format_rational, parse_rational, ParamId, Rational};
use ecles::{Case, Follows, MoveOutcome, Propagation, RowCombination};
use exact_ldu::ExactLdu;
use serde::Serialize;

impl Session {
    /// The propagation analysis of the parameters `names` (whole parameters, `source.name`),
    /// with the move `requested` (exact numbers separated by commas, one per coordinate of the
    /// picked parameters in order), if given.
    pub fn propagation(
        &self,
        names: &[String],
        requested: Option<&str>,
    ) -> Result<(Vec<ParamId>, Propagation), RunError> {
        let run = self.run_name();
        let mut picked = Vec::with_capacity(names.len());
        for name in names {
            let id = self.system.param_id(name).ok_or_else(|| {
                RunError::input(format!(
                    "{run}: no parameter named {name:?} (a propagation analysis picks whole parameters, named source.name, e.g. \"worm.v3\")"
                ))
            })?;
            picked.push(id);
        }
        let requested = match requested {
            Some(text) => Some(
                text.split(',')
                    .enumerate()
                    .map(|(k, part)| {
                        parse_rational(part)
                            .map_err(|e| RunError::input(format!("--move: value {}: {e}", k + 1)))
                    })
                    .collect::<Result<Vec<Rational>, RunError>>()?,
            ),
            None => None,
        };
        let analysis = ecles::analyze_propagation(
            &ExactLdu::default(),
            &self.system,
            &picked,
            requested.as_deref(),
            ecles::EXPLAIN_NULL_SPACE_BUDGET,
        )
        .map_err(|e| RunError::input(format!("{run}: {e}")))?;
        Ok((picked, analysis))
    }

    /// The propagation of an edit's anchor move (`anchors` moved to `targets` from their
    /// current values) as JSON for the edit's report; a component too large is skipped with a
    /// note, as is any other failure (the edit itself decides solvability).
    pub(super) fn edit_propagation(
        &self,
        anchors: &[ParamId],
        targets: &[Vec<Rational>],
    ) -> EditPropagation {
        let moves: Vec<Rational> = anchors
            .iter()
            .zip(targets)
            .flat_map(|(p, target)| {
                self.values
                    .get(*p)
                    .iter()
                    .zip(target)
                    .map(|(from, to)| api::rational_difference(to, from))
                    .collect::<Vec<_>>()
            })
            .collect();
        match ecles::analyze_propagation(
            &ExactLdu::default(),
            &self.system,
            anchors,
            Some(&moves),
            ecles::REPORT_NULL_SPACE_BUDGET,
        ) {
            Ok(analysis) => EditPropagation::Analysed(self.propagation_json(&analysis)),
            Err(e) => EditPropagation::Skipped {
                skipped: e.to_string(),
            },
        }
    }

    /// The analysis in words, one line each.
    pub fn propagation_lines(&self, analysis: &Propagation) -> Vec<String> {
        let name = |p: ParamId| self.system.params()[p.index()].name.clone();
        let mut picked_names: Vec<std::sync::Arc<str>> = Vec::new();
        for (p, _) in &analysis.picked {
            if !picked_names.contains(&name(*p)) {
                picked_names.push(name(*p));
            }
        }
        let picked = picked_names.join(", ");
        let mut lines = vec![format!(
            "propagation from {picked} (its component: {} coordinates):",
            analysis.component
        )];
        let vector = |v: &[api::Integer]| {
            format!(
                "({})",
                v.iter()
                    .map(ToString::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        };
        lines.push(match analysis.case {
            Case::FullyConstrained => format!("  {picked}: fully constrained, cannot move at all"),
            Case::Free => format!("  {picked}: free, can move in every direction"),
            Case::PartiallyConstrained => format!(
                "  {picked}: partially constrained, can move only along {}",
                analysis
                    .directions
                    .iter()
                    .map(|d| vector(d))
                    .collect::<Vec<_>>()
                    .join(" and ")
            ),
        });
        for lost in &analysis.lost {
            lines.push(format!(
                "  cannot move along {}: removed by {}",
                vector(&lost.direction),
                self.combination_text(&lost.rows)
            ));
        }
        match &analysis.outcome {
            None => {}
            Some(MoveOutcome::Blocked(rows)) => lines.push(format!(
                "  the requested move is impossible: {}",
                self.combination_text(rows)
            )),
            Some(MoveOutcome::Moves(follows)) => {
                let mut forced = Vec::new();
                let mut may_stay = Vec::new();
                let mut must_move = Vec::new();
                for (p, f) in follows {
                    match f {
                        Follows::Forced(by) => forced.push(format!(
                            "{} by ({})",
                            name(*p),
                            by.iter()
                                .map(format_rational)
                                .collect::<Vec<_>>()
                                .join(", ")
                        )),
                        Follows::MayStay { freedom } => {
                            may_stay.push(format!("{} ({freedom})", name(*p)))
                        }
                        Follows::MustMoveWithChoice { freedom } => {
                            must_move.push(format!("{} ({freedom})", name(*p)))
                        }
                    }
                }
                lines.push("  the requested move:".into());
                // At most LISTED names each; the JSON has them all.
                const LISTED: usize = 12;
                let list = |items: &[String]| match items.len() {
                    0 => "none".to_string(),
                    n if n <= LISTED => items.join(", "),
                    n => format!("{} … and {} more", items[..LISTED].join(", "), n - LISTED),
                };
                lines.push(format!("    necessarily moves: {}", list(&forced)));
                lines.push(format!(
                    "    must move, with a choice (dimensions of the choice): {}",
                    list(&must_move)
                ));
                lines.push(format!(
                    "    may stay or move (dimensions of the choice): {}",
                    list(&may_stay)
                ));
                lines.push("    everything else stays".into());
            }
        }
        lines
    }

    /// The analysis as JSON (the names of parameters and the labels of rows).
    pub fn propagation_json(&self, analysis: &Propagation) -> PropagationJson {
        let name = |p: ParamId| std::sync::Arc::clone(&self.system.params()[p.index()].name);
        let strings = |v: &[api::Integer]| v.iter().map(ToString::to_string).collect::<Vec<_>>();
        let outcome = analysis.outcome.as_ref().map(|outcome| match outcome {
            MoveOutcome::Blocked(rows) => OutcomeJson::Blocked {
                blocked_by: self.combination_json(rows),
            },
            MoveOutcome::Moves(follows) => OutcomeJson::Moves {
                moves: follows
                    .iter()
                    .map(|(p, f)| match f {
                        Follows::Forced(by) => FollowsJson::Forced {
                            by: by.iter().map(format_rational).collect(),
                            follows: "forced",
                            param: name(*p),
                        },
                        Follows::MayStay { freedom } => FollowsJson::WithChoice {
                            follows: "may_stay",
                            freedom: *freedom,
                            param: name(*p),
                        },
                        Follows::MustMoveWithChoice { freedom } => FollowsJson::WithChoice {
                            follows: "must_move_with_choice",
                            freedom: *freedom,
                            param: name(*p),
                        },
                    })
                    .collect(),
            },
        });
        PropagationJson {
            case: match analysis.case {
                Case::FullyConstrained => "fully_constrained",
                Case::PartiallyConstrained => "partially_constrained",
                Case::Free => "free",
            },
            component: analysis.component,
            directions: analysis.directions.iter().map(|d| strings(d)).collect(),
            lost: analysis
                .lost
                .iter()
                .map(|l| LostJson {
                    direction: strings(&l.direction),
                    rows: self.combination_json(&l.rows),
                })
                .collect(),
            outcome,
            picked: analysis
                .picked
                .iter()
                .map(|(p, k)| PickedJson {
                    coordinate: *k,
                    param: name(*p),
                })
                .collect(),
        }
    }

    /// Rows of a combination in words: `"label" × multiplier`, coordinates of vector rows as
    /// `[k]`.
    fn combination_text(&self, rows: &RowCombination) -> String {
        rows.iter()
            .map(|(row, k, y)| {
                let label = &self.system.rows()[row.index()].label;
                let coordinate = if self.row_is_vector(*row) {
                    format!("[{k}]")
                } else {
                    String::new()
                };
                format!("{label:?}{coordinate} × {}", format_rational(y))
            })
            .collect::<Vec<_>>()
            .join(", ")
    }

    fn combination_json(&self, rows: &RowCombination) -> Vec<RowJson> {
        rows.iter()
            .map(|(row, k, y)| RowJson {
                coordinate: *k,
                label: self.system.rows()[row.index()].label.clone(),
                multiplier: format_rational(y),
            })
            .collect()
    }

    fn row_is_vector(&self, row: api::RowId) -> bool {
        matches!(
            self.system.rows()[row.index()].body,
            api::RowBody::Vector { ref rhs, .. } if rhs.len() > 1
        )
    }
}

// The JSON of an analysis. Its fields are in the order of their names: the order this JSON has
// always had (it was first built as `serde_json` maps, which sort their keys), so reports stay
// byte-identical; typed, it is written without building a map per object.

/// A propagation analysis as the report and `ecles explain --json` write it.
#[derive(Debug, Clone, Serialize)]
pub struct PropagationJson {
    case: &'static str,
    component: usize,
    directions: Vec<Vec<String>>,
    lost: Vec<LostJson>,
    #[serde(rename = "move")]
    outcome: Option<OutcomeJson>,
    picked: Vec<PickedJson>,
}

/// An edit's propagation analysis, or why there is none.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum EditPropagation {
    /// The analysis of the anchors' move.
    Analysed(PropagationJson),
    /// Why it was not analysed (a component too large, a backend failure).
    Skipped {
        /// The reason, in words.
        skipped: String,
    },
}

/// One picked coordinate.
#[derive(Debug, Clone, Serialize)]
struct PickedJson {
    coordinate: usize,
    param: std::sync::Arc<str>,
}

/// A direction the picked coordinates cannot move in, with the rows that remove it.
#[derive(Debug, Clone, Serialize)]
struct LostJson {
    direction: Vec<String>,
    rows: Vec<RowJson>,
}

/// One row of a combination.
#[derive(Debug, Clone, Serialize)]
struct RowJson {
    coordinate: usize,
    label: String,
    multiplier: String,
}

/// What the requested move does.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
enum OutcomeJson {
    Blocked { blocked_by: Vec<RowJson> },
    Moves { moves: Vec<FollowsJson> },
}

/// How one other parameter follows the move.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
enum FollowsJson {
    Forced {
        by: Vec<String>,
        follows: &'static str,
        param: std::sync::Arc<str>,
    },
    WithChoice {
        follows: &'static str,
        freedom: usize,
        param: std::sync::Arc<str>,
    },
}
