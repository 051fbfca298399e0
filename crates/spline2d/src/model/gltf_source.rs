//! glTF 2.0 models, JSON (`.gltf`) or binary (`.glb`), parsed and validated by the `gltf` crate.
//!
//! **What is deformed.** Every mesh primitive's `POSITION` accessor, placed in the scene: a
//! mesh drawn by a node gets the node's world transform (the product of the node matrices or
//! translation–rotation–scale from its scene root), a mesh drawn by no node the identity. glTF
//! is `+Y` up; the spline's plane is `x, y` with `z` up, so a position `(x, y, z)` of the scene
//! is the point `(x, −z, y)` of the deformation (the rotation Blender applies when it imports
//! glTF): the ground plane of a glTF scene is the plane a spline deforms. A mesh drawn by nodes
//! with different world transforms cannot be deformed in place (one set of positions, several
//! places) and is refused, as are skinned meshes (their drawn positions follow the joints);
//! morph targets' displacements are kept as they are.
//!
//! **What is written.** The same file: the positions of the moved vertices, mapped back into
//! their mesh's own coordinates and rounded to `f32`; the `NORMAL`s of those vertices by the
//! inverse transpose of the Jacobian (in mesh coordinates, rescaled to their old length) and
//! their `TANGENT`s by the Jacobian (`w` kept); each changed `POSITION` accessor's `min` and
//! `max`, which glTF requires to bound the data. Nothing else changes: the JSON is the text as
//! written with only those `min`/`max` values replaced (found through `serde_json`'s raw
//! spans, not by serialising the document again, which would reorder keys and drop what the
//! `gltf` crate does not model), every other byte of every buffer is the same, and a vertex
//! that does not move keeps its bytes exactly. A buffer in a data URI is encoded again in
//! place; an external buffer (`"uri": "mesh.bin"`) is embedded in the deformed file as a data
//! URI, so the output is one file (its images keep their URIs as written). A model nothing
//! moves is written back byte for byte.

use super::matrix3::{invert, multiply, transform_normal, transform_tangent, Matrix};
use super::{Model, ModelError};
use base64::Engine as _;
use gltf::mesh::Mode;
use serde_json::value::RawValue;
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::Path;

/// An affine map `x ↦ A x + t`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Affine {
    linear: Matrix,
    translation: [f64; 3],
}

impl Affine {
    const IDENTITY: Affine = Affine {
        linear: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        translation: [0.0; 3],
    };

    /// The scene's `+Y` up turned into the spline's `+Z` up: `(x, y, z) ↦ (x, −z, y)`.
    const Y_UP_TO_Z_UP: Affine = Affine {
        linear: [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],
        translation: [0.0; 3],
    };

    /// A glTF column-major 4 × 4 matrix (its last row is `0 0 0 1` for node transforms).
    fn from_columns(m: [[f32; 4]; 4]) -> Affine {
        let mut linear = [[0.0; 3]; 3];
        for (r, row) in linear.iter_mut().enumerate() {
            for (c, x) in row.iter_mut().enumerate() {
                *x = f64::from(m[c][r]);
            }
        }
        Affine {
            linear,
            translation: [0, 1, 2].map(|r| f64::from(m[3][r])),
        }
    }

    fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        let mut out = self.translation;
        for (r, o) in out.iter_mut().enumerate() {
            *o += (0..3).map(|c| self.linear[r][c] * p[c]).sum::<f64>();
        }
        out
    }

    /// `self ∘ inner`.
    fn then_after(&self, inner: &Affine) -> Affine {
        Affine {
            linear: multiply(&self.linear, &inner.linear),
            translation: self.apply(inner.translation),
        }
    }

    /// The inverse map; `None` when `A` is singular.
    fn inverse(&self) -> Option<Affine> {
        let linear = invert(&self.linear)?;
        let t = self.translation;
        let translation = [0, 1, 2].map(|r| -(0..3).map(|c| linear[r][c] * t[c]).sum::<f64>());
        Some(Affine {
            linear,
            translation,
        })
    }
}

/// Where an accessor's elements are: buffer, offset of the first element, bytes between
/// elements, number of elements.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Strided {
    buffer: usize,
    offset: usize,
    stride: usize,
    count: usize,
}

impl Strided {
    /// The `f32` components `0..n` of element `k`.
    fn read<const N: usize>(&self, buffers: &[Vec<u8>], k: usize) -> [f64; N] {
        let at = self.offset + k * self.stride;
        let bytes = &buffers[self.buffer];
        std::array::from_fn(|i| {
            let b = &bytes[at + 4 * i..at + 4 * i + 4];
            f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        })
    }

    /// Writes `value` (rounded to `f32`) as element `k`'s first components.
    fn write(&self, buffers: &mut [Vec<u8>], k: usize, value: &[f64]) {
        let at = self.offset + k * self.stride;
        let bytes = &mut buffers[self.buffer];
        for (i, x) in value.iter().enumerate() {
            bytes[at + 4 * i..at + 4 * i + 4].copy_from_slice(&(*x as f32).to_le_bytes());
        }
    }
}

