//! The measured data of a fit: `t` [s], `R` [m], optional shape amplitudes `a2`, `a4`, … [m]
//! (fitted when present) and optional uncertainties `sigma_R`, `sigma_a2`, … [m].
//!
//! **Weights.** A column with its `sigma_*` column is weighted 1/σ_i² and its standard errors
//! are absolute. A column without one gets one weight for all its points, 1/σ_c² with σ_c the
//! column's standard deviation about its mean (1 % of the mean radius when that is 0): every
//! fitted column then counts by its shape, not by its size in metres, so a 10 nm a_2 weighs as
//! much as a 1 µm R oscillation ("R and shapes count comparably"); the covariance is then scaled
//! by the reduced χ² (the noise level is estimated from the residuals).

use anyhow::{bail, Context};

/// One fitted column.
#[derive(Debug, Clone)]
pub struct Column {
    /// `R`, `a2`, …
    pub name: String,
    pub values: Vec<f64>,
    /// σ_i per point [m].
    pub sigma: Vec<f64>,
    /// `true`: the σ came with the data (absolute standard errors).
    pub sigma_given: bool,
}

/// The data of a fit.
#[derive(Debug, Clone)]
pub struct Data {
    /// Strictly increasing [s].
    pub t: Vec<f64>,
    pub columns: Vec<Column>,
}

impl Data {
    /// Reads a CSV file (header line, comma-separated numbers; lines starting with `#` skipped).
    pub fn read(path: &std::path::Path) -> anyhow::Result<Data> {
        let text = std::fs::read_to_string(path).with_context(|| format!("cannot read the data file {}", path.display()))?;
        Self::parse(&text).with_context(|| format!("data file {}", path.display()))
    }

    /// Parses CSV text (see [`Data::read`]).
    pub fn parse(text: &str) -> anyhow::Result<Data> {
        Self::from_columns(csv_columns(text, "t, R[, a2, …][, sigma_R, …]")?)
    }

    /// Data from named columns (what a CSV file or a DataFrame holds).
    pub fn from_columns(columns: Vec<(String, Vec<f64>)>) -> anyhow::Result<Data> {
        let mut seen = std::collections::BTreeSet::new();
        for (name, v) in &columns {
            if !seen.insert(name.as_str()) {
                bail!("column `{name}` appears twice");
            }
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                bail!("column {name}, row {}: {} (NaN or infinite)", i + 1, v[i]);
            }
        }
        let get = |n: &str| columns.iter().find(|(c, _)| c == n).map(|(_, v)| v.clone());
        let t = get("t").context("no column `t` [s]")?;
        let r = get("R").context("no column `R` [m]")?;
        if t.len() < 2 {
            bail!("{} data rows: at least 2 are needed", t.len());
        }
        if let Some(i) = (1..t.len()).find(|&i| !(t[i] > t[i - 1])) {
            let what = if t[i] == t[i - 1] { "duplicated" } else { "not increasing" };
            bail!("column t, row {}: t = {:e} s after {:e} s ({what}: t must increase strictly)", i + 1, t[i], t[i - 1]);
        }
        let mut fitted = vec![("R".to_string(), r)];
        for (name, v) in &columns {
            let shape = name.strip_prefix('a').and_then(|k| k.parse::<usize>().ok());
            match (name.as_str(), shape) {
                ("t" | "R", _) => {}
                (_, Some(k)) if k >= 2 && k % 2 == 0 => fitted.push((name.clone(), v.clone())),
                _ if name.strip_prefix("sigma_").is_some_and(|c| c == "R" || columns.iter().any(|(n, _)| n == c && n != "t")) => {}
                _ => bail!("unknown column `{name}` (expected t, R, a2, a4, …, sigma_R, sigma_a2, …)"),
            }
        }
        let mean_r = fitted[0].1.iter().sum::<f64>() / t.len() as f64;
        let mut out = Vec::new();
        for (name, values) in fitted {
            let (sigma, given) = match get(&format!("sigma_{name}")) {
                Some(s) => {
                    if let Some(i) = s.iter().position(|&x| !(x > 0.0)) {
                        bail!("column sigma_{name}, row {}: {} (an uncertainty must be > 0)", i + 1, s[i]);
                    }
                    (s, true)
                }
                None => {
                    let mean = values.iter().sum::<f64>() / values.len() as f64;
                    let sd = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64).sqrt();
                    let sd = if sd > 0.0 { sd } else { 0.01 * mean_r.abs() };
                    (vec![sd; values.len()], false)
                }
            };
            out.push(Column { name, values, sigma, sigma_given: given });
        }
        Ok(Data { t, columns: out })
    }

    /// Points × columns: the number of residuals.
    pub fn len(&self) -> usize {
        self.t.len() * self.columns.len()
    }

    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }
}

/// The named columns of CSV text (header line, comma-separated finite numbers; lines starting
/// with `#` skipped); `expected` names the columns in the error for a missing header.
pub fn csv_columns(text: &str, expected: &str) -> anyhow::Result<Vec<(String, Vec<f64>)>> {
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let Some((_, header)) = lines.next() else { bail!("no header line (expected columns {expected})") };
    let names: Vec<String> = header.split(',').map(|s| s.trim().to_string()).collect();
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    for (i, line) in lines {
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        if cells.len() != names.len() {
            bail!("line {}: {} values, the header has {} columns", i + 1, cells.len(), names.len());
        }
        for ((c, cell), name) in cols.iter_mut().zip(&cells).zip(&names) {
            let v: f64 = cell.parse().map_err(|_| anyhow::anyhow!("line {}, column {name}: `{cell}` is not a number", i + 1))?;
            if !v.is_finite() {
                bail!("line {}, column {name}: {cell} (NaN or infinite)", i + 1);
            }
            c.push(v);
        }
    }
    Ok(names.into_iter().zip(cols).collect())
}
