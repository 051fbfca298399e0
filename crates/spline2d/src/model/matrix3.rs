//! 3 × 3 matrices in `f64` for the normals and tangents of deformed models: a normal moves by
//! the inverse transpose of the deformation's Jacobian, a tangent by the Jacobian, each kept at
//! its length.

/// A 3 × 3 matrix, rows first.
pub(super) type Matrix = [[f64; 3]; 3];

/// `a · b`.
pub(super) fn multiply(a: &Matrix, b: &Matrix) -> Matrix {
    let mut out = [[0.0; 3]; 3];
    for (r, row) in out.iter_mut().enumerate() {
        for (c, x) in row.iter_mut().enumerate() {
            *x = (0..3).map(|k| a[r][k] * b[k][c]).sum();
        }
    }
    out
}

/// `m⁻¹`; `None` when `m` is singular or its determinant is not finite.
pub(super) fn invert(m: &Matrix) -> Option<Matrix> {
    let cofactor = |r: usize, c: usize| {
        let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
        let (c1, c2) = ((c + 1) % 3, (c + 2) % 3);
        m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]
    };
    let det: f64 = (0..3).map(|c| m[0][c] * cofactor(0, c)).sum();
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let mut out = [[0.0; 3]; 3];
    for (r, row) in out.iter_mut().enumerate() {
        for (c, x) in row.iter_mut().enumerate() {
            // The inverse is the transposed cofactor matrix over the determinant.
            *x = cofactor(c, r) / det;
        }
    }
    Some(out)
}

/// `J^{−T} n` rescaled to the length of `n`; `None` when `J` is singular or the result is not
/// finite.
pub(super) fn transform_normal(j: &Matrix, n: [f64; 3]) -> Option<[f64; 3]> {
    let inverse = invert(j)?;
    // (J⁻¹)ᵀ n.
    let out = [0, 1, 2].map(|r| (0..3).map(|k| inverse[k][r] * n[k]).sum::<f64>());
    rescaled(out, &n)
}

/// `J t` rescaled to the length of `t`; `None` when it vanishes or is not finite.
pub(super) fn transform_tangent(j: &Matrix, t: [f64; 3]) -> Option<[f64; 3]> {
    let out = [0, 1, 2].map(|r| (0..3).map(|c| j[r][c] * t[c]).sum::<f64>());
    rescaled(out, &t)
}

/// `v` rescaled to the length of `like`; `None` when `v` vanishes or a result is not finite.
fn rescaled(v: [f64; 3], like: &[f64; 3]) -> Option<[f64; 3]> {
    let length = |v: &[f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let (old, new) = (length(like), length(&v));
    if new == 0.0 || !new.is_finite() {
        return None;
    }
    let scale = old / new;
    let result = v.map(|x| x * scale);
    result.iter().all(|x| x.is_finite()).then_some(result)
}
