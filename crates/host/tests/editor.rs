//! The editor's server through real HTTP on 127.0.0.1: who may talk to it, a drag that
//! commits exact values (every row holding), refusals that change nothing, undo and redo,
//! saving, the autosave and resuming it.

mod common;

use common::{
    build_align_plugin, call, commit_drag, exact, request, start, start_at, state, worm_copy,
};
use serde_json::{json, Value};

#[test]
fn only_this_origin_with_the_token_may_talk_to_the_editor() {
    let editor = start("worm.ron");
    let host = format!("Host: 127.0.0.1:{}", editor.port);
    let token = format!("x-ecles-token: {}", editor.token);
    // Without the token, with a wrong one, from another host name, from another origin.
    assert_eq!(
        request(
            &editor,
            "GET",
            "/api/state",
            std::slice::from_ref(&host),
            ""
        )
        .0,
        401
    );
    let wrong = "x-ecles-token: 0123".to_string();
    assert_eq!(
        request(&editor, "GET", "/api/state", &[host.clone(), wrong], "").0,
        401
    );
    let rebound = format!("Host: attacker.example:{}", editor.port);
    assert_eq!(
        request(&editor, "GET", "/api/state", &[rebound, token.clone()], "").0,
        403
    );
    let origin = "Origin: http://attacker.example".to_string();
    let drag = json!({"selection": {"source": "worm", "anchors": ["v3"], "neighborhood": 3}, "motion": {"translate": {"dx": "0", "dy": "1"}}, "commit": true});
    let (status, _) = request(
        &editor,
        "POST",
        "/api/drag",
        &[host.clone(), token.clone(), origin],
        &drag.to_string(),
    );
    assert_eq!(status, 403);
    // The page itself, with the token in its URL: script and style inlined, nothing fetched
    // from elsewhere.
    let (status, page) = request(
        &editor,
        "GET",
        &format!("/?token={}", editor.token),
        &[host],
        "",
    );
    assert_eq!(status, 200);
    assert!(page.contains("<canvas id=\"view\">") && page.contains("multiIndices"));
    assert!(
        !page.contains("/*SCRIPT*/") && !page.contains("http://") && !page.contains("https://")
    );
    // Nothing above changed the state.
    assert_eq!(state(&editor)["can_undo"], false);
}

#[test]
fn a_drag_commits_exact_values_and_undo_and_redo_restore_them() {
    let editor = start("worm.ron");
    let before = state(&editor);
    assert_eq!(before["violated_rows"], 0);
    let view = &before["sources"][0]["view"];
    assert_eq!(view["kind"], "bezier_triangles");
    assert_eq!(view["degree"], 5);
    assert_eq!(exact(&before, "worm.v3"), ["36", "17"]);
    // Frames of one drag: the edit is initialised once, then updated.
    let frame = |dy: &str, commit: bool| json!({"selection": {"source": "worm", "anchors": ["v3"], "neighborhood": 3}, "motion": {"translate": {"dx": "0", "dy": dy}}, "commit": commit});
    let (status, first) = call(&editor, "POST", "/api/drag", &frame("1.25", false));
    assert_eq!(status, 200, "{first}");
    assert_eq!(
        (first["ok"].clone(), first["initialized"].clone()),
        (json!(true), json!(true))
    );
    assert!(first["derived"].as_u64().expect("|D|") > 0);
    let (_, second) = call(&editor, "POST", "/api/drag", &frame("2.5", false));
    assert_eq!(second["initialized"], false, "{second}");
    // A translation is planned once: later frames' steps are affine in the displacement. The
    // run file names no commit policy: the editor commits snapped points, and its frames are
    // snapped on the same grid.
    assert!(
        second["planned"]
            .as_str()
            .is_some_and(|p| p.starts_with("once")),
        "{second}"
    );
    assert_eq!(second["frames"], "snapped 2^-24");
    assert_eq!(before["commit"], "snapped to 2^-24");
    // Frames change nothing on the server.
    assert_eq!(state(&editor)["points"], before["points"]);
    let (_, drawn) = call(&editor, "POST", "/api/drag", &frame("6", false));
    let (_, last) = call(&editor, "POST", "/api/drag", &frame("6", true));
    // A frame draws the commit's exact values, rounded: the same numbers.
    assert_eq!(drawn["moved"], last["moved"]);
    assert_eq!(
        (last["committed"].clone(), last["violated_rows"].clone()),
        (json!(true), json!(0))
    );
    let after = state(&editor);
    // The anchor moved by exactly (0, 6); every row holds exactly.
    assert_eq!(exact(&after, "worm.v3"), ["36", "23"]);
    assert_eq!(after["violated_rows"], 0);
    assert_eq!(after["can_undo"], true);
    // The release carries what the commit changed, as the whole state has it: every moved
    // point with its exact value, the counts, the same views.
    let changes = &last["state"];
    let changed = changes["points"].as_array().expect("points");
    assert_eq!(
        changed.len(),
        last["moved"].as_array().expect("moved").len()
    );
    for point in changed {
        let id = point["id"].as_u64().expect("an id") as usize;
        assert_eq!(point, &after["points"][id], "{point}");
    }
    for key in [
        "can_undo",
        "can_redo",
        "violated_rows",
        "committed",
        "views_version",
        "commit",
    ] {
        assert_eq!(changes[key], after[key], "{key}");
    }
    assert_eq!(changes["views_version"], before["views_version"]);
    let (_, undone) = call(&editor, "POST", "/api/undo", &json!({}));
    assert_eq!(undone["done"], true);
    assert_eq!(undone["points"], before["points"]);
    let (_, redone) = call(&editor, "POST", "/api/redo", &json!({}));
    assert_eq!(redone["points"], after["points"]);
    assert_eq!(redone["can_redo"], false);
}

