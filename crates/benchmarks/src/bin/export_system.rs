//! Writes the scalar C1 constraint matrix of a degree-5 spline on a perturbed `n × n` grid
//! (`2 n²` triangles) as text, and times this project's exact rank of the same matrix, for
//! `tools/linbox_compare.py` (which times LinBox and FLINT on it).
//!
//! `cargo run --release -p benchmarks --bin export_system -- N FILE`
//!
//! Output file: a line `rows cols`, then per row `col:value` pairs separated by spaces.
//! Standard output: `rank R mono_ms M blockwise_ms B` (best of 5 runs each).

use api::{ConstraintSystem, Values};
use std::io::Write;
use std::process::ExitCode;
use std::time::Instant;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let (Some(n), Some(path)) = (
        args.get(1).and_then(|a| a.parse::<usize>().ok()),
        args.get(2),
    ) else {
        eprintln!("usage: export_system N FILE");
        return ExitCode::from(2);
    };
    let spline = match spline2d::spline::Spline::new(benchmarks::perturbed_grid(n), 5, 1) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let mut system = ConstraintSystem::new();
    let mut values = Values::default();
    if let Err(e) = spline.declare(&mut system, &mut values, "phi", spline.identity_positions()) {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    let (matrix, _, _) = system.scalar_matrix();
    let mut text = format!("{} {}\n", matrix.rows(), matrix.cols());
    for row in matrix.row_iter() {
        let cells: Vec<String> = row.iter().map(|(c, v)| format!("{c}:{v}")).collect();
        text.push_str(&cells.join(" "));
        text.push('\n');
    }
    if let Err(e) = std::fs::File::create(path).and_then(|mut f| f.write_all(text.as_bytes())) {
        eprintln!("error: cannot write {path}: {e}");
        return ExitCode::from(2);
    }
    let best = |f: &dyn Fn() -> usize| -> (usize, f64) {
        let mut rank = 0;
        let mut best = f64::INFINITY;
        for _ in 0..5 {
            let t = Instant::now();
            rank = f();
            best = best.min(t.elapsed().as_secs_f64() * 1e3);
        }
        (rank, best)
    };
    let (rank, mono) = best(&|| {
        exact_ldu::sparse::eliminate(&matrix, &[], exact_ldu::sparse::Combinations::Skip).rank
    });
    let (rank_b, blockwise) = best(&|| {
        exact_ldu::sparse::eliminate_blockwise(&matrix, &[], exact_ldu::sparse::Combinations::Skip)
            .rank
    });
    if rank != rank_b {
        eprintln!("error: monolithic rank {rank} != block-wise rank {rank_b}");
        return ExitCode::FAILURE;
    }
    println!("rank {rank} mono_ms {mono:.3} blockwise_ms {blockwise:.3}");
    ExitCode::SUCCESS
}
