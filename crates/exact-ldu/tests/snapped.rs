//! Snapped least-squares solutions (`PreparedLeastSquares::solve_snapped`) on random matrices of
//! every shape and rank, small and above the certified-basis threshold: every row holds exactly
//! (redundant rows too), the proved distance bound really bounds the distance to the exact
//! optimum, the verdict is the optimum's, and the same inputs give the same values.

use api::{Factorization, IntMatrix, LinearBackend, PreparedLeastSquares, Rational, RhsFamily};
use backend_contract::cases;
use exact_ldu::{ExactLdu, Simplification};
use proptest::prelude::*;

fn r(n: i64, d: i64) -> Rational {
    Rational::new(n.into(), d.into())
}

/// `A x` for a rational `x`.
fn times(a: &IntMatrix, x: &[Rational]) -> Vec<Rational> {
    a.row_iter()
        .map(|row| {
            row.iter()
                .map(|(j, v)| Rational::from_integer(v.clone()) * &x[*j])
                .sum()
        })
        .collect()
}

fn check_snapped(
    backend: &ExactLdu,
    a: &IntMatrix,
    seed: &[i64],
    grid_bits: u32,
) -> Result<(), TestCaseError> {
    let n = a.cols();
    let pick = |k: usize| seed[k % seed.len()];
    // A consistent right-hand side from a point with denominators 7; hints with denominators 3;
    // weights from 1/2 to 3.
    let point: Vec<Rational> = (0..n).map(|j| r(pick(j), 7)).collect();
    let b = times(a, &point);
    let hints: Vec<Rational> = (0..n).map(|j| r(pick(j + 3) * 5 + 1, 3)).collect();
    let weights: Vec<Rational> = (0..n)
        .map(|j| r(1 + (pick(j + 1).rem_euclid(6)), 2))
        .collect();
    let f = backend.factor(a).expect("factor");
    let prepared = f
        .prepare_least_squares(&RhsFamily::single(b.clone()), &weights)
        .expect("valid weights");
    let optimum = prepared.solve(0, &[], &hints).expect("consistent");
    let snapped = prepared
        .solve_snapped(0, &[], &hints, grid_bits)
        .expect("consistent");
    prop_assert_eq!(
        times(a, &snapped.values),
        b.clone(),
        "every row holds exactly"
    );
    if snapped.optimum {
        prop_assert_eq!(&snapped.values, &optimum);
    } else {
        for (s, o) in snapped.values.iter().zip(&optimum) {
            let d = api::exact::rational_to_f64(&(s - o)).abs();
            prop_assert!(
                d <= snapped.distance_bound,
                "distance {} above the bound {}",
                d,
                snapped.distance_bound
            );
        }
    }
    let again = prepared
        .solve_snapped(0, &[], &hints, grid_bits)
        .expect("consistent");
    prop_assert_eq!(&again.values, &snapped.values, "deterministic");
    // An inconsistent right-hand side is refused exactly as by the optimum.
    if f.rank() < a.rows() {
        let mut bad = b;
        let Some(t) = f.redundancies().first().map(|red| red.row) else {
            return Ok(());
        };
        bad[t] += Rational::from_integer(1.into());
        let p = f
            .prepare_least_squares(&RhsFamily::single(bad), &weights)
            .expect("valid weights");
        prop_assert_eq!(
            p.solve_snapped(0, &[], &hints, grid_bits).err(),
            p.solve(0, &[], &hints).err()
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 160, ..ProptestConfig::default() })]

    /// Small matrices of every shape and rank (the fraction-free LDU factors them).
    #[test]
    fn snapped_solutions_hold_exactly_within_their_bound(
        (cols, rows) in cases::matrix(7),
        seed in prop::collection::vec(-40i64..=40, 1..12),
        grid_bits in 0u32..=30,
    ) {
        let a = IntMatrix::from_dense(cols, &rows).expect("rectangular");
        check_snapped(&ExactLdu::new(Simplification::Gcd), &a, &seed, grid_bits)?;
    }

    /// The same through the certified basis (every matrix above zero entries).
    #[test]
    fn snapped_solutions_through_a_certified_basis(
        (cols, rows) in cases::matrix(7),
        seed in prop::collection::vec(-40i64..=40, 1..12),
        grid_bits in 0u32..=30,
    ) {
        let a = IntMatrix::from_dense(cols, &rows).expect("rectangular");
        check_snapped(&ExactLdu::new(Simplification::Gcd).certified_above(0), &a, &seed, grid_bits)?;
    }
}

/// Rows that each have a column of their own (`a_i x_i + b_i x_{i+1} + c_i y_i = 0`): peeling
/// makes the shared columns free and solves each `y_i` by one division, so a snapped value has
/// the grid's denominator times at most one pivot, where the optimum's denominators grow with
/// the size of the system.
#[test]
fn snapped_values_divide_by_one_pivot_where_the_optimum_is_large() {
    let m = 60;
    let n = 2 * m + 1;
    let rows: Vec<Vec<i64>> = (0..m)
        .map(|i| {
            let mut row = vec![0i64; n];
            row[i] = 3 + (i as i64 % 5);
            row[i + 1] = -7 + (i as i64 % 3);
            row[m + 1 + i] = 5 + (i as i64 % 3);
            row
        })
        .collect();
    let a = IntMatrix::from_dense(n, &rows).expect("rectangular");
    let f = ExactLdu::default().factor(&a).expect("factor");
    let b = vec![Rational::from_integer(0.into()); a.rows()];
    let hints: Vec<Rational> = (0..n as i64).map(|j| r(j * j % 17, 5)).collect();
    let weights = vec![r(1, 1); n];
    let prepared = f
        .prepare_least_squares(&RhsFamily::single(b.clone()), &weights)
        .expect("weights");
    let optimum = prepared.solve(0, &[], &hints).expect("consistent");
    let grid_bits = 20;
    let snapped = prepared
        .solve_snapped(0, &[], &hints, grid_bits)
        .expect("consistent");
    assert!(!snapped.optimum);
    assert_eq!(times(&a, &snapped.values), b);
    let bits = |v: &[Rational]| v.iter().map(|x| x.denom().bits()).max().unwrap_or(0);
    assert!(
        bits(&optimum) > 100,
        "the optimum is large: {} bits",
        bits(&optimum)
    );
    // 2^20 times a pivot of at most 7 (3 bits).
    assert!(
        bits(&snapped.values) <= u64::from(grid_bits) + 3,
        "snapped: {} bits",
        bits(&snapped.values)
    );
    assert!(snapped.distance_bound < 1e-3, "{}", snapped.distance_bound);
}
