//! Block-wise factoring: a matrix whose bipartite graph (rows and columns joined by nonzero
//! entries) falls apart into connected components is factored one component at a time, and
//! components that are the same matrix up to renumbering (the x and y coordinates of a planar
//! spline) share one factorization.
//!
//! Because the pivot rule breaks ties on original indices and the GCD method starts from
//! primitive rows (see [`crate::Ldu`]), the pivots chosen inside a component do not depend on the
//! other components: rank, independent rows, redundancy combinations, basic solutions, least
//! squares and the null space are exactly those of one factoring of the whole matrix (property
//! tested); only the order in which rows and vectors are listed differs.

use crate::factorization::ExactFactorization;
use crate::ldu::Simplification;
use crate::lsq::ExactLeastSquares;
use crate::ring::{Int, Ring};
use api::backend::{check_len, validate_family, validate_weights};
use api::{
    BackendError, Factorization, Inconsistency, IntMatrix, PreparedLeastSquares, Rational,
    Redundancy, RhsFamily, SolveError, StrongFailure,
};
use num_traits::Zero;
use std::collections::HashMap;
use std::sync::Arc;

/// A component's matrix in its own numbering: equal keys mean identical components.
type ComponentKey = Vec<Vec<(usize, api::Integer)>>;

/// One connected component: its rows and columns (sorted) and the factorization of its
/// submatrix (shared between identical components).
#[derive(Debug, Clone)]
struct Component<R: Ring> {
    rows: Vec<usize>,
    cols: Vec<usize>,
    factor: Arc<ExactFactorization<R>>,
}

/// An exact factorization made of the factorizations of the connected components.
#[derive(Debug, Clone)]
pub struct BlockFactorization<R: Ring = Int> {
    m: usize,
    n: usize,
    components: Vec<Component<R>>,
    /// Number of distinct component matrices actually factored.
    distinct: usize,
}

