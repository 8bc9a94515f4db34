//! `sweep`: a grid of runs over scene keys, in parallel, one row per run
//! ([`crate::analysis::grid`]: planned and validated first, then run; resumable, shardable and
//! mergeable when written to a directory). The rows are handed to a sink in index order, so a
//! caller keeps them in whatever form it needs (the CLI counts them, Python fills typed
//! columns) instead of a second copy of every row.

use super::common::Monitor;
use super::scene::Scene;
use super::table::{Column, Table, TextBuilder};
use crate::analysis::grid::{self, GridError, GridOptions, GridPlan};
pub use crate::analysis::grid::{GridAxis, GridRow, GridStatus, Series};
use crate::analysis::sweep::Shard;
use std::path::PathBuf;

/// How to run a grid.
#[derive(Debug, Clone, Default)]
pub struct SweepRequest {
    /// `DIR/sweep.csv` (or `sweep.shard-i-of-n.csv`) with its `.meta.json`; rows already there
    /// are resumed. `None`: nothing is written.
    pub out: Option<PathBuf>,
    /// The slice of the grid to run (all of it when `None`).
    pub shard: Option<Shard>,
    /// Write each run's series to `DIR/series/<index>.csv` (needs `out`).
    pub keep_series: bool,
    /// Hand each row's series to the sink ([`GridRow::series`]).
    pub return_series: bool,
}

/// What [`sweep`] did (the rows went to the sink).
#[derive(Debug, Clone)]
pub struct SweepSummary {
    /// The CSV header, `index` first, then the grid keys and the result columns.
    pub header: Vec<String>,
    /// Rows handed to the sink (the shard's rows, all of them unless cancelled).
    pub rows: usize,
    /// Rows run by this call, and rows resumed from the CSV.
    pub computed: usize,
    pub resumed: usize,
    /// Whether the monitor's cancel stopped the grid early (a rerun into `out` resumes).
    pub cancelled: bool,
    /// The CSV written, when `out` was given.
    pub path: Option<PathBuf>,
}

/// Expands the grid on `scene` and validates every key, value and combination (the messages
/// of `--set`) before anything runs or is written.
pub fn plan(scene: &Scene, axes: &[GridAxis]) -> Result<GridPlan, GridError> {
    grid::plan_grid(scene.template(), axes)
}

/// Runs the points of `plan` (each run single-threaded, the points in parallel) and hands
/// every row of the shard to `sink`, in index order. Progress counts runs; a cancel keeps the
/// whole rows finished so far. A run that blows up or fails is a row, not an error.
pub fn sweep(plan: &GridPlan, req: &SweepRequest, monitor: &Monitor, sink: &mut dyn FnMut(GridRow)) -> Result<SweepSummary, GridError> {
    let on_run = monitor.counter();
    let options = GridOptions {
        out: req.out.as_deref(),
        shard: req.shard,
        keep_series: req.keep_series,
        return_series: req.return_series,
        cancel: monitor.cancel,
        on_run: monitor.report.is_some().then_some(&on_run as &(dyn Fn(usize, usize) + Sync)),
        progress_bar: monitor.bar,
    };
    let outcome = grid::run_grid(plan, &options)?;
    let rows = outcome.rows.len();
    for row in outcome.rows {
        sink(row);
    }
    Ok(SweepSummary {
        header: outcome.header,
        rows,
        computed: outcome.computed,
        resumed: outcome.resumed,
        cancelled: outcome.cancelled,
        path: outcome.csv,
    })
}

