//! The `linear` source through its public interface: the thesis pump system, a later source
//! constraining it, and equation text that must parse back to the row it was written from.

use api::{
    BuildRequest, ConstraintSource, ConstraintSystem, Contribution, Integer, ParamId, Rational,
    RowBody, SourceError, Values,
};
use plugins_linear::LinearSource;
use proptest::prelude::*;

fn request(name: &str, config: &str, system: &ConstraintSystem, values: &Values) -> BuildRequest {
    BuildRequest {
        schema: api::SCHEMA_VERSION,
        input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
        name: name.into(),
        config: config.into(),
        base_dir: ".".into(),
        system: system.clone(),
        values: values.clone(),
        sources: vec![],
    }
}

fn build(name: &str, config: &str, system: &ConstraintSystem) -> Result<Contribution, SourceError> {
    LinearSource::new().build(&request(name, config, system, &Values::zeros(system)))
}

const PUMP: &str = r#"(
    parameters: { "p1": 1, "p2": 2, "p3": 3, "p4": 8 },
    equations: [ "p1 + p2 - p3 = 0", "p4 - p3 = 5" ],
)"#;

#[test]
fn thesis_pump_system_holds_at_its_initial_values() {
    let mut system = ConstraintSystem::new();
    let mut values = Values::default();
    let contribution = build("pump", PUMP, &system).expect("valid");
    contribution
        .apply_to(&mut system, &mut values)
        .expect("apply");
    let names: Vec<&str> = system.params().iter().map(|p| &*p.name).collect();
    assert_eq!(names, ["pump.p1", "pump.p2", "pump.p3", "pump.p4"]);
    assert!(system.params().iter().all(|p| p.dim == 1));
    assert_eq!(system.rows().len(), 2);
    assert_eq!(system.rows()[0].label, "p1 + p2 - p3 = 0");
    assert_eq!(system.rows()[1].origin.item, "equation 2");
    assert!(system.violations(&values).is_empty());
    let (matrix, rhs, _) = system.scalar_matrix();
    assert_eq!((matrix.rows(), matrix.cols()), (2, 4));
    assert_eq!(matrix.get(1, 2), Integer::from(-1));
    assert_eq!(rhs, vec![Integer::from(0), Integer::from(5)]);

    // The same system in the matrix form gives the same rows.
    let matrix_form = build(
        "pump",
        r#"(
            matrix: [[1, 1, -1, 0], [0, 0, -1, 1]],
            rhs: [0, 5],
            names: ["p1", "p2", "p3", "p4"],
            values: ["1", "2", "3", "8"],
        )"#,
        &ConstraintSystem::new(),
    )
    .expect("valid");
    assert_eq!(matrix_form.parameters, contribution.parameters);
    let bodies = |c: &Contribution| c.rows.iter().map(|r| r.body.clone()).collect::<Vec<_>>();
    assert_eq!(bodies(&matrix_form), bodies(&contribution));

    // Moving p4 alone breaks the second row, and the system says so.
    values
        .set(
            &system,
            ParamId(3),
            vec![Rational::from_integer(Integer::from(9))],
        )
        .expect("set");
    let violated: Vec<usize> = system
        .violations(&values)
        .iter()
        .map(|v| v.0.index())
        .collect();
    assert_eq!(violated, [1]);
}

#[test]
fn a_later_source_constrains_the_pump() {
    let mut system = ConstraintSystem::new();
    let mut values = Values::default();
    build("pump", PUMP, &system)
        .expect("valid")
        .apply_to(&mut system, &mut values)
        .expect("apply");
    let later = LinearSource::new()
        .build(&request(
            "limits",
            r#"(parameters: { "total": "11" }, equations: ["total = pump.p3 + pump.p4"])"#,
            &system,
            &values,
        ))
        .expect("valid");
    later.apply_to(&mut system, &mut values).expect("apply");
    assert_eq!(system.params().len(), 5);
    assert_eq!(system.rows_of(ParamId(3)).len(), 2);
    assert!(system.violations(&values).is_empty());

    // Contributions cross the plugin ABI as JSON.
    let json = serde_json::to_string(&later).expect("serialise");
    let back: Contribution = serde_json::from_str(&json).expect("deserialise");
    assert_eq!(back, later);
}

