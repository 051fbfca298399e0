//! The factored matrix: rank decision by column-pivoted QR of `Aᵀ`, a thin QR of the
//! independent rows for solving, redundancy combinations, consistency checks with certificates
//! and the null space.

use crate::convert::{dot_with_magnitude, matrix_rows, rationals, FloatRow};
use crate::lsq::FloatLeastSquares;
use api::backend::{check_len, validate_family};
use api::{
    BackendError, Factorization, Inconsistency, IntMatrix, RankMargin, Rational, Redundancy,
    RhsFamily, SolveError, StrongFailure,
};
use nalgebra::{DMatrix, DVector, Dyn, QR};
use std::sync::Arc;

/// A redundant row and its combination of independent rows.
#[derive(Debug, Clone, PartialEq)]
struct Dependent {
    /// The redundant row of `A`.
    row: usize,
    /// `(position k in the independent rows, w_k)` with `|w_k|` above the support threshold,
    /// by increasing `k`: `a_row ≈ Σ w_k â_k`.
    combination: Vec<(usize, f64)>,
}

/// Everything computed from `A` once; shared (through an `Arc`) with prepared least squares.
#[derive(Debug, Clone)]
pub(crate) struct Core {
    n: usize,
    tolerance: f64,
    /// `A` in `f64`, by rows.
    rows: Vec<FloatRow>,
    /// `‖a_i‖₂` per row.
    row_norms: Vec<f64>,
    /// `‖Â‖_F`, the Frobenius norm of the independent rows.
    frobenius: f64,
    /// `|R_kk| / max |R_kk|` of the pivoted QR of `Aᵀ`, in pivot order (all zero for `A = 0`).
    relative_diagonal: Vec<f64>,
    margin: RankMargin,
    /// The first `r` pivots: independent rows of `A` (indices into `A`).
    independent: Vec<usize>,
    /// Thin QR of `Âᵀ` (`n × r`).
    qr: QR<f64, Dyn, Dyn>,
    /// `Q₁` (`n × r`) of that QR.
    q1: DMatrix<f64>,
    /// `R₁` (`r × r`, upper triangular, nonzero diagonal) of that QR.
    r1: DMatrix<f64>,
    /// Every row that is not independent, by increasing row.
    dependents: Vec<Dependent>,
    /// For each row of `A`, its index in `dependents` (`None` for independent rows).
    dependent_of_row: Vec<Option<usize>>,
}

/// A factored matrix (result of [`crate::FloatQr`]'s `factor`).
///
/// Cheap to clone: the factors are shared.
#[derive(Debug, Clone)]
pub struct FloatFactorization {
    core: Arc<Core>,
}

/// Householder QR with column-norm pivoting (Businger–Golub) of `a` (`n × m`): the diagonal of
/// `R` and the column order.
///
/// At each step the remaining column of largest norm becomes the pivot, so the diagonal
/// magnitudes never increase: the rank decision is then a clean threshold and the margin
/// (smallest kept against largest dropped) is meaningful. nalgebra's `col_piv_qr` pivots on the
/// largest single entry instead, which can put a tiny diagonal before large ones and make a
/// near-degenerate system look far more deficient than it is.
fn pivoted_householder(mut a: DMatrix<f64>) -> (Vec<f64>, Vec<usize>) {
    let (n, m) = a.shape();
    let mut order: Vec<usize> = (0..m).collect();
    let mut diagonal = Vec::with_capacity(n.min(m));
    for k in 0..n.min(m) {
        let remaining_norm = |a: &DMatrix<f64>, j: usize| -> f64 {
            (k..n).map(|i| a[(i, j)] * a[(i, j)]).sum::<f64>()
        };
        let (p, best) = (k..m)
            .map(|j| (j, remaining_norm(&a, j)))
            .fold((k, -1.0), |acc, x| if x.1 > acc.1 { x } else { acc });
        if best <= 0.0 {
            diagonal.extend(std::iter::repeat_n(0.0, n.min(m) - k));
            break;
        }
        if p != k {
            a.swap_columns(k, p);
            order.swap(k, p);
        }
        let norm = best.sqrt();
        let alpha = if a[(k, k)] > 0.0 { -norm } else { norm };
        // v = x − α e₁, normalised; H = I − 2 v vᵀ maps x to α e₁.
        let mut v: Vec<f64> = (k..n).map(|i| a[(i, k)]).collect();
        v[0] -= alpha;
        let v_norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if v_norm > 0.0 {
            for x in v.iter_mut() {
                *x /= v_norm;
            }
            for j in k..m {
                let dot: f64 = v.iter().enumerate().map(|(t, vt)| vt * a[(k + t, j)]).sum();
                for (t, vt) in v.iter().enumerate() {
                    a[(k + t, j)] -= 2.0 * vt * dot;
                }
            }
        }
        diagonal.push(alpha);
    }
    (diagonal, order)
}

