//! `magbubble accuracy SCENE --critical FREQ_HZ [--quick] [--plot]`: the error of the critical
//! ε_p against its cost (issue 13 part 5; method in [`crate::analysis::critical_accuracy`]).
//! Prints one row per search, writes `DIR/critical.csv`, `DIR/critical.json` and with `--plot`
//! `DIR/critical_work_precision.{svg,png}` (error against wall time, one curve per ladder).

use super::accuracy::AccuracyArgs;
use crate::api::accuracy::{critical, critical_options, CriticalRung};
use crate::api::Scene;
use crate::output::{write_json, CsvWriter, OutputDir};
use crate::plot::kinds::{work_precision, Curve};
use anyhow::Context;

pub(super) fn run(args: &AccuracyArgs, scene: &Scene, frequency_hz: f64) -> anyhow::Result<()> {
    let opts = critical_options(frequency_hz, args.quick, args.repeats, args.duration)?;
    anyhow::ensure!(scene.scene().drive.is_some(), "{}: --critical needs a [drive] section (ε_p is the varied quantity)", args.scene.display());
    let out = args.out.clone().unwrap_or_else(|| super::run::default_out_for(&args.scene, "accuracy"));
    let dir = OutputDir::create(&out)?;
    outln!("critical ε_p at f_d = {frequency_hz:e} Hz, N = {} (scene), bracket tolerance {:e} relative", scene.scene().modes.max_order, opts.tol);
    outln!("error = |ε_c − ε_c,ref| / ε_c,ref against the ladder's reference (error 0)");
    outln!("{:>8} {:>15} {:>8} {:>15} {:>11} {:>10} {:>6}  outcome", "ladder", "closure", "setting", "critical", "error", "wall s", "evals");
    // The rows are printed as each search ends; a stdout error stops printing and is returned.
    let mut stdout_error = None;
    let spinner = crate::output::Spinner::new("critical-ε_p searches");
    let mut print = |r: &CriticalRung| {
        if stdout_error.is_none() {
            let line = format_args!(
                "{:>8} {:>15} {:>8} {:>15.8e} {:>11.3e} {:>10.3} {:>6}  {}\n",
                r.ladder, r.closure, r.setting, r.critical, r.error, r.wall_seconds, r.evaluations, r.outcome
            );
            stdout_error = spinner.suspend(|| crate::output::write_out(line).err());
        }
    };
    let report = critical(scene, &opts, &mut print)?;
    drop(spinner);
    if let Some(e) = stdout_error {
        return Err(e.into());
    }
    let header = ["ladder", "setting", "critical", "error", "wall_seconds", "evaluations"];
    let mut csv = CsvWriter::create(&dir.join("critical.csv"), &header)?;
    for r in report.references.iter().chain(&report.rungs) {
        csv.labeled_row(r.ladder, &[r.setting as f64, r.critical, r.error, r.wall_seconds, r.evaluations as f64]);
    }
    csv.commit()?;
    write_json(&dir.join("critical.json"), &report)?;
    if args.plot {
        let mut curves = Vec::new();
        for name in ["magnus", "modes", "grid", "sdirk"] {
            let (x, y): (Vec<f64>, Vec<f64>) =
                report.rungs.iter().filter(|r| r.ladder == name && r.error > 0.0).map(|r| (r.wall_seconds, r.error)).unzip();
            if !x.is_empty() {
                curves.push(Curve::new(name.to_string(), x, y));
            }
        }
        let fig = work_precision(&format!("critical ε_p at {frequency_hz:e} Hz: {}", args.scene.display()), "|ε_c − ε_c,ref| / ε_c,ref", &[("wall time [s]", curves)]);
        fig.save(dir.path(), "critical_work_precision").context("writing the critical work–precision plot")?;
    } else {
        // an earlier run's plot would sit beside the new data (issue 29 item 9)
        for stale in crate::plot::remove_stale_plots(dir.path(), &["critical_work_precision"]) {
            noteln!("removed {} (an earlier run's plot; --plot draws a new one)", stale.display());
        }
    }
    outln!("wrote {}", out.display());
    Ok(())
}