/// One `POSITION` accessor: its vertices in the model, where it is, how its mesh is placed,
/// and the normals and tangents that go with it.
#[derive(Debug, Clone, PartialEq)]
struct PositionBlock {
    accessor: usize,
    first: usize,
    data: Strided,
    /// Mesh coordinates to the spline's (scene placement, then `+Z` up).
    placement: Affine,
    normals: Vec<Strided>,
    tangents: Vec<Strided>,
}

/// A buffer as the file holds it.
#[derive(Debug, Clone, PartialEq)]
enum BufferOrigin {
    /// The GLB's `BIN` chunk.
    Binary,
    /// A `data:` URI in the JSON.
    DataUri,
    /// A file beside the model.
    External,
}

/// A glTF file as read: its JSON text, buffers and what the deformation touches.
#[derive(Debug, Clone, PartialEq)]
pub struct GltfSource {
    /// The GLB container's header version, for a binary file.
    glb: Option<u32>,
    json: String,
    buffers: Vec<Vec<u8>>,
    origins: Vec<BufferOrigin>,
    blocks: Vec<PositionBlock>,
}

/// Components and size of the element types the deformation reads.
const FLOAT: gltf::accessor::DataType = gltf::accessor::DataType::F32;

impl GltfSource {
    /// Reads a glTF file's bytes (`file` names it in errors; external buffers are read from
    /// `directory`, each within `limit` bytes): the model (every deformable primitive's
    /// vertices and triangles, in the spline's coordinates) and its source.
    pub fn parse(
        bytes: &[u8],
        file: &str,
        directory: &Path,
        limit: u64,
    ) -> Result<(Model, GltfSource), ModelError> {
        let at = |line: usize, column: usize, message: String| ModelError::Parse {
            file: file.to_string(),
            line,
            column,
            message,
        };
        let (glb, json_bytes, blob) = if bytes.starts_with(b"glTF") {
            // The container's length first: the `gltf` crate's errors say nothing of where.
            let declared = bytes
                .get(8..12)
                .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
            match declared {
                None => {
                    return Err(at(
                        1,
                        1,
                        format!("byte {}: the GLB header needs 12 bytes", bytes.len()),
                    ))
                }
                Some(n) if n != bytes.len() => {
                    return Err(at(
                        1,
                        1,
                        format!(
                            "the GLB header (byte 8) declares {n} bytes, the file has {}",
                            bytes.len()
                        ),
                    ))
                }
                Some(_) => {}
            }
            let glb = gltf::binary::Glb::from_slice(bytes)
                .map_err(|e| at(1, 1, format!("not a GLB file this reader accepts: {e}")))?;
            (
                Some(glb.header.version),
                glb.json.into_owned(),
                glb.bin.map(|b| b.into_owned()),
            )
        } else {
            (None, bytes.to_vec(), None)
        };
        let json = String::from_utf8(json_bytes).map_err(|e| {
            let (line, column) = line_column(bytes, e.utf8_error().valid_up_to());
            at(line, column, "the glTF JSON is not UTF-8".into())
        })?;
        let spans = Spans::of(&json);
        let document = gltf::Gltf::from_slice(json.as_bytes())
            .map_err(|e| match &e {
                gltf::Error::Deserialize(j) => at(
                    j.line().max(1),
                    j.column().max(1),
                    format!("not glTF 2.0 JSON: {j}"),
                ),
                gltf::Error::Validation(errors) if !errors.is_empty() => {
                    let (path, error) = &errors[0];
                    let path = path.to_string();
                    let (line, column) = spans.position_of_path(&json, &path);
                    let more = match errors.len() {
                        1 => String::new(),
                        n => format!(" (and {} more problems)", n - 1),
                    };
                    at(
                        line,
                        column,
                        format!("invalid glTF at {path}: {error}{more}"),
                    )
                }
                other => at(1, 1, format!("not glTF 2.0: {other}")),
            })?
            .document;
        let item_error = |item: &str, index: usize, message: String| {
            let (line, column) = spans.position(&json, item, index);
            at(line, column, format!("{item}[{index}]: {message}"))
        };

        // Buffers: the BIN chunk, data URIs, files beside the model.
        let mut buffers = Vec::new();
        let mut origins = Vec::new();
        for buffer in document.buffers() {
            let index = buffer.index();
            let declared = buffer.length();
            if declared as u64 > limit {
                return Err(item_error(
                    "buffers",
                    index,
                    format!("{declared} bytes, more than the input limit of {limit}"),
                ));
            }
            let (data, origin) = match buffer.source() {
                gltf::buffer::Source::Bin => match &blob {
                    Some(bin) => (bin.clone(), BufferOrigin::Binary),
                    None => {
                        return Err(item_error(
                            "buffers",
                            index,
                            "has no URI and the file has no binary chunk".into(),
                        ))
                    }
                },
                gltf::buffer::Source::Uri(uri) => match uri.strip_prefix("data:") {
                    Some(rest) => {
                        let encoded = rest
                            .split_once(";base64,")
                            .map(|(_, data)| data)
                            .ok_or_else(|| {
                                item_error("buffers", index, "a data URI that is not base64".into())
                            })?;
                        let data = base64::engine::general_purpose::STANDARD
                            .decode(encoded)
                            .map_err(|e| {
                                item_error("buffers", index, format!("bad base64 data: {e}"))
                            })?;
                        (data, BufferOrigin::DataUri)
                    }
                    None => {
                        let name = relative_file(uri).ok_or_else(|| {
                            item_error(
                                "buffers",
                                index,
                                format!(
                                    "URI {uri:?}: only data URIs and relative file names are read"
                                ),
                            )
                        })?;
                        let data = api::input::read_regular_file(
                            &directory.join(&name),
                            "glTF buffer",
                            limit,
                        )
                        .map_err(|e| {
                            item_error("buffers", index, format!("{name}: {}", e.reason()))
                        })?;
                        (data, BufferOrigin::External)
                    }
                },
            };
            if data.len() < declared {
                return Err(item_error(
                    "buffers",
                    index,
                    format!(
                        "byteLength is {declared} but the data has {} bytes",
                        data.len()
                    ),
                ));
            }
            buffers.push(data);
            origins.push(origin);
        }

        // Where each mesh is drawn.
        let placements = mesh_placements(&document)
            .map_err(|(mesh, message)| item_error("meshes", mesh, message))?;

        // The deformable primitives' vertices, one block per POSITION accessor.
        let mut model = Model::default();
        let mut blocks: Vec<PositionBlock> = Vec::new();
        let mut block_of: BTreeMap<usize, usize> = BTreeMap::new();
        for mesh in document.meshes() {
            let placement = placements[mesh.index()];
            for primitive in mesh.primitives() {
                let Some(positions) = primitive.get(&gltf::Semantic::Positions) else {
                    continue;
                };
                let accessor = positions.index();
                let block = match block_of.get(&accessor) {
                    Some(&b) => {
                        if blocks[b].placement != placement {
                            return Err(item_error(
                                "meshes",
                                mesh.index(),
                                format!("its positions (accessors[{accessor}]) are drawn by meshes placed differently: they cannot be deformed in place"),
                            ));
                        }
                        b
                    }
                    None => {
                        let data = float_elements(&positions, 3, &buffers)
                            .map_err(|m| item_error("accessors", accessor, m))?;
                        let first = model.positions.len();
                        for k in 0..data.count {
                            let p = placement.apply(data.read::<3>(&buffers, k));
                            if p.iter().any(|x| !x.is_finite()) {
                                return Err(item_error(
                                    "accessors",
                                    accessor,
                                    format!("element {k} is not finite"),
                                ));
                            }
                            model.positions.push(p);
                        }
                        blocks.push(PositionBlock {
                            accessor,
                            first,
                            data,
                            placement,
                            normals: Vec::new(),
                            tangents: Vec::new(),
                        });
                        block_of.insert(accessor, blocks.len() - 1);
                        blocks.len() - 1
                    }
                };
                let count = blocks[block].data.count;
                for (semantic, components) in
                    [(gltf::Semantic::Normals, 3), (gltf::Semantic::Tangents, 4)]
                {
                    if let Some(attribute) = primitive.get(&semantic) {
                        let data = float_elements(&attribute, components, &buffers)
                            .map_err(|m| item_error("accessors", attribute.index(), m))?;
                        if data.count != count {
                            return Err(item_error(
                                "accessors",
                                attribute.index(),
                                format!("{} elements for {count} positions", data.count),
                            ));
                        }
                        let list = if components == 3 {
                            &mut blocks[block].normals
                        } else {
                            &mut blocks[block].tangents
                        };
                        if !list.contains(&data) {
                            list.push(data);
                        }
                    }
                }
                let first = blocks[block].first;
                let corners = primitive_indices(&primitive, count, &buffers)
                    .map_err(|(accessor, m)| item_error("accessors", accessor, m))?;
                let triangles = match primitive.mode() {
                    Mode::Triangles => corners
                        .chunks_exact(3)
                        .map(|c| [c[0], c[1], c[2]])
                        .collect(),
                    Mode::TriangleStrip => (2..corners.len())
                        .map(|k| {
                            if k % 2 == 0 {
                                [corners[k - 2], corners[k - 1], corners[k]]
                            } else {
                                [corners[k - 1], corners[k - 2], corners[k]]
                            }
                        })
                        .collect(),
                    Mode::TriangleFan => (2..corners.len())
                        .map(|k| [corners[0], corners[k - 1], corners[k]])
                        .collect(),
                    // Points and lines: vertices without triangles.
                    _ => Vec::new(),
                };
                model.triangles.extend(
                    triangles
                        .into_iter()
                        .map(|t: [usize; 3]| t.map(|v| first + v)),
                );
            }
        }
        if model.positions.is_empty() {
            return Err(ModelError::Empty {
                file: file.to_string(),
            });
        }
        Ok((
            model,
            GltfSource {
                glb,
                json,
                buffers,
                origins,
                blocks,
            },
        ))
    }

