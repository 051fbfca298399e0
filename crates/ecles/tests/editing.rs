//! ECLES edits on the thesis examples and on deliberately bad input, with the exact backend.

use api::{
    ConstraintRow, ConstraintSystem, Coord, Origin, ParamId, Rational, RowBody, RowId, Values,
};
use ecles::{Edit, EditError, EditSpec, Layout};
use exact_ldu::{ExactFactorization, ExactLdu, Simplification};

type ExactEdit = Edit<ExactFactorization>;

fn q(n: i64, d: i64) -> Rational {
    Rational::new(n.into(), d.into())
}

fn z(n: i64) -> Rational {
    q(n, 1)
}

fn vector_row(label: &str, terms: &[(ParamId, i64)], rhs: &[i64]) -> ConstraintRow {
    ConstraintRow {
        label: label.into(),
        origin: Origin {
            source: "test".into(),
            item: label.into(),
        },
        body: RowBody::Vector {
            terms: terms.iter().map(|(p, c)| (*p, (*c).into())).collect(),
            rhs: rhs.iter().map(|&v| v.into()).collect(),
        },
    }
}

/// The pump example (2.2): p1 + p2 = p3 and p4 = p3 + 5.
fn pumps() -> (ConstraintSystem, Vec<ParamId>, Values) {
    let mut s = ConstraintSystem::new();
    let p: Vec<ParamId> = (1..=4)
        .map(|i| s.add_parameter(format!("p{i}"), 1).expect("name"))
        .collect();
    s.add_row(vector_row("mix", &[(p[0], 1), (p[1], 1), (p[2], -1)], &[0]))
        .expect("row");
    s.add_row(vector_row("offset", &[(p[2], -1), (p[3], 1)], &[5]))
        .expect("row");
    let values = Values::from_vecs(&s, vec![vec![z(1)], vec![z(2)], vec![z(3)], vec![z(8)]])
        .expect("values");
    assert!(s.violations(&values).is_empty());
    (s, p, values)
}

fn backend() -> ExactLdu {
    ExactLdu::new(Simplification::Gcd)
}

#[test]
fn pump_with_exactly_determined_derived_rates() {
    let (s, p, mut values) = pumps();
    let spec = EditSpec::new(vec![p[0]], vec![p[2], p[3]]).strong();
    let edit: ExactEdit = Edit::initialize(&backend(), &s, &values, &spec).expect("init");
    let report = edit.report();
    assert_eq!(report.relevant, vec![RowId(0), RowId(1)]);
    assert_eq!(report.fixed_relevant, vec![p[1]]);
    assert_eq!(report.rank, 2);
    assert!(report.redundant.is_empty());
    assert_eq!(report.strongly_solvable, Some(true));
    assert_eq!(report.layout, Layout::Vector { dim: 1 });
    edit.apply(&s, &mut values, &[vec![z(4)]], &[vec![z(0)], vec![z(0)]])
        .expect("update");
    assert_eq!(values.get(p[0]), &[z(4)]);
    assert_eq!(values.get(p[2]), &[z(6)]);
    assert_eq!(values.get(p[3]), &[z(11)]);
    assert!(s.violations(&values).is_empty());
}

#[test]
fn pump_with_least_squares_over_three_derived_rates() {
    let (s, p, mut values) = pumps();
    let spec = EditSpec::new(vec![p[0]], vec![p[1], p[2], p[3]]);
    let edit: ExactEdit = Edit::initialize(&backend(), &s, &values, &spec).expect("init");
    // Hints = current values; minimise (p2−2)² + (p3−3)² + (p4−8)² with p1 = 4:
    // p3 = p2 + 4, p4 = p2 + 9 ⇒ p2 = 0.
    let hints = vec![vec![z(2)], vec![z(3)], vec![z(8)]];
    edit.apply(&s, &mut values, &[vec![z(4)]], &hints)
        .expect("update");
    assert_eq!(values.get(p[1]), &[z(0)]);
    assert_eq!(values.get(p[2]), &[z(4)]);
    assert_eq!(values.get(p[3]), &[z(9)]);
    // With weight 5 on p2 it moves less: (p2−2)·5 + (p2+1) + (p2+1) = 0 ⇒ p2 = 8/7.
    let spec =
        EditSpec::new(vec![p[0]], vec![p[1], p[2], p[3]]).with_weights(vec![z(5), z(1), z(1)]);
    let (s, _, values) = pumps();
    let edit: ExactEdit = Edit::initialize(&backend(), &s, &values, &spec).expect("init");
    let out = edit.update(&[vec![z(4)]], &hints).expect("update");
    assert_eq!(out.derived[0].1, vec![q(8, 7)]);
    assert_eq!(out.derived[1].1, vec![q(36, 7)]);
    // The preview is the same exact solution, rounded.
    let preview = edit.preview(&[vec![z(4)]], &hints).expect("preview");
    assert_eq!(preview[0], vec![8.0 / 7.0]);
    assert_eq!(preview[1], vec![36.0 / 7.0]);
}

