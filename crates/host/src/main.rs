//! `ecles`: exact editing of parameters under linear constraints, from a RON run file.
//!
//! * `ecles run RUN.ron [--out DIR] [--quiet] [--strict]` checks every input, builds the
//!   sources, runs the edits with the exact backend (cross-checked by the float backend),
//!   renders outputs and writes them with `DIR/report.json`, all or nothing.
//! * `ecles analyze RUN.ron [--json]` builds the system and reports on it without editing.
//! * `ecles explain RUN.ron PARAM... [--move VALUES] [--json]` says why parameters are fixed,
//!   limited or free, and how a change of them propagates.
//! * `ecles plugins [--path LIB]` lists the built-in sources, or checks a dynamic plugin.
//! * `ecles edit RUN.ron [--port P] [--no-token] [--no-autosave] [--open]` serves the
//!   interactive editor.
//!
//! Exit codes ([`host::error`]): 0 success; 1 the run completed but an edit failed (or, with
//! `--strict`, the backends disagreed); 2 bad input; 3 the environment failed (an output or
//! standard output could not be written).

use clap::{Parser, Subcommand};
use host::commands::{self, RunOptions};
use host::console::Console;
use std::path::PathBuf;
use std::process::ExitCode;

/// The allocator: exact arithmetic allocates a great many small blocks (every big integer's
/// digits), which mimalloc serves faster than the system's allocator (a whole-mesh analysis
/// takes a fifth less time). Feature `mimalloc`, on by default. Built without transparent
/// huge pages (`no_thp`): with them every first touch of a 2 MiB page is cleared whole, and on
/// the virtual machines measured (BENCHMARKS.md, 2026-12-03) that made a whole-mesh analysis
/// spend 2.4–2.6 s of 8–10 s in the kernel clearing pages, against 0.9–1.3 s without; a long
/// editing session's resident memory halves (55 → 27 MB) at the same speed.
#[cfg(feature = "mimalloc")]
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// mimalloc's `mi_option_purge_delay` (the 16th option of `mi_option_e` in mimalloc 3's
/// `mimalloc.h`, not named by `libmimalloc-sys`; the only option whose default is 1 000).
#[cfg(feature = "mimalloc")]
const MI_OPTION_PURGE_DELAY: libmimalloc_sys::mi_option_t = 15;

/// How long freed memory stays with mimalloc before it is returned to the system, in ms.
/// mimalloc 3 keeps it 1 s; a whole-mesh analysis frees and allocates in phases on different
/// threads, whose freed pages are not reused by the next phase in that time, so its peak
/// resident memory was 0.95–1.02·10⁹ bytes at 100 352 triangles for a live heap of 0.87·10⁹
/// (BENCHMARKS.md, 2026-12-04). At 200 ms the peak is the live heap (0.90·10⁹ bytes) for about
/// a tenth more time; small runs are unchanged. `MIMALLOC_PURGE_DELAY` (or its old name
/// `MIMALLOC_RESET_DELAY`) still overrides it.
#[cfg(feature = "mimalloc")]
const PURGE_DELAY_MS: std::ffi::c_long = 200;

/// Sets the allocator's options that differ from its defaults (see [`PURGE_DELAY_MS`]).
#[allow(unsafe_code)] // A call into mimalloc's C interface.
fn tune_allocator() {
    #[cfg(feature = "mimalloc")]
    // SAFETY: setting an option's default is a plain, unsynchronised store into mimalloc's
    // option table, valid for any option index below `_mi_option_last` and any value while no
    // other thread runs: `main` calls this first, before any thread is started.
    unsafe {
        libmimalloc_sys::mi_option_set_default(MI_OPTION_PURGE_DELAY, PURGE_DELAY_MS);
    }
}

