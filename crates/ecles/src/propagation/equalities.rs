//! Coordinates of a component tied by rows `x_i = ±x_j` (coincidences, horizontal and vertical
//! alignments, shared coordinates), merged before the propagation analysis factors anything.
//!
//! In the analysis every right-hand side of `A`'s rows is zero (moves are homogeneous), so a
//! row `±x_i ± x_j = 0` says only that the two coordinates move together, with or without a
//! change of sign. Merging them into classes (a union–find that keeps each coordinate's sign
//! relative to its class) maps `{δ : A δ = 0}` one to one onto `{δ' : A' δ' = 0}`, where `A'`
//! holds the other rows over the classes: `δ_c = ±δ'_class(c)`. A row that closes a cycle of
//! merges with the same sign says nothing more and is left out; one that closes it with the
//! other sign forces the class to zero and is kept (as `2 δ'_class = 0`). The picked rows map
//! the same way, so `M' = [A'; E'_P]` has the same projections on the picked coordinates, the
//! same nullity and, expanded, the same affine sets of moves as `M = [A; E_P]` — what
//! SolveSpace's `SolveBySubstitution` does for its numeric solve, here exactly and for the
//! analysis. What names rows of `A` (the rows removing a lost direction, the rows in the way of
//! a blocked move) is still taken from `A` itself.

use super::SparseRows;
use api::{IntMatrix, Integer};
use num_traits::{One, Signed};

/// The classes of a component's coordinates and the rows left over them.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Equalities {
    /// Per column of `A`: its class, and whether the column is the class's value negated.
    class_of: Vec<(usize, bool)>,
    /// The rows of `A` that are not merges, over the classes (rows made zero left out).
    reduced: IntMatrix,
}

impl Equalities {
    /// The classes of `a`'s columns under its rows `±x_i ± x_j = 0`, or `None` when no row
    /// merges two columns (then there is nothing to gain).
    pub(super) fn merge(a: &impl SparseRows) -> Option<Equalities> {
        let n = a.cols();
        let mut classes = SignedUnionFind::new(n);
        let mut kept: Vec<usize> = Vec::new();
        let mut merged_any = false;
        for row in 0..a.rows() {
            match equality(a.entries(row)) {
                Some((i, j, negated)) => match classes.union(i, j, negated) {
                    Union::Merged => merged_any = true,
                    Union::Implied => {}
                    Union::Contradicts => kept.push(row),
                },
                None => kept.push(row),
            }
        }
        if !merged_any {
            return None;
        }
        // Classes numbered in the order of their first column.
        let mut number_of_root = vec![usize::MAX; n];
        let mut count = 0;
        let class_of: Vec<(usize, bool)> = (0..n)
            .map(|c| {
                let (root, negated) = classes.find(c);
                if number_of_root[root] == usize::MAX {
                    number_of_root[root] = count;
                    count += 1;
                }
                (number_of_root[root], negated)
            })
            .collect();
        let rows: Vec<Vec<(usize, Integer)>> = kept
            .into_iter()
            .map(|row| {
                a.entries(row)
                    .map(|(c, v)| {
                        let (class, negated) = class_of[c];
                        (class, if negated { -v } else { v.clone() })
                    })
                    .collect()
            })
            .collect();
        // Columns are in range by construction; merged terms that cancel leave empty rows,
        // which say nothing when every right-hand side is zero.
        let mut reduced = IntMatrix::from_sparse(count, rows).ok()?;
        if reduced.row_iter().any(<[_]>::is_empty) {
            let nonzero: Vec<usize> = (0..reduced.rows())
                .filter(|&i| !reduced.row(i).is_empty())
                .collect();
            reduced = reduced.select(&nonzero, &(0..count).collect::<Vec<_>>());
        }
        Some(Equalities { class_of, reduced })
    }

    /// `A'`: the rows that are not merges, over the classes.
    pub(super) fn reduced(&self) -> &IntMatrix {
        &self.reduced
    }

    /// The row of `E'_P` that picks column `c` of `A`.
    pub(super) fn picked_row(&self, c: usize) -> Vec<(usize, Integer)> {
        let (class, negated) = self.class_of[c];
        let one = Integer::one();
        vec![(class, if negated { -one } else { one })]
    }

    /// A vector over the classes as the vector over `A`'s columns it stands for.
    pub(super) fn expand<T>(&self, v: &[T]) -> Vec<T>
    where
        T: Clone,
        for<'a> &'a T: std::ops::Neg<Output = T>,
    {
        self.class_of
            .iter()
            .map(|&(class, negated)| {
                if negated {
                    -&v[class]
                } else {
                    v[class].clone()
                }
            })
            .collect()
    }
}

/// A row `±x_i ± x_j = 0` as `(i, j, negated)`: `x_i = −x_j` when `negated`, else `x_i = x_j`.
fn equality<'v>(
    mut row: impl Iterator<Item = (usize, &'v Integer)>,
) -> Option<(usize, usize, bool)> {
    let ((i, a), (j, b)) = (row.next()?, row.next()?);
    if row.next().is_some() || !a.magnitude().is_one() || !b.magnitude().is_one() {
        return None;
    }
    // a x_i + b x_j = 0: x_i = −(b / a) x_j, negated exactly when a and b agree.
    Some((i, j, a.is_positive() == b.is_positive()))
}