/// Figure 2.1: five points of the plane; p0 p1 p2 p3 must stay a parallelogram
/// (p0 − p1 + p2 − p3 = 0); p4 is unrelated. Moving p0 by v with the current positions as hints
/// moves p1 and p3 by v/3 and p2 by −v/3.
fn parallelogram(split: bool) -> (ConstraintSystem, Vec<ParamId>, Values) {
    let mut s = ConstraintSystem::new();
    let p: Vec<ParamId> = (0..5)
        .map(|i| s.add_parameter(format!("p{i}"), 2).expect("name"))
        .collect();
    if split {
        for k in 0..2 {
            s.add_row(ConstraintRow {
                label: format!("parallelogram[{k}]"),
                origin: Origin::default(),
                body: RowBody::Scalar {
                    terms: [(0, 1), (1, -1), (2, 1), (3, -1)]
                        .iter()
                        .map(|&(i, c)| {
                            (
                                Coord {
                                    param: p[i],
                                    component: k,
                                },
                                c.into(),
                            )
                        })
                        .collect(),
                    rhs: 0.into(),
                },
            })
            .expect("row");
        }
    } else {
        s.add_row(vector_row(
            "parallelogram",
            &[(p[0], 1), (p[1], -1), (p[2], 1), (p[3], -1)],
            &[0, 0],
        ))
        .expect("row");
    }
    let pts = [(0, 0), (4, 0), (5, 3), (1, 3), (9, 9)];
    let values = Values::from_vecs(&s, pts.iter().map(|&(x, y)| vec![z(x), z(y)]).collect())
        .expect("values");
    assert!(s.violations(&values).is_empty());
    (s, p, values)
}

#[test]
fn parallelogram_vector_and_scalar_layouts_agree() {
    for split in [false, true] {
        let (s, p, mut values) = parallelogram(split);
        let spec = EditSpec::new(vec![p[0]], vec![p[1], p[2], p[3]]).strong();
        let edit: ExactEdit = Edit::initialize(&backend(), &s, &values, &spec).expect("init");
        let expected_layout = if split {
            Layout::Scalar
        } else {
            Layout::Vector { dim: 2 }
        };
        assert_eq!(edit.layout(), expected_layout);
        assert_eq!(edit.report().fixed_relevant, vec![]);
        let hints: Vec<Vec<Rational>> = (1..4).map(|i| values.get(p[i]).to_vec()).collect();
        edit.apply(&s, &mut values, &[vec![z(3), z(-6)]], &hints)
            .expect("update");
        assert_eq!(values.get(p[1]), &[z(5), z(-2)]);
        assert_eq!(values.get(p[2]), &[z(4), z(5)]);
        assert_eq!(values.get(p[3]), &[z(2), z(1)]);
        assert_eq!(values.get(p[4]), &[z(9), z(9)]);
        assert!(s.violations(&values).is_empty());
    }
}

