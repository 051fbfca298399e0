//! STL models, binary and ASCII: read into a [`Model`] (corners with the same coordinates
//! are one vertex, as every STL reader merges them) and written back as *the same file* with
//! what the deformation moved written again.
//!
//! Written here rather than with `stl_io`: that crate's errors carry no position, it takes a
//! binary file whose 80-byte header begins with `solid ` (a common exporter habit) for ASCII and
//! fails on it, it does not check a binary file's facet count against its size, and it does not
//! say where each number is, which writing the same file back needs. The format is small:
//!
//! * binary: an 80-byte header, a little-endian `u32` facet count, then 50 bytes per facet
//!   (normal and three corners as `f32`, a 2-byte attribute); the file has exactly
//!   `84 + 50 · count` bytes (that decides binary, whatever the header says);
//! * ASCII: `solid [name]`, then per facet `facet normal nx ny nz` / `outer loop` / three
//!   `vertex x y z` / `endloop` / `endfacet`, then `endsolid [name]`.
//!
//! On writing, a facet none of whose corners moved keeps its bytes; a moved corner gets the
//! deformed position rounded to `f32` (ASCII: the shortest decimal that reads back to it), and
//! the facet's normal becomes the unit normal of the deformed triangle, on the side of the old
//! one (a facet stays flat under any map, so this is its exact normal; a zero normal, which
//! some writers store, stays zero). Header, attribute bytes, names and layout are kept.

use super::{Model, ModelError};
use std::collections::HashMap;
use std::ops::Range;

/// Most facets an STL file may have (a bound checked before anything is allocated).
pub const MAX_FACETS: usize = 50_000_000;

/// Where a facet's numbers are.
#[derive(Debug, Clone, PartialEq)]
enum Place {
    /// Byte offset of the facet's 50 bytes.
    Binary(usize),
    /// Byte ranges of the 12 numbers: the normal's three, then each corner's three.
    Ascii(Box<[Range<usize>; 12]>),
}

/// One facet: its normal and corners as read, the model vertices of its corners, and where
/// its numbers are.
#[derive(Debug, Clone, PartialEq)]
struct Facet {
    normal: [f32; 3],
    corners: [usize; 3],
    place: Place,
}

/// An STL file as read.
#[derive(Debug, Clone, PartialEq)]
pub struct StlSource {
    bytes: Vec<u8>,
    facets: Vec<Facet>,
}

/// A parse error at a line and column (ASCII) or a facet (binary).
fn error(file: &str, line: usize, column: usize, message: String) -> ModelError {
    ModelError::Parse {
        file: file.to_string(),
        line,
        column,
        message,
    }
}

/// Merges corners with identical coordinates into vertices.
#[derive(Default)]
struct Vertices {
    index: HashMap<[u32; 3], usize>,
    positions: Vec<[f64; 3]>,
}

impl Vertices {
    fn add(&mut self, p: [f32; 3]) -> usize {
        // -0 and 0 are the same point.
        let key = p.map(|x| if x == 0.0 { 0 } else { x.to_bits() });
        *self.index.entry(key).or_insert_with(|| {
            self.positions.push(p.map(f64::from));
            self.positions.len() - 1
        })
    }
}

