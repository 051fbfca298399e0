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

use crate::mesh::{twice_area, Mesh, Point};
use api::{format_rational, parse_rational, Rational};
use num_traits::{Signed, Zero};
use std::collections::HashMap;
use std::fmt;
use std::path::Path;

/// Source name used in errors for [`from_text`].
const INLINE_SOURCE: &str = "inline mesh";
/// Source name used in errors for [`from_points`].
const POINTS_SOURCE: &str = "generated mesh";

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
    /// A clockwise triangle that was reversed ([`OrientationPolicy::Fix`]).
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

/// Why a mesh could not be read, and where.
///
/// Displayed as `source:line:column: element message`, leaving out the parts that are unknown,
/// e.g. `worm.obj:12: triangle 4 has zero area (vertices 3, 7, 9 are collinear)` or
/// `inline mesh: vertex 3 has an invalid y coordinate "1.x": expected ... (column 3)`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MeshError {
    /// The file name, `"inline mesh"` ([`from_text`]) or `"generated mesh"` ([`from_points`]).
    pub source: String,
    /// 1-based line, for OBJ input.
    pub line: Option<usize>,
    /// 1-based column (in characters) within the line, or within the coordinate text for
    /// [`from_text`].
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
    /// [`MeshOptions::snap`] is zero or negative.
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
    /// A clockwise triangle under [`OrientationPolicy::Reject`] (element: `triangle N`).
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
struct Origins {
    source: String,
    vertex_lines: Vec<Option<usize>>,
    triangle_lines: Vec<Option<usize>>,
}

impl Origins {
    fn error(
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

    fn triangle_line(&self, t: usize) -> Option<usize> {
        self.triangle_lines.get(t).copied().flatten()
    }

    fn vertex_line(&self, v: usize) -> Option<usize> {
        self.vertex_lines.get(v).copied().flatten()
    }

    fn triangle_error(&self, t: usize, kind: MeshErrorKind) -> MeshError {
        self.error(
            self.triangle_line(t),
            None,
            Some(format!("triangle {t}")),
            kind,
        )
    }
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

/// Whitespace-separated tokens of a line with their 1-based character columns.
fn tokens(line: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start: Option<(usize, usize)> = None; // (byte, column)
    let mut column = 0;
    for (byte, c) in line.char_indices() {
        column += 1;
        if c.is_whitespace() {
            if let Some((b, col)) = start.take() {
                out.push((col, &line[b..byte]));
            }
        } else if start.is_none() {
            start = Some((byte, column));
        }
    }
    if let Some((b, col)) = start {
        out.push((col, &line[b..]));
    }
    out
}

/// True for `[+-]digits`.
fn is_integer_text(text: &str) -> bool {
    let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
    !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit())
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
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut origins = Origins {
        source: file_name.to_string(),
        vertex_lines: Vec::new(),
        triangle_lines: Vec::new(),
    };
    let mut vertices: Vec<Point> = Vec::new();
    let mut faces: Vec<(usize, Vec<Corner>)> = Vec::new();
    for (number, raw_line) in text.lines().enumerate() {
        let line_no = number + 1;
        let content = match raw_line.find('#') {
            Some(hash) => &raw_line[..hash],
            None => raw_line,
        };
        let toks = tokens(content);
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
    let parts: Vec<&str> = token.split('/').collect();
    if parts.len() > 3
        || parts[1..]
            .iter()
            .any(|p| !p.is_empty() && !is_integer_text(p))
    {
        return Err(syntax(format!(
            "invalid face corner {token:?}: expected i, i/t, i//n or i/t/n with integer indices"
        )));
    }
    let index_text = parts[0];
    if !is_integer_text(index_text) {
        return Err(syntax(format!(
            "invalid vertex index {index_text:?} in face corner {token:?}"
        )));
    }
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
    let vertex = match index_text.parse::<i64>() {
        Ok(0) => {
            return Err(out_of_range(
                "OBJ indices start at 1; -1 is the last vertex defined".into(),
            ))
        }
        Ok(i) if i > 0 => usize::try_from(i - 1).unwrap_or(usize::MAX),
        Ok(i) => {
            let back = usize::try_from(i.unsigned_abs()).unwrap_or(usize::MAX);
            if back > defined {
                return Err(out_of_range(format!(
                    "only {defined} vertices are defined before this face"
                )));
            }
            defined - back
        }
        Err(_) if index_text.starts_with('-') => {
            return Err(out_of_range(format!(
                "only {defined} vertices are defined before this face"
            )))
        }
        // Too large for i64: certainly beyond the vertex count, reported once all are known.
        Err(_) => usize::MAX,
    };
    Ok(Corner {
        vertex,
        column,
        text: index_text.to_string(),
    })
}

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

/// Validates and orients the triangles, then builds the mesh (see the module documentation for
/// the checks and their order).
fn validate(
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
    let mut seen: HashMap<[usize; 3], usize> = HashMap::new();
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
        let area = twice_area(&vertices[a], &vertices[b], &vertices[c]);
        if area.is_zero() {
            return Err(origins.triangle_error(t, MeshErrorKind::ZeroArea { vertices: *tri }));
        }
        if area.is_negative() {
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

    // Directed edges `(triangle, from, to)` per undirected edge `(a, b)`, in triangle order.
    type Sides = Vec<(usize, usize, usize)>;
    let mut edges: HashMap<(usize, usize), Sides> = HashMap::new();
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (p, q) = (tri[k], tri[(k + 1) % 3]);
            edges
                .entry((p.min(q), p.max(q)))
                .or_default()
                .push((t, p, q));
        }
    }
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (p, q) = (tri[k], tri[(k + 1) % 3]);
            let (a, b) = (p.min(q), p.max(q));
            let Some(on_edge) = edges.get(&(a, b)) else {
                continue;
            };
            if on_edge.len() > 2 {
                let third = on_edge[2].0;
                return Err(origins.error(
                    origins.triangle_line(third),
                    None,
                    None,
                    MeshErrorKind::NonManifoldEdge {
                        a,
                        b,
                        triangles: on_edge
                            .iter()
                            .map(|&(s, _, _)| (s, origins.triangle_line(s)))
                            .collect(),
                    },
                ));
            }
            if let [(first, from, to), (second, _, _)] = on_edge[..] {
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

    fn q(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    fn ok(result: Result<MeshRead, MeshError>) -> MeshRead {
        match result {
            Ok(read) => read,
            Err(e) => panic!("unexpected error: {e}"),
        }
    }

    fn err(result: Result<MeshRead, MeshError>) -> MeshError {
        match result {
            Ok(read) => panic!("expected an error, got {read:?}"),
            Err(e) => e,
        }
    }

    fn obj(text: &str) -> Result<MeshRead, MeshError> {
        parse_obj(text, "test.obj", &MeshOptions::default())
    }

    const SQUARE: &str = "v 0 0\nv 1 0\nv 1 1\nv 0 1\n";

    fn pts(coords: &[(i64, i64)]) -> Vec<Point> {
        coords.iter().map(|&(x, y)| [q(x, 1), q(y, 1)]).collect()
    }

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

    #[test]
    fn tokens_have_character_columns() {
        assert_eq!(tokens("  é b\tc "), vec![(3, "é"), (5, "b"), (7, "c")]);
        assert!(tokens("   ").is_empty());
    }
}