/// An exact frame is the update, unreduced: the same values once reduced, on the exact backend
/// (unreduced fractions from the lifting) and on the block-wise one (the reduced answer as
/// fractions), in both layouts; and the same refusal for an impossible move.
#[test]
fn exact_frames_are_the_update_unreduced() {
    for split in [false, true] {
        let (s, p, values) = parallelogram(split);
        let spec = EditSpec::new(vec![p[0]], vec![p[1], p[2], p[3]]);
        let hints: Vec<Vec<Rational>> = (1..4)
            .map(|i| values.get(p[i]).iter().map(|v| v + q(1, 3)).collect())
            .collect();
        let anchors = [vec![q(7, 2), q(-6, 5)]];
        let exact: ExactEdit = Edit::initialize(&backend(), &s, &values, &spec).expect("init");
        let blockwise = Edit::initialize(
            &exact_ldu::BlockwiseLdu::new(exact_ldu::Simplification::Gcd),
            &s,
            &values,
            &spec,
        )
        .expect("init");
        let update = exact.update(&anchors, &hints).expect("update");
        for frame in [
            exact.frame(&anchors, &hints).expect("frame"),
            blockwise.frame(&anchors, &hints).expect("frame"),
        ] {
            let reduced: Vec<Vec<Rational>> = frame
                .iter()
                .map(|v| v.iter().map(api::Fraction::reduced).collect())
                .collect();
            let expected: Vec<Vec<Rational>> =
                update.derived.iter().map(|(_, v)| v.clone()).collect();
            assert_eq!(reduced, expected);
        }
    }
    let (s, p, values) = chain();
    let spec = EditSpec::new(vec![p[0], p[2]], vec![p[1]]);
    let edit: ExactEdit = Edit::initialize(&backend(), &s, &values, &spec).expect("init");
    assert!(matches!(
        edit.frame(&[vec![z(5)], vec![z(0)]], &[vec![z(0)]]),
        Err(EditError::Conflict(_))
    ));
}

/// An edit with its hints fixed (a drag) answers every anchor position as the edit does given
/// those hints each time — updates, previews, frames and snapped updates, in both layouts — and
/// checks hints once, anchor values every time.
#[test]
fn hinted_edits_answer_as_the_edit_with_the_same_hints() {
    for split in [false, true] {
        let (s, p, values) = parallelogram(split);
        let spec = EditSpec::new(vec![p[0]], vec![p[1], p[2], p[3]]);
        let edit: ExactEdit = Edit::initialize(&backend(), &s, &values, &spec).expect("init");
        let hints: Vec<Vec<Rational>> = (1..4)
            .map(|i| values.get(p[i]).iter().map(|v| v + q(1, 7)).collect())
            .collect();
        let hinted = edit.with_hints(&hints).expect("hints");
        for anchors in [
            vec![vec![q(7, 2), q(-6, 5)]],
            vec![vec![z(0), z(0)]],
            vec![vec![q(-11, 3), z(40)]],
        ] {
            assert_eq!(
                hinted.update(&anchors).expect("update"),
                edit.update(&anchors, &hints).expect("update")
            );
            assert_eq!(
                hinted.frame(&anchors).expect("frame"),
                edit.frame(&anchors, &hints).expect("frame")
            );
            assert_eq!(
                hinted.preview(&anchors).expect("preview"),
                edit.preview(&anchors, &hints).expect("preview")
            );
            let (snapped, summary) = hinted.update_snapped(&anchors, 8).expect("snapped");
            assert_eq!(
                (snapped, summary.distance_bound),
                edit.update_snapped(&anchors, &hints, 8)
                    .map(|(r, s)| (r, s.distance_bound))
                    .expect("snapped")
            );
        }
        assert!(matches!(
            hinted.update(&[vec![z(1)]]),
            Err(EditError::ValueDimension { .. })
        ));
        assert!(matches!(
            edit.with_hints(&hints[..2]),
            Err(EditError::Count { what: "hints", .. })
        ));
    }
}

/// p1 = p2 = p3 with A = {p1, p3}, D = {p2}: anchors can only move together.
fn chain() -> (ConstraintSystem, Vec<ParamId>, Values) {
    let mut s = ConstraintSystem::new();
    let p: Vec<ParamId> = (1..=3)
        .map(|i| s.add_parameter(format!("p{i}"), 1).expect("name"))
        .collect();
    s.add_row(vector_row("p1=p2", &[(p[0], 1), (p[1], -1)], &[0]))
        .expect("row");
    s.add_row(vector_row("p2=p3", &[(p[1], 1), (p[2], -1)], &[0]))
        .expect("row");
    let values = Values::from_vecs(&s, vec![vec![z(0)]; 3]).expect("values");
    (s, p, values)
}