/// The rank decision from the diagonal magnitudes in pivot order.
///
/// With column-norm pivoting the magnitudes do not increase, so the rank is the number of them
/// above the tolerance (counted as the leading run, which is the same thing).
fn rank_decision(diagonal: &[f64], tolerance: f64) -> (usize, Vec<f64>, RankMargin) {
    let largest = diagonal.iter().fold(0.0_f64, |acc, d| acc.max(d.abs()));
    let relative: Vec<f64> = if largest > 0.0 {
        diagonal.iter().map(|d| d.abs() / largest).collect()
    } else {
        vec![0.0; diagonal.len()]
    };
    let rank = relative.iter().take_while(|&&d| d > tolerance).count();
    let smallest_kept = relative[..rank].iter().copied().fold(1.0_f64, f64::min);
    let largest_dropped = relative[rank..].iter().copied().fold(0.0_f64, f64::max);
    (
        rank,
        relative,
        RankMargin {
            smallest_kept,
            largest_dropped,
            tolerance,
        },
    )
}

/// A right-hand side in `f64` with, per row, the magnitude of the terms that produced it
/// (`|b_i|`, or `|c_i| + Σ_k |K_ik| |α_k|` for a family).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FloatRhs {
    pub(crate) values: Vec<f64>,
    pub(crate) magnitudes: Vec<f64>,
}

impl FloatRhs {
    /// A plain right-hand side.
    pub(crate) fn plain(values: Vec<f64>) -> Self {
        let magnitudes = values.iter().map(|v| v.abs()).collect();
        FloatRhs { values, magnitudes }
    }
}

impl Core {
    fn new(matrix: &IntMatrix, tolerance: f64) -> Result<Self, BackendError> {
        let m = matrix.rows();
        let n = matrix.cols();
        let rows = matrix_rows(matrix, "matrix")?;

        // Column-pivoted QR of Aᵀ: its columns are the rows of A, each scaled to unit length.
        // Scaling rows does not change which are independent, but integer constraint rows can
        // differ in size by many orders of magnitude (coefficients from coordinates of 10^6
        // next to coefficients of 1); without it a relative tolerance would call the small rows
        // dependent on scale alone.
        let mut at = DMatrix::<f64>::zeros(n, m);
        for (i, row) in rows.iter().enumerate() {
            let norm = row.iter().map(|(_, v)| v * v).sum::<f64>().sqrt();
            for (j, v) in row {
                at[(*j, i)] = *v / norm;
            }
        }
        let (diagonal, order) = pivoted_householder(at);
        let (rank, relative_diagonal, margin) = rank_decision(&diagonal, tolerance);
        let independent: Vec<usize> = order[..rank].to_vec();

        // Thin QR of Âᵀ (n × r, full column rank).
        let mut a_hat_t = DMatrix::<f64>::zeros(n, rank);
        for (k, &i) in independent.iter().enumerate() {
            for (j, v) in &rows[i] {
                a_hat_t[(*j, k)] = *v;
            }
        }
        let qr = a_hat_t.qr();
        let q1 = qr.q();
        let r1 = qr.r();

        // Combinations of the redundant rows: Âᵀ w = a_tᵀ in the least-squares sense,
        // w = R₁⁻¹ Q₁ᵀ a_tᵀ.
        let mut dependent_of_row = vec![None; m];
        let mut is_independent = vec![false; m];
        for &i in &independent {
            is_independent[i] = true;
        }
        let redundant: Vec<usize> = (0..m).filter(|&i| !is_independent[i]).collect();
        let mut redundant_t = DMatrix::<f64>::zeros(n, redundant.len());
        for (c, &i) in redundant.iter().enumerate() {
            for (j, v) in &rows[i] {
                redundant_t[(*j, c)] = *v;
            }
            dependent_of_row[i] = Some(c);
        }
        let weights = r1
            .solve_upper_triangular(&(q1.transpose() * redundant_t))
            .ok_or_else(|| {
                BackendError::Numerical("singular triangular factor of the independent rows".into())
            })?;
        let dependents = redundant
            .iter()
            .enumerate()
            .map(|(c, &row)| {
                let w = weights.column(c);
                let threshold = support_threshold(w.iter().copied(), tolerance);
                Dependent {
                    row,
                    combination: w
                        .iter()
                        .enumerate()
                        .filter(|(_, v)| v.abs() > threshold)
                        .map(|(k, v)| (k, *v))
                        .collect(),
                }
            })
            .collect();

        let row_norms: Vec<f64> = rows
            .iter()
            .map(|row| row.iter().map(|(_, v)| v * v).sum::<f64>().sqrt())
            .collect();
        let frobenius = independent
            .iter()
            .map(|&i| row_norms[i] * row_norms[i])
            .sum::<f64>()
            .sqrt();
        Ok(Core {
            n,
            tolerance,
            rows,
            row_norms,
            frobenius,
            relative_diagonal,
            margin,
            independent,
            qr,
            q1,
            r1,
            dependents,
            dependent_of_row,
        })
    }

