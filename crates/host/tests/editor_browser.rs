//! The editor in a real headless Chromium, with real mouse events: the page loads the worm,
//! a control point dragged with the mouse commits exact values (every row holding), the
//! picture changes near the point and not far from it, undo from the page restores the exact
//! state, and the page is refused without the token.
//!
//! Needs Chromium (`$CHROMIUM`, else `/usr/bin/chromium`); `.ci/run` installs it and runs
//! these with `--ignored`.

#[path = "common/cdp.rs"]
mod cdp;
mod common;

use api::parse_rational;
use cdp::Browser;
use common::{exact, start, state};
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
    // Exact: x unchanged, y moved up by the decimal displacement the page sent; every row holds.
    let moved = exact(&after, "worm.v3");
    assert_eq!(moved[0], "36");
    let y = parse_rational(&moved[1]).expect("an exact value");
    assert!(y > parse_rational("17").expect("17"), "{moved:?}");
    let micro = api::Rational::from_integer(1_000_000.into());
    assert!(
        (y * micro).is_integer(),
        "a displacement of at most six decimals: {moved:?}"
    );
    assert_eq!(after["violated_rows"], 0);
    // The picture changed near the point and not at the other end of the worm.
    browser.wait_for("document.getElementById('status').textContent.includes('violated rows 0')");
    let moved_at = screen_position(&mut browser, "worm.v3");
    assert!(
        (moved_at.1 - (v3.1 - 60.0)).abs() < 2.0,
        "{moved_at:?} follows the mouse"
    );
    assert_ne!(ink(&mut browser, v3), near_ink);
    assert_eq!(ink(&mut browser, far), far_ink);

    // Undo from the page: the exact state before the drag.
    let button = browser.eval(
        "(() => { const r = document.getElementById('undo').getBoundingClientRect(); \
         return [r.left + r.width / 2, r.top + r.height / 2]; })()",
    );
    let (bx, by) = (
        button[0].as_f64().expect("x"),
        button[1].as_f64().expect("y"),
    );
    browser.mouse("mousePressed", bx, by);
    browser.mouse("mouseReleased", bx, by);
    let deadline = Instant::now() + Duration::from_secs(20);
    while state(&editor)["can_undo"] == true {
        assert!(Instant::now() < deadline, "undo did not happen");
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
