//! Drags along a straight line: when the anchor values and the hints both move linearly with a
//! parameter `t` (a soft translation or a vertical raise: anchors `a0 + t (a1 − a0)`, hints
//! `h0 + t (h1 − h0)`), the solution of ECLES.Update is affine in `(anchors, hints)` and therefore
//! exactly `x(t) = x0 + t (x1 − x0)`. Two updates at the ends give every point of the drag:
//! drawing a frame is a linear interpolation, and the exact value at any `t` is one
//! multiply-add per coordinate.

use crate::edit::Edit;
use crate::error::EditError;
use api::{Factorization, ParamId, Rational, Value};

/// A drag between two sets of anchor values and hints, solved at both ends.
#[derive(Debug, Clone)]
pub struct Drag<S> {
    anchors: Vec<ParamId>,
    derived: Vec<ParamId>,
    start_anchors: Vec<Vec<Rational>>,
    end_anchors: Vec<Vec<Rational>>,
    start: Vec<Vec<S>>,
    end: Vec<Vec<S>>,
    start_f64: Vec<Vec<f64>>,
    end_f64: Vec<Vec<f64>>,
}

impl<F: Factorization> Edit<F> {
    /// Solves the edit at both ends of a straight drag. Every intermediate position is then
    /// solvable too (the solvable anchor values form an affine set), so the drag can only fail
    /// here.
    pub fn drag(
        &self,
        start_anchors: &[Vec<Rational>],
        start_hints: &[Vec<Rational>],
        end_anchors: &[Vec<Rational>],
        end_hints: &[Vec<Rational>],
    ) -> Result<Drag<F::Scalar>, EditError<F::Scalar>> {
        let start = self.update(start_anchors, start_hints)?;
        let end = self.update(end_anchors, end_hints)?;
        let values = |r: &crate::UpdateResult<F::Scalar>| -> Vec<Vec<F::Scalar>> {
            r.derived.iter().map(|(_, v)| v.clone()).collect()
        };
        let (start, end) = (values(&start), values(&end));
        let floats = |v: &[Vec<F::Scalar>]| -> Vec<Vec<f64>> {
            v.iter()
                .map(|p| p.iter().map(Value::to_f64).collect())
                .collect()
        };
        Ok(Drag {
            anchors: self.anchors().to_vec(),
            derived: self.derived().to_vec(),
            start_anchors: start_anchors.to_vec(),
            end_anchors: end_anchors.to_vec(),
            start_f64: floats(&start),
            end_f64: floats(&end),
            start,
            end,
        })
    }
}

impl<S> Drag<S> {
    /// The anchors, in the order of their values.
    pub fn anchors(&self) -> &[ParamId] {
        &self.anchors
    }

    /// The derived parameters, in the order of their values.
    pub fn derived(&self) -> &[ParamId] {
        &self.derived
    }

    /// The derived values at `t` (0 at the start, 1 at the end), rounded, for drawing a frame.
    pub fn preview(&self, t: f64) -> Vec<Vec<f64>> {
        self.start_f64
            .iter()
            .zip(&self.end_f64)
            .map(|(a, b)| a.iter().zip(b).map(|(x, y)| x + t * (y - x)).collect())
            .collect()
    }
}

impl Drag<Rational> {
    /// The exact anchor and derived values at `t`: exactly what [`Edit::update`] returns for the
    /// interpolated anchor values and hints.
    pub fn at(&self, t: &Rational) -> (Vec<Vec<Rational>>, Vec<Vec<Rational>>) {
        let lerp = |a: &[Vec<Rational>], b: &[Vec<Rational>]| -> Vec<Vec<Rational>> {
            a.iter()
                .zip(b)
                .map(|(p, q)| p.iter().zip(q).map(|(x, y)| x + t * (y - x)).collect())
                .collect()
        };
        (
            lerp(&self.start_anchors, &self.end_anchors),
            lerp(&self.start, &self.end),
        )
    }
}
