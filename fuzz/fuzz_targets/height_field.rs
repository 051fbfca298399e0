//! The height-field readers (ESRI ASCII grid and plain grid), and the triangulation of what
//! they read: any text is a grid or an error naming the file, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use plugins_terrain::heightfield::HeightField;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    for field in [
        HeightField::parse_esri(&text, "fuzz.asc"),
        HeightField::parse_plain(&text, "fuzz.txt"),
    ] {
        match field {
            Ok(field) => {
                let model = field.to_model();
                assert!(model.positions.len() <= field.columns * field.rows);
            }
            Err(e) => assert!(e.to_string().starts_with("fuzz."), "{e}"),
        }
    }
});
