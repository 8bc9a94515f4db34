//! `magbubble sweep SCENE --grid KEY=V1,V2,… […] [--set k=v]… [--out DIR] [--shard i/n]
//! [--keep-series]`: a grid of runs in parallel, one CSV row per run, resumable, shardable and
//! mergeable (`magbubble merge`). The work is [`crate::analysis::grid`]; docs/user-guide.md
//! describes the CSV.

use crate::analysis::sweep::Shard;
use crate::api::sweep::{self, GridAxis, GridRow, GridStatus, SweepRequest};
use crate::api::{Monitor, Scene};
use anyhow::Context as _;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct SweepArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// A grid axis: KEY=V1,V2,… (values as --set takes them) or KEY=START:STOP:N[:log]
    /// (repeatable; the grid is every combination, the first --grid slowest).
    #[arg(long = "grid", value_name = "KEY=V1,V2,…", required = true)]
    pub grid: Vec<String>,
    /// Override a scene key for every run, KEY=VALUE (repeatable; --grid values win).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Output directory: sweep.csv (+ .meta.json), series/<index>.csv with --keep-series.
    /// Output directory (default: out/<scene file stem>-sweep).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Shard i/n of the grid points (default from SLURM_ARRAY_TASK_ID/COUNT).
    #[arg(long)]
    pub shard: Option<String>,
    /// Write each run's series to DIR/series/<index>.csv (the format of `run`'s series.csv).
    #[arg(long)]
    pub keep_series: bool,
}

pub fn run(args: &SweepArgs) -> anyhow::Result<()> {
    let shard = match &args.shard {
        Some(s) => Shard::parse(s)?,
        None => Shard::from_env()?.unwrap_or(Shard::ALL),
    };
    let axes = args.grid.iter().map(|g| GridAxis::parse(g)).collect::<Result<Vec<_>, _>>()?;
    let scene = Scene::load(&args.scene, &args.set)?;
    for w in &scene.scene().warnings {
        noteln!("warning: {w}");
    }
    let plan = sweep::plan(&scene, &axes)?;
    noteln!("sweep: {} points, {} in shard {}/{}", plan.len(), plan.shard_len(shard), shard.index, shard.count);
    #[cfg(unix)]
    let cancel = Some(crate::output::cancel_on_signal());
    #[cfg(not(unix))]
    let cancel = None;
    let out_dir = args.out.clone().unwrap_or_else(|| super::run::default_out_for(&args.scene, "sweep"));
    let request = SweepRequest { out: Some(out_dir), shard: Some(shard), keep_series: args.keep_series, return_series: false };
    let monitor = Monitor { cancel, bar: true, ..Monitor::default() };
    let mut counts = [0usize; 3];
    let mut first_failed: Option<GridRow> = None;
    let outcome = sweep::sweep(&plan, &request, &monitor, &mut |row| {
        match row.status {
            GridStatus::Completed => counts[0] += 1,
            GridStatus::BlowUp => counts[1] += 1,
            GridStatus::Failed => {
                counts[2] += 1;
                first_failed.get_or_insert(row);
            }
            GridStatus::OutOfCredibleRange => {}
        }
    })
    .with_context(|| format!("sweep of {}", args.scene.display()))?;
    let csv = outcome.path.clone().unwrap_or_default();
    noteln!(
        "{}: {} runs ({} computed, {} resumed): {} completed, {} blow_up, {} failed",
        csv.display(),
        outcome.rows,
        outcome.computed,
        outcome.resumed,
        counts[0],
        counts[1],
        counts[2]
    );
    if outcome.cancelled {
        noteln!("interrupted: {} finished rows kept in {}; rerun the same command to resume", outcome.rows, csv.display());
        crate::output::flush_out()?;
        #[cfg(unix)]
        std::process::exit(128 + crate::output::cancelling_signal().unwrap_or(libc::SIGINT));
        #[cfg(not(unix))]
        std::process::exit(130);
    }
    if let Some(first) = first_failed {
        anyhow::bail!(
            "{} of {} runs failed (first: index {}, {}: {}); their rows are in {}",
            counts[2],
            outcome.rows,
            first.index,
            plan.keys().iter().zip(&first.values).map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>().join(", "),
            first.note,
            csv.display()
        );
    }
    Ok(())
}
