//! The symbolic part of a sparse `P A Pᵀ = L D Lᵀ`, shared by the numeric factorings over
//! `Z/p` ([`crate::modular`], the inverse of Dixon's lifting) and over `f64` (the approximate
//! optimum a snapped commit rounds, [`crate::snap`]): a fill-reducing order, the elimination
//! tree with the column counts of `L`, and the pattern of each row of `L` (T. A. Davis,
//! "Algorithm 849: a concise sparse Cholesky factorization package", ACM TOMS 31, 2005).

/// No parent in the elimination tree.
pub(crate) const ROOT: usize = usize::MAX;

/// Pivot `k` of the factoring is row and column `order[k]` of `A`: a fill-reducing order of
/// the symmetric pattern given by `rows` (each row's column indices, increasing, the diagonal
/// included; the values are not read). The identity when the ordering cannot be computed (an
/// order only changes speed).
pub(crate) fn fill_reducing_order<T>(rows: &[Vec<(usize, T)>]) -> Vec<usize> {
    let n = rows.len();
    let identity = || (0..n).collect();
    let Ok(size) = isize::try_from(n) else {
        return identity();
    };
    let mut starts: Vec<isize> = Vec::with_capacity(n + 1);
    let mut indices: Vec<isize> = Vec::new();
    starts.push(0);
    for row in rows {
        indices.extend(row.iter().map(|(j, _)| *j as isize));
        starts.push(indices.len() as isize);
    }
    match amd::order::<isize>(size, &starts, &indices, &amd::Control::default()) {
        Ok((order, _, _)) if order.len() == n => order.into_iter().map(|k| k as usize).collect(),
        _ => identity(),
    }
}

/// The elimination tree of `P A Pᵀ` (`parent[i]`, [`ROOT`] for a root) and the number of
/// entries of each column of `L` below the diagonal (Davis' `ldl_symbolic`).
pub(crate) fn elimination_tree<T>(
    rows: &[Vec<(usize, T)>],
    order: &[usize],
    position: &[usize],
) -> (Vec<usize>, Vec<usize>) {
    let n = rows.len();
    let mut parent = vec![ROOT; n];
    let mut counts = vec![0usize; n];
    let mut flag = vec![ROOT; n];
    for k in 0..n {
        flag[k] = k;
        for &(j, _) in &rows[order[k]] {
            let mut i = position[j];
            if i >= k {
                continue;
            }
            while flag[i] != k {
                if parent[i] == ROOT {
                    parent[i] = k;
                }
                counts[i] += 1;
                flag[i] = k;
                i = parent[i];
            }
        }
    }
    (parent, counts)
}

/// The pattern of each row of `L`, one row at a time, in the up-looking order (row `k` needs
/// the rows above it): the nodes reached from `A`'s entries left of the diagonal by walking up
/// the elimination tree, stacked so that descendants come first.
pub(crate) struct RowPatterns {
    flag: Vec<usize>,
    pattern: Vec<usize>,
}

impl RowPatterns {
    /// Scratch for an `n × n` matrix.
    pub(crate) fn new(n: usize) -> Self {
        RowPatterns {
            flag: vec![ROOT; n],
            pattern: vec![0; n],
        }
    }

    /// The columns `i < k` of row `k` of `L` (`row` is row `order[k]` of `A`), in an order in
    /// which a sparse triangular solve may take them.
    pub(crate) fn row<T>(
        &mut self,
        row: &[(usize, T)],
        k: usize,
        position: &[usize],
        parent: &[usize],
    ) -> &[usize] {
        let n = self.pattern.len();
        let mut top = n;
        self.flag[k] = k;
        for &(j, _) in row {
            let mut i = position[j];
            if i > k {
                continue;
            }
            let mut len = 0;
            while self.flag[i] != k {
                self.pattern[len] = i;
                len += 1;
                self.flag[i] = k;
                i = parent[i];
            }
            while len > 0 {
                top -= 1;
                len -= 1;
                self.pattern[top] = self.pattern[len];
            }
        }
        &self.pattern[top..n]
    }
}