#[test]
fn refused_moves_and_bad_requests_change_nothing() {
    let editor = start("worm.ron");
    let before = state(&editor);
    // The source refuses a point it does not have: the page shows its message.
    let (status, refused) = call(
        &editor,
        "POST",
        "/api/drag",
        &json!({"selection": {"source": "worm", "anchors": ["v99"], "neighborhood": 3}, "motion": {"translate": {"dx": "1", "dy": "0"}}, "commit": true}),
    );
    assert_eq!(status, 200);
    assert_eq!(refused["ok"], false, "{refused}");
    assert!(
        refused["conflict"]["message"]
            .as_str()
            .is_some_and(|c| c.contains("v99")),
        "{refused}"
    );
    for (bad, why) in [
        (
            json!({"selection": {"source": "nope", "anchors": ["v3"], "neighborhood": 3}, "motion": {"translate": {"dx": "0", "dy": "1"}}, "commit": true}),
            "unknown source",
        ),
        (
            json!({"selection": {"source": "worm", "anchors": ["v3\"]"], "neighborhood": 3}, "motion": {"translate": {"dx": "0", "dy": "1"}}, "commit": true}),
            "not a control point name",
        ),
        (
            json!({"selection": {"source": "worm", "anchors": ["v3"], "neighborhood": 3}, "motion": {"translate": {"dx": "0.1x", "dy": "1"}}, "commit": true}),
            "dx",
        ),
        (
            json!({"selection": {"source": "worm", "anchors": ["v3"], "neighborhood": 3}, "motion": {"translate": {"dx": "0", "dy": "1".repeat(65)}}, "commit": true}),
            "dy has 65 characters",
        ),
        (
            json!({"selection": {"source": "worm", "anchors": [], "neighborhood": 3}, "motion": {"translate": {"dx": "0", "dy": "1"}}, "commit": true}),
            "between 1 and",
        ),
        (
            json!({"selection": {"source": "worm", "anchors": ["v3"], "neighborhood": 3}, "motion": {"translate": {"dx": "0", "dy": "0/5"}}, "commit": true}),
            "moves nothing commits nothing",
        ),
    ] {
        let (status, answer) = call(&editor, "POST", "/api/drag", &bad);
        assert_eq!(status, 400, "{bad}: {answer}");
        assert!(
            answer["error"].as_str().is_some_and(|e| e.contains(why)),
            "{why}: {answer}"
        );
    }
    let (status, _) = call(
        &editor,
        "POST",
        "/api/drag",
        &json!({"source": "worm", "extra": 1}),
    );
    assert_eq!(status, 422);
    assert_eq!(state(&editor), before);
}

