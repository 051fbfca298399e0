//! Drag frames: a drag is a sequence of [`DragRequest`]s for the same selection, each with the
//! motion since the drag began; the last one commits.
//!
//! * **Mouse-down** (the first frame of a selection): the source plans the operation (2DSD
//!   Select and ExpandDerived) and the edit is initialised once (ECLES Initialize). For a
//!   translation the plan is affine in the displacement `d` (anchors `a + d`, hints
//!   `p + θ d`), so it is also planned for `d = (1, 0)` and `(0, 1)` (a terrain lift: `dz = 1`),
//!   once the mouse-down frame is answered ([`prepare_linear_steps`]): every later frame's step
//!   is `origin + dx·along_x + dy·along_y`, exact, without planning again ([`LinearSteps`]).
//!   Rotations and scalings are planned at every frame.
//! * **A frame** is one exact Update with the values rounded for drawing: the exact optimum
//!   (`preview`) for an edit initialised within [`OPTIMUM_FRAME_BUDGET`] while its frames take
//!   no longer, else a snapped point (`update_snapped`: every constraint exact, small values, a
//!   proved distance to the optimum, the same verdict). A frame that moves nothing (the
//!   mouse-down frame) is the current values. A run whose commits are snapped draws snapped frames on its own grid, so
//!   a frame is its commit. An impossible move is refused with the constraints in the way.
//! * **The motion response** of a translation or lift: ECLES Update is affine in the step, and
//!   the step is affine in the motion, so the exact optimum of every frame is
//!   `P(c) = P(0) + Σ c_k·Δ_k` with `Δ_k = P(e_k) − P(0)`. Once the steps are affine, the
//!   `Δ_k` are made by exact Updates on a thread of their own (the drag's frames go on
//!   meanwhile) and sent, rounded, with the next frame ([`MotionResponse`]); the page then draws
//!   every move itself, the exact optimum rounded, without a round trip.
//! * **The release** plans the operation exactly at the final motion (not interpolated) and
//!   commits the run's kind of update; the page shows how far the last frame was from it.
//! * **Another change criterion** (the page's selector: L1, fewest changed points; Brenner
//!   3.1): every frame and the release are exact Updates under it ([`ecles::Edit::update_by`]),
//!   committed as chosen (not snapped), and there is no motion response: the choice is
//!   piecewise, not affine, in the motion.

use super::motion::{DragRequest, Motion, Selection};
use crate::runfile::{CommitPolicy, MeasureName};
use crate::session::{ActiveEdit, PlannedEdit, Planning, Session};
use api::{ParamId, PlannedStep, Rational};
use num_traits::Zero;
use serde_json::{json, Value};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

/// Frames show the exact optimum while one costs at most this; slower edits draw snapped
/// points (a 60-frames-a-second drag leaves about 16 ms for the server, the transfer and the
/// drawing together).
const OPTIMUM_FRAME_BUDGET: Duration = Duration::from_millis(2);

/// The grid of snapped frames of a run that commits the optimum (`2^−24`: far below a pixel
/// for any drawing, values stay short).
const FRAME_GRID_BITS: u32 = 24;

/// How frames of a drag are computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum FrameKind {
    /// The exact optimum, rounded.
    Optimum,
    /// A snapped exact point on the grid `2^−bits`.
    Snapped(u32),
}

/// The steps of a translation or a lift as an affine function of the motion's coordinates.
struct LinearSteps {
    origin: PlannedStep,
    /// The change of the step per unit of each coordinate.
    along: Vec<PlannedStep>,
}

impl LinearSteps {
    /// The step for the coordinates `c`: `origin + Σ c_k · along_k`.
    fn at(&self, c: &[Rational]) -> PlannedStep {
        let combine = |pick: fn(&PlannedStep) -> &Vec<Vec<Rational>>| -> Vec<Vec<Rational>> {
            pick(&self.origin)
                .iter()
                .enumerate()
                .map(|(i, point)| {
                    point
                        .iter()
                        .enumerate()
                        .map(|(j, o)| {
                            // Most terms vanish (a translation along x leaves every y alone):
                            // exact products and sums are paid only for the others.
                            self.along.iter().zip(c).fold(o.clone(), |sum, (a, c)| {
                                let a = &pick(a)[i][j];
                                if a.is_zero() || c.is_zero() {
                                    sum
                                } else {
                                    api::exact::rational_sum(&sum, &(c * a))
                                }
                            })
                        })
                        .collect()
                })
                .collect()
        };
        PlannedStep {
            anchors: combine(|s| &s.anchors),
            hints: combine(|s| &s.hints),
        }
    }
}

