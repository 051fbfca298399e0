//! End-to-end tests through the real `ecles` binary and the real plugin libraries: the bundled
//! examples, malformed inputs (exit codes, messages, no report left behind), and the dynamic
//! plugin path against the static one.

mod common;

use base64::Engine as _;
use common::{
    ecles, example_text, expect_bad_input, library, read_report, root, run_file, run_quietly,
    run_text_ok, stderr, temp, without_origin,
};
use serde_json::Value;

#[test]
fn bundled_spline_examples_run_exactly_and_deterministically() {
    for (name, files) in [
        ("worm", &["worm.svg", "worm-model-deformed.obj"]),
        ("starfish", &["starfish.svg", "starfish-model-deformed.obj"]),
        ("grid", &["grid.svg", "grid-model-deformed.obj"]),
    ] {
        let out_a = temp();
        let out_b = temp();
        let run = format!("examples/{name}.ron");
        for out in [&out_a, &out_b] {
            let o = ecles(&[
                "run",
                &run,
                "--quiet",
                "--out",
                &out.path().display().to_string(),
            ]);
            assert!(o.status.success(), "{name}: {}", stderr(&o));
        }
        let report = read_report(out_a.path());
        assert_eq!(report["consistent"], Value::Bool(true), "{name}");
        for edit in report["edits"].as_array().expect("edits") {
            assert_eq!(edit["solvable"], Value::Bool(true), "{name}: {edit}");
            assert_eq!(edit["max_residual"], "0", "{name}");
            assert_eq!(edit["float_agrees"], Value::Bool(true), "{name}: {edit}");
        }
        if name == "grid" {
            // The local move's R_ED (24 × 36 entries) is cross-checked by the float backend's
            // own dense edit, the global move's (40 × 120) by the sparse twin.
            let methods: Vec<&Value> = report["edits"]
                .as_array()
                .expect("edits")
                .iter()
                .map(|edit| &edit["float_method"])
                .collect();
            assert_eq!(
                methods,
                [&Value::from("dense QR"), &Value::from("sparse QR")]
            );
        }
        for f in files {
            assert!(out_a.path().join(f).exists(), "{name}: {f} missing");
        }
        let a = std::fs::read(out_a.path().join("report.json")).expect("report");
        let b = std::fs::read(out_b.path().join("report.json")).expect("report");
        assert_eq!(
            a, b,
            "{name}: the report must be byte-identical across runs"
        );
    }
    // The Table 19 counts come out of the bundled meshes.
    let o = ecles(&["analyze", "examples/starfish.ron", "--json"]);
    let report: Value = serde_json::from_slice(&o.stdout).expect("JSON on stdout");
    let counts = &report["sources"][0]["counts"];
    assert_eq!(counts["control_points"], 151);
    assert_eq!(counts["conditions"], 50);
    assert_eq!(report["redundant"].as_array().map(Vec::len), Some(2));
    let o = ecles(&["analyze", "examples/grid.ron", "--json"]);
    let report: Value = serde_json::from_slice(&o.stdout).expect("JSON on stdout");
    assert_eq!(report["sources"][0]["counts"]["control_points"], 121);
    assert_eq!(report["sources"][0]["counts"]["conditions"], 40);
    assert_eq!(report["rank"], 76);
}

