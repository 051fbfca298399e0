//! A basis of the columns of `Â` found by peeling, and the exact solve for its columns once the
//! others are fixed.
//!
//! A snapped commit fixes the *free* columns of `Â x = b̂` on a grid and solves for the *basic*
//! ones, `Â_P x_P = b̂ − Â_F x_F`. Which columns are basic decides the size of the answer: a
//! basic value divides by the pivots on its chain of substitutions, so short chains give small
//! denominators, and chains that only depend on the mesh (not on earlier edits) keep the values
//! bounded over a long session. Peeling gives such chains:
//!
//! 1. while some row has exactly one column left that is neither basic nor free, that column
//!    becomes the row's basic column (its value follows from the row by one division);
//! 2. otherwise the column that occurs in most unfinished rows becomes free (it unblocks the
//!    most rows), and peeling goes on;
//! 3. a row left with no such column ("closing" row) takes one by an augmenting path through
//!    the rows already peeled (a breadth-first search, so no recursion): the basis grows by one
//!    column that was free.
//!
//! `Â_P` is then square and structurally nonsingular; its Dulmage–Mendelsohn fine blocks
//! ([`structure::decompose`], unique for a square matrix) are solved in order, single rows by a
//! division, larger blocks by the fraction-free LDU. A block that is singular for the actual
//! coefficients makes the basis unusable (the caller falls back to the optimum).

use super::UnreducedSum;
use crate::factorization::SparseRow;
use crate::ring::Ring;
use crate::{ExactFactorization, Simplification};
use api::{Factorization, IntMatrix, Integer, Rational};
use std::collections::{BinaryHeap, VecDeque};

/// Not assigned.
const NONE: usize = usize::MAX;

/// One block of the solve: rows of `Â` and the basic columns they determine.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Block {
    /// Row `row` gives column `col` by one division.
    Single { row: usize, col: usize },
    /// Rows and columns solved together (`factor` is `Â` on them, nonsingular).
    Coupled {
        rows: Vec<usize>,
        cols: Vec<usize>,
        factor: Box<ExactFactorization>,
    },
}

/// The peeled basis of `Â`: which columns are free, and the blocks that give the others.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct PeeledBasis {
    /// `free[c]`: column `c` is fixed on the grid.
    free: Vec<bool>,
    /// Blocks in solve order.
    blocks: Vec<Block>,
}

impl PeeledBasis {
    /// The basis of `a_hat` (independent rows, `cols` columns); `None` when a block of `Â_P`
    /// is singular for the actual coefficients.
    pub(crate) fn new<R: Ring>(a_hat: &[SparseRow<R>], cols: usize) -> Option<Self> {
        let pivot = peel(a_hat, cols)?;
        let mut free = vec![true; cols];
        for &c in &pivot {
            free[c] = false;
        }
        // Â_P with its columns renumbered 0..r in the order of the rows they pivot.
        let mut local = vec![NONE; cols];
        for (k, &c) in pivot.iter().enumerate() {
            local[c] = k;
        }
        let pattern: Vec<Vec<usize>> = a_hat
            .iter()
            .map(|row| {
                let mut p: Vec<usize> = row
                    .iter()
                    .filter(|(c, _)| local[*c] != NONE)
                    .map(|(c, _)| local[*c])
                    .collect();
                p.sort_unstable();
                p
            })
            .collect();
        let graph = structure::Bipartite::from_pattern(pivot.len(), &pattern).ok()?;
        let dm = structure::decompose(&graph);
        if !dm.is_well_constrained() {
            return None;
        }
        let blocks = dm
            .blocks
            .iter()
            .map(|b| {
                let cols: Vec<usize> = b.cols.iter().map(|&k| pivot[k]).collect();
                if let ([row], [col]) = (&b.rows[..], &cols[..]) {
                    return Some(Block::Single {
                        row: *row,
                        col: *col,
                    });
                }
                let rows: Vec<Vec<(usize, Integer)>> = b
                    .rows
                    .iter()
                    .map(|&i| {
                        cols.iter()
                            .enumerate()
                            .filter_map(|(j, &c)| {
                                a_hat[i]
                                    .iter()
                                    .find(|(cc, _)| *cc == c)
                                    .map(|(_, v)| (j, v.to_bigint()))
                            })
                            .collect()
                    })
                    .collect();
                let matrix = IntMatrix::from_sparse(cols.len(), rows).ok()?;
                let factor = ExactFactorization::new(&matrix, Simplification::Gcd);
                (factor.rank() == cols.len()).then(|| Block::Coupled {
                    rows: b.rows.clone(),
                    cols,
                    factor: Box::new(factor),
                })
            })
            .collect::<Option<Vec<_>>>()?;
        Some(PeeledBasis { free, blocks })
    }

