//! The liquid's viscous normal stress at the wall in the radial balance, −4ηṘ/R (eq 2.62,
//! FORMULATION §4.1). The viscous terms of the shape modes belong to the closure (boundary layer
//! or vorticity), not here.

use super::{At, LoadJacobian, Loads, PressureRate, Term};

#[derive(Debug, Clone, Copy)]
pub struct LiquidViscosity {
    pub eta: f64,
}

impl Term for LiquidViscosity {
    fn name(&self) -> &'static str {
        "liquid viscosity"
    }
    #[inline]
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>) {
        loads.pressure -= 4.0 * self.eta * at.rdot() / at.r();
    }
    fn add_jacobian(&self, at: &At<'_>, jac: &mut LoadJacobian) {
        let (r, rd) = (at.r(), at.rdot());
        jac.pressure[0] += 4.0 * self.eta * rd / (r * r);
        jac.pressure[1] -= 4.0 * self.eta / r;
    }
    fn add_pressure_gradient(&self, at: &At<'_>, dp: &mut [f64; 2]) {
        let (r, rd) = (at.r(), at.rdot());
        dp[0] += 4.0 * self.eta * rd / (r * r);
        dp[1] -= 4.0 * self.eta / r;
    }
    /// P = −4ηṘ/R: q = ∂P/∂R Ṙ = 4ηṘ²/R², s = ∂P/∂Ṙ = −4η/R.
    fn add_rate(&self, at: &At<'_>, rate: &mut PressureRate) -> bool {
        let (r, rd, e) = (at.r(), at.rdot(), 4.0 * self.eta);
        rate.q += e * rd * rd / (r * r);
        rate.dq[0] -= 2.0 * e * rd * rd / (r * r * r);
        rate.dq[1] += 2.0 * e * rd / (r * r);
        rate.s -= e / r;
        rate.ds[0] += e / (r * r);
        true
    }
}
