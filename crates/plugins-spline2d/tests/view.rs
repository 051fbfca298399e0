//! The editor's view of the worm (examples/worm.ron) with the model its output deforms: the
//! model as the file has it, each vertex placed in the reference mesh where render's
//! deformation evaluates it, and the Bézier patches at those places giving the vertex back at
//! the initial (identity) control points.

use api::exact::rational_to_f64;
use api::{
    BuildRequest, ConstraintSource, ConstraintSystem, SourceView, Values, ViewModel, ViewRequest,
};
use plugins_spline2d::plugin::Spline2dSource;
use spline2d::eval::{FloatSpline, Locator};
use spline2d::model::{deform_model, load_model};
use std::path::PathBuf;

/// The output of examples/worm.ron, as written there.
const WORM_OUTPUT: &str = r#"(picture: "worm.svg", model: "models/worm-model.obj")"#;

fn examples() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// The worm source of examples/worm.ron, built, with the system and initial values it makes.
fn worm() -> (Spline2dSource, ConstraintSystem, Values) {
    let request = BuildRequest {
        base_dir: examples(),
        ..conformance::request(
            "worm",
            r#"(mesh: "meshes/worm.obj", degree: 5, smoothness: 1)"#,
        )
    };
    let mut source = Spline2dSource::default();
    let contribution = source.build(&request).expect("the worm builds");
    let mut system = ConstraintSystem::new();
    let mut values = Values::default();
    contribution
        .apply_to(&mut system, &mut values)
        .expect("applies");
    (source, system, values)
}

fn view_of(source: &Spline2dSource, outputs: &[&str]) -> Result<SourceView, api::SourceError> {
    source
        .view(&ViewRequest {
            schema: api::SCHEMA_VERSION,
            outputs: outputs.iter().map(|o| o.to_string()).collect(),
        })
        .map(|view| view.expect("spline2d draws"))
}

/// `(statements starting with "v ", with "f ")` of an OBJ file.
fn counts(path: &std::path::Path) -> (usize, usize) {
    let text = std::fs::read_to_string(path).expect("reads");
    let starting = |word: &str| text.lines().filter(|l| l.starts_with(word)).count();
    (starting("v "), starting("f "))
}

/// `Σ d!/(i! j! k!) β0^i β1^j β2^k c_ijk` over the control points of a patch, listed in the
/// view's multi-index order `(d,0,0), (d−1,1,0), (d−1,0,1), …, (0,0,d)`.
fn bezier(degree: usize, points: &[[f64; 2]], beta: [f64; 3]) -> [f64; 2] {
    let factorial = |n: usize| (1..=n).map(|k| k as f64).product::<f64>();
    let power = |b: f64, e: usize| (0..e).fold(1.0, |acc, _| acc * b);
    let mut value = [0.0; 2];
    let mut at = 0;
    for i in (0..=degree).rev() {
        for j in (0..=degree - i).rev() {
            let k = degree - i - j;
            let weight = factorial(degree) / (factorial(i) * factorial(j) * factorial(k))
                * power(beta[0], i)
                * power(beta[1], j)
                * power(beta[2], k);
            for c in 0..2 {
                value[c] += weight * points[at][c];
            }
            at += 1;
        }
    }
    assert_eq!(at, points.len(), "a complete patch");
    value
}

