//! Arbitrary bytes and arbitrary mutations of the bundled run files, run in process as
//! `ecles run` would: never a panic, and never an exit code other than 0 (success), 1 (an edit
//! not solvable) or 2 (bad input). Mutations delete, insert, swap and duplicate bytes and lines
//! but never insert digits, so no mutation turns `steps: 4` into a run of minutes.

use host::commands::{self, RunOptions};
use host::console::Console;
use proptest::prelude::*;
use std::path::{Path, PathBuf};

/// The bundled run files the mutations start from (the small ones, all built in).
const EXAMPLES: &[&str] = &[
    "worm.ron",
    "starfish.ron",
    "pumps.ron",
    "near-degenerate.ron",
];

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// Runs `text` as a run file next to the bundled meshes and models; returns the exit code.
fn run_text(text: &[u8]) -> u8 {
    let dir = tempfile::tempdir().expect("temporary directory");
    #[cfg(unix)]
    for sub in ["meshes", "models", "terrains"] {
        std::os::unix::fs::symlink(examples().join(sub), dir.path().join(sub)).expect("link");
    }
    let run = dir.path().join("run.ron");
    std::fs::write(&run, text).expect("write run file");
    let options = RunOptions {
        run,
        out: Some(dir.path().join("out")),
        quiet: true,
        strict: false,
        max_input_bytes: api::input::DEFAULT_MAX_INPUT_BYTES,
    };
    let mut sink = Vec::new();
    let mut console = Console::new(&mut sink);
    match commands::run(&options, &mut console) {
        Ok(code) => code,
        Err(e) => e.exit_code(),
    }
}

/// One mutation of a text.
#[derive(Debug, Clone)]
enum Mutation {
    Delete(usize),
    Insert(usize, u8),
    Swap(usize),
    DuplicateLine(usize),
    DeleteLine(usize),
    Truncate(usize),
}

/// Bytes a mutation may insert: RON punctuation, letters, quotes, whitespace and a few
/// non-ASCII bytes, but no digits.
const INSERTABLE: &[u8] = b"()[]{},:;\"'/*#-+.eE_ anxyzSomeNone\n\t\xc3\xa9\xff";

fn mutation() -> impl Strategy<Value = Mutation> {
    let at = any::<usize>();
    prop_oneof![
        at.prop_map(Mutation::Delete),
        (any::<usize>(), prop::sample::select(INSERTABLE))
            .prop_map(|(i, b)| Mutation::Insert(i, b)),
        any::<usize>().prop_map(Mutation::Swap),
        any::<usize>().prop_map(Mutation::DuplicateLine),
        any::<usize>().prop_map(Mutation::DeleteLine),
        any::<usize>().prop_map(Mutation::Truncate),
    ]
}

fn apply(text: &mut Vec<u8>, m: &Mutation) {
    if text.is_empty() {
        return;
    }
    let n = text.len();
    match *m {
        Mutation::Delete(i) => {
            text.remove(i % n);
        }
        Mutation::Insert(i, b) => text.insert(i % (n + 1), b),
        Mutation::Swap(i) if n > 1 => text.swap(i % (n - 1), i % (n - 1) + 1),
        Mutation::Swap(_) => {}
        Mutation::DuplicateLine(i) | Mutation::DeleteLine(i) => {
            let starts: Vec<usize> = std::iter::once(0)
                .chain(
                    text.iter()
                        .enumerate()
                        .filter(|(_, &b)| b == b'\n')
                        .map(|(k, _)| k + 1),
                )
                .filter(|&k| k < n)
                .collect();
            let start = starts[i % starts.len()];
            let end = text[start..]
                .iter()
                .position(|&b| b == b'\n')
                .map_or(n, |k| start + k + 1);
            let line: Vec<u8> = text[start..end].to_vec();
            if matches!(m, Mutation::DuplicateLine(_)) {
                text.splice(start..start, line);
            } else {
                text.drain(start..end);
            }
        }
        Mutation::Truncate(i) => text.truncate(i % n),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    #[test]
    fn mutated_run_files_exit_cleanly(
        example in prop::sample::select(EXAMPLES),
        mutations in prop::collection::vec(mutation(), 1..4),
    ) {
        let mut text = std::fs::read(examples().join(example)).expect("bundled run file");
        for m in &mutations {
            apply(&mut text, m);
        }
        let code = run_text(&text);
        prop_assert!(code <= 2, "exit code {code} for {:?}", String::from_utf8_lossy(&text));
    }

    #[test]
    fn arbitrary_bytes_exit_cleanly(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let code = run_text(&bytes);
        prop_assert!(code <= 2, "exit code {code}");
    }
}

#[test]
fn the_unmutated_examples_run() {
    for example in EXAMPLES {
        let text = std::fs::read(examples().join(example)).expect("bundled run file");
        let code = run_text(&text);
        // pumps.ron refuses one edit by design.
        let expected = if *example == "pumps.ron" { 1 } else { 0 };
        assert_eq!(code, expected, "{example}");
    }
}
