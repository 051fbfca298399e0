//! Solvability of an edit for the anchor moves actually requested.
//!
//! Strong solvability (algorithm 3) asks that *every* anchor value be reachable: every column
//! of `R_EA` in the range of `R_ED`. An operation that moves the anchors along a known path (a
//! translation, a rotation, a drag) needs less: with `Δ_k` the displacement of the anchors at
//! step `k` and `P_A` their current values, every step is solvable exactly when
//!
//! ```text
//! c − R_EA P_A ∈ range R_ED      (the current state, restricted to the edit)
//! R_EA Δ_k ∈ range R_ED          for every k
//! ```
//!
//! (`c = q_E − R_EF' P_F'`). Moving a point pinned in x along y is then solvable, and when a
//! move is not, the certificate names exactly the rows that block *that* move: a minimal set
//! `y` with `yᵀ R_ED = 0` and `yᵀ R_EA Δ_k ≠ 0`, checked by the backend. The displacements
//! are first reduced to a basis (exact elimination on vectors of anchor coordinates), so a
//! drag of many steps costs as many checks as it has independent directions.

use crate::edit::{validate_spec, Layout};
use crate::error::{Conflict, ConflictingRow, EditError};
use crate::reduce::{reduce, ReducedSystem};
use crate::relevant::extract_relevant;
use api::{
    ConstraintSystem, Factorization, IntMatrix, Integer, LinearBackend, Rational, RhsFamily,
    StrongFailure, Values,
};
use num_integer::Integer as _;
use num_traits::{One, Zero};

/// Checks that the edit `spec` can move its anchors by every displacement of `moves` (each one
/// vector per anchor, in anchor order, of the anchor's dimension), from `values`. `Ok` means
/// every anchor value `P_A + Σ t_k Δ_k` is weakly solvable; otherwise the error is
/// [`EditError::CurrentStateInconsistent`] (the current values already conflict within the
/// edit) or [`EditError::MoveBlocked`] with the rows that block one requested move.
pub fn check_moves<B, F>(
    backend: &B,
    system: &ConstraintSystem,
    values: &Values,
    spec: &crate::EditSpec,
    moves: &[Vec<Vec<Rational>>],
) -> Result<(), EditError<F::Scalar>>
where
    B: LinearBackend<Factorization = F>,
    F: Factorization,
{
    validate_spec::<F::Scalar>(system, values, spec)?;
    let dims: Vec<usize> = spec
        .anchors
        .iter()
        .map(|p| system.params()[p.index()].dim)
        .collect();
    for m in moves {
        let shape_ok = m.len() == dims.len() && m.iter().zip(&dims).all(|(v, d)| v.len() == *d);
        if !shape_ok {
            return Err(EditError::Count {
                what: "anchor displacements (per anchor and coordinate) of a move",
                expected: dims.iter().sum(),
                found: m.iter().map(Vec::len).sum(),
            });
        }
    }
    let relevant = extract_relevant(system, &spec.anchors, &spec.derived);
    let reduced = reduce(system, values, spec, &relevant);
    let current: Vec<Vec<Rational>> = spec
        .anchors
        .iter()
        .map(|p| values.get(*p).to_vec())
        .collect();
    let basis = basis_of(moves);
    let (family, coordinates) = directed_family(&reduced, &dims, &current, &basis);
    let factorization = backend.factor(&reduced.r_ed)?;
    match factorization.check_strongly_consistent(&family)? {
        Ok(()) => Ok(()),
        Err(StrongFailure::Constant {
            column,
            inconsistency,
        }) => Err(crate::edit::state_inconsistent(
            &reduced,
            column,
            inconsistency,
        )),
        Err(StrongFailure::Direction {
            parameter,
            inconsistency,
        }) => {
            let coordinate = coordinates.get(parameter).copied().flatten();
            Err(EditError::MoveBlocked(Box::new(Conflict {
                coordinate,
                rows: inconsistency
                    .rows
                    .iter()
                    .zip(inconsistency.certificate)
                    .map(|(&i, multiplier)| ConflictingRow {
                        row: reduced.rows[i],
                        label: reduced.labels[i].clone(),
                        multiplier,
                    })
                    .collect(),
                discrepancy: inconsistency.discrepancy,
            })))
        }
    }
}