    /// The file again with the positions of `deformed` (the model read from it, deformed),
    /// normals and tangents of the moved vertices transformed by `jacobian(v)` (the Jacobian of
    /// the deformation at vertex `v`, in the spline's coordinates), and the changed position
    /// accessors' bounds. See the module documentation.
    pub fn write_deformed(
        &self,
        original: &Model,
        deformed: &Model,
        jacobian: impl Fn(usize) -> Option<[[f64; 3]; 3]>,
    ) -> Result<Vec<u8>, String> {
        let vertices: usize = self.blocks.iter().map(|b| b.data.count).sum();
        if original.positions.len() != vertices || deformed.positions.len() != vertices {
            return Err("the deformed model has another number of vertices".into());
        }
        let mut buffers = self.buffers.clone();
        let mut bounds: Vec<(usize, [f64; 3], [f64; 3])> = Vec::new();
        for block in &self.blocks {
            let back = block.placement.inverse().ok_or_else(|| {
                format!(
                    "accessors[{}]: its mesh's transform is singular",
                    block.accessor
                )
            })?;
            let mut moved_any = false;
            for k in 0..block.data.count {
                let v = block.first + k;
                let (old, new) = (original.positions[v], deformed.positions[v]);
                if old == new {
                    continue;
                }
                moved_any = true;
                let local = back.apply(new);
                if local
                    .iter()
                    .any(|x| !x.is_finite() || x.abs() > f64::from(f32::MAX))
                {
                    return Err(format!(
                        "vertex {v}: the deformed position does not fit an f32"
                    ));
                }
                block.data.write(&mut buffers, k, &local);
                // In mesh coordinates the deformation's Jacobian is A⁻¹ J A.
                let Some(j) = jacobian(v) else { continue };
                let j_local = multiply(&back.linear, &multiply(&j, &block.placement.linear));
                for normals in &block.normals {
                    if let Some(n) = transform_normal(&j_local, normals.read::<3>(&self.buffers, k))
                    {
                        normals.write(&mut buffers, k, &n);
                    }
                }
                for tangents in &block.tangents {
                    let t = tangents.read::<3>(&self.buffers, k);
                    if let Some(turned) = transform_tangent(&j_local, t) {
                        tangents.write(&mut buffers, k, &turned);
                    }
                }
            }
            if moved_any {
                let mut min = [f64::INFINITY; 3];
                let mut max = [f64::NEG_INFINITY; 3];
                for k in 0..block.data.count {
                    let p = block.data.read::<3>(&buffers, k);
                    for i in 0..3 {
                        min[i] = min[i].min(p[i]);
                        max[i] = max[i].max(p[i]);
                    }
                }
                bounds.push((block.accessor, min, max));
            }
        }
        let json = self.json_with(&bounds, &buffers)?;
        match self.glb {
            Some(version) => {
                let bin = self
                    .origins
                    .iter()
                    .position(|o| *o == BufferOrigin::Binary)
                    .map(|b| std::borrow::Cow::Borrowed(buffers[b].as_slice()));
                let glb = gltf::binary::Glb {
                    header: gltf::binary::Header {
                        magic: *b"glTF",
                        version,
                        // Computed again by `to_vec`.
                        length: 0,
                    },
                    json: std::borrow::Cow::Borrowed(json.as_bytes()),
                    bin,
                };
                glb.to_vec()
                    .map_err(|e| format!("the deformed GLB cannot be written: {e}"))
            }
            None => Ok(json.into_bytes()),
        }
    }

