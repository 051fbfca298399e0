//! The fraction-free LDU factoring `A = Π_R L D⁻¹ U Π_C` (thesis, algorithms 6–13).
//!
//! For an `m × n` integer matrix `A` of rank `r` the factoring yields integer matrices
//! `L` (`m × r`, lower trapezoidal), `D` (`r × r`, diagonal) and `U` (`r × n`, upper
//! trapezoidal) and two permutations. The first `r` rows of `Π_R⁻¹ A` are independent; every
//! later row is the combination `L̃ L̂⁻¹` of them.
//!
//! # Conventions
//! * `row_perm[k]` is the row of `A` at position `k` of `Π_R⁻¹ A`; `col_perm[k]` is the column
//!   of `A` at position `k` of `A Π_C⁻¹`. Hence
//!   `A[row_perm[k]][col_perm[c]] = Σ_{j ≤ min(k, r−1)} L[k][j] · U[j][c] / D[j]`.
//! * Pivoting (algorithm 7): columns that are zero in the remaining rows are moved to the end
//!   (swapping with the last active column), then the pivot is an entry of smallest nonzero
//!   absolute value; ties go to the lowest original row, then the lowest original column (the
//!   thesis takes the first in the current scan order; see below).
//! * Elimination (algorithm 8): `L_ti ← L_tt U_ti`, `D_tt ← D_tt U_ii`,
//!   `U_ts ← U_ii U_ts − U_ti U_is`. The pending `D_tt` of all uneliminated rows are always equal,
//!   so they are kept as one value.
//! * Simplification (algorithms 9–13): `None`; `Gcd` divides each new row of `U` by the GCD of
//!   its entries (moving the factor into `L_tt`) and each column of `L` together with `D_ii` by
//!   their GCD; `Turner` divides each new row by the previous pivot `U_{i−1,i−1}` (Bareiss) and,
//!   as the invariant requires, `D_tt ← D_tt / U_{i−1,i−1}` (the printed algorithm 13 has a slip
//!   there).
//!
//! Two deliberate departures from the printed algorithms make the pivots of a block-diagonal
//! matrix independent of the order its blocks are eliminated in, so that factoring connected
//! components separately gives exactly the same rank, independent rows, combinations and
//! solutions as one factoring: ties in the pivot search are broken on original indices, and the
//! `Gcd` method makes every row primitive before the first stage (the thesis simplifies a row
//! after its first elimination). The thesis' worked examples come out unchanged.
//!
//! The `Gcd` method also takes two shortcuts with the same results as the plain steps: the
//! elimination multipliers are divided by `gcd(U_ii, U_ti)` first (the row GCD absorbs that
//! factor anyway), and a row with `U_ti = 0`, already primitive, is only negated when
//! `U_ii < 0` instead of being multiplied by `U_ii` and divided back.

use crate::qvec::QVec;
use crate::ring::{gcd_all, Ring};
use api::BackendError;
use api::Rational as BigRational;
use num_bigint::BigInt;
use num_traits::Zero;
use std::cmp::Ordering;

/// How common factors are removed during the factoring (thesis, chapter 7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Simplification {
    /// Plain fraction-free elimination: entries grow exponentially with the rank.
    None,
    /// Divide rows of `U` and columns of `L` by their GCD (smallest entries; the default).
    #[default]
    Gcd,
    /// Turner's GCD-free division by the previous pivot (Bareiss): linear growth, no GCDs.
    Turner,
}

/// How the pivot of each stage is chosen (after zero columns are moved to the end).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Pivoting {
    /// Full pivoting on the entry of smallest nonzero magnitude (algorithm 7; the default).
    #[default]
    SmallestMagnitude,
    /// The first nonzero entry in row-major order of the remaining block: no exchanges while
    /// the diagonal is nonzero (as in the hand-worked examples of thesis section 7).
    FirstNonzero,
}

