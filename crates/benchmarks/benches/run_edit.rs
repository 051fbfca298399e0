//! A whole generic edit as `ecles run` does it, in process: the run file of
//! `tools/peer_bench.py` (`benchmarks::point_run_text`: one point of a linear point system
//! dragged by (3, −2), every other parameter derived, `cross_check: None`), its session built
//! and dropped untimed, then `Session::run_edit` (plan, Initialize, Update, propagation
//! analysis, structure, values and their text, commit) and the edit's report serialised to
//! JSON. The peer benchmark times whole processes, whose start-up noise hides this share at 10
//! points.
//!
//! `cargo bench -p benchmarks --bench run_edit`

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

use benchmarks::{point_run_text, PointSystem};
use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion};
use host::session::Session;
use std::hint::black_box;
use std::path::Path;

/// A session of `text` with nothing edited yet.
fn session(text: &str) -> Session {
    Session::build_text(text, "points.ron", Path::new("."), 1 << 30).expect("a valid run file")
}

fn run_edits(c: &mut Criterion) {
    let mut group = c.benchmark_group("run-edit");
    group.sample_size(20);
    for (kind, label) in [
        (PointSystem::Chain, "chain"),
        (PointSystem::Grid, "grid"),
        (PointSystem::Parallelograms, "parallelograms"),
    ] {
        for n in [10, 100] {
            let n = if kind == PointSystem::Parallelograms {
                n + 1
            } else {
                n
            };
            let text = point_run_text(kind, n);
            // The edit is solved exactly once before it is timed.
            let report = session(&text).run_edit(0).expect("the edit runs");
            assert!(report.solvable, "{label}{n}: {:?}", report.error);
            assert_eq!(report.max_residual, "0", "{label}{n}");
            group.bench_function(BenchmarkId::new("exact", format!("{label}{n}")), |b| {
                b.iter_batched(
                    || {
                        // Every edit starts as a fresh process's would: not from the memo of
                        // the previous iteration's last factoring.
                        exact_ldu::forget_last_factoring();
                        session(&text)
                    },
                    |mut session| {
                        let report = session.run_edit(0).expect("the edit runs");
                        // Into a buffer of a `BufWriter`'s size, as `ecles run` streams it.
                        let mut json = Vec::with_capacity(8 << 10);
                        serde_json::to_writer(&mut json, &report).expect("JSON");
                        // The session is returned, so criterion drops it after the clock
                        // stops: its building is not timed and neither is its end.
                        (session, black_box(json))
                    },
                    BatchSize::LargeInput,
                )
            });
        }
    }
    group.finish();
}

criterion_group!(benches, run_edits);
criterion_main!(benches);