    pub(crate) fn rows(&self) -> usize {
        self.rows.len()
    }

    pub(crate) fn cols(&self) -> usize {
        self.n
    }

    pub(crate) fn independent(&self) -> &[usize] {
        &self.independent
    }

    pub(crate) fn row(&self, i: usize) -> &[(usize, f64)] {
        &self.rows[i]
    }

    /// Converts and length-checks a plain right-hand side.
    fn plain_rhs(&self, rhs: &[Rational]) -> Result<FloatRhs, BackendError> {
        check_len("right-hand side", rhs.len(), self.rows())?;
        Ok(FloatRhs::plain(rationals(rhs, "right-hand side")?))
    }

    /// The minimum-norm solution of `Â x = b̂`: `x = Q₁ R₁⁻ᵀ b̂`.
    fn min_norm(&self, b: &[f64]) -> Result<Vec<f64>, BackendError> {
        let b_hat = DVector::from_iterator(
            self.independent.len(),
            self.independent.iter().map(|&i| b[i]),
        );
        let z = self.r1.tr_solve_upper_triangular(&b_hat).ok_or_else(|| {
            BackendError::Numerical("singular triangular factor of the independent rows".into())
        })?;
        let x: Vec<f64> = (&self.q1 * z).iter().copied().collect();
        if x.iter().all(|v| v.is_finite()) {
            Ok(x)
        } else {
            Err(BackendError::Numerical(
                "the solution overflows f64".to_string(),
            ))
        }
    }

    /// Weak consistency of `A x = b`: the minimum-norm solution of the independent rows, checked
    /// against every row. Returns that solution.
    ///
    /// Row `i` passes when `|a_i·x − b_i| ≤ tolerance · s_i` with the rounding scale
    ///
    /// ```text
    /// s_i = ‖a_i‖ ‖x‖ + β_i + Σ_k |w_ik| (‖Â‖_F ‖x‖ + β_{ind_k})
    /// ```
    ///
    /// where `β` are the magnitudes of the right-hand side ([`FloatRhs::magnitudes`]) and `w_i`
    /// the combination of row `i` over the independent rows (`e_k` for independent row `k`).
    /// The first two terms bound the rounding of evaluating the residual; the sum bounds the
    /// residual the (normwise backward stable) QR solve leaves on the independent rows,
    /// propagated to row `i` through its combination.
    pub(crate) fn weak_check(&self, rhs: &FloatRhs) -> Result<Vec<f64>, SolveError<f64>> {
        let x = self.min_norm(&rhs.values)?;
        let x_norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
        let solve_error = |k: usize| self.frobenius * x_norm + rhs.magnitudes[self.independent[k]];
        // (support size, −relative violation, dependent index) of the best failing row.
        let mut best: Option<(usize, f64, usize)> = None;
        let mut independent_failure = None;
        for (i, row) in self.rows.iter().enumerate() {
            let (ax, _) = dot_with_magnitude(row, &x);
            let residual = (ax - rhs.values[i]).abs();
            let evaluation = self.row_norms[i] * x_norm + rhs.magnitudes[i];
            let propagated = match self.dependent_of_row[i] {
                Some(d) => self.dependents[d]
                    .combination
                    .iter()
                    .map(|(k, w)| w.abs() * solve_error(*k))
                    .sum(),
                None => self.frobenius * x_norm + rhs.magnitudes[i],
            };
            let scale = evaluation + propagated;
            if residual <= self.tolerance * scale {
                continue;
            }
            match self.dependent_of_row[i] {
                Some(d) => {
                    let key = (
                        self.dependents[d].combination.len() + 1,
                        -(residual / scale),
                        d,
                    );
                    if best.is_none_or(|b| (key.0, key.1) < (b.0, b.1)) {
                        best = Some(key);
                    }
                }
                None => independent_failure = independent_failure.or(Some(i)),
            }
        }
        if let Some((_, _, d)) = best {
            return Err(SolveError::Inconsistent(
                self.certificate(&self.dependents[d], &rhs.values),
            ));
        }
        if let Some(i) = independent_failure {
            return Err(SolveError::Input(BackendError::Numerical(format!(
                "independent row {i} is not satisfied to the tolerance: \
                 the independent rows are too ill-conditioned for f64"
            ))));
        }
        Ok(x)
    }

