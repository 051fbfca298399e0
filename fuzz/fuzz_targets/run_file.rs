//! The run-file reader: any text is a run file or a located error, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Err(e) = host::runfile::parse(text, "fuzz.ron") {
            // Every error names the file.
            assert!(e.to_string().starts_with("fuzz.ron"), "{e}");
        }
    }
});
