//! The OBJ readers: the exact reference-mesh reader (with and without snapping) and the model
//! reader. Any text is a mesh, a model or an error naming the file, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use spline2d::mesh_io::{parse_obj, MeshOptions, OrientationPolicy};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let snapped = MeshOptions {
        snap: Some(api::Rational::new(1.into(), 1000.into())),
        orientation: OrientationPolicy::Reject,
    };
    for options in [MeshOptions::default(), snapped] {
        if let Err(e) = parse_obj(&text, "fuzz.obj", &options) {
            assert!(e.to_string().starts_with("fuzz.obj"), "{e}");
        }
    }
    if let Err(e) = spline2d::model::parse_model(&text, "fuzz.obj") {
        assert!(e.to_string().starts_with("fuzz.obj"), "{e}");
    }
});
