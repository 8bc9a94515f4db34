//! Physics tests of the boundary-layer model (issue 3): linearizations of FORMULATION §4.1/§4.3
//! computed here, independently of the model's code, and compared with simulated runs.
//! Run with `cargo test --release --test physics_bl`.

use std::collections::BTreeMap;

use magbubble::coefficients::{membrane, Amp, Load, COIL, KMAX};
use magbubble::field::{coil, MU0};
use magbubble::model::{Model, RunStatus};
use magbubble::scene::*;
use nalgebra::{DMatrix, DVector, Matrix3};
use crate::common::water::*;
use crate::common::{C1, C2, R0};


fn scene(max_order: usize, dt: f64, duration: f64, sample: f64) -> Scene {
    Scene {
        bubble: Bubble {
            radius: R0,
            initial: Initial { radius: R0, velocity: 0.0, a: BTreeMap::new(), a_velocity: BTreeMap::new(), b: BTreeMap::new(), seed: Default::default() },
        },
        shell: Shell::mooney_rivlin(C1, C2, 20e-9, 1.0, MembraneForm::Paper),
        gas: Gas { polytropic_exponent: KAPPA, reference_pressure: P0, reference_pressure_given: true, vapour_pressure: 0.0, thermal: Thermal::Polytropic },
        liquid: Liquid { density: RHO, viscosity: ETA, ambient_pressure: P0, sound_speed: None, temperature: 293.15 },
        drive: None,
        field: None,
        modes: Modes { max_order, viscous: Viscous::BoundaryLayer, boundary_layer_frequency: BoundaryLayerFrequency::Auto, coupling: Coupling::Linear, credible_amplitude: 0.1 },
        vorticity: VorticityGrid { y_max: 2.0, points: 200, stretching: 1.0, scheme: VorticityScheme::Monolithic },
        run: Run {
            duration,
            sample_interval: sample,
            integrator: IntegratorSettings { method: Method::Rk4, rtol: 1e-8, atol: 1e-12, dt, dt_given: true, max_steps: 100_000_000 },
            blow_up_threshold: 0.5,
            max_output_bytes: 1e9,
        },
        warnings: Vec::new(),
        echo: None,
        population: None,
    }
}

/// Runs and returns (t, rows).
fn run(s: &Scene) -> (Model, Vec<f64>, Vec<Vec<f64>>) {
    let model = Model::from_scene(s).expect("model");
    let (mut t, mut rows) = (vec![], vec![]);
    let rep = model.run(&s.run, &mut |ti, row| {
        t.push(ti);
        rows.push(row.to_vec());
    });
    assert_eq!(rep.status, RunStatus::Completed, "{rep:?}");
    (model, t, rows)
}

/// Zero crossings (linear interpolation) of x(t).
fn crossings(t: &[f64], x: &[f64]) -> Vec<f64> {
    (1..x.len())
        .filter(|&i| x[i - 1] != 0.0 && x[i - 1].signum() != x[i].signum())
        .map(|i| t[i - 1] + (t[i] - t[i - 1]) * x[i - 1] / (x[i - 1] - x[i]))
        .collect()
}

/// Positive local maxima of x(t), refined by a parabola through three samples.
fn peaks(t: &[f64], x: &[f64]) -> Vec<(f64, f64)> {
    (1..x.len() - 1)
        .filter(|&i| x[i] > 0.0 && x[i] >= x[i - 1] && x[i] > x[i + 1])
        .map(|i| {
            let (a, b, c) = (x[i - 1], x[i], x[i + 1]);
            let h = t[i] - t[i - 1];
            let d = 0.5 * (a - c) / (a - 2.0 * b + c);
            (t[i] + d * h, b - 0.25 * (a - c) * d)
        })
        .collect()
}

/// (angular frequency, envelope decay rate) of a damped oscillation, after `t_skip`.
fn measure(t: &[f64], x: &[f64], t_skip: f64) -> (f64, f64) {
    let i0 = t.iter().position(|&ti| ti >= t_skip).unwrap();
    let (t, x) = (&t[i0..], &x[i0..]);
    let z = crossings(t, x);
    assert!(z.len() > 6, "too few crossings: {}", z.len());
    let omega = std::f64::consts::PI * (z.len() - 1) as f64 / (z[z.len() - 1] - z[0]);
    let p = peaks(t, x);
    assert!(p.len() > 3, "too few peaks");
    let (first, last) = (p[0], p[p.len() - 1]);
    let gamma = -(last.1 / first.1).ln() / (last.0 - first.0);
    (omega, gamma)
}

