//! Issue 30 part 3, the linear response (runtime/analysis/response.rs) against the closed forms
//! of a free bubble (Minnaert with surface tension; the viscous and Keller–Miksis radiation
//! damping of Prosperetti 1977 / Commander & Prosperetti 1989 in their linear-oscillator form),
//! σ_s against 4πR0²/[((ω0/ω)² − 1)² + δ²], and a small-amplitude run against the response.

use magbubble::analysis::response::{parse_grid, response};
use magbubble::scene::load_str;
use std::f64::consts::PI;

const NONE: &[&str] = &[];
const R0: f64 = 10e-6;
const GAMMA: f64 = 0.072;

fn free(extra: &str) -> magbubble::scene::Scene {
    let text = format!(
        "[bubble]\nradius = 10e-6\n[shell]\nc1 = 0.0\nc2 = 0.0\nsurface_tension = 0.072\n[modes]\nmax_order = 0\n{extra}"
    );
    load_str(&text, "free", NONE).unwrap_or_else(|e| panic!("{e}"))
}

/// (ω0², 4η/(ρR0²)) of the free bubble at the defaults (ρ = 1000, η = 1e-3, p0 = 101325, κ = 1.4).
fn closed(eta: f64) -> (f64, f64, f64) {
    let (rho, p0, kappa) = (1000.0, 101325.0, 1.4);
    let pg0 = p0 + 2.0 * GAMMA / R0;
    let stiff = 3.0 * kappa * pg0 - 2.0 * GAMMA / R0;
    (stiff / (rho * R0 * R0), 4.0 * eta / (rho * R0 * R0), stiff)
}

#[test]
fn free_bubble_incompressible() {
    let s = free("");
    let freqs = parse_grid("1e4:3e6:1000:log").unwrap();
    let r = response(&s, &freqs).unwrap();
    let (w02, c_vis, _) = closed(1e-3);
    let f0 = w02.sqrt() / (2.0 * PI);
    assert!((r.natural_frequency_hz - f0).abs() < 1e-10 * f0, "{} vs {f0}", r.natural_frequency_hz);
    let c = &r.damping_rates_per_s;
    assert!((c.liquid_viscosity - c_vis).abs() < 1e-10 * c_vis, "{} vs {c_vis}", c.liquid_viscosity);
    assert_eq!((c.radiation, c.shell_viscosity), (0.0, 0.0));
    for p in &r.points {
        let w = 2.0 * PI * p.frequency_hz;
        let delta = c_vis / w;
        let sigma = 4.0 * PI * R0 * R0 / (((w02 / (w * w)) - 1.0).powi(2) + delta * delta);
        assert!((p.sigma_s_m2 - sigma).abs() < 1e-9 * sigma, "{} Hz: {} vs {sigma}", p.frequency_hz, p.sigma_s_m2);
        assert!((p.delta.liquid_viscosity - delta).abs() < 1e-12 * delta);
    }
    // the peak of |X| sits just below f0 (√(ω0² − c²/2))
    let peak = (w02 - c_vis * c_vis / 2.0).sqrt() / (2.0 * PI);
    assert!((r.resonance_frequency_hz - peak).abs() < 0.01 * peak);
}

/// Keller–Miksis: D = 1 + 4η/(ρcR0), c_vis = 4η/(ρR0²D), c_rad = (3κp_g0 − 2γ/R0)/(ρcR0D), i.e.
/// δ_rad = ω0 R0/c at resonance (Prosperetti's kR0).
#[test]
fn free_bubble_keller_miksis() {
    let s = free("[liquid]\nsound_speed = 1500.0\n");
    let r = response(&s, &[3e5]).unwrap();
    let (_, c_vis, stiff) = closed(1e-3);
    let d = 1.0 + 4.0 * 1e-3 / (1000.0 * 1500.0 * R0);
    let c = &r.damping_rates_per_s;
    assert!((c.liquid_viscosity - c_vis / d).abs() < 1e-10 * c_vis);
    let c_rad = stiff / (1000.0 * 1500.0 * R0 * d);
    assert!((c.radiation - c_rad).abs() < 1e-10 * c_rad, "{} vs {c_rad}", c.radiation);
    assert!(r.points[0].sigma_e_m2.unwrap() > r.points[0].sigma_s_m2);
}

/// 1,000 frequencies well under 0.1 s.
#[test]
fn thousand_frequencies_fast() {
    let s = free("");
    let f = parse_grid("1e5:1e7:1000").unwrap();
    let t = std::time::Instant::now();
    let r = response(&s, &f).unwrap();
    let dt = t.elapsed().as_secs_f64();
    assert_eq!(r.points.len(), 1000);
    assert!(dt < 0.1, "{dt} s");
}

/// A small-amplitude run (ε_p = 1e-3 at 200 kHz, η = 0.01 Pa s so the transient is gone by
/// 40 µs): its fundamental (projection of R − R0 on cos, sin over 40–60 µs) against
/// |X/P_a| ε_p p0 and the phase, to O(ε_p).
#[test]
fn small_run_matches_response() {
    let extra = "[liquid]\nviscosity = 0.01\n[drive]\namplitude = 1e-3\nfrequency_hz = 2e5\n\
                 [run]\nduration = 60e-6\nsample_interval = 1e-8\n[run.integrator]\nmethod = \"dop853\"\nrtol = 1e-11\natol = 1e-16\n";
    let s = free(extra);
    let mut rows = Vec::new();
    magbubble::model::simulate(&s, &mut |t, row| rows.push((t, row[0]))).unwrap();
    let w = 2.0 * PI * 2e5;
    let (mut c, mut sn, mut n) = (0.0, 0.0, 0.0);
    for &(t, r) in rows.iter().filter(|(t, _)| *t >= 40e-6 - 1e-12 && *t < 60e-6 - 1e-12) {
        c += (r - R0) * (w * t).cos();
        sn += (r - R0) * (w * t).sin();
        n += 1.0;
    }
    let (a, b) = (2.0 * c / n, 2.0 * sn / n); // x ≈ a cos ωt + b sin ωt
    let resp = &response(&s, &[2e5]).unwrap().points[0];
    let p = 1e-3 * 101325.0;
    let (amp, phase) = (a.hypot(b), (-b).atan2(a)); // x = Re(A e^{iφ} e^{iωt})
    assert!((amp - resp.amplitude_m_per_pa * p).abs() < 5e-3 * amp, "{amp:e} vs {:e}", resp.amplitude_m_per_pa * p);
    let dphi = (phase - resp.phase_rad + PI).rem_euclid(2.0 * PI) - PI;
    assert!(dphi.abs() < 5e-3, "phase {phase} vs {}", resp.phase_rad);
}

#[test]
fn bad_grid() {
    for g in ["1:2", "2e6:1e6:10", "1e5:1e6:1", "a:b:c", "1e5:1e6:10:lin"] {
        assert!(parse_grid(g).unwrap_err().contains("--freq"));
    }
}
