//! Golden fixtures of every JSON payload a host and a plugin exchange, at
//! [`api::SCHEMA_VERSION`]: a change to an `api` request or answer type that changes its JSON
//! fails here until the fixture is regenerated (`UPDATE_GOLDEN=1 cargo test -p plugin-abi
//! --test payload_schema`) and the schema version is raised, so an older plugin is never broken
//! silently. Fixtures also read back into the same values.

use api::config::TextPosition;
use api::{BezierTriangles, Prisms, SourceView, ViewModel, ViewRequest};
use api::{
    BuildRequest, ConstraintRow, ConstraintSystem, Contribution, Coord, Highlight, NewParameter,
    OperationCheckRequest, OperationPlan, Origin, OutputCheck, OutputCheckRequest, OutputFile,
    ParamId, PlanRequest, PlannedStep, Rational, RenderRequest, RowBody, RowId, SourceError,
    SourceInfo, StructureParts, SummaryItem, Values,
};
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::fmt::Debug;
use std::path::PathBuf;

fn q(n: i64, d: i64) -> Rational {
    Rational::new(n.into(), d.into())
}

/// A small system: a point `s.p` (2D) and a scalar `s.a`, a vector row and a scalar row.
fn system() -> (ConstraintSystem, Values) {
    let mut system = ConstraintSystem::new();
    let p = system.add_parameter("s.p", 2).expect("name");
    let a = system.add_parameter("s.a", 1).expect("name");
    system
        .add_row(ConstraintRow {
            label: "s: p = (1, 2)".into(),
            origin: Origin {
                source: "s".into(),
                item: "p".into(),
            },
            body: RowBody::Vector {
                terms: vec![(p, 2.into())],
                rhs: vec![2.into(), 4.into()],
            },
        })
        .expect("row");
    system
        .add_row(ConstraintRow {
            label: "s: p x = a".into(),
            origin: Origin {
                source: "s".into(),
                item: "x".into(),
            },
            body: RowBody::Scalar {
                terms: vec![
                    (
                        Coord {
                            param: p,
                            component: 0,
                        },
                        1.into(),
                    ),
                    (
                        Coord {
                            param: a,
                            component: 0,
                        },
                        (-1).into(),
                    ),
                ],
                rhs: 0.into(),
            },
        })
        .expect("row");
    let values =
        Values::from_vecs(&system, vec![vec![q(1, 1), q(2, 1)], vec![q(1, 1)]]).expect("values");
    (system, values)
}

/// Compares `value`'s JSON with the fixture `name` (or writes it with `UPDATE_GOLDEN=1`), and
/// reads the fixture back into `value`.
fn golden<T: Serialize + DeserializeOwned + PartialEq + Debug>(name: &str, value: &T) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden")
        .join(format!("{name}.json"));
    let json = serde_json::to_string_pretty(value).expect("serialise") + "\n";
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::write(&path, &json).expect("write fixture");
    }
    let fixture = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e}; generate it with UPDATE_GOLDEN=1 and raise api::SCHEMA_VERSION",
            path.display()
        )
    });
    assert_eq!(
        json, fixture,
        "the JSON of {name} changed: raise api::SCHEMA_VERSION ({}) and regenerate the fixtures with UPDATE_GOLDEN=1",
        api::SCHEMA_VERSION
    );
    let back: T = serde_json::from_str(&fixture).expect("the fixture reads back");
    assert_eq!(&back, value, "{name} does not round-trip");
}

