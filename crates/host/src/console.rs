//! Standard output that never panics.
//!
//! `println!` panics when standard output fails ("failed printing to stdout"), so
//! `ecles analyze RUN --json | head -c1` or `ecles run RUN > /dev/full` would abort. A
//! [`Console`] writes through a fallible writer instead: when the reader has gone away (a
//! closed pipe) it stops printing quietly and the command carries on to its normal end; any
//! other failure (a full disk) is a [`RunError::Environment`] with a message.

use crate::error::RunError;
use std::fmt::Display;
use std::io::{ErrorKind, Write};

/// Where a command prints its results.
pub struct Console<'a> {
    out: Box<dyn Write + 'a>,
    /// The reader closed the pipe: nothing more is printed.
    closed: bool,
}

impl<'a> Console<'a> {
    /// A console on any writer (tests capture the output in a `Vec<u8>`).
    pub fn new(out: impl Write + 'a) -> Self {
        Console {
            out: Box::new(out),
            closed: false,
        }
    }

    /// The process's standard output.
    pub fn stdout() -> Console<'static> {
        Console::new(std::io::stdout())
    }

    /// Prints one line.
    pub fn line(&mut self, text: impl Display) -> Result<(), RunError> {
        if self.closed {
            return Ok(());
        }
        let result = writeln!(self.out, "{text}");
        self.check(result)
    }

    /// Flushes what was printed (and reports a failure that buffering hid).
    pub fn flush(&mut self) -> Result<(), RunError> {
        if self.closed {
            return Ok(());
        }
        let result = self.out.flush();
        self.check(result)
    }

    /// True once the reader went away.
    pub fn is_closed(&self) -> bool {
        self.closed
    }

    fn check(&mut self, result: std::io::Result<()>) -> Result<(), RunError> {
        match result {
            Ok(()) => Ok(()),
            Err(e) if e.kind() == ErrorKind::BrokenPipe => {
                self.closed = true;
                Ok(())
            }
            Err(e) => Err(RunError::environment(format!(
                "cannot write to standard output: {e}"
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A writer that fails with `kind` after `capacity` bytes.
    struct Failing {
        written: Vec<u8>,
        capacity: usize,
        kind: ErrorKind,
    }

    impl Write for Failing {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            if self.written.len() + buf.len() > self.capacity {
                return Err(std::io::Error::from(self.kind));
            }
            self.written.extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_closed_pipe_ends_printing_quietly() {
        let mut sink = Failing {
            written: Vec::new(),
            capacity: 4,
            kind: ErrorKind::BrokenPipe,
        };
        let mut console = Console::new(&mut sink);
        console.line("abc").expect("fits");
        console
            .line("defgh")
            .expect("a closed pipe is not an error");
        assert!(console.is_closed());
        console.line("more").expect("nothing more is printed");
        console.flush().expect("flush");
        drop(console);
        assert_eq!(sink.written, b"abc\n");
    }

    #[test]
    fn a_full_device_is_an_environment_error() {
        let mut sink = Failing {
            written: Vec::new(),
            capacity: 0,
            kind: ErrorKind::StorageFull,
        };
        let mut console = Console::new(&mut sink);
        let error = console.line("x").expect_err("full");
        assert_eq!(error.exit_code(), crate::error::EXIT_ENVIRONMENT);
        assert!(error
            .to_string()
            .starts_with("cannot write to standard output"));
    }
}
