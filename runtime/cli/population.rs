//! `magbubble population` and `magbubble attenuation` (issue 33; docs/population.md): thin over
//! [`crate::api::population`] and [`crate::api::attenuation`].

use crate::analysis::sweep::Shard;
use crate::api::attenuation::{attenuation, AttenuationRequest};
use crate::api::population::{population, PopulationRequest};
use crate::api::stability::FreqAxis;
use crate::api::{Monitor, Scene};
use anyhow::Context;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct PopulationArgs {
    /// Scene file (TOML) with a [population] section.
    pub scene: PathBuf,
    /// Drive frequencies [Hz]: START:STOP:N, START:STOP:N:log, or F1,F2,…
    #[arg(long)]
    pub freq: String,
    /// Search range LO:HI of ε_p per bin; also the ε_p grid of population.csv.
    #[arg(long, default_value = "0:1")]
    pub range: String,
    /// Points of the ε_p grid of population.csv (LO..HI inclusive).
    #[arg(long, default_value_t = 101)]
    pub eps_points: usize,
    /// Bracket tolerance relative to the critical value (as `stability --tol`).
    #[arg(long, default_value_t = 1e-3)]
    pub tol: f64,
    /// Absolute bracket tolerance in ε_p (replaces --tol).
    #[arg(long, value_name = "TOL")]
    pub abs_tol: Option<f64>,
    /// Coarse scan intervals before bisection.
    #[arg(long, default_value_t = 8)]
    pub scan: usize,
    /// Skip the Floquet check at the top of the range that reports bins with a second stable
    /// window (one evaluation per bin with a threshold).
    #[arg(long)]
    pub no_window_check: bool,
    /// Output directory (default: out/<scene file stem>-population).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Shard i/n of the (frequency, bin) points (default from SLURM_ARRAY_TASK_ID/COUNT). Join
    /// the shards with `magbubble merge … --out DIR/population_points.csv`, then run the
    /// command again without --shard into DIR: it resumes every point and writes the tables.
    #[arg(long)]
    pub shard: Option<String>,
    /// Override a scene key, KEY=VALUE (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

#[derive(Debug, clap::Args)]
pub struct AttenuationArgs {
    /// Scene file (TOML) with a [population] section and population.concentration.
    pub scene: PathBuf,
    /// Frequencies [Hz]: A:B:N, A:B:N:log, or F1,F2,…
    #[arg(long)]
    pub freq: String,
    /// Output directory (default: out/<scene file stem>-attenuation).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Shard i/n of the frequencies (merge as for population, into DIR/attenuation_points.csv).
    #[arg(long)]
    pub shard: Option<String>,
    /// Override a scene key, KEY=VALUE (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

fn shard_of(s: &Option<String>) -> anyhow::Result<Shard> {
    Ok(match s {
        Some(s) => Shard::parse(s)?,
        None => Shard::from_env()?.unwrap_or(Shard::ALL),
    })
}

fn monitor() -> Monitor<'static> {
    #[cfg(unix)]
    let cancel = Some(crate::output::cancel_on_signal());
    #[cfg(not(unix))]
    let cancel = None;
    Monitor { cancel, bar: true, ..Monitor::default() }
}

pub fn run_population(args: &PopulationArgs) -> anyhow::Result<()> {
    let freq = FreqAxis::parse(&args.freq)?;
    let (lo, hi) = args.range.split_once(':').with_context(|| format!("--range '{}': expected LO:HI", args.range))?;
    let range: (f64, f64) = (lo.trim().parse().context("--range LO")?, hi.trim().parse().context("--range HI")?);
    let req = PopulationRequest {
        freq,
        range,
        eps_points: args.eps_points,
        tol: args.tol,
        abs_tol: args.abs_tol,
        scan: args.scan,
        window_check: !args.no_window_check,
        out: args.out.clone().unwrap_or_else(|| super::run::default_out_for(&args.scene, "population")),
        shard: shard_of(&args.shard)?,
    };
    req.check()?;
    let scene = Scene::load(&args.scene, &args.set)?;
    for w in &scene.scene().warnings {
        noteln!("warning: {w}");
    }
    let out = population(&scene, &req, &monitor())?;
    let r = &out.report;
    noteln!("{}: {} points ({} computed, {} resumed)", out.points_csv.display(), r.rows.len(), r.computed, r.resumed);
    if out.cancelled {
        noteln!("interrupted: the finished points are kept; rerun the same command to resume");
        crate::output::flush_out()?;
        std::process::exit(130);
    }
    if let Some(t) = &out.tables {
        for m in &t.multi_window {
            noteln!("more than one stability window (counted unstable from the first threshold): {m}");
        }
        noteln!("wrote {}, population.csv and population_map.svg/png", req.out.join("population_bins.csv").display());
    }
    anyhow::ensure!(out.failed.is_none(), "{}", out.failed.unwrap_or_default());
    Ok(())
}

pub fn run_attenuation(args: &AttenuationArgs) -> anyhow::Result<()> {
    let req = AttenuationRequest {
        freq: FreqAxis::parse(&args.freq)?,
        out: args.out.clone().unwrap_or_else(|| super::run::default_out_for(&args.scene, "attenuation")),
        shard: shard_of(&args.shard)?,
    };
    let scene = Scene::load(&args.scene, &args.set)?;
    for w in &scene.scene().warnings {
        noteln!("warning: {w}");
    }
    let out = attenuation(&scene, &req, &monitor())?;
    let r = &out.report;
    noteln!("{}: {} points ({} computed, {} resumed)", out.points_csv.display(), r.rows.len(), r.computed, r.resumed);
    if out.points.is_some() {
        noteln!("wrote {}", req.out.join("attenuation.csv").display());
    }
    anyhow::ensure!(out.failed.is_none(), "{}", out.failed.unwrap_or_default());
    Ok(())
}
