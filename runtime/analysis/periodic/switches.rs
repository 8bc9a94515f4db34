//! Branch switches inside the period map (issue 31; docs/stability.md, "Floquet on a kinked law").
//!
//! A kinked shell law (Marmottant's R_b and R_r, a tension curve's knots) changes its formula
//! where R crosses a switch: the radial right-hand side has a kink there and the shape system's
//! A(t) a jump. A fixed RK4 step across such an instant samples two formulas in its stages and
//! loses its order. So a grid step whose end has crossed a switch (or that holds a pair of
//! crossings: R's extremum inside the step beyond the switch, [`run_loop::hidden_crossing`]) is
//! redone in two parts: up to
//! the crossing — located by the run loop's own bisection ([`run_loop::locate`]) on the step's
//! cubic Hermite dense output (the run loop's RK4 dense output, `integrate::hermite`), with the
//! run's own event functions ([`Switching::events`]) — and from there to the grid point, on the
//! branch the run's event enters ([`Event::update`], from the dense state at the crossing, as
//! the run loop does). As in a run, each part evaluates the formula of one branch (continued a
//! little beyond its kink), never re-decided from R at a stage. The grid points stay where they
//! are; each switch is logged ([`Switch`]) for the sampled orbit and the monodromy's Magnus
//! steps, which split there too (analysis/stability/systems.rs, analysis/floquet/magnus.rs).
//!
//! The location error of the Hermite output is O(h⁴) in time; f being continuous at the switch,
//! it moves y by O(h⁸) and the jump of A(t) by O(h⁴) of one step: both within the methods'
//! order 4.

use super::tangent::{Buf, Tangent};
use super::{Observer, PeriodicError, RkFlow};
use crate::integrate::run_loop::{self, Event};
use crate::model::Model;

/// A right-hand side whose formula switches branch where event functions of the state cross
/// zero (a kinked shell law, issue 31).
pub trait Switching {
    /// The event functions of the switches (those of a run, [`Model::branch_events`]); each
    /// one's [`Event::update`] enters the branch on its crossed side, without a state jump.
    fn events(&self) -> Vec<Box<dyn Event + '_>>;
    /// The branch the right-hand side is evaluated on, an opaque code (0: the state's own at
    /// each evaluation).
    fn branch(&self) -> u8;
    /// Sets the branch [`Switching::branch`] returned.
    fn set_branch(&self, code: u8);
    /// Enters the branch of state `y` at time `t` (the start of a run).
    fn enter(&self, t: f64, y: &[f64]);
}

impl Switching for Model {
    fn events(&self) -> Vec<Box<dyn Event + '_>> {
        self.branch_events()
    }
    fn branch(&self) -> u8 {
        self.branch_code()
    }
    fn set_branch(&self, code: u8) {
        self.set_branch_code(code)
    }
    fn enter(&self, t: f64, y: &[f64]) {
        self.start_branches(t, y)
    }
}

/// A located branch switch of the period map.
#[derive(Debug, Clone, PartialEq)]
pub struct Switch {
    /// Its time.
    pub t: f64,
    /// The state there (the RK4 part that ends at t).
    pub y: Vec<f64>,
    /// f(t, y) on the branch left and on the branch entered (equal for a law whose τ is
    /// continuous, as Marmottant's and a tension curve's are).
    pub f_before: Vec<f64>,
    pub f_after: Vec<f64>,
    /// The branch entered ([`Switching::branch`]).
    pub branch: u8,
}

/// At most this many switches are located inside one grid step; beyond, the step is taken
/// whole (a state chattering about a switch).
const MAX_SWITCHES_PER_STEP: usize = 8;

/// The buffers of the located switch of one grid step: the step's start and end (y, f) for its
/// dense output, and the state at the crossing.
struct StepEnds {
    y0: Vec<f64>,
    f0: Vec<f64>,
    y1: Vec<f64>,
    f1: Vec<f64>,
    z: Vec<f64>,
}

