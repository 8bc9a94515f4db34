//! A free bubble with surface tension (issue 10, "Checks against independent references"):
//! `modes` (the library function behind `magbubble modes`) against Lamb's shape frequencies
//! and the radial frequency of the exact linearization, with and without vapour pressure.
//!
//! Scene: R0 = 5 µm, ρ = 1000 kg/m³, p0 = 101325 Pa, κ = 1.4, γ = 0.072 N/m, no membrane
//! (`shell.c1 = shell.c2 = 0`), incompressible. Viscosity η = 1e-9 Pa s: `liquid.viscosity` must
//! be > 0 and the Reynolds number R0√(ρp0)/η ≤ 1e12, so η ≳ 5e-14 is allowed; 1e-9 is the
//! "inviscid limit" used here (it cannot change the result: see the derivation).
//!
//! Derivation (the linearization tested against). The pressure balance of the terms is
//!
//! ```text
//! P(R, Ṙ) = p_v + p_g0 (R0/R)^{3κ} − p0 − 2γ/R − 4ηṘ/R,   p_g0 = p0 − p_v + 2γ/R0,
//! R̈ = P/(ρR) − 3Ṙ²/(2R)   (paper eq 2.62 with the membrane removed)
//! ```
//! so P(R0, 0) = 0 (equilibrium). With R = R0 + x: P = P_R x + P_Ṙ ẋ + O(2), P_R =
//! −3κ p_g0/R0 + 2γ/R0², P_Ṙ = −4η/R0, and the Ṙ² term is second order, so
//! ẍ + (4η/(ρR0²)) ẋ + ω0² x = 0 with ω0² = −P_R/(ρR0) = [3κ p_g0 − 2γ/R0]/(ρR0²) exactly;
//! η only damps, and `modes` reports the undamped ω0 (∂R̈/∂R at Ṙ = 0, where 4ηṘ/R and its
//! R-derivative vanish identically).
//!
//! Shape modes: with no membrane there is no tangential load (G_t ≡ 0) and the normal load of
//! the isotropic tension on mode k is (k−1)(k+2)γ/R² a_k (tension form, generated). The
//! inviscid shape equation at R = R0, Ṙ = 0 (FORMULATION §4.4, 𝒟 = (k+1)/(ρR0)) is
//! ä_k + (k+1)(k−1)(k+2)γ/(ρR0³) a_k = 0: Lamb's ω_k² = (k−1)(k+1)(k+2)γ/(ρR0³), the
//! viscous terms multiplying ȧ_k only (they vanish in the undamped frequency for every η).

use magbubble::analysis::frequencies::natural_frequencies;
use magbubble::model::Model;
use magbubble::scene::{self, Scene};
use crate::common::water::*;

const R0: f64 = 5e-6;

fn scene(pv: f64) -> Scene {
    let text = format!(
        "[bubble]\nradius = {R0:e}\n[liquid]\nviscosity = 1e-9\n[shell]\nc1 = 0.0\nc2 = 0.0\nsurface_tension = {GAMMA}\n\
         [gas]\npolytropic_exponent = {KAPPA}\nvapour_pressure = {pv}\n[modes]\nmax_order = 4\n"
    );
    scene::load_str(&text, "free bubble with surface tension (test)", &[] as &[&str]).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn lamb_shape_and_radial_frequencies_of_a_free_bubble() {
    let mut worst_shape = 0.0f64;
    let mut worst_radial = 0.0f64;
    for pv in [0.0, 2330.0] {
        let s = scene(pv);
        let pg0 = P0 - pv + 2.0 * GAMMA / R0;
        let m = Model::from_scene(&s).unwrap();
        assert!((m.groups().p_g0_pa / pg0 - 1.0).abs() < 1e-15, "p_g0 = {} vs {pg0}", m.groups().p_g0_pa);
        assert!(m.equations().has("surface tension") && !m.equations().has("membrane"));
        let f = natural_frequencies(&s, 16).unwrap();
        let w0sq = (3.0 * KAPPA * pg0 - 2.0 * GAMMA / R0) / (RHO * R0 * R0);
        let e = (f.radial.omega_rad_s.powi(2) / w0sq - 1.0).abs();
        assert!(e < 1e-9, "pv = {pv}: ω0² = {} vs {w0sq} (rel {e:e})", f.radial.omega_rad_s.powi(2));
        worst_radial = worst_radial.max(e);
        let ks: Vec<usize> = f.shape.iter().map(|m| m.k).collect();
        assert_eq!(ks, (2..=16).collect::<Vec<_>>(), "one frequency per k = 2…16");
        for mode in &f.shape {
            let k = mode.k as f64;
            let lamb = (k - 1.0) * (k + 1.0) * (k + 2.0) * GAMMA / (RHO * R0.powi(3));
            let got = mode.omega_rad_s.powi(2);
            let e = (got / lamb - 1.0).abs();
            assert!(e < 1e-9, "pv = {pv}, k = {}: ω² = {got} vs Lamb {lamb} (rel {e:e})", mode.k);
            worst_shape = worst_shape.max(e);
        }
    }
    eprintln!("worst relative error: shape ω_k² {worst_shape:e}, radial ω0² {worst_radial:e}");
}

/// The odd modes (computed mode by mode, not from the model's loads) see surface tension too:
/// k = 3 alone, against Lamb, and nonzero (it used to read the membrane only).
#[test]
fn an_odd_mode_of_a_free_bubble_sees_surface_tension() {
    let f = natural_frequencies(&scene(0.0), 3).unwrap();
    let k3 = f.shape.iter().find(|m| m.k == 3).expect("k = 3 reported");
    let lamb = 2.0 * 4.0 * 5.0 * GAMMA / (RHO * R0.powi(3));
    assert!(k3.omega_sq_nondim > 0.0);
    assert!((k3.omega_rad_s.powi(2) / lamb - 1.0).abs() < 1e-9, "{} vs {lamb}", k3.omega_rad_s.powi(2));
}
