//! The parts of a 2DSD operation as written in a run file (anchors, neighbourhood, the move,
//! steps), shared by every source that edits a spline with [`crate::edit::SplineEditor`]
//! (`spline2d` itself, and the terrain surfaces).
//!
//! Everything here is checked without the values of the edit's turn, so a host can check every
//! operation of a run before the first edit runs. The limits keep a malformed run file from
//! asking for unbounded time or memory:
//!
//! | field | limit |
//! | --- | --- |
//! | `steps` | 1 ..= [`MAX_STEPS`], and steps × control points ≤ [`MAX_STEP_VALUES`] |
//! | `neighborhood` | 0 ..= [`MAX_NEIGHBORHOOD`] net steps, or `"all"` |

use crate::edit::{Neighborhood, Operation, Plan, Selection};
use crate::spline::Spline;
use api::exact::Exact;
use api::{OperationPlan, PlannedStep, Rational, SummaryItem};
use num_traits::One;
use serde::de::{self, Deserializer, Visitor};
use serde::Deserialize;
use std::collections::BTreeSet;
use std::fmt;

/// Most steps a drag may be split into.
pub const MAX_STEPS: u64 = 100_000;

/// Most anchor values and hints a planned drag may hold in all (steps × moved control points):
/// every step carries one value per anchor and derived point.
pub const MAX_STEP_VALUES: u64 = 50_000_000;

/// Largest radius `δ_max` (net steps) a neighbourhood may be given as; a larger radius is
/// written `"all"`.
pub const MAX_NEIGHBORHOOD: u64 = 1_000_000;

/// The neighbourhood of an operation: `3` (net steps, `δ_max`) or `"all"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NeighborhoodConfig(pub Neighborhood);

impl<'de> Deserialize<'de> for NeighborhoodConfig {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct NeighborhoodVisitor;
        impl Visitor<'_> for NeighborhoodVisitor {
            type Value = NeighborhoodConfig;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(
                    f,
                    "a number of net steps from 0 to {MAX_NEIGHBORHOOD}, or \"all\""
                )
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<NeighborhoodConfig, E> {
                if v > MAX_NEIGHBORHOOD {
                    return Err(E::custom(format!(
                        "neighborhood {v} is above the limit of {MAX_NEIGHBORHOOD} net steps; write \"all\" for every control point"
                    )));
                }
                // Bounded by MAX_NEIGHBORHOOD, which fits a u32.
                Ok(NeighborhoodConfig(Neighborhood::Radius(v as u32)))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<NeighborhoodConfig, E> {
                match u64::try_from(v) {
                    Ok(v) => self.visit_u64(v),
                    Err(_) => Err(E::custom(format!(
                        "neighborhood {v} is negative: give a number of net steps (0 to {MAX_NEIGHBORHOOD}) or \"all\""
                    ))),
                }
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<NeighborhoodConfig, E> {
                if v == "all" {
                    Ok(NeighborhoodConfig(Neighborhood::All))
                } else {
                    Err(E::custom(format!(
                        "neighborhood {v:?}: give a number of net steps (0 to {MAX_NEIGHBORHOOD}) or \"all\""
                    )))
                }
            }
        }
        deserializer.deserialize_any(NeighborhoodVisitor)
    }
}

/// A list of exact numbers written as a tuple `("1", "-2")` or a list `["1", "-2"]` (a
/// translation, a vertical move).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExactList(pub Vec<Exact>);

impl<'de> Deserialize<'de> for ExactList {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ListVisitor;
        impl<'de> Visitor<'de> for ListVisitor {
            type Value = ExactList;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a tuple of exact numbers such as (\"3/2\", \"-1\")")
            }
            fn visit_seq<A: de::SeqAccess<'de>>(self, mut seq: A) -> Result<ExactList, A::Error> {
                let mut out = Vec::new();
                while let Some(e) = seq.next_element::<Exact>()? {
                    if out.len() == MAX_COORDINATES {
                        return Err(de::Error::custom(format!(
                            "more than {MAX_COORDINATES} coordinates"
                        )));
                    }
                    out.push(e);
                }
                Ok(ExactList(out))
            }
        }
        deserializer.deserialize_any(ListVisitor)
    }
}

/// Most coordinates a written move may have (splines have 1 or 2).
const MAX_COORDINATES: usize = 16;

/// A soft rotation as written: `(center: (x, y), degrees: d, precision: 1000000)`.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotateConfig {
    /// Centre of rotation.
    pub center: (Exact, Exact),
    /// Angle in degrees, counter-clockwise.
    pub degrees: Exact,
    /// See [`Operation::Rotate`].
    #[serde(default = "default_precision")]
    pub precision: u64,
}

/// A soft scaling as written: `(center: (x, y), factor: f, precision: 1000000)`.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScaleConfig {
    /// Centre of scaling.
    pub center: (Exact, Exact),
    /// Scale factor, positive.
    pub factor: Exact,
    /// See [`Operation::Scale`].
    #[serde(default = "default_precision")]
    pub precision: u64,
}

/// The default precision of rotations and scalings.
pub fn default_precision() -> u64 {
    1_000_000
}

