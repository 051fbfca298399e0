//! Why a command could not complete, and the exit code that says so.
//!
//! | code | meaning |
//! | --- | --- |
//! | 0 | success |
//! | 1 | the run completed, but an edit was not solvable (or, with `--strict`, the float backend disagreed) |
//! | 2 | bad input: run file, mesh, model, plugin, an edit or output that cannot run, contradicting constraints |
//! | 3 | the environment failed: an output could not be written (disk full, no permission), standard output is full |
//!
//! Codes 2 and 3 leave no `report.json` and none of the run's outputs behind.

/// Why a command stopped before completing.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RunError {
    /// The input is bad (exit code 2). The message names the file with line and column, or
    /// the item.
    #[error("{0}")]
    Input(String),
    /// The environment failed (exit code 3): writing an output or standard output.
    #[error("{0}")]
    Environment(String),
}

impl RunError {
    /// Bad input.
    pub fn input(message: impl Into<String>) -> Self {
        RunError::Input(message.into())
    }

    /// A failure of the environment.
    pub fn environment(message: impl Into<String>) -> Self {
        RunError::Environment(message.into())
    }

    /// The process exit code: 2 for bad input, 3 for the environment.
    pub fn exit_code(&self) -> u8 {
        match self {
            RunError::Input(_) => EXIT_INPUT,
            RunError::Environment(_) => EXIT_ENVIRONMENT,
        }
    }
}

/// Exit code: an edit was not solvable, or the backends disagreed under `--strict`.
pub const EXIT_EDIT_FAILED: u8 = 1;
/// Exit code: bad input.
pub const EXIT_INPUT: u8 = 2;
/// Exit code: the environment failed.
pub const EXIT_ENVIRONMENT: u8 = 3;
