//! Exact linear algebra on integer matrices: the fraction-free LDU factoring of the ECLES thesis
//! (algorithms 6–13) and everything built on it: exact solve (algorithm 14), weak and strong
//! solvability (8.2.1, 8.2.2), weighted least squares (algorithm 15), the integer null space and
//! inconsistency certificates.
//!
//! Every decision (rank, redundancy, consistency) is exact. Entries are kept in machine integers
//! while they fit ([`Int`]) and move to big integers only on overflow; the algorithms are generic
//! over [`Ring`], so the same code runs on [`num_bigint::BigInt`] alone
//! ([`ExactLdu::without_machine_integers`]) with identical results.
//!
//! ```
//! use api::{Factorization, IntMatrix, LinearBackend, Rational};
//! use exact_ldu::{ExactLdu, Simplification};
//!
//! // p1 + p2 - p3 = 0, p4 - p3 = 5 (the pump example of the thesis, 2.2)
//! let a = IntMatrix::from_dense(4, &[vec![1, 1, -1, 0], vec![0, 0, -1, 1]]).unwrap();
//! let f = ExactLdu::new(Simplification::Gcd).factor(&a).unwrap();
//! assert_eq!(f.rank(), 2);
//! let b = [Rational::from_integer(0.into()), Rational::from_integer(5.into())];
//! let x = f.solve(&b).unwrap();
//! assert_eq!(x[0].clone() + x[1].clone() - x[2].clone(), b[0]);
//! ```

mod bareiss_small;
mod blocks;
mod certified;
mod decimal_lanes;
mod decimal_words;
mod dixon;
mod factorization;
mod gcd;
mod gram_words;
// SIMD loads and stores need `unsafe`.
#[allow(unsafe_code)]
mod ifma;
// SIMD intrinsics need `unsafe` (the processor's features are checked at run time).
#[allow(unsafe_code)]
mod lane_products;
mod ldlt_symbolic;
mod ldu;
mod lsq;
mod memo;
mod modular;
mod montgomery;
// SIMD intrinsics need `unsafe` (the processor's features are checked at run time).
#[allow(unsafe_code)]
mod montgomery_lanes;
mod padic_lanes;
mod qvec;
mod reduce;
mod reduce_words;
mod ring;
mod shared_once;
mod snap;
pub mod sparse;
mod word_combination;
mod word_division;

pub use blocks::{
    component_matrices, components, submatrix, BlockFactorization, BlockLeastSquares,
};
pub use decimal_lanes::decimal_texts;
pub use factorization::ExactFactorization;
pub use gcd::{gcd_bigint, reduced_ratio, reduced_small_ratio};
pub use ldu::{Ldu, Pivoting, Simplification, StageSnapshot};
pub use lsq::ExactLeastSquares;
pub use memo::forget_last_factoring;
pub use qvec::QVec;
pub use reduce::reduce_over;
pub use ring::{gcd_all, Int, Ring};

use api::{BackendError, IntMatrix, LinearBackend};
use num_bigint::BigInt;
use std::marker::PhantomData;

/// Matrices with more entries (rows × columns) than this are factored through a certified row
/// basis ([`ExactFactorization::certified`]) rather than the fraction-free LDU: below it the
/// LDU is as fast and its pivots are the thesis' own (see ARCHITECTURE.md, "Certified row
/// bases").
pub const CERTIFIED_ABOVE_ENTRIES: usize = 4096;

/// The exact backend: factors with the fraction-free LDU in the integer type `R`, large
/// matrices through a certified row basis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ExactLdu<R: Ring = Int> {
    method: Simplification,
    certified_above: usize,
    ring: PhantomData<R>,
}

impl ExactLdu<Int> {
    /// The exact backend with the machine-integer fast path.
    pub fn new(method: Simplification) -> Self {
        ExactLdu {
            method,
            certified_above: CERTIFIED_ABOVE_ENTRIES,
            ring: PhantomData,
        }
    }
}

impl ExactLdu<BigInt> {
    /// The exact backend computing in big integers throughout (for comparison and benchmarks).
    pub fn without_machine_integers(method: Simplification) -> Self {
        ExactLdu {
            method,
            certified_above: CERTIFIED_ABOVE_ENTRIES,
            ring: PhantomData,
        }
    }
}

impl Default for ExactLdu<Int> {
    fn default() -> Self {
        ExactLdu::new(Simplification::default())
    }
}

impl<R: Ring> ExactLdu<R> {
    /// The simplification method.
    pub fn method(&self) -> Simplification {
        self.method
    }

    /// The same backend with certified row bases for matrices of more than `entries` entries
    /// (`0`: always; `usize::MAX`: never, the fraction-free LDU throughout).
    pub fn certified_above(self, entries: usize) -> Self {
        ExactLdu {
            certified_above: entries,
            ..self
        }
    }
}

impl<R: Ring> LinearBackend for ExactLdu<R> {
    type Factorization = ExactFactorization<R>;

    fn name(&self) -> &'static str {
        "exact-ldu"
    }

    /// Factors `matrix` (through a certified row basis above the size limit); the same matrix
    /// factored twice in a row is factored once (the memo of the last factoring: ExpandDerived
    /// and ECLES Initialize factor the same `R_ED`).
    fn factor(&self, matrix: &IntMatrix) -> Result<Self::Factorization, BackendError> {
        let certified = matrix.rows().saturating_mul(matrix.cols()) > self.certified_above;
        Ok(memo::factor(matrix, self.method, certified))
    }

    /// The fraction-free LDU at once below the size limit (a solve or the null space would
    /// make it anyway), without the Gram proof of independent rows that only least squares
    /// uses; not kept in the memo (the edit's `R_ED` stays there).
    fn factor_for_solves(&self, matrix: &IntMatrix) -> Result<Self::Factorization, BackendError> {
        if matrix.rows().saturating_mul(matrix.cols()) > self.certified_above {
            return self.factor(matrix);
        }
        Ok(ExactFactorization::fraction_free_now(matrix, self.method))
    }
}

/// The exact backend factoring each connected component of the matrix separately (identical
/// components share one factorization). Same answers as [`ExactLdu`]; much less work when the
/// matrix falls apart into components (the coordinates of vector parameters, independent parts
/// of a model).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BlockwiseLdu<R: Ring = Int> {
    method: Simplification,
    ring: PhantomData<R>,
}

impl BlockwiseLdu<Int> {
    /// The block-wise exact backend with the machine-integer fast path.
    pub fn new(method: Simplification) -> Self {
        BlockwiseLdu {
            method,
            ring: PhantomData,
        }
    }
}

impl Default for BlockwiseLdu<Int> {
    fn default() -> Self {
        BlockwiseLdu::new(Simplification::default())
    }
}

impl<R: Ring> LinearBackend for BlockwiseLdu<R> {
    type Factorization = BlockFactorization<R>;

    fn name(&self) -> &'static str {
        "exact-ldu (block-wise)"
    }

    fn factor(&self, matrix: &IntMatrix) -> Result<Self::Factorization, BackendError> {
        Ok(BlockFactorization::new(matrix, self.method))
    }
}
