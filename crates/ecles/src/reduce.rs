//! The reduced system of an edit (thesis 5.2, algorithm 1): with `E` the relevant rows, `D` the
//! derived and `A` the anchor parameters and `F'` the fixed relevant ones,
//!
//! ```text
//! R_ED x = b(α),   b(α) = c − R_EA α,   c = q_E − R_EF' P_F'
//! ```
//!
//! [`ReducedSystem`] is the one owner of `R_ED`: ECLES factors it, and reports (the
//! Dulmage–Mendelsohn view of an edit) describe exactly this matrix. Its layout is either one
//! unknown per parameter with the coordinates as right-hand-side columns ([`Layout::Vector`]),
//! or one unknown per coordinate with vector rows split by [`api::RowBody::scalar_equations`]
//! ([`Layout::Scalar`]).

use crate::edit::{EditSpec, Layout, RowRef};
use crate::relevant::Relevant;
use api::{
    rational_difference, rational_times_integer, ConstraintSystem, Coord, IntMatrix, Integer,
    ParamId, Rational, RhsFamily, RowBody, Values,
};

/// `R_ED`, the family `b(α) = c − R_EA α` and what each row of `R_ED` is.
#[derive(Debug, Clone, PartialEq)]
pub struct ReducedSystem {
    pub(crate) layout: Layout,
    pub(crate) r_ed: IntMatrix,
    pub(crate) family: RhsFamily,
    pub(crate) rows: Vec<RowRef>,
    pub(crate) labels: Vec<String>,
}

impl ReducedSystem {
    /// How unknowns and right-hand sides are laid out.
    pub fn layout(&self) -> Layout {
        self.layout
    }

    /// `R_ED`: one row per relevant row (per coordinate in the scalar layout), one column per
    /// derived parameter (per derived coordinate in the scalar layout).
    pub fn r_ed(&self) -> &IntMatrix {
        &self.r_ed
    }

    /// `c` (one column per coordinate in the vector layout) and `R_EA`.
    pub fn family(&self) -> &RhsFamily {
        &self.family
    }

    /// The constraint (and coordinate, for split rows) of each row of `R_ED`.
    pub fn rows(&self) -> &[RowRef] {
        &self.rows
    }

    /// The label of each row of `R_ED` (the constraint's label).
    pub fn labels(&self) -> &[String] {
        &self.labels
    }
}

/// Where a parameter sits in the reduced system.
#[derive(Clone, Copy)]
enum Role {
    Anchor(usize),
    Derived(usize),
}

