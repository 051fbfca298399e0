//! The last matrix an [`crate::ExactLdu`] factored, with its factoring.
//!
//! An edit factors its reduced matrix `R_ED` twice in a row with nothing in between:
//! ExpandDerived checks the requested moves on it (inside the source's plan), then ECLES
//! Initialize factors the same matrix in the host. On real meshes that factoring is a large part
//! of the mouse-down, so the second call takes the first one's result. A memo of a pure function
//! (the factoring is deterministic): it never changes an answer, holds one entry, and shares the
//! factors with the caller (an [`crate::ExactFactorization`] is a pair of reference-counted
//! parts), so it adds no copy of them.

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
    matrix: IntMatrix,
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
                && last.matrix == *matrix
            {
                if let Some(f) = last.factorization.downcast_ref::<ExactFactorization<R>>() {
                    return f.clone();
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
            matrix: matrix.clone(),
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
}
