//! Liquid and gas effects (issue 10) against independent references: the free bubble's
//! radial frequency with and without vapour pressure, the Keller–Miksis linearization
//! (frequency and radiation damping) and a Keller–Miksis time series against an RK4
//! integration of a right-hand side written here in SI units; the exact KM Jacobian against
//! finite differences; every analysis command on the free-bubble scene. These use γ = 0; the
//! same checks with surface tension (Lamb's ω_k, ω0 with 2γ/R0, KM + γ) are in lamb_modes.rs
//! and lamb_km.rs.

use crate::support::rk4_ref::rk4_at_rows;
use crate::support::jacobian::assert_jacobian_matches_fd;
use magbubble::analysis::frequencies::natural_frequencies;
use magbubble::model::{simulate, Model, RunStatus};
use magbubble::scene::{self, Scene};
use std::process::Command;
use crate::common::water::*;

const R0: f64 = 5e-6;

fn free(extra: &str, overrides: &[&str]) -> Scene {
    let text = format!(
        "[bubble]\nradius = {R0:e}\n[shell]\nc1 = 0.0\nc2 = 0.0\n[gas]\npolytropic_exponent = {KAPPA}\n{extra}\n[modes]\nmax_order = 4\n"
    );
    scene::load_str(&text, "free bubble (test)", overrides).unwrap_or_else(|e| panic!("{e}"))
}

/// Free bubble, incompressible: R̈ = P/(ρR) − 3Ṙ²/(2R), P = p_v + p_g0 (R0/R)^{3κ} − p0 − 4ηṘ/R,
/// p_g0 = p0 − p_v. At rest at R0: ∂R̈/∂R = −3κ p_g0/(ρR0²), so ω0² = 3κ(p0 − p_v)/(ρR0²)
/// (the viscous term vanishes at Ṙ = 0; it damps at the rate 2η/(ρR0²), not tested here).
#[test]
fn free_bubble_radial_frequency_with_and_without_vapour() {
    for pv in [0.0, 2330.0] {
        let s = free(&format!("vapour_pressure = {pv}"), &[]);
        let m = Model::from_scene(&s).unwrap();
        let pg0 = P0 - pv;
        assert_eq!(m.groups().p_g0_pa, pg0, "equilibrium rule p_g0 = p0 - p_v");
        assert_eq!(m.groups().p_g0_rule, "equilibrium");
        assert_eq!(m.equations().has("vapour pressure"), pv != 0.0, "vapour term only when asked for");
        assert!(!m.equations().has("membrane"), "free bubble: no membrane term");
        let f = natural_frequencies(&s, 4).unwrap();
        let w0 = (3.0 * KAPPA * pg0 / (RHO * R0 * R0)).sqrt();
        assert!((f.radial.omega_rad_s / w0 - 1.0).abs() < 1e-12, "pv = {pv}: {} vs {w0}", f.radial.omega_rad_s);
        // No surface tension, no membrane: the shape modes are neutral.
        assert!(f.shape.iter().all(|m| m.omega_sq_nondim == 0.0), "{:?}", f.shape);
    }
    // The override still overrides.
    let s = free("reference_pressure = 2e5", &[]);
    let m = Model::from_scene(&s).unwrap();
    assert_eq!((m.groups().p_g0_pa, m.groups().p_g0_rule), (2e5, "override"));
}

