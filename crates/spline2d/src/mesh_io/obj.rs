//! Reading the reference mesh from Wavefront OBJ: a file ([`read_obj`]) or its text
//! ([`parse_obj`]), with every error located by line and column.

use super::error::{MeshErrorKind, Origins};
use super::validate::validate;
use super::{check_options, coordinate_name, snap, MeshError, MeshOptions, MeshRead};
use crate::mesh::Point;
use crate::obj_text::{statements, tokens, FaceCorner, IndexError};
use api::{parse_rational, Rational};
use std::path::Path;

/// Reads an OBJ file of at most `limit` bytes (see [`parse_obj`] for the accepted subset). A
/// file that is not a regular file, too large or binary, and I/O errors, are reported as
/// [`MeshError`]s naming the file; bytes that are not UTF-8 are refused where a number or a
/// keyword belongs, with their line and column, and accepted in comments.
pub fn read_obj(path: &Path, options: &MeshOptions, limit: u64) -> Result<MeshRead, MeshError> {
    let name = path.display().to_string();
    let text = api::input::read_text_file(path, "mesh", limit).map_err(|e| {
        let (line, column) = e.position().unzip();
        MeshError {
            source: name.clone(),
            line,
            column,
            element: None,
            kind: match e.position() {
                Some(_) => MeshErrorKind::Syntax(format!("the mesh {}", e.reason())),
                None => MeshErrorKind::Io(format!("the mesh {}", e.reason())),
            },
        }
    })?;
    parse_obj(&text, &name, options)
}

/// A face corner whose index is resolved to a 0-based vertex, or a positive index checked once
/// all vertices are known (OBJ allows faces to refer to vertices defined later).
struct Corner {
    vertex: usize,
    column: usize,
    text: String,
}

