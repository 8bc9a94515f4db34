//! `run` with `[echo]`: echo.csv (t, then p_s at each point [Pa]) and spectrum.csv
//! (frequency_hz, then the level of each point's echo [dB re 1 Pa]) from the typed tables of
//! [`crate::api::echo::Echo`] (runtime/echo/; docs/model.md, "Echo").

use crate::api::echo::{float_row, Echo};
use crate::api::table::{Column, Table};
use crate::output::{CsvWriter, OutputDir};

/// Writes echo.csv and spectrum.csv into `dir`.
pub(super) fn write(dir: &OutputDir, echo: &Echo) -> anyhow::Result<()> {
    write_table(dir, "echo.csv", &echo.echo)?;
    write_table(dir, "spectrum.csv", &echo.spectrum)
}

fn write_table(dir: &OutputDir, name: &str, table: &Table) -> anyhow::Result<()> {
    let mut csv = CsvWriter::create(&dir.join(name), &table.names)?;
    let mut line = Vec::with_capacity(table.names.len());
    for i in 0..table.rows() {
        float_row(table, i, &mut line);
        csv.row(&line);
    }
    csv.commit()?;
    Ok(())
}

/// `--plot`: echo.svg / echo.png, the pressure at each point against time above its spectrum,
/// the spectrum up to 4.5 times the drive's main frequency (f, 2f, 3f, 4f and the sub- and
/// ultraharmonics between), or for a file drive up to the last bin within 80 dB of the peak.
pub(super) fn plot(echo: &Echo, f0: Option<f64>, out: &std::path::Path) -> anyhow::Result<()> {
    let floats = |t: &Table| -> Vec<(String, Vec<f64>)> {
        t.names
            .iter()
            .zip(&t.columns)
            .filter_map(|(n, c)| match c {
                Column::Float(v) => Some((n.clone(), v.clone())),
                _ => None,
            })
            .collect()
    };
    let (e, s) = (floats(&echo.echo), floats(&echo.spectrum));
    let named = |cols: &[(String, Vec<f64>)]| -> Vec<(String, Vec<f64>)> { cols.iter().skip(1).cloned().collect() };
    let (pe, ps) = (named(&e), named(&s));
    let f = &s[0].1;
    let shown = match f0 {
        Some(f0) => f.partition_point(|&x| x <= 4.5 * f0),
        None => {
            let peak = ps.iter().flat_map(|(_, v)| v.iter().copied()).fold(f64::NEG_INFINITY, f64::max);
            1 + (0..f.len()).rev().find(|&j| ps.iter().any(|(_, v)| v[j] >= peak - 80.0)).unwrap_or(f.len().saturating_sub(1))
        }
    }
    .clamp(f.len().min(2), f.len());
    let pressure: Vec<(&str, &[f64])> = pe.iter().map(|(n, v)| (n.as_str(), v.as_slice())).collect();
    let levels: Vec<(&str, &[f64])> = ps.iter().map(|(n, v)| (n.as_str(), &v[..shown])).collect();
    let title = format!("echo ({} field): pressure at the receiver, spectrum", echo.series.form);
    crate::plot::echo_plot(&title, &e[0].1, &pressure, &f[..shown], &levels, out)?;
    Ok(())
}
