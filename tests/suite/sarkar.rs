//! `shell.law = "sarkar"`, the exponential elasticity model of Paul et al. 2010 (issue 31;
//! docs/model.md, "Lipid shells: Sarkar"): the radial R(t) against an RK4 of the published
//! equation written here, the small-amplitude radial frequency against its closed form, the
//! unstrained radius, bad input.

use crate::common;
use crate::common::water::*;
use magbubble::analysis::frequencies::natural_frequencies;
use magbubble::scene::{load_str, Sarkar, Scene, ShellLaw};

/// E0^s, α^s, γ0, κ^s: of the order Paul et al. 2010 fitted for lipid-coated agents.
const E0: f64 = 0.55;
const ALPHA: f64 = 1.5;
const GAMMA0: f64 = 0.02;
const KAPPA_S: f64 = 5e-9;

/// R_E by bisection on γ(R0) = 0, written here: γ(R) = γ0 + E0 β e^{−αβ}, β = R²/R_E² − 1.
fn unstrained_radius(e0: f64, alpha: f64, g0: f64, r0: f64) -> f64 {
    let gamma_at_r0 = |re: f64| {
        let b = (r0 / re).powi(2) - 1.0;
        g0 + e0 * b * (-alpha * b).exp()
    };
    // γ(R0) falls from γ0 (R_E = R0) as R_E grows
    let (mut lo, mut hi) = (r0, 10.0 * r0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if gamma_at_r0(mid) > 0.0 { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}

fn law() -> Sarkar {
    Sarkar { elasticity: E0, elasticity_decay: ALPHA, reference_tension: GAMMA0, unstrained_radius: unstrained_radius(E0, ALPHA, GAMMA0, common::R0) }
}

/// The paper's bubble with the EEM shell (p_g0 = p0: no net tension at rest).
fn scene(eps: f64, f_hz: f64) -> Scene {
    let mut s = common::scene(0, eps, f_hz);
    s.shell.law = ShellLaw::Sarkar(law());
    s.shell.dilatational_viscosity = KAPPA_S;
    s
}

/// Paul et al. 2010's Rayleigh–Plesset equation with the EEM, in SI:
/// ρ(RR̈ + 3/2Ṙ²) = p_g0(R0/R)^{3κ} − p0(1 + ε_p cos ωt) − 4ηṘ/R − 2γ(R)/R − 4κ^sṘ/R².
fn rhs(t: f64, y: [f64; 2], eps: f64, w: f64, re: f64) -> [f64; 2] {
    let (r, v) = (y[0], y[1]);
    let b = r * r / (re * re) - 1.0;
    let gamma = GAMMA0 + E0 * b * (-ALPHA * b).exp();
    let p = P0 * (common::R0 / r).powf(3.0 * KAPPA) - P0 * (1.0 + eps * (w * t).cos()) - 4.0 * ETA * v / r - 2.0 * gamma / r - 4.0 * KAPPA_S * v / (r * r);
    [v, (p / RHO - 1.5 * v * v) / r]
}

/// R at the times `ts` by classical RK4 with step ≤ h.
fn reference(eps: f64, f_hz: f64, ts: &[f64], h: f64) -> Vec<f64> {
    let w = 2.0 * std::f64::consts::PI * f_hz;
    let re = law().unstrained_radius;
    let f = |t: f64, y: [f64; 2]| rhs(t, y, eps, w, re);
    common::rk4_at_times(&f, [common::R0, 0.0], ts, h)
}

#[test]
fn radial_motion_matches_the_published_equation_to_1e_8() {
    common::assert_radial_matches_reference(&[0.1, 0.3, 0.6, 1.0], 3e-6, 2e-8, &|e| scene(e, 1e6), &|e, ts| reference(e, 1e6, ts, 1e-11));
}

#[test]
fn the_unstrained_radius_and_the_radial_frequency_are_the_closed_forms() {
    // R_E (resolved by the scene) against the bisection here; then, with γ(R0) = 0 and
    // p_g0 = p0, ρR0²ω0² = 3κp0 + 2R0 dγ/dR(R0) = 3κp0 + 4E0 (R0²/R_E²)(1 − αβ0)e^{−αβ0}/R0
    let r0 = common::R0;
    for &(e0, a, g0) in &[(0.55, 1.5, 0.02), (1.0, 0.0, 0.05), (0.3, 4.0, 0.0)] {
        let text = format!("[shell]\nlaw = \"sarkar\"\nelasticity = {e0}\nelasticity_decay = {a}\nreference_tension = {g0}\n");
        let s = load_str(&text, "test", &[] as &[&str]).unwrap();
        let ShellLaw::Sarkar(p) = s.shell.law else { panic!("{:?}", s.shell.law) };
        let re = unstrained_radius(e0, a, g0, r0);
        assert!((p.unstrained_radius - re).abs() < 1e-12 * re, "{} vs {re}", p.unstrained_radius);
        let mut s = common::scene(4, 0.0, 1e6);
        s.shell.law = ShellLaw::Sarkar(p);
        let f = natural_frequencies(&s, 4).unwrap();
        let b0 = (r0 / re).powi(2) - 1.0;
        let w2 = (3.0 * KAPPA * P0 + 4.0 * e0 * (r0 * r0 / (re * re)) * (1.0 - a * b0) * (-a * b0).exp() / r0) / (RHO * r0 * r0);
        let rel = (f.radial.omega_rad_s - w2.sqrt()).abs() / w2.sqrt();
        assert!(rel < 1e-9, "E0={e0} a={a} g0={g0}: {} vs {} ({rel:e})", f.radial.omega_rad_s, w2.sqrt());
        // no tension at rest: the shape modes have no elastic stiffness there (an area-only law:
        // ω_k² ∝ γ(R0) = 0, to round-off in model units)
        assert!(f.shape.iter().all(|m| m.omega_sq_nondim.abs() < 1e-12), "{:?}", f.shape);
    }
}

#[test]
fn bad_sarkar_input_is_refused_naming_the_key() {
    let err = |text: &str| load_str(text, "test", &[] as &[&str]).unwrap_err().to_string();
    let e = err("[shell]\nlaw = \"sarkar\"\n");
    assert!(e.contains("shell.elasticity") && e.contains("required"), "{e}");
    let e = err("[shell]\nlaw = \"marmottant\"\nelasticity = 0.5\nelasticity_decay = 1.0\n");
    assert!(e.contains("shell.elasticity_decay") && e.contains("sarkar"), "{e}");
    let e = err("[shell]\nlaw = \"sarkar\"\nelasticity = 0.5\nbuckling_radius = 9e-6\n");
    assert!(e.contains("shell.buckling_radius"), "{e}");
    let e = err("[shell]\nlaw = \"sarkar\"\nelasticity = 0.5\nreference_tension = 5.0\n");
    assert!(e.contains("shell.reference_tension") && e.contains("unstrained"), "{e}");
    let e = err("[shell]\nlaw = \"sarkar\"\nelasticity = 0.5\nelasticity_decay = -1\n");
    assert!(e.contains("shell.elasticity_decay"), "{e}");
    let s = magbubble::scene::load("scenes/no_field.toml", &["shell.law=\"sarkar\"", "shell.elasticity=0.5", "modes.coupling=\"quadratic\""]).unwrap();
    let e = magbubble::model::Model::from_scene(&s).unwrap_err().to_string();
    assert!(e.contains("modes.coupling") && e.contains("Sarkar"), "{e}");
}
