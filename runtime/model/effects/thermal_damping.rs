//! Thermal damping of the gas, `gas.thermal = "prosperetti"` (issue 31 part 2; docs/model.md,
//! "Thermal damping"): Prosperetti's linear theory of the heat exchange between the gas and a
//! liquid held at its ambient temperature (Prosperetti 1977, JASA 61, 17, eqs 14–17, in the
//! limit of a liquid of large thermal conductivity and negligible G1 = M D ω/(γ R_g T) — the
//! form Prosperetti, Crum & Commander 1988, JASA 83, 502, use; the equation numbers are those a
//! public MATLAB implementation, `calc_thermal_damp.m`, cites for its full eqs 16–17):
//!
//!   Φ(ω) = 3γ / (1 − 3(γ − 1) iχ [√(i/χ) coth √(i/χ) − 1]),   χ = D/(ωR0²),
//!
//! with D the gas's thermal diffusivity at rest. A small radial motion ξ ∝ e^{iωt} sees the gas
//! pressure p_g0(1 − Φ ξ/R0): the effective polytropic exponent κ_eff = Re Φ/3 and the thermal
//! viscosity μ_th = p_g0 Im Φ/(4ω) (Prosperetti 1977 eqs 14–15), which the run uses as
//! p_in = p_g0 (R0/R)^{3κ_eff} − 4μ_th Ṙ/R at one frequency ω: the drive's, or for an undriven
//! scene the radial natural frequency ω0 with κ_eff(ω0) (a fixed point, [`natural_omega`]).
//! κ_eff goes into the gas term ([`super::gas::PolytropicGas`]); −4μ_th Ṙ/R is [`ThermalDamping`].

use super::{At, LoadJacobian, Loads, PressureRate, Term};
use nalgebra::Complex;

/// G(Pe) = z coth z − 1 with z = √(iPe) = (1 + i)√(Pe/2), Pe = ωR0²/D: the transfer function
/// of the linearised heat equation in the gas that Prosperetti's Φ (below) and the reduced
/// model's Ψ ([`super::reduced_gas::transfer`]) are both made of. coth z = (1 + e^{−2z})/(1 −
/// e^{−2z}), stable for Re z > 0.
pub(crate) fn z_coth_z_minus_one(pe: f64) -> Complex<f64> {
    let s = (0.5 * pe).sqrt();
    let z = Complex::new(s, s);
    let e = (-2.0 * z).exp();
    let coth = (1.0 + e) / (1.0 - e);
    z * coth - 1.0
}

/// Φ(ω) of Prosperetti's linear theory (module doc): D [m²/s], γ, ω [rad/s], R0 [m] (any
/// consistent units: only χ = D/(ωR0²) enters).
pub fn prosperetti_phi(omega: f64, r0: f64, diffusivity: f64, gamma: f64) -> (f64, f64) {
    let chi = diffusivity / (omega * r0 * r0);
    // iχ (z coth z − 1)
    let w = Complex::new(0.0, chi) * z_coth_z_minus_one(1.0 / chi);
    let phi = Complex::new(3.0 * gamma, 0.0) / (1.0 - 3.0 * (gamma - 1.0) * w);
    (phi.re, phi.im)
}

/// κ_eff = Re Φ/3 and μ_th = p_g0 Im Φ/(4ω) at ω (units of p_g0 / ω).
pub fn effective(omega: f64, r0: f64, diffusivity: f64, gamma: f64, pg0: f64) -> (f64, f64) {
    let (re, im) = prosperetti_phi(omega, r0, diffusivity, gamma);
    (re / 3.0, pg0 * im / (4.0 * omega))
}

