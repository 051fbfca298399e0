//! Helpers of the editor's tests: a served editor and HTTP requests to it.
//!
//! Each test binary uses a part of them.
#![allow(dead_code)]

use host::editor::{serve, EditorOptions};
use serde_json::Value;
use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::PathBuf;
use std::sync::mpsc;

/// A served editor: its port and token.
pub struct Editor {
    pub port: u16,
    pub token: String,
}

pub fn examples() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// Serves `examples/{run}` on a free port, without autosave (the server lives until the test
/// process ends).
pub fn start(run: &str) -> Editor {
    start_at(examples().join(run), false)
}

/// Serves the run file `path` on a free port, with or without autosave.
pub fn start_at(path: PathBuf, autosave: bool) -> Editor {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let options = EditorOptions {
            port: 0,
            token: true,
            autosave,
        };
        let result = serve(
            &path,
            api::input::DEFAULT_MAX_INPUT_BYTES,
            &options,
            |url| {
                let _ = tx.send(url.to_string());
            },
        );
        panic!("the server stopped: {result:?}");
    });
    let url = rx.recv().expect("the editor serves");
    let rest = url.strip_prefix("http://127.0.0.1:").expect("a local URL");
    let (port, token) = rest.split_once("/?token=").expect("a token in the URL");
    Editor {
        port: port.parse().expect("a port"),
        token: token.to_string(),
    }
}

/// One HTTP/1.1 request with the given extra header lines; the status and the body.
pub fn request(
    editor: &Editor,
    method: &str,
    path: &str,
    headers: &[String],
    body: &str,
) -> (u16, String) {
    let mut stream = TcpStream::connect(("127.0.0.1", editor.port)).expect("connects");
    let mut text = format!("{method} {path} HTTP/1.1\r\nConnection: close\r\n");
    for h in headers {
        text.push_str(h);
        text.push_str("\r\n");
    }
    if !body.is_empty() {
        text.push_str("Content-Type: application/json\r\n");
    }
    text.push_str(&format!("Content-Length: {}\r\n\r\n{body}", body.len()));
    stream.write_all(text.as_bytes()).expect("sends");
    let mut bytes = Vec::new();
    stream.read_to_end(&mut bytes).expect("reads");
    // Binary bodies (an image) are compared by their text with replacement characters.
    let answer = String::from_utf8_lossy(&bytes).into_owned();
    let status = answer[9..12].parse().expect("a status code");
    let body = answer
        .split_once("\r\n\r\n")
        .map(|(_, b)| b.to_string())
        .unwrap_or_default();
    (status, body)
}

/// A request as the page sends it: the right host and the token.
pub fn call(editor: &Editor, method: &str, path: &str, body: &Value) -> (u16, Value) {
    let headers = [
        format!("Host: 127.0.0.1:{}", editor.port),
        format!("x-ecles-token: {}", editor.token),
    ];
    let text = if body.is_null() {
        String::new()
    } else {
        body.to_string()
    };
    let (status, answer) = request(editor, method, path, &headers, &text);
    (
        status,
        serde_json::from_str(&answer).unwrap_or(Value::String(answer)),
    )
}

pub fn state(editor: &Editor) -> Value {
    let (status, state) = call(editor, "GET", "/api/state", &Value::Null);
    assert_eq!(status, 200, "{state}");
    state
}

/// The exact value of point `name` in a state.
pub fn exact(state: &Value, name: &str) -> Vec<String> {
    let point = state["points"]
        .as_array()
        .expect("points")
        .iter()
        .find(|p| p["name"] == name)
        .unwrap_or_else(|| panic!("{name} in the state"));
    serde_json::from_value(point["exact"].clone()).expect("exact strings")
}

/// A copy of the worm example (run file, mesh and model) in a fresh directory, where saves and
/// autosaves may be written; the run file's path.
pub fn worm_copy() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("a temporary directory");
    for file in ["worm.ron", "meshes/worm.obj", "models/worm-model.obj"] {
        let target = dir.path().join(file);
        std::fs::create_dir_all(target.parent().expect("a parent")).expect("mkdir");
        std::fs::copy(examples().join(file), &target).expect("copy");
    }
    let run = dir.path().join("worm.ron");
    (dir, run)
}

/// A drag of `anchors` of the worm by (dx, dy), committed; the answer.
pub fn commit_drag(
    editor: &Editor,
    anchors: &[&str],
    neighborhood: u32,
    dx: &str,
    dy: &str,
) -> Value {
    let (status, answer) = call(
        editor,
        "POST",
        "/api/drag",
        &serde_json::json!({"selection": {"source": "worm", "anchors": anchors, "neighborhood": neighborhood},
            "motion": {"translate": {"dx": dx, "dy": dy}}, "commit": true}),
    );
    assert_eq!(status, 200, "{answer}");
    assert_eq!(answer["committed"], true, "{answer}");
    answer
}

/// Builds the `align` plugin library where `examples/align.ron` loads it
/// (`target/release`), once per test binary.
pub fn build_align_plugin() {
    static BUILT: std::sync::OnceLock<()> = std::sync::OnceLock::new();
    BUILT.get_or_init(|| {
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
        let status = std::process::Command::new(cargo)
            .current_dir(&root)
            .args(["build", "--release", "-p", "plugins-align", "--target-dir"])
            .arg(root.join("target"))
            .status()
            .expect("cargo runs");
        assert!(status.success(), "building the align plugin failed");
    });
}
