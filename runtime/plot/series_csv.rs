//! Reading a `series.csv` (one row per output sample) back for plotting.
//!
//! Column names are matched loosely so the reader survives small changes of the writer:
//! a name is split into a base and a unit, `R [m]`, `R (m)`, `R_m` → (`R`, m); the bases
//! recognised are `t`/`time`, `R`/`radius`, `a2`/`a_2`, `b4`/`b_4`, and for shape velocities
//! `adot2`/`adot_2`/`a2dot`/`da2`. Values are converted to SI from the unit (s, ms, us/µs, ns;
//! m, mm, um/µm, nm); a column without a unit is taken as SI.

use super::kinds::{time_series, TimeSeries};
use super::{Axis, Panel, Series};
use super::{PlotError, Saved};
use std::path::{Path, PathBuf};

/// A CSV table, column-major, with its header.
#[derive(Debug, Clone, PartialEq)]
pub struct SeriesTable {
    pub path: PathBuf,
    pub columns: Vec<String>,
    pub data: Vec<Vec<f64>>,
}

/// Splits `R [um]`, `R (um)`, `R_um` into (`R`, Some(scale to SI)).
fn split_unit(name: &str) -> (String, f64) {
    let name = name.trim();
    let scale_of = |u: &str| -> Option<f64> {
        Some(match u.trim() {
            "s" | "m" => 1.0,
            "ms" | "mm" => 1e-3,
            "us" | "µs" | "μs" | "um" | "µm" | "μm" => 1e-6,
            "ns" | "nm" => 1e-9,
            _ => return None,
        })
    };
    for (open, close) in [('[', ']'), ('(', ')')] {
        if let (Some(i), true) = (name.find(open), name.ends_with(close)) {
            let unit = &name[i + open.len_utf8()..name.len() - close.len_utf8()];
            return (name[..i].trim().to_string(), scale_of(unit).unwrap_or(1.0));
        }
    }
    if let Some((base, unit)) = name.rsplit_once('_') {
        if let Some(s) = scale_of(unit) {
            return (base.to_string(), s);
        }
    }
    (name.to_string(), 1.0)
}

/// `a2`, `a_2` → Some(('a', 2)); the velocity spellings → Some(('A', k)) for ȧ, ('B', k) for ḃ.
fn shape_key(base: &str) -> Option<(char, usize)> {
    let b = base.replace('_', "");
    let parse = |s: &str| s.parse::<usize>().ok();
    for (prefix, kind) in [("adot", 'A'), ("bdot", 'B'), ("da", 'A'), ("db", 'B')] {
        if let Some(k) = b.strip_prefix(prefix).and_then(parse) {
            return Some((kind, k));
        }
    }
    for (kind, vel) in [('a', 'A'), ('b', 'B')] {
        if let Some(rest) = b.strip_prefix(kind) {
            if let Some(k) = rest.strip_suffix("dot").and_then(parse) {
                return Some((vel, k));
            }
            if let Some(k) = parse(rest) {
                return Some((kind, k));
            }
        }
    }
    None
}

