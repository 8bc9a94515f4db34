//! The liquid's viscous normal stress at the wall in the radial balance, −4ηṘ/R (eq 2.62,
//! FORMULATION §4.1). The viscous terms of the shape modes belong to the closure (boundary layer
//! or vorticity), not here.

use super::{At, LoadJacobian, Loads, Term};

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
}