/// The working matrix `U` after one elimination stage: all `m` rows, in working order.
pub type StageSnapshot = Vec<Vec<BigInt>>;

/// A fraction-free LDU factoring of an integer matrix.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ldu<R: Ring> {
    rows: usize,
    cols: usize,
    rank: usize,
    row_perm: Vec<usize>,
    col_perm: Vec<usize>,
    /// Row `k` holds `L[k][0..=min(k, r−1)]`.
    l: Vec<Vec<R>>,
    d: Vec<R>,
    /// Row `k < r` holds `U[k][0..n]` in permuted column order.
    u: Vec<Vec<R>>,
    method: Simplification,
}

fn check_rectangular<R>(rows: &[Vec<R>], cols: usize) -> Result<(), BackendError> {
    match rows.iter().find(|r| r.len() != cols) {
        Some(row) => Err(BackendError::DimensionMismatch {
            what: "matrix row",
            expected: cols,
            found: row.len(),
        }),
        None => Ok(()),
    }
}

fn swap_columns<R: Ring>(u: &mut [Vec<R>], col_perm: &mut [usize], a: usize, b: usize) {
    for row in u.iter_mut() {
        row.swap(a, b);
    }
    col_perm.swap(a, b);
}

impl<R: Ring> Ldu<R> {
    /// Factors the dense `m × n` matrix given by rows; every row must have `cols` entries.
    pub fn factor(
        rows: Vec<Vec<R>>,
        cols: usize,
        method: Simplification,
    ) -> Result<Self, BackendError> {
        check_rectangular(&rows, cols)?;
        Ok(Self::factor_impl(
            rows,
            cols,
            method,
            Pivoting::SmallestMagnitude,
            None,
        ))
    }

    /// Factors like [`Ldu::factor`] with a chosen pivoting rule, and also returns the working
    /// matrix `U` (all `m` rows, working row and column order) after every stage, as the thesis
    /// prints it in chapter 7.
    pub fn factor_traced(
        rows: Vec<Vec<R>>,
        cols: usize,
        method: Simplification,
        pivoting: Pivoting,
    ) -> Result<(Self, Vec<StageSnapshot>), BackendError> {
        check_rectangular(&rows, cols)?;
        let mut stages = Vec::new();
        let ldu = Self::factor_impl(rows, cols, method, pivoting, Some(&mut stages));
        Ok((ldu, stages))
    }