/// Chooses the layout and builds `R_ED`, `R_EA` and the constant parts `q_E − R_EF' P_F'`.
pub(crate) fn reduce(
    system: &ConstraintSystem,
    values: &Values,
    spec: &EditSpec,
    relevant: &Relevant,
) -> ReducedSystem {
    let dim_of = |p: &ParamId| system.params()[p.index()].dim;
    // A projection has no anchors: its first derived parameter sets the dimension.
    let first_dim = spec
        .anchors
        .first()
        .or(spec.derived.first())
        .map_or(1, dim_of);
    let uniform = spec
        .anchors
        .iter()
        .chain(&spec.derived)
        .chain(&relevant.fixed)
        .all(|p| dim_of(p) == first_dim);
    let all_vector = relevant.constraints.iter().all(|r| {
        matches!(&system.rows()[r.index()].body, RowBody::Vector { rhs, .. } if rhs.len() == first_dim)
    });
    let layout = if uniform && all_vector {
        Layout::Vector { dim: first_dim }
    } else {
        Layout::Scalar
    };

    // The role of each editable parameter, sorted by id for binary search (no hashing: the
    // ids are distinct, validated by `Edit::initialize`).
    let mut roles: Vec<(ParamId, Role)> = spec
        .anchors
        .iter()
        .enumerate()
        .map(|(k, p)| (*p, Role::Anchor(k)))
        .chain(
            spec.derived
                .iter()
                .enumerate()
                .map(|(k, p)| (*p, Role::Derived(k))),
        )
        .collect();
    roles.sort_unstable_by_key(|(p, _)| *p);
    let role = |p: &ParamId| {
        roles
            .binary_search_by_key(p, |(q, _)| *q)
            .ok()
            .map(|i| &roles[i].1)
    };

    let mut ed_rows = Vec::new();
    let mut ea_rows = Vec::new();
    let mut rows = Vec::new();
    let mut labels = Vec::new();
    match layout {
        Layout::Vector { dim } => {
            let mut constant = vec![Vec::with_capacity(relevant.constraints.len()); dim];
            for &id in &relevant.constraints {
                let row = &system.rows()[id.index()];
                let RowBody::Vector { terms, rhs } = &row.body else {
                    unreachable!("vector layout has only vector rows")
                };
                let mut ed = Vec::with_capacity(terms.len());
                let mut ea = Vec::new();
                let mut c: Vec<Rational> = rhs
                    .iter()
                    .map(|q| Rational::from_integer(q.clone()))
                    .collect();
                for (p, coeff) in terms {
                    match role(p) {
                        Some(Role::Derived(k)) => ed.push((*k, coeff.clone())),
                        Some(Role::Anchor(k)) => ea.push((*k, coeff.clone())),
                        None => {
                            for (cj, pj) in c.iter_mut().zip(values.get(*p)) {
                                *cj = rational_difference(cj, &rational_times_integer(pj, coeff));
                            }
                        }
                    }
                }
                for (column, cj) in constant.iter_mut().zip(c) {
                    column.push(cj);
                }
                ed_rows.push(ed);
                ea_rows.push(ea);
                rows.push(RowRef {
                    row: id,
                    component: None,
                });
                labels.push(row.label.clone());
            }
            let r_ed = IntMatrix::from_sparse(spec.derived.len(), ed_rows)
                .expect("columns index derived parameters");
            let r_ea =
                IntMatrix::from_sparse(spec.anchors.len(), ea_rows).expect("columns index anchors");
            ReducedSystem {
                layout,
                r_ed,
                family: RhsFamily {
                    constant,
                    coefficients: r_ea,
                },
                rows,
                labels,
            }
        }
        Layout::Scalar => {
            let offsets = |ids: &[ParamId]| -> (Vec<usize>, usize) {
                let mut out = Vec::with_capacity(ids.len());
                let mut next = 0;
                for p in ids {
                    out.push(next);
                    next += dim_of(p);
                }
                (out, next)
            };
            let (d_off, d_cols) = offsets(&spec.derived);
            let (a_off, a_cols) = offsets(&spec.anchors);
            let capacity = relevant.constraints.len();
            let mut constant = Vec::with_capacity(capacity);
            ed_rows.reserve(capacity);
            ea_rows.reserve(capacity);
            rows.reserve(capacity);
            labels.reserve(capacity);
            for &id in &relevant.constraints {
                let row = &system.rows()[id.index()];
                let mut push = |component: Option<usize>,
                                terms: &mut dyn Iterator<Item = (Coord, &Integer)>,
                                rhs: &Integer| {
                    // Most terms are derived: one allocation of the row, no growth.
                    let mut ed = Vec::with_capacity(terms.size_hint().0);
                    let mut ea = Vec::new();
                    let mut c = Rational::from_integer(rhs.clone());
                    for (coord, coeff) in terms {
                        match role(&coord.param) {
                            Some(Role::Derived(k)) => {
                                ed.push((d_off[*k] + coord.component, coeff.clone()))
                            }
                            Some(Role::Anchor(k)) => {
                                ea.push((a_off[*k] + coord.component, coeff.clone()))
                            }
                            None => {
                                c = rational_difference(
                                    &c,
                                    &rational_times_integer(
                                        &values.get(coord.param)[coord.component],
                                        coeff,
                                    ),
                                );
                            }
                        }
                    }
                    constant.push(c);
                    ed_rows.push(ed);
                    ea_rows.push(ea);
                    rows.push(RowRef { row: id, component });
                    labels.push(row.label.clone());
                };
                match &row.body {
                    // A scalar row is one equation as it stands (no split, no copy).
                    RowBody::Scalar { terms, rhs } => {
                        push(None, &mut terms.iter().map(|(c, v)| (*c, v)), rhs)
                    }
                    RowBody::Vector { .. } => {
                        for equation in row.body.scalar_equations() {
                            push(equation.component(), &mut equation.terms(), equation.rhs());
                        }
                    }
                }
            }
            let r_ed =
                IntMatrix::from_sparse(d_cols, ed_rows).expect("columns index derived coordinates");
            let r_ea =
                IntMatrix::from_sparse(a_cols, ea_rows).expect("columns index anchor coordinates");
            ReducedSystem {
                layout,
                r_ed,
                family: RhsFamily {
                    constant: vec![constant],
                    coefficients: r_ea,
                },
                rows,
                labels,
            }
        }
    }
}

/// ExtractRelevant and the reduced system of an edit, after the checks of
/// [`crate::Edit::initialize`] on `spec` (anchors, ids, overlaps, weights): what ECLES would
/// factor, for reports that describe an edit whether or not it can be initialised.
pub fn reduce_edit<S: std::fmt::Debug>(
    system: &ConstraintSystem,
    values: &Values,
    spec: &EditSpec,
) -> Result<(Relevant, ReducedSystem), crate::EditError<S>> {
    crate::edit::validate_spec::<S>(system, values, spec)?;
    let relevant = crate::relevant::extract_relevant(system, &spec.anchors, &spec.derived);
    let reduced = reduce(system, values, spec, &relevant);
    Ok((relevant, reduced))
}
