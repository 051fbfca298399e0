//! Declaring a spline's control points and conditions in a shared constraint system.

use crate::spline::Spline;
use api::{
    ConstraintRow, ConstraintSystem, Integer, Origin, ParamId, Rational, RowBody, RowId,
    SystemError, Values,
};
use std::collections::HashMap;

/// Where a spline's control points and conditions live in a [`ConstraintSystem`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SplineParams {
    /// Prefix of every parameter name and row label (the source's name).
    pub prefix: String,
    /// Coordinates per control point: 2 for a deformation of the plane, 1 for a scalar spline.
    pub dim: usize,
    /// The parameter of each control point.
    pub ids: Vec<ParamId>,
    /// The row of each condition, in [`Spline::conditions`] order.
    pub rows: Vec<RowId>,
    /// Control point of each parameter id.
    point_of: HashMap<ParamId, usize>,
}

impl SplineParams {
    /// The control point of a parameter, if it belongs to this spline.
    pub fn point_of(&self, id: ParamId) -> Option<usize> {
        self.point_of.get(&id).copied()
    }

    /// The current positions of all control points.
    pub fn positions(&self, values: &Values) -> Vec<Vec<Rational>> {
        self.ids.iter().map(|id| values.get(*id).to_vec()).collect()
    }
}

impl Spline {
    /// Declares one parameter of dimension `dim` per control point (named
    /// `{prefix}.{point name}`) and one vector row per condition (labelled
    /// `{prefix}: {condition label}`, origin `spline2d` / the edge and order).
    pub fn declare(
        &self,
        system: &mut ConstraintSystem,
        prefix: &str,
        dim: usize,
    ) -> Result<SplineParams, SystemError> {
        let ids: Vec<ParamId> = self
            .points()
            .iter()
            .map(|p| system.add_parameter(format!("{prefix}.{}", p.name), dim))
            .collect::<Result<_, _>>()?;
        let rows = self
            .conditions()
            .iter()
            .map(|c| {
                system.add_row(ConstraintRow {
                    label: format!("{prefix}: {}", c.label),
                    origin: Origin {
                        source: "spline2d".into(),
                        item: c.label.clone(),
                    },
                    body: RowBody::Vector {
                        terms: c.terms.iter().map(|(p, v)| (ids[*p], v.clone())).collect(),
                        rhs: vec![Integer::from(0); dim],
                    },
                })
            })
            .collect::<Result<_, _>>()?;
        let point_of = ids.iter().enumerate().map(|(i, id)| (*id, i)).collect();
        Ok(SplineParams {
            prefix: prefix.to_string(),
            dim,
            ids,
            rows,
            point_of,
        })
    }

    /// The identity deformation: every control point at its nominal position.
    pub fn identity_positions(&self) -> Vec<Vec<Rational>> {
        self.points().iter().map(|p| p.nominal.to_vec()).collect()
    }

    /// A constant scalar spline (a flat surface at height `value`).
    pub fn constant_positions(&self, value: &Rational) -> Vec<Vec<Rational>> {
        vec![vec![value.clone()]; self.points().len()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spline::tests::grid;

    #[test]
    fn declared_identity_satisfies_every_condition() {
        let spline = Spline::new(grid(2, true), 5, 1).expect("spline");
        let mut system = ConstraintSystem::new();
        let params = spline.declare(&mut system, "phi", 2).expect("declare");
        assert_eq!(params.ids.len(), 121);
        assert_eq!(params.rows.len(), 40);
        let values = Values::from_vecs(&system, spline.identity_positions()).expect("values");
        assert!(system.violations(&values).is_empty());
        assert_eq!(params.point_of(params.ids[7]), Some(7));
        assert_eq!(system.params()[params.ids[0].index()].name, "phi.v0");
        assert!(system.rows()[0].label.starts_with("phi: C1 edge"));
        // Declaring the same prefix twice is refused by the system.
        assert!(spline.declare(&mut system, "phi", 2).is_err());
    }
}
