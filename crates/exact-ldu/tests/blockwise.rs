//! Block-wise factoring gives exactly the answers of one factoring of the whole matrix.

use api::{Factorization, IntMatrix, LinearBackend, Rational, RhsFamily, SolveError};
use exact_ldu::{BlockwiseLdu, ExactLdu, Simplification};
use proptest::prelude::*;
use std::collections::BTreeSet;

const METHODS: [Simplification; 3] = [
    Simplification::None,
    Simplification::Gcd,
    Simplification::Turner,
];

fn r(v: i64) -> Rational {
    Rational::from_integer(v.into())
}

/// A matrix made of blocks placed on scattered rows and columns (by a fixed shuffle), so the
/// components are interleaved in the numbering.
#[derive(Debug, Clone)]
struct Case {
    rows: usize,
    cols: usize,
    entries: Vec<(usize, usize, i64)>,
}

fn block() -> impl Strategy<Value = Vec<Vec<i64>>> {
    (1usize..=4, 1usize..=4).prop_flat_map(|(m, n)| {
        prop_oneof![
            prop::collection::vec(prop::collection::vec(-3i64..=3, n), m),
            // rank-1 blocks
            (
                prop::collection::vec(-2i64..=2, m),
                prop::collection::vec(-2i64..=2, n)
            )
                .prop_map(|(u, v)| u
                    .iter()
                    .map(|a| v.iter().map(|b| a * b).collect())
                    .collect()),
        ]
    })
}

fn case() -> impl Strategy<Value = Case> {
    (
        prop::collection::vec(block(), 1..=4),
        any::<bool>(),
        0u64..1000,
    )
        .prop_map(|(mut blocks, duplicate, seed)| {
            if duplicate {
                let first = blocks[0].clone();
                blocks.push(first);
            }
            placed(&blocks, 1, seed)
        })
}

/// `blocks` placed on the diagonal of a matrix with `free` empty columns more, rows and columns
/// then scattered by a fixed shuffle (`seed`), so the components are interleaved in the
/// numbering.
fn placed(blocks: &[Vec<Vec<i64>>], free: usize, seed: u64) -> Case {
    let rows: usize = blocks.iter().map(Vec::len).sum();
    let cols: usize = blocks.iter().map(|b| b[0].len()).sum::<usize>() + free;
    let shuffle = |k: usize, len: usize| (k * 7 + seed as usize) % len;
    let mut row_map: Vec<usize> = (0..rows).collect();
    let mut col_map: Vec<usize> = (0..cols).collect();
    for k in 0..rows {
        row_map.swap(k, shuffle(k, rows));
    }
    for k in 0..cols {
        col_map.swap(k, shuffle(k, cols));
    }
    let mut entries = Vec::new();
    let (mut r0, mut c0) = (0, 0);
    for b in blocks {
        for (i, row) in b.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                if *v != 0 {
                    entries.push((row_map[r0 + i], col_map[c0 + j], *v));
                }
            }
        }
        r0 += b.len();
        c0 += b[0].len();
    }
    Case {
        rows,
        cols,
        entries,
    }
}

fn matrix(c: &Case) -> IntMatrix {
    let mut rows = vec![Vec::new(); c.rows];
    for &(i, j, v) in &c.entries {
        rows[i].push((j, v.into()));
    }
    IntMatrix::from_sparse(c.cols, rows).expect("in range")
}

/// Redundancies as a set, each combination sorted by row: comparable whatever the order.
fn redundancy_set(
    redundancies: Vec<api::Redundancy<Rational>>,
) -> BTreeSet<(usize, Vec<(usize, Rational)>)> {
    redundancies
        .into_iter()
        .map(|r| {
            let mut combo = r.combination;
            combo.sort_by_key(|(i, _)| *i);
            (r.row, combo)
        })
        .collect()
}