/// Save writes the session as a run file and what `ecles run` writes for it; running the saved
/// file again gives the same report, model and values byte for byte, and the editor's exact
/// values. The autosave kept after every change is offered to a new editor, which resumes it
/// to the same values.
#[test]
fn a_saved_session_reruns_exactly_and_the_autosave_resumes() {
    let (dir, run) = worm_copy();
    let editor = start_at(run.clone(), true);
    assert_eq!(state(&editor)["autosave"]["offer"], Value::Null);
    commit_drag(&editor, &["v3"], 3, "0", "6");
    commit_drag(&editor, &["v7"], 4, "-3/7", "2.5");
    commit_drag(&editor, &["v5"], 2, "1", "1");
    let (_, undone) = call(&editor, "POST", "/api/undo", &json!({}));
    assert_eq!(undone["done"], true);
    commit_drag(&editor, &["e0-1:2", "e0-1:3"], 2, "-1", "0.75");
    let edited = state(&editor);
    assert_eq!(edited["committed"], 3);
    let autosave = dir.path().join("worm.autosave.ron");
    let autosaved = std::fs::read_to_string(&autosave).expect("an autosave");
    assert_eq!(
        autosaved.matches("Source(source: \"worm\"").count(),
        3,
        "{autosaved}"
    );

    // Bad names are refused, nothing written.
    for bad in [
        "../x.ron",
        "worm.ron",
        "worm.autosave.ron",
        "x.txt",
        ".x.ron",
    ] {
        let (status, answer) = call(&editor, "POST", "/api/save", &json!({"name": bad}));
        assert_eq!(status, 422, "{bad}: {answer}");
    }
    let (status, saved) = call(&editor, "POST", "/api/save", &json!({"name": null}));
    assert_eq!(status, 200, "{saved}");
    let out = dir.path().join("worm.session.out");
    let values: Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("values.json")).expect("values.json"),
    )
    .expect("json");
    for point in edited["points"].as_array().expect("points") {
        let name = point["name"].as_str().expect("a name");
        let saved_value = values["values"]
            .as_array()
            .expect("values")
            .iter()
            .find(|v| v["name"] == name)
            .expect("every parameter saved");
        assert_eq!(saved_value["exact"], point["exact"], "{name}");
    }

    // `ecles run` on the saved file, elsewhere: the same report, model and picture, byte for
    // byte.
    let again = dir.path().join("again");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_ecles"))
        .args(["run", "--quiet", "--out"])
        .arg(&again)
        .arg(dir.path().join("worm.session.ron"))
        .status()
        .expect("ecles runs");
    assert!(status.success());
    let files: Vec<String> = serde_json::from_value(saved["files"].clone()).expect("files");
    assert_eq!(
        files,
        ["worm-model-deformed.obj", "worm.svg", "values.json"]
    );
    for file in ["report.json", "worm.svg", "worm-model-deformed.obj"] {
        assert_eq!(
            std::fs::read(out.join(file)).expect("saved"),
            std::fs::read(again.join(file)).expect("run again"),
            "{file}"
        );
    }

    // A new editor on the run finds the autosave, resumes it and has the same values.
    let second = start_at(run, true);
    let offered = state(&second);
    assert_eq!(offered["autosave"]["offer"]["edits"], 3, "{offered}");
    let (status, resumed) = call(&second, "POST", "/api/resume", &json!({"resume": true}));
    assert_eq!(status, 200, "{resumed}");
    assert_eq!(resumed["resumed"], 3);
    assert_eq!(resumed["points"], edited["points"]);
    assert_eq!(resumed["autosave"]["offer"], Value::Null);
    let (status, _) = call(&second, "POST", "/api/resume", &json!({"resume": true}));
    assert_eq!(status, 422, "offered once");
}

/// A pinned point cannot move: the answer names the alignment row in the way and explains the
/// over-determined part; a release there commits nothing.
#[test]
fn a_pinned_point_is_refused_with_the_constraints_in_the_way() {
    build_align_plugin();
    let editor = start("align.ron");
    let before = state(&editor);
    for commit in [false, true] {
        let (status, refused) = call(
            &editor,
            "POST",
            "/api/drag",
            &json!({"selection": {"source": "worm", "anchors": ["v1"], "neighborhood": 3}, "motion": {"translate": {"dx": "2", "dy": "0"}}, "commit": commit}),
        );
        assert_eq!(status, 200, "{refused}");
        assert_eq!(refused["ok"], false, "{refused}");
        let conflict = &refused["conflict"];
        assert_eq!(
            conflict["labels"],
            json!(["align row 5: worm.v1 x = 12"]),
            "{refused}"
        );
        let explanation: Vec<String> =
            serde_json::from_value(conflict["explanation"].clone()).expect("lines");
        assert!(
            explanation
                .iter()
                .any(|l| l.starts_with("structurally over-determined")
                    && l.contains("worm row 1: C1 edge 1-2")),
            "{explanation:?}"
        );
    }
    let after = state(&editor);
    assert_eq!(after["points"], before["points"]);
    assert_eq!(after["can_undo"], false);
}

