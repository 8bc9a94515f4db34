//! The gas inside the bubble: polytropic, p_in = p_g0 (R0/R)^{3κ} (FORMULATION §4.1, audit 7).
//! Vapour pressure (issue 10) is one more term ([`super::vapour`]).

use super::{At, LoadJacobian, Loads, PressureRate, Term};

#[derive(Debug, Clone, Copy)]
pub struct PolytropicGas {
    /// p̄_g0
    pub pg0: f64,
    pub r0: f64,
    /// 3κ
    pub three_kappa: f64,
}

impl Term for PolytropicGas {
    fn name(&self) -> &'static str {
        "gas"
    }
    #[inline]
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>) {
        loads.pressure += self.p_in(at.r());
    }
    fn add_jacobian(&self, at: &At<'_>, jac: &mut LoadJacobian) {
        let r = at.r();
        let p_in = self.p_in(r);
        jac.pressure[0] -= self.three_kappa * p_in / r;
    }
    fn add_pressure_gradient(&self, at: &At<'_>, dp: &mut [f64; 2]) {
        let r = at.r();
        dp[0] -= self.three_kappa * self.pg0 * (self.r0 / r).powf(self.three_kappa) / r;
    }
    /// One power for both (the same expressions as `add` and `add_pressure_gradient`).
    fn add_pressure_and_gradient(&self, at: &At<'_>, p: &mut f64, dp: &mut [f64; 2]) {
        let r = at.r();
        let x = (self.r0 / r).powf(self.three_kappa);
        *p += self.pg0 * x;
        dp[0] -= self.three_kappa * self.pg0 * x / r;
    }
    /// q = −3κ p_in Ṙ/R, s = 0.
    fn add_rate(&self, at: &At<'_>, rate: &mut PressureRate) -> bool {
        self.rate_of(self.p_in(at.r()), at, rate);
        true
    }
    /// One power for both (the same expressions as `add` and `add_rate`).
    #[inline]
    fn add_with_rate(&self, at: &At<'_>, loads: &mut Loads<'_>, rate: &mut PressureRate) -> bool {
        let p_in = self.p_in(at.r());
        loads.pressure += p_in;
        self.rate_of(p_in, at, rate);
        true
    }
}

impl PolytropicGas {
    /// p_in = p_g0 (R0/R)^{3κ}.
    #[inline]
    fn p_in(&self, r: f64) -> f64 {
        self.pg0 * (self.r0 / r).powf(self.three_kappa)
    }
    /// q = −3κ p_in Ṙ/R and its (R, Ṙ)-gradient, given p_in.
    #[inline]
    fn rate_of(&self, p_in: f64, at: &At<'_>, rate: &mut PressureRate) {
        let (r, rd, n) = (at.r(), at.rdot(), self.three_kappa);
        rate.q -= n * p_in * rd / r;
        rate.dq[0] += n * (n + 1.0) * p_in * rd / (r * r);
        rate.dq[1] -= n * p_in / r;
    }
}
