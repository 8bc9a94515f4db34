//! The exponential elasticity model (EEM) of Paul, Katiyar, Sarkar, Chatterjee, Shi & Forsberg
//! 2010 (JASA 127, 3846), `shell.law = "sarkar"` (issue 31; docs/model.md, "Lipid shells:
//! Sarkar"): an area-only interfacial tension
//!
//!   γ(R) = γ0 + E^s β,  E^s = E0^s e^{−α^s β},  β = R²/R_E² − 1 = J/J_E − 1,  J = R²/R0²,
//!
//! with R_E the unstrained radius at which the net tension vanishes at rest (γ(R0) = 0,
//! scene/validate/sarkar.rs). As a function τ(J) it enters the shape-mode equations exactly as
//! the Marmottant law does (effects/lipid.rs: loads linear in τ and τ′ through the generated
//! tables of derivations/shell/marmottant.rs, the spec's W = chib J²/2 − chi J being the basis of
//! every isotropic W(J)); the surface dilatational viscosity κ^s (4κ^sṘ/R²) is the existing
//! `shell.dilatational_viscosity`. Smooth: no branches, no events.

/// The EEM tension law, nondimensional tensions (model units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SarkarTension {
    /// E0^s
    pub e0: f64,
    /// α^s
    pub alpha: f64,
    /// γ0
    pub gamma0: f64,
    /// J_E = (R_E/R0)²
    pub je: f64,
}

impl SarkarTension {
    /// τ(J), dτ/dJ, d²τ/dJ²: with β = J/J_E − 1 and e = e^{−αβ},
    /// τ = γ0 + E0 β e, τ′ = E0 (1 − αβ) e / J_E, τ″ = −E0 α (2 − αβ) e / J_E².
    pub fn tension(&self, j: f64) -> [f64; 3] {
        let b = j / self.je - 1.0;
        let e = (-self.alpha * b).exp();
        let (e0, a, je) = (self.e0, self.alpha, self.je);
        [self.gamma0 + e0 * b * e, e0 * (1.0 - a * b) * e / je, -e0 * a * (2.0 - a * b) * e / (je * je)]
    }
}
