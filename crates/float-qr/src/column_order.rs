//! A fill-reducing order of the columns of a sparse `A` for its QR: approximate minimum degree
//! (the `amd` crate) on the pattern of `Aᵀ A`, whose Cholesky factor has the pattern of `R`.
//!
//! At a whole mesh (1.26 million columns) the pattern and AMD's workspace are the float
//! cross-check's peak of memory, so everything here is held as compactly as the answer allows:
//! the rows of `A` as one flat array of `u32` columns, their transpose likewise, only the strict
//! upper triangle of `Aᵀ A` (AMD orders `B + Bᵀ` whatever triangle it is given, and ignores the
//! diagonal), and its indices as `i32` whenever they and AMD's workspace fit one. AMD's
//! arithmetic on indices is exact in either type, so the order does not depend on that choice.

use api::BackendError;

/// The pattern of the rows of a sparse matrix: row `r`'s columns are
/// `columns[starts[r]..starts[r + 1]]`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RowPattern {
    starts: Vec<usize>,
    columns: Vec<u32>,
    width: usize,
}

impl RowPattern {
    /// An empty pattern over `width` columns, with room for `rows` rows.
    pub(crate) fn with_capacity(rows: usize, width: usize) -> Result<Self, BackendError> {
        u32::try_from(width).map_err(|_| BackendError::Numerical("too many columns".into()))?;
        let mut starts = Vec::with_capacity(rows + 1);
        starts.push(0);
        Ok(RowPattern {
            starts,
            columns: Vec::new(),
            width,
        })
    }

    /// The pattern of `rows` (column indices below `width`; the values are not read).
    pub(crate) fn of_rows<T>(rows: &[Vec<(usize, T)>], width: usize) -> Result<Self, BackendError> {
        let mut pattern = RowPattern::with_capacity(rows.len(), width)?;
        pattern.columns.reserve(rows.iter().map(Vec::len).sum());
        for row in rows {
            for (c, _) in row {
                pattern.push(*c)?;
            }
            pattern.end_row();
        }
        Ok(pattern)
    }

    /// Adds column `column` to the row being made.
    pub(crate) fn push(&mut self, column: usize) -> Result<(), BackendError> {
        match u32::try_from(column) {
            Ok(c) if column < self.width => {
                self.columns.push(c);
                Ok(())
            }
            _ => Err(BackendError::Numerical(format!(
                "column {column} outside the {} columns of the pattern",
                self.width
            ))),
        }
    }

    /// Ends the row being made.
    pub(crate) fn end_row(&mut self) {
        self.starts.push(self.columns.len());
    }

    /// The number of rows.
    fn rows(&self) -> usize {
        self.starts.len() - 1
    }

    /// Row `r`'s columns.
    fn row(&self, r: usize) -> &[u32] {
        &self.columns[self.starts[r]..self.starts[r + 1]]
    }

    /// The transpose: for each column, the rows that use it, increasing (a row that repeats a
    /// column is listed once per repeat), as starts and rows.
    fn transpose(&self) -> Option<(Vec<usize>, Vec<u32>)> {
        let mut starts = vec![0usize; self.width + 1];
        for &c in &self.columns {
            starts[c as usize + 1] += 1;
        }
        for c in 0..self.width {
            starts[c + 1] += starts[c];
        }
        let mut next = starts.clone();
        let mut rows = vec![0u32; self.columns.len()];
        for r in 0..self.rows() {
            let r32 = u32::try_from(r).ok()?;
            for &c in self.row(r) {
                rows[next[c as usize]] = r32;
                next[c as usize] += 1;
            }
        }
        Some((starts, rows))
    }
}

/// An order of the columns of `A` (given by its row pattern) that keeps `R` sparse; the
/// natural order if it cannot be computed (an order only changes speed and fill).
pub(crate) fn column_order(pattern: &RowPattern) -> Vec<usize> {
    let cols = pattern.width;
    let narrow = upper_normal_pattern::<i32>(pattern)
        .filter(|(_, indices)| fits_amd_workspace(indices.len(), cols))
        .and_then(|(starts, indices)| minimum_degree_order(cols, &starts, &indices));
    narrow
        .or_else(|| {
            let (starts, indices) = upper_normal_pattern::<isize>(pattern)?;
            minimum_degree_order(cols, &starts, &indices)
        })
        .unwrap_or_else(|| (0..cols).collect())
}