    /// The JSON text with the `min`/`max` of the accessors in `bounds` replaced (or added) and
    /// every changed buffer that is not the GLB's `BIN` chunk written as a data URI; every other
    /// character as it was.
    fn json_with(
        &self,
        bounds: &[(usize, [f64; 3], [f64; 3])],
        buffers: &[Vec<u8>],
    ) -> Result<String, String> {
        let text = &self.json;
        let root: BTreeMap<String, &RawValue> = serde_json::from_str(text)
            .map_err(|e| format!("the glTF JSON cannot be read again: {e}"))?;
        let items = |key: &str| -> Result<Vec<&RawValue>, String> {
            match root.get(key) {
                Some(raw) => serde_json::from_str(raw.get()).map_err(|e| format!("{key}: {e}")),
                None => Ok(Vec::new()),
            }
        };
        let mut edits: Vec<(Range<usize>, String)> = Vec::new();
        let accessors = items("accessors")?;
        for (accessor, min, max) in bounds {
            let raw = accessors.get(*accessor).ok_or("an accessor is missing")?;
            let fields: BTreeMap<String, &RawValue> = serde_json::from_str(raw.get())
                .map_err(|e| format!("accessors[{accessor}]: {e}"))?;
            // Shortest `f32` decimals, `-0` written `0`.
            let number = |x: f64| if x == 0.0 { 0.0f32 } else { x as f32 };
            let array =
                |v: &[f64; 3]| format!("[{},{},{}]", number(v[0]), number(v[1]), number(v[2]));
            let mut added = String::new();
            for (key, value) in [("min", min), ("max", max)] {
                match fields.get(key) {
                    Some(old) => edits.push((span(text, old), array(value))),
                    None => added.push_str(&format!("\"{key}\":{},", array(value))),
                }
            }
            if !added.is_empty() {
                // Right after the accessor's opening brace.
                let start = span(text, raw).start + 1;
                edits.push((start..start, added));
            }
        }
        for (b, raw) in items("buffers")?.iter().enumerate() {
            if self.origins[b] == BufferOrigin::Binary || buffers[b] == self.buffers[b] {
                continue;
            }
            let fields: BTreeMap<String, &RawValue> =
                serde_json::from_str(raw.get()).map_err(|e| format!("buffers[{b}]: {e}"))?;
            let uri = fields
                .get("uri")
                .ok_or_else(|| format!("buffers[{b}] has no URI"))?;
            let encoded = base64::engine::general_purpose::STANDARD.encode(&buffers[b]);
            edits.push((
                span(text, uri),
                format!("\"data:application/octet-stream;base64,{encoded}\""),
            ));
        }
        edits.sort_by_key(|(range, _)| range.start);
        let mut out = String::with_capacity(text.len());
        let mut at = 0;
        for (range, replacement) in edits {
            out.push_str(&text[at..range.start]);
            out.push_str(&replacement);
            at = range.end;
        }
        out.push_str(&text[at..]);
        Ok(out)
    }
}