impl StlSource {
    /// Reads an STL file's bytes (`file` names it in errors): the model and its source.
    pub fn parse(bytes: Vec<u8>, file: &str) -> Result<(Model, StlSource), ModelError> {
        let binary_count = bytes
            .get(80..84)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as usize);
        let (vertices, facets) = match binary_count {
            Some(count) if 84 + 50 * (count as u64) == bytes.len() as u64 => {
                Self::parse_binary(&bytes, count, file)?
            }
            _ => {
                let text = std::str::from_utf8(&bytes).map_err(|e| {
                    let before = &bytes[..e.valid_up_to()];
                    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
                    error(
                        file,
                        line,
                        1,
                        format!(
                            "not an STL file: not ASCII, and a binary STL with the facet count of its header ({}) would have {} bytes, not {}",
                            binary_count.unwrap_or(0),
                            84 + 50 * binary_count.unwrap_or(0) as u64,
                            bytes.len()
                        ),
                    )
                })?;
                Self::parse_ascii(text, file)?
            }
        };
        if facets.is_empty() {
            return Err(ModelError::Empty {
                file: file.to_string(),
            });
        }
        let model = Model {
            positions: vertices.positions,
            triangles: facets.iter().map(|f| f.corners).collect(),
        };
        Ok((model, StlSource { bytes, facets }))
    }

    fn parse_binary(
        bytes: &[u8],
        count: usize,
        file: &str,
    ) -> Result<(Vertices, Vec<Facet>), ModelError> {
        if count > MAX_FACETS {
            return Err(error(
                file,
                1,
                81,
                format!("{count} facets, more than the limit of {MAX_FACETS}"),
            ));
        }
        let mut vertices = Vertices::default();
        let mut facets = Vec::with_capacity(count);
        for k in 0..count {
            let at = 84 + 50 * k;
            let f = |i: usize| {
                let o = at + 4 * i;
                f32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]])
            };
            let numbers: [f32; 12] = std::array::from_fn(f);
            if let Some(i) = numbers.iter().position(|x| !x.is_finite()) {
                return Err(error(
                    file,
                    1,
                    at + 4 * i + 1,
                    format!(
                        "facet {k}: a number that is not finite (byte {})",
                        at + 4 * i
                    ),
                ));
            }
            let corner = |c: usize| [numbers[3 + 3 * c], numbers[4 + 3 * c], numbers[5 + 3 * c]];
            facets.push(Facet {
                normal: [numbers[0], numbers[1], numbers[2]],
                corners: [0, 1, 2].map(|c| vertices.add(corner(c))),
                place: Place::Binary(at),
            });
        }
        Ok((vertices, facets))
    }

    fn parse_ascii(text: &str, file: &str) -> Result<(Vertices, Vec<Facet>), ModelError> {
        // Tokens with their line, column and byte range.
        let mut tokens = Vec::new();
        for (number, line) in text.split('\n').enumerate() {
            let start = line.as_ptr() as usize - text.as_ptr() as usize;
            let mut column = 0;
            let mut from: Option<(usize, usize)> = None;
            for (byte, c) in line.char_indices() {
                column += 1;
                match (c.is_whitespace(), from) {
                    (true, Some((b, col))) => {
                        tokens.push((number + 1, col, start + b..start + byte));
                        from = None;
                    }
                    (false, None) => from = Some((byte, column)),
                    _ => {}
                }
            }
            if let Some((b, col)) = from {
                tokens.push((number + 1, col, start + b..start + line.len()));
            }
        }
        let mut at = 0;
        let word = |k: usize| tokens.get(k).map(|(_, _, r)| &text[r.clone()]);
        let fail = |k: usize, expected: &str| {
            let end = || {
                let last = text.rsplit('\n').next().unwrap_or("");
                (text.matches('\n').count() + 1, last.chars().count() + 1)
            };
            let (line, column) = tokens.get(k).map_or_else(end, |(l, c, _)| (*l, *c));
            let found = word(k).map_or("the end of the file".to_string(), |w| format!("{w:?}"));
            error(
                file,
                line,
                column,
                format!("expected {expected}, found {found} (ASCII STL)"),
            )
        };
        if word(0) != Some("solid") {
            return Err(fail(0, "\"solid\" (this is not an STL file)"));
        }
        // The solid's name: words up to the first `facet` or `endsolid`.
        at += 1;
        while word(at).is_some_and(|w| w != "facet" && w != "endsolid") {
            at += 1;
        }
        let mut vertices = Vertices::default();
        let mut facets = Vec::new();
        loop {
            match word(at) {
                Some("endsolid") => break,
                Some("facet") => {}
                _ => return Err(fail(at, "\"facet\" or \"endsolid\"")),
            }
            if facets.len() >= MAX_FACETS {
                return Err(fail(at, &format!("at most {MAX_FACETS} facets")));
            }
            let expect = |at: &mut usize, keyword: &str| {
                if word(*at) == Some(keyword) {
                    *at += 1;
                    Ok(())
                } else {
                    Err(fail(*at, &format!("{keyword:?}")))
                }
            };
            expect(&mut at, "facet")?;
            expect(&mut at, "normal")?;
            let mut ranges: Vec<Range<usize>> = Vec::with_capacity(12);
            let mut numbers = [0f32; 12];
            let mut read_three = |at: &mut usize, slot: usize, ranges: &mut Vec<Range<usize>>| {
                for i in 0..3 {
                    let value = word(*at)
                        .and_then(|w| w.parse::<f32>().ok())
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| fail(*at, "a finite number"))?;
                    numbers[slot + i] = value;
                    ranges.push(tokens[*at].2.clone());
                    *at += 1;
                }
                Ok::<(), ModelError>(())
            };
            read_three(&mut at, 0, &mut ranges)?;
            expect(&mut at, "outer")?;
            expect(&mut at, "loop")?;
            for c in 0..3 {
                expect(&mut at, "vertex")?;
                read_three(&mut at, 3 + 3 * c, &mut ranges)?;
            }
            expect(&mut at, "endloop")?;
            expect(&mut at, "endfacet")?;
            let corner = |c: usize| [numbers[3 + 3 * c], numbers[4 + 3 * c], numbers[5 + 3 * c]];
            let place: [Range<usize>; 12] = std::array::from_fn(|i| ranges[i].clone());
            facets.push(Facet {
                normal: [numbers[0], numbers[1], numbers[2]],
                corners: [0, 1, 2].map(|c| vertices.add(corner(c))),
                place: Place::Ascii(Box::new(place)),
            });
        }
        Ok((vertices, facets))
    }

    /// The file again with the positions of `deformed` (the model read from this file,
    /// deformed: same vertices); see the module documentation.
    pub fn write_deformed(&self, original: &Model, deformed: &Model) -> Result<Vec<u8>, String> {
        if original.positions.len() != deformed.positions.len() {
            return Err("the deformed model has another number of vertices".into());
        }
        let mut binary = self.bytes.clone();
        let mut edits: Vec<(Range<usize>, String)> = Vec::new();
        for facet in &self.facets {
            let moved = facet
                .corners
                .iter()
                .any(|&v| original.positions[v] != deformed.positions[v]);
            if !moved {
                continue;
            }
            let corners = facet
                .corners
                .map(|v| deformed.positions[v].map(|x| x as f32));
            if corners.iter().flatten().any(|x| !x.is_finite()) {
                return Err("a deformed corner does not fit f32".into());
            }
            let normal = deformed_normal(facet.normal, corners);
            let numbers: Vec<f32> = normal
                .iter()
                .chain(corners.iter().flatten())
                .copied()
                .collect();
            match &facet.place {
                Place::Binary(at) => {
                    for (i, x) in numbers.iter().enumerate() {
                        binary[at + 4 * i..at + 4 * i + 4].copy_from_slice(&x.to_le_bytes());
                    }
                }
                Place::Ascii(ranges) => {
                    for (range, x) in ranges.iter().zip(&numbers) {
                        let x = if *x == 0.0 { 0.0 } else { *x };
                        edits.push((range.clone(), format!("{x}")));
                    }
                }
            }
        }
        if edits.is_empty() {
            return Ok(binary);
        }
        edits.sort_by_key(|(r, _)| r.start);
        let mut out = Vec::with_capacity(self.bytes.len() + 16 * edits.len());
        let mut at = 0;
        for (range, text) in &edits {
            out.extend_from_slice(&self.bytes[at..range.start]);
            out.extend_from_slice(text.as_bytes());
            at = range.end;
        }
        out.extend_from_slice(&self.bytes[at..]);
        Ok(out)
    }
}

