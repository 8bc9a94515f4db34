//! Streaming CSV: rows are formatted and written as they come (bounded memory).

use super::{AtomicFile, OutputError};
use crate::scene::Scene;
use std::io::Write;
use std::path::Path;

/// The header of a run's `series.csv`: t, R, then a_k, b_k for k = 2, 4, …, N, then p_b [Pa]
/// with `gas.thermal = "reduced"` (its gas slot; shared by `run`, `sweep --keep-series` and the
/// Python binding; the model's row is [`crate::model::Model::state_names`]).
pub fn series_header(scene: &Scene) -> Vec<String> {
    let mut h = vec!["t".to_string(), "R".to_string()];
    for k in scene.modes.orders() {
        h.push(format!("a{k}"));
        h.push(format!("b{k}"));
    }
    if matches!(scene.gas.thermal, crate::scene::Thermal::Reduced { .. }) {
        h.push("p_b".to_string());
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
#[cfg(test)]
pub(crate) fn push_exp(out: &mut Vec<u8>, v: f64) {
    let at = out.len();
    out.resize(at + MAX_VALUE_BYTES, 0);
    let end = put_exp(out, at, v);
    out.truncate(end);
}

/// The longest text [`put_exp`] writes: `-d.dddddddddddddddde-324`.
const MAX_VALUE_BYTES: usize = 24;

/// Writes `v` as [`push_exp`] does at `out[at..]` (`out` holds at least [`MAX_VALUE_BYTES`]
/// bytes from `at`); returns the end. The common shapes of zmij's output are rewritten in place:
/// the exponent form (`+` of the exponent dropped) and the fixed form `0.0…0ddd` of 1e-5 ≤ |v| <
/// 1e-1 (to `d.dde-x`); every other value takes the general path of [`exp_bytes`]. One copy per
/// value into the row (issue 16: the CSV was 22 % of the boundary-layer run, two thirds of it
/// the copies and searches around zmij's digits).
#[inline]
fn put_exp(out: &mut [u8], at: usize, v: f64) -> usize {
    if v.is_finite() && v != 0.0 {
        let mut buf = zmij::Buffer::new();
        let s = buf.format_finite(v).as_bytes();
        if let Some(end) = rewrite_common(s, &mut out[at..at + MAX_VALUE_BYTES]) {
            return at + end;
        }
    }
    let mut o = [0u8; 32];
    let n = exp_bytes(v, &mut o);
    out[at..at + n].copy_from_slice(&o[..n]);
    at + n
}

/// zmij's text `s` of a finite non-zero value in `{:e}` form into `o` when it is one of the two
/// common shapes (see [`put_exp`]); `None` for any other (then nothing is promised about `o`).
#[inline(always)]
fn rewrite_common(s: &[u8], o: &mut [u8]) -> Option<usize> {
    let n = s.len();
    if !(3..=MAX_VALUE_BYTES).contains(&n) {
        return None;
    }
    let m0 = usize::from(s[0] == b'-');
    // the exponent form: the 'e' is followed by a sign and 1–3 digits
    let p = if s[n - 3] == b'e' {
        n - 3
    } else if n >= 4 && s[n - 4] == b'e' {
        n - 4
    } else if n >= 5 && s[n - 5] == b'e' {
        n - 5
    } else {
        return rewrite_small_fixed(s, m0, o);
    };
    // a normalised mantissa "d" or "d.dd…d" (no trailing 0), as `{:e}`
    let normalised = s[m0] != b'0' && (p == m0 + 1 || (p > m0 + 2 && s[m0 + 1] == b'.' && s[p - 1] != b'0'));
    if !normalised {
        return None;
    }
    copy_short(s, o);
    if s[p + 1] != b'+' {
        return Some(n);
    }
    o[p + 1..n - 1].copy_from_slice(&s[p + 2..n]);
    Some(n - 1)
}

/// Copies `s` (3 ≤ len ≤ [`MAX_VALUE_BYTES`]) to the front of `o` (at least that long) with
/// fixed-size moves: two overlapping 16- and 8-byte (or 8- and 8-byte) copies instead of a
/// `memcpy` call of a variable length (the same bytes).
#[inline(always)]
fn copy_short(s: &[u8], o: &mut [u8]) {
    let n = s.len();
    if n >= 16 {
        o[..16].copy_from_slice(&s[..16]);
        o[n - 8..n].copy_from_slice(&s[n - 8..n]);
    } else if n >= 8 {
        o[..8].copy_from_slice(&s[..8]);
        o[n - 8..n].copy_from_slice(&s[n - 8..n]);
    } else {
        o[..n].copy_from_slice(s);
    }
}

/// zmij's fixed form `[-]0.0…0d…d` (at most 4 zeros after the point: 1e-5 ≤ |v| < 1e-1) as
/// `[-]d.d…de-x`; `None` for another shape.
#[inline(always)]
fn rewrite_small_fixed(s: &[u8], m0: usize, o: &mut [u8]) -> Option<usize> {
    let n = s.len();
    if s[m0] != b'0' || s[m0 + 1] != b'.' {
        return None;
    }
    let mut lead = m0 + 2;
    while lead < n && s[lead] == b'0' {
        lead += 1;
    }
    let zeros = lead - (m0 + 2);
    if lead >= n || zeros > 4 || s[n - 1] == b'0' {
        return None;
    }
    o[0] = b'-';
    let mut k = m0;
    o[k] = s[lead];
    k += 1;
    if n - lead > 1 {
        o[k] = b'.';
        k += 1;
        let rest = &s[lead + 1..n];
        o[k..k + rest.len()].copy_from_slice(rest);
        k += rest.len();
    }
    o[k] = b'e';
    o[k + 1] = b'-';
    o[k + 2] = b'1' + zeros as u8;
    Some(k + 3)
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
        // the row is written into a buffer long enough for its widest text, then cut
        let lab = label.map_or(0, str::len);
        let need = lab + (MAX_VALUE_BYTES + 1) * values.len() + 1;
        if self.line.len() < need {
            self.line.resize(need, 0);
        }
        let line = &mut self.line[..];
        let mut at = 0;
        if let Some(l) = label {
            line[..lab].copy_from_slice(l.as_bytes());
            at = lab;
        }
        for (i, v) in values.iter().enumerate() {
            if i > 0 || label.is_some() {
                line[at] = b',';
                at += 1;
            }
            at = put_exp(line, at, *v);
        }
        line[at] = b'\n';
        at += 1;
        if let Err(e) = self.file.write_all(&self.line[..at]) {
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
    use super::{exp_bytes, push_exp, rewrite_common};

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
            // every decade of the fixed and exponent shapes, both signs, short and long digits
            let e = (x >> 40) % 40;
            let m = 1.0 + (x % 1_000_000_007) as f64 / 1e9;
            let w = m * 10f64.powi(e as i32 - 25);
            values.extend([w, -w, (w * 1e4).round() / 1e4, 1e-5 * m, 9.9999e-6 * m]);
        }
        let mut out = Vec::new();
        let mut differ = 0;
        for v in values.into_iter().filter(|v| v.is_finite()) {
            out.clear();
            push_exp(&mut out, v);
            // the direct digits and the rewrite of zmij's shapes write what the general path
            // (zmij's text, re-parsed) writes
            let mut o = [0u8; 32];
            let n = exp_bytes(v, &mut o);
            assert_eq!(&out[..], &o[..n], "{v:e}");
            if v.is_finite() && v != 0.0 {
                let mut w = [0u8; 32];
                if let Some(m) = rewrite_common(zmij::Buffer::new().format_finite(v).as_bytes(), &mut w) {
                    assert_eq!(&w[..m], &o[..n], "{v:e}");
                }
            }
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