    /// `y = e_t − Σ_k w_k e_{ind_k}` for a failing redundant row, with `yᵀb`.
    fn certificate(&self, dependent: &Dependent, b: &[f64]) -> Inconsistency<f64> {
        let mut y: Vec<(usize, f64)> = Vec::with_capacity(dependent.combination.len() + 1);
        y.push((dependent.row, 1.0));
        y.extend(
            dependent
                .combination
                .iter()
                .map(|(k, w)| (self.independent[*k], -w)),
        );
        y.sort_by_key(|(i, _)| *i);
        let discrepancy = y.iter().map(|(i, v)| v * b[*i]).sum();
        Inconsistency {
            rows: y.iter().map(|(i, _)| *i).collect(),
            certificate: y.iter().map(|(_, v)| *v).collect(),
            discrepancy,
        }
    }
}

/// Entries of a combination at or below this magnitude are rounding noise: the tolerance
/// relative to the largest entry of `y = e_t − Σ w_k e_{ind_k}` (which is at least 1).
pub(crate) fn support_threshold(w: impl Iterator<Item = f64>, tolerance: f64) -> f64 {
    tolerance * w.fold(1.0_f64, |acc, v| acc.max(v.abs()))
}

impl FloatFactorization {
    /// Factors `matrix` with the given relative tolerance (see [`crate::FloatQr`]).
    pub fn new(matrix: &IntMatrix, tolerance: f64) -> Result<Self, BackendError> {
        Ok(FloatFactorization {
            core: Arc::new(Core::new(matrix, tolerance)?),
        })
    }

    /// The relative tolerance that decided rank and consistency.
    pub fn tolerance(&self) -> f64 {
        self.core.tolerance
    }

    /// The diagonal magnitudes `|R_kk|` of the pivoted QR of `Aᵀ`, relative to the largest, in
    /// pivot order (`min(m, n)` values; all zero for the zero matrix). Entries before
    /// [`Factorization::rank`] were kept, the others dropped.
    pub fn relative_diagonal(&self) -> &[f64] {
        &self.core.relative_diagonal
    }

    pub(crate) fn core(&self) -> &Arc<Core> {
        &self.core
    }

    /// Weak check of one vector, mapping an inconsistency to a strong-consistency failure.
    fn strong_part(
        &self,
        rhs: FloatRhs,
        failure: impl FnOnce(Inconsistency<f64>) -> StrongFailure<f64>,
    ) -> Result<Result<(), StrongFailure<f64>>, BackendError> {
        match self.core.weak_check(&rhs) {
            Ok(_) => Ok(Ok(())),
            Err(SolveError::Inconsistent(inconsistency)) => Ok(Err(failure(inconsistency))),
            Err(SolveError::Input(e)) => Err(e),
        }
    }
}

impl Factorization for FloatFactorization {
    type Scalar = f64;
    type LeastSquares = FloatLeastSquares;

    fn rows(&self) -> usize {
        self.core.rows()
    }

    fn cols(&self) -> usize {
        self.core.n
    }

    fn rank(&self) -> usize {
        self.core.independent.len()
    }

    fn independent_rows(&self) -> Vec<usize> {
        self.core.independent.clone()
    }

