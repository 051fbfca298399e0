//! The RON configuration of a `linear` source: its serde shape and its validation.

use crate::equation::is_valid_name;
use api::{parse_rational, Integer, Rational, SourceError};
use serde::de::{self, Deserializer, MapAccess, Visitor};
use serde::Deserialize;
use std::collections::HashSet;
use std::fmt;

/// A number as written in the configuration: a RON integer, a string (read exactly later) or a
/// RON float (always refused later, with a message naming the item).
#[derive(Debug, Clone, PartialEq)]
enum Number {
    Int(Integer),
    Text(String),
    Float(f64),
}

impl<'de> Deserialize<'de> for Number {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct NumberVisitor;
        impl Visitor<'_> for NumberVisitor {
            type Value = Number;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("an integer or a string holding an exact number such as \"-2.5\"")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Number, E> {
                Ok(Number::Int(v.into()))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Number, E> {
                Ok(Number::Int(v.into()))
            }
            fn visit_i128<E: de::Error>(self, v: i128) -> Result<Number, E> {
                Ok(Number::Int(v.into()))
            }
            fn visit_u128<E: de::Error>(self, v: u128) -> Result<Number, E> {
                Ok(Number::Int(v.into()))
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Number, E> {
                Ok(Number::Float(v))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Number, E> {
                Ok(Number::Text(v.to_string()))
            }
        }
        deserializer.deserialize_any(NumberVisitor)
    }
}

/// Why a float is refused, and what to write instead.
fn float_message(v: f64) -> String {
    if v.is_finite() {
        format!(
            "{v:?} is a floating-point number, which is not exact; quote it (\"{v:?}\") to have \
             it read exactly (integers beyond 64 bits must be quoted too)"
        )
    } else {
        format!("{v:?} is not a finite number")
    }
}

impl Number {
    /// The exact value; `what` names the item in messages.
    fn rational(&self, what: &str) -> Result<Rational, SourceError> {
        match self {
            Number::Int(v) => Ok(Rational::from_integer(v.clone())),
            Number::Text(text) => parse_rational(text)
                .map_err(|e| SourceError::new(format!("{what}: invalid value: {e}"))),
            Number::Float(v) => Err(SourceError::new(format!("{what}: {}", float_message(*v)))),
        }
    }

    /// The value, which must be an integer; `what` names the item in messages.
    fn integer(&self, what: &str) -> Result<Integer, SourceError> {
        match self {
            Number::Int(v) => Ok(v.clone()),
            Number::Text(text) => parse_integer_text(text).ok_or_else(|| {
                SourceError::new(format!(
                    "{what}: {text:?} is not an integer (entries must be integers; multiply \
                     the row through)"
                ))
            }),
            Number::Float(v) if v.is_finite() => Err(SourceError::new(format!(
                "{what}: {v:?} is a floating-point number, but entries must be integers \
                 (multiply the row through; write integers beyond 64 bits as strings, e.g. \
                 \"123456789012345678901234567890\")"
            ))),
            Number::Float(v) => Err(SourceError::new(format!("{what}: {}", float_message(*v)))),
        }
    }
}

/// `[+-]digits` with surrounding whitespace, as an arbitrary-size integer.
fn parse_integer_text(text: &str) -> Option<Integer> {
    let body = text.trim();
    let digits = body.strip_prefix(['+', '-']).unwrap_or(body);
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let value: Integer = digits.parse().ok()?;
    Some(if body.starts_with('-') { -value } else { value })
}

/// The `parameters` map in the order it was written (RON maps are read entry by entry);
/// duplicate names are refused while reading, so the error carries a position.
#[derive(Debug, Clone, PartialEq, Default)]
struct OrderedParameters(Vec<(String, Number)>);

impl<'de> Deserialize<'de> for OrderedParameters {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct MapVisitor;
        impl<'de> Visitor<'de> for MapVisitor {
            type Value = OrderedParameters;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a map from parameter names to initial values")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
                let mut seen = HashSet::new();
                let mut entries = Vec::new();
                while let Some(name) = map.next_key::<String>()? {
                    if !seen.insert(name.clone()) {
                        return Err(de::Error::custom(format!(
                            "parameter {name:?} is declared twice"
                        )));
                    }
                    let value = map.next_value::<Number>()?;
                    entries.push((name, value));
                }
                Ok(OrderedParameters(entries))
            }
        }
        deserializer.deserialize_map(MapVisitor)
    }
}

