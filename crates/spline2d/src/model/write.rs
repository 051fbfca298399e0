//! Writing a model back as Wavefront OBJ (deterministic, shortest round-tripping decimals), and
//! the output name of a deformed model.

use super::Model;
use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::Path;

/// Formats a coordinate for OBJ output: the shortest decimal that reads back to the same
/// `f64` (Rust's `Display`), never in exponent form, with `-0` written as `0`. Deterministic.
fn number(out: &mut String, x: f64) {
    let x = if x == 0.0 { 0.0 } else { x };
    // Writing to a String cannot fail.
    let _ = write!(out, "{x}");
}

/// Writes a model as OBJ: a comment with the counts, `v x y z` per vertex (shortest decimals
/// that read back exactly, so [`parse_model`](super::parse_model) returns the same model) and
/// `f a b c` per triangle, 1-based. Fails with [`io::ErrorKind::InvalidInput`] if a triangle refers to a
/// missing vertex or a coordinate is not finite, before writing anything.
pub fn write_obj(model: &Model, writer: &mut impl Write) -> io::Result<()> {
    let count = model.positions.len();
    if let Some((t, _)) = model
        .triangles
        .iter()
        .enumerate()
        .find(|(_, tri)| tri.iter().any(|&v| v >= count))
    {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("triangle {t} refers to a vertex beyond the {count} of the model"),
        ));
    }
    if let Some(v) = model
        .positions
        .iter()
        .position(|p| p.iter().any(|x| !x.is_finite()))
    {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("vertex {v} has a coordinate that is not finite"),
        ));
    }
    let mut text = String::new();
    let _ = writeln!(
        text,
        "# {count} vertices, {} triangles",
        model.triangles.len()
    );
    let flush = |text: &mut String, writer: &mut dyn Write| -> io::Result<()> {
        writer.write_all(text.as_bytes())?;
        text.clear();
        Ok(())
    };
    for p in &model.positions {
        text.push('v');
        for &x in p {
            text.push(' ');
            number(&mut text, x);
        }
        text.push('\n');
        if text.len() > 1 << 16 {
            flush(&mut text, writer)?;
        }
    }
    for [a, b, c] in &model.triangles {
        let _ = writeln!(text, "f {} {} {}", a + 1, b + 1, c + 1);
        if text.len() > 1 << 16 {
            flush(&mut text, writer)?;
        }
    }
    flush(&mut text, writer)
}

/// The output file name of a deformed model: `<stem>-deformed.stl` for an STL model at
/// `path`, `.ply` for a PLY model, `.gltf` or `.glb` for glTF (as the input), `<stem>-deformed.obj` for any other (`model-deformed…` when the path has no usable
/// stem), so the deformed model lands in the output directory next to the report, in its own
/// format, never over its input.
pub fn deformed_name(path: &str) -> String {
    let stem = Path::new(path)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .filter(|s| !s.is_empty() && !s.starts_with('.'))
        .unwrap_or_else(|| "model".into());
    let extension = if super::read::is_stl(Path::new(path)) {
        "stl"
    } else if super::read::is_ply(Path::new(path)) {
        "ply"
    } else if super::read::is_gltf(Path::new(path)) {
        if path.to_ascii_lowercase().ends_with(".glb") {
            "glb"
        } else {
            "gltf"
        }
    } else {
        "obj"
    };
    format!("{stem}-deformed.{extension}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::parse_model;

    #[test]
    fn writing_rejects_bad_models_and_round_trips() {
        let mut out = Vec::new();
        let bad = Model {
            positions: vec![[0.0; 3]],
            triangles: vec![[0, 0, 1]],
        };
        assert!(write_obj(&bad, &mut out).is_err());
        assert!(out.is_empty());
        let model = Model {
            positions: vec![[0.1, -0.0, 1e-300], [1e300, 2.5, -3.0], [0.3, 0.7, 0.0]],
            triangles: vec![[0, 1, 2]],
        };
        write_obj(&model, &mut out).expect("write");
        let text = String::from_utf8(out).expect("utf8");
        assert!(text.contains("v 0.1 0 0.000"), "{text}");
        assert_eq!(parse_model(&text, "round").expect("read"), model);
    }
}
