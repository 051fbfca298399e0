//! Deforming a model (a triangle mesh or point cloud in `f64`) by a spline deformation `φ` of
//! the plane: every vertex `(x, y, z)` becomes `(φ(x, y), z)`.
//!
//! Models are read from Wavefront OBJ ([`load_model`], [`parse_model`]) and written back with
//! the same vertex numbering and topology ([`write_obj`]). The reader is a small one of its
//! own rather than `tobj`: `tobj` rejects 2D vertices (`v x y`), drops vertices used by no
//! face (so point clouds come back empty), renumbers vertices, and stores `f32` unless its
//! `use_f64` feature is on; a model's vertex numbers must survive the round trip so that
//! vertices reported outside the reference mesh can be found in the user's file.

use crate::eval::{FloatSpline, Locator};
use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// A model: vertex positions and triangles (0-based, possibly none for a point cloud).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Model {
    /// Vertex positions `(x, y, z)`; 2D files have `z = 0`.
    pub positions: Vec<[f64; 3]>,
    /// Triangles as vertex indices (polygons of the file fan-triangulated).
    pub triangles: Vec<[usize; 3]>,
}

/// A deformed model and the vertices that could not be deformed.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Deformed {
    /// The model with `(x, y)` of every vertex inside the reference mesh replaced by `φ(x, y)`;
    /// same vertex numbering and triangles.
    pub model: Model,
    /// Vertices outside the reference mesh (ascending). They keep their position; callers
    /// should report them rather than ship a silently half-deformed model.
    pub outside: Vec<usize>,
}

/// Why a model could not be read or deformed. Errors about files name the file.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// The file could not be read: missing, not a regular file, or too large.
    #[error("{path}: the model {reason}")]
    Input {
        /// The file.
        path: PathBuf,
        /// Why it was not read.
        reason: String,
    },
    /// The file has no vertices: it is not a model.
    #[error("{file}: the model has no vertices (no `v` lines)")]
    Empty {
        /// The file (or the name given to [`parse_model`]).
        file: String,
    },
    /// The OBJ text is malformed.
    #[error("{file}:{line}: {message}")]
    Parse {
        /// The file (or the name given to [`parse_model`]).
        file: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// [`deform_model`] needs a deformation of the plane (values with 2 coordinates).
    #[error("a model can only be deformed by a spline with 2 coordinates, this one has {dim}")]
    NotAPlaneDeformation {
        /// Coordinates of the spline's values.
        dim: usize,
    },
    /// The locator and the spline were built from meshes with different triangle counts.
    #[error(
        "the locator has {locator} triangles but the spline has {spline}: build both from the same mesh"
    )]
    MeshMismatch {
        /// Triangles of the locator.
        locator: usize,
        /// Triangles of the spline.
        spline: usize,
    },
}

/// Reads a model from an OBJ file of at most `limit` bytes (see [`parse_model`] for what is
/// understood). Only regular text files are read (see [`api::input`]).
pub fn load_model(path: &Path, limit: u64) -> Result<Model, ModelError> {
    let text =
        api::input::read_text_file(path, "model", limit).map_err(|e| match e.position() {
            Some((line, column)) => ModelError::Parse {
                file: path.display().to_string(),
                line,
                message: format!("column {column}: the model {}", e.reason()),
            },
            None => ModelError::Input {
                path: path.to_path_buf(),
                reason: e.reason(),
            },
        })?;
    parse_model(&text, &path.display().to_string())
}

/// Statements of the OBJ format that [`parse_model`] accepts without using them: the rest of
/// the format (texture coordinates, normals, groups, materials, free-form geometry). Any other
/// first word is an error, so that a file that is not OBJ at all (a run file, `/etc/passwd`)
/// is refused instead of read as an empty model.
const IGNORED_STATEMENTS: [&str; 31] = [
    "vt", "vn", "vp", "l", "p", "o", "g", "s", "mg", "mtllib", "usemtl", "maplib", "usemap",
    "cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm", "trim", "hole", "scrv", "sp",
    "end", "con", "lod", "bevel", "c_interp", "d_interp",
];

