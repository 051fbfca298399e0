//! The align source on a spline2d system: rows and labels, exact scaling, errors, an edit that
//! keeps an alignment and one that would break it, and the conformance checks.

use api::{parse_rational, Values};
use api::{BuildRequest, ConstraintSource, ConstraintSystem, Coord, ParamId, Rational, RowBody};
use conformance::{self, Samples};
use ecles::{Edit, EditError, EditSpec};
use exact_ldu::{ExactFactorization, ExactLdu};
use plugins_align::*;
use plugins_spline2d::plugin::Spline2dSource;

/// A degree-3 C1 spline `phi` on the 2 × 2 grid of side 10: vertex `v(3y + x)` at `(10x, 10y)`.
fn spline_system() -> (ConstraintSystem, Values) {
    let config = "(mesh: (vertices: [(0, 0), (10, 0), (20, 0), (0, 10), (10, 10), (20, 10), \
                  (0, 20), (10, 20), (20, 20)], triangles: [(0, 1, 4), (0, 4, 3), (1, 2, 5), \
                  (1, 5, 4), (3, 4, 7), (3, 7, 6), (4, 5, 8), (4, 8, 7)]), degree: 3)";
    let contribution = Spline2dSource::default()
        .build(&conformance::request("phi", config))
        .unwrap_or_else(|e| panic!("{e}"));
    let mut system = ConstraintSystem::new();
    let mut values = Values::default();
    contribution
        .apply_to(&mut system, &mut values)
        .expect("applies");
    (system, values)
}

fn request(config: &str) -> BuildRequest {
    let (system, values) = spline_system();
    BuildRequest {
        system,
        values,
        ..conformance::request("align", config)
    }
}

fn q(text: &str) -> Rational {
    parse_rational(text).unwrap_or_else(|e| panic!("{e}"))
}

fn coord(system: &ConstraintSystem, name: &str, component: usize) -> Coord {
    Coord {
        param: system.param_id(name).unwrap_or_else(|| panic!("{name}")),
        component,
    }
}

const ALL_KINDS: &str = r#"(constraints: [
    SameX(["phi.v1", "phi.v4", "phi.v7"]),
    SameY(["phi.v3", "phi.v5"]),
    OnLine(points: ["phi.v0", "phi.v4"], through: (("0", "0"), ("10", "5"))),
    Fixed(point: "phi.v8", at: ("20", "41/2")),
    Offset(point: "phi.v2", from: "phi.v1", by: (10, "-1/3")),
])"#;

