//! Unit tests of the source: both forms, name resolution, cancelling rows, error messages.

use super::*;
use api::{ConstraintSystem, RowId, Values};

fn request(name: &str, config: &str, system: ConstraintSystem) -> BuildRequest {
    let values = Values::zeros(&system);
    BuildRequest {
        schema: api::SCHEMA_VERSION,
        input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
        name: name.into(),
        config: config.into(),
        base_dir: ".".into(),
        system,
        values,
        sources: vec![],
    }
}

fn build(name: &str, config: &str, system: ConstraintSystem) -> Result<Contribution, SourceError> {
    LinearSource::new().build(&request(name, config, system))
}

fn int(n: i64) -> Integer {
    Integer::from(n)
}

fn q(n: i64, d: i64) -> Rational {
    Rational::new(n.into(), d.into())
}

/// The terms and right-hand side of a scalar row as `(param index, coefficient)`.
fn scalar(row: &ConstraintRow) -> (Vec<(u32, Integer)>, Integer) {
    match &row.body {
        RowBody::Scalar { terms, rhs } => (
            terms
                .iter()
                .map(|(c, v)| {
                    assert_eq!(c.component, 0);
                    (c.param.0, v.clone())
                })
                .collect(),
            rhs.clone(),
        ),
        RowBody::Vector { .. } => panic!("scalar row expected"),
    }
}

fn summary(c: &Contribution) -> Vec<(&str, u64)> {
    c.summary
        .iter()
        .map(|s| (s.key.as_str(), s.value))
        .collect()
}

#[test]
fn equations_form_declares_prefixed_parameters_and_scalar_rows() {
    let c = build(
        "lin",
        r#"(
            parameters: { "p1": "3", "p2": "-2.5", "p3": "7/3", "p4": "0" },
            equations: [ "p1 + p2 - p3 = 0", "  3 p3 - 5 p4 = 7 ", "2 p1 = p2 + 3 + p2" ],
        )"#,
        ConstraintSystem::new(),
    )
    .expect("valid");
    let names: Vec<&str> = c.parameters.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["lin.p1", "lin.p2", "lin.p3", "lin.p4"]);
    assert_eq!(c.parameters[1].value, vec![q(-5, 2)]);
    assert_eq!(c.parameters[2].value, vec![q(7, 3)]);
    assert_eq!(c.rows.len(), 3);
    assert_eq!(
        scalar(&c.rows[0]),
        (vec![(0, int(1)), (1, int(1)), (2, int(-1))], int(0))
    );
    assert_eq!(
        scalar(&c.rows[1]),
        (vec![(2, int(3)), (3, int(-5))], int(7))
    );
    // Repeated names are summed.
    assert_eq!(
        scalar(&c.rows[2]),
        (vec![(0, int(2)), (1, int(-2))], int(3))
    );
    assert_eq!(c.rows[1].label, "3 p3 - 5 p4 = 7");
    assert_eq!(
        c.rows[1].origin,
        Origin {
            source: "lin".into(),
            item: "equation 2".into()
        }
    );
    assert_eq!(summary(&c), [("parameters", 4), ("equations", 3)]);
    assert!(c.warnings.is_empty());
}

#[test]
fn ids_follow_declaration_order_after_existing_parameters() {
    let mut system = ConstraintSystem::new();
    system.add_parameter("other.x", 1).expect("new");
    system.add_parameter("other.y", 1).expect("new");
    let c = build(
        "lin",
        r#"(parameters: { "z": 1, "b": 2, "a": 3 }, equations: ["a - z = 2"])"#,
        system,
    )
    .expect("valid");
    let names: Vec<&str> = c.parameters.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["lin.z", "lin.b", "lin.a"]);
    assert_eq!(
        scalar(&c.rows[0]),
        (vec![(2, int(-1)), (4, int(1))], int(2))
    );
}

