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

use super::save;
use crate::error::RunError;
use crate::session::{ActiveEdit, Planning, Session};
use api::{format_rational, parse_rational, ParamId, Rational, Values};
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Instant;
use tokio::sync::oneshot;

/// The largest number of anchors one drag may name.
const MAX_ANCHORS: usize = 1_000;

/// The longest text of a displacement (a mouse move needs a few digits; this bounds the
/// exact numbers a request can make the session compute with).
const MAX_NUMBER_TEXT: usize = 64;

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
}

/// One frame of a drag: the anchors (control point names of `source`, without the source's
/// prefix), the neighbourhood (`None`: every point), the displacement since the drag began
/// as exact decimal text, and whether this is the release.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DragRequest {
    /// The source whose points move.
    pub source: String,
    /// Point names (`v3`, `e3-7:2`, `t5:2,2,1`).
    pub anchors: Vec<String>,
    /// `δ_max` on the control net; `None` for every point.
    pub neighborhood: Option<u32>,
    /// Displacement in x and y since the drag began (decimal or fraction text, exact).
    pub dx: String,
    /// See `dx`.
    pub dy: String,
    /// Commit the exact result (the mouse was released).
    pub commit: bool,
}

/// The drag under way: what it was planned for and its initialised edit.
struct ActiveDrag {
    key: (String, Vec<String>, Option<u32>),
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
    json!({
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
        }),
    }
}

/// The answer to a move that cannot be made: the message, the labels of the constraints in
/// the way and the explanation (the state is unchanged).
fn refused(message: String, labels: Vec<String>, explanation: Vec<String>) -> Value {
    json!({
        "ok": false,
        "conflict": { "message": message, "labels": labels, "explanation": explanation },
    })
}

/// Checks a point name before it goes into the source's operation text.
fn check_point_name(name: &str) -> Result<(), String> {
    let allowed = |c: char| c.is_ascii_alphanumeric() || "-_:,.".contains(c);
    if name.is_empty() || name.len() > 64 || !name.chars().all(allowed) {
        return Err(format!("{name:?} is not a control point name"));
    }
    Ok(())
}

fn drag_frame(
    session: &mut Session,
    drag: &mut Option<ActiveDrag>,
    request: &DragRequest,
) -> Result<Value, String> {
    let started = Instant::now();
    if request.anchors.is_empty() || request.anchors.len() > MAX_ANCHORS {
        return Err(format!(
            "a drag needs between 1 and {MAX_ANCHORS} anchors, not {}",
            request.anchors.len()
        ));
    }
    for name in &request.anchors {
        check_point_name(name)?;
    }
    if !session.source_names().any(|s| s == request.source) {
        return Err(format!("unknown source {:?}", request.source));
    }
    let exact = |what: &str, text: &str| -> Result<Rational, String> {
        if text.len() > MAX_NUMBER_TEXT {
            return Err(format!(
                "{what} has {} characters, more than {MAX_NUMBER_TEXT}",
                text.len()
            ));
        }
        parse_rational(text).map_err(|e| format!("{what} {text:?}: {e}"))
    };
    let (dx, dy) = (exact("dx", &request.dx)?, exact("dy", &request.dy)?);
    let neighborhood = request
        .neighborhood
        .map_or_else(|| "\"all\"".to_string(), |n| n.to_string());
    let anchors: Vec<String> = request.anchors.iter().map(|a| format!("{a:?}")).collect();
    let operation = format!(
        "(anchors: [{}], neighborhood: {neighborhood}, translate: ({:?}, {:?}), steps: 1)",
        anchors.join(", "),
        format_rational(&dx),
        format_rational(&dy),
    );
    let plan = match session
        .plan_operation(&request.source, &operation)
        .map_err(|e| e.to_string())?
    {
        Planning::Planned(plan) => plan,
        Planning::Refused(message) => return Ok(refused(message, Vec::new(), Vec::new())),
    };
    let key = (
        request.source.clone(),
        request.anchors.clone(),
        request.neighborhood,
    );
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
    if let Some(result) = committed {
        let Some(active) = drag.take() else {
            return Err("no drag under way".into());
        };
        // Source names are letters, digits, '_' and '-' (the run file's rule): `{:?}` is their
        // RON string.
        let entry = format!(
            "Source(source: {:?}, operation: {operation})",
            request.source
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