/// Linearized Keller–Miksis at rest (no drive), derived by hand from
/// (1 − Ṙ/c)RR̈ + 3/2(1 − Ṙ/3c)Ṙ² = (1 + Ṙ/c)P/ρ + (R/ρc) dP/dt, dP/dt = P_R Ṙ + P_Ṙ R̈:
/// R̈ ≈ [P_R x + (P_Ṙ/ρ + R0 P_R/(ρc)) ẋ] / [R0 (1 + 4η/(ρcR0))], P_R = −3κp0/R0, P_Ṙ = −4η/R0.
/// So ω² = 3κp0/(ρR0² D), 2β = [4η/(ρR0²) + 3κp0/(ρcR0)]/D, D = 1 + 4η/(ρcR0); the
/// radiation part of β is ω0²R0/(2c) to O(1/c²).
#[test]
fn keller_miksis_linear_frequency_and_radiation_damping() {
    let s = free(&format!("[liquid]\nsound_speed = {C}"), &["modes.max_order=0"]);
    let m = Model::from_scene(&s).unwrap();
    assert!(m.active_effects()[0].contains("Keller-Miksis"));
    let (ts, sys) = (m.time_scale(), m.system());
    let mut jac = [0.0; 4];
    assert!(sys.jacobian(0.0, &[1.0, 0.0], &mut jac));
    let d = 1.0 + 4.0 * ETA / (RHO * C * R0);
    let w2 = 3.0 * KAPPA * P0 / (RHO * R0 * R0 * d);
    let two_beta = (4.0 * ETA / (RHO * R0 * R0) + 3.0 * KAPPA * P0 / (RHO * C * R0)) / d;
    assert!((-jac[2] / (ts * ts) / w2 - 1.0).abs() < 1e-12, "ω²: {} vs {w2}", -jac[2] / (ts * ts));
    assert!((-jac[3] / ts / two_beta - 1.0).abs() < 1e-12, "2β: {} vs {two_beta}", -jac[3] / ts);
    // Radiation damping ≈ ω0² R0 / (2c) (ω0 the incompressible one).
    let w0sq = 3.0 * KAPPA * P0 / (RHO * R0 * R0);
    let radiation = two_beta / 2.0 - 2.0 * ETA / (RHO * R0 * R0) / d;
    assert!((radiation / (w0sq * R0 / (2.0 * C)) - 1.0).abs() < 1e-3, "{radiation}");
    // Incompressible limit: no sound speed, no radiation.
    let m0 = Model::from_scene(&free("", &["modes.max_order=0"])).unwrap();
    let mut j0 = [0.0; 4];
    m0.system().jacobian(0.0, &[1.0, 0.0], &mut j0);
    let t0 = m0.time_scale();
    assert!((-j0[3] / t0 - 4.0 * ETA / (RHO * R0 * R0)).abs() < 1e-9 * two_beta);
}

/// KM right-hand side in SI, written independently of the model (free bubble, drive ε cos ωt,
/// vapour p_v): R̈ = [(1 + Ṙ/c)P/ρ + R Q/(ρc) − 3/2(1 − Ṙ/3c)Ṙ²] / [(1 − Ṙ/c)R + 4η/(ρc)],
/// Q = dP/dt without its R̈ part.
fn km_si(t: f64, y: [f64; 2], eps: f64, w: f64, pv: f64) -> [f64; 2] {
    let (r, v) = (y[0], y[1]);
    let pg = (P0 - pv) * (R0 / r).powf(3.0 * KAPPA);
    let p = pg + pv - P0 * (1.0 + eps * (w * t).cos()) - 4.0 * ETA * v / r;
    let q = -3.0 * KAPPA * pg * v / r + P0 * eps * w * (w * t).sin() + 4.0 * ETA * v * v / (r * r);
    let num = (1.0 + v / C) * p / RHO + r * q / (RHO * C) - 1.5 * (1.0 - v / (3.0 * C)) * v * v;
    [v, num / ((1.0 - v / C) * r + 4.0 * ETA / (RHO * C))]
}

