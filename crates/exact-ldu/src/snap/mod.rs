//! Snapped commits: a point of the constraint set near the least-squares optimum whose values
//! have small denominators, with a proved bound on its distance to the optimum.
//!
//! The exact optimum of an edit on a real mesh has denominators of thousands of digits
//! (products of triangle areas over the rank of `G = Â V Âᵀ`), and committing it makes the next
//! edit start from those numbers: over a session the values grow without bound, and so does
//! the time of every edit. A snapped commit writes instead
//!
//! 1. `x̃ ≈ x*`, the optimum in `f64`: `G λ̃ = ρ` (`ρ = Â h − b̂`) by a sparse `L D Lᵀ` in
//!    `f64` ([`float_ldlt`]), `x̃ = h − V Âᵀ λ̃`;
//! 2. the free columns of a peeled basis ([`basis`]) rounded to the grid `2^−g`;
//! 3. the basic columns solved **exactly** from `Â x = b̂`: every constraint holds exactly
//!    (the redundant rows too, since the weak check passed for this right-hand side), and a
//!    basic value divides only by the pivots of its short chain, which depend on the mesh and
//!    not on the history, so the size of the values stays bounded over a session.
//!
//! The distance is proved in exact arithmetic. For any multipliers `λ`, the minimiser of the
//! Lagrangian `φ(x) + λᵀ(Â x − b̂)` (`φ(x) = ½ Σ (x_s − h_s)² / V_s`) is `x̂ = h − V Âᵀ λ`;
//! `x̂ − x*` lies in the range of `V Âᵀ` and `x − x*` in the kernel of `Â` for every `x` with
//! `Â x = b̂`, which are orthogonal in the `V⁻¹` inner product, so
//! `‖x − x*‖²_{V⁻¹} ≤ ‖x − x̂‖²_{V⁻¹}` (Pythagoras; it is also `2 (φ(x) − g(λ))`, the duality
//! gap). With `λ̂` the `f64` multipliers rounded to a dyadic grid, every `x_s − x̂_s` is computed
//! exactly and `|x_s − x*_s| ≤ sqrt(V_max Σ (x_s − x̂_s)² / V_s)`, a sum of nonnegative terms
//! whose rounding is covered when it is taken in `f64`.
//! Floats only choose the point; whether it satisfies the constraints and how far it is from
//! the optimum are exact.

mod basis;
mod float_ldlt;

use crate::factorization::SparseRow;
use crate::ring::Ring;
use api::exact::rational_to_f64;
use api::Rational;
use basis::PeeledBasis;
use float_ldlt::FloatLdlt;
use num_bigint::BigInt;
use num_traits::{FromPrimitive, Signed, Zero};

/// What a snapped solve needs beyond the exact least squares, prepared once per edit.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Snapper {
    basis: PeeledBasis,
    /// `G = Â V Âᵀ` factored in `f64`.
    normal: FloatLdlt,
    /// `Â` in `f64` and as integers.
    a_float: Vec<Vec<(usize, f64)>>,
    a_exact: Vec<Vec<(usize, BigInt)>>,
    /// `V` in `f64` and exactly, and its largest entry.
    v_float: Vec<f64>,
    v_max: BigInt,
}

/// A snapped solution and the bound on its distance to the optimum (per value, rounded up).
pub(crate) struct SnappedSolve {
    pub(crate) values: Vec<Rational>,
    pub(crate) distance_bound: f64,
}

impl Snapper {
    /// Prepares snapping for `Â` (independent rows, `n` columns), weights `V` and
    /// `G = Â V Âᵀ`; `None` when the peeled basis has a singular block or `G` is too badly
    /// conditioned for `f64` (the caller commits the optimum instead).
    pub(crate) fn new<R: Ring>(
        a_hat: &[SparseRow<R>],
        v: &[BigInt],
        gram: Vec<Vec<(usize, BigInt)>>,
    ) -> Option<Self> {
        let n = v.len();
        let basis = PeeledBasis::new(a_hat, n)?;
        let g_float: Vec<Vec<(usize, f64)>> = gram
            .iter()
            .map(|row| row.iter().map(|(c, x)| (*c, big_to_f64(x))).collect())
            .collect();
        let normal = FloatLdlt::factor(&g_float)?;
        let a_exact: Vec<Vec<(usize, BigInt)>> = a_hat
            .iter()
            .map(|row| row.iter().map(|(c, x)| (*c, x.to_bigint())).collect())
            .collect();
        let a_float = a_exact
            .iter()
            .map(|row| row.iter().map(|(c, x)| (*c, big_to_f64(x))).collect())
            .collect();
        Some(Snapper {
            basis,
            normal,
            a_float,
            a_exact,
            v_float: v.iter().map(big_to_f64).collect(),
            v_max: v.iter().max().cloned().unwrap_or_else(|| BigInt::from(1)),
        })
    }

