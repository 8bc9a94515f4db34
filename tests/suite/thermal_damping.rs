//! `gas.thermal = "prosperetti"` (issue 31 part 2; docs/model.md, "Thermal damping";
//! runtime/model/effects/thermal_damping.rs) against closed forms written here: Eller's real
//! form (Eller 1970, JASA 47, 1469) of the same linear theory for κ_eff and the damping ratio
//! d_th = Im Φ / Re Φ, and the model's radial Jacobian at rest (its stiffness and damping)
//! against ω0 and μ_th computed here from it; bad input.

use magbubble::model::effects::thermal_damping::prosperetti_phi;
use magbubble::model::Model;

const D_AIR: f64 = 2.0e-5;
const GAMMA: f64 = 1.4;

/// Eller 1970: with X = R0 √(2ω/D),
/// d = 3(γ−1)[X(sinh X + sin X) − 2(cosh X − cos X)] / [X²(cosh X − cos X) + 3(γ−1)X(sinh X − sin X)],
/// κ = γ / {(1 + d²)[1 + 3(γ−1)/X · (sinh X − sin X)/(cosh X − cos X)]}.
pub fn eller(omega: f64, r0: f64, d: f64, g: f64) -> (f64, f64) {
    let x = r0 * (2.0 * omega / d).sqrt();
    let (sh, s, ch, c) = (x.sinh(), x.sin(), x.cosh(), x.cos());
    let dth = 3.0 * (g - 1.0) * (x * (sh + s) - 2.0 * (ch - c)) / (x * x * (ch - c) + 3.0 * (g - 1.0) * x * (sh - s));
    let kappa = g / ((1.0 + dth * dth) * (1.0 + 3.0 * (g - 1.0) / x * (sh - s) / (ch - c)));
    (kappa, dth)
}

/// Prosperetti's undriven radial mode of a free air bubble in water (ρ 1000, η 1e-3, p0 101325,
/// surface tension `sigma`), written here: ω0 from the fixed point ρR0²ω0² = 3κ(ω0)p_g0 − 2σ/R0,
/// p_g0 = p0 + 2σ/R0 (κ, d_th from [`eller`]), μ_th = p_g0 · 3κ d_th/(4ω0). Returns (ω0, μ_th, κ).
pub fn prosperetti_mode(r0: f64, d: f64, sigma: f64) -> (f64, f64, f64) {
    let (rho, p0) = (1000.0, 101325.0);
    let pg0 = p0 + 2.0 * sigma / r0;
    let mut w: f64 = 1e6;
    for _ in 0..300 {
        let (k, _) = eller(w, r0, d, GAMMA);
        w = ((3.0 * k * pg0 - 2.0 * sigma / r0) / (rho * r0 * r0)).sqrt();
    }
    let (k, dth) = eller(w, r0, d, GAMMA);
    (w, pg0 * 3.0 * k * dth / (4.0 * w), k)
}

#[test]
fn effective_exponent_and_damping_ratio_match_ellers_closed_form() {
    let mut worst: f64 = 0.0;
    for &r0 in &[1e-6, 2e-6, 5e-6, 10e-6] {
        for &f in &[0.5e6, 1e6, 2e6, 5e6] {
            let w = 2.0 * std::f64::consts::PI * f;
            let (re, im) = prosperetti_phi(w, r0, D_AIR, GAMMA);
            let (kappa, dth) = eller(w, r0, D_AIR, GAMMA);
            let ek = (re / 3.0 - kappa).abs() / kappa;
            let ed = (im / re - dth).abs() / dth;
            worst = worst.max(ek).max(ed);
            assert!(ek < 1e-6 && ed < 1e-6, "R0 = {r0}, f = {f}: kappa {} vs {kappa}, d {} vs {dth}", re / 3.0, im / re);
        }
    }
    println!("worst relative difference: {worst:e}");
    // the limits: isothermal (κ → 1) for a small slow bubble, adiabatic (κ → γ) for a large fast one
    let (re, _) = prosperetti_phi(2.0 * std::f64::consts::PI * 1e3, 1e-6, D_AIR, GAMMA);
    assert!((re / 3.0 - 1.0).abs() < 1e-6, "{}", re / 3.0);
    let (re, _) = prosperetti_phi(2.0 * std::f64::consts::PI * 1e7, 1e-3, D_AIR, GAMMA);
    assert!((re / 3.0 - GAMMA).abs() < 1e-3, "{}", re / 3.0);
}

