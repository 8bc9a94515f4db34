//! The model's hooks into the run loop ([`crate::integrate::run_loop`]): the known
//! discontinuity times of a run ([`Model::stop_times`]) and its event functions
//! ([`Model::events`]). The run executor ([`super::executor`]) passes both to the loop.

use super::Model;
use crate::integrate::run_loop::Event;

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

impl Model {
    /// The event functions of a run, in priority order for events located at the same time;
    /// each sees the boundary-layer layout z = [R, Ṙ, (a, ȧ, b)_k] (nondimensional). Default:
    /// the blow-up threshold alone ([`BlowUpEvent`]); the executor maps a stop at event 0 to
    /// [`Model::stop_status`].
    ///
    /// **For a kinked shell law** (wire at merge): add one event per branch switch with
    /// g = the law's branch-switch margin (e.g. strain − kink strain), `Direction::Either`,
    /// `Action::Restart`, and [`Event::update`] setting the law's branch (interior
    /// mutability); the equations must evaluate the law on the current branch, not re-decide
    /// it from the state inside a step. The executor reports every Stop event by
    /// [`Model::stop_status`]: a new kind of Stop event adds its status there.
    pub fn events(&self) -> Vec<Box<dyn Event + '_>> {
        vec![Box::new(BlowUpEvent { model: self })]
    }
}
