//! The reduced heat-transfer model of the gas, `gas.thermal = "reduced"` (issue 31 part 2;
//! docs/model.md, "Reduced thermal model"): Preston, Colonius & Brennen 2007 (Phys. Fluids 19,
//! 123302, the "constant heat transfer" model of their §III; the form MFC's `thermal = 3`
//! implements, `f_bpres_dot` in src/simulation/m_bubbles.fpp). The bubble pressure p_b is a
//! state variable (its slot: [`crate::model::layout::StateLayout::p_b`]):
//!
//! ```text
//! ṗ_b = (3/R) [−γ p_b Ṙ + (γ − 1) K ∂T/∂r|_R]                     (energy of a uniform-pressure gas)
//! ∂T/∂r|_R = −(T0/R) [Re Ψ θ + (Im Ψ/ω) θ̇],   θ = T̄/T0 − 1 = p_b R³/(p_b0 R0³) − 1
//! Ψ(Pe) = 1 / (1/(√(iPe) coth √(iPe) − 1) − 3/(iPe)),   Pe = ωR0²/D
//! ```
//!
//! T̄ from the ideal-gas law with the gas mass fixed, the liquid (the wall) at T0, Ψ the
//! transfer function of the linearised heat equation in the gas (Preston's eq for the
//! Peclet-number transfer function; MFC's `s_transcoeff`). Preston keeps Re Ψ alone (MFC sets
//! `Im_trans_T = 0`); the Im Ψ θ̇/ω part (the form of Sugiyama, Takagi & Matsumoto 2005, which
//! MFC's history carries) is kept here, so that the small-amplitude limit is Prosperetti's linear
//! theory *exactly* at ω: with R = R0(1 + x), p_b = p_b0(1 + π), e^{iωt},
//! π = −Φ(ω) x with Φ of [`super::thermal_damping`] (docs/model.md derives it). ω is the one the
//! `prosperetti` effect uses (the drive's, else the radial natural frequency with κ_eff).
//!
//! Conventions: D = K/(ρ_g0 c_p) is `gas.thermal_diffusivity` at rest (the same key and meaning
//! as Prosperetti's), γ is `gas.heat_capacity_ratio`; the ideal gas at rest gives
//! (γ − 1) K T0 = γ D p_b0, so K itself is not needed: with κ = 3γD,
//!
//! ```text
//! ṗ_b = N/Q,  N = −3γ p_b Ṙ/R − a κ p_b R/R0³ + a κ p_b0/R² − 3 b κ p_b Ṙ/R0³,  Q = 1 + b κ R/R0³
//! ```
//!
//! (a = Re Ψ, b = Im Ψ/ω; θ̇ holds ṗ_b, solved for). The vapour pressure, if any, stays its own
//! term (p_b is the non-condensable gas's pressure).

use super::{At, LoadJacobian, Loads, PressureRate, Term};
use nalgebra::Complex;

/// Below this Pe, Ψ from the series of z coth z (z² = iPe): the closed form's G = z coth z − 1
/// and 1/G − 3/(iPe) cancel there (the isothermal limit, D → ∞).
const SERIES_BELOW: f64 = 0.1;

/// Why the quadratic coupling is refused with the reduced gas (validation and assembly): its
/// second-order terms use the polytropic gas pressure p_g0 (R0/R)^{3κ} and its κ
/// (runtime/model/effects/quadratic.rs), which a state p_b does not provide.
pub const WITH_QUADRATIC: &str = "gas.thermal = \"reduced\" with modes.coupling = \"quadratic\": the quadratic coupling's second-order terms use the polytropic gas pressure p_g0 (R0/R)^(3 kappa), not the reduced model's state p_b; use modes.coupling = \"linear\", or gas.thermal = \"prosperetti\" or \"polytropic\"";

/// Why the vorticity model is refused with the reduced gas (validation and the full model).
pub const WITH_VORTICITY: &str = "gas.thermal = \"reduced\" with modes.viscous = \"vorticity\": the vorticity model's state does not carry the gas slot p_b; use modes.viscous = \"boundary-layer\"";