    fn factor_impl(
        rows: Vec<Vec<R>>,
        cols: usize,
        method: Simplification,
        pivoting: Pivoting,
        mut trace: Option<&mut Vec<StageSnapshot>>,
    ) -> Self {
        let m = rows.len();
        let n = cols;
        let mut u = rows;
        let mut row_perm: Vec<usize> = (0..m).collect();
        let mut col_perm: Vec<usize> = (0..n).collect();
        let mut l: Vec<Vec<R>> = vec![Vec::new(); m];
        let mut ldiag: Vec<R> = vec![R::one(); m];
        let mut primitive = vec![false; m];
        let mut d: Vec<R> = Vec::new();
        let mut pending_d = R::one();
        if method == Simplification::Gcd {
            // SimplifyURow on every row before the first stage (the thesis simplifies the first
            // pivot row here and every other row after its first elimination): all rows start
            // primitive, so pivot choices never depend on which block was eliminated first.
            for ((row, l_tt), is_primitive) in u.iter_mut().zip(&mut ldiag).zip(&mut primitive) {
                let g = gcd_all(row);
                if g.is_zero() {
                    continue;
                }
                if !g.is_one() {
                    for v in row.iter_mut() {
                        *v = v.div_exact(&g);
                    }
                    *l_tt = l_tt.mul(&g);
                }
                *is_primitive = true;
            }
        }
        let mut i = 0;
        let mut j = n;
        while i < m && i < j {
            // LinSys.GatherNonzeroColumns: move columns that vanish in rows i.. past j.
            let mut q = i;
            while q < j {
                if u[i..].iter().all(|row| row[q].is_zero()) {
                    j -= 1;
                    if q != j {
                        swap_columns(&mut u, &mut col_perm, q, j);
                    }
                } else {
                    q += 1;
                }
            }
            if j <= i {
                break;
            }
            // LinSys.Pivot: an entry of smallest nonzero magnitude; among equal magnitudes the
            // one of lowest original row, then lowest original column (the thesis takes the
            // first in the current scan order; breaking ties on original indices makes the
            // choice independent of the positions earlier pivots moved rows to, so factoring
            // the connected components of a matrix separately gives the same pivots).
            let mut best: Option<(usize, usize)> = None;
            for (p, row) in u.iter().enumerate().skip(i) {
                for (q, v) in row.iter().enumerate().take(j).skip(i) {
                    if v.is_zero() {
                        continue;
                    }
                    let better = match (best, pivoting) {
                        (None, _) => true,
                        (Some(_), Pivoting::FirstNonzero) => false,
                        (Some((bp, bq)), Pivoting::SmallestMagnitude) => {
                            match v.abs_cmp(&u[bp][bq]) {
                                Ordering::Less => true,
                                Ordering::Greater => false,
                                Ordering::Equal => {
                                    (row_perm[p], col_perm[q]) < (row_perm[bp], col_perm[bq])
                                }
                            }
                        }
                    };
                    if better {
                        best = Some((p, q));
                    }
                }
            }
            let Some((s, t)) = best else { break };
            if t != i {
                swap_columns(&mut u, &mut col_perm, i, t);
            }
            if s != i {
                u.swap(i, s);
                l.swap(i, s);
                ldiag.swap(i, s);
                primitive.swap(i, s);
                row_perm.swap(i, s);
            }
            let pivot = u[i][i].clone();
            let lii = ldiag[i].mul(&pivot);
            l[i].push(lii);
            d.push(pending_d.mul(&pivot));
            let turner_divisor = if method == Simplification::Turner && i >= 1 {
                Some(u[i - 1][i - 1].clone())
            } else {
                None
            };
            let (head, tail) = u.split_at_mut(i + 1);
            let pivot_row = &head[i];
            for (offset, row) in tail.iter_mut().enumerate() {
                let t = i + 1 + offset;
                let uti = std::mem::replace(&mut row[i], R::zero());
                l[t].push(ldiag[t].mul(&uti));
                match method {
                    Simplification::None | Simplification::Turner => {
                        for s in i + 1..n {
                            row[s] = R::mul_sub(&pivot, &row[s], &uti, &pivot_row[s]);
                        }
                        if let Some(div) = &turner_divisor {
                            for v in row[i + 1..].iter_mut() {
                                *v = v.div_exact(div);
                            }
                        }
                    }
                    Simplification::Gcd => {
                        eliminate_gcd(
                            row,
                            pivot_row,
                            &pivot,
                            &uti,
                            i,
                            &mut ldiag[t],
                            &mut primitive[t],
                        );
                    }
                }
            }
            pending_d = pending_d.mul(&pivot);
            if let Some(div) = &turner_divisor {
                pending_d = pending_d.div_exact(div);
            }
            if method == Simplification::Gcd {
                // LinSys.SimplifyLColumnGCD.
                let mut g = d[i].abs();
                for row in l.iter().skip(i) {
                    if g.is_one() {
                        break;
                    }
                    g = g.gcd(&row[i]);
                }
                if !g.is_one() && !g.is_zero() {
                    d[i] = d[i].div_exact(&g);
                    for row in l.iter_mut().skip(i) {
                        row[i] = row[i].div_exact(&g);
                    }
                }
            }
            if let Some(stages) = trace.as_deref_mut() {
                stages.push(
                    u.iter()
                        .map(|row| row.iter().map(Ring::to_bigint).collect())
                        .collect(),
                );
            }
            i += 1;
        }
        let rank = i;
        u.truncate(rank);
        Ldu {
            rows: m,
            cols: n,
            rank,
            row_perm,
            col_perm,
            l,
            d,
            u,
            method,
        }
    }

