//! `shell.law = "church-hoff"` (issue 31; docs/model.md, "Shells: Church–Hoff"): Church 1995's
//! viscoelastic solid shell in the thin-shell form of Hoff, Sontum & Hovem 2000 (JASA 107,
//! 2272), a radial pressure
//!
//!   p_shell = 12 G_s d R0²/R³ (1 − R0/R) + 12 η_s d R0² Ṙ/R⁴,
//!
//! G_s the shell's bulk shear modulus [Pa], η_s its shear viscosity [Pa s], d its thickness at
//! rest (`shell.thickness`). Radial-only: Church's shell resists shape change through its shear
//! stiffness, which is not an isotropic surface energy W(A), and its shape-mode loads are not
//! derived — a scene with shape modes is refused (scene/validate.rs, `Model::from_scene`).

use super::{At, LoadJacobian, Loads, Term};

/// The Church–Hoff shell term (model units: g = 12 G_s d, v = 12 η_s d, pressures × lengths).
#[derive(Debug, Clone)]
pub struct ChurchHoff {
    /// 12 G_s d R0²
    pub g: f64,
    /// 12 η_s d R0²
    pub v: f64,
    pub r0: f64,
    pub label: String,
}

impl ChurchHoff {
    /// (p_shell, ∂/∂R, ∂/∂Ṙ) at (R, Ṙ).
    #[inline]
    fn pressure(&self, r: f64, rd: f64) -> [f64; 3] {
        let (g, v, r0) = (self.g, self.v, self.r0);
        let (r3, r4) = (r * r * r, r * r * r * r);
        // g/R³ − g R0/R⁴ + v Ṙ/R⁴
        let p = g / r3 - g * r0 / r4 + v * rd / r4;
        let dr = -3.0 * g / r4 + 4.0 * g * r0 / (r4 * r) - 4.0 * v * rd / (r4 * r);
        [p, dr, v / r4]
    }
}

impl Term for ChurchHoff {
    fn name(&self) -> &'static str {
        "church-hoff shell"
    }
    fn label(&self) -> Option<String> {
        Some(self.label.clone())
    }
    #[inline]
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>) {
        loads.pressure -= self.pressure(at.r(), at.rdot())[0];
    }
    fn add_jacobian(&self, at: &At<'_>, jac: &mut LoadJacobian) {
        let [_, dr, drd] = self.pressure(at.r(), at.rdot());
        jac.pressure[0] -= dr;
        jac.pressure[1] -= drd;
    }
    fn add_pressure_gradient(&self, at: &At<'_>, dp: &mut [f64; 2]) {
        let [_, dr, drd] = self.pressure(at.r(), at.rdot());
        dp[0] -= dr;
        dp[1] -= drd;
    }
}

/// The scene's Church–Hoff term, if its law is that one.
pub fn term(shell: &crate::scene::Shell, sc: &crate::model::Scales, r0: f64) -> Option<ChurchHoff> {
    let crate::scene::ShellLaw::ChurchHoff { modulus, viscosity } = shell.law else {
        return None;
    };
    let d = shell.thickness / sc.length;
    let (g, v) = (modulus / sc.pressure, viscosity / (sc.pressure * sc.time));
    Some(ChurchHoff {
        g: 12.0 * g * d * r0 * r0,
        v: 12.0 * v * d * r0 * r0,
        r0,
        label: format!("church-hoff shell G_s = {modulus} Pa, eta_s = {viscosity} Pa s, d = {} m (radial only)", shell.thickness),
    })
}
