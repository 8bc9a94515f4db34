//! Running a planned grid ([`run_grid`]) on the sweep machinery of [`crate::analysis::sweep`].

use super::row::{mode_columns, GridRow, GridStatus, Series};
use super::{GridError, GridPlan};
use crate::analysis::sweep::{self, Control, Shard, SweepError, SweepMeta};
use crate::model::{simulate, RunStatus};
use crate::output::CsvWriter;
use crate::scene::Scene;
use std::collections::BTreeMap;
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Instant;

/// How to run a grid. `GridOptions::default()` runs the whole grid in memory, silently.
#[derive(Clone, Copy, Default)]
pub struct GridOptions<'a> {
    /// Output directory: the CSV is `out/sweep.csv` (`out/sweep.shard-i-of-n.csv` for a shard)
    /// with its `.meta.json`; rows already there are resumed. `None`: nothing is written.
    pub out: Option<&'a Path>,
    /// The slice of the grid to run (`Shard::ALL` when `None`).
    pub shard: Option<Shard>,
    /// Write each run's series to `out/series/<index>.csv` (needs `out`).
    pub keep_series: bool,
    /// Return each row's series in [`GridRow::series`] (kept in memory for the fresh runs, read
    /// back from `out/series/` for the resumed ones when it is there).
    pub return_series: bool,
    /// Checked before each run and at each output sample of a run: once set, no run starts, the
    /// runs in flight are abandoned (no row, no series file), the finished rows are kept and
    /// [`GridOutcome::cancelled`] is set. (A Python binding sets it on KeyboardInterrupt.)
    pub cancel: Option<&'a AtomicBool>,
    /// Called after each finished run with (runs finished in this call, runs this call
    /// computes), from the worker thread that finished it.
    pub on_run: Option<&'a (dyn Fn(usize, usize) + Sync)>,
    /// Draw a progress bar on stderr when it is a terminal.
    pub progress_bar: bool,
}

/// What [`run_grid`] did.
#[derive(Debug, Clone)]
pub struct GridOutcome {
    /// The CSV header, `index` first ([`GridPlan::header`] after it).
    pub header: Vec<String>,
    /// The rows of the shard, sorted by index (all of them unless `cancelled`).
    pub rows: Vec<GridRow>,
    /// Rows run by this call, and rows resumed from the CSV.
    pub computed: usize,
    pub resumed: usize,
    /// Whether the cancel flag stopped the grid early (a rerun into `out` resumes).
    pub cancelled: bool,
    /// The CSV written, when `out` was given.
    pub csv: Option<PathBuf>,
}

/// The CSV of a shard in `out`: `sweep.csv`, or `sweep.shard-i-of-n.csv`.
pub fn csv_path(out: &Path, shard: Shard) -> PathBuf {
    if shard == Shard::ALL {
        out.join("sweep.csv")
    } else {
        out.join(format!("sweep.shard-{}-of-{}.csv", shard.index, shard.count))
    }
}

/// Runs the points of `plan` (those of `options.shard`) in parallel on the current rayon pool,
/// each run single-threaded, and returns their rows sorted by index. A run that blows up or
/// fails is a row (`status`), not an error; errors are I/O, a CSV of another grid in `out`
/// ([`SweepError::Mismatch`]), or `keep_series` without `out`.
pub fn run_grid(plan: &GridPlan, options: &GridOptions) -> Result<GridOutcome, GridError> {
    if options.keep_series && options.out.is_none() {
        return Err(GridError::Grid {
            what: "keep_series".into(),
            why: "the series are written to DIR/series/<index>.csv: give an output directory (or use return_series)".into(),
        });
    }
    let shard = options.shard.unwrap_or(Shard::ALL);
    // a shard too large for one process, or with a point the scene rejects: refused before any run
    plan.check_shard(shard)?;
    // one process at a time in `out` (issue 29 item 3), held over the whole grid
    let _lock = options.out.map(crate::output::DirLock::acquire).transpose()?;
    let csv = options.out.map(|o| csv_path(o, shard));
    let series_dir = options.out.filter(|_| options.keep_series).map(|o| o.join("series"));
    if let Some(dir) = &series_dir {
        std::fs::create_dir_all(dir).map_err(|source| SweepError::Io { path: dir.clone(), source })?;
    }
    let series_file = |i: usize| series_dir.as_ref().map(|d| d.join(format!("{i}.csv")));
    let meta = SweepMeta { fingerprint: plan.fingerprint.clone(), total: plan.len(), shard, header: plan.header() };
    let naxes = plan.axes.len();
    // A resumed row whose series was asked for but is missing runs again (unless it failed
    // before producing a series).
    let retry = |i: usize, fields: &[String]| {
        series_file(i).is_some_and(|p| !p.exists()) && fields.get(naxes).is_some_and(|s| s != GridStatus::Failed.as_str())
    };
    let fresh_series: Mutex<BTreeMap<usize, Series>> = Mutex::new(BTreeMap::new());
    let control = Control { progress_bar: options.progress_bar, cancel: options.cancel, on_point: options.on_run, retry: Some(&retry) };
    let report = sweep::run_with(csv.as_deref(), &meta, &control, |i| {
        let values = plan.values(i).into_iter().map(str::to_string).collect();
        let point = Point { index: i, values, orders: &plan.orders, series_file: series_file(i), in_memory: options.return_series };
        let scene = plan.scene(i).ok()?; // validated by check_shard
        let mut row = run_point(&scene, point, options.cancel)?;
        let fields = row.fields();
        if let Some(s) = row.series.take() {
            fresh_series.lock().unwrap_or_else(|p| p.into_inner()).insert(i, s);
        }
        Some(fields)
    })?;
    let mut fresh_series = fresh_series.into_inner().unwrap_or_else(|p| p.into_inner());
    let mut rows = Vec::with_capacity(report.rows.len());
    for (i, fields) in &report.rows {
        let mut row = GridRow::from_fields(*i, fields, naxes, &plan.orders).ok_or_else(|| SweepError::Corrupt {
            path: csv.clone().unwrap_or_default(),
            why: format!("row {i} does not parse as a grid row"),
        })?;
        if options.return_series {
            row.series = fresh_series.remove(i).or_else(|| {
                let text = std::fs::read_to_string(series_file(*i)?).ok()?;
                Series::parse(&text)
            });
        }
        rows.push(row);
    }
    let mut header = vec!["index".to_string()];
    header.extend(meta.header);
    Ok(GridOutcome { header, rows, computed: report.computed, resumed: report.resumed, cancelled: report.cancelled, csv })
}

