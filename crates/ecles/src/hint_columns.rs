//! The hints of the last update, gathered per coordinate column.
//!
//! A vector-layout edit solves each coordinate on its own, so every update gathers coordinate
//! `j` of every derived parameter's hint into one vector — on a drag the same hints every frame.
//! Copying them costs two big-integer allocations per value per column, as much as the rest of a
//! small exact frame; comparing them with the last ones costs none.

use api::Rational;
use std::sync::{Arc, Mutex};

/// Per-parameter hints as given (`hints[k][j]`) and, gathered from them, one vector per
/// coordinate (`columns[j][k]`), for the last update.
type Gathered = (Vec<Vec<Rational>>, Arc<Vec<Vec<Rational>>>);

/// The last update's hints by column (shared by clones of an edit until either updates).
#[derive(Debug, Default)]
pub(crate) struct HintColumns(Mutex<Option<Gathered>>);

impl HintColumns {
    /// `hints` (one vector of `dim` coordinates per derived parameter) by coordinate: from the
    /// memo when they equal the last hints, gathered (and remembered) otherwise.
    pub(crate) fn by_column(&self, hints: &[Vec<Rational>], dim: usize) -> Arc<Vec<Vec<Rational>>> {
        if let Ok(guard) = self.0.lock() {
            if let Some((given, columns)) = guard.as_ref() {
                if given.len() == hints.len()
                    && given
                        .iter()
                        .zip(hints)
                        .all(|(a, b)| api::identical_rationals(a, b))
                {
                    return Arc::clone(columns);
                }
            }
        }
        let columns: Arc<Vec<Vec<Rational>>> = Arc::new(
            (0..dim)
                .map(|j| hints.iter().map(|v| v[j].clone()).collect())
                .collect(),
        );
        if let Ok(mut guard) = self.0.lock() {
            *guard = Some((hints.to_vec(), Arc::clone(&columns)));
        }
        columns
    }
}

impl Clone for HintColumns {
    fn clone(&self) -> Self {
        HintColumns(Mutex::new(self.0.lock().map(|g| g.clone()).unwrap_or(None)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64) -> Rational {
        Rational::from_integer(n.into())
    }

    #[test]
    fn gathers_by_column_and_follows_new_hints() {
        let memo = HintColumns::default();
        let first = vec![vec![q(1), q(2)], vec![q(3), q(4)]];
        let columns = memo.by_column(&first, 2);
        assert_eq!(*columns, vec![vec![q(1), q(3)], vec![q(2), q(4)]]);
        // The same hints again: the same gathered vectors, not a copy.
        assert!(Arc::ptr_eq(&columns, &memo.by_column(&first, 2)));
        // New hints are gathered anew.
        let second = vec![vec![q(1), q(2)], vec![q(3), q(5)]];
        assert_eq!(
            *memo.by_column(&second, 2),
            vec![vec![q(1), q(3)], vec![q(2), q(5)]]
        );
        // A clone starts from the same memo.
        assert!(Arc::ptr_eq(
            &memo.clone().by_column(&second, 2),
            &memo.by_column(&second, 2)
        ));
    }
}
