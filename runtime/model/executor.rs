//! The run executor of every scheme (boundary layer, radial only, monolithic and staggered full
//! model): the model's run on the one run loop ([`crate::integrate::run_loop`]) — rows in SI
//! units, their running maxima, typed statuses and the statistics of the stepper, on success
//! and on failure.
//!
//! Stop times: the drive's pieces ([`Model::enter_piece`]): p_a is evaluated on the piece being
//! integrated ([t0, first stop], then from each stop time to the next or t_end), so a step
//! landing on an edge keeps its side.
//!
//! Sampling: rows at t0 + i·Δ (dense output, not a step constraint, unless the stepper asks to
//! land on them) and at t_end. Stop times and events are the model's ([`Model::stop_times`],
//! [`Model::events`]): by default the blow-up threshold alone, located on the dense output to
//! the last representable time, so the reported time does not depend on `run.sample_interval`
//! ([`crate::integrate::run_loop::locate`]); the last row
//! is the state at the crossing.

use super::simulate::{Failure, RunStatus};
use super::layout::StateLayout;
use super::Model;
use crate::integrate::run_loop::{run, Event, Schedule, StopReason};
use crate::integrate::{Control, IntegrateError, OdeSystem, Output, Stats, Stepper};

/// A run to execute (nondimensional times).
pub(crate) struct Plan<'a> {
    pub sys: &'a dyn OdeSystem,
    pub t_end: f64,
    pub sample: f64,
    pub max_steps: u64,
    /// Step to every sample time (the staggered scheme: its interpolant is only linear).
    pub land_on_samples: bool,
    /// The boundary-layer layout z = [R, Ṙ, (a, ȧ, b)_k] of a state: z_j = y_{layout[j]} (only
    /// these components are interpolated at the samples).
    pub layout: &'a [usize],
    /// The mode a state component belongs to (for a non-finite state).
    pub component_mode: &'a dyn Fn(usize) -> String,
}

/// What [`execute`] found (SI times).
pub(crate) struct Outcome {
    pub status: RunStatus,
    pub stats: Stats,
    /// Time of the last row [s].
    pub t_last: f64,
    pub max_abs: Vec<f64>,
    /// The last row (R, a2, b2, …) [m].
    pub row: Vec<f64>,
    /// The fractions of time on each branch of a kinked Marmottant law (issue 31).
    pub branches: Option<super::events::BranchFractions>,
}

/// One output row of a run: the time [s], the row in SI units (R, a2, b2, … [m]) and the full
/// state in the boundary-layer layout z = [R, Ṙ, (a, ȧ, b)_k] (model units).
pub struct Row<'a> {
    pub t: f64,
    pub si: &'a [f64],
    pub z: &'a [f64],
}

struct Rows<'a> {
    model: &'a Model,
    observer: &'a mut dyn FnMut(&Row<'_>),
    row: Vec<f64>,
    max_abs: Vec<f64>,
    t_last: f64,
}

impl Rows<'_> {
    fn emit(&mut self, t: f64, z: &[f64]) {
        let ts = self.model.time_scale();
        self.model.to_si_into(z, &mut self.row);
        for (m, v) in self.max_abs.iter_mut().zip(&self.row) {
            // `f64::max` without its NaN branch: a NaN |v| leaves m, as `max` does
            if v.abs() > *m {
                *m = v.abs();
            }
        }
        self.t_last = t * ts;
        (self.observer)(&Row { t: t * ts, si: &self.row, z });
    }

    fn outcome(self, status: RunStatus, stats: Stats) -> Outcome {
        Outcome { status, stats, t_last: self.t_last, max_abs: self.max_abs, row: self.row, branches: None }
    }
}

