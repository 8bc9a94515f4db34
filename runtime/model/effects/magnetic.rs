//! The magnetic loads (eq 2.40, FORMULATION §0 and §4.1, χ_s = εχ): +M0 in the radial balance
//! and −M_n,k, −M_t,k in G_n,k, G_t,k, from the generated field tables
//! ([`crate::field::loads::MagneticLoads`]). The time and R prefactors are computed once per
//! call (counted: `Model::magnetic_evaluations`). The loads are affine in (a, b) with couplings
//! k → k, k ± 2 (wider for H4 fields); the zero-order parts ℋ2, ℋ¹2 are the forcing.

use super::{At, LoadJacobian, Loads, PressureRate, Term};
use crate::field::loads::MagneticLoads;

#[derive(Debug)]
pub struct MagneticTerm {
    pub loads: MagneticLoads,
    /// e.g. "coil field (static current)"
    pub label: String,
}

impl Term for MagneticTerm {
    fn name(&self) -> &'static str {
        "magnetic"
    }
    fn label(&self) -> Option<String> {
        Some(self.label.clone())
    }
    #[inline]
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>) {
        let l = &self.loads;
        let f = l.factors(at.t, at.r());
        l.add_to_balances(&f, at.z, &mut loads.pressure, loads.gn, loads.gt);
    }
    fn band(&self) -> usize {
        self.loads.width()
    }
    fn evaluations(&self) -> u64 {
        self.loads.evaluations()
    }
    /// P ∋ +M0: its rate, exact ([`MagneticLoads::add_radial_rate`]); the ḃ part goes to
    /// `rate.db` (the closure's ḃ, added by the boundary-layer system).
    fn add_rate(&self, at: &At<'_>, rate: &mut PressureRate) -> bool {
        self.loads.add_radial_rate(at.t, at.z, 1.0, rate);
        true
    }
    /// The row-0 gradient into a stack buffer (M0 depends on R and, with a field, on a_2, b_2 …).
    fn add_pressure_gradient(&self, at: &At<'_>, dp: &mut [f64; 2]) {
        let l = &self.loads;
        let f = l.factors(at.t, at.r());
        let mut g = [0.0; super::MAX_DIM];
        l.add_row_gradient(&f, 0, at.z, true, 1.0, &mut g[..at.z.len()]);
        dp[0] += g[0];
        dp[1] += g[1];
    }
    /// The prefactors once for both; ∂M0/∂R without a gradient buffer
    /// ([`MagneticLoads::radial_gradient`], the same sums; M0 does not depend on Ṙ).
    fn add_pressure_and_gradient(&self, at: &At<'_>, p: &mut f64, dp: &mut [f64; 2]) {
        let l = &self.loads;
        let f = l.factors(at.t, at.r());
        l.add_to_balances(&f, at.z, p, &mut [], &mut []);
        dp[0] += l.radial_gradient(&f, at.z);
    }
    fn add_jacobian(&self, at: &At<'_>, jac: &mut LoadJacobian) {
        let l = &self.loads;
        let f = l.factors(at.t, at.r());
        let n = jac.n;
        l.add_row_gradient(&f, 0, at.z, true, 1.0, &mut jac.pressure);
        for m in 0..jac.modes() {
            l.add_row_gradient(&f, m + 1, at.z, true, -1.0, &mut jac.gn[m * n..(m + 1) * n]);
            l.add_row_gradient(&f, m + 1, at.z, false, -1.0, &mut jac.gt[m * n..(m + 1) * n]);
        }
    }
}