/// The rows of a sweep as typed columns, filled one row at a time (a [`sweep`] sink): the
/// columns of `sweep.csv` (`index`, the grid keys typed by [`super::table`]'s rule, `status`,
/// `t_blow_up`, …, `wall_seconds`), numbers as numbers (an absent value is NaN), and each
/// row's series when they were asked for.
pub struct SweepTable {
    header: Vec<String>,
    index: Vec<i64>,
    keys: Vec<TextBuilder>,
    status: TextBuilder,
    t_blow_up: Vec<f64>,
    blow_up_mode: TextBuilder,
    t_end: Vec<f64>,
    r_min: Vec<f64>,
    r_max: Vec<f64>,
    max_shape: Vec<f64>,
    max_shape_mode: TextBuilder,
    max_abs: Vec<Vec<f64>>,
    steps: Vec<i64>,
    rejected_steps: Vec<i64>,
    rhs_evaluations: Vec<i64>,
    note: TextBuilder,
    wall_seconds: Vec<f64>,
    /// Each row's series (`None` unless asked for, or for a run that produced none).
    pub series: Vec<Option<Series>>,
}

impl SweepTable {
    /// An empty table for the rows of `plan`.
    pub fn new(plan: &GridPlan) -> SweepTable {
        let mut header = vec!["index".to_string()];
        header.extend(plan.header());
        // the result columns: 8 before the modes, 5 after them (analysis::grid::row)
        let modes = header.len() - 1 - plan.axes().len() - 13;
        SweepTable {
            header,
            index: Vec::new(),
            keys: plan.axes().iter().map(|_| TextBuilder::default()).collect(),
            status: TextBuilder::default(),
            t_blow_up: Vec::new(),
            blow_up_mode: TextBuilder::default(),
            t_end: Vec::new(),
            r_min: Vec::new(),
            r_max: Vec::new(),
            max_shape: Vec::new(),
            max_shape_mode: TextBuilder::default(),
            max_abs: vec![Vec::new(); modes],
            steps: Vec::new(),
            rejected_steps: Vec::new(),
            rhs_evaluations: Vec::new(),
            note: TextBuilder::default(),
            wall_seconds: Vec::new(),
            series: Vec::new(),
        }
    }

    /// Appends one row (its series, if any, is kept in [`SweepTable::series`]).
    pub fn push(&mut self, mut row: GridRow) {
        let nan = f64::NAN;
        self.index.push(row.index as i64);
        for (b, v) in self.keys.iter_mut().zip(&row.values) {
            b.push(v);
        }
        self.status.push(row.status.as_str());
        self.t_blow_up.push(row.t_blow_up.unwrap_or(nan));
        self.blow_up_mode.push(row.blow_up_mode.as_deref().unwrap_or(""));
        self.t_end.push(row.t_end);
        self.r_min.push(row.r_min);
        self.r_max.push(row.r_max);
        self.max_shape.push(row.max_shape.as_ref().map_or(nan, |m| m.1));
        self.max_shape_mode.push(row.max_shape.as_ref().map_or("", |m| m.0.as_str()));
        for (col, (_, v)) in self.max_abs.iter_mut().zip(&row.max_abs) {
            col.push(v.unwrap_or(nan));
        }
        self.steps.push(row.steps as i64);
        self.rejected_steps.push(row.rejected_steps as i64);
        self.rhs_evaluations.push(row.rhs_evaluations as i64);
        self.note.push(&row.note.replace([',', '\n', '\r'], ";"));
        self.wall_seconds.push(row.wall_seconds);
        self.series.push(row.series.take());
    }

    /// The columns, in the CSV's order, and the series.
    pub fn finish(self) -> (Table, Vec<Option<Series>>) {
        use Column::{Float, Int};
        let mut columns = vec![Int(self.index)];
        columns.extend(self.keys.into_iter().map(TextBuilder::finish));
        columns.extend([
            self.status.finish(),
            Float(self.t_blow_up),
            self.blow_up_mode.finish(),
            Float(self.t_end),
            Float(self.r_min),
            Float(self.r_max),
            Float(self.max_shape),
            self.max_shape_mode.finish(),
        ]);
        columns.extend(self.max_abs.into_iter().map(Float));
        columns.extend([Int(self.steps), Int(self.rejected_steps), Int(self.rhs_evaluations), self.note.finish(), Float(self.wall_seconds)]);
        (Table { names: self.header, columns }, self.series)
    }
}
