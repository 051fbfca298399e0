//! The float twin of an edit: the same edit run by [`float_qr::SparseLeastSquares`] (sparse
//! rank test, least squares by a sparse QR), so the cross-check of a big neighbourhood takes
//! about as long as the edit instead of minutes, and of a medium one a fraction of the dense
//! QR's time.

use super::edit::{Execution, InitFacts};
use api::{exact::rational_to_f64, BackendError, ConstraintSystem, PlannedStep, Rational, Values};
use ecles::{EditError, EditSpec, Layout, UpdateResult};
use num_traits::{One, Signed};

/// Edits whose `R_ED` has more entries (rows × columns) than this are cross-checked by the
/// sparse float twin; up to it, by the float backend itself (dense QR), which runs the whole
/// ECLES edit in floats. The sparse twin is the faster from the smallest edits on
/// (`cargo bench -p benchmarks --bench spline -- float-cross-check`, the grid's edits: 169
/// entries 31 against 21 µs, 1 080 entries 86 against 44 µs, 31 968 entries 5.96 against
/// 0.33 ms), so the dense QR is kept only where both take microseconds.
pub(crate) const DENSE_EDIT_LIMIT: usize = 1_000;

/// Runs `spec` with `steps` on the sparse float twin: the rank of `R_ED` and, per step, the
/// derived values (or why the float side refuses the step).
pub(crate) fn execute_sparse(
    system: &ConstraintSystem,
    values: &Values,
    spec: &EditSpec,
    steps: &[PlannedStep],
    tolerance: f64,
) -> Execution<f64> {
    let failed = |e: BackendError| Execution {
        init: None,
        outcome: Err(EditError::Backend(e)),
    };
    let reduced = match ecles::reduce_edit::<f64>(system, values, spec) {
        Ok((_, reduced)) => reduced,
        Err(e) => {
            return Execution {
                init: None,
                outcome: Err(e),
            }
        }
    };
    let dims: Vec<usize> = spec
        .derived
        .iter()
        .map(|p| system.params()[p.index()].dim)
        .collect();
    let one = Rational::one();
    let weights: Vec<f64> = spec
        .derived
        .iter()
        .enumerate()
        .flat_map(|(k, _)| {
            let w = spec.weights.as_ref().map_or(&one, |w| &w[k]);
            let copies = match reduced.layout() {
                Layout::Vector { .. } => 1,
                Layout::Scalar => dims[k],
            };
            std::iter::repeat_n(rational_to_f64(w), copies)
        })
        .collect();
    let (lsq, rank) = match float_qr::SparseLeastSquares::new(reduced.r_ed(), &weights, tolerance) {
        Ok(prepared) => prepared,
        Err(e) => return failed(e),
    };
    // In scalar equations, as the exact backend's counts (see `equation_counts`).
    let copies = match reduced.layout() {
        Layout::Vector { dim } => dim,
        Layout::Scalar => 1,
    };
    let init = InitFacts {
        relevant: 0,
        fixed: Vec::new(),
        rank: rank.rank * copies,
        redundant: (reduced.r_ed().rows() - rank.rank) * copies,
        independent: Vec::new(),
        // Only the exact run's facts shape the report's structure.
        independent_rows: false,
        reduced: None,
    };
    let family = reduced.family();
    // b_j = c_j − K α and the magnitudes its rounding is proportional to, per row.
    let right_hand_side = |column: usize, alpha: &[Rational]| -> (Vec<f64>, Vec<f64>) {
        family.constant[column]
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let mut b = c.clone();
                let mut magnitude = rational_to_f64(&c.abs());
                for (k, kv) in family.coefficients.row(i) {
                    let term = Rational::from_integer(kv.clone()) * &alpha[*k];
                    magnitude += rational_to_f64(&term.abs());
                    b -= term;
                }
                (rational_to_f64(&b), magnitude)
            })
            .unzip()
    };
    let mut results = Vec::with_capacity(steps.len());
    for step in steps {
        let mut derived: Vec<Vec<f64>> = dims.iter().map(|&d| vec![0.0; d]).collect();
        let solved = match reduced.layout() {
            Layout::Vector { dim } => (0..dim).try_for_each(|j| {
                let alpha: Vec<Rational> = step.anchors.iter().map(|v| v[j].clone()).collect();
                let hints: Vec<f64> = step.hints.iter().map(|v| rational_to_f64(&v[j])).collect();
                let (b, magnitudes) = right_hand_side(j, &alpha);
                let x = lsq.solve(&b, &magnitudes, &hints)?;
                for (slot, value) in derived.iter_mut().zip(x) {
                    slot[j] = value;
                }
                Ok(())
            }),
            Layout::Scalar => {
                let alpha: Vec<Rational> = step.anchors.iter().flatten().cloned().collect();
                let hints: Vec<f64> = step.hints.iter().flatten().map(rational_to_f64).collect();
                let (b, magnitudes) = right_hand_side(0, &alpha);
                lsq.solve(&b, &magnitudes, &hints).map(|x| {
                    let mut x = x.into_iter();
                    for slot in derived.iter_mut() {
                        for value in slot.iter_mut() {
                            *value = x.next().unwrap_or(0.0);
                        }
                    }
                })
            }
        };
        if let Err(unsatisfied) = solved {
            let label = reduced
                .labels()
                .get(unsatisfied.row)
                .cloned()
                .unwrap_or_default();
            return Execution {
                init: Some(init),
                outcome: Err(EditError::Backend(BackendError::Numerical(format!(
                    "the float least-squares solution does not satisfy {label:?}"
                )))),
            };
        }
        results.push(UpdateResult {
            anchors: spec
                .anchors
                .iter()
                .copied()
                .zip(step.anchors.iter().cloned())
                .collect(),
            derived: spec.derived.iter().copied().zip(derived).collect(),
        });
    }
    Execution {
        init: Some(init),
        outcome: Ok(results),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::Planning;
    use crate::testutil::session;

    /// On edits small enough for both, the sparse twin and the dense float backend agree: the
    /// same rank of `R_ED` and the same values (to rounding), and the same refusal of a move
    /// the constraints forbid.
    #[test]
    fn the_sparse_twin_agrees_with_the_dense_float_backend() {
        let (_dir, session) = session(
            r#"(sources: [
                (name: "worm", plugin: "spline2d", config: (mesh: "meshes/worm.obj")),
            ])"#,
        );
        for operation in [
            r#"(anchors: ["v3"], neighborhood: 3, translate: ("1/3", "6"), steps: 2)"#,
            r#"(anchors: ["e0-1:2", "e0-1:3"], neighborhood: 2, scale: (center: ("0", "0"), factor: "3/2", precision: 1000))"#,
        ] {
            let Planning::Planned(plan) = session.plan_operation("worm", operation).expect("plans")
            else {
                panic!("refused");
            };
            let sparse = execute_sparse(
                &session.system,
                &session.values,
                &plan.spec,
                &plan.steps,
                1e-10,
            );
            let dense = super::super::edit::execute(
                &float_qr::FloatQr::default(),
                &session.system,
                &session.values,
                &plan.spec,
                &plan.steps,
                |edit, step| edit.update(&step.anchors, &step.hints),
            );
            assert_eq!(
                sparse.init.as_ref().map(|i| i.rank),
                dense.init.as_ref().map(|i| i.rank)
            );
            let (Ok(s), Ok(d)) = (&sparse.outcome, &dense.outcome) else {
                panic!("both solve {operation}");
            };
            for (ss, ds) in s.iter().zip(d) {
                for ((_, sv), (_, dv)) in ss.derived.iter().zip(&ds.derived) {
                    for (x, y) in sv.iter().zip(dv) {
                        assert!((x - y).abs() < 1e-9 * (1.0 + y.abs()), "{x} vs {y}");
                    }
                }
            }
        }
        // Pin v2 by making it an anchor that stays and ask v3 to move with nothing derived
        // around it but one point: a move the constraints forbid is refused by both.
        let v3 = session.system.param_id("worm.v3").expect("v3");
        let v2 = session.system.param_id("worm.v2").expect("v2");
        let e = session.system.param_id("worm.e2-3:1").expect("edge point");
        let here = |p| session.values.get(p).to_vec();
        let mut moved = here(v3);
        moved[1] += Rational::from_integer(5.into());
        let spec = EditSpec::new(vec![v3, v2], vec![e]);
        let step = PlannedStep {
            anchors: vec![moved, here(v2)],
            hints: vec![here(e)],
        };
        let sparse = execute_sparse(
            &session.system,
            &session.values,
            &spec,
            std::slice::from_ref(&step),
            1e-10,
        );
        let dense = super::super::edit::execute(
            &float_qr::FloatQr::default(),
            &session.system,
            &session.values,
            &spec,
            &[step],
            |edit, step| edit.update(&step.anchors, &step.hints),
        );
        assert!(
            dense.outcome.is_err(),
            "the dense float backend refuses too"
        );
        let Err(refusal) = sparse.outcome else {
            panic!("the sparse twin refuses");
        };
        assert!(
            refusal.to_string().contains("does not satisfy"),
            "{refusal}"
        );
    }
}
