//! ECLES Updates under change criteria (Brenner 3.1): Brenner's own figure 3 exactly, both
//! layouts of a vector edit, the least-squares criterion through the criteria crate equal to
//! ECLES' own update, and refusals unchanged.

use api::{ConstraintRow, ConstraintSystem, Origin, ParamId, Rational, RowBody, Values};
use ecles::{Criterion, Edit, EditSpec, Layout, Measure};
use exact_ldu::{ExactFactorization, ExactLdu, Simplification};

type ExactEdit = Edit<ExactFactorization>;

fn q(n: i64, d: i64) -> Rational {
    Rational::new(n.into(), d.into())
}

fn z(n: i64) -> Rational {
    q(n, 1)
}

fn backend() -> ExactLdu {
    ExactLdu::new(Simplification::Gcd)
}

fn row(label: &str, terms: &[(ParamId, i64)], rhs: &[i64]) -> ConstraintRow {
    ConstraintRow {
        label: label.into(),
        origin: Origin::default(),
        body: RowBody::Vector {
            terms: terms.iter().map(|(p, c)| (*p, (*c).into())).collect(),
            rhs: rhs.iter().map(|&v| v.into()).collect(),
        },
    }
}

const NAMES: [&str; 12] = [
    "x1", "y1", "x2", "y2", "x3", "y3", "a1", "b1", "c1", "a2", "b2", "c2",
];

/// Brenner's figure 3(a): p1 = (0, 0), p2 = (1, 0), p3 = (0, 1), l1 = (0, 1, 0) through p1 and
/// p2, l2 = (1, 0, 0) through p1 and p3 (a line `a x + b y + c = 0`), the unit-normal and
/// incidence constraints linearised at that configuration; with `perpendicular`, figure 3(d)'s
/// l1 ⊥ l2.
fn brenner(perpendicular: bool) -> (ConstraintSystem, Vec<ParamId>, Values) {
    let mut s = ConstraintSystem::new();
    let p: Vec<ParamId> = NAMES
        .iter()
        .map(|n| s.add_parameter(n.to_string(), 1).expect("name"))
        .collect();
    let [x1, y1, _x2, y2, x3, _y3, a1, b1, c1, a2, b2, c2] = p[..] else {
        unreachable!("twelve parameters")
    };
    s.add_row(row("unit normal l1", &[(b1, 2)], &[2]))
        .expect("row");
    s.add_row(row("unit normal l2", &[(a2, 2)], &[2]))
        .expect("row");
    s.add_row(row("p1 on l1", &[(y1, 1), (c1, 1)], &[0]))
        .expect("row");
    s.add_row(row("p2 on l1", &[(y2, 1), (a1, 1), (c1, 1)], &[0]))
        .expect("row");
    s.add_row(row("p1 on l2", &[(x1, 1), (c2, 1)], &[0]))
        .expect("row");
    s.add_row(row("p3 on l2", &[(x3, 1), (b2, 1), (c2, 1)], &[0]))
        .expect("row");
    if perpendicular {
        s.add_row(row("l1 perpendicular to l2", &[(a1, 1), (b2, 1)], &[0]))
            .expect("row");
    }
    let start = [0, 0, 1, 0, 0, 1, 0, 1, 0, 1, 0, 0];
    let values =
        Values::from_vecs(&s, start.iter().map(|&v| vec![z(v)]).collect()).expect("values");
    assert!(s.violations(&values).is_empty());
    (s, p, values)
}

