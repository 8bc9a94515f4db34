//! `shell.law = "church-hoff"` (issue 31; docs/model.md, "Shells: Church–Hoff"): the radial R(t)
//! against an RK4 of Hoff, Sontum & Hovem 2000's equation written here, the small-amplitude
//! stiffness against its closed form, radial-only and bad input.

use crate::common;
use crate::common::water::*;
use magbubble::model::Model;
use magbubble::scene::{load_str, Scene, ShellLaw};

/// A Sonazoid-type shell (Hoff et al. 2000 fitted G_s ≈ 50 MPa, η_s ≈ 0.8 Pa s, d ≈ 4 nm).
const G_S: f64 = 50e6;
const ETA_S: f64 = 0.8;
const D: f64 = 4e-9;

fn scene(eps: f64, f_hz: f64) -> Scene {
    let mut s = common::scene(0, eps, f_hz);
    s.shell.law = ShellLaw::ChurchHoff { modulus: G_S, viscosity: ETA_S };
    s.shell.thickness = D;
    s
}

/// Hoff et al. 2000: ρ(RR̈ + 3/2Ṙ²) = p_g0(R0/R)^{3κ} − p0(1 + ε_p cos ωt) − 4ηṘ/R
/// − 12 η_s d R0² Ṙ/R⁴ − 12 G_s d R0²/R³ (1 − R0/R), p_g0 = p0.
fn rhs(t: f64, y: [f64; 2], eps: f64, w: f64) -> [f64; 2] {
    let (r, v, r0) = (y[0], y[1], common::R0);
    let shell = 12.0 * ETA_S * D * r0 * r0 * v / r.powi(4) + 12.0 * G_S * D * r0 * r0 / r.powi(3) * (1.0 - r0 / r);
    let p = P0 * (r0 / r).powf(3.0 * KAPPA) - P0 * (1.0 + eps * (w * t).cos()) - 4.0 * ETA * v / r - shell;
    [v, (p / RHO - 1.5 * v * v) / r]
}

fn reference(eps: f64, f_hz: f64, ts: &[f64], h: f64) -> Vec<f64> {
    let w = 2.0 * std::f64::consts::PI * f_hz;
    let f = |t: f64, y: [f64; 2]| rhs(t, y, eps, w);
    common::rk4_at_times(&f, [common::R0, 0.0], ts, h)
}

#[test]
fn radial_motion_matches_the_published_equation_to_1e_8() {
    common::assert_radial_matches_reference(&[0.1, 0.3, 0.6, 1.0], 2e-6, 1e-8, &|e| scene(e, 2e6), &|e, ts| reference(e, 2e6, ts, 5e-12));
}

#[test]
fn the_radial_stiffness_and_damping_at_rest_are_the_closed_forms() {
    // ρR0²ω0² = 3κp0 + 12 G_s d/R0 and ∂R̈/∂Ṙ = −(4η + 12 η_s d/R0)/(ρR0²), from the R̈ row of
    // the radial Jacobian at rest (undriven)
    let mut s = scene(0.0, 1e6);
    s.drive = None;
    let model = Model::from_scene(&s).unwrap();
    let sys = model.system();
    let mut jac = vec![0.0; 4];
    assert!(sys.jacobian(0.0, &[1.0, 0.0], &mut jac));
    let ts = model.time_scale();
    let r0 = common::R0;
    let w2 = (3.0 * KAPPA * P0 + 12.0 * G_S * D / r0) / (RHO * r0 * r0);
    let damp = -(4.0 * ETA + 12.0 * ETA_S * D / r0) / (RHO * r0 * r0);
    let (got_w2, got_damp) = (-jac[2] / (ts * ts), jac[3] / ts);
    println!("f0 = {:.4} MHz (free: {:.4})", w2.sqrt() / 2e6 / std::f64::consts::PI, (3.0 * KAPPA * P0 / (RHO * r0 * r0)).sqrt() / 2e6 / std::f64::consts::PI);
    assert!((got_w2 - w2).abs() < 1e-9 * w2, "{got_w2:e} vs {w2:e}");
    assert!((got_damp - damp).abs() < 1e-9 * damp.abs(), "{got_damp:e} vs {damp:e}");
}

#[test]
fn church_hoff_is_radial_only_and_bad_input_is_refused() {
    let err = |text: &str| load_str(text, "test", &[] as &[&str]).unwrap_err().to_string();
    let e = err("[shell]\nlaw = \"church-hoff\"\nmodulus = 5e7\n");
    assert!(e.contains("modes.max_order") && e.contains("radial only"), "{e}");
    let e = err("[shell]\nlaw = \"church-hoff\"\n[modes]\nmax_order = 0\n");
    assert!(e.contains("shell.modulus") && e.contains("required"), "{e}");
    let e = err("[shell]\nlaw = \"church-hoff\"\nmodulus = 5e7\nelasticity = 0.5\n[modes]\nmax_order = 0\n");
    assert!(e.contains("shell.elasticity"), "{e}");
    let e = err("[shell]\nmodulus = 5e7\n");
    assert!(e.contains("shell.modulus") && e.contains("church-hoff"), "{e}");
    let e = err("[shell]\nlaw = \"church-hoff\"\nmodulus = -1\n[modes]\nmax_order = 0\n");
    assert!(e.contains("shell.modulus"), "{e}");
    // the model refuses shape modes too (a scene built in code)
    let mut s = scene(0.1, 1e6);
    s.modes.max_order = 4;
    let e = Model::from_scene(&s).unwrap_err().to_string();
    assert!(e.contains("modes.max_order") && e.contains("church-hoff"), "{e}");
}
