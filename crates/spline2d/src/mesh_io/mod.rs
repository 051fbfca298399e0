//! Reading the reference mesh of a spline deformation: exact coordinates, validated topology,
//! and errors that say where the problem is.
//!
//! Three readers produce a [`MeshRead`] (a valid [`Mesh`] plus warnings):
//!
//! * [`read_obj`] / [`parse_obj`]: a subset of Wavefront OBJ (see [`parse_obj`]);
//! * [`from_text`]: the inline form of a RON model (coordinates as decimal text, 0-based
//!   triangles);
//! * [`from_points`]: meshes built by programs (generators, tests).
//!
//! Coordinates are read with [`api::parse_rational`], never through `f64`: `0.1` is exactly
//! `1/10`. Files written from floating point may carry noise (`0.30000000000000004`);
//! [`MeshOptions::snap`] rounds every coordinate to a grid to remove it.
//!
//! **Vertex numbers.** Vertices keep their original order and are numbered from 0 in the
//! resulting mesh and in every message (an OBJ vertex with index `k` is vertex `k - 1`), so models
//! and users can refer to them. Triangles are numbered from 0 in the order they are produced
//! (after fan triangulation of OBJ polygons).
//!
//! **Validation** (every reader): indices in range; no zero-area triangle (including a vertex
//! repeated within a triangle); no duplicate triangle (same vertices in any order); no edge in
//! more than two triangles; every triangle counter-clockwise (clockwise ones are flipped with a
//! warning, or rejected, see [`OrientationPolicy`]); two triangles sharing an edge traverse it in
//! opposite directions (otherwise they fold over each other); at least one triangle. Vertices in
//! no triangle are kept and reported as warnings. Overlaps between triangles that share no edge
//! are not detected.

// `MeshError` keeps its location fields and kind inline (a plain, matchable struct); it is built
// at most once per read, so the size of `Result<_, MeshError>` does not matter.
#![allow(clippy::result_large_err)]

mod error;
mod inline;
mod obj;
mod validate;

pub use error::{summarize_warnings, MeshError, MeshErrorKind, MeshWarning, WARNINGS_SHOWN};
pub use inline::{from_points, from_text};
pub use obj::{parse_obj, read_obj};

use crate::mesh::Mesh;
use api::{format_rational, Rational};
use num_traits::Signed;

/// How the readers treat the input beyond plain validation.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct MeshOptions {
    /// When `Some(step)` (`step > 0`), every coordinate is rounded to the nearest multiple of
    /// `step`, exactly, half-way cases away from zero. Meant for files whose coordinates carry
    /// float noise (`0.30000000000000004` with step `1/1000` becomes `3/10`). Validation runs on
    /// the snapped coordinates, so snapping that collapses a triangle is reported as zero area.
    pub snap: Option<Rational>,
    /// What to do with clockwise triangles.
    pub orientation: OrientationPolicy,
}

/// What the readers do with a clockwise triangle (the mesh stores counter-clockwise triangles
/// only, so that every triangle's barycentric coordinates and the smoothness conditions across
/// its edges have one consistent sign convention).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum OrientationPolicy {
    /// Reverse the triangle (swap its last two vertices) and report a [`MeshWarning::Flipped`].
    #[default]
    Fix,
    /// Report a [`MeshErrorKind::Clockwise`] error.
    Reject,
}

/// A validated mesh and the warnings met while reading it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MeshRead {
    /// The mesh: original vertex numbering, counter-clockwise triangles.
    pub mesh: Mesh,
    /// Things the reader repaired or that may be unintended, in the order found.
    pub warnings: Vec<MeshWarning>,
}

/// Checks the snap step (it must be positive).
fn check_options(options: &MeshOptions, source: &str) -> Result<(), MeshError> {
    match &options.snap {
        Some(step) if !step.is_positive() => Err(MeshError {
            source: source.to_string(),
            line: None,
            column: None,
            element: None,
            kind: MeshErrorKind::InvalidSnap {
                step: format_rational(step),
            },
        }),
        _ => Ok(()),
    }
}

