//! `run`: simulate a scene. [`stream`] hands each output row to a sink (the CLI writes
//! `series.csv` from it, in constant memory); [`run`] keeps the series in memory (Python).
//! Both return the run's report and the typed [`Summary`], whose serialisation is
//! `summary.json`.

use super::common::{Cancelled, Monitor};
use super::scene::Scene;
use crate::model::{Groups, ModelError, RunReport, RunStatus};
use crate::output::OrderedMap;
use serde::{Serialize, Serializer};
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};

/// The simulation entry point ([`crate::model::simulate`]; tests pass a stand-in).
pub type SimulateFn = fn(&crate::scene::Scene, &mut dyn FnMut(f64, &[f64])) -> Result<RunReport, ModelError>;

/// What a run did, without its series.
#[derive(Debug, Clone)]
pub struct RunOutcome {
    /// The series' columns: `t, R, a2, b2, …` (SI units), as the header of `series.csv`.
    pub columns: Vec<String>,
    /// Output rows produced.
    pub rows: u64,
    /// Status (completed, blow-up, failed, out of the credible range), statistics, the
    /// active effects, max |x| and the final state, the nondimensional groups.
    pub report: RunReport,
    /// The typed `summary.json`.
    pub summary: Summary,
    /// The recorded echo (scenes with `[echo]`; docs/model.md, "Echo"): its series and
    /// spectrum tables (echo.csv, spectrum.csv) and its levels (also in `summary.echo`).
    pub echo: Option<super::echo::Echo>,
}

/// A run with its series in memory.
#[derive(Debug, Clone)]
pub struct RunResult {
    /// Row-major, `outcome.rows × outcome.columns.len()`: `t, R, a2, b2, …` per row.
    pub values: Vec<f64>,
    pub outcome: RunOutcome,
}

/// `summary.json`: the status, the work, max |x| and the final state per column, the active
/// effects, the nondimensional groups, every resolved parameter and the source (file and
/// overrides). Serialises to the bytes `run` has always written.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    pub status: RunStatus,
    pub t_end: f64,
    pub steps: u64,
    pub rejected_steps: u64,
    pub rhs_evaluations: u64,
    /// Jacobian evaluations (analytic, finite-difference or structured).
    pub jacobian_evaluations: u64,
    /// LU factorisations of the Newton matrix.
    pub lu_decompositions: u64,
    /// Which integrator ran and why (issue 34): method, "auto" or "scene", the reason, the
    /// spectral radius it was decided from.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub integrator: Option<crate::model::IntegratorChoice>,
    pub wall_seconds: f64,
    pub rows: u64,
    #[serde(serialize_with = "ordered")]
    pub max_abs: Vec<(String, f64)>,
    #[serde(serialize_with = "ordered")]
    pub final_state: Vec<(String, f64)>,
    pub active_effects: Vec<String>,
    pub state_dimension: usize,
    /// Written with its keys sorted (as summary.json always had them).
    #[serde(serialize_with = "sorted")]
    pub groups: Groups,
    /// Every resolved parameter (defaults applied, overrides included).
    pub scene: crate::scene::Scene,
    /// The scene file and the overrides it was run with.
    pub source: Source,
    /// The echo's levels (issue 30 part 2), with `[echo]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub echo: Option<serde_json::Value>,
    /// Issue 31: with the kinked Marmottant law, the fractions of the run's time spent
    /// buckled / elastic / ruptured (from the located branch switches) and the switch count.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shell_branches: Option<crate::model::BranchFractions>,
}

/// Where a run's scene came from.
#[derive(Debug, Clone, Serialize)]
pub struct Source {
    pub file: String,
    pub overrides: Vec<String>,
}

fn ordered<S: Serializer>(pairs: &[(String, f64)], s: S) -> Result<S::Ok, S::Error> {
    OrderedMap(pairs).serialize(s)
}

fn sorted<S: Serializer>(groups: &Groups, s: S) -> Result<S::Ok, S::Error> {
    serde_json::to_value(groups).unwrap_or(serde_json::Value::Null).serialize(s)
}

