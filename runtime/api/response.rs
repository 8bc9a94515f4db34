//! `response`: the linear radial response of a scene per frequency ([`crate::analysis::response`];
//! docs/model.md, "Linear response"): the typed [`Response`], its table (the columns of
//! response.csv, what Python's `mb.response` is) and the frequency grid `A:B:N[:log]`.

use super::scene::Scene;
use super::table::{Column, Table};
pub use crate::analysis::response::{DampingSplit, Response, ResponsePoint};

/// response.csv's columns, in order.
pub const COLUMNS: [&str; 10] = [
    "frequency_hz",
    "amplitude_m_per_pa",
    "phase_rad",
    "delta_total",
    "delta_liquid_viscosity",
    "delta_radiation",
    "delta_shell_viscosity",
    "delta_other",
    "sigma_s_m2",
    "sigma_e_m2",
];

/// `A:B:N[:log]` → N frequencies from A to B [Hz] (linear, or logarithmic with `:log`).
pub fn grid(spec: &str) -> anyhow::Result<Vec<f64>> {
    crate::analysis::response::parse_grid(spec).map_err(anyhow::Error::msg)
}

/// The linear response of `scene` (its drive ignored) at `frequencies` [Hz] (each finite and
/// > 0; at least one).
pub fn response(scene: &Scene, frequencies: &[f64]) -> anyhow::Result<Response> {
    if frequencies.is_empty() {
        anyhow::bail!("response: no frequencies given (e.g. --freq 1e5:1e7:200:log)");
    }
    if let Some((i, f)) = frequencies.iter().enumerate().find(|(_, f)| !(f.is_finite() && **f > 0.0)) {
        anyhow::bail!("response: frequency [{i}] = {f} Hz must be finite and > 0");
    }
    crate::analysis::response::response(scene.scene(), frequencies)
        .map_err(anyhow::Error::new)
        .map_err(|e| e.context(format!("linear response of {}", scene.origin())))
}

/// The per-frequency table (response.csv): [`COLUMNS`]; `sigma_e_m2` NaN without
/// `liquid.sound_speed`.
pub fn table(r: &Response) -> Table {
    let col = |f: &dyn Fn(&ResponsePoint) -> f64| Column::Float(r.points.iter().map(f).collect());
    let columns = vec![
        col(&|p| p.frequency_hz),
        col(&|p| p.amplitude_m_per_pa),
        col(&|p| p.phase_rad),
        col(&|p| p.delta.total),
        col(&|p| p.delta.liquid_viscosity),
        col(&|p| p.delta.radiation),
        col(&|p| p.delta.shell_viscosity),
        col(&|p| p.delta.other),
        col(&|p| p.sigma_s_m2),
        col(&|p| p.sigma_e_m2.unwrap_or(f64::NAN)),
    ];
    Table { names: COLUMNS.iter().map(|s| s.to_string()).collect(), columns }
}