/// Ψ(Pe) = (Re, Im) of the module doc, Pe = ωR0²/D (> 0). Ψ → 5 + iPe/7 as Pe → 0 (isothermal),
/// Ψ → √(iPe) + 2 as Pe → ∞ (adiabatic).
pub fn transfer(pe: f64) -> (f64, f64) {
    if pe < SERIES_BELOW {
        // z coth z = Σ c_n wⁿ, c_n = 2²ⁿB₂ₙ/(2n)!, w = z² = iPe. With G = (w/3)(1 − r),
        // r/w = −3 Σ_{n≥2} c_n w^{n−2}, and Ψ = 1/(1/G − 3/w) = (1 − r)/(3 r/w): no cancellation.
        const B: [f64; 8] = [-1.0 / 30.0, 1.0 / 42.0, -1.0 / 30.0, 5.0 / 66.0, -691.0 / 2730.0, 7.0 / 6.0, -3617.0 / 510.0, 43867.0 / 798.0];
        let w = Complex::new(0.0, pe);
        let (mut rw, mut wn) = (Complex::new(0.0, 0.0), Complex::new(1.0, 0.0));
        let mut fact = 24.0; // (2n)! from n = 2
        for (i, b) in B.iter().enumerate() {
            let n = i + 2;
            let c = 4f64.powi(n as i32) * b / fact;
            rw += wn * (-3.0 * c);
            wn *= w;
            fact *= ((2 * n + 1) * (2 * n + 2)) as f64;
        }
        let psi = (1.0 - rw * w) / (3.0 * rw);
        return (psi.re, psi.im);
    }
    // 1/G − 3/(iPe) = 1/G + 3i/Pe, G = z coth z − 1 (the same G as Prosperetti's Φ)
    let g = super::thermal_damping::z_coth_z_minus_one(pe);
    let psi = 1.0 / (1.0 / g + Complex::new(0.0, 3.0 / pe));
    (psi.re, psi.im)
}

/// The reduced gas (module doc), model units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReducedGas {
    /// p_b0: the gas pressure at rest (R0, T0)
    pub pb0: f64,
    /// R0³
    pub r0_cubed: f64,
    pub gamma: f64,
    /// κ = 3γD
    pub kappa: f64,
    /// a = Re Ψ(ω)
    pub re: f64,
    /// b = Im Ψ(ω)/ω
    pub im_per_omega: f64,
    /// The index of p_b in the state.
    pub index: usize,
}

impl ReducedGas {
    /// The model at frequency ω (model units: D, ω, R0 in t*, L).
    pub fn new(pb0: f64, r0: f64, gamma: f64, diffusivity: f64, omega: f64, index: usize) -> Self {
        let (re, im) = transfer(omega * r0 * r0 / diffusivity);
        Self { pb0, r0_cubed: r0 * r0 * r0, gamma, kappa: 3.0 * gamma * diffusivity, re, im_per_omega: im / omega, index }
    }

    /// ṗ_b at (R, Ṙ, p_b).
    #[inline]
    pub fn rate(&self, r: f64, v: f64, p: f64) -> f64 {
        let (n, q) = self.num_den(r, v, p);
        n / q
    }

    #[inline]
    fn num_den(&self, r: f64, v: f64, p: f64) -> (f64, f64) {
        let (k, a, b, w) = (self.kappa, self.re, self.im_per_omega, self.r0_cubed);
        let n = -3.0 * self.gamma * p * v / r - a * k * p * r / w + a * k * self.pb0 / (r * r) - 3.0 * b * k * p * v / w;
        (n, 1.0 + b * k * r / w)
    }

    /// ṗ_b and its exact (∂/∂R, ∂/∂Ṙ, ∂/∂p_b).
    pub fn rate_partials(&self, r: f64, v: f64, p: f64) -> (f64, [f64; 3]) {
        let (k, a, b, w, g) = (self.kappa, self.re, self.im_per_omega, self.r0_cubed, self.gamma);
        let (n, q) = self.num_den(r, v, p);
        let f = n / q;
        let dn_r = 3.0 * g * p * v / (r * r) - a * k * p / w - 2.0 * a * k * self.pb0 / (r * r * r);
        let dn_v = -3.0 * g * p / r - 3.0 * b * k * p / w;
        let dn_p = -3.0 * g * v / r - a * k * r / w - 3.0 * b * k * v / w;
        (f, [(dn_r - f * b * k / w) / q, dn_v / q, dn_p / q])
    }