fn set<T: Ord + Clone>(v: &[T]) -> BTreeSet<T> {
    v.iter().cloned().collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn blockwise_equals_monolithic(
        c in case(),
        x in prop::collection::vec(-5i64..=5, 20),
        h in prop::collection::vec(-5i64..=5, 20),
        noise in 0usize..20,
    ) {
        let a = matrix(&c);
        for method in METHODS {
            let mono = ExactLdu::new(method).factor(&a).expect("factor");
            let blocks = BlockwiseLdu::new(method).factor(&a).expect("factor");
            prop_assert_eq!(mono.rank(), blocks.rank());
            prop_assert_eq!(set(&mono.independent_rows()), set(&blocks.independent_rows()));
            prop_assert_eq!(redundancy_set(mono.redundancies()), redundancy_set(blocks.redundancies()));
            prop_assert_eq!(set(&mono.null_space()), set(&blocks.null_space()));
            // A consistent right-hand side: identical basic solutions and least squares.
            let xr: Vec<Rational> = (0..c.cols).map(|j| r(x[j % x.len()])).collect();
            let b: Vec<Rational> = a.row_iter().map(|row| {
                row.iter().map(|(j, v)| Rational::from_integer(v.clone()) * &xr[*j]).sum()
            }).collect();
            let (sm, sb) = (mono.solve(&b).expect("consistent"), blocks.solve(&b).expect("consistent"));
            prop_assert_eq!(&sm, &sb);
            for (side, x) in [("mono", &sm), ("blocks", &sb)] {
                for (row, bi) in a.row_iter().zip(&b) {
                    let ax: Rational = row.iter().map(|(j, v)| Rational::from_integer(v.clone()) * &x[*j]).sum();
                    prop_assert_eq!(&ax, bi, "{:?} {}", method, side);
                }
            }
            let hints: Vec<Rational> = (0..c.cols).map(|j| r(h[j % h.len()])).collect();
            let weights: Vec<Rational> = (0..c.cols).map(|j| Rational::new((1 + j as i64 % 3).into(), 2.into())).collect();
            prop_assert_eq!(
                mono.least_squares(&b, &hints, &weights).expect("consistent"),
                blocks.least_squares(&b, &hints, &weights).expect("consistent")
            );
            let family = RhsFamily::single(b.clone());
            let prepared = blocks.prepare_least_squares(&family, &weights).expect("prepare");
            let approx = api::PreparedLeastSquares::solve_approx(&prepared, 0, &[], &hints).expect("consistent");
            let exact = api::PreparedLeastSquares::solve(&prepared, 0, &[], &hints).expect("consistent");
            for (a, e) in approx.iter().zip(&exact) {
                prop_assert_eq!(*a, api::Value::to_f64(e));
            }
            // A perturbed right-hand side: the same verdict, valid certificates.
            let mut bad = b.clone();
            if !bad.is_empty() {
                let k = noise % bad.len();
                bad[k] += r(1);
            }
            match (mono.check_consistent(&bad), blocks.check_consistent(&bad)) {
                (Ok(()), Ok(())) => {}
                (Err(SolveError::Inconsistent(m)), Err(SolveError::Inconsistent(bl))) => {
                    prop_assert_eq!(m.rows.len(), bl.rows.len());
                    for j in 0..c.cols {
                        let s: Rational = bl.rows.iter().zip(&bl.certificate)
                            .map(|(&i, y)| y * Rational::from_integer(a.get(i, j))).sum();
                        prop_assert_eq!(s, r(0));
                    }
                }
                (m, bl) => prop_assert!(false, "verdicts differ: {:?} vs {:?}", m.is_ok(), bl.is_ok()),
            }
        }
    }
}

#[test]
fn identical_components_share_one_factorization() {
    // Two copies of the same 2 × 3 block (x and y of a vector row, say) and a free column.
    let a = IntMatrix::from_sparse(
        7,
        vec![
            vec![(0, 1.into()), (2, (-1).into())],
            vec![(1, 1.into()), (3, (-1).into())],
            vec![(2, 2.into()), (4, 1.into())],
            vec![(3, 2.into()), (5, 1.into())],
        ],
    )
    .expect("matrix");
    let f = BlockwiseLdu::default().factor(&a).expect("factor");
    assert_eq!(f.component_count(), 3);
    assert_eq!(f.distinct_factorizations(), 2);
    assert_eq!(f.rank(), 4);
    assert_eq!(f.null_space().len(), 3);
}