    /// Whether column `c` is free (fixed on the grid by the caller).
    pub(crate) fn is_free(&self, c: usize) -> bool {
        self.free[c]
    }

    /// Completes `x` (free columns set, basic ones ignored) so that `Â x = b̂` holds exactly.
    pub(crate) fn solve<R: Ring>(
        &self,
        a_hat: &[SparseRow<R>],
        b_hat: &[Rational],
        x: &mut [Rational],
    ) {
        // The rest of row i once every column but those of its block is known, summed over an
        // unreduced common denominator (one GCD per value, at the division).
        let remainder = |i: usize, skip: &dyn Fn(usize) -> bool, x: &[Rational]| {
            let mut s = UnreducedSum::from(&b_hat[i]);
            for (c, v) in &a_hat[i] {
                if !skip(*c) {
                    s.add_scaled(&x[*c], &(-v.to_bigint()));
                }
            }
            s
        };
        for block in &self.blocks {
            match block {
                Block::Single { row, col } => {
                    let s = remainder(*row, &|c| c == *col, x);
                    let pivot = a_hat[*row]
                        .iter()
                        .find(|(c, _)| c == col)
                        .map(|(_, v)| v.to_bigint())
                        .expect("a basic column is in its row");
                    x[*col] = s.divided_by(&pivot);
                }
                Block::Coupled { rows, cols, factor } => {
                    let rhs: Vec<Rational> = rows
                        .iter()
                        .map(|&i| remainder(i, &|c| cols.contains(&c), x).reduced())
                        .collect();
                    let solution = factor
                        .solve(&rhs)
                        .expect("a nonsingular block solves every right-hand side");
                    for (&c, v) in cols.iter().zip(solution) {
                        x[c] = v;
                    }
                }
            }
        }
    }
}

/// The basic column of each row of `a_hat` (distinct), by peeling then augmenting paths for
/// the closing rows; `None` when no complete assignment exists (rows not independent).
fn peel<R: Ring>(a_hat: &[SparseRow<R>], cols: usize) -> Option<Vec<usize>> {
    let r = a_hat.len();
    let mut rows_of: Vec<Vec<usize>> = vec![Vec::new(); cols];
    for (k, row) in a_hat.iter().enumerate() {
        for (c, _) in row {
            rows_of[*c].push(k);
        }
    }
    // Columns not yet basic or free in each row; rows waiting with one such column.
    let mut open: Vec<usize> = a_hat.iter().map(Vec::len).collect();
    let mut done = vec![false; r];
    let mut assigned = vec![false; cols];
    let mut pivot = vec![NONE; r];
    let mut ready: Vec<usize> = (0..r).filter(|&k| open[k] == 1).collect();
    let mut closing = Vec::new();
    // Candidates to free, by the number of unfinished rows they occur in (lazily updated).
    let mut heap: BinaryHeap<(usize, std::cmp::Reverse<usize>)> = (0..cols)
        .map(|c| (rows_of[c].len(), std::cmp::Reverse(c)))
        .collect();
    let mut unfinished = r;
    let take = |c: usize,
                assigned: &mut Vec<bool>,
                open: &mut Vec<usize>,
                ready: &mut Vec<usize>,
                done: &[bool]| {
        assigned[c] = true;
        for &k in &rows_of[c] {
            open[k] -= 1;
            if !done[k] && open[k] == 1 {
                ready.push(k);
            }
        }
    };
    while unfinished > 0 {
        if let Some(k) = ready.pop() {
            if done[k] || open[k] != 1 {
                continue;
            }
            let (c, _) = a_hat[k].iter().find(|(c, _)| !assigned[*c])?;
            let c = *c;
            done[k] = true;
            unfinished -= 1;
            pivot[k] = c;
            take(c, &mut assigned, &mut open, &mut ready, &done);
            continue;
        }
        for k in 0..r {
            if !done[k] && open[k] == 0 {
                done[k] = true;
                unfinished -= 1;
                closing.push(k);
            }
        }
        if unfinished == 0 {
            break;
        }
        // Free the column in most unfinished rows.
        loop {
            let (score, std::cmp::Reverse(c)) = heap.pop()?;
            if assigned[c] {
                continue;
            }
            let now = rows_of[c].iter().filter(|&&k| !done[k]).count();
            if now < score {
                heap.push((now, std::cmp::Reverse(c)));
                continue;
            }
            take(c, &mut assigned, &mut open, &mut ready, &done);
            break;
        }
    }
    let mut owner = vec![NONE; cols];
    for (k, &c) in pivot.iter().enumerate() {
        if c != NONE {
            owner[c] = k;
        }
    }
    for k in closing {
        augment(a_hat, k, &mut pivot, &mut owner)?;
    }
    Some(pivot)
}

