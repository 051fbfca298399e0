//! The 2DSD editing operations (thesis chapter 14, 18.4–18.6): selecting anchors and a
//! neighbourhood, expanding it to a derived set that makes the edit strongly solvable,
//! relative magnitudes `θ`, and the soft translation, rotation, scaling and vertical (`z`)
//! moves turned into ECLES anchor values and hints.
//!
//! # ExpandDerived
//! Figure 14.6 of the thesis (the per-type rules for which extra points become derived) is a
//! picture missing from the text, so the expansion uses a rule that needs no picture and works
//! for any constraint source: starting from `D = S`, run the exact strong-solvability check of
//! ECLES (`range R_EA ⊆ range R_ED`); when it fails, its certificate names the conditions that
//! block some anchor direction, and the fixed control points in those conditions nearest to the
//! anchors (on the control net) join `D`. Repeat until the check passes. Every added point is
//! needed by a blocking condition, so `D` stays local (for `d ≥ 5` the thesis' bound of the
//! anchors' triangles plus a few neighbours), and the result is verified, not assumed.

use crate::motion;
use crate::net::{ControlNet, Distances};
use crate::params::SplineParams;
use crate::spline::{PointType, Spline};
use api::{ConstraintSystem, ParamId, Rational, Values};
use ecles::{Edit, EditError, EditSpec};
use exact_ldu::{ExactFactorization, ExactLdu};
use num_traits::{One, Signed, Zero};
use std::collections::BTreeSet;

/// Which control points become derived before expansion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Neighborhood {
    /// Points within this many steps of an anchor on the control net (`δ_max`).
    Radius(u32),
    /// Every control point (`δ_max = ∞`): global moves.
    All,
}

/// The outcome of 2DSD.Select.
#[derive(Debug, Clone, PartialEq)]
pub struct Selection {
    /// Anchor control points `A`.
    pub anchors: Vec<usize>,
    /// The initial derived points `S` from the neighbourhood.
    pub initial: Vec<usize>,
    /// The final derived points `D ⊇ S` (sorted).
    pub derived: Vec<usize>,
    /// `D \ S`: points ExpandDerived added, in the order added.
    pub added: Vec<usize>,
    /// Relative magnitude `θ` of each derived point, in the order of `derived`:
    /// `δ''/(δ' + δ'')` (anchors have 1 and fixed points 0 by definition, and are not listed).
    pub theta: Vec<Rational>,
    /// Solvability checks run by ExpandDerived (1 when `S` was already enough).
    pub checks: usize,
    /// Set when no derived set can make the edit solvable: no fixed control point is left in
    /// the conditions that block it. The selection is still complete, so the edit can be run
    /// and refused by ECLES with its exact certificate and explanation.
    pub blocked: Option<Blocked>,
}

/// The outcome of ExpandDerived.
#[derive(Debug, Clone, PartialEq)]
pub struct Expansion {
    /// The derived points `D ⊇ S`, sorted.
    pub derived: Vec<usize>,
    /// `D \ S`, in the order added.
    pub added: Vec<usize>,
    /// Solvability checks run.
    pub checks: usize,
    /// Set when no derived set makes the edit solvable.
    pub blocked: Option<Blocked>,
}

/// Why ExpandDerived stopped without making the edit solvable.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Blocked {
    /// What cannot happen: `"moving v3[1]"`, `"the requested move"` or `"the current values"`.
    pub what: String,
    /// Labels of the blocking conditions (the exact certificate's rows).
    pub conditions: Vec<String>,
}

impl std::fmt::Display for Blocked {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} conflicts with {:?}", self.what, self.conditions)
    }
}

impl Selection {
    /// Number of anchors of each point type (figure 14.5), for reports.
    pub fn anchor_types(&self, spline: &Spline) -> Vec<(PointType, usize)> {
        let mut out: Vec<(PointType, usize)> = Vec::new();
        for &a in &self.anchors {
            let kind = spline.points()[a].kind;
            match out.iter_mut().find(|(k, _)| *k == kind) {
                Some((_, n)) => *n += 1,
                None => out.push((kind, 1)),
            }
        }
        out.sort();
        out
    }
}

