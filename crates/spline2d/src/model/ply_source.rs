//! PLY models, ASCII and binary (read and written with `ply-rs`): the `vertex` element's `x`,
//! `y`, `z` are the positions, the `face` element's `vertex_indices` (or `vertex_index`) the
//! polygons (fan-triangulated for the deformation, kept as they are in the file). The deformed
//! model is the same file — same encoding, elements, properties and their types, comments —
//! with the moved vertices' positions written again (in the property's own type, `float` or
//! `double`) and their normals `nx ny nz`, if the file has them, transformed by the inverse
//! transpose of the deformation's Jacobian and rescaled to their old length; every other
//! property (colours, texture coordinates, confidence, other elements) is kept. A model nothing
//! moves is written back byte for byte.

use super::{Model, ModelError};
use ply_rs::parser::Parser;
use ply_rs::ply::{DefaultElement, Ply, Property};
use ply_rs::writer::Writer;

/// A PLY file as read.
#[derive(Debug, Clone, PartialEq)]
pub struct PlySource {
    ply: Ply<DefaultElement>,
    /// The file as read: written back as it is when nothing moves (`ply-rs` writes the same
    /// values, not the same bytes).
    bytes: Vec<u8>,
}

/// A scalar property as `f64` (`None` for lists).
fn number(property: &Property) -> Option<f64> {
    Some(match property {
        Property::Char(x) => f64::from(*x),
        Property::UChar(x) => f64::from(*x),
        Property::Short(x) => f64::from(*x),
        Property::UShort(x) => f64::from(*x),
        Property::Int(x) => f64::from(*x),
        Property::UInt(x) => f64::from(*x),
        Property::Float(x) => f64::from(*x),
        Property::Double(x) => *x,
        _ => return None,
    })
}

/// A list property's entries as indices (`None` for scalars or negative entries).
fn indices(property: &Property) -> Option<Vec<usize>> {
    let convert = |v: Vec<i64>| v.into_iter().map(|i| usize::try_from(i).ok()).collect();
    match property {
        Property::ListChar(v) => convert(v.iter().map(|&i| i64::from(i)).collect()),
        Property::ListUChar(v) => convert(v.iter().map(|&i| i64::from(i)).collect()),
        Property::ListShort(v) => convert(v.iter().map(|&i| i64::from(i)).collect()),
        Property::ListUShort(v) => convert(v.iter().map(|&i| i64::from(i)).collect()),
        Property::ListInt(v) => convert(v.iter().map(|&i| i64::from(i)).collect()),
        Property::ListUInt(v) => convert(v.iter().map(|&i| i64::from(i)).collect()),
        _ => None,
    }
}

/// `value` in the type of `old` (`float` or `double`); `None` for other types.
fn same_type(old: &Property, value: f64) -> Option<Property> {
    match old {
        Property::Float(_) => {
            let x = value as f32;
            x.is_finite().then_some(Property::Float(x))
        }
        Property::Double(_) => value.is_finite().then_some(Property::Double(value)),
        _ => None,
    }
}

/// The header's length in bytes and lines (through the line `end_header`), when it has one.
fn header_extent(bytes: &[u8]) -> Option<(usize, usize)> {
    let mut offset = 0;
    for (k, line) in bytes.split(|&b| b == b'\n').enumerate() {
        offset += line.len() + 1;
        if line.strip_suffix(b"\r").unwrap_or(line) == b"end_header" {
            return Some((offset.min(bytes.len()), k + 1));
        }
    }
    None
}

