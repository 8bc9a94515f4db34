//! `magbubble run SCENE [--out DIR] [--set key=value]...`: simulates a scene and writes
//! `DIR/series.csv` (header `t,R,a2,b2,a4,b4,…`, SI units) and `DIR/summary.json` (status,
//! statistics, nondimensional groups and every resolved parameter).
//!
//! Nothing is created when the scene is invalid; when the model cannot be assembled or a write
//! fails, the temp files are removed and so is the output directory if this run created it.

use anyhow::Context as _;
use crate::output::{write_json, CsvWriter, OrderedMap, OutputDir, Progress};
use crate::scene::{self, Scene};
use serde::Serialize;
use std::path::{Path, PathBuf};

use sim::{ModelError, RunReport, RunStatus};

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

/// The simulation entry point (`crate::model::simulate`).
pub(crate) type SimulateFn =
    fn(&Scene, &mut dyn FnMut(f64, &[f64])) -> Result<RunReport, ModelError>;

pub fn run(args: &RunArgs) -> anyhow::Result<()> {
    execute(args, sim::simulate)
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

/// `summary.json` (built by [`summary`]; also what the Python `Run.summary` holds).
#[derive(Serialize)]
pub struct Summary<'a> {
    status: &'a RunStatus,
    t_end: f64,
    steps: u64,
    rejected_steps: u64,
    rhs_evaluations: u64,
    /// Jacobian evaluations (analytic, finite-difference or structured).
    jacobian_evaluations: u64,
    /// LU factorisations of the Newton matrix.
    lu_decompositions: u64,
    wall_seconds: f64,
    rows: u64,
    max_abs: OrderedMap<'a>,
    final_state: OrderedMap<'a>,
    active_effects: &'a [String],
    state_dimension: usize,
    groups: serde_json::Value,
    /// Every resolved parameter (defaults applied, overrides included).
    scene: &'a Scene,
    /// The scene file and the `--set` overrides it was run with.
    source: Source<'a>,
    /// The echo's levels (issue 30 part 2), with `[echo]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    echo: Option<serde_json::Value>,
}

#[derive(Serialize)]
struct Source<'a> {
    file: String,
    overrides: &'a [String],
}

/// The `summary.json` of a run of `scene` (from the file `file` with the `--set` overrides
/// `overrides`) that wrote `rows` rows.
pub fn summary<'a>(report: &'a RunReport, scene: &'a Scene, rows: u64, file: &str, overrides: &'a [String]) -> Summary<'a> {
    Summary {
        status: &report.status,
        t_end: report.t_end,
        steps: report.stats.steps,
        rejected_steps: report.stats.rejected,
        rhs_evaluations: report.stats.rhs_evals,
        jacobian_evaluations: report.stats.jac_evals,
        lu_decompositions: report.stats.lu_decompositions,
        wall_seconds: report.wall_seconds,
        rows,
        max_abs: OrderedMap(&report.max_abs),
        final_state: OrderedMap(&report.final_state),
        active_effects: &report.active_effects,
        state_dimension: report.state_dimension,
        groups: serde_json::to_value(&report.groups).unwrap_or(serde_json::Value::Null),
        scene,
        source: Source { file: file.to_string(), overrides },
        echo: None,
    }
}

pub(crate) fn execute(args: &RunArgs, simulate: SimulateFn) -> anyhow::Result<()> {
    let scene = scene::load(&args.scene, &args.set)?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| default_out_dir(&args.scene));
    let header = series_header(&scene);
    let width = header.len() - 1;

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
    let mut progress = Progress::new(scene.run.duration, &format!("run {}", args.scene.display()));
    let mut line = Vec::with_capacity(width + 1);
    let mut width_error = None;
    let mut observer = |t: f64, row: &[f64]| {
        if row.len() != width {
            width_error.get_or_insert((t, row.len()));
            return;
        }
        line.clear();
        line.push(t);
        line.extend_from_slice(row);
        csv.row(&line);
        progress.set(t);
    };
    let (result, echo) = match scene.echo {
        None => (simulate(&scene, &mut observer), None),
        Some(_) => match crate::echo::simulate(&scene, &mut observer) {
            Ok((r, e)) => (Ok(r), e),
            Err(e) => (Err(e), None),
        },
    };
    progress.finish();

    let report = match (result, width_error) {
        (Ok(report), None) => report,
        (Ok(_), Some((t, len))) => {
            drop(csv);
            dir.discard();
            anyhow::bail!("internal error: the model gave a row of {len} values at t = {t:e} s, expected {width}");
        }
        (Err(e), _) => {
            drop(csv);
            dir.discard();
            return Err(
                anyhow::Error::new(e).context(format!("cannot simulate {}", args.scene.display()))
            );
        }
    };
    let rows = csv.rows();
    let summary_path = dir.join("summary.json");
    let echo_summary = match echo.as_ref().map(|e| echo::write(&dir, e, &scene)).transpose() {
        Ok(s) => s,
        Err(e) => {
            drop(csv);
            dir.discard();
            return Err(e);
        }
    };
    let mut sum = summary(&report, &scene, rows, &args.scene.display().to_string(), &args.set);
    sum.echo = echo_summary;
    let written = csv.commit().and_then(|()| write_json(&summary_path, &sum));
    if let Err(e) = written {
        let _ = std::fs::remove_file(&series_path);
        dir.discard();
        return Err(e.into());
    }

    print_summary(&report, &scene, &out, rows)?;
    if args.plot {
        crate::plot::series_plot(&series_path, &out)
            .with_context(|| format!("plotting {}", series_path.display()))?;
        outln!("plotted:    {}", out.join("series.svg").display());
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

fn print_summary(report: &RunReport, scene: &Scene, out: &Path, rows: u64) -> anyhow::Result<()> {
    let status = match &report.status {
        RunStatus::Completed => "completed".to_string(),
        RunStatus::BlowUp { t, mode } => format!("blow-up of {mode} at t = {t:e} s"),
        RunStatus::Failed { reason } => format!("FAILED: {reason}"),
        RunStatus::OutOfCredibleRange { t, mode, bound } => {
            format!("out_of_credible_range: |{mode}|/R0 exceeded {bound} (modes.credible_amplitude) at t = {t:e} s")
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
        .filter(|(n, _)| n != "R")
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

/// The simulation entry points this command uses.
mod sim {
    pub use crate::model::{simulate, ModelError, RunReport, RunStatus};
}

mod echo;
#[cfg(test)]
mod tests;