    fn redundancies(&self) -> Vec<Redundancy<f64>> {
        self.core
            .dependents
            .iter()
            .map(|d| Redundancy {
                row: d.row,
                combination: d
                    .combination
                    .iter()
                    .map(|(k, w)| (self.core.independent[*k], *w))
                    .collect(),
            })
            .collect()
    }

    fn rank_margin(&self) -> Option<RankMargin> {
        Some(self.core.margin)
    }

    fn solve(&self, rhs: &[Rational]) -> Result<Vec<f64>, SolveError<f64>> {
        let rhs = self.core.plain_rhs(rhs)?;
        self.core.weak_check(&rhs)
    }

    fn check_consistent(&self, rhs: &[Rational]) -> Result<(), SolveError<f64>> {
        self.solve(rhs).map(|_| ())
    }

    fn check_strongly_consistent(
        &self,
        family: &RhsFamily,
    ) -> Result<Result<(), StrongFailure<f64>>, BackendError> {
        validate_family(family, self.core.rows())?;
        // Directions first: when every column of K is in the range, a constant part outside it
        // means the current values themselves are inconsistent, which is then reported as such.
        let k = matrix_rows(&family.coefficients, "family coefficient matrix")?;
        for parameter in 0..family.coefficients.cols() {
            let mut column = vec![0.0; self.core.rows()];
            for (i, row) in k.iter().enumerate() {
                if let Ok(pos) = row.binary_search_by_key(&parameter, |(c, _)| *c) {
                    column[i] = row[pos].1;
                }
            }
            let rhs = FloatRhs::plain(column);
            if let Err(failure) =
                self.strong_part(rhs, |inconsistency| StrongFailure::Direction {
                    parameter,
                    inconsistency,
                })?
            {
                return Ok(Err(failure));
            }
        }
        for (column, c) in family.constant.iter().enumerate() {
            let rhs = FloatRhs::plain(rationals(c, "family constant column")?);
            if let Err(failure) =
                self.strong_part(rhs, |inconsistency| StrongFailure::Constant {
                    column,
                    inconsistency,
                })?
            {
                return Ok(Err(failure));
            }
        }
        Ok(Ok(()))
    }

    fn null_space(&self) -> Vec<Vec<f64>> {
        let n = self.core.n;
        // Qᵀ of the full orthogonal factor of Âᵀ = Q [R₁; 0]; its rows r.. span {x : Â x = 0}.
        let mut qt = DMatrix::<f64>::identity(n, n);
        self.core.qr.q_tr_mul(&mut qt);
        (self.rank()..n)
            .map(|k| qt.row(k).iter().copied().collect())
            .collect()
    }