/// One way of writing the piece `value · x{var}` (or a constant when `var` is `None`).
fn write_term(out: &mut String, first: bool, value: &Integer, var: Option<usize>, style: u8) {
    let negative = *value < Integer::from(0);
    let magnitude = if negative { -value } else { value.clone() };
    let space = if style & 1 == 1 { " " } else { "" };
    match (first, negative) {
        (true, false) if style & 2 == 0 => {}
        (true, false) => out.push('+'),
        (true, true) => out.push('-'),
        (false, false) => out.push_str(&format!("{space}+{space}")),
        (false, true) => out.push_str(&format!("{space}-{space}")),
    }
    match var {
        None => out.push_str(&magnitude.to_string()),
        Some(j) => {
            // A coefficient of one may be left out.
            if magnitude != Integer::from(1) || style & 4 == 4 {
                out.push_str(&magnitude.to_string());
                out.push_str(match style >> 3 & 3 {
                    0 => "",
                    1 => " ",
                    2 => "*",
                    _ => " * ",
                });
            }
            out.push_str(&format!("x{j}"));
        }
    }
}

/// Builds `Σ c_j x_j = rhs` as text, each coefficient split in two pieces placed on random
/// sides in a random order, with constants on both sides.
fn equation_text(
    coefficients: &[Integer],
    rhs: &Integer,
    splits: &[(Integer, bool, bool, u32, u32)],
    left_constant: &Integer,
    styles: &[u8],
) -> String {
    // (order key, on the left, written value, variable)
    let mut pieces: Vec<(u32, bool, Integer, Option<usize>)> = Vec::new();
    for (j, (c, (a, left_a, left_b, key_a, key_b))) in coefficients.iter().zip(splits).enumerate() {
        let b = c - a;
        pieces.push((
            *key_a,
            *left_a,
            if *left_a { a.clone() } else { -a },
            Some(j),
        ));
        pieces.push((
            *key_b,
            *left_b,
            if *left_b { b.clone() } else { -b },
            Some(j),
        ));
    }
    // Σ c x + left_constant = right_constant, so right_constant = rhs + left_constant.
    pieces.push((u32::MAX / 3, true, left_constant.clone(), None));
    pieces.push((u32::MAX / 2, false, rhs + left_constant, None));
    pieces.sort_by_key(|p| p.0);
    let mut sides = [String::new(), String::new()];
    let mut style = styles.iter().cycle();
    for (_, left, value, var) in pieces {
        let side = &mut sides[usize::from(!left)];
        let first = side.is_empty();
        write_term(side, first, &value, var, style.next().copied().unwrap_or(0));
    }
    format!("{} = {}", sides[0], sides[1])
}

fn integer() -> impl Strategy<Value = Integer> {
    (
        prop_oneof![-3i64..=3, any::<i64>()],
        prop::bool::weighted(0.2),
    )
        .prop_map(|(v, big)| {
            let v = Integer::from(v);
            if big {
                v * num_traits::pow(Integer::from(10), 25)
            } else {
                v
            }
        })
}

proptest! {
    #[test]
    fn written_equations_parse_back_to_the_same_row(
        (coefficients, splits) in (1usize..6).prop_flat_map(|n| (
            prop::collection::vec(integer(), n),
            prop::collection::vec((integer(), any::<bool>(), any::<bool>(), any::<u32>(), any::<u32>()), n),
        )),
        rhs in integer(),
        left_constant in integer(),
        styles in prop::collection::vec(0u8..32, 1..8),
    ) {
        let text = equation_text(&coefficients, &rhs, &splits, &left_constant, &styles);
        let parameters: Vec<String> =
            (0..coefficients.len()).map(|j| format!("\"x{j}\": 0")).collect();
        let config = format!(
            "(parameters: {{ {} }}, equations: [{text:?}])",
            parameters.join(", ")
        );
        let contribution = build("eq", &config, &ConstraintSystem::new())
            .map_err(|e| TestCaseError::fail(format!("{text}: {e}")))?;
        let expected: Vec<(u32, Integer)> = coefficients
            .iter()
            .enumerate()
            .filter(|(_, c)| **c != Integer::from(0))
            .map(|(j, c)| (j as u32, c.clone()))
            .collect();
        if expected.is_empty() && rhs == Integer::from(0) {
            prop_assert!(contribution.rows.is_empty(), "{}", text);
            prop_assert_eq!(contribution.warnings.len(), 1);
        } else {
            prop_assert_eq!(contribution.rows.len(), 1);
            let RowBody::Scalar { terms, rhs: got } = &contribution.rows[0].body else {
                return Err(TestCaseError::fail("scalar row expected"));
            };
            let got_terms: Vec<(u32, Integer)> =
                terms.iter().map(|(c, v)| (c.param.0, v.clone())).collect();
            prop_assert_eq!(&got_terms, &expected, "{}", text);
            prop_assert_eq!(got, &rhs, "{}", text);
            prop_assert_eq!(&contribution.rows[0].label, &text);
        }
    }
}
