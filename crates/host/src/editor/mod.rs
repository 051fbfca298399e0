//! `ecles edit RUN.ron`: the interactive editor, a page served from this process.
//!
//! The server binds 127.0.0.1 only and serves one editing session. Every request must name
//! the host it was sent to as `127.0.0.1:PORT` or `localhost:PORT` (a page of another site
//! that rebinds a name to 127.0.0.1 is refused: DNS rebinding), must come from this origin when
//! the browser says where it comes from (`Origin`), and must carry the session's token (as the
//! `x-ecles-token` header, or as `?token=` in the URL: the page itself, its WebSocket and its
//! image, which a browser fetches without custom headers), unless `--no-token` was given for
//! scripted use. The page (HTML, script and style) is compiled into the binary: no build step,
//! no network.
//!
//! The session itself runs on a thread of its own ([`actor`]); handlers only forward.

mod actor;
mod frames;
mod motion;
mod save;
mod uploads;

pub use motion::{DragRequest, Motion, Selection};
pub use save::{autosave_offer, autosave_path, default_save_name, VALUES_FILE};

use crate::error::RunError;
use axum::body::Bytes;
use axum::extract::ws::{Message, WebSocket, WebSocketUpgrade};
use axum::extract::{DefaultBodyLimit, Query, Request, State};
use axum::http::{header, HeaderMap, HeaderValue, StatusCode};
use axum::middleware::{self, Next};
use axum::response::{Html, IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use serde_json::Value;
use std::net::{Ipv4Addr, SocketAddr};
use std::path::Path;
use std::sync::{mpsc, Arc, Mutex};
use tokio::sync::oneshot;

/// The page, its script and its style, assembled into one response.
const PAGE_HTML: &str = include_str!("page/index.html");
const PAGE_GEOMETRY_JS: &str = include_str!("page/geometry.js");
const PAGE_PRISMS_JS: &str = include_str!("page/prisms.js");
const PAGE_JS: &str = include_str!("page/editor.js");
const PAGE_CSS: &str = include_str!("page/editor.css");

/// How `ecles edit` serves.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EditorOptions {
    /// Port on 127.0.0.1 (0: any free port).
    pub port: u16,
    /// Require a random token in every request (off only for scripted use).
    pub token: bool,
    /// Keep an autosave of the session beside the run file (see [`autosave_path`]) and offer
    /// to resume one found at start.
    pub autosave: bool,
}

/// What the handlers share: the way to the session and what requests must carry.
struct Shared {
    commands: Mutex<mpsc::Sender<actor::Command>>,
    token: Option<String>,
    port: u16,
    /// The largest file the page may load (the limit of every input of the run).
    input_limit: u64,
}

