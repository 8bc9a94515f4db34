//! Issue 13 part 4: Floquet on the full vorticity model (analysis/floquet_full.rs).
//!
//! Three checks that could each fail on their own:
//! 1. at rest (no drive) the monodromy over t* has the multipliers exp(s t*) of the discrete
//!    dispersion roots s of the same grid (model/vorticity/linear.rs, found independently by a
//!    secant search on φ_d(s));
//! 2. driven (ε_p = 0.3, 1 MHz, k ≤ 8, no field): a full-model time-domain run seeded with a
//!    tiny a_8 and started on the radial orbit grows per drive period by max|μ| per drive
//!    period (measured 3e-7 relative; asserted 1e-5, the issue asks 1 %);
//! 3. the inviscid limit: boundary-layer and full max|μ| approach each other as η → 0.

use super::common;
use magbubble::analysis::stability::{floquet, FloquetOptions, FloquetReport};
use magbubble::model::vorticity::scene::{damped_spectrum, simulate_full};
use magbubble::analysis::periodic::{find_orbit, ShootingOptions};
use magbubble::analysis::stability::Radial;
use magbubble::model::{Model, RunStatus};
use magbubble::scene::{Method, Scene, Viscous, VorticityGrid, VorticityScheme};

fn full(mut s: Scene, points: usize) -> Scene {
    s.modes.viscous = Viscous::Vorticity;
    s.vorticity = VorticityGrid { y_max: 3.0, points, stretching: 20.0, scheme: VorticityScheme::Monolithic };
    s
}

fn report(s: &Scene, steps: usize) -> FloquetReport {
    let opts = FloquetOptions { magnus_steps: steps, ..FloquetOptions::default() };
    floquet(s, &opts).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn at_rest_the_multipliers_are_the_discrete_dispersion_roots() {
    let mut s = full(common::scene(6, 0.0, 1e6), 81);
    s.drive = None;
    let spectrum = damped_spectrum(&s).unwrap();
    assert_eq!(spectrum.closure, "vorticity");
    // Distance of exp(s t*) to the nearest multiplier, relative to |exp(s t*)|, per k.
    let errors = |steps: usize| -> Vec<f64> {
        let r = report(&s, steps);
        assert_eq!(r.closure, "vorticity");
        assert!(r.drive_period_s.is_none());
        // Undriven, at rest: nothing grows.
        assert!(!r.unstable && r.max_multiplier < 1.0, "{}", r.max_multiplier);
        let t = r.period_s; // t*
        spectrum
            .shape
            .iter()
            .map(|d| {
                let (re, im) = (-d.decay_per_s * t, d.omega_rad_s * t);
                let e = (re.exp() * im.cos(), re.exp() * im.sin());
                let nearest = r.multipliers.iter().map(|z| (z[0] - e.0).hypot(z[1] - e.1)).fold(f64::INFINITY, f64::min);
                nearest / re.exp()
            })
            .collect()
    };
    let (coarse, fine) = (errors(100), errors(200));
    for (k, (c, f)) in coarse.iter().zip(&fine).enumerate() {
        // SDIRK4: fourth order (ratio 16 for halved steps), 1e-8 at 200 steps per t*.
        assert!(*f < 1e-8 && c / f > 10.0, "k = {}: relative error {c:e} (100 steps), {f:e} (200 steps)", 2 * k + 2);
    }
}

#[test]
fn a_full_model_run_grows_by_the_full_model_multiplier() {
    let mut s = full(common::scene(8, 0.3, 1e6), 101);
    let r = report(&s, 64);
    assert_eq!((r.mode, r.orbit_multiple), (8, 1), "{r:?}");
    let mu = r.max_multiplier_per_drive_period;
    assert!(mu > 1.2, "the full model is unstable here (1.29 on the default grid): {mu}");
    // Start the run on the radial orbit (the radial transient decays over ≈ 50 µs and modulates
    // the growth by ±5 % meanwhile), seeded with a_8 only (no field: modes do not couple).
    let model = Model::from_scene(&common::scene(8, 0.3, 1e6)).unwrap();
    let radial = Radial::of(&model).unwrap();
    let ts = model.time_scale();
    let opts = ShootingOptions { transient_time: 100e-6 / ts, ..ShootingOptions::default() };
    let orbit = find_orbit(&radial, 0.0, &[1.0, 0.0], 1e-6 / ts, &opts).unwrap();
    s.bubble.initial.radius = orbit.y0[0] * common::R0;
    s.bubble.initial.velocity = orbit.y0[1] * common::R0 / ts;
    s.bubble.initial.a.insert(8, 1e-30);
    s.run.duration = 60e-6;
    s.run.sample_interval = 1e-8;
    s.run.integrator.method = Method::Radau5;
    let col = 1 + 2 * 3; // R, a2, b2, a4, b4, a6, b6, a8
    let (mut early, mut late) = (0.0f64, 0.0f64);
    let rep = simulate_full(&s, &mut |t, row| {
        if (20e-6..40e-6).contains(&t) {
            early = early.max(row[col].abs());
        } else if t >= 40e-6 {
            late = late.max(row[col].abs());
        }
    })
    .unwrap();
    assert_eq!(rep.status, RunStatus::Completed, "{:?}", rep.status);
    let growth = (late / early).powf(1.0 / 20.0);
    eprintln!("time domain {growth}, Floquet {mu}");
    assert!((growth / mu - 1.0).abs() < 1e-5, "time domain {growth}, Floquet {mu}");
}

#[test]
fn the_closures_approach_each_other_in_the_inviscid_limit() {
    let mut gaps = Vec::new();
    for eta in [1e-3, 1e-4, 1e-5] {
        let mut bl = common::scene(8, 0.3, 1e6);
        bl.liquid.viscosity = eta;
        let mut fm = full(bl.clone(), 101);
        fm.vorticity.stretching = 30.0;
        let (b, f) = (report(&bl, 400).max_multiplier, report(&fm, 32).max_multiplier);
        gaps.push((f / b - 1.0).abs());
    }
    assert!(gaps[0] > gaps[1] && gaps[1] > gaps[2], "{gaps:?}");
    assert!(gaps[2] < 0.07, "{gaps:?}");
}

#[test]
fn floquet_cli_reports_the_closure_and_stability_refuses_series_on_vorticity() {
    let bin = env!("CARGO_BIN_EXE_magbubble");
    let dir = env!("CARGO_MANIFEST_DIR");
    let set = ["--set", "modes.viscous=vorticity", "--set", "modes.max_order=2", "--set", "vorticity.points=41"];
    let out = std::process::Command::new(bin)
        .current_dir(dir)
        .args(["floquet", "scenes/no_field.toml", "--json", "--steps", "32"])
        .args(set)
        .output()
        .unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(out.status.success(), "{v}");
    assert_eq!(v["closure"], "vorticity");
    let tmp = std::env::temp_dir().join(format!("mb_full_series_{}", std::process::id()));
    let out = std::process::Command::new(bin)
        .current_dir(dir)
        .args(["stability", "scenes/no_field.toml", "--method", "series", "--freq", "1e6", "--out"])
        .arg(&tmp)
        .args(set)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("modes.viscous") && err.contains("floquet"), "{err}");
    assert!(!tmp.join("stability.csv").exists());
    let _ = std::fs::remove_dir_all(&tmp);
}
