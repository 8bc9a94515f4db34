//! The one integration loop: every stepper ([`super::Rk4`], [`super::ExplicitRk`] for Dopri5 and
//! Dop853, [`super::Radau5`], [`super::Rosenbrock23`], the staggered vorticity scheme) runs
//! inside [`run`]. The loop owns
//!
//! - the **step budget** (`max_steps` accepted steps, then [`IntegrateError::MaxSteps`]);
//! - **sampling** ([`Output`]): every step, or uniform times t0 + i·Δ from the stepper's dense
//!   output (not a step constraint), or uniform times the stepper lands on;
//! - the **observer**, called at every sample with the observed components, which may stop the
//!   run ([`Control::Stop`] → [`StopReason::Observer`]);
//! - **stop times** ([`Schedule::stop_times`]): known discontinuity times (a burst's start and
//!   end, a measured waveform's knots). No step crosses one: the step lands exactly on it, the
//!   optional [`Schedule::on_stop_time`] callback updates the state and the model's branch, and
//!   the stepper restarts there ([`super::Stepper::restart`]: f re-evaluated, FSAL stage
//!   discarded, a fresh initial step and error history, Radau's extrapolated starting values
//!   dropped), so each piece between two stop times is integrated as a smooth problem (Hairer,
//!   Nørsett & Wanner, *Solving ODEs I*, sec. II.6, "discontinuities");
//! - **event functions** ([`Event`]): state-dependent switches g(t, z). g is evaluated at every
//!   sample inside a step and at the step's end; where it crosses zero in the event's
//!   [`Direction`] the crossing is bisected on the stepper's dense output to the last
//!   representable time ([`locate`]), and the event either stops the run ([`Action::Stop`] →
//!   [`StopReason::Event`]) or restarts the stepper at the crossing ([`Action::Restart`], after
//!   [`Event::update`]). An event that knows its rate ([`Event::rate`]) is also checked at an
//!   extremum of g between two checked points ([`hidden_crossing`]): a pair of crossings inside
//!   one step is not stepped over;
//! - typed stop reasons ([`StopReason`]) and errors ([`IntegrateError`], each with its time).
//!
//! **Branches at an edge.** A step that lands on a stop time evaluates its last stage *at* that
//! time, and the first stage of the next step too. A term that switches there must therefore
//! take its branch from the state of the run (set by `on_stop_time` / [`Event::update`]), not
//! by comparing t with the edge — otherwise one of the two steps sees the wrong branch in one
//! stage and the order collapses to 1 (tests/suite/run_loop.rs shows it). The scene executor
//! does this for the drive (`Model::enter_piece` from `on_stop_time`; tests/suite/drive_edges.rs).
//!
//! **Variational equations** ([`super::Variational`]) are part of the state: a stop time or a
//! Restart event without a state jump leaves the fundamental matrix continuous (for a stop time
//! g = t − s, ∇_y g = 0: no saltation term). A state-dependent switch of the right-hand side
//! needs the saltation matrix applied in [`Event::update`]
//! (Φ⁺ = (I + (f⁺ − f⁻) ∇gᵀ / (∇g · f⁻)) Φ⁻), which only the model knows.

use super::{Control, IntegrateError, OdeSystem, Output, Stepper};

/// Which zero crossings of g an [`Event`] reacts to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// g from ≤ 0 to > 0.
    Rising,
    /// g from ≥ 0 to < 0.
    Falling,
    /// Either.
    Either,
}

impl Direction {
    /// Whether g went through zero in this direction from `before` to `now`.
    pub fn crossed(self, before: f64, now: f64) -> bool {
        // `!(before > 0)`: a NaN before counts as not crossed yet
        let rise = !(before > 0.0) && now > 0.0;
        let fall = !(before < 0.0) && now < 0.0;
        match self {
            Direction::Rising => rise,
            Direction::Falling => fall,
            Direction::Either => rise || fall,
        }
    }
}

/// What the loop does at a located event.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// End the run at the crossing ([`StopReason::Event`]).
    Stop,
    /// Call [`Event::update`] at the crossing and restart the stepper there.
    Restart,
}

