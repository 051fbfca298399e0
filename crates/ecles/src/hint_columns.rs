//! The hints of the last update, gathered per coordinate column.
//!
//! A vector-layout edit solves each coordinate on its own, so every update gathers coordinate
//! `j` of every derived parameter's hint into one vector; a scalar-layout edit solves once, for
//! every coordinate of every derived parameter in one vector — on a drag the same hints every
//! frame. Copying them costs two big-integer allocations per value, as much as the rest of a
//! small exact frame; comparing them with the last ones costs none.

use api::Rational;
use std::sync::{Arc, Mutex};

/// The hints of the last update, gathered: one vector per coordinate (`columns[j][k]` is
/// coordinate `j` of hint `k`), or every coordinate of every hint in one vector. They are also
/// the memo's key: the next hints are compared with them, not with a copy of the hints as
/// given.
type Gathered = Arc<Vec<Vec<Rational>>>;

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
        let gathered = self.gathered(
            |columns| {
                columns.len() == dim
                    && hints.iter().enumerate().all(|(k, v)| {
                        v.len() == dim
                            && v.iter()
                                .zip(columns.iter())
                                .all(|(x, column)| column.get(k).is_some_and(|y| identical(x, y)))
                    })
                    && columns.iter().all(|column| column.len() == hints.len())
            },
            || {
                (0..dim)
                    .map(|j| hints.iter().map(|v| v[j].clone()).collect())
                    .collect()
            },
        );
        (0..dim).map(|j| HintColumn::new(&gathered, j)).collect()
    }

    /// `hints` (one vector per derived parameter, of any dimensions) as one column, every
    /// coordinate of every parameter in order: from the memo when they equal the last hints.
    pub(crate) fn flattened(&self, hints: &[Vec<Rational>]) -> HintColumn {
        let gathered = self.gathered(
            |columns| match columns.as_slice() {
                [flat] => {
                    flat.len() == hints.iter().map(Vec::len).sum::<usize>()
                        && hints
                            .iter()
                            .flatten()
                            .zip(flat)
                            .all(|(x, y)| identical(x, y))
                }
                _ => false,
            },
            || vec![hints.iter().flatten().cloned().collect()],
        );
        HintColumn::new(&gathered, 0)
    }

    /// The memo's gathering when `is_gathering_of_hints` says it is that of `hints`, number for
    /// number; `gather()` (remembered) otherwise. One memo serves one layout: an edit never
    /// changes its layout.
    fn gathered(
        &self,
        is_gathering_of_hints: impl FnOnce(&Vec<Vec<Rational>>) -> bool,
        gather: impl FnOnce() -> Vec<Vec<Rational>>,
    ) -> Gathered {
        if let Ok(guard) = self.0.lock() {
            if let Some(columns) = guard.as_ref() {
                if is_gathering_of_hints(columns) {
                    return Arc::clone(columns);
                }
            }
        }
        let columns = Arc::new(gather());
        if let Ok(mut guard) = self.0.lock() {
            *guard = Some(Arc::clone(&columns));
        }
        columns
    }
}

/// Whether `a` and `b` hold the same numerator and denominator ([`api::identical_rationals`]).
fn identical(a: &Rational, b: &Rational) -> bool {
    api::identical_rationals(std::slice::from_ref(a), std::slice::from_ref(b))
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
        // One hint more or fewer is new hints, even when the others are the same.
        let longer = vec![vec![q(1), q(2)], vec![q(4)], vec![q(5)]];
        assert_eq!(&*memo.flattened(&longer), [q(1), q(2), q(4), q(5)]);
        assert_eq!(&*memo.flattened(&first[..1]), [q(1), q(2)]);
    }

    /// The memo compares new hints with its gathering: a hint more, a hint fewer, a coordinate
    /// changed or an equal value written unreduced each gather again; the same numbers do not.
    #[test]
    fn gathered_columns_are_the_key() {
        let memo = HintColumns::default();
        let first = vec![vec![q(1), q(2)], vec![q(3), q(4)]];
        let columns = memo.by_column(&first, 2);
        let fewer = memo.by_column(&first[..1], 2);
        assert_eq!(&*fewer[0], [q(1)]);
        assert_eq!(&*fewer[1], [q(2)]);
        let more = vec![vec![q(1), q(2)], vec![q(3), q(4)], vec![q(5), q(6)]];
        let gathered = memo.by_column(&more, 2);
        assert_eq!(&*gathered[0], [q(1), q(3), q(5)]);
        assert_eq!(&*gathered[1], [q(2), q(4), q(6)]);
        let changed = vec![vec![q(1), q(2)], vec![q(3), q(7)], vec![q(5), q(6)]];
        assert_eq!(&*memo.by_column(&changed, 2)[1], [q(2), q(7), q(6)]);
        let again = memo.by_column(&changed, 2);
        assert!(again[0].same_as(&memo.by_column(&changed.clone(), 2)[0]));
        let unreduced = Rational::new_raw(6.into(), 2.into());
        let written = vec![vec![q(1), q(2)], vec![unreduced, q(7)], vec![q(5), q(6)]];
        let regathered = memo.by_column(&written, 2);
        assert!(!regathered[0].same_as(&again[0]));
        assert!(!columns[0].same_as(&regathered[0]));
    }
}