/// The byte range of `raw` (a slice of `text`) in `text`.
fn span(text: &str, raw: &RawValue) -> Range<usize> {
    let start = raw.get().as_ptr() as usize - text.as_ptr() as usize;
    start..start + raw.get().len()
}

/// 1-based line and column (in characters) of byte `offset` of `bytes`.
fn line_column(bytes: &[u8], offset: usize) -> (usize, usize) {
    let before = &bytes[..offset.min(bytes.len())];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |p| p + 1);
    let column = String::from_utf8_lossy(&before[start..]).chars().count() + 1;
    (line, column)
}

/// Positions of the top-level arrays' items, for errors at a line and column.
struct Spans {
    items: BTreeMap<String, Vec<usize>>,
}

impl Spans {
    fn of(text: &str) -> Spans {
        let mut items = BTreeMap::new();
        if let Ok(root) = serde_json::from_str::<BTreeMap<String, &RawValue>>(text) {
            for (key, raw) in root {
                if let Ok(list) = serde_json::from_str::<Vec<&RawValue>>(raw.get()) {
                    items.insert(key, list.iter().map(|r| span(text, r).start).collect());
                }
            }
        }
        Spans { items }
    }

    /// Line and column of item `index` of the top-level array `key` (1:1 when unknown).
    fn position(&self, text: &str, key: &str, index: usize) -> (usize, usize) {
        self.items
            .get(key)
            .and_then(|list| list.get(index))
            .map_or((1, 1), |&offset| line_column(text.as_bytes(), offset))
    }

    /// Line and column of the item a validation path such as `meshes[0].primitives[1]` starts
    /// in (its top-level item).
    fn position_of_path(&self, text: &str, path: &str) -> (usize, usize) {
        let head = path.split('.').next().unwrap_or_default();
        match head.split_once('[') {
            Some((key, rest)) => match rest.trim_end_matches(']').parse() {
                Ok(index) => self.position(text, key, index),
                Err(_) => (1, 1),
            },
            None => (1, 1),
        }
    }
}

/// A URI naming a file beside the model: relative, no scheme, percent-decoded; `None` else.
fn relative_file(uri: &str) -> Option<String> {
    if uri.contains(':') || uri.starts_with('/') || uri.starts_with('\\') {
        return None;
    }
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    let name = String::from_utf8(out).ok()?;
    (!name.split(['/', '\\']).any(|part| part == "..")).then_some(name)
}

/// Where `accessor`'s `components` float components per element are, checked to lie in its
/// buffer view and buffer.
fn float_elements(
    accessor: &gltf::Accessor<'_>,
    components: usize,
    buffers: &[Vec<u8>],
) -> Result<Strided, String> {
    if accessor.data_type() != FLOAT
        || accessor.dimensions().multiplicity() != components
        || accessor.normalized()
    {
        return Err(format!(
            "{:?} {:?} elements: this reader deforms {components}-component float vertex data only (quantized meshes are not read)",
            accessor.data_type(),
            accessor.dimensions()
        ));
    }
    if accessor.sparse().is_some() {
        return Err("sparse vertex data is not read".into());
    }
    let view = accessor
        .view()
        .ok_or("vertex data without a buffer view is not read")?;
    let element = 4 * components;
    let stride = view.stride().unwrap_or(element);
    let count = accessor.count();
    located(view, accessor.offset(), stride, element, count, buffers)
}