/// Union–find over rows `0..m` and columns `m..m+n`.
fn find(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

/// The connected components of the bipartite graph of `matrix`, as (rows, cols), ordered by
/// their smallest row (components without rows last, by column).
pub fn components(matrix: &IntMatrix) -> Vec<(Vec<usize>, Vec<usize>)> {
    let (m, n) = (matrix.rows(), matrix.cols());
    let mut parent: Vec<usize> = (0..m + n).collect();
    for (i, row) in matrix.row_iter().enumerate() {
        for (c, _) in row {
            let (a, b) = (find(&mut parent, i), find(&mut parent, m + c));
            if a != b {
                parent[a.max(b)] = a.min(b);
            }
        }
    }
    // The component number of each root, by the root's index (roots are the smallest member,
    // so components come out ordered by their smallest row).
    let mut index: Vec<usize> = vec![usize::MAX; m + n];
    let mut out: Vec<(Vec<usize>, Vec<usize>)> = Vec::new();
    for x in 0..m + n {
        let root = find(&mut parent, x);
        if index[root] == usize::MAX {
            index[root] = out.len();
            out.push((Vec::new(), Vec::new()));
        }
        let k = index[root];
        if x < m {
            out[k].0.push(x);
        } else {
            out[k].1.push(x - m);
        }
    }
    out
}

/// [`components`] with each component's submatrix (its rows and columns in increasing order),
/// built in one pass over the matrix: every column belongs to one component, so a column's
/// local index is the same in every row.
pub fn component_matrices(matrix: &IntMatrix) -> Vec<(Vec<usize>, Vec<usize>, IntMatrix)> {
    submatrices(matrix, components(matrix))
}

/// The submatrix of `matrix` with rows `rows` and columns `cols` (increasing; every column
/// those rows use, as for a connected component): column `cols[k]` becomes column `k`.
///
/// # Panics
/// Panics if a row uses a column outside `cols`.
pub fn submatrix(matrix: &IntMatrix, rows: &[usize], cols: &[usize]) -> IntMatrix {
    let local_rows = rows
        .iter()
        .map(|&i| {
            matrix
                .row(i)
                .iter()
                .map(|(c, v)| {
                    let k = cols
                        .binary_search(c)
                        .expect("the rows use only the given columns");
                    (k, v.clone())
                })
                .collect()
        })
        .collect();
    IntMatrix::from_sparse(cols.len(), local_rows).expect("local columns are in range")
}

/// The submatrix of each of `parts` (the [`components`] of `matrix`), with its rows and
/// columns.
pub(crate) fn submatrices(
    matrix: &IntMatrix,
    parts: Vec<(Vec<usize>, Vec<usize>)>,
) -> Vec<(Vec<usize>, Vec<usize>, IntMatrix)> {
    let mut local_col = vec![0usize; matrix.cols()];
    for (_, cols) in &parts {
        for (k, &c) in cols.iter().enumerate() {
            local_col[c] = k;
        }
    }
    parts
        .into_iter()
        .map(|(rows, cols)| {
            let local_rows: Vec<Vec<(usize, api::Integer)>> = rows
                .iter()
                .map(|&i| {
                    matrix
                        .row(i)
                        .iter()
                        .map(|(c, v)| (local_col[*c], v.clone()))
                        .collect()
                })
                .collect();
            let local = IntMatrix::from_sparse(cols.len(), local_rows)
                .expect("a component's rows use only its columns");
            (rows, cols, local)
        })
        .collect()
}

impl<R: Ring> BlockFactorization<R> {
    /// Factors each connected component of `matrix`, sharing identical ones.
    pub fn new(matrix: &IntMatrix, method: Simplification) -> Self {
        let mut cache: HashMap<ComponentKey, Arc<ExactFactorization<R>>> = HashMap::new();
        let mut parts = Vec::new();
        for (rows, cols, local) in component_matrices(matrix) {
            let key: ComponentKey = local.row_iter().map(|r| r.to_vec()).collect();
            let key = if local.rows() == 0 {
                // Components without rows (free columns) differ only in their width.
                vec![vec![(local.cols(), api::Integer::from(0))]]
            } else {
                key
            };
            let factor = cache
                .entry(key)
                .or_insert_with(|| Arc::new(ExactFactorization::new(&local, method)))
                .clone();
            parts.push(Component { rows, cols, factor });
        }
        BlockFactorization {
            m: matrix.rows(),
            n: matrix.cols(),
            distinct: cache.len(),
            components: parts,
        }
    }

    /// Number of connected components.
    pub fn component_count(&self) -> usize {
        self.components.len()
    }

    /// Number of component matrices factored (identical components share one).
    pub fn distinct_factorizations(&self) -> usize {
        self.distinct
    }

    fn local(values: &[Rational], indices: &[usize]) -> Vec<Rational> {
        indices.iter().map(|&i| values[i].clone()).collect()
    }

    fn global(&self, c: &Component<R>, inc: Inconsistency<Rational>) -> Inconsistency<Rational> {
        Inconsistency {
            rows: inc.rows.iter().map(|&i| c.rows[i]).collect(),
            certificate: inc.certificate,
            discrepancy: inc.discrepancy,
        }
    }

    /// Runs `check` on every component's part of `rhs`; the failure with the smallest support
    /// wins (ties: the component listed first).
    fn first_failure(
        &self,
        rhs: &[Rational],
        check: impl Fn(&ExactFactorization<R>, &[Rational]) -> Result<(), SolveError<Rational>>,
    ) -> Result<(), SolveError<Rational>> {
        let mut best: Option<Inconsistency<Rational>> = None;
        for c in &self.components {
            match check(&c.factor, &Self::local(rhs, &c.rows)) {
                Ok(()) => {}
                Err(SolveError::Inconsistent(inc)) => {
                    let inc = self.global(c, inc);
                    if best.as_ref().is_none_or(|b| inc.rows.len() < b.rows.len()) {
                        best = Some(inc);
                    }
                }
                Err(e) => return Err(e),
            }
        }
        match best {
            Some(inc) => Err(SolveError::Inconsistent(inc)),
            None => Ok(()),
        }
    }

    fn restrict(&self, c: &Component<R>, family: &RhsFamily) -> RhsFamily {
        let all: Vec<usize> = (0..family.coefficients.cols()).collect();
        RhsFamily {
            constant: family
                .constant
                .iter()
                .map(|col| Self::local(col, &c.rows))
                .collect(),
            coefficients: family.coefficients.select(&c.rows, &all),
        }
    }
}

impl<R: Ring> Factorization for BlockFactorization<R> {
    type Scalar = Rational;
    type LeastSquares = BlockLeastSquares<R>;

    fn rows(&self) -> usize {
        self.m
    }

    fn cols(&self) -> usize {
        self.n
    }

    fn rank(&self) -> usize {
        self.components.iter().map(|c| c.factor.rank()).sum()
    }

    fn independent_rows(&self) -> Vec<usize> {
        self.components
            .iter()
            .flat_map(|c| c.factor.independent_rows().into_iter().map(|i| c.rows[i]))
            .collect()
    }

    fn redundancies(&self) -> Vec<Redundancy<Rational>> {
        self.components
            .iter()
            .flat_map(|c| {
                c.factor.redundancies().into_iter().map(|r| Redundancy {
                    row: c.rows[r.row],
                    combination: r
                        .combination
                        .into_iter()
                        .map(|(i, w)| (c.rows[i], w))
                        .collect(),
                })
            })
            .collect()
    }

    fn solve(&self, rhs: &[Rational]) -> Result<Vec<Rational>, SolveError<Rational>> {
        check_len("right-hand side", rhs.len(), self.m)?;
        self.first_failure(rhs, |f, b| f.check_consistent(b))?;
        let mut x = vec![Rational::zero(); self.n];
        for c in &self.components {
            let local = c.factor.solve(&Self::local(rhs, &c.rows))?;
            for (j, v) in c.cols.iter().zip(local) {
                x[*j] = v;
            }
        }
        Ok(x)
    }

    fn check_consistent(&self, rhs: &[Rational]) -> Result<(), SolveError<Rational>> {
        check_len("right-hand side", rhs.len(), self.m)?;
        self.first_failure(rhs, |f, b| f.check_consistent(b))
    }

    fn check_strongly_consistent(
        &self,
        family: &RhsFamily,
    ) -> Result<Result<(), StrongFailure<Rational>>, BackendError> {
        validate_family(family, self.m)?;
        // Directions first over all components, then constants (as one factoring would).
        let mut constant_failure = None;
        for c in &self.components {
            match c
                .factor
                .check_strongly_consistent(&self.restrict(c, family))?
            {
                Ok(()) => {}
                Err(StrongFailure::Direction {
                    parameter,
                    inconsistency,
                }) => {
                    return Ok(Err(StrongFailure::Direction {
                        parameter,
                        inconsistency: self.global(c, inconsistency),
                    }))
                }
                Err(StrongFailure::Constant {
                    column,
                    inconsistency,
                }) => {
                    if constant_failure.is_none() {
                        constant_failure = Some(StrongFailure::Constant {
                            column,
                            inconsistency: self.global(c, inconsistency),
                        });
                    }
                }
            }
        }
        Ok(match constant_failure {
            Some(f) => Err(f),
            None => Ok(()),
        })
    }

    fn null_space(&self) -> Vec<Vec<Rational>> {
        self.components
            .iter()
            .flat_map(|c| {
                c.factor.null_space().into_iter().map(|v| {
                    let mut full = vec![Rational::zero(); self.n];
                    for (j, x) in c.cols.iter().zip(v) {
                        full[*j] = x;
                    }
                    full
                })
            })
            .collect()
    }

    fn prepare_least_squares(
        &self,
        family: &RhsFamily,
        weights: &[Rational],
    ) -> Result<Self::LeastSquares, BackendError> {
        validate_family(family, self.m)?;
        validate_weights(weights, self.n)?;
        let parts = self
            .components
            .iter()
            .map(|c| {
                c.factor.prepare_least_squares(
                    &self.restrict(c, family),
                    &Self::local(weights, &c.cols),
                )
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(BlockLeastSquares {
            n: self.n,
            parameters: family.coefficients.cols(),
            columns: family.constant.len(),
            rows: self.components.iter().map(|c| c.rows.clone()).collect(),
            cols: self.components.iter().map(|c| c.cols.clone()).collect(),
            parts,
        })
    }
}

/// Least squares prepared per component: the objective is a sum over columns and the
/// constraints of different components share no column, so the problem splits.
#[derive(Debug, Clone)]
pub struct BlockLeastSquares<R: Ring = Int> {
    n: usize,
    parameters: usize,
    columns: usize,
    rows: Vec<Vec<usize>>,
    cols: Vec<Vec<usize>>,
    parts: Vec<ExactLeastSquares<R>>,
}

impl<R: Ring> BlockLeastSquares<R> {
    fn validate(&self, column: usize, alpha: &[Rational]) -> Result<(), BackendError> {
        if column >= self.columns {
            return Err(BackendError::NoSuchColumn {
                column,
                columns: self.columns,
            });
        }
        check_len("parameter vector α", alpha.len(), self.parameters)
    }

    fn solve_parts<T: Clone>(
        &self,
        column: usize,
        alpha: &[Rational],
        hints: &[Rational],
        zero: T,
        solve: impl Fn(&ExactLeastSquares<R>, &[Rational]) -> Result<Vec<T>, SolveError<Rational>>,
    ) -> Result<Vec<T>, SolveError<Rational>> {
        self.validate(column, alpha)?;
        check_len("hints", hints.len(), self.n)?;
        // Check every component first: nothing is computed for an inconsistent move.
        let mut best: Option<Inconsistency<Rational>> = None;
        for (part, rows) in self.parts.iter().zip(&self.rows) {
            if let Err(e) = part.check(column, alpha) {
                match e {
                    SolveError::Inconsistent(inc) => {
                        let inc = Inconsistency {
                            rows: inc.rows.iter().map(|&i| rows[i]).collect(),
                            certificate: inc.certificate,
                            discrepancy: inc.discrepancy,
                        };
                        if best.as_ref().is_none_or(|b| inc.rows.len() < b.rows.len()) {
                            best = Some(inc);
                        }
                    }
                    other => return Err(other),
                }
            }
        }
        if let Some(inc) = best {
            return Err(SolveError::Inconsistent(inc));
        }
        let mut x = vec![zero; self.n];
        for (part, cols) in self.parts.iter().zip(&self.cols) {
            let local: Vec<Rational> = cols.iter().map(|&j| hints[j].clone()).collect();
            for (j, v) in cols.iter().zip(solve(part, &local)?) {
                x[*j] = v;
            }
        }
        Ok(x)
    }
}

impl<R: Ring> PreparedLeastSquares for BlockLeastSquares<R> {
    type Scalar = Rational;

    fn check(&self, column: usize, alpha: &[Rational]) -> Result<(), SolveError<Rational>> {
        self.solve_parts(
            column,
            alpha,
            &vec![Rational::zero(); self.n],
            (),
            |_, l| Ok(vec![(); l.len()]),
        )
        .map(|_| ())
    }

    fn solve(
        &self,
        column: usize,
        alpha: &[Rational],
        hints: &[Rational],
    ) -> Result<Vec<Rational>, SolveError<Rational>> {
        self.solve_parts(column, alpha, hints, Rational::zero(), |part, local| {
            part.solve(column, alpha, local)
        })
    }

    fn solve_approx(
        &self,
        column: usize,
        alpha: &[Rational],
        hints: &[Rational],
    ) -> Result<Vec<f64>, SolveError<Rational>> {
        self.solve_parts(column, alpha, hints, 0.0, |part, local| {
            part.solve_approx(column, alpha, local)
        })
    }
}
