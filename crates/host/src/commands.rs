//! The `ecles` commands as functions: what `main` calls, and what tests call in process.
//!
//! Each command prints through a [`Console`] and returns its exit code (see
//! [`crate::error`]); nothing here panics on any input, and nothing is written before every
//! input has been checked.

use crate::console::Console;
use crate::error::{RunError, EXIT_EDIT_FAILED};
use crate::outputs;
use crate::registry;
use crate::report::{self, Report};
use crate::session::{describe, OutputsPlan, Session};
use api::OutputFile;
use std::path::{Path, PathBuf};

/// Options of `ecles run`.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// The run file.
    pub run: PathBuf,
    /// Output directory (default: `<run file without extension>.out` next to it).
    pub out: Option<PathBuf>,
    /// Print nothing but errors.
    pub quiet: bool,
    /// Exit with 1 when the float backend disagrees with the exact one.
    pub strict: bool,
    /// Largest input file, in bytes.
    pub max_input_bytes: u64,
}

/// The default output directory of a run file: `<stem>.out` next to it.
pub fn default_out_dir(run: &Path) -> PathBuf {
    let stem = run
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "run".into());
    run.with_file_name(format!("{stem}.out"))
}

/// A run that passed every check, ready to execute: the session, the whole-system report
/// and what the outputs will write.
pub struct PreparedRun {
    /// The built session.
    pub session: Session,
    /// The whole-system report (edits are added by [`PreparedRun::execute`]).
    pub report: Report,
    /// What the outputs write and read.
    pub outputs: OutputsPlan,
}

impl PreparedRun {
    /// Builds the session, checks every edit and output, analyses the system, and refuses
    /// contradicting constraints and initial values that violate them.
    pub fn prepare(run: &Path, max_input_bytes: u64) -> Result<PreparedRun, RunError> {
        let session = Session::build(run, max_input_bytes)?;
        // Every edit and output is checked before any work on the system.
        let outputs = session.check()?;
        let report = session.analyze();
        let run_name = run.display().to_string();
        if !report.consistent {
            return Err(RunError::input(format!(
                "{run_name}: the constraints contradict each other: {}",
                report.conflict.clone().unwrap_or_default().join(", ")
            )));
        }
        if !report.violated.is_empty() {
            return Err(RunError::input(format!(
                "{run_name}: the initial values violate {}",
                report.violated.join(", ")
            )));
        }
        Ok(PreparedRun {
            session,
            report,
            outputs,
        })
    }

    /// Runs every edit (calling `after_edit` after each), renders the outputs and completes
    /// the report. Nothing is written.
    pub fn execute(mut self, mut after_edit: impl FnMut()) -> Result<Executed, RunError> {
        let mut report = self.report;
        for i in 0..self.session.edit_count() {
            let edit = self.session.run_edit(i)?;
            after_edit();
            report.edits.push(edit);
        }
        let files = self.session.render_outputs(&self.outputs)?;
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
        Ok(Executed {
            report,
            files,
            values: self.session.values().clone(),
        })
    }
}

/// What a run made: its report, its rendered outputs and the final exact values.
pub struct Executed {
    /// The completed report.
    pub report: Report,
    /// The rendered outputs, not yet written.
    pub files: Vec<OutputFile>,
    /// Every parameter's value after the last edit.
    pub values: api::Values,
}

impl Executed {
    /// Writes the report as `report.json` holds it: pretty JSON and a final newline.
    fn write_report(&self, out: &mut dyn std::io::Write) -> std::io::Result<()> {
        serde_json::to_writer_pretty(&mut *out, &self.report).map_err(std::io::Error::other)?;
        out.write_all(b"\n")
    }

    /// Writes the outputs, then `extra` files, then `report.json` into `out_dir` (created if
    /// needed), all or nothing.
    pub fn write(&self, out_dir: &Path, extra: Vec<(String, Vec<u8>)>) -> Result<(), RunError> {
        outputs::create_dir(out_dir)?;
        let contents: Vec<(&str, &[u8])> = self
            .files
            .iter()
            .map(|f| (f.name.as_str(), f.bytes.as_slice()))
            .chain(
                extra
                    .iter()
                    .map(|(name, bytes)| (name.as_str(), bytes.as_slice())),
            )
            .collect();
        outputs::write_all(out_dir, &contents, |out| self.write_report(out))
    }
}

/// `ecles run`: checks everything, runs the edits, renders the outputs and writes them with
/// the report, all or nothing.
pub fn run(options: &RunOptions, console: &mut Console<'_>) -> Result<u8, RunError> {
    let out_dir = options
        .out
        .clone()
        .unwrap_or_else(|| default_out_dir(&options.run));
    // A failed run must not leave the previous run's report behind.
    outputs::remove_stale_report(&out_dir)?;
    let prepared = PreparedRun::prepare(&options.run, options.max_input_bytes)?;
    outputs::check_targets(&out_dir, &prepared.outputs.files, &prepared.outputs.inputs)?;
    if !options.quiet {
        print_system(&prepared.report, console)?;
        console.flush()?;
    }
    let progress = if options.quiet {
        indicatif::ProgressBar::hidden()
    } else {
        let bar = indicatif::ProgressBar::new(prepared.session.edit_count() as u64);
        if let Ok(style) =
            indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} edits {msg}")
        {
            bar.set_style(style);
        }
        bar
    };
    let executed = prepared.execute(|| progress.inc(1))?;
    progress.finish_and_clear();
    executed.write(&out_dir, Vec::new())?;
    let report = executed.report;
    if !options.quiet {
        print_edits(&report, &out_dir, console)?;
        console.flush()?;
    }
    let failed = report.summary.failed > 0 || (options.strict && report.summary.disagreements > 0);
    Ok(if failed { EXIT_EDIT_FAILED } else { 0 })
}