/// R̈'s row of the Jacobian at rest (R = R0, Ṙ = 0, t = 0), in SI: (∂R̈/∂R, ∂R̈/∂Ṙ) [1/s², 1/s].
fn radial_row(set: &[&str]) -> (f64, f64, Model) {
    let s = magbubble::scene::load("scenes/free_bubble.toml", set).unwrap();
    let model = Model::from_scene(&s).unwrap();
    let sys = model.system();
    let n = sys.dim();
    let mut y = vec![0.0; n];
    y[0] = 1.0;
    let mut jac = vec![0.0; n * n];
    assert!(sys.jacobian(0.0, &y, &mut jac));
    let ts = model.time_scale();
    (jac[n] / (ts * ts), jac[n + 1] / ts, model)
}

#[test]
fn the_undriven_radial_mode_has_prosperettis_frequency_and_damping() {
    // free bubble, R0 = 5 µm, γ_s = 0.072 N/m: ρR0²ω0² = 3κ(ω0) p_g0 − 2γ_s/R0 with
    // p_g0 = p0 + 2γ_s/R0 (a fixed point, iterated here with Eller's κ), and the damping
    // ∂R̈/∂Ṙ = −4(η + μ_th)/(ρR0²), μ_th = p_g0 Im Φ/(4ω0) = p_g0 · 3κ d_th/(4ω0)
    let (rho, eta, r0) = (1000.0, 1e-3, 5e-6);
    for &d in &[D_AIR, 1e-6, 1e-3] {
        let dset = format!("gas.thermal_diffusivity={d}");
        let set = ["gas.thermal=\"prosperetti\"", &dset, "drive.amplitude=0", "gas.vapour_pressure=0", "shell.surface_tension=0.072", "modes.max_order=2"];
        let (drr, drd, _) = radial_row(&set);
        let (w, mu, k) = prosperetti_mode(r0, d, 0.072);
        let (stiff, damp) = (-w * w, -4.0 * (eta + mu) / (rho * r0 * r0));
        println!("D = {d}: f0 = {:.1} Hz, kappa = {k:.6}, mu_th = {mu:e} Pa s; model {drr:e} {drd:e}", w / (2.0 * std::f64::consts::PI));
        assert!((drr - stiff).abs() < 1e-6 * stiff.abs(), "D = {d}: dR''/dR {drr:e} vs {stiff:e}");
        assert!((drd - damp).abs() < 1e-6 * damp.abs(), "D = {d}: dR''/dRdot {drd:e} vs {damp:e}");
    }
}

#[test]
fn a_driven_scene_takes_the_damping_at_the_drive_frequency() {
    let (eta, rho, r0) = (1e-3, 1000.0, 5e-6);
    let set = ["gas.thermal=\"prosperetti\"", "gas.vapour_pressure=0", "modes.max_order=2", "drive.frequency_hz=2e6"];
    let (_, drd, model) = radial_row(&set);
    let pg0 = model.groups().p_g0_pa;
    let w = 2.0 * std::f64::consts::PI * 2e6;
    let (k, dth) = eller(w, r0, D_AIR, GAMMA);
    let damp = -4.0 * (eta + pg0 * 3.0 * k * dth / (4.0 * w)) / (rho * r0 * r0);
    assert!((drd - damp).abs() < 1e-6 * damp.abs(), "{drd:e} vs {damp:e}");
    assert!(model.active_effects().iter().any(|e| e.contains("thermal damping (Prosperetti")), "{:?}", model.active_effects());
    // the polytropic default has no thermal term and the Jacobian of the liquid alone
    let (_, drd0, m0) = radial_row(&["gas.vapour_pressure=0", "modes.max_order=2"]);
    assert!(!m0.active_effects().iter().any(|e| e.contains("thermal")));
    assert!((drd0 + 4.0 * eta / (rho * r0 * r0)).abs() < 1e-9 * drd0.abs(), "{drd0:e}");
}

#[test]
fn bad_thermal_input_is_refused_naming_the_key() {
    let err = |set: &[&str]| magbubble::scene::load("scenes/no_field.toml", set).unwrap_err().to_string();
    let e = err(&["gas.thermal_diffusivity=1e-5"]);
    assert!(e.contains("gas.thermal_diffusivity") && e.contains("polytropic"), "{e}");
    let e = err(&["gas.heat_capacity_ratio=1.67"]);
    assert!(e.contains("gas.heat_capacity_ratio"), "{e}");
    let e = err(&["gas.thermal=\"prosperetti\"", "gas.thermal_diffusivity=-1"]);
    assert!(e.contains("gas.thermal_diffusivity"), "{e}");
    let e = err(&["gas.thermal=\"isothermal\""]);
    assert!(e.contains("gas.thermal"), "{e}");
    // κ given explicitly under prosperetti: a warning naming it
    let s = magbubble::scene::load("scenes/free_bubble.toml", &["gas.thermal=\"prosperetti\""]).unwrap();
    let w = s.warnings.join("\n");
    assert!(w.contains("gas.polytropic_exponent") && w.contains("prosperetti"), "{w}");
}
