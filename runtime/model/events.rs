//! The model's hooks into the run loop ([`crate::integrate::run_loop`]): the known
//! discontinuity times of a run ([`Model::stop_times`]) and its event functions
//! ([`Model::events`]): the blow-up threshold and, for the kinked Marmottant law, its branch
//! switches ([`BranchEvent`]). The run executor ([`super::executor`]) passes both to the loop,
//! starts the branch clock ([`Model::start_branches`]) and reads it at the end
//! ([`Model::finish_branches`]).

use super::effects::lipid::{Branch, LipidLaw};
use super::Model;
use crate::integrate::run_loop::{Action, Direction, Event};
use serde::Serialize;

/// The blow-up threshold as an event: g = [`Model::blow_up_margin`] on the boundary-layer
/// layout z = [R, Ṙ, (a, ȧ, b)_k], rising through 0, located to 1e-13 · max(t, t_end) on the
/// dense output, stopping the run ([`Model::stop_status`] says why). It also fires at t = 0
/// when the initial state is already beyond the threshold.
pub struct BlowUpEvent<'a> {
    pub model: &'a Model,
}

impl Event for BlowUpEvent<'_> {
    // direction, tolerance and action: the defaults (rising, 1e-13, stop)
    fn g(&self, _t: f64, z: &[f64]) -> f64 {
        self.model.blow_up_margin(z)
    }
    fn fires_at_start(&self) -> bool {
        true
    }
}

/// A branch switch of the kinked Marmottant law (issue 31; docs/model.md, "Branch switches"):
/// g = R − R_b (`which` = 0) or R − R_r (1), either direction, located on the dense output to
/// the last representable time ([`crate::integrate::run_loop::locate`]); at the crossing the run's branch becomes R's there and the stepper
/// restarts, so no step straddles a kink of τ(R) and the law inside each step is the smooth
/// formula of one branch. Both layouts the executor runs (boundary layer, monolithic) start
/// with [R, Ṙ].
pub struct BranchEvent<'a> {
    pub law: &'a LipidLaw,
    pub which: usize,
    pub clock: &'a std::sync::Mutex<BranchClock>,
}

impl Event for BranchEvent<'_> {
    fn g(&self, _t: f64, z: &[f64]) -> f64 {
        self.law.margin(z[0], self.which)
    }
    fn direction(&self) -> Direction {
        Direction::Either
    }
    fn action(&self) -> Action {
        Action::Restart
    }
    /// Ṙ is z[1]: a dip of R below R_b (or above R_r, across a knot) and back inside one step
    /// is found too (`run_loop::hidden_crossing`), not stepped over.
    fn rate(&self, _t: f64, z: &[f64]) -> Option<f64> {
        Some(self.law.margin_rate(z[0], z[1]))
    }
    fn update(&self, t: f64, y: &mut [f64]) {
        let b = self.law.enter(y[0]);
        if let Ok(mut c) = self.clock.lock() {
            c.switch(t, b);
        }
    }
}

/// The time a run has spent on each branch (model units).
#[derive(Debug, Default, Clone)]
pub struct BranchClock {
    start: f64,
    current: Option<Branch>,
    since: f64,
    spent: [f64; 3],
    switches: u64,
}

impl BranchClock {
    fn index(b: Branch) -> usize {
        Branch::ALL.iter().position(|&x| x == b).unwrap_or(0)
    }

    /// The run is on branch `b` from time t.
    fn switch(&mut self, t: f64, b: Branch) {
        if let Some(c) = self.current {
            self.spent[Self::index(c)] += t - self.since;
            if c != b {
                self.switches += 1;
            }
        }
        self.current = Some(b);
        self.since = t;
    }
}

/// `summary.json`'s `shell_branches` (issue 31): the fraction of the run's time spent on each
/// branch of the kinked Marmottant law, from the located switch times, and the number of
/// switches.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BranchFractions {
    pub buckled: f64,
    pub elastic: f64,
    pub ruptured: f64,
    pub switches: u64,
}

impl Model {
    /// The event functions of a run, in priority order for events located at the same time;
    /// each sees the boundary-layer layout z = [R, Ṙ, (a, ȧ, b)_k] (nondimensional): the
    /// blow-up threshold ([`BlowUpEvent`], index 0: the executor maps a stop at it to
    /// [`Model::stop_status`]), then, for the kinked Marmottant law, its two branch switches
    /// ([`BranchEvent`], `Action::Restart`). The equations evaluate the law on the run's
    /// branch ([`crate::model::effects::lipid::BranchState`]), which
    /// [`Model::start_branches`] sets at t0 and each switch updates.
    pub fn events(&self) -> Vec<Box<dyn Event + '_>> {
        let mut v: Vec<Box<dyn Event + '_>> = vec![Box::new(BlowUpEvent { model: self })];
        v.extend(self.branch_events());
        v
    }

    /// The branch switches of [`Model::events`] alone (empty without a kinked law): they read
    /// R = z[0] only, so they also serve the radial state [R, Ṙ] of the Floquet analysis's
    /// period map (analysis/periodic, docs/stability.md "Floquet on a kinked law").
    pub fn branch_events(&self) -> Vec<Box<dyn Event + '_>> {
        let Some((law, clock)) = &self.kinked else { return Vec::new() };
        (0..law.event_count()).map(|which| Box::new(BranchEvent { law, which, clock }) as Box<dyn Event + '_>).collect()
    }

    /// The kinked law's branch the equations are evaluated on, as an opaque code (0: none set,
    /// R's branch at each evaluation; always 0 without a kinked law).
    pub fn branch_code(&self) -> u8 {
        self.kinked.as_ref().map_or(0, |(law, _)| law.branch.code())
    }

    /// Sets the branch [`Model::branch_code`] returned (no-op without a kinked law).
    pub fn set_branch_code(&self, code: u8) {
        if let Some((law, _)) = &self.kinked {
            law.branch.set_code(code);
        }
    }

    /// The events of [`Model::events`] without the branch switches: the law re-decides its
    /// branch from R at every evaluation and the steppers step over its kinks (for comparison
    /// in tests; tests/suite/marmottant_events.rs).
    pub fn events_without_branches(&self) -> Vec<Box<dyn Event + '_>> {
        vec![Box::new(BlowUpEvent { model: self })]
    }

    /// Starts a run at time t0 from state z0 (R first): the kinked law's branch becomes R0's
    /// and the branch clock starts. No-op without a kinked law.
    pub fn start_branches(&self, t0: f64, z0: &[f64]) {
        if let Some((law, clock)) = &self.kinked {
            let b = law.enter(z0[0]);
            if let Ok(mut c) = clock.lock() {
                *c = BranchClock { start: t0, ..Default::default() };
                c.switch(t0, b);
            }
        }
    }

    /// Ends a run at time t: the fractions of [t0, t] spent on each branch, and the law back
    /// to R's branch at each evaluation (for analyses after the run). `None` without a kinked
    /// law or before [`Model::start_branches`].
    pub fn finish_branches(&self, t: f64) -> Option<BranchFractions> {
        let (law, clock) = self.kinked.as_ref()?;
        law.branch.set(None);
        let mut c = clock.lock().ok()?;
        let b = c.current?;
        c.switch(t, b);
        let total = t - c.start;
        let f = |i: usize| if total > 0.0 { c.spent[i] / total } else { (i == BranchClock::index(b)) as u8 as f64 };
        Some(BranchFractions { buckled: f(0), elastic: f(1), ruptured: f(2), switches: c.switches })
    }
}