#[test]
fn keller_miksis_time_series_matches_an_independent_rk4() {
    let (eps, f, pv) = (0.5, 3e5, 2330.0);
    let s = free(
        &format!("vapour_pressure = {pv}\n[liquid]\nsound_speed = {C}\n[drive]\namplitude = {eps}\nfrequency_hz = {f:e}"),
        &["modes.max_order=0", "run.duration=10e-6", "run.sample_interval=1e-7", "run.integrator.method=rk4", "run.integrator.dt=1e-10",
        ],
    );
    let mut rows = Vec::new();
    let rep = simulate(&s, &mut |t, row| rows.push((t, row[0]))).unwrap();
    assert_eq!(rep.status, RunStatus::Completed);
    // RK4 at dt = 1e-11 s (sample interval / 1e4).
    let w = 2.0 * std::f64::consts::PI * f;
    let (dt, per) = (1e-11, 10_000);
    let reference = rk4_at_rows(|t, y| km_si(t, y, eps, w, pv), R0, &rows, dt, per, 1e-15);
    let (mut worst, mut rmax) = (0.0f64, 0.0f64);
    for (&(_, r), y) in rows.iter().zip(reference) {
        worst = worst.max((r - y).abs() / R0);
        rmax = rmax.max(r / R0);
    }
    assert!(rmax > 1.3, "a nonlinear oscillation (max R/R0 = {rmax})");
    assert!(worst < 1e-7, "max |R - R_rk4|/R0 = {worst:e}");
}

/// The exact KM Jacobian (coated bubble, drive, viscosity) against central differences.
#[test]
fn keller_miksis_jacobian_matches_finite_differences() {
    let text = format!(
        "[bubble]\nradius = 10e-6\n[liquid]\nsound_speed = {C}\n[drive]\namplitude = 0.7\nfrequency_hz = 1e6\n[modes]\nmax_order = 4\n"
    );
    for overrides in [vec!["modes.max_order=0"], vec![]] {
        let s = scene::load_str(&text, "km (test)", &overrides).unwrap();
        let m = Model::from_scene(&s).unwrap();
        assert_jacobian_matches_fd(m.system(), &format!("{overrides:?}"));
    }
}

/// KM with a magnetic field and the vorticity closure is refused with the key named (dM0/dt
/// needs the closure's ḃ; the boundary-layer system provides it: tests/suite/km_field.rs).
#[test]
fn keller_miksis_with_a_field_and_vorticity_is_a_clear_error() {
    let text = format!("[liquid]\nsound_speed = {C}\n[field.coil]\ncurrent = 100e3\n[modes]\nmax_order = 4\nviscous = \"vorticity\"\n");
    let e = scene::load_str(&text, "km+field", &[] as &[&str]).unwrap_err().to_string();
    assert!(e.contains("liquid.sound_speed") && e.contains("vorticity"), "{e}");
    let ok = text.replace("viscous = \"vorticity\"\n", "");
    let s = scene::load_str(&ok, "km+field", &[] as &[&str]).unwrap();
    assert!(Model::from_scene(&s).is_ok());
}

#[test]
fn free_bubble_scene_rules() {
    let bad = scene::load_str("[shell]\nc1 = 0.0\nc2 = 0.1\n", "x", &[] as &[&str]).unwrap_err().to_string();
    assert!(bad.contains("shell.c2") && bad.contains("free bubble"), "{bad}");
    let bad = scene::load_str("[shell]\nc1 = 0.0\nc2 = 0.0\n[field.coil]\ncurrent = 1e5\n", "x", &[] as &[&str])
        .unwrap_err()
        .to_string();
    assert!(bad.contains("field"), "{bad}");
    let s = free("", &[]);
    let g = Model::from_scene(&s).unwrap().groups();
    assert!((g.t_star - R0 * (RHO / P0).sqrt()).abs() < 1e-20);
    assert!(g.p.is_none() && g.alpha.is_none());
    assert!((g.reynolds - R0 * (RHO * P0).sqrt() / ETA).abs() < 1e-12 * g.reynolds);
}

