//! Block-wise factoring against one factoring on a real spline system: the scalar C1 system of
//! a planar spline has two identical components (x and y), factored once block-wise.

use api::{ConstraintSystem, Factorization, LinearBackend, Rational, Values};
use exact_ldu::{BlockwiseLdu, ExactLdu};
use spline2d::spline::Spline;
use std::collections::BTreeSet;

#[test]
fn blockwise_factoring_of_a_spline_system_equals_one_factoring() {
    let spline = Spline::new(spline2d::mesh::grid(2, 10, true), 5, 1).expect("spline");
    let mut system = ConstraintSystem::new();
    let mut values = Values::default();
    spline
        .declare(&mut system, &mut values, "phi", spline.identity_positions())
        .expect("declare");
    let (matrix, _, _) = system.scalar_matrix();
    let one = ExactLdu::default().factor(&matrix).expect("factor");
    let blocks = BlockwiseLdu::default().factor(&matrix).expect("factor");
    // The x and y conditions are two identical components (factored once); every control point
    // in no condition is a free column of its own (all those share one trivial factorization).
    assert_eq!(blocks.distinct_factorizations(), 2);
    assert!(blocks.component_count() > 2);
    assert_eq!(one.rank(), blocks.rank());
    let set = |v: Vec<usize>| v.into_iter().collect::<BTreeSet<_>>();
    assert_eq!(set(one.independent_rows()), set(blocks.independent_rows()));
    let reds = |f: Vec<api::Redundancy<Rational>>| -> BTreeSet<(usize, Vec<(usize, Rational)>)> {
        f.into_iter()
            .map(|r| {
                let mut c = r.combination;
                c.sort_by_key(|(i, _)| *i);
                (r.row, c)
            })
            .collect()
    };
    assert_eq!(reds(one.redundancies()), reds(blocks.redundancies()));
    // The current values (the identity) solve the system; a least-squares pull towards other
    // hints gives identical exact answers.
    let rhs: Vec<Rational> = (0..matrix.rows())
        .map(|_| Rational::from_integer(0.into()))
        .collect();
    let hints: Vec<Rational> = (0..matrix.cols())
        .map(|j| Rational::new((((j * 7) % 11) as i64).into(), 3.into()))
        .collect();
    let weights = vec![Rational::from_integer(1.into()); matrix.cols()];
    assert_eq!(
        one.least_squares(&rhs, &hints, &weights)
            .expect("consistent"),
        blocks
            .least_squares(&rhs, &hints, &weights)
            .expect("consistent")
    );
    assert_eq!(
        one.solve(&rhs).expect("consistent"),
        blocks.solve(&rhs).expect("consistent")
    );
}
