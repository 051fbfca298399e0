//! The exact and float backends give the same verdicts and (to rounding) the same values on
//! random, well-conditioned edits of small integer systems; and both reject an impossible
//! anchor move naming the same constraint.

use api::{ConstraintRow, ConstraintSystem, Origin, ParamId, Rational, RowBody, Value, Values};
use ecles::{Edit, EditError, EditSpec};
use exact_ldu::{ExactFactorization, ExactLdu};
use float_qr::{FloatFactorization, FloatQr};
use proptest::prelude::*;

/// A random system: `n` parameters of dimension `dim`, rows with 2–4 terms and coefficients in
/// −3..3, integer current values, right-hand sides making the values consistent.
#[derive(Debug, Clone)]
struct Case {
    dim: usize,
    values: Vec<Vec<i64>>,
    rows: Vec<Vec<(usize, i64)>>,
    anchors: Vec<usize>,
    derived: Vec<usize>,
    moves: Vec<Vec<(i64, i64)>>,
    hints: Vec<Vec<(i64, i64)>>,
}

fn case() -> impl Strategy<Value = Case> {
    (1usize..=2, 4usize..=10, 1usize..=7)
        .prop_flat_map(|(dim, n, m)| {
            let rows = prop::collection::vec(
                prop::collection::vec((0..n, prop_oneof![-3i64..=-1, 1i64..=3]), 2..=4),
                m,
            );
            let values = prop::collection::vec(prop::collection::vec(-9i64..=9, dim), n);
            let perm = Just((0..n).collect::<Vec<usize>>()).prop_shuffle();
            (Just(dim), values, rows, perm, 1usize..=2, 0usize..=6).prop_flat_map(
                move |(dim, values, rows, perm, a, d)| {
                    let d = d.min(n - a);
                    let anchors = perm[..a].to_vec();
                    let derived = perm[a..a + d].to_vec();
                    let rat = || (-20i64..=20, 1i64..=5);
                    (
                        Just(dim),
                        Just(values),
                        Just(rows),
                        Just(anchors),
                        Just(derived),
                        prop::collection::vec(prop::collection::vec(rat(), dim), a),
                        prop::collection::vec(prop::collection::vec(rat(), dim), d),
                    )
                },
            )
        })
        .prop_map(|(dim, values, rows, anchors, derived, moves, hints)| Case {
            dim,
            values,
            rows,
            anchors,
            derived,
            moves,
            hints,
        })
}

fn build(c: &Case) -> (ConstraintSystem, Vec<ParamId>, Values) {
    let mut s = ConstraintSystem::new();
    let p: Vec<ParamId> = (0..c.values.len())
        .map(|i| s.add_parameter(format!("p{i}"), c.dim).expect("name"))
        .collect();
    for (i, row) in c.rows.iter().enumerate() {
        let rhs: Vec<api::Integer> = (0..c.dim)
            .map(|k| {
                row.iter()
                    .map(|(j, coeff)| coeff * c.values[*j][k])
                    .sum::<i64>()
                    .into()
            })
            .collect();
        s.add_row(ConstraintRow {
            label: format!("row{i}"),
            origin: Origin::default(),
            body: RowBody::Vector {
                terms: row
                    .iter()
                    .map(|(j, coeff)| (p[*j], (*coeff).into()))
                    .collect(),
                rhs,
            },
        })
        .expect("row");
    }
    let values = Values::from_vecs(
        &s,
        c.values
            .iter()
            .map(|v| {
                v.iter()
                    .map(|&x| Rational::from_integer(x.into()))
                    .collect()
            })
            .collect(),
    )
    .expect("values");
    (s, p, values)
}

fn rationals(v: &[Vec<(i64, i64)>]) -> Vec<Vec<Rational>> {
    v.iter()
        .map(|x| {
            x.iter()
                .map(|&(n, d)| Rational::new(n.into(), d.into()))
                .collect()
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn exact_and_float_agree(c in case()) {
        let (s, p, values) = build(&c);
        let spec = EditSpec::new(
            c.anchors.iter().map(|&i| p[i]).collect(),
            c.derived.iter().map(|&i| p[i]).collect(),
        );
        let exact: Edit<ExactFactorization> =
            Edit::initialize(&ExactLdu::default(), &s, &values, &spec).expect("exact init");
        let float: Edit<FloatFactorization> =
            Edit::initialize(&FloatQr::default(), &s, &values, &spec).expect("float init");
        let (er, fr) = (exact.report(), float.report());
        prop_assert_eq!(er.rank, fr.rank);
        prop_assert_eq!(er.relevant, fr.relevant);
        prop_assert_eq!(er.fixed_relevant, fr.fixed_relevant);
        let anchors = rationals(&c.moves);
        let hints = rationals(&c.hints);
        match (exact.update(&anchors, &hints), float.update(&anchors, &hints)) {
            (Ok(e), Ok(f)) => {
                for ((_, ev), (_, fv)) in e.derived.iter().zip(&f.derived) {
                    for (x, y) in ev.iter().zip(fv) {
                        let x = x.to_f64();
                        prop_assert!((x - y).abs() <= 1e-8 * (1.0 + x.abs()), "{} vs {}", x, y);
                    }
                }
            }
            (Err(EditError::Conflict(_)), Err(EditError::Conflict(_))) => {}
            (e, f) => prop_assert!(false, "verdicts differ: exact {:?}, float {:?}", e.is_ok(), f.is_ok()),
        }
    }
}

/// p1 = p2 = p3 and p3 fixed: moving p1 with p2 derived must fail on both backends, and both
/// name the row that ties p2 to the fixed p3.
#[test]
fn both_backends_reject_an_impossible_move() {
    let mut s = ConstraintSystem::new();
    let p: Vec<ParamId> = (1..=3)
        .map(|i| s.add_parameter(format!("p{i}"), 1).expect("name"))
        .collect();
    for (label, a, b) in [("p1=p2", 0, 1), ("p2=p3", 1, 2)] {
        s.add_row(ConstraintRow {
            label: label.into(),
            origin: Origin::default(),
            body: RowBody::Vector {
                terms: vec![(p[a], 1.into()), (p[b], (-1).into())],
                rhs: vec![0.into()],
            },
        })
        .expect("row");
    }
    let values = Values::zeros(&s);
    let spec = EditSpec::new(vec![p[0]], vec![p[1]]);
    let one = vec![vec![Rational::from_integer(1.into())]];
    let zero = vec![vec![Rational::from_integer(0.into())]];
    let exact: Edit<ExactFactorization> =
        Edit::initialize(&ExactLdu::default(), &s, &values, &spec).expect("init");
    let float: Edit<FloatFactorization> =
        Edit::initialize(&FloatQr::default(), &s, &values, &spec).expect("init");
    for labels in [
        match exact.update(&one, &zero) {
            Err(EditError::Conflict(c)) => {
                c.labels().iter().map(|l| l.to_string()).collect::<Vec<_>>()
            }
            other => panic!("exact accepted: {other:?}"),
        },
        match float.update(&one, &zero) {
            Err(EditError::Conflict(c)) => {
                c.labels().iter().map(|l| l.to_string()).collect::<Vec<_>>()
            }
            other => panic!("float accepted: {other:?}"),
        },
    ] {
        let mut labels = labels;
        labels.sort();
        assert_eq!(labels, vec!["p1=p2".to_string(), "p2=p3".to_string()]);
    }
}