    /// The snapped solution of `min φ(x)` subject to `Â x = b̂` for hints `h` on the grid
    /// `2^−grid_bits`; `None` when the `f64` optimum is not finite.
    pub(crate) fn solve<R: Ring>(
        &self,
        a_hat: &[SparseRow<R>],
        v: &[BigInt],
        b_hat: &[Rational],
        hints: &[Rational],
        grid_bits: u32,
    ) -> Option<SnappedSolve> {
        // ρ = Â h − b̂, each entry summed exactly over an unreduced common denominator.
        let rho: Vec<f64> = a_hat
            .iter()
            .zip(b_hat)
            .map(|(row, b)| {
                let mut sum = UnreducedSum::from(&-b.clone());
                for (c, x) in row {
                    sum.add_scaled(&hints[*c], &x.to_bigint());
                }
                sum.to_f64()
            })
            .collect();
        // G λ̃ = ρ and x̃ = h − V Âᵀ λ̃ in f64.
        let mut lambda = rho;
        self.normal.solve_in_place(&mut lambda);
        let mut approx: Vec<f64> = hints.iter().map(rational_to_f64).collect();
        for (row, l) in self.a_float.iter().zip(&lambda) {
            for (c, a) in row {
                approx[*c] -= self.v_float[*c] * a * l;
            }
        }
        // Free columns on the grid, basic ones exactly.
        let scale = 2f64.powi(i32::try_from(grid_bits).ok()?);
        let denominator = BigInt::from(1) << grid_bits;
        let mut x: Vec<Rational> = Vec::with_capacity(approx.len());
        for (c, a) in approx.iter().enumerate() {
            x.push(if self.basis.is_free(c) {
                Rational::new(BigInt::from_f64((a * scale).round())?, denominator.clone())
            } else {
                Rational::zero()
            });
        }
        self.basis.solve(a_hat, b_hat, &mut x);
        let distance_bound = self.distance_bound(&x, hints, v, &lambda);
        Some(SnappedSolve {
            values: x,
            distance_bound,
        })
    }

    /// `sqrt(V_max Σ_s (x_s − x̂_s)² / V_s)` rounded up, with `x̂ = h − V Âᵀ λ̂` for the
    /// multipliers `lambda` on a dyadic grid (module documentation): each difference is exact,
    /// and the sum of nonnegative terms is taken in `f64` with its rounding error covered.
    fn distance_bound(
        &self,
        x: &[Rational],
        hints: &[Rational],
        v: &[BigInt],
        lambda: &[f64],
    ) -> f64 {
        let n = x.len();
        // Âᵀ λ̂ = (Âᵀ L) / 2^shift with integers L.
        let largest = lambda.iter().fold(0f64, |m, l| m.max(l.abs()));
        let shift = if largest > 0.0 && largest.is_finite() {
            52 - largest.log2().ceil() as i64
        } else {
            0
        };
        let mut combined = vec![<BigInt as Zero>::zero(); n];
        if largest > 0.0 && largest.is_finite() {
            for (row, l) in self.a_exact.iter().zip(lambda) {
                let l = dyadic_integer(*l, shift);
                if Zero::is_zero(&l) {
                    continue;
                }
                for (c, a) in row {
                    combined[*c] += a * &l;
                }
            }
        }
        let (multiplier, denominator) = dyadic_scale(shift);
        let mut sum = 0f64;
        for s in 0..n {
            // x_s − x̂_s = (x_s − h_s) + V_s (Âᵀ L)_s / 2^shift, exactly, unreduced.
            let mut d = UnreducedSum::from(&x[s]);
            d.add_scaled(&hints[s], &BigInt::from(-1));
            d.add(&(&v[s] * &combined[s] * &multiplier), &denominator);
            let d = d.to_f64().abs();
            sum += d * d / self.v_float[s];
        }
        // Terms below the normal range lose relative precision: their absolute error is covered
        // by the smallest normal number.
        sum += f64::MIN_POSITIVE;
        // Each term is within a factor (1 ± 2⁻⁵²)⁴ of its exact value (the rounding of the
        // difference, of V_s, the square and the quotient) and the sum of n nonnegative terms
        // within (1 ± 2⁻⁵³)ⁿ: covered by (1 + (n + 8)·2⁻⁵²), then for the product with V_max
        // and the square root.
        let up = 1.0 + (n as f64 + 16.0) * f64::EPSILON;
        (sum * up * big_to_f64(&self.v_max) * up).sqrt() * up
    }
}