#[test]
fn inconsistent_anchor_move_is_rejected_with_labels_and_changes_nothing() {
    let (s, p, mut values) = chain();
    let spec = EditSpec::new(vec![p[0], p[2]], vec![p[1]]);
    let edit: ExactEdit = Edit::initialize(&backend(), &s, &values, &spec).expect("init");
    assert_eq!(edit.report().rank, 1);
    assert_eq!(edit.report().redundant.len(), 1);
    let before = values.clone();
    let err = edit
        .apply(&s, &mut values, &[vec![z(5)], vec![z(0)]], &[vec![z(0)]])
        .expect_err("p1 = 5 and p3 = 0 cannot both hold");
    let EditError::Conflict(conflict) = &err else {
        panic!("expected a conflict, got {err:?}")
    };
    assert!(matches!(
        edit.preview(&[vec![z(5)], vec![z(0)]], &[vec![z(0)]]),
        Err(EditError::Conflict(_))
    ));
    let mut labels = conflict.labels();
    labels.sort();
    assert_eq!(labels, vec!["p1=p2", "p2=p3"]);
    assert_ne!(conflict.discrepancy, z(0));
    assert_eq!(values, before);
    assert!(err.to_string().contains("p1=p2"));
    // Moving both anchors together is fine.
    edit.apply(&s, &mut values, &[vec![z(5)], vec![z(5)]], &[vec![z(0)]])
        .expect("consistent move");
    assert_eq!(values.get(p[1]), &[z(5)]);
    // The strong check refuses the same edit up front.
    let err =
        Edit::<ExactFactorization>::initialize(&backend(), &s, &values, &spec.clone().strong())
            .expect_err("not strongly solvable");
    assert!(
        matches!(err, EditError::NotStronglySolvable { .. }),
        "{err:?}"
    );
    let err = Edit::<ExactFactorization>::check_strongly_solvable(&backend(), &s, &values, &spec)
        .expect_err("not strongly solvable");
    assert!(
        matches!(err, EditError::NotStronglySolvable { .. }),
        "{err:?}"
    );
}

#[test]
fn bad_specs_are_typed_errors() {
    let (s, p, values) = pumps();
    let init =
        |spec: EditSpec| Edit::<ExactFactorization>::initialize(&backend(), &s, &values, &spec);
    assert!(matches!(
        init(EditSpec::new(vec![], vec![p[1]])),
        Err(EditError::NoAnchors)
    ));
    assert!(matches!(
        init(EditSpec::new(vec![ParamId(99)], vec![])),
        Err(EditError::UnknownParameter(ParamId(99)))
    ));
    assert!(matches!(
        init(EditSpec::new(vec![p[0]], vec![p[0]])),
        Err(EditError::AnchorAlsoDerived { .. })
    ));
    assert!(matches!(
        init(EditSpec::new(vec![p[0]], vec![p[1], p[1]])),
        Err(EditError::Duplicate { .. })
    ));
    assert!(matches!(
        init(EditSpec::new(vec![p[0]], vec![p[1]]).with_weights(vec![])),
        Err(EditError::WeightCount { .. })
    ));
    for weight in [z(0), z(-1), q(-1, 3)] {
        assert!(matches!(
            init(EditSpec::new(vec![p[0]], vec![p[1]]).with_weights(vec![weight])),
            Err(EditError::NonPositiveWeight { .. })
        ));
    }
    assert!(init(EditSpec::new(vec![p[0]], vec![p[1]]).with_weights(vec![q(1, 1000)])).is_ok());
    let edit = init(EditSpec::new(vec![p[0]], vec![p[1], p[2], p[3]])).expect("init");
    assert!(matches!(
        edit.update(&[], &[vec![z(0)], vec![z(0)], vec![z(0)]]),
        Err(EditError::Count {
            what: "anchor values",
            ..
        })
    ));
    assert!(matches!(
        edit.update(&[vec![z(1), z(2)]], &[vec![z(0)], vec![z(0)], vec![z(0)]]),
        Err(EditError::ValueDimension { .. })
    ));
    assert!(matches!(
        edit.update(&[vec![z(1)]], &[vec![z(0)]]),
        Err(EditError::Count { what: "hints", .. })
    ));
}