#[test]
fn every_kind_becomes_labelled_integer_scalar_rows() {
    let request = request(ALL_KINDS);
    let c = AlignSource::default().build(&request).expect("builds");
    let labels: Vec<&str> = c.rows.iter().map(|r| r.label.as_str()).collect();
    assert_eq!(
        labels,
        [
            "align: phi.v1 x = phi.v4 x",
            "align: phi.v1 x = phi.v7 x",
            "align: phi.v3 y = phi.v5 y",
            "align: phi.v0 on the line through (0, 0) and (10, 5)",
            "align: phi.v4 on the line through (0, 0) and (10, 5)",
            "align: phi.v8 x = 20",
            "align: phi.v8 y = 41/2",
            "align: phi.v2 x = phi.v1 x + 10",
            "align: phi.v2 y = phi.v1 y - 1/3",
        ]
    );
    let s = &request.system;
    let row = |i: usize| c.rows[i].body.clone();
    assert_eq!(
        row(0),
        RowBody::Scalar {
            terms: vec![
                (coord(s, "phi.v1", 0), 1.into()),
                (coord(s, "phi.v4", 0), (-1).into())
            ],
            rhs: 0.into()
        }
    );
    // 5 x − 10 y = 0, scaled to coprime integers.
    assert_eq!(
        row(3),
        RowBody::Scalar {
            terms: vec![
                (coord(s, "phi.v0", 0), 1.into()),
                (coord(s, "phi.v0", 1), (-2).into())
            ],
            rhs: 0.into()
        }
    );
    assert_eq!(
        row(6),
        RowBody::Scalar {
            terms: vec![(coord(s, "phi.v8", 1), 2.into())],
            rhs: 41.into()
        }
    );
    assert_eq!(
        row(8),
        RowBody::Scalar {
            terms: vec![
                (coord(s, "phi.v2", 1), 3.into()),
                (coord(s, "phi.v1", 1), (-3).into())
            ],
            rhs: (-1).into()
        }
    );
    assert_eq!(c.rows[5].origin.item, "constraint 4 (Fixed)");
    let count = |key: &str| c.summary.iter().find(|s| s.key == key).map(|s| s.value);
    assert_eq!(
        [
            count("constraints"),
            count("rows"),
            count("same_x"),
            count("on_line"),
            count("fixed")
        ],
        [Some(5), Some(9), Some(1), Some(1), Some(1)]
    );
    // Applied to the identity deformation: everything holds but the rows that describe other
    // geometry (v4 = (10, 10) is not on x = 2y, v8 = (20, 20), v2 − v1 = (10, 0)).
    let mut system = request.system.clone();
    let mut values = request.values.clone();
    c.apply_to(&mut system, &mut values).expect("applies");
    let violated: Vec<&str> = system
        .violations(&values)
        .iter()
        .map(|(r, _, _)| system.rows()[r.index()].label.as_str())
        .collect();
    assert_eq!(
        violated,
        [
            "align: phi.v4 on the line through (0, 0) and (10, 5)",
            "align: phi.v8 y = 41/2",
            "align: phi.v2 y = phi.v1 y - 1/3"
        ]
    );
}