/// Rotations and scalings about a centre are exact; the derived set of a selection is known
/// before a drag and grows with δ_max; the state carries the constraints on the control
/// points (the C1 quadrilaterals) and a drag the relevant rows it keeps.
#[test]
fn rotations_scalings_and_the_derived_set_before_a_drag() {
    let editor = start("worm.ron");
    let before = state(&editor);
    let c1: Vec<&Value> = before["constraints"]
        .as_array()
        .expect("constraints")
        .iter()
        .filter(|c| c["label"].as_str().is_some_and(|l| l.contains("C1")))
        .collect();
    assert!(!c1.is_empty());
    assert!(c1
        .iter()
        .all(|c| c["points"].as_array().map(Vec::len) == Some(4)));
    let derived = |neighborhood: u32| {
        let (status, selected) = call(
            &editor,
            "POST",
            "/api/select",
            &json!({"source": "worm", "anchors": ["v3"], "neighborhood": neighborhood}),
        );
        assert_eq!(status, 200, "{selected}");
        assert_eq!(selected["anchors"].as_array().map(Vec::len), Some(1));
        selected["derived"]
            .as_array()
            .map(Vec::len)
            .expect("derived")
    };
    let (near, far) = (derived(1), derived(3));
    assert!(0 < near && near < far, "{near} {far}");

    let int = |text: &str| text.parse::<i64>().expect("an integer coordinate");
    let v7: Vec<i64> = exact(&before, "worm.v7").iter().map(|t| int(t)).collect();
    let (status, rotated) = call(
        &editor,
        "POST",
        "/api/drag",
        &json!({"selection": {"source": "worm", "anchors": ["v7"], "neighborhood": 4},
            "motion": {"rotate": {"center": ["60", "11"], "degrees": "90"}}, "commit": true}),
    );
    assert_eq!(rotated["committed"], true, "{status} {rotated}");
    assert!(rotated["relevant"]
        .as_array()
        .is_some_and(|r| !r.is_empty()));
    // A quarter turn about (60, 11) is exact.
    let turned = [60 - (v7[1] - 11), 11 + (v7[0] - 60)].map(|c| c.to_string());
    assert_eq!(exact(&state(&editor), "worm.v7"), turned);

    let corner = exact(&before, "worm.e0-1:2");
    let (_, scaled) = call(
        &editor,
        "POST",
        "/api/drag",
        &json!({"selection": {"source": "worm", "anchors": ["e0-1:2"], "neighborhood": 2},
            "motion": {"scale": {"center": ["0", "0"], "factor": "1.5"}}, "commit": true}),
    );
    assert_eq!(scaled["committed"], true, "{scaled}");
    let after = state(&editor);
    let times = |t: &str| {
        let r: api::Rational =
            api::parse_rational(t).expect("exact") * api::parse_rational("3/2").expect("exact");
        api::format_rational(&r)
    };
    assert_eq!(
        exact(&after, "worm.e0-1:2"),
        corner.iter().map(|t| times(t)).collect::<Vec<_>>()
    );
    assert_eq!(after["violated_rows"], 0);
}

/// Writes a 4 × 3 grey PNG to `path`.
fn write_png(path: &std::path::Path) {
    let file = std::fs::File::create(path).expect("create");
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), 4, 3);
    encoder.set_color(png::ColorType::Grayscale);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().expect("header");
    writer.write_image_data(&[128; 12]).expect("pixels");
}

/// A target image named in the run file is checked before serving, served to the page with its
/// settings, and kept in a saved session; a file that is not an image stops the editor before
/// it serves, naming the file.
#[test]
fn the_run_files_target_image_is_checked_served_and_saved() {
    let (dir, run) = worm_copy();
    write_png(&dir.path().join("target.png"));
    let text = std::fs::read_to_string(&run).expect("run file");
    let with_image = text.trim_end().trim_end_matches(')').to_string()
        + "    editor: (image: (file: \"target.png\", opacity: \"0.25\", position: (\"-10\", \"40\"), units_per_pixel: \"1/2\")),\n)\n";
    std::fs::write(&run, &with_image).expect("write");
    let editor = start_at(run.clone(), false);
    let image = state(&editor)["image"].clone();
    assert_eq!(
        image,
        json!({"file": "target.png", "opacity": 0.25, "x": -10.0, "y": 40.0,
            "units_per_pixel": 0.5, "size": [4, 3]})
    );
    let headers = [
        format!("Host: 127.0.0.1:{}", editor.port),
        format!("x-ecles-token: {}", editor.token),
    ];
    let (status, body) = common::request(&editor, "GET", "/api/image", &headers, "");
    assert_eq!(status, 200);
    assert!(
        body.starts_with("\u{fffd}PNG") || body.contains("PNG"),
        "{body:?}"
    );
    commit_drag(&editor, &["v3"], 3, "0", "2");
    let (status, saved) = call(&editor, "POST", "/api/save", &json!({"name": null}));
    assert_eq!(status, 200, "{saved}");
    let session = std::fs::read_to_string(dir.path().join("worm.session.ron")).expect("saved");
    assert!(
        session.contains("editor: (image: (file: \"target.png\""),
        "{session}"
    );

    // Not an image: refused before serving, the file named.
    std::fs::write(dir.path().join("target.png"), "not a picture").expect("write");
    let options = host::editor::EditorOptions {
        port: 0,
        token: true,
        autosave: false,
    };
    let error = host::editor::serve(&run, api::input::DEFAULT_MAX_INPUT_BYTES, &options, |_| {
        panic!("served a run whose image is not one")
    })
    .expect_err("refused");
    assert!(
        error
            .to_string()
            .contains("target.png: neither a PNG nor a JPEG"),
        "{error}"
    );
}