impl RkFlow<'_> {
    /// The grid steps of [`RkFlow::integrate`] from t0 (`total` steps of h) on a kinked law: each
    /// step whose end has crossed a switch split there (module doc). `obs` at every grid point
    /// as in the plain loop; each switch appended to `log`. The caller restores the branch.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn integrate_switched<T: Tangent, B: Buf>(
        &self,
        sw: &dyn Switching,
        t0: f64,
        y: &mut B,
        tan: &mut T,
        total: usize,
        h: f64,
        ky: &mut [B; 4],
        tmp: &mut B,
        mut obs: Option<&mut Observer<'_>>,
        mut log: Option<&mut Vec<Switch>>,
    ) -> Result<(), PeriodicError> {
        let n = y.as_ref().len();
        let events = sw.events();
        sw.enter(t0, y.as_ref());
        let mut g: Vec<f64> = events.iter().map(|e| e.g(t0, y.as_ref())).collect();
        let mut g_new = g.clone();
        // dg/dt (Ṙ for R − R_b): a pair of crossings inside one step is found as in a run
        let mut r: Vec<Option<f64>> = events.iter().map(|e| e.rate(t0, y.as_ref())).collect();
        let mut r_new = r.clone();
        let zero = || vec![0.0; n];
        let mut b = StepEnds { y0: zero(), f0: zero(), y1: zero(), f1: zero(), z: zero() };
        let finite = |y: &B, tan: &T, t: f64| {
            if y.as_ref().iter().all(|v| v.is_finite()) && tan.is_finite() {
                Ok(())
            } else {
                Err(PeriodicError::NonFinite { t })
            }
        };
        for s in 0..total {
            let t = t0 + s as f64 * h;
            let (mut tc, mut hc) = (t, h);
            for located in 0..=MAX_SWITCHES_PER_STEP {
                b.y0.copy_from_slice(y.as_ref());
                tan.save();
                // obs at the grid point only (a redone part starts at the switch)
                let o = if tc == t { obs.as_deref_mut() } else { None };
                self.rk4_step(tc, hc, y, ky, tmp, tan, o);
                let te = tc + hc;
                finite(y, tan, te)?;
                for ((gi, ri), e) in g_new.iter_mut().zip(r_new.iter_mut()).zip(&events) {
                    *gi = e.g(te, y.as_ref());
                    *ri = e.rate(te, y.as_ref());
                }
                let any_crossed = (0..events.len()).any(|i| events[i].direction().crossed(g[i], g_new[i]));
                // (as in the run loop: an event whose sign test saw nothing, beside another's crossing too)
                let turns = |i: &usize| !events[*i].direction().crossed(g[*i], g_new[*i]) && run_loop::extremum_between(g[*i], r[*i], r_new[*i]);
                let hidden = (0..events.len()).any(|i| turns(&i));
                if located == MAX_SWITCHES_PER_STEP || !(any_crossed || hidden) {
                    std::mem::swap(&mut g, &mut g_new);
                    std::mem::swap(&mut r, &mut r_new);
                    break;
                }
                // the step's dense output (on the branch it was taken on)
                b.f0.copy_from_slice(ky[0].as_ref());
                b.y1.copy_from_slice(y.as_ref());
                self.sys.rhs(te, &b.y1, &mut b.f1);
                let StepEnds { y0, f0, y1, f1, z } = &mut b;
                let dense = |tq: f64, out: &mut [f64]| crate::integrate::hermite(tc, hc, y0, f0, y1, f1, tq, out);
                // a pair of crossings inside the step: the earliest extremum beyond zero ends
                // the bracket (`run_loop::hidden_crossing`, as the run loop does)
                let mut t_hi = te;
                if hidden {
                    for i in (0..events.len()).filter(turns) {
                        if let Some(t_x) = run_loop::hidden_crossing(&*events[i], g[i], tc, t_hi, z, dense) {
                            t_hi = t_x;
                        }
                    }
                    if t_hi == te && !any_crossed {
                        std::mem::swap(&mut g, &mut g_new);
                        std::mem::swap(&mut r, &mut r_new);
                        break;
                    }
                    if t_hi < te {
                        dense(t_hi, z);
                        for (gi, e) in g_new.iter_mut().zip(&events) {
                            *gi = e.g(t_hi, z);
                        }
                    }
                }
                let crossed = |i: usize| events[i].direction().crossed(g[i], g_new[i]);
                let (mut first, mut ts) = (0, f64::INFINITY);
                for i in (0..events.len()).filter(|&i| crossed(i)) {
                    let ti = run_loop::locate(&*events[i], g[i], tc, t_hi, z, dense);
                    if ti < ts {
                        (first, ts) = (i, ti);
                    }
                }
                // the step again, up to the crossing, on the branch it started on
                y.as_mut().copy_from_slice(y0);
                tan.restore();
                self.rk4_step(tc, ts - tc, y, ky, tmp, tan, None);
                finite(y, tan, ts)?;
                let mut f_before = vec![0.0; n];
                if log.is_some() {
                    self.sys.rhs(ts, y.as_ref(), &mut f_before);
                }
                // the run's event enters the new branch from the dense state at the crossing
                // (on the crossed side by construction), as in the run loop
                dense(ts, z);
                events[first].update(ts, z);
                for ((gi, ri), e) in g.iter_mut().zip(r.iter_mut()).zip(&events) {
                    *gi = e.g(ts, z);
                    *ri = e.rate(ts, z);
                }
                if let Some(l) = log.as_deref_mut() {
                    let mut f_after = vec![0.0; n];
                    self.sys.rhs(ts, y.as_ref(), &mut f_after);
                    l.push(Switch { t: ts, y: y.as_ref().to_vec(), f_before, f_after, branch: sw.branch() });
                }
                (tc, hc) = (ts, te - ts);
                if hc <= 0.0 {
                    break;
                }
            }
        }
        Ok(())
    }
}