/// The radial natural frequency with κ_eff(ω0), a fixed point of
/// ρR0²ω0² = 3κ_eff(ω0) p_g0 − R0 P′_rest, P′_rest the R-derivative of every other radial
/// pressure at rest (model units: `omega_of` maps ω to (D/R0², …) through χ). Converges in a
/// few iterations (κ_eff moves between 1 and γ); `None` if the rest stiffness is not positive.
pub fn natural_omega(rho: f64, r0: f64, pg0: f64, dp_rest: f64, diffusivity: f64, gamma: f64) -> Option<f64> {
    let stiff = |kappa: f64| (3.0 * kappa * pg0 / r0 - dp_rest) / (rho * r0);
    let mut w = stiff(gamma).max(0.0).sqrt();
    for _ in 0..200 {
        if !(w > 0.0) {
            return None;
        }
        let (k, _) = effective(w, r0, diffusivity, gamma, pg0);
        let next = stiff(k);
        if !(next > 0.0) {
            return None;
        }
        let next = next.sqrt();
        if (next - w).abs() <= 1e-14 * w {
            return Some(next);
        }
        w = next;
    }
    Some(w)
}

/// −4μ_th Ṙ/R in the radial balance: Prosperetti's thermal damping at its frequency (module doc).
#[derive(Debug, Clone)]
pub struct ThermalDamping {
    /// μ_th (model units, like η)
    pub mu: f64,
    pub label: String,
}

impl ThermalDamping {
    /// The same −4μṘ/R form as the liquid's viscous stress, with μ_th for η: one implementation.
    fn as_viscous(&self) -> super::viscosity::LiquidViscosity {
        super::viscosity::LiquidViscosity { eta: self.mu }
    }
}

impl Term for ThermalDamping {
    fn name(&self) -> &'static str {
        "thermal damping"
    }
    fn label(&self) -> Option<String> {
        Some(self.label.clone())
    }
    #[inline]
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>) {
        self.as_viscous().add(at, loads)
    }
    fn add_jacobian(&self, at: &At<'_>, jac: &mut LoadJacobian) {
        self.as_viscous().add_jacobian(at, jac)
    }
    fn add_pressure_gradient(&self, at: &At<'_>, dp: &mut [f64; 2]) {
        self.as_viscous().add_pressure_gradient(at, dp)
    }
    /// P = −4μ_thṘ/R: q = 4μ_thṘ²/R², s = −4μ_th/R (the viscous term's).
    fn add_rate(&self, at: &At<'_>, rate: &mut PressureRate) -> bool {
        self.as_viscous().add_rate(at, rate)
    }
}

/// The frequency the thermal models are evaluated at (model units): the drive's, else
/// [`natural_omega`] from the radial stiffness at rest of every term but the gas (`terms[0]`)
/// and `skip` (Prosperetti's damping placeholder). `value` names the model in the error.
fn frequency(
    scene: &crate::scene::Scene,
    d: f64,
    gamma: f64,
    params: &crate::model::Params,
    terms: &[Box<dyn Term>],
    skip: Option<usize>,
    value: &str,
) -> Result<f64, crate::model::ModelError> {
    let omega = match params.drive {
        Some((_, w)) => Some(w),
        None => {
            let dim = crate::model::layout::StateLayout::reduced(scene.modes.orders().count()).dim();
            let mut z = vec![0.0; dim];
            z[0] = params.r0;
            let mut dp = [0.0; 2];
            let rest = At { t: 0.0, z: &z };
            for (i, t) in terms.iter().enumerate() {
                if i != 0 && Some(i) != skip {
                    t.add_pressure_gradient(&rest, &mut dp);
                }
            }
            natural_omega(params.rho, params.r0, params.pg0, dp[0], d, gamma)
        }
    };
    omega.filter(|w| w.is_finite() && *w > 0.0).ok_or(crate::model::ModelError::Unsupported {
        key: "gas.thermal",
        value: value.into(),
        reason: "an undriven scene whose radial stiffness at rest is not positive has no natural frequency to evaluate the thermal model at",
    })
}

