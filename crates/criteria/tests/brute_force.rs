//! The criteria against brute force on small random systems: every change satisfies every
//! row exactly; L2 is optimal by its first-order condition; L1's optimum and the dimension of
//! its optimal face equal those found by enumerating every basic solution; Fewest's size and
//! ties equal those found by enumerating every support; primary-first changes are optimal
//! for both stages.

use api::Rational;
use criteria::{solve, Measure, Problem};
use num_traits::{Signed, Zero};
use proptest::prelude::*;

fn q(n: i64) -> Rational {
    Rational::from_integer(n.into())
}

/// Gauss–Jordan over the rationals (written again here, independent of the crate): the rank,
/// the reduced rows and their pivot columns.
fn reduce(mut m: Vec<Vec<Rational>>, pivot_cols: usize) -> (Vec<Vec<Rational>>, Vec<usize>) {
    let mut pivots = Vec::new();
    for col in 0..pivot_cols {
        let r = pivots.len();
        let Some(p) = (r..m.len()).find(|&i| !m[i][col].is_zero()) else {
            continue;
        };
        m.swap(r, p);
        let inv = m[r][col].recip();
        m[r] = m[r].iter().map(|v| v * &inv).collect();
        let pivot_row = m[r].clone();
        for (i, row) in m.iter_mut().enumerate() {
            if i != r && !row[col].is_zero() {
                let f = row[col].clone();
                for (v, p) in row.iter_mut().zip(&pivot_row) {
                    *v -= &f * p;
                }
            }
        }
        pivots.push(col);
    }
    (m, pivots)
}

/// A basis of the null space of `m` (width `n`).
fn null_space(m: &[Vec<Rational>], n: usize) -> Vec<Vec<Rational>> {
    let (r, pivots) = reduce(m.to_vec(), n);
    (0..n)
        .filter(|c| !pivots.contains(c))
        .map(|free| {
            let mut z = vec![q(0); n];
            z[free] = q(1);
            for (row, &p) in r.iter().zip(&pivots) {
                z[p] = -row[free].clone();
            }
            z
        })
        .collect()
}

fn times(m: &[Vec<Rational>], y: &[Rational]) -> Vec<Rational> {
    m.iter()
        .map(|row| row.iter().zip(y).map(|(a, b)| a * b).sum())
        .collect()
}

fn dot_weighted(a: &[Rational], b: &[Rational], w: &[Rational], keep: &[bool]) -> Rational {
    (0..a.len())
        .filter(|&j| keep[j])
        .map(|j| &a[j] * &b[j] * &w[j])
        .sum()
}

/// The solution of `m y = t` with support `cols` when the columns are independent and `t` is
/// in their span.
fn basic_solution(m: &[Vec<Rational>], t: &[Rational], cols: &[usize]) -> Option<Vec<Rational>> {
    let sub: Vec<Vec<Rational>> = m
        .iter()
        .zip(t)
        .map(|(row, t)| {
            cols.iter()
                .map(|&c| row[c].clone())
                .chain([t.clone()])
                .collect()
        })
        .collect();
    let (r, pivots) = reduce(sub, cols.len());
    if pivots.len() != cols.len()
        || r[pivots.len()..]
            .iter()
            .any(|row| !row[cols.len()].is_zero())
    {
        return None;
    }
    let mut y = vec![q(0); m[0].len()];
    for (row, &p) in r.iter().zip(&pivots) {
        y[cols[p]] = row[cols.len()].clone();
    }
    Some(y)
}

fn subsets(n: usize) -> impl Iterator<Item = Vec<usize>> {
    (0u32..1 << n).map(move |mask| (0..n).filter(|&j| mask & (1 << j) != 0).collect())
}

fn rank(m: &[Vec<Rational>], n: usize) -> usize {
    reduce(m.to_vec(), n).1.len()
}

