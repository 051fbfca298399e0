//! The editor in a real headless Chromium, with real mouse events: the page loads the worm,
//! a control point dragged with the mouse commits exact values (every row holding), the
//! picture changes near the point and not far from it, undo from the page restores the exact
//! state, and the page is refused without the token; a pinned point's drag shows the
//! constraints in the way and changes nothing; a rotation about a right-clicked centre is
//! exact; the session saved from the page reruns to the same values and an autosave is resumed
//! from the page's banner; the continuity is switched from the settings and a reference mesh
//! and a model are loaded through the file chooser (a bad one refused with its line and
//! column).
//!
//! Needs Chromium (`$CHROMIUM`, else `/usr/bin/chromium`); `.ci/run` installs it and runs
//! these with `--ignored`.

#[path = "common/cdp.rs"]
mod cdp;
mod common;

use api::parse_rational;
use cdp::Browser;
use common::{build_align_plugin, exact, start, start_at, state, worm_copy};
use std::time::{Duration, Instant};

/// The viewport position of point `name` as the page draws it.
fn screen_position(browser: &mut Browser, name: &str) -> (f64, f64) {
    let at = browser.eval(&format!(
        "(() => {{ const [id] = [...points].find(([, p]) => p.name === {name:?}); \
         const [x, y] = toScreen(points.get(id).value); \
         const r = canvas.getBoundingClientRect(); return [x + r.left, y + r.top]; }})()"
    ));
    (at[0].as_f64().expect("x"), at[1].as_f64().expect("y"))
}

/// The darkness of the canvas in the square of half-width 12 around viewport point `(x, y)`.
fn ink(browser: &mut Browser, (x, y): (f64, f64)) -> f64 {
    browser
        .eval(&format!(
            "(() => {{ const r = canvas.getBoundingClientRect(), s = window.devicePixelRatio || 1; \
             const d = ctx.getImageData(({x} - r.left - 12) * s, ({y} - r.top - 12) * s, 24 * s, 24 * s).data; \
             let ink = 0; for (let i = 0; i < d.length; i += 4) ink += d[i + 3] * (765 - d[i] - d[i + 1] - d[i + 2]); \
             return ink; }})()"
        ))
        .as_f64()
        .expect("a number")
}