#[test]
fn every_request_and_answer_matches_its_fixture() {
    let (system, values) = system();
    let schema = api::SCHEMA_VERSION;
    golden(
        "build_request",
        &BuildRequest {
            schema,
            name: "t".into(),
            config: "(spline: \"s\")".into(),
            base_dir: "runs".into(),
            system: system.clone(),
            values: values.clone(),
            sources: vec![SourceInfo {
                name: "s".into(),
                kind: "linear".into(),
                config: "()".into(),
            }],
            input_limit: 1024,
        },
    );
    golden(
        "contribution",
        &Contribution {
            parameters: vec![NewParameter {
                name: "t.b".into(),
                value: vec![q(-7, 3)],
            }],
            rows: vec![system.rows()[1].clone()],
            summary: vec![SummaryItem {
                key: "rows".into(),
                value: 1,
            }],
            warnings: vec!["t: a warning".into()],
            inputs: vec!["runs/mesh.obj".into()],
        },
    );
    golden(
        "plan_request",
        &PlanRequest {
            schema,
            operation: "(anchors: [\"p\"])".into(),
            system: system.clone(),
            values: values.clone(),
        },
    );
    golden(
        "operation_plan",
        &OperationPlan {
            anchors: vec![ParamId(0)],
            derived: vec![ParamId(1)],
            weights: vec![q(1, 2)],
            strong: true,
            steps: vec![PlannedStep {
                anchors: vec![vec![q(3, 2), q(2, 1)]],
                hints: vec![vec![q(3, 2)]],
            }],
            summary: vec![SummaryItem {
                key: "initial_derived".into(),
                value: 1,
            }],
        },
    );
    golden(
        "render_request",
        &RenderRequest {
            schema,
            output: "(picture: \"x.svg\")".into(),
            base_dir: "runs".into(),
            system: system.clone(),
            initial: values.clone(),
            values: values.clone(),
            highlight: Some(Highlight {
                anchors: vec![ParamId(0)],
                derived: vec![ParamId(1)],
                independent_rows: vec![RowId(1)],
            }),
            structure: Some(StructureParts {
                over: vec![ParamId(0)],
                well: vec![],
                over_rows: vec![RowId(0)],
                well_rows: vec![],
            }),
            input_limit: 1024,
        },
    );
    golden(
        "output_files",
        &vec![OutputFile::new("x.svg", b"<svg/>".to_vec()).with_note("one note")],
    );
    golden(
        "operation_check_request",
        &OperationCheckRequest {
            schema,
            operation: "(anchors: [\"p\"])".into(),
        },
    );
    golden(
        "output_check_request",
        &OutputCheckRequest {
            schema,
            output: "(model: \"m.obj\")".into(),
            base_dir: "runs".into(),
            input_limit: 1024,
        },
    );
    golden(
        "output_check",
        &OutputCheck::new(vec!["m-deformed.obj".into()], vec!["runs/m.obj".into()]),
    );
    golden(
        "source_error",
        &SourceError::new("t config: unknown field")
            .with_position(TextPosition { line: 2, column: 5 }),
    );
    golden(
        "view_request",
        &ViewRequest {
            schema: api::SCHEMA_VERSION,
            outputs: vec![
                "(picture: \"m.svg\", model: \"m.obj\")".into(),
                "(picture: \"n.svg\")".into(),
            ],
        },
    );
    golden(
        "source_view",
        &Some(SourceView::BezierTriangles(BezierTriangles {
            degree: 1,
            smoothness: 0,
            vertices: vec![[q(0, 1), q(0, 1)], [q(1, 2), q(0, 1)], [q(0, 1), q(3, 1)]],
            triangles: vec![[0, 1, 2]],
            patches: vec![vec![ParamId(0), ParamId(0), ParamId(0)]],
            models: vec![ViewModel {
                name: "m.obj".into(),
                vertices: vec![[0.0, 0.0, 0.0], [0.25, 0.5, 1.0], [9.0, 9.0, -1.5]],
                faces: vec![vec![0, 1, 2]],
                embedding: vec![
                    Some((0, [1.0, 0.0, 0.0])),
                    Some((0, [0.5, 0.25, 0.25])),
                    None,
                ],
                relative_height: Vec::new(),
            }],
        })),
    );
    // A terrain's view: heights `s.a` for both surfaces, `φ` of the point `s.p`, the layer
    // between -20 and 41/2, and a model with its relative heights (the third vertex above the
    // top, left in place).
    let prisms = SourceView::Prisms(Prisms {
        degree: 1,
        smoothness: 0,
        vertices: vec![[q(0, 1), q(0, 1)], [q(1, 2), q(0, 1)], [q(0, 1), q(3, 1)]],
        triangles: vec![[0, 1, 2]],
        bottom: vec![vec![ParamId(1), ParamId(1), ParamId(1)]],
        top: vec![vec![ParamId(1), ParamId(1), ParamId(1)]],
        xy: Some(vec![vec![ParamId(0), ParamId(0), ParamId(0)]]),
        reference_bottom: q(-20, 1),
        reference_top: q(41, 2),
        models: vec![ViewModel {
            name: "hills.asc".into(),
            vertices: vec![[0.0, 0.0, -20.0], [0.25, 0.5, 0.25], [9.0, 9.0, 30.0]],
            faces: vec![vec![0, 1, 2]],
            embedding: vec![
                Some((0, [1.0, 0.0, 0.0])),
                Some((0, [0.5, 0.25, 0.25])),
                None,
            ],
            relative_height: vec![0.0, 0.5, 1.2345679012345678],
        }],
    });
    assert_eq!(prisms.validate(&system), Ok(()), "a view a host accepts");
    golden("source_view_prisms", &Some(prisms));
}