/// A `ply-rs` error as an error at a position: its `Line N:` and, inside its message, the
/// grammar's `error at 1:C` for the column; for binary data that ends early, the line after
/// the header and the byte where the data ends. The message is `ply-rs`'s first line, without
/// the debugging detail it appends.
fn read_error(bytes: &[u8], file: &str, text: &str) -> ModelError {
    let at = |line: usize, column: usize, message: String| ModelError::Parse {
        file: file.to_string(),
        line,
        column,
        message: format!("not a PLY model this reader accepts: {message}"),
    };
    let first = text.lines().next().unwrap_or(text).trim();
    if let Some(rest) = first.strip_prefix("Line ") {
        let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
        let line = digits.parse().unwrap_or(1);
        let column = text
            .split("error at 1:")
            .nth(1)
            .and_then(|c| c.split(|ch: char| !ch.is_ascii_digit()).next())
            .and_then(|c| c.parse().ok())
            .unwrap_or(1);
        let what = rest[digits.len()..].trim_start_matches(':').trim();
        let what = if what.contains("element line") {
            "the values on this line do not match the properties the header declares".to_string()
        } else if what.contains("parse line") {
            "a header line this reader does not understand".to_string()
        } else {
            what.to_string()
        };
        return at(line, column, what);
    }
    match header_extent(bytes) {
        Some((data, lines)) if text.contains("fill whole buffer") => at(
            lines + 1,
            1,
            format!(
                "the data (from byte {data}) ends at byte {}, before every element the header declares",
                bytes.len()
            ),
        ),
        _ => at(1, 1, first.to_string()),
    }
}

impl PlySource {
    /// Reads a PLY file's bytes (`file` names it in errors): the model and its source.
    pub fn parse(bytes: &[u8], file: &str) -> Result<(Model, PlySource), ModelError> {
        let error = |line: usize, message: String| ModelError::Parse {
            file: file.to_string(),
            line,
            column: 1,
            message,
        };
        let ply = Parser::<DefaultElement>::new()
            .read_ply(&mut std::io::Cursor::new(bytes))
            .map_err(|e| read_error(bytes, file, &e.to_string()))?;
        let vertices = ply.payload.get("vertex").map(Vec::as_slice).unwrap_or(&[]);
        let mut positions = Vec::with_capacity(vertices.len());
        for (v, vertex) in vertices.iter().enumerate() {
            let coordinate = |name: &str, required: bool| -> Result<f64, ModelError> {
                match vertex.get(name).map(number) {
                    Some(Some(x)) if x.is_finite() => Ok(x),
                    None if !required => Ok(0.0),
                    _ => Err(error(
                        1,
                        format!("vertex {v}: property {name:?} is missing, a list, or not finite"),
                    )),
                }
            };
            positions.push([
                coordinate("x", true)?,
                coordinate("y", true)?,
                coordinate("z", false)?,
            ]);
        }
        if positions.is_empty() {
            return Err(ModelError::Empty {
                file: file.to_string(),
            });
        }
        let mut triangles = Vec::new();
        for (f, face) in ply
            .payload
            .get("face")
            .map(Vec::as_slice)
            .unwrap_or(&[])
            .iter()
            .enumerate()
        {
            let corners = face
                .get("vertex_indices")
                .or_else(|| face.get("vertex_index"))
                .and_then(indices)
                .filter(|c| c.len() >= 3 && c.iter().all(|&i| i < positions.len()))
                .ok_or_else(|| {
                    error(
                        1,
                        format!(
                            "face {f}: vertex_indices must list at least 3 of the {} vertices",
                            positions.len()
                        ),
                    )
                })?;
            for k in 1..corners.len() - 1 {
                triangles.push([corners[0], corners[k], corners[k + 1]]);
            }
        }
        Ok((
            Model {
                positions,
                triangles,
            },
            PlySource {
                ply,
                bytes: bytes.to_vec(),
            },
        ))
    }

