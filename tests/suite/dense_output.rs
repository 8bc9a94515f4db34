//! Sampled output carries the error the tolerance asks for (issue 29 item 6): each method's own
//! dense output (Dop853: its 7th-order continuous extension; Dopri5: its 4th-order one; Radau5:
//! the collocation polynomial; Rosenbrock23: its 2nd-order one; RK4: the cubic Hermite).
//!
//! The free-bubble cosine run (scenes/free_bubble.toml, ε_p = 0.2, 8 modes, 20 µs sampled every
//! 10 ns) at rtol 1e-10: every method's samples (dense output between steps) against a
//! reference (Dop853 at rtol 1e-13 landing on every sample), compared with the same method's
//! error when it lands on the samples (no interpolation). Before this, Dop853's samples came
//! from a cubic Hermite and missed by 4.3e-6 R0 while its step ends agreed to ~1e-11.

use magbubble::integrate::{solve, stepper, Control, Method, Output};
use magbubble::model::Model;
use magbubble::scene;
use std::path::PathBuf;

fn model() -> Model {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes/free_bubble.toml");
    let s = scene::load(path, &[] as &[String]).expect("scene");
    Model::from_scene(&s).expect("model")
}

/// The samples (nondimensional, lengths / R0) of `method` every `d` up to `t_end`.
fn samples(model: &Model, method: &Method, output: Output, t_end: f64) -> Vec<Vec<f64>> {
    let mut out = vec![];
    solve(model.system(), 0.0, model.initial_state(), t_end, method, output, 10_000_000, &mut |_, y| {
        out.push(y.to_vec());
        Control::Continue
    })
    .expect("integrates");
    out
}

fn max_diff(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).flat_map(|(x, y)| x.iter().zip(y).map(|(p, q)| (p - q).abs())).fold(0.0, f64::max)
}

/// The reference (Dop853 at rtol 1e-13) at the times `ts`, landing on each.
fn reference_at(model: &Model, ts: &[f64]) -> Vec<Vec<f64>> {
    let sys = model.system();
    let t_end = *ts.last().unwrap();
    let mut rs = stepper(sys, &Method::Dop853 { rtol: 1e-13, atol: 1e-15 }, 0.0, model.initial_state(), t_end).unwrap();
    ts.iter()
        .map(|&t| {
            while rs.t() < t {
                rs.step(sys, t).unwrap();
            }
            rs.y().to_vec()
        })
        .collect()
}

#[test]
fn every_methods_samples_are_as_accurate_as_its_steps() {
    let m = model();
    let ts = m.time_scale();
    let (t_end, d) = (20e-6 / ts, 1e-8 / ts);
    let reference = samples(&m, &Method::Dop853 { rtol: 1e-13, atol: 1e-15 }, Output::Landing(d), t_end);
    let (rtol, atol) = (1e-10, 1e-12);
    let methods = [
        Method::Dop853 { rtol, atol },
        Method::Dopri5 { rtol, atol },
        Method::Radau5 { rtol, atol },
        Method::Rosenbrock23 { rtol: 1e-8, atol: 1e-10 },
        Method::Rk4 { dt: 2.5e-11 / ts },
    ];
    for method in methods {
        let dense = max_diff(&samples(&m, &method, Output::Every(d), t_end), &reference);
        // the same method's own step ends (no interpolation) against the reference there
        let (mut st_t, mut st_y) = (vec![], vec![]);
        solve(m.system(), 0.0, m.initial_state(), t_end, &method, Output::Steps, 10_000_000, &mut |t, y| {
            if t > 0.0 {
                st_t.push(t);
                st_y.push(y.to_vec());
            }
            Control::Continue
        })
        .unwrap();
        let steps = max_diff(&st_y, &reference_at(&m, &st_t));
        eprintln!("{}: sample error {dense:.2e} R0 (dense output), step-end error {steps:.2e} R0 ({} steps)", method.name(), st_t.len());
        // Radau5's collocation polynomial has the stage order 3 (Hairer & Wanner II, sec. IV.5;
        // RADAU5's CONTR5): between steps its error is O(h⁴) against O(h⁶) at the step ends, so
        // its samples are NOT as accurate as its steps (issue 29 item 6 is open for Radau5):
        // measured 4.8e-9 vs 4.3e-10 R0 (11×) before the per-component error weights, 4.1e-9 vs
        // 1.6e-10 R0 (26×) with them (the steps got better, the interpolant did not). What holds
        // is that level: its samples stay within 1e-8 R0 here. The explicit methods' extensions
        // stay within 10× of their steps (1e-12 R0: the reference's own accuracy, where RK4 at
        // 2.5e-11 s sits).
        if matches!(method, Method::Radau5 { .. }) {
            assert!(dense <= 1e-8, "radau5: samples {dense:.2e} R0 (steps {steps:.2e} R0)");
        } else {
            assert!(dense <= 10.0 * steps + 1e-12, "{}: samples {dense:.2e} R0, steps {steps:.2e} R0", method.name());
        }
    }
}

#[test]
fn dop853_dense_output_is_of_order_7_and_the_hermite_was_not() {
    // one run stepped by hand: at the midpoint of every step, the continuous extension (after
    // prepare_dense) and the cubic Hermite (without), against the reference at that time
    let m = model();
    let ts = m.time_scale();
    let t_end = 2e-6 / ts;
    let sys = m.system();
    let mut st = stepper(sys, &Method::Dop853 { rtol: 1e-10, atol: 1e-12 }, 0.0, m.initial_state(), t_end).unwrap();
    let mut mids = vec![];
    let (mut e7, mut e3) = (vec![], vec![]);
    let n = m.initial_state().len();
    let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
    while st.t() < t_end {
        st.step(sys, t_end).unwrap();
        let mid = 0.5 * (st.t_prev() + st.t());
        st.interpolate(mid, &mut b); // before prepare_dense: the cubic Hermite
        st.prepare_dense(sys);
        st.interpolate(mid, &mut a);
        mids.push(mid);
        e7.push(a.clone());
        e3.push(b.clone());
    }
    // the reference at the midpoints, landing on each
    let mut refs = vec![];
    let mut rs = stepper(sys, &Method::Dop853 { rtol: 1e-13, atol: 1e-15 }, 0.0, m.initial_state(), t_end).unwrap();
    for &t in &mids {
        while rs.t() < t {
            rs.step(sys, t).unwrap();
        }
        refs.push(rs.y().to_vec());
    }
    let (err7, err3) = (max_diff(&e7, &refs), max_diff(&e3, &refs));
    eprintln!("dop853 mid-step error: continuous extension {err7:.2e} R0, cubic Hermite {err3:.2e} R0 ({} steps)", mids.len());
    assert!(err7 < 1e-9, "{err7:.2e}");
    assert!(err3 > 100.0 * err7, "{err3:.2e} vs {err7:.2e}");
}
