//! The editing session on a thread of its own: the server's handlers send it [`Command`]s and
//! await the replies, so the session (and the plugin instances in it) never crosses threads
//! and one command runs at a time.
//!
//! A drag is a sequence of [`DragRequest`]s for the same source, anchors and neighbourhood,
//! each with the total displacement so far: every move plans the source's translation
//! (2DSD Select and ExpandDerived for that move), reuses the initialised edit while the plan's
//! anchors, derived set and weights stay the same (ECLES Initialize once), and answers the
//! moved points for drawing: the exact verdict with the values rounded (`preview`, which skips
//! reducing fractions); the last request commits the exact update.

use super::motion::{DragRequest, Selection};
use super::save;
use crate::error::RunError;
use crate::session::{ActiveEdit, Planning, Session};
use api::{format_rational, ParamId, Rational, Values};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Instant;
use tokio::sync::oneshot;

/// A request of the page, with the channel for its answer.
pub(crate) enum Command {
    /// The whole state: sources with their views, points with their values, counts.
    State(oneshot::Sender<Value>),
    /// One frame of a drag, or its end.
    Drag(DragRequest, oneshot::Sender<Result<Value, String>>),
    /// Undo (`true`) or redo (`false`) the last committed edit.
    History(bool, oneshot::Sender<Value>),
    /// Save the session under a name (`None`: the default name).
    Save(Option<String>, oneshot::Sender<Result<Value, String>>),
    /// Resume the autosave offered at start (`true`), or decline it (`false`).
    Resume(bool, oneshot::Sender<Result<Value, String>>),
    /// The points a selection would move (2DSD Select and ExpandDerived, nothing initialised).
    Select(Selection, oneshot::Sender<Result<Value, String>>),
}

/// The drag under way: what it was planned for and its initialised edit.
struct ActiveDrag {
    key: Selection,
    spec: ecles::EditSpec,
    edit: ActiveEdit,
    /// Rank of `R_ED` and its redundant rows (from the edit's report, made once).
    rank: usize,
    redundant: usize,
}

/// The editor's side of the session: the session, the drag under way and the autosave.
pub(crate) struct Editor {
    session: Session,
    drag: Option<ActiveDrag>,
    /// Where the autosave goes (`None`: no autosave).
    autosave: Option<PathBuf>,
    /// An autosave found at start, with its number of edits, until resumed, declined or
    /// replaced by a commit.
    offer: Option<(PathBuf, usize)>,
    /// The last autosave's failure, shown until one succeeds.
    autosave_error: Option<String>,
    input_limit: u64,
}

impl Editor {
    /// The editor of a built session; with `autosave`, the autosave beside the run file is
    /// kept after every change, and one found now is offered for resuming.
    pub(crate) fn new(session: Session, autosave: bool, input_limit: u64) -> Editor {
        let autosave = autosave.then(|| save::autosave_path(&session.run_path));
        let offer = autosave
            .as_ref()
            .and_then(|path| Some((path.clone(), save::autosave_offer(path, input_limit)?)));
        Editor {
            session,
            drag: None,
            autosave,
            offer,
            autosave_error: None,
            input_limit,
        }
    }

    /// Answers commands until every sender is gone.
    pub(crate) fn run(mut self, commands: mpsc::Receiver<Command>) {
        for command in commands {
            match command {
                Command::State(reply) => {
                    let _ = reply.send(self.state());
                }
                Command::Drag(request, reply) => {
                    let answer = self.drag_frame(&request);
                    let _ = reply.send(answer);
                }
                Command::History(undo, reply) => {
                    self.drag = None;
                    let done = if undo {
                        self.session.undo()
                    } else {
                        self.session.redo()
                    };
                    if done {
                        self.changed();
                    }
                    let mut answer = self.state();
                    answer["done"] = json!(done);
                    let _ = reply.send(answer);
                }
                Command::Save(name, reply) => {
                    let answer = save::save(&self.session, name.as_deref(), self.input_limit)
                        .map_err(|e| e.to_string());
                    let _ = reply.send(answer);
                }
                Command::Resume(resume, reply) => {
                    let _ = reply.send(self.resume(resume));
                }
                Command::Select(selection, reply) => {
                    let _ = reply.send(select(&self.session, &selection));
                }
            }
        }
    }

