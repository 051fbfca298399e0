//! Screenshots of the editor for `docs/editor.md`, taken in a real headless Chromium with real
//! mouse events: xy mode on the worm in the middle of a drag, the conflict panel of a pinned
//! point (examples/align.ron), a terrain's top surface raised in z1 mode, and view mode.
//!
//! ```text
//! cargo build --release -p plugins-align
//! cargo run --release -p host --example editor_screenshots -- docs/editor
//! ```
//!
//! Needs Chromium (`$CHROMIUM`, else `/usr/bin/chromium`).

// The tests' CDP client and served editors; this program uses a part of them.
#[allow(dead_code)]
#[path = "../tests/common/cdp.rs"]
mod cdp;
#[path = "../tests/common/mod.rs"]
mod common;

use base64::Engine;
use std::path::{Path, PathBuf};

/// Serves `examples/{run}` and opens the page; the browser.
fn open(run: &str) -> cdp::Browser {
    let editor = common::start_at(common::examples().join(run), false);
    let url = format!("http://127.0.0.1:{}/?token={}", editor.port, editor.token);
    let mut browser = cdp::Browser::launch(&url);
    browser.wait_for("document.getElementById('status').textContent.includes('points')");
    browser
}

/// The viewport position of the control point named `name`.
fn position(browser: &mut cdp::Browser, name: &str) -> (f64, f64) {
    let at = browser.eval(&format!(
        "(() => {{ const [id] = [...points].find(([, p]) => p.name === {name:?}); \
         const [x, y] = screenOf(id); const r = canvas.getBoundingClientRect(); \
         return [x + r.left, y + r.top]; }})()"
    ));
    (at[0].as_f64().expect("x"), at[1].as_f64().expect("y"))
}

/// Presses on `from` and moves by `(dx, dy)` in steps, without releasing; waits until the
/// frames are drawn and `drawn` holds.
fn hold_drag(browser: &mut cdp::Browser, from: (f64, f64), (dx, dy): (f64, f64), drawn: &str) {
    browser.mouse("mousePressed", from.0, from.1);
    for step in 1..=8 {
        let t = f64::from(step) / 8.0;
        browser.mouse("mouseMoved", from.0 + t * dx, from.1 + t * dy);
    }
    browser.wait_for(&format!(
        "drag !== null && !drag.inFlight && !drag.pending && ({drawn})"
    ));
}

fn release(browser: &mut cdp::Browser, at: (f64, f64)) {
    browser.mouse("mouseReleased", at.0, at.1);
    browser.wait_for("drag === null");
}

fn shoot(browser: &mut cdp::Browser, file: &Path) {
    let shot = browser.call(
        "Page.captureScreenshot",
        serde_json::json!({ "format": "png" }),
    );
    let data = shot["data"].as_str().expect("a screenshot");
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(data)
        .expect("base64");
    std::fs::write(file, bytes).unwrap_or_else(|e| panic!("cannot write {}: {e}", file.display()));
    println!("wrote {}", file.display());
}

fn main() {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "docs/editor".into()),
    );
    std::fs::create_dir_all(&out).expect("the output directory");

    let mut worm = open("worm.ron");
    let v3 = position(&mut worm, "worm.v3");
    hold_drag(&mut worm, v3, (0.0, -70.0), "frames.length > 1");
    shoot(&mut worm, &out.join("xy.png"));
    release(&mut worm, (v3.0, v3.1 - 70.0));

    let mut align = open("align.ron");
    let v1 = position(&mut align, "worm.v1");
    hold_drag(
        &mut align,
        v1,
        (50.0, 0.0),
        "!document.getElementById('conflict').hidden",
    );
    shoot(&mut align, &out.join("conflict.png"));
    release(&mut align, (v1.0 + 50.0, v1.1));

    let mut terrain = open("terrain.ron");
    let top = position(&mut terrain, "terrain.top.v4");
    hold_drag(&mut terrain, top, (0.0, -60.0), "frames.length > 1");
    shoot(&mut terrain, &out.join("z1.png"));
    release(&mut terrain, (top.0, top.1 - 60.0));
    terrain.eval("document.querySelector('input[name=mode][value=view]').click()");
    terrain.eval("setCamera(-40, 30)");
    shoot(&mut terrain, &out.join("view.png"));
}
