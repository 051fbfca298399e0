//! Tests of the terrain source's view ([`api::Prisms`]): its structure on the bundled example,
//! the models of `examples/terrain.ron`'s outputs placed in the mesh, and an editor's
//! evaluation of the view (the formula at [`api::Prisms`]) drawing what the render deforms.

use super::tests::{built, edit, example, small_height_field};
use super::*;
use crate::heightfield::HeightField;
use api::exact::rational_to_f64;
use api::{ConstraintSystem, Prisms, ViewModel};
use std::path::Path;

/// The bundled examples directory.
fn examples() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// The outputs of `examples/terrain.ron`, as written there.
fn example_outputs() -> Vec<String> {
    let run = std::fs::read_to_string(examples().join("terrain.ron")).expect("terrain.ron");
    let outputs = [
        r#"(model: "terrains/hills.asc", picture: "hills.png")"#,
        r#"(model: "terrains/tower.obj")"#,
    ];
    for output in outputs {
        assert!(run.contains(output), "examples/terrain.ron has {output}");
    }
    outputs.map(String::from).to_vec()
}

/// The source's view for `outputs`, checked by the host's validation.
fn prisms(source: &TerrainSource, system: &ConstraintSystem, outputs: &[String]) -> Prisms {
    let view = source
        .view(&ViewRequest {
            schema: api::SCHEMA_VERSION,
            outputs: outputs.to_vec(),
        })
        .expect("view")
        .expect("the terrain has a view");
    view.validate(system).expect("a valid view");
    let SourceView::Prisms(view) = view else {
        panic!("the terrain draws prisms, not {view:?}")
    };
    view
}

/// The value at barycentric `beta` of the Bézier patch of degree `d` whose control values
/// (`dim` coordinates each) are `ids` in the view's multi-index order `(d,0,0), (d−1,1,0),
/// (d−1,0,1), …, (0,0,d)`: `Σ d!/(i! j! k!) β0ⁱ β1ʲ β2ᵏ c_ijk`, computed here from the
/// definition, independently of the source.
fn bezier(values: &Values, ids: &[ParamId], d: usize, beta: [f64; 3], dim: usize) -> Vec<f64> {
    let factorial = |n: usize| (1..=n).map(|k| k as f64).product::<f64>();
    let mut out = vec![0.0; dim];
    let mut ids = ids.iter();
    for i in (0..=d).rev() {
        for j in (0..=d - i).rev() {
            let k = d - i - j;
            let id = ids.next().expect("a control point per multi-index");
            let weight = factorial(d) / (factorial(i) * factorial(j) * factorial(k))
                * beta[0].powi(i as i32)
                * beta[1].powi(j as i32)
                * beta[2].powi(k as i32);
            for (o, c) in out.iter_mut().zip(values.get(*id)) {
                *o += weight * rational_to_f64(c);
            }
        }
    }
    assert!(
        ids.next().is_none(),
        "no control point beyond the multi-indices"
    );
    out
}

/// What an editor draws for vertex `v` of `model`: `ψ` by the formula at [`api::Prisms`] from
/// the view and `values` (`None` for a vertex without an embedding, left in place).
fn drawn(view: &Prisms, model: &ViewModel, values: &Values, v: usize) -> Option<[f64; 3]> {
    let (t, beta) = model.embedding[v]?;
    let t = t as usize;
    let d = view.degree;
    let [x, y, _] = model.vertices[v];
    let (x, y) = match &view.xy {
        Some(xy) => {
            let p = bezier(values, &xy[t], d, beta, 2);
            (p[0], p[1])
        }
        None => (x, y),
    };
    let s0 = bezier(values, &view.bottom[t], d, beta, 1)[0];
    let s1 = bezier(values, &view.top[t], d, beta, 1)[0];
    let alpha = model.relative_height[v];
    Some([x, y, (1.0 - alpha) * s0 + alpha * s1])
}