    /// T̄/T0 = p_b R³/(p_b0 R0³) (the ideal gas, its mass fixed).
    pub fn temperature_ratio(&self, r: f64, p: f64) -> f64 {
        p * r * r * r / (self.pb0 * self.r0_cubed)
    }
}

/// p_b in the radial balance (the gas term `terms[0]` of a reduced-thermal scene). Its
/// derivative ∂P/∂p_b = 1 and the rate's ∂ṗ_b/∂p_b are the p_b column of the radial system's
/// Jacobian ([`crate::model::RadialSystem`]); with respect to (R, Ṙ), P has none.
impl Term for ReducedGas {
    fn name(&self) -> &'static str {
        "gas"
    }
    fn label(&self) -> Option<String> {
        None
    }
    #[inline]
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>) {
        loads.pressure += at.z[self.index];
    }
    fn add_jacobian(&self, _at: &At<'_>, _jac: &mut LoadJacobian) {}
    fn add_pressure_gradient(&self, _at: &At<'_>, _dp: &mut [f64; 2]) {}
    fn add_pressure_and_gradient(&self, at: &At<'_>, p: &mut f64, _dp: &mut [f64; 2]) {
        *p += at.z[self.index];
    }
    /// q = ṗ_b, s = 0; dq = (∂ṗ_b/∂R, ∂ṗ_b/∂Ṙ).
    fn add_rate(&self, at: &At<'_>, rate: &mut PressureRate) -> bool {
        let (f, d) = self.rate_partials(at.r(), at.rdot(), at.z[self.index]);
        rate.q += f;
        rate.dq[0] += d[0];
        rate.dq[1] += d[1];
        true
    }
    #[inline]
    fn add_with_rate(&self, at: &At<'_>, loads: &mut Loads<'_>, rate: &mut PressureRate) -> bool {
        let p = at.z[self.index];
        loads.pressure += p;
        rate.q += self.rate(at.r(), at.rdot(), p);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ψ's limits: 5 + iPe/7 + O(Pe²) at small Pe, √(iPe) + 2 + O(1/√Pe) at large Pe; the
    /// series and the closed form agree where they meet.
    #[test]
    fn transfer_function_limits() {
        let pe = 1e-4;
        let (re, im) = transfer(pe);
        assert!((re - 5.0).abs() < 1e-7 && (im - pe / 7.0).abs() < 1e-7, "{re} {im}");
        let pe = 1e8;
        let (re, im) = transfer(pe);
        let s = (0.5 * pe).sqrt();
        assert!((re - (s + 2.0)).abs() < 0.05 && (im - s).abs() < 0.05, "{re} {im} {s}");
        let (a, b) = (transfer(SERIES_BELOW * (1.0 - 1e-12)), transfer(SERIES_BELOW));
        assert!((a.0 - b.0).abs() < 1e-11 && (a.1 - b.1).abs() < 1e-11, "{a:?} {b:?}");
    }

    /// The exact partials against central differences.
    #[test]
    fn partials_match_differences() {
        let g = ReducedGas::new(1.3, 1.0, 1.4, 0.05, 2.0, 2);
        let x = [0.8, -0.3, 1.9];
        let (_, d) = g.rate_partials(x[0], x[1], x[2]);
        for j in 0..3 {
            let h = 1e-6;
            let (mut p, mut m) = (x, x);
            p[j] += h;
            m[j] -= h;
            let fd = (g.rate(p[0], p[1], p[2]) - g.rate(m[0], m[1], m[2])) / (2.0 * h);
            assert!((fd - d[j]).abs() < 1e-7 * (1.0 + d[j].abs()), "{j}: {fd} vs {}", d[j]);
        }
    }
}
