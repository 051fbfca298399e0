//! Evaluating a [`FloatSpline`]: values and displacements at barycentric coordinates or at
//! points of the plane, and their partial derivatives, without allocating on the hot paths.

use super::{Base, FloatSpline};
use crate::eval::Locator;

/// Degrees up to this use a stack buffer for the powers of `β` in evaluation.
const STACK_DEGREE: usize = 31;
/// Degrees up to this use a smaller stack buffer.
const SMALL_DEGREE: usize = 7;

impl FloatSpline {
    /// Reference `c` on triangle `t` at `beta` (the identity as `Σ βk·vk`).
    #[inline]
    fn base_at(&self, t: usize, beta: [f64; 3], c: usize) -> f64 {
        match self.bases[c] {
            Base::Zero => 0.0,
            Base::Constant(v) => v,
            Base::Identity(axis) => {
                let k = &self.corners[t];
                beta[0] * k[0][axis] + beta[1] * k[1][axis] + beta[2] * k[2][axis]
            }
        }
    }

    /// Reference `c` at the point `p` (the identity is `p` itself).
    #[inline]
    fn base_at_point(&self, p: [f64; 2], c: usize) -> f64 {
        match self.bases[c] {
            Base::Zero => 0.0,
            Base::Constant(v) => v,
            Base::Identity(axis) => p[axis],
        }
    }

    /// `φ` on triangle `t` at barycentric coordinates `beta`; `None` if `t` is not a triangle.
    pub fn evaluate(&self, t: usize, beta: [f64; 3]) -> Option<Vec<f64>> {
        if t >= self.triangle_count() {
            return None;
        }
        let mut out = vec![0.0; self.dim];
        self.evaluate_into(t, beta, &mut out);
        Some(out)
    }

    /// `φ` on triangle `t` at `beta`, written to `out` without allocating (for degrees up to
    /// 31): the reference at `beta` (the identity as `Σ βk·vk` from the rounded corners) plus
    /// the displacement. For drawing; to map a point use
    /// [`FloatSpline::evaluate_point_into`], which takes the identity from the point itself.
    ///
    /// # Panics
    /// If `t` is not a triangle or `out.len()` differs from [`FloatSpline::dim`].
    pub fn evaluate_into(&self, t: usize, beta: [f64; 3], out: &mut [f64]) {
        self.displacement_into(t, beta, out);
        let moved = self.displaced[t];
        for (c, o) in out.iter_mut().enumerate() {
            let base = self.base_at(t, beta, c);
            *o = if moved { base + *o } else { base };
        }
    }

    /// The displacement `D(β) = Σ B_i(β)·δ_i` from the references on triangle `t` at `beta`,
    /// written to `out` without allocating (zeros where [`FloatSpline::is_displaced`] is
    /// false). The hot path for deforming large models: the value is the reference plus this.
    /// Error bound: see [`FloatSpline`].
    ///
    /// # Panics
    /// If `t` is not a triangle or `out.len()` differs from [`FloatSpline::dim`].
    #[inline]
    pub fn displacement_into(&self, t: usize, beta: [f64; 3], out: &mut [f64]) {
        assert_eq!(
            out.len(),
            self.dim,
            "output has the wrong number of coordinates"
        );
        if !self.displaced[t] {
            out.fill(0.0);
            return;
        }
        let coefficients = &self.coefficients[t * self.stride..(t + 1) * self.stride];
        match self.dim {
            1 => {
                let mut o = [0.0; 1];
                self.sum::<1>(coefficients, beta, &mut o);
                out.copy_from_slice(&o);
            }
            2 => {
                let mut o = [0.0; 2];
                self.sum::<2>(coefficients, beta, &mut o);
                out.copy_from_slice(&o);
            }
            3 => {
                let mut o = [0.0; 3];
                self.sum::<3>(coefficients, beta, &mut o);
                out.copy_from_slice(&o);
            }
            4 => {
                let mut o = [0.0; 4];
                self.sum::<4>(coefficients, beta, &mut o);
                out.copy_from_slice(&o);
            }
            _ => self.sum_dyn(coefficients, beta, out),
        }
    }

    /// Fills `powers[a * (d + 1) + e] = beta[a]^e`.
    #[inline]
    fn powers(d: usize, beta: [f64; 3], powers: &mut [f64]) {
        for (a, b) in beta.iter().enumerate() {
            let row = &mut powers[a * (d + 1)..(a + 1) * (d + 1)];
            let mut acc = 1.0;
            for p in row.iter_mut() {
                *p = acc;
                acc *= b;
            }
        }
    }

