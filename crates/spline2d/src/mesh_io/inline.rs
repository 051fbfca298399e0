//! Building the reference mesh from data rather than a file: the inline form of a run file
//! ([`from_text`], coordinates as decimal text) and exact points from programs
//! ([`from_points`]). Errors name `vertex N` or `triangle N` instead of a line.

use super::error::{MeshErrorKind, Origins};
use super::validate::validate;
use super::{check_options, coordinate_name, snap, MeshError, MeshOptions, MeshRead};
use crate::mesh::Point;
use api::parse_rational;

/// Source name used in errors for [`from_text`].
const INLINE_SOURCE: &str = "inline mesh";
/// Source name used in errors for [`from_points`].
const POINTS_SOURCE: &str = "generated mesh";

/// Builds a mesh from the inline (RON) form: coordinates as text (read exactly with
/// [`api::parse_rational`]), triangles as 0-based vertex indices. Errors name `"vertex N"` or
/// `"triangle N"` instead of a line; `source_name` (e.g. `"inline mesh"` or a model's name) is
/// their source.
pub fn from_text(
    vertices: &[(String, String)],
    triangles: &[[usize; 3]],
    source_name: &str,
    options: &MeshOptions,
) -> Result<MeshRead, MeshError> {
    let source = if source_name.is_empty() {
        INLINE_SOURCE
    } else {
        source_name
    };
    check_options(options, source)?;
    let origins = Origins {
        source: source.to_string(),
        vertex_lines: Vec::new(),
        triangle_lines: Vec::new(),
    };
    let mut points = Vec::with_capacity(vertices.len());
    for (v, (x, y)) in vertices.iter().enumerate() {
        let read = |k: usize, text: &str| {
            parse_rational(text)
                .map(|value| snap(value, options))
                .map_err(|e| {
                    origins.error(
                        None,
                        Some(e.column),
                        Some(format!("vertex {v}")),
                        MeshErrorKind::InvalidNumber {
                            coordinate: coordinate_name(k),
                            text: text.to_string(),
                            message: e.message,
                        },
                    )
                })
        };
        let px = read(0, x)?;
        let py = read(1, y)?;
        points.push([px, py]);
    }
    validate(points, triangles.to_vec(), &origins, options)
}

/// Builds a mesh from exact points and 0-based triangles (generators, tests), with the same
/// validation and options as the file readers. Errors have the source `"generated mesh"`.
pub fn from_points(
    vertices: Vec<Point>,
    triangles: Vec<[usize; 3]>,
    options: &MeshOptions,
) -> Result<MeshRead, MeshError> {
    check_options(options, POINTS_SOURCE)?;
    let origins = Origins {
        source: POINTS_SOURCE.to_string(),
        vertex_lines: Vec::new(),
        triangle_lines: Vec::new(),
    };
    let vertices = vertices
        .into_iter()
        .map(|[x, y]| [snap(x, options), snap(y, options)])
        .collect();
    validate(vertices, triangles, &origins, options)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh_io::test_support::*;
    use crate::mesh_io::MeshWarning;

    #[test]
    fn inline_form() {
        let vertices: Vec<(String, String)> = [("0", "0"), ("1", "0"), ("1", "1"), ("0.5", "1")]
            .iter()
            .map(|(x, y)| (x.to_string(), y.to_string()))
            .collect();
        let read = ok(from_text(
            &vertices,
            &[[0, 1, 2], [0, 3, 2]],
            INLINE_SOURCE,
            &MeshOptions::default(),
        ));
        assert_eq!(read.mesh.vertices()[3], [q(1, 2), q(1, 1)]);
        assert_eq!(
            read.warnings,
            vec![MeshWarning::Flipped {
                triangle: 1,
                line: None
            }]
        );
        let mut bad = vertices.clone();
        bad[3].1 = "1.x".into();
        let e = err(from_text(
            &bad,
            &[[0, 1, 2]],
            INLINE_SOURCE,
            &MeshOptions::default(),
        ));
        assert_eq!(e.element.as_deref(), Some("vertex 3"));
        assert_eq!((e.line, e.column), (None, Some(3)));
        assert!(e
            .to_string()
            .starts_with("inline mesh: vertex 3 has an invalid y coordinate \"1.x\""));
        assert!(e.to_string().ends_with("(column 3)"));
        let e = err(from_text(
            &vertices,
            &[[0, 1, 2], [0, 1, 2]],
            INLINE_SOURCE,
            &MeshOptions::default(),
        ));
        assert_eq!(
            e.to_string(),
            "inline mesh: triangle 1 repeats triangle 0 (same vertices 0, 1, 2)"
        );
        let e = err(from_text(&vertices, &[], "", &MeshOptions::default()));
        assert_eq!(e.source, "inline mesh");
        assert_eq!(e.kind, MeshErrorKind::Empty);
    }
}