#[test]
fn equations_may_use_earlier_parameters_by_full_name() {
    let mut system = ConstraintSystem::new();
    system.add_parameter("other.x", 1).expect("new");
    system.add_parameter("other.pt", 2).expect("new");
    let c = build(
        "lin",
        r#"(parameters: { "y": "1" }, equations: ["other.x = 2 y", "lin.y + other.x = 4"])"#,
        system.clone(),
    )
    .expect("valid");
    assert_eq!(
        scalar(&c.rows[0]),
        (vec![(0, int(1)), (2, int(-2))], int(0))
    );
    // Own parameters may be named by their full name too.
    assert_eq!(scalar(&c.rows[1]), (vec![(0, int(1)), (2, int(1))], int(4)));

    // A source with equations only, constraining earlier parameters.
    let c = build("extra", r#"(equations: ["2 other.x = 5"])"#, system.clone()).expect("valid");
    assert!(c.parameters.is_empty());
    assert_eq!(scalar(&c.rows[0]), (vec![(0, int(2))], int(5)));
    assert_eq!(summary(&c), [("parameters", 0), ("equations", 1)]);

    // Own parameters win over an earlier parameter of the same (full) name.
    let c = build(
        "lin",
        r#"(parameters: { "other.x": 0 }, equations: ["other.x = 1"])"#,
        system.clone(),
    )
    .expect("valid");
    assert_eq!(c.parameters[0].name, "lin.other.x");
    assert_eq!(scalar(&c.rows[0]), (vec![(2, int(1))], int(1)));

    // Short names of earlier sources are not resolved.
    let e = build("lin", r#"(equations: ["y + x = 1"])"#, system.clone()).expect_err("unknown");
    assert_eq!(
        e.message,
        "equation 1, column 1: unknown parameter 'y' (neither declared in `parameters` nor the \
         full name of an earlier source's parameter)"
    );
    let e = build(
        "lin",
        r#"(equations: ["1 = 1", "1 + x = 1"])"#,
        system.clone(),
    )
    .expect_err("unknown");
    assert!(
        e.message
            .starts_with("equation 2, column 5: unknown parameter 'x'"),
        "{}",
        e.message
    );
    // Vector parameters are refused.
    let e = build("lin", r#"(equations: ["other.pt = 1"])"#, system.clone()).expect_err("vector");
    assert_eq!(
        e.message,
        "equation 1, column 1: parameter 'other.pt' has 2 coordinates; linear equations are \
         over scalar parameters"
    );
    // Declaring a name an earlier source already holds is refused.
    let e = build("other", r#"(parameters: { "x": 1 })"#, system).expect_err("duplicate");
    assert_eq!(
        e.message,
        "parameter \"x\": an earlier source already declares \"other.x\""
    );
}

#[test]
fn applying_with_an_earlier_source_keeps_every_row_satisfied() {
    let mut system = ConstraintSystem::new();
    let mut values = Values::default();
    let first = build(
        "other",
        r#"(parameters: { "x": "3/2", "w": 1 }, equations: ["2 x - 3 w = 0"])"#,
        system.clone(),
    )
    .expect("valid");
    first.apply_to(&mut system, &mut values).expect("apply");
    let second = build(
        "lin",
        r#"(parameters: { "y": "-1.5" }, equations: ["other.x + y = 0"])"#,
        system.clone(),
    )
    .expect("valid");
    second.apply_to(&mut system, &mut values).expect("apply");
    assert_eq!(system.params().len(), 3);
    assert_eq!(system.rows_of(ParamId(0)), &[RowId(0), RowId(1)]);
    assert!(system.violations(&values).is_empty());
}

#[test]
fn cancelling_rows_are_kept_only_when_inconsistent() {
    let c = build(
        "lin",
        r#"(parameters: { "p1": 0, "p2": 0 }, equations: [
            "p1 - p1 = 3", "p1 + p2 = p2 + p1", "2 = 2", "1 = 2", "0 p1 + p2 = 1",
        ])"#,
        ConstraintSystem::new(),
    )
    .expect("valid");
    let labels: Vec<&str> = c.rows.iter().map(|r| r.label.as_str()).collect();
    assert_eq!(labels, ["p1 - p1 = 3", "1 = 2", "0 p1 + p2 = 1"]);
    assert_eq!(scalar(&c.rows[0]), (vec![], int(3)));
    assert_eq!(scalar(&c.rows[1]), (vec![], int(1)));
    // Zero coefficients are dropped.
    assert_eq!(scalar(&c.rows[2]), (vec![(1, int(1))], int(1)));
    // Origins keep the numbering of the config.
    assert_eq!(c.rows[2].origin.item, "equation 5");
    assert_eq!(
        c.warnings,
        [
            "equation 1 (\"p1 - p1 = 3\"): every coefficient cancels, leaving 0 = 3; kept, so \
             the system is inconsistent",
            "equation 2 (\"p1 + p2 = p2 + p1\"): every coefficient cancels (0 = 0); dropped",
            "equation 3 (\"2 = 2\"): every coefficient cancels (0 = 0); dropped",
            "equation 4 (\"1 = 2\"): every coefficient cancels, leaving 0 = 1; kept, so the \
             system is inconsistent",
        ]
    );
    assert_eq!(summary(&c), [("parameters", 2), ("equations", 3)]);
    // The host sees the inconsistency as a violated row.
    let (mut system, mut values) = (ConstraintSystem::new(), Values::default());
    c.apply_to(&mut system, &mut values).expect("apply");
    let violated: Vec<RowId> = system
        .violations(&values)
        .into_iter()
        .map(|v| v.0)
        .collect();
    assert_eq!(violated, [RowId(0), RowId(1), RowId(2)]);
}

#[test]
fn equation_errors_name_the_equation_and_column() {
    let config = r#"(parameters: { "p1": 1, "p2": 2 }, equations: ["p1 = p2", "p1 + * p2 = 0"])"#;
    let e = build("lin", config, ConstraintSystem::new()).expect_err("syntax");
    assert_eq!(
        e.message,
        "equation 2, column 6: expected a parameter name or a number, found '*'"
    );
    let config = r#"(parameters: { "p1": 1, "p2": 2 }, equations: ["0.5 p1 = p2"])"#;
    let e = build("lin", config, ConstraintSystem::new()).expect_err("decimal");
    assert_eq!(
        e.message,
        "equation 1, column 1: coefficients must be integers; multiply the equation through \
         (found '0.5')"
    );
}

#[test]
fn floats_are_refused_with_advice_to_quote_them() {
    let e = build(
        "lin",
        r#"(parameters: { "p1": 0.1 }, equations: [])"#,
        ConstraintSystem::new(),
    )
    .expect_err("float");
    assert!(
        e.message
            .starts_with("parameter \"p1\": 0.1 is a floating-point number, which is not exact; quote it (\"0.1\")"),
        "{}",
        e.message
    );
    // Quoted, the same value is read exactly.
    let c = build(
        "lin",
        r#"(parameters: { "p1": "0.1" })"#,
        ConstraintSystem::new(),
    )
    .expect("valid");
    assert_eq!(c.parameters[0].value, vec![q(1, 10)]);
}

#[test]
fn matrix_form_builds_labelled_rows() {
    let c = build(
        "gen",
        r#"(
            matrix: [[1, 1, -1], [0, 2, 1], [0, 0, 0]],
            rhs: [0, 5, 0],
            names: ["a", "b", "c"],
            values: ["1", "2", "3"],
        )"#,
        ConstraintSystem::new(),
    )
    .expect("valid");
    let names: Vec<&str> = c.parameters.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["gen.a", "gen.b", "gen.c"]);
    assert_eq!(c.parameters[2].value, vec![q(3, 1)]);
    assert_eq!(c.rows.len(), 2);
    assert_eq!(
        scalar(&c.rows[0]),
        (vec![(0, int(1)), (1, int(1)), (2, int(-1))], int(0))
    );
    assert_eq!(scalar(&c.rows[1]), (vec![(1, int(2)), (2, int(1))], int(5)));
    assert_eq!(c.rows[1].label, "row 2");
    assert_eq!(
        c.rows[1].origin,
        Origin {
            source: "gen".into(),
            item: "row 2".into()
        }
    );
    assert_eq!(
        c.warnings,
        ["matrix row 3: every coefficient cancels (0 = 0); dropped"]
    );
    assert_eq!(summary(&c), [("parameters", 3), ("equations", 2)]);

    // Defaults: p0..p{n-1} at zero, ids after the existing parameters.
    let mut system = ConstraintSystem::new();
    system.add_parameter("other.x", 1).expect("new");
    let c = build("gen", r#"(matrix: [[1, 1]], rhs: [0])"#, system).expect("valid");
    let names: Vec<&str> = c.parameters.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["gen.p0", "gen.p1"]);
    assert_eq!(scalar(&c.rows[0]), (vec![(1, int(1)), (2, int(1))], int(0)));
    assert!(c.parameters.iter().all(|p| p.value == vec![q(0, 1)]));
}