#[test]
fn small_free_radial_oscillation_matches_linearization() {
    let mut s = scene(0, 1e-9, 20e-6, 5e-9);
    s.bubble.initial.radius = R0 * (1.0 + 1e-4);
    let (_, t, rows) = run(&s);
    let x: Vec<f64> = rows.iter().map(|r| r[0] / R0 - 1.0).collect();
    let (omega, gamma) = measure(&t, &x, 0.0);
    // FORMULATION §4.1 linearized: ω0² = [3κp0 + 24(c1+c2)/R0]/(ρR0²), γ = 2η/(ρR0²).
    let w0sq = (3.0 * KAPPA * P0 + 24.0 * (C1 + C2) / R0) / (RHO * R0 * R0);
    let g = 2.0 * ETA / (RHO * R0 * R0);
    let wd = (w0sq - g * g).sqrt();
    eprintln!("radial: omega {omega:.6e} vs {wd:.6e} ({:.2e}), gamma {gamma:.6e} vs {g:.6e} ({:.2e})",
        omega / wd - 1.0, gamma / g - 1.0);
    assert!((omega / wd - 1.0).abs() < 5e-3);
    assert!((gamma / g - 1.0).abs() < 5e-3);
}

/// The 3×3 linear (a, ȧ, b) system of mode k at R0, Ṙ = R̈ = 0, no field, from the
/// coefficients of (3.2) as given in FORMULATION §4.3 (C_a1, C_b1, C_a, C_b, D_a1, D_b1, D_a, D_b).
fn linear_mode_matrix(k: f64, delta: f64) -> Matrix3<f64> {
    let (r, nu) = (R0, ETA / RHO);
    let s1 = membrane::paper::s1(r, R0, C1, C2, k);
    let s2 = membrane::paper::s2(r, R0, C1, C2, k);
    let s11 = membrane::paper::s11(r, R0, C1, C2, k);
    let s12 = membrane::paper::s12(r, R0, C1, C2, k);
    let ca1 = k * nu / (r * delta) + 4.0 * (k + 1.0) * nu / (r * r);
    let cb1 = k * (k + 1.0) * nu / (r * delta) - 2.0 * k * (k + 1.0).powi(2) * nu / (r * r);
    let ca = (k + 1.0) * s1 / (RHO * r);
    let cb = (k + 1.0) * s2 / (RHO * r);
    let da1 = -nu / ((k + 1.0) * r * delta) + 2.0 * nu / (r * r);
    let db1 = -nu / (r * delta) - 2.0 * nu / (r * r);
    let da = -s11 / (RHO * r);
    let db = -s12 / (RHO * r);
    // ḃ = −(D_a1 ȧ + D_a a + D_b b)/D_b1 ;  ä = −C_a1 ȧ − C_b1 ḃ − C_a a − C_b b
    let (bd_a, bd_ad, bd_b) = (-da / db1, -da1 / db1, -db / db1);
    Matrix3::new(
        0.0, 1.0, 0.0,
        -ca - cb1 * bd_a, -ca1 - cb1 * bd_ad, -cb - cb1 * bd_b,
        bd_a, bd_ad, bd_b,
    )
}

#[test]
fn free_decay_of_a2_matches_boundary_layer_eigenvalues() {
    let mut s = scene(2, 2e-9, 60e-6, 10e-9);
    s.bubble.initial.a.insert(2, 1e-3 * R0);
    let (_, t, rows) = run(&s);
    // R stays at R0 exactly (no field: the radial equation does not see a_k).
    assert!(rows.iter().all(|r| r[0] == R0));
    let a2: Vec<f64> = rows.iter().map(|r| r[1]).collect();
    let (omega, gamma) = measure(&t, &a2, 1e-6);
    // δ_2 with ω = ω_2 of §4.4 (no drive).
    let k = 2.0;
    let w2 = (12.0 * (C1 + C2) * (k - 1.0) * (k + 1.0) * (k + 2.0) / (RHO * R0.powi(3) * (2.0 * k * k + 2.0 * k - 1.0))).sqrt();
    let delta = (ETA / RHO / w2).sqrt().min(R0 / (2.0 * k));
    let ev = linear_mode_matrix(k, delta).complex_eigenvalues();
    let osc = ev.iter().find(|z| z.im > 0.0).expect("an oscillatory pair");
    eprintln!("a2: eigenvalues {ev:?}");
    eprintln!("a2: omega {omega:.6e} vs {:.6e} ({:.2e}), gamma {gamma:.6e} vs {:.6e} ({:.2e})",
        osc.im, omega / osc.im - 1.0, -osc.re, gamma / -osc.re - 1.0);
    assert!((omega / osc.im - 1.0).abs() < 1e-2);
    assert!((gamma / -osc.re - 1.0).abs() < 1e-2);
}

