//! The far-field pressure p∞(t) = p0 (1 + ε_p cos ω_d t) (FORMULATION §4.1), entering the radial
//! balance as −p∞. Without a drive (absent or ε_p = 0) it is the constant p0 and the term is not
//! listed as an effect ("no drive term").

use super::{At, LoadJacobian, Loads, PressureRate, Term};

#[derive(Debug, Clone, Copy)]
pub struct FarField {
    /// p̄0
    pub p0: f64,
    /// (ε_p p̄0, ω_d t*) when driven.
    pub drive: Option<(f64, f64)>,
}

impl FarField {
    /// p∞(t).
    #[inline]
    pub fn p_inf(&self, t: f64) -> f64 {
        match self.drive {
            None => self.p0,
            Some((amp, w)) => self.p0 + amp * (w * t).cos(),
        }
    }
    /// dp∞/dt (for a radial form that needs the pressure's time derivative, e.g. Keller–Miksis).
    pub fn p_inf_dt(&self, t: f64) -> f64 {
        self.drive.map_or(0.0, |(amp, w)| -amp * w * (w * t).sin())
    }
}

impl Term for FarField {
    fn name(&self) -> &'static str {
        "far field"
    }
    fn label(&self) -> Option<String> {
        self.drive.map(|_| "acoustic drive".to_string())
    }
    #[inline]
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>) {
        loads.pressure -= self.p_inf(at.t);
    }
    fn add_jacobian(&self, _at: &At<'_>, _jac: &mut LoadJacobian) {}
    fn add_pressure_gradient(&self, _at: &At<'_>, _dp: &mut [f64; 2]) {}
    /// q = −dp∞/dt (the driving pressure's time derivative in the radiation term).
    fn add_rate(&self, at: &At<'_>, rate: &mut PressureRate) -> bool {
        rate.q -= self.p_inf_dt(at.t);
        true
    }
}
