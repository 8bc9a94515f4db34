//! The population's tables from its (frequency, bin) points: population_bins.csv (one row per
//! point), population.csv (the fraction unstable on the ε_p grid) and the map plot (the ε_p at
//! which 10, 50 and 90 % of the population is unstable, against frequency).

use super::fraction::{fraction_unstable, Threshold};
use crate::analysis::stability::CRITICAL_HEADER;
use crate::output::AtomicFile;
use crate::plot::{Axis, Figure, Panel, Series};
use std::io::Write;
use std::path::Path;

/// The header of the points CSV (after its `index`): the point, then the critical point's
/// fields ([`CRITICAL_HEADER`]), then `windows` ("1", "2+" or empty when not checked).
pub const POINTS_HEADER: [&str; 14] = [
    "frequency_hz",
    "radius",
    "weight",
    CRITICAL_HEADER[0],
    CRITICAL_HEADER[1],
    CRITICAL_HEADER[2],
    CRITICAL_HEADER[3],
    CRITICAL_HEADER[4],
    CRITICAL_HEADER[5],
    CRITICAL_HEADER[6],
    CRITICAL_HEADER[7],
    CRITICAL_HEADER[8],
    CRITICAL_HEADER[9],
    "windows",
];
const CRITICAL: usize = 3;
const OUTCOME: usize = 4;
const UNSTABLE: usize = 6;
const MODE: usize = 7;
const NOTE: usize = 12;
const WINDOWS: usize = 13;

/// A point that failed (outcome `error`): computed again on resume.
pub fn is_error_row(fields: &[String]) -> bool {
    fields.get(OUTCOME).is_some_and(|o| o == "error")
}

/// The contour levels of the map plot.
pub const LEVELS: [f64; 3] = [0.1, 0.5, 0.9];

/// The tables of a complete population.
#[derive(Debug, Clone, PartialEq)]
pub struct PopulationTables {
    /// population_bins.csv: frequency_hz, radius, weight, critical_eps_p, mode, outcome,
    /// windows, note (text, as in the points CSV).
    pub bins: Vec<[String; 8]>,
    /// population.csv: (frequency_hz, eps_p, fraction_unstable).
    pub fraction: Vec<(f64, f64, f64)>,
    /// Per frequency, the smallest ε_p at which at least 10, 50, 90 % is unstable (NaN: never
    /// within the range).
    pub contours: Vec<(f64, [f64; 3])>,
    /// The points whose bin is stable again at the top of the range (more than one window).
    pub multi_window: Vec<String>,
}

fn num(s: &str) -> f64 {
    s.parse().unwrap_or(f64::NAN)
}

fn clean(s: &str) -> String {
    s.replace([',', '\n', '\r'], ";")
}

impl PopulationTables {
    /// From every point's row (index, fields), `bins` per frequency, on the ε_p grid `eps`.
    pub fn from_rows(rows: &[(usize, Vec<String>)], bins: usize, eps: &[f64]) -> anyhow::Result<PopulationTables> {
        anyhow::ensure!(bins >= 1 && rows.len() % bins == 0, "population: {} points are not whole frequencies of {bins} bins", rows.len());
        let mut t = PopulationTables { bins: Vec::new(), fraction: Vec::new(), contours: Vec::new(), multi_window: Vec::new() };
        for (k, chunk) in rows.chunks(bins).enumerate() {
            anyhow::ensure!(chunk.iter().enumerate().all(|(j, (i, r))| *i == k * bins + j && r.len() == POINTS_HEADER.len()), "population: the points of frequency {k} are incomplete");
            let f = num(&chunk[0].1[0]);
            let mut thresholds = Vec::with_capacity(bins);
            for (_, r) in chunk {
                thresholds.push((Threshold::of(&r[OUTCOME], num(&r[CRITICAL]), num(&r[UNSTABLE])), num(&r[2])));
                t.bins.push([r[0].clone(), r[1].clone(), r[2].clone(), r[CRITICAL].clone(), r[MODE].clone(), r[OUTCOME].clone(), r[WINDOWS].clone(), clean(&r[NOTE])]);
                if r[WINDOWS] == "2+" {
                    t.multi_window.push(format!("f = {} Hz, radius {} m: stable again at the top of the range", r[0], r[1]));
                }
            }
            for &e in eps {
                t.fraction.push((f, e, fraction_unstable(&thresholds, e)));
            }
            t.contours.push((f, LEVELS.map(|q| level(&thresholds, q))));
        }
        Ok(t)
    }

    /// population_bins.csv, population.csv and population_map.svg/png into `dir` (each file
    /// atomically).
    pub fn write(&self, dir: &Path) -> anyhow::Result<()> {
        let mut f = AtomicFile::create(&dir.join("population_bins.csv"))?;
        writeln!(f, "frequency_hz,radius,weight,critical_eps_p,mode,outcome,windows,note")?;
        for r in &self.bins {
            writeln!(f, "{}", r.join(","))?;
        }
        f.commit()?;
        let mut f = AtomicFile::create(&dir.join("population.csv"))?;
        writeln!(f, "frequency_hz,eps_p,fraction_unstable")?;
        for (fr, e, x) in &self.fraction {
            writeln!(f, "{fr:.8e},{e:e},{x:e}")?;
        }
        f.commit()?;
        let mut panel = Panel::new(Axis::linear("f [MHz]"), Axis::linear("eps_p [-]"));
        for (j, q) in LEVELS.iter().enumerate() {
            let (x, y): (Vec<f64>, Vec<f64>) = self.contours.iter().filter(|c| c.1[j].is_finite()).map(|c| (c.0 / 1e6, c.1[j])).unzip();
            if !x.is_empty() {
                panel.push(Series::line_points(format!("{:.0} % unstable", q * 100.0), x, y));
            }
        }
        // no level reached anywhere in the range: nothing to draw (population.csv says so)
        if !panel.series.is_empty() {
            Figure::single(panel).title("population: fraction shape-unstable (contours of the map)").save(dir, "population_map")?;
        }
        Ok(())
    }
}

/// The smallest threshold at which the unstable weight reaches `q` (NaN if it never does, or
/// if a bin failed).
pub fn level(thresholds: &[(Threshold, f64)], q: f64) -> f64 {
    if thresholds.iter().any(|t| t.0 == Threshold::Unknown) {
        return f64::NAN;
    }
    let mut from: Vec<(f64, f64)> = thresholds.iter().filter_map(|&(t, w)| if let Threshold::From(c) = t { Some((c, w)) } else { None }).collect();
    from.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut sum = 0.0;
    for (c, w) in from {
        sum += w;
        if sum >= q - 1e-12 {
            return c;
        }
    }
    f64::NAN
}
