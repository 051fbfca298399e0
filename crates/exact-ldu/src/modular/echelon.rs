//! The row rank profile of a sparse matrix modulo a prime: which rows, taken in order, are not
//! combinations of the rows before them (modulo `p`).
//!
//! Each row in turn is reduced against the pivot rows found so far, columns in increasing
//! order; a row that does not vanish becomes a pivot row with its leftmost remaining column as
//! pivot (scaled so that the pivot is 1). Every pivot row then has no entry left of its pivot,
//! so one pass over the columns of a row in increasing order reduces it completely, and a
//! reduction only touches columns at or after the one it removes.
//!
//! Modulo `p` the rank can only drop: the rows chosen are independent over the rationals too
//! (a nonzero minor modulo `p` is nonzero), and the profile is the rational one unless `p`
//! divides one of a few minors. [`crate::certified`] proves that every other row is a
//! combination of the chosen ones, so a bad prime is detected, never believed.

use super::Modulus;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Independent rows (increasing) and the pivot column of each, modulo a prime.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct RowProfile {
    /// The rows that are not combinations of the rows before them.
    pub(crate) independent: Vec<usize>,
    /// The pivot column of each independent row (distinct).
    pub(crate) pivot_columns: Vec<usize>,
}

/// The row rank profile of `rows` (residues modulo `modulus`, zeros dropped, columns below
/// `cols`).
pub(crate) fn row_profile(rows: &[Vec<(usize, u64)>], cols: usize, modulus: Modulus) -> RowProfile {
    let p = modulus.prime();
    // pivot_of[c]: the pivot row (index into `pivot_rows`) whose pivot is column c.
    let mut pivot_of: Vec<u32> = vec![u32::MAX; cols];
    let mut pivot_rows: Vec<Vec<(usize, u64)>> = Vec::new();
    let mut profile = RowProfile {
        independent: Vec::new(),
        pivot_columns: Vec::new(),
    };
    let mut acc = vec![0u64; cols];
    let mut touched_flag = vec![false; cols];
    let mut touched: Vec<usize> = Vec::new();
    let mut pending: BinaryHeap<Reverse<usize>> = BinaryHeap::new();
    for (i, row) in rows.iter().enumerate() {
        for &(c, v) in row {
            acc[c] = v;
            touched_flag[c] = true;
            touched.push(c);
            if pivot_of[c] != u32::MAX {
                pending.push(Reverse(c));
            }
        }
        while let Some(Reverse(c)) = pending.pop() {
            let factor = acc[c];
            if factor == 0 {
                continue;
            }
            // acc -= factor · pivot row (its first entry is (c, 1)).
            let negated = p - factor;
            for &(j, v) in &pivot_rows[pivot_of[c] as usize] {
                acc[j] = modulus.reduce(acc[j] + modulus.mul(negated, v));
                if !touched_flag[j] {
                    touched_flag[j] = true;
                    touched.push(j);
                    if pivot_of[j] != u32::MAX {
                        pending.push(Reverse(j));
                    }
                }
            }
        }
        touched.sort_unstable();
        let leading = touched.iter().copied().find(|&c| acc[c] != 0);
        if let Some(lead) = leading {
            let inverse = modulus.inverse(acc[lead]);
            let pivot_row: Vec<(usize, u64)> = touched
                .iter()
                .filter(|&&c| acc[c] != 0)
                .map(|&c| (c, modulus.mul(acc[c], inverse)))
                .collect();
            pivot_of[lead] = pivot_rows.len() as u32;
            pivot_rows.push(pivot_row);
            profile.independent.push(i);
            profile.pivot_columns.push(lead);
        }
        for &c in &touched {
            acc[c] = 0;
            touched_flag[c] = false;
        }
        touched.clear();
    }
    profile
}

#[cfg(test)]
mod tests {
    use super::*;

    fn residues(dense: &[Vec<i64>], m: &Modulus) -> Vec<Vec<(usize, u64)>> {
        dense
            .iter()
            .map(|row| {
                row.iter()
                    .enumerate()
                    .filter(|(_, v)| **v != 0)
                    .map(|(c, v)| (c, m.residue_i128(i128::from(*v))))
                    .collect()
            })
            .collect()
    }

    /// Rows that repeat or combine earlier rows are left out; the first of equal rows is kept.
    #[test]
    fn later_combinations_are_left_out() {
        let m = Modulus::new(2_147_483_629);
        let a = vec![
            vec![0, 0, 0, 0],
            vec![1, 2, 0, 3],
            vec![2, 4, 0, 6],
            vec![0, 1, 1, 0],
            vec![1, 3, 1, 3],
            vec![0, 0, 0, 5],
        ];
        let profile = row_profile(&residues(&a, &m), 4, m);
        assert_eq!(profile.independent, vec![1, 3, 5]);
        assert_eq!(profile.pivot_columns, vec![0, 1, 3]);
    }

    /// A prime that divides a minor lowers the rank modulo that prime: rows independent over
    /// the rationals can look dependent (which is why the profile is certified afterwards).
    #[test]
    fn a_prime_dividing_a_minor_lowers_the_rank() {
        let p = 2_147_483_629i64;
        let m = Modulus::new(p as u64);
        let a = vec![vec![1, 1], vec![1, 1 + p]];
        assert_eq!(row_profile(&residues(&a, &m), 2, m).independent, vec![0]);
        let other = Modulus::new(2_147_483_647);
        assert_eq!(
            row_profile(&residues(&a, &other), 2, other).independent,
            vec![0, 1]
        );
    }
}
