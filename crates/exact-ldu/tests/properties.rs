//! Algebraic invariants of the exact factoring on random matrices of every shape and rank,
//! beyond the backend contract (`tests/contract.rs`, which checks every answer against an
//! independent oracle): the factors reconstruct `A` exactly, and machine integers and big
//! integers give bit-identical factors.

use api::{IntMatrix, LinearBackend};
use backend_contract::{cases, oracle};
use exact_ldu::{ExactLdu, Simplification};
use proptest::prelude::*;

const METHODS: [Simplification; 3] = [
    Simplification::None,
    Simplification::Gcd,
    Simplification::Turner,
];

proptest! {
    #![proptest_config(ProptestConfig { cases: 160, ..ProptestConfig::default() })]

    /// A = Π_R L D⁻¹ U Π_C exactly (invariant I1), and the same algorithm over plain big
    /// integers gives bit-identical factors and permutations.
    #[test]
    fn factoring_invariants((cols, rows) in cases::matrix(7)) {
        let matrix = IntMatrix::from_dense(cols, &rows).expect("rectangular");
        let a = oracle::dense(&matrix);
        for method in METHODS {
            let f = ExactLdu::new(method).factor(&matrix).expect("factor");
            prop_assert_eq!(&f.ldu().expect("factored fraction-free").reconstruct(), &a);
            let big = ExactLdu::without_machine_integers(method).factor(&matrix).expect("factor");
            prop_assert_eq!(big.ldu().expect("factored fraction-free").dense_factors(), f.ldu().expect("factored fraction-free").dense_factors());
            prop_assert_eq!(big.ldu().expect("factored fraction-free").row_perm(), f.ldu().expect("factored fraction-free").row_perm());
            prop_assert_eq!(big.ldu().expect("factored fraction-free").col_perm(), f.ldu().expect("factored fraction-free").col_perm());
        }
    }
}
