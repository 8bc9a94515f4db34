//! Forward sensitivities (issue 32 part 2, runtime/fit/sensitivities.rs) against central finite
//! differences of whole runs, for a parameter of every kind — shell, gas, liquid, drive, field,
//! initial state — in the boundary-layer model and with Keller–Miksis: relative 1e-6 of each
//! sensitivity's largest value over the run.

use magbubble::fit::sensitivities::{scale_of, Derivative, ModelRates};
use magbubble::fit::solve::{model_time, solve};
use magbubble::model::Model;
use magbubble::scene::SceneTemplate;

/// A coated bubble in a coil field with shape modes; `extra` adds keys.
fn scene(extra: &str, method: &str) -> String {
    format!(
        "[bubble]\nradius = 10e-6\n[bubble.initial]\na = {{ 2 = 2e-8 }}\n\
         [shell]\nc1 = 0.1\nc2 = 0.12\nthickness = 20e-9\nsusceptibility = 1.0\ndilatational_viscosity = 1e-9\n\
         [drive]\namplitude = 0.4\nfrequency_hz = 1e6\n\
         [field.coil]\ncurrent = 3e5\n\
         [modes]\nmax_order = 4\n\
         [run]\nduration = 3e-6\nsample_interval = 2e-8\n\
         [run.integrator]\nmethod = \"{method}\"\nrtol = 1e-12\natol = 1e-15\n{extra}"
    )
}

/// The rows at the SI times of a model at `key = v`.
fn rows_at(t: &SceneTemplate, key: &str, v: f64, times: &[f64]) -> Vec<Vec<f64>> {
    let sc = t.with(&[(key, v)]).unwrap();
    let m = Model::from_scene(&sc).unwrap();
    let s: Vec<f64> = times.iter().map(|&x| model_time(x, &m, &sc.run)).collect();
    let c = solve(&m, &sc.run, &s, None);
    assert_eq!(c.reached(), times.len(), "{key} = {v}: {:?}", c.status);
    c.rows
}

/// Checks ∂row/∂θ of `key` against central differences of whole runs; returns how ∂f/∂p was formed.
fn check(text: &str, key: &str, value: f64) -> Derivative {
    check_to(text, key, value, 1e-6)
}

fn check_to(text: &str, key: &str, value: f64, tol: f64) -> Derivative {
    let t = SceneTemplate::from_str(text, "test", &[] as &[&str]).unwrap();
    let sc = t.with(&[(key, value)]).unwrap();
    let m = Model::from_scene(&sc).unwrap();
    let times: Vec<f64> = (1..=15).map(|i| i as f64 * 2e-7).collect();
    let s: Vec<f64> = times.iter().map(|&x| model_time(x, &m, &sc.run)).collect();
    let rates = ModelRates::new(&t, &[key], &[value], &m).unwrap();
    let c = solve(&m, &sc.run, &s, Some(&rates));
    assert_eq!(c.reached(), times.len(), "{key}: {:?}", c.status);
    let scale = scale_of(value);
    // Richardson-extrapolated central differences of whole runs (h and h/2)
    let h = 1e-3 * scale; // larger steps: less of the adaptive steps' noise (tol/h); Richardson removes O(h²)
    let (p1, m1) = (rows_at(&t, key, value + h, &times), rows_at(&t, key, value - h, &times));
    let (p2, m2) = (rows_at(&t, key, value + h / 2.0, &times), rows_at(&t, key, value - h / 2.0, &times));
    let width = c.rows[0].len();
    for col in 0..width {
        let fd: Vec<f64> = (0..times.len())
            .map(|i| {
                let d1 = (p1[i][col] - m1[i][col]) / (2.0 * h);
                let d2 = (p2[i][col] - m2[i][col]) / h;
                (4.0 * d2 - d1) / 3.0 * scale
            })
            .collect();
        let big = fd.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if big == 0.0 {
            continue;
        }
        let worst = (0..times.len()).map(|i| (c.sens[i][0][col] - fd[i]).abs()).fold(0.0, f64::max) / big;
        eprintln!("{key} column {col}: max |S − FD| / max |FD| = {worst:.2e} ({:?})", rates.derivative[0]);
        assert!(worst < tol, "{key}, column {col}: sensitivity vs finite differences {worst:.2e}");
    }
    rates.derivative[0]
}

#[test]
fn boundary_layer_every_kind() {
    let text = scene("", "dop853");
    // shell (affine: exact quotient), liquid, gas, drive, field, initial state
    assert_eq!(check(&text, "shell.c2", 0.12), Derivative::Exact);
    check(&text, "shell.dilatational_viscosity", 1e-9);
    check(&text, "liquid.viscosity", 1e-3);
    assert_eq!(check(&text, "gas.polytropic_exponent", 1.4), Derivative::FiniteDifference);
    assert_eq!(check(&text, "drive.amplitude", 0.4), Derivative::Exact);
    check(&text, "shell.susceptibility", 1.0);
    check(&text, "bubble.radius", 10e-6);
}

#[test]
fn keller_miksis_every_kind() {
    let text = scene("[liquid]\nsound_speed = 1500.0\n", "dop853");
    check(&text, "shell.c1", 0.1);
    check(&text, "liquid.viscosity", 1e-3);
    check(&text, "gas.polytropic_exponent", 1.4);
    assert_eq!(check(&text, "drive.amplitude", 0.4), Derivative::Exact);
    check(&text, "shell.susceptibility", 1.0);
    check(&text, "bubble.radius", 10e-6);
}

/// Radau5 (the default method): the sensitivity system's block-diagonal Newton matrix
/// (integrate/sensitivity.rs). Its Newton iteration stops at a tolerance of its own and the
/// whole-run differences carry that noise (about 5e-6 measured at rtol 1e-12), so 1e-5 here; the
/// derivatives themselves are the ones checked to 1e-6 above.
#[test]
fn radau5_block_newton() {
    let text = scene("[liquid]\nsound_speed = 1500.0\n", "radau5");
    check_to(&text, "shell.c1", 0.1, 1e-5);
    check_to(&text, "liquid.viscosity", 1e-3, 1e-5);
    let text = scene("", "radau5");
    check_to(&text, "shell.c2", 0.12, 1e-5);
    check_to(&text, "bubble.radius", 10e-6, 1e-5);
}
