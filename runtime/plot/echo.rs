//! The echo of a run (`run --plot` with `[echo]`): the scattered pressure at each receiver
//! against time above its spectrum (docs/model.md, "Echo"), written as echo.svg / echo.png.

use super::{Axis, Figure, Panel, PlotError, Saved, Series};
use std::path::Path;

/// The echo figure: `pressure` = (name, p_s [Pa]) per point over `t` [s], `levels` = (name,
/// level [dB re 1 Pa]) per point over `f` [Hz].
pub fn echo_plot(
    title: &str,
    t: &[f64],
    pressure: &[(&str, &[f64])],
    f: &[f64],
    levels: &[(&str, &[f64])],
    out_dir: &Path,
) -> Result<Saved, PlotError> {
    let us: Vec<f64> = t.iter().map(|t| t * 1e6).collect();
    let mut p = Panel::new(Axis::linear("t [us]"), Axis::linear("p_s [Pa]"));
    for (name, v) in pressure {
        p.push(Series::line(*name, us.clone(), v.to_vec()));
    }
    let mhz: Vec<f64> = f.iter().map(|f| f / 1e6).collect();
    let mut s = Panel::new(Axis::linear("f [MHz]"), Axis::linear("level [dB re 1 Pa]"));
    for (name, v) in levels {
        s.push(Series::line(*name, mhz.clone(), v.to_vec()));
    }
    Figure::new(vec![p, s]).title(title).save(out_dir, "echo")
}

/// Removes an earlier run's echo.svg / echo.png (see [`super::remove_stale_series_plot`]).
pub fn remove_stale_echo_plot(out_dir: &Path) -> Vec<std::path::PathBuf> {
    ["echo.svg", "echo.png"].iter().map(|n| out_dir.join(n)).filter(|p| std::fs::remove_file(p).is_ok()).collect()
}
