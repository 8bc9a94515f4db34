//! `magbubble response SCENE --freq A:B:N[:log]`: the linear radial response
//! ([`crate::api::response`]; formatting only here): response.csv (per frequency), response.json (the whole
//! result) and response.svg/png (|X/P_a| and σ_s against frequency) in the output directory.

use crate::api::echo::float_row;
use crate::api::{self, response};
use crate::output::{write_json, CsvWriter, OutputDir};
use crate::plot::{Axis, Figure, Panel, Series};
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct ResponseArgs {
    /// The scene file (TOML).
    pub scene: PathBuf,
    /// Frequencies: A:B:N (linear) or A:B:N:log [Hz].
    #[arg(long)]
    pub freq: String,
    /// Output directory (default: out/<scene file stem>-response).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Override a scene key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

pub fn run(args: &ResponseArgs) -> anyhow::Result<()> {
    let freqs = response::grid(&args.freq)?;
    let scene = api::Scene::load(&args.scene, &args.set)?;
    let r = response::response(&scene, &freqs)?;
    let out = args.out.clone().unwrap_or_else(|| super::run::default_out_for(&args.scene, "response"));
    let dir = OutputDir::create(&out)?;
    let table = response::table(&r);
    let mut csv = CsvWriter::create(&dir.join("response.csv"), &table.names)?;
    let mut line = Vec::with_capacity(table.names.len());
    for i in 0..table.rows() {
        float_row(&table, i, &mut line);
        csv.row(&line);
    }
    csv.commit()?;
    write_json(&dir.join("response.json"), &r)?;
    let f: Vec<f64> = r.points.iter().map(|p| p.frequency_hz / 1e6).collect();
    let amp = Panel::new(Axis::linear("f [MHz]"), Axis::log("|X/P_a| [m/Pa]"))
        .series(Series::line("|X/P_a|", f.clone(), r.points.iter().map(|p| p.amplitude_m_per_pa).collect()))
        .vline(r.natural_frequency_hz / 1e6, "f0");
    let sig = Panel::new(Axis::linear("f [MHz]"), Axis::log("sigma_s [m^2]"))
        .series(Series::line("sigma_s", f, r.points.iter().map(|p| p.sigma_s_m2).collect()));
    Figure::stacked(vec![amp, sig]).title(format!("linear response: {}", args.scene.display())).save(&out, "response")?;
    outln!("natural frequency: {:e} Hz; largest |X/P_a| at {:e} Hz", r.natural_frequency_hz, r.resonance_frequency_hz);
    let c = &r.damping_rates_per_s;
    outln!(
        "damping rates [1/s]: total {:e} = liquid viscosity {:e} + radiation {:e} + shell viscosity {:e} + other {:e}",
        c.total, c.liquid_viscosity, c.radiation, c.shell_viscosity, c.other
    );
    outln!("wrote: {} ({} frequencies), response.json, response.svg", out.join("response.csv").display(), r.points.len());
    Ok(())
}