/// A state-dependent switch g(t, z) = 0, z the observed components of the state
/// ([`Schedule::observed`]).
pub trait Event {
    /// The switching function.
    fn g(&self, t: f64, z: &[f64]) -> f64;
    fn direction(&self) -> Direction {
        Direction::Rising
    }
    fn action(&self) -> Action {
        Action::Stop
    }
    /// `true`: a g already on the crossed side at t0 (g > 0 for [`Direction::Rising`], < 0 for
    /// Falling) fires at t0 (a threshold the start may already exceed, e.g. blow-up).
    fn fires_at_start(&self) -> bool {
        false
    }
    /// For [`Action::Restart`]: updates the full state `y` at the crossing time `t` (and, with
    /// interior mutability, the model's branch) before the stepper restarts.
    fn update(&self, _t: f64, _y: &mut [f64]) {}
    /// dg/dt at (t, z), when the event knows it from the observed components (g = R − R_b:
    /// Ṙ). With it the loop also sees a *pair* of crossings between two checked points — g on
    /// the same side at both, an extremum of g between them on the other side
    /// ([`hidden_crossing`]) — which a sign test at the points steps over. `None`: only sign
    /// changes at the checked points are seen.
    fn rate(&self, _t: f64, _z: &[f64]) -> Option<f64> {
        None
    }
}

/// Why [`run`] ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StopReason {
    /// t_end reached.
    End,
    /// The observer returned [`Control::Stop`].
    Observer,
    /// Event `index` of [`Schedule::events`] with [`Action::Stop`] fired.
    Event { index: usize },
}

/// The end of a [`run`]: time, reason and the observed components there (the full state when
/// [`Schedule::observed`] is `None`).
#[derive(Debug, Clone)]
pub struct Finish {
    pub t: f64,
    pub reason: StopReason,
    pub z: Vec<f64>,
}

/// What [`run`] does besides stepping: end time, sampling, budget, stop times and events.
pub struct Schedule<'a> {
    pub t_end: f64,
    pub output: Output,
    pub max_steps: u64,
    /// Known discontinuity times, sorted ascending; those outside (t0, t_end) are ignored.
    pub stop_times: &'a [f64],
    /// Called when a step has landed on a stop time (after the samples and events there) with
    /// (t, y); may change y (and the model's branch) before the stepper restarts.
    pub on_stop_time: Option<&'a mut dyn FnMut(f64, &mut [f64])>,
    pub events: &'a [&'a dyn Event],
    /// The state components the observer and the events see (`None`: all, in order).
    pub observed: Option<&'a [usize]>,
    /// Explicit sample times, sorted ascending, strictly inside (t0, t_end), replacing the
    /// uniform grid of `Output::Every` (dense output, not a step constraint; the fit samples the
    /// model at the data's times). The observer still sees t0 and t_end. `None`: the grid.
    pub sample_times: Option<&'a [f64]>,
}

impl<'a> Schedule<'a> {
    /// Sampling and budget only: no stop times, no events, the whole state observed.
    pub fn new(t_end: f64, output: Output, max_steps: u64) -> Self {
        Schedule { t_end, output, max_steps, stop_times: &[], on_stop_time: None, events: &[], observed: None, sample_times: None }
    }
}

/// The components the observer and the events see.
#[derive(Clone, Copy)]
struct View<'a> {
    idx: Option<&'a [usize]>,
    /// `idx` is every component in order: the contiguous dense output serves the samples.
    whole: bool,
}

impl View<'_> {
    /// The observed components at `t` into `z`: the state itself at the step end, otherwise the
    /// dense output.
    fn at(&self, st: &dyn Stepper, t: f64, z: &mut [f64]) {
        if t == st.t() {
            let y = st.y();
            match self.idx {
                Some(idx) => z.iter_mut().zip(idx).for_each(|(zj, &i)| *zj = y[i]),
                None => z.copy_from_slice(y),
            }
        } else {
            match self.idx {
                Some(idx) if !self.whole => st.interpolate_at(t, idx, z),
                _ => st.interpolate(t, z),
            }
        }
    }

    /// As [`at`](Self::at), through [`Stepper::interpolate_at`] whenever components are selected
    /// (the bisection of an event).
    fn dense(&self, st: &dyn Stepper, t: f64, z: &mut [f64]) {
        match self.idx {
            Some(idx) if t != st.t() => st.interpolate_at(t, idx, z),
            _ => self.at(st, t, z),
        }
    }
}

