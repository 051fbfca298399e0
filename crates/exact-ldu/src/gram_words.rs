//! The Gram matrix `G = A V Aᵀ` of a few sparse integer rows (`V` diagonal), in machine
//! words: the small normal matrices of least squares and the full-row-rank proof of a small
//! matrix. Both are formed on every small edit, so this avoids what a dense `m × m` array of
//! `i128` (zeroed, 4 KB for 16 rows) and a vector per column of `A` cost there.
//!
//! Row `k` of `G` is `Σ_s A_ks V_s A_{:,s}`: the entries of each of its unknowns' columns,
//! scaled, summed into one scratch row of `m` words, read off in column order and reset. The
//! columns of `A` are one flat transposed copy (counted, then placed). Every product and sum is
//! checked in an `i128`.

use crate::factorization::SparseRow;
use crate::ring::Ring;
use api::words::checked_mul_i128;

/// `G = A V Aᵀ` for the sparse rows `a` over `cols` unknowns, with `V_s = scale(s)`, as sparse
/// rows (nonzero entries only, in column order) converted by `convert`; `None` when an entry of
/// `A` or `V` leaves an `i64`, a row names an unknown beyond `cols`, a product or sum leaves an `i128`, or `convert` refuses a value.
pub(crate) fn gram_rows<R, T>(
    a: &[SparseRow<R>],
    cols: usize,
    scale: impl Fn(usize) -> Option<i64>,
    convert: impl Fn(i128) -> Option<T>,
) -> Option<Vec<Vec<(usize, T)>>>
where
    R: Ring,
{
    let m = a.len();
    // The columns of `A`: `starts[s]..starts[s + 1]` of `entries`, by increasing row.
    let mut starts = vec![0usize; cols + 1];
    for row in a {
        for (s, _) in row {
            *starts.get_mut(*s + 1)? += 1;
        }
    }
    for s in 0..cols {
        starts[s + 1] += starts[s];
    }
    let mut filled = starts.clone();
    let mut entries = vec![(0usize, 0i128); starts[cols]];
    for (k, row) in a.iter().enumerate() {
        for (s, v) in row {
            entries[filled[*s]] = (k, i128::from(v.to_i64()?));
            filled[*s] += 1;
        }
    }
    // The scratch row, and the entries of it this row touched (read off in column order and
    // reset, not the whole row scanned: a row of `G` has a few entries of `m`).
    let mut scratch = vec![0i128; m];
    let mut marked = vec![false; m];
    let mut touched: Vec<usize> = Vec::with_capacity(m);
    let mut gram = Vec::with_capacity(m);
    for row in a {
        for (s, v) in row {
            // Two `i64`s: their product fits.
            let scaled = i128::from(v.to_i64()?) * i128::from(scale(*s)?);
            for &(l, other) in &entries[starts[*s]..starts[*s + 1]] {
                if !marked[l] {
                    marked[l] = true;
                    touched.push(l);
                }
                scratch[l] = scratch[l].checked_add(checked_mul_i128(scaled, other)?)?;
            }
        }
        touched.sort_unstable();
        let mut out = Vec::with_capacity(touched.len());
        for &l in &touched {
            // Terms that cancel leave a zero: it is not an entry.
            let x = std::mem::take(&mut scratch[l]);
            marked[l] = false;
            if x != 0 {
                out.push((l, convert(x)?));
            }
        }
        touched.clear();
        gram.push(out);
    }
    Some(gram)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ring::Int;

    fn rows(dense: &[&[i64]]) -> Vec<SparseRow<Int>> {
        dense
            .iter()
            .map(|row| {
                row.iter()
                    .enumerate()
                    .filter(|(_, v)| **v != 0)
                    .map(|(s, v)| (s, Int::from_i64(*v)))
                    .collect()
            })
            .collect()
    }

    /// `A V Aᵀ` by its definition, densely.
    fn dense_gram(dense: &[&[i64]], v: &[i64]) -> Vec<Vec<i128>> {
        dense
            .iter()
            .map(|k| {
                dense
                    .iter()
                    .map(|l| {
                        (0..v.len())
                            .map(|s| i128::from(k[s]) * i128::from(v[s]) * i128::from(l[s]))
                            .sum()
                    })
                    .collect()
            })
            .collect()
    }

    /// The nonzero entries of each dense row, in column order.
    fn nonzero_entries(dense: &[Vec<i128>]) -> Vec<Vec<(usize, i128)>> {
        dense
            .iter()
            .map(|row| {
                row.iter()
                    .enumerate()
                    .filter(|(_, x)| **x != 0)
                    .map(|(l, x)| (l, *x))
                    .collect()
            })
            .collect()
    }

    #[test]
    fn gram_rows_are_the_sparse_rows_of_a_v_a_transposed() {
        let dense: &[&[i64]] = &[&[1, -2, 0, 0, 3], &[0, 0, 4, 0, 0], &[2, 0, 0, -1, 1]];
        let v = [3, 1, 5, 2, 7];
        let gram = gram_rows(&rows(dense), 5, |s| Some(v[s]), Some).expect("small values");
        assert_eq!(gram, nonzero_entries(&dense_gram(dense, &v)));
        // Rows 0 and 1 share no unknown: their entry is absent, not zero.
        assert!(gram[0].iter().all(|(l, _)| *l != 1));
    }

    /// Entries whose terms cancel are absent, and no row leaves anything behind for the
    /// next: rows overlapping in several unknowns, in and out of order, against the dense
    /// product.
    #[test]
    fn cancelled_entries_are_absent_and_rows_start_clean() {
        let dense: &[&[i64]] = &[
            &[1, 1, 0, 0],
            &[1, -1, 0, 2],
            &[0, 0, 3, 1],
            &[2, 0, -1, 0],
            &[1, -1, 0, 2],
        ];
        let v = [1, 1, 2, 1];
        let gram = gram_rows(&rows(dense), 4, |s| Some(v[s]), Some).expect("small values");
        // Row 0 · row 1 = 1 − 1 = 0: no entry, either way.
        assert!(gram[0].iter().all(|(l, _)| *l != 1));
        assert!(gram[1].iter().all(|(l, _)| *l != 0));
        assert_eq!(gram, nonzero_entries(&dense_gram(dense, &v)));
    }

    #[test]
    fn values_beyond_words_are_refused() {
        // A product of `i64::MAX²` (about 2^126) fits an `i128`, so does twice it, not thrice.
        let big: &[&[i64]] = &[&[i64::MAX], &[i64::MAX]];
        assert!(gram_rows(&rows(big), 1, |_| Some(1), Some).is_some());
        assert!(gram_rows(&rows(big), 1, |_| Some(2), Some).is_some());
        assert!(gram_rows(&rows(big), 1, |_| Some(3), Some).is_none());
        // Nor does a sum of three such products.
        let wide: &[&[i64]] = &[&[i64::MAX, i64::MAX, i64::MAX]];
        assert!(gram_rows(&rows(wide), 3, |_| Some(1), Some).is_none());
        let two: &[&[i64]] = &[&[i64::MAX, i64::MAX]];
        assert!(gram_rows(&rows(two), 2, |_| Some(1), Some).is_some());
        // A conversion or a scale that refuses a value refuses the matrix.
        let small: &[&[i64]] = &[&[1 << 32, 1 << 32]];
        assert!(gram_rows(&rows(small), 2, |_| Some(1), |x| i64::try_from(x).ok()).is_none());
        assert!(gram_rows(&rows(small), 2, |_| Some(1), Some).is_some());
        assert!(gram_rows(&rows(small), 2, |_| None, Some).is_none());
    }
}