/// Frames over the WebSocket: the same answers as `/api/drag`, in order; a message that is
/// not a drag request is answered with an error and the socket stays open; the handshake
/// needs the token and this origin like every request.
#[test]
fn drag_frames_travel_over_a_websocket_with_the_same_guard() {
    use tungstenite::Message;
    let editor = start("worm.ron");
    let connect = |query: &str, origin: &str| {
        let stream = std::net::TcpStream::connect(("127.0.0.1", editor.port)).expect("connects");
        let request = tungstenite::http::Request::builder()
            .uri(format!("ws://127.0.0.1:{}/api/frames{query}", editor.port))
            .header("Host", format!("127.0.0.1:{}", editor.port))
            .header("Origin", origin)
            .header("Connection", "Upgrade")
            .header("Upgrade", "websocket")
            .header("Sec-WebSocket-Version", "13")
            .header(
                "Sec-WebSocket-Key",
                tungstenite::handshake::client::generate_key(),
            )
            .body(())
            .expect("a request");
        // The handshake's error carries the whole response: its text is enough here.
        tungstenite::client(request, stream).map_err(|e| e.to_string())
    };
    let here = format!("http://127.0.0.1:{}", editor.port);
    assert!(connect("", &here).is_err(), "no token, no socket");
    assert!(
        connect(&format!("?token={}", editor.token), "http://evil.example").is_err(),
        "another origin, no socket"
    );
    let (mut socket, _) =
        connect(&format!("?token={}", editor.token), &here).expect("the page's socket");
    let mut ask = |text: String| -> Value {
        socket.send(Message::text(text)).expect("sends");
        loop {
            match socket.read().expect("an answer") {
                Message::Text(answer) => return serde_json::from_str(&answer).expect("JSON"),
                _ => continue,
            }
        }
    };
    let frame = |dy: &str, commit: bool| {
        json!({"selection": {"source": "worm", "anchors": ["v3"], "neighborhood": 3},
            "motion": {"translate": {"dx": "0", "dy": dy}}, "commit": commit})
        .to_string()
    };
    let still = ask(frame("0", false));
    assert_eq!(
        (still["ok"].clone(), still["initialized"].clone()),
        (json!(true), json!(true))
    );
    let moved = ask(frame("3/2", false));
    assert_eq!(moved["initialized"], false, "{moved}");
    let bad = ask("{\"selection\": 1}".into());
    assert!(
        bad["error"]
            .as_str()
            .is_some_and(|e| e.contains("not a drag request")),
        "{bad}"
    );
    let committed = ask(frame("3/2", true));
    assert_eq!(committed["committed"], true, "{committed}");
    assert_eq!(exact(&state(&editor), "worm.v3"), ["36", "37/2"]);
}

/// A file loaded from the page, as the page sends it: the bytes as the body, what it replaces
/// in the query.
fn load(editor: &common::Editor, kind: &str, name: &str, bytes: &str) -> (u16, Value) {
    let headers = [
        format!("Host: 127.0.0.1:{}", editor.port),
        format!("x-ecles-token: {}", editor.token),
    ];
    let path = format!("/api/load?source=worm&kind={kind}&name={name}");
    let (status, answer) = common::request(editor, "POST", &path, &headers, bytes);
    (
        status,
        serde_json::from_str(&answer).unwrap_or(Value::String(answer)),
    )
}