#[test]
fn matrix_errors_name_the_row() {
    let e = build(
        "gen",
        r#"(matrix: [[1, 1, -1], [0, 2]], rhs: [0, 5])"#,
        ConstraintSystem::new(),
    )
    .expect_err("ragged");
    assert_eq!(
        e.message,
        "matrix row 2 has 2 entries, expected 3 (the length of row 1)"
    );
    let e = build(
        "gen",
        r#"(matrix: [[1, 1], [0, "1/2"]], rhs: [0, 5])"#,
        ConstraintSystem::new(),
    )
    .expect_err("fraction");
    assert!(
        e.message
            .starts_with("matrix row 2, entry 2: \"1/2\" is not an integer"),
        "{}",
        e.message
    );
}

#[test]
fn ron_errors_carry_their_position() {
    let e = build(
        "lin",
        "(\n    parameters: { \"p1\": \"1\" },\n    equatoins: [],\n)",
        ConstraintSystem::new(),
    )
    .expect_err("unknown field");
    assert_eq!(e.at.map(|p| p.line), Some(3), "{}", e.message);
    assert!(e.message.starts_with("config: "), "{}", e.message);
    assert!(e.message.contains("equatoins"), "{}", e.message);
}

#[test]
fn plan_and_render_are_refused() {
    let source = LinearSource::new();
    assert_eq!(source.kind(), "linear");
    assert_eq!(source.version(), env!("CARGO_PKG_VERSION"));
    let system = ConstraintSystem::new();
    let values = Values::default();
    let e = source
        .plan(&PlanRequest {
            schema: api::SCHEMA_VERSION,
            operation: "()".into(),
            system: system.clone(),
            values: values.clone(),
        })
        .expect_err("no operations");
    assert_eq!(e.message, "the linear source has no operations");
    let e = source
        .render(&RenderRequest {
            schema: api::SCHEMA_VERSION,
            input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
            output: "()".into(),
            base_dir: ".".into(),
            system,
            initial: values.clone(),
            values,
            highlight: None,
            structure: None,
        })
        .expect_err("no outputs");
    assert_eq!(e.message, "the linear source has no outputs");
}

#[test]
fn empty_config_contributes_nothing_with_a_warning() {
    let c = build("lin", "()", ConstraintSystem::new()).expect("valid");
    assert!(c.parameters.is_empty() && c.rows.is_empty());
    assert_eq!(
        c.warnings,
        ["the config declares no parameters and no equations"]
    );
}
