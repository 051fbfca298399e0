//! `ecles explain RUN PARAM... --move ...`: how a change of the picked parameters propagates
//! ([`ecles::analyze_propagation`], Brenner 3.1), in words and as JSON.

use super::Session;
use crate::error::RunError;
use api::{format_rational, parse_rational, ParamId, Rational};
use ecles::{Case, Follows, MoveOutcome, Propagation, RowCombination};
use exact_ldu::ExactLdu;
use serde_json::{json, Value};

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
    pub(super) fn edit_propagation(&self, anchors: &[ParamId], targets: &[Vec<Rational>]) -> Value {
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
            Ok(analysis) => self.propagation_json(&analysis),
            Err(e) => json!({ "skipped": e.to_string() }),
        }
    }

    /// The analysis in words, one line each.
    pub fn propagation_lines(&self, analysis: &Propagation) -> Vec<String> {
        let name = |p: ParamId| self.system.params()[p.index()].name.clone();
        let mut picked_names: Vec<String> = Vec::new();
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
    pub fn propagation_json(&self, analysis: &Propagation) -> Value {
        let name = |p: ParamId| self.system.params()[p.index()].name.clone();
        let strings = |v: &[api::Integer]| v.iter().map(ToString::to_string).collect::<Vec<_>>();
        let outcome = match &analysis.outcome {
            None => Value::Null,
            Some(MoveOutcome::Blocked(rows)) => {
                json!({ "blocked_by": self.combination_json(rows) })
            }
            Some(MoveOutcome::Moves(follows)) => {
                let entries: Vec<Value> = follows
                    .iter()
                    .map(|(p, f)| match f {
                        Follows::Forced(by) => json!({
                            "param": name(*p),
                            "follows": "forced",
                            "by": by.iter().map(format_rational).collect::<Vec<_>>(),
                        }),
                        Follows::MayStay { freedom } => json!({
                            "param": name(*p), "follows": "may_stay", "freedom": freedom,
                        }),
                        Follows::MustMoveWithChoice { freedom } => json!({
                            "param": name(*p), "follows": "must_move_with_choice", "freedom": freedom,
                        }),
                    })
                    .collect();
                json!({ "moves": entries })
            }
        };
        json!({
            "picked": analysis.picked.iter().map(|(p, k)| json!({"param": name(*p), "coordinate": k})).collect::<Vec<_>>(),
            "case": match analysis.case {
                Case::FullyConstrained => "fully_constrained",
                Case::PartiallyConstrained => "partially_constrained",
                Case::Free => "free",
            },
            "directions": analysis.directions.iter().map(|d| strings(d)).collect::<Vec<_>>(),
            "lost": analysis.lost.iter().map(|l| json!({
                "direction": strings(&l.direction),
                "rows": self.combination_json(&l.rows),
            })).collect::<Vec<_>>(),
            "component": analysis.component,
            "move": outcome,
        })
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

    fn combination_json(&self, rows: &RowCombination) -> Vec<Value> {
        rows.iter()
            .map(|(row, k, y)| {
                json!({
                    "label": self.system.rows()[row.index()].label,
                    "coordinate": k,
                    "multiplier": format_rational(y),
                })
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