/// Reads a model from OBJ text; `file` names the source in errors.
///
/// * `v x y [z [w]]`: a vertex; a missing `z` is 0 (2D files), `w` divides `x y z`. Seven or
///   six numbers are read as `x y z` followed by a colour, which is ignored. Coordinates must
///   be finite.
/// * `f a b c ...`: a face; corners are `v`, `v/vt`, `v//vn` or `v/vt/vn` (only `v` is used),
///   1-based, negative meaning relative to the vertices defined so far. Faces with more than
///   three corners are fan-triangulated from their first corner. Indices may refer to vertices
///   defined later in the file and are checked at the end.
/// * The other statements of the format (`vt`, `vn`, `o`, `g`, `s`, `usemtl`, `mtllib`, `l`,
///   `p`, free-form geometry, see [`IGNORED_STATEMENTS`]) and comments are ignored, so a file
///   with vertices only is a point cloud. Any other statement is an error naming its line and
///   column, and so is a file without vertices.
pub fn parse_model(text: &str, file: &str) -> Result<Model, ModelError> {
    let error = |line: usize, message: String| ModelError::Parse {
        file: file.to_string(),
        line,
        message,
    };
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut positions: Vec<[f64; 3]> = Vec::new();
    // (line, corner indices 0-based but not yet range-checked)
    let mut faces: Vec<(usize, Vec<i64>)> = Vec::new();
    for (number, raw) in text.lines().enumerate() {
        let line = number + 1;
        let content = raw.split('#').next().unwrap_or("");
        let mut tokens = content.split_whitespace();
        match tokens.next() {
            Some("v") => {
                // At most 7 numbers (x y z and a colour with alpha); no allocation per line.
                let mut buffer = [0.0f64; 7];
                let mut found = 0;
                for tok in tokens {
                    let value = tok
                        .parse::<f64>()
                        .ok()
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| error(line, format!("invalid vertex coordinate {tok:?}")))?;
                    if found < buffer.len() {
                        buffer[found] = value;
                    }
                    found += 1;
                }
                let values: &[f64] = if found > buffer.len() {
                    &[]
                } else {
                    &buffer[..found]
                };
                let position = match values {
                    [x, y] => [*x, *y, 0.0],
                    [x, y, z] | [x, y, z, _, _, _] | [x, y, z, _, _, _, _] => [*x, *y, *z],
                    [x, y, z, w] => {
                        if *w == 0.0 {
                            return Err(error(line, "vertex weight w is 0".into()));
                        }
                        [x / w, y / w, z / w]
                    }
                    _ => {
                        return Err(error(
                            line,
                            format!(
                                "a vertex needs 2 to 4 coordinates (or x y z and a colour), got {found}"
                            ),
                        ))
                    }
                };
                positions.push(position);
            }
            Some("f") => {
                let defined = positions.len() as i64;
                let corners: Vec<i64> = tokens
                    .map(|tok| {
                        let index = tok.split('/').next().unwrap_or("");
                        match index.parse::<i64>() {
                            Ok(0) | Err(_) => Err(error(
                                line,
                                format!("invalid face corner {tok:?} (vertex indices start at 1)"),
                            )),
                            Ok(i) if i < 0 => Ok(defined + i),
                            Ok(i) => Ok(i - 1),
                        }
                    })
                    .collect::<Result<_, _>>()?;
                if corners.len() < 3 {
                    return Err(error(
                        line,
                        format!("a face needs at least 3 corners, got {}", corners.len()),
                    ));
                }
                faces.push((line, corners));
            }
            Some(keyword) if IGNORED_STATEMENTS.contains(&keyword) => {}
            Some(keyword) => {
                let column = content
                    .find(keyword)
                    .map_or(1, |at| content[..at].chars().count() + 1);
                let shown: String = keyword.chars().take(40).collect();
                return Err(error(
                    line,
                    format!(
                        "column {column}: {shown:?} is not an OBJ statement (this does not look like an OBJ model)"
                    ),
                ));
            }
            None => {}
        }
    }
    if positions.is_empty() {
        return Err(ModelError::Empty {
            file: file.to_string(),
        });
    }
    let count = positions.len();
    let mut triangles = Vec::new();
    for (line, corners) in faces {
        let mut vertices = Vec::with_capacity(corners.len());
        for c in corners {
            match usize::try_from(c) {
                Ok(v) if v < count => vertices.push(v),
                _ => {
                    return Err(error(
                        line,
                        format!(
                            "face refers to vertex {} but the file defines {count}",
                            if c < 0 { c } else { c + 1 }
                        ),
                    ))
                }
            }
        }
        for k in 1..vertices.len() - 1 {
            triangles.push([vertices[0], vertices[k], vertices[k + 1]]);
        }
    }
    Ok(Model {
        positions,
        triangles,
    })
}

