//! `magbubble accuracy SCENE [--out DIR] [--set k=v]… [--quick] [--repeats N] [--plot]`:
//! work–precision of every integrator on a scene (issue 6, part 1; method in
//! [`crate::analysis::accuracy`]). Prints the ladders, writes `DIR/accuracy.csv` (one row per
//! rung), `DIR/sizes.csv` (mode and grid ladders), `DIR/accuracy.json` (everything) and with
//! `--plot` `DIR/work_precision.{svg,png}` (error against wall time, log–log).

use crate::api::accuracy::{options, study, MIN_WORK_RATIO};
use crate::api::{Monitor, Scene};
use crate::output::{write_json, CsvWriter, OutputDir};
use crate::plot::kinds::{work_precision, Curve};
use anyhow::Context;
use std::path::PathBuf;

/// Arguments of `magbubble accuracy`.
#[derive(Debug, clap::Args)]
pub struct AccuracyArgs {
    /// The scene file (TOML).
    pub scene: PathBuf,
    /// Output directory (default: out/<scene file stem>-accuracy).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Override a scene key, e.g. --set modes.max_order=8 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Short study (5 µs, three rungs per ladder, one repeat): for tests and a first look.
    #[arg(long)]
    pub quick: bool,
    /// Repeats per setting; the wall time is their median (default 3, 1 with --quick).
    #[arg(long)]
    pub repeats: Option<usize>,
    /// Simulated time [s] (default: the scene's run.duration, 5 µs with --quick).
    #[arg(long)]
    pub duration: Option<f64>,
    /// Write the work–precision plot (error against wall time).
    #[arg(long)]
    pub plot: bool,
    /// Instead of the time-series study: the error of the critical ε_p at this drive frequency
    /// [Hz] against its cost, per Magnus steps, mode cutoff N, closure, grid and SDIRK steps
    /// (issue 13 part 5; writes critical.csv and critical.json).
    #[arg(long, value_name = "FREQ_HZ")]
    pub critical: Option<f64>,
}

pub fn run(args: &AccuracyArgs) -> anyhow::Result<()> {
    let scene = Scene::load(&args.scene, &args.set).with_context(|| format!("loading {}", args.scene.display()))?;
    if let Some(f) = args.critical {
        return super::accuracy_critical::run(args, &scene, f);
    }
    let opts = options(args.quick, args.repeats, args.duration)?;
    // A fraction-done bar over the study's simulations (on a terminal only).
    let report = study(&scene, &opts, &Monitor { bar: true, ..Monitor::default() })?;
    outln!(
        "reference: {} (estimated error {:.2e}, {:.2} s); compared over {:.3e} s, {} samples; t* = {:.4e} s",
        report.reference,
        report.reference_error,
        report.reference_wall_seconds,
        report.duration,
        opts.samples,
        report.t_star
    );
    outln!("the scene's integrator: {} ({}: {})", report.integrator.method, report.integrator.chosen, report.integrator.reason);
    outln!("error = max(max_t |R - R_ref|/R0, max_t max_k |a_k - a_k,ref|/R0)");
    outln!(
        "{:>10} {:>11} {:>11} {:>11} {:>11} {:>10} {:>9} {:>8}  status",
        "method", "setting", "e_R", "e_a", "error", "wall s", "rhs", "rejected"
    );
    let out = args.out.clone().unwrap_or_else(|| super::run::default_out_for(&args.scene, "accuracy"));
    let dir = OutputDir::create(&out)?;
    let header = ["method", "setting", "e_r", "e_a", "error", "wall_seconds", "rhs_evals", "steps", "rejected"];
    let mut csv = CsvWriter::create(&dir.join("accuracy.csv"), &header)?;
    let (mut curves, mut counted) = (vec![], vec![]);
    for l in &report.ladders {
        for r in &l.rungs {
            outln!(
                "{:>10} {:>11.3e} {:>11.3e} {:>11.3e} {:>11.3e} {:>10.4} {:>9} {:>8}  {}",
                l.method, r.setting, r.e_r, r.e_a, r.error, r.wall_seconds, r.stats.rhs_evals, r.stats.rejected, r.status
            );
            csv.labeled_row(&l.method, &[
                r.setting,
                r.e_r,
                r.e_a,
                r.error,
                r.wall_seconds,
                r.stats.rhs_evals as f64,
                r.stats.steps as f64,
                r.stats.rejected as f64,
            ]);
        }
        let fmt = |o: Option<f64>| o.map_or("n/a".to_string(), |v| format!("{v:.2}"));
        let work = match l.order_work {
            Some(v) => format!("{v:.2}"),
            None if l.work_ratio.is_finite() => format!("n/a (work ratio {:.2} < {MIN_WORK_RATIO})", l.work_ratio),
            None => "n/a".to_string(),
        };
        outln!("{:>10} observed order: vs dt {}, vs work {work}", l.method, fmt(l.order_dt));
        let (x, y) = l.rungs.iter().map(|r| (r.wall_seconds, r.error)).unzip();
        curves.push(Curve::new(l.method.clone(), x, y));
        let (x, y) = l.rungs.iter().map(|r| (r.stats.rhs_evals as f64, r.error)).unzip();
        counted.push(Curve::new(l.method.clone(), x, y));
    }
    csv.commit()?;
    let mut sizes = CsvWriter::create(&dir.join("sizes.csv"), &["ladder", "size", "wall_seconds", "rhs_evals", "steps", "delta_r", "delta_a2"])?;
    for (label, name, rows) in [("modes", "modes N", &report.modes), ("grid", "grid points", &report.grid)] {
        if rows.is_empty() {
            continue;
        }
        outln!("{name} ladder ({}); delta = max |x - x_largest| / R0:", report.size_ladder_method);
        outln!("{:>8} {:>10} {:>10} {:>11} {:>11}  status", "size", "wall s", "rhs", "delta R", "delta a2");
        for r in rows.iter() {
            outln!(
                "{:>8} {:>10.4} {:>10} {:>11.3e} {:>11.3e}  {}",
                r.size, r.wall_seconds, r.stats.rhs_evals, r.delta_r, r.delta_a2, r.status
            );
            sizes.labeled_row(label, &[
                r.size as f64,
                r.wall_seconds,
                r.stats.rhs_evals as f64,
                r.stats.steps as f64,
                r.delta_r,
                r.delta_a2,
            ]);
        }
    }
    sizes.commit()?;
    write_json(&dir.join("accuracy.json"), &report)?;
    if args.plot {
        let fig = work_precision(
            &format!(
                "work–precision: {}; the scene's integrator: {} ({})",
                args.scene.display(),
                report.integrator.method,
                report.integrator.chosen
            ),
            "max error / R0",
            &[("rhs evaluations (Jacobian columns included; LU solves not)", counted), ("wall time [s], median of the repeats", curves)],
        );
        fig.save(dir.path(), "work_precision").context("writing the work–precision plot")?;
    } else {
        // an earlier run's plot would sit beside the new data (issue 29 item 9)
        for stale in crate::plot::remove_stale_plots(dir.path(), &["work_precision"]) {
            noteln!("removed {} (an earlier run's plot; --plot draws a new one)", stale.display());
        }
    }
    outln!("wrote {}", out.display());
    Ok(())
}