/// Parses OBJ text; `file_name` is used in errors only.
///
/// Accepted subset of Wavefront OBJ:
/// * `v x y [z [w]]`: a vertex; `x` and `y` are read exactly with [`api::parse_rational`]
///   (decimals, exponents, and also fractions like `1/3`); `z`, `w` (and any further numbers,
///   e.g. vertex colours) are ignored but must be numbers.
/// * `f i j k ...`: a face; each corner is `i`, `i/t`, `i//n` or `i/t/n` (texture and normal
///   indices are ignored). Indices are 1-based; a negative index is relative (`-1` is the last
///   vertex defined before the face). Positive indices may refer to vertices defined later.
///   A face with `n > 3` corners is **fan-triangulated** from its first corner:
///   `a b c d` gives triangles `a b c`, `a c d` (so non-convex polygons need care).
///   A face with fewer than 3 corners is an error.
/// * Comments (`#` to the end of the line), empty lines and every other statement (`vn`, `vt`,
///   `o`, `g`, `s`, `usemtl`, `mtllib`, `l`, `p`, ...) are ignored. Line continuations (`\`)
///   are not supported.
///
/// Errors carry the line and column (for a bad number, the column of the offending character).
pub fn parse_obj(
    text: &str,
    file_name: &str,
    options: &MeshOptions,
) -> Result<MeshRead, MeshError> {
    check_options(options, file_name)?;
    let mut origins = Origins {
        source: file_name.to_string(),
        vertex_lines: Vec::new(),
        triangle_lines: Vec::new(),
    };
    let mut vertices: Vec<Point> = Vec::new();
    let mut faces: Vec<(usize, Vec<Corner>)> = Vec::new();
    for (line_no, content) in statements(text) {
        let toks: Vec<(usize, &str)> = tokens(content).collect();
        let Some(&(_, keyword)) = toks.first() else {
            continue;
        };
        match keyword {
            "v" => {
                let vertex = vertices.len();
                let numbers = &toks[1..];
                if numbers.len() < 2 {
                    let column = numbers
                        .last()
                        .map_or(toks[0].0 + 1, |(c, t)| c + t.chars().count());
                    return Err(origins.error(
                        Some(line_no),
                        Some(column),
                        None,
                        MeshErrorKind::Syntax(format!(
                            "vertex {vertex} needs x and y coordinates, found {} number(s)",
                            numbers.len()
                        )),
                    ));
                }
                let mut xy: Vec<Rational> = Vec::with_capacity(2);
                for (k, &(column, token)) in numbers.iter().enumerate() {
                    let value = parse_rational(token).map_err(|e| {
                        origins.error(
                            Some(line_no),
                            Some(column + e.column.saturating_sub(1)),
                            Some(format!("vertex {vertex}")),
                            MeshErrorKind::InvalidNumber {
                                coordinate: coordinate_name(k),
                                text: token.to_string(),
                                message: e.message,
                            },
                        )
                    })?;
                    if k < 2 {
                        xy.push(snap(value, options));
                    }
                }
                let mut xy = xy.into_iter();
                if let (Some(x), Some(y)) = (xy.next(), xy.next()) {
                    vertices.push([x, y]);
                    origins.vertex_lines.push(Some(line_no));
                }
            }
            "f" => {
                let corners = &toks[1..];
                let mut face = Vec::with_capacity(corners.len());
                for &(column, token) in corners {
                    face.push(parse_corner(
                        &origins,
                        line_no,
                        column,
                        token,
                        vertices.len(),
                    )?);
                }
                if face.len() < 3 {
                    return Err(origins.error(
                        Some(line_no),
                        Some(toks[0].0),
                        Some("face".into()),
                        MeshErrorKind::TooFewVertices { count: face.len() },
                    ));
                }
                faces.push((line_no, face));
            }
            _ => {}
        }
    }
    let count = vertices.len();
    let mut triangles = Vec::new();
    for (line_no, face) in &faces {
        if let Some(bad) = face.iter().find(|c| c.vertex >= count) {
            let hint = if count == 0 {
                "the file defines no vertices".to_string()
            } else {
                format!("the file defines {count} vertices, numbered 1 to {count}")
            };
            return Err(origins.error(
                Some(*line_no),
                Some(bad.column),
                Some("face".into()),
                MeshErrorKind::IndexOutOfRange {
                    index: bad.text.clone(),
                    hint,
                },
            ));
        }
        for pair in face[1..].windows(2) {
            triangles.push([face[0].vertex, pair[0].vertex, pair[1].vertex]);
            origins.triangle_lines.push(Some(*line_no));
        }
    }
    validate(vertices, triangles, &origins, options)
}

