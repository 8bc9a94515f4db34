//! Keller–Miksis with the shell's dilatational viscosity κ_s (issue 10 left part, issue 11 part 3
//! radial): `ShellViscosity::add_rate` (runtime/model/effects/shell.rs) gives dP/dt of
//! −4κ_sṘ/R², so KM + κ_s is assembled. Checked against
//!
//! * the pressure's rate along a trajectory: a central difference of P(t, z(t)) equals q + s R̈;
//! * the property ∂q/∂R relies on (the generated Ŝ0 ∝ Ṙ/R²: Ŝ0_RR = −3Ŝ0_R/R);
//! * the analytic linearization: with P_R = −3κp_g0/R0 + 2γ/R0² − 24(c1+c2)/R0²,
//!   P_Ṙ = −4η/R0 − 4κ_s/R0², KM gives R0 D ẍ = (P_R/ρ)x + (P_Ṙ/ρ + R0P_R/(ρc))ẋ with
//!   D = 1 − P_Ṙ/(ρc), i.e. ω² = −P_R/(ρR0D), 2β = −(P_Ṙ/ρ + R0P_R/(ρc))/(R0D);
//! * the exact Jacobian against finite differences;
//! * a driven time series against an independent SI RK4 of KM with γ, κ_s and the Mooney–Rivlin
//!   radial load written out by hand (paper eq 2.62's membrane term).

use crate::support::rk4_ref::rk4_at_rows;
use crate::support::jacobian::assert_jacobian_matches_fd;
use magbubble::coefficients::membrane::viscous;
use magbubble::model::Model;
use magbubble::model::effects::ShapeRate;
use magbubble::scene;
use crate::common::water::*;

const KS: f64 = 1e-9;

fn scene_text(r0: f64, c1: f64, c2: f64, drive: Option<(f64, f64)>) -> String {
    let d = drive.map_or(String::new(), |(e, f)| format!("[drive]\namplitude = {e}\nfrequency_hz = {f:e}\n"));
    format!(
        "[bubble]\nradius = {r0:e}\n[liquid]\nsound_speed = {C}\n[shell]\nc1 = {c1}\nc2 = {c2}\nsurface_tension = {GAMMA}\n\
         dilatational_viscosity = {KS:e}\n[gas]\npolytropic_exponent = {KAPPA}\n{d}[modes]\nmax_order = 0\n"
    )
}

fn model(text: &str, over: &[&str]) -> Model {
    let s = scene::load_str(text, "km + kappa_s (test)", over).unwrap();
    Model::from_scene(&s).unwrap_or_else(|e| panic!("KM + κ_s must be assembled: {e}"))
}

#[test]
fn dilatational_viscosity_radial_load_is_linear_in_rdot_and_homogeneous_in_r() {
    use viscous::tension::{s0, s0_dr};
    for r in [0.4, 1.0, 2.3] {
        for rd in [-0.7, 0.3] {
            let (s, d) = (s0(r, 1.0, rd, 0.0, 0.5), s0_dr(r, 1.0, rd, 0.0, 0.5));
            assert!((s - rd * s0(r, 1.0, 1.0, 0.0, 0.5)).abs() < 1e-15, "linear in Ṙ");
            let h = 1e-5 * r;
            let drr = (s0_dr(r + h, 1.0, rd, 0.0, 0.5) - s0_dr(r - h, 1.0, rd, 0.0, 0.5)) / (2.0 * h);
            assert!((drr + 3.0 * d / r).abs() < 1e-8 * (1.0 + drr.abs()), "Ŝ0_RR {drr} vs −3Ŝ0_R/R {}", -3.0 * d / r);
            assert!((s * r * r - 2.0 * rd).abs() < 1e-14, "Ŝ0 = 4κ_sṘ/R² with κ_s = 0.5");
        }
    }
}

