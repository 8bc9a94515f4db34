//! Running a scene: the integrator loop, SI output, blow-up detection and the run report.

use serde::Serialize;
use std::time::Instant;

use super::{Groups, Model, ModelError};
use crate::scene::{Run, Scene};
use crate::integrate::{solve, Control, IntegrateError, Method, Output, Stats};

/// How a run ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    Completed,
    /// A shape mode exceeded the blow-up threshold (or R left (0, ∞), or the state became
    /// non-finite) at time t [s]; a result, not an error (FORMULATION §5).
    BlowUp { t: f64, mode: String },
    /// The integrator gave up (e.g. step size too small, step budget exhausted).
    Failed { reason: String },
}

/// The summary of one run (SI units).
#[derive(Debug, Clone, Serialize)]
pub struct RunReport {
    pub status: RunStatus,
    /// Time of the last output sample [s].
    pub t_end: f64,
    pub stats: Stats,
    pub wall_seconds: f64,
    /// max |x| over the output samples, per output column (R, a2, b2, …) [m].
    pub max_abs: Vec<(String, f64)>,
    /// The last output sample (R, a2, b2, …) [m].
    pub final_state: Vec<(String, f64)>,
    pub active_effects: Vec<String>,
    /// Dimension of the integrated state (2 + 3M).
    pub state_dimension: usize,
    pub groups: Groups,
}

/// Builds the model of `scene` and runs it; `observer` gets (t [s], row R, a2, b2, … [m]) at
/// every output sample (`run.sample_interval`), including t = 0.
pub fn simulate(scene: &Scene, observer: &mut dyn FnMut(f64, &[f64])) -> Result<RunReport, ModelError> {
    if scene.modes.viscous == crate::scene::Viscous::Vorticity && scene.modes.max_order > 0 {
        return super::vorticity::scene::simulate_full(scene, observer)
            .map_err(|e| ModelError::FullModel(e.to_string()));
    }
    let model = Model::from_scene(scene)?;
    Ok(model.run(&scene.run, observer))
}

impl Model {
    /// The mode a component of the integrated state belongs to: "R" (R, Ṙ), "a{k}" (a_k, ȧ_k)
    /// or "b{k}".
    fn component_mode(&self, component: usize) -> String {
        match component {
            0 | 1 => "R".into(),
            c => {
                let k = self.orders.get((c - 2) / 3).copied().unwrap_or(0);
                if (c - 2) % 3 == 2 { format!("b{k}") } else { format!("a{k}") }
            }
        }
    }

    /// Runs this model with the run settings `run` (see [`simulate`]).
    pub fn run(&self, run: &Run, observer: &mut dyn FnMut(f64, &[f64])) -> RunReport {
        let start = Instant::now();
        let ts = self.time_scale();
        let names = self.state_names();
        let mut row = vec![0.0; names.len()];
        let mut max_abs = vec![0.0f64; names.len()];
        let mut last_t = 0.0;
        let mut blow: Option<(f64, String)> = None;
        let method = Method::from_settings(&run.integrator, ts);
        let mut obs = |t: f64, y: &[f64]| -> Control {
            self.to_si_into(y, &mut row);
            last_t = t * ts;
            for (m, v) in max_abs.iter_mut().zip(&row) {
                *m = m.max(v.abs());
            }
            observer(t * ts, &row);
            match self.blow_up(y) {
                Some(mode) => {
                    blow = Some((t * ts, mode));
                    Control::Stop
                }
                None => Control::Continue,
            }
        };
        let result = solve(
            self.system(),
            0.0,
            self.initial_state(),
            run.duration / ts,
            &method,
            Output::Every(run.sample_interval / ts),
            run.integrator.max_steps,
            &mut obs,
        );
        let (status, stats) = match result {
            Ok(sol) => (
                match blow.take() {
                    Some((t, mode)) => RunStatus::BlowUp { t, mode },
                    None => RunStatus::Completed,
                },
                sol.stats,
            ),
            // A state that turns non-finite between two output samples is, by the definition of
            // `blow_up::classify`, a blow-up: report it as one (with the mode of the offending
            // component and the time it went non-finite, an upper bound of the threshold crossing)
            // rather than as an integrator failure (docs/hard-cases.md).
            Err(IntegrateError::NonFinite { t, component }) => {
                (RunStatus::BlowUp { t: t * ts, mode: self.component_mode(component) }, Stats::default())
            }
            Err(e) => (RunStatus::Failed { reason: e.to_string() }, Stats::default()),
        };
        RunReport {
            status,
            t_end: last_t,
            stats,
            wall_seconds: start.elapsed().as_secs_f64(),
            max_abs: names.iter().cloned().zip(max_abs).collect(),
            final_state: names.iter().cloned().zip(row.iter().copied()).collect(),
            active_effects: self.active_effects(),
            state_dimension: self.system().dim(),
            groups: self.groups(),
        }
    }
}
