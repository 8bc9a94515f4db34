//! Running a scene: the run report, typed stop reasons, and [`Model::run`] on the one run
//! executor ([`super::executor`]).

use serde::Serialize;
use std::time::Instant;

use super::executor::{execute, Plan};
pub use super::executor::Row;
use super::{Groups, Model, ModelError};
use crate::integrate::{stepper, IntegrateError, Method, Stats, Stepper};
use crate::scene::{IntegratorSettings, Run, Scene};

/// How a run ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    Completed,
    /// A shape mode exceeded the blow-up threshold (or R left (0, ∞), or the state became
    /// non-finite) at time t [s]; a result, not an error (FORMULATION §5).
    BlowUp { t: f64, mode: String },
    /// Quadratic coupling (issue 12): max_k |a_k|/R0 of shape mode `mode` exceeded `bound`
    /// (`modes.credible_amplitude`) at time t [s], where second order stops being credible; a
    /// result (the run stops there), not a blow-up.
    OutOfCredibleRange { t: f64, mode: String, bound: f64 },
    /// The integrator gave up (serialised as its message, a string, as before).
    Failed { reason: Failure },
}

/// Why a run failed (times in seconds).
#[derive(Debug, Clone, PartialEq)]
pub enum Failure {
    /// The step size fell below round-off at t (h the last step tried) [s].
    StepSizeTooSmall { t: f64, h: f64 },
    /// `run.integrator.max_steps` accepted steps were taken by t [s].
    StepLimit { t: f64, steps: u64 },
    /// The simplified Newton iteration of an implicit method failed repeatedly at t [s].
    NewtonFailed { t: f64 },
    /// A linear system of the method was singular at t [s].
    Singular { t: f64 },
    /// The integrator refused its settings or the initial state before the first step.
    Setup(String),
}

impl Failure {
    /// The failure as a report, from an integrator error in units of the model's `time_scale` [s].
    pub fn from_integrate(e: &IntegrateError, time_scale: f64) -> Failure {
        match *e {
            IntegrateError::StepSizeTooSmall { t, h } => Failure::StepSizeTooSmall { t: t * time_scale, h: h * time_scale },
            IntegrateError::MaxSteps { t, steps } => Failure::StepLimit { t: t * time_scale, steps },
            IntegrateError::NewtonFailed { t } => Failure::NewtonFailed { t: t * time_scale },
            IntegrateError::SingularMatrix { t } => Failure::Singular { t: t * time_scale },
            IntegrateError::NonFinite { .. } | IntegrateError::InvalidSetting { .. } | IntegrateError::DimensionMismatch { .. } => {
                Failure::Setup(e.to_string())
            }
        }
    }

    /// Time of the failure [s] (`None` before the first step).
    pub fn t(&self) -> Option<f64> {
        match *self {
            Failure::StepSizeTooSmall { t, .. } | Failure::StepLimit { t, .. } | Failure::NewtonFailed { t } | Failure::Singular { t } => Some(t),
            Failure::Setup(_) => None,
        }
    }
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::StepSizeTooSmall { t, h } => write!(
                f,
                "step size too small at t = {t:e} s: h = {h:e} s (the solution may blow up or the problem is too stiff for this method)"
            ),
            Failure::StepLimit { t, steps } => write!(f, "step limit run.integrator.max_steps = {steps} reached at t = {t:e} s"),
            Failure::NewtonFailed { t } => {
                write!(f, "Newton iteration of the implicit method failed repeatedly at t = {t:e} s (singular or divergent)")
            }
            Failure::Singular { t } => write!(f, "singular linear system in the integrator at t = {t:e} s"),
            Failure::Setup(what) => write!(f, "{what}"),
        }
    }
}