/// `b − a`, coordinate by coordinate.
fn difference(a: &PlannedStep, b: &PlannedStep) -> PlannedStep {
    let minus = |a: &[Vec<Rational>], b: &[Vec<Rational>]| {
        a.iter()
            .zip(b)
            .map(|(a, b)| {
                a.iter()
                    .zip(b)
                    .map(|(a, b)| api::exact::rational_difference(b, a))
                    .collect()
            })
            .collect()
    };
    PlannedStep {
        anchors: minus(&a.anchors, &b.anchors),
        hints: minus(&a.hints, &b.hints),
    }
}

/// The response of a drag's optimum to its motion, for the page: its points, their values at
/// the origin and their change per unit of each coordinate, rounded (as every frame is for
/// drawing) and flattened point by point, with a bound on how far the drawn frames can be from
/// the exact optimum beyond rounding.
struct MotionResponse {
    ids: Vec<u32>,
    dim: usize,
    base: Vec<f64>,
    along: Vec<Vec<f64>>,
    /// Every coordinate of `base + Σ c_k·along_k` is within `bound·(1 + Σ |c_k|)` of the exact
    /// optimum at `c` (rounding aside).
    bound: f64,
    /// The kind of frames it was taken from: zero bound for optimum frames; a drag that was
    /// slow (a busy machine, a large edit) takes it from snapped ones.
    frames: FrameKind,
}

/// Points with exact values, in an edit's order (anchors, then derived parameters).
type Points = Vec<(ParamId, Vec<Rational>)>;

/// The motion at which a snapped response is taken: the snapped points' distance to the
/// optimum does not grow with the motion, so divided by this it is negligible.
const SNAPPED_RESPONSE_SCALE: i64 = 1 << 20;

impl MotionResponse {
    /// The response of `edit` to `linear`, with frames of kind `frames`: for optimum frames
    /// `P(0)` and `P(e_k) − P(0)` by exact Updates; for snapped frames (large edits, whose
    /// exact optimum is slow) `(S(s·e_k) − P(0))/s` with snapped Updates `S` at the motion
    /// `s = 2^20`, each within its proved distance of the optimum, so the response is within
    /// that distance divided by `s`. `P(0)` is `known_origin` when given (the current values,
    /// when they are the optimum of the zero motion), else an Update too. `None` when an Update
    /// is refused (some motions are impossible: frames stay Updates on the server, each with
    /// its own verdict).
    fn of(
        edit: &ActiveEdit,
        linear: &LinearSteps,
        frames: FrameKind,
        known_origin: Option<Points>,
    ) -> Option<MotionResponse> {
        let dimension = linear.along.len();
        let scale = match frames {
            FrameKind::Optimum => 1,
            FrameKind::Snapped(_) => SNAPPED_RESPONSE_SCALE,
        };
        let at = |k: Option<usize>| -> Vec<Rational> {
            (0..dimension)
                .map(|j| Rational::from_integer(if Some(j) == k { scale } else { 0 }.into()))
                .collect()
        };
        // The points' exact values at motion `c`, and their proved distance to the optimum.
        let solve = |c: &[Rational]| -> Option<(Points, f64)> {
            let step = linear.at(c);
            let (result, bound) = match frames {
                FrameKind::Optimum => (edit.update(&step).ok()?, 0.0),
                FrameKind::Snapped(bits) => {
                    let (result, summary) = edit.update_snapped(&step, bits).ok()?;
                    (result, summary.distance_bound)
                }
            };
            Some((
                result.anchors.into_iter().chain(result.derived).collect(),
                bound,
            ))
        };
        let (origin, origin_bound) = match known_origin {
            Some(origin) => (origin, 0.0),
            None => solve(&at(None))?,
        };
        let dim = origin.first().map_or(0, |(_, v)| v.len());
        if origin.iter().any(|(_, v)| v.len() != dim) {
            return None;
        }
        let divisor = api::Integer::from(scale);
        let mut along = Vec::with_capacity(dimension);
        let mut bound = origin_bound;
        for k in 0..dimension {
            let (unit, unit_bound) = solve(&at(Some(k)))?;
            bound = bound.max((origin_bound + unit_bound) / scale as f64);
            along.push(
                unit.iter()
                    .zip(&origin)
                    .flat_map(|((_, u), (_, o))| {
                        u.iter().zip(o).map(|(u, o)| {
                            api::exact::rational_to_f64(&api::exact::rational_over_integer(
                                &api::exact::rational_difference(u, o),
                                &divisor,
                            ))
                        })
                    })
                    .collect(),
            );
        }
        Some(MotionResponse {
            ids: origin.iter().map(|(id, _)| id.0).collect(),
            dim,
            base: origin
                .iter()
                .flat_map(|(_, v)| v.iter().map(api::exact::rational_to_f64))
                .collect(),
            along,
            bound,
            frames,
        })
    }