/// Every command on the shipped free-bubble scene (R0 = 5 µm, κ = 1.4, p_v = 2330 Pa, ε_p = 0.2
/// at 500 kHz, k = 2…8, no surface tension), from the command line, and what each writes:
/// `run`: R(t) of series.csv against an RK4 integration of the Rayleigh–Plesset equation written
/// here (free bubble: the radial equation does not see the shape modes without a field);
/// `modes`: ω0 = √(3κ(p0 − p_v)/(ρR0²)) and neutral shape modes (no restoring force);
/// `modes --damped`: the same neutrality of the damped spectrum; `floquet`: one multiplier per
/// (a, ȧ) of each simulated mode (the free bubble's neutral b_k blocks left out), below 1 at this
/// drive, over the drive period; `stability`: each point brackets max|μ| = 1 and the threshold
/// is lower near the radial resonance (649 kHz) than below it; `accuracy`: the RK4 ladder shows
/// order 4.
#[test]
fn every_command_runs_on_the_free_bubble_scene() {
    let exe = env!("CARGO_BIN_EXE_magbubble");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/free_bubble.toml");
    let dir = std::env::temp_dir().join(format!("magbubble-liquid-{}", std::process::id()));
    let d = |s: &str| dir.join(s).display().to_string();
    let run = |args: &[&str]| {
        let out = Command::new(exe).args(args).output().unwrap();
        assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8(out.stdout).unwrap()
    };
    let (r0, pv, eps, f) = (5e-6, 2330.0, 0.2, 5e5);

    // run: R(t) against Rayleigh–Plesset, R̈ = [p_v + p_g0 (R0/R)^{3κ} − p0(1 + ε cos ωt) − 4ηṘ/R]/(ρR) − 3Ṙ²/(2R)
    run(&["run", scene, "--out", &d("run"), "--set", "run.duration=2e-6"]);
    let csv = std::fs::read_to_string(dir.join("run/series.csv")).unwrap();
    assert!(csv.starts_with("t,R,a2,b2,a4,b4,a6,b6,a8,b8\n"), "{}", csv.lines().next().unwrap_or(""));
    let rows: Vec<(f64, f64)> = csv.lines().skip(1).map(|l| {
        let mut c = l.split(',').map(|x| x.parse::<f64>().unwrap());
        (c.next().unwrap(), c.next().unwrap())
    }).collect();
    assert_eq!(rows.len(), 201, "2 µs sampled every 10 ns");
    let w = 2.0 * std::f64::consts::PI * f;
    let rp = |t: f64, y: [f64; 2]| {
        let (r, v) = (y[0], y[1]);
        let p = (P0 - pv) * (r0 / r).powf(3.0 * KAPPA) + pv - P0 * (1.0 + eps * (w * t).cos()) - 4.0 * ETA * v / r;
        [v, p / (RHO * r) - 1.5 * v * v / r]
    };
    let reference = rk4_at_rows(rp, r0, &rows, 1e-11, 1000, 1e-15);
    let worst = rows.iter().zip(&reference).map(|(&(_, r), y)| (r - y).abs() / r0).fold(0.0, f64::max);
    let swing = rows.iter().map(|&(_, r)| (r - r0).abs() / r0).fold(0.0, f64::max);
    assert!(swing > 1e-2 && worst < 1e-6 * swing.max(1.0), "max |R − R_RP|/R0 = {worst:e} (swing {swing:e})");

    // modes: the closed-form radial frequency, neutral shape modes
    let modes: serde_json::Value = serde_json::from_str(&run(&["modes", scene, "--json"])).unwrap();
    let w0 = (3.0 * KAPPA * (P0 - pv) / (RHO * r0 * r0)).sqrt();
    let got = modes["radial"]["omega_rad_s"].as_f64().unwrap();
    assert!((got / w0 - 1.0).abs() < 1e-12, "ω0 {got} vs {w0}");
    let shape = modes["shape"].as_array().unwrap();
    assert_eq!(shape.iter().map(|m| m["k"].as_u64().unwrap()).collect::<Vec<_>>(), (2..=8).collect::<Vec<_>>());
    assert!(shape.iter().all(|m| m["omega_rad_s"].as_f64() == Some(0.0)), "no restoring force: {shape:?}");

    // modes --damped: k = 2, 4, 6, 8, each s = 0 (the slowest root of a mode without stiffness)
    let damped = run(&["modes", scene, "--damped"]);
    let table: Vec<Vec<f64>> = damped.lines().skip(2).map(|l| l.split_whitespace().take(3).map(|x| x.parse().unwrap()).collect()).collect();
    assert_eq!(table.iter().map(|r| r[0]).collect::<Vec<_>>(), [2.0, 4.0, 6.0, 8.0], "{damped}");
    assert!(table.iter().all(|r| r[1] == 0.0 && r[2] == 0.0), "{damped}");

    // floquet: (a, ȧ) multipliers of the 4 even modes over one drive period, stable at ε_p = 0.2
    let fl: serde_json::Value = serde_json::from_str(&run(&["floquet", scene, "--json"])).unwrap();
    assert_eq!(fl["drive_period_s"].as_f64(), Some(1.0 / f));
    assert_eq!(fl["convergence"]["converged"].as_bool(), Some(true));
    let mu: Vec<f64> = fl["multipliers"].as_array().unwrap().iter().map(|z| z[0].as_f64().unwrap().hypot(z[1].as_f64().unwrap())).collect();
    assert_eq!(mu.len(), 2 * 4, "{mu:?}");
    let max = mu.iter().copied().fold(0.0, f64::max);
    let reported = fl["max_multiplier"].as_f64().unwrap();
    assert!(max < 1.0 && (max - reported).abs() <= 1e-12 * reported, "{mu:?} vs max_multiplier {reported}");

    // stability: two frequencies, each a bracket of max|μ| = 1; lower threshold near resonance
    run(&["stability", scene, "--freq", "4e5:6e5:2", "--out", &d("stab"), "--set", "modes.max_order=4"]);
    let st = std::fs::read_to_string(dir.join("stab/stability.csv")).unwrap();
    let head: Vec<&str> = st.lines().next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap_or_else(|| panic!("column {name}"));
    let pts: Vec<Vec<String>> = st.lines().skip(1).map(|l| l.split(',').map(String::from).collect()).collect();
    assert_eq!(pts.len(), 2);
    let num = |p: &Vec<String>, name: &str| p[col(name)].parse::<f64>().unwrap();
    for p in &pts {
        assert_eq!(p[col("outcome")], "critical", "{p:?}");
        let (lo, hi) = (num(p, "stable"), num(p, "unstable"));
        assert!(lo < hi && (hi - lo) < 1e-3 * hi && (lo..=hi).contains(&num(p, "critical")), "{p:?}");
        assert!(num(p, "max_multiplier_stable") <= 1.0 && num(p, "max_multiplier_unstable") > 1.0, "{p:?}");
    }
    assert!(num(&pts[1], "critical") < num(&pts[0], "critical"), "600 kHz (near ω0) less stable than 400 kHz: {st}");

    // accuracy: the RK4 rungs converge at order 4
    run(&["accuracy", scene, "--quick", "--out", &d("acc")]);
    let acc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("acc/accuracy.json")).unwrap()).unwrap();
    let rk4 = acc["ladders"].as_array().unwrap().iter().find(|l| l["method"] == "rk4").expect("an RK4 ladder");
    let rungs: Vec<(f64, f64)> = rk4["rungs"].as_array().unwrap().iter().map(|r| (r["setting"].as_f64().unwrap(), r["error"].as_f64().unwrap())).collect();
    assert!(rungs.len() >= 2);
    for p in rungs.windows(2) {
        let order = (p[0].1 / p[1].1).ln() / (p[0].0 / p[1].0).ln();
        assert!((3.6..4.4).contains(&order), "RK4 observed order {order} ({rungs:?})");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
