//! The one-step-at-a-time interface [`Stepper`], the constructor [`stepper`] of a [`Method`],
//! and [`solve`] / [`drive`]: the run loop ([`super::run_loop`]) with sampling and a budget only.

use super::explicit::{ExplicitRk, Rk4};
use super::radau::Radau5;
use super::rosenbrock::Rosenbrock23;
use super::tableau::ButcherTableau;
use super::run_loop::{run, Schedule, StopReason};
use super::{Control, IntegrateError, Method, OdeSystem, Output, Solution, Stats};

/// A stepper owns its state (t, y), advances it one accepted step at a time and interpolates
/// inside the last step. Obtain one with [`stepper`]; the driver [`solve`] is built on it.
pub trait Stepper {
    /// Current time (end of the last accepted step).
    fn t(&self) -> f64;
    /// Current state.
    fn y(&self) -> &[f64];
    /// Start of the last accepted step (= `t()` before the first step).
    fn t_prev(&self) -> f64;
    /// Cost so far.
    fn stats(&self) -> Stats;
    /// Takes one accepted step (retrying internally after rejections), never beyond `t_stop`;
    /// the step lands exactly on `t_stop` when it reaches it.
    fn step(&mut self, sys: &dyn OdeSystem, t_stop: f64) -> Result<(), IntegrateError>;
    /// Restarts at (t, y) as a new stepper would start there (the run loop's stop times and
    /// events): f(t, y) re-evaluated (a first-same-as-last stage discarded), a fresh initial step
    /// bounded by `t_end` and a fresh error history, no extrapolated starting values; the
    /// statistics carry on. The dense output is empty until the next step.
    fn restart(&mut self, sys: &dyn OdeSystem, t: f64, y: &[f64], t_end: f64) -> Result<(), IntegrateError>;
    /// Readies the dense output of the last step when it needs more evaluations of f (DOP853's
    /// three extra stages); the run loop calls it before interpolating inside a step. Default:
    /// nothing to do.
    fn prepare_dense(&mut self, _sys: &dyn OdeSystem) {}
    /// Dense output: y(t) for t in [t_prev(), t()] into `out`: each method's own — RK4: the cubic
    /// Hermite from y and f at both ends (error O(h⁴), the order of RK4's global error);
    /// Dopri5: its 4th-order continuous extension; Dop853: its 7th-order one (after
    /// [`prepare_dense`](Self::prepare_dense), else the cubic Hermite); Radau5: the collocation
    /// polynomial; Rosenbrock23: its 2nd-order continuous extension (ode23s).
    fn interpolate(&self, t: f64, out: &mut [f64]);
    /// Dense output of the components `idx` only: `out[j]` = y_{idx[j]}(t), the same values as
    /// [`interpolate`](Self::interpolate) gives them (a run writes 2 + 3M of the monolithic
    /// system's 2 + M(3 + n) components). The default interpolates all of them.
    fn interpolate_at(&self, t: f64, idx: &[usize], out: &mut [f64]) {
        let mut all = vec![0.0; self.y().len()];
        self.interpolate(t, &mut all);
        for (o, &i) in out.iter_mut().zip(idx) {
            *o = all[i];
        }
    }
}

/// Builds the stepper of `method` at (t0, y0). `t_end` bounds the initial step of the adaptive
/// methods. Evaluates f(t0, y0) (and, adaptive methods, one more rhs for the initial step).
pub fn stepper<'a>(sys: &dyn OdeSystem, method: &Method, t0: f64, y0: &[f64], t_end: f64) -> Result<Box<dyn Stepper + 'a>, IntegrateError> {
    method.validate()?;
    if y0.len() != sys.dim() {
        return Err(IntegrateError::DimensionMismatch { expected: sys.dim(), got: y0.len() });
    }
    if !t0.is_finite() {
        return Err(IntegrateError::InvalidSetting { what: "t0", value: t0, reason: "must be finite" });
    }
    if !(t_end.is_finite() && t_end >= t0) {
        return Err(IntegrateError::InvalidSetting { what: "t_end", value: t_end, reason: "must be finite and not before t0" });
    }
    Ok(match *method {
        Method::Rk4 { dt } => Box::new(Rk4::new(sys, t0, y0, dt)?),
        Method::Dopri5 { rtol, atol } => Box::new(ExplicitRk::new(sys, ButcherTableau::dopri5(), t0, y0, t_end, rtol, atol)?),
        Method::Dop853 { rtol, atol } => Box::new(ExplicitRk::new(sys, ButcherTableau::dop853(), t0, y0, t_end, rtol, atol)?),
        Method::Radau5 { rtol, atol } => Box::new(Radau5::new(sys, t0, y0, t_end, rtol, atol)?),
        Method::Rosenbrock23 { rtol, atol } => Box::new(Rosenbrock23::new(sys, t0, y0, t_end, rtol, atol)?),
    })
}

/// Integrates y' = f(t, y) from (t0, y0) to t_end.
///
/// The observer sees (t0, y0) first, then every accepted step ([`Output::Steps`]) or the
/// samples t0 + i·Δ < t_end obtained by dense output and finally t_end ([`Output::Every`]).
/// Returning [`Control::Stop`] ends the run with `stopped = true` at the time it was shown.
/// More than `max_steps` accepted steps is [`IntegrateError::MaxSteps`]. NaN/Inf in the state or
/// the rhs is [`IntegrateError::NonFinite`] (adaptive methods first retry smaller steps).
#[allow(clippy::too_many_arguments)]
pub fn solve(
    sys: &dyn OdeSystem,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    method: &Method,
    output: Output,
    max_steps: u64,
    observer: &mut dyn FnMut(f64, &[f64]) -> Control,
) -> Result<Solution, IntegrateError> {
    // `drive` validates the output interval.
    let mut st = stepper(sys, method, t0, y0, t_end)?;
    drive(&mut *st, sys, t_end, output, max_steps, observer)
}

/// [`solve`] with a stepper built elsewhere (e.g. a scheme outside this module), from its
/// current (t, y): [`run_loop::run`](super::run_loop::run) without stop times or events. On an
/// error, the stepper keeps its statistics.
pub fn drive(
    st: &mut dyn Stepper,
    sys: &dyn OdeSystem,
    t_end: f64,
    output: Output,
    max_steps: u64,
    observer: &mut dyn FnMut(f64, &[f64]) -> Control,
) -> Result<Solution, IntegrateError> {
    let fin = run(st, sys, Schedule::new(t_end, output, max_steps), observer)?;
    Ok(Solution { t: fin.t, y: fin.z, stats: st.stats(), stopped: fin.reason == StopReason::Observer })
}
