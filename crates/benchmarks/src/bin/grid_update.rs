//! One Update of the `spline` bench's grid edit, repeated: the soft translation by
//! `(7/3, −5/4)` of the middle edge point `e264-265:2` of the 968-triangle perturbed grid
//! (degree 5, C1) with neighbourhood `δ_max`, the exact Update (reduced values) and the float
//! Update of the same edit, `N` times each, in `ROUNDS` alternating rounds. Prints the mean
//! time per Update of each round and the exact/float ratio, and at the end the best round of
//! each. On a shared machine whose speed drifts by tens of percent within minutes, alternating
//! rounds of many repetitions compare the two backends (or two builds) better than separate
//! criterion runs.
//!
//! `cargo run --release -p benchmarks --bin grid_update -- [N] [DELTA] [ROUNDS]`
//! (defaults: 2000 8 5)

use api::{ConstraintSystem, Values};
use benchmarks::perturbed_grid;
use ecles::Edit;
use exact_ldu::ExactLdu;
use float_qr::FloatQr;
use spline2d::edit::{Neighborhood, Operation, SplineEditor};
use spline2d::net::ControlNet;
use spline2d::spline::Spline;
use std::hint::black_box;
use std::process::ExitCode;
use std::time::Instant;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let number =
        |i: usize, default: u32| args.get(i).map_or(Some(default), |a| a.parse::<u32>().ok());
    let (Some(repetitions), Some(delta), Some(rounds)) =
        (number(0, 2000), number(1, 8), number(2, 5))
    else {
        eprintln!("usage: grid_update [N] [DELTA] [ROUNDS]");
        return ExitCode::from(2);
    };
    match run(repetitions.max(1), delta, rounds.max(1)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("grid_update: {message}");
            ExitCode::FAILURE
        }
    }
}

fn run(repetitions: u32, delta: u32, rounds: u32) -> Result<(), String> {
    let spline = Spline::new(perturbed_grid(22), 5, 1).map_err(|e| e.to_string())?;
    let net = ControlNet::new(&spline);
    let mut system = ConstraintSystem::new();
    let mut values = Values::default();
    let params = spline
        .declare(&mut system, &mut values, "phi", spline.identity_positions())
        .map_err(|e| e.to_string())?;
    let anchor = spline
        .points()
        .iter()
        .position(|p| &*p.name == "e264-265:2")
        .ok_or("the grid has no point e264-265:2")?;
    let editor = SplineEditor {
        spline: &spline,
        net: &net,
        params: &params,
    };
    let selection = editor
        .select(&system, &values, &[anchor], Neighborhood::Radius(delta))
        .map_err(|e| e.to_string())?;
    let by = vec![
        api::Rational::new(7.into(), 3.into()),
        api::Rational::new((-5).into(), 4.into()),
    ];
    let plan = editor
        .plan(&selection, &values, &Operation::Translate { by }, 1)
        .map_err(|e| e.to_string())?;
    let step = plan.steps.first().ok_or("the plan has no step")?;
    let exact = Edit::initialize(&ExactLdu::default(), &system, &values, &plan.spec)
        .map_err(|e| e.to_string())?;
    let float = Edit::initialize(&FloatQr::default(), &system, &values, &plan.spec)
        .map_err(|e| e.to_string())?;
    // The first Update builds the memos a drag reuses: not timed.
    exact
        .update(&step.anchors, &step.hints)
        .map_err(|e| e.to_string())?;
    float
        .update(&step.anchors, &step.hints)
        .map_err(|e| e.to_string())?;
    println!(
        "delta {delta}: {} derived, {repetitions} Updates per round",
        plan.spec.derived.len()
    );
    let mean_micros = |update: &dyn Fn() -> bool| -> Result<f64, String> {
        let start = Instant::now();
        for _ in 0..repetitions {
            if !black_box(update()) {
                return Err("an Update failed".into());
            }
        }
        Ok(start.elapsed().as_secs_f64() * 1e6 / f64::from(repetitions))
    };
    let (mut best_exact, mut best_float) = (f64::INFINITY, f64::INFINITY);
    for round in 1..=rounds {
        let e = mean_micros(&|| exact.update(&step.anchors, &step.hints).is_ok())?;
        let f = mean_micros(&|| float.update(&step.anchors, &step.hints).is_ok())?;
        println!(
            "round {round}: exact {e:.1} µs, float {f:.1} µs, exact / float {:.2}",
            e / f
        );
        best_exact = best_exact.min(e);
        best_float = best_float.min(f);
    }
    println!(
        "best: exact {best_exact:.1} µs, float {best_float:.1} µs, exact / float {:.2}",
        best_exact / best_float
    );
    Ok(())
}