/// Deserialises a present field as `Some` (RON would otherwise want `Some(...)` around it).
fn present<'de, D: Deserializer<'de>, T: Deserialize<'de>>(d: D) -> Result<Option<T>, D::Error> {
    T::deserialize(d).map(Some)
}

/// Both forms in one struct; which fields are present decides the form.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct LinearConfig {
    #[serde(default, deserialize_with = "present")]
    parameters: Option<OrderedParameters>,
    #[serde(default, deserialize_with = "present")]
    equations: Option<Vec<String>>,
    #[serde(default, deserialize_with = "present")]
    matrix: Option<Vec<Vec<Number>>>,
    #[serde(default, deserialize_with = "present")]
    rhs: Option<Vec<Number>>,
    #[serde(default, deserialize_with = "present")]
    names: Option<Vec<String>>,
    #[serde(default, deserialize_with = "present")]
    values: Option<Vec<Number>>,
}

/// A validated configuration.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Config {
    /// Named parameters and equation texts.
    Equations {
        /// Short names and initial values, in declaration order.
        parameters: Vec<(String, Rational)>,
        /// Equation texts, as written.
        equations: Vec<String>,
    },
    /// An integer matrix over the parameters `names`.
    Matrix {
        /// Short names and initial values, one per column.
        parameters: Vec<(String, Rational)>,
        /// Rows of coefficients, each as long as `parameters`.
        rows: Vec<Vec<Integer>>,
        /// One right-hand side per row.
        rhs: Vec<Integer>,
    },
}

/// Checks that a short parameter name is valid; `what` names it in messages.
fn check_name(name: &str, what: &str) -> Result<(), SourceError> {
    if is_valid_name(name) {
        Ok(())
    } else {
        Err(SourceError::new(format!(
            "{what} {name:?} is not a valid parameter name: names match [A-Za-z_][A-Za-z0-9_.]*"
        )))
    }
}

/// Reads and validates the RON text of a configuration.
pub(crate) fn parse_config(text: &str) -> Result<Config, SourceError> {
    let raw: LinearConfig = api::config::from_ron(text, "config")?;
    let matrix_form =
        raw.matrix.is_some() || raw.rhs.is_some() || raw.names.is_some() || raw.values.is_some();
    let equations_form = raw.parameters.is_some() || raw.equations.is_some();
    if matrix_form && equations_form {
        return Err(SourceError::new(
            "the config mixes the equations form (`parameters`, `equations`) with the matrix \
             form (`matrix`, `rhs`, `names`, `values`); use one of them",
        ));
    }
    if matrix_form {
        matrix_config(raw)
    } else {
        let mut parameters = Vec::new();
        for (name, value) in raw.parameters.unwrap_or_default().0 {
            check_name(&name, "parameter")?;
            let value = value.rational(&format!("parameter {name:?}"))?;
            parameters.push((name, value));
        }
        Ok(Config::Equations {
            parameters,
            equations: raw.equations.unwrap_or_default(),
        })
    }
}

