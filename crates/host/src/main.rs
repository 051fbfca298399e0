//! `ecles`: exact editing of parameters under linear constraints, from a RON run file.
//!
//! * `ecles run RUN.ron [--out DIR] [--quiet] [--strict]` builds the sources, runs the edits with
//!   the exact backend (cross-checked by the float backend), renders outputs and writes
//!   `DIR/report.json`.
//! * `ecles analyze RUN.ron [--json]` builds the system and reports on it without editing.
//! * `ecles explain RUN.ron PARAM` says why a parameter is fixed, limited or free.
//! * `ecles plugins [--path LIB]` lists the built-in sources, or checks a dynamic plugin.
//!
//! Exit codes: 0 success; 1 the run completed but an edit failed (or, with `--strict`, the
//! backends disagreed); 2 bad input (run file, mesh, plugin, inconsistent constraints).

mod analysis;
mod registry;
mod report;
mod runfile;
mod session;
mod structural;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use report::Report;
use session::{describe, InputError, Session};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Exact editing of parameters under linear constraints.
#[derive(Debug, Parser)]
#[command(name = "ecles", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run the edits of a run file and write the report, pictures and models.
    Run {
        /// The RON run file.
        run: PathBuf,
        /// Output directory (default: `<run file without extension>.out` next to it).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Print nothing but errors.
        #[arg(long)]
        quiet: bool,
        /// Exit with 1 when the float backend disagrees with the exact one.
        #[arg(long)]
        strict: bool,
    },
    /// Build the system and report on it without editing.
    Analyze {
        /// The RON run file.
        run: PathBuf,
        /// Print the report as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Explain why a parameter is fixed, limited or free (Dulmage–Mendelsohn blocks in solve
    /// order).
    Explain {
        /// The RON run file.
        run: PathBuf,
        /// Parameter name (`src.name`), or one coordinate `src.name[k]`.
        param: String,
    },
    /// List built-in sources, or check a dynamic plugin library.
    Plugins {
        /// A plugin library to load and describe.
        #[arg(long)]
        path: Option<PathBuf>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match cli.command {
        Command::Run {
            run,
            out,
            quiet,
            strict,
        } => run_command(&run, out, quiet, strict),
        Command::Analyze { run, json } => analyze_command(&run, json),
        Command::Explain { run, param } => explain_command(&run, &param),
        Command::Plugins { path } => plugins_command(path.as_deref()),
    };
    match outcome {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn build(run: &Path) -> Result<Session> {
    Ok(Session::build(run)?)
}

fn analyze_command(run: &Path, json: bool) -> Result<ExitCode> {
    let session = build(run)?;
    let report = session.analyze();
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print_system(&report);
    }
    Ok(ExitCode::SUCCESS)
}

fn print_system(report: &Report) {
    for s in &report.sources {
        let counts: Vec<String> = s.counts.iter().map(|(k, v)| format!("{k} {v}")).collect();
        println!(
            "source {} ({} {}): {} parameters, {} rows{}",
            s.name,
            s.plugin,
            s.version,
            s.parameters,
            s.rows,
            if counts.is_empty() {
                String::new()
            } else {
                format!(" [{}]", counts.join(", "))
            }
        );
        for w in &s.warnings {
            println!("  warning: {w}");
        }
    }
    println!("system: {}", describe(report));
    let cc = &report.cross_check;
    if cc.enabled {
        match (cc.float_rank, cc.agree, &cc.skipped) {
            (_, _, Some(reason)) => println!("cross-check skipped: {reason}"),
            (Some(rank), Some(agree), None) => println!(
                "cross-check: float rank {rank}, {}{}",
                if agree { "agrees" } else { "DISAGREES" },
                cc.margin
                    .map(|m| format!(
                        " (smallest kept {:.3e}, largest dropped {:.3e})",
                        m.smallest_kept, m.largest_dropped
                    ))
                    .unwrap_or_default()
            ),
            _ => {}
        }
        for d in &cc.disagreements {
            println!("  {d}");
        }
    }
}

fn default_out_dir(run: &Path) -> PathBuf {
    let stem = run
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "run".into());
    run.with_file_name(format!("{stem}.out"))
}

fn run_command(run: &Path, out: Option<PathBuf>, quiet: bool, strict: bool) -> Result<ExitCode> {
    let mut session = build(run)?;
    let mut report = session.analyze();
    if !report.consistent {
        return Err(InputError(format!(
            "{}: the constraints contradict each other: {}",
            run.display(),
            report.conflict.clone().unwrap_or_default().join(", ")
        ))
        .into());
    }
    if !report.violated.is_empty() {
        return Err(InputError(format!(
            "{}: the initial values violate {}",
            run.display(),
            report.violated.join(", ")
        ))
        .into());
    }
    session.validate_edits()?;
    if !quiet {
        print_system(&report);
    }
    let progress = if quiet {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::new(session.edit_count() as u64);
        if let Ok(style) = ProgressStyle::with_template("{bar:30} {pos}/{len} edits {msg}") {
            bar.set_style(style);
        }
        bar
    };
    for i in 0..session.edit_count() {
        let edit = session.run_edit(i)?;
        progress.inc(1);
        report.edits.push(edit);
    }
    progress.finish_and_clear();
    let files = session.render_outputs()?;
    report.summary.edits = report.edits.len();
    report.summary.failed = report.edits.iter().filter(|e| !e.solvable).count();
    report.summary.disagreements = report.cross_check.disagreements.len()
        + report
            .edits
            .iter()
            .map(|e| e.disagreements.len())
            .sum::<usize>();
    report.outputs = files.iter().map(|f| f.name.clone()).collect();
    report.output_notes = files
        .iter()
        .flat_map(|f| {
            f.notes.iter().map(|note| report::OutputNote {
                file: f.name.clone(),
                note: note.clone(),
            })
        })
        .collect();

    let out_dir = out.unwrap_or_else(|| default_out_dir(run));
    std::fs::create_dir_all(&out_dir)
        .with_context(|| format!("cannot create the output directory {}", out_dir.display()))?;
    for file in &files {
        let path = out_dir.join(&file.name);
        std::fs::write(&path, &file.bytes)
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    // The report is written last and atomically: its presence means the run completed.
    let report_path = out_dir.join("report.json");
    let partial = out_dir.join(".report.json.partial");
    let json = serde_json::to_string_pretty(&report)? + "\n";
    std::fs::write(&partial, json)
        .with_context(|| format!("cannot write {}", partial.display()))?;
    std::fs::rename(&partial, &report_path)
        .with_context(|| format!("cannot write {}", report_path.display()))?;

    if !quiet {
        for e in &report.edits {
            let what = match &e.source {
                Some(s) => format!("edit {} ({s})", e.index),
                None => format!("edit {}", e.index),
            };
            if e.solvable {
                println!(
                    "{what}: ok, {} anchors, {} derived, rank {}, residual {}{}",
                    e.anchors.len(),
                    e.derived.len(),
                    e.rank,
                    e.max_residual,
                    e.float_deviation
                        .map(|d| format!(", float deviation {d:.2e}"))
                        .unwrap_or_default()
                );
            } else {
                println!(
                    "{what}: FAILED: {}",
                    e.error.clone().unwrap_or_else(|| "unknown".into())
                );
                for line in &e.explanation {
                    println!("  {line}");
                }
            }
            for d in &e.disagreements {
                println!("  float disagrees: {d}");
            }
        }
        println!(
            "{} edits, {} failed, {} disagreements; wrote {}{}",
            report.summary.edits,
            report.summary.failed,
            report.summary.disagreements,
            report_path.display(),
            if files.is_empty() {
                String::new()
            } else {
                format!(
                    " and {}",
                    files
                        .iter()
                        .map(|f| f.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            }
        );
        for n in &report.output_notes {
            println!("note: {}: {}", n.file, n.note);
        }
    }
    let failed = report.summary.failed > 0 || (strict && report.summary.disagreements > 0);
    Ok(if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

fn explain_command(run: &Path, param: &str) -> Result<ExitCode> {
    let session = build(run)?;
    match session.explain(param) {
        Some(lines) => {
            for line in lines {
                println!("{line}");
            }
            Ok(ExitCode::SUCCESS)
        }
        None => Err(InputError(format!("{}: no parameter named {param:?}", run.display())).into()),
    }
}

fn plugins_command(path: Option<&Path>) -> Result<ExitCode> {
    match path {
        None => {
            println!(
                "built-in sources (plugin ABI {}):",
                plugin_abi::abi::ABI_VERSION
            );
            for b in registry::builtins() {
                let source = (b.make)();
                println!("  {} {}", b.kind, source.version());
            }
        }
        Some(path) => {
            let loaded = plugin_abi::load(path)?;
            println!(
                "{}: plugin {} version {}, ABI {}",
                path.display(),
                loaded.kind,
                loaded.version,
                loaded.abi_version
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}
