//! Every bench and tool of this package measures with the `ecles` binary's allocator.
//!
//! The allocator is declared in the `benchmarks` library (`#[global_allocator]`), and a target
//! links the library only when its source uses it: `real_mesh` and `decimal` did not, and
//! measured with the system's allocator for three sessions.

use std::path::Path;

/// The Rust files directly in `dir` (not its modules' folders).
fn sources(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(Result::ok)
        .map(|entry| entry.path())
        .filter(|path| path.extension().is_some_and(|ext| ext == "rs"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_bench_and_tool_links_the_library_that_declares_the_allocator() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut targets = sources(&root.join("benches"));
    targets.extend(sources(&root.join("src/bin")));
    assert!(targets.len() >= 10, "found only {targets:?}");
    let unlinked: Vec<String> = targets
        .iter()
        .filter(|path| {
            let text = std::fs::read_to_string(path).unwrap_or_default();
            // Code lines only: a comment naming the library links nothing.
            !text.lines().map(str::trim_start).any(|line| {
                !line.starts_with("//")
                    && (line.starts_with("use benchmarks") || line.contains("benchmarks::"))
            })
        })
        .map(|path| path.display().to_string())
        .collect();
    assert!(
        unlinked.is_empty(),
        "these targets do not use the `benchmarks` library, so they run with the system's \
         allocator instead of mimalloc (add `use benchmarks as _;`): {unlinked:?}"
    );
}