/// Tall and wide blocks up to 10 × 6, sparse: whole matrices of up to 60 rows, above the size
/// where the exact backend proves independent rows through the Gram matrix, and transposes of
/// wide systems (as the propagation analysis factors `Aᵀ`), where most rows are dependent.
fn tall_block() -> impl Strategy<Value = Vec<Vec<i64>>> {
    (1usize..=10, 1usize..=6).prop_flat_map(|(m, n)| {
        prop::collection::vec(
            prop::collection::vec(prop_oneof![3 => Just(0i64), 2 => -2i64..=2], n),
            m,
        )
        .prop_map(move |mut b| {
            // Every block keeps at least one entry, so it is a component of its own or joins
            // others only through shared rows and columns it really has.
            if b.iter().all(|row| row.iter().all(|v| *v == 0)) {
                b[0][0] = 1;
            }
            b
        })
    })
}

fn tall_case() -> impl Strategy<Value = Case> {
    (prop::collection::vec(tall_block(), 1..=6), 0u64..1000)
        .prop_map(|(blocks, seed)| placed(&blocks, 0, seed))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 120, ..ProptestConfig::default() })]

    /// The claim of `blocks.rs` where rows are mostly dependent: the block-wise factoring, the
    /// whole factoring and the whole factoring for solves (no Gram proof, LDU at once) give the
    /// same rank, independent rows, redundancy combinations, null space and basic solution.
    #[test]
    fn blockwise_equals_monolithic_on_tall_matrices(
        c in tall_case(),
        x in prop::collection::vec(-5i64..=5, 36),
    ) {
        let a = matrix(&c);
        for method in METHODS {
            let whole = ExactLdu::new(method).factor(&a).expect("factor");
            let for_solves = ExactLdu::new(method).factor_for_solves(&a).expect("factor");
            let blocks = BlockwiseLdu::new(method).factor(&a).expect("factor");
            let xr: Vec<Rational> = (0..c.cols).map(|j| r(x[j % x.len()])).collect();
            let b: Vec<Rational> = a.row_iter().map(|row| {
                row.iter().map(|(j, v)| Rational::from_integer(v.clone()) * &xr[*j]).sum()
            }).collect();
            let expected = whole.solve(&b).expect("consistent");
            prop_assert_eq!(whole.rank(), for_solves.rank(), "{:?} for solves", method);
            prop_assert_eq!(set(&whole.independent_rows()), set(&for_solves.independent_rows()));
            prop_assert_eq!(redundancy_set(whole.redundancies()), redundancy_set(for_solves.redundancies()));
            prop_assert_eq!(set(&whole.null_space()), set(&for_solves.null_space()));
            prop_assert_eq!(&expected, &for_solves.solve(&b).expect("consistent"));
            prop_assert_eq!(whole.rank(), blocks.rank(), "{:?} blocks", method);
            prop_assert_eq!(set(&whole.independent_rows()), set(&blocks.independent_rows()));
            prop_assert_eq!(redundancy_set(whole.redundancies()), redundancy_set(blocks.redundancies()));
            prop_assert_eq!(set(&whole.null_space()), set(&blocks.null_space()));
            prop_assert_eq!(&expected, &blocks.solve(&b).expect("consistent"));
            // Inconsistent right-hand sides: the same verdict and valid certificates.
            for k in 0..b.len().min(4) {
                let mut bad = b.clone();
                bad[(k * 5 + x[0].unsigned_abs() as usize) % b.len()] += r(1);
                let verdicts = [
                    whole.check_consistent(&bad),
                    for_solves.check_consistent(&bad),
                    blocks.check_consistent(&bad),
                ];
                let lengths: Vec<Option<usize>> = verdicts.iter().map(|v| match v {
                    Ok(()) => None,
                    Err(SolveError::Inconsistent(inc)) => Some(inc.rows.len()),
                    Err(e) => panic!("unexpected {e:?}"),
                }).collect();
                prop_assert_eq!(lengths[0], lengths[1], "{:?}", method);
                prop_assert_eq!(lengths[0], lengths[2], "{:?}", method);
                for v in &verdicts {
                    if let Err(SolveError::Inconsistent(inc)) = v {
                        for j in 0..c.cols {
                            let s: Rational = inc.rows.iter().zip(&inc.certificate)
                                .map(|(&i, y)| y * Rational::from_integer(a.get(i, j))).sum();
                            prop_assert_eq!(s, r(0));
                        }
                        let yb: Rational = inc.rows.iter().zip(&inc.certificate)
                            .map(|(&i, y)| y * &bad[i]).sum();
                        prop_assert!(yb != r(0), "the certificate does not refute");
                    }
                }
            }
        }
    }
}