#[test]
fn bad_constraints_are_refused_naming_the_constraint_and_point() {
    let cases = [
        (
            r#"(constraints: [SameX(["phi.v1", "phi.v99"])])"#,
            "align: constraint 1 (SameX): no parameter named \"phi.v99\"",
        ),
        (
            r#"(constraints: [SameY(["phi.v1"])])"#,
            "constraint 1 (SameY) needs at least 2 point(s), got 1",
        ),
        (
            r#"(constraints: [SameX(["phi.v1", "phi.v4"]), SameX(["phi.v1", "phi.v1"])])"#,
            "constraint 2 (SameX) names \"phi.v1\" twice",
        ),
        (
            r#"(constraints: [OnLine(points: ["phi.v1"], through: (("1", "1"), ("1", "1")))])"#,
            "the two points the line goes through are equal",
        ),
        (
            r#"(constraints: [OnLine(points: [], through: (("0", "0"), ("1", "1")))])"#,
            "needs at least 1 point(s), got 0",
        ),
        (
            r#"(constraints: [Offset(point: "phi.v1", from: "phi.v1", by: ("0", "0"))])"#,
            "names \"phi.v1\" twice",
        ),
        (
            r#"(constraints: [Fixed(point: "phi.v1", at: (0.5, "0"))])"#,
            "floating-point",
        ),
        (
            r#"(constraints: [Fixed(point: "phi.v1", at: ("0", "0"), extra: 1)])"#,
            "extra",
        ),
        (r#"(constraints: [Parallel(["phi.v1"])])"#, "Parallel"),
        (r#"(constraint: [])"#, "constraint"),
    ];
    for (config, needle) in cases {
        let error = AlignSource::default()
            .build(&request(config))
            .expect_err(config);
        assert!(error.message.starts_with("align"), "{error}");
        assert!(error.message.contains(needle), "{needle}: {error}");
    }
    // A scalar parameter is not a point.
    let mut req = request(r#"(constraints: [SameX(["phi.v1", "t"])])"#);
    req.system.add_parameter("t", 1).expect("fresh");
    let error = AlignSource::default().build(&req).expect_err("scalar");
    assert!(error.message.contains("\"t\" has dimension 1"), "{error}");
}

/// ECLES on a system mixing the spline's vector rows with scalar alignment rows: moving an
/// aligned point along its line works, moving it off the line is refused naming the row.
#[test]
fn edits_keep_alignments_or_are_refused_naming_them() {
    let request = request(r#"(constraints: [SameX(["phi.v1", "phi.v4", "phi.v7"])])"#);
    let c = AlignSource::default().build(&request).expect("builds");
    let mut system = request.system.clone();
    let mut values = request.values.clone();
    c.apply_to(&mut system, &mut values).expect("applies");
    let id = |n: &str| system.param_id(n).unwrap_or_else(|| panic!("{n}"));
    let (v1, v4, v7) = (id("phi.v1"), id("phi.v4"), id("phi.v7"));
    // Everything but the anchor and the two points aligned with it follows.
    let derived: Vec<ParamId> = (0..system.params().len() as u32)
        .map(ParamId)
        .filter(|p| ![v1, v4, v7].contains(p))
        .collect();
    let spec = EditSpec::new(vec![v4], derived);
    let edit: Edit<ExactFactorization> =
        Edit::initialize(&ExactLdu::default(), &system, &values, &spec).expect("initialises");
    let hints: Vec<Vec<Rational>> = spec
        .derived
        .iter()
        .map(|p| values.get(*p).to_vec())
        .collect();
    // Up: x unchanged, the alignment holds.
    edit.apply(&system, &mut values, &[vec![q("10"), q("13")]], &hints)
        .expect("a vertical move keeps the alignment");
    assert!(system.violations(&values).is_empty());
    assert_eq!(values.get(v4), &[q("10"), q("13")]);
    // Sideways with v1 and v7 fixed: refused, naming the alignment rows; nothing changes.
    let before = values.clone();
    let error = edit
        .apply(&system, &mut values, &[vec![q("12"), q("13")]], &hints)
        .expect_err("sideways breaks the alignment");
    match &error {
        EditError::Conflict(conflict) => {
            let labels = conflict.labels();
            assert!(
                labels
                    .iter()
                    .any(|l| l.starts_with("align: phi.v1 x = phi.v4 x")),
                "{labels:?}"
            );
        }
        other => panic!("expected a conflict, got {other}"),
    }
    assert_eq!(values, before);
}

#[test]
fn passes_the_conformance_checks() {
    let bad = [
        r#"(constraints: [SameX(["phi.v1", "nope"])])"#,
        r#"(constraints: [SameX(["phi.v1"])])"#,
        r#"(constraints: [Fixed(point: "phi.v1", at: ("1/0", "0"))])"#,
        "(constraints: [",
        "()",
    ];
    let samples = Samples {
        good: vec![
            request(ALL_KINDS),
            request("(constraints: [])"),
            request(
                r#"(constraints: [OnLine(points: ["phi.v0"], through: (("0", "0"), ("0", "1")))])"#,
            ),
        ],
        bad: bad.iter().map(|c| request(c)).collect(),
        operations: vec!["(anchors: [\"phi.v1\"])".into()],
        outputs: vec!["(picture: \"align.svg\")".into()],
    };
    let contributions =
        conformance::check_source(&mut || Box::new(AlignSource::default()), &samples)
            .unwrap_or_else(|e| panic!("statically linked: {e}"));
    // The same checks on the crate's own dynamic library, loaded through the ABI: identical
    // contributions.
    let path = plugin_abi::library_beside_test("plugins-align").expect("test executable path");
    let plugin = plugin_abi::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(plugin.kind, KIND);
    let loaded = conformance::check_source(&mut || Box::new(plugin.instantiate()), &samples)
        .unwrap_or_else(|e| panic!("loaded from {}: {e}", path.display()));
    assert_eq!(loaded, contributions);
    assert_eq!(contributions[1].warnings, ["no constraints declared"]);
    // A vertical line x = 0: the row is 1·x = 0 (coefficient made positive).
    assert_eq!(
        contributions[2].rows[0].body,
        RowBody::Scalar {
            terms: vec![(coord(&samples.good[2].system, "phi.v0", 0), 1.into())],
            rhs: 0.into()
        }
    );
}
