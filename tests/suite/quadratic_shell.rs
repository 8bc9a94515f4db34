//! `modes.coupling = "quadratic"` on the paper's encapsulated bubble (issue 12, scope 1: the
//! membrane's second-order loads, effects/quadratic_membrane.rs): the term is assembled for the
//! Mooney–Rivlin shell, and the quadratic − linear difference of an undriven shelled bubble is
//! O(ε²): halving the initial amplitude divides it by 4, in R, the a's and the b's.

use magbubble::model::{simulate, Model};
use magbubble::scene::{load, Scene};

const R0: f64 = 10e-6;

/// The no-field scene (Mooney–Rivlin c1 = 0.1, c2 = 0.12 N/m), undriven, a_2(0) = ε R0, k ≤ 4.
fn shelled(eps: f64, coupling: &str, form: &str) -> Scene {
    let a2 = format!("bubble.initial.a={{2 = {:e}}}", eps * R0);
    let c = format!("modes.coupling=\"{coupling}\"");
    let f = format!("shell.form=\"{form}\"");
    load(
        "scenes/no_field.toml",
        &[
            "drive.amplitude=0.0",
            "modes.max_order=4",
            "run.duration=3e-6",
            "run.sample_interval=1e-8",
            "run.integrator.rtol=1e-11",
            "run.integrator.atol=1e-15",
            &a2,
            &c,
            &f,
        ],
    )
    .expect("scene")
}

fn rows(s: &Scene) -> Vec<Vec<f64>> {
    let mut v = Vec::new();
    simulate(s, &mut |_, row| v.push(row.to_vec())).expect("runs");
    v
}

/// max over the samples of |quadratic − linear| per column (R, a2, b2, a4, b4), in units of R0.
fn difference(eps: f64, form: &str) -> Vec<f64> {
    let (q, l) = (rows(&shelled(eps, "quadratic", form)), rows(&shelled(eps, "linear", form)));
    assert_eq!(q.len(), l.len());
    (0..q[0].len()).map(|c| q.iter().zip(&l).map(|(x, y)| (x[c] - y[c]).abs()).fold(0.0, f64::max) / R0).collect()
}

#[test]
fn the_membrane_term_is_assembled_for_a_shelled_bubble() {
    let m = Model::from_scene(&shelled(1e-3, "quadratic", "paper")).unwrap();
    assert!(m.equations().has("quadratic membrane"));
    assert!(m.equations().has("quadratic coupling"));
    let l = Model::from_scene(&shelled(1e-3, "linear", "paper")).unwrap();
    assert!(!l.equations().has("quadratic membrane"));
}

#[test]
fn shelled_quadratic_minus_linear_scales_as_eps_squared() {
    for form in ["paper", "tension"] {
        let (d1, d2) = (difference(2e-3, form), difference(1e-3, form));
        for (c, name) in [(0, "R"), (1, "a2"), (2, "b2"), (3, "a4"), (4, "b4")] {
            let ratio = d1[c] / d2[c];
            eprintln!("{form} {name}: max|q − l|/R0 = {:.3e} (eps = 2e-3), {:.3e} (eps = 1e-3), ratio {ratio:.4}", d1[c], d2[c]);
            assert!(d2[c] > 0.0, "{form} {name}: no quadratic effect");
            assert!((ratio - 4.0).abs() < 0.2, "{form} {name}: halving eps divides the difference by {ratio}, not 4");
        }
    }
}

/// The whole system's analytic Jacobian (boundary-layer closure) against central differences,
/// with the second-order membrane term assembled: Mooney–Rivlin (both forms), Skalak, a field.
/// Step floor 1e-6 (the default 1e-9 floor leaves round-off of ~2e-6 relative in the k ≤ 16 rows,
/// whose rates are large; central differences are exact for the bilinear terms at any step).
#[test]
fn shelled_quadratic_jacobians_match_differences() {
    use crate::support::jacobian::assert_jacobian_matches_fd_step;
    let q = "modes.coupling=\"quadratic\"";
    let cases: [(&str, &[&str]); 4] = [
        ("scenes/no_field.toml", &["modes.max_order=16", q]),
        ("scenes/no_field.toml", &["modes.max_order=8", q, "shell.form=\"tension\""]),
        ("scenes/skalak.toml", &["modes.max_order=8", q]),
        ("scenes/coil_static.toml", &["modes.max_order=8", q]),
    ];
    for (file, o) in cases {
        let m = Model::from_scene(&load(file, o).expect("scene")).expect("model");
        assert!(m.equations().has("quadratic membrane"), "{file}");
        assert_jacobian_matches_fd_step(m.system(), &format!("{file} {o:?}"), 1e-6);
    }
}

/// The term alone: its exact Jacobian against central differences of its loads, at finite
/// amplitudes (so that the bilinear derivatives are large), every row (P, G_n, G_t).
#[test]
fn quadratic_membrane_term_jacobian_matches_differences() {
    use magbubble::coefficients::quadratic_membrane::Form;
    use magbubble::model::effects::quadratic_membrane::QuadraticMembrane;
    use crate::support::load_jacobian::{assert_load_jacobian_matches_fd, finite_state, flat_loads};
    use magbubble::model::effects::{At, LoadJacobian, Term};
    let modes = 6;
    let orders: Vec<f64> = (1..=modes).map(|i| 2.0 * i as f64).collect();
    for (name, form) in [("mooney_rivlin", Form::Paper), ("mooney_rivlin", Form::Tension), ("skalak", Form::Paper)] {
        let t = QuadraticMembrane::new(QuadraticMembrane::law(name).unwrap(), form, 1.0, (0.9, 0.3), &orders).unwrap();
        let y = finite_state(modes);
        let mut jac = LoadJacobian::new(modes);
        t.add_jacobian(&At { t: 0.0, z: &y }, &mut jac);
        assert_load_jacobian_matches_fd(&jac, &y, |z| flat_loads(modes, |l| t.add(&At { t: 0.0, z }, l)), &format!("{name} {form:?}"));
    }
}