/// A 2DSD operation on the anchors.
#[derive(Debug, Clone, PartialEq)]
pub enum Operation {
    /// Soft translation by a vector (`dim` coordinates): anchors move by `v`, derived points are
    /// pulled by `θ v`.
    Translate {
        /// The displacement.
        by: Vec<Rational>,
    },
    /// Soft rotation about `center` by `degrees` (planar splines only): anchors rotate by the
    /// angle, derived points are pulled by `θ` times it.
    ///
    /// Every point moves by an exact rational rotation ([`motion::Rotation`]): the angle is
    /// reduced exactly modulo 360, multiples of 90 degrees are exact (a multiple of 360 leaves
    /// the point unchanged), and otherwise `tan` of the half angle is rounded to the grid
    /// `1/precision`, so `cos² + sin² = 1` exactly, distances to the centre are preserved
    /// exactly and the angle is within `(1 + 1/32)/precision` radians of the request.
    Rotate {
        /// Centre of rotation.
        center: [Rational; 2],
        /// Angle in degrees, counter-clockwise.
        degrees: Rational,
        /// Denominator of the grid of `tan(angle/2)`: `1..=`[`motion::MAX_PRECISION`]
        /// (`10^12`).
        precision: u64,
    },
    /// Soft scaling about `center` by `factor > 0` (planar splines only): anchors scale by
    /// `factor`, derived points are pulled by `factor^θ` (each step by the power `t = θ ·` step
    /// fraction).
    ///
    /// The full factor (`t = 1`: anchors at the last step) is exact; other powers are exact
    /// rationals ([`motion::scale_power`]) of relative error below `1/precision` (at most
    /// `0.63/precision`) for any positive rational factor, however large or small.
    Scale {
        /// Centre of scaling.
        center: [Rational; 2],
        /// Scale factor, positive.
        factor: Rational,
        /// Inverse of the relative precision of `factor^θ`: `1..=`[`motion::MAX_PRECISION`]
        /// (`10^12`).
        precision: u64,
    },
}

impl Operation {
    /// Checks the operation against a spline of dimension `dim` without running anything: a
    /// translation has `dim` coordinates; rotation and scaling need a planar spline (`dim = 2`)
    /// and a precision in `1..=`[`motion::MAX_PRECISION`]; the scale factor is positive.
    pub fn validate(&self, dim: usize) -> Result<(), SelectError> {
        let invalid = |message: String| Err(SelectError::InvalidOperation(message));
        let planar = |what: &str| {
            if dim == 2 {
                Ok(())
            } else {
                invalid(format!(
                    "{what} needs a planar spline (dimension 2), this spline has dimension {dim}"
                ))
            }
        };
        let precision = |p: u64| {
            motion::check_precision(p).map_err(|e| SelectError::InvalidOperation(e.to_string()))
        };
        match self {
            Operation::Translate { by } if by.len() != dim => invalid(format!(
                "translate has {} coordinates, the spline has dimension {dim}",
                by.len()
            )),
            Operation::Translate { .. } => Ok(()),
            Operation::Rotate { precision: p, .. } => {
                planar("rotate")?;
                precision(*p)
            }
            Operation::Scale {
                factor,
                precision: p,
                ..
            } => {
                planar("scale")?;
                precision(*p)?;
                if factor.is_positive() {
                    Ok(())
                } else {
                    invalid(format!(
                        "scale factor {} must be positive",
                        api::format_rational(factor)
                    ))
                }
            }
        }
    }
}

/// Anchor values and hints of one step of an operation.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// New values of the anchors, in [`Plan::spec`] anchor order.
    pub anchors: Vec<Vec<Rational>>,
    /// Hints of the derived points, in [`Plan::spec`] derived order.
    pub hints: Vec<Vec<Rational>>,
}

/// An ECLES edit ready to run: which parameters, and the anchor values and hints per step.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// Anchors and derived parameters (strong solvability verified by the selection).
    pub spec: EditSpec,
    /// Steps from the start of the drag; each is relative to the state at initialisation, so
    /// the last step alone gives the final result.
    pub steps: Vec<Step>,
}