/// Drags p1 by (1, 0) under `criterion`; the derived values by name, and the summary.
fn drag_p1(
    perpendicular: bool,
    measure: Measure,
    points_primary: bool,
) -> (Vec<(&'static str, Rational)>, ecles::CriterionSummary) {
    let (s, p, values) = brenner(perpendicular);
    let derived: Vec<ParamId> = p[2..].to_vec();
    let spec = EditSpec::new(vec![p[0], p[1]], derived.clone());
    let edit: ExactEdit = Edit::initialize(&backend(), &s, &values, &spec).expect("init");
    let hints: Vec<Vec<Rational>> = derived.iter().map(|d| values.get(*d).to_vec()).collect();
    let criterion = Criterion {
        measure,
        primary: points_primary.then(|| p[2..6].to_vec()),
    };
    let (result, summary) = edit
        .update_by(&criterion, &[vec![z(1)], vec![z(0)]], &hints)
        .expect("solvable");
    let mut after = values.clone();
    result.write_into(&mut after);
    assert!(s.violations(&after).is_empty(), "every row holds exactly");
    let changes = result
        .derived
        .iter()
        .zip(&hints)
        .map(|((id, v), h)| (NAMES[id.index()], &v[0] - &h[0]))
        .filter(|(_, d)| *d != z(0))
        .collect();
    (changes, summary)
}

#[test]
fn brenner_figure_3_least_squares_on_everything_and_on_points_first() {
    // 3(c): least squares on every derived parameter moves p3 by 1/2 and turns l2 half-way.
    let (changes, summary) = drag_p1(false, Measure::L2, false);
    assert_eq!(
        changes,
        vec![("x3", q(1, 2)), ("b2", q(1, 2)), ("c2", z(-1))]
    );
    assert_eq!(summary.value, q(3, 2));
    // 3(b): points primary, lines secondary: p2 and p3 stay, l2 turns.
    let (changes, summary) = drag_p1(false, Measure::L2, true);
    assert_eq!(changes, vec![("b2", z(1)), ("c2", z(-1))]);
    assert_eq!((summary.value, summary.primary.len()), (z(0), 4));
    // 3(f): with l1 ⊥ l2, points first still moves p2 and p3 by 1/2 each.
    let (changes, summary) = drag_p1(true, Measure::L2, true);
    assert_eq!(
        changes,
        vec![
            ("y2", q(1, 2)),
            ("x3", q(1, 2)),
            ("a1", q(-1, 2)),
            ("b2", q(1, 2)),
            ("c2", z(-1))
        ]
    );
    assert_eq!(summary.value, q(1, 2));
}

#[test]
fn brenner_figure_3_least_absolute_change_is_not_unique_and_fewest_has_two_answers() {
    // 3(g): L1 on the points: minimum 1 on a segment of optima (dimension 1).
    let (changes, summary) = drag_p1(true, Measure::L1, true);
    assert_eq!(summary.value, z(1));
    assert_eq!(summary.optimal_face_dimension, Some(1));
    let moved: Rational = changes
        .iter()
        .filter(|(n, _)| ["x2", "y2", "x3", "y3"].contains(n))
        .map(|(_, d)| d.clone())
        .sum();
    assert_eq!(moved, z(1), "{changes:?}");
    // 3(h): fewest changed points: one point coordinate, two ways (p2 up or p3 right).
    let (changes, summary) = drag_p1(true, Measure::Fewest, true);
    assert_eq!(summary.value, z(1));
    let supports = summary.supports.expect("supports");
    assert_eq!((supports.count, supports.proven_minimal), (2, true));
    let name = |p: &ParamId| NAMES[p.index()];
    assert_eq!(
        supports
            .ties
            .iter()
            .map(|t| t.iter().map(name).collect::<Vec<_>>())
            .collect::<Vec<_>>(),
        vec![vec!["x3"]]
    );
    assert_eq!(
        changes,
        vec![("y2", z(1)), ("a1", z(-1)), ("b2", z(1)), ("c2", z(-1))]
    );
    assert_eq!(
        summary.changed.iter().map(name).collect::<Vec<_>>(),
        vec!["y2", "a1", "b2", "c2"]
    );
}

/// Figure 2.1's parallelogram p0 − p1 + p2 − p3 = 0, written as one vector row or as two
/// scalar rows.
fn parallelogram(split: bool) -> (ConstraintSystem, Vec<ParamId>, Values) {
    let mut s = ConstraintSystem::new();
    let p: Vec<ParamId> = (0..4)
        .map(|i| s.add_parameter(format!("p{i}"), 2).expect("name"))
        .collect();
    let terms = [(p[0], 1), (p[1], -1), (p[2], 1), (p[3], -1)];
    if split {
        for k in 0..2 {
            s.add_row(ConstraintRow {
                label: format!("parallelogram[{k}]"),
                origin: Origin::default(),
                body: RowBody::Scalar {
                    terms: terms
                        .iter()
                        .map(|(param, c)| {
                            (
                                api::Coord {
                                    param: *param,
                                    component: k,
                                },
                                (*c).into(),
                            )
                        })
                        .collect(),
                    rhs: 0.into(),
                },
            })
            .expect("row");
        }
    } else {
        s.add_row(row("parallelogram", &terms, &[0, 0]))
            .expect("row");
    }
    let pts = [(0, 0), (4, 0), (5, 3), (1, 3)];
    let values = Values::from_vecs(&s, pts.iter().map(|&(x, y)| vec![z(x), z(y)]).collect())
        .expect("values");
    (s, p, values)
}

#[test]
fn both_layouts_agree_under_every_criterion_and_least_squares_is_ecles_own() {
    let mut answers = Vec::new();
    for split in [false, true] {
        let (s, p, values) = parallelogram(split);
        let spec = EditSpec::new(vec![p[0]], p[1..].to_vec());
        let edit: ExactEdit = Edit::initialize(&backend(), &s, &values, &spec).expect("init");
        assert_eq!(edit.layout() == Layout::Scalar, split);
        let hints: Vec<Vec<Rational>> = p[1..].iter().map(|d| values.get(*d).to_vec()).collect();
        let anchor = [vec![z(3), z(-6)]];
        // Least squares through the criteria (every derived parameter primary) is ECLES' own.
        let everything = Criterion {
            measure: Measure::L2,
            primary: Some(p[1..].to_vec()),
        };
        let (through, _) = edit
            .update_by(&everything, &anchor, &hints)
            .expect("solvable");
        assert_eq!(through, edit.update(&anchor, &hints).expect("solvable"));
        let mut per_measure = Vec::new();
        for measure in [Measure::L1, Measure::Fewest] {
            let criterion = Criterion {
                measure,
                primary: None,
            };
            let (result, summary) = edit
                .update_by(&criterion, &anchor, &hints)
                .expect("solvable");
            let mut after = values.clone();
            result.write_into(&mut after);
            assert!(s.violations(&after).is_empty());
            per_measure.push((result, summary));
        }
        // L1: |3| + |−6| wherever the move goes: a face of dimension 2 per coordinate.
        assert_eq!(per_measure[0].1.value, z(9));
        assert_eq!(per_measure[0].1.optimal_face_dimension, Some(4));
        // Fewest: any one of p1, p2, p3 can carry the whole move (three ties); p1 is first.
        let supports = per_measure[1].1.supports.clone().expect("supports");
        assert_eq!((supports.count, per_measure[1].1.value.clone()), (3, z(1)));
        assert_eq!(per_measure[1].1.changed, vec![p[1]]);
        assert_eq!(per_measure[1].0.derived[0].1, vec![z(7), z(-6)]);
        answers.push(per_measure);
    }
    assert_eq!(answers[0], answers[1]);
}

#[test]
fn a_refused_move_is_refused_the_same_way_under_every_criterion() {
    // p1 pinned by p1 on l2 and the unit normal of l2 when c2 is not derived: x1 cannot move.
    let (s, p, values) = brenner(false);
    let derived: Vec<ParamId> = p[2..11].to_vec();
    let spec = EditSpec::new(vec![p[0], p[1]], derived.clone());
    let edit: ExactEdit = Edit::initialize(&backend(), &s, &values, &spec).expect("init");
    let hints: Vec<Vec<Rational>> = derived.iter().map(|d| values.get(*d).to_vec()).collect();
    let anchors = [vec![z(1)], vec![z(0)]];
    let refusal = edit.update(&anchors, &hints).expect_err("blocked");
    for measure in [Measure::L2, Measure::L1, Measure::Fewest] {
        let criterion = Criterion {
            measure,
            primary: Some(p[2..6].to_vec()),
        };
        assert_eq!(
            edit.update_by(&criterion, &anchors, &hints)
                .expect_err("blocked"),
            refusal
        );
    }
    assert_eq!(
        refusal.conflict().expect("a certificate").labels(),
        vec!["p1 on l2"]
    );
}