    #[inline]
    fn with_powers<R>(&self, beta: [f64; 3], f: impl FnOnce(&[f64]) -> R) -> R {
        let d = self.degree;
        let n = 3 * (d + 1);
        if d <= SMALL_DEGREE {
            // Common degrees: a small buffer is cheaper to initialise.
            let mut stack = [0.0f64; 3 * (SMALL_DEGREE + 1)];
            Self::powers(d, beta, &mut stack[..n]);
            f(&stack[..n])
        } else if d <= STACK_DEGREE {
            let mut stack = [0.0f64; 3 * (STACK_DEGREE + 1)];
            Self::powers(d, beta, &mut stack[..n]);
            f(&stack[..n])
        } else {
            let mut heap = vec![0.0f64; n];
            Self::powers(d, beta, &mut heap);
            f(&heap)
        }
    }

    #[inline]
    fn sum<const K: usize>(&self, coefficients: &[f64], beta: [f64; 3], out: &mut [f64; K]) {
        let d = self.degree;
        self.with_powers(beta, |pw| {
            let (p0, rest) = pw.split_at(d + 1);
            let (p1, p2) = rest.split_at(d + 1);
            let mut chunks = coefficients.chunks_exact(K);
            for i in (0..=d).rev() {
                let a = p0[i];
                for j in (0..=d - i).rev() {
                    let w = a * p1[j] * p2[d - i - j];
                    if let Some(q) = chunks.next() {
                        for c in 0..K {
                            out[c] += w * q[c];
                        }
                    }
                }
            }
        });
    }

    fn sum_dyn(&self, coefficients: &[f64], beta: [f64; 3], out: &mut [f64]) {
        let d = self.degree;
        out.iter_mut().for_each(|o| *o = 0.0);
        self.with_powers(beta, |pw| {
            let (p0, rest) = pw.split_at(d + 1);
            let (p1, p2) = rest.split_at(d + 1);
            let mut chunks = coefficients.chunks_exact(self.dim);
            for i in (0..=d).rev() {
                for j in (0..=d - i).rev() {
                    let w = p0[i] * p1[j] * p2[d - i - j];
                    if let Some(q) = chunks.next() {
                        for (o, x) in out.iter_mut().zip(q) {
                            *o += w * x;
                        }
                    }
                }
            }
        });
    }

    /// The displacement `D` on triangle `t` at `beta` with its partial derivatives with
    /// respect to the three barycentric coordinates, taken as independent variables of the
    /// Bernstein form: `∂D/∂β0 = Σ_{i ≥ 1} i · β0^(i−1) β1^j β2^k · stored_{ijk}` and likewise
    /// for `β1`, `β2`. The derivative along a direction `u` of the plane is
    /// `Σ_a ∂D/∂β_a · ∂β_a/∂u` (the `∂β_a/∂u` of a triangle sum to zero, so a term common to
    /// the three partials does not matter). Returns the displacement (bit-identical to
    /// [`FloatSpline::displacement_into`]) and the three partials (each with
    /// [`FloatSpline::dim`] coordinates; all zero where [`FloatSpline::is_displaced`] is
    /// false); `None` if `t` is not a triangle.
    pub fn displacement_with_derivatives(
        &self,
        t: usize,
        beta: [f64; 3],
    ) -> Option<(Vec<f64>, [Vec<f64>; 3])> {
        if t >= self.triangle_count() {
            return None;
        }
        let d = self.degree;
        let dim = self.dim;
        let mut value = vec![0.0; dim];
        let mut partials = [vec![0.0; dim], vec![0.0; dim], vec![0.0; dim]];
        if !self.displaced[t] {
            return Some((value, partials));
        }
        let coefficients = &self.coefficients[t * self.stride..(t + 1) * self.stride];
        self.with_powers(beta, |pw| {
            let (p0, rest) = pw.split_at(d + 1);
            let (p1, p2) = rest.split_at(d + 1);
            // β^e and e·β^(e−1) for one coordinate.
            let power = |p: &[f64], e: usize| p[e];
            let derivative = |p: &[f64], e: usize| if e == 0 { 0.0 } else { e as f64 * p[e - 1] };
            let mut chunks = coefficients.chunks_exact(dim);
            for i in (0..=d).rev() {
                for j in (0..=d - i).rev() {
                    let k = d - i - j;
                    let Some(q) = chunks.next() else { return };
                    let (a, b, c) = (power(p0, i), power(p1, j), power(p2, k));
                    let weights = [
                        a * b * c,
                        derivative(p0, i) * b * c,
                        a * derivative(p1, j) * c,
                        a * b * derivative(p2, k),
                    ];
                    for (coordinate, x) in q.iter().enumerate() {
                        value[coordinate] += weights[0] * x;
                        for (partial, w) in partials.iter_mut().zip(&weights[1..]) {
                            partial[coordinate] += w * x;
                        }
                    }
                }
            }
        });
        Some((value, partials))
    }

