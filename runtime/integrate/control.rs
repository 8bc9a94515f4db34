//! The one step-size controller of the adaptive steppers (Dopri5, Dop853, Radau5, Rosenbrock).
//!
//! With err the scaled RMS error of the step (accept when err ≤ 1), q the controller order and
//! `safe` the safety factor, the step ratio is h/h_new = clamp(quot, 1/ratio_max, 1/ratio_min):
//! - after a rejection: quot = err^(1/q − 0.75β) / safe;
//! - after an acceptance, PI form (Hairer–Nørsett–Wanner I, sec. II.4, `dopri5.f`; β = 0 is the
//!   classical I controller): quot = err^(1/q − 0.75β) / err_old^β / safe;
//! - predictive form (Gustafsson, HW II eq. IV.8.25, `radau5.f`): quot = max(quot_I,
//!   (h_old/h)(err²/err_old)^(1/q) / 0.9) from the second accepted step on.
//!
//! err_old is floored at 1e-4 (PI) or 1e-2 (predictive), as in the two Hairer codes.

/// Safety factor of the predictive correction (RADAU5's SAFE).
const SAFE_PRED: f64 = 0.9;

#[derive(Debug, Clone, Copy)]
pub(crate) struct StepController {
    /// 1/q.
    expo: f64,
    beta: f64,
    ratio_min: f64,
    ratio_max: f64,
    predictive: bool,
    err_old: f64,
    h_old: f64,
    accepted: u64,
}

impl StepController {
    /// PI controller of order `q`, gain β, h_new/h ∈ [ratio_min, ratio_max].
    pub(crate) fn pi(q: f64, beta: f64, (ratio_min, ratio_max): (f64, f64)) -> Self {
        StepController { expo: 1.0 / q, beta, ratio_min, ratio_max, predictive: false, err_old: 1e-4, h_old: 0.0, accepted: 0 }
    }

    /// Gustafsson's predictive controller of order `q`.
    pub(crate) fn predictive(q: f64, ratio: (f64, f64)) -> Self {
        StepController { predictive: true, ..Self::pi(q, 0.0, ratio) }
    }

    fn clamp(&self, quot: f64) -> f64 {
        quot.clamp(1.0 / self.ratio_max, 1.0 / self.ratio_min)
    }

    fn quot_basic(&self, err: f64, safe: f64) -> f64 {
        err.powf(self.expo - 0.75 * self.beta) / safe
    }

    /// The next step after an accepted step h with error err (updates the controller's memory).
    pub(crate) fn accept(&mut self, h: f64, err: f64, safe: f64) -> f64 {
        let mut quot = self.quot_basic(err, safe) / self.err_old.powf(self.beta);
        if self.predictive {
            if self.accepted >= 1 {
                let gus = (self.h_old / h) * (err * err / self.err_old).powf(self.expo) / SAFE_PRED;
                quot = quot.max(gus);
            }
            self.err_old = err.max(1e-2);
        } else {
            self.err_old = err.max(1e-4);
        }
        self.h_old = h;
        self.accepted += 1;
        h / self.clamp(quot)
    }

    /// The retry after a rejected step h with error err > 1.
    pub(crate) fn reject(&self, h: f64, err: f64, safe: f64) -> f64 {
        h / self.clamp(self.quot_basic(err, safe))
    }

    /// Whether a proposed ratio h_new/h is close enough to 1 to keep h (and the LU factors of
    /// an implicit stepper): h_new/h ∈ [1, 1.2], as in `ode23s` (Radau5 has its own window).
    pub(crate) fn keeps(ratio: f64) -> bool {
        (1.0..=1.2).contains(&ratio)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_and_memory() {
        let mut c = StepController::pi(5.0, 0.04, (0.2, 10.0));
        // a tiny error grows the step by at most ratio_max
        assert!((c.accept(1.0, 1e-30, 0.9) - 10.0).abs() < 1e-12);
        // a huge error shrinks it by at most ratio_min
        assert!((c.reject(1.0, 1e30, 0.9) - 0.2).abs() < 1e-12);
        // err = 1 with err_old = 1: h_new = safe · h
        let mut c = StepController::pi(5.0, 0.0, (0.2, 10.0));
        assert!((c.accept(1.0, 1.0, 0.9) - 0.9).abs() < 1e-12);
        // predictive: after a step whose error fell, the prediction limits growth
        let mut p = StepController::predictive(4.0, (0.2, 8.0));
        let h1 = p.accept(1.0, 0.5, 0.9);
        let h2 = p.accept(h1, 0.01, 0.9);
        let plain = h1 / (0.01f64.powf(0.25) / 0.9).clamp(0.125, 5.0);
        assert!(h2 <= plain + 1e-12, "{h2} {plain}");
        assert!(StepController::keeps(1.1) && !StepController::keeps(0.99) && !StepController::keeps(1.3));
    }
}