/// dP/dt along the motion (central difference of P(t, z + h ż)) against q + s R̈ of the terms.
#[test]
fn pressure_rate_matches_a_finite_difference_along_the_trajectory() {
    let text = scene_text(3e-6, 0.1, 0.12, Some((0.6, 1.5e6)));
    for over in [vec![], vec!["shell.c1=0", "shell.c2=0"]] {
        let m = model(&text, &over);
        let (eq, sys) = (m.equations(), m.system());
        for (t, z) in [(0.37, [1.3, -0.4]), (2.1, [0.8, 0.9]), (0.0, [1.0, 0.0])] {
            let mut dz = [0.0; 2];
            sys.rhs(t, &z, &mut dz);
            let mut shape = ShapeRate::default();
            let (rate, all) = eq.rate(t, &z, &mut shape);
            assert!(all, "every term provides the rate");
            let p = |h: f64| eq.loads(t + h, &[z[0] + h * dz[0], z[1] + h * dz[1]], &mut [], &mut []);
            let h = 1e-5;
            let fd = (p(h) - p(-h)) / (2.0 * h);
            let exact = rate.q + rate.s * dz[1];
            assert!((fd - exact).abs() < 1e-7 * (1.0 + fd.abs()), "{over:?} t = {t}: FD {fd} vs q + sR̈ {exact}");
        }
    }
}

#[test]
fn keller_miksis_with_dilatational_viscosity_linear_frequency_and_damping() {
    for (r0, c1, c2) in [(5e-6, 0.0, 0.0), (2e-6, 0.1, 0.12)] {
        let m = model(&scene_text(r0, c1, c2, None), &[]);
        let (ts, sys) = (m.time_scale(), m.system());
        let mut jac = [0.0; 4];
        assert!(sys.jacobian(0.0, &[1.0, 0.0], &mut jac));
        let pg0 = P0 + 2.0 * GAMMA / r0;
        let p_r = -3.0 * KAPPA * pg0 / r0 + 2.0 * GAMMA / (r0 * r0) - 24.0 * (c1 + c2) / (r0 * r0);
        let p_rd = -4.0 * ETA / r0 - 4.0 * KS / (r0 * r0);
        let d = 1.0 - p_rd / (RHO * C);
        let w2 = -p_r / (RHO * r0 * d);
        let two_beta = -(p_rd / RHO + r0 * p_r / (RHO * C)) / (r0 * d);
        let (ew, eb) = ((-jac[2] / (ts * ts) / w2 - 1.0).abs(), (-jac[3] / ts / two_beta - 1.0).abs());
        eprintln!("R0 = {r0:e}, c1 = {c1}: rel error ω² {ew:e}, 2β {eb:e}");
        assert!(ew < 1e-12, "ω²: {} vs {w2}", -jac[2] / (ts * ts));
        assert!(eb < 1e-12, "2β: {} vs {two_beta}", -jac[3] / ts);
        // κ_s's share of the damping is the incompressible 2κ_s/(ρR0³) up to D (issue 11)
        let without = -(-4.0 * ETA / r0 / RHO + r0 * p_r / (RHO * C)) / (r0 * d);
        assert!(((two_beta - without) / 2.0 / (2.0 * KS / (RHO * r0.powi(3)) / d) - 1.0).abs() < 1e-12);
    }
}

#[test]
fn keller_miksis_with_dilatational_viscosity_jacobian_matches_finite_differences() {
    let text = scene_text(3e-6, 0.1, 0.12, Some((0.7, 1e6)));
    for over in [vec![], vec!["shell.c1=0", "shell.c2=0"], vec!["shell.surface_tension=0"]] {
        let m = model(&text, &over);
        assert!(m.equations().has("shell viscosity"));
        assert_jacobian_matches_fd(m.system(), &format!("{over:?}"));
    }
}