/// `round(l · 2^shift)` as an integer.
fn dyadic_integer(l: f64, shift: i64) -> BigInt {
    let (mantissa, exponent) = decompose(l);
    let e = exponent + shift;
    if e >= 0 {
        mantissa << e as usize
    } else {
        // Round to nearest: add half before the shift (toward +∞ for ties: any λ̂ gives a
        // valid bound).
        let e = (-e) as usize;
        (mantissa + (BigInt::from(1) << (e - 1))) >> e
    }
}

/// `l = mantissa · 2^exponent` exactly.
fn decompose(l: f64) -> (BigInt, i64) {
    if l == 0.0 {
        return (<BigInt as Zero>::zero(), 0);
    }
    let bits = l.to_bits();
    let sign = if bits >> 63 == 1 { -1 } else { 1 };
    let raw_exponent = ((bits >> 52) & 0x7ff) as i64;
    let fraction = bits & ((1u64 << 52) - 1);
    let (mantissa, exponent) = if raw_exponent == 0 {
        (fraction, -1074)
    } else {
        (fraction | (1u64 << 52), raw_exponent - 1075)
    };
    (BigInt::from(sign) * BigInt::from(mantissa), exponent)
}

/// `2^−e` as `(multiplier, denominator)`: `(1, 2^e)` for `e ≥ 0`, `(2^−e, 1)` otherwise.
fn dyadic_scale(e: i64) -> (BigInt, BigInt) {
    if e >= 0 {
        (BigInt::from(1), BigInt::from(1) << e as usize)
    } else {
        (BigInt::from(1) << (-e) as usize, BigInt::from(1))
    }
}

/// A sum of rationals over a common denominator that is never reduced (no GCD): for values
/// that are only converted to `f64` afterwards, or reduced once at the end.
pub(crate) struct UnreducedSum {
    numerator: BigInt,
    denominator: BigInt,
}

impl UnreducedSum {
    /// The sum holding `x`.
    pub(crate) fn from(x: &Rational) -> Self {
        UnreducedSum {
            numerator: x.numer().clone(),
            denominator: x.denom().clone(),
        }
    }

    /// Adds `k · x`.
    pub(crate) fn add_scaled(&mut self, x: &Rational, k: &BigInt) {
        if Zero::is_zero(x.numer()) || Zero::is_zero(k) {
            return;
        }
        self.add(&(x.numer() * k), x.denom());
    }

    /// Adds `numerator / denominator` (`denominator > 0`).
    pub(crate) fn add(&mut self, numerator: &BigInt, denominator: &BigInt) {
        if Zero::is_zero(numerator) {
            return;
        }
        if *denominator == self.denominator {
            self.numerator += numerator;
        } else {
            self.numerator = &self.numerator * denominator + numerator * &self.denominator;
            self.denominator *= denominator;
        }
    }

    /// The nearest `f64` (one rounding).
    pub(crate) fn to_f64(&self) -> f64 {
        api::exact::rational_to_f64_nearest(&Rational::new_raw(
            self.numerator.clone(),
            self.denominator.clone(),
        ))
    }

    /// The sum in lowest terms.
    pub(crate) fn reduced(self) -> Rational {
        crate::gcd::reduced_ratio(self.numerator, self.denominator)
    }

    /// The sum divided by `divisor` (nonzero), in lowest terms.
    pub(crate) fn divided_by(self, divisor: &BigInt) -> Rational {
        crate::gcd::reduced_ratio(self.numerator, self.denominator * divisor)
    }
}

fn big_to_f64(x: &BigInt) -> f64 {
    rational_to_f64(&Rational::from_integer(x.clone()))
}
