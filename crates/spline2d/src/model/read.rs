//! Reading a model from Wavefront OBJ into `f64` positions and triangles, keeping the file's
//! vertex numbering (point clouds included).

use super::{GltfSource, Model, ModelError, ObjSource, PlySource, StlSource};
use crate::obj_text::{statements, tokens, FaceCorner};
use std::path::Path;

/// Reads a model from an OBJ file of at most `limit` bytes (see [`parse_model`] for what is
/// understood). Only regular text files are read (see [`api::input`]).
pub fn load_model(path: &Path, limit: u64) -> Result<Model, ModelError> {
    let text = read_model_text(path, limit)?;
    parse_model(&text, &path.display().to_string())
}

/// A model file as read, for writing the deformed model back as the same file, in its format.
#[derive(Debug, Clone, PartialEq)]
pub enum ModelSource {
    /// Wavefront OBJ.
    Obj(ObjSource),
    /// STL, binary or ASCII.
    Stl(StlSource),
    /// PLY, ASCII or binary.
    Ply(PlySource),
    /// glTF 2.0, JSON or binary (GLB).
    Gltf(GltfSource),
}

impl ModelSource {
    /// The file again with the positions of `deformed` (the model read from it, deformed) and,
    /// for OBJ, its normals transformed by `jacobian(v)` (see [`ObjSource::write_deformed`]);
    /// an STL facet's normal is the deformed facet's own.
    pub fn write_deformed(
        &self,
        original: &Model,
        deformed: &Model,
        jacobian: impl Fn(usize) -> Option<[[f64; 3]; 3]>,
    ) -> Result<Vec<u8>, String> {
        match self {
            ModelSource::Obj(obj) => obj.write_deformed(original, deformed, jacobian),
            ModelSource::Stl(stl) => stl.write_deformed(original, deformed),
            ModelSource::Ply(ply) => ply.write_deformed(original, deformed, jacobian),
            ModelSource::Gltf(gltf) => gltf.write_deformed(original, deformed, jacobian),
        }
    }
}

/// Whether `path` names an STL file (extension `.stl`, any case).
pub fn is_stl(path: &Path) -> bool {
    has_extension(path, "stl")
}

/// Whether `path` names a PLY file (extension `.ply`, any case).
pub fn is_ply(path: &Path) -> bool {
    has_extension(path, "ply")
}

/// Whether `path` names a glTF file (extension `.gltf` or `.glb`, any case).
pub fn is_gltf(path: &Path) -> bool {
    has_extension(path, "gltf") || has_extension(path, "glb")
}

fn has_extension(path: &Path, extension: &str) -> bool {
    path.extension()
        .is_some_and(|e| e.to_string_lossy().eq_ignore_ascii_case(extension))
}

/// Reads a model of at most `limit` bytes in its format (STL for `.stl`, PLY for `.ply`, glTF
/// for `.gltf` and `.glb` — its external buffers beside it —, else OBJ, see
/// [`load_model`]) with the file itself, for writing the deformed model back as the same file
/// ([`ModelSource::write_deformed`]).
pub fn load_model_with_source(path: &Path, limit: u64) -> Result<(Model, ModelSource), ModelError> {
    let file = path.display().to_string();
    if is_stl(path) || is_ply(path) || is_gltf(path) {
        let bytes =
            api::input::read_regular_file(path, "model", limit).map_err(|e| ModelError::Input {
                path: path.to_path_buf(),
                reason: e.reason(),
            })?;
        if is_gltf(path) {
            let directory = path.parent().unwrap_or_else(|| Path::new("."));
            let (model, source) = GltfSource::parse(&bytes, &file, directory, limit)?;
            return Ok((model, ModelSource::Gltf(source)));
        }
        if is_ply(path) {
            let (model, source) = PlySource::parse(&bytes, &file)?;
            return Ok((model, ModelSource::Ply(source)));
        }
        let (model, source) = StlSource::parse(bytes, &file)?;
        return Ok((model, ModelSource::Stl(source)));
    }
    let text = read_model_text(path, limit)?;
    let model = parse_model(&text, &file)?;
    let source = ObjSource::parse(text, &file)?;
    Ok((model, ModelSource::Obj(source)))
}

