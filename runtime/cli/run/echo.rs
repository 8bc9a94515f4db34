//! `run` with `[echo]`: echo.csv (t, then p_s at each point [Pa]), spectrum.csv (frequency_hz,
//! then the level of each point's echo [dB re 1 Pa]) and summary.json's `echo` object
//! (runtime/echo/; docs/model.md, "Echo").

use crate::echo::spectrum::{db, summarize, Spectrum};
use crate::echo::EchoSeries;
use crate::output::{CsvWriter, OutputDir};
use crate::scene::Scene;

/// Writes echo.csv and spectrum.csv into `dir`; the summary's `echo` object.
pub(super) fn write(dir: &OutputDir, echo: &EchoSeries, scene: &Scene) -> anyhow::Result<serde_json::Value> {
    let mut header = vec!["t".to_string()];
    header.extend(echo.names.iter().cloned());
    let mut csv = CsvWriter::create(&dir.join("echo.csv"), &header)?;
    let mut line = Vec::with_capacity(header.len());
    for (i, t) in echo.t.iter().enumerate() {
        line.clear();
        line.push(*t);
        line.extend(echo.p.iter().map(|c| c[i]));
        csv.row(&line);
    }
    csv.commit()?;

    // the spectrum's samples: the window, or the whole run
    let (a, b) = match scene.echo.as_ref().and_then(|e| e.window) {
        Some([t0, t1]) => (echo.t.partition_point(|&t| t < t0), echo.t.partition_point(|&t| t <= t1)),
        None => (0, echo.t.len()),
    };
    let dt = scene.run.sample_interval;
    let spectra: Vec<Spectrum> = echo.p.iter().map(|c| Spectrum::of(&c[a..b], dt)).collect();
    let mut header = vec!["frequency_hz".to_string()];
    header.extend(echo.names.iter().map(|n| format!("{n}_db")));
    let mut csv = CsvWriter::create(&dir.join("spectrum.csv"), &header)?;
    if let Some(first) = spectra.first() {
        for (j, f) in first.f.iter().enumerate() {
            line.clear();
            line.push(*f);
            line.extend(spectra.iter().map(|s| db(s.amplitude[j])));
            csv.row(&line);
        }
    }
    csv.commit()?;
    let f0 = scene.drive.as_ref().filter(|d| d.file.is_none()).map(|d| d.frequency_hz);
    let empty = Spectrum { f: Vec::new(), amplitude: Vec::new() };
    let s = summarize(&echo.p[0][a..b], &echo.shape_part[a..b], &echo.t[a..b], spectra.first().unwrap_or(&empty), f0, echo.form);
    Ok(serde_json::to_value(s)?)
}
