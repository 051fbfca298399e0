//! A deformed model written back as *the same OBJ file*: every line, comment, texture
//! coordinate, material, group and polygon kept as the user wrote it; only what the
//! deformation moves is written again.
//!
//! * A vertex whose position did not change keeps its line byte for byte (`3138` stays
//!   `3138`); a moved vertex's line becomes `v x y z` with the shortest decimals that read back
//!   to the deformed `f64` values, followed by its colour as written (a 2D vertex stays 2D; a
//!   weighted vertex `v x y z w` is written as the point `x/w y/w z/w`).
//! * A normal is a covector: under a deformation `ψ` with Jacobian `J` it becomes `J^{−T} n`
//!   (the inverse transpose), rescaled to its old length. A `vn` used only at vertices that
//!   give it the same new value is changed in place; when the vertices that share it move
//!   differently, the first keeps it and each other new value is a `vn` appended at the end of
//!   the file, the face corners that use it pointing there (their other indices as written).
//!   Normals at vertices the deformation leaves in place are untouched.
//! * Everything else — `vt`, `mtllib`, `usemtl`, `o`, `g`, `s`, quads and polygons, index
//!   forms `v/vt/vn` with negative indices, line endings — is copied.

use super::{Model, ModelError};
use crate::obj_text::{statements, tokens, FaceCorner};
use std::collections::HashMap;
use std::fmt::Write as _;
use std::ops::Range;

/// A face corner that names a normal.
#[derive(Debug, Clone, PartialEq)]
struct NormalCorner {
    /// The corner token's bytes in the text.
    token: Range<usize>,
    /// Its vertex (0-based).
    vertex: usize,
    /// Its normal (0-based).
    normal: usize,
}

/// The text of an OBJ model as read, and where its vertices, normals and normal-carrying face
/// corners are in it.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjSource {
    text: String,
    /// The statement (the line without its comment) of each vertex, in vertex order.
    vertices: Vec<Range<usize>>,
    /// Each `vn`: its statement and value.
    normals: Vec<(Range<usize>, [f64; 3])>,
    corners: Vec<NormalCorner>,
}

/// The byte range of `part`, a slice of `text`, in `text`.
fn range_in(text: &str, part: &str) -> Range<usize> {
    let start = part.as_ptr() as usize - text.as_ptr() as usize;
    start..start + part.len()
}

impl ObjSource {
    /// Reads where things are in `text`, an OBJ file that [`super::parse_model`] accepted
    /// (`file` names it in errors).
    pub fn parse(text: String, file: &str) -> Result<ObjSource, ModelError> {
        let error = |line: usize, column: usize, message: String| ModelError::Parse {
            file: file.to_string(),
            line,
            column,
            message,
        };
        let mut vertices = Vec::new();
        let mut normals = Vec::new();
        let mut corners = Vec::new();
        for (line, statement) in statements(&text) {
            // Trailing spaces before a comment stay where they are.
            let statement = statement.trim_end();
            let mut words = tokens(statement);
            match words.next() {
                Some((_, "v")) => vertices.push(range_in(&text, statement)),
                Some((_, "vn")) => {
                    let mut value = [0.0; 3];
                    let mut count = 0;
                    for (column, word) in words {
                        let x = word.parse::<f64>().ok().filter(|x| x.is_finite());
                        match (x, value.get_mut(count)) {
                            (Some(x), Some(slot)) => *slot = x,
                            _ => {
                                return Err(error(
                                    line,
                                    column,
                                    format!("invalid normal coordinate {word:?}"),
                                ))
                            }
                        }
                        count += 1;
                    }
                    if count != 3 {
                        return Err(error(
                            line,
                            1,
                            format!("a normal needs 3 coordinates, got {count}"),
                        ));
                    }
                    normals.push((range_in(&text, statement), value));
                }
                Some((_, "f")) => {
                    for (column, word) in words {
                        let corner = FaceCorner::new(word);
                        let Some(normal) = corner.normal_index(normals.len()) else {
                            continue;
                        };
                        let vertex = corner
                            .vertex(vertices.len())
                            .ok()
                            .and_then(|v| usize::try_from(v).ok());
                        match (vertex, normal) {
                            (Some(vertex), Ok(normal)) => corners.push(NormalCorner {
                                token: range_in(&text, word),
                                vertex,
                                normal,
                            }),
                            _ => {
                                return Err(error(
                                    line,
                                    column,
                                    format!("invalid face corner {word:?}"),
                                ))
                            }
                        }
                    }
                }
                _ => {}
            }
        }
        if let Some(c) = corners
            .iter()
            .find(|c| c.normal >= normals.len() || c.vertex >= vertices.len())
        {
            let before = &text[..c.token.start];
            return Err(ModelError::Parse {
                file: file.to_string(),
                line: before.matches('\n').count() + 1,
                column: before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1,
                message: format!(
                    "face corner {:?} refers to a vertex or normal the file does not define",
                    &text[c.token.clone()]
                ),
            });
        }
        Ok(ObjSource {
            text,
            vertices,
            normals,
            corners,
        })
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.vertices.len()
    }

