//! The hints of the last update, gathered per coordinate column.
//!
//! A vector-layout edit solves each coordinate on its own, so every update gathers coordinate
//! `j` of every derived parameter's hint into one vector; a scalar-layout edit solves once, for
//! every coordinate of every derived parameter in one vector — on a drag the same hints every
//! frame. Copying them costs two big-integer allocations per value, as much as the rest of a
//! small exact frame; comparing them with the last ones costs none.

use api::Rational;
use std::sync::{Arc, Mutex};

/// Per-parameter hints as given (`hints[k][j]`) and, gathered from them, one vector per
/// coordinate (`columns[j][k]`), for the last update.
type Gathered = (Vec<Vec<Rational>>, Arc<Vec<Vec<Rational>>>);

/// One column of gathered hints. Two columns from the same gathering are the same hints
/// ([`HintColumn::same_as`], a pointer comparison): the memos of the steps that follow (the
/// substitution's group hints) recognise a drag's unchanged hints without comparing numbers.
/// The column keeps its gathering alive, so the identity cannot be taken by other hints.
#[derive(Debug, Clone)]
pub(crate) struct HintColumn {
    gathered: Arc<Vec<Vec<Rational>>>,
    column: usize,
}

impl HintColumn {
    /// Whether `other` is this column of the same gathering (then it holds the same hints).
    pub(crate) fn same_as(&self, other: &HintColumn) -> bool {
        Arc::ptr_eq(&self.gathered, &other.gathered) && self.column == other.column
    }

    /// Column `column` of `gathered`.
    fn new(gathered: &Arc<Vec<Vec<Rational>>>, column: usize) -> Self {
        HintColumn {
            gathered: Arc::clone(gathered),
            column,
        }
    }
}

impl std::ops::Deref for HintColumn {
    type Target = [Rational];

    fn deref(&self) -> &[Rational] {
        &self.gathered[self.column]
    }
}

/// The last update's hints by column (shared by clones of an edit until either updates).
#[derive(Debug, Default)]
pub(crate) struct HintColumns(Mutex<Option<Gathered>>);

impl HintColumns {
    /// `hints` (one vector of `dim` coordinates per derived parameter) by coordinate: from the
    /// memo when they equal the last hints, gathered (and remembered) otherwise.
    pub(crate) fn by_column(&self, hints: &[Vec<Rational>], dim: usize) -> Vec<HintColumn> {
        let gathered = self.gathered(hints, |hints| {
            (0..dim)
                .map(|j| hints.iter().map(|v| v[j].clone()).collect())
                .collect()
        });
        (0..dim).map(|j| HintColumn::new(&gathered, j)).collect()
    }

    /// `hints` (one vector per derived parameter, of any dimensions) as one column, every
    /// coordinate of every parameter in order: from the memo when they equal the last hints.
    pub(crate) fn flattened(&self, hints: &[Vec<Rational>]) -> HintColumn {
        let gathered = self.gathered(hints, |hints| {
            vec![hints.iter().flatten().cloned().collect()]
        });
        HintColumn::new(&gathered, 0)
    }

    /// The memo's columns when `hints` are, number for number, the last hints; `gather(hints)`
    /// (remembered) otherwise. One memo serves one layout: an edit never changes its layout.
    fn gathered(
        &self,
        hints: &[Vec<Rational>],
        gather: impl FnOnce(&[Vec<Rational>]) -> Vec<Vec<Rational>>,
    ) -> Arc<Vec<Vec<Rational>>> {
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
        let columns = Arc::new(gather(hints));
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
        assert_eq!(&*columns[0], [q(1), q(3)]);
        assert_eq!(&*columns[1], [q(2), q(4)]);
        assert!(!columns[0].same_as(&columns[1]));
        // The same hints again (equal, not the same vectors): the same gathering, not a copy.
        let again = memo.by_column(&first.clone(), 2);
        assert!(columns[0].same_as(&again[0]) && columns[1].same_as(&again[1]));
        // New hints are gathered anew.
        let second = vec![vec![q(1), q(2)], vec![q(3), q(5)]];
        let new = memo.by_column(&second, 2);
        assert_eq!(&*new[1], [q(2), q(5)]);
        assert!(!new[1].same_as(&columns[1]));
        // A clone starts from the same memo.
        assert!(memo.clone().by_column(&second, 2)[0].same_as(&new[0]));
    }

    #[test]
    fn flattens_every_coordinate_in_order_and_follows_new_hints() {
        let memo = HintColumns::default();
        let first = vec![vec![q(1), q(2)], vec![q(3)]];
        let flat = memo.flattened(&first);
        assert_eq!(&*flat, [q(1), q(2), q(3)]);
        assert!(flat.same_as(&memo.flattened(&first)));
        let second = vec![vec![q(1), q(2)], vec![q(4)]];
        let new = memo.flattened(&second);
        assert_eq!(&*new, [q(1), q(2), q(4)]);
        assert!(!new.same_as(&flat));
    }
}