/// KM + γ + κ_s + Mooney–Rivlin in SI, written out independently of the model: P = p_g0(R0/R)^{3κ}
/// − p0(1 + ε cos ωt) − 2γ/R − 4ηṘ/R − 4κ_sṘ/R² − S_MR(R), with the paper's membrane pressure
/// S_MR = 4c1(1/R − R0⁶/R⁷) + 4c2(R/R0² − R0⁴/R⁵); KM solved for R̈ (it is linear in R̈).
fn km_si(t: f64, y: [f64; 2], r0: f64, c: (f64, f64), eps: f64, w: f64) -> [f64; 2] {
    let (r, v) = (y[0], y[1]);
    let (c1, c2) = c;
    let pg = (P0 + 2.0 * GAMMA / r0) * (r0 / r).powf(3.0 * KAPPA);
    let smr = 4.0 * c1 * (1.0 / r - r0.powi(6) / r.powi(7)) + 4.0 * c2 * (r / (r0 * r0) - r0.powi(4) / r.powi(5));
    let smr_r = 4.0 * c1 * (-1.0 / (r * r) + 7.0 * r0.powi(6) / r.powi(8)) + 4.0 * c2 * (1.0 / (r0 * r0) + 5.0 * r0.powi(4) / r.powi(6));
    let p = pg - P0 * (1.0 + eps * (w * t).cos()) - 2.0 * GAMMA / r - 4.0 * ETA * v / r - 4.0 * KS * v / (r * r) - smr;
    // dP/dt = q + s R̈
    let q = -3.0 * KAPPA * pg * v / r + P0 * eps * w * (w * t).sin() + 2.0 * GAMMA * v / (r * r) + 4.0 * ETA * v * v / (r * r)
        + 8.0 * KS * v * v / (r * r * r)
        - smr_r * v;
    let s = -4.0 * ETA / r - 4.0 * KS / (r * r);
    let num = (1.0 + v / C) * p / RHO + r * q / (RHO * C) - 1.5 * (1.0 - v / (3.0 * C)) * v * v;
    [v, num / ((1.0 - v / C) * r - r * s / (RHO * C))]
}

#[test]
fn keller_miksis_with_dilatational_viscosity_time_series_matches_an_independent_rk4() {
    for (r0, c1, c2, eps, f) in [(5e-6, 0.0, 0.0, 0.5, 3e5), (2e-6, 0.1, 0.12, 0.6, 2.5e6)] {
        let text = scene_text(r0, c1, c2, Some((eps, f)));
        let dur = 20.0 / f;
        let over = [
            format!("run.duration={dur:e}"),
            format!("run.sample_interval={:e}", dur / 100.0),
            "run.integrator.method=rk4".into(),
            format!("run.integrator.dt={:e}", dur / 2e5),
        ];
        let s = scene::load_str(&text, "km + kappa_s (test)", &over).unwrap();
        let mut rows = Vec::new();
        let rep = magbubble::model::simulate(&s, &mut |t, row| rows.push((t, row[0]))).unwrap();
        assert_eq!(rep.status, magbubble::model::RunStatus::Completed);
        let w = 2.0 * std::f64::consts::PI * f;
        let per = 20_000;
        let dt = dur / 100.0 / per as f64;
        let reference = rk4_at_rows(|t, y| km_si(t, y, r0, (c1, c2), eps, w), r0, &rows, dt, per, 1e-9 * dur);
        let (mut worst, mut span) = (0.0f64, (f64::MAX, 0.0f64));
        for (&(_, r), y) in rows.iter().zip(reference) {
            worst = worst.max((r - y).abs() / r0);
            span = (span.0.min(r / r0), span.1.max(r / r0));
        }
        eprintln!("R0 = {r0:e}: max |R − R_rk4|/R0 = {worst:.2e}, R/R0 in [{:.4}, {:.4}]", span.0, span.1);
        assert!(span.1 - span.0 > 0.05, "the case must be nonlinear enough to matter: {span:?}");
        assert!(worst < 1e-9, "max |R − R_rk4|/R0 = {worst:e}");
    }
}
