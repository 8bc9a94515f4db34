//! The full model linearised at R0 against the exact dispersion relation of a viscous shape mode
//! (analysis::dispersion, Prosperetti 1977 with magbubble's boundary conditions), and the free
//! decay of a_2 in the time domain.

use magbubble::analysis::dispersion::{LinearMode, C64};

use crate::support::prony;
use prony::prony;
use magbubble::integrate::OdeSystem;
use magbubble::model::vorticity::linear::{full_root, initial_guess, LinearCoupling};
use magbubble::model::vorticity::monolithic::Monolithic;
use magbubble::model::vorticity::staggered::Staggered;
use magbubble::model::vorticity::Grid;

/// The paper's bubble (R0 = 10 µm, c1 = 0.1, c2 = 0.12 N/m, water). The membrane coefficients at
/// R = R0 are FORMULATION §2's reduced values (test inputs: the dispersion relation holds for any).
fn mode(k: usize) -> LinearMode {
    crate::common::paper_mode(k)
}

fn grid() -> Grid {
    Grid::new(3.0, 200, 30.0).unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

#[test]
fn linearised_full_model_matches_the_exact_dispersion_relation() {
    for k in [2usize, 4] {
        let m = mode(k);
        let exact = m.exact_root(initial_guess(&m)).expect("exact root");
        let disc = full_root(&m, &grid(), exact).expect("discrete root");
        println!("k = {k}: exact s = {exact:.6e}, discrete s = {disc:.6e}");
        assert!(exact.re < 0.0 && exact.im > 0.0);
        assert!(rel(disc.re, exact.re) < 5e-3, "decay rate k={k}: {} vs {}", disc.re, exact.re);
        assert!(rel(disc.im, exact.im) < 5e-3, "frequency k={k}: {} vs {}", disc.im, exact.im);
    }
}

#[test]
fn discrete_root_is_an_eigenvalue_of_the_method_of_lines_jacobian() {
    // Small grid, dense finite-difference Jacobian of the actual right-hand side.
    let m = mode(2);
    let g = Grid::new(2.5, 40, 10.0).unwrap();
    let c = LinearCoupling::new(vec![m]);
    let sys = Monolithic::new(&c, g.clone());
    let n = sys.dim();
    let mut y0 = vec![0.0; n];
    y0[0] = m.r0;
    let mut f0 = vec![0.0; n];
    sys.rhs(0.0, &y0, &mut f0);
    let mut jac = nalgebra::DMatrix::<f64>::zeros(n, n);
    let mut f1 = vec![0.0; n];
    for j in 2..n {
        let mut y = y0.clone();
        let h = 1e-9;
        y[j] += h;
        sys.rhs(0.0, &y, &mut f1);
        for i in 0..n {
            jac[(i, j)] = (f1[i] - f0[i]) / h;
        }
    }
    // R, Ṙ rows/cols: R̈ = 0, Ṙ = 0 → the block for R is nilpotent; drop it. Balance the
    // matrix (a, b ~ R0, ȧ ~ R0 ω, T ~ ω) so that the eigen-solver sees O(1) entries.
    let w = m.omega2_inviscid().sqrt();
    let scale = |i: usize| match i {
        0 | 2 => m.r0,
        1 => m.r0 * w,
        _ => w,
    };
    let mut sub = jac.view((2, 2), (n - 2, n - 2)).into_owned();
    for i in 0..n - 2 {
        for j in 0..n - 2 {
            sub[(i, j)] *= scale(j) / scale(i) / w;
        }
    }
    let sub = sub;
    let eig: Vec<_> = sub.complex_eigenvalues().iter().map(|e| e * w).collect();
    let root = full_root(&m, &g, m.exact_root(initial_guess(&m)).unwrap()).unwrap();
    let nearest = eig.iter().map(|e| (C64::new(e.re, e.im) - root).norm()).fold(f64::INFINITY, f64::min);
    println!("discrete root {root:.6e}, nearest eigenvalue distance {nearest:.3e}");
    assert!(nearest < 1e-5 * root.norm(), "nearest eigenvalue is {nearest} away from {root}");
}


#[test]
fn free_decay_of_a2_agrees_with_the_dispersion_relation() {
    let m = mode(2);
    let exact = m.exact_root(initial_guess(&m)).unwrap();
    let c = LinearCoupling::new(vec![m]);
    let period = 2.0 * std::f64::consts::PI / exact.im;
    let dt = period / 4000.0;
    let mut st = Staggered::new(&c, grid(), dt).unwrap();
    let mut s = st.initial_state(0.0, m.r0, 0.0, vec![1e-3 * m.r0], vec![0.0], vec![0.0]);
    let (mut ts, mut xs) = (vec![], vec![]);
    st.run(&mut s, 8.0 * period, |s, _| {
        ts.push(s.t);
        xs.push(s.a[0]);
        true
    })
    .unwrap();
    // skip the first period (fast vorticity and b transients), then fit 6 periods
    let stride = 50; // samples every period/80
    let x: Vec<f64> = xs.iter().zip(&ts).filter(|(_, t)| **t > period).map(|(x, _)| *x).step_by(stride).collect();
    let roots = prony(&x, dt * stride as f64, 6);
    let mode = roots
        .iter()
        .filter(|s| s.im > 0.0)
        .max_by(|a, b| a.re.partial_cmp(&b.re).unwrap())
        .copied()
        .expect("an oscillatory exponent");
    let (gamma, omega) = (-mode.re, mode.im);
    println!("time domain: gamma = {gamma:.6e}, omega = {omega:.6e}; exact {:.6e}, {:.6e}; all {roots:?}", -exact.re, exact.im);
    assert!(rel(omega, exact.im) < 5e-3, "omega {omega} vs {}", exact.im);
    assert!(rel(gamma, -exact.re) < 5e-3, "gamma {gamma} vs {}", -exact.re);
}

#[test]
fn monolithic_free_decay_agrees_with_the_dispersion_relation() {
    use magbubble::integrate::{solve, Control, Method, Output};
    // nondimensional units of FORMULATION §4.5 (R0 = ρ = 1, c1 = 1/2): the integrator's
    // absolute tolerance is meant for O(1) states
    let m = crate::common::paper_mode_nd(2, 44.72);
    let exact = m.exact_root(initial_guess(&m)).unwrap();
    let cpl = LinearCoupling::new(vec![m]);
    let sys = Monolithic::new(&cpl, grid());
    let period = 2.0 * std::f64::consts::PI / exact.im;
    let st = Staggered::new(&cpl, grid(), 1.0).unwrap();
    let y = sys.pack(&st.initial_state(0.0, 1.0, 0.0, vec![1e-3], vec![0.0], vec![0.0]));
    let dt_out = period / 80.0;
    // both implicit steppers, each through the structured solve of the linear-solver hook
    for method in [Method::Rosenbrock23 { rtol: 1e-7, atol: 1e-12 }, Method::Radau5 { rtol: 1e-7, atol: 1e-12 }] {
        let mut xs = vec![];
        solve(&sys, 0.0, &y, 7.0 * period, &method, Output::Every(dt_out), 100_000, &mut |t, y| {
            if t > period * (1.0 - 1e-9) {
                xs.push(y[2]);
            }
            Control::Continue
        })
        .unwrap();
        let roots = prony(&xs, dt_out, 6);
        let mode = roots.iter().filter(|s| s.im > 0.0).max_by(|a, b| a.re.partial_cmp(&b.re).unwrap()).copied().unwrap();
        println!("monolithic {}: s = {mode:.6e}, exact {exact:.6e}", method.name());
        assert!(rel(mode.im, exact.im) < 5e-3, "{}: omega {} vs {}", method.name(), mode.im, exact.im);
        assert!(rel(-mode.re, -exact.re) < 5e-3, "{}: gamma {} vs {}", method.name(), -mode.re, -exact.re);
    }
}