/// `ecles analyze`: the whole-system report, as text or JSON. Exits with 2 when the
/// constraints contradict each other or the initial values violate them (the report, printed
/// first, says which rows).
pub fn analyze(
    run: &Path,
    json: bool,
    max_input_bytes: u64,
    console: &mut Console<'_>,
) -> Result<u8, RunError> {
    let report = Session::build(run, max_input_bytes)?.analyze_alone();
    if json {
        let text = serde_json::to_string_pretty(&report)
            .map_err(|e| RunError::environment(format!("cannot encode the report: {e}")))?;
        console.line(text)?;
    } else {
        print_system(&report, console)?;
    }
    console.flush()?;
    if !report.consistent {
        return Err(RunError::input(format!(
            "{}: the constraints contradict each other: {}",
            run.display(),
            report.conflict.clone().unwrap_or_default().join(", ")
        )));
    }
    if !report.violated.is_empty() {
        return Err(RunError::input(format!(
            "{}: the initial values violate {}",
            run.display(),
            report.violated.join(", ")
        )));
    }
    Ok(0)
}

/// `ecles explain`: why a parameter or coordinate is fixed, limited or free.
pub fn explain(
    run: &Path,
    params: &[String],
    requested: Option<&str>,
    json: bool,
    max_input_bytes: u64,
    console: &mut Console<'_>,
) -> Result<u8, RunError> {
    let session = Session::build(run, max_input_bytes)?;
    // Every name is checked (and the analysis made) before anything is printed.
    let mut blocks = Vec::new();
    for param in params {
        blocks.push(session.explain(param)?);
    }
    // The propagation analysis picks whole parameters: a coordinate `name[k]` is explained by
    // its blocks only.
    let whole: Vec<String> = params
        .iter()
        .filter(|p| !p.ends_with(']'))
        .cloned()
        .collect();
    let analysis = if whole.is_empty() {
        if requested.is_some() {
            return Err(RunError::input(
                "--move needs whole parameters (source.name), not coordinates",
            ));
        }
        None
    } else {
        Some(session.propagation(&whole, requested)?.1)
    };
    if json {
        let value = analysis.as_ref().map(|a| session.propagation_json(a));
        console.line(
            serde_json::to_string_pretty(&value)
                .map_err(|e| RunError::environment(e.to_string()))?,
        )?;
    } else {
        for line in blocks.into_iter().flatten() {
            console.line(line)?;
        }
        if let Some(analysis) = &analysis {
            for line in session.propagation_lines(analysis) {
                console.line(line)?;
            }
        }
    }
    console.flush()?;
    Ok(0)
}

/// `ecles plugins`: the built-in sources, or one plugin library (a path without an extension
/// names the platform's library file, as in run files).
pub fn plugins(path: Option<&Path>, console: &mut Console<'_>) -> Result<u8, RunError> {
    match path {
        None => {
            console.line(format!(
                "built-in sources (plugin ABI {}):",
                plugin_abi::abi::ABI_VERSION
            ))?;
            for b in registry::builtins() {
                let source = (b.make)();
                console.line(format!("  {} {}", b.kind, source.version()))?;
            }
        }
        Some(path) => {
            let library = registry::library_path(&path.to_string_lossy(), Path::new(""));
            let loaded = plugin_abi::load(&library).map_err(|e| RunError::input(e.to_string()))?;
            console.line(format!(
                "{}: plugin {} version {}, ABI {}",
                library.display(),
                loaded.kind,
                loaded.version,
                loaded.abi_version
            ))?;
        }
    }
    console.flush()?;
    Ok(0)
}

/// The sources and the whole-system verdict, as printed before the edits.
fn print_system(report: &Report, console: &mut Console<'_>) -> Result<(), RunError> {
    for s in &report.sources {
        let counts: Vec<String> = s.counts.iter().map(|(k, v)| format!("{k} {v}")).collect();
        console.line(format!(
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
        ))?;
        for w in &s.warnings {
            console.line(format!("  warning: {w}"))?;
        }
    }
    console.line(format!("system: {}", describe(report)))?;
    let cc = &report.cross_check;
    if cc.enabled {
        match (cc.float_rank, cc.agree, &cc.skipped) {
            (_, _, Some(reason)) => console.line(format!("cross-check skipped: {reason}"))?,
            (Some(rank), Some(agree), None) => console.line(format!(
                "cross-check: float rank {rank}, {}{}",
                if agree { "agrees" } else { "DISAGREES" },
                cc.margin
                    .map(|m| format!(
                        " (smallest kept {:.3e}, largest dropped {:.3e})",
                        m.smallest_kept, m.largest_dropped
                    ))
                    .unwrap_or_default()
            ))?,
            _ => {}
        }
        for d in &cc.disagreements {
            console.line(format!("  {d}"))?;
        }
    }
    Ok(())
}