    /// The file again with the positions of `deformed` (the model read from this file,
    /// deformed: same vertices) and the normals transformed by `jacobian(v)`, the Jacobian of
    /// the deformation at vertex `v` (row `r`, column `c`: `∂ψ_r/∂x_c`; `None` for a vertex
    /// left in place). See the module documentation.
    pub fn write_deformed(
        &self,
        original: &Model,
        deformed: &Model,
        jacobian: impl Fn(usize) -> Option<[[f64; 3]; 3]>,
    ) -> Result<Vec<u8>, String> {
        let count = self.vertices.len();
        if original.positions.len() != count || deformed.positions.len() != count {
            return Err(format!(
                "the model has {} and {} vertices, its file {count}",
                original.positions.len(),
                deformed.positions.len()
            ));
        }
        let mut edits: Vec<(Range<usize>, String)> = Vec::new();
        for (v, range) in self.vertices.iter().enumerate() {
            let (old, new) = (original.positions[v], deformed.positions[v]);
            if old == new {
                continue;
            }
            if new.iter().any(|x| !x.is_finite()) {
                return Err(format!("vertex {v} has a coordinate that is not finite"));
            }
            edits.push((range.clone(), self.vertex_line(range, new)));
        }
        let appended = self.transform_normals(original, deformed, &jacobian, &mut edits);
        edits.sort_by_key(|(range, _)| range.start);
        let mut out = String::with_capacity(self.text.len() + 64 * appended.len());
        let mut at = 0;
        for (range, replacement) in &edits {
            out.push_str(&self.text[at..range.start]);
            out.push_str(replacement);
            at = range.end;
        }
        out.push_str(&self.text[at..]);
        if !appended.is_empty() {
            if !out.ends_with('\n') {
                out.push('\n');
            }
            out.push_str(
                "# normals of vertices that shared a normal with vertices deformed differently\n",
            );
            for n in &appended {
                out.push_str(&vector_line("vn", n));
                out.push('\n');
            }
        }
        Ok(out.into_bytes())
    }

    /// A moved vertex's statement: `v x y [z]` and the colour as written.
    fn vertex_line(&self, range: &Range<usize>, p: [f64; 3]) -> String {
        let words: Vec<&str> = tokens(&self.text[range.clone()])
            .map(|(_, w)| w)
            .skip(1)
            .collect();
        let leading = &self.text[range.start..]
            [..self.text[range.clone()].len() - self.text[range.clone()].trim_start().len()];
        let mut line = String::from(leading);
        match words.len() {
            2 => line.push_str(&vector_line("v", &p[..2])),
            6 | 7 => {
                line.push_str(&vector_line("v", &p));
                for colour in &words[3..] {
                    line.push(' ');
                    line.push_str(colour);
                }
            }
            _ => line.push_str(&vector_line("v", &p)),
        }
        line
    }

    /// The normals' edits: `vn` statements changed in place, face corners pointing at
    /// appended normals; returns the appended normals.
    fn transform_normals(
        &self,
        original: &Model,
        deformed: &Model,
        jacobian: &impl Fn(usize) -> Option<[[f64; 3]; 3]>,
        edits: &mut Vec<(Range<usize>, String)>,
    ) -> Vec<[f64; 3]> {
        // The normal each (vertex, normal) pair gets, computed once per pair.
        let mut pairs: HashMap<(usize, usize), Option<[f64; 3]>> = HashMap::new();
        // Per normal: the value it is given in place (None: unchanged so far).
        let mut in_place: Vec<Option<[f64; 3]>> = vec![None; self.normals.len()];
        let mut claimed = vec![false; self.normals.len()];
        let mut appended: Vec<[f64; 3]> = Vec::new();
        let mut appended_index: HashMap<[u64; 3], usize> = HashMap::new();
        for corner in &self.corners {
            let (v, k) = (corner.vertex, corner.normal);
            let n = self.normals[k].1;
            let moved = original.positions[v] != deformed.positions[v];
            let new = *pairs.entry((v, k)).or_insert_with(|| {
                if moved {
                    jacobian(v).and_then(|j| super::matrix3::transform_normal(&j, n))
                } else {
                    None
                }
            });
            // What this corner's normal must be.
            let wanted = new.unwrap_or(n);
            let current = in_place[k].unwrap_or(n);
            if !claimed[k] {
                claimed[k] = true;
                if wanted != n {
                    in_place[k] = Some(wanted);
                }
                continue;
            }
            if wanted == current {
                continue;
            }
            let key = wanted.map(f64::to_bits);
            let index = *appended_index.entry(key).or_insert_with(|| {
                appended.push(wanted);
                self.normals.len() + appended.len() - 1
            });
            edits.push((
                corner.token.clone(),
                corner_with_normal(&self.text[corner.token.clone()], index + 1),
            ));
        }
        for (k, value) in in_place.iter().enumerate() {
            if let Some(value) = value {
                let range = self.normals[k].0.clone();
                let statement = &self.text[range.clone()];
                let leading = &statement[..statement.len() - statement.trim_start().len()];
                edits.push((range, format!("{leading}{}", vector_line("vn", value))));
            }
        }
        appended
    }
}

