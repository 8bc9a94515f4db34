//! `magbubble convergence SCENE [--out DIR] [--set key=value]…`: time-step convergence of the
//! paper's staggered scheme (paper §5.1, fig 3, eq 5.4). Runs the scene's full model with a fine
//! reference step (default Δt′ = 1.7·10⁻⁴, as the paper) and with integer multiples of it, and
//! prints e_s (shape amplitudes over time) and e_f (vorticity at the end) with the observed
//! orders. Writes `DIR/convergence.csv` and `DIR/convergence.json` (atomically), and with
//! `--plot` `DIR/convergence.{svg,png}`: e_s and e_f against Δt′ (slope-2 guide) and against
//! the wall time, log–log.

use crate::analysis::convergence::convergence_study;
use crate::model::vorticity::scene::FullModel;
use crate::output::{write_json, CsvWriter, OutputDir};
use crate::plot::study::{convergence_figure, ConvergencePoint};
use crate::scene;
use anyhow::Context;
use std::path::PathBuf;

/// Arguments of `magbubble convergence`.
#[derive(Debug, clap::Args)]
pub struct ConvergenceArgs {
    /// The scene file (TOML); its shape modes, drive, field and vorticity grid are used.
    pub scene: PathBuf,
    /// Output directory (default: out/<scene file stem>-convergence).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Override a scene key, e.g. --set modes.max_order=8 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Reference step in units of t* = √(ρR0³/(2c1)).
    #[arg(long, default_value_t = 1.7e-4)]
    pub reference_dt: f64,
    /// Steps of the ladder as multiples of the reference step.
    #[arg(long, value_delimiter = ',', default_values_t = vec![2u64, 4, 8, 16])]
    pub multiples: Vec<u64>,
    /// Simulated time [s] (default: the scene's run.duration; the paper uses 100 µs).
    #[arg(long)]
    pub duration: Option<f64>,
    /// Also draw the errors against the step and against the work (convergence.svg/.png).
    #[arg(long)]
    pub plot: bool,
}

pub fn run(args: &ConvergenceArgs) -> anyhow::Result<()> {
    if !(args.reference_dt.is_finite() && args.reference_dt > 0.0) {
        anyhow::bail!("--reference-dt = {}: must be a positive number (units of t*)", args.reference_dt);
    }
    if args.multiples.is_empty() || args.multiples.contains(&0) {
        anyhow::bail!("--multiples {:?}: need positive integers", args.multiples);
    }
    let scene = scene::load(&args.scene, &args.set).with_context(|| format!("loading {}", args.scene.display()))?;
    let fm = FullModel::from_scene(&scene).context("assembling the full (vorticity) model")?;
    let ts = fm.base().time_scale();
    let duration = args.duration.unwrap_or(scene.run.duration);
    if !(duration.is_finite() && duration > 0.0) {
        anyhow::bail!("--duration = {duration}: must be a positive time in seconds");
    }
    let c = fm.coupling();
    noteln!(
        "convergence: {} modes, grid {} points, {:.3e} s = {:.4} t*, reference dt' = {:.3e}",
        fm.base().orders().len(),
        fm.grid.len(),
        duration,
        duration / ts,
        args.reference_dt
    );
    let report = convergence_study(&c, &fm.grid, &fm.initial_state(), duration / ts, args.reference_dt, &args.multiples)
        .context("the reference run failed (reduce --reference-dt)")?;
    let out = args.out.clone().unwrap_or_else(|| super::run::default_out_for(&args.scene, "convergence"));
    let dir = OutputDir::create(&out)?;
    let mut csv = CsvWriter::create(&dir.join("convergence.csv"), &["dt_prime", "dt_s", "e_s", "e_f", "worst_k", "seconds"])?;
    outln!("{:>12} {:>12} {:>12} {:>8} {:>9}", "dt'", "e_s", "e_f", "worst k", "seconds");
    for r in &report.rows {
        outln!("{:>12.4e} {:>12.4e} {:>12.4e} {:>8} {:>9.2}", r.dt, r.e_s, r.e_f, r.worst_k_s, r.seconds);
        csv.row(&[r.dt, r.dt * ts, r.e_s, r.e_f, r.worst_k_s as f64, r.seconds]);
    }
    csv.commit()?;
    let fmt = |o: Option<f64>| o.map_or("n/a".to_string(), |v| format!("{v:.3}"));
    outln!("observed order: e_s {}, e_f {} (paper: 1.995, 2.065)", fmt(report.order_s), fmt(report.order_f));
    write_json(&dir.join("convergence.json"), &report)?;
    if args.plot {
        let points: Vec<ConvergencePoint> =
            report.rows.iter().map(|r| ConvergencePoint { dt: r.dt, e_s: r.e_s, e_f: r.e_f, steps: r.steps as f64 }).collect();
        convergence_figure(&format!("time-step convergence: {}", args.scene.display()), &points, 2)
            .save(dir.path(), "convergence")
            .context("writing the convergence plot")?;
        outln!("plotted {}", dir.join("convergence.svg").display());
    } else {
        // an earlier run's plot would sit beside the new data (issue 29 item 9)
        for stale in crate::plot::remove_stale_plots(dir.path(), &["convergence"]) {
            noteln!("removed {} (an earlier run's plot; --plot draws a new one)", stale.display());
        }
    }
    outln!("wrote {}", out.display());
    Ok(())
}
