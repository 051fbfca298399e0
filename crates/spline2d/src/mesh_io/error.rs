//! What the mesh readers report: the warnings a usable mesh may come with, the located errors
//! that stop a read, and where each element of a mesh came from (for those locations).

use std::fmt;

/// Something worth telling the user that does not stop the mesh from being used.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum MeshWarning {
    /// A vertex in no triangle. It is kept (so the numbering of the others does not change) and
    /// the spline ignores it.
    UnusedVertex {
        /// The vertex (0-based).
        vertex: usize,
        /// The line defining it, for OBJ input.
        line: Option<usize>,
    },
    /// A clockwise triangle that was reversed
    /// ([`OrientationPolicy::Fix`](super::OrientationPolicy::Fix)).
    Flipped {
        /// The triangle (0-based, after fan triangulation).
        triangle: usize,
        /// The line of its face, for OBJ input.
        line: Option<usize>,
    },
}

impl fmt::Display for MeshWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshWarning::UnusedVertex { vertex, line } => write!(
                f,
                "vertex {vertex}{} is in no triangle; it is kept but the spline ignores it",
                line_note(line)
            ),
            MeshWarning::Flipped { triangle, line } => write!(
                f,
                "triangle {triangle}{} was clockwise and has been flipped to counter-clockwise",
                line_note(line)
            ),
        }
    }
}

/// How many warnings of one kind are given one by one; the rest are counted
/// ([`summarize_warnings`]).
pub const WARNINGS_SHOWN: usize = 5;

/// The warnings of a mesh as lines for a report: each warning while a kind has at most
/// [`WARNINGS_SHOWN`]; beyond that, one line per kind with the count and the first few (a mesh
/// whose every face is reversed gives one line, not one per triangle).
pub fn summarize_warnings(warnings: &[MeshWarning]) -> Vec<String> {
    let flipped: Vec<&MeshWarning> = warnings
        .iter()
        .filter(|w| matches!(w, MeshWarning::Flipped { .. }))
        .collect();
    let unused: Vec<&MeshWarning> = warnings
        .iter()
        .filter(|w| matches!(w, MeshWarning::UnusedVertex { .. }))
        .collect();
    let mut lines = Vec::new();
    for (kind, what) in [
        (
            unused,
            "vertices are in no triangle; they are kept but the spline ignores them",
        ),
        (
            flipped,
            "triangles were clockwise and have been flipped to counter-clockwise",
        ),
    ] {
        if kind.len() <= WARNINGS_SHOWN {
            lines.extend(kind.iter().map(|w| w.to_string()));
            continue;
        }
        let first: Vec<String> = kind[..WARNINGS_SHOWN]
            .iter()
            .map(|w| match w {
                MeshWarning::UnusedVertex { vertex, line } => {
                    format!("vertex {vertex}{}", line_note(line))
                }
                MeshWarning::Flipped { triangle, line } => {
                    format!("triangle {triangle}{}", line_note(line))
                }
            })
            .collect();
        lines.push(format!(
            "{} {what}: {}, and {} more",
            kind.len(),
            first.join(", "),
            kind.len() - WARNINGS_SHOWN
        ));
    }
    lines
}

/// Why a mesh could not be read, and where.
///
/// Displayed as `source:line:column: element message`, leaving out the parts that are unknown,
/// e.g. `worm.obj:12: triangle 4 has zero area (vertices 3, 7, 9 are collinear)` or
/// `inline mesh: vertex 3 has an invalid y coordinate "1.x": expected ... (column 3)`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MeshError {
    /// The file name, `"inline mesh"` ([`from_text`](super::from_text)) or `"generated mesh"`
    /// ([`from_points`](super::from_points)).
    pub source: String,
    /// 1-based line, for OBJ input.
    pub line: Option<usize>,
    /// 1-based column (in characters) within the line, or within the coordinate text for
    /// [`from_text`](super::from_text).
    pub column: Option<usize>,
    /// The element at fault, e.g. `"triangle 4"`, `"vertex 3"` or `"face"`; when present, the
    /// message of [`MeshError::kind`] completes a sentence starting with it.
    pub element: Option<String>,
    /// What is wrong.
    pub kind: MeshErrorKind,
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.source)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(column) = self.column {
                write!(f, ":{column}")?;
            }
        }
        write!(f, ": ")?;
        if let Some(element) = &self.element {
            write!(f, "{element} ")?;
        }
        write!(f, "{}", self.kind)?;
        if let (None, Some(column)) = (self.line, self.column) {
            write!(f, " (column {column})")?;
        }
        Ok(())
    }
}