    fn prepare_least_squares(
        &self,
        family: &RhsFamily,
        weights: &[Rational],
    ) -> Result<FloatLeastSquares, BackendError> {
        FloatLeastSquares::prepare(self, family, weights)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::LinearBackend;

    fn factor(cols: usize, rows: &[Vec<i64>]) -> FloatFactorization {
        let a = IntMatrix::from_dense(cols, rows).expect("matrix");
        crate::FloatQr::default().factor(&a).expect("factor")
    }

    fn q(v: i64) -> Rational {
        Rational::from_integer(v.into())
    }

    /// Exact rank of some rows of a small dense matrix (the exact backend as oracle).
    fn exact_rank(cols: usize, rows: &[Vec<i64>]) -> usize {
        let a = IntMatrix::from_dense(cols, rows).expect("matrix");
        exact_ldu::ExactLdu::default()
            .factor(&a)
            .expect("factor")
            .rank()
    }

    #[test]
    fn column_norm_pivoting_orders_rows_by_remaining_norm() {
        // Rows of norms 5, 1, 9, 3 (orthogonal except rows 1 and 3). The factorization scales
        // rows to unit length first, so the first of two parallel rows wins: row 3 = 3 · row 1.
        let a = [vec![5, 0, 0], vec![0, 1, 0], vec![0, 0, 9], vec![0, 3, 0]];
        let f = factor(3, &a);
        assert_eq!(f.rank(), 3);
        assert_eq!(f.independent_rows(), vec![0, 1, 2]);
        let reds = f.redundancies();
        assert_eq!(reds.len(), 1);
        assert_eq!(reds[0].row, 3);
        assert_eq!(reds[0].combination.len(), 1);
        assert_eq!(reds[0].combination[0].0, 1);
        assert!((reds[0].combination[0].1 - 3.0).abs() < 1e-15);
        // Unscaled, pivoting follows the remaining column norms.
        let at = DMatrix::<f64>::from_fn(3, 4, |j, i| a[i][j] as f64);
        let (diagonal, order) = pivoted_householder(at);
        assert_eq!(order, vec![2, 0, 3, 1]);
        // Column norms 9, 5, 3 (1 is dependent on 3): non-increasing magnitudes.
        let mags: Vec<f64> = diagonal.iter().map(|d| d.abs()).collect();
        assert!((mags[0] - 9.0).abs() < 1e-12 && (mags[1] - 5.0).abs() < 1e-12);
        assert!((mags[2] - 3.0).abs() < 1e-12);
    }

    #[test]
    fn independent_rows_are_independent_and_duplicates_redundant() {
        let a = vec![
            vec![1, 2, 3, 4],
            vec![0, 1, 0, 1],
            vec![1, 2, 3, 4],
            vec![2, 5, 6, 9],
            vec![0, 0, 0, 0],
            vec![7, -1, 0, 2],
        ];
        let f = factor(4, &a);
        assert_eq!(f.rank(), 3);
        let ind = f.independent_rows();
        let sub: Vec<Vec<i64>> = ind.iter().map(|&i| a[i].clone()).collect();
        assert_eq!(exact_rank(4, &sub), 3, "independent rows {ind:?}");
        // Rows 0 and 2 are equal: at most one of them is independent.
        assert!(!(ind.contains(&0) && ind.contains(&2)));
        let reds = f.redundancies();
        assert_eq!(reds.len(), 3);
        assert!(reds.windows(2).all(|w| w[0].row < w[1].row));
        for red in &reds {
            // a_row ≈ Σ w a_k.
            let mut s = a[red.row].iter().map(|&v| -(v as f64)).collect::<Vec<_>>();
            for (k, w) in &red.combination {
                for (acc, akj) in s.iter_mut().zip(&a[*k]) {
                    *acc += w * *akj as f64;
                }
            }
            assert!(s.iter().all(|v| v.abs() < 1e-12), "{red:?}");
        }
        // A duplicate of an independent row is redundant with the single coefficient 1.
        let g = factor(4, &[a[0].clone(), a[1].clone(), a[0].clone()]);
        assert_eq!(g.rank(), 2);
        let dup = g.redundancies();
        assert_eq!(dup.len(), 1);
        let partner = if dup[0].row == 0 { 2 } else { 0 };
        assert_eq!(dup[0].combination.len(), 1, "{dup:?}");
        assert_eq!(dup[0].combination[0].0, partner);
        assert!((dup[0].combination[0].1 - 1.0).abs() < 1e-12);
        let zero = reds.iter().find(|r| r.row == 4).expect("zero row");
        assert!(zero.combination.is_empty());
    }

    #[test]
    fn duplicate_row_with_other_rhs_is_inconsistent() {
        let f = factor(2, &[vec![1, 1], vec![1, -1], vec![1, 1]]);
        let err = f.solve(&[q(2), q(0), q(3)]).expect_err("inconsistent");
        let SolveError::Inconsistent(c) = err else {
            panic!("{err:?}")
        };
        assert_eq!(c.rows, vec![0, 2]);
        assert!((c.certificate[0] + c.certificate[1]).abs() < 1e-12);
        assert!((c.discrepancy.abs() - 1.0).abs() < 1e-12);
        let x = f.solve(&[q(2), q(0), q(2)]).expect("consistent");
        assert!((x[0] - 1.0).abs() < 1e-12 && (x[1] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn rank_decision_conventions() {
        let (r, rel, m) = rank_decision(&[], 1e-10);
        assert_eq!((r, rel.len()), (0, 0));
        assert_eq!((m.smallest_kept, m.largest_dropped), (1.0, 0.0));
        let (r, _, m) = rank_decision(&[0.0, 0.0], 1e-10);
        assert_eq!(r, 0);
        assert_eq!((m.smallest_kept, m.largest_dropped), (1.0, 0.0));
        let (r, _, m) = rank_decision(&[-4.0, 2.0, 1e-14], 1e-10);
        assert_eq!(r, 2);
        assert_eq!(m.smallest_kept, 0.5);
        assert!((m.largest_dropped - 2.5e-15).abs() < 1e-20);
    }
}