/// Runs `stepper` (already at t0 with y0) under `plan`; `observer` gets every [`Row`].
pub(crate) fn execute(
    model: &Model,
    plan: &Plan<'_>,
    stepper: Result<Box<dyn Stepper + '_>, IntegrateError>,
    observer: &mut dyn FnMut(&Row<'_>),
) -> Outcome {
    let ts = model.time_scale();
    let width = model.state_names().len();
    let mut rows = Rows { model, observer, row: vec![0.0; width], max_abs: vec![0.0; width], t_last: 0.0 };
    let mut st = match stepper {
        Ok(st) => st,
        Err(e) => {
            let status = failure_status(&e, ts, plan);
            return rows.outcome(status, Stats::default());
        }
    };
    debug_assert_eq!(plan.layout.len(), StateLayout::reduced(model.orders().len()).dim(), "layout of z");
    let t0 = st.t();
    let z0: Vec<f64> = plan.layout.iter().map(|&i| st.y()[i]).collect();
    let session = RunSession::begin(model, t0, &z0, plan.t_end);
    let stop_times = session.stop_times().to_vec();
    let mut next_piece = |t: f64, _y: &mut [f64]| session.on_stop_time(t);
    let events = model.events();
    let events: Vec<&dyn Event> = events.iter().map(|e| &**e).collect();
    let schedule = Schedule {
        t_end: plan.t_end,
        output: if plan.land_on_samples { Output::Landing(plan.sample) } else { Output::Every(plan.sample) },
        max_steps: plan.max_steps,
        stop_times: &stop_times,
        on_stop_time: Some(&mut next_piece),
        events: &events,
        observed: Some(plan.layout),
        sample_times: None,
    };
    let result = run(&mut *st, plan.sys, schedule, &mut |t, z| {
        rows.emit(t, z);
        Control::Continue
    });
    let t_fin = result.as_ref().map_or(st.t(), |f| f.t);
    let branches = session.finish(t_fin);
    let status = match result {
        Ok(fin) => match fin.reason {
            StopReason::End | StopReason::Observer => RunStatus::Completed,
            StopReason::Event { .. } => {
                // the row at t0 is already out; a crossing inside the run is the last row
                if fin.t > t0 {
                    rows.emit(fin.t, &fin.z);
                }
                model.stop_status(fin.t * ts, &fin.z)
            }
        },
        Err(e) => failure_status(&e, ts, plan),
    };
    Outcome { branches, ..rows.outcome(status, st.stats()) }
}

/// What a run of the model on the run loop sets up and tears down — the scene executor's and the
/// fit's solves alike, so both integrate the same equations: the drive's piece (p_a evaluated on
/// the piece being integrated, from t0 and then from each stop time on, cleared when the run
/// ends however it ends, also by an unwind) and the kinked law's branch state and clock
/// ([`Model::start_branches`]).
pub(crate) struct RunSession<'m> {
    model: &'m Model,
    stop_times: Vec<f64>,
    t_end: f64,
}

impl<'m> RunSession<'m> {
    /// Starts a run at t0 from z0 (nondimensional, R first) that ends at t_end.
    pub(crate) fn begin(model: &'m Model, t0: f64, z0: &[f64], t_end: f64) -> Self {
        model.start_branches(t0, z0);
        let session = RunSession { model, stop_times: model.stop_times(), t_end };
        if !session.stop_times.is_empty() {
            model.enter_piece(Some((t0, session.piece_to(t0))));
        }
        session
    }

    /// The drive's stop times (the run loop's `Schedule::stop_times`).
    pub(crate) fn stop_times(&self) -> &[f64] {
        &self.stop_times
    }

    /// The run loop's `on_stop_time`: the piece from t on.
    pub(crate) fn on_stop_time(&self, t: f64) {
        self.model.enter_piece(Some((t, self.piece_to(t))));
    }

    fn piece_to(&self, t: f64) -> f64 {
        self.stop_times.iter().copied().find(|&s| s > t).unwrap_or(self.t_end)
    }

    /// Ends the run at t: the fractions of time on each branch of a kinked law.
    pub(crate) fn finish(&self, t: f64) -> Option<super::events::BranchFractions> {
        self.model.finish_branches(t)
    }
}

impl Drop for RunSession<'_> {
    fn drop(&mut self) {
        if !self.stop_times.is_empty() {
            self.model.enter_piece(None);
        }
    }
}

/// A failed step: a non-finite state is a blow-up (a result, FORMULATION §5), the rest are
/// failures with their time in seconds.
fn failure_status(e: &IntegrateError, ts: f64, plan: &Plan<'_>) -> RunStatus {
    match *e {
        IntegrateError::NonFinite { t, component } => RunStatus::BlowUp { t: t * ts, mode: (plan.component_mode)(component) },
        _ => RunStatus::Failed { reason: Failure::from_integrate(e, ts) },
    }
}