/// The default number of steps: one.
pub fn default_steps() -> u64 {
    1
}

/// The control points named by `names`: at least one, each once, each a control point of
/// `spline`.
pub fn find_anchors(spline: &Spline, names: &[String]) -> Result<Vec<usize>, String> {
    if names.is_empty() {
        return Err("anchors is empty: name at least one control point".into());
    }
    let mut seen = BTreeSet::new();
    names
        .iter()
        .map(|name| {
            if !seen.insert(name.as_str()) {
                return Err(format!("anchor {name:?} is named twice"));
            }
            spline.point_index(name).ok_or_else(|| {
                format!(
                    "no control point named {name:?} (names look like \"v3\", \"e3-7:2\", \"t5:2,2,1\")"
                )
            })
        })
        .collect()
}

/// The move of an operation from exactly one of `translate`, `rotate` and `scale`, checked
/// for a spline whose values have `dim` coordinates.
pub fn motion(
    translate: Option<&ExactList>,
    rotate: Option<&RotateConfig>,
    scale: Option<&ScaleConfig>,
    dim: usize,
) -> Result<Operation, String> {
    let operation = match (translate, rotate, scale) {
        (Some(by), None, None) => Operation::Translate {
            by: by.0.iter().map(|e| e.0.clone()).collect(),
        },
        (None, Some(r), None) => Operation::Rotate {
            center: [r.center.0 .0.clone(), r.center.1 .0.clone()],
            degrees: r.degrees.0.clone(),
            precision: r.precision,
        },
        (None, None, Some(s)) => Operation::Scale {
            center: [s.center.0 .0.clone(), s.center.1 .0.clone()],
            factor: s.factor.0.clone(),
            precision: s.precision,
        },
        _ => return Err("give exactly one of translate, rotate or scale".into()),
    };
    operation.validate(dim).map_err(|e| e.to_string())?;
    Ok(operation)
}

/// `steps` checked against [`MAX_STEPS`] and, with `points` control points moving at most,
/// against [`MAX_STEP_VALUES`].
pub fn checked_steps(steps: u64, points: usize) -> Result<usize, String> {
    let count = api::config::bounded_count(steps, "steps", 1, MAX_STEPS)?;
    let values = steps.saturating_mul(points as u64);
    if values > MAX_STEP_VALUES {
        return Err(format!(
            "steps {steps} for {points} control points would plan {values} values, more than the limit of {MAX_STEP_VALUES}"
        ));
    }
    Ok(count)
}

/// The plan of a 2DSD edit as a source answers it: unit weights, no strong check (the selection
/// already verified the requested moves, or found them blocked), and the selection's facts for
/// the report (`expansion_blocked` only when ExpandDerived found no way to make the edit
/// solvable: ECLES then refuses it with the exact certificate).
pub fn operation_plan(selection: &Selection, plan: Plan) -> OperationPlan {
    let mut summary: Vec<SummaryItem> = [
        ("initial_derived", selection.initial.len()),
        ("added_by_expansion", selection.added.len()),
        ("solvability_checks", selection.checks),
    ]
    .into_iter()
    .map(|(key, value)| SummaryItem {
        key: key.into(),
        value: value as u64,
    })
    .collect();
    if selection.blocked.is_some() {
        summary.push(SummaryItem {
            key: "expansion_blocked".into(),
            value: 1,
        });
    }
    OperationPlan {
        weights: vec![Rational::one(); plan.spec.derived.len()],
        anchors: plan.spec.anchors,
        derived: plan.spec.derived,
        strong: false,
        steps: plan
            .steps
            .into_iter()
            .map(|s| PlannedStep {
                anchors: s.anchors,
                hints: s.hints,
            })
            .collect(),
        summary,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::config::from_ron;

    #[derive(Debug, Deserialize)]
    struct Holder {
        n: NeighborhoodConfig,
    }

    #[test]
    fn neighborhoods_are_numbers_or_all_with_clear_messages() {
        let read = |text: &str| from_ron::<Holder>(text, "op").map(|h| h.n.0);
        assert_eq!(read("(n: 3)"), Ok(Neighborhood::Radius(3)));
        assert_eq!(read("(n: \"all\")"), Ok(Neighborhood::All));
        for (text, needle) in [
            ("(n: -1)", "neighborhood -1 is negative"),
            ("(n: 1000001)", "above the limit of 1000000"),
            ("(n: \"most\")", "neighborhood \"most\""),
            ("(n: 2.5)", "a number of net steps"),
        ] {
            let e = read(text).expect_err(text);
            assert!(e.message.contains(needle), "{text}: {}", e.message);
            assert!(!e.message.contains("Number("), "{}", e.message);
            assert!(e.at.is_some());
        }
    }

    #[test]
    fn steps_are_bounded() {
        assert_eq!(checked_steps(4, 100), Ok(4));
        assert!(checked_steps(0, 100)
            .expect_err("zero")
            .contains("between 1 and 100000"));
        assert!(checked_steps(u64::MAX, 1).is_err());
        assert!(checked_steps(100_000, 1_000)
            .expect_err("too many values")
            .contains("more than the limit"));
    }
}
