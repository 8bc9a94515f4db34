//! `modes --damped` (issue 4 part 6): the damped spectrum s = −γ ± iω at R0 of both closures,
//! checked against independent computations for k = 2:
//! - boundary layer: the free decay of a_2 in the time domain (the nonlinear BL model run by
//!   `model::simulate` from a small seed, no drive), fitted by Prony's method;
//! - vorticity: the exact (continuous) dispersion relation (Prosperetti 1977,
//!   `analysis::dispersion`) of the same linear coefficients, on a converged grid.
use crate::common;
use magbubble::model::vorticity::linear::{initial_guess, linear_modes};
use magbubble::model::vorticity::scene::{damped_spectrum, FullModel};
use magbubble::scene::Viscous;
use std::collections::BTreeMap;

use crate::support::prony;
use prony::prony;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}


#[test]
fn boundary_layer_spectrum_matches_the_free_decay_of_a2() {
    let mut s = common::scene(2, 0.0, 1e6);
    s.drive = None;
    s.bubble.initial.a = BTreeMap::from([(2usize, 1e-4 * common::R0)]);
    let d = damped_spectrum(&s).unwrap();
    assert_eq!(d.closure, "boundary-layer");
    assert_eq!(d.shape.len(), 1);
    let m = d.shape[0];
    assert_eq!(m.k, 2);
    assert!(m.decay_per_s > 0.0 && m.omega_rad_s > 0.0, "{m:?}");
    let period = 2.0 * std::f64::consts::PI / m.omega_rad_s;
    s.run.sample_interval = period / 80.0;
    s.run.duration = 4.0 * period;
    s.run.integrator.rtol = 1e-10;
    s.run.integrator.atol = 1e-18;
    let (mut ts, mut xs) = (vec![], vec![]);
    let rep = magbubble::model::simulate(&s, &mut |t, row| {
        ts.push(t);
        xs.push(row[1]); // a2
    })
    .unwrap();
    assert!(matches!(rep.status, magbubble::model::RunStatus::Completed), "{:?}", rep.status);
    // skip a quarter period (the b relaxation), fit the rest
    let x: Vec<f64> = xs.iter().zip(&ts).filter(|(_, t)| **t > 0.25 * period).map(|(x, _)| *x).collect();
    let roots = prony(&x, s.run.sample_interval, 4);
    let fit = roots
        .iter()
        .filter(|r| r.im > 0.0)
        .max_by(|a, b| a.re.partial_cmp(&b.re).unwrap())
        .copied()
        .expect("an oscillatory exponent");
    println!("BL spectrum {m:?}; time domain γ = {:.6e}, ω = {:.6e}; all {roots:?}", -fit.re, fit.im);
    assert!(rel(fit.im, m.omega_rad_s) < 5e-3, "ω {} vs {}", fit.im, m.omega_rad_s);
    assert!(rel(-fit.re, m.decay_per_s) < 5e-3, "γ {} vs {}", -fit.re, m.decay_per_s);
}

#[test]
fn vorticity_spectrum_matches_the_exact_dispersion_relation() {
    let mut s = common::scene(4, 0.0, 1e6);
    s.drive = None;
    s.modes.viscous = Viscous::Vorticity;
    s.vorticity.y_max = 4.0;
    s.vorticity.points = 400;
    s.vorticity.stretching = 10.0;
    let d = damped_spectrum(&s).unwrap();
    assert_eq!(d.closure, "vorticity");
    let fm = FullModel::from_scene(&s).unwrap();
    let ts = fm.base().time_scale();
    let lin = linear_modes(&fm.coupling(), 0.0, 1.0);
    for (m, l) in d.shape.iter().zip(&lin) {
        assert_eq!(m.k, l.k);
        let exact = l.exact_root(initial_guess(l)).unwrap();
        let (g, w) = (-exact.re / ts, exact.im / ts);
        println!("k={}: grid γ = {:.6e}, ω = {:.6e}; exact γ = {g:.6e}, ω = {w:.6e}", m.k, m.decay_per_s, m.omega_rad_s);
        assert!(rel(m.omega_rad_s, w) < 5e-3, "k={} ω {} vs {w}", m.k, m.omega_rad_s);
        assert!(rel(m.decay_per_s, g) < 5e-3, "k={} γ {} vs {g}", m.k, m.decay_per_s);
    }
}

#[test]
fn cli_prints_the_damped_spectrum_as_json() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_magbubble"))
        .args(["modes", "scenes/no_field.toml", "--damped", "--json", "--set", "modes.max_order=4"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["closure"], "boundary-layer");
    let shape = v["shape"].as_array().unwrap();
    assert_eq!(shape.len(), 2);
    for (m, k) in shape.iter().zip([2, 4]) {
        assert_eq!(m["k"], k);
        assert!(m["decay_per_s"].as_f64().unwrap() > 0.0);
        assert!(m["omega_rad_s"].as_f64().unwrap() > 0.0);
    }
}