/// A random token from the operating system's generator (128 bits, hex).
fn fresh_token() -> Result<String, RunError> {
    let mut bytes = [0u8; 16];
    let mut file = std::fs::File::open("/dev/urandom")
        .map_err(|e| RunError::environment(format!("cannot read /dev/urandom: {e}")))?;
    std::io::Read::read_exact(&mut file, &mut bytes)
        .map_err(|e| RunError::environment(format!("cannot read /dev/urandom: {e}")))?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

/// Builds the session of `run`, binds the port and serves until the process ends; `ready`
/// receives the page's URL (with the token) once the server accepts connections. Bad input
/// (the run file, its sources, its edits and outputs) is reported before anything is served.
pub fn serve(
    run: &Path,
    max_input_bytes: u64,
    options: &EditorOptions,
    ready: impl FnOnce(&str),
) -> Result<(), RunError> {
    let (commands, inbox) = mpsc::channel();
    let (built, build_result) = mpsc::channel();
    let run_path = run.to_path_buf();
    let autosave = options.autosave;
    std::thread::Builder::new()
        .name("ecles-session".into())
        .spawn(move || match actor::build(&run_path, max_input_bytes) {
            Ok(session) => {
                let _ = built.send(Ok(()));
                actor::Editor::new(session, autosave, max_input_bytes).run(inbox);
            }
            Err(e) => {
                let _ = built.send(Err(e));
            }
        })
        .map_err(|e| RunError::environment(format!("cannot start the session thread: {e}")))?;
    build_result
        .recv()
        .map_err(|_| RunError::environment("the session thread ended while building"))??;

    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_io()
        .enable_time()
        .build()
        .map_err(|e| RunError::environment(format!("cannot start the server: {e}")))?;
    runtime.block_on(async move {
        let listener =
            tokio::net::TcpListener::bind(SocketAddr::from((Ipv4Addr::LOCALHOST, options.port)))
                .await
                .map_err(|e| {
                    RunError::environment(format!(
                        "cannot listen on 127.0.0.1:{}: {e}",
                        options.port
                    ))
                })?;
        let port = listener
            .local_addr()
            .map_err(|e| RunError::environment(format!("no local address: {e}")))?
            .port();
        let token = if options.token {
            Some(fresh_token()?)
        } else {
            None
        };
        let url = match &token {
            Some(t) => format!("http://127.0.0.1:{port}/?token={t}"),
            None => format!("http://127.0.0.1:{port}/"),
        };
        let shared = Arc::new(Shared {
            commands: Mutex::new(commands),
            token,
            port,
            input_limit: max_input_bytes,
        });
        let app = router(shared);
        ready(&url);
        axum::serve(listener, app)
            .await
            .map_err(|e| RunError::environment(format!("the server stopped: {e}")))
    })
}

fn router(shared: Arc<Shared>) -> Router {
    Router::new()
        .route("/", get(page))
        .route("/api/state", get(state))
        .route("/api/drag", post(drag))
        .route("/api/frames", get(frames))
        .route("/api/undo", post(undo))
        .route("/api/redo", post(redo))
        .route("/api/save", post(save_session))
        .route("/api/resume", post(resume))
        .route("/api/select", post(select))
        .route("/api/explain", post(explain))
        .route("/api/image", get(target_image))
        .route("/api/continuity", post(continuity))
        .route(
            "/api/load",
            post(load).layer(DefaultBodyLimit::max(
                usize::try_from(shared.input_limit).unwrap_or(usize::MAX),
            )),
        )
        .layer(middleware::from_fn_with_state(shared.clone(), guard))
        .with_state(shared)
}

/// Refuses requests sent to another host name, from another origin, or without the token.
async fn guard(State(shared): State<Arc<Shared>>, request: Request, next: Next) -> Response {
    let headers = request.headers();
    let port = shared.port;
    let host_ok = headers
        .get(header::HOST)
        .and_then(|h| h.to_str().ok())
        .is_some_and(|h| h == format!("127.0.0.1:{port}") || h == format!("localhost:{port}"));
    if !host_ok {
        return (StatusCode::FORBIDDEN, "wrong Host").into_response();
    }
    let origin_ok = headers
        .get(header::ORIGIN)
        .and_then(|o| o.to_str().ok())
        .is_none_or(|o| {
            o == format!("http://127.0.0.1:{port}") || o == format!("http://localhost:{port}")
        });
    if !origin_ok {
        return (StatusCode::FORBIDDEN, "wrong Origin").into_response();
    }
    if let Some(token) = &shared.token {
        let in_header = headers
            .get("x-ecles-token")
            .and_then(|t| t.to_str().ok())
            .is_some_and(|t| t == token);
        let in_query = request
            .uri()
            .query()
            .is_some_and(|q| q.split('&').any(|kv| kv == format!("token={token}")));
        if !(in_header || in_query) {
            return (StatusCode::UNAUTHORIZED, "missing or wrong token").into_response();
        }
    }
    next.run(request).await
}

async fn page() -> impl IntoResponse {
    let html = PAGE_HTML.replace("/*STYLE*/", PAGE_CSS).replace(
        "/*SCRIPT*/",
        &format!("{PAGE_GEOMETRY_JS}\n{PAGE_PRISMS_JS}\n{PAGE_JS}"),
    );
    let mut headers = HeaderMap::new();
    headers.insert(
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static(
            "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; \
             connect-src 'self'; img-src 'self' data: blob:",
        ),
    );
    (headers, Html(html))
}

/// Sends a command to the session and waits for its answer.
async fn ask<T>(
    shared: &Shared,
    command: impl FnOnce(oneshot::Sender<T>) -> actor::Command,
) -> Result<T, Response> {
    let (reply, answer) = oneshot::channel();
    let sent = shared
        .commands
        .lock()
        .map_err(|_| unavailable())?
        .send(command(reply));
    sent.map_err(|_| unavailable())?;
    answer.await.map_err(|_| unavailable())
}

fn unavailable() -> Response {
    (StatusCode::SERVICE_UNAVAILABLE, "the session has ended").into_response()
}

async fn state(State(shared): State<Arc<Shared>>) -> Response {
    match ask(&shared, actor::Command::State).await {
        Ok(state) => Json(state).into_response(),
        Err(response) => response,
    }
}

async fn drag(State(shared): State<Arc<Shared>>, Json(request): Json<DragRequest>) -> Response {
    match ask(&shared, |reply| actor::Command::Drag(request, reply)).await {
        Ok(Ok(answer)) => Json(answer).into_response(),
        Ok(Err(message)) => (
            StatusCode::BAD_REQUEST,
            Json(serde_json::json!({ "error": message })),
        )
            .into_response(),
        Err(response) => response,
    }
}

/// Drag frames over a WebSocket: each text message is a [`DragRequest`], answered in order
/// with the answer `/api/drag` gives (a bad request: `{"error": message}`). One connection
/// carries a whole drag without a request's overhead per frame.
async fn frames(State(shared): State<Arc<Shared>>, upgrade: WebSocketUpgrade) -> Response {
    upgrade
        .max_message_size(MAX_FRAME_MESSAGE)
        .max_frame_size(MAX_FRAME_MESSAGE)
        .on_upgrade(move |socket| drag_frames(shared, socket))
}

/// The largest message a frame socket takes: a drag request of 1 000 anchors is far below.
const MAX_FRAME_MESSAGE: usize = 256 * 1024;

async fn drag_frames(shared: Arc<Shared>, mut socket: WebSocket) {
    while let Some(Ok(message)) = socket.recv().await {
        let text = match message {
            Message::Text(text) => text,
            Message::Close(_) => break,
            _ => continue,
        };
        let answer = match serde_json::from_str::<DragRequest>(text.as_str()) {
            Ok(request) => match ask(&shared, |reply| actor::Command::Drag(request, reply)).await {
                Ok(Ok(answer)) => answer,
                Ok(Err(message)) => serde_json::json!({ "error": message }),
                Err(_) => break,
            },
            Err(e) => serde_json::json!({ "error": format!("not a drag request: {e}") }),
        };
        if socket
            .send(Message::Text(answer.to_string().into()))
            .await
            .is_err()
        {
            break;
        }
    }
}

async fn history(shared: Arc<Shared>, undo: bool) -> Response {
    match ask(&shared, |reply| actor::Command::History(undo, reply)).await {
        Ok(state) => Json::<Value>(state).into_response(),
        Err(response) => response,
    }
}

async fn undo(State(shared): State<Arc<Shared>>) -> Response {
    history(shared, true).await
}

async fn redo(State(shared): State<Arc<Shared>>) -> Response {
    history(shared, false).await
}

/// What `/api/save` takes: the file name (`null`: the default, see [`default_save_name`]).
#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SaveRequest {
    name: Option<String>,
}