/// Checks that `count` elements of `element` bytes, `stride` apart from `offset` in `view`,
/// lie inside the view and its buffer.
fn located(
    view: gltf::buffer::View<'_>,
    offset: usize,
    stride: usize,
    element: usize,
    count: usize,
    buffers: &[Vec<u8>],
) -> Result<Strided, String> {
    let buffer = view.buffer().index();
    let start = view
        .offset()
        .checked_add(offset)
        .ok_or("offset overflows")?;
    let span = match count {
        0 => 0,
        n => (n - 1)
            .checked_mul(stride)
            .and_then(|s| s.checked_add(element))
            .ok_or("the data overflows")?,
    };
    let view_end = view
        .offset()
        .checked_add(view.length())
        .ok_or("the view overflows")?;
    let end = start.checked_add(span).ok_or("the data overflows")?;
    if stride < element
        || offset.checked_add(span).is_none_or(|e| e > view.length())
        || end > view_end
        || view_end > buffers[buffer].len()
    {
        return Err(format!(
            "{count} elements of {element} bytes, {stride} apart from byte {offset} do not fit its buffer view (bufferViews[{}], {} bytes)",
            view.index(),
            view.length()
        ));
    }
    Ok(Strided {
        buffer,
        offset: start,
        stride,
        count,
    })
}

/// A primitive's vertex indices (`0..count` without an index accessor), each checked below
/// `count`; on error the accessor and the message.
fn primitive_indices(
    primitive: &gltf::Primitive<'_>,
    count: usize,
    buffers: &[Vec<u8>],
) -> Result<Vec<usize>, (usize, String)> {
    let Some(indices) = primitive.indices() else {
        return Ok((0..count).collect());
    };
    let index = indices.index();
    let size = match indices.data_type() {
        gltf::accessor::DataType::U8 => 1,
        gltf::accessor::DataType::U16 => 2,
        gltf::accessor::DataType::U32 => 4,
        other => return Err((index, format!("indices of type {other:?}"))),
    };
    if indices.sparse().is_some() || indices.dimensions().multiplicity() != 1 {
        return Err((index, "indices must be plain scalars".into()));
    }
    let view = indices
        .view()
        .ok_or((index, "indices without a buffer view".to_string()))?;
    let stride = view.stride().unwrap_or(size);
    let data = located(
        view,
        indices.offset(),
        stride,
        size,
        indices.count(),
        buffers,
    )
    .map_err(|m| (index, m))?;
    let bytes = &buffers[data.buffer];
    (0..data.count)
        .map(|k| {
            let at = data.offset + k * data.stride;
            let v = match size {
                1 => usize::from(bytes[at]),
                2 => usize::from(u16::from_le_bytes([bytes[at], bytes[at + 1]])),
                _ => u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
                    as usize,
            };
            if v < count {
                Ok(v)
            } else {
                Err((
                    index,
                    format!("index {v} (element {k}) beyond the {count} vertices"),
                ))
            }
        })
        .collect()
}

