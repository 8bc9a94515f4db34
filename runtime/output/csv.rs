//! Streaming CSV: rows are formatted and written as they come (bounded memory).

use super::{AtomicFile, OutputError};
use crate::scene::Scene;
use std::io::Write;
use std::path::Path;

/// The header of a run's `series.csv`: t, R, then a_k, b_k for k = 2, 4, …, N (shared by `run`,
/// `sweep --keep-series` and the Python binding).
pub fn series_header(scene: &Scene) -> Vec<String> {
    let mut h = vec!["t".to_string(), "R".to_string()];
    for k in scene.modes.orders() {
        h.push(format!("a{k}"));
        h.push(format!("b{k}"));
    }
    h
}

/// A CSV file with a fixed header, written atomically (see [`AtomicFile`]).
#[derive(Debug)]
pub struct CsvWriter {
    file: AtomicFile,
    columns: usize,
    rows: u64,
    error: Option<std::io::Error>,
    /// The row being formatted (one write per row).
    line: Vec<u8>,
}

/// Appends `v` as Rust's `{:e}` prints it (shortest round-trip digits, `d.ddde±x`), from the
/// shortest digits of `zmij` (Schubfach), several times faster than `fmt`. The value reads back
/// exactly; when 17 digits are needed, the last digit may differ from std's choice.
pub(crate) fn push_exp(out: &mut Vec<u8>, v: f64) {
    if !v.is_finite() {
        out.extend_from_slice(format!("{v:e}").as_bytes());
        return;
    }
    let mut buf = zmij::Buffer::new();
    let s = buf.format_finite(v).as_bytes();
    let (neg, s) = match s.first() {
        Some(b'-') => (true, &s[1..]),
        _ => (false, s),
    };
    let (mant, exp) = match s.iter().position(|&c| c == b'e' || c == b'E') {
        Some(p) => (&s[..p], std::str::from_utf8(&s[p + 1..]).ok().and_then(|e| e.parse::<i32>().ok()).unwrap_or(0)),
        None => (s, 0),
    };
    // digits without the point, and the position of the point among them
    let mut digits = [0u8; 32];
    let (mut nd, mut point) = (0usize, None);
    for &c in mant {
        if c == b'.' {
            point = Some(nd);
        } else if nd < digits.len() {
            digits[nd] = c;
            nd += 1;
        }
    }
    let point = point.unwrap_or(nd) as i32;
    let lead = digits[..nd].iter().position(|&c| c != b'0');
    if neg {
        out.push(b'-');
    }
    let Some(lead) = lead else {
        out.extend_from_slice(b"0e0");
        return;
    };
    let last = digits[..nd].iter().rposition(|&c| c != b'0').unwrap_or(lead);
    let e10 = exp + point - lead as i32 - 1;
    out.push(digits[lead]);
    if last > lead {
        out.push(b'.');
        out.extend_from_slice(&digits[lead + 1..=last]);
    }
    out.push(b'e');
    out.extend_from_slice(e10.to_string().as_bytes());
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
            line: Vec::new(),
        })
    }

    /// Writes one row (`f64` in shortest round-trip form). An I/O error is remembered and
    /// returned by [`CsvWriter::commit`], so this can be called from an observer closure.
    pub fn row(&mut self, values: &[f64]) {
        self.row_after(None, values);
    }

    /// Writes one row whose first column is the text `label` (a name such as `radau5`; it must
    /// not contain a comma, quote or newline), then `values` as in [`CsvWriter::row`].
    pub fn labeled_row(&mut self, label: &str, values: &[f64]) {
        debug_assert!(!label.contains([',', '"', '\n']), "CSV label {label:?}");
        self.row_after(Some(label), values);
    }

    fn row_after(&mut self, label: Option<&str>, values: &[f64]) {
        debug_assert_eq!(values.len() + usize::from(label.is_some()), self.columns, "CSV row width");
        if self.error.is_some() {
            return;
        }
        self.line.clear();
        if let Some(l) = label {
            self.line.extend_from_slice(l.as_bytes());
        }
        for (i, v) in values.iter().enumerate() {
            if i > 0 || label.is_some() {
                self.line.push(b',');
            }
            push_exp(&mut self.line, *v);
        }
        self.line.push(b'\n');
        if let Err(e) = self.file.write_all(&self.line) {
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

#[cfg(test)]
mod tests {
    use super::push_exp;

    #[test]
    fn fast_exponent_format_is_the_std_one() {
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut values = vec![0.0, -0.0, 1.0, -1.0, 0.1, 1e-8, 1e-4, 123456.0, 1e21, 5e-324, f64::MAX, f64::MIN_POSITIVE, 2.5e-9, 10.0];
        for _ in 0..20000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            values.push(f64::from_bits(x));
            values.push((x % 1_000_000) as f64 * 1e-9);
        }
        let mut out = Vec::new();
        let mut differ = 0;
        for v in values.into_iter().filter(|v| v.is_finite()) {
            out.clear();
            push_exp(&mut out, v);
            // the `{:e}` shape with shortest round-trip digits (when 17 digits are needed the last
            // one may differ from std's choice; both read back as v)
            let (ours, std) = (std::str::from_utf8(&out).unwrap(), format!("{v:e}"));
            assert_eq!(ours.parse::<f64>().unwrap().to_bits(), v.to_bits(), "{ours} vs {std}");
            assert_eq!(ours.len(), std.len(), "{ours} vs {std}");
            if ours != std {
                differ += 1;
            }
        }
        assert!(differ < 100, "{differ} values differ from std's digits");
    }
}
