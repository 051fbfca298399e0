//! Measures the editor's frame times in a real headless Chromium (BENCHMARKS.md, "The editor
//! in the browser"): serves a run file, presses the mouse on an anchor, moves it in `MOVES`
//! steps at 60 events a second, releases, and prints what the page measured with its
//! performance clock: mouse-down to the first painted frame (2DSD Select, ExpandDerived and
//! ECLES Initialize), each move to its painted frame (median, 90th percentile, worst), split
//! into the request's round trip, the server's part, the model's deformation and the drawing
//! (moves drawn by the page from the drag's motion response have no round trip), and the
//! release to the committed state drawn.
//!
//! ```text
//! python3 tools/make_editor_bench.py /tmp/eb
//! cargo run --release -p host --example editor_frames -- /tmp/eb/grid.ron v264 3 [MOVES] [DX,DY]
//! ```
//!
//! Needs Chromium (`$CHROMIUM`, else `/usr/bin/chromium`).

// The tests' CDP client and served editors; this program uses a part of them.
#[allow(dead_code)]
#[path = "../tests/common/cdp.rs"]
mod cdp;
#[path = "../tests/common/mod.rs"]
mod common;

use serde_json::Value;
use std::path::PathBuf;
use std::time::{Duration, Instant};

fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let at = ((sorted.len() - 1) as f64 * q).round() as usize;
    sorted[at]
}

/// The numbers of field `field` of the move frames (not the first), sorted.
fn column(frames: &[Value], field: &str) -> Vec<f64> {
    let mut out: Vec<f64> = frames
        .iter()
        .filter(|f| f["first"] == false)
        .filter_map(|f| f[field].as_f64())
        .collect();
    out.sort_by(f64::total_cmp);
    out
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 3 {
        eprintln!("usage: editor_frames RUN.ron ANCHOR NEIGHBORHOOD|all [MOVES] [DX,DY pixels]");
        std::process::exit(2);
    }
    let run = PathBuf::from(&args[0]);
    let anchor = args[1].clone();
    let neighborhood = args[2].clone();
    let moves: u32 = args
        .get(3)
        .map_or(60, |m| m.parse().expect("MOVES is a number"));
    let (dx, dy): (f64, f64) = args.get(4).map_or((0.0, -90.0), |d| {
        let (x, y) = d.split_once(',').expect("DX,DY");
        (x.parse().expect("DX"), y.parse().expect("DY"))
    });

    let editor = common::start_at(run, false);
    let url = format!("http://127.0.0.1:{}/?token={}", editor.port, editor.token);
    let loading = Instant::now();
    let mut browser = cdp::Browser::launch(&url);
    browser.wait_for("document.getElementById('status').textContent.includes('points')");
    let loaded = loading.elapsed();
    let setup = format!(
        "(() => {{ const input = document.getElementById('neighborhood'); \
         if ({all}) document.getElementById('all').checked = true; else input.value = {n}; \
         const [id] = [...points].find(([, p]) => p.name.endsWith('.' + {anchor:?})); \
         const [x, y] = toScreen(points.get(id).value); \
         const r = canvas.getBoundingClientRect(); \
         return [x + r.left, y + r.top, models.reduce((s, m) => s + m.positions.length, 0)]; }})()",
        all = neighborhood == "all",
        n = if neighborhood == "all" {
            "0"
        } else {
            &neighborhood
        },
    );
    let at = browser.eval(&setup);
    let (x, y) = (at[0].as_f64().expect("x"), at[1].as_f64().expect("y"));
    let model_vertices = at[2].as_u64().unwrap_or(0);

    browser.mouse("mousePressed", x, y);
    browser.wait_for("frames.length >= 1");
    let step = Duration::from_micros(16_667);
    let mut next = Instant::now();
    for i in 1..=moves {
        let t = f64::from(i) / f64::from(moves);
        next += step;
        browser.mouse("mouseMoved", x + t * dx, y + t * dy);
        if let Some(wait) = next.checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
    }
    browser.wait_for("drag !== null && !drag.inFlight && !drag.pending");
    browser.mouse("mouseReleased", x + dx, y + dy);
    browser.wait_for("drag === null && commits.length === 1");

    let frames = browser.eval("frames");
    let frames = frames.as_array().expect("frames");
    let first = frames
        .iter()
        .find(|f| f["first"] == true)
        .expect("the mouse-down frame");
    let commit = browser.eval("commits[0]").as_f64().unwrap_or(f64::NAN);
    let status = browser.eval("document.getElementById('status').textContent");
    let total = column(frames, "total");
    println!("run {} · anchor {anchor} · δ {neighborhood} · model vertices {model_vertices} · page loaded in {:.0} ms", args[0], loaded.as_secs_f64() * 1e3);
    println!(
        "mouse-down to first frame {:.1} ms (server {:.1} ms, request {:.1} ms, deform {:.1} ms, draw {:.1} ms)",
        first["total"].as_f64().unwrap_or(f64::NAN),
        first["server"].as_f64().unwrap_or(f64::NAN),
        first["request"].as_f64().unwrap_or(f64::NAN),
        first["deform"].as_f64().unwrap_or(f64::NAN),
        first["draw"].as_f64().unwrap_or(f64::NAN),
    );
    println!(
        "{} move frames for {moves} mouse moves: total median {:.1} ms, p90 {:.1}, worst {:.1}",
        total.len(),
        quantile(&total, 0.5),
        quantile(&total, 0.9),
        quantile(&total, 1.0)
    );
    let slow: Vec<String> = frames
        .iter()
        .filter(|f| f["first"] == false)
        .enumerate()
        .filter(|(_, f)| f["total"].as_f64().is_some_and(|t| t > 1000.0 / 60.0))
        .map(|(i, f)| {
            format!(
                "{}: {:.0} ms",
                i + 1,
                f["total"].as_f64().unwrap_or(f64::NAN)
            )
        })
        .collect();
    println!(
        "  moves painted later than 16.7 ms (move: time): {}",
        slow.join(", ")
    );
    let local = frames.iter().filter(|f| f["local"] == true).count();
    println!("  {local} of them drawn by the page from the motion response (no round trip)");
    for field in ["ready", "request", "server", "deform", "draw", "moved"] {
        let c = column(frames, field);
        println!(
            "  {field:8} median {:.2}, p90 {:.2}, worst {:.2}",
            quantile(&c, 0.5),
            quantile(&c, 0.9),
            quantile(&c, 1.0)
        );
    }
    println!("release to committed state drawn {commit:.1} ms");
    println!("status: {}", status.as_str().unwrap_or_default());
}
