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
    if v.is_finite() {
        let mut buf = zmij::Buffer::new();
        let s = buf.format_finite(v).as_bytes();
        if let Some((head, exp)) = normalised_exponent_form(s) {
            out.extend_from_slice(head);
            out.extend_from_slice(exp);
            return;
        }
    }
    let mut o = [0u8; 32];
    let n = exp_bytes(v, &mut o);
    out.extend_from_slice(&o[..n]);
}

/// zmij's output `[-]d[.dd…d]e[±]x` with a normalised mantissa (leading digit not 0, no
/// trailing 0 after the point) is `{:e}` already, but for a `+` of the exponent: the text up to
/// and including the `e`, and the exponent without the `+` (zmij writes no leading zeros in the
/// exponent). `None` for any other shape (plain decimals: the general path of [`exp_bytes`]).
/// This is the common case of a run's series (lengths in m, times in s), copied without
/// re-parsing (issue 16: the CSV was 17 % of the boundary-layer run).
#[inline]
fn normalised_exponent_form(s: &[u8]) -> Option<(&[u8], &[u8])> {
    // the exponent is at most "e-324": its 'e' is one of the last 5 bytes
    let n = s.len();
    let p = (n.saturating_sub(5)..n).rev().find(|&i| s[i] == b'e')?;
    let mant = match s.first()? {
        b'-' => &s[1..p],
        _ => &s[..p],
    };
    let normalised = match mant {
        [d] => *d != b'0',
        [d, b'.', .., last] => *d != b'0' && *last != b'0',
        _ => false,
    };
    if !normalised {
        return None;
    }
    let exp = &s[p + 1..];
    let exp = match exp.first() {
        Some(b'+') => &exp[1..],
        _ => exp,
    };
    Some((&s[..=p], exp))
}

/// [`push_exp`] into a stack buffer (at most 24 bytes: `-d.dddddddddddddddde-324`); returns the
/// length. One copy per value instead of a push per byte.
fn exp_bytes(v: f64, o: &mut [u8; 32]) -> usize {
    if !v.is_finite() {
        let s: &[u8] = if v.is_nan() { b"NaN" } else if v > 0.0 { b"inf" } else { b"-inf" };
        o[..s.len()].copy_from_slice(s);
        return s.len();
    }
    let mut buf = zmij::Buffer::new();
    let s = buf.format_finite(v).as_bytes();
    let mut n = 0;
    let s = match s.first() {
        Some(b'-') => {
            o[0] = b'-';
            n = 1;
            &s[1..]
        }
        _ => s,
    };
    // the exponent is at most "e-324": look for it from the back
    let (mant, exp) = match s.iter().rposition(|&c| c == b'e' || c == b'E') {
        Some(p) => (&s[..p], parse_exponent(&s[p + 1..])),
        None => (s, 0),
    };
    // Fast path: zmij's exponent form with a normalised mantissa "d" or "d.dd…d" (no trailing 0).
    let normalised = match mant {
        [d] => *d != b'0',
        [d, b'.', .., last] => *d != b'0' && *last != b'0',
        _ => false,
    };
    if normalised && mant.len() < s.len() {
        o[n..n + mant.len()].copy_from_slice(mant);
        n += mant.len();
        o[n] = b'e';
        return put_int(o, n + 1, exp);
    }
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
    let Some(lead) = digits[..nd].iter().position(|&c| c != b'0') else {
        o[n..n + 3].copy_from_slice(b"0e0");
        return n + 3;
    };
    let last = digits[..nd].iter().rposition(|&c| c != b'0').unwrap_or(lead);
    let e10 = exp + point - lead as i32 - 1;
    o[n] = digits[lead];
    n += 1;
    if last > lead {
        o[n] = b'.';
        n += 1;
        let d = &digits[lead + 1..=last];
        // 17 significant digits at most, so this stays inside `o`
        o[n..n + d.len()].copy_from_slice(d);
        n += d.len();
    }
    o[n] = b'e';
    put_int(o, n + 1, e10)
}

/// The exponent digits zmij prints after `e` (`-7`, `+21`, `21`).
fn parse_exponent(s: &[u8]) -> i32 {
    let (neg, digits) = match s.first() {
        Some(b'-') => (true, &s[1..]),
        Some(b'+') => (false, &s[1..]),
        _ => (false, s),
    };
    let e = digits.iter().take_while(|c| c.is_ascii_digit()).fold(0i32, |e, &c| e * 10 + i32::from(c - b'0'));
    if neg { -e } else { e }
}

/// Writes a decimal exponent (|e| ≤ 400) at `o[n..]`; returns the new length.
fn put_int(o: &mut [u8; 32], mut n: usize, e: i32) -> usize {
    if e < 0 {
        o[n] = b'-';
        n += 1;
    }
    let u = e.unsigned_abs();
    if u >= 100 {
        o[n] = b'0' + (u / 100) as u8;
        n += 1;
    }
    if u >= 10 {
        o[n] = b'0' + (u / 10 % 10) as u8;
        n += 1;
    }
    o[n] = b'0' + (u % 10) as u8;
    n + 1
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
        self.line.reserve(24 * values.len() + 8 + label.map_or(0, str::len));
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
    use super::{exp_bytes, push_exp};

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
            // the direct copy of zmij's exponent form writes what the general path writes
            let mut o = [0u8; 32];
            let n = exp_bytes(v, &mut o);
            assert_eq!(&out[..], &o[..n], "{v:e}");
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
        for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            out.clear();
            push_exp(&mut out, v);
            assert_eq!(std::str::from_utf8(&out).unwrap(), format!("{v:e}"));
        }
    }
}