/// Why a selection or an operation was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SelectError {
    /// No anchors.
    #[error("select at least one anchor control point")]
    NoAnchors,
    /// An anchor id is not a control point.
    #[error("control point {0} does not exist")]
    UnknownPoint(usize),
    /// The operation does not fit the spline (rotation of a scalar spline, wrong vector size,
    /// non-positive scale, zero steps, precision outside `1..=`[`motion::MAX_PRECISION`]), or
    /// a motion's float error bound would not be far below its rounding grid.
    #[error("invalid operation: {0}")]
    InvalidOperation(String),
    /// ECLES refused the edit for another reason.
    #[error("edit refused: {0}")]
    Edit(String),
}

/// 2DSD on one spline declared in a system.
#[derive(Debug, Clone, Copy)]
pub struct SplineEditor<'a> {
    /// The spline.
    pub spline: &'a Spline,
    /// Its control net.
    pub net: &'a ControlNet,
    /// Its parameters in the system.
    pub params: &'a SplineParams,
}

impl SplineEditor<'_> {
    /// 2DSD.Select for an edit whose moves are not known yet (a mouse-down before the drag):
    /// the neighbourhood `S`, ExpandDerived to `D` until the edit is **strongly** solvable
    /// (every anchor move can be absorbed; verified exactly against every row of `system`,
    /// including rows other sources put on these points), and ComputeRelMagnitude.
    pub fn select(
        &self,
        system: &ConstraintSystem,
        values: &Values,
        anchors: &[usize],
        neighborhood: Neighborhood,
    ) -> Result<Selection, SelectError> {
        self.expand(system, values, anchors, neighborhood, None)
    }

    /// 2DSD.Select for known anchor moves (`moves[k]`: one displacement per anchor, in
    /// ascending anchor order): ExpandDerived grows `D` only until *these* moves can be
    /// absorbed ([`ecles::check_moves`]), so a point pinned in x can still be dragged along y.
    pub fn select_for_moves(
        &self,
        system: &ConstraintSystem,
        values: &Values,
        anchors: &[usize],
        neighborhood: Neighborhood,
        moves: &[Vec<Vec<Rational>>],
    ) -> Result<Selection, SelectError> {
        self.expand(system, values, anchors, neighborhood, Some(moves))
    }

    /// The neighbourhood, ExpandDerived (against `moves`, or every direction) and `θ`.
    fn expand(
        &self,
        system: &ConstraintSystem,
        values: &Values,
        anchors: &[usize],
        neighborhood: Neighborhood,
        moves: Option<&[Vec<Vec<Rational>>]>,
    ) -> Result<Selection, SelectError> {
        if anchors.is_empty() {
            return Err(SelectError::NoAnchors);
        }
        let n = self.spline.points().len();
        if let Some(&bad) = anchors.iter().find(|&&a| a >= n) {
            return Err(SelectError::UnknownPoint(bad));
        }
        let anchor_set: BTreeSet<usize> = anchors.iter().copied().collect();
        let anchors: Vec<usize> = anchor_set.iter().copied().collect();
        let mut to_anchor = self.net.distances_from(&anchors);
        let initial: Vec<usize> = match neighborhood {
            Neighborhood::All => (0..n).filter(|p| !anchor_set.contains(p)).collect(),
            Neighborhood::Radius(r) => {
                let mut near: Vec<usize> = to_anchor
                    .within(r)
                    .iter()
                    .copied()
                    .filter(|p| !anchor_set.contains(p))
                    .collect();
                near.sort_unstable();
                near
            }
        };
        let expansion =
            self.expand_derived(system, values, &anchors, &initial, &mut to_anchor, moves)?;
        let derived = expansion.derived;
        let theta = self.relative_magnitudes(&anchors, &derived, &mut to_anchor);
        Ok(Selection {
            anchors,
            initial,
            derived,
            added: expansion.added,
            theta,
            checks: expansion.checks,
            blocked: expansion.blocked,
        })
    }

    /// 2DSD.ExpandDerived (thesis 14.3; its figure 14.6 is missing, see the module doc): from
    /// `D = S` (`initial`), run the exact solvability check — for `moves` when they are known
    /// ([`ecles::check_moves`]), strong solvability otherwise — and add the fixed control points
    /// of the blocking conditions nearest to the anchors on the control net, until it passes or
    /// no such point is left ([`Expansion::blocked`]).
    ///
    /// Complexity: one exact factoring of `R_ED` per round; the rounds are at most the net
    /// distance from the anchors to the farthest point added.
    pub fn expand_derived(
        &self,
        system: &ConstraintSystem,
        values: &Values,
        anchors: &[usize],
        initial: &[usize],
        to_anchor: &mut Distances<'_>,
        moves: Option<&[Vec<Vec<Rational>>]>,
    ) -> Result<Expansion, SelectError> {
        let anchor_set: BTreeSet<usize> = anchors.iter().copied().collect();
        let mut derived: BTreeSet<usize> = initial.iter().copied().collect();
        let mut added = Vec::new();
        let mut checks = 0;
        let mut blocked = None;
        loop {
            checks += 1;
            let spec = EditSpec::new(self.ids(anchors), self.ids(derived.iter()));
            let outcome = match moves {
                Some(moves) => {
                    ecles::check_moves(&ExactLdu::default(), system, values, &spec, moves)
                }
                None => Edit::<ExactFactorization>::check_strongly_solvable(
                    &ExactLdu::default(),
                    system,
                    values,
                    &spec,
                ),
            };
            let (what, conflict) = match outcome {
                Ok(()) => break,
                Err(EditError::NotStronglySolvable {
                    anchor,
                    component,
                    conflict,
                }) => (
                    format!(
                        "moving {anchor}{}",
                        component.map(|k| format!("[{k}]")).unwrap_or_default()
                    ),
                    conflict,
                ),
                Err(EditError::MoveBlocked(conflict)) => {
                    ("the requested move".to_string(), conflict)
                }
                Err(EditError::CurrentStateInconsistent(conflict)) => {
                    // No derived point repairs values that already violate the conditions.
                    blocked = Some(Blocked {
                        what: "the current values".into(),
                        conditions: conflict.labels().iter().map(|s| s.to_string()).collect(),
                    });
                    break;
                }
                Err(other) => return Err(SelectError::Edit(other.to_string())),
            };
            let mut candidates: Vec<usize> = Vec::new();
            for row in conflict.row_ids() {
                for p in system.rows()[row.index()].body.params() {
                    if let Some(cp) = self.params.point_of(p) {
                        if !anchor_set.contains(&cp) && !derived.contains(&cp) {
                            candidates.push(cp);
                        }
                    }
                }
            }
            let nearest = candidates
                .iter()
                .map(|&c| to_anchor.get(c).unwrap_or(u32::MAX))
                .min();
            let Some(nearest) = nearest else {
                blocked = Some(Blocked {
                    what,
                    conditions: conflict.labels().iter().map(|s| s.to_string()).collect(),
                });
                break;
            };
            candidates.sort_unstable();
            candidates.dedup();
            for c in candidates {
                if to_anchor.get(c).unwrap_or(u32::MAX) == nearest {
                    derived.insert(c);
                    added.push(c);
                }
            }
        }
        Ok(Expansion {
            derived: derived.into_iter().collect(),
            added,
            checks,
            blocked,
        })
    }

    /// The whole 2DSD edit for an operation: the anchors' moves first (they do not depend on
    /// the derived set), then Select and ExpandDerived for exactly those moves, then the hints.
    /// The selection may be [`Selection::blocked`]; the plan is complete either way.
    pub fn plan_operation(
        &self,
        system: &ConstraintSystem,
        values: &Values,
        anchors: &[usize],
        neighborhood: Neighborhood,
        operation: &Operation,
        steps: usize,
    ) -> Result<(Selection, Plan), SelectError> {
        if steps == 0 {
            return Err(SelectError::InvalidOperation(
                "steps must be at least 1".into(),
            ));
        }
        operation.validate(self.params.dim)?;
        let n = self.spline.points().len();
        if let Some(&bad) = anchors.iter().find(|&&a| a >= n) {
            return Err(SelectError::UnknownPoint(bad));
        }
        let sorted: Vec<usize> = anchors
            .iter()
            .copied()
            .collect::<BTreeSet<_>>()
            .into_iter()
            .collect();
        let moves: Vec<Vec<Vec<Rational>>> = (1..=steps)
            .map(|k| {
                let fraction = Rational::new(k.into(), steps.into());
                sorted
                    .iter()
                    .map(|&a| {
                        let from = values.get(self.params.ids[a]);
                        let to = move_point(operation, from, &fraction)?;
                        Ok(to.iter().zip(from).map(|(t, f)| t - f).collect())
                    })
                    .collect::<Result<Vec<Vec<Rational>>, SelectError>>()
            })
            .collect::<Result<_, _>>()?;
        let selection = self.select_for_moves(system, values, &sorted, neighborhood, &moves)?;
        let plan = self.plan(&selection, values, operation, steps)?;
        Ok((selection, plan))
    }

    fn ids<'b>(&self, points: impl IntoIterator<Item = &'b usize>) -> Vec<ParamId> {
        points.into_iter().map(|&p| self.params.ids[p]).collect()
    }

    /// 2DSD.ComputeRelMagnitude: `θ_s = δ''/(δ' + δ'')` for each derived point `s` (in the
    /// order of `derived`), with `δ'` the net distance to the nearest anchor and `δ''` to the
    /// nearest fixed point. Both searches stay near the edit: `δ''` never leaves the anchors
    /// and derived points ([`ControlNet::distances_out_of`]).
    fn relative_magnitudes(
        &self,
        anchors: &[usize],
        derived: &[usize],
        to_anchor: &mut Distances<'_>,
    ) -> Vec<Rational> {
        let moving: Vec<usize> = derived.iter().chain(anchors).copied().collect();
        let to_fixed = self.net.distances_out_of(&moving);
        derived
            .iter()
            .zip(&to_fixed)
            .map(|(&p, &f)| match (to_anchor.get(p), f) {
                (Some(a), Some(f)) => Rational::new(f.into(), (a + f).into()),
                (Some(_), None) => Rational::one(),
                (None, _) => Rational::zero(),
            })
            .collect()
    }

    /// Turns an operation into anchor values and hints for `steps` equal steps (the drag), from
    /// the current `values`.
    pub fn plan(
        &self,
        selection: &Selection,
        values: &Values,
        operation: &Operation,
        steps: usize,
    ) -> Result<Plan, SelectError> {
        if steps == 0 {
            return Err(SelectError::InvalidOperation(
                "steps must be at least 1".into(),
            ));
        }
        operation.validate(self.params.dim)?;
        let position = |p: usize| values.get(self.params.ids[p]).to_vec();
        let steps_out = (1..=steps)
            .map(|k| {
                let fraction = Rational::new(k.into(), steps.into());
                let moved = |p: usize, theta: &Rational| {
                    move_point(operation, &position(p), &(theta * &fraction))
                };
                Ok(Step {
                    anchors: selection
                        .anchors
                        .iter()
                        .map(|&a| moved(a, &Rational::one()))
                        .collect::<Result<_, _>>()?,
                    hints: selection
                        .derived
                        .iter()
                        .zip(&selection.theta)
                        .map(|(&s, theta)| moved(s, theta))
                        .collect::<Result<_, _>>()?,
                })
            })
            .collect::<Result<_, SelectError>>()?;
        Ok(Plan {
            spec: EditSpec::new(self.ids(&selection.anchors), self.ids(&selection.derived)),
            steps: steps_out,
        })
    }
}

