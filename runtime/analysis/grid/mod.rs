//! Grid sweeps: every combination of a few scene keys' values, one run each, in parallel
//! (`magbubble sweep SCENE --grid KEY=V1,V2,… …`, and the library API the Python binding wraps).
//!
//! A grid is planned, then run:
//!
//! 1. [`plan_grid`]`(template, axes)` expands the Cartesian product of the [`GridAxis`] values
//!    and validates every key, every value and every combination through
//!    [`SceneTemplate::with_overrides`](crate::scene::SceneTemplate::with_overrides) — the path
//!    of `--set`, so the messages are those of `--set` — before anything runs or is written.
//!    Point `index` takes value `i_k` of axis `k` with the first axis slowest:
//!    `index = Σ_k i_k · Π_{j>k} n_j` (row-major, as `itertools::iproduct!` or numpy's
//!    `meshgrid(indexing="ij")`).
//! 2. [`run_grid`]`(&plan, &GridOptions)` runs the points (each run single-threaded, the points
//!    in parallel on the current rayon pool) through [`crate::analysis::sweep`], so a grid is
//!    resumable, shardable (`index % n == i`) and mergeable (`magbubble merge`) exactly like a
//!    stability sweep. It returns one typed [`GridRow`] per point of the shard, sorted by index.
//!
//! ## The CSV (`DIR/sweep.csv`, or `DIR/sweep.shard-i-of-n.csv`)
//!
//! `index`, one column per grid key (named by the key, holding the value as it was set), then
//! [`row::result_header`]: `status` (`completed`, `blow_up`, `failed`), `t_blow_up` and
//! `blow_up_mode` (empty unless `blow_up`), `t_end`, `R_min` and `R_max` over the output samples,
//! `max_shape` and `max_shape_mode` (the largest max |a_k|, |b_k| and its column; empty without
//! shape modes), `max_a2`, `max_b2`, … (max |x| over the samples, one column per mode of the
//! largest `modes.max_order` of the grid; empty for a point without that mode), `steps`,
//! `rejected_steps`, `rhs_evaluations`, `note` (why a run failed) and, last, `wall_seconds`.
//!
//! Every column but the last depends only on the point, so those columns are byte-identical
//! for any thread count and any shard split once merged; `wall_seconds` (the run's wall time)
//! is the one column that is not, and is last so that it is easy to drop before comparing.
//! Numbers are Rust's `{:e}` (shortest round-trip), and the figures are those `run` prints in
//! `summary.json` for the same scene (`max_abs`, `steps`, …).
//!
//! ## Series
//!
//! With `keep_series`, each run's series is written to `DIR/series/<index>.csv` in the format of
//! `run`'s `series.csv` (byte for byte the same file), before its row; a resumed row whose series
//! file is missing is run again. With `return_series`, the series come back in the rows.

mod plan;
pub mod row;
mod run;

pub use plan::{plan_grid, GridAxis, GridPlan, GridValue, MAX_SHARD_POINTS, VALIDATE_ALL};
pub use row::{GridRow, GridStatus, Series};
pub use run::{csv_path, run_grid, GridOptions, GridOutcome};

use super::sweep::SweepError;
use crate::output::OutputError;
use crate::scene::SceneError;

/// Why a grid could not be planned or run (a run that fails or blows up is a row, not an error).
#[derive(Debug, thiserror::Error)]
pub enum GridError {
    /// A malformed grid: `what` names the argument (`--grid KEY=…`), `why` says what is wrong.
    #[error("{what}: {why}")]
    Grid { what: String, why: String },
    /// A key or value the scene rejects (the messages of `--set`); `context` names the grid
    /// value or point (`--grid bubble.radius=-1`, `grid point 3 (…)`).
    #[error("{context}: {source}")]
    Scene {
        context: String,
        #[source]
        source: SceneError,
    },
    #[error(transparent)]
    Sweep(#[from] SweepError),
    #[error(transparent)]
    Output(#[from] OutputError),
}

impl GridError {
    /// The scene problems (key, value, reason) behind a [`GridError::Scene`]; empty otherwise.
    pub fn issues(&self) -> &[crate::scene::Issue] {
        match self {
            GridError::Scene { source, .. } => source.issues(),
            _ => &[],
        }
    }
}