/// The unit normal of the triangle `corners`, on the side of `old` (zero stays zero; a
/// degenerate deformed triangle keeps the old normal).
fn deformed_normal(old: [f32; 3], corners: [[f32; 3]; 3]) -> [f32; 3] {
    if old == [0.0; 3] {
        return old;
    }
    let [a, b, c] = corners.map(|p| p.map(f64::from));
    let (u, v) = (
        [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
        [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
    );
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let length = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if length == 0.0 || !length.is_finite() {
        return old;
    }
    let side = n[0] * f64::from(old[0]) + n[1] * f64::from(old[1]) + n[2] * f64::from(old[2]);
    let sign = if side < 0.0 { -1.0 } else { 1.0 };
    n.map(|x| (sign * x / length) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    const ASCII: &str = "solid square\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n      vertex 1 1 0\n    endloop\n  endfacet\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 1 0\n      vertex 0 1 0\n    endloop\n  endfacet\nendsolid square\n";

    fn binary(header: &[u8]) -> Vec<u8> {
        let mut bytes = header.to_vec();
        bytes.resize(80, b' ');
        bytes.extend(2u32.to_le_bytes());
        for (corners, attribute) in [
            ([[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]], 7u16),
            ([[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]], 9u16),
        ] {
            for x in [0.0f32, 0.0, 1.0].iter().chain(corners.iter().flatten()) {
                bytes.extend(x.to_le_bytes());
            }
            bytes.extend(attribute.to_le_bytes());
        }
        bytes
    }

    #[test]
    fn both_layouts_read_to_the_same_model_and_write_back_unchanged() {
        let (ascii_model, ascii) =
            StlSource::parse(ASCII.as_bytes().to_vec(), "a.stl").expect("ascii");
        // A binary header that begins with "solid " is still binary (its size says so).
        let bytes = binary(b"solid exported by a tool");
        let (binary_model, source) = StlSource::parse(bytes.clone(), "b.stl").expect("binary");
        assert_eq!(ascii_model, binary_model);
        assert_eq!(
            ascii_model.positions.len(),
            4,
            "shared corners are one vertex"
        );
        assert_eq!(ascii_model.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(
            source
                .write_deformed(&binary_model, &binary_model)
                .expect("same"),
            bytes
        );
        assert_eq!(
            ascii
                .write_deformed(&ascii_model, &ascii_model)
                .expect("same"),
            ASCII.as_bytes()
        );
    }

    #[test]
    fn moved_corners_and_their_facets_normals_are_written_again() {
        let (model, ascii) = StlSource::parse(ASCII.as_bytes().to_vec(), "a.stl").expect("ascii");
        let mut deformed = model.clone();
        // Lift vertex 3 (0, 1, 0) to z = 1: the second facet tilts, the first stays.
        deformed.positions[3] = [0.0, 1.0, 1.0];
        let text = String::from_utf8(ascii.write_deformed(&model, &deformed).expect("written"))
            .expect("text");
        // The tilted facet (0,0,0), (1,1,0), (0,1,1): normal (1, −1, 1)/√3.
        let expected = ASCII.replacen(
            "facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 1 0\n      vertex 0 1 0",
            "facet normal 0.57735026 -0.57735026 0.57735026\n    outer loop\n      vertex 0 0 0\n      vertex 1 1 0\n      vertex 0 1 1",
            1,
        );
        assert_eq!(text, expected);
        let bytes = binary(b"header");
        let (model, source) = StlSource::parse(bytes.clone(), "b.stl").expect("binary");
        let out = source.write_deformed(&model, &deformed).expect("written");
        assert_eq!(out.len(), bytes.len());
        assert_eq!(
            out[..84 + 50],
            bytes[..84 + 50],
            "the first facet and the header stay"
        );
        assert_eq!(out[84 + 98..], bytes[84 + 98..], "the attribute stays");
        let (again, _) = StlSource::parse(out, "b.stl").expect("reads back");
        assert_eq!(again.positions, deformed.positions);
    }

    #[test]
    fn malformed_files_name_the_position() {
        for (text, needle) in [
            ("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\nvertex 1 0 0\n", "a.stl:5:1: expected a finite number, found \"vertex\""),
            ("solid x\nfacet normal 0 0 nan\n", "a.stl:2:18: expected a finite number"),
            ("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nendloop\n", "a.stl:8:1: expected \"endfacet\", found the end of the file"),
            ("v 1 2 3\n", "a.stl:1:1: expected \"solid\""),
            ("solid x\nendsolid x\n", "a.stl: the model has no vertices"),
        ] {
            let e = StlSource::parse(text.as_bytes().to_vec(), "a.stl").expect_err(text);
            assert!(e.to_string().starts_with(needle), "{e}\nexpected {needle}");
        }
        let mut truncated = binary(b"x");
        truncated.pop();
        let e = StlSource::parse(truncated, "b.stl").expect_err("truncated");
        assert!(
            e.to_string().contains("would have 184 bytes, not 183"),
            "{e}"
        );
    }
}