/// A basis of the span of `moves` (each flattened over anchors and coordinates), found by
/// exact elimination; the basis vectors are moves of the input (not combinations), in order.
fn basis_of(moves: &[Vec<Vec<Rational>>]) -> Vec<Vec<Vec<Rational>>> {
    // Echelon rows (reduced copies) with their pivot positions, and the chosen originals.
    let mut echelon: Vec<(usize, Vec<Rational>)> = Vec::new();
    let mut chosen = Vec::new();
    for m in moves {
        let mut v: Vec<Rational> = m.iter().flatten().cloned().collect();
        for (pivot, row) in &echelon {
            if !v[*pivot].is_zero() {
                let f = &v[*pivot] / &row[*pivot];
                for (x, r) in v.iter_mut().zip(row) {
                    *x -= &f * r;
                }
            }
        }
        if let Some(pivot) = v.iter().position(|x| !x.is_zero()) {
            echelon.push((pivot, v));
            chosen.push(m.clone());
        }
    }
    chosen
}

/// The family `b(α) = (c − R_EA P_A) − K α` whose columns `K` are the directions `R_EA Δ`
/// of the basis moves (per coordinate for the vector layout), scaled to integers; with, per
/// column, the coordinate it belongs to (vector layouts of dimension > 1).
fn directed_family(
    reduced: &ReducedSystem,
    dims: &[usize],
    current: &[Vec<Rational>],
    basis: &[Vec<Vec<Rational>>],
) -> (RhsFamily, Vec<Option<usize>>) {
    let r_ea = &reduced.family.coefficients;
    let m = r_ea.rows();
    // The coefficient of anchor coordinate (a, j) in row i, as the column index of R_EA.
    let offsets: Vec<usize> = dims
        .iter()
        .scan(0, |next, d| {
            let at = *next;
            *next += d;
            Some(at)
        })
        .collect();
    // R_EA · x for a per-anchor vector x, in coordinate j (vector layout) or over all
    // coordinates (scalar layout).
    let apply = |x: &[Vec<Rational>], j: Option<usize>| -> Vec<Rational> {
        (0..m)
            .map(|i| {
                let mut sum = Rational::zero();
                for (col, coeff) in r_ea.row(i) {
                    let value = match (reduced.layout, j) {
                        (Layout::Vector { .. }, Some(j)) => &x[*col][j],
                        _ => {
                            let a = offsets.partition_point(|&o| o <= *col) - 1;
                            &x[a][*col - offsets[a]]
                        }
                    };
                    if !value.is_zero() {
                        sum += Rational::from_integer(coeff.clone()) * value;
                    }
                }
                sum
            })
            .collect()
    };
    let (constant, mut columns, mut coordinates) = match reduced.layout {
        Layout::Vector { dim } => {
            let constant = (0..dim)
                .map(|j| {
                    let shift = apply(current, Some(j));
                    reduced.family.constant[j]
                        .iter()
                        .zip(shift)
                        .map(|(c, s)| c - s)
                        .collect()
                })
                .collect();
            let mut columns = Vec::new();
            let mut coordinates = Vec::new();
            for mv in basis {
                for j in 0..dim {
                    columns.push(apply(mv, Some(j)));
                    coordinates.push((dim > 1).then_some(j));
                }
            }
            (constant, columns, coordinates)
        }
        Layout::Scalar => {
            let shift = apply(current, None);
            let constant = vec![reduced.family.constant[0]
                .iter()
                .zip(shift)
                .map(|(c, s)| c - s)
                .collect()];
            let columns: Vec<Vec<Rational>> = basis.iter().map(|mv| apply(mv, None)).collect();
            let coordinates = vec![None; columns.len()];
            (constant, columns, coordinates)
        }
    };
    // Zero directions need no check.
    let keep: Vec<bool> = columns
        .iter()
        .map(|c| c.iter().any(|x| !x.is_zero()))
        .collect();
    let mut kept = keep.iter();
    columns.retain(|_| *kept.next().unwrap_or(&false));
    let mut kept = keep.iter();
    coordinates.retain(|_| *kept.next().unwrap_or(&false));
    // Scale every direction to integers (only its span matters).
    let mut rows: Vec<Vec<(usize, Integer)>> = vec![Vec::new(); m];
    for (k, column) in columns.iter().enumerate() {
        let lcm = column
            .iter()
            .fold(Integer::one(), |acc, x| acc.lcm(x.denom()));
        for (i, x) in column.iter().enumerate() {
            if !x.is_zero() {
                rows[i].push((k, x.numer() * (&lcm / x.denom())));
            }
        }
    }
    let coefficients =
        IntMatrix::from_sparse(columns.len(), rows).expect("columns index the directions");
    (
        RhsFamily {
            constant,
            coefficients,
        },
        coordinates,
    )
}