    /// After a commit, undo, redo or resume: the offer lapses, the autosave is written.
    fn changed(&mut self) {
        self.offer = None;
        if let Some(path) = &self.autosave {
            self.autosave_error = save::autosave(&self.session, path)
                .err()
                .map(|e| e.to_string());
        }
    }

    /// Resumes the offered autosave, or declines it.
    fn resume(&mut self, resume: bool) -> Result<Value, String> {
        let Some((path, _)) = self.offer.clone() else {
            return Err("there is no autosave to resume".into());
        };
        if !resume {
            self.offer = None;
            return Ok(self.state());
        }
        self.drag = None;
        let repeated = self.session.resume(&path).map_err(|e| e.to_string())?;
        self.changed();
        let mut answer = self.state();
        answer["resumed"] = json!(repeated);
        Ok(answer)
    }

    /// The state ([`session_state`]) with the autosave's offer and failure.
    fn state(&self) -> Value {
        let mut state = session_state(&self.session);
        state["autosave"] = json!({
            "path": self.autosave.as_ref().map(|p| p.display().to_string()),
            "offer": self.offer.as_ref().map(|(path, edits)| json!({
                "path": path.display().to_string(),
                "edits": edits,
            })),
            "error": self.autosave_error,
        });
        state["committed"] = json!(self.session.committed_count());
        state
    }

    /// A drag frame ([`drag_frame`]); a commit is autosaved.
    fn drag_frame(&mut self, request: &DragRequest) -> Result<Value, String> {
        let answer = drag_frame(&mut self.session, &mut self.drag, request)?;
        if answer["committed"] == json!(true) {
            self.changed();
        }
        Ok(answer)
    }
}

/// Builds the session of `run` (on the caller's thread: the actor's own thread), or the error.
pub(crate) fn build(run: &Path, max_input_bytes: u64) -> Result<Session, RunError> {
    let session = Session::build(run, max_input_bytes)?;
    session.check()?;
    Ok(session)
}

/// A point's coordinates rounded for drawing.
fn approx(values: &Values, id: ParamId) -> Vec<f64> {
    values
        .get(id)
        .iter()
        .map(api::exact::rational_to_f64)
        .collect()
}

/// The whole state: sources with their views, points with their values, counts.
fn session_state(session: &Session) -> Value {
    let system = session.system();
    let values = session.values();
    let mut sources = Vec::new();
    for name in session.source_names() {
        let view = match session.view(name) {
            Ok(view) => serde_json::to_value(view.map(drawable_view)).unwrap_or(Value::Null),
            Err(e) => json!({ "error": e.to_string() }),
        };
        sources.push(json!({ "name": name, "view": view }));
    }
    let points: Vec<Value> = system
        .params()
        .iter()
        .enumerate()
        .filter(|(_, p)| p.dim == 2)
        .map(|(i, p)| {
            let id = ParamId(i as u32);
            json!({
                "id": i,
                "name": p.name,
                "value": approx(values, id),
                "exact": values.get(id).iter().map(format_rational).collect::<Vec<_>>(),
            })
        })
        .collect();
    let (can_undo, can_redo) = session.can_undo_redo();
    let rows = (0..system.rows().len()).map(|r| api::RowId(r as u32));
    json!({
        "constraints": drawable_rows(system, rows),
        "run": session.run_path.display().to_string(),
        "sources": sources,
        "points": points,
        "rows": system.rows().len(),
        "violated_rows": system.violations(values).len(),
        "can_undo": can_undo,
        "can_redo": can_redo,
    })
}

/// A view as the page draws it: exact vertices rounded (the page never computes with them),
/// parameters as indices.
fn drawable_view(view: api::SourceView) -> Value {
    match view {
        api::SourceView::BezierTriangles(v) => json!({
            "kind": "bezier_triangles",
            "degree": v.degree,
            "smoothness": v.smoothness,
            "vertices": v.vertices.iter().map(|p| [
                api::exact::rational_to_f64(&p[0]),
                api::exact::rational_to_f64(&p[1]),
            ]).collect::<Vec<_>>(),
            "triangles": v.triangles,
            "patches": v.patches.iter().map(|p| p.iter().map(|id| id.0).collect::<Vec<_>>()).collect::<Vec<_>>(),
            // Drawn deformed by the page from the control points (floats: drawing only).
            "models": v.models,
        }),
    }
}

