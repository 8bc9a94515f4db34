//! `magbubble run SCENE [--out DIR] [--set key=value]...`: simulates a scene and writes
//! `DIR/series.csv` (header `t,R,a2,b2,a4,b4,…`, SI units) and `DIR/summary.json` (status,
//! statistics, nondimensional groups and every resolved parameter).
//!
//! Nothing is created when the scene is invalid; when the model cannot be assembled or a write
//! fails, the temp files are removed and so is the output directory if this run created it.

use anyhow::Context as _;
use crate::api::run::{stream_with, SimulateFn};
use crate::api::{Monitor, Scene};
use crate::model::{RunReport, RunStatus};
use crate::output::{write_json, CsvWriter, OutputDir};
use std::path::{Path, PathBuf};

/// Arguments of `magbubble run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// The scene file (TOML), e.g. scenes/coil_static.toml.
    pub scene: PathBuf,
    /// Output directory (default: out/<scene file stem>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Override a scene key, e.g. --set drive.amplitude=0.3 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Also draw the time series (R and the shape modes) as series.svg and series.png.
    #[arg(long)]
    pub plot: bool,
}

pub fn run(args: &RunArgs) -> anyhow::Result<()> {
    execute(args, crate::model::simulate)
}

/// The default output directory of a command on a scene, the one rule of every command that
/// writes a directory (docs/user-guide.md "Where output goes"): `out/<scene file stem>` for
/// `run`, `out/<scene file stem>-<command>` for the others (`-stability`, `-sweep`, `-accuracy`,
/// `-convergence`, `-compare`).
pub fn default_out_for(scene: &Path, command: &str) -> PathBuf {
    let base = default_out_dir(scene);
    let mut name = base.file_name().map(|s| s.to_os_string()).unwrap_or_default();
    name.push(format!("-{command}"));
    base.with_file_name(name)
}

/// The default output directory of a scene: `out/<file stem>`.
pub fn default_out_dir(scene: &Path) -> PathBuf {
    let stem = scene
        .file_stem()
        .map_or_else(|| "run".into(), |s| s.to_string_lossy().into_owned());
    Path::new("out").join(stem)
}

pub use crate::output::series_header;

pub(crate) fn execute(args: &RunArgs, simulate: SimulateFn) -> anyhow::Result<()> {
    let scene = Scene::load(&args.scene, &args.set)?;
    for w in &scene.scene().warnings {
        noteln!("warning: {w}");
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| default_out_dir(&args.scene));
    let header = series_header(scene.scene());

    let dir = OutputDir::create(&out)?;
    let series_path = dir.join("series.csv");
    #[cfg(unix)]
    crate::output::clean_up_on_signal(&[
        &dir.join("series.csv.tmp"),
        &dir.join("summary.json.tmp"),
    ]);
    let mut csv = match CsvWriter::create(&series_path, &header) {
        Ok(csv) => csv,
        Err(e) => {
            dir.discard();
            return Err(e.into());
        }
    };
    let mut line = Vec::with_capacity(header.len());
    let monitor = Monitor { bar: true, ..Monitor::default() };
    let result = stream_with(&scene, simulate, &monitor, &mut |t, row| {
        line.clear();
        line.push(t);
        line.extend_from_slice(row);
        csv.row(&line);
    });
    let outcome = match result {
        Ok(outcome) => outcome,
        Err(e) => {
            drop(csv);
            dir.discard();
            return Err(e);
        }
    };
    // echo.csv and spectrum.csv (scenes with [echo]; the summary has their levels)
    if let Err(e) = outcome.echo.as_ref().map_or(Ok(()), |e| echo::write(&dir, e)) {
        drop(csv);
        dir.discard();
        return Err(e);
    }
    let rows = csv.rows();
    let summary_path = dir.join("summary.json");
    let written = csv.commit().and_then(|()| write_json(&summary_path, &outcome.summary));
    if let Err(e) = written {
        let _ = std::fs::remove_file(&series_path);
        dir.discard();
        return Err(e.into());
    }

    let report = &outcome.report;
    print_summary(report, scene.scene(), &out, rows)?;
    if args.plot {
        crate::plot::series_plot(&series_path, &out)
            .with_context(|| format!("plotting {}", series_path.display()))?;
        outln!("plotted:    {}", out.join("series.svg").display());
        if let Some(e) = &outcome.echo {
            echo::plot(e, scene.scene().drive.as_ref().filter(|d| d.file.is_none()).map(|d| d.frequency_hz), &out).with_context(|| format!("plotting the echo of {}", scene.origin()))?;
            outln!("plotted:    {}", out.join("echo.svg").display());
        }
    } else {
        // a plot of an earlier run would sit beside the new data (issue 29 item 9)
        let mut stale = crate::plot::remove_stale_series_plot(&out);
        stale.extend(crate::plot::remove_stale_echo_plot(&out));
        for stale in stale {
            noteln!("removed {} (an earlier run's plot; --plot draws a new one)", stale.display());
        }
    }
    if let RunStatus::Failed { reason } = &report.status {
        anyhow::bail!(
            "the integration failed: {reason} (outputs up to t = {:e} s written to {})",
            report.t_end,
            out.display()
        );
    }
    Ok(())
}

fn print_summary(report: &RunReport, scene: &crate::scene::Scene, out: &Path, rows: u64) -> anyhow::Result<()> {
    let status = match &report.status {
        RunStatus::Completed => "completed".to_string(),
        RunStatus::BlowUp { t, mode } => format!("blow-up of {mode} at t = {t:e} s"),
        RunStatus::Failed { reason } => format!("FAILED: {reason}"),
        RunStatus::OutOfCredibleRange { t, mode, bound } => {
            format!("out_of_credible_range: |{mode}|/R0 exceeded {bound:e} (modes.credible_amplitude) at t = {t:e} s")
        }
    };
    outln!("status:     {status}");
    outln!(
        "t_end:      {:e} s of {:e} s",
        report.t_end, scene.run.duration
    );
    outln!(
        "steps:      {} ({} rejected), {} rhs evaluations, {:.3} s wall",
        report.stats.steps, report.stats.rejected, report.stats.rhs_evals, report.wall_seconds
    );
    if let Some(c) = &report.integrator {
        outln!("integrator: {} ({}: {})", c.method, c.chosen, c.reason);
    }
    outln!(
        "effects:    {} (state dimension {})",
        report.active_effects.join(", "),
        report.state_dimension
    );
    if let Ok(serde_json::Value::Object(groups)) = serde_json::to_value(&report.groups) {
        let list: Vec<String> = groups
            .iter()
            .map(|(k, v)| match v.as_f64() {
                Some(x) => format!("{k} = {}", crate::scene::schema::fmt_sig(x)),
                None => format!("{k} = {v}"),
            })
            .collect();
        outln!("groups:     {}", list.join(", "));
    }
    let largest = report
        .max_abs
        .iter()
        .filter(|(n, _)| n != "R" && n != "p_b")
        .max_by(|a, b| a.1.total_cmp(&b.1));
    if let Some((name, v)) = largest {
        outln!(
            "largest:    max |{name}| = {v:e} m (|{name}|/R0 = {:.3e})",
            v / scene.bubble.radius
        );
    }
    outln!(
        "wrote:      {} ({rows} rows), {}",
        out.join("series.csv").display(),
        out.join("summary.json").display()
    );
    Ok(())
}

#[cfg(test)]
mod tests;

mod echo;