/// The text of the model file at `path` (at most `limit` bytes).
fn read_model_text(path: &Path, limit: u64) -> Result<String, ModelError> {
    let text =
        api::input::read_text_file(path, "model", limit).map_err(|e| match e.position() {
            Some((line, column)) => ModelError::Parse {
                file: path.display().to_string(),
                line,
                column,
                message: format!("the model {}", e.reason()),
            },
            None => ModelError::Input {
                path: path.to_path_buf(),
                reason: e.reason(),
            },
        })?;
    Ok(text)
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
///   `p`, free-form geometry, see `IGNORED_STATEMENTS`) and comments are ignored, so a file
///   with vertices only is a point cloud. Any other statement is an error naming its line and
///   column, and so is a file without vertices.
pub fn parse_model(text: &str, file: &str) -> Result<Model, ModelError> {
    let error = |line: usize, column: usize, message: String| ModelError::Parse {
        file: file.to_string(),
        line,
        column,
        message,
    };
    let mut positions: Vec<[f64; 3]> = Vec::new();
    // (line, (column, corner index 0-based but not yet range-checked))
    let mut faces: Vec<(usize, Vec<(usize, i64)>)> = Vec::new();
    for (line, content) in statements(text) {
        let mut tokens = tokens(content);
        match tokens.next() {
            Some((_, "v")) => {
                // At most 7 numbers (x y z and a colour with alpha); no allocation per line.
                let mut buffer = [0.0f64; 7];
                let mut found = 0;
                for (column, tok) in tokens {
                    let value = tok
                        .parse::<f64>()
                        .ok()
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| {
                            // At the first character no number has (as the mesh reader points).
                            let at = tok
                                .chars()
                                .position(|c| !(c.is_ascii_digit() || "+-.eE".contains(c)))
                                .unwrap_or(0);
                            error(
                                line,
                                column + at,
                                format!("invalid vertex coordinate {tok:?}"),
                            )
                        })?;
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
                            return Err(error(line, 1, "vertex weight w is 0".into()));
                        }
                        [x / w, y / w, z / w]
                    }
                    _ => {
                        return Err(error(
                            line,
                            1,
                            format!(
                                "a vertex needs 2 to 4 coordinates (or x y z and a colour), got {found}"
                            ),
                        ))
                    }
                };
                positions.push(position);
            }
            Some((_, "f")) => {
                let defined = positions.len();
                let corners: Vec<(usize, i64)> = tokens
                    .map(|(column, tok)| {
                        let vertex = FaceCorner::new(tok).vertex(defined).map_err(|_| {
                            error(
                                line,
                                column,
                                format!("invalid face corner {tok:?} (vertex indices start at 1)"),
                            )
                        })?;
                        Ok((column, vertex))
                    })
                    .collect::<Result<_, _>>()?;
                if corners.len() < 3 {
                    return Err(error(
                        line,
                        1,
                        format!("a face needs at least 3 corners, got {}", corners.len()),
                    ));
                }
                faces.push((line, corners));
            }
            Some((_, keyword)) if IGNORED_STATEMENTS.contains(&keyword) => {}
            Some((column, keyword)) => {
                let shown: String = keyword.chars().take(40).collect();
                return Err(error(
                    line,
                    column,
                    format!(
                        "{shown:?} is not an OBJ statement (this does not look like an OBJ model)"
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
        for (column, c) in corners {
            match usize::try_from(c) {
                Ok(v) if v < count => vertices.push(v),
                _ => {
                    return Err(error(
                        line,
                        column,
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

#[cfg(test)]
mod tests {
    use super::*;

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
            ("v 0 0\nv 1 x\n", "bad.obj:2:5: invalid vertex coordinate"),
            ("v 0 0\nv 1 nan\n", "bad.obj:2:5: invalid vertex coordinate"),
            (
                "v 0 0\nv 1\u{fffd} 0\n",
                "bad.obj:2:4: invalid vertex coordinate",
            ),
            ("v 0\n", "bad.obj:1:1: a vertex needs"),
            (
                "v 1 2 3 4 5\n",
                "bad.obj:1:1: a vertex needs 2 to 4 coordinates (or x y z and a colour), got 5",
            ),
            (
                "v 1 2 3 4 5 6 7 8\n",
                "bad.obj:1:1: a vertex needs 2 to 4 coordinates (or x y z and a colour), got 8",
            ),
            ("v 0 0\nf 1 2\n", "bad.obj:2:1: a face needs at least 3"),
            (
                "v 0 0\nf 1 2 3\nv 1 1\n",
                "bad.obj:2:7: face refers to vertex 3",
            ),
            ("v 0 0\nf 0 1 1\n", "bad.obj:2:3: invalid face corner"),
            ("v 0 0\nf -3 1 1\n", "bad.obj:2:3: face refers to vertex -2"),
            ("v 0 0 0 0\n", "bad.obj:1:1: vertex weight"),
        ] {
            let e = parse_model(text, "bad.obj").expect_err(text);
            assert!(e.to_string().starts_with(needle), "{e}");
        }
    }
}
