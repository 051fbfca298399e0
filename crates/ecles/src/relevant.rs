//! ECLES.ExtractRelevant (thesis, algorithm 2).

use api::{ConstraintSystem, ParamId, RowId};

/// The part of the system an edit touches.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Relevant {
    /// `E`: rows involving a parameter of `A ∪ D`, increasing.
    pub constraints: Vec<RowId>,
    /// `F'`: parameters outside `A ∪ D` that occur in a row of `E`, increasing.
    pub fixed: Vec<ParamId>,
}

/// Finds the relevant constraints `E` and the fixed relevant parameters `F'` of an edit with
/// anchors `anchors` and derived parameters `derived`.
///
/// Uses the parameter→row incidence of the system, so the cost is proportional to the rows
/// touched, not to the size of the system.
///
/// # Panics
/// Panics if an id is not a parameter of `system` ([`crate::Edit::initialize`] validates ids
/// before calling this).
pub fn extract_relevant(
    system: &ConstraintSystem,
    anchors: &[ParamId],
    derived: &[ParamId],
) -> Relevant {
    // Sorted vectors, not ordered sets: the same sorted, duplicate-free answers with one
    // allocation each (an edit of a few points is initialised in microseconds).
    let mut editable: Vec<ParamId> = anchors.iter().chain(derived).copied().collect();
    editable.sort_unstable();
    editable.dedup();
    let mut constraints: Vec<RowId> = editable
        .iter()
        .flat_map(|p| system.rows_of(*p).iter().copied())
        .collect();
    constraints.sort_unstable();
    constraints.dedup();
    let mut fixed = Vec::new();
    for row in &constraints {
        let body = &system.rows()[row.index()].body;
        fixed.extend(
            body.term_params()
                .filter(|p| editable.binary_search(p).is_err()),
        );
    }
    fixed.sort_unstable();
    fixed.dedup();
    Relevant { constraints, fixed }
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::{ConstraintRow, Origin, RowBody};

    /// The classification of figure 2.2 in miniature: rows without editable parameters are not
    /// relevant, and fixed parameters outside relevant rows are not in F'.
    #[test]
    fn classifies_rows_and_fixed_parameters() {
        let mut s = ConstraintSystem::new();
        let p: Vec<ParamId> = (0..6)
            .map(|i| s.add_parameter(format!("p{i}"), 1).expect("fresh name"))
            .collect();
        let row = |terms: &[usize]| ConstraintRow {
            label: format!("{terms:?}"),
            origin: Origin::default(),
            body: RowBody::Vector {
                terms: terms.iter().map(|&i| (p[i], 1.into())).collect(),
                rhs: vec![0.into()],
            },
        };
        s.add_row(row(&[0, 1])).expect("row");
        s.add_row(row(&[2, 3])).expect("row");
        s.add_row(row(&[1, 4])).expect("row");
        let rel = extract_relevant(&s, &[p[0]], &[p[4]]);
        assert_eq!(rel.constraints, vec![RowId(0), RowId(2)]);
        assert_eq!(rel.fixed, vec![p[1]]);
    }
}
