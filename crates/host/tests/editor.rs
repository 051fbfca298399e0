//! The editor's server through real HTTP on 127.0.0.1: who may talk to it, and a drag that
//! commits exact values (every row holding), refusals that change nothing, undo and redo.

mod common;

use common::{call, exact, request, start, state};
use serde_json::json;

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
    let drag = json!({"source": "worm", "anchors": ["v3"], "neighborhood": 3, "dx": "0", "dy": "1", "commit": true});
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
    let frame = |dy: &str, commit: bool| json!({"source": "worm", "anchors": ["v3"], "neighborhood": 3, "dx": "0", "dy": dy, "commit": commit});
    let (status, first) = call(&editor, "POST", "/api/drag", &frame("1.25", false));
    assert_eq!(status, 200, "{first}");
    assert_eq!(
        (first["ok"].clone(), first["initialized"].clone()),
        (json!(true), json!(true))
    );
    assert!(first["derived"].as_u64().expect("|D|") > 0);
    let (_, second) = call(&editor, "POST", "/api/drag", &frame("2.5", false));
    assert_eq!(second["initialized"], false, "{second}");
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
        &json!({"source": "worm", "anchors": ["v99"], "neighborhood": 3, "dx": "1", "dy": "0", "commit": true}),
    );
    assert_eq!(status, 200);
    assert_eq!(refused["ok"], false, "{refused}");
    assert!(
        refused["conflict"]
            .as_str()
            .is_some_and(|c| c.contains("v99")),
        "{refused}"
    );
    for (bad, why) in [
        (
            json!({"source": "nope", "anchors": ["v3"], "neighborhood": 3, "dx": "0", "dy": "1", "commit": true}),
            "unknown source",
        ),
        (
            json!({"source": "worm", "anchors": ["v3\"]"], "neighborhood": 3, "dx": "0", "dy": "1", "commit": true}),
            "not a control point name",
        ),
        (
            json!({"source": "worm", "anchors": ["v3"], "neighborhood": 3, "dx": "0.1x", "dy": "1", "commit": true}),
            "dx",
        ),
        (
            json!({"source": "worm", "anchors": ["v3"], "neighborhood": 3, "dx": "0", "dy": "1".repeat(65), "commit": true}),
            "dy has 65 characters",
        ),
        (
            json!({"source": "worm", "anchors": [], "neighborhood": 3, "dx": "0", "dy": "1", "commit": true}),
            "between 1 and",
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