/// `word a b …` with the shortest decimals that read back exactly (`-0` written `0`).
fn vector_line(word: &str, values: &[f64]) -> String {
    let mut line = String::from(word);
    for &x in values {
        let x = if x == 0.0 { 0.0 } else { x };
        let _ = write!(line, " {x}");
    }
    line
}

/// A face corner `v/vt/vn` (or `v//vn`) with its normal index replaced by `index` (1-based).
fn corner_with_normal(token: &str, index: usize) -> String {
    match token.rsplit_once('/') {
        Some((head, _)) => format!("{head}/{index}"),
        None => token.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::parse_model;

    const TEXTURED: &str = "# a textured quad\r\nmtllib quad.mtl\r\no quad\r\nv 0 0 0\r\nv 3138 0 0 # far\r\nv 1 1 0 0.5 0.5 0.5\r\nv 0 1 0\r\nvt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvt 0 1\r\nvn 0 0 1\r\nusemtl skin\r\ns 1\r\nf 1/1/1 2/2/1 3/3/1 4/4/1\r\n";

    fn source(text: &str) -> (ObjSource, Model) {
        let model = parse_model(text, "m.obj").expect("model");
        (
            ObjSource::parse(text.to_string(), "m.obj").expect("source"),
            model,
        )
    }

    #[test]
    fn an_unmoved_model_is_written_back_byte_for_byte() {
        let (source, model) = source(TEXTURED);
        let out = source
            .write_deformed(&model, &model, |_| None)
            .expect("written");
        assert_eq!(String::from_utf8(out).expect("text"), TEXTURED);
    }

    #[test]
    fn moved_vertices_change_and_everything_else_stays() {
        let (source, model) = source(TEXTURED);
        let mut deformed = model.clone();
        deformed.positions[2] = [1.5, 0.25, 0.0];
        deformed.positions[0] = [-0.0, 0.1, 0.0];
        // A shear in x: J = [[1, 1, 0], [0, 1, 0], [0, 0, 1]]; (0, 0, 1) stays (0, 0, 1).
        let shear = [[1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let out = source
            .write_deformed(&model, &deformed, |_| Some(shear))
            .expect("written");
        let text = String::from_utf8(out).expect("text");
        assert_eq!(
            text,
            TEXTURED
                .replace("v 0 0 0\r\n", "v 0 0.1 0\r\n")
                .replace("v 1 1 0 0.5 0.5 0.5", "v 1.5 0.25 0 0.5 0.5 0.5")
        );
        assert_eq!(
            parse_model(&text, "m.obj").expect("reads").positions,
            deformed.positions
        );
    }

    #[test]
    fn normals_are_transformed_by_the_inverse_transpose_and_split_when_shared() {
        // Two triangles sharing the normal (0, 1, 0) at every corner; only vertex 1 moves.
        let text = "v 0 0\nv 1 0\nv 0 1\nv 1 1\nvn 0 1 0\nf 1//1 2//1 3//1\nf 2//1 4//1 3//1\n";
        let (source, model) = source(text);
        let mut deformed = model.clone();
        deformed.positions[1] = [2.0, 0.0, 0.0];
        // A stretch by 2 along x at vertex 1: a normal along y keeps its direction…
        let stretch = [[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let out = source
            .write_deformed(&model, &deformed, |_| Some(stretch))
            .expect("written");
        assert_eq!(
            String::from_utf8(out).expect("text"),
            "v 0 0\nv 2 0\nv 0 1\nv 1 1\nvn 0 1 0\nf 1//1 2//1 3//1\nf 2//1 4//1 3//1\n"
        );
        // …a shear turns it: (0, 1, 0) under J = [[1, 0, 0], [1, 1, 0], [0, 0, 1]] becomes
        // J^{-T} (0, 1, 0) = (−1, 1, 0), rescaled to length 1. Vertex 1 takes the new normal;
        // the others keep the old one: it is appended and their corners point there.
        let shear = [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let out = source
            .write_deformed(&model, &deformed, |_| Some(shear))
            .expect("written");
        let text = String::from_utf8(out).expect("text");
        let (head, last) = text.trim_end().rsplit_once('\n').expect("lines");
        assert_eq!(
            head,
            "v 0 0\nv 2 0\nv 0 1\nv 1 1\nvn 0 1 0\nf 1//1 2//2 3//1\nf 2//2 4//1 3//1\n\
             # normals of vertices that shared a normal with vertices deformed differently"
        );
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let appended: Vec<f64> = last
            .strip_prefix("vn ")
            .expect("a normal")
            .split(' ')
            .map(|x| x.parse().expect("a number"))
            .collect();
        assert_eq!(appended.len(), 3);
        for (got, want) in appended.iter().zip([-h, h, 0.0]) {
            assert!((got - want).abs() < 1e-15, "{last}");
        }
    }
}
