//! A scripted editing session on the benchmark mesh (`data/figure.obj`, degree 5, C1): `N`
//! soft translations of random control points by random moves in `[−20, 20]²` with
//! neighbourhood `δ_max`, each one mouse-down (Select + ExpandDerived + Initialize) and one
//! committed Update, as an editor would run them. Prints, per edit, its time, `|D|` and (for
//! snapped commits) the proved distance to the exact optimum; after every 10 edits the largest
//! numerator and denominator of all values in bits; at the end the mean time of the first and
//! last 20 edits.
//!
//! `cargo run --release -p benchmarks --bin session -- [EDITS] [DELTA] [optimum|snapped:G] [SEED]`
//! (defaults: 200 8 snapped:24 7)

use api::{ConstraintSystem, ParamId, Rational, Values};
use ecles::Edit;
use exact_ldu::ExactLdu;
use spline2d::edit::{Neighborhood, Operation, SplineEditor};
use spline2d::mesh_io::{parse_obj, MeshOptions};
use spline2d::net::ControlNet;
use spline2d::spline::Spline;
use std::process::ExitCode;
use std::time::Instant;

/// What each edit commits.
#[derive(Clone, Copy)]
enum Commit {
    Optimum,
    Snapped(u32),
}

/// The largest numerator and denominator of all values, in bits.
fn largest_bits(system: &ConstraintSystem, values: &Values) -> (u64, u64) {
    (0..system.params().len())
        .flat_map(|p| values.get(ParamId(p as u32)))
        .fold((0, 0), |(n, d), v| {
            (n.max(v.numer().bits()), d.max(v.denom().bits()))
        })
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let number =
        |i: usize, default: u64| args.get(i).map_or(Some(default), |a| a.parse::<u64>().ok());
    let commit = match args.get(2).map(String::as_str) {
        None => Some(Commit::Snapped(24)),
        Some("optimum") => Some(Commit::Optimum),
        Some(other) => other
            .strip_prefix("snapped:")
            .and_then(|g| g.parse().ok())
            .map(Commit::Snapped),
    };
    let (Some(edits), Some(delta), Some(commit), Some(seed)) =
        (number(0, 200), number(1, 8), commit, number(3, 7))
    else {
        eprintln!("usage: session [EDITS] [DELTA] [optimum|snapped:GRID_BITS] [SEED]");
        return ExitCode::from(2);
    };
    let Ok(delta) = u32::try_from(delta) else {
        eprintln!("DELTA too large");
        return ExitCode::from(2);
    };
    let text = include_str!("../../data/figure.obj");
    let read = parse_obj(text, "figure.obj", &MeshOptions::default()).expect("bundled mesh");
    let spline = Spline::new(read.mesh, 5, 1).expect("degree 5, C1");
    let net = ControlNet::new(&spline);
    let mut system = ConstraintSystem::new();
    let mut values = Values::default();
    let params = spline
        .declare(&mut system, &mut values, "fig", spline.identity_positions())
        .expect("fresh system");
    let editor = SplineEditor {
        spline: &spline,
        net: &net,
        params: &params,
    };
    let backend = ExactLdu::default();
    let mut rng = benchmarks::Rng::new(seed);
    let points = spline.points().len() as u64;
    let mut times = Vec::with_capacity(edits as usize);
    for e in 0..edits {
        let anchor = (rng.next_u64() % points) as usize;
        let by = vec![
            Rational::from_integer(rng.range(-20, 20).into()),
            Rational::from_integer(rng.range(-20, 20).into()),
        ];
        let start = Instant::now();
        let outcome = editor
            .plan_operation(
                &system,
                &values,
                &[anchor],
                Neighborhood::Radius(delta),
                &Operation::Translate { by },
                1,
            )
            .map_err(|e| e.to_string())
            .and_then(|(_, plan)| {
                let edit = Edit::initialize(&backend, &system, &values, &plan.spec)
                    .map_err(|e| e.to_string())?;
                let step = &plan.steps[0];
                let (result, bound) = match commit {
                    Commit::Optimum => (edit.update(&step.anchors, &step.hints), None),
                    Commit::Snapped(grid_bits) => {
                        match edit.update_snapped(&step.anchors, &step.hints, grid_bits) {
                            Ok((r, s)) => (Ok(r), Some(s.distance_bound)),
                            Err(e) => (Err(e), None),
                        }
                    }
                };
                result.map_err(|e| e.to_string())?.write_into(&mut values);
                Ok((plan.spec.derived.len(), bound))
            });
        let ms = start.elapsed().as_secs_f64() * 1e3;
        times.push(ms);
        match outcome {
            Ok((derived, bound)) => {
                let bound = bound.map_or(String::new(), |b| format!("  distance ≤ {b:.2e}"));
                println!("edit {e:>4}  anchor {anchor:>5}  |D| {derived:>5}  {ms:>9.1} ms{bound}");
            }
            Err(why) => println!("edit {e:>4}  anchor {anchor:>5}  refused: {why}"),
        }
        if (e + 1) % 10 == 0 {
            let (num, den) = largest_bits(&system, &values);
            println!(
                "after {:>4} edits: largest numerator {num} bits, denominator {den} bits",
                e + 1
            );
        }
    }
    if !system.violations(&values).is_empty() {
        eprintln!("error: the committed values violate a constraint");
        return ExitCode::FAILURE;
    }
    let mean = |s: &[f64]| s.iter().sum::<f64>() / s.len().max(1) as f64;
    let k = times.len().min(20);
    println!(
        "first {k} edits {:.1} ms mean, last {k} edits {:.1} ms mean; every constraint holds exactly",
        mean(&times[..k]),
        mean(&times[times.len() - k..])
    );
    ExitCode::SUCCESS
}
