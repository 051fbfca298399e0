//! The editing session on a thread of its own: the server's handlers send it [`Command`]s and
//! await the replies, so the session (and the plugin instances in it) never crosses threads
//! and one command runs at a time.
//!
//! Drags are made in [`super::frames`]; saving, the autosave and resuming in [`super::save`].
//! The state the page draws is the sources' views (made once per build of the sources: they
//! hold structure, not values) with the current values. A continuity switch and a loaded
//! reference mesh rebuild the sources (a `Configure(...)` edit); a loaded model changes the
//! outputs; files loaded from the page are kept beside the run file ([`super::uploads`]).

use super::frames::{drag_frame, drawable_rows, prepare_linear_steps, refused, ActiveDrag};
use super::motion::{DragRequest, Selection};
use super::save;
use super::uploads;
use crate::config_text::set_field;
use crate::error::RunError;
use crate::runfile::CommitPolicy;
use crate::session::{CheckedImage, Planning, Session};
use api::{format_rational, ParamId, Values};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
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
    /// How a change of some points propagates ([`Session::propagation`]).
    Explain(ExplainRequest, oneshot::Sender<Result<Value, String>>),
    /// The run file's target image: its bytes and media type.
    Image(oneshot::Sender<Option<(Vec<u8>, &'static str)>>),
    /// Another continuity `C^r` for a source: a `Configure(...)` edit.
    Continuity(ContinuityRequest, oneshot::Sender<Result<Value, String>>),
    /// A reference mesh or model loaded from the page.
    Load(LoadRequest, oneshot::Sender<Result<Value, String>>),
}

/// What `/api/continuity` takes: the source and its new smoothness `r` (`C^r`).
#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ContinuityRequest {
    pub source: String,
    pub smoothness: u32,
}

/// What a file loaded from the page replaces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum LoadKind {
    /// The source's reference mesh (its `mesh` configuration field): a `Configure(...)` edit.
    Mesh,
    /// The model its outputs deform (see [`Session::replace_model`]).
    Model,
}