#[test]
fn older_payloads_still_read_and_newer_requests_are_refused() {
    // A request of schema 1 (before the field existed) reads with the defaults.
    let old: OperationCheckRequest =
        serde_json::from_str(r#"{"operation": "()"}"#).expect("schema 1 request");
    assert_eq!(old.schema, 1);
    let error: SourceError = serde_json::from_str(r#"{"message": "m"}"#).expect("schema 1 error");
    assert_eq!(error.at, None);
    // View requests and views from before the view's models (added with serde defaults within
    // schema 2) read with none.
    let request: ViewRequest = serde_json::from_str(r#"{"schema": 2}"#).expect("old request");
    assert!(request.outputs.is_empty());
    let view: Option<SourceView> = serde_json::from_str(
        r#"{"kind": "bezier_triangles", "degree": 1, "smoothness": 0, "vertices": [],
            "triangles": [], "patches": []}"#,
    )
    .expect("old view");
    let Some(SourceView::BezierTriangles(view)) = view else {
        panic!("a view")
    };
    assert!(view.models.is_empty());
    // A plugin refuses a request of a newer schema, naming both versions.
    let mut source = plugin_example::ExampleSource::default();
    let newer = format!(
        r#"{{"schema": {}, "operation": "()"}}"#,
        api::SCHEMA_VERSION + 1
    );
    let (status, bytes) = plugin_abi::dispatch(
        &mut source,
        plugin_abi::abi::METHOD_CHECK_OPERATION,
        newer.as_bytes(),
    );
    assert_eq!(status, plugin_abi::abi::STATUS_BAD_INPUT);
    let text = String::from_utf8_lossy(&bytes);
    assert!(
        text.contains(&format!("payload schema {}", api::SCHEMA_VERSION + 1))
            && text.contains(&format!("this plugin's {}", api::SCHEMA_VERSION)),
        "{text}"
    );
}

/// Floats cross the boundary bit for bit (the view's models are `f64`): the JSON of any finite
/// `f64` reads back as the same `f64` (serde_json's `float_roundtrip`, which plugin-abi turns
/// on; the default parser may be an ulp off for 17-digit numbers).
#[test]
fn floats_cross_the_boundary_unchanged() {
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let values: Vec<f64> = std::iter::from_fn(|| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        Some(f64::from_bits(state))
    })
    .filter(|x| x.is_finite())
    .take(20_000)
    .chain([
        0.1 + 0.2,
        4.554761126667309e-17,
        -0.0,
        f64::MIN_POSITIVE / 3.0,
    ])
    .collect();
    let json = serde_json::to_string(&values).expect("serialise");
    let back: Vec<f64> = serde_json::from_str(&json).expect("parse");
    assert_eq!(
        back.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        values.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
    );
}