#[test]
fn the_worm_view_places_its_model_where_the_identity_patches_give_it_back() {
    let (source, system, values) = worm();
    let view = view_of(&source, &[WORM_OUTPUT]).expect("the view");
    view.validate(&system).expect("a view the host accepts");
    let SourceView::BezierTriangles(view) = view else {
        panic!("spline2d draws Bézier triangles")
    };
    assert_eq!(view.models.len(), 1);
    let model: &ViewModel = &view.models[0];
    assert_eq!(model.name, "models/worm-model.obj");

    // The model as the file has it (every face of the worm's model is a triangle).
    let file = examples().join("models/worm-model.obj");
    let (vertex_lines, face_lines) = counts(&file);
    assert_eq!(
        (model.vertices.len(), model.faces.len()),
        (vertex_lines, face_lines)
    );
    let read = load_model(&file, api::input::DEFAULT_MAX_INPUT_BYTES).expect("the model reads");
    assert_eq!(model.vertices, read.positions);
    let triangles: Vec<Vec<u32>> = read
        .triangles
        .iter()
        .map(|t| t.iter().map(|&v| v as u32).collect())
        .collect();
    assert_eq!(model.faces, triangles);
    assert_eq!(model.embedding.len(), model.vertices.len());

    // Placed exactly where render's deformation evaluates: the vertices left in place are
    // those without a place.
    let spline = source.spline().expect("built");
    let identity: Vec<Vec<api::Rational>> = spline.nominals().iter().map(|p| p.to_vec()).collect();
    let float = FloatSpline::new(spline, &identity).expect("float spline");
    let deformed = deform_model(&read, &float, &Locator::new(spline.mesh())).expect("deforms");
    let unplaced: Vec<usize> = (0..model.embedding.len())
        .filter(|&v| model.embedding[v].is_none())
        .collect();
    assert_eq!(unplaced, deformed.outside);
    assert!(
        unplaced.len() * 10 < model.vertices.len(),
        "most vertices are placed: {} of {} are not",
        unplaced.len(),
        model.vertices.len()
    );

    let reference: Vec<[f64; 2]> = view
        .vertices
        .iter()
        .map(|p| [rational_to_f64(&p[0]), rational_to_f64(&p[1])])
        .collect();
    for (v, (place, p)) in model.embedding.iter().zip(&model.vertices).enumerate() {
        let Some((t, beta)) = *place else { continue };
        let t = t as usize;
        let sum: f64 = beta.iter().sum();
        assert!(
            (sum - 1.0).abs() <= 1e-12,
            "vertex {v}: weights sum to {sum}"
        );
        // The coordinates reproduce the vertex from the triangle's reference vertices ...
        let corners = view.triangles[t].map(|k| reference[k]);
        for c in 0..2 {
            let x: f64 = (0..3).map(|k| beta[k] * corners[k][c]).sum();
            assert!(
                (x - p[c]).abs() <= 1e-9,
                "vertex {v} coordinate {c}: {x} ≠ {}",
                p[c]
            );
        }
        // ... and the patch at the initial control points (the identity) gives it back.
        let points: Vec<[f64; 2]> = view.patches[t]
            .iter()
            .map(|&id| {
                let q = values.get(id);
                [rational_to_f64(&q[0]), rational_to_f64(&q[1])]
            })
            .collect();
        let image = bezier(view.degree, &points, beta);
        for c in 0..2 {
            assert!(
                (image[c] - p[c]).abs() <= 1e-9,
                "vertex {v} coordinate {c}: the patch gives {} for {}",
                image[c],
                p[c]
            );
        }
    }
}

#[test]
fn a_view_without_outputs_or_models_has_no_models() {
    let (source, system, _) = worm();
    for outputs in [&[][..], &[r#"(picture: "worm.svg")"#][..]] {
        let view = view_of(&source, outputs).expect("the view");
        view.validate(&system).expect("valid");
        let SourceView::BezierTriangles(view) = view else {
            panic!("spline2d draws Bézier triangles")
        };
        assert!(view.models.is_empty(), "{outputs:?}");
        assert_eq!(view.triangles.len(), 6);
    }
    // Two outputs naming models give two, in the outputs' order; the rest of the view is the
    // same as without outputs.
    let SourceView::BezierTriangles(plain) = view_of(&source, &[]).expect("plain") else {
        panic!("spline2d draws Bézier triangles")
    };
    let SourceView::BezierTriangles(mut both) = view_of(
        &source,
        &[
            WORM_OUTPUT,
            r#"(picture: "a.svg")"#,
            r#"(model: "models/worm-model.obj")"#,
        ],
    )
    .expect("two models") else {
        panic!("spline2d draws Bézier triangles")
    };
    assert_eq!(both.models.len(), 2);
    assert_eq!(both.models[0], both.models[1]);
    both.models.clear();
    assert_eq!(both, plain);
}

#[test]
fn a_bad_output_or_a_missing_model_fails_the_view_naming_the_file() {
    let (source, _, _) = worm();
    for (output, needle) in [
        (
            r#"(model: "models/no-such-model.obj")"#,
            "no-such-model.obj",
        ),
        (r#"(model: "meshes/../worm.ron")"#, "worm.ron"),
        (r#"(picture: "worm.svg", modle: "x.obj")"#, "modle"),
    ] {
        let error = view_of(&source, &[WORM_OUTPUT, output]).expect_err(output);
        assert!(
            error.message.contains(needle),
            "{output}: {}",
            error.message
        );
        assert!(
            error.message.starts_with("worm output"),
            "{}",
            error.message
        );
    }
}
