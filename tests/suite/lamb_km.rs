//! Keller–Miksis with surface tension (issue 10): the surface-tension term now provides the
//! pressure's rate (`Term::add_rate`), so KM + γ is assembled; checked against the analytic
//! linearization (frequency and damping), the exact Jacobian against finite differences, and
//! the property `add_rate`'s ∂q/∂R relies on (Ŝ0 ∝ 1/R for the tension table, 0 for bending).
//!
//! Linearization (free bubble, no drive), from the KM form of runtime/model/keller_miksis.rs,
//! (1 − Ṙ/c)RR̈ + 3/2(1 − Ṙ/3c)Ṙ² = (1 + Ṙ/c)P/ρ + (R/ρc)(P_R Ṙ + P_Ṙ R̈), with
//! P = p_v + p_g0(R0/R)^{3κ} − p0 − 2γ/R − 4ηṘ/R, p_g0 = p0 − p_v + 2γ/R0, P(R0, 0) = 0:
//! P_R = −3κp_g0/R0 + 2γ/R0², P_Ṙ = −4η/R0, and to first order in x = R − R0
//! R0 D ẍ = (P_R/ρ) x + (P_Ṙ/ρ + R0P_R/(ρc)) ẋ,  D = 1 + 4η/(ρcR0), so
//! ω² = [3κp_g0 − 2γ/R0]/(ρR0² D),  2β = [4η/(ρR0²) + (3κp_g0 − 2γ/R0)/(ρcR0)]/D.

use crate::support::rk4_ref::rk4_at_rows;
use magbubble::model::effects::shell::{bending_table, surface_tension_table};
use crate::support::jacobian::assert_jacobian_matches_fd;
use magbubble::model::Model;
use magbubble::scene;
use crate::common::water::*;

const R0: f64 = 5e-6;

#[test]
fn keller_miksis_with_surface_tension_linear_frequency_and_damping() {
    for pv in [0.0, 2330.0] {
        let text = format!(
            "[bubble]\nradius = {R0:e}\n[liquid]\nsound_speed = {C}\n[shell]\nc1 = 0.0\nc2 = 0.0\nsurface_tension = {GAMMA}\n\
             [gas]\npolytropic_exponent = {KAPPA}\nvapour_pressure = {pv}\n[modes]\nmax_order = 0\n"
        );
        let s = scene::load_str(&text, "km + gamma (test)", &[] as &[&str]).unwrap();
        let m = Model::from_scene(&s).unwrap_or_else(|e| panic!("KM + γ must be assembled: {e}"));
        assert!(m.active_effects()[0].contains("Keller-Miksis") && m.equations().has("surface tension"));
        let (ts, sys) = (m.time_scale(), m.system());
        let mut jac = [0.0; 4];
        assert!(sys.jacobian(0.0, &[1.0, 0.0], &mut jac));
        let pg0 = P0 - pv + 2.0 * GAMMA / R0;
        let stiff = 3.0 * KAPPA * pg0 - 2.0 * GAMMA / R0;
        let d = 1.0 + 4.0 * ETA / (RHO * C * R0);
        let w2 = stiff / (RHO * R0 * R0 * d);
        let two_beta = (4.0 * ETA / (RHO * R0 * R0) + stiff / (RHO * C * R0)) / d;
        let (ew, eb) = ((-jac[2] / (ts * ts) / w2 - 1.0).abs(), (-jac[3] / ts / two_beta - 1.0).abs());
        eprintln!("pv = {pv}: rel error ω² {ew:e}, 2β {eb:e}");
        assert!(ew < 1e-12, "ω²: {} vs {w2}", -jac[2] / (ts * ts));
        assert!(eb < 1e-12, "2β: {} vs {two_beta}", -jac[3] / ts);
        // the radiation part of β ≈ ω0²R0/(2c), ω0 the incompressible one (with γ)
        let radiation = two_beta / 2.0 - 2.0 * ETA / (RHO * R0 * R0) / d;
        let w0sq = stiff / (RHO * R0 * R0);
        assert!((radiation / (w0sq * R0 / (2.0 * C)) - 1.0).abs() < 1e-3, "{radiation}");
    }
}