/// A derived parameter in no relevant constraint simply takes its hint; an anchor in no
/// constraint just moves.
#[test]
fn unconstrained_parameters_take_their_hints() {
    let (s, p, mut values) = parallelogram(false);
    let spec = EditSpec::new(vec![p[4]], vec![p[3]]);
    let edit: ExactEdit = Edit::initialize(&backend(), &s, &values, &spec).expect("init");
    // p3 is in the parallelogram row, which becomes relevant with p0, p1, p2 fixed: p3 cannot move.
    let out = edit
        .update(&[vec![z(1), z(1)]], &[vec![z(7), z(7)]])
        .expect("update");
    assert_eq!(out.derived[0].1, vec![z(1), z(3)]);
    let spec = EditSpec::new(vec![p[4]], vec![]);
    let edit: ExactEdit = Edit::initialize(&backend(), &s, &values, &spec).expect("init");
    assert!(edit.report().relevant.is_empty());
    edit.apply(&s, &mut values, &[vec![q(1, 3), z(2)]], &[])
        .expect("free move");
    assert_eq!(values.get(p[4]), &[q(1, 3), z(2)]);
}

/// A straight drag is exact at every point: interpolating the two end solutions gives exactly
/// what an update at the interpolated anchor values and hints gives.
#[test]
fn straight_drags_interpolate_exactly() {
    let (s, p, values) = parallelogram(false);
    let spec =
        EditSpec::new(vec![p[0]], vec![p[1], p[2], p[3]]).with_weights(vec![z(1), z(3), z(2)]);
    let edit: ExactEdit = Edit::initialize(&backend(), &s, &values, &spec).expect("init");
    let hints0: Vec<Vec<Rational>> = (1..4).map(|i| values.get(p[i]).to_vec()).collect();
    let hints1: Vec<Vec<Rational>> = hints0
        .iter()
        .map(|h| vec![&h[0] + q(1, 2), &h[1] - q(2, 3)])
        .collect();
    let a0 = vec![values.get(p[0]).to_vec()];
    let a1 = vec![vec![z(3), z(-6)]];
    let drag = edit.drag(&a0, &hints0, &a1, &hints1).expect("drag");
    for t in [q(0, 1), q(1, 3), q(5, 7), q(1, 1), q(3, 2)] {
        let lerp = |a: &[Vec<Rational>], b: &[Vec<Rational>]| -> Vec<Vec<Rational>> {
            a.iter()
                .zip(b)
                .map(|(x, y)| x.iter().zip(y).map(|(u, v)| u + &t * (v - u)).collect())
                .collect()
        };
        let direct = edit
            .update(&lerp(&a0, &a1), &lerp(&hints0, &hints1))
            .expect("update");
        let (anchors, derived) = drag.at(&t);
        assert_eq!(anchors, lerp(&a0, &a1));
        let expected: Vec<Vec<Rational>> = direct.derived.into_iter().map(|(_, v)| v).collect();
        assert_eq!(derived, expected);
        let tf = api::Value::to_f64(&t);
        for (pv, ev) in drag.preview(tf).iter().zip(&expected) {
            for (x, y) in pv.iter().zip(ev) {
                assert!((x - api::Value::to_f64(y)).abs() < 1e-12);
            }
        }
    }
}

/// A point `p` tied to `q` (`p − q = 0`, vector row) and pinned in x (`p x = 0`, scalar row).
fn pinned_in_x() -> (ConstraintSystem, Vec<ParamId>, Values) {
    let mut s = ConstraintSystem::new();
    let p = s.add_parameter("p", 2).expect("name");
    let q = s.add_parameter("q", 2).expect("name");
    s.add_row(vector_row("p = q", &[(p, 1), (q, -1)], &[0, 0]))
        .expect("row");
    s.add_row(ConstraintRow {
        label: "p x = 0".into(),
        origin: Origin::default(),
        body: RowBody::Scalar {
            terms: vec![(
                Coord {
                    param: p,
                    component: 0,
                },
                1.into(),
            )],
            rhs: 0.into(),
        },
    })
    .expect("row");
    let values = Values::from_vecs(&s, vec![vec![z(0), z(2)], vec![z(0), z(2)]]).expect("values");
    (s, vec![p, q], values)
}