/// Exact editing of parameters under linear constraints.
#[derive(Debug, Parser)]
#[command(name = "ecles", version, about)]
struct Cli {
    /// Largest input file (run file, mesh, model, height field) read, in bytes.
    #[arg(long, global = true, default_value_t = api::input::DEFAULT_MAX_INPUT_BYTES)]
    max_input_bytes: u64,
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
    /// Explain why parameters are fixed, limited or free (Dulmage–Mendelsohn blocks in solve
    /// order) and how a change of them propagates (exact null space: the directions they can
    /// move in, the constraints that remove the others, what a move forces).
    Explain {
        /// The RON run file.
        run: PathBuf,
        /// Parameter names (`src.name`); for the blocks alone also one coordinate `src.name[k]`.
        #[arg(required = true, num_args = 1..)]
        params: Vec<String>,
        /// A move of the parameters: exact numbers separated by commas, one per coordinate in
        /// order (`"3,-2"`): which other parameters it forces, and by how much.
        #[arg(long = "move", value_name = "VALUES", allow_hyphen_values = true)]
        requested: Option<String>,
        /// Print the propagation analysis as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Serve the interactive editor for a run file on 127.0.0.1 and print its URL.
    Edit {
        /// The RON run file.
        run: PathBuf,
        /// Port on 127.0.0.1 (0: any free port).
        #[arg(long, default_value_t = 0)]
        port: u16,
        /// Serve without the session token (scripted use only: any local program can then
        /// drive the editor).
        #[arg(long)]
        no_token: bool,
        /// Keep no autosave (by default the session is autosaved after every change as
        /// `<run>.autosave.ron` beside the run file, and one found at start is offered for
        /// resuming).
        #[arg(long)]
        no_autosave: bool,
        /// Open the page in the system's browser.
        #[arg(long)]
        open: bool,
    },
    /// List built-in sources, or check a dynamic plugin library.
    Plugins {
        /// A plugin library to load and describe (without an extension: the platform's
        /// library file name, as in run files).
        #[arg(long)]
        path: Option<PathBuf>,
    },
}

fn main() -> ExitCode {
    tune_allocator();
    let cli = Cli::parse();
    let limit = cli.max_input_bytes;
    let mut console = Console::stdout();
    let outcome = match cli.command {
        Command::Run {
            run,
            out,
            quiet,
            strict,
        } => commands::run(
            &RunOptions {
                run,
                out,
                quiet,
                strict,
                max_input_bytes: limit,
            },
            &mut console,
        ),
        Command::Analyze { run, json } => commands::analyze(&run, json, limit, &mut console),
        Command::Explain {
            run,
            params,
            requested,
            json,
        } => commands::explain(
            &run,
            &params,
            requested.as_deref(),
            json,
            limit,
            &mut console,
        ),
        Command::Plugins { path } => commands::plugins(path.as_deref(), &mut console),
        Command::Edit {
            run,
            port,
            no_token,
            no_autosave,
            open,
        } => commands::edit(
            &run,
            &host::editor::EditorOptions {
                port,
                token: !no_token,
                autosave: !no_autosave,
            },
            open,
            limit,
            &mut console,
        ),
    };
    match outcome {
        Ok(code) => ExitCode::from(code),
        Err(e) => {
            // Standard error may be closed too: never panic over a message.
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

#[cfg(all(test, feature = "mimalloc"))]
mod tests {
    use super::*;

    /// The option index names the purge delay: untouched in this test process, it holds the
    /// purge delay's default (1 000 ms, no other option's default), unless the environment
    /// overrides it; [`tune_allocator`] then sets it.
    #[test]
    #[allow(unsafe_code)] // Calls into mimalloc's C interface.
    fn the_purge_delay_option_is_the_one_set() {
        if ["MIMALLOC_PURGE_DELAY", "MIMALLOC_RESET_DELAY"]
            .iter()
            .any(|name| std::env::var_os(name).is_some())
        {
            return;
        }
        // SAFETY: reading an option is a plain load from mimalloc's option table.
        let read = || unsafe { libmimalloc_sys::mi_option_get(MI_OPTION_PURGE_DELAY) };
        assert_eq!(read(), 1000);
        // The only test of this binary: no other thread sets options meanwhile.
        tune_allocator();
        assert_eq!(read(), PURGE_DELAY_MS);
    }
}