/// Runs `st` (at its current (t0, y0)) under `schedule`. The observer sees (t0, z0) first, then
/// the samples of [`Output`] (with `Output::Every`, also t_end). Errors leave the stepper with
/// its statistics.
pub fn run(
    st: &mut dyn Stepper,
    sys: &dyn OdeSystem,
    mut schedule: Schedule<'_>,
    observer: &mut dyn FnMut(f64, &[f64]) -> Control,
) -> Result<Finish, IntegrateError> {
    let t_end = schedule.t_end;
    if let Output::Every(d) | Output::Landing(d) = schedule.output {
        if !(d > 0.0 && d.is_finite()) {
            return Err(IntegrateError::InvalidSetting { what: "output interval", value: d, reason: "must be positive and finite" });
        }
    }
    if let Some(&s) = schedule.stop_times.iter().find(|s| !s.is_finite()) {
        return Err(IntegrateError::InvalidSetting { what: "stop time", value: s, reason: "must be finite" });
    }
    if let Some(w) = schedule.stop_times.windows(2).find(|w| w[1] < w[0]) {
        return Err(IntegrateError::InvalidSetting { what: "stop time", value: w[1], reason: "stop times must be sorted ascending" });
    }
    let n = st.y().len();
    let view = View {
        idx: schedule.observed,
        whole: schedule.observed.is_some_and(|o| o.len() == n && o.iter().enumerate().all(|(j, &i)| i == j)),
    };
    let t0 = st.t();
    let mut z = vec![0.0; schedule.observed.map_or(n, |o| o.len())];
    // the observed components at the probes of a search that must leave z as it is
    let mut scratch = z.clone();
    view.at(st, t0, &mut z);
    let finish = |t: f64, reason: StopReason, z: &[f64]| Ok(Finish { t, reason, z: z.to_vec() });
    if observer(t0, &z) == Control::Stop {
        return finish(t0, StopReason::Observer, &z);
    }
    let events = schedule.events;
    // g at the last checked point and at the current one, per event
    let mut g_last: Vec<f64> = events.iter().map(|e| e.g(t0, &z)).collect();
    let mut g_now = g_last.clone();
    // dg/dt at the same points, for the events that know it
    let mut r_last: Vec<Option<f64>> = events.iter().map(|e| e.rate(t0, &z)).collect();
    let mut r_now = r_last.clone();
    for (i, e) in events.iter().enumerate() {
        if e.fires_at_start() && e.direction().crossed(0.0, g_last[i]) {
            return finish(t0, StopReason::Event { index: i }, &z);
        }
    }
    let mut stops = schedule.stop_times.iter().copied().filter(|&s| s > t0 && s < t_end).peekable();
    let mut full = Vec::new();
    let mut sample: u64 = 1;
    let d = match schedule.output {
        Output::Every(d) | Output::Landing(d) => d,
        Output::Steps => f64::INFINITY,
    };
    if let Some(times) = schedule.sample_times {
        if let Some(w) = times.windows(2).find(|w| !(w[1] > w[0])) {
            return Err(IntegrateError::InvalidSetting { what: "sample time", value: w[1], reason: "sample times must be increasing" });
        }
        if let Some(&s) = times.iter().find(|&&s| !(s > t0 && s < t_end)) {
            return Err(IntegrateError::InvalidSetting { what: "sample time", value: s, reason: "must lie strictly inside (t0, t_end)" });
        }
    }
    // the i-th sample (i ≥ 1) and the margin before t_end inside which no sample is taken
    let times = schedule.sample_times;
    let sample_at = |i: u64| match times {
        Some(v) => v.get(i as usize - 1).copied().unwrap_or(f64::INFINITY),
        None => t0 + i as f64 * d,
    };
    let margin = if times.is_some() { 0.0 } else { 1e-9 * d };
    while st.t() < t_end {
        if st.stats().steps >= schedule.max_steps {
            return Err(IntegrateError::MaxSteps { t: st.t(), steps: st.stats().steps });
        }
        while stops.next_if(|&s| s <= st.t()).is_some() {}
        let mut t_stop = t_end;
        if let Output::Landing(d) = schedule.output {
            let next = t0 + sample as f64 * d;
            if next < t_end - 1e-9 * d {
                t_stop = next;
            }
        }
        let stop_time = stops.peek().copied().filter(|&s| s <= t_stop);
        if let Some(s) = stop_time {
            t_stop = s;
        }
        st.step(sys, t_stop)?;
        let first_sample = sample_at(sample);
        if first_sample < st.t() && first_sample < t_end - margin {
            st.prepare_dense(sys);
        }
        // The points of this step in time order: the samples (emitted once the events are
        // checked there), then the step end.
        let mut t_left = st.t_prev();
        loop {
            let ts_i = sample_at(sample);
            let is_sample = ts_i <= st.t() && ts_i < t_end - margin;
            let t_pt = if is_sample { ts_i } else { st.t() };
            view.at(st, t_pt, &mut z);
            for ((g, r), e) in g_now.iter_mut().zip(r_now.iter_mut()).zip(events) {
                *g = e.g(t_pt, &z);
                *r = e.rate(t_pt, &z);
            }
            let mut crossed = events.iter().enumerate().any(|(i, e)| e.direction().crossed(g_last[i], g_now[i]));
            // a pair of crossings between the points (of an event whose sign test saw nothing,
            // also beside another event's crossing): the earliest extremum beyond zero becomes
            // the right end of the bracket (g of every event there)
            let turns = |i: usize| !events[i].direction().crossed(g_last[i], g_now[i]) && extremum_between(g_last[i], r_last[i], r_now[i]);
            let mut t_chk = t_pt;
            if (0..events.len()).any(turns) {
                st.prepare_dense(sys);
                let mut hidden = false;
                for i in (0..events.len()).filter(|&i| turns(i)) {
                    if let Some(te) = hidden_crossing(events[i], g_last[i], t_left, t_chk, &mut scratch, |t, z| view.dense(st, t, z)) {
                        t_chk = te;
                        hidden = true;
                    }
                }
                if hidden {
                    crossed = true;
                    view.dense(st, t_chk, &mut z);
                    for (g, e) in g_now.iter_mut().zip(events) {
                        *g = e.g(t_chk, &z);
                    }
                }
            }
            if crossed {
                st.prepare_dense(sys);
            }
            if let Some(ev) = crossed.then(|| first_event(st, &schedule, view, &g_last, &g_now, t_left, t_chk, &mut z)).flatten() {
                let e = events[ev.index];
                if e.action() == Action::Stop {
                    return finish(ev.t, StopReason::Event { index: ev.index }, &z);
                }
                full.resize(n, 0.0);
                if ev.t == st.t() {
                    full.copy_from_slice(st.y());
                } else {
                    st.interpolate(ev.t, &mut full);
                }
                e.update(ev.t, &mut full);
                st.restart(sys, ev.t, &full, t_end)?;
                view.at(st, ev.t, &mut z);
                for ((g, r), e) in g_last.iter_mut().zip(r_last.iter_mut()).zip(events) {
                    *g = e.g(ev.t, &z);
                    *r = e.rate(ev.t, &z);
                }
                break;
            }
            std::mem::swap(&mut g_last, &mut g_now);
            std::mem::swap(&mut r_last, &mut r_now);
            if !is_sample {
                let sampled = matches!(schedule.output, Output::Steps) || st.t() >= t_end;
                if sampled && observer(st.t(), &z) == Control::Stop {
                    return finish(st.t(), StopReason::Observer, &z);
                }
                if stop_time.is_some_and(|s| st.t() == s) {
                    full.clear();
                    full.extend_from_slice(st.y());
                    if let Some(cb) = schedule.on_stop_time.as_mut() {
                        cb(st.t(), &mut full);
                    }
                    st.restart(sys, st.t(), &full, t_end)?;
                }
                break;
            }
            sample += 1;
            if observer(t_pt, &z) == Control::Stop {
                return finish(t_pt, StopReason::Observer, &z);
            }
            t_left = t_pt;
        }
    }
    finish(st.t(), StopReason::End, &z)
}