/// The exact KM Jacobian with γ (driven, off equilibrium) against central differences.
#[test]
fn keller_miksis_with_surface_tension_jacobian_matches_finite_differences() {
    let text = format!(
        "[bubble]\nradius = 3e-6\n[liquid]\nsound_speed = {C}\n[shell]\nsurface_tension = {GAMMA}\n\
         [drive]\namplitude = 0.7\nfrequency_hz = 1e6\n[modes]\nmax_order = 4\n"
    );
    for overrides in [vec!["modes.max_order=0"], vec![], vec!["shell.c1=0", "shell.c2=0"]] {
        let s = scene::load_str(&text, "km + gamma (test)", &overrides).unwrap();
        let m = Model::from_scene(&s).unwrap_or_else(|e| panic!("{overrides:?}: {e}"));
        assert_jacobian_matches_fd(m.system(), &format!("{overrides:?}"));
    }
}

/// `OneConstant::add_rate` uses Ŝ0″ = −2Ŝ0′/R: true iff R·Ŝ0(R) is constant (or Ŝ0 ≡ 0).
#[test]
fn shell_radial_loads_are_proportional_to_one_over_r() {
    let (st, b) = (surface_tension_table(), bending_table());
    for r in [0.3, 1.0, 2.7] {
        let x = r * (st.s.0)(r, 1.0, 0.5);
        assert!((x - 1.0).abs() < 1e-14, "R·Ŝ0 = {x} (2γ with γ = 0.5)");
        assert!(((st.dr.0)(r, 1.0, 0.5) * r * r + 1.0).abs() < 1e-14);
        assert_eq!((b.s.0)(r, 1.0, 0.5), 0.0);
        assert_eq!((b.dr.0)(r, 1.0, 0.5), 0.0);
    }
}

/// KM + γ right-hand side in SI, written independently of the model (free bubble, drive
/// ε cos ωt): P = p_g0(R0/R)^{3κ} − p0(1 + ε cos ωt) − 2γ/R − 4ηṘ/R, Q = dP/dt without R̈.
fn km_si(t: f64, y: [f64; 2], eps: f64, w: f64) -> [f64; 2] {
    let (r, v) = (y[0], y[1]);
    let pg = (P0 + 2.0 * GAMMA / R0) * (R0 / r).powf(3.0 * KAPPA);
    let p = pg - P0 * (1.0 + eps * (w * t).cos()) - 2.0 * GAMMA / r - 4.0 * ETA * v / r;
    let q = -3.0 * KAPPA * pg * v / r + P0 * eps * w * (w * t).sin() + 2.0 * GAMMA * v / (r * r) + 4.0 * ETA * v * v / (r * r);
    let num = (1.0 + v / C) * p / RHO + r * q / (RHO * C) - 1.5 * (1.0 - v / (3.0 * C)) * v * v;
    [v, num / ((1.0 - v / C) * r + 4.0 * ETA / (RHO * C))]
}

#[test]
fn keller_miksis_with_surface_tension_time_series_matches_an_independent_rk4() {
    let (eps, f) = (0.5, 3e5);
    let text = format!(
        "[bubble]\nradius = {R0:e}\n[liquid]\nsound_speed = {C}\n[shell]\nc1 = 0.0\nc2 = 0.0\nsurface_tension = {GAMMA}\n\
         [gas]\npolytropic_exponent = {KAPPA}\n[drive]\namplitude = {eps}\nfrequency_hz = {f:e}\n[modes]\nmax_order = 0\n"
    );
    let over = ["run.duration=10e-6", "run.sample_interval=1e-7", "run.integrator.method=rk4", "run.integrator.dt=1e-10"];
    let s = scene::load_str(&text, "km + gamma (test)", &over).unwrap();
    let mut rows = Vec::new();
    let rep = magbubble::model::simulate(&s, &mut |t, row| rows.push((t, row[0]))).unwrap();
    assert_eq!(rep.status, magbubble::model::RunStatus::Completed);
    let w = 2.0 * std::f64::consts::PI * f;
    let (dt, per) = (1e-11, 10_000);
    let reference = rk4_at_rows(|t, y| km_si(t, y, eps, w), R0, &rows, dt, per, 1e-15);
    let (mut worst, mut rmax) = (0.0f64, 0.0f64);
    for (&(_, r), y) in rows.iter().zip(reference) {
        worst = worst.max((r - y).abs() / R0);
        rmax = rmax.max(r / R0);
    }
    eprintln!("KM + γ: max |R − R_rk4|/R0 = {worst:e}, max R/R0 = {rmax}");
    // guard that the run is nonlinear (γ stiffens the 5 µm bubble: measured max R/R0 = 1.197)
    assert!(rmax > 1.15, "a nonlinear oscillation (max R/R0 = {rmax})");
    assert!(worst < 1e-7, "max |R - R_rk4|/R0 = {worst:e}");
}