/// The point `p` moved by the fraction `t` of an operation (`t = θ · step fraction`), exactly
/// (see [`motion`]).
fn move_point(
    operation: &Operation,
    p: &[Rational],
    t: &Rational,
) -> Result<Vec<Rational>, SelectError> {
    let invalid = |e: motion::MotionError| SelectError::InvalidOperation(e.to_string());
    fn planar(p: &[Rational]) -> Result<&[Rational; 2], SelectError> {
        <&[Rational; 2]>::try_from(p).map_err(|_| {
            SelectError::InvalidOperation(format!(
                "rotation and scaling need planar points, this one has {} coordinates",
                p.len()
            ))
        })
    }
    match operation {
        Operation::Translate { by } => Ok(p
            .iter()
            .zip(by)
            .map(|(x, v)| api::exact::rational_sum(x, &(v * t)))
            .collect()),
        Operation::Rotate {
            center,
            degrees,
            precision,
        } => motion::rotate_point(center, planar(p)?, degrees, t, *precision)
            .map(Vec::from)
            .map_err(invalid),
        Operation::Scale {
            center,
            factor,
            precision,
        } => motion::scale_point(center, planar(p)?, factor, t, *precision)
            .map(Vec::from)
            .map_err(invalid),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spline::tests::grid;

    struct Fixture {
        spline: Spline,
        net: ControlNet,
        system: ConstraintSystem,
        params: SplineParams,
        values: Values,
    }

    fn fixture(n: usize) -> Fixture {
        let spline = Spline::new(grid(n, true), 5, 1).expect("spline");
        let net = ControlNet::new(&spline);
        let mut system = ConstraintSystem::new();
        let mut values = Values::default();
        let params = spline
            .declare(&mut system, &mut values, "phi", spline.identity_positions())
            .expect("declare");
        Fixture {
            spline,
            net,
            system,
            params,
            values,
        }
    }

    impl Fixture {
        fn editor(&self) -> SplineEditor<'_> {
            SplineEditor {
                spline: &self.spline,
                net: &self.net,
                params: &self.params,
            }
        }
    }

    fn point(f: &Fixture, name: &str) -> usize {
        f.spline
            .points()
            .iter()
            .position(|p| p.name == name)
            .expect("point exists")
    }

    fn run(f: &mut Fixture, selection: &Selection, op: &Operation) {
        let editor = f.editor();
        let plan = editor.plan(selection, &f.values, op, 3).expect("plan");
        let edit: Edit<ExactFactorization> =
            Edit::initialize(&ExactLdu::default(), &f.system, &f.values, &plan.spec).expect("init");
        let last = plan.steps.last().expect("steps");
        edit.apply(&f.system, &mut f.values, &last.anchors, &last.hints)
            .expect("strongly solvable edits never fail");
        assert!(f.system.violations(&f.values).is_empty());
    }

    #[test]
    fn translating_an_edge_point_keeps_the_spline_smooth() {
        let mut f = fixture(4);
        let editor = f.editor();
        let anchor = point(&f, "e6-12:2");
        let sel = editor
            .select(&f.system, &f.values, &[anchor], Neighborhood::Radius(3))
            .expect("select");
        assert!(sel.derived.len() >= sel.initial.len());
        assert_eq!(sel.theta.len(), sel.derived.len());
        for theta in &sel.theta {
            assert!(*theta > Rational::zero() && *theta < Rational::one());
        }
        let op = Operation::Translate {
            by: vec![
                Rational::new(7.into(), 2.into()),
                Rational::new((-5).into(), 3.into()),
            ],
        };
        run(&mut f, &sel, &op);
        let moved = f.values.get(f.params.ids[anchor]).to_vec();
        let nominal = f.spline.nominal(anchor);
        assert_eq!(moved[0], &nominal[0] + Rational::new(7.into(), 2.into()));
        // Points far away did not move.
        let far = point(&f, "v24");
        assert_eq!(
            f.values.get(f.params.ids[far]),
            f.spline.nominal(far).as_slice()
        );
    }

    #[test]
    fn an_interior_vertex_needs_expansion_and_gets_it() {
        let mut f = fixture(4);
        let editor = f.editor();
        // Radius 0: S is empty, so every derived point is added by ExpandDerived.
        let anchor = point(&f, "v12");
        let sel = editor
            .select(&f.system, &f.values, &[anchor], Neighborhood::Radius(0))
            .expect("select");
        assert!(sel.initial.is_empty());
        assert!(!sel.added.is_empty());
        assert!(sel.checks > 1);
        run(
            &mut f,
            &sel,
            &Operation::Translate {
                by: vec![
                    Rational::from_integer(2.into()),
                    Rational::from_integer(1.into()),
                ],
            },
        );
    }

    #[test]
    fn rotation_and_scaling_round_and_still_solve_exactly() {
        for op in [
            Operation::Rotate {
                center: [Rational::zero(), Rational::zero()],
                degrees: Rational::from_integer(30.into()),
                precision: 1000,
            },
            Operation::Scale {
                center: [
                    Rational::from_integer(20.into()),
                    Rational::from_integer(20.into()),
                ],
                factor: Rational::new(3.into(), 2.into()),
                precision: 1000,
            },
        ] {
            let mut f = fixture(4);
            let editor = f.editor();
            let anchors = [point(&f, "v12"), point(&f, "e12-13:4")];
            let sel = editor
                .select(&f.system, &f.values, &anchors, Neighborhood::Radius(2))
                .expect("select");
            run(&mut f, &sel, &op);
        }
    }

    #[test]
    fn global_moves_use_every_point() {
        let mut f = fixture(2);
        let editor = f.editor();
        let anchor = point(&f, "v4");
        let sel = editor
            .select(&f.system, &f.values, &[anchor], Neighborhood::All)
            .expect("select");
        assert_eq!(sel.derived.len(), f.spline.points().len() - 1);
        // With no fixed point left, every hint moves fully with the anchor.
        assert!(sel.theta.iter().all(|theta| *theta == Rational::one()));
        run(
            &mut f,
            &sel,
            &Operation::Translate {
                by: vec![
                    Rational::from_integer(1.into()),
                    Rational::from_integer(1.into()),
                ],
            },
        );
        // A pure translation of everything is an affine map: every point moved by (1, 1).
        for (p, id) in f.params.ids.iter().enumerate() {
            let nominal = f.spline.nominal(p);
            assert_eq!(f.values.get(*id)[0], &nominal[0] + Rational::one());
        }
    }

    /// The `z` mode of scalar splines (terrain heights): a translation along the one axis.
    #[test]
    fn scalar_splines_translate_along_their_axis() {
        let spline = Spline::new(grid(3, true), 5, 1).expect("spline");
        let net = ControlNet::new(&spline);
        let mut system = ConstraintSystem::new();
        let mut values = Values::default();
        let params = spline
            .declare(
                &mut system,
                &mut values,
                "z0",
                spline.constant_positions(&Rational::from_integer((-5).into())),
            )
            .expect("declare");
        let editor = SplineEditor {
            spline: &spline,
            net: &net,
            params: &params,
        };
        let anchor = spline
            .points()
            .iter()
            .position(|p| &*p.name == "v5")
            .expect("interior vertex");
        let sel = editor
            .select(&system, &values, &[anchor], Neighborhood::Radius(3))
            .expect("select");
        let dz = Rational::new(9.into(), 2.into());
        let plan = editor
            .plan(
                &sel,
                &values,
                &Operation::Translate {
                    by: vec![dz.clone()],
                },
                2,
            )
            .expect("plan");
        assert!(editor
            .plan(
                &sel,
                &values,
                &Operation::Rotate {
                    center: [Rational::zero(), Rational::zero()],
                    degrees: Rational::one(),
                    precision: 10
                },
                1
            )
            .is_err());
        let edit: Edit<ExactFactorization> =
            Edit::initialize(&ExactLdu::default(), &system, &values, &plan.spec).expect("init");
        let last = plan.steps.last().expect("steps");
        edit.apply(&system, &mut values, &last.anchors, &last.hints)
            .expect("strongly solvable");
        assert!(system.violations(&values).is_empty());
        assert_eq!(
            values.get(params.ids[anchor])[0],
            Rational::from_integer((-5).into()) + dz
        );
    }

    #[test]
    fn bad_requests_are_errors() {
        let f = fixture(1);
        let editor = f.editor();
        assert!(matches!(
            editor.select(&f.system, &f.values, &[], Neighborhood::All),
            Err(SelectError::NoAnchors)
        ));
        assert!(matches!(
            editor.select(&f.system, &f.values, &[9999], Neighborhood::All),
            Err(SelectError::UnknownPoint(9999))
        ));
        let sel = editor
            .select(&f.system, &f.values, &[0], Neighborhood::Radius(2))
            .expect("select");
        assert!(editor
            .plan(
                &sel,
                &f.values,
                &Operation::Translate {
                    by: vec![Rational::one()]
                },
                1
            )
            .is_err());
        assert!(editor
            .plan(
                &sel,
                &f.values,
                &Operation::Scale {
                    center: [Rational::zero(), Rational::zero()],
                    factor: Rational::zero(),
                    precision: 10
                },
                1
            )
            .is_err());
    }

    #[test]
    fn exact_motions_in_plans_and_their_validation() {
        let f = fixture(2);
        let editor = f.editor();
        let anchor = point(&f, "v4");
        let sel = editor
            .select(&f.system, &f.values, &[anchor], Neighborhood::Radius(2))
            .expect("select");
        let center = [
            Rational::from_integer(3.into()),
            Rational::from_integer((-2).into()),
        ];
        // 3.6e401 degrees is a whole number of turns: the anchor stays exactly in place.
        let op = Operation::Rotate {
            center: center.clone(),
            degrees: api::parse_rational("3.6e401").expect("degrees"),
            precision: 1_000_000,
        };
        let plan = editor.plan(&sel, &f.values, &op, 2).expect("plan");
        let last = plan.steps.last().expect("steps");
        assert_eq!(
            last.anchors[0].as_slice(),
            f.spline.nominal(anchor).as_slice()
        );
        // A scale by 1e300 moves the anchor exactly.
        let factor = api::parse_rational("1e300").expect("factor");
        let op = Operation::Scale {
            center: center.clone(),
            factor: factor.clone(),
            precision: 1_000_000,
        };
        let plan = editor.plan(&sel, &f.values, &op, 1).expect("plan");
        let nominal = f.spline.nominal(anchor);
        assert_eq!(
            plan.steps[0].anchors[0][0],
            &center[0] + &factor * (&nominal[0] - &center[0])
        );
        // Precision and factor limits, with messages naming the field and the limit.
        for precision in [0, motion::MAX_PRECISION + 1] {
            let op = Operation::Rotate {
                center: center.clone(),
                degrees: Rational::one(),
                precision,
            };
            let expected = format!(
                "invalid operation: precision {precision} must be between 1 and 1000000000000"
            );
            let err = op.validate(2).expect_err("refused");
            assert_eq!(err.to_string(), expected);
            let err = editor.plan(&sel, &f.values, &op, 1).expect_err("refused");
            assert_eq!(err.to_string(), expected);
        }
        let op = Operation::Scale {
            center: center.clone(),
            factor: -Rational::one(),
            precision: 10,
        };
        assert_eq!(
            op.validate(2).expect_err("refused").to_string(),
            "invalid operation: scale factor -1 must be positive"
        );
        assert!(op.validate(1).is_err());
        let op = Operation::Scale {
            center,
            factor: Rational::one(),
            precision: motion::MAX_PRECISION,
        };
        assert!(op.validate(2).is_ok());
        assert!(op.validate(1).is_err());
        let op = Operation::Translate {
            by: vec![Rational::one()],
        };
        assert!(op.validate(1).is_ok());
        assert_eq!(
            op.validate(2).expect_err("refused").to_string(),
            "invalid operation: translate has 1 coordinates, the spline has dimension 2"
        );
    }

    #[test]
    fn expand_derived_grows_from_nothing_until_the_edit_is_solvable() {
        let f = fixture(4);
        let editor = f.editor();
        let anchor = point(&f, "v12");
        let mut to_anchor = f.net.distances_from(&[anchor]);
        let strong = editor
            .expand_derived(&f.system, &f.values, &[anchor], &[], &mut to_anchor, None)
            .expect("expands");
        assert!(strong.blocked.is_none());
        assert!(!strong.derived.is_empty() && strong.checks > 1);
        assert_eq!(strong.added.len(), strong.derived.len());
        // Every point added lies on a blocking condition: none is farther than needed, and the
        // result passes the exact strong check.
        let spec = EditSpec::new(editor.ids(&[anchor]), editor.ids(strong.derived.iter())).strong();
        Edit::<ExactFactorization>::check_strongly_solvable(
            &ExactLdu::default(),
            &f.system,
            &f.values,
            &spec,
        )
        .expect("strongly solvable");
        // A known move needs at most what every direction needs.
        let along_x = vec![vec![vec![Rational::one(), Rational::zero()]]];
        let directed = editor
            .expand_derived(
                &f.system,
                &f.values,
                &[anchor],
                &[],
                &mut to_anchor,
                Some(&along_x),
            )
            .expect("expands");
        assert!(directed.blocked.is_none());
        assert!(directed.derived.len() <= strong.derived.len());
    }
}