/// A file loaded from the page: its name, its bytes, what it replaces in which source.
pub(crate) struct LoadRequest {
    pub source: String,
    pub kind: LoadKind,
    pub name: String,
    pub bytes: Vec<u8>,
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
    /// The run file's target image (checked with the run, before serving).
    image: Option<CheckedImage>,
    /// The sources' views as the page draws them ([`source_views`]), made once per build of
    /// the sources (and when a model is replaced).
    views: Value,
    /// The [`Session::build_generation`] the views were made at.
    views_build: u64,
    /// How many times the views were made: the page keeps what it derived from them (a model's
    /// edges) while this stays the same.
    views_version: u64,
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
        // Checked with the rest of the run before the server started.
        let image = session.target_image().ok().flatten();
        let views = source_views(&session);
        Editor {
            views,
            views_build: session.build_generation(),
            views_version: 0,
            session,
            drag: None,
            autosave,
            offer,
            autosave_error: None,
            image,
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
                    // Work of the drag that the answer did not need to wait for.
                    prepare_linear_steps(&self.session, &mut self.drag);
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
                Command::Explain(request, reply) => {
                    let _ = reply.send(explain(&self.session, &request));
                }
                Command::Continuity(request, reply) => {
                    let _ = reply.send(self.continuity(&request));
                }
                Command::Load(request, reply) => {
                    let _ = reply.send(self.load(&request));
                }
                Command::Image(reply) => {
                    let _ = reply.send(
                        self.image
                            .as_ref()
                            .map(|image| (image.bytes.clone(), image.media_type)),
                    );
                }
            }
        }
    }

    /// After a commit, undo, redo or resume: the offer lapses, the views are made again if the
    /// sources were rebuilt, the autosave is written.
    fn changed(&mut self) {
        self.offer = None;
        if self.session.build_generation() != self.views_build {
            self.views = source_views(&self.session);
            self.views_build = self.session.build_generation();
            self.views_version += 1;
        }
        if let Some(path) = &self.autosave {
            self.autosave_error = save::autosave(&self.session, path)
                .err()
                .map(|e| e.to_string());
        }
    }

    /// Source `source` with continuity `C^r` from now on ([`Session::configure`]).
    fn continuity(&mut self, request: &ContinuityRequest) -> Result<Value, String> {
        let current = self
            .session
            .source_config(&request.source)
            .map_err(|e| e.to_string())?;
        let config = set_field(
            current,
            "smoothness",
            &request.smoothness.to_string(),
            "mesh",
        )
        .map_err(|e| format!("source {:?}: {e}", request.source))?;
        let done = self
            .session
            .configure(&request.source, &config)
            .map_err(|e| e.to_string())?;
        self.rebuilt();
        let mut answer = self.state();
        answer["configured"] = configured(done);
        Ok(answer)
    }

    /// A reference mesh or model loaded from the page: kept beside the run file
    /// ([`uploads::store`]), then made the source's mesh (a `Configure(...)` edit) or its
    /// outputs' model. Refused with the reader's message (the file, line and column) and
    /// nothing kept or changed when the source refuses it.
    fn load(&mut self, request: &LoadRequest) -> Result<Value, String> {
        let stored = uploads::store(&self.session.run_path, &request.name, &request.bytes)?;
        let path = serde_json::to_string(&stored.relative).map_err(|e| e.to_string())?;
        let outcome = match request.kind {
            LoadKind::Mesh => self
                .session
                .source_config(&request.source)
                .map_err(|e| e.to_string())
                .and_then(|current| {
                    set_field(current, "mesh", &path, "mesh")
                        .map_err(|e| format!("source {:?}: {e}", request.source))
                })
                .and_then(|config| {
                    self.session
                        .configure(&request.source, &config)
                        .map(|done| Some(configured(done)))
                        .map_err(|e| e.to_string())
                }),
            LoadKind::Model => self
                .session
                .replace_model(&request.source, &stored.relative)
                .map(|()| None)
                .map_err(|e| e.to_string()),
        };
        let done = match outcome {
            Ok(done) => done,
            Err(message) => {
                uploads::discard(&stored);
                return Err(format!("{} not loaded: {message}", request.name));
            }
        };
        self.rebuilt();
        let mut answer = self.state();
        answer["loaded"] = json!(stored.relative);
        if let Some(done) = done {
            answer["configured"] = done;
        }
        Ok(answer)
    }

    /// After the sources or outputs changed: no drag goes on, the views are made again, the
    /// autosave is written.
    fn rebuilt(&mut self) {
        self.drag = None;
        self.views = source_views(&self.session);
        self.views_build = self.session.build_generation();
        self.views_version += 1;
        self.changed();
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
        let mut state = session_state(&self.session, &self.views);
        self.add_editor_counts(&mut state);
        state["image"] = match &self.image {
            Some(image) => {
                let f = api::exact::rational_to_f64;
                let s = &image.settings;
                json!({
                    "file": s.file,
                    "opacity": f(&s.opacity),
                    "x": f(&s.position[0]),
                    "y": f(&s.position[1]),
                    "units_per_pixel": f(&s.units_per_pixel),
                    "size": image.size,
                })
            }
            None => Value::Null,
        };
        state
    }

    /// What a commit changed, for the page to apply to the state it has: the points in
    /// `moved` (the committed anchors and derived parameters, `[id, ...]` each) with their
    /// exact values, and the counts. Far smaller than the whole state (the views, every point
    /// and every row), which the page fetches again only when `views_version` changed.
    fn committed_state(&self, moved: &Value) -> Value {
        let count = self.session.system().params().len();
        let points: Vec<Value> = moved
            .as_array()
            .into_iter()
            .flatten()
            .filter_map(|entry| entry.get(0).and_then(Value::as_u64))
            .filter(|&id| id < count as u64)
            .map(|id| point_state(&self.session, ParamId(id as u32)))
            .collect();
        let mut state = Value::Object(value_counts(&self.session));
        state["points"] = Value::Array(points);
        self.add_editor_counts(&mut state);
        state
    }

    /// The editor's part of a state: the autosave's offer and failure, the number of commits,
    /// the version of the views.
    fn add_editor_counts(&self, state: &mut Value) {
        state["autosave"] = json!({
            "path": self.autosave.as_ref().map(|p| p.display().to_string()),
            "offer": self.offer.as_ref().map(|(path, edits)| json!({
                "path": path.display().to_string(),
                "edits": edits,
            })),
            "error": self.autosave_error,
        });
        state["committed"] = json!(self.session.committed_count());
        state["views_version"] = json!(self.views_version);
    }

    /// A drag frame ([`drag_frame`]); a commit is autosaved.
    fn drag_frame(&mut self, request: &DragRequest) -> Result<Value, String> {
        let mut answer = drag_frame(&mut self.session, &mut self.drag, request)?;
        if answer["committed"] == json!(true) {
            self.changed();
            answer["state"] = self.committed_state(&answer["moved"]);
        }
        Ok(answer)
    }
}

/// Which points to explain (ids, as the state gives them) and, optionally, a move of them
/// (exact numbers, one per coordinate in order).
#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ExplainRequest {
    ids: Vec<u32>,
    #[serde(default, rename = "move")]
    requested: Option<Vec<String>>,
}

/// The propagation analysis of the requested points: `lines` in words and `analysis` as JSON.
fn explain(session: &Session, request: &ExplainRequest) -> Result<Value, String> {
    let params = session.system().params();
    let names = request
        .ids
        .iter()
        .map(|&id| {
            params
                .get(id as usize)
                .map(|p| p.name.to_string())
                .ok_or_else(|| format!("no point {id}"))
        })
        .collect::<Result<Vec<String>, String>>()?;
    let requested = request.requested.as_ref().map(|values| values.join(","));
    let (_, analysis) = session
        .propagation(&names, requested.as_deref())
        .map_err(|e| e.to_string())?;
    Ok(json!({
        "ok": true,
        "lines": session.propagation_lines(&analysis),
        "analysis": session.propagation_json(&analysis),
    }))
}

/// What a `Configure(...)` did with the values, for the page.
fn configured(done: crate::session::Configured) -> Value {
    json!({
        "carried": done.carried,
        "restarted": done.restarted,
        "projected": done.projected,
    })
}