/// Per mesh, the map from its coordinates to the spline's: the world transform of the nodes
/// that draw it (in any scene), then `+Y` up to `+Z` up. On error the mesh and why.
fn mesh_placements(document: &gltf::Document) -> Result<Vec<Affine>, (usize, String)> {
    let meshes = document.meshes().len();
    let mut placed: Vec<Option<Affine>> = vec![None; meshes];
    let nodes = document.nodes().len();
    // Depth-first from every scene root, with the path length bounded by the node count (a
    // cycle, which validation does not catch, would exceed it).
    let mut stack: Vec<(gltf::Node<'_>, Affine, usize)> = document
        .scenes()
        .flat_map(|scene| scene.nodes())
        .map(|node| (node, Affine::IDENTITY, 1))
        .collect();
    // A valid scene is a forest: each scene visits each node at most once.
    let most = document.scenes().len().max(1).saturating_mul(nodes);
    let mut visits = 0usize;
    while let Some((node, parent, depth)) = stack.pop() {
        visits += 1;
        if depth > nodes || visits > most {
            return Err((0, "the scene's nodes form a cycle or share children".into()));
        }
        let world = parent.then_after(&Affine::from_columns(node.transform().matrix()));
        if let Some(mesh) = node.mesh() {
            if node.skin().is_some() {
                return Err((mesh.index(), format!("drawn skinned by nodes[{}]: its drawn positions follow the joints, they cannot be deformed in place", node.index())));
            }
            match placed[mesh.index()] {
                Some(other) if !close(&other, &world) => {
                    return Err((mesh.index(), "drawn by several nodes with different transforms: one set of positions cannot be deformed in several places".into()));
                }
                _ => placed[mesh.index()] = Some(world),
            }
        }
        for child in node.children() {
            stack.push((child, world, depth + 1));
        }
    }
    placed
        .into_iter()
        .enumerate()
        .map(|(mesh, world)| {
            let placement = Affine::Y_UP_TO_Z_UP.then_after(&world.unwrap_or(Affine::IDENTITY));
            placement
                .inverse()
                .map(|_| placement)
                .ok_or((mesh, "its node's transform is singular".to_string()))
        })
        .collect()
}

/// Two placements equal up to the rounding of products of `f32` matrices.
fn close(a: &Affine, b: &Affine) -> bool {
    let near = |x: f64, y: f64| (x - y).abs() <= 1e-9 * (1.0 + x.abs().max(y.abs()));
    (0..3).all(|r| {
        (0..3).all(|c| near(a.linear[r][c], b.linear[r][c]))
            && near(a.translation[r], b.translation[r])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A quad (two triangles, indexed) with normals, in one buffer; `uri` is the buffer's URI
    /// (`None`: the GLB's `BIN` chunk); the node moves it by (1, 0, 0).
    fn quad_json(uri: Option<&str>, length: usize) -> String {
        let uri = uri
            .map(|u| format!("\"uri\": \"{u}\", "))
            .unwrap_or_default();
        format!(
            r#"{{
  "asset": {{"version": "2.0", "generator": "by hand"}},
  "extras": {{"kept": [1, 2, 3]}},
  "scene": 0,
  "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0, "translation": [1, 0, 0], "name": "quad"}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1}}, "indices": 2, "material": 0}}]}}],
  "materials": [{{"name": "paint", "pbrMetallicRoughness": {{"baseColorFactor": [1, 0.5, 0, 1]}}}}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, -1], "max": [1, 0, 0]}},
    {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"}},
    {{"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}}
  ],
  "bufferViews": [
    {{"buffer": 0, "byteOffset": 0, "byteLength": 48}},
    {{"buffer": 0, "byteOffset": 48, "byteLength": 48}},
    {{"buffer": 0, "byteOffset": 96, "byteLength": 12}}
  ],
  "buffers": [{{{uri}"byteLength": {length}}}]
}}
"#
        )
    }

    /// The quad's buffer: positions in the glTF plane `y = 0` (the spline's plane after `+Y`
    /// up), normals `+Y`, indices.
    fn quad_buffer() -> Vec<u8> {
        let mut out = Vec::new();
        for p in [
            [0f32, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 0.0, -1.0],
            [0.0, 0.0, -1.0],
        ] {
            for x in p {
                out.extend(x.to_le_bytes());
            }
        }
        for _ in 0..4 {
            for x in [0f32, 1.0, 0.0] {
                out.extend(x.to_le_bytes());
            }
        }
        for i in [0u16, 1, 2, 0, 2, 3] {
            out.extend(i.to_le_bytes());
        }
        out
    }

    fn glb() -> Vec<u8> {
        let buffer = quad_buffer();
        let json = quad_json(None, buffer.len());
        gltf::binary::Glb {
            header: gltf::binary::Header {
                magic: *b"glTF",
                version: 2,
                length: 0,
            },
            json: std::borrow::Cow::Owned(json.into_bytes()),
            bin: Some(std::borrow::Cow::Owned(buffer)),
        }
        .to_vec()
        .expect("a GLB")
    }

    fn parse(bytes: &[u8]) -> Result<(Model, GltfSource), ModelError> {
        GltfSource::parse(bytes, "quad.glb", Path::new("."), 1 << 20)
    }

    #[test]
    fn a_glb_quad_is_placed_in_the_splines_plane_and_written_back_byte_for_byte() {
        let bytes = glb();
        let (model, source) = parse(&bytes).expect("read");
        // Node translation (1, 0, 0), then (x, y, z) -> (x, -z, y): the quad lies in z = 0.
        assert_eq!(
            model.positions,
            vec![
                [1.0, 0.0, 0.0],
                [2.0, 0.0, 0.0],
                [2.0, 1.0, 0.0],
                [1.0, 1.0, 0.0]
            ]
        );
        assert_eq!(model.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        let same = source
            .write_deformed(&model, &model, |_| None)
            .expect("write");
        assert_eq!(same, bytes, "nothing moved: the same file");
    }

    #[test]
    fn a_deformed_glb_moves_positions_normals_and_bounds_and_keeps_the_rest() {
        let bytes = glb();
        let (model, source) = parse(&bytes).expect("read");
        // Shear in the plane: x' = x + y, vertex 0 left in place; the Jacobian [[1,1,0],[0,1,0],[0,0,1]].
        let mut deformed = model.clone();
        for p in deformed.positions.iter_mut().skip(1) {
            p[0] += p[1];
        }
        let shear = [[1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let out = source
            .write_deformed(&model, &deformed, |v| (v > 0).then_some(shear))
            .expect("write");
        let (again, written) = parse(&out).expect("read again");
        assert_eq!(again.positions, deformed.positions);
        assert_eq!(again.triangles, model.triangles);
        // Normals: the plane's normal stays the plane's normal (+Y in glTF), unit length.
        let normals = written.blocks[0].normals[0];
        for k in 0..4 {
            let n = normals.read::<3>(&written.buffers, k);
            assert!(
                (n[0]).abs() < 1e-7 && (n[1] - 1.0).abs() < 1e-7 && n[2].abs() < 1e-7,
                "{n:?}"
            );
        }
        // The JSON changed only in the position bounds.
        let json = String::from_utf8(
            gltf::binary::Glb::from_slice(&out)
                .expect("glb")
                .json
                .to_vec(),
        )
        .expect("utf-8");
        assert!(
            json.contains(r#""min": [0,0,-1], "max": [2,0,0]}"#),
            "{json}"
        );
        assert!(json.contains(r#""extras": {"kept": [1, 2, 3]}"#));
        assert!(json.contains(r#""baseColorFactor": [1, 0.5, 0, 1]"#));
        // Vertex 0 did not move: its bytes are the original ones.
        assert_eq!(written.buffers[0][..12], source.buffers[0][..12]);
    }

    #[test]
    fn a_json_gltf_with_a_data_uri_or_an_external_buffer_round_trips() {
        let buffer = quad_buffer();
        let encoded = base64::engine::general_purpose::STANDARD.encode(&buffer);
        let text = quad_json(
            Some(&format!("data:application/octet-stream;base64,{encoded}")),
            buffer.len(),
        );
        let (model, source) =
            GltfSource::parse(text.as_bytes(), "quad.gltf", Path::new("."), 1 << 20).expect("read");
        assert_eq!(
            source
                .write_deformed(&model, &model, |_| None)
                .expect("write"),
            text.as_bytes()
        );
        let mut moved = model.clone();
        moved.positions[2][1] += 0.5;
        let out = source
            .write_deformed(&model, &moved, |_| None)
            .expect("write");
        let (again, _) =
            GltfSource::parse(&out, "quad.gltf", Path::new("."), 1 << 20).expect("read again");
        assert_eq!(again.positions, moved.positions);

        let dir = tempfile::tempdir().expect("a directory");
        std::fs::write(dir.path().join("quad data.bin"), &buffer).expect("write");
        let text = quad_json(Some("quad%20data.bin"), buffer.len());
        let (model, source) =
            GltfSource::parse(text.as_bytes(), "quad.gltf", dir.path(), 1 << 20).expect("read");
        let out = source
            .write_deformed(&model, &moved, |_| None)
            .expect("write");
        let out = String::from_utf8(out).expect("utf-8");
        assert!(
            out.contains("data:application/octet-stream;base64,"),
            "embedded"
        );
        let (again, _) = GltfSource::parse(
            out.as_bytes(),
            "quad.gltf",
            Path::new("/nonexistent"),
            1 << 20,
        )
        .expect("self-contained");
        assert_eq!(again.positions, moved.positions);
    }

    #[test]
    fn malformed_files_are_refused_with_their_position() {
        let message = |bytes: &[u8]| parse(bytes).expect_err("refused").to_string();
        assert!(
            message(b"{\"asset\": {\"version\": \"2.0\"},\n \"meshes\": [}")
                .starts_with("quad.glb:2:"),
            "{}",
            message(b"{\"asset\": {\"version\": \"2.0\"},\n \"meshes\": [}")
        );
        assert!(message(b"glTF\x02\0\0\0").contains("byte 8: the GLB header needs 12 bytes"));
        assert!(
            message(b"glTF\x02\0\0\0\xff\0\0\0").contains("declares 255 bytes, the file has 12")
        );
        let buffer = quad_buffer();
        // An index beyond the vertices, reported at its accessor's line.
        let mut bad = buffer.clone();
        let last = bad.len() - 2;
        bad[last..].copy_from_slice(&9u16.to_le_bytes());
        let encoded = base64::engine::general_purpose::STANDARD.encode(&bad);
        let text = quad_json(
            Some(&format!("data:application/octet-stream;base64,{encoded}")),
            bad.len(),
        );
        let error = GltfSource::parse(text.as_bytes(), "quad.gltf", Path::new("."), 1 << 20)
            .expect_err("refused")
            .to_string();
        assert!(
            error.starts_with("quad.gltf:12:5:")
                && error.contains("accessors[2]")
                && error.contains("index 9"),
            "{error}"
        );
        // A buffer view too short for its accessor.
        let text =
            quad_json(None, buffer.len()).replace("\"byteLength\": 48}", "\"byteLength\": 40}");
        let bytes = gltf::binary::Glb {
            header: gltf::binary::Header {
                magic: *b"glTF",
                version: 2,
                length: 0,
            },
            json: std::borrow::Cow::Owned(text.into_bytes()),
            bin: Some(std::borrow::Cow::Owned(buffer.clone())),
        }
        .to_vec()
        .expect("a GLB");
        assert!(
            message(&bytes).contains("do not fit its buffer view"),
            "{}",
            message(&bytes)
        );
        // External files outside the model's directory are not read.
        let text = quad_json(Some("../secret.bin"), buffer.len());
        let error = GltfSource::parse(text.as_bytes(), "quad.gltf", Path::new("."), 1 << 20)
            .expect_err("refused")
            .to_string();
        assert!(
            error.contains("only data URIs and relative file names"),
            "{error}"
        );
    }
}