/// The earliest event crossed between the checked points `t_left` (g = `g_last`) and `t_pt`
/// (g = `g_now`), located on the dense output ([`locate`]); `z` is left at the located time.
/// `None`: no event crossed (z unchanged).
#[allow(clippy::too_many_arguments)]
fn first_event(
    st: &dyn Stepper,
    schedule: &Schedule<'_>,
    view: View<'_>,
    g_last: &[f64],
    g_now: &[f64],
    t_left: f64,
    t_pt: f64,
    z: &mut [f64],
) -> Option<Located> {
    let mut found: Option<Located> = None;
    for (index, e) in schedule.events.iter().enumerate() {
        if !e.direction().crossed(g_last[index], g_now[index]) {
            continue;
        }
        // z as the search's scratch: it is set to the earliest crossing below
        let hi = locate(*e, g_last[index], t_left, t_pt, z, |t, z| view.dense(st, t, z));
        if found.as_ref().is_none_or(|f| hi < f.t) {
            found = Some(Located { index, t: hi });
        }
    }
    if let Some(f) = &found {
        view.dense(st, f.t, z);
    }
    found
}

/// The crossing of event `e` between `lo` (where g was `g_before`) and `hi` (crossed), narrowed
/// on the dense output `dense(t, z)` (the observed components at t into `z`) until no
/// floating-point time lies between the bracket's ends ([`narrow`]); returns the end on the
/// crossed side (`z` is left at some point of the search). Located to the last representable
/// time, the crossing is the same from any bracket around it: where the checked points of a step
/// fall (the output samples, the fit's data times) does not move it, so a run's trajectory does
/// not depend on its sampling (a bisection stopped at a tolerance ended within it at a
/// bracket-dependent time: the fit's solve and `run` differed by 1.2e-12 after a Marmottant
/// switch). The run loop's locator, also used by the fixed-step period map of the Floquet
/// analysis (`analysis::periodic`) on a kinked law.
pub fn locate(e: &dyn Event, g_before: f64, lo: f64, hi: f64, z: &mut [f64], mut dense: impl FnMut(f64, &mut [f64])) -> f64 {
    dense(hi, z);
    let g_hi = e.g(hi, z);
    let side = |t: f64, z: &mut [f64], dense: &mut dyn FnMut(f64, &mut [f64])| {
        dense(t, z);
        let g = e.g(t, z);
        (e.direction().crossed(g_before, g), g)
    };
    narrow(lo, hi, g_before, g_hi, |t| side(t, z, &mut dense)).1
}