#[test]
fn requested_moves_are_checked_not_every_direction() {
    let (s, p, values) = pinned_in_x();
    let spec = EditSpec::new(vec![p[0]], vec![p[1]]);
    let check =
        |moves: &[Vec<Vec<Rational>>]| ecles::check_moves(&backend(), &s, &values, &spec, moves);
    // Strong solvability fails (x is pinned) ...
    assert!(matches!(
        ExactEdit::check_strongly_solvable(&backend(), &s, &values, &spec.clone().strong()),
        Err(EditError::NotStronglySolvable { .. })
    ));
    // ... but a move along y is possible, also as a drag of several steps ...
    check(&[vec![vec![z(0), z(1)]]]).expect("y is free");
    check(&[
        vec![vec![z(0), z(1)]],
        vec![vec![z(0), z(2)]],
        vec![vec![z(0), q(5, 2)]],
    ])
    .expect("y is free at every step");
    check(&[]).expect("no move");
    // ... and a move with an x component is blocked by the pin alone, not by the tie.
    match check(&[vec![vec![z(0), z(1)]], vec![vec![z(1), z(1)]]]) {
        Err(EditError::MoveBlocked(conflict)) => {
            assert_eq!(conflict.labels(), ["p x = 0"]);
        }
        other => panic!("expected MoveBlocked, got {other:?}"),
    }
    // Every step of an edit that check_moves accepts solves exactly.
    let edit = ExactEdit::initialize(&backend(), &s, &values, &spec).expect("init");
    let mut after = values.clone();
    edit.apply(&s, &mut after, &[vec![z(0), z(5)]], &[vec![z(0), z(2)]])
        .expect("the y move solves");
    assert_eq!(after.get(p[1]), &[z(0), z(5)]);
    // Displacements must have the anchors' shape.
    assert!(matches!(
        check(&[vec![vec![z(1)]]]),
        Err(EditError::Count { .. })
    ));
}

/// A projection moves the derived parameters the least (unit weights) onto the rows: the pumps
/// with p3 moved to 6 break both rows; with p1 fixed, the nearest state that keeps them is
/// found exactly.
#[test]
fn a_projection_is_the_nearest_state_that_keeps_every_row() {
    let (s, p, mut values) = pumps();
    values.set(&s, p[2], vec![z(6)]).expect("set");
    assert_eq!(s.violations(&values).len(), 2);
    let edit: ExactEdit =
        Edit::projection(&backend(), &s, &values, vec![p[1], p[2], p[3]]).expect("projection");
    let result = edit.project(&values).expect("projects");
    result.write_into(&mut values);
    assert!(s.violations(&values).is_empty());
    // min (p2-2)² + (p3-6)² + (p4-8)² with p3 = 1 + p2, p4 = p3 + 5: (x-2)² + (x-5)² + (x-2)²
    // is least at p2 = x = 3.
    assert_eq!(values.get(p[1]), &[z(3)]);
    assert_eq!(values.get(p[2]), &[z(4)]);
    assert_eq!(values.get(p[3]), &[z(9)]);
    // A state that keeps every row is its own projection.
    let again: ExactEdit =
        Edit::projection(&backend(), &s, &values, vec![p[1], p[2], p[3]]).expect("projection");
    let before = values.clone();
    again
        .project(&values)
        .expect("projects")
        .write_into(&mut values);
    assert_eq!(values, before);
}

/// A report describes the initialised edit's reduced system instead of reducing the edit
/// again: both ways give the same `R_ED`, `R_EA`, right-hand sides and layout.
#[test]
fn an_edit_keeps_the_reduced_system_reduce_edit_gives() {
    let (s, p, values) = pumps();
    for spec in [
        EditSpec::new(vec![p[0]], vec![p[2], p[3]]),
        EditSpec::new(vec![p[0]], vec![p[1], p[2], p[3]]),
        EditSpec::new(vec![p[3]], vec![p[2]]),
    ] {
        let (_, expected) = ecles::reduce_edit::<Rational>(&s, &values, &spec).expect("reduce");
        let edit: ExactEdit = Edit::initialize(&backend(), &s, &values, &spec).expect("init");
        assert_eq!(edit.into_reduced(), expected);
    }
}