impl Serialize for Failure {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// The summary of one run (SI units).
#[derive(Debug, Clone, Serialize)]
pub struct RunReport {
    pub status: RunStatus,
    /// Time of the last output row [s] (at a blow-up: the located crossing).
    pub t_end: f64,
    /// Work of the integrator up to the end of the run, also after a failure or a blow-up.
    pub stats: Stats,
    pub wall_seconds: f64,
    /// max |x| over the output rows, per output column (R, a2, b2, …) [m].
    pub max_abs: Vec<(String, f64)>,
    /// The last output row (R, a2, b2, …) [m].
    pub final_state: Vec<(String, f64)>,
    pub active_effects: Vec<String>,
    /// Dimension of the integrated state (2 + 3M).
    pub state_dimension: usize,
    pub groups: Groups,
    /// The kinked Marmottant law's fractions of time buckled / elastic / ruptured (issue 31).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shell_branches: Option<super::events::BranchFractions>,
    /// Which integrator ran and why (issue 34; `None` for a run on a given stepper).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub integrator: Option<super::stiffness::IntegratorChoice>,
}

/// The integrator of a scene's settings; `time_scale` [s] is the model's unit of time (the model
/// is nondimensional, FORMULATION §4.5), so RK4's `dt` [s] becomes `dt / time_scale`.
/// `auto` here is Radau5 (the full vorticity model's method); a boundary-layer run resolves
/// it from the stiffness estimate instead ([`Model::choose_integrator`]).
pub fn method_of(s: &IntegratorSettings, time_scale: f64) -> Method {
    use crate::scene::Method as M;
    match s.method {
        M::Auto => Method::Radau5 { rtol: s.rtol, atol: s.atol },
        M::Rk4 => Method::Rk4 { dt: s.dt / time_scale },
        M::Dopri5 => Method::Dopri5 { rtol: s.rtol, atol: s.atol },
        M::Dop853 => Method::Dop853 { rtol: s.rtol, atol: s.atol },
        M::Radau5 => Method::Radau5 { rtol: s.rtol, atol: s.atol },
        M::Rosenbrock23 => Method::Rosenbrock23 { rtol: s.rtol, atol: s.atol },
    }
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
        self.run_rows(run, &mut |row| observer(row.t, row.si))
    }

    /// [`run`](Self::run) handing each output [`Row`] with the full state too (the echo needs
    /// the velocities, which the output row does not hold).
    pub fn run_rows(&self, run: &Run, observer: &mut dyn FnMut(&Row<'_>)) -> RunReport {
        let t_end = run.duration / self.time_scale();
        let (method, choice) = self.choose_integrator(&run.integrator);
        let st = stepper(self.system(), &method, 0.0, self.initial_state(), t_end);
        let mut report = self.execute_run(run, st, observer);
        report.integrator = Some(choice);
        report
    }

    /// [`run_rows`](Self::run_rows) on a given stepper, already at (0, the initial state), in
    /// place of the scene's integrator (an order study with fixed steps): the same run
    /// executor, stop times, events and rows; `run.integrator` only gives `max_steps`.
    pub fn run_stepper(&self, run: &Run, st: Box<dyn Stepper + '_>, observer: &mut dyn FnMut(&Row<'_>)) -> RunReport {
        self.execute_run(run, Ok(st), observer)
    }

    fn execute_run(&self, run: &Run, st: Result<Box<dyn Stepper + '_>, IntegrateError>, observer: &mut dyn FnMut(&Row<'_>)) -> RunReport {
        let start = Instant::now();
        let ts = self.time_scale();
        let sys = self.system();
        let layout: Vec<usize> = (0..sys.dim()).collect();
        let plan = Plan {
            sys,
            t_end: run.duration / ts,
            sample: run.sample_interval / ts,
            max_steps: run.integrator.max_steps,
            land_on_samples: false,
            layout: &layout,
            component_mode: &|c| self.component_mode(c),
        };
        let out = execute(self, &plan, st, observer);
        self.report(out, start, self.active_effects(), sys.dim())
    }

    /// The report of an executed run.
    pub(crate) fn report(&self, out: super::executor::Outcome, start: Instant, active_effects: Vec<String>, dim: usize) -> RunReport {
        let names = self.state_names();
        RunReport {
            status: out.status,
            t_end: out.t_last,
            stats: out.stats,
            wall_seconds: start.elapsed().as_secs_f64(),
            max_abs: names.iter().cloned().zip(out.max_abs).collect(),
            final_state: names.iter().cloned().zip(out.row).collect(),
            active_effects,
            state_dimension: dim,
            groups: self.groups(),
            integrator: None,
            shell_branches: out.branches,
        }
    }
}