/// What a run needs besides its scene.
struct Point<'a> {
    index: usize,
    values: Vec<String>,
    orders: &'a [usize],
    series_file: Option<PathBuf>,
    in_memory: bool,
}

/// The unwind payload that abandons a run when the cancel flag is set (raised with
/// `resume_unwind`, so no panic message is printed; caught in [`run_point`]).
struct Abandoned;

/// Runs one point; `None` when the cancel flag abandoned it.
fn run_point(scene: &Scene, point: Point, cancel: Option<&AtomicBool>) -> Option<GridRow> {
    let mut row = GridRow {
        index: point.index,
        values: point.values,
        status: GridStatus::Failed,
        t_blow_up: None,
        blow_up_mode: None,
        t_end: f64::NAN,
        r_min: f64::NAN,
        r_max: f64::NAN,
        max_shape: None,
        max_abs: mode_columns(point.orders).into_iter().map(|m| (m, None)).collect(),
        steps: 0,
        rejected_steps: 0,
        rhs_evaluations: 0,
        note: String::new(),
        wall_seconds: 0.0,
        series: None,
    };
    let header = crate::output::series_header(scene);
    let mut writer = match point.series_file.as_deref().map(|p| CsvWriter::create(p, &header)).transpose() {
        Ok(w) => w,
        Err(e) => {
            row.note = format!("cannot write the series: {e}");
            return Some(row);
        }
    };
    let (mut r_min, mut r_max) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut line = Vec::with_capacity(header.len());
    let mut memory = Vec::new();
    let start = Instant::now();
    let result = catch_unwind(AssertUnwindSafe(|| {
        simulate(scene, &mut |t, x| {
            if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                resume_unwind(Box::new(Abandoned));
            }
            r_min = r_min.min(x[0]);
            r_max = r_max.max(x[0]);
            line.clear();
            line.push(t);
            line.extend_from_slice(x);
            if let Some(w) = writer.as_mut() {
                w.row(&line);
            }
            if point.in_memory {
                memory.extend_from_slice(&line);
            }
        })
    }));
    row.wall_seconds = start.elapsed().as_secs_f64();
    let report = match result {
        Err(payload) if payload.is::<Abandoned>() => return None,
        Err(payload) => {
            let msg = payload.downcast_ref::<&str>().map(|s| s.to_string()).or_else(|| payload.downcast_ref::<String>().cloned());
            row.note = format!("internal error (panic): {}", msg.unwrap_or_default());
            return Some(row);
        }
        Ok(Err(e)) => {
            row.note = e.to_string();
            return Some(row);
        }
        Ok(Ok(report)) => report,
    };
    if r_min <= r_max {
        (row.r_min, row.r_max) = (r_min, r_max);
    }
    row.t_end = report.t_end;
    match &report.status {
        RunStatus::Completed => row.status = GridStatus::Completed,
        RunStatus::BlowUp { t, mode } => {
            row.status = GridStatus::BlowUp;
            row.t_blow_up = Some(*t);
            row.blow_up_mode = Some(mode.clone());
        }
        RunStatus::Failed { reason } => row.note = reason.to_string(),
        RunStatus::OutOfCredibleRange { t, mode, bound } => {
            row.status = GridStatus::OutOfCredibleRange;
            row.note = format!("|{mode}|/R0 > {bound} at t = {t:e} s");
        }
    }
    for (name, v) in &mut row.max_abs {
        *v = report.max_abs.iter().find(|(n, _)| n == name).map(|p| p.1);
    }
    row.max_shape = report.max_abs.iter().filter(|(n, _)| n != "R" && n != "p_b").max_by(|a, b| a.1.total_cmp(&b.1)).cloned();
    row.steps = report.stats.steps;
    row.rejected_steps = report.stats.rejected;
    row.rhs_evaluations = report.stats.rhs_evals;
    if let Some(w) = writer {
        if let Err(e) = w.commit() {
            row.status = GridStatus::Failed;
            row.note = format!("cannot write the series: {e}");
        }
    }
    if point.in_memory {
        row.series = Some(Series { columns: header, values: memory });
    }
    Some(row)
}