/// Deforms a model by the plane deformation `spline` (values with 2 coordinates): `(x, y)`
/// of each vertex goes through `φ`, `z` is unchanged. Vertices outside the reference mesh (as
/// seen by `locator`, built from the spline's mesh) keep their position and are listed in
/// [`Deformed::outside`]. Allocates only the output.
///
/// `φ` is evaluated as the identity plus a displacement ([`FloatSpline::evaluate_point_into`];
/// [`FloatSpline::new`] measures 2-coordinate values from the identity): `x' = x + D̂_x`,
/// `y' = y + D̂_y`. A vertex in a triangle whose control points are all at their nominal
/// positions comes back bit-identical, so the identity deformation returns the model
/// unchanged; a moved vertex is within `u·|x'| + 1.01·K·M_x` of the exact `φ` at the rational
/// value of its `f64` coordinates (`u = 2^-53`; `K` and the largest displacement `M_x` of
/// the triangle's control points as stated at [`FloatSpline`]), an error proportional to the
/// displacement rather than to `|x|`.
pub fn deform_model(
    model: &Model,
    spline: &FloatSpline,
    locator: &Locator,
) -> Result<Deformed, ModelError> {
    if spline.dim() != 2 {
        return Err(ModelError::NotAPlaneDeformation { dim: spline.dim() });
    }
    if spline.triangle_count() != locator.triangle_count() {
        return Err(ModelError::MeshMismatch {
            locator: locator.triangle_count(),
            spline: spline.triangle_count(),
        });
    }
    let mut positions = Vec::with_capacity(model.positions.len());
    let mut outside = Vec::new();
    let mut xy = [0.0; 2];
    for (v, p) in model.positions.iter().enumerate() {
        if spline.evaluate_point_into(locator, [p[0], p[1]], &mut xy) {
            positions.push([xy[0], xy[1], p[2]]);
        } else {
            positions.push(*p);
            outside.push(v);
        }
    }
    Ok(Deformed {
        model: Model {
            positions,
            triangles: model.triangles.clone(),
        },
        outside,
    })
}

/// How many vertex numbers [`left_in_place_note`] lists before it summarises the rest.
const NOTE_LISTS: usize = 20;

/// A one-line note for the run report about model vertices a deformation left in place
/// (`where_` says why: "outside the reference mesh"). Vertex numbers are 0-based, as in the
/// reports; the first twenty are listed, the deformed OBJ's header lists them all. `None` when
/// no vertex was left in place.
pub fn left_in_place_note(vertices: &[usize], where_: &str) -> Option<String> {
    if vertices.is_empty() {
        return None;
    }
    let listed: Vec<String> = vertices
        .iter()
        .take(NOTE_LISTS)
        .map(|v| v.to_string())
        .collect();
    let more = vertices.len().saturating_sub(NOTE_LISTS);
    let tail = if more > 0 {
        format!(" and {more} more")
    } else {
        String::new()
    };
    let noun = if vertices.len() == 1 {
        "vertex"
    } else {
        "vertices"
    };
    Some(format!(
        "{} model {noun} {where_} left in place (0-based): {}{tail}",
        vertices.len(),
        listed.join(", ")
    ))
}

/// Formats a coordinate for OBJ output: the shortest decimal that reads back to the same
/// `f64` (Rust's `Display`), never in exponent form, with `-0` written as `0`. Deterministic.
fn number(out: &mut String, x: f64) {
    let x = if x == 0.0 { 0.0 } else { x };
    // Writing to a String cannot fail.
    let _ = write!(out, "{x}");
}

/// Writes a model as OBJ: a comment with the counts, `v x y z` per vertex (shortest decimals
/// that read back exactly, so [`parse_model`] returns the same model) and `f a b c` per
/// triangle, 1-based. Fails with [`io::ErrorKind::InvalidInput`] if a triangle refers to a
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