#[test]
#[ignore = "needs Chromium: .ci/run installs it and runs this with --ignored"]
fn dragging_a_control_point_with_the_mouse_commits_exact_values_and_undo_restores_them() {
    let editor = start("worm.ron");
    let url = format!("http://127.0.0.1:{}/?token={}", editor.port, editor.token);
    let mut browser = Browser::launch(&url);
    browser.wait_for("document.getElementById('status').textContent.includes('points')");
    let before = state(&editor);
    let v3 = screen_position(&mut browser, "worm.v3");
    let far = screen_position(&mut browser, "worm.v0");
    let (near_ink, far_ink) = (ink(&mut browser, v3), ink(&mut browser, far));
    assert!(near_ink > 0.0, "the worm is drawn around v3");

    // Press on v3, move up in steps, release.
    browser.mouse("mousePressed", v3.0, v3.1);
    for step in 1..=6 {
        browser.mouse("mouseMoved", v3.0, v3.1 - 10.0 * f64::from(step));
    }
    browser.mouse("mouseReleased", v3.0, v3.1 - 60.0);
    let deadline = Instant::now() + Duration::from_secs(20);
    let after = loop {
        let s = state(&editor);
        if s["can_undo"] == true {
            break s;
        }
        assert!(Instant::now() < deadline, "the drag was not committed");
        std::thread::sleep(Duration::from_millis(50));
    };
    // Exact: x unchanged, y moved up by the dyadic displacement the page sent; every row holds.
    let moved = exact(&after, "worm.v3");
    assert_eq!(moved[0], "36");
    let y = parse_rational(&moved[1]).expect("an exact value");
    assert!(y > parse_rational("17").expect("17"), "{moved:?}");
    let grid = api::Rational::from_integer((1u64 << 30).into());
    assert!(
        (y * grid).is_integer(),
        "a displacement on a power-of-two grid: {moved:?}"
    );
    assert_eq!(after["violated_rows"], 0);
    // The picture changed near the point and not at the other end of the worm.
    browser.wait_for(
        "drag === null && document.getElementById('status').textContent.includes('1 edits')",
    );
    let moved_at = screen_position(&mut browser, "worm.v3");
    assert!(
        (moved_at.1 - (v3.1 - 60.0)).abs() < 2.0,
        "{moved_at:?} follows the mouse"
    );
    assert_ne!(ink(&mut browser, v3), near_ink);
    assert_eq!(ink(&mut browser, far), far_ink);
    // The model is drawn deformed: vertices near v3 moved, the others are where the file has
    // them.
    let model = browser.eval(
        "(() => { const m = models[0]; let moved = 0; \
         m.positions.forEach((p, i) => { if (Math.hypot(p[0] - m.reference[i][0], p[1] - m.reference[i][1]) > 1e-9) moved++; }); \
         return [m.name, moved, m.positions.length]; })()",
    );
    assert_eq!(model[0], "models/worm-model.obj");
    let (moved, all) = (model[1].as_u64().expect("n"), model[2].as_u64().expect("n"));
    assert!(
        0 < moved && moved < all,
        "{moved} of {all} model vertices moved"
    );

    // Undo from the page: the exact state before the drag.
    browser.wait_for("drag === null && !document.getElementById('undo').disabled");
    browser.click_element("undo");
    let deadline = Instant::now() + Duration::from_secs(20);
    while state(&editor)["can_undo"] == true {
        assert!(
            Instant::now() < deadline,
            "undo did not happen: {}",
            browser.eval("[document.getElementById('undo').disabled, document.getElementById('status').textContent, document.getElementById('conflict').textContent, String(drag)]")
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    assert_eq!(state(&editor)["points"], before["points"]);

    // Without the token the page is not served.
    browser.navigate(&format!("http://127.0.0.1:{}/", editor.port));
    let body = browser.eval("document.body.innerText");
    assert!(
        body.as_str()
            .is_some_and(|b| b.contains("missing or wrong token")),
        "{body}"
    );
}

/// Waits until the server's state satisfies `done`.
fn wait_for_state(
    editor: &common::Editor,
    what: &str,
    done: impl Fn(&serde_json::Value) -> bool,
) -> serde_json::Value {
    let deadline = Instant::now() + Duration::from_secs(20);
    loop {
        let s = state(editor);
        if done(&s) {
            return s;
        }
        assert!(Instant::now() < deadline, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn open(editor: &common::Editor) -> Browser {
    let url = format!("http://127.0.0.1:{}/?token={}", editor.port, editor.token);
    let mut browser = Browser::launch(&url);
    browser.wait_for("document.getElementById('status').textContent.includes('points')");
    browser
}

/// Drags from `from` by `(dx, dy)` pixels in six moves, then releases.
fn mouse_drag(browser: &mut Browser, from: (f64, f64), (dx, dy): (f64, f64)) {
    browser.mouse("mousePressed", from.0, from.1);
    for step in 1..=6 {
        let t = f64::from(step) / 6.0;
        browser.mouse("mouseMoved", from.0 + t * dx, from.1 + t * dy);
    }
    browser.mouse("mouseReleased", from.0 + dx, from.1 + dy);
}

#[test]
#[ignore = "needs Chromium: .ci/run installs it and runs this with --ignored"]
fn dragging_a_pinned_point_shows_the_constraints_in_the_way_and_changes_nothing() {
    build_align_plugin();
    let editor = start("align.ron");
    let mut browser = open(&editor);
    let before = state(&editor);
    let v1 = screen_position(&mut browser, "worm.v1");
    mouse_drag(&mut browser, v1, (40.0, 0.0));
    browser.wait_for(
        "!document.getElementById('conflict').hidden && \
         document.getElementById('conflict').textContent.includes('align row 5: worm.v1 x = 12')",
    );
    let panel = browser.eval("document.getElementById('conflict').textContent");
    assert!(
        panel
            .as_str()
            .is_some_and(|t| t.contains("structurally over-determined")),
        "{panel}"
    );
    // The anchor is drawn red; the state did not change.
    assert_eq!(browser.eval("points.get(blocked).name"), "worm.v1");
    browser.wait_for("drag === null");
    // Explain says why: the pinned point cannot move at all, and which pins remove each
    // direction.
    browser.click_element("explain-button");
    browser.wait_for(
        "!document.getElementById('explain').hidden && \
         document.getElementById('explain').textContent.includes('worm.v1: fully constrained') && \
         document.getElementById('explain').textContent.includes('worm.v1 x = 12')",
    );
    let after = state(&editor);
    assert_eq!(after["points"], before["points"]);
    assert_eq!(after["can_undo"], false);
}

#[test]
#[ignore = "needs Chromium: .ci/run installs it and runs this with --ignored"]
fn a_rotation_about_a_right_clicked_centre_is_exact() {
    let editor = start("worm.ron");
    let mut browser = open(&editor);
    let before = state(&editor);
    browser.eval("setOperation('rotate')");
    let v5 = screen_position(&mut browser, "worm.v5");
    let v7 = screen_position(&mut browser, "worm.v7");
    browser.right_click(v5.0, v5.1);
    browser.wait_for("center !== null");
    // A quarter turn of v7 about v5 (screen y points down: counter-clockwise is up).
    let (rx, ry) = (v7.0 - v5.0, v7.1 - v5.1);
    browser.mouse("mousePressed", v7.0, v7.1);
    for step in 1..=9 {
        let angle = f64::from(step) * std::f64::consts::FRAC_PI_2 / 9.0;
        let (c, s) = (angle.cos(), angle.sin());
        browser.mouse("mouseMoved", v5.0 + c * rx + s * ry, v5.1 - s * rx + c * ry);
    }
    browser.mouse("mouseReleased", v5.0 + ry, v5.1 - rx);
    let after = wait_for_state(&editor, "the rotation's commit", |s| s["can_undo"] == true);
    assert_eq!(after["violated_rows"], 0);
    // Exact: distances to the centre are kept exactly by the rational rotation.
    let q = |name: &str, s: &serde_json::Value| -> Vec<api::Rational> {
        exact(s, name)
            .iter()
            .map(|t| parse_rational(t).expect("exact"))
            .collect()
    };
    // The centre exactly as the page sends it.
    let centre = browser.eval("center.map(dyadic)");
    let c: Vec<api::Rational> = centre
        .as_array()
        .expect("centre")
        .iter()
        .map(|t| parse_rational(t.as_str().expect("text")).expect("exact"))
        .collect();
    let distance = |p: &[api::Rational]| {
        let (dx, dy) = (&p[0] - &c[0], &p[1] - &c[1]);
        &dx * &dx + &dy * &dy
    };
    assert_eq!(
        distance(&q("worm.v7", &after)),
        distance(&q("worm.v7", &before))
    );
    assert_ne!(q("worm.v7", &after), q("worm.v7", &before));
}

#[test]
#[ignore = "needs Chromium: .ci/run installs it and runs this with --ignored"]
fn a_session_saved_from_the_page_reruns_and_its_autosave_resumes_from_the_banner() {
    let (dir, run) = worm_copy();
    let editor = start_at(run.clone(), true);
    let mut browser = open(&editor);
    let v3 = screen_position(&mut browser, "worm.v3");
    mouse_drag(&mut browser, v3, (0.0, -50.0));
    let edited = wait_for_state(&editor, "the drag's commit", |s| s["can_undo"] == true);
    browser.wait_for("drag === null");
    browser.eval("document.getElementById('save-name').value = 'mine.ron'");
    browser.click_element("save");
    browser.wait_for("document.getElementById('conflict').textContent.startsWith('Saved 1 edits')");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_ecles"))
        .args(["run", "--quiet", "--out"])
        .arg(dir.path().join("again"))
        .arg(dir.path().join("mine.ron"))
        .status()
        .expect("ecles runs");
    assert!(status.success());
    assert_eq!(
        std::fs::read(dir.path().join("mine.out/report.json")).expect("saved"),
        std::fs::read(dir.path().join("again/report.json")).expect("rerun")
    );

    // A second editor on the run offers the autosave; the banner's button resumes it.
    let second = start_at(run, true);
    let mut page = open(&second);
    page.wait_for("!document.getElementById('banner').hidden");
    page.click_element("resume");
    let resumed = wait_for_state(&second, "the resume", |s| s["committed"] == 1);
    assert_eq!(resumed["points"], edited["points"]);
    page.wait_for("document.getElementById('banner').hidden");
}

/// A terrain in z1 mode: the top surface's control point dragged up with the mouse along its
/// vertical line commits an exact raise (every row holding) and the model rises with it; view
/// mode turns the scene.
#[test]
#[ignore = "needs Chromium: .ci/run installs it and runs this with --ignored"]
fn a_terrain_height_dragged_up_in_z1_mode_commits_exactly_and_view_mode_turns_the_scene() {
    let editor = start("terrain.ron");
    let mut browser = open(&editor);
    assert_eq!(
        browser.eval("document.getElementById('modes').hidden"),
        false
    );
    assert_eq!(browser.eval("editMode()"), "z1");
    let before = state(&editor);
    assert_eq!(exact(&before, "terrain.top.v4"), ["20"]);
    let at = browser.eval(
        "(() => { const [id] = [...points].find(([, p]) => p.name === 'terrain.top.v4'); \
         const [x, y] = screenOf(id); const r = canvas.getBoundingClientRect(); \
         return [x + r.left, y + r.top]; })()",
    );
    let v4 = (at[0].as_f64().expect("x"), at[1].as_f64().expect("y"));
    // A click (no move) selects and commits nothing.
    browser.mouse("mousePressed", v4.0, v4.1);
    browser.wait_for("frames.length >= 1");
    browser.mouse("mouseReleased", v4.0, v4.1);
    browser.wait_for("drag === null");
    assert_eq!(
        state(&editor)["can_undo"],
        false,
        "a click committed an edit"
    );
    let heights_before = browser.eval("models[0].positions.map((p) => p[2])");
    mouse_drag(&mut browser, v4, (0.0, -40.0));
    let after = wait_for_state(&editor, "the lift's commit", |s| s["can_undo"] == true);
    assert_eq!(after["violated_rows"], 0);
    let raised = parse_rational(&exact(&after, "terrain.top.v4")[0]).expect("exact");
    assert!(raised > parse_rational("20").expect("20"), "{raised}");
    // Only the top surface's heights moved: v4's bottom and φ stay.
    assert_eq!(
        exact(&after, "terrain.bottom.v4"),
        exact(&before, "terrain.bottom.v4")
    );
    assert_eq!(
        exact(&after, "terrain.xy.v4"),
        exact(&before, "terrain.xy.v4")
    );
    browser.wait_for("drag === null");
    let heights_after = browser.eval("models[0].positions.map((p) => p[2])");
    let rose = heights_before
        .as_array()
        .expect("heights")
        .iter()
        .zip(heights_after.as_array().expect("heights"))
        .filter(|(a, b)| b.as_f64() > a.as_f64())
        .count();
    assert!(rose > 0, "the terrain model rises with the top surface");

    // View mode: dragging empty space turns the scene.
    browser.eval("document.querySelector('input[name=mode][value=view]').click()");
    let azimuth = browser.eval("camera.azimuth").as_f64().expect("azimuth");
    // A corner of the canvas: empty space.
    let corner = browser.eval(
        "(() => { const r = canvas.getBoundingClientRect(); return [r.left + 20, r.bottom - 20]; })()",
    );
    let corner = (
        corner[0].as_f64().expect("x"),
        corner[1].as_f64().expect("y"),
    );
    mouse_drag(&mut browser, corner, (60.0, 0.0));
    let turned = browser.eval("camera.azimuth").as_f64().expect("azimuth");
    assert!((turned - azimuth).abs() > 10.0, "{azimuth} -> {turned}");
}

/// The settings' continuity switch (C1 → C0: the worm's rows are gone, a point then moves
/// alone), a bad reference mesh chosen in the file chooser (refused: the panel names its line
/// and column, nothing changes) and a model chosen there (drawn, kept beside the run file).
#[test]
#[ignore = "needs Chromium: .ci/run installs it and runs this with --ignored"]
fn continuity_and_files_chosen_in_the_page_change_the_session() {
    let (dir, run) = worm_copy();
    let editor = start_at(run, false);
    let mut browser = open(&editor);
    browser.eval(
        "(() => { const s = document.getElementById('continuity-worm'); s.value = '0'; \
         s.dispatchEvent(new Event('change')); })()",
    );
    let c0 = wait_for_state(&editor, "C0", |s| s["rows"] == 0);
    assert_eq!(c0["sources"][0]["view"]["smoothness"], 0);
    browser.wait_for("document.getElementById('continuity-worm').value === '0'");

    // Under C0 a control point dragged with the mouse moves alone.
    browser.eval("document.getElementById('neighborhood').value = '0'");
    let v5 = screen_position(&mut browser, "worm.v5");
    mouse_drag(&mut browser, v5, (30.0, 0.0));
    let moved = wait_for_state(&editor, "the drag's commit", |s| s["committed"] == 2);
    let changed: Vec<&str> = moved["points"]
        .as_array()
        .expect("points")
        .iter()
        .zip(c0["points"].as_array().expect("points"))
        .filter(|(a, b)| a["exact"] != b["exact"])
        .map(|(a, _)| a["name"].as_str().expect("a name"))
        .collect();
    assert_eq!(changed, ["worm.v5"]);
    browser.wait_for("drag === null");

    let bad = dir.path().join("bad.obj");
    std::fs::write(&bad, "v 0 0 0\nv 9 0 0\nf 1 2 q\n").expect("write");
    browser.choose_file("load-mesh-worm", &bad);
    browser.wait_for("document.getElementById('conflict').textContent.includes('bad.obj:3:')");
    assert_eq!(state(&editor)["points"], moved["points"]);
    assert!(!dir.path().join("worm.inputs").exists());

    let model = dir.path().join("tri.obj");
    std::fs::write(&model, "v 10 10\nv 20 10\nv 10 20\nf 1 2 3\n").expect("write");
    browser.choose_file("load-model-worm", &model);
    browser.wait_for(
        "document.getElementById('conflict').textContent.includes('worm.inputs/tri.obj')",
    );
    let loaded = state(&editor);
    assert_eq!(
        loaded["sources"][0]["view"]["models"][0]["vertices"]
            .as_array()
            .map(Vec::len),
        Some(3)
    );
    assert!(dir.path().join("worm.inputs/tri.obj").exists());
    assert_eq!(browser.eval("models.length"), serde_json::json!(1));
}

/// The change-criterion selector: a drag under "fewest points" commits exactly, and the
/// status bar says what the criterion chose.
#[test]
#[ignore = "needs Chromium: .ci/run installs it and runs this with --ignored"]
fn a_drag_under_the_fewest_points_criterion_commits_exactly_and_says_what_it_chose() {
    let editor = start("worm.ron");
    let mut browser = open(&editor);
    let before = state(&editor);
    browser.eval("document.getElementById('criterion').value = 'Fewest'");
    let v3 = screen_position(&mut browser, "worm.v3");
    mouse_drag(&mut browser, v3, (0.0, -50.0));
    let after = wait_for_state(&editor, "the drag's commit", |s| s["can_undo"] == true);
    assert_eq!(after["violated_rows"], 0);
    assert_ne!(exact(&after, "worm.v3"), exact(&before, "worm.v3"));
    browser.wait_for(
        "drag === null && document.getElementById('status').textContent.includes('Fewest') && \
         document.getElementById('status').textContent.includes('points changed')",
    );
    // Fewer points moved than there are derived points: the criterion kept the rest.
    let moved = after["points"]
        .as_array()
        .expect("points")
        .iter()
        .zip(before["points"].as_array().expect("points"))
        .filter(|(a, b)| a["exact"] != b["exact"])
        .count();
    let derived = browser.eval("derived.size").as_u64().expect("|D|") as usize;
    assert!(moved <= derived, "{moved} moved, {derived} derived");
}
