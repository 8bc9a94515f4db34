//! One solve of the model sampled at given times, with or without the sensitivity equations,
//! on the one run loop ([`crate::integrate::run_loop`]) with the model's stop times and events —
//! the stepper, the schedule and the steps of `run` itself, so the plain solve's rows at the
//! run's sample times are `run`'s rows bit for bit (sampling is dense output, never a step
//! constraint).

use super::sensitivities::ModelRates;
use crate::integrate::run_loop::{self, Event, Schedule, StopReason};
use crate::integrate::sensitivity::Sensitivity;
use crate::integrate::{stepper, Control, IntegrateError, OdeSystem, Output, Stats};
use crate::model::{layout::StateLayout, Failure, Model, RunStatus};

/// The model at the requested times.
#[derive(Debug, Clone)]
pub struct Curve {
    /// Per reached time: the output row (R, a2, b2, …) [m].
    pub rows: Vec<Vec<f64>>,
    /// Per reached time: its time derivative [m/s] (the time offset's column of the Jacobian).
    pub rates: Vec<Vec<f64>>,
    /// Per reached time, per parameter θ_j: ∂row/∂θ_j [m] (empty without sensitivities).
    pub sens: Vec<Vec<Vec<f64>>>,
    pub status: RunStatus,
    pub stats: Stats,
}

impl Curve {
    /// Times reached (all of them unless the run stopped early).
    pub fn reached(&self) -> usize {
        self.rows.len()
    }
}

/// The model-unit time of a run time [s]: snapped to `run`'s sample grid i·Δ (and to t_end) when
/// within 1e-9 Δ of it, so a datum taken at a sample of `run` is compared with that very row.
pub fn model_time(t: f64, model: &Model, run: &crate::scene::Run) -> f64 {
    let ts = model.time_scale();
    let d = run.sample_interval / ts;
    let t_end = run.duration / ts;
    let s = t / ts;
    let k = (s / d).round();
    let snapped = if (s - k * d).abs() <= 1e-9 * d { 0.0 + k * d } else { s };
    if snapped >= t_end - 1e-9 * d {
        t_end
    } else {
        snapped.max(0.0)
    }
}

/// Solves `model` under the run settings `run`, sampled at `times` (model units, nondecreasing,
/// inside [0, t_end]); with `rates`, the sensitivities too.
pub fn solve(model: &Model, run: &crate::scene::Run, times: &[f64], rates: Option<&ModelRates>) -> Curve {
    let ts = model.time_scale();
    let t_end = run.duration / ts;
    let (method, _) = model.choose_integrator(&run.integrator);
    let base = model.system();
    let n = base.dim();
    let sens = rates.map(|r| Sensitivity::new(base, r));
    let sys: &dyn OdeSystem = match &sens {
        Some(s) => s,
        None => base,
    };
    let y0 = match (&sens, rates) {
        (Some(s), Some(r)) => s.initial_state(model.initial_state(), &r.s0),
        _ => model.initial_state().to_vec(),
    };
    let p = rates.map_or(0, |r| r.s0.len());
    let mut interior: Vec<f64> = times.iter().copied().filter(|&s| s > 0.0 && s < t_end).collect();
    interior.dedup();
    // the executor's session: the drive's pieces and the kinked law's branches, so the fit
    // integrates what `run` integrates
    let session = crate::model::RunSession::begin(model, 0.0, &y0[..n], t_end);
    let stop_times = session.stop_times().to_vec();
    let mut next_piece = |t: f64, _y: &mut [f64]| session.on_stop_time(t);
    let events = model.events();
    let events: Vec<&dyn Event> = events.iter().map(|e| &**e).collect();
    let width = model.state_names().len();
    let lay = StateLayout::reduced(model.orders().len());
    let mut curve = Curve { rows: Vec::new(), rates: Vec::new(), sens: Vec::new(), status: RunStatus::Completed, stats: Stats::default() };
    let mut st = match stepper(sys, &method, 0.0, &y0, t_end) {
        Ok(st) => st,
        Err(e) => {
            curve.status = status_of(&e, ts);
            return curve;
        }
    };
    let schedule = Schedule {
        t_end,
        output: Output::Every(run.sample_interval / ts),
        max_steps: run.integrator.max_steps,
        stop_times: &stop_times,
        on_stop_time: Some(&mut next_piece),
        events: &events,
        observed: None,
        sample_times: Some(&interior),
    };
    let (mut f, mut zf) = (vec![0.0; n], vec![0.0; n]);
    let mut next = 0usize;
    let result = run_loop::run(&mut *st, sys, schedule, &mut |t: f64, z: &[f64]| {
        while next < times.len() && times[next] == t {
            let mut row = vec![0.0; width];
            model.to_si_into(&z[..n], &mut row);
            // the rates of R, a, b: Ṙ, ȧ from the state, ḃ from the rhs
            base.rhs(t, &z[..n], &mut f);
            zf.copy_from_slice(&f);
            zf[lay.r()] = z[lay.rdot()];
            for m in 0..lay.modes() {
                zf[lay.a(m)] = z[lay.adot(m)];
            }
            let mut rate = vec![0.0; width];
            model.to_si_into(&zf, &mut rate);
            rate.iter_mut().for_each(|v| *v /= ts);
            let s_rows: Vec<Vec<f64>> = (0..p)
                .map(|j| {
                    let mut r = vec![0.0; width];
                    model.to_si_into(&z[n * (1 + j)..n * (2 + j)], &mut r);
                    r
                })
                .collect();
            curve.rows.push(row);
            curve.rates.push(rate);
            curve.sens.push(s_rows);
            next += 1;
        }
        Control::Continue
    });
    curve.status = match result {
        Ok(fin) => match fin.reason {
            StopReason::End | StopReason::Observer => RunStatus::Completed,
            StopReason::Event { .. } => model.stop_status(fin.t * ts, &fin.z[..n]),
        },
        Err(e) => status_of(&e, ts),
    };
    session.finish(st.t());
    curve.stats = st.stats();
    curve
}

fn status_of(e: &IntegrateError, ts: f64) -> RunStatus {
    match *e {
        IntegrateError::NonFinite { t, component } => RunStatus::BlowUp { t: t * ts, mode: format!("non-finite state (component {component})") },
        _ => RunStatus::Failed { reason: Failure::from_integrate(e, ts) },
    }
}