/// The output file name of a deformed model: `<stem>-deformed.obj` for the model at `path`
/// (`model-deformed.obj` when the path has no usable stem), so the deformed model lands in the
/// output directory next to the report, never over its input.
pub fn deformed_name(path: &str) -> String {
    let stem = Path::new(path)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .filter(|s| !s.is_empty() && !s.starts_with('.'))
        .unwrap_or_else(|| "model".into());
    format!("{stem}-deformed.obj")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spline::tests::grid;
    use crate::spline::Spline;
    use api::Rational;

    fn identity(spline: &Spline) -> Vec<Vec<Rational>> {
        spline.points().iter().map(|p| p.nominal.to_vec()).collect()
    }

    #[test]
    fn parses_2d_quads_negative_indices_and_colours() {
        let text = "# a 2D quad\nv 0 0\nv 1 0\nv 1 1 0 1 0 0\nv 0 1 0 2\nf -4/1 -3/2 -2//3 -1\n";
        let model = parse_model(text, "quad.obj").expect("model");
        assert_eq!(
            model.positions,
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 0.5, 0.0]
            ]
        );
        assert_eq!(model.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn malformed_files_name_file_and_line() {
        for (text, needle) in [
            ("v 0 0\nv 1 x\n", "bad.obj:2: invalid vertex coordinate"),
            ("v 0 0\nv 1 nan\n", "bad.obj:2: invalid vertex coordinate"),
            ("v 0\n", "bad.obj:1: a vertex needs"),
            (
                "v 1 2 3 4 5\n",
                "bad.obj:1: a vertex needs 2 to 4 coordinates (or x y z and a colour), got 5",
            ),
            (
                "v 1 2 3 4 5 6 7 8\n",
                "bad.obj:1: a vertex needs 2 to 4 coordinates (or x y z and a colour), got 8",
            ),
            ("v 0 0\nf 1 2\n", "bad.obj:2: a face needs at least 3"),
            (
                "v 0 0\nf 1 2 3\nv 1 1\n",
                "bad.obj:2: face refers to vertex 3",
            ),
            ("v 0 0\nf 0 1 1\n", "bad.obj:2: invalid face corner"),
            ("v 0 0\nf -3 1 1\n", "bad.obj:2: face refers to vertex -2"),
            ("v 0 0 0 0\n", "bad.obj:1: vertex weight"),
        ] {
            let e = parse_model(text, "bad.obj").expect_err(text);
            assert!(e.to_string().starts_with(needle), "{e}");
        }
    }

    #[test]
    fn notes_on_vertices_left_in_place() {
        assert_eq!(left_in_place_note(&[], "outside the reference mesh"), None);
        assert_eq!(
            left_in_place_note(&[1], "outside the reference mesh").as_deref(),
            Some("1 model vertex outside the reference mesh left in place (0-based): 1")
        );
        let many: Vec<usize> = (0..23).collect();
        let note = left_in_place_note(&many, "outside the reference mesh").expect("a note");
        assert!(note.starts_with("23 model vertices outside"), "{note}");
        assert!(
            note.ends_with(
                ": 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19 and 3 more"
            ),
            "{note}"
        );
    }

    #[test]
    fn identity_and_outside_vertices() {
        let spline = Spline::new(grid(2, true), 3, 1).expect("spline");
        let float = FloatSpline::new(&spline, &identity(&spline)).expect("float");
        let locator = Locator::new(spline.mesh());
        let model = Model {
            positions: vec![
                [1.5, 2.25, 7.0],
                [25.0, 5.0, 1.0],
                [20.0, 20.0, -1.0],
                [0.0, 0.0, 0.0],
            ],
            triangles: vec![[0, 1, 2]],
        };
        let deformed = deform_model(&model, &float, &locator).expect("deform");
        assert_eq!(deformed.outside, vec![1]);
        for (a, b) in deformed.model.positions.iter().zip(&model.positions) {
            for c in 0..3 {
                assert!((a[c] - b[c]).abs() <= 1e-12 * (1.0 + b[c].abs()));
            }
        }
        assert_eq!(deformed.model.positions[1], model.positions[1]);
        let scalar = FloatSpline::new(
            &spline,
            &vec![vec![Rational::from_integer(1.into())]; spline.points().len()],
        )
        .expect("float");
        assert!(matches!(
            deform_model(&model, &scalar, &locator),
            Err(ModelError::NotAPlaneDeformation { dim: 1 })
        ));
    }

    /// The unit roundoff `u = 2^-53`.
    const U: f64 = 1.0 / 9_007_199_254_740_992.0;

    /// `δ_β` of [`FloatSpline`]'s error bound for `p` in the triangle with these corners:
    /// `7u·h(2L + 3h)/A`.
    fn barycentric_error(corners: [[f64; 2]; 3], p: [f64; 2]) -> f64 {
        let [a, b, c] = corners;
        let length = |u: [f64; 2], v: [f64; 2]| (u[0] - v[0]).hypot(u[1] - v[1]);
        let h = length(a, b).max(length(b, c)).max(length(c, a));
        let area = ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs();
        let l = corners
            .iter()
            .chain(std::iter::once(&p))
            .flatten()
            .fold(0.0f64, |m, x| m.max(x.abs()));
        7.0 * U * h * (2.0 * l + 3.0 * h) / area
    }

    /// `K = (N + d + 5)·u + 9·d·δ_β` of [`FloatSpline`]'s error bound.
    fn factor(d: usize, delta: f64) -> f64 {
        let n = (d + 1) * (d + 2) / 2;
        (n + d + 5) as f64 * U + 9.0 * d as f64 * delta
    }

    /// The identity leaves every vertex bit-identical, awkward coordinates included (the
    /// nominal positions of this perturbed mesh have denominator 5, so they are not `f64`s);
    /// after a local edit, vertices in triangles whose control points did not move are
    /// bit-identical and the others agree with the exact `φ` within the stated bound.
    #[test]
    fn identity_and_local_edits_leave_unmoved_vertices_bit_identical() {
        use crate::eval::{evaluate_exact, locate_exact};
        use api::exact::{rational_from_f64, rational_to_f64};
        let spline = Spline::new(crate::mesh::grid(4, 5000, true), 5, 1).expect("spline");
        let nominal = identity(&spline);
        let locator = Locator::new(spline.mesh());
        let awkward = [
            0.1,
            246.5,
            1e-7,
            12345.678,
            0.0,
            20000.0,
            1.0 / 3.0,
            19999.999999999996,
            5e-324,
            7777.7777,
            4.531,
        ];
        let mut positions: Vec<[f64; 3]> = awkward
            .iter()
            .flat_map(|&x| awkward.iter().map(move |&y| [x, y, 0.1]))
            .collect();
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % 2_000_000_000) as f64 / 100_000.0
        };
        for _ in 0..600 {
            positions.push([next(), next(), next()]);
        }
        let model = Model {
            positions,
            triangles: Vec::new(),
        };
        let float = FloatSpline::new(&spline, &nominal).expect("float");
        let deformed = deform_model(&model, &float, &locator).expect("deform");
        assert!(deformed.outside.is_empty());
        for (image, p) in deformed.model.positions.iter().zip(&model.positions) {
            assert_eq!(image.map(f64::to_bits), p.map(f64::to_bits), "{p:?}");
        }
        // Move the control points near the corner (0, 0) by awkward amounts.
        let limit = Rational::from_integer(7000.into());
        let moved: Vec<Vec<Rational>> = spline
            .points()
            .iter()
            .enumerate()
            .map(|(i, point)| {
                let [x, y] = &point.nominal;
                if x + y < limit {
                    let i = i as i64;
                    vec![
                        x + Rational::new((i * 7 % 13 - 6).into(), 3.into()),
                        y + Rational::new((i * 5 % 11 - 5).into(), 7.into()),
                    ]
                } else {
                    vec![x.clone(), y.clone()]
                }
            })
            .collect();
        let float = FloatSpline::new(&spline, &moved).expect("float");
        let deformed = deform_model(&model, &float, &locator).expect("deform");
        let corners = |t: usize| {
            spline.mesh().triangles()[t].map(|v| {
                let p = &spline.mesh().vertices()[v];
                [rational_to_f64(&p[0]), rational_to_f64(&p[1])]
            })
        };
        let (mut far, mut near, mut worst) = (0, 0, 0.0f64);
        for (image, p) in deformed.model.positions.iter().zip(&model.positions) {
            assert_eq!(image[2].to_bits(), p[2].to_bits());
            let (t, _) = locator.locate([p[0], p[1]]).expect("inside");
            let unchanged = spline
                .triangle_points(t)
                .iter()
                .all(|&i| moved[i] == nominal[i]);
            assert_eq!(float.is_displaced(t), !unchanged);
            if unchanged {
                assert_eq!(image.map(f64::to_bits), p.map(f64::to_bits), "{p:?}");
                far += 1;
                continue;
            }
            near += 1;
            let exact_p = [p[0], p[1]].map(|c| rational_from_f64(c).expect("finite"));
            let (te, _) = locate_exact(spline.mesh(), &exact_p).expect("inside");
            let exact = evaluate_exact(&spline, &moved, &exact_p).expect("inside");
            let (mut m, mut delta) = ([0.0f64; 2], 0.0f64);
            for s in [t, te] {
                for &i in spline.triangle_points(s) {
                    for (c, mc) in m.iter_mut().enumerate() {
                        let d = rational_to_f64(&(&moved[i][c] - &nominal[i][c]));
                        *mc = mc.max(d.abs());
                    }
                }
                delta = delta.max(barycentric_error(corners(s), [p[0], p[1]]));
            }
            let k = factor(spline.degree(), delta);
            for c in 0..2 {
                let exact_c = &exact[c];
                let error = rational_from_f64(image[c]).expect("finite") - exact_c;
                let error = rational_to_f64(&error).abs();
                let bound = (U * rational_to_f64(exact_c).abs() + 1.01 * k * m[c]) * (1.0 + 1e-9);
                assert!(
                    error <= bound,
                    "{p:?} coordinate {c}: error {error:e} > {bound:e}"
                );
                worst = worst.max(error / bound);
            }
        }
        assert!(far > 100 && near > 100, "{far} far, {near} near");
        eprintln!("{near} moved vertices, largest error / bound {worst:.3}");
    }

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