    fn to_json(&self) -> Value {
        json!({
            "ids": self.ids,
            "dim": self.dim,
            "base": self.base,
            "along": self.along,
            "bound": self.bound,
            "frames": frame_kind_text(self.frames),
        })
    }
}

/// The drag under way: what it was planned for, its initialised edit and how its frames are
/// made.
pub(super) struct ActiveDrag {
    key: Selection,
    spec: ecles::EditSpec,
    /// Shared with the thread that makes the motion response.
    edit: Arc<ActiveEdit>,
    /// The motion response being made: taken by the first frame after it is ready.
    response: Option<mpsc::Receiver<Option<MotionResponse>>>,
    linear: Option<LinearSteps>,
    /// A translation or lift initialised but not yet made affine: its motion, plan and
    /// coordinates, for [`prepare_linear_steps`] after the mouse-down frame is answered.
    linear_pending: Option<(Motion, PlannedEdit, Vec<Rational>)>,
    frames: FrameKind,
    /// The change criterion of the latest frame.
    criterion: MeasureName,
    /// Rank of `R_ED` and its redundant rows in scalar equations (from the edit's report, made
    /// once).
    rank: usize,
    redundant: usize,
}

/// The answer to a move that cannot be made: the message, the labels of the constraints in
/// the way and the explanation (the state is unchanged).
pub(super) fn refused(message: String, labels: Vec<String>, explanation: Vec<String>) -> Value {
    json!({
        "ok": false,
        "conflict": { "message": message, "labels": labels, "explanation": explanation },
    })
}

/// Rows as the page draws them: the label and the points (parameters of dimension 2) in each
/// row, for rows made of points only.
pub(super) fn drawable_rows(
    system: &api::ConstraintSystem,
    rows: impl Iterator<Item = api::RowId>,
) -> Vec<Value> {
    rows.filter_map(|r| {
        let row = &system.rows()[r.index()];
        let params = row.body.params();
        let points = params.iter().all(|p| system.params()[p.index()].dim == 2);
        (points && params.len() >= 2).then(|| {
            json!({ "label": row.label, "points": params.iter().map(|p| p.0).collect::<Vec<_>>() })
        })
    })
    .collect()
}

/// Plans `motion` of `selection`: the plan, or the answer refusing it.
fn plan(
    session: &Session,
    selection: &Selection,
    motion: &Motion,
) -> Result<Result<PlannedEdit, Value>, String> {
    let operation = selection.operation(motion)?;
    Ok(
        match session
            .plan_operation(&selection.source, &operation)
            .map_err(|e| e.to_string())?
        {
            Planning::Planned(plan) => Ok(plan),
            Planning::Refused(message) => Err(refused(message, Vec::new(), Vec::new())),
        },
    )
}

/// The last step of a plan.
fn last_step(plan: &PlannedEdit) -> Result<&PlannedStep, String> {
    plan.steps
        .last()
        .ok_or_else(|| "the source planned no step".to_string())
}