#[test]
fn a_rejected_edit_exits_1_and_names_the_constraint() {
    let out = temp();
    let o = ecles(&[
        "run",
        "examples/pumps.ron",
        "--quiet",
        "--out",
        &out.path().display().to_string(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let report = read_report(out.path());
    assert_eq!(report["summary"]["failed"], 1);
    let edit = &report["edits"][1];
    assert_eq!(edit["solvable"], Value::Bool(false));
    assert_eq!(edit["conflict"][0], "pump row 2: p4 - p3 = 5");
    // The failed edit changed nothing: the values after edit 0 stand.
    assert_eq!(report["edits"][0]["values"][3]["exact"][0], "9");
}

#[test]
fn model_vertices_outside_the_mesh_are_reported() {
    let (dir, run, out) = run_file(&format!(
        r#"(
            sources: [(name: "g", plugin: "spline2d", config: (mesh: {mesh:?}))],
            edits: [Source(source: "g", operation: (anchors: ["v4"], neighborhood: 2, translate: ("3", "1")))],
            outputs: [(source: "g", output: (model: "far.obj"))],
        )"#,
        mesh = root()
            .join("examples/meshes/grid.obj")
            .display()
            .to_string()
    ));
    // Vertices 1 and 3 lie outside the 40 × 40 reference grid.
    std::fs::write(
        dir.path().join("far.obj"),
        "v 10 10 0\nv 50 10 0\nv 30 30 1\nv -1 5 2\nf 1 2 3\n",
    )
    .expect("write model");
    let o = ecles(&[
        "run",
        &run.display().to_string(),
        "--out",
        &out.display().to_string(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let note = "2 model vertices outside the reference mesh left in place (0-based): 1, 3";
    let report = read_report(&out);
    assert_eq!(
        report["output_notes"],
        serde_json::json!([{ "file": "far-deformed.obj", "note": note }])
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains(&format!("note: far-deformed.obj: {note}")),
        "{stdout}"
    );
    let obj = std::fs::read_to_string(out.join("far-deformed.obj")).expect("model written");
    assert!(
        obj.contains("\nv 50 10 0\n") && obj.contains("\nv -1 5 2\n"),
        "{obj}"
    );
}

/// The edit the model tests make on the example grid: its corner vertex `v0` moved by (2, 1)
/// with its neighbourhood 1 (the grid's far cell, 20 < x, y < 40, is not reached).
const CORNER_EDIT: &str =
    r#"Source(source: "g", operation: (anchors: ["v0"], neighborhood: 1, translate: ("2", "1")))"#;

/// `ecles run` of the example grid with `edits` and `bytes` as its output's model `name`; the
/// deformed model's bytes (`<stem>-deformed.<extension>`).
fn deformed_model_file(name: &str, bytes: &[u8], edits: &str) -> Vec<u8> {
    let (dir, run, out) = run_file(&format!(
        r#"(
            sources: [(name: "g", plugin: "spline2d", config: (mesh: {mesh:?}))],
            edits: [{edits}],
            outputs: [(source: "g", output: (model: {name:?}))],
        )"#,
        mesh = root()
            .join("examples/meshes/grid.obj")
            .display()
            .to_string()
    ));
    std::fs::write(dir.path().join(name), bytes).expect("write model");
    let o = ecles(&[
        "run",
        &run.display().to_string(),
        "--out",
        &out.display().to_string(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (stem, extension) = name.rsplit_once('.').expect("an extension");
    std::fs::read(out.join(format!("{stem}-deformed.{extension}"))).expect("written")
}

/// A textured, smooth-shaded model with quads comes back as its own file: every comment,
/// `mtllib`, `usemtl`, `o`, `g`, `s`, `vt` and face line as written (quads stay quads, index
/// forms and CRLF kept), the vertices the edit does not reach byte for byte (`3.0e1` stays
/// `3.0e1`), the moved ones and their normals written again, and an unedited run gives the
/// file back unchanged.
#[test]
fn a_deformed_obj_keeps_the_models_structure() {
    let model = "# exported\r\nmtllib skin.mtl\r\no sheet\r\n\
        v 10 10 0\r\nv 20 10 0\r\nv 20 20 0\r\nv 10 20 0\r\n\
        v 3.0e1 35 1\r\nv 39 35 1\r\nv 39 39 1\r\n\
        vt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvt 0 1\r\n\
        vn 0 0 1\r\nvn 0.6 0.8 0\r\n\
        g front\r\nusemtl skin\r\ns 1\r\n\
        f 1/1/1 2/2/1 3/3/2 4/4/1\r\nf -3/1/1 -2/2/2 -1/3/1\r\n";
    let run = |edits: &str| {
        String::from_utf8(deformed_model_file("skin.obj", model.as_bytes(), edits)).expect("text")
    };
    assert_eq!(run(""), model);

    let text = run(CORNER_EDIT);
    let (lines, original): (Vec<&str>, Vec<&str>) =
        (text.split("\r\n").collect(), model.split("\r\n").collect());
    assert_eq!(lines.len(), original.len(), "{text}");
    let mut moved = 0;
    for (out, was) in lines.iter().zip(&original) {
        if out != was {
            assert!(
                (out.starts_with("v ") && was.starts_with("v "))
                    || (out.starts_with("vn ") && was.starts_with("vn ")),
                "only positions and normals change: {out:?} was {was:?}"
            );
            moved += usize::from(out.starts_with("v "));
        }
    }
    assert!(moved > 0, "the edit moves the sheet: {text}");
    assert!(
        text.contains("v 3.0e1 35 1\r\nv 39 35 1\r\nv 39 39 1\r\n"),
        "far away: {text}"
    );
    for kept in [
        "mtllib skin.mtl",
        "usemtl skin",
        "g front",
        "s 1",
        "vt 1 1",
        "f 1/1/1 2/2/1 3/3/2 4/4/1",
        "f -3/1/1 -2/2/2 -1/3/1",
    ] {
        assert!(text.contains(kept), "{kept}: {text}");
    }
}

/// An STL model comes back as STL, binary as binary (its 80-byte header, though it begins
/// with "solid ", and each facet's attribute bytes kept) and ASCII as ASCII: facets the edit
/// does not reach byte for byte, moved ones with their corners and normals written again.
#[test]
fn a_deformed_stl_stays_the_same_stl() {
    // Two facets near the grid's corner vertex v0 (which the edit moves) and one in the far
    // cell, which the edit does not reach.
    let facets = [
        [[2.0f32, 2.0, 0.0], [6.0, 2.0, 0.0], [6.0, 6.0, 1.0]],
        [[2.0, 2.0, 0.0], [6.0, 6.0, 1.0], [2.0, 6.0, 0.0]],
        [[30.0, 35.0, 0.0], [39.0, 35.0, 0.0], [39.0, 39.0, 0.0]],
    ];
    let mut binary = b"solid exported".to_vec();
    binary.resize(80, 0);
    binary.extend(3u32.to_le_bytes());
    let mut ascii = String::from("solid part\n");
    for (k, corners) in facets.iter().enumerate() {
        for x in [0.0f32, 0.0, 1.0].iter().chain(corners.iter().flatten()) {
            binary.extend(x.to_le_bytes());
        }
        binary.extend((k as u16 + 40).to_le_bytes());
        ascii.push_str(" facet normal 0 0 1\n  outer loop\n");
        for c in corners {
            ascii.push_str(&format!("   vertex {} {} {}\n", c[0], c[1], c[2]));
        }
        ascii.push_str("  endloop\n endfacet\n");
    }
    ascii.push_str("endsolid part\n");
    for (name, bytes) in [("bin.stl", binary), ("text.stl", ascii.into_bytes())] {
        let written = deformed_model_file(name, &bytes, CORNER_EDIT);
        assert_ne!(written, bytes, "{name}: the edit moves the first facets");
        if name == "bin.stl" {
            assert_eq!(written.len(), bytes.len());
            assert_eq!(written[..84], bytes[..84], "the header");
            for k in 0..3 {
                let attribute = 84 + 50 * k + 48;
                assert_eq!(
                    written[attribute..attribute + 2],
                    bytes[attribute..attribute + 2]
                );
            }
            assert_eq!(written[84 + 100..], bytes[84 + 100..], "the corner facet");
        } else {
            let (w, b) = (
                String::from_utf8(written).expect("text"),
                String::from_utf8(bytes).expect("text"),
            );
            assert_eq!(w.lines().count(), b.lines().count());
            let tail = |t: &str| t.lines().skip(14).collect::<Vec<_>>().join("\n");
            assert_eq!(tail(&w), tail(&b), "the corner facet and endsolid");
            assert!(w.starts_with("solid part\n"));
        }
    }
}

/// A PLY model comes back as PLY with every property: the header as it was (comments,
/// elements, property types), colours kept, the vertex the edit does not reach as it was, the
/// moved ones changed.
#[test]
fn a_deformed_ply_keeps_its_properties() {
    let ply = "ply\nformat ascii 1.0\ncomment scanned\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n2 2 0 11\n6 2 0 22\n6 6 1 33\n35 35 0 44\n3 0 1 2\n";
    let text = String::from_utf8(deformed_model_file("scan.ply", ply.as_bytes(), CORNER_EDIT))
        .expect("text");
    let (header, body) = text.split_once("end_header\n").expect("a header");
    let (old_header, old_body) = ply.split_once("end_header\n").expect("a header");
    assert_eq!(header, old_header);
    // ply-rs ends each data line with a space: the same values, not the same bytes.
    let (lines, old_lines): (Vec<&str>, Vec<&str>) = (
        body.lines().map(str::trim_end).collect(),
        old_body.lines().collect(),
    );
    assert_eq!(lines.len(), old_lines.len());
    assert_eq!(lines[3..], old_lines[3..], "the far vertex and the face");
    for (line, colour) in lines[..3].iter().zip(["11", "22", "33"]) {
        assert!(line.ends_with(&format!(" {colour}")), "{line}");
    }
    assert_ne!(
        lines[..3],
        old_lines[..3],
        "the edit moves the first vertices"
    );
}

/// A GLB sheet near the example grid's corner (three vertices the corner edit moves, one far
/// away), indexed: the file, its JSON chunk and its binary chunk.
fn sheet_glb() -> (Vec<u8>, Vec<u8>, Vec<u8>) {
    let corners = [
        [2.0f32, 2.0, 0.0],
        [6.0, 2.0, 0.0],
        [6.0, 6.0, 1.0],
        [35.0, 35.0, 0.0],
    ];
    let mut bin = Vec::new();
    for [x, y, z] in corners {
        for c in [x, z, -y] {
            bin.extend(c.to_le_bytes());
        }
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        bin.extend(i.to_le_bytes());
    }
    let mut json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
 "meshes": [{{"name": "sheet", "primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}],
 "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [2, 0, -35], "max": [35, 1, -2]}},
  {{"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}}],
 "bufferViews": [{{"buffer": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 12}}],
 "buffers": [{{"byteLength": {}}}]}}"#,
        bin.len()
    )
    .into_bytes();
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    let mut glb = b"glTF".to_vec();
    glb.extend(2u32.to_le_bytes());
    glb.extend(((12 + 8 + json.len() + 8 + bin.len()) as u32).to_le_bytes());
    glb.extend((json.len() as u32).to_le_bytes());
    glb.extend(b"JSON");
    glb.extend(&json);
    glb.extend((bin.len() as u32).to_le_bytes());
    glb.extend(b"BIN\0");
    glb.extend(&bin);
    (glb, json, bin)
}

/// A GLB model comes back as the same GLB: the same length and chunks, the JSON as written but
/// for the position bounds, the vertex the edit does not reach byte for byte, the moved ones
/// changed; an unedited run gives the file back byte for byte. glTF is `+Y` up: the spline
/// point `(x, y, z)` is the glTF point `(x, z, −y)`.
#[test]
fn a_deformed_glb_stays_the_same_glb() {
    let (glb, json, bin) = sheet_glb();
    assert_eq!(
        deformed_model_file("sheet.glb", &glb, ""),
        glb,
        "nothing moves"
    );
    let written = deformed_model_file("sheet.glb", &glb, CORNER_EDIT);
    let out_json_length = u32::from_le_bytes(written[12..16].try_into().expect("4 bytes")) as usize;
    let out_json = String::from_utf8(written[20..20 + out_json_length].to_vec()).expect("JSON");
    let out_bin = &written[20 + out_json_length + 8..];
    assert_eq!(&written[..4], b"glTF");
    assert_eq!(out_bin.len(), bin.len());
    assert_eq!(out_bin[36..], bin[36..], "the far vertex and the indices");
    assert_ne!(
        out_bin[..36],
        bin[..36],
        "the edit moves the first vertices"
    );
    // The JSON as written, but for the bounds of the positions.
    let (before, after) = (String::from_utf8(json.clone()).expect("JSON"), &out_json);
    let cut = |t: &str| {
        let start = t.find(r#""min""#).expect("min");
        let end = t[start..].find('}').expect("the accessor's end") + start;
        (t[..start].to_string(), t[end..].trim_end().to_string())
    };
    assert_eq!(cut(&before), cut(after), "{after}");
}

/// Golden round trips: a model in every format, read and written back by a run that moves
/// nothing, is the same file byte for byte — OBJ with texture coordinates, materials and quads,
/// binary and ASCII STL, ASCII and binary PLY, glTF with a data URI, GLB — and so are a
/// terrain's ESRI grid and GeoTIFF (`<stem>-deformed.asc`, `.tif`; the GeoTIFF is
/// `tests/fixtures/terrain-3x3.tif`, by `tools/make_format_fixtures.py`).
#[test]
fn every_format_comes_back_byte_for_byte_when_nothing_moves() {
    let mut stl = b"binary header".to_vec();
    stl.resize(80, 0);
    stl.extend(1u32.to_le_bytes());
    for x in [
        0.0f32, 0.0, 1.0, 2.0, 2.0, 0.0, 6.0, 2.0, 0.0, 6.0, 6.0, 1.0,
    ] {
        stl.extend(x.to_le_bytes());
    }
    stl.extend(7u16.to_le_bytes());
    let mut binary_ply = b"ply\nformat binary_little_endian 1.0\ncomment scanned\nelement vertex 3\nproperty double x\nproperty double y\nproperty float z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
    for (p, z) in [
        ([2.0f64, 2.0], 0.5f32),
        ([6.0, 2.0], 0.25),
        ([6.0, 6.0], 1.0),
    ] {
        binary_ply.extend(p[0].to_le_bytes());
        binary_ply.extend(p[1].to_le_bytes());
        binary_ply.extend(z.to_le_bytes());
        binary_ply.push(200);
    }
    binary_ply.push(3);
    for i in [0i32, 1, 2] {
        binary_ply.extend(i.to_le_bytes());
    }
    let (glb, _, bin) = sheet_glb();
    let gltf = format!(
        r#"{{"asset": {{"version": "2.0"}}, "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [2, 0, -35], "max": [35, 1, -2]}},
    {{"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 12}}],
  "buffers": [{{"uri": "data:application/octet-stream;base64,{}", "byteLength": {}}}]}}
"#,
        base64::engine::general_purpose::STANDARD.encode(&bin),
        bin.len()
    );
    let cases: [(&str, Vec<u8>); 7] = [
        ("skin.obj", b"mtllib skin.mtl\nv 2 2 0\nv 6 2 0\nv 6 6 1\nv 2 6 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl skin\nf 1/1 2/2 3/3 4/4\n".to_vec()),
        ("binary.stl", stl),
        ("text.stl", b"solid s\n facet normal 0 0 1\n  outer loop\n   vertex 2 2 0\n   vertex 6 2 0\n   vertex 6 6 1\n  endloop\n endfacet\nendsolid s\n".to_vec()),
        ("text.ply", b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n2 2 0\n6 2 0\n6 6 1\n3 0 1 2\n".to_vec()),
        ("binary.ply", binary_ply),
        ("sheet.gltf", gltf.into_bytes()),
        ("sheet.glb", glb),
    ];
    for (name, bytes) in &cases {
        assert_eq!(&deformed_model_file(name, bytes, ""), bytes, "{name}");
    }

    // Terrains without phi: an ESRI grid and a GeoTIFF of the same heights.
    let esri = "ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 10\nNODATA_value -9999\n1 2 3\n4 -9999 6\n7 8 9.5\n";
    let geotiff = std::fs::read(root().join("tests/fixtures/terrain-3x3.tif")).expect("fixture");
    let (dir, run, out) = run_file(&format!(
        r#"(
            sources: [(name: "t", plugin: "terrain", config: (spline: (mesh: {mesh:?}), top: "20"))],
            outputs: [(source: "t", output: (model: "grid.asc")), (source: "t", output: (model: "dem.tif"))],
        )"#,
        mesh = root()
            .join("examples/terrains/reference.obj")
            .display()
            .to_string()
    ));
    std::fs::write(dir.path().join("grid.asc"), esri).expect("write");
    std::fs::write(dir.path().join("dem.tif"), &geotiff).expect("write");
    let o = ecles(&[
        "run",
        &run.display().to_string(),
        "--out",
        &out.display().to_string(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read_to_string(out.join("grid-deformed.asc")).expect("grid"),
        esri
    );
    assert_eq!(
        std::fs::read(out.join("dem-deformed.tif")).expect("GeoTIFF"),
        geotiff
    );
    // The GeoTIFF and the grid are the same terrain: the same deformed OBJ.
    assert_eq!(
        std::fs::read(out.join("dem-deformed.obj")).expect("model"),
        std::fs::read(out.join("grid-deformed.obj")).expect("model")
    );
}

/// A malformed model or terrain of every format is refused before anything runs: exit 2, the
/// run file's line:column of the output, the file and the position in it (line:column for
/// text, the byte for binary containers), nothing written.
#[test]
fn malformed_files_of_every_format_are_refused_with_their_position() {
    let cases: [(&str, &str, &[u8], &str); 10] = [
        ("spline2d", "bad.obj", b"v 1 2\nv 3 q\n", "bad.obj:2:5: "),
        ("spline2d", "bad.stl", b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 1 2 q\n", "bad.stl:4:15: "),
        ("spline2d", "short.stl", b"short", "short.stl:1:1: "),
        ("spline2d", "bad.ply", b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nend_header\n1 2\n3 x\n", "bad.ply:8:3: "),
        ("spline2d", "short.ply", b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nend_header\n\0\0", "short.ply:7:1: not a PLY model this reader accepts: the data (from byte 98) ends at byte 100"),
        ("spline2d", "bad.gltf", br#"{"asset": {"version": "2.0"}, "meshes": [1]}"#, "bad.gltf:1:42: "),
        ("spline2d", "short.glb", b"glTF\x02\0\0\0\xff\0\0\0", "short.glb:1:1: the GLB header (byte 8) declares 255 bytes, the file has 12"),
        ("terrain", "bad.asc", b"ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n3 x\n", "bad.asc:7:3: "),
        ("terrain", "bad.tif", b"II*\0\x08\0\0\0\x01\0", "bad.tif: not a GeoTIFF this reader accepts (10 bytes)"),
        ("terrain", "bad.glb", b"glTF", "bad.glb:1:1: byte 4: the GLB header needs 12 bytes"),
    ];
    for (plugin, name, bytes, expected) in cases {
        let config = match plugin {
            "terrain" => format!(
                "(spline: (mesh: {:?}), top: \"20\")",
                root()
                    .join("examples/terrains/reference.obj")
                    .display()
                    .to_string()
            ),
            _ => format!(
                "(mesh: {:?})",
                root()
                    .join("examples/meshes/grid.obj")
                    .display()
                    .to_string()
            ),
        };
        let (dir, run, out) = run_file(&format!(
            "(sources: [(name: \"s\", plugin: {plugin:?}, config: {config})],\n outputs: [(source: \"s\", output: (model: {name:?}))])"
        ));
        std::fs::write(dir.path().join(name), bytes).expect("write");
        let o = ecles(&[
            "run",
            &run.display().to_string(),
            "--out",
            &out.display().to_string(),
        ]);
        let message = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{name}: {message}");
        assert!(
            message.contains(":2:") && message.contains(expected),
            "{name}: {message}"
        );
        assert!(!out.join("report.json").exists(), "{name}: nothing written");
    }
}

/// A spline picture named `.png` is the SVG's drawing rasterised: a PNG twice the SVG's size,
/// ink where the mesh is, the same bytes on every run.
#[test]
fn a_png_picture_is_the_drawing_rasterised() {
    let run = || {
        let (dir, run, out) = run_file(&format!(
            r#"(
                sources: [(name: "worm", plugin: "spline2d", config: (mesh: {mesh:?}))],
                edits: [Source(source: "worm", operation: (anchors: ["v3"], neighborhood: 3, translate: ("0", "6")))],
                outputs: [(source: "worm", output: (picture: "worm.png")), (source: "worm", output: (picture: "worm.svg"))],
            )"#,
            mesh = root()
                .join("examples/meshes/worm.obj")
                .display()
                .to_string()
        ));
        let o = ecles(&[
            "run",
            &run.display().to_string(),
            "--out",
            &out.display().to_string(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let png = std::fs::read(out.join("worm.png")).expect("written");
        let svg = std::fs::read_to_string(out.join("worm.svg")).expect("written");
        drop(dir);
        (png, svg)
    };
    let (png, svg) = run();
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"));
    let width: f64 = svg
        .split("width=\"")
        .nth(1)
        .and_then(|rest| rest.split('"').next())
        .and_then(|w| w.parse().ok())
        .expect("the SVG's width");
    let decoder = png::Decoder::new(std::io::Cursor::new(&png));
    let mut reader = decoder.read_info().expect("a PNG");
    let mut pixels = vec![0; reader.output_buffer_size().expect("size")];
    let info = reader.next_frame(&mut pixels).expect("pixels");
    assert_eq!(f64::from(info.width), 2.0 * width.round());
    let dark = pixels.chunks(4).filter(|p| p[0] < 128).count();
    assert!(dark > 1000, "the mesh is drawn: {dark} dark pixels");
    assert_eq!(run().0, png, "deterministic");
}

/// The bundled image example: the checkerboard deformed where the edit reaches and the same,
/// pixel for pixel, where it does not; deterministic. A file that is not an image, or a bad
/// fill colour, is bad input (exit 2, named, nothing written).
#[test]
fn an_image_is_deformed_where_the_spline_moves_it() {
    let run = |out: &std::path::Path| {
        let o = ecles(&[
            "run",
            "examples/image.ron",
            "--quiet",
            "--out",
            &out.display().to_string(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(out.join("checker-deformed.png")).expect("written")
    };
    let dir = temp();
    let bytes = run(&dir.path().join("a"));
    assert_eq!(run(&dir.path().join("b")), bytes, "deterministic");
    let decode = |bytes: &[u8]| {
        let mut reader = png::Decoder::new(std::io::Cursor::new(bytes.to_vec()))
            .read_info()
            .expect("a PNG");
        let mut pixels = vec![0; reader.output_buffer_size().expect("size")];
        let info = reader.next_frame(&mut pixels).expect("pixels");
        let channels = pixels.len() / (info.width * info.height) as usize;
        (info.width, info.height, channels, pixels)
    };
    let (w, h, c, out) = decode(&bytes);
    let (wi, hi, ci, input) =
        decode(&std::fs::read(root().join("examples/images/checker.png")).expect("input"));
    assert_eq!((w, h, wi, hi), (400, 400, 400, 400));
    let rgb = |pixels: &[u8], channels: usize, i: usize, j: usize| {
        pixels[channels * (j * 400 + i)..channels * (j * 400 + i) + 3].to_vec()
    };
    // The edit (v4 at the centre, δ_max 3) reaches every triangle of this small grid but not
    // the mesh's corners, whose control points stay: unchanged there; changed at the centre.
    for (i, j) in [(2, 2), (397, 2), (2, 397), (397, 397)] {
        assert_eq!(
            rgb(&out, c, i, j),
            rgb(&input, ci, i, j),
            "corner ({i}, {j})"
        );
    }
    let changed = (0..400 * 400)
        .filter(|k| rgb(&out, c, k % 400, k / 400) != rgb(&input, ci, k % 400, k / 400))
        .count();
    assert!(changed > 10_000, "{changed} pixels changed");

    let mesh = root()
        .join("examples/meshes/grid.obj")
        .display()
        .to_string();
    let not_an_image = root().join("examples/worm.ron").display().to_string();
    expect_bad_input(
        &format!(
            r#"(sources: [(name: "g", plugin: "spline2d", config: (mesh: {mesh:?}))],
                outputs: [(source: "g", output: (image: (file: {not_an_image:?})))])"#
        ),
        &["worm.ron", "not a PNG or JPEG"],
    );
    let image = root()
        .join("examples/images/checker.png")
        .display()
        .to_string();
    expect_bad_input(
        &format!(
            r#"(sources: [(name: "g", plugin: "spline2d", config: (mesh: {mesh:?}))],
                outputs: [(source: "g", output: (image: (file: {image:?}, fill: "white")))])"#
        ),
        &["fill \"white\""],
    );
}

#[test]
fn float_and_exact_disagree_on_the_near_degenerate_mesh() {
    let o = ecles(&["analyze", "examples/near-degenerate.ron", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report: Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(report["rank"], 36);
    assert_eq!(report["cross_check"]["float_rank"], 34);
    assert_eq!(report["cross_check"]["agree"], Value::Bool(false));
    let dropped = report["cross_check"]["margin"]["largest_dropped"]
        .as_f64()
        .expect("margin");
    assert!(dropped < 1e-6 && dropped > 1e-9, "{dropped}");
    let out = temp();
    let dir = out.path().display().to_string();
    let o = ecles(&[
        "run",
        "examples/near-degenerate.ron",
        "--quiet",
        "--out",
        &dir,
    ]);
    assert_eq!(o.status.code(), Some(0));
    let o = ecles(&[
        "run",
        "examples/near-degenerate.ron",
        "--quiet",
        "--strict",
        "--out",
        &dir,
    ]);
    assert_eq!(o.status.code(), Some(1), "--strict fails on disagreement");
}

#[test]
fn malformed_inputs_exit_2_with_located_messages() {
    let meshes = root().join("examples/meshes");
    let grid = meshes.join("grid.obj").display().to_string();
    // RON syntax error: file, line and column.
    expect_bad_input(
        "(\n  sources: [\n    (name: \"a\" plugin: \"linear\"),\n  ],\n)",
        &["run.ron:3:"],
    );
    // Unknown field.
    expect_bad_input("(sources: [], edist: [])", &["run.ron:1:", "edist"]);
    // Missing mesh file.
    expect_bad_input(
        "(sources: [(name: \"s\", plugin: \"spline2d\", config: (mesh: \"nowhere.obj\"))])",
        &["nowhere.obj"],
    );
    // Broken mesh: a zero-area triangle, reported with its line.
    let (dir, _, _) = run_file("");
    let broken = dir.path().join("broken.obj");
    std::fs::write(&broken, "v 0 0\nv 1 0\nv 2 0\nv 0 1\nf 1 2 4\nf 1 2 3\n").expect("mesh");
    expect_bad_input(
        &format!(
            "(sources: [(name: \"s\", plugin: \"spline2d\", config: (mesh: {:?}))])",
            broken.display().to_string()
        ),
        &["broken.obj:6", "zero area"],
    );
    // Inconsistent linear system: the conflicting equations are named.
    expect_bad_input(
        "(sources: [(name: \"l\", plugin: \"linear\", config: (parameters: {\"a\": \"1\", \"b\": \"1\"}, equations: [\"a + b = 2\", \"a + b = 3\"]))])",
        &["contradict", "a + b = 2", "a + b = 3"],
    );
    // A plugin path that is not a library.
    expect_bad_input(
        &format!(
            "(sources: [(name: \"p\", plugin: {:?})])",
            grid.replace("grid.obj", "grid.so")
        ),
        &["grid.so"],
    );
    expect_bad_input(
        &format!("(sources: [(name: \"p\", plugin: {grid:?})])"),
        &["grid.obj"],
    );
    // An unknown built-in plugin.
    expect_bad_input(
        "(sources: [(name: \"p\", plugin: \"c3\")])",
        &["unknown plugin", "c3"],
    );
    // A missing run file.
    let o = ecles(&["run", "no/such/run.ron"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("no/such/run.ron"));
}

#[test]
fn dynamic_plugins_give_the_same_results_as_the_static_ones() {
    let mesh = root()
        .join("examples/meshes/worm.obj")
        .display()
        .to_string();
    let model = root()
        .join("examples/models/worm-model.obj")
        .display()
        .to_string();
    let spline = library("plugins_spline2d_dylib").display().to_string();
    let linear = library("plugins_linear_dylib").display().to_string();
    let run = |spline_plugin: &str, linear_plugin: &str| {
        let text = format!(
            r#"(
                sources: [
                    (name: "w", plugin: {spline_plugin:?}, config: (mesh: {mesh:?})),
                    (name: "l", plugin: {linear_plugin:?}, config: (
                        parameters: {{"a": "1", "b": "2"}},
                        equations: ["a + b = 3"],
                    )),
                ],
                edits: [
                    Source(source: "w", operation: (anchors: ["v3"], neighborhood: 3, translate: ("1", "2"), steps: 2)),
                    Ecles(anchors: {{"l.a": "5/2"}}, derived: ["l.b"]),
                ],
                outputs: [(source: "w", output: (picture: "w.svg", model: {model:?}))],
            )"#
        );
        let (dir, path, out) = run_file(&text);
        let o = run_quietly(&path, &out);
        assert!(o.status.success(), "{}", stderr(&o));
        let svg = std::fs::read(out.join("w.svg")).expect("picture");
        (without_origin(read_report(&out)), svg, dir)
    };
    let (static_report, static_svg, _a) = run("spline2d", "linear");
    let (dynamic_report, dynamic_svg, _b) = run(&spline, &linear);
    assert_eq!(static_report, dynamic_report);
    assert_eq!(static_svg, dynamic_svg);
    assert_eq!(static_report["sources"][1]["rows"], 1);
    assert_eq!(static_report["edits"][1]["values"][1]["exact"][0], "1/2");

    let o = ecles(&["plugins", "--path", &spline]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("plugin spline2d"));
}

#[test]
fn explain_traces_brenners_example_and_analyze_reports_structure() {
    // Brenner's example (3) as a linear system: well-constrained, three blocks in solve order.
    let (_dir, path, _) = run_file(
        r#"(sources: [(name: "b", plugin: "linear", config: (
            parameters: {"x1": "0", "x2": "0", "x3": "0", "x4": "0", "x5": "0", "x6": "0", "x7": "0"},
            equations: ["x1 + x2 = 0", "x1 - x2 = 0", "x2 + x3 + x4 = 0", "x1 + 2 x3 - x4 = 0",
                        "x3 + x5 + x7 = 0", "x4 + x5 - x6 = 0", "x6 + 3 x7 = 0"],
        ))])"#,
    );
    let run = path.display().to_string();
    let o = ecles(&["explain", &run, "b.x6"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.starts_with("b.x6 is fixed by"), "{text}");
    assert!(
        text.contains("b.x1 and b.x2 are fixed by b row 1: x1 + x2 = 0, b row 2: x1 - x2 = 0"),
        "{text}"
    );
    let o = ecles(&["explain", &run, "b.x9"]);
    assert_eq!(o.status.code(), Some(2));
    let o = ecles(&["analyze", &run, "--json"]);
    let report: Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let s = &report["structure"];
    assert_eq!(s["structural_rank"], 7);
    assert_eq!(s["exact_rank"], 7);
    assert_eq!(s["well"]["rows"], 7);
    assert_eq!(s["blocks_total"], 3);
    assert_eq!(s["blocks"][2]["depends_on"], serde_json::json!([1]));
    // The starfish: two dependencies per coordinate carried by the main component.
    let o = ecles(&["analyze", "examples/starfish.ron", "--json"]);
    let report: Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let s = &report["structure"];
    assert_eq!(s["numerical_dependency"], 4);
    assert_eq!(s["dependent"][0]["structural_rank"], 100);
    assert_eq!(s["dependent"][0]["exact_rank"], 96);
}

/// `ecles explain RUN PARAM... --move VALUES --json` on the pump example (p1 + p2 = p3,
/// p4 = p3 + 5): moving p1 and p2 forces p3 and p4 by exactly their sum; moving p1 alone
/// leaves a choice to the others; p3 and p4 cannot move apart, and the row in the way is named.
#[test]
fn explain_says_how_a_move_propagates() {
    let pumps = root().join("examples/pumps.ron").display().to_string();
    let explain = |args: &[&str]| -> Value {
        let mut all = vec!["explain", &pumps];
        all.extend(args);
        let o = ecles(&all);
        assert!(o.status.success(), "{}", stderr(&o));
        serde_json::from_slice(&o.stdout).expect("JSON")
    };
    let both = explain(&["pump.p1", "pump.p2", "--move", "1,2", "--json"]);
    assert_eq!(both["case"], "free");
    assert_eq!(
        both["move"]["moves"],
        serde_json::json!([
            {"param": "pump.p3", "follows": "forced", "by": ["3"]},
            {"param": "pump.p4", "follows": "forced", "by": ["3"]},
        ])
    );
    let alone = explain(&["pump.p1", "--move", "1/2", "--json"]);
    let follows: Vec<&str> = alone["move"]["moves"]
        .as_array()
        .expect("moves")
        .iter()
        .map(|m| m["follows"].as_str().expect("kind"))
        .collect();
    assert_eq!(follows, ["may_stay", "may_stay", "may_stay"]);
    let apart = explain(&["pump.p3", "pump.p4", "--move", "1,0", "--json"]);
    assert_eq!(apart["case"], "partially_constrained");
    assert_eq!(apart["directions"], serde_json::json!([["1", "1"]]));
    assert_eq!(
        apart["move"]["blocked_by"][0]["label"],
        "pump row 2: p4 - p3 = 5"
    );
    // In words, with the blocks of each parameter first.
    let o = ecles(&["explain", &pumps, "pump.p3", "pump.p4", "--move", "1,0"]);
    let text = String::from_utf8(o.stdout).expect("text");
    assert!(
        text.contains("can move only along (1, 1)")
            && text.contains("the requested move is impossible: \"pump row 2: p4 - p3 = 5\""),
        "{text}"
    );
    // Each edit's report says the same for its anchors' move: raising p3 (the second edit,
    // refused because p4 is not derived) forces p4 by exactly 3.
    let (_dir, _, out) = run_file("()");
    let o = ecles(&[
        "run",
        &pumps,
        "--out",
        &out.display().to_string(),
        "--quiet",
    ]);
    assert_eq!(o.status.code(), Some(1), "the second edit is refused");
    let report: Value =
        serde_json::from_slice(&std::fs::read(out.join("report.json")).expect("report"))
            .expect("JSON");
    let second = &report["edits"][1]["propagation"];
    assert_eq!(second["picked"][0]["param"], "pump.p3");
    let forced: Vec<&Value> = second["move"]["moves"]
        .as_array()
        .expect("moves")
        .iter()
        .filter(|m| m["follows"] == "forced")
        .collect();
    assert_eq!(
        forced,
        [&serde_json::json!({"param": "pump.p4", "follows": "forced", "by": ["3"]})]
    );
    // A move of the wrong size and an unknown parameter are input errors.
    for bad in [
        vec!["explain", &pumps, "pump.p1", "--move", "1,2"],
        vec!["explain", &pumps, "pump.nope"],
        vec!["explain", &pumps, "pump.p1", "--move", "x"],
    ] {
        let o = ecles(&bad);
        assert_eq!(o.status.code(), Some(2), "{bad:?}: {}", stderr(&o));
    }
}

/// Brenner's figure 3 through the CLI (`examples/brenner.ron`): each edit drags p1 of its own
/// copy of the figure by (1, 0) under another criterion; report.json says what each chose.
#[test]
fn brenners_figure_3_under_every_criterion() {
    let dir = temp();
    let out = dir.path().display().to_string();
    let o = ecles(&["run", "examples/brenner.ron", "--quiet", "--out", &out]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report = read_report(dir.path());
    let edits = report["edits"].as_array().expect("edits");
    assert_eq!(edits.len(), 5);
    let change = |e: &Value, name: &str| -> String {
        e["values"]
            .as_array()
            .expect("values")
            .iter()
            .find(|v| v["name"] == name)
            .map(|v| v["exact"][0].as_str().expect("exact").to_string())
            .expect("a value")
    };
    for e in edits {
        assert_eq!(e["solvable"], true, "{e}");
        assert_eq!(e["max_residual"], "0");
    }
    // 3(c) least squares on everything: p3 moves by 1/2; no criterion entry (the default).
    assert_eq!(change(&edits[0], "c.x3"), "1/2");
    assert!(edits[0].get("criterion").is_none());
    // 3(b) points first: p3 stays, l2 turns.
    assert_eq!(change(&edits[1], "b.x3"), "0");
    assert_eq!(change(&edits[1], "b.b2"), "1");
    assert_eq!(
        edits[1]["criterion"]["changed"],
        serde_json::json!(["b.b2", "b.c2"])
    );
    // 3(f) with l1 ⊥ l2: p2 and p3 both move by 1/2.
    assert_eq!(
        (change(&edits[2], "f.y2"), change(&edits[2], "f.x3")),
        ("1/2".into(), "1/2".into())
    );
    assert_eq!(edits[2]["criterion"]["value"], "1/2");
    // 3(g) L1: a total move of 1, not unique (a segment of optima).
    let l1 = &edits[3]["criterion"];
    assert_eq!(
        (l1["measure"].as_str(), l1["value"].as_str()),
        (Some("L1"), Some("1"))
    );
    assert_eq!(
        (
            l1["unique"].as_bool(),
            l1["optimal_face_dimension"].as_u64()
        ),
        (Some(false), Some(1))
    );
    // 3(h) fewest: one coordinate, two answers (y2 chosen, x3 the tie).
    let fewest = &edits[4]["criterion"];
    assert_eq!(fewest["value"], "1");
    assert_eq!(fewest["proven_minimal"], true);
    assert_eq!(fewest["minimum_sets"], 2);
    assert_eq!(fewest["ties"], serde_json::json!([["h.x3"]]));
    assert_eq!(change(&edits[4], "h.y2"), "1");
    assert_eq!(change(&edits[4], "h.x3"), "0");
    let text =
        String::from_utf8_lossy(&ecles(&["run", "examples/brenner.ron", "--out", &out]).stdout)
            .into_owned();
    assert!(
        text.contains("not unique: the optima form a set of dimension 1"),
        "{text}"
    );
    assert!(
        text.contains("2 equally small choices, also [h.x3]"),
        "{text}"
    );
}

/// A criterion is checked with the edit before anything runs: an unknown measure and an
/// unknown or repeated primary parameter are refused at their line:column.
#[test]
fn bad_criteria_are_refused_before_the_first_edit() {
    let source = "(name: \"l\", plugin: \"linear\", config: (parameters: {\"a\": \"1\", \"b\": \"1\"}, equations: [\"a + b = 2\"]))";
    expect_bad_input(
        &format!("(sources: [{source}],\n edits: [\n  Ecles(anchors: {{\"l.a\": \"2\"}}, derived: [\"l.b\"], criterion: L3)])"),
        &["run.ron:3:", "L3"],
    );
    expect_bad_input(
        &format!("(sources: [{source}],\n edits: [\n  Ecles(anchors: {{\"l.a\": \"2\"}}, derived: [\"l.b\"], primary: [\"l.c\"])])"),
        &["run.ron:3:3", "edit 0", "primary", "l.c"],
    );
    expect_bad_input(
        &format!("(sources: [{source}],\n edits: [\n  Ecles(anchors: {{\"l.a\": \"2\"}}, derived: [\"l.b\"], primary: [\"l.b\", \"l.b\"])])"),
        &["run.ron:3:3", "listed twice"],
    );
    expect_bad_input(
        &format!("(sources: [{source}],\n edits: [\n  Ecles(anchors: {{\"l.a\": \"2\"}}, derived: [\"l.b\"], hints: {{\"l.b\": \"5\"}}, criterion: Fewest)])"),
        &["run.ron:3:3", "hints belong to least squares"],
    );
}

/// A source operation under another criterion: a spline translation under L1 and with the
/// fewest changed control points still holds every row exactly; the fewest changed are
/// proven minimal, no more than L1 changes, and fewer than the derived points.
#[test]
fn a_source_operation_takes_a_criterion() {
    let text = example_text("worm.ron", &["meshes/"]);
    let start = text.find("edits: [").expect("edits");
    let mut chosen = Vec::new();
    for criterion in ["L1", "Fewest"] {
        let report = run_text_ok(&format!(
            "{}edits: [Source(source: \"worm\", operation: (anchors: [\"v3\"], neighborhood: 2, translate: (\"0\", \"6\")), criterion: {criterion})])",
            &text[..start]
        ));
        let e = report["edits"][0].clone();
        assert_eq!(e["solvable"], true, "{e}");
        assert_eq!(e["max_residual"], "0");
        assert_eq!(e["criterion"]["measure"], criterion);
        chosen.push(e);
    }
    let changed = |e: &Value| e["criterion"]["changed"].as_array().expect("changed").len();
    let fewest = &chosen[1];
    assert_eq!(fewest["criterion"]["proven_minimal"], true);
    assert_eq!(fewest["criterion"]["value"], changed(fewest).to_string());
    assert!(changed(fewest) >= 1);
    assert!(changed(fewest) <= changed(&chosen[0]));
    assert!(changed(fewest) < fewest["derived"].as_array().expect("derived").len());
}

/// Terrain operations take criteria too: a z1 lift with the fewest changed heights and an xy
/// translation with the least absolute change, every row exact.
#[test]
fn terrain_operations_take_criteria() {
    let text = example_text("terrain.ron", &["terrains/", "meshes/", "models/"])
        .replace(
            "dz: \"16\", steps: 2)),",
            "dz: \"16\", steps: 2), criterion: Fewest),",
        )
        .replace(
            "translate: (\"-6\", \"0\"))),",
            "translate: (\"-6\", \"0\")), criterion: L1),",
        );
    let report = run_text_ok(&text);
    let edits = report["edits"].as_array().expect("edits");
    for (e, measure) in edits.iter().zip(["Fewest", "L1"]) {
        assert_eq!(e["solvable"], true, "{e}");
        assert_eq!(e["max_residual"], "0");
        assert_eq!(e["criterion"]["measure"], measure);
        let changed = e["criterion"]["changed"].as_array().expect("changed").len();
        assert!(changed >= 1 && changed < e["derived"].as_array().expect("derived").len());
    }
}