/// An augmenting path from the unmatched row `start`: breadth-first over rows, through columns
/// already basic to the rows that own them, to a column that is not basic; the matching is
/// flipped along it. `None` when there is none.
fn augment<R: Ring>(
    a_hat: &[SparseRow<R>],
    start: usize,
    pivot: &mut [usize],
    owner: &mut [usize],
) -> Option<()> {
    // came_from[c]: the row from which column c was reached.
    let mut came_from: std::collections::HashMap<usize, usize> = Default::default();
    let mut queue = VecDeque::from([start]);
    let mut end = None;
    'search: while let Some(k) = queue.pop_front() {
        for (c, _) in &a_hat[k] {
            if came_from.contains_key(c) {
                continue;
            }
            came_from.insert(*c, k);
            if owner[*c] == NONE {
                end = Some(*c);
                break 'search;
            }
            queue.push_back(owner[*c]);
        }
    }
    let mut c = end?;
    loop {
        let k = came_from[&c];
        let previous = pivot[k];
        pivot[k] = c;
        owner[c] = k;
        if k == start {
            return Some(());
        }
        c = previous;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ring::Int;
    use num_traits::Zero;

    fn rows(data: &[&[(usize, i64)]]) -> Vec<SparseRow<Int>> {
        data.iter()
            .map(|r| r.iter().map(|(c, v)| (*c, Int::from_i64(*v))).collect())
            .collect()
    }

    fn q(n: i64) -> Rational {
        Rational::from_integer(n.into())
    }

    /// A chain `x_i − 2 x_{i+1} = 1` peels into single rows; the solve satisfies every row
    /// exactly for any values of the free columns.
    #[test]
    fn a_chain_peels_into_single_divisions() {
        let a = rows(&[&[(0, 1), (1, -2)], &[(1, 1), (2, -2)], &[(2, 1), (3, -2)]]);
        let basis = PeeledBasis::new(&a, 4).expect("independent rows");
        assert_eq!((0..4).filter(|&c| basis.is_free(c)).count(), 1);
        assert!(basis
            .blocks
            .iter()
            .all(|b| matches!(b, Block::Single { .. })));
        let b_hat = vec![q(1), q(1), q(1)];
        let mut x: Vec<Rational> = (0..4).map(|i| Rational::new(i.into(), 3.into())).collect();
        basis.solve(&a, &b_hat, &mut x);
        for (row, b) in a.iter().zip(&b_hat) {
            let s: Rational = row
                .iter()
                .map(|(c, v)| &x[*c] * Rational::from_integer(v.to_bigint()))
                .sum();
            assert_eq!(&s, b);
        }
    }

    /// A cycle of rows (every column in two rows) has a closing row: the augmenting path gives
    /// it a column, and the coupled block is solved exactly.
    #[test]
    fn a_closing_row_gets_a_column_by_an_augmenting_path() {
        // x0 + x1 = 3, x1 + x2 = 5, x2 + 2 x0 = 7: nonsingular 3×3 with one cycle.
        let a = rows(&[&[(0, 1), (1, 1)], &[(1, 1), (2, 1)], &[(0, 2), (2, 1)]]);
        let basis = PeeledBasis::new(&a, 3).expect("nonsingular");
        assert!((0..3).all(|c| !basis.is_free(c)));
        let mut x = vec![Rational::zero(); 3];
        basis.solve(&a, &[q(3), q(5), q(7)], &mut x);
        assert_eq!(
            x,
            vec![
                Rational::new(5.into(), 3.into()),
                Rational::new(4.into(), 3.into()),
                Rational::new(11.into(), 3.into())
            ]
        );
    }

    /// Rows that are dependent have no complete assignment or a singular block: no basis.
    #[test]
    fn dependent_rows_have_no_basis() {
        let a = rows(&[&[(0, 1), (1, 1)], &[(0, 2), (1, 2)]]);
        assert!(PeeledBasis::new(&a, 2).is_none());
    }
}