/// What both thermal models share at assembly: D in model units, the frequency ω
/// ([`frequency`], `skip` and `value` as there), and κ_eff(ω), μ_th(ω) with 3κ_eff written into
/// `params.three_kappa`. Returns (D, ω, κ_eff, μ_th).
fn at_frequency(
    scene: &crate::scene::Scene,
    sc: &crate::model::Scales,
    params: &mut crate::model::Params,
    terms: &[Box<dyn Term>],
    (thermal_diffusivity, gamma): (f64, f64),
    skip: Option<usize>,
    value: &str,
) -> Result<(f64, f64, f64, f64), crate::model::ModelError> {
    let d = thermal_diffusivity * sc.time / (sc.length * sc.length);
    let omega = frequency(scene, d, gamma, params, terms, skip, value)?;
    let (kappa, mu) = effective(omega, params.r0, d, gamma, params.pg0);
    params.three_kappa = 3.0 * kappa;
    Ok((d, omega, kappa, mu))
}

/// Sets up `gas.thermal = "prosperetti"` in an assembled term list (`Model::from_scene`): the
/// frequency ([`frequency`]), κ_eff into `params.three_kappa` and the gas term `terms[0]`, μ_th
/// into the [`ThermalDamping`] placeholder at `terms[at]`.
pub(crate) fn assemble(
    scene: &crate::scene::Scene,
    sc: &crate::model::Scales,
    params: &mut crate::model::Params,
    terms: &mut [Box<dyn Term>],
    at: usize,
) -> Result<(), crate::model::ModelError> {
    let crate::scene::Thermal::Prosperetti { thermal_diffusivity, heat_capacity_ratio: gamma } = scene.gas.thermal else {
        return Ok(());
    };
    let (_, omega, kappa, mu) = at_frequency(scene, sc, params, terms, (thermal_diffusivity, gamma), Some(at), "\"prosperetti\"")?;
    terms[0] = Box::new(super::gas::PolytropicGas { pg0: params.pg0, r0: params.r0, three_kappa: params.three_kappa });
    let si_mu = mu * sc.pressure * sc.time;
    terms[at] = Box::new(ThermalDamping {
        mu,
        label: format!(
            "thermal damping (Prosperetti 1977, linear) at f = {:.6e} Hz: kappa_eff = {:.6}, mu_th = {:.4e} Pa s",
            omega / (2.0 * std::f64::consts::PI * sc.time),
            kappa,
            si_mu
        ),
    });
    Ok(())
}

/// Sets up `gas.thermal = "reduced"` (runtime/model/effects/reduced_gas.rs): the reduced gas at
/// the same frequency as [`assemble`]'s, as the gas term `terms[0]` (p_b at `index`), κ_eff(ω)
/// into `params.three_kappa` (what the rest stiffness of the linear analyses would use), and
/// the run's label.
pub(crate) fn assemble_reduced(
    scene: &crate::scene::Scene,
    sc: &crate::model::Scales,
    params: &mut crate::model::Params,
    terms: &mut [Box<dyn Term>],
    index: usize,
) -> Result<Option<(super::reduced_gas::ReducedGas, String)>, crate::model::ModelError> {
    let crate::scene::Thermal::Reduced { thermal_diffusivity, heat_capacity_ratio: gamma } = scene.gas.thermal else {
        return Ok(None);
    };
    let (d, omega, _, _) = at_frequency(scene, sc, params, terms, (thermal_diffusivity, gamma), None, "\"reduced\"")?;
    let gas = super::reduced_gas::ReducedGas::new(params.pg0, params.r0, gamma, d, omega, index);
    terms[0] = Box::new(gas);
    let label = format!(
        "reduced thermal model (Preston et al. 2007, p_b a state variable) at f = {:.6e} Hz: Re Psi = {:.6}, Im Psi = {:.6}",
        omega / (2.0 * std::f64::consts::PI * sc.time),
        gas.re,
        gas.im_per_omega * omega
    );
    Ok(Some((gas, label)))
}