/// For a translation or a lift of `selection` planned as `base` at coordinates `at`: the steps
/// at the origin and at unit coordinates, when the source plans the same edit for them (the
/// same anchors, derived set and weights) and its plan is affine (checked at `at`).
fn linear_steps(
    session: &Session,
    selection: &Selection,
    motion: &Motion,
    base: &PlannedEdit,
    at: &[Rational],
) -> Result<Option<LinearSteps>, String> {
    let plan_at = |coordinates: &[&str]| -> Result<Option<PlannedStep>, String> {
        let Some(m) = motion.with_coordinates(coordinates) else {
            return Ok(None);
        };
        Ok(match plan(session, selection, &m)? {
            Ok(p) if p.spec == base.spec => Some(last_step(&p)?.clone()),
            _ => None,
        })
    };
    let zero = Rational::from_integer(0.into());
    let dimension = at.len();
    // The mouse-down frame is planned at the origin already.
    let origin = if at.iter().all(|c| *c == zero) {
        last_step(base)?.clone()
    } else {
        match plan_at(&vec!["0"; dimension])? {
            Some(step) => step,
            None => return Ok(None),
        }
    };
    let mut along = Vec::with_capacity(dimension);
    for k in 0..dimension {
        let mut unit = vec!["0"; dimension];
        unit[k] = "1";
        match plan_at(&unit)? {
            Some(step) => along.push(difference(&origin, &step)),
            None => return Ok(None),
        }
    }
    let linear = LinearSteps { origin, along };
    // The source's plan must be affine in the motion: checked at the frame's own coordinates
    // and at (2, …, 2), a point the unit plans do not contain.
    if linear.at(at) != *last_step(base)? {
        return Ok(None);
    }
    let two = Rational::from_integer(2.into());
    Ok(match plan_at(&vec!["2"; dimension])? {
        Some(step) if linear.at(&vec![two; dimension]) == step => Some(linear),
        _ => None,
    })
}

/// The frame kind a drag starts with, committing under `policy`, whose Initialize took
/// `initialize`: an edit that is slow to initialise is large, and its optimum frames would be
/// slow too. An optimum frame over [`OPTIMUM_FRAME_BUDGET`] switches the drag to snapped frames
/// (see [`slower_frames`]).
fn first_frame_kind(policy: CommitPolicy, initialize: Duration) -> FrameKind {
    match policy {
        CommitPolicy::Snapped { grid_bits } => FrameKind::Snapped(grid_bits),
        CommitPolicy::Optimum if initialize > OPTIMUM_FRAME_BUDGET => {
            FrameKind::Snapped(FRAME_GRID_BITS)
        }
        CommitPolicy::Optimum => FrameKind::Optimum,
    }
}

/// How frames of kind `kind` are named in answers.
fn frame_kind_text(kind: FrameKind) -> String {
    match kind {
        FrameKind::Optimum => "optimum".to_string(),
        FrameKind::Snapped(bits) => format!("snapped 2^-{bits}"),
    }
}

/// The frame kind after a frame of kind `kind` took `took`.
fn slower_frames(kind: FrameKind, took: Duration) -> FrameKind {
    match kind {
        FrameKind::Optimum if took > OPTIMUM_FRAME_BUDGET => FrameKind::Snapped(FRAME_GRID_BITS),
        other => other,
    }
}

