//! The sparse Givens QR's rank (`float_qr::sparse_row_rank`) against the exact rank on random
//! sparse integer systems with planted dependencies (combinations of earlier and later rows,
//! duplicates, zero rows), in every row order: the ranks agree, the kept rows are independent
//! exactly, and the margin separates kept from dropped by orders of magnitude.

use api::{IntMatrix, LinearBackend};
use exact_ldu::sparse::{eliminate, Combinations};
use proptest::prelude::*;

fn system() -> impl Strategy<Value = (usize, Vec<Vec<(usize, i64)>>)> {
    (4usize..=30, 2usize..=25).prop_flat_map(|(n, m)| {
        let row = prop::collection::vec((0..n, prop_oneof![-6i64..=-1, 1i64..=6]), 1..=4);
        let plants = prop::collection::vec((0..m, 0..m, -3i64..=3, 0usize..=m), 0..=6);
        (Just(n), prop::collection::vec(row, m), plants).prop_map(|(n, mut rows, plants)| {
            for (a, b, k, at) in plants {
                // k·row_a + row_b, inserted anywhere: before its parts or after them.
                let mut combo: Vec<(usize, i64)> =
                    rows[a].iter().map(|(c, v)| (*c, k * v)).collect();
                combo.extend(rows[b].iter().copied());
                rows.insert(at.min(rows.len()), combo);
            }
            (n, rows)
        })
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn sparse_rank_agrees_with_the_exact_rank((n, rows) in system()) {
        let matrix = IntMatrix::from_sparse(
            n,
            rows.iter().map(|r| r.iter().map(|(c, v)| (*c, (*v).into())).collect()).collect(),
        ).expect("in range");
        let exact = eliminate(&matrix, &[], Combinations::Skip).rank;
        let float = float_qr::sparse_row_rank(&matrix, 1e-10).expect("finite");
        prop_assert_eq!(float.rank, exact);
        let all: Vec<usize> = (0..n).collect();
        let kept = eliminate(&matrix.select(&float.independent, &all), &[], Combinations::Skip).rank;
        prop_assert_eq!(kept, float.independent.len(), "kept rows independent exactly");
        prop_assert!(float.margin.largest_dropped < 1e-12, "{:?}", float.margin);
        // The dense column-pivoted QR agrees.
        let dense = float_qr::FloatQr::default().factor(&matrix).expect("factor");
        prop_assert_eq!(api::Factorization::rank(&dense), exact);
    }
}