impl std::error::Error for MeshError {}

/// The problems a mesh reader detects. Variants whose message starts with a verb are always
/// reported with [`MeshError::element`] set (the message completes the sentence).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum MeshErrorKind {
    /// The file could not be read (missing, not a regular file, too large).
    #[error("{0}")]
    Io(String),
    /// Text that is not the expected OBJ syntax (or not UTF-8).
    #[error("{0}")]
    Syntax(String),
    /// A coordinate that is not a number (element: `vertex N`).
    #[error("has an invalid {coordinate} coordinate {text:?}: {message}")]
    InvalidNumber {
        /// Which coordinate: `x`, `y`, `z`, `w` or `number 5`, ...
        coordinate: String,
        /// The text as written.
        text: String,
        /// What was expected (from [`api::ParseRationalError`]).
        message: String,
    },
    /// [`MeshOptions::snap`](super::MeshOptions::snap) is zero or negative.
    #[error("the snap step must be positive, got {step}")]
    InvalidSnap {
        /// The step given, as `p` or `p/q`.
        step: String,
    },
    /// An OBJ face with fewer than three vertices (element: `face`).
    #[error("has only {count} vertices; a face needs at least 3")]
    TooFewVertices {
        /// Number of vertices of the face.
        count: usize,
    },
    /// A vertex index that names no vertex (element: `face` or `triangle N`).
    #[error("refers to vertex {index}, which does not exist ({hint})")]
    IndexOutOfRange {
        /// The index as written (1-based or negative for OBJ, 0-based otherwise).
        index: String,
        /// The valid range.
        hint: String,
    },
    /// A triangle using one vertex twice (element: `triangle N`).
    #[error("uses vertex {vertex} more than once")]
    RepeatedVertex {
        /// The repeated vertex (0-based).
        vertex: usize,
    },
    /// A triangle whose three vertices are collinear (element: `triangle N`).
    #[error("has zero area (vertices {} are collinear)", list(.vertices))]
    ZeroArea {
        /// Its vertices (0-based).
        vertices: [usize; 3],
    },
    /// A clockwise triangle under [`OrientationPolicy::Reject`](super::OrientationPolicy::Reject)
    /// (element: `triangle N`).
    #[error("is clockwise (vertices {}); the orientation policy rejects clockwise triangles", list(.vertices))]
    Clockwise {
        /// Its vertices (0-based), as given.
        vertices: [usize; 3],
    },
    /// A triangle with the same vertex set as an earlier one (element: `triangle N`).
    #[error("repeats triangle {first}{} (same vertices {})", line_note(.first_line), list(.vertices))]
    DuplicateTriangle {
        /// The earlier triangle.
        first: usize,
        /// The line of the earlier triangle, for OBJ input.
        first_line: Option<usize>,
        /// The shared vertices (0-based).
        vertices: [usize; 3],
    },
    /// An edge in more than two triangles (the location is the first triangle too many).
    #[error("edge ({a}, {b}) is shared by more than two triangles: {}", triangle_list(.triangles))]
    NonManifoldEdge {
        /// Smaller vertex of the edge.
        a: usize,
        /// Larger vertex of the edge.
        b: usize,
        /// Every triangle on the edge, with its line for OBJ input.
        triangles: Vec<(usize, Option<usize>)>,
    },
    /// Two (counter-clockwise) triangles traversing a shared edge in the same direction: they
    /// lie on the same side of it, so the mesh folds over itself (the location is the later one).
    #[error(
        "triangles {first} and {second} overlap across edge ({a}, {b}): both run from {from} to {to}{}",
        first_line_note(*.first, .first_line)
    )]
    Overlap {
        /// The earlier triangle.
        first: usize,
        /// The line of the earlier triangle, for OBJ input.
        first_line: Option<usize>,
        /// The later triangle.
        second: usize,
        /// Smaller vertex of the edge.
        a: usize,
        /// Larger vertex of the edge.
        b: usize,
        /// Start of the edge as both triangles traverse it.
        from: usize,
        /// End of the edge as both triangles traverse it.
        to: usize,
    },
    /// No triangles at all.
    #[error("the mesh has no triangles")]
    Empty,
}

