//! The one run executor of every scheme (boundary layer, radial only, monolithic and staggered
//! full model): sampling, the step budget, blow-up located by an event function on the dense
//! output, typed stop reasons and the statistics of the stepper, on success and on failure.
//!
//! Sampling: rows at t0 + i·Δ (dense output, not a step constraint, unless the stepper asks to
//! land on them) and at t_end. Blow-up: after every accepted step the event function
//! g = [`super::blow_up::margin`] is evaluated at the samples inside the step and at its end;
//! at the first point with g > 0 the crossing g = 0 is bracketed with the previous point and
//! bisected on the stepper's interpolant to 1e-13 relative, so the reported time does not
//! depend on `run.sample_interval`. The last row is the state at the crossing.

use super::simulate::{Failure, RunStatus};
use super::Model;
use crate::integrate::{IntegrateError, OdeSystem, Stats, Stepper};

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
}

struct Rows<'a> {
    model: &'a Model,
    observer: &'a mut dyn FnMut(f64, &[f64]),
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
        (self.observer)(t * ts, &self.row);
    }
}

/// Runs `stepper` (already at t0 with y0) under `plan`; `observer(t [s], row [m])` gets every row.
pub(crate) fn execute(
    model: &Model,
    plan: &Plan<'_>,
    stepper: Result<Box<dyn Stepper + '_>, IntegrateError>,
    observer: &mut dyn FnMut(f64, &[f64]),
) -> Outcome {
    let ts = model.time_scale();
    let width = model.state_names().len();
    let mut rows = Rows { model, observer, row: vec![0.0; width], max_abs: vec![0.0; width], t_last: 0.0 };
    let outcome = |rows: Rows<'_>, status: RunStatus, stats: Stats| Outcome {
        status,
        stats,
        t_last: rows.t_last,
        max_abs: rows.max_abs,
        row: rows.row,
    };
    let mut st = match stepper {
        Ok(st) => st,
        Err(e) => {
            let status = failure_status(&e, ts, plan);
            return outcome(rows, status, Stats::default());
        }
    };
    let nz = 2 + 3 * model.orders().len();
    debug_assert_eq!(plan.layout.len(), nz, "layout of z");
    let mut z = vec![0.0; nz];
    // the layout is the whole state (the boundary-layer system): the stepper's contiguous dense
    // output, the same values as `interpolate_at` gives (its contract)
    let whole = plan.layout.len() == st.y().len() && plan.layout.iter().enumerate().all(|(j, &i)| i == j);
    let t0 = st.t();
    gather(st.y(), plan.layout, &mut z);
    rows.emit(t0, &z);
    if model.blow_up_margin(&z) > 0.0 {
        let status = model.stop_status(t0 * ts, &z);
        let stats = st.stats();
        return outcome(rows, status, stats);
    }
    let d = plan.sample;
    let mut sample: u64 = 1;
    while st.t() < plan.t_end {
        if st.stats().steps >= plan.max_steps {
            let status = RunStatus::Failed { reason: Failure::StepLimit { t: st.t() * ts, steps: st.stats().steps } };
            let stats = st.stats();
            return outcome(rows, status, stats);
        }
        let next = t0 + sample as f64 * d;
        let t_stop = if plan.land_on_samples && next < plan.t_end - 1e-9 * d { next } else { plan.t_end };
        if let Err(e) = st.step(plan.sys, t_stop) {
            let status = failure_status(&e, ts, plan);
            let stats = st.stats();
            return outcome(rows, status, stats);
        }
        // The points of this step in time order: samples (emitted), then the step end (checked).
        let mut t_left = st.t_prev();
        loop {
            let ts_i = t0 + sample as f64 * d;
            let is_sample = ts_i <= st.t() && ts_i < plan.t_end - 1e-9 * d;
            let (t_pt, at_end) = if is_sample { (ts_i, ts_i == st.t()) } else { (st.t(), true) };
            if at_end {
                gather(st.y(), plan.layout, &mut z);
            } else if whole {
                st.interpolate(t_pt, &mut z);
            } else {
                st.interpolate_at(t_pt, plan.layout, &mut z);
            }
            if model.blow_up_margin(&z) > 0.0 {
                let t_b = locate_crossing(model, plan, &*st, t_left, t_pt, &mut z);
                let status = model.stop_status(t_b * ts, &z);
                rows.emit(t_b, &z);
                let stats = st.stats();
                return outcome(rows, status, stats);
            }
            if !is_sample {
                if st.t() >= plan.t_end {
                    rows.emit(plan.t_end, &z);
                }
                break;
            }
            rows.emit(t_pt, &z);
            sample += 1;
            t_left = t_pt;
        }
    }
    let stats = st.stats();
    outcome(rows, RunStatus::Completed, stats)
}

/// Bisects g(t) = margin(z(t)) = 0 on the stepper's interpolant in [lo, hi] (g(lo) ≤ 0 < g(hi));
/// returns the upper end (g > 0 there), its layout left in `z`.
fn locate_crossing(model: &Model, plan: &Plan<'_>, st: &dyn Stepper, mut lo: f64, mut hi: f64, z: &mut [f64]) -> f64 {
    let tol = 1e-13 * hi.abs().max(plan.t_end);
    while hi - lo > tol {
        let mid = 0.5 * (lo + hi);
        st.interpolate_at(mid, plan.layout, z);
        if model.blow_up_margin(z) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    if hi == st.t() {
        gather(st.y(), plan.layout, z);
    } else {
        st.interpolate_at(hi, plan.layout, z);
    }
    hi
}

/// z_j = y_{layout[j]}.
fn gather(y: &[f64], layout: &[usize], z: &mut [f64]) {
    for (zj, &i) in z.iter_mut().zip(layout) {
        *zj = y[i];
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