/// One frame of a drag, or its release (see the module documentation).
pub(super) fn drag_frame(
    session: &mut Session,
    drag: &mut Option<ActiveDrag>,
    request: &DragRequest,
) -> Result<Value, String> {
    let started = Instant::now();
    let selection = &request.selection;
    if !session.source_names().any(|s| s == selection.source) {
        return Err(format!("unknown source {:?}", selection.source));
    }
    let motion = &request.motion;
    let coordinates = motion.linear_coordinates()?;
    let same = drag.as_ref().is_some_and(|d| d.key == *selection);
    // A frame of a translation or lift under way: its step, exactly, without planning.
    let interpolated = match (same, request.commit, &coordinates, drag.as_ref()) {
        (
            true,
            false,
            Some(c),
            Some(ActiveDrag {
                linear: Some(l), ..
            }),
        ) if l.along.len() == c.len() => Some(l.at(c)),
        _ => None,
    };
    let mut initialized = false;
    let step = match interpolated {
        Some(step) => step,
        None => {
            let planned = match plan(session, selection, motion)? {
                Ok(p) => p,
                Err(answer) => return Ok(answer),
            };
            if !(same && drag.as_ref().is_some_and(|d| d.spec == planned.spec)) {
                *drag = None;
                let initializing = Instant::now();
                let edit = match session.initialize(&planned) {
                    Ok(edit) => edit,
                    Err(e) => {
                        let (labels, explanation) = session.conflict_details(&planned.spec, &e);
                        return Ok(refused(e.to_string(), labels, explanation));
                    }
                };
                let report = edit.edit().report();
                let (_, rank, redundant) =
                    crate::session::equation_counts(session.system(), &report);
                *drag = Some(ActiveDrag {
                    key: selection.clone(),
                    spec: planned.spec.clone(),
                    edit: Arc::new(edit),
                    response: None,
                    linear: None,
                    linear_pending: coordinates
                        .clone()
                        .map(|at| (motion.clone(), planned.clone(), at)),
                    frames: first_frame_kind(session.commit_policy(), initializing.elapsed()),
                    criterion: request.criterion,
                    rank,
                    redundant,
                });
                initialized = true;
            }
            last_step(&planned)?.clone()
        }
    };
    let Some(active) = drag.as_mut() else {
        return Err("no drag under way".into());
    };
    active.criterion = request.criterion;
    let criterion = request.criterion.criterion();
    if !criterion.is_least_squares() {
        // Its frames are not affine in the motion: no response is drawn from.
        active.response = None;
    }
    let mut chosen = None;
    let to_f64 = |v: &[Rational]| {
        v.iter()
            .map(api::exact::rational_to_f64)
            .collect::<Vec<_>>()
    };
    // A moved point as `[id, x, y]` (a height: `[id, z]`): compact, a frame may carry
    // thousands.
    let moved_point = |id: &ParamId, value: Vec<f64>| {
        let mut entry = Vec::with_capacity(1 + value.len());
        entry.push(Value::from(id.0));
        entry.extend(value.into_iter().map(Value::from));
        Value::Array(entry)
    };
    let conflict = |session: &Session, active: &ActiveDrag, e: &ecles::EditError<Rational>| {
        let (labels, explanation) = session.conflict_details(&active.spec, e);
        refused(e.to_string(), labels, explanation)
    };
    let mut snap_bound = None;
    let (moved, committed) = if request.commit {
        if motion.is_identity() {
            return Err("a release that moves nothing commits nothing".into());
        }
        let result = if criterion.is_least_squares() {
            session.committed_update(&active.edit, &step)
        } else {
            let hints = session.criterion_hints(&criterion, &active.spec, &step);
            active
                .edit
                .update_by(&criterion, &step, &hints)
                .map(|(result, summary)| {
                    chosen = Some(summary);
                    result
                })
        };
        let result = match result {
            Ok(result) => result,
            Err(e) => return Ok(conflict(session, active, &e)),
        };
        let moved: Vec<Value> = result
            .anchors
            .iter()
            .chain(&result.derived)
            .map(|(id, v)| moved_point(id, to_f64(v)))
            .collect();
        (moved, Some(result))
    } else {
        let solving = Instant::now();
        let still =
            motion.is_identity() && session.system().violations(session.values()).is_empty();
        let derived: Vec<Vec<f64>> = if still {
            // Nothing moves (the mouse-down frame) and every row holds: the current values
            // are the solution (feasible and equal to the hints), nothing to solve.
            let values = session.values();
            active
                .spec
                .derived
                .iter()
                .map(|id| to_f64(values.get(*id)))
                .collect()
        } else if !criterion.is_least_squares() {
            let hints = session.criterion_hints(&criterion, &active.spec, &step);
            match active.edit.update_by(&criterion, &step, &hints) {
                Ok((result, summary)) => {
                    chosen = Some(summary);
                    result.derived.iter().map(|(_, v)| to_f64(v)).collect()
                }
                Err(e) => return Ok(conflict(session, active, &e)),
            }
        } else {
            match active.frames {
                FrameKind::Optimum => match active.edit.preview(&step) {
                    Ok(derived) => derived,
                    Err(e) => return Ok(conflict(session, active, &e)),
                },
                FrameKind::Snapped(bits) => match active.edit.update_snapped(&step, bits) {
                    Ok((result, summary)) => {
                        snap_bound = Some(summary.distance_bound);
                        result.derived.iter().map(|(_, v)| to_f64(v)).collect()
                    }
                    Err(e) => return Ok(conflict(session, active, &e)),
                },
            }
        };
        active.frames = slower_frames(active.frames, solving.elapsed());
        let edit = active.edit.edit();
        let moved: Vec<Value> = edit
            .anchors()
            .iter()
            .zip(&step.anchors)
            .map(|(id, v)| moved_point(id, to_f64(v)))
            .chain(
                edit.derived()
                    .iter()
                    .zip(derived)
                    .map(|(id, v)| moved_point(id, v)),
            )
            .collect();
        (moved, None)
    };
    let mut answer = json!({
        "ok": true,
        "moved": moved,
        "anchors": active.spec.anchors.len(),
        "derived": active.spec.derived.len(),
        "rank": active.rank,
        "redundant": active.redundant,
        "initialized": initialized,
        "frames": frame_kind_text(active.frames),
        "snap_bound": snap_bound,
        "planned": planned_text(active.linear.is_some() || active.linear_pending.is_some()),
    });
    if let Some(summary) = &chosen {
        // What report.json says of it: the page's status bar shows it.
        answer["criterion"] = json!(session.criterion_report(summary));
    }
    if let Some(response) = &active.response {
        match response.try_recv() {
            Ok(Some(response)) => {
                answer["affine"] = response.to_json();
                active.response = None;
            }
            Ok(None) | Err(mpsc::TryRecvError::Disconnected) => active.response = None,
            Err(mpsc::TryRecvError::Empty) => {}
        }
    }
    if initialized {
        // Once per drag: which points are derived, and the non-redundant relevant constraints
        // (the rows the edit keeps), for drawing.
        let mut independent: Vec<api::RowId> = active
            .edit
            .edit()
            .report()
            .independent
            .iter()
            .map(|r| r.row)
            .collect();
        independent.sort();
        independent.dedup();
        answer["derived_ids"] = json!(active.spec.derived.iter().map(|p| p.0).collect::<Vec<_>>());
        answer["relevant"] = json!(drawable_rows(session.system(), independent.into_iter()));
    }
    if let Some(result) = committed {
        let Some(active) = drag.take() else {
            return Err("no drag under way".into());
        };
        // Source names are letters, digits, '_' and '-' (the run file's rule): `{:?}` is their
        // RON string.
        let criterion_text = match request.criterion {
            MeasureName::L2 => String::new(),
            other => format!(", criterion: {other:?}"),
        };
        let entry = format!(
            "Source(source: {:?}, operation: {}{criterion_text})",
            selection.source,
            selection.operation(motion)?
        );
        session
            .apply(&active.edit, &result, entry)
            .map_err(|e| e.to_string())?;
        answer["committed"] = json!(true);
        answer["violated_rows"] = json!(session.system().violations(session.values()).len());
    }
    answer["server_ms"] = json!(started.elapsed().as_secs_f64() * 1e3);
    Ok(answer)
}