/// What the editor commits when the run file does not say: snapped points on the grid `2^−24`.
/// Every constraint holds exactly and the distance to the exact optimum is proved, as with any
/// snapped commit, and the values stay short over a long session, so that a drag over a region
/// edited before is as fast as the first (the exact optimum's denominators grow with every
/// commit: thousands of digits after a few edits of an irregular mesh). `commit: Optimum` in
/// the run file gives the thesis' optimum instead.
pub(crate) const EDITOR_COMMIT: CommitPolicy = CommitPolicy::Snapped { grid_bits: 24 };

/// Builds the session of `run` (on the caller's thread: the actor's own thread), or the error.
pub(crate) fn build(run: &Path, max_input_bytes: u64) -> Result<Session, RunError> {
    let mut session = Session::build(run, max_input_bytes)?;
    session.default_commit_policy(EDITOR_COMMIT);
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

/// Each source with its view as the page draws it. Views hold structure, not values: made once
/// per build of the sources (a view places every model vertex in the reference mesh).
fn source_views(session: &Session) -> Value {
    let mut sources = Vec::new();
    for name in session.source_names() {
        let view = match session.view(name) {
            Ok(view) => serde_json::to_value(view.map(drawable_view)).unwrap_or(Value::Null),
            Err(e) => json!({ "error": e.to_string() }),
        };
        sources.push(json!({ "name": name, "view": view }));
    }
    Value::Array(sources)
}

/// A point as the page keeps it: id, name, value rounded for drawing and exact.
fn point_state(session: &Session, id: ParamId) -> Value {
    let values = session.values();
    json!({
        "id": id.0,
        "name": session.system().params()[id.index()].name,
        "value": approx(values, id),
        "exact": values.get(id).iter().map(format_rational).collect::<Vec<_>>(),
    })
}

/// What changes with the values: residual, history, commit policy.
fn value_counts(session: &Session) -> serde_json::Map<String, Value> {
    let (can_undo, can_redo) = session.can_undo_redo();
    let mut counts = serde_json::Map::new();
    counts.insert(
        "violated_rows".into(),
        json!(session.system().violations(session.values()).len()),
    );
    counts.insert("can_undo".into(), json!(can_undo));
    counts.insert("can_redo".into(), json!(can_redo));
    counts.insert(
        "commit".into(),
        json!(match session.commit_policy() {
            CommitPolicy::Optimum => "the exact optimum".to_string(),
            CommitPolicy::Snapped { grid_bits } => format!("snapped to 2^-{grid_bits}"),
        }),
    );
    counts
}

/// The whole state: `sources` (from [`source_views`]), points with their values, counts.
fn session_state(session: &Session, sources: &Value) -> Value {
    let system = session.system();
    let points: Vec<Value> = system
        .params()
        .iter()
        .enumerate()
        // Points (dimension 2) and heights (dimension 1, a terrain's surfaces).
        .filter(|(_, p)| p.dim <= 2)
        .map(|(i, _)| point_state(session, ParamId(i as u32)))
        .collect();
    let rows = (0..system.rows().len()).map(|r| api::RowId(r as u32));
    let mut state = json!({
        "constraints": drawable_rows(system, rows),
        "run": session.run_path.display().to_string(),
        "sources": sources,
        "points": points,
        "rows": system.rows().len(),
    });
    if let Value::Object(fields) = &mut state {
        fields.extend(value_counts(session));
    }
    state
}

/// Reference vertices rounded for drawing (the page never computes with them).
fn drawable_vertices(vertices: &[[api::Rational; 2]]) -> Vec<[f64; 2]> {
    vertices
        .iter()
        .map(|p| p.each_ref().map(api::exact::rational_to_f64))
        .collect()
}

/// Patches of parameter ids as the page indexes them.
fn ids(patches: &[Vec<ParamId>]) -> Vec<Vec<u32>> {
    patches
        .iter()
        .map(|p| p.iter().map(|id| id.0).collect())
        .collect()
}

/// A view as the page draws it: exact vertices rounded (the page never computes with them),
/// parameters as indices.
fn drawable_view(view: api::SourceView) -> Value {
    match view {
        api::SourceView::BezierTriangles(v) => json!({
            "kind": "bezier_triangles",
            "degree": v.degree,
            "smoothness": v.smoothness,
            "vertices": drawable_vertices(&v.vertices),
            "triangles": v.triangles,
            "patches": ids(&v.patches),
            // Drawn deformed by the page from the control points (floats: drawing only).
            "models": v.models,
        }),
        api::SourceView::Prisms(v) => json!({
            "kind": "prisms",
            "degree": v.degree,
            "smoothness": v.smoothness,
            "vertices": drawable_vertices(&v.vertices),
            "triangles": v.triangles,
            "bottom": ids(&v.bottom),
            "top": ids(&v.top),
            "xy": v.xy.as_ref().map(|xy| ids(xy)),
            "reference_bottom": api::exact::rational_to_f64(&v.reference_bottom),
            "reference_top": api::exact::rational_to_f64(&v.reference_top),
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