fn matrix_config(raw: LinearConfig) -> Result<Config, SourceError> {
    let (Some(matrix), Some(rhs)) = (raw.matrix, raw.rhs) else {
        return Err(SourceError::new(
            "the matrix form needs both `matrix` and `rhs` (`names` and `values` are optional)",
        ));
    };
    // The number of columns, and what decided it (for messages).
    let (columns, decided_by) = match (&raw.names, &raw.values) {
        (Some(names), Some(values)) if names.len() != values.len() => {
            return Err(SourceError::new(format!(
                "`names` has {} entries but `values` has {}",
                names.len(),
                values.len()
            )))
        }
        (Some(names), _) => (names.len(), "the number of names".to_string()),
        (None, Some(values)) => (values.len(), "the number of values".to_string()),
        (None, None) => (
            matrix.first().map_or(0, Vec::len),
            "the length of row 1".to_string(),
        ),
    };
    if rhs.len() != matrix.len() {
        return Err(SourceError::new(format!(
            "`rhs` has {} entries but `matrix` has {} rows",
            rhs.len(),
            matrix.len()
        )));
    }
    let names = match raw.names {
        Some(names) => {
            let mut seen = HashSet::new();
            for name in &names {
                check_name(name, "name")?;
                if !seen.insert(name.as_str()) {
                    return Err(SourceError::new(format!(
                        "parameter {name:?} is named twice in `names`"
                    )));
                }
            }
            names
        }
        None => (0..columns).map(|j| format!("p{j}")).collect(),
    };
    let values = match raw.values {
        Some(values) => values
            .iter()
            .enumerate()
            .map(|(j, v)| v.rational(&format!("`values` entry {} ({:?})", j + 1, names[j])))
            .collect::<Result<Vec<_>, _>>()?,
        None => vec![Rational::from_integer(Integer::from(0)); columns],
    };
    let mut rows = Vec::with_capacity(matrix.len());
    for (i, row) in matrix.iter().enumerate() {
        if row.len() != columns {
            return Err(SourceError::new(format!(
                "matrix row {} has {} entries, expected {columns} ({decided_by})",
                i + 1,
                row.len()
            )));
        }
        rows.push(
            row.iter()
                .enumerate()
                .map(|(j, v)| v.integer(&format!("matrix row {}, entry {}", i + 1, j + 1)))
                .collect::<Result<Vec<_>, _>>()?,
        );
    }
    let rhs = rhs
        .iter()
        .enumerate()
        .map(|(i, v)| v.integer(&format!("`rhs` entry {} (matrix row {})", i + 1, i + 1)))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Config::Matrix {
        parameters: names.into_iter().zip(values).collect(),
        rows,
        rhs,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    fn err(text: &str) -> String {
        parse_config(text).expect_err(text).message
    }

    #[test]
    fn reads_the_equations_form_in_declaration_order() {
        let config = parse_config(
            r#"(
                parameters: { "p1": "3", "p2": "-2.5", "p3": "7/3", "p4": 0, "a": -12 },
                equations: [ "p1 + p2 - p3 = 0", "3 p3 - 5 p4 = 7" ],
            )"#,
        )
        .expect("valid");
        let Config::Equations {
            parameters,
            equations,
        } = config
        else {
            panic!("equations form expected");
        };
        let names: Vec<&str> = parameters.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["p1", "p2", "p3", "p4", "a"]);
        assert_eq!(parameters[1].1, q(-5, 2));
        assert_eq!(parameters[2].1, q(7, 3));
        assert_eq!(parameters[3].1, q(0, 1));
        assert_eq!(parameters[4].1, q(-12, 1));
        assert_eq!(equations.len(), 2);
        // Both fields are optional.
        assert_eq!(
            parse_config("()").expect("empty"),
            Config::Equations {
                parameters: vec![],
                equations: vec![]
            }
        );
    }

    #[test]
    fn reads_the_matrix_form_with_defaults() {
        let config = parse_config(
            r#"(matrix: [[1, 1, -1], [0, "123456789012345678901234567890", 1]], rhs: [0, 5])"#,
        )
        .expect("valid");
        let Config::Matrix {
            parameters,
            rows,
            rhs,
        } = config
        else {
            panic!("matrix form expected");
        };
        let names: Vec<&str> = parameters.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["p0", "p1", "p2"]);
        assert!(parameters.iter().all(|(_, v)| *v == q(0, 1)));
        assert_eq!(
            rows[1][1],
            "123456789012345678901234567890"
                .parse::<Integer>()
                .expect("digits")
        );
        assert_eq!(rhs, vec![Integer::from(0), Integer::from(5)]);

        let config = parse_config(
            r#"(matrix: [[1, 1, -1]], rhs: [0], names: ["a", "b", "c"], values: ["1", 2, "1/2"])"#,
        )
        .expect("valid");
        let Config::Matrix { parameters, .. } = config else {
            panic!("matrix form expected");
        };
        assert_eq!(parameters[2], ("c".to_string(), q(1, 2)));
    }

    #[test]
    fn refuses_floats_with_advice_to_quote() {
        let message = err(r#"(parameters: { "p1": 0.1 }, equations: [])"#);
        assert_eq!(
            message,
            "parameter \"p1\": 0.1 is a floating-point number, which is not exact; quote it \
             (\"0.1\") to have it read exactly (integers beyond 64 bits must be quoted too)"
        );
        let message = err(r#"(matrix: [[1, 0.5]], rhs: [1])"#);
        assert!(
            message.starts_with(
                "matrix row 1, entry 2: 0.5 is a floating-point number, but entries must be \
                 integers"
            ),
            "{message}"
        );
        let message = err(r#"(matrix: [[1]], rhs: [1], values: [2.5])"#);
        assert!(
            message.starts_with("`values` entry 1 (\"p0\"): 2.5 is a floating-point"),
            "{message}"
        );
        let message = err(r#"(matrix: [[1]], rhs: [1.0])"#);
        assert!(
            message.starts_with("`rhs` entry 1 (matrix row 1)"),
            "{message}"
        );
    }

    #[test]
    fn reports_bad_values_and_names() {
        let message = err(r#"(parameters: { "p1": "7/0" })"#);
        assert_eq!(
            message,
            "parameter \"p1\": invalid value: denominator must be nonzero at column 3 of \"7/0\""
        );
        let message = err(r#"(parameters: { "1p": "1" })"#);
        assert!(message.starts_with("parameter \"1p\" is not a valid parameter name"));
        let message = err(r#"(matrix: [[1]], rhs: [0], names: ["a b"])"#);
        assert!(
            message.starts_with("name \"a b\" is not a valid"),
            "{message}"
        );
        let message = err(r#"(matrix: [[1, 1]], rhs: [0], names: ["a", "a"])"#);
        assert_eq!(message, "parameter \"a\" is named twice in `names`");
        let message = err(r#"(matrix: [["x"]], rhs: [0])"#);
        assert!(
            message.starts_with("matrix row 1, entry 1: \"x\" is not an integer"),
            "{message}"
        );
        let message = err(r#"(matrix: [[1]], rhs: ["0.5"])"#);
        assert!(message.contains("\"0.5\" is not an integer"), "{message}");
    }

    #[test]
    fn reports_shape_errors_naming_the_row() {
        assert_eq!(
            err(r#"(matrix: [[1, 1, -1], [0, 2]], rhs: [0, 5])"#),
            "matrix row 2 has 2 entries, expected 3 (the length of row 1)"
        );
        assert_eq!(
            err(r#"(matrix: [[1, 1, -1]], rhs: [0], names: ["a", "b"])"#),
            "matrix row 1 has 3 entries, expected 2 (the number of names)"
        );
        assert_eq!(
            err(r#"(matrix: [[1, 1]], rhs: [0], values: ["1"])"#),
            "matrix row 1 has 2 entries, expected 1 (the number of values)"
        );
        assert_eq!(
            err(r#"(matrix: [[1]], rhs: [0], names: ["a"], values: [1, 2])"#),
            "`names` has 1 entries but `values` has 2"
        );
        assert_eq!(
            err(r#"(matrix: [[1], [2]], rhs: [0])"#),
            "`rhs` has 1 entries but `matrix` has 2 rows"
        );
        assert!(err(r#"(matrix: [[1]])"#).starts_with("the matrix form needs both"));
        assert!(err(r#"(names: ["a"])"#).starts_with("the matrix form needs both"));
        assert!(err(r#"(parameters: {}, matrix: [[1]], rhs: [0])"#).starts_with("the config mixes"));
    }

    #[test]
    fn reports_ron_errors_with_their_position() {
        let at = |text: &str| {
            let e = parse_config(text).expect_err(text);
            (e.at.map(|p| p.line), e.message)
        };
        let (line, message) = at("(\n  parameters: { \"p1\": \"1\" },\n  equatoins: [],\n)");
        assert_eq!(line, Some(3), "{message}");
        assert!(message.starts_with("config: "), "{message}");
        assert!(message.contains("equatoins"), "{message}");
        let (line, message) = at("(\n  parameters: { \"p1\": \"1\", \"p1\": \"2\" },\n)");
        assert_eq!(line, Some(2), "{message}");
        assert!(message.contains("\"p1\" is declared twice"), "{message}");
        let (line, message) = at("(parameters: { \"p1\": true })");
        assert_eq!(line, Some(1), "{message}");
        assert!(message.contains("an integer or a string"), "{message}");
        let (line, _) = at("(equations: [\"a = 1\"");
        assert_eq!(line, Some(1));
    }
}