/// Rounds `value` to the nearest multiple of the snap step, half-way cases away from zero.
fn snap(value: Rational, options: &MeshOptions) -> Rational {
    match &options.snap {
        Some(step) if step.is_positive() => (value / step).round() * step,
        _ => value,
    }
}

/// Name of the `k`-th (0-based) number of a vertex statement.
fn coordinate_name(k: usize) -> String {
    match k {
        0 => "x".into(),
        1 => "y".into(),
        2 => "z".into(),
        3 => "w".into(),
        _ => format!("number {}", k + 1),
    }
}

#[cfg(test)]
mod test_support {
    //! What the readers' tests share: exact numbers, unwrapping with the error shown, a square.
    use super::*;
    use crate::mesh::Point;

    pub(super) fn q(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    pub(super) fn ok(result: Result<MeshRead, MeshError>) -> MeshRead {
        match result {
            Ok(read) => read,
            Err(e) => panic!("unexpected error: {e}"),
        }
    }

    pub(super) fn err(result: Result<MeshRead, MeshError>) -> MeshError {
        match result {
            Ok(read) => panic!("expected an error, got {read:?}"),
            Err(e) => e,
        }
    }

    pub(super) fn obj(text: &str) -> Result<MeshRead, MeshError> {
        parse_obj(text, "test.obj", &MeshOptions::default())
    }

    pub(super) const SQUARE: &str = "v 0 0\nv 1 0\nv 1 1\nv 0 1\n";

    pub(super) fn pts(coords: &[(i64, i64)]) -> Vec<Point> {
        coords.iter().map(|&(x, y)| [q(x, 1), q(y, 1)]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh_io::test_support::*;

    #[test]
    fn snap_rounds_to_the_grid_ties_away_from_zero() {
        let options = MeshOptions {
            snap: Some(q(1, 1000)),
            ..MeshOptions::default()
        };
        let text = "v 0.30000000000000004 -0.0015\nv 1.0005 0\nv 0 1\nf 1 2 3\n";
        let read = ok(parse_obj(text, "noisy.obj", &options));
        assert_eq!(read.mesh.vertices()[0], [q(3, 10), q(-2, 1000)]);
        assert_eq!(read.mesh.vertices()[1][0], q(1001, 1000));
        let half = MeshOptions {
            snap: Some(q(1, 2)),
            ..MeshOptions::default()
        };
        let read = ok(from_points(
            vec![[q(1, 4), q(-1, 4)], [q(7, 3), q(0, 1)], [q(0, 1), q(5, 3)]],
            vec![[0, 1, 2]],
            &half,
        ));
        assert_eq!(read.mesh.vertices()[0], [q(1, 2), q(-1, 2)]);
        assert_eq!(read.mesh.vertices()[1], [q(5, 2), q(0, 1)]);
        assert_eq!(read.mesh.vertices()[2], [q(0, 1), q(3, 2)]);
        // Snapping that collapses a triangle is caught.
        let coarse = MeshOptions {
            snap: Some(q(1, 1)),
            ..MeshOptions::default()
        };
        let e = err(parse_obj(
            "v 0 0\nv 1 0\nv 0.2 0.3\nf 1 2 3\n",
            "c.obj",
            &coarse,
        ));
        assert!(matches!(e.kind, MeshErrorKind::ZeroArea { .. }));
        let bad = MeshOptions {
            snap: Some(q(-1, 2)),
            ..MeshOptions::default()
        };
        let e = err(parse_obj(SQUARE, "c.obj", &bad));
        assert_eq!(
            e.to_string(),
            "c.obj: the snap step must be positive, got -1/2"
        );
        assert!(matches!(
            err(from_points(
                vec![],
                vec![],
                &MeshOptions {
                    snap: Some(q(0, 1)),
                    ..MeshOptions::default()
                }
            ))
            .kind,
            MeshErrorKind::InvalidSnap { .. }
        ));
    }
}
