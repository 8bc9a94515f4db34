//! Issue 29 item 5: `bubble.initial.seed = "thermal"` (docs/model.md, "Thermal seed") and the
//! per-mode error weights (runtime/model/thermal.rs), so that a blow-up time does not depend on
//! the integrator.
use magbubble::model::{thermal, Model, RunStatus};
use magbubble::scene::{self, Scene};
use std::f64::consts::PI;

const KB: f64 = 1.380649e-23;

fn load(path: &str, set: &[&str]) -> Scene {
    scene::load(path, set).unwrap()
}

/// a_th,k = √(k_B T/K_k) by hand: K_k = m_k ω_k², m_k = 4πρR0³/((k+1)(2k+1)), with the closed
/// forms of ω_k² (membrane: docs/model.md §4.4; free bubble: Lamb's).
#[test]
fn thermal_amplitudes_match_the_hand_computation() {
    // the paper's membrane, no field: K_k = 48π(c1+c2)(k−1)(k+2)/[(2k+1)(2k²+2k−1)]
    let s = load("scenes/no_field.toml", &["bubble.initial.seed=\"thermal\"", "liquid.temperature=310", "modes.max_order=8"]);
    let th = thermal::amplitudes(&s).unwrap();
    for (k, a) in &th {
        let kf = *k as f64;
        let stiffness = 48.0 * PI * (0.1 + 0.12) * (kf - 1.0) * (kf + 2.0) / ((2.0 * kf + 1.0) * (2.0 * kf * kf + 2.0 * kf - 1.0));
        let hand = (KB * 310.0 / stiffness).sqrt();
        eprintln!("membrane k = {k}: a_th = {a:.6e} m, by hand {hand:.6e} m");
        assert!((a / hand - 1.0).abs() < 1e-9, "k = {k}: {a} vs {hand}");
    }
    // 293.15 K by default; k = 2 of the paper's bubble: 4.1e-11 m
    let s = load("scenes/no_field.toml", &["bubble.initial.seed=\"thermal\"", "modes.max_order=2"]);
    let a2 = thermal::amplitudes(&s).unwrap()[&2];
    let hand = (KB * 293.15 / (48.0 * PI * 0.22 * 4.0 / (5.0 * 11.0))).sqrt();
    assert!((a2 / hand - 1.0).abs() < 1e-9 && (a2 - 4.1e-11).abs() < 1e-12, "{a2} vs {hand}");
    // a free bubble with surface tension γ: K_k = 4πγ(k−1)(k+2)/(2k+1), the surface energy
    let s = load("scenes/free_bubble.toml", &["bubble.initial.seed=\"thermal\"", "shell.surface_tension=0.072", "drive.amplitude=0"]);
    for (k, a) in thermal::amplitudes(&s).unwrap() {
        let kf = k as f64;
        let hand = (KB * 293.15 * (2.0 * kf + 1.0) / (4.0 * PI * 0.072 * (kf - 1.0) * (kf + 2.0))).sqrt();
        eprintln!("free bubble k = {k}: a_th = {a:.6e} m, by hand {hand:.6e} m");
        assert!((a / hand - 1.0).abs() < 1e-6, "k = {k}: {a} vs {hand}");
    }
}