    /// `m`.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// `n`.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// The rank `r`.
    pub fn rank(&self) -> usize {
        self.rank
    }

    /// `Π_R` as a vector: position `k` of `Π_R⁻¹ A` holds row `row_perm()[k]` of `A`.
    pub fn row_perm(&self) -> &[usize] {
        &self.row_perm
    }

    /// `Π_C` as a vector: position `k` of `A Π_C⁻¹` holds column `col_perm()[k]` of `A`.
    pub fn col_perm(&self) -> &[usize] {
        &self.col_perm
    }

    /// Row `k` of `L` (`min(k + 1, r)` entries; the rest are zero).
    pub fn l_row(&self, k: usize) -> &[R] {
        &self.l[k]
    }

    /// `L[k][j]` (zero above the diagonal).
    pub fn l_at(&self, k: usize, j: usize) -> &R {
        &self.l[k][j]
    }

    /// The diagonal of `D`.
    pub fn d(&self) -> &[R] {
        &self.d
    }

    /// Row `k` of `U` (`n` entries, permuted column order).
    pub fn u_row(&self, k: usize) -> &[R] {
        &self.u[k]
    }

    /// The simplification method used.
    pub fn method(&self) -> Simplification {
        self.method
    }

    /// Largest bit size among the entries of `L`, `D` and `U` (the quantity of thesis figures
    /// 7.1–7.4).
    pub fn max_entry_bits(&self) -> u64 {
        self.l
            .iter()
            .flatten()
            .chain(self.d.iter())
            .chain(self.u.iter().flatten())
            .map(Ring::bits)
            .max()
            .unwrap_or(0)
    }

    /// `Π_R L D⁻¹ U Π_C` computed with rationals: equals `A` exactly (invariant I1).
    pub fn reconstruct(&self) -> Vec<Vec<BigRational>> {
        let mut out = vec![vec![BigRational::zero(); self.cols]; self.rows];
        for k in 0..self.rows {
            for (j, lkj) in self.l[k].iter().enumerate() {
                if lkj.is_zero() {
                    continue;
                }
                let coeff = BigRational::new(lkj.to_bigint(), self.d[j].to_bigint());
                for c in 0..self.cols {
                    let ujc = &self.u[j][c];
                    if !ujc.is_zero() {
                        out[self.row_perm[k]][self.col_perm[c]] +=
                            &coeff * BigRational::from_integer(ujc.to_bigint());
                    }
                }
            }
        }
        out
    }

    /// Dense `L` (`m × r`), `D` (diagonal) and `U` (`r × n`) as big integers, rows of `L` in
    /// `Π_R` order and columns of `U` in `Π_C` order, as printed in the thesis.
    pub fn dense_factors(&self) -> (Vec<Vec<BigInt>>, Vec<BigInt>, Vec<Vec<BigInt>>) {
        let l = self
            .l
            .iter()
            .map(|row| {
                let mut dense = vec![BigInt::from(0); self.rank];
                for (j, v) in row.iter().enumerate() {
                    dense[j] = v.to_bigint();
                }
                dense
            })
            .collect();
        let d = self.d.iter().map(Ring::to_bigint).collect();
        let u = self
            .u
            .iter()
            .map(|row| row.iter().map(Ring::to_bigint).collect())
            .collect();
        (l, d, u)
    }