/// A random consistent system: `rows × n` entries in −3..=3, `t = M y0`, weights 1..=3,
/// unknowns grouped in pairs or alone.
fn system() -> impl Strategy<Value = (Problem, Vec<bool>)> {
    (1usize..=4, 2usize..=6).prop_flat_map(|(rows, n)| {
        (
            prop::collection::vec(prop::collection::vec(-3i64..=3, n), rows),
            prop::collection::vec(-2i64..=2, n),
            prop::collection::vec(1i64..=3, n),
            prop::collection::vec(any::<bool>(), n),
            any::<bool>(),
        )
            .prop_map(move |(m, y0, w, primary, pairs)| {
                let matrix: Vec<Vec<Rational>> = m
                    .iter()
                    .map(|r| r.iter().map(|&v| q(v)).collect())
                    .collect();
                let y0: Vec<Rational> = y0.iter().map(|&v| q(v)).collect();
                let rhs = vec![times(&matrix, &y0)];
                let groups = (0..n).map(|j| if pairs { j / 2 } else { j }).collect();
                (
                    Problem {
                        matrix,
                        rhs,
                        weights: w.iter().map(|&v| q(v)).collect(),
                        groups,
                        primary: None,
                    },
                    primary,
                )
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 160, ..ProptestConfig::default() })]

    #[test]
    fn least_squares_is_feasible_and_orthogonal_to_every_free_move((problem, _) in system()) {
        let s = solve(&problem, Measure::L2).expect("consistent");
        let y = &s.changes[0];
        prop_assert_eq!(times(&problem.matrix, y), problem.rhs[0].clone());
        let n = problem.weights.len();
        for z in null_space(&problem.matrix, n) {
            prop_assert!(dot_weighted(y, &z, &problem.weights, &vec![true; n]).is_zero());
        }
    }

    #[test]
    fn least_absolute_change_is_the_best_basic_solution((problem, _) in system()) {
        let s = solve(&problem, Measure::L1).expect("consistent");
        let y = &s.changes[0];
        let (m, t, w) = (&problem.matrix, &problem.rhs[0], &problem.weights);
        prop_assert_eq!(&times(m, y), t);
        let n = w.len();
        let l1 = |y: &[Rational]| -> Rational { y.iter().zip(w).map(|(y, w)| y.abs() * w).sum() };
        prop_assert_eq!(l1(y), s.measure.clone());
        let basic: Vec<Vec<Rational>> =
            subsets(n).filter_map(|cols| basic_solution(m, t, &cols)).collect();
        let best = basic.iter().map(|b| l1(b)).min().expect("a basic solution");
        prop_assert_eq!(&s.measure, &best);
        // The optimal face is the hull of the optimal basic solutions (bounded: w > 0).
        let optimal: Vec<&Vec<Rational>> = basic.iter().filter(|b| l1(b) == best).collect();
        let differences: Vec<Vec<Rational>> = optimal
            .iter()
            .map(|b| b.iter().zip(optimal[0]).map(|(x, y)| x - y).collect())
            .collect();
        prop_assert_eq!(s.optimal_face_dimension, Some(rank(&differences, n)));
    }

    #[test]
    fn fewest_changed_is_the_smallest_support_with_every_tie((problem, _) in system()) {
        let s = solve(&problem, Measure::Fewest).expect("consistent");
        let (m, t) = (&problem.matrix, &problem.rhs[0]);
        prop_assert_eq!(&times(m, &s.changes[0]), t);
        let supports = s.supports.expect("supports");
        prop_assert!(supports.proven_minimal);
        let n = problem.weights.len();
        let groups = problem.groups.iter().max().map_or(0, |g| g + 1);
        // Every set of groups whose columns carry t, by size.
        let carrying: Vec<Vec<usize>> = subsets(groups)
            .filter(|set| {
                let cols: Vec<usize> =
                    (0..n).filter(|&j| set.contains(&problem.groups[j])).collect();
                let with: Vec<Vec<Rational>> = m
                    .iter()
                    .zip(t)
                    .map(|(row, t)| cols.iter().map(|&c| row[c].clone()).chain([t.clone()]).collect())
                    .collect();
                let without: Vec<Vec<Rational>> =
                    with.iter().map(|row| row[..cols.len()].to_vec()).collect();
                rank(&with, cols.len() + 1) == rank(&without, cols.len())
            })
            .collect();
        let size = carrying.iter().map(Vec::len).min().expect("all groups carry t");
        let ties = carrying.iter().filter(|s| s.len() == size).count();
        prop_assert_eq!(supports.chosen.len(), size);
        prop_assert_eq!(s.measure.clone(), q(size as i64));
        prop_assert_eq!(supports.count, ties);
        prop_assert_eq!(supports.ties.len(), ties - 1);
        // The change moves exactly the chosen groups (each of a minimum support must move).
        let moved: Vec<usize> = (0..n)
            .filter(|&j| !s.changes[0][j].is_zero())
            .map(|j| problem.groups[j])
            .collect();
        for g in &supports.chosen {
            prop_assert!(moved.contains(g));
        }
        for g in &moved {
            prop_assert!(supports.chosen.contains(g));
        }
    }

    #[test]
    fn primary_first_is_optimal_in_both_stages((mut problem, primary) in system()) {
        problem.primary = Some(primary.clone());
        let s = solve(&problem, Measure::L2).expect("consistent");
        let y = &s.changes[0];
        prop_assert_eq!(&times(&problem.matrix, y), &problem.rhs[0]);
        let n = problem.weights.len();
        let secondary: Vec<bool> = primary.iter().map(|p| !p).collect();
        // Stage 1: no free move lowers the primary squares to first order.
        for z in null_space(&problem.matrix, n) {
            prop_assert!(dot_weighted(y, &z, &problem.weights, &primary).is_zero());
        }
        // Stage 2: among moves that keep the primary unknowns, none lowers the secondary ones.
        let mut pinned = problem.matrix.clone();
        for j in (0..n).filter(|&j| primary[j]) {
            let mut row = vec![q(0); n];
            row[j] = q(1);
            pinned.push(row);
        }
        for z in null_space(&pinned, n) {
            prop_assert!(dot_weighted(y, &z, &problem.weights, &secondary).is_zero());
        }
    }

    #[test]
    fn every_measure_with_primaries_keeps_every_row((mut problem, primary) in system()) {
        problem.primary = Some(primary);
        for measure in [Measure::L1, Measure::Fewest] {
            let s = solve(&problem, measure).expect("consistent");
            prop_assert_eq!(&times(&problem.matrix, &s.changes[0]), &problem.rhs[0]);
        }
    }
}

#[test]
fn bad_problems_are_refused_before_any_work() {
    let problem = Problem {
        matrix: vec![vec![q(1), q(1)]],
        rhs: vec![vec![q(1)]],
        weights: vec![q(1), q(0)],
        groups: vec![0, 1],
        primary: None,
    };
    assert!(solve(&problem, Measure::L1)
        .expect_err("zero weight")
        .to_string()
        .contains("weight 1 is 0"));
    let inconsistent = Problem {
        matrix: vec![vec![q(1), q(1)], vec![q(2), q(2)]],
        rhs: vec![vec![q(1), q(3)]],
        weights: vec![q(1), q(1)],
        groups: vec![0, 1],
        primary: None,
    };
    for measure in [Measure::L2, Measure::L1, Measure::Fewest] {
        assert_eq!(
            solve(&inconsistent, measure),
            Err(criteria::CriterionError::Inconsistent(0))
        );
    }
    let large = Problem {
        matrix: vec![vec![q(0); 1000]; 300],
        rhs: vec![vec![q(0); 300]],
        weights: vec![q(1); 1000],
        groups: (0..1000).collect(),
        primary: None,
    };
    assert!(matches!(
        solve(&large, Measure::L1),
        Err(criteria::CriterionError::TooLarge { .. })
    ));
}
