//! Vapour pressure inside the bubble (issue 10): a constant p_v added to the gas pressure,
//! p_in = p_v + p_g0 (R0/R)^{3κ} (docs/model.md, "Liquid and gas effects"; e.g. Brennen,
//! *Cavitation and Bubble Dynamics*, eq 2.6). Assembled only when `gas.vapour_pressure` > 0.

use super::{At, LoadJacobian, Loads, PressureRate, Term};

#[derive(Debug, Clone, Copy)]
pub struct VapourPressure {
    /// p̄_v
    pub pv: f64,
}

impl Term for VapourPressure {
    fn name(&self) -> &'static str {
        "vapour pressure"
    }
    fn label(&self) -> Option<String> {
        Some("vapour pressure".to_string())
    }
    #[inline]
    fn add(&self, _at: &At<'_>, loads: &mut Loads<'_>) {
        loads.pressure += self.pv;
    }
    fn add_jacobian(&self, _at: &At<'_>, _jac: &mut LoadJacobian) {}
    fn add_pressure_gradient(&self, _at: &At<'_>, _dp: &mut [f64; 2]) {}
    /// Constant: no rate.
    fn add_rate(&self, _at: &At<'_>, _rate: &mut PressureRate) -> bool {
        true
    }
}