/// The view of `examples/terrain.ron` (its configuration and outputs): degree 5 on 8
/// triangles, 21 control points per patch of each surface, `φ` edited, the layer (-20, 20);
/// the height field `hills.asc` with every grid sample, faces as the deformed OBJ writes them,
/// embeddings that reproduce `(x, y)`, and with the initial values (`σ0 ≡ -20`, `σ1 ≡ 20`,
/// `φ` the identity) an editor's evaluation gives back every vertex.
#[test]
fn the_view_of_the_example_terrain_places_its_models() {
    let (source, system, values, hills) = example();
    let outputs = example_outputs();
    let view = prisms(&source, &system, &outputs);
    assert_eq!((view.degree, view.smoothness), (5, 1));
    assert_eq!((view.vertices.len(), view.triangles.len()), (9, 8));
    let q = |n: i64| Rational::from_integer(n.into());
    assert_eq!(
        (&view.reference_bottom, &view.reference_top),
        (&q(-20), &q(20))
    );
    let xy = view.xy.as_ref().expect("xy: true edits φ");
    for (surface, patches) in [("bottom", &view.bottom), ("top", &view.top), ("xy", xy)] {
        assert_eq!(patches.len(), 8, "{surface}");
        assert!(patches.iter().all(|p| p.len() == 21), "{surface}");
        let prefix = format!("terrain.{surface}.");
        assert!(
            patches
                .iter()
                .flatten()
                .all(|id| system.params()[id.index()].name.starts_with(&prefix)),
            "{surface}"
        );
    }
    // φ's control points are at their nominal positions, in multi-index order: the point
    // (i, j, k) of triangle t is (i·v0 + j·v1 + k·v2)/d, exactly.
    let d = view.degree;
    for (tri, patch) in view.triangles.iter().zip(xy) {
        let mut ids = patch.iter();
        for i in (0..=d).rev() {
            for j in (0..=d - i).rev() {
                let weights = [i, j, d - i - j].map(|w| Rational::new(w.into(), d.into()));
                let nominal: Vec<Rational> = (0..2)
                    .map(|c| {
                        (0..3)
                            .map(|v| &weights[v] * &view.vertices[tri[v]][c])
                            .sum()
                    })
                    .collect();
                assert_eq!(
                    values.get(*ids.next().expect("a point")),
                    nominal.as_slice()
                );
            }
        }
    }

    assert_eq!(view.models.len(), 2);
    let model = &view.models[0];
    assert_eq!(model.name, "terrains/hills.asc");
    let field = HeightField::read(
        &examples().join("terrains/hills.asc"),
        api::input::DEFAULT_MAX_INPUT_BYTES,
    )
    .expect("hills.asc");
    assert_eq!(model.vertices.len(), field.columns * field.rows);
    assert_eq!(model.vertices, hills.positions);
    let faces: Vec<Vec<u32>> = hills
        .triangles
        .iter()
        .map(|t| t.iter().map(|&v| v as u32).collect())
        .collect();
    assert_eq!(model.faces, faces);
    assert_eq!(model.faces.len(), 2 * 32 * 32);
    assert_eq!(model.relative_height.len(), model.vertices.len());
    let corners = |t: u32| view.triangles[t as usize].map(|v| view.vertices[v].clone());
    let mut placed = 0;
    for (v, p) in model.vertices.iter().enumerate() {
        let alpha = model.relative_height[v];
        assert!((alpha - (p[2] + 20.0) / 40.0).abs() < 1e-15, "vertex {v}");
        let Some((t, beta)) = model.embedding[v] else {
            continue;
        };
        placed += 1;
        assert!((beta.iter().sum::<f64>() - 1.0).abs() < 1e-12, "vertex {v}");
        let corners = corners(t);
        for (c, coordinate) in [p[0], p[1]].into_iter().enumerate() {
            let at: f64 = (0..3)
                .map(|k| beta[k] * rational_to_f64(&corners[k][c]))
                .sum();
            assert!(
                (at - coordinate).abs() < 1e-9,
                "vertex {v}: {at} for {coordinate}"
            );
        }
        let image = drawn(&view, model, &values, v).expect("placed");
        assert!(
            (image[0] - p[0]).abs() < 1e-9,
            "vertex {v}: {image:?} for {p:?}"
        );
        assert!(
            (image[1] - p[1]).abs() < 1e-9,
            "vertex {v}: {image:?} for {p:?}"
        );
        let z = (1.0 - alpha) * -20.0 + alpha * 20.0;
        assert!((image[2] - z).abs() < 1e-9, "vertex {v}: {image:?} for {z}");
        assert!(
            (image[2] - p[2]).abs() < 1e-9,
            "vertex {v}: {image:?} for {p:?}"
        );
    }
    // Every sample lies over the reference mesh [0, 40]² (cell centres) and inside the layer.
    assert_eq!(placed, 33 * 33);

    let tower = &view.models[1];
    assert_eq!(tower.name, "terrains/tower.obj");
    assert_eq!((tower.vertices.len(), tower.faces.len()), (8, 12));
    assert!(tower.embedding.iter().all(Option::is_some));
}