#[test]
fn rest_state_stays_at_rest() {
    let s = scene(16, 0.5e-9, 5e-6, 50e-9);
    let (model, _, rows) = run(&s);
    assert_eq!(model.magnetic_evaluations(), 0);
    for r in &rows {
        assert!((r[0] / R0 - 1.0).abs() <= 1e-15, "R drifted: {}", r[0]);
        assert!(r[1..].iter().all(|v| v.abs() <= 1e-30 * R0), "shape modes moved: {r:?}");
    }
}

/// Static equilibrium of the full system with a static coil, solved here from the tables:
/// radial balance p_g0 (R0/R)^{3κ} − p0 − Ŝ0(R) + M0 = 0 and, per mode (ḃ = ä = 0 ⇒ T_w = 0),
/// Ŝ1 a + Ŝ2 b = M_n,k, Ŝ11 a + Ŝ12 b = M_t,k. Returns (R, [a_k, b_k]...).
fn static_coil_equilibrium(current: f64, n: usize) -> (f64, Vec<f64>) {
    let h2 = coil::h2(current, 0.1, 1000.0, (3.0f64 / 7.0).sqrt().acos());
    let chi_s = 20e-9 * 1.0;
    let m = n / 2;
    let mut r = R0;
    let mut x = DVector::<f64>::zeros(2 * m);
    for _ in 0..20 {
        // Loads from the tables: Σ_c ℋ_c [R^m zero + R^(m−1) Σ value·amp].
        let mut mat = DMatrix::<f64>::zeros(2 * m, 2 * m);
        let mut rhs = DVector::<f64>::zeros(2 * m);
        let mut m0 = 0.0;
        for c in COIL.components {
            let mut hc = c.prefactor.coeff;
            for &(sym, p) in c.prefactor.powers {
                hc *= match sym {
                    "mu0" => MU0,
                    "chi_s" => chi_s,
                    "H2" => h2,
                    "H4" => 0.0,
                    "a" => 0.1,
                    "R0" => R0,
                    "R" => r,
                    other => panic!("symbol {other}"),
                }
                .powi(p);
            }
            let zf = hc * r.powi(c.r_power);
            let cf = hc * r.powi(c.r_power - 1);
            for &(j, v) in c.zero_normal {
                if j == 0 {
                    m0 += zf * v;
                } else if j % 2 == 0 && j / 2 <= m {
                    rhs[2 * (j / 2 - 1)] += zf * v;
                }
            }
            for &(j, v) in c.zero_tangential {
                if j >= 2 && j % 2 == 0 && j / 2 <= m {
                    rhs[2 * (j / 2 - 1) + 1] += zf * v;
                }
            }
            for cp in c.couplings {
                for k in (0..=n.min(KMAX)).step_by(2) {
                    let Some(v) = cp.values[k] else { continue };
                    let src = k as i64 + cp.offset as i64;
                    if src < 2 || src > n as i64 {
                        continue;
                    }
                    let col = 2 * (src as usize / 2 - 1) + matches!(cp.amp, Amp::B) as usize;
                    if k == 0 {
                        if cp.load == Load::Normal {
                            m0 += cf * v * x[col];
                        }
                        continue;
                    }
                    let row = 2 * (k / 2 - 1) + (cp.load == Load::Tangential) as usize;
                    mat[(row, col)] -= cf * v; // moved to the left-hand side
                }
            }
        }
        for i in 0..m {
            let k = 2.0 * (i + 1) as f64;
            mat[(2 * i, 2 * i)] += membrane::paper::s1(r, R0, C1, C2, k);
            mat[(2 * i, 2 * i + 1)] += membrane::paper::s2(r, R0, C1, C2, k);
            mat[(2 * i + 1, 2 * i)] += membrane::paper::s11(r, R0, C1, C2, k);
            mat[(2 * i + 1, 2 * i + 1)] += membrane::paper::s12(r, R0, C1, C2, k);
        }
        x = mat.lu().solve(&rhs).expect("static system solvable");
        // Newton on the radial balance with M0 frozen.
        for _ in 0..5 {
            let f = |r: f64| P0 * (R0 / r).powf(3.0 * KAPPA) - P0 - membrane::paper::s0(r, R0, C1, C2) + m0;
            let h = 1e-6 * R0;
            r -= f(r) / ((f(r + h) - f(r - h)) / (2.0 * h));
        }
    }
    (r, x.iter().copied().collect())
}