/// Narrows [lo, hi] to two adjacent floats across the flip of `probe(t)`'s side (`false` at lo,
/// `true` at hi), using its value `v` to interpolate: Brent's method (the `zeroin` of Forsythe,
/// Malcolm & Moler 1977: inverse quadratic or secant steps, a bisection whenever they do not
/// shrink the bracket fast enough) on φ = ±|v| signed by the side, with tolerance 0 (steps of at
/// least 2ε|t|, so it ends within a few floats), then a bisection on the side to the last float.
/// Where the side flips once in the bracket this ends on the same pair of floats as a bisection
/// from the start, in about 10 probes instead of about 50 (unit test below).
pub fn narrow(lo: f64, hi: f64, v_lo: f64, v_hi: f64, mut probe: impl FnMut(f64) -> (bool, f64)) -> (f64, f64) {
    // φ: negative on lo's side, positive on hi's, |v| (never 0, never NaN) as its size
    let phi = |crossed: bool, v: f64| {
        let m = if v.is_finite() { v.abs().max(f64::MIN_POSITIVE) } else { f64::MAX };
        if crossed { m } else { -m }
    };
    let (mut a, mut fa) = (lo, phi(false, v_lo));
    let (mut b, mut fb) = (hi, phi(true, v_hi));
    let (mut c, mut fc) = (a, fa);
    let (mut d, mut e) = (b - a, b - a);
    for _ in 0..200 {
        if (fb > 0.0) == (fc > 0.0) {
            (c, fc) = (a, fa);
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            (a, fa) = (b, fb);
            (b, fb) = (c, fc);
            (c, fc) = (a, fa);
        }
        let tol = 2.0 * f64::EPSILON * b.abs() + f64::MIN_POSITIVE;
        let xm = 0.5 * (c - b);
        if xm.abs() <= tol {
            break;
        }
        if e.abs() >= tol && fa.abs() > fb.abs() {
            // inverse quadratic interpolation (secant when a = c)
            let s = fb / fa;
            let (mut p, mut q) = if a == c {
                (2.0 * xm * s, 1.0 - s)
            } else {
                let (qa, r) = (fa / fc, fb / fc);
                (s * (2.0 * xm * qa * (qa - r) - (b - a) * (r - 1.0)), (qa - 1.0) * (r - 1.0) * (s - 1.0))
            };
            if p > 0.0 {
                q = -q;
            }
            p = p.abs();
            if 2.0 * p < (3.0 * xm * q - (tol * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = xm;
                e = d;
            }
        } else {
            d = xm;
            e = d;
        }
        (a, fa) = (b, fb);
        b += if d.abs() > tol { d } else { tol.copysign(xm) };
        let (crossed, v) = probe(b);
        fb = phi(crossed, v);
    }
    // b and c hold the flip between them, a few floats apart (lo's side first: if not, the side
    // flipped more than once, and the whole bracket is bisected): bisect to the last float
    let (nc, cr) = if fb > 0.0 { (c, b) } else { (b, c) };
    let (mut lo, mut hi) = if nc < cr { (nc, cr) } else { (lo, hi) };
    loop {
        let mid = 0.5 * (lo + hi);
        if !(mid > lo && mid < hi) {
            return (lo, hi);
        }
        if probe(mid).0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
}

/// Whether g, on one side of zero at the left point (value `g`, rate `r_lo`), turns back toward
/// zero before the right point (rate `r_hi`): a minimum of a positive g (rate − → +) or a
/// maximum of a negative one (+ → −) lies between them, which may reach the other side.
pub fn extremum_between(g: f64, r_lo: Option<f64>, r_hi: Option<f64>) -> bool {
    match (r_lo, r_hi) {
        (Some(a), Some(b)) => (g > 0.0 && a < 0.0 && b > 0.0) || (g < 0.0 && a > 0.0 && b < 0.0),
        _ => false,
    }
}

/// A pair of crossings of `e` inside (lo, hi) that a sign test at lo and hi does not see: g is
/// `g_lo` at lo (on one side of zero), its rate turns toward zero between lo and hi
/// ([`extremum_between`] at the two ends). The extremum (the rate's sign change, narrowed on
/// the dense output to the last representable time, [`narrow`]) is returned when g there has crossed in
/// the event's direction: the first crossing of the pair then lies in (lo, extremum] and
/// [`locate`] finds it from that bracket. `None`: the extremum stays on g_lo's side (`z` is
/// left at some point of the bisection). Only one extremum per interval is looked for: an
/// interval between checked points of one step holding two turns of R is not resolved.
pub fn hidden_crossing(e: &dyn Event, g_lo: f64, lo: f64, hi: f64, z: &mut [f64], mut dense: impl FnMut(f64, &mut [f64])) -> Option<f64> {
    // the rate's side: still toward zero (negative for a positive g) or past the extremum
    let mut rate = |t: f64, z: &mut [f64]| {
        dense(t, z);
        let r = e.rate(t, z).unwrap_or(f64::NAN);
        (!(if g_lo > 0.0 { r < 0.0 } else { r > 0.0 }), r)
    };
    let (r_a, r_b) = (rate(lo, z).1, rate(hi, z).1);
    let (a, b) = narrow(lo, hi, r_a, r_b, |t| rate(t, z));
    // the extremum lies in [a, b] (adjacent floats): whichever end is beyond zero
    [a, b].into_iter().find(|&t| {
        rate(t, z);
        e.direction().crossed(g_lo, e.g(t, z))
    })
}

/// A located event: its index and time.
struct Located {
    index: usize,
    t: f64,
}

#[cfg(test)]
mod tests {
    use super::narrow;

    /// Bisection to the last float, the reference `narrow` must agree with.
    fn bisect(mut lo: f64, mut hi: f64, side: impl Fn(f64) -> bool) -> (f64, f64) {
        loop {
            let mid = 0.5 * (lo + hi);
            if !(mid > lo && mid < hi) {
                return (lo, hi);
            }
            if side(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
    }

    /// On smooth monotone functions narrow ends on bisection's pair of adjacent floats, in fewer
    /// probes.
    #[test]
    fn narrow_ends_where_bisection_does_in_fewer_probes() {
        let cases: [(&str, fn(f64) -> f64, f64, f64); 4] = [
            ("linear", |t| t - 1.2345678901234567, 1.0, 2.0),
            ("cubic", |t| (t - 0.3).powi(3) + 0.01 * (t - 0.3), 0.0, 1.0),
            ("exp", |t| (5.0 * t).exp() - 20.0, 0.0, 1.0),
            ("cos", |t| (7.0 * t).cos(), 19.9, 20.1),
        ];
        for (name, f, lo, hi) in cases {
            let (flo, fhi) = (f(lo), f(hi));
            let side = |t: f64| (f(t) < 0.0) != (flo < 0.0);
            let probes = std::cell::Cell::new(0);
            let got = narrow(lo, hi, flo, fhi, |t| {
                probes.set(probes.get() + 1);
                (side(t), f(t))
            });
            let want = bisect(lo, hi, side);
            println!("{name}: {} probes, bracket {:?}", probes.get(), got);
            assert_eq!(got, want, "{name}");
            assert_eq!(got.1, got.0.next_up(), "{name}: adjacent floats");
            assert!(probes.get() <= 20, "{name}: {} probes (bisection: ~53)", probes.get());
        }
    }
}
