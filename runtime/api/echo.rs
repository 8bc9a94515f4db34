//! The echo of a run (scenes with `[echo]`; docs/model.md, "Echo") as typed tables: what `run`
//! writes as echo.csv and spectrum.csv, what Python's `Run.echo` and `Run.spectrum` are, and
//! the levels of summary.json's `echo` object. The spectrum is computed here, once, for both.

use super::table::{Column, Table};
use crate::echo::spectrum::{db, summarize, EchoSummary, Spectrum};
use crate::echo::EchoSeries;

/// A run's echo: its series, its spectrum and its levels.
#[derive(Debug, Clone)]
pub struct Echo {
    /// echo.csv: `t` [s], then the scattered pressure [Pa] at each point, `p_<distance>m_<angle>deg`.
    pub echo: Table,
    /// spectrum.csv: `frequency_hz`, then each point's level [dB re 1 Pa], `<point>_db` (the
    /// one-sided amplitude spectrum over `echo.window` or the whole run, Hann window).
    pub spectrum: Table,
    /// summary.json's `echo` object.
    pub levels: EchoSummary,
    /// The recorded series, with the shape modes' part of the far field.
    pub series: EchoSeries,
}

impl Echo {
    /// The tables and levels of a recorded echo of a run of `scene`.
    pub fn of(series: EchoSeries, scene: &crate::scene::Scene) -> Echo {
        let mut names = vec!["t".to_string()];
        names.extend(series.names.iter().cloned());
        let mut columns = vec![Column::Float(series.t.clone())];
        columns.extend(series.p.iter().map(|c| Column::Float(c.clone())));
        let echo = Table { names, columns };

        // the spectrum's samples: the window, or the whole run
        let t = &series.t;
        let (a, b) = match scene.echo.as_ref().and_then(|e| e.window) {
            Some([t0, t1]) => (t.partition_point(|&x| x < t0), t.partition_point(|&x| x <= t1)),
            None => (0, t.len()),
        };
        let dt = scene.run.sample_interval;
        let spectra: Vec<Spectrum> = series.p.iter().map(|c| Spectrum::of(&c[a..b], dt)).collect();
        let mut names = vec!["frequency_hz".to_string()];
        names.extend(series.names.iter().map(|n| format!("{n}_db")));
        let f = spectra.first().map_or_else(Vec::new, |s| s.f.clone());
        let mut columns = vec![Column::Float(f)];
        columns.extend(spectra.iter().map(|s| Column::Float(s.amplitude.iter().map(|&x| db(x)).collect())));
        let spectrum = Table { names, columns };

        let f0 = scene.drive.as_ref().filter(|d| d.file.is_none()).map(|d| d.frequency_hz);
        let empty = Spectrum { f: Vec::new(), amplitude: Vec::new() };
        let levels = summarize(&series.p[0][a..b], &series.shape_part[a..b], &t[a..b], spectra.first().unwrap_or(&empty), f0, series.form);
        Echo { echo, spectrum, levels, series }
    }
}

/// Row `i` of a table of float columns (what the CSV writers take).
pub fn float_row(table: &Table, i: usize, line: &mut Vec<f64>) {
    line.clear();
    line.extend(table.columns.iter().map(|c| match c {
        Column::Float(v) => v[i],
        Column::Int(v) => v[i] as f64,
        Column::Text { .. } => f64::NAN,
    }));
}
