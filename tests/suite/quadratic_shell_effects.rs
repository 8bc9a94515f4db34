//! `modes.coupling = "quadratic"` with bending and shell viscosity (issue 12, scope 1: every
//! shell law; effects/quadratic_bending.rs, effects/quadratic_shell_viscosity.rs): the terms are
//! assembled when their keys are set, the whole system's Jacobian is exact (the viscous term holds
//! the first-order ḃ, and the linear ḃ loads are solved again after the second pass), and the
//! quadratic − linear difference of an undriven shelled bubble is O(ε²): halving the initial
//! amplitude divides it by 4, in R, the a's and the b's.

use crate::support::jacobian::assert_jacobian_matches_fd_step;
use magbubble::model::{simulate, Model};
use magbubble::scene::{load, Scene};

const R0: f64 = 10e-6;
/// k_b [J] (17× the no-field shell's own E h³/12(1−ν²), the value at which fig 5's curve
/// settles at 16 modes: docs/model.md) and the supplementary tables' shell viscosities.
const BENDING: &str = "shell.bending_modulus=1e-15";
const SHEAR: &str = "shell.shear_viscosity=5.18e-10";
const DILATATION: &str = "shell.dilatational_viscosity=1.55e-9";

/// The no-field scene (Mooney–Rivlin), undriven, a_2(0) = ε R0, k ≤ 4, with `extra` keys.
fn shelled(eps: f64, coupling: &str, extra: &[&str]) -> Scene {
    let a2 = format!("bubble.initial.a={{2 = {:e}}}", eps * R0);
    let c = format!("modes.coupling=\"{coupling}\"");
    let mut o = vec!["drive.amplitude=0.0", "modes.max_order=4", "run.duration=3e-6", "run.sample_interval=1e-8", "run.integrator.rtol=1e-11", "run.integrator.atol=1e-15", &a2, &c];
    o.extend_from_slice(extra);
    load("scenes/no_field.toml", &o).expect("scene")
}

fn rows(s: &Scene) -> Vec<Vec<f64>> {
    let mut v = Vec::new();
    simulate(s, &mut |_, row| v.push(row.to_vec())).expect("runs");
    v
}

/// max over the samples of |quadratic − linear| per column (R, a2, b2, a4, b4), in units of R0.
fn difference(eps: f64, extra: &[&str]) -> Vec<f64> {
    let (q, l) = (rows(&shelled(eps, "quadratic", extra)), rows(&shelled(eps, "linear", extra)));
    assert_eq!(q.len(), l.len());
    (0..q[0].len()).map(|c| q.iter().zip(&l).map(|(x, y)| (x[c] - y[c]).abs()).fold(0.0, f64::max) / R0).collect()
}

#[test]
fn bending_and_viscous_terms_are_assembled_only_with_their_keys() {
    let m = Model::from_scene(&shelled(1e-3, "quadratic", &[BENDING, SHEAR, DILATATION])).unwrap();
    assert!(m.equations().has("quadratic bending"));
    assert!(m.equations().has("quadratic shell viscosity"));
    assert!(m.equations().has("quadratic membrane"));
    let only_dilatation = Model::from_scene(&shelled(1e-3, "quadratic", &[DILATATION])).unwrap();
    assert!(only_dilatation.equations().has("quadratic shell viscosity"));
    assert!(!only_dilatation.equations().has("quadratic bending"));
    let off = Model::from_scene(&shelled(1e-3, "quadratic", &[])).unwrap();
    assert!(!off.equations().has("quadratic bending") && !off.equations().has("quadratic shell viscosity"));
    let linear = Model::from_scene(&shelled(1e-3, "linear", &[BENDING, SHEAR, DILATATION])).unwrap();
    assert!(!linear.equations().has("quadratic bending") && !linear.equations().has("quadratic shell viscosity"));
}

#[test]
fn quadratic_minus_linear_scales_as_eps_squared_with_bending_and_shell_viscosity() {
    for (name, extra) in [("bending", &[BENDING][..]), ("shell viscosity", &[SHEAR, DILATATION][..]), ("both", &[BENDING, SHEAR, DILATATION][..])] {
        let (d1, d2) = (difference(2e-3, extra), difference(1e-3, extra));
        for (c, col) in [(0, "R"), (1, "a2"), (2, "b2"), (3, "a4"), (4, "b4")] {
            let ratio = d1[c] / d2[c];
            eprintln!("{name} {col}: max|q − l|/R0 = {:.3e} (eps = 2e-3), {:.3e} (eps = 1e-3), ratio {ratio:.4}", d1[c], d2[c]);
            assert!(d2[c] > 0.0, "{name} {col}: no quadratic effect");
            assert!((ratio - 4.0).abs() < 0.2, "{name} {col}: halving eps divides the difference by {ratio}, not 4");
        }
    }
}

/// The whole system's analytic Jacobian (boundary-layer closure) against central differences,
/// with the second-order bending and shell-viscous terms (and the membrane's, and a field).
/// Step floor 1e-6 as the membrane's quadratic Jacobian test (tests/suite/quadratic_shell.rs).
#[test]
fn quadratic_jacobians_with_bending_and_shell_viscosity_match_differences() {
    let q = "modes.coupling=\"quadratic\"";
    let cases: [(&str, &[&str]); 5] = [
        ("scenes/free_bubble.toml", &["modes.max_order=8", q, "shell.surface_tension=0.072", "shell.bending_modulus=1e-15", "shell.dilatational_viscosity=1e-9"]),
        ("scenes/no_field.toml", &["modes.max_order=8", q, "shell.bending_modulus=1e-13"]),
        ("scenes/no_field.toml", &["modes.max_order=8", q, "shell.shear_viscosity=5e-8", "shell.dilatational_viscosity=2e-8"]),
        ("scenes/no_field.toml", &["modes.max_order=12", q, "shell.form=\"tension\"", "shell.bending_modulus=1e-13", "shell.shear_viscosity=5e-8", "shell.dilatational_viscosity=2e-8"]),
        ("scenes/coil_static.toml", &["modes.max_order=8", q, "shell.bending_modulus=1e-13", "shell.shear_viscosity=5e-8"]),
    ];
    for (file, o) in cases {
        let m = Model::from_scene(&load(file, o).expect("scene")).expect("model");
        assert_jacobian_matches_fd_step(m.system(), &format!("{file} {o:?}"), 1e-6);
    }
}
