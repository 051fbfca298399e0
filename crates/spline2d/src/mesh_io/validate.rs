//! The checks every mesh reader runs on the triangles it read (indices, zero area, duplicates,
//! edges in more than two triangles, orientation, folds, unused vertices), in the order the
//! module documentation of [`crate::mesh_io`] gives.

use super::error::{MeshErrorKind, MeshWarning, Origins};
use super::{MeshError, MeshOptions, MeshRead, OrientationPolicy};
use crate::mesh::{orientation, Mesh, Point};
use std::collections::HashMap;

/// Validates and orients the triangles, then builds the mesh (see the module documentation for
/// the checks and their order).
pub(super) fn validate(
    vertices: Vec<Point>,
    mut triangles: Vec<[usize; 3]>,
    origins: &Origins,
    options: &MeshOptions,
) -> Result<MeshRead, MeshError> {
    if triangles.is_empty() {
        return Err(origins.error(None, None, None, MeshErrorKind::Empty));
    }
    let count = vertices.len();
    let mut warnings = Vec::new();
    // A fast hash with a random seed per process: the keys come from the user's file.
    let mut seen: HashMap<[usize; 3], usize, foldhash::fast::RandomState> =
        HashMap::with_capacity_and_hasher(triangles.len(), Default::default());
    for (t, tri) in triangles.iter_mut().enumerate() {
        if let Some(&bad) = tri.iter().find(|&&v| v >= count) {
            let hint = if count == 0 {
                "there are no vertices".to_string()
            } else {
                format!("vertices are numbered 0 to {}", count - 1)
            };
            return Err(origins.triangle_error(
                t,
                MeshErrorKind::IndexOutOfRange {
                    index: bad.to_string(),
                    hint,
                },
            ));
        }
        let [a, b, c] = *tri;
        if a == b || a == c {
            return Err(origins.triangle_error(t, MeshErrorKind::RepeatedVertex { vertex: a }));
        }
        if b == c {
            return Err(origins.triangle_error(t, MeshErrorKind::RepeatedVertex { vertex: b }));
        }
        let area = orientation(&vertices[a], &vertices[b], &vertices[c]);
        if area.is_eq() {
            return Err(origins.triangle_error(t, MeshErrorKind::ZeroArea { vertices: *tri }));
        }
        if area.is_lt() {
            match options.orientation {
                OrientationPolicy::Fix => {
                    *tri = [a, c, b];
                    warnings.push(MeshWarning::Flipped {
                        triangle: t,
                        line: origins.triangle_line(t),
                    });
                }
                OrientationPolicy::Reject => {
                    return Err(
                        origins.triangle_error(t, MeshErrorKind::Clockwise { vertices: *tri })
                    );
                }
            }
        }
        let mut key = *tri;
        key.sort_unstable();
        if let Some(&first) = seen.get(&key) {
            return Err(origins.triangle_error(
                t,
                MeshErrorKind::DuplicateTriangle {
                    first,
                    first_line: origins.triangle_line(first),
                    vertices: key,
                },
            ));
        }
        seen.insert(key, t);
    }

    // Directed sides `(a, b, triangle, from, to)` of the undirected edges `(a, b)`, sorted by
    // edge, then triangle: each edge's sides are a run in triangle order (a sort, not a map of
    // vectors: no allocation per edge, which at a whole mesh was most of the check's time).
    let mut sides: Vec<(usize, usize, usize, usize, usize)> =
        Vec::with_capacity(3 * triangles.len());
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (p, q) = (tri[k], tri[(k + 1) % 3]);
            sides.push((p.min(q), p.max(q), t, p, q));
        }
    }
    sides.sort_unstable();
    let on_edge_of = |a: usize, b: usize| {
        let from = sides.partition_point(|s| (s.0, s.1) < (a, b));
        let to = from + sides[from..].partition_point(|s| (s.0, s.1) == (a, b));
        &sides[from..to]
    };
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (p, q) = (tri[k], tri[(k + 1) % 3]);
            let (a, b) = (p.min(q), p.max(q));
            let on_edge = on_edge_of(a, b);
            if on_edge.len() > 2 {
                let third = on_edge[2].2;
                return Err(origins.error(
                    origins.triangle_line(third),
                    None,
                    None,
                    MeshErrorKind::NonManifoldEdge {
                        a,
                        b,
                        triangles: on_edge
                            .iter()
                            .map(|&(_, _, s, _, _)| (s, origins.triangle_line(s)))
                            .collect(),
                    },
                ));
            }
            if let [(_, _, first, from, to), (_, _, second, _, _)] = *on_edge {
                if second == t && (from, to) == (p, q) {
                    return Err(origins.error(
                        origins.triangle_line(t),
                        None,
                        None,
                        MeshErrorKind::Overlap {
                            first,
                            first_line: origins.triangle_line(first),
                            second: t,
                            a,
                            b,
                            from,
                            to,
                        },
                    ));
                }
            }
        }
    }

    let mut used = vec![false; count];
    for tri in &triangles {
        for &v in tri {
            used[v] = true;
        }
    }
    warnings.extend(used.iter().enumerate().filter(|(_, u)| !**u).map(|(v, _)| {
        MeshWarning::UnusedVertex {
            vertex: v,
            line: origins.vertex_line(v),
        }
    }));
    Ok(MeshRead {
        mesh: Mesh::from_validated(vertices, triangles),
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh_io::test_support::*;
    use crate::mesh_io::{from_points, parse_obj, MeshWarning, OrientationPolicy};

    #[test]
    fn zero_area_and_repeated_vertex() {
        let e = err(obj("v 0 0\nv 1 1\nv 2 2\nv 0 1\nf 1 2 4\nf 1 2 3\n"));
        assert_eq!(
            e.kind,
            MeshErrorKind::ZeroArea {
                vertices: [0, 1, 2]
            }
        );
        assert_eq!(e.line, Some(6));
        assert_eq!(
            e.to_string(),
            "test.obj:6: triangle 1 has zero area (vertices 0, 1, 2 are collinear)"
        );
        let e = err(obj(&format!("{SQUARE}f 1 2 2\n")));
        assert_eq!(e.kind, MeshErrorKind::RepeatedVertex { vertex: 1 });
        let e = err(from_points(
            pts(&[(0, 0), (1, 0), (0, 1)]),
            vec![[2, 0, 2]],
            &MeshOptions::default(),
        ));
        assert_eq!(e.kind, MeshErrorKind::RepeatedVertex { vertex: 2 });
    }

    #[test]
    fn duplicate_triangles_in_any_order() {
        let e = err(obj(&format!("{SQUARE}f 1 2 3\nf 1 3 4\nf 3 1 2\n")));
        assert_eq!(
            e.kind,
            MeshErrorKind::DuplicateTriangle {
                first: 0,
                first_line: Some(5),
                vertices: [0, 1, 2]
            }
        );
        assert_eq!(e.element.as_deref(), Some("triangle 2"));
        // Reversed orientation: flipped first, then found equal.
        let e = err(obj(&format!("{SQUARE}f 1 2 3\nf 3 2 1\n")));
        assert!(matches!(
            e.kind,
            MeshErrorKind::DuplicateTriangle { first: 0, .. }
        ));
    }

    #[test]
    fn edge_in_three_triangles() {
        // Edge 0-1 with triangles above, and two more fanning below at different depths.
        let text = "v 0 0\nv 2 0\nv 1 1\nv 1 -1\nv 1 -2\nf 1 2 3\nf 2 1 4\nf 2 1 5\n";
        let e = err(obj(text));
        match &e.kind {
            MeshErrorKind::NonManifoldEdge { a, b, triangles } => {
                assert_eq!((*a, *b), (0, 1));
                assert_eq!(triangles, &vec![(0, Some(6)), (1, Some(7)), (2, Some(8))]);
            }
            other => panic!("unexpected {other:?}"),
        }
        assert_eq!(e.line, Some(8));
        assert!(e
            .to_string()
            .contains("edge (0, 1) is shared by more than two triangles"));
    }

    #[test]
    fn folded_triangles_overlap() {
        // Both triangles lie above edge 0-1, both counter-clockwise.
        let e = err(obj("v 0 0\nv 2 0\nv 1 1\nv 1 2\nf 1 2 3\nf 1 2 4\n"));
        assert!(matches!(
            e.kind,
            MeshErrorKind::Overlap {
                first: 0,
                second: 1,
                a: 0,
                b: 1,
                from: 0,
                to: 1,
                ..
            }
        ));
        assert!(e
            .to_string()
            .starts_with("test.obj:6: triangles 0 and 1 overlap across edge (0, 1)"));
    }

    #[test]
    fn empty_mesh() {
        let e = err(obj(SQUARE));
        assert_eq!(e.kind, MeshErrorKind::Empty);
        assert_eq!(e.to_string(), "test.obj: the mesh has no triangles");
        assert_eq!(err(obj("")).kind, MeshErrorKind::Empty);
    }

    #[test]
    fn unused_vertices_are_warnings() {
        let read = ok(obj("v 0 0\nv 5 5\nv 1 0\nv 0 1\nf 1 3 4\n"));
        assert_eq!(
            read.warnings,
            vec![MeshWarning::UnusedVertex {
                vertex: 1,
                line: Some(2)
            }]
        );
        assert_eq!(read.mesh.vertices().len(), 4);
        assert_eq!(read.mesh.triangles(), &[[0, 2, 3]]);
        assert_eq!(
            read.warnings[0].to_string(),
            "vertex 1 (line 2) is in no triangle; it is kept but the spline ignores it"
        );
    }

    #[test]
    fn flip_or_reject_clockwise_triangles() {
        let text = format!("{SQUARE}f 1 2 3\nf 1 4 3\n");
        let read = ok(obj(&text));
        assert_eq!(read.mesh.triangles(), &[[0, 1, 2], [0, 2, 3]]);
        assert_eq!(
            read.warnings,
            vec![MeshWarning::Flipped {
                triangle: 1,
                line: Some(6)
            }]
        );
        assert_eq!(
            read.warnings[0].to_string(),
            "triangle 1 (line 6) was clockwise and has been flipped to counter-clockwise"
        );
        let reject = MeshOptions {
            orientation: OrientationPolicy::Reject,
            ..MeshOptions::default()
        };
        let e = err(parse_obj(&text, "test.obj", &reject));
        assert_eq!(
            e.kind,
            MeshErrorKind::Clockwise {
                vertices: [0, 3, 2]
            }
        );
        assert_eq!(e.element.as_deref(), Some("triangle 1"));
    }
}
