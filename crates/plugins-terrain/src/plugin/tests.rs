//! Tests of the terrain source: contributions, operations, outputs, C1 smoothness of the
//! deformed terrain, exactness where nothing moved.

use super::*;
use api::exact::rational_to_f64;
use api::{ConstraintSystem, Factorization, IntMatrix, LinearBackend, RowBody};
use conformance::{self, Samples};
use ecles::{Edit, EditSpec};
use exact_ldu::{ExactFactorization, ExactLdu};
use std::path::PathBuf;

/// The reference mesh of thesis Table 19.2 (a 2 × 2 grid of squares split by diagonals, 9
/// vertices and 8 triangles), with the centre moved off the grid lines.
const GRID: &str = r#"(mesh: (vertices: [("0", "0"), ("20", "0"), ("40", "0"), ("0", "20"), ("21", "19"),
    ("40", "20"), ("0", "40"), ("20", "40"), ("40", "40")],
    triangles: [(0, 1, 4), (0, 4, 3), (1, 2, 5), (1, 5, 4), (3, 4, 7), (3, 7, 6), (4, 5, 8), (4, 8, 7)]))"#;

fn config(xy: bool) -> String {
    format!(r#"(spline: {GRID}, top: "20", xy: {xy})"#)
}

fn request(config: &str) -> BuildRequest {
    BuildRequest {
        base_dir: PathBuf::from("."),
        ..conformance::request("hills", config)
    }
}

/// A built source with its system and values.
pub(super) fn built(xy: bool) -> (TerrainSource, ConstraintSystem, Values) {
    let mut source = TerrainSource::default();
    let contribution = source.build(&request(&config(xy))).expect("build");
    let mut system = ConstraintSystem::new();
    let mut values = Values::default();
    contribution
        .apply_to(&mut system, &mut values)
        .expect("contribution applies");
    (source, system, values)
}

/// Plans `operation` and applies its last step exactly.
pub(super) fn edit(
    source: &TerrainSource,
    system: &ConstraintSystem,
    values: &mut Values,
    operation: &str,
) {
    let plan = source
        .plan(&PlanRequest {
            schema: api::SCHEMA_VERSION,
            operation: operation.into(),
            system: system.clone(),
            values: values.clone(),
        })
        .expect("plan");
    let spec = EditSpec::new(plan.anchors.clone(), plan.derived.clone());
    let edit: Edit<ExactFactorization> =
        Edit::initialize(&ExactLdu::default(), system, values, &spec).expect("initialize");
    let last = plan.steps.last().expect("a step");
    edit.apply(system, values, &last.anchors, &last.hints)
        .expect("strongly solvable edits succeed");
    assert!(system.violations(values).is_empty());
}

#[test]
fn declares_two_surfaces_or_three_with_their_conditions() {
    for xy in [false, true] {
        let (source, system, values) = built(xy);
        let spline = source.spline().expect("built");
        let (n, conditions) = (spline.points().len(), spline.conditions().len());
        assert_eq!(
            (n, conditions),
            (121, 40),
            "thesis Table 19.2 (rows swapped back)"
        );
        let surfaces = if xy { 3 } else { 2 };
        assert_eq!(system.params().len(), surfaces * n);
        assert_eq!(system.rows().len(), surfaces * conditions);
        assert!(system.violations(&values).is_empty());
        let names: Vec<&str> = system.params().iter().map(|p| &*p.name).collect();
        assert_eq!(names[0], "hills.bottom.v0");
        assert_eq!(names[n], "hills.top.v0");
        assert_eq!(
            values.get(ParamId(0)),
            &[Rational::from_integer((-20).into())]
        );
        assert_eq!(
            values.get(ParamId(n as u32)),
            &[Rational::from_integer(20.into())]
        );
        if xy {
            assert_eq!(names[2 * n], "hills.xy.v0");
            assert!(names.contains(&"hills.xy.v4"));
            assert_eq!(system.params()[2 * n].dim, 2);
        }
        for (s, surface) in SURFACES.iter().take(surfaces).enumerate() {
            let rows = &system.rows()[s * conditions..(s + 1) * conditions];
            assert!(rows
                .iter()
                .all(|r| r.label.starts_with(&format!("hills: {surface} C1 edge"))));
            assert!(rows.iter().all(|r| r.origin.source == "hills"));
            // The rank of each surface's system is points − dim S^r_d.
            let first = (s * n) as u32;
            let sparse: Vec<Vec<(usize, api::Integer)>> = rows
                .iter()
                .map(|r| match &r.body {
                    RowBody::Vector { terms, .. } => terms
                        .iter()
                        .map(|(id, c)| ((id.0 - first) as usize, c.clone()))
                        .collect(),
                    RowBody::Scalar { .. } => panic!("spline rows are vector rows"),
                })
                .collect();
            let matrix = IntMatrix::from_sparse(n, sparse).expect("in range");
            let rank = ExactLdu::default().factor(&matrix).expect("factor").rank();
            assert_eq!(rank, n - spline.spline_space_dimension(), "{surface}");
            // The 8 conditions around the interior vertex carry 2 dependencies.
            assert_eq!(rank, 38);
        }
    }
}

#[test]
fn passes_the_conformance_checks() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let terrain = dir.path().join("t.txt");
    std::fs::write(&terrain, "0 1 2\n1 2 3\n2 3 4\n").expect("write");
    let mut earlier = ConstraintSystem::new();
    earlier.add_parameter("earlier", 1).expect("fresh name");
    let on_earlier = BuildRequest {
        values: Values::zeros(&earlier),
        system: earlier,
        ..request(&config(true))
    };
    let samples = Samples {
        good: vec![request(&config(false)), on_earlier],
        bad: [
            r#"(spline: (mesh: "missing.obj"), top: "1")"#.to_string(),
            format!(r#"(spline: {GRID}, top: "1", bottom: "1")"#),
            format!(r#"(spline: {GRID}, top: 0.5)"#),
            format!(r#"(spline: {GRID}, top: "1", colour: 3)"#),
            format!(r#"(spline: {GRID})"#),
            "(".into(),
        ]
        .iter()
        .map(|c| request(c))
        .collect(),
        operations: vec![
            r#"(mode: "z1", anchors: ["v4"], dz: "3")"#.into(),
            r#"(mode: "xy", anchors: ["v4"], translate: ("1", "0"))"#.into(),
            r#"(mode: "z2", anchors: ["v4"], dz: "3")"#.into(),
        ],
        outputs: vec![
            r#"(picture: "x.png")"#.into(),
            format!(
                r#"(model: {:?}, picture: "x.png", size: 32)"#,
                terrain.display().to_string()
            ),
        ],
    };
    let contributions =
        conformance::check_source(&mut || Box::new(TerrainSource::default()), &samples)
            .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(contributions[1].parameters[0].name, "hills.bottom.v0");
}

#[test]
fn bad_operations_and_outputs_say_what_is_wrong() {
    let (source, system, values) = built(false);
    let plan = |op: &str| {
        source
            .plan(&PlanRequest {
                schema: api::SCHEMA_VERSION,
                operation: op.into(),
                system: system.clone(),
                values: values.clone(),
            })
            .expect_err(op)
            .message
    };
    for (op, needle) in [
        (
            r#"(mode: "xy", anchors: ["v4"], translate: ("1", "0"))"#,
            "needs `xy: true`",
        ),
        (
            r#"(mode: "z1", anchors: ["v4"], translate: ("1", "0"))"#,
            "give dz",
        ),
        (r#"(mode: "z3", anchors: ["v4"], dz: "1")"#, "mode must be"),
        (
            r#"(mode: "z0", anchors: ["v99"], dz: "1")"#,
            "no control point named \"v99\"",
        ),
        (
            r#"(mode: "z0", anchors: ["v4"], dz: 1.5)"#,
            "floating-point",
        ),
        (
            r#"(mode: "z0", anchors: ["v4"], dz: "1", neighborhood: "some")"#,
            "neighborhood",
        ),
        (r#"(mode: "z0", anchors: [], dz: "1")"#, "anchors is empty"),
    ] {
        let message = plan(op);
        assert!(message.starts_with("hills operation: "), "{message}");
        assert!(message.contains(needle), "{needle}: {message}");
    }
    let (source, system, values) = built(true);
    let message = source
        .plan(&PlanRequest {
            schema: api::SCHEMA_VERSION,
            operation: r#"(mode: "xy", anchors: ["v4"], dz: "1")"#.into(),
            system,
            values: values.clone(),
        })
        .expect_err("dz in xy")
        .message;
    assert!(message.contains("exactly one of translate"), "{message}");
    let render = |output: &str| {
        source
            .render(&RenderRequest {
                schema: api::SCHEMA_VERSION,
                input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
                output: output.into(),
                base_dir: PathBuf::from("."),
                system: ConstraintSystem::new(),
                initial: values.clone(),
                values: values.clone(),
                highlight: None,
                structure: None,
            })
            .expect_err(output)
            .message
    };
    assert!(render("(picture: \"x.png\")").contains("give the model"));
    assert!(render("(model: \"t.asc\", picture: \"x.svg\")").contains("must end in .png"));
    assert!(render("(model: \"t.asc\", picture: \"d/x.png\")").contains("no directories"));
    assert!(
        render("(model: \"no/such.asc\")").contains("no/such.asc: the height field cannot be read")
    );
    assert!(render("(model: \"/dev/zero\")").contains("character device"));
    assert!(render("(model: \"t.asc\", size: 100000)").contains("picture width"));
    let message = TerrainSource::default()
        .render(&RenderRequest {
            schema: api::SCHEMA_VERSION,
            input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
            output: "(model: \"t.asc\")".into(),
            base_dir: PathBuf::from("."),
            system: ConstraintSystem::new(),
            initial: Values::default(),
            values: Values::default(),
            highlight: None,
            structure: None,
        })
        .expect_err("not built")
        .message;
    assert!(message.contains("not been built"), "{message}");
}

/// A smooth terrain inside the layer [−20, 20] and its gradient.
fn terrain(p: [f64; 2]) -> (f64, [f64; 2]) {
    let (x, y) = (p[0] / 6.0, p[1] / 9.0);
    (
        4.0 + 3.0 * x.sin() * y.cos(),
        [0.5 * x.cos() * y.cos(), -(3.0 / 9.0) * x.sin() * y.sin()],
    )
}

/// After a z edit and an xy edit the deformed terrain `S(x, y) = ψ(x, y, h(x, y))` of a
/// smooth `h` is C1 across every interior edge of the reference mesh: evaluated with the
/// polynomial pieces of the two triangles, value and gradient agree to rounding.
#[test]
fn deformed_terrains_are_c1_across_triangle_edges() {
    let (source, system, mut values) = built(true);
    let initial = values.clone();
    edit(
        &source,
        &system,
        &mut values,
        r#"(mode: "z1", anchors: ["v4"], neighborhood: 3, dz: "12", steps: 2)"#,
    );
    edit(
        &source,
        &system,
        &mut values,
        r#"(mode: "z0", anchors: ["e1-4:2"], neighborhood: 2, dz: "-5")"#,
    );
    edit(
        &source,
        &system,
        &mut values,
        r#"(mode: "xy", anchors: ["e4-5:2", "e4-5:3"], neighborhood: 4, translate: ("-6", "3/2"))"#,
    );
    let built = source.built().expect("built");
    let psi = built.psi(&values).expect("psi");
    let before = built.psi(&initial).expect("psi");
    let mut moved = [0.0f64; 3];
    let mut checked = 0;
    let vertices = built.spline.mesh().vertices();
    for edge in built
        .spline
        .topology()
        .edges
        .iter()
        .filter(|e| e.is_interior())
    {
        let [a, b] = [edge.a, edge.b].map(|v| vertices[v].clone().map(|c| rational_to_f64(&c)));
        for s in 1..8 {
            let u = f64::from(s) / 8.0;
            let p = [a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1])];
            let (h, dh) = terrain(p);
            let sides: Vec<([f64; 3], [[f64; 3]; 2])> = edge
                .faces
                .iter()
                .map(|&(t, _)| {
                    let (value, j) = psi.jacobian_in(t, [p[0], p[1], h]).expect("triangle");
                    // Chain rule: ∂S/∂x = ∂ψ/∂x + ∂ψ/∂z · ∂h/∂x.
                    let grad =
                        [0, 1].map(|axis| [0, 1, 2].map(|r| j[r][axis] + j[r][2] * dh[axis]));
                    (value, grad)
                })
                .collect();
            let ((v0, g0), (v1, g1)) = (sides[0], sides[1]);
            let scale = v0
                .iter()
                .chain(g0.iter().flatten())
                .fold(1.0f64, |m, x| m.max(x.abs()));
            for (x, y) in v0
                .iter()
                .zip(&v1)
                .chain(g0.iter().flatten().zip(g1.iter().flatten()))
            {
                assert!(
                    (x - y).abs() <= 1e-9 * scale,
                    "edge {}-{} at {p:?}: {x} vs {y}",
                    edge.a,
                    edge.b
                );
            }
            // The edits changed the terrain here (at least somewhere).
            let old = before.map([p[0], p[1], h]).expect("inside");
            for c in 0..3 {
                moved[c] = moved[c].max((v0[c] - old[c]).abs());
            }
            // The float map agrees with its own pieces.
            let mapped = psi.map([p[0], p[1], h]).expect("inside");
            for c in 0..3 {
                assert!((mapped[c] - v0[c]).abs() <= 1e-9 * scale);
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 8 * 7);
    // The derivatives are those of ψ: central differences inside each triangle agree.
    for t in 0..built.spline.mesh().triangles().len() {
        let corners = built.spline.mesh().triangles()[t]
            .map(|v| vertices[v].clone().map(|c| rational_to_f64(&c)));
        let p = [0, 1].map(|c| 0.3 * corners[0][c] + 0.3 * corners[1][c] + 0.4 * corners[2][c]);
        let at = [p[0], p[1], terrain(p).0];
        let (_, j) = psi.jacobian_in(t, at).expect("triangle");
        let step = 1e-5;
        for axis in 0..3 {
            let (mut plus, mut minus) = (at, at);
            plus[axis] += step;
            minus[axis] -= step;
            let (f, g) = (
                psi.map(plus).expect("inside"),
                psi.map(minus).expect("inside"),
            );
            for r in 0..3 {
                let numeric = (f[r] - g[r]) / (2.0 * step);
                assert!(
                    (numeric - j[r][axis]).abs() < 1e-5 * (1.0 + numeric.abs()),
                    "{numeric} vs {}",
                    j[r][axis]
                );
            }
        }
    }
    assert!(moved.iter().all(|m| *m > 0.1), "{moved:?}");
}

/// The bundled terrain example's source (`examples/terrain.ron`) and the bundled height
/// field `examples/terrains/hills.asc`.
pub(super) fn example() -> (TerrainSource, ConstraintSystem, Values, Model) {
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let config = r#"(spline: (mesh: "terrains/reference.obj", degree: 5, smoothness: 1),
        top: "20", xy: true)"#;
    let mut source = TerrainSource::default();
    let contribution = source
        .build(&BuildRequest {
            base_dir: examples.clone(),
            ..conformance::request("terrain", config)
        })
        .expect("build");
    let mut system = ConstraintSystem::new();
    let mut values = Values::default();
    contribution
        .apply_to(&mut system, &mut values)
        .expect("contribution applies");
    let hills = load_terrain(
        &examples.join("terrains/hills.asc"),
        api::input::DEFAULT_MAX_INPUT_BYTES,
    )
    .expect("hills.asc");
    (source, system, values, hills)
}

/// Without an edit the bundled terrain comes back bit-identical (x, y and z of every
/// vertex; `α0·σ0 + α1·σ1` used to round heights such as 4.531 to 4.530999999999998).
#[test]
fn the_undeformed_example_terrain_is_returned_bit_identical() {
    let (source, _, values, hills) = example();
    let built = source.built().expect("built");
    let deformed = built.psi(&values).expect("psi").deform(&hills);
    assert_eq!(deformed.model.triangles, hills.triangles);
    assert_eq!(deformed.model.positions.len(), 33 * 33);
    for (image, p) in deformed.model.positions.iter().zip(&hills.positions) {
        assert_eq!(image.map(f64::to_bits), p.map(f64::to_bits), "{p:?}");
    }
    // Every sample is inside the prisms (cell centres on [0, 40]²), so all went through ψ.
    assert!(deformed.outside().is_empty());
}

/// Local edits of the bundled terrain (the top and bottom raised near vertex 0, φ moved
/// near vertex 2, by awkward amounts): vertices over prisms whose control values did not
/// change are bit-identical, the others agree with the exact `ψ` within the bound of
/// [`Psi::map`].
#[test]
fn local_edits_of_the_example_terrain_leave_far_vertices_bit_identical() {
    let (source, system, mut values, hills) = example();
    for operation in [
        r#"(mode: "z1", anchors: ["v0"], neighborhood: 2, dz: "7/3")"#,
        r#"(mode: "z0", anchors: ["v0"], neighborhood: 2, dz: "-1/3")"#,
        r#"(mode: "xy", anchors: ["v2"], neighborhood: 2, translate: ("1/3", "-2/7"))"#,
    ] {
        edit(&source, &system, &mut values, operation);
    }
    let built = source.built().expect("built");
    let bottom = built.bottom.positions(&values);
    let top = built.top.positions(&values);
    let xy = built.xy.as_ref().expect("xy").positions(&values);
    let surfaces = Surfaces {
        phi: Some(&xy),
        bottom: &bottom,
        top: &top,
    };
    let checked = crate::deform::tests::check_against_exact(
        &built.spline,
        &built.layer,
        surfaces,
        &hills.positions,
    );
    assert!(
        checked.unchanged > 100 && checked.moved > 100,
        "{checked:?}"
    );
    // Samples on the walls between changed and unchanged prisms, where the exact ψ leaves
    // them in place, stay in place in floats too (their barycentric coordinate across the
    // wall is exactly 0, so only the wall's unchanged control values contribute).
    assert!(checked.exactly_in_place > 0, "{checked:?}");
    assert_eq!(checked.moved_in_floats_only, 0, "{checked:?}");
    eprintln!("{checked:?}");
}

/// An ESRI grid of 9 × 9 samples over [0, 40]² (cell 5), heights `(r·c) mod 7` but at the
/// `special` (row, column) samples.
pub(super) fn small_height_field(special: &[((usize, usize), &str)]) -> String {
    let mut text = String::from("ncols 9\nnrows 9\nxllcenter 0\nyllcenter 0\ncellsize 5\n");
    for r in 0..9 {
        let row: Vec<String> = (0..9)
            .map(|c| match special.iter().find(|(at, _)| *at == (r, c)) {
                Some((_, h)) => h.to_string(),
                None => format!("{}", (r * c) % 7),
            })
            .collect();
        text.push_str(&row.join(" "));
        text.push('\n');
    }
    text
}

#[test]
fn renders_the_deformed_model_and_pictures() {
    let dir = tempfile::tempdir().expect("temporary directory");
    // One sample above the top.
    std::fs::write(
        dir.path().join("t.asc"),
        small_height_field(&[((0, 0), "25")]),
    )
    .expect("write");
    std::fs::write(
        dir.path().join("m.obj"),
        "v 1 1 0\nv 50 1 0\nv 1 30 2\nf 1 2 3\n",
    )
    .expect("write");
    let (source, system, mut values) = built(true);
    let initial = values.clone();
    edit(
        &source,
        &system,
        &mut values,
        r#"(mode: "z1", anchors: ["v4"], dz: "10")"#,
    );
    let built = source.built().expect("built");
    let highlight = api::Highlight {
        anchors: vec![built.top.ids[4]],
        derived: vec![built.top.ids[5], built.top.ids[6]],
        independent_rows: vec![],
    };
    let render = |output: &str| {
        source.render(&RenderRequest {
            schema: api::SCHEMA_VERSION,
            input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
            output: output.into(),
            base_dir: dir.path().to_path_buf(),
            system: system.clone(),
            initial: initial.clone(),
            values: values.clone(),
            highlight: Some(highlight.clone()),
            structure: None,
        })
    };
    // The light's options: checked, and they change the pictures.
    for (bad, needle) in [
        (
            r#"(model: "t.asc", picture: "t.png", exaggeration: "0")"#,
            "must be positive",
        ),
        (
            r#"(model: "t.asc", picture: "t.png", horizontal_units: "feet")"#,
            "\"same\" or \"degrees\"",
        ),
    ] {
        let e = render(bad).expect_err(bad);
        assert!(e.message.contains(needle), "{}", e.message);
    }
    let steep = render(r#"(model: "t.asc", picture: "t.png", size: 64, exaggeration: "5/2", horizontal_units: "same")"#)
        .expect("render");
    let rendered = render(r#"(model: "t.asc", picture: "t.png", size: 64)"#).expect("render");
    assert_ne!(
        steep[3].bytes, rendered[3].bytes,
        "an exaggerated relief is lit differently"
    );
    let names: Vec<&str> = rendered.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "t-deformed.obj",
            "t-deformed.asc",
            "t-before.png",
            "t-after.png"
        ]
    );
    // The model and the relief pictures (the grid written back is checked below).
    let files: Vec<_> = rendered
        .iter()
        .filter(|f| f.name != "t-deformed.asc")
        .cloned()
        .collect();
    let obj = String::from_utf8(files[0].bytes.clone()).expect("utf8");
    assert!(obj.starts_with(
        "# hills: deformed by the 2.5D map psi (prisms between z = -20 and z = 20)\n"
    ));
    // The sample at height 25 (north-west corner, vertex 72) is above the top.
    assert!(
        obj.contains(
            "# 1 vertices below the bottom or above the top were left in place (0-based): [72]"
        ),
        "{obj}"
    );
    assert_eq!(
        files[0].notes,
        ["1 model vertex below the bottom or above the top left in place (0-based): 72"]
    );
    assert!(files[1..].iter().all(|f| f.notes.is_empty()));
    assert!(obj.contains("81 vertices, 128 triangles"));
    assert!(files[1..].iter().all(|f| f.bytes.starts_with(b"\x89PNG")));
    assert_ne!(files[1].bytes, files[2].bytes);
    // Deterministic.
    assert_eq!(
        render(r#"(model: "t.asc", picture: "t.png", size: 64)"#).expect("again"),
        rendered
    );
    // An OBJ model comes back as its own file, only what moved written again; the vertex left
    // in place is named in the report.
    let files = render(r#"(model: "m.obj")"#).expect("render");
    let obj = String::from_utf8(files[0].bytes.clone()).expect("utf8");
    let original = std::fs::read_to_string(dir.path().join("m.obj")).expect("the model");
    assert_eq!(obj.lines().count(), original.lines().count(), "{obj}");
    for (out, was) in obj.lines().zip(original.lines()) {
        assert!(
            out == was || (out.starts_with("v ") && was.starts_with("v ")),
            "{out} / {was}"
        );
    }
    assert_eq!(
        files[0].notes,
        ["1 model vertex outside the reference mesh left in place (0-based): 1"]
    );
    assert!(obj.contains("\nv 50 1 0\n"));
}

/// A terrain without φ keeps its samples on their grid: its ESRI grid is also written back as
/// the same grid, header and untouched values byte for byte, the raised ones written again;
/// with φ the deformed surface is sampled on the grid again, which after a z edit (φ the
/// identity) gives the same grid.
#[test]
fn an_esri_grid_without_phi_comes_back_as_the_same_grid() {
    let dir = tempfile::tempdir().expect("dir");
    let grid = small_height_field(&[]);
    std::fs::write(dir.path().join("t.asc"), &grid).expect("write");
    let mut written_with_phi = None;
    let mut written_without = None;
    for xy in [true, false] {
        let files = edited_and_rendered(
            xy,
            r#"(mode: "z1", anchors: ["v4"], dz: "10")"#,
            dir.path(),
            r#"(model: "t.asc")"#,
        );
        let names: Vec<&str> = files.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(names, ["t-deformed.obj", "t-deformed.asc"]);
        if xy {
            // φ is the identity after a z edit: the grid sampled again is the same grid.
            written_with_phi = Some(files[1].bytes.clone());
            continue;
        }
        let written = String::from_utf8(files[1].bytes.clone()).expect("text");
        let (head, body) = grid.split_at(grid.find("\n0").map_or(0, |i| i + 1));
        assert!(
            written.starts_with(head),
            "the header as written:\n{written}"
        );
        let (old, new): (Vec<&str>, Vec<&str>) = (
            body.split_whitespace().collect(),
            written[head.len()..].split_whitespace().collect(),
        );
        assert_eq!(old.len(), new.len());
        let changed = old.iter().zip(&new).filter(|(a, b)| a != b).count();
        assert!(
            changed > 0 && changed < old.len(),
            "{changed} of {} heights raised",
            old.len()
        );
        // The raised heights are the deformed model's.
        let model = spline2d::model::parse_model(
            &String::from_utf8(files[0].bytes.clone()).expect("text"),
            "t.obj",
        )
        .expect("the OBJ reads");
        let field = crate::heightfield::HeightField::parse_esri(&written, "t.asc").expect("reads");
        let heights: Vec<f64> = field.heights.iter().flatten().copied().collect();
        let zs: Vec<f64> = model.positions.iter().map(|p| p[2]).collect();
        assert_eq!(heights, zs);
        written_without = Some(files[1].bytes.clone());
    }
    assert_eq!(written_with_phi, written_without);
}

/// A GeoTIFF terrain without φ comes back as the same GeoTIFF too (`t-deformed.tif`): the same
/// georeferencing, the raised heights those of the deformed model.
#[test]
fn a_geotiff_without_phi_comes_back_as_a_geotiff() {
    use tiff::encoder::{colortype, TiffEncoder};
    use tiff::tags::Tag;
    let dir = tempfile::tempdir().expect("dir");
    let grid = crate::heightfield::HeightField::parse_esri(&small_height_field(&[]), "t.asc")
        .expect("the grid");
    // The same grid as a GeoTIFF: `PixelIsArea`, tie point at the raster's north-west corner.
    let f = |q: &api::Rational| api::exact::rational_to_f64(q);
    let (cx, cy) = (f(&grid.cell[0]), f(&grid.cell[1]));
    let west = f(&grid.origin[0]) - cx / 2.0;
    let north = f(&grid.origin[1]) + (grid.rows as f64 - 0.5) * cy;
    let mut samples = Vec::new();
    for row in (0..grid.rows).rev() {
        for column in 0..grid.columns {
            samples.push(grid.heights[row * grid.columns + column].expect("a full grid") as f32);
        }
    }
    let mut bytes = std::io::Cursor::new(Vec::new());
    let mut encoder = TiffEncoder::new(&mut bytes).expect("encoder");
    let mut image = encoder
        .new_image::<colortype::Gray32Float>(grid.columns as u32, grid.rows as u32)
        .expect("image");
    image
        .encoder()
        .write_tag(Tag::ModelPixelScaleTag, &[cx, cy, 0.0][..])
        .expect("tag");
    image
        .encoder()
        .write_tag(
            Tag::ModelTiepointTag,
            &[0.0, 0.0, 0.0, west, north, 0.0][..],
        )
        .expect("tag");
    image.write_data(&samples).expect("data");
    std::fs::write(dir.path().join("t.tif"), bytes.into_inner()).expect("write");
    let files = edited_and_rendered(
        false,
        r#"(mode: "z1", anchors: ["v4"], dz: "10")"#,
        dir.path(),
        r#"(model: "t.tif")"#,
    );
    let names: Vec<&str> = files.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["t-deformed.obj", "t-deformed.tif"]);
    let written = crate::geotiff::parse(&files[1].bytes, "t-deformed.tif").expect("reads");
    assert_eq!(
        (&written.origin, &written.cell),
        (&grid.origin, &grid.cell),
        "the georeferencing"
    );
    let model = spline2d::model::parse_model(
        &String::from_utf8(files[0].bytes.clone()).expect("text"),
        "t.obj",
    )
    .expect("the OBJ reads");
    let heights: Vec<f64> = written.heights.iter().flatten().copied().collect();
    let zs: Vec<f64> = model
        .positions
        .iter()
        .map(|p| f64::from(p[2] as f32))
        .collect();
    assert_eq!(heights, zs, "the deformed heights, as f32 samples");
    let raised = heights
        .iter()
        .zip(grid.heights.iter().flatten())
        .filter(|(a, b)| a != b)
        .count();
    assert!(raised > 0 && raised < heights.len(), "{raised} raised");
}

/// An xy edit moves the samples off their grid: the ESRI grid written back is the deformed
/// surface sampled on the grid again — the samples the edit leaves in place as written (byte
/// for byte), some near the moved point changed, every written height finite.
#[test]
fn an_xy_edit_writes_the_grid_sampled_again() {
    let dir = tempfile::tempdir().expect("dir");
    let grid = small_height_field(&[]);
    std::fs::write(dir.path().join("t.asc"), &grid).expect("write");
    let files = edited_and_rendered(
        true,
        r#"(mode: "xy", anchors: ["v4"], neighborhood: 1, translate: ("3", "2"))"#,
        dir.path(),
        r#"(model: "t.asc")"#,
    );
    assert_eq!(files[1].name, "t-deformed.asc");
    let written = String::from_utf8(files[1].bytes.clone()).expect("text");
    let field = crate::heightfield::HeightField::parse_esri(&written, "t.asc").expect("reads");
    let old = crate::heightfield::HeightField::parse_esri(&grid, "t.asc").expect("reads");
    let changed = old
        .heights
        .iter()
        .zip(&field.heights)
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        changed > 0 && changed < old.heights.len() / 2,
        "{changed} of {} samples changed",
        old.heights.len()
    );
    assert!(field.heights.iter().flatten().all(|h| h.is_finite()));
    // The header as written.
    let header = |t: &str| t.lines().take(6).collect::<Vec<_>>().join("\n");
    assert_eq!(header(&written), header(&grid));
}

/// Builds the terrain (with φ when `xy`), applies `operation` and renders `output` from
/// `directory`: the output's files.
fn edited_and_rendered(
    xy: bool,
    operation: &str,
    directory: &std::path::Path,
    output: &str,
) -> Vec<api::OutputFile> {
    let (source, system, mut values) = built(xy);
    let initial = values.clone();
    edit(&source, &system, &mut values, operation);
    source
        .render(&RenderRequest {
            schema: api::SCHEMA_VERSION,
            input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
            output: output.into(),
            base_dir: directory.to_path_buf(),
            system,
            initial,
            values,
            highlight: None,
            structure: None,
        })
        .expect("render")
}
