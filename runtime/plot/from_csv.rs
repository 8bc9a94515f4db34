//! Plots straight from the CSVs the analysis commands write, for their `--plot` flags.
//!
//! `magbubble stability` writes one CSV per family with the columns
//! `index, <frequency key>, critical, outcome, …, mode, max_multiplier_stable, …`;
//! [`stability_plot`] turns a set of them into the stability diagram and the first-unstable-
//! mode staircase.

use super::kinds::{first_unstable_mode, stability_diagram, Curve};
use super::{PlotError, Saved, Series};
use std::path::{Path, PathBuf};

/// A CSV kept as text: header and rows (double-quoted fields may contain commas).
#[derive(Debug, Clone, PartialEq)]
pub struct CsvTable {
    pub path: PathBuf,
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

fn split_fields(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(std::mem::take(&mut cur)),
            _ => cur.push(c),
        }
    }
    out.push(cur);
    out.into_iter().map(|f| f.trim().to_string()).collect()
}

impl CsvTable {
    /// Reads a CSV with a header; `#` lines and blank lines are skipped.
    pub fn read(path: &Path) -> Result<Self, PlotError> {
        let text = std::fs::read_to_string(path).map_err(|source| PlotError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'));
        let Some((_, head)) = lines.next() else {
            return Err(PlotError::Csv {
                path: path.to_path_buf(),
                line: 1,
                reason: "the file has no header line".into(),
            });
        };
        let header = split_fields(head);
        let mut rows = Vec::new();
        for (i, line) in lines {
            let fields = split_fields(line);
            if fields.len() != header.len() {
                return Err(PlotError::Csv {
                    path: path.to_path_buf(),
                    line: i + 1,
                    reason: format!("{} fields, the header has {}", fields.len(), header.len()),
                });
            }
            rows.push(fields);
        }
        Ok(Self {
            path: path.to_path_buf(),
            header,
            rows,
        })
    }

    /// Index of the first column satisfying `pred`.
    pub fn find(&self, pred: impl Fn(&str) -> bool) -> Option<usize> {
        self.header.iter().position(|h| pred(h))
    }

    /// A column as numbers; a cell that is not a number is NaN.
    pub fn numbers(&self, col: usize) -> Vec<f64> {
        self.rows
            .iter()
            .map(|r| r[col].parse::<f64>().unwrap_or(f64::NAN))
            .collect()
    }

    fn require(&self, what: &str, pred: impl Fn(&str) -> bool) -> Result<usize, PlotError> {
        self.find(pred).ok_or_else(|| PlotError::Csv {
            path: self.path.clone(),
            line: 1,
            reason: format!("no {what} column (columns: {})", self.header.join(", ")),
        })
    }
}

/// `a12` → 12, `12` → 12; anything else NaN.
fn mode_number(cell: &str) -> f64 {
    cell.trim_start_matches(|c: char| c.is_ascii_alphabetic())
        .parse::<f64>()
        .unwrap_or(f64::NAN)
}

/// Stability diagram from `magbubble stability` CSVs, one `(legend, csv)` per family: writes
/// `out_dir/stem.svg/png` (critical value against frequency in MHz) and, when the CSVs have
/// a `mode` column, `stem_mode.svg/png` (first unstable mode). `y_label` names the critical
/// quantity with its unit (`"critical ε_p"`, `"critical I0 [A]"`).
///
/// A frequency whose outcome is `stable_throughout` has no critical value; it is drawn as a
/// marker at the top of the searched range (the `stable` column) so that a sweep stable at every
/// frequency is a plot, not an error (issue 15 class 8).
pub fn stability_plot(
    families: &[(String, PathBuf)],
    out_dir: &Path,
    stem: &str,
    y_label: &str,
    log_y: bool,
) -> Result<Vec<Saved>, PlotError> {
    let mut crit = Vec::new();
    let mut modes = Vec::new();
    let mut tops = Vec::new();
    let mut x_label = "f [MHz]";
    for (label, path) in families {
        let t = CsvTable::read(path)?;
        let f = t.require("frequency (…frequency_hz)", |h| {
            h.ends_with("frequency_hz")
        })?;
        if t.header[f].starts_with("field.coil.current") {
            x_label = "f2 [MHz]";
        } else if t.header[f].starts_with("drive") {
            x_label = "f_d [MHz]";
        }
        let c = t.require("critical", |h| h == "critical")?;
        let x: Vec<f64> = t.numbers(f).iter().map(|v| v * 1e-6).collect();
        crit.push(Curve::new(label.clone(), x.clone(), t.numbers(c)));
        if let (Some(o), Some(s)) = (t.find(|h| h == "outcome"), t.find(|h| h == "stable")) {
            let top: Vec<f64> = t
                .rows
                .iter()
                .map(|r| if r[o] == "stable_throughout" { r[s].parse().unwrap_or(f64::NAN) } else { f64::NAN })
                .collect();
            tops.push(Curve::new(format!("{label}: stable up to the range top"), x.clone(), top));
        }
        if let Some(m) = t.find(|h| h == "mode") {
            modes.push(Curve::new(
                label.clone(),
                x,
                t.rows.iter().map(|r| mode_number(&r[m])).collect(),
            ));
        }
    }
    let mut diagram = stability_diagram("stability diagram", x_label, y_label, &crit, log_y);
    for (i, c) in tops.into_iter().enumerate() {
        if c.y.iter().any(|v| v.is_finite()) {
            diagram.panels[0].push(Series::points(c.label, c.x, c.y).color(i));
        }
    }
    let mut saved = vec![diagram.save(out_dir, stem)?];
    if modes.iter().any(|c| c.y.iter().any(|v| v.is_finite())) {
        saved.push(
            first_unstable_mode("first unstable mode", x_label, &modes)
                .save(out_dir, &format!("{stem}_mode"))?,
        );
    }
    Ok(saved)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoted_fields_keep_their_commas() {
        assert_eq!(split_fields(r#"1,"a, b",c"#), vec!["1", "a, b", "c"]);
        assert_eq!(split_fields(r#""say ""hi""",2"#), vec![r#"say "hi""#, "2"]);
        assert_eq!(mode_number("a12"), 12.0);
        assert!(mode_number("").is_nan());
    }
}
