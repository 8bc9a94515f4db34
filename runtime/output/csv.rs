//! Streaming CSV: rows are formatted and written as they come (bounded memory).

use super::{AtomicFile, OutputError};
use std::io::Write;
use std::path::Path;

/// A CSV file with a fixed header, written atomically (see [`AtomicFile`]).
#[derive(Debug)]
pub struct CsvWriter {
    file: AtomicFile,
    columns: usize,
    rows: u64,
    error: Option<std::io::Error>,
}

impl CsvWriter {
    /// Creates `path.tmp` and writes the header line.
    pub fn create<S: AsRef<str>>(path: &Path, header: &[S]) -> Result<Self, OutputError> {
        let mut file = AtomicFile::create(path)?;
        let line = header
            .iter()
            .map(|h| h.as_ref())
            .collect::<Vec<_>>()
            .join(",");
        writeln!(file, "{line}").map_err(|source| OutputError::Write {
            path: path.display().to_string(),
            source,
        })?;
        Ok(CsvWriter {
            file,
            columns: header.len(),
            rows: 0,
            error: None,
        })
    }

    /// Writes one row (`f64` in shortest round-trip form). An I/O error is remembered and
    /// returned by [`CsvWriter::commit`], so this can be called from an observer closure.
    pub fn row(&mut self, values: &[f64]) {
        debug_assert_eq!(values.len(), self.columns, "CSV row width");
        if self.error.is_some() {
            return;
        }
        let mut result = Ok(());
        for (i, v) in values.iter().enumerate() {
            let sep = if i == 0 { "" } else { "," };
            result = write!(self.file, "{sep}{v:e}");
            if result.is_err() {
                break;
            }
        }
        if let Err(e) = result.and_then(|_| writeln!(self.file)) {
            self.error = Some(e);
        } else {
            self.rows += 1;
        }
    }

    /// Rows written so far.
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// Renames the file into place, or reports the first write error (the temp file is removed).
    pub fn commit(self) -> Result<(), OutputError> {
        if let Some(source) = self.error {
            return Err(OutputError::Write {
                path: self.file.path().display().to_string(),
                source,
            });
        }
        self.file.commit()
    }
}