    /// The file again with the positions of `deformed` and the normals at moved vertices
    /// transformed by `jacobian(v)`; see the module documentation.
    pub fn write_deformed(
        &self,
        original: &Model,
        deformed: &Model,
        jacobian: impl Fn(usize) -> Option<[[f64; 3]; 3]>,
    ) -> Result<Vec<u8>, String> {
        if original.positions == deformed.positions
            && original.positions.len() == self.ply.payload.get("vertex").map_or(0, Vec::len)
        {
            return Ok(self.bytes.clone());
        }
        let mut ply = self.ply.clone();
        let vertices = ply
            .payload
            .get_mut("vertex")
            .ok_or("the PLY file has no vertices")?;
        if vertices.len() != deformed.positions.len() || vertices.len() != original.positions.len()
        {
            return Err("the deformed model has another number of vertices".into());
        }
        for (v, vertex) in vertices.iter_mut().enumerate() {
            let (old, new) = (original.positions[v], deformed.positions[v]);
            if old == new {
                continue;
            }
            for (name, value) in ["x", "y", "z"].into_iter().zip(new) {
                let Some(property) = vertex.get(name) else {
                    continue;
                };
                let replaced = same_type(property, value).ok_or_else(|| {
                    format!("vertex {v}: {name} is not a float or double property, it cannot hold the deformed position")
                })?;
                vertex.insert(name.to_string(), replaced);
            }
            let normal: Option<[f64; 3]> = ["nx", "ny", "nz"]
                .iter()
                .map(|n| vertex.get(*n).and_then(number))
                .collect::<Option<Vec<f64>>>()
                .and_then(|n| n.try_into().ok());
            if let (Some(n), Some(j)) = (normal, jacobian(v)) {
                if let Some(turned) = super::matrix3::transform_normal(&j, n) {
                    for (name, value) in ["nx", "ny", "nz"].into_iter().zip(turned) {
                        if let Some(replaced) = vertex.get(name).and_then(|p| same_type(p, value)) {
                            vertex.insert(name.to_string(), replaced);
                        }
                    }
                }
            }
        }
        let mut out = Vec::new();
        Writer::<DefaultElement>::new()
            .write_ply(&mut out, &mut ply)
            .map_err(|e| format!("the deformed PLY cannot be written: {e}"))?;
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ASCII: &str = "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0 1 0 10\n1 0 0 0 1 0 20\n1 1 0 0 1 0 30\n0 1 0 0 1 0 40\n4 0 1 2 3\n";

    #[test]
    fn malformed_files_are_refused_at_their_line_and_column() {
        let message = |text: &[u8]| {
            PlySource::parse(text, "bad.ply")
                .expect_err("refused")
                .to_string()
        };
        let ascii = message(b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nend_header\n1 2\n3 x\n");
        assert!(
            ascii.starts_with("bad.ply:8:3: ")
                && ascii.contains("do not match")
                && !ascii.contains('\n'),
            "{ascii}"
        );
        let header =
            message(b"ply\nformat ascii 1.0\nelement vertex 2\nproperty flot x\nend_header\n");
        assert!(
            header.starts_with("bad.ply:4:") && header.contains("header line"),
            "{header}"
        );
        let binary = message(b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nend_header\n\0\0");
        assert!(
            binary.starts_with("bad.ply:7:1: ")
                && binary.contains("from byte 98) ends at byte 100"),
            "{binary}"
        );
    }

    #[test]
    fn a_quad_reads_and_writes_back_with_every_property() {
        let (model, source) = PlySource::parse(ASCII.as_bytes(), "q.ply").expect("read");
        assert_eq!(model.positions.len(), 4);
        assert_eq!(model.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        let same = source
            .write_deformed(&model, &model, |_| None)
            .expect("written");
        let (again, _) = PlySource::parse(&same, "q.ply").expect("reads back");
        assert_eq!(again, model);
        let text = String::from_utf8(same).expect("text");
        assert!(
            text.contains("comment made by hand") && text.contains("property uchar red"),
            "{text}"
        );

        let mut deformed = model.clone();
        deformed.positions[2] = [2.0, 1.0, 0.0];
        // A shear at vertex 2 turns its normal (0, 1, 0) to (−1, 1, 0)/√2.
        let shear = [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let out = source
            .write_deformed(&model, &deformed, |_| Some(shear))
            .expect("written");
        let (read, changed) = PlySource::parse(&out, "q.ply").expect("reads back");
        assert_eq!(read.positions, deformed.positions);
        let vertex = &changed.ply.payload["vertex"][2];
        let h = std::f32::consts::FRAC_1_SQRT_2;
        assert!(matches!(vertex["nx"], Property::Float(x) if (x + h).abs() < 1e-6));
        assert!(matches!(vertex["red"], Property::UChar(30)));
        assert_eq!(
            changed.ply.payload["vertex"][1],
            source.ply.payload["vertex"][1]
        );
    }

    #[test]
    fn malformed_files_are_refused() {
        for (text, needle) in [
            ("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n", "property \"y\""),
            ("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0\n3 0 1 2\n", "face 0"),
            ("not a ply\n", "not a PLY model"),
        ] {
            let e = PlySource::parse(text.as_bytes(), "bad.ply").expect_err(text);
            assert!(e.to_string().contains(needle), "{e}");
            assert!(e.to_string().starts_with("bad.ply:"), "{e}");
        }
    }
}
