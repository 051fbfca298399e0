//! The last matrix an [`crate::ExactLdu`] factored, with its factoring.
//!
//! An edit factors its reduced matrix `R_ED` twice in a row with nothing in between:
//! ExpandDerived checks the requested moves on it (inside the source's plan), then ECLES
//! Initialize factors the same matrix in the host. On real meshes that factoring is a large part
//! of the mouse-down, so the second call takes the first one's result. A memo of a pure function
//! (the factoring is deterministic): it never changes an answer, holds one entry, and shares the
//! factors with the caller (an [`crate::ExactFactorization`] is a pair of reference-counted
//! parts), so it adds no copy of them, nor of the matrix: the factoring's own rows are what the
//! next matrix is compared with.

use crate::factorization::ExactFactorization;
use crate::ldu::Simplification;
use crate::ring::Ring;
use api::IntMatrix;
use std::any::{Any, TypeId};
use std::sync::Mutex;

struct LastFactored {
    method: Simplification,
    certified: bool,
    ring: TypeId,
    factorization: Box<dyn Any + Send>,
}

static LAST_FACTORED: Mutex<Option<LastFactored>> = Mutex::new(None);

/// Empties the memo, so that the next factoring is made afresh (benchmarks of a first
/// mouse-down; nothing else needs it, the memo never changes an answer).
pub fn forget_last_factoring() {
    if let Ok(mut guard) = LAST_FACTORED.lock() {
        *guard = None;
    }
}

/// The factoring of `matrix` by `method` in the ring `R` (through a certified row basis when
/// `certified`), from the memo when it is the last one made.
pub(crate) fn factor<R: Ring>(
    matrix: &IntMatrix,
    method: Simplification,
    certified: bool,
) -> ExactFactorization<R> {
    if let Ok(guard) = LAST_FACTORED.lock() {
        if let Some(last) = guard.as_ref() {
            if last.method == method
                && last.certified == certified
                && last.ring == TypeId::of::<R>()
            {
                if let Some(f) = last.factorization.downcast_ref::<ExactFactorization<R>>() {
                    if f.is_of(matrix) {
                        return f.clone();
                    }
                }
            }
        }
    }
    let f = if certified {
        ExactFactorization::<R>::certified(matrix, method)
    } else {
        ExactFactorization::<R>::new(matrix, method)
    };
    if let Ok(mut guard) = LAST_FACTORED.lock() {
        *guard = Some(LastFactored {
            method,
            certified,
            ring: TypeId::of::<R>(),
            factorization: Box::new(f.clone()),
        });
    }
    f
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ring::Int;
    use api::Factorization;
    use num_bigint::BigInt;

    /// The memo answers exactly what a fresh factoring does, for the same matrix, and does not
    /// answer for another method or another matrix.
    #[test]
    fn the_memo_equals_a_fresh_factoring() {
        let a =
            IntMatrix::from_dense(3, &[vec![1, 2, 0], vec![2, 4, 0], vec![0, 1, 7]]).expect("a");
        let b =
            IntMatrix::from_dense(3, &[vec![1, 2, 0], vec![2, 5, 0], vec![0, 1, 7]]).expect("b");
        for (matrix, method) in [
            (&a, Simplification::Gcd),
            (&a, Simplification::Gcd),
            (&a, Simplification::None),
            (&b, Simplification::Gcd),
            (&a, Simplification::Gcd),
        ] {
            let memo = factor::<Int>(matrix, method, false);
            assert_eq!(memo, ExactFactorization::<Int>::new(matrix, method));
            let memo = factor::<Int>(matrix, method, true);
            assert_eq!(memo, ExactFactorization::<Int>::certified(matrix, method));
            assert!(memo.is_certified());
        }
        assert_eq!(factor::<Int>(&a, Simplification::Gcd, false).rank(), 2);
        assert_eq!(factor::<Int>(&b, Simplification::Gcd, true).rank(), 3);
    }

    /// The memo compares the next matrix with the factoring's own rows by value: entries
    /// beyond an `i64`, a big entry against a small one, another shape, a zero left out.
    #[test]
    fn the_memo_tells_matrices_apart_by_value() {
        let big = BigInt::from(1u8) << 70u32;
        let with = |entry: BigInt, last: i64, cols: usize| {
            IntMatrix::from_sparse(
                cols,
                vec![
                    vec![(0, BigInt::from(1)), (1, entry)],
                    vec![(1, BigInt::from(last))],
                ],
            )
            .expect("a matrix")
        };
        let a = with(big.clone(), 3, 2);
        let same = with(big.clone(), 3, 2);
        let other_big = with(big.clone() + 1, 3, 2);
        let small = with(BigInt::from(5), 3, 2);
        let other_small = with(big.clone(), 4, 2);
        let wider = with(big.clone(), 3, 3);
        let fewer = IntMatrix::from_sparse(2, vec![vec![(0, BigInt::from(1)), (1, big.clone())]])
            .expect("a matrix");
        let f = factor::<Int>(&a, Simplification::Gcd, false);
        assert!(f.is_of(&a) && f.is_of(&same));
        for (m, what) in [
            (&other_big, "another big entry"),
            (&small, "a small entry"),
            (&other_small, "another small entry"),
            (&wider, "another width"),
            (&fewer, "fewer rows"),
        ] {
            assert!(!f.is_of(m), "{what}");
            assert_eq!(
                factor::<Int>(m, Simplification::Gcd, false),
                ExactFactorization::<Int>::new(m, Simplification::Gcd),
                "{what}"
            );
            factor::<Int>(&a, Simplification::Gcd, false);
        }
        let g = factor::<BigInt>(&a, Simplification::Gcd, false);
        assert!(g.is_of(&same) && !g.is_of(&other_big) && !g.is_of(&small));
    }
}