impl SeriesTable {
    /// Reads a CSV with a header line; lines starting with `#` are skipped; empty cells are NaN.
    pub fn read(path: &Path) -> Result<Self, PlotError> {
        let text = std::fs::read_to_string(path).map_err(|source| PlotError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let err = |line: usize, reason: String| PlotError::Csv {
            path: path.to_path_buf(),
            line,
            reason,
        };
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'));
        let Some((_, header)) = lines.next() else {
            return Err(err(1, "the file has no header line".into()));
        };
        let columns: Vec<String> = header.split(',').map(|c| c.trim().to_string()).collect();
        let mut data = vec![Vec::new(); columns.len()];
        for (i, line) in lines {
            let cells: Vec<&str> = line.split(',').collect();
            if cells.len() != columns.len() {
                return Err(err(
                    i + 1,
                    format!("{} fields, the header has {}", cells.len(), columns.len()),
                ));
            }
            for (col, cell) in data.iter_mut().zip(cells) {
                let cell = cell.trim();
                let v = if cell.is_empty() {
                    f64::NAN
                } else {
                    cell.parse::<f64>()
                        .map_err(|_| err(i + 1, format!("`{cell}` is not a number")))?
                };
                col.push(v);
            }
        }
        Ok(Self {
            path: path.to_path_buf(),
            columns,
            data,
        })
    }

    /// The column whose name (unit stripped) satisfies `pred`, converted to SI.
    fn find(&self, pred: impl Fn(&str) -> bool) -> Option<Vec<f64>> {
        self.columns.iter().zip(&self.data).find_map(|(name, col)| {
            let (base, scale) = split_unit(name);
            pred(&base).then(|| col.iter().map(|v| v * scale).collect())
        })
    }

    /// Time [s].
    pub fn time_s(&self) -> Option<Vec<f64>> {
        self.find(|b| matches!(b, "t" | "time" | "T"))
    }

    /// R [m].
    pub fn radius_m(&self) -> Option<Vec<f64>> {
        self.find(|b| matches!(b, "R" | "radius" | "r"))
    }

    /// The bubble pressure p_b [Pa] of the reduced thermal model (`gas.thermal = "reduced"`).
    pub fn bubble_pressure_pa(&self) -> Option<Vec<f64>> {
        self.find(|b| matches!(b, "p_b" | "pb"))
    }

    /// a_k (`kind = 'a'`), b_k (`'b'`) [m], ȧ_k (`'A'`), ḃ_k (`'B'`) [m/s].
    pub fn shape(&self, kind: char, k: usize) -> Option<Vec<f64>> {
        self.find(|b| shape_key(b) == Some((kind, k)))
    }

    /// The orders k present for a kind, ascending.
    pub fn orders(&self, kind: char) -> Vec<usize> {
        let mut ks: Vec<usize> = self
            .columns
            .iter()
            .filter_map(|c| shape_key(&split_unit(c).0))
            .filter(|&(c, _)| c == kind)
            .map(|(_, k)| k)
            .collect();
        ks.sort_unstable();
        ks.dedup();
        ks
    }

    /// The run as plain vectors: t, R and every a_k (and b_k when `with_b`).
    pub fn to_time_series(&self, label: &str, with_b: bool) -> Result<TimeSeries, PlotError> {
        let missing = |what: &str| PlotError::Csv {
            path: self.path.clone(),
            line: 1,
            reason: format!("no {what} column (columns: {})", self.columns.join(", ")),
        };
        let t_s = self.time_s().ok_or_else(|| missing("time (t)"))?;
        let radius_m = self.radius_m().ok_or_else(|| missing("radius (R)"))?;
        let mut shapes = Vec::new();
        let kinds: &[char] = if with_b { &['a', 'b'] } else { &['a'] };
        for &kind in kinds {
            for k in self.orders(kind) {
                if let Some(v) = self.shape(kind, k) {
                    shapes.push((format!("{kind}_{k}"), v));
                }
            }
        }
        Ok(TimeSeries {
            label: label.to_string(),
            t_s,
            radius_m,
            shapes,
            blow_up: None,
        })
    }
}

/// The blow-up (mode, t [s]) recorded in a `summary.json` of `magbubble run`
/// (`"status": {"blow_up": {"t": …, "mode": …}}`); `None` without one or when unreadable.
pub fn summary_blow_up(summary: &Path) -> Option<(String, f64)> {
    let text = std::fs::read_to_string(summary).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    let b = v.get("status")?.get("blow_up")?;
    Some((b.get("mode")?.as_str()?.to_string(), b.get("t")?.as_f64()?))
}

/// Reads `csv_path` (a `series.csv` of `magbubble run`) and writes `out_dir/series.svg` and
/// `out_dir/series.png`: R(t) above a_k(t) for every mode in the file, and p_b(t) below them
/// when the file has the reduced thermal model's `p_b`. A blow-up recorded in
/// the `summary.json` next to the CSV is marked (dashed line, title) and puts the shape modes
/// on a log |a_k| axis.
pub fn series_plot(csv_path: &Path, out_dir: &Path) -> Result<Saved, PlotError> {
    let table = SeriesTable::read(csv_path)?;
    let mut run = table.to_time_series("", false)?;
    let summary_path = csv_path.with_file_name("summary.json");
    run.blow_up = summary_blow_up(&summary_path);
    let summary = std::fs::read_to_string(&summary_path).ok().and_then(|t| serde_json::from_str(&t).ok());
    let title = match summary.as_ref().and_then(run_title) {
        Some(t) => t,
        // a series.csv without its summary: the folder's name
        None => {
            let dir = csv_path.parent().and_then(|p| p.file_name()).map(|n| n.to_string_lossy().into_owned());
            let title = dir.unwrap_or_else(|| "run".into());
            match &run.blow_up {
                Some((mode, t)) => format!("{title}: blow-up of {mode} at t = {:.2} µs", t * 1e6),
                None => title,
            }
        }
    };
    let mut figure = time_series(&title, std::slice::from_ref(&run));
    if let Some(pb) = table.bubble_pressure_pa() {
        // the reduced thermal model's p_b (issue 31) in a panel of its own, below the others
        // on a log axis by the shape panel's rule (`wants_log`: it grows or falls two decades)
        let t = run.t_s.iter().map(|t| t * 1e6).collect();
        let kpa: Vec<f64> = pb.iter().map(|p| p * 1e-3).collect();
        let y = if super::wants_log(std::slice::from_ref(&kpa), false) { Axis::log("p_b [kPa]") } else { Axis::linear("p_b [kPa]") };
        let mut panel = Panel::new(Axis::linear("t [µs]"), y);
        panel.push(Series::line("", t, kpa));
        figure.panels.push(panel);
        figure.share_x = true;
        figure.panel_height = 400;
    }
    figure.save(out_dir, "series")
}

/// The title of a run's plot from its summary.json (issue 29 item 14): the scene (file stem,
/// and how many overrides), the model (Keller–Miksis or not, closure, coupling, shell law,
/// integrator) and how the run ended — a blow-up, a stop at the credible bound, a failure.
pub fn run_title(summary: &serde_json::Value) -> Option<String> {
    let scene = summary.get("scene")?;
    let file = summary.pointer("/source/file")?.as_str()?;
    let stem = Path::new(file).file_stem()?.to_string_lossy().into_owned();
    let overrides = summary.pointer("/source/overrides").and_then(|o| o.as_array()).map_or(0, |o| o.len());
    let name = match overrides {
        0 => stem,
        1 => format!("{stem} (1 override)"),
        n => format!("{stem} ({n} overrides)"),
    };
    let mut model = vec![];
    if scene.pointer("/liquid/sound_speed").is_some_and(|c| !c.is_null()) {
        model.push("Keller–Miksis".to_string());
    }
    if scene.pointer("/modes/max_order").and_then(|n| n.as_u64()).unwrap_or(0) > 0 {
        model.push(scene.pointer("/modes/viscous")?.as_str()?.to_string());
        model.push(format!("{} coupling", scene.pointer("/modes/coupling")?.as_str()?));
    }
    let free = summary.get("active_effects").and_then(|e| e.as_array()).is_some_and(|e| e.iter().any(|e| e.as_str() == Some("free bubble (no membrane)")));
    let law = scene.pointer("/shell/law/name").and_then(|n| n.as_str()).unwrap_or("mooney-rivlin");
    model.push(if free { "free bubble".to_string() } else { law.to_string() });
    if let Some(thermal) = scene.pointer("/gas/thermal/name").and_then(|n| n.as_str()).filter(|n| *n != "polytropic") {
        model.push(format!("{thermal} thermal"));
    }
    // the method that ran (issue 34: under `auto`, the one the stiffness estimate chose)
    let ran = summary.pointer("/integrator/method").and_then(|m| m.as_str());
    model.push(ran.or(scene.pointer("/run/integrator/method").and_then(|m| m.as_str()))?.to_string());
    let us = |v: Option<&serde_json::Value>| v.and_then(|t| t.as_f64()).map_or("?".to_string(), |t| format!("{:.2} µs", t * 1e6));
    let status = summary.get("status")?;
    let end = if let Some(b) = status.get("blow_up") {
        format!("blow-up of {} at {}", b.get("mode")?.as_str()?, us(b.get("t")))
    } else if let Some(c) = status.get("out_of_credible_range") {
        let bound = c.get("bound").and_then(|b| b.as_f64()).unwrap_or(f64::NAN);
        format!("{} left |a|/R0 ≤ {bound} at {}", c.get("mode")?.as_str()?, us(c.get("t")))
    } else if status.as_str() == Some("completed") {
        format!("completed {}", us(summary.get("t_end")))
    } else {
        format!("{} at {}", status.as_object().and_then(|o| o.keys().next()).map_or("failed", |k| k.as_str()), us(summary.get("t_end")))
    };
    Some(format!("{name}: {} — {end}", model.join(", ")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_and_shape_names_are_recognised() {
        assert_eq!(split_unit("R [um]"), ("R".into(), 1e-6));
        assert_eq!(split_unit("t_s"), ("t".into(), 1.0));
        assert_eq!(split_unit("a_2"), ("a_2".into(), 1.0));
        assert_eq!(split_unit("t (ns)"), ("t".into(), 1e-9));
        assert_eq!(shape_key("a_2"), Some(('a', 2)));
        assert_eq!(shape_key("b12"), Some(('b', 12)));
        assert_eq!(shape_key("adot_4"), Some(('A', 4)));
        assert_eq!(shape_key("a4dot"), Some(('A', 4)));
        assert_eq!(shape_key("da2"), Some(('A', 2)));
        assert_eq!(shape_key("Rdot"), None);
        assert_eq!(shape_key("alpha"), None);
    }
}

/// Removes `out_dir/series.svg` and `series.png` (the plot [`series_plot`] draws) and returns
/// those that were there: a run without `--plot` must not leave an earlier run's plot beside its
/// new data (issue 29 item 9).
pub fn remove_stale_series_plot(out_dir: &Path) -> Vec<std::path::PathBuf> {
    remove_stale_plots(out_dir, &["series"])
}

/// Removes `out_dir/STEM.svg` and `STEM.png` for each stem: a command run without `--plot`
/// into a folder where an earlier run drew its plot (issue 29 item 9); the paths removed.
pub fn remove_stale_plots(out_dir: &Path, stems: &[&str]) -> Vec<std::path::PathBuf> {
    stems
        .iter()
        .flat_map(|s| [format!("{s}.svg"), format!("{s}.png")])
        .map(|n| out_dir.join(n))
        .filter(|p| std::fs::remove_file(p).is_ok())
        .collect()
}
