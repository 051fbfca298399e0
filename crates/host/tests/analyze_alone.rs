//! `Session::analyze_alone` (what `ecles analyze` runs: sources, system and values released
//! before the elimination) gives exactly the report of `Session::analyze` on a session kept
//! whole, on every bundled run file built in (the dynamic-library ones need the plugin builds).

use host::session::Session;
use std::path::{Path, PathBuf};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

#[test]
fn releasing_the_system_changes_no_report() {
    for name in [
        "worm.ron",
        "starfish.ron",
        "pumps.ron",
        "near-degenerate.ron",
        "grid.ron",
        "terrain.ron",
    ] {
        let run = examples().join(name);
        let limit = api::input::DEFAULT_MAX_INPUT_BYTES;
        let kept = Session::build(&run, limit).expect("bundled example builds");
        let whole = serde_json::to_value(kept.analyze()).expect("report encodes");
        let alone = Session::build(&run, limit)
            .expect("bundled example builds")
            .analyze_alone();
        let alone = serde_json::to_value(alone).expect("report encodes");
        assert_eq!(whole, alone, "{name}");
        assert!(
            whole["parameters"].as_u64().is_some_and(|p| p > 0),
            "{name}"
        );
    }
}