/// One line per edit and the summary, as printed after the run.
fn print_edits(report: &Report, out_dir: &Path, console: &mut Console<'_>) -> Result<(), RunError> {
    for e in &report.edits {
        let what = match &e.source {
            Some(s) => format!("edit {} ({s})", e.index),
            None => format!("edit {}", e.index),
        };
        if e.solvable {
            console.line(format!(
                "{what}: ok, {} anchors, {} derived, rank {}, residual {}{}",
                e.anchors.len(),
                e.derived.len(),
                e.rank,
                e.max_residual,
                e.float_deviation
                    .map(|d| format!(", float deviation {d:.2e}"))
                    .unwrap_or_default()
            ))?;
            if let Some(c) = &e.criterion {
                console.line(format!("  {}", criterion_line(c)))?;
            }
        } else {
            console.line(format!(
                "{what}: FAILED: {}",
                e.error.clone().unwrap_or_else(|| "unknown".into())
            ))?;
            for line in &e.explanation {
                console.line(format!("  {line}"))?;
            }
        }
        for d in &e.disagreements {
            console.line(format!("  float disagrees: {d}"))?;
        }
    }
    console.line(format!(
        "{} edits, {} failed, {} disagreements; wrote {}{}",
        report.summary.edits,
        report.summary.failed,
        report.summary.disagreements,
        out_dir.join(outputs::REPORT).display(),
        if report.outputs.is_empty() {
            String::new()
        } else {
            format!(" and {}", report.outputs.join(", "))
        }
    ))?;
    for n in &report.output_notes {
        console.line(format!("note: {}: {}", n.file, n.note))?;
    }
    Ok(())
}

/// What an edit's change criterion chose, in one line.
fn criterion_line(c: &crate::report::CriterionReport) -> String {
    let what = match c.measure.as_str() {
        "L1" => "least absolute change",
        "Fewest" => "fewest changed parameters",
        _ => "least squares",
    };
    let mut line = format!(
        "criterion {}: {what} {} over {} primary parameter(s); changed: {}",
        c.measure,
        c.value,
        c.primary.len(),
        if c.changed.is_empty() {
            "nothing".to_string()
        } else {
            c.changed.join(", ")
        }
    );
    if let Some(d) = c.optimal_face_dimension {
        line.push_str(&if d == 0 {
            "; the optimum is unique".to_string()
        } else {
            format!("; not unique: the optima form a set of dimension {d}, this is one vertex")
        });
    }
    if let (Some(sets), Some(proven)) = (c.minimum_sets, c.proven_minimal) {
        if !proven {
            line.push_str("; not proven minimal (heuristic beyond the exact search)");
        } else if c.ties_complete == Some(false) {
            line.push_str(&format!(
                "; at least {sets} equally small choice(s) (the search for ties was cut short)"
            ));
        } else if sets > 1 {
            // A few of the others; report.json lists up to 31.
            let mut others: Vec<String> = c
                .ties
                .iter()
                .take(3)
                .map(|t| format!("[{}]", t.join(", ")))
                .collect();
            if sets > 4 {
                others.push("…".into());
            }
            line.push_str(&format!(
                "; {sets} equally small choices, also {}",
                others.join(" or ")
            ));
        }
    }
    line
}

/// `ecles edit`: serves the interactive editor for `run` until the process is stopped; prints
/// the page's URL once it is served and, with `open`, hands it to the system's browser.
pub fn edit(
    run: &Path,
    options: &crate::editor::EditorOptions,
    open: bool,
    max_input_bytes: u64,
    console: &mut Console<'_>,
) -> Result<u8, RunError> {
    let mut printed = Ok(());
    crate::editor::serve(run, max_input_bytes, options, |url| {
        printed = console
            .line(format!("ecles edit: serving {} at {url}", run.display()))
            .and_then(|()| {
                let autosave = crate::editor::autosave_path(run);
                if !options.autosave {
                    console.line("no autosave (--no-autosave)")
                } else if crate::editor::autosave_offer(&autosave, max_input_bytes).is_some() {
                    console.line(format!(
                        "an autosave is at {}: the page offers to resume it; the first new edit replaces it",
                        autosave.display()
                    ))
                } else {
                    console.line(format!("autosaving to {}", autosave.display()))
                }
            })
            .and_then(|()| console.line("stop with Ctrl+C"))
            .and_then(|()| console.flush());
        if open {
            let opener = if cfg!(target_os = "macos") {
                "open"
            } else {
                "xdg-open"
            };
            if std::process::Command::new(opener).arg(url).spawn().is_err() {
                let _ = console.line(format!("(could not start {opener}: open the URL yourself)"));
            }
        }
    })?;
    printed?;
    Ok(0)
}