/// The continuity switch (C1 → C0 keeps the deformation, C0 → C1 projects it onto the nearest
/// smooth one), a bad reference mesh refused with its line and column and nothing kept, a
/// model and a mesh loaded from the page: each a step of the session that undo takes back,
/// and the saved session repeats all of it exactly.
#[test]
fn continuity_and_files_loaded_from_the_page_are_steps_of_the_session() {
    let (dir, run) = worm_copy();
    let editor = start_at(run, true);
    commit_drag(&editor, &["v3"], 3, "0", "6");
    let smooth = state(&editor);
    let c1_rows = smooth["rows"].as_u64().expect("rows");
    assert!(c1_rows > 0);

    let (status, c0) = call(
        &editor,
        "POST",
        "/api/continuity",
        &json!({"source": "worm", "smoothness": 0}),
    );
    assert_eq!(status, 200, "{c0}");
    assert_eq!(c0["sources"][0]["view"]["smoothness"], 0);
    assert_eq!(
        (c0["rows"].as_u64(), c0["committed"].as_u64()),
        (Some(0), Some(2))
    );
    assert_eq!(c0["configured"]["projected"], 0);
    assert_eq!(
        c0["points"], smooth["points"],
        "a C1 deformation is a C0 one"
    );

    // Under C0 a control point moves alone; back to C1, the nearest smooth deformation.
    commit_drag(&editor, &["v5"], 0, "3", "0");
    let rough = state(&editor);
    assert_eq!(rough["violated_rows"], 0, "C0 has no rows to break");
    let (status, c1) = call(
        &editor,
        "POST",
        "/api/continuity",
        &json!({"source": "worm", "smoothness": 1}),
    );
    assert_eq!(status, 200, "{c1}");
    assert!(
        c1["configured"]["projected"].as_u64() > Some(0),
        "{}",
        c1["configured"]
    );
    assert_eq!(
        (c1["rows"].as_u64(), c1["violated_rows"].as_u64()),
        (Some(c1_rows), Some(0))
    );
    let (status, refused) = call(
        &editor,
        "POST",
        "/api/continuity",
        &json!({"source": "worm", "smoothness": 5}),
    );
    assert_eq!(status, 422, "{refused}");
    assert!(
        refused["error"].as_str().is_some_and(|e| e.contains("C^5")),
        "{refused}"
    );

    // A bad mesh: the reader's line and column, nothing kept, nothing changed.
    let (status, bad) = load(&editor, "mesh", "bad.obj", "v 0 0 0\nv 9 0 0\nf 1 2 q\n");
    assert_eq!(status, 422, "{bad}");
    let message = bad["error"].as_str().expect("a message");
    assert!(message.contains("bad.obj:3:"), "{message}");
    assert!(!dir.path().join("worm.inputs").exists(), "nothing kept");
    assert_eq!(state(&editor)["points"], c1["points"]);

    // A model: kept beside the run file, drawn by the view, named by the saved session.
    let (status, model) = load(
        &editor,
        "model",
        "tri.obj",
        "v 10 10\nv 20 10\nv 10 20\nf 1 2 3\n",
    );
    assert_eq!(status, 200, "{model}");
    assert_eq!(model["loaded"], "worm.inputs/tri.obj");
    let models = &model["sources"][0]["view"]["models"];
    assert_eq!(models.as_array().map(Vec::len), Some(1), "{models}");
    assert_eq!(model["points"], c1["points"], "a model changes no value");
    let (status, saved) = call(&editor, "POST", "/api/save", &json!({"name": "mixed.ron"}));
    assert_eq!(status, 200, "{saved}");
    let text = std::fs::read_to_string(dir.path().join("mixed.ron")).expect("saved");
    assert_eq!(
        text.matches("Configure(source: \"worm\"").count(),
        2,
        "{text}"
    );
    assert!(text.contains("model: \"worm.inputs/tri.obj\""), "{text}");
    let again = dir.path().join("again");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_ecles"))
        .args(["run", "--quiet", "--out"])
        .arg(&again)
        .arg(dir.path().join("mixed.ron"))
        .status()
        .expect("ecles runs");
    assert!(status.success());
    assert!(again.join("tri-deformed.obj").exists());

    // Another reference mesh (the worm's own, under another name: every control point is the
    // same, so the deformation is kept); undo takes it back.
    let worm_mesh = std::fs::read_to_string(dir.path().join("meshes/worm.obj")).expect("mesh");
    let (status, mesh) = load(&editor, "mesh", "worm-copy.obj", &worm_mesh);
    assert_eq!(status, 200, "{mesh}");
    assert_eq!(mesh["configured"]["restarted"], 0, "{}", mesh["configured"]);
    assert_eq!(mesh["configured"]["projected"], 0);
    assert_eq!(mesh["points"], c1["points"]);
    assert_eq!(mesh["committed"], 5);
    let (_, undone) = call(&editor, "POST", "/api/undo", &json!({}));
    assert_eq!(undone["committed"], 4);
    let (_, undone) = call(&editor, "POST", "/api/undo", &json!({}));
    assert_eq!(undone["sources"][0]["view"]["smoothness"], 0);
    assert_eq!(undone["rows"], 0);
    assert_eq!(undone["points"], rough["points"]);
    assert_ne!(rough["points"], c1["points"]);
}

