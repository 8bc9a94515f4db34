//! The radial equation (paper eq 2.62, corrected: FORMULATION §4.1):
//! ρ(R R̈ + 3/2 Ṙ²) = p_in − p∞(t) − 4ηṘ/R − Ŝ0(R) + M0,  p_in = p_g0 (R0/R)^{3κ}.

use super::params::Params;
use crate::field::loads::MagneticLoads;
use crate::integrate::OdeSystem;

/// R̈ from the radial equation, given M0 (0 without a field). Nondimensional.
#[inline]
pub fn radial_acceleration(p: &Params, t: f64, r: f64, rd: f64, m0: f64) -> f64 {
    let p_in = p.pg0 * (p.r0 / r).powf(p.three_kappa);
    let s0 = (p.membrane.s0)(r, p.r0, p.c1, p.c2);
    (p_in - p.p_inf(t) - 4.0 * p.eta * rd / r - s0 + m0) / (p.rho * r) - 1.5 * rd * rd / r
}

/// Radial motion alone (max_order = 0): y = [R, Ṙ]. With a field, only the zero-order
/// magnetic load ℋ0 acts (there are no a_2, b_2).
#[derive(Debug)]
pub struct RadialSystem {
    pub(crate) params: Params,
    pub(crate) loads: Option<MagneticLoads>,
}

impl OdeSystem for RadialSystem {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let m0 = match &self.loads {
            None => 0.0,
            Some(l) => {
                let f = l.factors(t, y[0]);
                l.radial(&f, y)
            }
        };
        dy[0] = y[1];
        dy[1] = radial_acceleration(&self.params, t, y[0], y[1], m0);
    }
    fn bandwidth(&self) -> Option<(usize, usize)> {
        Some((1, 1))
    }
}
