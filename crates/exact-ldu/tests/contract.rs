//! The backend contract (`backend-contract`) on every exact backend: the fraction-free LDU with
//! each simplification (machine integers and big integers only), the certified row basis (every
//! matrix, also the small fixtures), the block-wise factoring, and
//! the rank, redundancy and consistency answers of the sparse elimination.

use api::{IntMatrix, Integer, Rational, Redundancy};
use backend_contract::analysis::{Analysis, RankAnalysis};
use backend_contract::{analysis_tests, backend_tests, Contract};
use exact_ldu::sparse::{eliminate, eliminate_blockwise, Combinations, SparseElimination};
use exact_ldu::{BlockwiseLdu, ExactLdu, Simplification};
use num_integer::Integer as _;

// Without simplification entries double in size every stage: small matrices only.
backend_tests!(none: ExactLdu::new(Simplification::None), Contract::exact().max_dim(5));
backend_tests!(gcd: ExactLdu::new(Simplification::Gcd), Contract::exact());
backend_tests!(turner: ExactLdu::new(Simplification::Turner), Contract::exact());
backend_tests!(
    bigint_none: ExactLdu::without_machine_integers(Simplification::None),
    Contract::exact().max_dim(5)
);
backend_tests!(
    bigint_gcd: ExactLdu::without_machine_integers(Simplification::Gcd),
    Contract::exact()
);
backend_tests!(
    bigint_turner: ExactLdu::without_machine_integers(Simplification::Turner),
    Contract::exact()
);
backend_tests!(
    certified: ExactLdu::new(Simplification::Gcd).certified_above(0),
    Contract::exact()
);
backend_tests!(
    bigint_certified: ExactLdu::without_machine_integers(Simplification::Gcd).certified_above(0),
    Contract::exact()
);
backend_tests!(
    blockwise_none: BlockwiseLdu::new(Simplification::None),
    Contract::exact().max_dim(5)
);
backend_tests!(blockwise_gcd: BlockwiseLdu::new(Simplification::Gcd), Contract::exact());
backend_tests!(
    blockwise_turner: BlockwiseLdu::new(Simplification::Turner),
    Contract::exact()
);
analysis_tests!(sparse: Sparse(eliminate), Contract::exact());
analysis_tests!(sparse_blockwise: Sparse(eliminate_blockwise), Contract::exact());

/// The sparse elimination (`eliminate` or `eliminate_blockwise`) as a [`RankAnalysis`]:
/// rational right-hand sides are scaled to integers column by column (which changes no
/// verdict), and every combination is asked for.
struct Sparse(fn(&IntMatrix, &[Vec<Integer>], Combinations) -> SparseElimination);

impl RankAnalysis for Sparse {
    type Scalar = Rational;

    fn name(&self) -> &'static str {
        "exact-ldu sparse elimination"
    }

    fn analyse(&self, matrix: &IntMatrix, rhs: &[Vec<Rational>]) -> Analysis<Rational> {
        let columns: Vec<Vec<Integer>> = rhs
            .iter()
            .map(|b| {
                let den = b.iter().fold(Integer::from(1), |l, v| l.lcm(v.denom()));
                b.iter().map(|v| v.numer() * (&den / v.denom())).collect()
            })
            .collect();
        let e = (self.0)(matrix, &columns, Combinations::Exact);
        Analysis {
            rank: e.rank,
            independent_rows: e.pivots.iter().map(|(row, _)| *row).collect(),
            redundancies: e
                .redundant
                .iter()
                .map(|r| Redundancy {
                    row: r.row,
                    combination: r.combination.clone().expect("combinations were asked for"),
                })
                .collect(),
            consistent: (0..rhs.len())
                .map(|k| {
                    e.redundant
                        .iter()
                        .all(|r| !r.inconsistent_columns.contains(&k))
                })
                .collect(),
        }
    }
}