/// After edits of all three surfaces, an editor's evaluation of the view draws each vertex
/// where the render's `ψ` puts it (within 1e-9 on a terrain of size 40), and exactly the
/// vertices `ψ` leaves in place (outside the mesh, above the top) have no embedding.
#[test]
fn the_view_draws_what_the_render_deforms() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let text = small_height_field(&[((0, 0), "25"), ((8, 8), "-20")]);
    std::fs::write(dir.path().join("t.asc"), text).expect("write");
    std::fs::write(
        dir.path().join("m.obj"),
        "v 1 1 0\nv 50 1 0\nv 1 30 2\nv 30 30 20\nf 1 2 3 4\n",
    )
    .expect("write");
    let (mut source, system, mut values) = built(true);
    // The view resolves model paths against the build's base directory.
    if let Some(built) = source.built.as_mut() {
        built.base_dir = dir.path().to_path_buf();
    }
    for operation in [
        r#"(mode: "z1", anchors: ["v4"], neighborhood: 2, dz: "7/3")"#,
        r#"(mode: "z0", anchors: ["v0"], neighborhood: 2, dz: "-1/3")"#,
        r#"(mode: "xy", anchors: ["v4"], neighborhood: 2, translate: ("1/3", "-2/7"))"#,
    ] {
        edit(&source, &system, &mut values, operation);
    }
    let outputs = [
        r#"(model: "t.asc", picture: "t.png")"#,
        r#"(model: "m.obj")"#,
    ]
    .map(String::from)
    .to_vec();
    let view = prisms(&source, &system, &outputs);
    let built = source.built().expect("built");
    let psi = built.psi(&values).expect("psi");
    for (model, file) in view.models.iter().zip(["t.asc", "m.obj"]) {
        let read = load_terrain(&dir.path().join(file), api::input::DEFAULT_MAX_INPUT_BYTES)
            .expect("model");
        let deformed = psi.deform(&read);
        let outside = deformed.outside();
        let unplaced: Vec<usize> = (0..model.vertices.len())
            .filter(|&v| model.embedding[v].is_none())
            .collect();
        assert_eq!(unplaced, outside, "{file}");
        assert!(!outside.is_empty(), "{file} has vertices left in place");
        let mut moved = 0;
        for (v, image) in deformed.model.positions.iter().enumerate() {
            let Some(at) = drawn(&view, model, &values, v) else {
                continue;
            };
            moved += usize::from(at != model.vertices[v]);
            for c in 0..3 {
                assert!(
                    (at[c] - image[c]).abs() < 1e-9,
                    "{file} vertex {v}: drawn {at:?}, rendered {image:?}"
                );
            }
        }
        assert!(moved > 0, "{file}: the edits move something");
    }
    // The OBJ model is fan-triangulated as its render writes it.
    assert_eq!(view.models[1].faces, [vec![0, 1, 2], vec![0, 2, 3]]);
}