#[test]
fn static_coil_gives_the_predicted_steady_a2() {
    let n = 6;
    let (r_eq, ab) = static_coil_equilibrium(100e3, n);
    let mut s = scene(n, 2e-9, 150e-6, 20e-9);
    s.field = Some(crate::common::coil(100e3));
    let (model, t, rows) = run(&s);
    assert!(model.magnetic_evaluations() > 0);
    // average over the last 10 µs (residual transient oscillations average out)
    let i0 = t.iter().position(|&ti| ti >= t[t.len() - 1] - 10e-6).unwrap();
    let avg = |c: usize| rows[i0..].iter().map(|r| r[c]).sum::<f64>() / (rows.len() - i0) as f64;
    let (a2, b2, r) = (avg(1), avg(2), avg(0));
    eprintln!("static coil: R {r:.9e} vs {r_eq:.9e}; a2 {a2:.6e} vs {:.6e}; b2 {b2:.6e} vs {:.6e}", ab[0], ab[1]);
    assert!(ab[0] != 0.0 && a2.signum() == ab[0].signum(), "sign of a2");
    assert!((a2 / ab[0] - 1.0).abs() < 1e-4, "a2 {a2} vs {}", ab[0]);
    assert!((b2 / ab[1] - 1.0).abs() < 1e-4, "b2 {b2} vs {}", ab[1]);
    assert!((r / r_eq - 1.0).abs() < 1e-7);
}

#[test]
fn no_field_equals_zero_current_coil_and_evaluates_no_magnetic_term() {
    let mut s = scene(4, 2e-9, 10e-6, 20e-9);
    s.drive = Some(Drive::cosine(0.3, 1e6));
    s.bubble.initial.a.insert(2, 1e-8);
    let (m_plain, _, plain) = run(&s);
    s.field = Some(crate::common::coil(0.0));
    let (m_coil, _, coil) = run(&s);
    assert_eq!(m_plain.magnetic_evaluations(), 0);
    assert!(m_coil.magnetic_evaluations() > 0);
    assert_eq!(plain.len(), coil.len());
    let scale: Vec<f64> = (0..plain[0].len()).map(|c| plain.iter().map(|r| r[c].abs()).fold(0.0, f64::max)).collect();
    for (p, c) in plain.iter().zip(&coil) {
        for j in 0..p.len() {
            assert!((p[j] - c[j]).abs() <= 1e-12 * scale[j], "column {j}: {} vs {}", p[j], c[j]);
        }
    }
    assert!(m_coil.active_effects().iter().any(|e| e.starts_with("coil field")));
    assert!(!m_plain.active_effects().iter().any(|e| e.contains("field")));
}

#[test]
fn radial_only_scene_is_a_two_state_system() {
    let s = scene(0, 1e-9, 1e-6, 1e-7);
    let m = Model::from_scene(&s).unwrap();
    assert_eq!(m.system().dim(), 2);
    assert_eq!(m.active_effects(), vec!["radial".to_string()]);
    assert_eq!(m.state_names(), vec!["R".to_string()]);
    let m16 = Model::from_scene(&scene(16, 1e-9, 1e-6, 1e-7)).unwrap();
    assert_eq!(m16.system().dim(), 2 + 3 * 8);
    assert_eq!(m16.state_names().len(), 1 + 2 * 8);
}

#[test]
fn groups_follow_their_definitions() {
    let mut s = scene(16, 1e-9, 1e-6, 1e-7);
    s.field = Some(crate::common::coil(100e3));
    s.drive = Some(Drive::cosine(0.5, 1e6));
    let g = Model::from_scene(&s).unwrap().groups();
    let h2 = coil::h2(100e3, 0.1, 1000.0, (3.0f64 / 7.0).sqrt().acos());
    let rn = MU0 * 20e-9 * h2 * h2 * R0 * R0 / (2.0 * C1 * 0.01);
    let t_star = (RHO * R0.powi(3) / (2.0 * C1)).sqrt();
    eprintln!("groups: {g:?}");
    assert!((g.t_star / t_star - 1.0).abs() < 1e-14);
    assert!((g.reynolds / ((2.0 * RHO * C1 * R0).sqrt() / ETA) - 1.0).abs() < 1e-14);
    assert!((g.p.unwrap() / (P0 * R0 / C1) - 1.0).abs() < 1e-14);
    assert!((g.alpha.unwrap() - C2 / C1).abs() < 1e-14);
    assert!((g.rn.unwrap() / rn - 1.0).abs() < 1e-12);
    assert!(g.mn.is_none());
    assert!((g.omega_d_star.unwrap() / (2.0 * std::f64::consts::PI * 1e6 * t_star) - 1.0).abs() < 1e-14);
    // The membrane stiffness of k = 16 turns negative under 10 % compression (docs/model.md).
    assert!(membrane::paper::s1(0.9 * R0, R0, C1, C2, 16.0) < 0.0);
    assert!(membrane::paper::s1(R0, R0, C1, C2, 16.0) > 0.0);
}
