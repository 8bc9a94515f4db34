//! Output files: atomic (written to `NAME.tmp` in the same directory, renamed into place on
//! success, removed on failure), streaming CSV with bounded memory, pretty JSON, and a
//! progress bar that appears only on a terminal.
//!
//! An output directory is created by [`OutputDir::create`] only once the inputs are known to be
//! valid; if it did not exist and the run fails, [`OutputDir::discard`] removes it again, so a
//! failed run leaves nothing behind.

mod atomic;
#[macro_use]
mod console;
mod csv;
#[cfg(unix)]
mod interrupt;
mod lock;
mod progress;

pub use atomic::{AtomicFile, OutputDir};
pub use console::{flush_out, write_err, write_out, StdoutError};
pub use csv::{series_header, CsvWriter};
pub use lock::{is_lock_file, DirLock, LOCK_FILE};
#[cfg(unix)]
pub use interrupt::{cancel_on_signal, cancelling_signal, clean_up_on_signal, note_on_signal};
pub use progress::{Counter, Progress, Spinner};

use std::path::Path;

/// Errors writing output (the path is always named).
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("cannot create output directory {path}: {source}")]
    CreateDir {
        path: String,
        source: std::io::Error,
    },
    #[error("cannot write {path}: {source}")]
    Write {
        path: String,
        source: std::io::Error,
    },
    #[error("output directory {path} is in use by another process{}: wait for it to finish or choose another output directory", owner.map(|p| format!(" (pid {p})")).unwrap_or_default())]
    Busy {
        path: String,
        /// The owner's pid, when its note could be read.
        owner: Option<u32>,
    },
    #[error("cannot serialize {path}: {source}")]
    Json {
        path: String,
        source: serde_json::Error,
    },
}

/// Writes `value` as pretty JSON to `path`, atomically.
pub fn write_json<T: serde::Serialize + ?Sized>(path: &Path, value: &T) -> Result<(), OutputError> {
    let mut file = AtomicFile::create(path)?;
    serde_json::to_writer_pretty(&mut file, value).map_err(|source| OutputError::Json {
        path: path.display().to_string(),
        source,
    })?;
    use std::io::Write;
    file.write_all(b"\n").map_err(|source| OutputError::Write {
        path: path.display().to_string(),
        source,
    })?;
    file.commit()
}

/// Serializes `(name, value)` pairs as a JSON object, keeping their order (R, a2, b2, a4, …).
#[derive(Debug, Clone, Copy)]
pub struct OrderedMap<'a>(pub &'a [(String, f64)]);

impl serde::Serialize for OrderedMap<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = s.serialize_map(Some(self.0.len()))?;
        for (k, v) in self.0 {
            map.serialize_entry(k, v)?;
        }
        map.end()
    }
}