/// Without outputs a view has no models, and without `xy` `φ` has no parameters.
#[test]
fn a_view_without_outputs_has_no_models_and_without_xy_no_phi() {
    for xy in [false, true] {
        let (source, system, _) = built(xy);
        let view = prisms(&source, &system, &[]);
        assert!(view.models.is_empty());
        assert_eq!(view.xy.is_some(), xy);
        assert_eq!((view.degree, view.triangles.len()), (5, 8));
        // The reference mesh is the source's, exactly (the centre off the grid lines).
        let q = |n: i64| Rational::from_integer(n.into());
        assert_eq!(view.vertices[4], [q(21), q(19)]);
    }
}

/// A view asked before the source is built, or for an output it cannot read, is refused with
/// a message naming the instance and the problem.
#[test]
fn a_view_of_an_unbuilt_source_or_a_missing_model_is_refused() {
    let request = |outputs: &[&str]| ViewRequest {
        schema: api::SCHEMA_VERSION,
        outputs: outputs.iter().map(|o| o.to_string()).collect(),
    };
    let unbuilt = TerrainSource::default()
        .view(&request(&[]))
        .expect_err("unbuilt");
    assert!(
        unbuilt.message.contains("has not been built"),
        "{unbuilt:?}"
    );
    let (source, _, _) = built(false);
    let missing = source
        .view(&request(&[r#"(model: "no/such.asc")"#]))
        .expect_err("missing model");
    assert!(
        missing.message.starts_with("hills output:") && missing.message.contains("no/such.asc"),
        "{missing:?}"
    );
}

/// The operation texts an editor sends for a drag of a view's point (docs/plugins.md): the
/// mode from the surface the point's parameter belongs to (`z0` bottom, `z1` top, `xy` φ),
/// the anchor named by the parameter's name without the `{source}.{surface}.` prefix. Each
/// plans an edit anchoring exactly that parameter, with a radius or `"all"`.
#[test]
fn operation_texts_for_a_views_points_anchor_those_points() {
    let (source, system, values) = built(true);
    let view = prisms(&source, &system, &[]);
    let xy = view.xy.clone().expect("xy");
    let patch = |surface: &[Vec<ParamId>]| surface[3].clone();
    for (mode, prefix, points, neighborhood) in [
        ("z0", "hills.bottom.", patch(&view.bottom), "2"),
        ("z1", "hills.top.", patch(&view.top), "\"all\""),
        ("xy", "hills.xy.", patch(&xy), "1"),
    ] {
        // A vertex, an edge's point and the triangle's own point (multi-index (3,1,1)).
        for &k in &[0, 1, 7] {
            let id = points[k];
            let name = &system.params()[id.index()].name;
            let anchor = name.strip_prefix(prefix).expect("the surface's prefix");
            let motion = if mode == "xy" {
                r#"translate: ("-1/2", "3")"#
            } else {
                r#"dz: "5/2""#
            };
            let operation = format!(
                r#"(mode: "{mode}", anchors: ["{anchor}"], neighborhood: {neighborhood}, {motion}, steps: 1)"#
            );
            source
                .check_operation(&api::OperationCheckRequest {
                    schema: api::SCHEMA_VERSION,
                    operation: operation.clone(),
                })
                .unwrap_or_else(|e| panic!("{operation}: {e:?}"));
            let plan = source
                .plan(&PlanRequest {
                    schema: api::SCHEMA_VERSION,
                    operation: operation.clone(),
                    system: system.clone(),
                    values: values.clone(),
                })
                .unwrap_or_else(|e| panic!("{operation}: {e:?}"));
            assert_eq!(plan.anchors, [id], "{operation}");
        }
    }
}