    /// `φ` on triangle `t` at `beta` with its partial derivatives with respect to the three
    /// barycentric coordinates: the reference plus [`FloatSpline::displacement_with_derivatives`],
    /// the reference differentiated as the linear function `Σ βa·ra` (for the identity
    /// `∂/∂βa = va`, the corner; a constant has none). Partials of the degree-`d` Bernstein
    /// form differ from these by a term common to the three, so directional derivatives
    /// `Σ_a ∂φ/∂β_a · ∂β_a/∂u` are the same. The value is bit-identical to
    /// [`FloatSpline::evaluate`]; `None` if `t` is not a triangle.
    pub fn evaluate_with_derivatives(
        &self,
        t: usize,
        beta: [f64; 3],
    ) -> Option<(Vec<f64>, [Vec<f64>; 3])> {
        let (mut value, mut partials) = self.displacement_with_derivatives(t, beta)?;
        let moved = self.displaced[t];
        for (c, v) in value.iter_mut().enumerate() {
            let base = self.base_at(t, beta, c);
            *v = if moved { base + *v } else { base };
            if let Base::Identity(axis) = self.bases[c] {
                for (a, partial) in partials.iter_mut().enumerate() {
                    partial[c] += self.corners[t][a][axis];
                }
            }
        }
        Some((value, partials))
    }

    /// `φ(p)`: locates `p` with `locator` (built from the same mesh) and evaluates. `None` when
    /// `p` is outside the mesh or the locator belongs to a mesh with other triangles.
    pub fn evaluate_point(&self, locator: &Locator, p: [f64; 2]) -> Option<Vec<f64>> {
        let mut out = vec![0.0; self.dim];
        self.evaluate_point_into(locator, p, &mut out)
            .then_some(out)
    }