/// What `/api/resume` takes: resume the autosave offered, or decline it.
#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ResumeRequest {
    resume: bool,
}

/// An answer that may be refused: 200 with the answer, or 422 with the message.
fn answered(answer: Result<Result<Value, String>, Response>) -> Response {
    match answer {
        Ok(Ok(value)) => Json(value).into_response(),
        Ok(Err(message)) => (
            StatusCode::UNPROCESSABLE_ENTITY,
            Json(serde_json::json!({ "error": message })),
        )
            .into_response(),
        Err(response) => response,
    }
}

async fn save_session(
    State(shared): State<Arc<Shared>>,
    Json(request): Json<SaveRequest>,
) -> Response {
    answered(ask(&shared, |reply| actor::Command::Save(request.name, reply)).await)
}

async fn resume(State(shared): State<Arc<Shared>>, Json(request): Json<ResumeRequest>) -> Response {
    answered(
        ask(&shared, |reply| {
            actor::Command::Resume(request.resume, reply)
        })
        .await,
    )
}

async fn select(State(shared): State<Arc<Shared>>, Json(selection): Json<Selection>) -> Response {
    answered(ask(&shared, |reply| actor::Command::Select(selection, reply)).await)
}

async fn explain(
    State(shared): State<Arc<Shared>>,
    Json(request): Json<actor::ExplainRequest>,
) -> Response {
    answered(ask(&shared, |reply| actor::Command::Explain(request, reply)).await)
}

async fn continuity(
    State(shared): State<Arc<Shared>>,
    Json(request): Json<actor::ContinuityRequest>,
) -> Response {
    answered(ask(&shared, |reply| actor::Command::Continuity(request, reply)).await)
}

/// The query of `/api/load`: which source, what the file replaces, the file's name. The body
/// is the file's bytes, at most the run's input limit.
#[derive(Debug, serde::Deserialize)]
struct LoadQuery {
    source: String,
    kind: actor::LoadKind,
    name: String,
}

async fn load(
    State(shared): State<Arc<Shared>>,
    Query(query): Query<LoadQuery>,
    bytes: Bytes,
) -> Response {
    let request = actor::LoadRequest {
        source: query.source,
        kind: query.kind,
        name: query.name,
        bytes: bytes.to_vec(),
    };
    answered(ask(&shared, |reply| actor::Command::Load(request, reply)).await)
}

/// The run file's target image (404 when it names none).
async fn target_image(State(shared): State<Arc<Shared>>) -> Response {
    match ask(&shared, actor::Command::Image).await {
        Ok(Some((bytes, media_type))) => (
            [(header::CONTENT_TYPE, HeaderValue::from_static(media_type))],
            bytes,
        )
            .into_response(),
        Ok(None) => (StatusCode::NOT_FOUND, "the run file names no target image").into_response(),
        Err(response) => response,
    }
}