/// After the mouse-down frame of a translation or lift was answered: plans the unit motions and
/// makes the drag's steps affine ([`LinearSteps`]), so that the mouse-down frame waits only for
/// Select, ExpandDerived and Initialize, and every move after it for an Update. A source whose
/// plan is not affine leaves the drag planning every frame.
pub(super) fn prepare_linear_steps(session: &Session, drag: &mut Option<ActiveDrag>) {
    let Some(active) = drag.as_mut() else {
        return;
    };
    let Some((motion, planned, at)) = active.linear_pending.take() else {
        return;
    };
    active.linear = linear_steps(session, &active.key, &motion, &planned, &at)
        .ok()
        .flatten();
    if let (Some(linear), MeasureName::L2) = (&active.linear, active.criterion) {
        // The steps at the origin and at unit motions, for the thread.
        let steps = LinearSteps {
            origin: linear.origin.clone(),
            along: linear.along.clone(),
        };
        let edit = Arc::clone(&active.edit);
        let frames = active.frames;
        let known_origin = current_optimum(session, &active.edit, &linear.origin);
        let (answer, response) = mpsc::channel();
        let spawned = std::thread::Builder::new()
            .name("ecles-motion-response".into())
            .spawn(move || {
                // The drag may be over before this is done: nobody listens then.
                let _ = answer.send(MotionResponse::of(&edit, &steps, frames, known_origin));
            });
        active.response = spawned.ok().map(|_| response);
    }
}

/// The optimum of `edit` at `step` when it is the current values: the step leaves the anchors
/// where they are and hints the derived parameters' current values, and every row holds (the
/// current values are then feasible and meet every hint). The points in the edit's order.
fn current_optimum(session: &Session, edit: &ActiveEdit, step: &PlannedStep) -> Option<Points> {
    let values = session.values();
    let edit = edit.edit();
    let unmoved = |ids: &[ParamId], wanted: &[Vec<Rational>]| {
        ids.len() == wanted.len()
            && ids
                .iter()
                .zip(wanted)
                .all(|(id, w)| values.get(*id) == w.as_slice())
    };
    let still = unmoved(edit.anchors(), &step.anchors)
        && unmoved(edit.derived(), &step.hints)
        && session.system().violations(values).is_empty();
    still.then(|| {
        edit.anchors()
            .iter()
            .chain(edit.derived())
            .map(|id| (*id, values.get(*id).to_vec()))
            .collect()
    })
}

/// How the frames' steps are made, for the page's status.
fn planned_text(linear: bool) -> &'static str {
    if linear {
        "once (affine in the motion)"
    } else {
        "every frame"
    }
}