    /// Like [`FloatSpline::evaluate_point`] without allocating: writes `φ(p)` to `out` and
    /// returns `true`, or returns `false` (leaving `out` unchanged) when `p` is outside, the
    /// locator's triangle is not one of this spline's, or `out` has the wrong length.
    ///
    /// The value is the reference at `p` plus the displacement: an identity coordinate is
    /// `fl(x + D̂_x)` with `x` the input itself, so a point in a triangle that is not
    /// displaced ([`FloatSpline::is_displaced`]) comes back bit-identical and a displaced one
    /// is within the bound stated at [`FloatSpline`].
    pub fn evaluate_point_into(&self, locator: &Locator, p: [f64; 2], out: &mut [f64]) -> bool {
        if out.len() != self.dim {
            return false;
        }
        match locator.locate(p) {
            Some((t, beta)) if t < self.triangle_count() => {
                self.displacement_into(t, beta, out);
                let moved = self.displaced[t];
                for (c, o) in out.iter_mut().enumerate() {
                    let base = self.base_at_point(p, c);
                    *o = if moved { base + *o } else { base };
                }
                true
            }
            _ => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::test_support::*;
    use crate::eval::{evaluate_exact, evaluate_in_triangle};
    use crate::spline::tests::{grid, q, strip};
    use crate::spline::Spline;
    use api::exact::rational_to_f64;
    use api::Rational;

    #[test]
    fn corners_reproduce_control_points() {
        let spline = Spline::new(grid(2, true), 4, 1).expect("spline");
        // Arbitrary positions, three coordinates.
        let positions: Vec<Vec<Rational>> = (0..spline.points().len() as i64)
            .map(|i| vec![frac(i * 7 % 11, 3), q(i), frac(-i, 5)])
            .collect();
        let float = FloatSpline::new(&spline, &positions).expect("float");
        let d = spline.degree();
        for (t, tri) in spline.mesh().triangles().iter().enumerate() {
            for (corner, idx) in [[d, 0, 0], [0, d, 0], [0, 0, d]].into_iter().enumerate() {
                let point = spline.triangle_points(t)[spline.local_index(idx)];
                let mut beta = [q(0), q(0), q(0)];
                beta[corner] = q(1);
                let exact = evaluate_in_triangle(&spline, &positions, t, &beta).expect("value");
                assert_eq!(exact, positions[point]);
                let v = &spline.mesh().vertices()[tri[corner]];
                assert_eq!(
                    evaluate_exact(&spline, &positions, v).expect("inside"),
                    positions[point]
                );
                let mut bf = [0.0; 3];
                bf[corner] = 1.0;
                let f = float.evaluate(t, bf).expect("triangle");
                let expected: Vec<f64> = positions[point].iter().map(rational_to_f64).collect();
                assert_eq!(f, expected);
            }
        }
    }

    #[test]
    fn derivatives_match_the_identity_and_finite_differences() {
        let spline = Spline::new(grid(2, true), 5, 1).expect("spline");
        let identity = FloatSpline::new(&spline, &nominal(&spline)).expect("float");
        let mut rng = Rng(77);
        let positions: Vec<Vec<Rational>> = spline
            .points()
            .iter()
            .map(|_| vec![frac(rng.below(200) - 100, 7)])
            .collect();
        let bumpy = FloatSpline::new(&spline, &positions).expect("float");
        assert!(identity
            .evaluate_with_derivatives(99, [1.0, 0.0, 0.0])
            .is_none());
        for t in 0..spline.mesh().triangles().len() {
            let beta = [0.2, 0.5, 0.3];
            // Identity: the x coordinate changes by the change of x along any direction.
            let (value, partials) = identity.evaluate_with_derivatives(t, beta).expect("t");
            assert_eq!(Some(value.clone()), identity.evaluate(t, beta));
            let corners = spline.mesh().triangles()[t]
                .map(|v| spline.mesh().vertices()[v].clone())
                .map(|p| [rational_to_f64(&p[0]), rational_to_f64(&p[1])]);
            for c in 0..2 {
                // Moving from corner 0 to corner 1 is d/dβ1 − d/dβ0.
                let along = partials[1][c] - partials[0][c];
                let expected = corners[1][c] - corners[0][c];
                assert!((along - expected).abs() < 1e-9, "{along} vs {expected}");
            }
            // Arbitrary scalar values: central differences in barycentric directions.
            let (_, partials) = bumpy.evaluate_with_derivatives(t, beta).expect("t");
            let h = 1e-6;
            for (from, to) in [(0, 1), (1, 2), (2, 0)] {
                let mut plus = beta;
                let mut minus = beta;
                plus[to] += h;
                plus[from] -= h;
                minus[to] -= h;
                minus[from] += h;
                let f = |b: [f64; 3]| bumpy.evaluate(t, b).expect("t")[0];
                let numeric = (f(plus) - f(minus)) / (2.0 * h);
                let analytic = partials[to][0] - partials[from][0];
                assert!(
                    (numeric - analytic).abs() < 1e-5 * (1.0 + analytic.abs()),
                    "{numeric} vs {analytic}"
                );
            }
        }
    }

    #[test]
    fn high_degrees_and_many_coordinates_use_the_general_path() {
        let spline = Spline::new(strip(1), 33, 0).expect("spline");
        let positions: Vec<Vec<Rational>> = spline
            .nominals()
            .iter()
            .map(|p| vec![p[0].clone(), p[1].clone(), q(2), q(-1)])
            .collect();
        let float = FloatSpline::new(&spline, &positions).expect("float");
        let v = float.evaluate(0, [0.25, 0.25, 0.5]).expect("triangle");
        let x = |corner: usize| {
            let vertex = spline.mesh().triangles()[0][corner];
            rational_to_f64(&spline.mesh().vertices()[vertex][0])
        };
        let expected = 0.25 * x(0) + 0.25 * x(1) + 0.5 * x(2);
        assert!((v[0] - expected).abs() < 1e-9, "{} vs {expected}", v[0]);
        assert!((v[2] - 2.0).abs() < 1e-9 && (v[3] + 1.0).abs() < 1e-9);
    }
}