/// Parses one face corner `i[/t[/n]]`; `defined` is the number of vertices so far.
fn parse_corner(
    origins: &Origins,
    line_no: usize,
    column: usize,
    token: &str,
    defined: usize,
) -> Result<Corner, MeshError> {
    let syntax = |message: String| {
        origins.error(
            Some(line_no),
            Some(column),
            None,
            MeshErrorKind::Syntax(message),
        )
    };
    let corner = FaceCorner::new(token);
    if !corner.references_are_integers() {
        return Err(syntax(format!(
            "invalid face corner {token:?}: expected i, i/t, i//n or i/t/n with integer indices"
        )));
    }
    let index_text = corner.index;
    let out_of_range = |hint: String| {
        origins.error(
            Some(line_no),
            Some(column),
            Some("face".into()),
            MeshErrorKind::IndexOutOfRange {
                index: index_text.to_string(),
                hint,
            },
        )
    };
    let before_the_first = || {
        out_of_range(format!(
            "only {defined} vertices are defined before this face"
        ))
    };
    let vertex = match corner.vertex(defined) {
        Err(IndexError::NotAnInteger) => {
            return Err(syntax(format!(
                "invalid vertex index {index_text:?} in face corner {token:?}"
            )))
        }
        Err(IndexError::Zero) => {
            return Err(out_of_range(
                "OBJ indices start at 1; -1 is the last vertex defined".into(),
            ))
        }
        Err(IndexError::TooLarge { negative: true }) => return Err(before_the_first()),
        // Too large for i64: certainly beyond the vertex count, reported once all are known.
        Err(IndexError::TooLarge { negative: false }) => usize::MAX,
        Ok(v) if v < 0 => return Err(before_the_first()),
        Ok(v) => usize::try_from(v).unwrap_or(usize::MAX),
    };
    Ok(Corner {
        vertex,
        column,
        text: index_text.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh_io::from_points;
    use crate::mesh_io::test_support::*;

    #[test]
    fn reads_a_square_with_comments_and_ignored_statements() {
        let text = "# square\nmtllib a.mtl\no square\n\nv 0 0 0\nv 1 0 0 1\nv 1 1 0\nv 0 1 0\n\
                    vn 0 0 1\nvt 0 0\ng g1\ns off\nusemtl m\nl 1 2\nf 1 2 3\nf 1 3 4 # second\n";
        let read = ok(obj(text));
        assert_eq!(read.mesh.vertices().len(), 4);
        assert_eq!(read.mesh.triangles(), &[[0, 1, 2], [0, 2, 3]]);
        assert!(read.warnings.is_empty());
    }

    #[test]
    fn coordinates_are_exact_decimals() {
        let text = "v 0.1 1e-3\nv 1 0\nv 0 7/3\nf 1 2 3\n";
        let read = ok(obj(text));
        assert_eq!(read.mesh.vertices()[0], [q(1, 10), q(1, 1000)]);
        assert_eq!(read.mesh.vertices()[2], [q(0, 1), q(7, 3)]);
    }

    #[test]
    fn corner_forms_and_negative_indices() {
        let text = format!("{SQUARE}vt 0 0\nvn 0 0 1\nf 1/1 2/1/1 3//1\nf -4 -2 -1\n");
        let read = ok(obj(&text));
        assert_eq!(read.mesh.triangles(), &[[0, 1, 2], [0, 2, 3]]);
        // Relative indices count the vertices defined so far.
        let text = "v 0 0\nv 1 0\nv 0 1\nf -3 -2 -1\nv 1 1\nf -3 -1 -2\n";
        let read = ok(obj(text));
        assert_eq!(read.mesh.triangles(), &[[0, 1, 2], [1, 3, 2]]);
        // Forward references with positive indices are allowed.
        let read = ok(obj("f 1 2 3\nv 0 0\nv 1 0\nv 0 1\n"));
        assert_eq!(read.mesh.triangles(), &[[0, 1, 2]]);
    }

    #[test]
    fn quads_and_polygons_are_fan_triangulated() {
        let read = ok(obj(&format!("{SQUARE}f 1 2 3 4\n")));
        assert_eq!(read.mesh.triangles(), &[[0, 1, 2], [0, 2, 3]]);
        let text = "v 0 0\nv 2 0\nv 3 1\nv 1 2\nv -1 1\nf 1 2 3 4 5\n";
        let read = ok(obj(text));
        assert_eq!(read.mesh.triangles(), &[[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
    }

    #[test]
    fn windows_line_endings_and_bom() {
        let text = "\u{feff}v 0 0\r\nv 1 0\r\nv 0 1\r\nf 1 2 3\r\n";
        let read = ok(obj(text));
        assert_eq!(read.mesh.triangles().len(), 1);
    }

    #[test]
    fn invalid_number_is_located() {
        let e = err(obj("v 0 0\nv 1   0.5x\n"));
        assert_eq!((e.line, e.column), (Some(2), Some(10)));
        assert_eq!(e.element.as_deref(), Some("vertex 1"));
        assert!(matches!(
            &e.kind,
            MeshErrorKind::InvalidNumber { coordinate, text, .. } if coordinate == "y" && text == "0.5x"
        ));
        assert!(e
            .to_string()
            .starts_with("test.obj:2:10: vertex 1 has an invalid y coordinate"));
        // z must be a number even though it is ignored.
        let e = err(obj("v 0 0 zed\n"));
        assert_eq!((e.line, e.column), (Some(1), Some(7)));
        assert!(
            matches!(&e.kind, MeshErrorKind::InvalidNumber { coordinate, .. } if coordinate == "z")
        );
        // NaN and infinities are not numbers here.
        assert!(err(obj("v nan 0\n"))
            .to_string()
            .contains("invalid x coordinate"));
    }

    #[test]
    fn syntax_errors_are_located() {
        let e = err(obj("v 1\n"));
        assert!(matches!(e.kind, MeshErrorKind::Syntax(_)));
        assert_eq!(e.line, Some(1));
        let e = err(obj(&format!("{SQUARE}f 1 x 3\n")));
        assert!(matches!(e.kind, MeshErrorKind::Syntax(_)));
        assert_eq!((e.line, e.column), (Some(5), Some(5)));
        let e = err(obj(&format!("{SQUARE}f 1 2/3/4/5 3\n")));
        assert!(matches!(e.kind, MeshErrorKind::Syntax(_)));
        let e = err(obj(&format!("{SQUARE}f 1 2/a 3\n")));
        assert!(matches!(e.kind, MeshErrorKind::Syntax(_)));
    }

    #[test]
    fn face_with_too_few_vertices() {
        let e = err(obj(&format!("{SQUARE}f 1 2\n")));
        assert_eq!(e.kind, MeshErrorKind::TooFewVertices { count: 2 });
        assert_eq!(
            e.to_string(),
            "test.obj:5:1: face has only 2 vertices; a face needs at least 3"
        );
    }

    #[test]
    fn out_of_range_indices() {
        let e = err(obj(&format!("{SQUARE}f 1 2 5\n")));
        assert!(matches!(&e.kind, MeshErrorKind::IndexOutOfRange { index, .. } if index == "5"));
        assert_eq!((e.line, e.column), (Some(5), Some(7)));
        let e = err(obj(&format!("{SQUARE}f 0 1 2\n")));
        assert!(matches!(&e.kind, MeshErrorKind::IndexOutOfRange { index, .. } if index == "0"));
        let e = err(obj(&format!("{SQUARE}f -5 -1 -2\n")));
        assert!(matches!(&e.kind, MeshErrorKind::IndexOutOfRange { index, .. } if index == "-5"));
        let e = err(obj(&format!("{SQUARE}f 1 2 99999999999999999999999\n")));
        assert!(matches!(e.kind, MeshErrorKind::IndexOutOfRange { .. }));
        let e = err(from_points(
            pts(&[(0, 0), (1, 0)]),
            vec![[0, 1, 2]],
            &MeshOptions::default(),
        ));
        assert_eq!(e.element.as_deref(), Some("triangle 0"));
        assert_eq!(
            e.to_string(),
            "generated mesh: triangle 0 refers to vertex 2, which does not exist \
             (vertices are numbered 0 to 1)"
        );
    }

    #[test]
    fn read_obj_reports_io_errors_with_the_file_name() {
        let path = Path::new("/nonexistent/dir/worm.obj");
        let e = err(read_obj(
            path,
            &MeshOptions::default(),
            api::input::DEFAULT_MAX_INPUT_BYTES,
        ));
        assert!(matches!(e.kind, MeshErrorKind::Io(_)));
        assert!(e
            .to_string()
            .starts_with("/nonexistent/dir/worm.obj: the mesh cannot be read:"));
        let dir = err(read_obj(
            Path::new("/"),
            &MeshOptions::default(),
            api::input::DEFAULT_MAX_INPUT_BYTES,
        ));
        assert_eq!(
            dir.to_string(),
            "/: the mesh must be a regular file, but this is a directory"
        );
    }
}
