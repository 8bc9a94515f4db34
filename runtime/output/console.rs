//! The terminal streams. Every line a command prints goes through [`write_out`] (stdout, an error
//! when the stream is closed or full) or [`write_err`] (stderr, messages only: a failure to
//! write a message is ignored, it must not stop the work). Never `println!`: it panics on a
//! closed pipe (`magbubble modes | head`) or a full disk (`> /dev/full`).
//!
//! The macros `outln!`/`out!` (`?` inside: use them in functions returning `anyhow::Result`)
//! and `noteln!` are exported at the crate root.

use std::fmt;
use std::io::{self, Write};

/// Standard output could not be written. A broken pipe (the reader went away, `| head`) ends
/// the command quietly; anything else (ENOSPC, EIO) is reported.
#[derive(Debug, thiserror::Error)]
#[error("cannot write to standard output: {0}")]
pub struct StdoutError(#[source] pub io::Error);

impl StdoutError {
    /// The reader closed the pipe: not worth a message.
    pub fn is_broken_pipe(&self) -> bool {
        self.0.kind() == io::ErrorKind::BrokenPipe
    }
}

/// Writes to stdout (line-buffered: a full line reaches the OS before this returns).
pub fn write_out(args: fmt::Arguments<'_>) -> Result<(), StdoutError> {
    io::stdout().lock().write_fmt(args).map_err(StdoutError)
}

/// Flushes stdout (what `print!` without a newline left in the buffer).
pub fn flush_out() -> Result<(), StdoutError> {
    io::stdout().lock().flush().map_err(StdoutError)
}

/// Writes a message to stderr; an error (closed or full stderr) is ignored.
pub fn write_err(args: fmt::Arguments<'_>) {
    let _ = io::stderr().lock().write_fmt(args);
}

/// `println!` that returns (through `?`) a [`StdoutError`] instead of panicking.
#[macro_export]
macro_rules! outln {
    () => { $crate::output::write_out(format_args!("\n"))? };
    ($($t:tt)*) => { $crate::output::write_out(format_args!("{}\n", format_args!($($t)*)))? };
}

/// `print!` that returns (through `?`) a [`StdoutError`] instead of panicking.
#[macro_export]
macro_rules! out {
    ($($t:tt)*) => { $crate::output::write_out(format_args!($($t)*))? };
}

/// `eprintln!` that never panics (a message lost on a closed stderr is not an error).
#[macro_export]
macro_rules! noteln {
    ($($t:tt)*) => { $crate::output::write_err(format_args!("{}\n", format_args!($($t)*))) };
}