impl Summary {
    /// The summary of a run of `scene` that produced `rows` rows.
    pub fn new(report: &RunReport, scene: &Scene, rows: u64) -> Summary {
        Summary {
            status: report.status.clone(),
            t_end: report.t_end,
            steps: report.stats.steps,
            rejected_steps: report.stats.rejected,
            rhs_evaluations: report.stats.rhs_evals,
            jacobian_evaluations: report.stats.jac_evals,
            lu_decompositions: report.stats.lu_decompositions,
            integrator: report.integrator.clone(),
            wall_seconds: report.wall_seconds,
            rows,
            max_abs: report.max_abs.clone(),
            final_state: report.final_state.clone(),
            active_effects: report.active_effects.clone(),
            state_dimension: report.state_dimension,
            groups: report.groups.clone(),
            scene: scene.scene().clone(),
            source: Source { file: scene.origin().to_string(), overrides: scene.overrides().to_vec() },
            echo: None,
            shell_branches: report.shell_branches,
        }
    }
}

/// Simulates `scene`, handing each output row (t, then R, a2, b2, … [SI]) to `sink`.
/// A model that cannot be assembled is an error ("cannot simulate FILE"); a blow-up or a
/// failed integration is the report's status. Progress is the simulated time; a cancel
/// stops the run at the next output row with [`Cancelled`].
pub fn stream(scene: &Scene, monitor: &Monitor, sink: &mut dyn FnMut(f64, &[f64])) -> anyhow::Result<RunOutcome> {
    stream_with(scene, crate::model::simulate, monitor, sink)
}

/// [`stream`] with the simulation entry point given.
pub fn stream_with(
    scene: &Scene,
    simulate: SimulateFn,
    monitor: &Monitor,
    sink: &mut dyn FnMut(f64, &[f64]),
) -> anyhow::Result<RunOutcome> {
    let sc = scene.scene();
    let columns = crate::output::series_header(sc);
    let width = columns.len() - 1;
    let duration = sc.run.duration;
    let mut bar = monitor.bar.then(|| crate::output::Progress::new(duration, &format!("run {}", scene.origin())));
    let mut width_error = None;
    let mut rows = 0u64;
    let result = catch_unwind(AssertUnwindSafe(|| {
        let mut observer = |t: f64, row: &[f64]| {
            if monitor.cancelled() {
                resume_unwind(Box::new(Cancelled));
            }
            if row.len() != width {
                width_error.get_or_insert((t, row.len()));
                return;
            }
            sink(t, row);
            rows += 1;
            monitor.progress(t, duration);
            if let Some(b) = bar.as_mut() {
                b.set(t);
            }
        };
        match sc.echo {
            None => simulate(sc, &mut observer).map(|r| (r, None)),
            Some(_) => crate::echo::simulate(sc, &mut observer),
        }
    }));
    if let Some(b) = bar {
        b.finish();
    }
    let result = match result {
        Ok(r) => r,
        Err(payload) if payload.is::<Cancelled>() => return Err(Cancelled.into()),
        Err(payload) => resume_unwind(payload),
    };
    let (report, echo) = result.map_err(|e| anyhow::Error::new(e).context(format!("cannot simulate {}", scene.origin())))?;
    if let Some((t, len)) = width_error {
        anyhow::bail!("internal error: the model gave a row of {len} values at t = {t:e} s, expected {width}");
    }
    let mut summary = Summary::new(&report, scene, rows);
    let echo = echo.map(|e| super::echo::Echo::of(e, sc));
    if let Some(e) = &echo {
        summary.echo = Some(serde_json::to_value(&e.levels)?);
    }
    Ok(RunOutcome { columns, rows, report, summary, echo })
}

/// Simulates `scene` with the series kept in memory (row-major, the values `series.csv`
/// holds, bit for bit).
pub fn run(scene: &Scene, monitor: &Monitor) -> anyhow::Result<RunResult> {
    let mut values = Vec::new();
    let outcome = stream(scene, monitor, &mut |t, row| {
        values.push(t);
        values.extend_from_slice(row);
    })?;
    Ok(RunResult { values, outcome })
}