/// Whether AMD's workspace for a triangle of `entries` indices over `cols` columns (`1.2 ·` the
/// off-diagonal entries of `B + Bᵀ`, twice the triangle, plus a few arrays of the columns) can
/// be indexed by an `i32`.
fn fits_amd_workspace(entries: usize, cols: usize) -> bool {
    entries
        .checked_mul(3)
        .and_then(|w| w.checked_add(cols.checked_mul(2)?))
        .and_then(|w| w.checked_add(64))
        .is_some_and(|w| i32::try_from(w).is_ok())
}

/// The approximate minimum degree order of the pattern (`starts`, `indices`) over `cols`
/// columns; `None` if AMD refuses it.
fn minimum_degree_order<I>(cols: usize, starts: &[I], indices: &[I]) -> Option<Vec<usize>>
where
    I: num_traits::PrimInt + num_traits::NumAssignOps + std::fmt::Display + TryFrom<usize>,
{
    let size = I::try_from(cols).ok()?;
    match amd::order::<I>(size, starts, indices, &amd::Control::default()) {
        Ok((order, _, _)) if order.len() == cols => {
            order.into_iter().map(|k| k.to_usize()).collect()
        }
        _ => None,
    }
}

/// The strict upper triangle of the pattern of `Aᵀ A`: for each column, the later columns it
/// shares a row with, once and increasing, as column starts and indices; `None` if an index
/// does not fit an `I`. Gathered column by column through the transpose with a marker per
/// column, so no pair is held twice.
fn upper_normal_pattern<I>(pattern: &RowPattern) -> Option<(Vec<I>, Vec<I>)>
where
    I: TryFrom<usize> + Ord + Copy,
{
    let (row_starts, rows_of) = pattern.transpose()?;
    let index = |k: usize| I::try_from(k).ok();
    let mut mark = vec![u32::MAX; pattern.width];
    let mut starts = Vec::with_capacity(pattern.width + 1);
    let mut indices = Vec::new();
    starts.push(index(0)?);
    for c in 0..pattern.width {
        let c32 = u32::try_from(c).ok()?;
        let from = indices.len();
        for &r in &rows_of[row_starts[c]..row_starts[c + 1]] {
            for &d in pattern.row(r as usize) {
                if d > c32 && mark[d as usize] != c32 {
                    mark[d as usize] = c32;
                    indices.push(index(d as usize)?);
                }
            }
        }
        indices[from..].sort_unstable();
        starts.push(index(indices.len())?);
    }
    drop((row_starts, rows_of, mark));
    // The doubling slack of the growth would otherwise sit beside AMD's workspace.
    indices.shrink_to_fit();
    Some((starts, indices))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rows of a `n × n` grid's five-point stencil, forward half (so the order is not
    /// trivial).
    fn grid_rows(n: usize) -> Vec<Vec<(usize, f64)>> {
        (0..n * n)
            .map(|k| {
                let (x, y) = (k % n, k / n);
                let mut row = vec![(k, 4.0)];
                if x + 1 < n {
                    row.push((k + 1, -1.0));
                }
                if y + 1 < n {
                    row.push((k + n, -1.0));
                }
                row
            })
            .collect()
    }

    /// The upper triangle of the pattern of `Aᵀ A`: each column with the later columns it
    /// shares a row with, once, sorted (a repeated entry counted once); the order a
    /// permutation.
    #[test]
    fn the_normal_pattern_has_each_pair_once() {
        let rows: Vec<Vec<(usize, f64)>> = vec![
            vec![(3, 1.0), (0, 2.0)],
            vec![(0, 1.0), (1, -1.0), (3, 4.0)],
            vec![(1, 2.0), (1, 2.0)],
        ];
        let pattern = RowPattern::of_rows(&rows, 5).expect("fits");
        let (starts, indices) = upper_normal_pattern::<i32>(&pattern).expect("small");
        let columns: Vec<&[i32]> = starts
            .windows(2)
            .map(|w| &indices[w[0] as usize..w[1] as usize])
            .collect();
        assert_eq!(columns, vec![&[1, 3][..], &[3], &[], &[], &[]]);
        let mut order = column_order(&pattern);
        order.sort_unstable();
        assert_eq!(order, vec![0, 1, 2, 3, 4]);
    }

    /// The narrow and the wide index types give AMD the same pattern and the same order.
    #[test]
    fn the_order_does_not_depend_on_the_index_type() {
        let n = 12;
        let pattern = RowPattern::of_rows(&grid_rows(n), n * n).expect("fits");
        let (starts, indices) = upper_normal_pattern::<i32>(&pattern).expect("small");
        let narrow = minimum_degree_order(n * n, &starts, &indices).expect("ordered");
        let (starts, indices) = upper_normal_pattern::<isize>(&pattern).expect("small");
        let wide = minimum_degree_order(n * n, &starts, &indices).expect("ordered");
        assert_eq!(narrow, wide);
        assert_ne!(narrow, (0..n * n).collect::<Vec<_>>());
        assert_eq!(column_order(&pattern), narrow);
    }

    /// Giving AMD one triangle orders the same graph as giving it the whole symmetric
    /// pattern: the fill of the Cholesky factor (the number of entries of `R`) is the same
    /// for both orders on the grid.
    #[test]
    fn one_triangle_orders_as_well_as_the_whole_pattern() {
        let n = 12;
        let rows = grid_rows(n);
        let pattern = RowPattern::of_rows(&rows, n * n).expect("fits");
        let (starts, indices) = upper_normal_pattern::<i32>(&pattern).expect("small");
        let mut full: Vec<Vec<i32>> = vec![Vec::new(); n * n];
        for c in 0..n * n {
            full[c].push(c as i32);
            for &d in &indices[starts[c] as usize..starts[c + 1] as usize] {
                full[c].push(d);
                full[d as usize].push(c as i32);
            }
        }
        let mut full_starts = vec![0i32];
        let mut full_indices = Vec::new();
        for column in &mut full {
            column.sort_unstable();
            full_indices.extend_from_slice(column);
            full_starts.push(full_indices.len() as i32);
        }
        let whole = minimum_degree_order(n * n, &full_starts, &full_indices).expect("ordered");
        let triangle = column_order(&pattern);
        assert_eq!(whole, triangle);
        assert_eq!(fill(&rows, &whole), fill(&rows, &triangle));
    }

    /// The number of entries of the Cholesky factor of `Aᵀ A` under `order`, by symbolic
    /// elimination of its graph.
    fn fill(rows: &[Vec<(usize, f64)>], order: &[usize]) -> usize {
        let n = order.len();
        let mut position = vec![0; n];
        for (k, &c) in order.iter().enumerate() {
            position[c] = k;
        }
        let mut adjacent: Vec<std::collections::BTreeSet<usize>> = vec![Default::default(); n];
        for row in rows {
            for (a, _) in row {
                for (b, _) in row {
                    if a != b {
                        adjacent[position[*a]].insert(position[*b]);
                    }
                }
            }
        }
        let mut entries = 0;
        for k in 0..n {
            let later: Vec<usize> = adjacent[k].iter().copied().filter(|&j| j > k).collect();
            entries += later.len() + 1;
            for &a in &later {
                for &b in &later {
                    if a != b {
                        adjacent[a].insert(b);
                    }
                }
            }
        }
        entries
    }

    /// A column outside the pattern's width is refused, not stored.
    #[test]
    fn a_column_outside_the_width_is_refused() {
        let mut pattern = RowPattern::with_capacity(1, 3).expect("fits");
        assert!(pattern.push(2).is_ok());
        assert!(pattern.push(3).is_err());
    }

    /// AMD's workspace decides the index type: it must be addressable by an `i32`.
    #[test]
    fn the_narrow_type_is_used_only_while_amds_workspace_fits_it() {
        assert!(fits_amd_workspace(1_000_000, 100_000));
        assert!(!fits_amd_workspace(800_000_000, 1));
        assert!(!fits_amd_workspace(usize::MAX / 2, 1));
    }
}