/// Drag frames of a translation until an answer carries the motion response; the response.
fn motion_response(editor: &common::Editor, frame: &dyn Fn(&str, &str, bool) -> Value) -> Value {
    let (status, first) = call(editor, "POST", "/api/drag", &frame("0", "0", false));
    assert_eq!(status, 200, "{first}");
    for n in 1..200 {
        let (status, answer) = call(
            editor,
            "POST",
            "/api/drag",
            &frame("0", &format!("{n}/64"), false),
        );
        assert_eq!(status, 200, "{answer}");
        if !answer["affine"].is_null() {
            return answer["affine"].clone();
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    panic!("no motion response");
}

/// A translation's motion response is the exact optimum's affine form: the page's frame at
/// any displacement, `base + dx·along_x + dy·along_y`, is the committed exact value there (to
/// rounding) — with optimum frames, and with snapped ones within the response's bound.
#[test]
fn a_translations_motion_response_predicts_the_committed_values() {
    // The editor's default (snapped commits, the run file says nothing) and the exact optimum.
    for snapped in [true, false] {
        let (dir, run) = worm_copy();
        if !snapped {
            let text = std::fs::read_to_string(&run).expect("run file");
            std::fs::write(
                &run,
                text.replacen("edits:", "commit: Optimum,\n    edits:", 1),
            )
            .expect("write");
        }
        let editor = start_at(run, false);
        let expected = if snapped {
            "snapped to 2^-24"
        } else {
            "the exact optimum"
        };
        assert_eq!(state(&editor)["commit"], expected);
        let frame = |dx: &str, dy: &str, commit: bool| json!({"selection": {"source": "worm", "anchors": ["v3"], "neighborhood": 3}, "motion": {"translate": {"dx": dx, "dy": dy}}, "commit": commit});
        let response = motion_response(&editor, &frame);
        let ids: Vec<u64> = serde_json::from_value(response["ids"].clone()).expect("ids");
        let base: Vec<f64> = serde_json::from_value(response["base"].clone()).expect("base");
        let along: Vec<Vec<f64>> =
            serde_json::from_value(response["along"].clone()).expect("along");
        let bound = response["bound"].as_f64().expect("a bound");
        assert_eq!((response["dim"].as_u64(), along.len()), (Some(2), 2));
        assert_eq!((base.len(), along[0].len()), (2 * ids.len(), 2 * ids.len()));
        assert!(ids.len() > 1, "the anchor and its derived points");
        // Optimum frames give the exact response; a drag whose Initialize or frames were slow
        // (a busy machine) switches to snapped frames, whose response is within its bound.
        let snapped_frames = response["frames"] != "optimum";
        if snapped {
            assert_eq!(response["frames"], "snapped 2^-24");
        }
        assert!(
            if snapped_frames {
                bound < 1e-9
            } else {
                bound == 0.0
            },
            "{bound} from {} frames",
            response["frames"]
        );

        let (status, committed) = call(&editor, "POST", "/api/drag", &frame("-5/8", "9/4", true));
        assert_eq!(status, 200, "{committed}");
        let after = state(&editor);
        // A snapped commit is itself within its grid of the optimum.
        let tolerance = if snapped || snapped_frames {
            1e-6
        } else {
            1e-12
        };
        for (i, id) in ids.iter().enumerate() {
            let point = &after["points"][*id as usize];
            assert_eq!(point["id"].as_u64(), Some(*id));
            for k in 0..2 {
                let exact = api::parse_rational(point["exact"][k].as_str().expect("exact"))
                    .expect("a rational");
                let exact = api::exact::rational_to_f64(&exact);
                let predicted =
                    base[2 * i + k] - 0.625 * along[0][2 * i + k] + 2.25 * along[1][2 * i + k];
                assert!(
                    (predicted - exact).abs() <= tolerance * exact.abs().max(1.0),
                    "{} [{k}]: predicted {predicted}, committed {exact}",
                    point["name"]
                );
            }
        }
        drop(dir);
    }
}

/// The page's Explain: how a change of the selected points propagates, in words and as JSON,
/// with a move if given; a point that does not exist is refused. Nothing changes.
#[test]
fn explain_says_how_the_selected_points_can_move() {
    let editor = start("worm.ron");
    let before = state(&editor);
    let id = |name: &str| {
        before["points"]
            .as_array()
            .expect("points")
            .iter()
            .find(|p| p["name"] == name)
            .and_then(|p| p["id"].as_u64())
            .expect("a point")
    };
    let (status, answer) = call(
        &editor,
        "POST",
        "/api/explain",
        &json!({"ids": [id("worm.v3")]}),
    );
    assert_eq!(status, 200, "{answer}");
    assert_eq!(answer["analysis"]["case"], "free");
    let lines: Vec<&str> = answer["lines"]
        .as_array()
        .expect("lines")
        .iter()
        .map(|l| l.as_str().expect("text"))
        .collect();
    assert!(lines[1].contains("worm.v3: free"), "{lines:?}");
    let (status, moved) = call(
        &editor,
        "POST",
        "/api/explain",
        &json!({"ids": [id("worm.v3")], "move": ["1", "-1/2"]}),
    );
    assert_eq!(status, 200, "{moved}");
    assert!(moved["analysis"]["move"]["moves"].is_array(), "{moved}");
    let (status, refused) = call(&editor, "POST", "/api/explain", &json!({"ids": [999999]}));
    assert_eq!(status, 422, "{refused}");
    assert_eq!(state(&editor)["points"], before["points"]);
}

/// The page's change criterion (Brenner 3.1): frames and the release of a drag under
/// "Fewest" are exact Updates under it (no motion response), the commit holds every row
/// exactly and changes only the points the criterion names, and the saved session states the
/// criterion, so `ecles run` reproduces the values.
#[test]
fn a_drag_under_another_criterion_commits_its_exact_choice() {
    let (dir, run) = worm_copy();
    let editor = start_at(run, true);
    let before = state(&editor);
    let frame = |dy: &str, commit: bool| json!({"selection": {"source": "worm", "anchors": ["v3"], "neighborhood": 2}, "motion": {"translate": {"dx": "0", "dy": dy}}, "commit": commit, "criterion": "Fewest"});
    for n in 0..8 {
        let (status, answer) = call(
            &editor,
            "POST",
            "/api/drag",
            &frame(&format!("{n}/4"), false),
        );
        assert_eq!(status, 200, "{answer}");
        assert_eq!(answer["ok"], true, "{answer}");
        assert!(
            answer["affine"].is_null(),
            "no motion response under Fewest"
        );
        if n > 0 {
            assert_eq!(answer["criterion"]["measure"], "Fewest", "{answer}");
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let (status, released) = call(&editor, "POST", "/api/drag", &frame("3/2", true));
    assert_eq!(status, 200, "{released}");
    assert_eq!(released["committed"], true, "{released}");
    let chosen = &released["criterion"];
    assert_eq!(chosen["proven_minimal"], true, "{chosen}");
    let after = state(&editor);
    assert_eq!(after["violated_rows"], 0);
    let moved: Vec<&str> = after["points"]
        .as_array()
        .expect("points")
        .iter()
        .zip(before["points"].as_array().expect("points"))
        .filter(|(a, b)| a["exact"] != b["exact"])
        .map(|(a, _)| a["name"].as_str().expect("name"))
        .collect();
    // The anchor and exactly the derived points the criterion changed.
    assert_eq!(
        moved.len() as u64,
        chosen["changed"].as_array().expect("changed").len() as u64 + 1
    );
    assert!(moved.contains(&"worm.v3"), "{moved:?}");
    for name in chosen["changed"].as_array().expect("changed") {
        assert!(
            moved.contains(&name.as_str().expect("a name")),
            "{name} {moved:?}"
        );
    }
    let autosave =
        std::fs::read_to_string(dir.path().join("worm.autosave.ron")).expect("an autosave");
    assert!(autosave.contains("criterion: Fewest"), "{autosave}");
    // `ecles run` on the autosaved session gives the committed values.
    let out = dir.path().join("again");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_ecles"))
        .args(["run", "--quiet", "--out"])
        .arg(&out)
        .arg(dir.path().join("worm.autosave.ron"))
        .status()
        .expect("ecles runs");
    assert!(status.success());
    let report: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).expect("report"))
            .expect("json");
    let edit = &report["edits"][0];
    assert_eq!(edit["criterion"]["measure"], "Fewest");
    for value in edit["values"].as_array().expect("values") {
        let point = after["points"]
            .as_array()
            .expect("points")
            .iter()
            .find(|p| p["name"] == value["name"])
            .expect("the point");
        assert_eq!(point["exact"], value["exact"], "{}", value["name"]);
    }
}