fn line_note(line: &Option<usize>) -> String {
    match line {
        Some(l) => format!(" (line {l})"),
        None => String::new(),
    }
}

fn first_line_note(first: usize, line: &Option<usize>) -> String {
    match line {
        Some(l) => format!("; triangle {first} is on line {l}"),
        None => String::new(),
    }
}

fn list(vertices: &[usize; 3]) -> String {
    format!("{}, {}, {}", vertices[0], vertices[1], vertices[2])
}

fn triangle_list(triangles: &[(usize, Option<usize>)]) -> String {
    triangles
        .iter()
        .map(|(t, line)| format!("{t}{}", line_note(line)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Where the elements of a mesh came from, for error locations.
pub(super) struct Origins {
    /// The file name or the name of the inline source.
    pub(super) source: String,
    /// The line of each vertex, for OBJ input.
    pub(super) vertex_lines: Vec<Option<usize>>,
    /// The line of each triangle, for OBJ input.
    pub(super) triangle_lines: Vec<Option<usize>>,
}

impl Origins {
    pub(super) fn error(
        &self,
        line: Option<usize>,
        column: Option<usize>,
        element: Option<String>,
        kind: MeshErrorKind,
    ) -> MeshError {
        MeshError {
            source: self.source.clone(),
            line,
            column,
            element,
            kind,
        }
    }

    pub(super) fn triangle_line(&self, t: usize) -> Option<usize> {
        self.triangle_lines.get(t).copied().flatten()
    }

    pub(super) fn vertex_line(&self, v: usize) -> Option<usize> {
        self.vertex_lines.get(v).copied().flatten()
    }

    pub(super) fn triangle_error(&self, t: usize, kind: MeshErrorKind) -> MeshError {
        self.error(
            self.triangle_line(t),
            None,
            Some(format!("triangle {t}")),
            kind,
        )
    }
}

#[cfg(test)]
mod summary_tests {
    use super::*;

    #[test]
    fn many_warnings_of_a_kind_become_one_line() {
        let flipped: Vec<MeshWarning> = (0..1267)
            .map(|t| MeshWarning::Flipped {
                triangle: t,
                line: Some(t + 700),
            })
            .collect();
        let mut all = flipped.clone();
        all.push(MeshWarning::UnusedVertex {
            vertex: 3,
            line: Some(4),
        });
        let lines = summarize_warnings(&all);
        assert_eq!(lines.len(), 2, "{lines:?}");
        assert_eq!(lines[0], all[1267].to_string());
        assert!(
            lines[1].starts_with("1267 triangles were clockwise and have been flipped to counter-clockwise: triangle 0 (line 700), triangle 1 (line 701),"),
            "{}",
            lines[1]
        );
        assert!(
            lines[1].ends_with("triangle 4 (line 704), and 1262 more"),
            "{}",
            lines[1]
        );
        // Few warnings are given one by one.
        let few = summarize_warnings(&flipped[..WARNINGS_SHOWN]);
        assert_eq!(
            few,
            flipped[..WARNINGS_SHOWN]
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
        );
    }
}
