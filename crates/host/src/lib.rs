//! The host of ecles-rs as a library: everything the `ecles` command does, for the command
//! itself, for tests that run it in process, and for fuzzing the run-file reader.
//!
//! * [`runfile`]: the RON run file, with positions for every error (also inside the
//!   fragments forwarded to sources);
//! * [`registry`]: built-in sources and dynamic plugin libraries;
//! * [`session`]: a run — sources built into one system, every edit and output checked before
//!   the first edit, edits on both backends, outputs rendered;
//! * [`analysis`], [`structural`], [`report`]: the whole-system analysis and the report;
//! * [`outputs`]: writing a run's files all or nothing, the report last;
//! * [`console`]: standard output that ends quietly on a closed pipe and fails cleanly when
//!   full;
//! * [`commands`]: `run`, `analyze`, `explain`, `plugins`, returning exit codes
//!   ([`error`]).

pub mod analysis;
pub mod commands;
pub mod config_text;
pub mod console;
pub mod editor;
pub mod error;
pub mod outputs;
pub mod registry;
pub mod report;
pub mod runfile;
pub mod session;
pub mod structural;
#[cfg(test)]
mod testutil;