#[test]
fn the_thermal_seed_starts_every_unset_mode_and_keeps_the_given_ones() {
    let s = load("scenes/no_field.toml", &["bubble.initial.seed=\"thermal\"", "modes.max_order=6"]);
    let th = thermal::amplitudes(&s).unwrap();
    let m = Model::from_scene(&s).unwrap();
    let y0 = m.initial_state();
    let r0 = s.bubble.radius;
    // a_2 is set in the scene (1e-8 m) and stays; a_4, a_6 start thermal
    assert_eq!(y0[2] * r0, 1e-8);
    assert!((y0[5] * r0 / th[&4] - 1.0).abs() < 1e-12 && (y0[8] * r0 / th[&6] - 1.0).abs() < 1e-12);
    // the default is the given seed: a_4 = 0
    let g = Model::from_scene(&load("scenes/no_field.toml", &["modes.max_order=6"])).unwrap();
    assert_eq!(g.initial_state()[5], 0.0);
    // error weights: R, Ṙ at 1; a seeded mode at its seed/R0; an unseeded one at ε²
    let w = g.system().error_scale().unwrap();
    assert_eq!(&w[..2], &[1.0, 1.0]);
    assert_eq!(w[2], 1e-8 / r0);
    assert_eq!(w[5], thermal::UNSEEDED);
    let w = m.system().error_scale().unwrap();
    assert!((w[5] - th[&4] / r0).abs() < 1e-20);
    // a mode the field forces at rest has the weight of its static response |f_k|/ω_k²
    let c = Model::from_scene(&load("scenes/coil_static.toml", &[])).unwrap();
    let w = c.system().error_scale().unwrap();
    let w16 = w[2 + 3 * 7];
    eprintln!("coil_static weights: a4 {:.3e}, a16 {w16:.3e}", w[5]);
    assert!(w16 > thermal::UNSEEDED && w16 < 1e-20 && w[5] > w16, "{w:?}");
    // no stiffness (a free bubble without surface tension): an error naming the key
    let e = Model::from_scene(&load("scenes/free_bubble.toml", &["bubble.initial.seed=\"thermal\"", "shell.surface_tension=0"])).unwrap_err();
    assert!(e.to_string().contains("bubble.initial.seed") && e.to_string().contains("stiffness"), "{e}");
}

fn blow_up_time(s: &Scene) -> (f64, String) {
    let m = Model::from_scene(s).unwrap();
    match m.run(&s.run, &mut |_, _| {}).status {
        RunStatus::BlowUp { t, mode } => (t, mode),
        other => panic!("expected a blow-up: {other:?}"),
    }
}

/// Every method at its default tolerance gives the same blow-up time within 1 % (before the
/// weights: Dopri5 10.54 µs, Dop853 12.46 µs, Radau5 20.57 µs on coil_static.toml).
#[test]
fn the_blow_up_time_does_not_depend_on_the_integrator() {
    for path in ["scenes/coil_static.toml", "scenes/coil_ac_current.toml", "scenes/coil_oscillating_distance.toml", "scenes/dipole.toml"] {
        let reference = blow_up_time(&load(path, &[]));
        for m in ["dopri5", "dop853", "rosenbrock23"] {
            let (t, mode) = blow_up_time(&load(path, &[&format!("run.integrator.method=\"{m}\"")]));
            eprintln!("{path} {m}: blow-up of {mode} at {:.4} µs (radau5 {:.4} µs, {})", t * 1e6, reference.0 * 1e6, reference.1);
            assert!((t / reference.0 - 1.0).abs() < 0.01, "{path} {m}: {t} vs {}", reference.0);
            assert_eq!(mode, reference.1);
        }
    }
    // RK4 at the reference step
    let s = load("scenes/coil_static.toml", &["run.integrator.method=\"rk4\"", "run.integrator.dt=1e-10"]);
    let (t, _) = blow_up_time(&s);
    let r = blow_up_time(&load("scenes/coil_static.toml", &[])).0;
    assert!((t / r - 1.0).abs() < 0.01, "rk4 {t} vs radau5 {r}");
}

#[test]
fn a_thermal_seed_gives_a_blow_up_time_every_method_agrees_on() {
    let set = |m: &str| vec!["bubble.initial.seed=\"thermal\"".to_string(), format!("run.integrator.method=\"{m}\"")];
    let path = "scenes/coil_static.toml";
    let sc = |m: &str| scene::load(path, &set(m)).unwrap();
    let (r, mode) = blow_up_time(&sc("radau5"));
    eprintln!("thermal seed: blow-up of {mode} at {:.4} µs", r * 1e6);
    for m in ["dopri5", "dop853", "rosenbrock23"] {
        let (t, _) = blow_up_time(&sc(m));
        assert!((t / r - 1.0).abs() < 0.01, "{m}: {t} vs {r}");
    }
}