/// What one equality did to the classes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Union {
    /// Two classes became one.
    Merged,
    /// Both sides were in one class already, with the signs the row gives.
    Implied,
    /// Both sides were in one class already, with the other sign: the class is zero.
    Contradicts,
}

/// Union–find over coordinates with each one's sign relative to its parent (`x = −parent`
/// when set), union by size, paths compressed.
struct SignedUnionFind {
    parent: Vec<usize>,
    negated: Vec<bool>,
    size: Vec<usize>,
}

impl SignedUnionFind {
    fn new(n: usize) -> Self {
        SignedUnionFind {
            parent: (0..n).collect(),
            negated: vec![false; n],
            size: vec![1; n],
        }
    }

    /// The root of `x`'s class and whether `x` is the root's value negated.
    fn find(&mut self, x: usize) -> (usize, bool) {
        // First the root and the sign along the path, then every node on the path pointed at
        // the root with its own sign.
        let (mut root, mut sign) = (x, false);
        while self.parent[root] != root {
            sign ^= self.negated[root];
            root = self.parent[root];
        }
        let (mut node, mut node_sign) = (x, sign);
        while self.parent[node] != root && self.parent[node] != node {
            let (next, next_sign) = (self.parent[node], node_sign ^ self.negated[node]);
            self.parent[node] = root;
            self.negated[node] = node_sign;
            node = next;
            node_sign = next_sign;
        }
        (root, sign)
    }

    /// Records `x_i = ±x_j` (`−` when `negated`).
    fn union(&mut self, i: usize, j: usize, negated: bool) -> Union {
        let (ri, si) = self.find(i);
        let (rj, sj) = self.find(j);
        if ri == rj {
            return if si ^ sj == negated {
                Union::Implied
            } else {
                Union::Contradicts
            };
        }
        // x_i = ±x_ri and x_j = ±x_rj, so x_ri = (−1)^(si ⊕ negated ⊕ sj) x_rj.
        let relative = si ^ negated ^ sj;
        let (child, root) = if self.size[ri] < self.size[rj] {
            (ri, rj)
        } else {
            (rj, ri)
        };
        self.parent[child] = root;
        self.negated[child] = relative;
        self.size[root] += self.size[child];
        Union::Merged
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::Rational;

    fn matrix(rows: &[Vec<i64>]) -> IntMatrix {
        IntMatrix::from_dense(rows[0].len(), rows).expect("rows of one length")
    }

    fn q(n: i64) -> Rational {
        Rational::from_integer(n.into())
    }

    #[test]
    fn equal_and_opposite_coordinates_share_a_class_with_their_signs() {
        // x0 = x1, x2 = −x1, x3 free, and a row x0 + x3 − 2 x2 = 0 over them.
        let a = matrix(&[vec![1, -1, 0, 0], vec![0, 1, 1, 0], vec![1, 0, -2, 1]]);
        let e = Equalities::merge(&a).expect("two merges");
        let classes: Vec<usize> = e.class_of.iter().map(|c| c.0).collect();
        assert_eq!(classes[0], classes[1]);
        assert_eq!(classes[1], classes[2]);
        assert_ne!(classes[3], classes[0]);
        // x0 = x1 = −x2: expanding (t, s) over the classes gives (t, t, −t, s) up to the
        // class's own sign.
        let v = e.expand(&[q(5), q(7)]);
        assert_eq!(v[0], v[1]);
        assert_eq!(v[2], -v[1].clone());
        // The third row is x0 + x3 + 2 x0 = 3 x0 + x3 over the classes (signs aside): kept.
        assert_eq!(e.reduced().rows(), 1);
        assert_eq!(e.reduced().row(0).len(), 2);
        assert_eq!(
            e.reduced().row(0).iter().map(|(_, v)| v.abs()).max(),
            Some(Integer::from(3))
        );
    }

    #[test]
    fn cycles_are_left_out_when_implied_and_kept_when_they_force_zero() {
        // x0 = x1 = x2, then x2 = x0 again (implied): no row left.
        let implied = matrix(&[vec![1, -1, 0], vec![0, 1, -1], vec![-1, 0, 1]]);
        let e = Equalities::merge(&implied).expect("merges");
        assert_eq!(e.reduced().rows(), 0);
        // x0 = x1, then x0 = −x1: the class is zero, 2 x = 0 kept.
        let forced = matrix(&[vec![1, -1], vec![1, 1]]);
        let e = Equalities::merge(&forced).expect("a merge");
        assert_eq!(e.reduced().rows(), 1);
        assert_eq!(e.reduced().row(0), &[(0, Integer::from(2))][..]);
    }

    #[test]
    fn no_equality_no_classes() {
        let a = matrix(&[vec![2, -1, 0], vec![1, 1, 1]]);
        assert_eq!(Equalities::merge(&a), None);
    }

    #[test]
    fn a_picked_row_carries_its_columns_sign() {
        let a = matrix(&[vec![1, 1]]);
        let e = Equalities::merge(&a).expect("a merge");
        let (c0, c1) = (e.picked_row(0), e.picked_row(1));
        assert_eq!(c0[0].0, c1[0].0);
        assert_eq!(c0[0].1.clone() + c1[0].1.clone(), Integer::from(0));
    }
}