/// The anchors and derived points of `selection` (the initial derived set S the page shows as
/// soon as the selection or `δ_max` changes), planned for a translation by zero.
fn select(session: &Session, selection: &Selection) -> Result<Value, String> {
    if !session.source_names().any(|s| s == selection.source) {
        return Err(format!("unknown source {:?}", selection.source));
    }
    let still = super::Motion::Translate {
        dx: "0".into(),
        dy: "0".into(),
    };
    let operation = selection.operation(&still)?;
    match session
        .plan_operation(&selection.source, &operation)
        .map_err(|e| e.to_string())?
    {
        Planning::Planned(plan) => Ok(json!({
            "ok": true,
            "anchors": plan.spec.anchors.iter().map(|p| p.0).collect::<Vec<_>>(),
            "derived": plan.spec.derived.iter().map(|p| p.0).collect::<Vec<_>>(),
        })),
        Planning::Refused(message) => Ok(refused(message, Vec::new(), Vec::new())),
    }
}

/// Rows as the page draws them: the label and the points (parameters of dimension 2) in each
/// row, for rows made of points only.
fn drawable_rows(
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

/// The answer to a move that cannot be made: the message, the labels of the constraints in
/// the way and the explanation (the state is unchanged).
fn refused(message: String, labels: Vec<String>, explanation: Vec<String>) -> Value {
    json!({
        "ok": false,
        "conflict": { "message": message, "labels": labels, "explanation": explanation },
    })
}

fn drag_frame(
    session: &mut Session,
    drag: &mut Option<ActiveDrag>,
    request: &DragRequest,
) -> Result<Value, String> {
    let started = Instant::now();
    let selection = &request.selection;
    if !session.source_names().any(|s| s == selection.source) {
        return Err(format!("unknown source {:?}", selection.source));
    }
    let operation = selection.operation(&request.motion)?;
    let plan = match session
        .plan_operation(&selection.source, &operation)
        .map_err(|e| e.to_string())?
    {
        Planning::Planned(plan) => plan,
        Planning::Refused(message) => return Ok(refused(message, Vec::new(), Vec::new())),
    };
    let key = selection.clone();
    let reuse = drag
        .as_ref()
        .is_some_and(|d| d.key == key && d.spec == plan.spec);
    if !reuse {
        let edit = match session.initialize(&plan) {
            Ok(edit) => edit,
            Err(e) => {
                *drag = None;
                let (labels, explanation) = session.conflict_details(&plan.spec, &e);
                return Ok(refused(e.to_string(), labels, explanation));
            }
        };
        let report = edit.edit().report();
        *drag = Some(ActiveDrag {
            key,
            spec: plan.spec.clone(),
            edit,
            rank: report.rank,
            redundant: report.redundant.len(),
        });
    }
    let Some(active) = drag.as_ref() else {
        return Err("no drag under way".into());
    };
    let step = plan
        .steps
        .last()
        .ok_or_else(|| "the source planned no step".to_string())?;
    let to_f64 = |v: &[Rational]| {
        v.iter()
            .map(api::exact::rational_to_f64)
            .collect::<Vec<_>>()
    };
    let moved_point = |id: &ParamId, value: Vec<f64>| json!({ "id": id.0, "value": value });
    // A frame is drawn: the exact verdict with the values rounded (`preview`); the release
    // commits the exact update.
    let (moved, committed) = if request.commit {
        let result = match session.committed_update(&active.edit, step) {
            Ok(result) => result,
            Err(e) => {
                let (labels, explanation) = session.conflict_details(&active.spec, &e);
                return Ok(refused(e.to_string(), labels, explanation));
            }
        };
        let moved: Vec<Value> = result
            .anchors
            .iter()
            .chain(&result.derived)
            .map(|(id, v)| moved_point(id, to_f64(v)))
            .collect();
        (moved, Some(result))
    } else {
        let derived = match active.edit.preview(step) {
            Ok(derived) => derived,
            Err(e) => {
                let (labels, explanation) = session.conflict_details(&active.spec, &e);
                return Ok(refused(e.to_string(), labels, explanation));
            }
        };
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
        "initialized": !reuse,
    });
    if !reuse {
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
        let entry = format!(
            "Source(source: {:?}, operation: {operation})",
            selection.source
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
