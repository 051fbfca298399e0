//! Declaring a spline's control points and conditions in a shared constraint system, and the
//! counts a report gives of it.

use crate::spline::Spline;
use api::{
    ConstraintRow, ConstraintSystem, Contribution, Integer, NewParameter, Origin, ParamId,
    Rational, RowBody, SystemError, Values,
};

/// Where a spline's control points and conditions live in a [`ConstraintSystem`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SplineParams {
    /// Prefix of every parameter name and row label (the source's name).
    pub prefix: String,
    /// Coordinates per control point: 2 for a deformation of the plane, 1 for a scalar spline.
    pub dim: usize,
    /// The parameter of each control point: consecutive ids, from the first one on.
    pub ids: Vec<ParamId>,
}

impl SplineParams {
    /// The control point of a parameter, if it belongs to this spline (the ids are consecutive,
    /// so this is a subtraction, not a map a million entries long).
    pub fn point_of(&self, id: ParamId) -> Option<usize> {
        let first = self.ids.first()?.index();
        let k = id.index().checked_sub(first)?;
        (k < self.ids.len()).then_some(k)
    }

    /// The current positions of all control points.
    pub fn positions(&self, values: &Values) -> Vec<Vec<Rational>> {
        self.ids.iter().map(|id| values.get(*id).to_vec()).collect()
    }
}

impl Spline {
    /// The parameters and rows of this spline as a [`Contribution`] to a system that already
    /// has `existing` parameters: one parameter of dimension `dim` per control point (named
    /// `{prefix}.{point name}`, initial value from `initial`) and one vector row per condition
    /// (labelled `{prefix}: {condition label}`, origin `spline2d` / the condition).
    ///
    /// # Panics
    /// Panics if `initial` does not have one value of length `dim` per control point.
    pub fn contribution(
        &self,
        prefix: &str,
        dim: usize,
        existing: usize,
        initial: Vec<Vec<Rational>>,
    ) -> (Contribution, SplineParams) {
        assert_eq!(
            initial.len(),
            self.points().len(),
            "one value per control point"
        );
        let ids: Vec<ParamId> = (0..self.points().len())
            .map(|k| ParamId((existing + k) as u32))
            .collect();
        let parameters = self
            .points()
            .iter()
            .zip(initial)
            .map(|(p, value)| {
                assert_eq!(value.len(), dim, "values have the spline's dimension");
                NewParameter {
                    name: joined(prefix, ".", &p.name),
                    value,
                }
            })
            .collect();
        // The conditions are made one at a time and moved into their rows: a whole mesh's
        // conditions are never held twice.
        let mut rows = Vec::with_capacity(self.condition_bound());
        self.for_each_condition(|c| {
            rows.push(ConstraintRow {
                label: joined(prefix, ": ", &c.label),
                origin: Origin {
                    source: prefix.to_string(),
                    item: c.label,
                },
                body: RowBody::Vector {
                    terms: c.terms.into_iter().map(|(p, v)| (ids[p], v)).collect(),
                    rhs: vec![Integer::from(0); dim],
                },
            })
        });
        let params = SplineParams {
            prefix: prefix.to_string(),
            dim,
            ids,
        };
        (
            Contribution {
                parameters,
                rows,
                ..Contribution::default()
            },
            params,
        )
    }

    /// Declares the spline in `system` with `values` (see [`Spline::contribution`]), all or
    /// nothing.
    pub fn declare(
        &self,
        system: &mut ConstraintSystem,
        values: &mut Values,
        prefix: &str,
        initial: Vec<Vec<Rational>>,
    ) -> Result<SplineParams, SystemError> {
        let dim = initial.first().map_or(1, Vec::len);
        let (contribution, params) = self.contribution(prefix, dim, system.params().len(), initial);
        contribution.apply_to(system, values)?;
        Ok(params)
    }

    /// The identity deformation: every control point at its nominal position.
    pub fn identity_positions(&self) -> Vec<Vec<Rational>> {
        let mut out = vec![Vec::new(); self.points().len()];
        self.for_each_nominal(|point, position| out[point] = position.to_vec());
        out
    }

    /// The counts a report gives of every source built on this spline, as `(key, count)`:
    /// the mesh (`vertices`, `edges`, `interior_edges`, `interior_vertices`, `triangles`) and
    /// the spline space (`degree`, `smoothness`, `spline_space_dimension`). Sources add their
    /// own (control points and conditions per surface, say).
    pub fn summary_counts(&self) -> Vec<(&'static str, usize)> {
        let topology = self.topology();
        vec![
            ("vertices", self.mesh().vertices().len()),
            ("edges", topology.edges.len()),
            ("interior_edges", topology.interior_edges()),
            ("interior_vertices", topology.interior_vertices()),
            ("triangles", self.mesh().triangles().len()),
            ("degree", self.degree()),
            ("smoothness", self.smoothness()),
            ("spline_space_dimension", self.spline_space_dimension()),
        ]
    }

    /// A constant scalar spline (a flat surface at height `value`).
    pub fn constant_positions(&self, value: &Rational) -> Vec<Vec<Rational>> {
        vec![vec![value.clone()]; self.points().len()]
    }
}

/// `a`, `between` and `b` in one string of exactly their length (a whole mesh names millions of
/// parameters and rows this way; `format!` and its growth were a tenth of building one).
fn joined(a: &str, between: &str, b: &str) -> String {
    let mut out = String::with_capacity(a.len() + between.len() + b.len());
    out.push_str(a);
    out.push_str(between);
    out.push_str(b);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spline::tests::grid;

    #[test]
    fn declared_identity_satisfies_every_condition() {
        let spline = Spline::new(grid(2, true), 5, 1).expect("spline");
        let mut system = ConstraintSystem::new();
        let mut values = Values::default();
        let params = spline
            .declare(&mut system, &mut values, "phi", spline.identity_positions())
            .expect("declare");
        assert_eq!(params.ids.len(), 121);
        assert_eq!(system.rows().len(), 40);
        assert!(system.violations(&values).is_empty());
        assert_eq!(params.point_of(params.ids[7]), Some(7));
        assert_eq!(&*system.params()[params.ids[0].index()].name, "phi.v0");
        assert!(system.rows()[0].label.starts_with("phi: C1 edge"));
        // Declaring the same prefix twice is refused, and changes nothing.
        let before = system.clone();
        assert!(spline
            .declare(&mut system, &mut values, "phi", spline.identity_positions())
            .is_err());
        assert_eq!(system, before);
    }
}