    /// Forward substitution on a right-hand side given in `Π_R` order (length `m`): afterwards
    /// entries `0..r` hold `z = L̂⁻¹ b̂` and entries `r..m` the residuals `b̃ − L̃ z`, all over
    /// the common denominator. The system is consistent exactly when the residuals vanish.
    pub fn forward(&self, b: &mut QVec<R>) {
        debug_assert_eq!(b.num.len(), self.rows);
        for k in 0..self.rank {
            let row = &self.l[k];
            let mut s = b.num[k].clone();
            for (j, lkj) in row.iter().enumerate().take(k) {
                if !lkj.is_zero() && !b.num[j].is_zero() {
                    s = s.sub(&lkj.mul(&b.num[j]));
                }
            }
            b.divide_entry(k, s, &row[k]);
        }
        for t in self.rank..self.rows {
            let mut s = b.num[t].clone();
            for (j, ltj) in self.l[t].iter().enumerate() {
                if !ltj.is_zero() && !b.num[j].is_zero() {
                    s = s.sub(&ltj.mul(&b.num[j]));
                }
            }
            b.num[t] = s;
        }
    }

    /// Back substitution `Û x̂ = y` in place (`y` of length `r`, permuted column order).
    pub fn backward(&self, y: &mut QVec<R>) {
        debug_assert_eq!(y.num.len(), self.rank);
        for k in (0..self.rank).rev() {
            let row = &self.u[k];
            let mut s = y.num[k].clone();
            for (j, ukj) in row.iter().enumerate().take(self.rank).skip(k + 1) {
                if !ukj.is_zero() && !y.num[j].is_zero() {
                    s = s.sub(&ukj.mul(&y.num[j]));
                }
            }
            y.divide_entry(k, s, &row[k]);
        }
    }

    /// The coefficients `w` with `row t of Π_R⁻¹A = Σ_k w_k · row k` for a redundant position
    /// `t ≥ r`, i.e. row `t` of `L̃ L̂⁻¹`, over a common denominator.
    pub fn redundancy_weights(&self, t: usize) -> QVec<R> {
        debug_assert!(t >= self.rank && t < self.rows);
        let mut w = QVec::from_integers(self.l[t].clone());
        // Solve L̂ᵀ w = l_t (upper triangular), from the last unknown to the first.
        for k in (0..self.rank).rev() {
            let mut s = w.num[k].clone();
            for j in k + 1..self.rank {
                let ljk = &self.l[j][k];
                if !ljk.is_zero() && !w.num[j].is_zero() {
                    s = s.sub(&ljk.mul(&w.num[j]));
                }
            }
            w.divide_entry(k, s, &self.l[k][k]);
        }
        w
    }
}

/// Eliminates column `i` from `row` with the GCD method (see the module notes for the shortcuts).
fn eliminate_gcd<R: Ring>(
    row: &mut [R],
    pivot_row: &[R],
    pivot: &R,
    uti: &R,
    i: usize,
    ldiag: &mut R,
    primitive: &mut bool,
) {
    let tail = &mut row[i + 1..];
    if uti.is_zero() {
        if *primitive {
            if pivot.is_negative() {
                for v in tail.iter_mut() {
                    *v = v.neg();
                }
            }
            *ldiag = ldiag.mul(&pivot.abs());
            return;
        }
        let g = gcd_all(tail);
        if g.is_zero() {
            return;
        }
        let negate = pivot.is_negative();
        for v in tail.iter_mut() {
            let q = v.div_exact(&g);
            *v = if negate { q.neg() } else { q };
        }
        *ldiag = ldiag.mul(&pivot.abs().mul(&g));
        *primitive = true;
        return;
    }
    let h = pivot.gcd(uti);
    let a = pivot.div_exact(&h);
    let b = uti.div_exact(&h);
    for (v, p) in tail.iter_mut().zip(&pivot_row[i + 1..]) {
        *v = R::mul_sub(&a, v, &b, p);
    }
    let g = gcd_all(tail);
    if g.is_zero() {
        *primitive = false;
        return;
    }
    if !g.is_one() {
        for v in tail.iter_mut() {
            *v = v.div_exact(&g);
        }
    }
    *ldiag = ldiag.mul(&h.mul(&g));
    *primitive = true;
}
