//! Scenes built by hand for the analysis tests (the paper's fig 5–12 parameters).
#![allow(dead_code)]

use magbubble::scene::*;
use std::collections::BTreeMap;

pub const R0: f64 = 10e-6;
pub const C1: f64 = 0.1;
pub const C2: f64 = 0.12;

/// Water at 20 °C and air, the liquid and gas of the hand-built scenes: density [kg/m³],
/// viscosity [Pa s], ambient pressure [Pa], polytropic exponent, sound speed [m/s], surface
/// tension [N/m].
pub mod water {
    pub const RHO: f64 = 1000.0;
    pub const ETA: f64 = 1e-3;
    pub const P0: f64 = 101325.0;
    pub const KAPPA: f64 = 1.4;
    pub const C: f64 = 1500.0;
    pub const GAMMA: f64 = 0.072;
}

/// The linear shape mode k of a Mooney–Rivlin shell at rest, for the dispersion relation and
/// the vorticity closure (FORMULATION §2's reduced membrane coefficients at R = R0, ∝ (c1 + c2)/R0²):
/// density ρ, viscosity η, radius R0, and c1 + c2 (test inputs: the relation holds for any).
pub fn shell_mode(k: usize, rho: f64, eta: f64, r0: f64, c1_plus_c2: f64) -> magbubble::analysis::dispersion::LinearMode {
    let n = (k * (k + 1)) as f64;
    let c = c1_plus_c2 / (r0 * r0);
    magbubble::analysis::dispersion::LinearMode { k, rho, eta, r0, s1: 24.0 * c, s2: -12.0 * n * c, s11: -12.0 * c, s12: 4.0 * (2.0 * n - 1.0) * c }
}

/// [`shell_mode`] of the paper's bubble (R0 = 10 µm, c1 = 0.1, c2 = 0.12 N/m, water).
pub fn paper_mode(k: usize) -> magbubble::analysis::dispersion::LinearMode {
    shell_mode(k, 1000.0, 1e-3, R0, C1 + C2)
}

/// [`shell_mode`] in the nondimensional units of FORMULATION §4.5 (R0 = ρ = 1, c1 = 1/2,
/// c2 = 0.6) at Reynolds number `re` (44.72 for the paper's bubble: t* = 2.236 µs).
pub fn paper_mode_nd(k: usize, re: f64) -> magbubble::analysis::dispersion::LinearMode {
    shell_mode(k, 1.0, 1.0 / re, 1.0, 0.5 + 0.6)
}

pub fn scene(max_order: usize, eps_p: f64, f_hz: f64) -> Scene {
    Scene {
        bubble: Bubble {
            radius: R0,
            initial: Initial { radius: R0, velocity: 0.0, a: BTreeMap::new(), a_velocity: BTreeMap::new(), b: BTreeMap::new(), seed: Default::default() },
        },
        shell: Shell::mooney_rivlin(C1, C2, 20e-9, 1.0, MembraneForm::Paper),
        gas: Gas { polytropic_exponent: 1.4, reference_pressure: 101325.0, reference_pressure_given: true, vapour_pressure: 0.0, thermal: Thermal::Polytropic },
        liquid: Liquid { density: 1000.0, viscosity: 1e-3, ambient_pressure: 101325.0, sound_speed: None, temperature: 293.15 },
        drive: Some(Drive::cosine(eps_p, f_hz)),
        field: None,
        modes: Modes { max_order, viscous: Viscous::BoundaryLayer, boundary_layer_frequency: BoundaryLayerFrequency::Auto, coupling: Coupling::Linear, credible_amplitude: 0.1 },
        vorticity: VorticityGrid { y_max: 2.0, points: 200, stretching: 1.0, scheme: VorticityScheme::Monolithic },
        run: Run {
            duration: 100e-6,
            sample_interval: 1e-7,
            integrator: IntegratorSettings { method: Method::Dopri5, rtol: 1e-8, atol: 1e-12, dt: 1e-9, dt_given: true, max_steps: 100_000_000 },
            blow_up_threshold: 0.5,
            max_output_bytes: 1e9,
        },
        warnings: Vec::new(),
        echo: None,
        population: None,
    }
}

pub fn coil(current: f64) -> Field {
    Field::Coil(Coil {
        turns: 1000.0,
        distance: 0.1,
        angle: (3.0f64 / 7.0).sqrt().acos(),
        current: Current::Static { value: current },
        distance_oscillation: None,
        include_h4: false,
    })
}

pub fn dipole(moment: f64, distance: f64) -> Field {
    Field::Dipole(Dipole { moment, distance })
}

/// One classical RK4 step of a 2-state ODE y' = f(t, y) (the tests' independent radial
/// references: marmottant, sarkar, church_hoff).
pub fn rk4_step2(t: f64, y: [f64; 2], h: f64, f: &dyn Fn(f64, [f64; 2]) -> [f64; 2]) -> [f64; 2] {
    let add = |y: [f64; 2], k: [f64; 2], c: f64| [y[0] + c * k[0], y[1] + c * k[1]];
    let k1 = f(t, y);
    let k2 = f(t + h / 2.0, add(y, k1, h / 2.0));
    let k3 = f(t + h / 2.0, add(y, k2, h / 2.0));
    let k4 = f(t + h, add(y, k3, h));
    [y[0] + h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]), y[1] + h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1])]
}

/// y[0] at the times `ts` (increasing, from t = 0) by fixed RK4 steps of at most h from y0, each
/// step shortened to land on the next time.
pub fn rk4_at_times(f: &dyn Fn(f64, [f64; 2]) -> [f64; 2], y0: [f64; 2], ts: &[f64], h: f64) -> Vec<f64> {
    let (mut t, mut y, mut out) = (0.0, y0, Vec::with_capacity(ts.len()));
    for &target in ts {
        while t < target - 1e-18 {
            let s = h.min(target - t);
            y = rk4_step2(t, y, s, f);
            t += s;
        }
        out.push(y[0]);
    }
    out
}

/// The sample times and R of a run of `s` at `rtol` (atol 1e-14), asserted completed.
pub fn radial_series(s: &Scene, rtol: f64) -> (Vec<f64>, Vec<f64>) {
    use magbubble::model::{simulate, RunStatus};
    let mut s = s.clone();
    s.run.integrator.rtol = rtol;
    s.run.integrator.atol = 1e-14;
    let (mut ts, mut rs) = (vec![], vec![]);
    let rep = simulate(&s, &mut |t, row| {
        ts.push(t);
        rs.push(row[0]);
    })
    .unwrap();
    assert!(matches!(rep.status, RunStatus::Completed), "{:?}", rep.status);
    (ts, rs)
}

/// Runs `scene(ε_p)` for each ε_p of `eps` at rtol 1e-12 (duration, sample interval given) and
/// asserts its R(t) within 1e-8 R0 of `reference(ε_p, sample times)` (the published equation
/// integrated in the test): the radial check of every shell law written from its paper.
pub fn assert_radial_matches_reference(
    eps: &[f64],
    duration: f64,
    sample_interval: f64,
    scene: &dyn Fn(f64) -> magbubble::scene::Scene,
    reference: &dyn Fn(f64, &[f64]) -> Vec<f64>,
) {
    for &e in eps {
        let mut s = scene(e);
        s.run.duration = duration;
        s.run.sample_interval = sample_interval;
        let (ts, rs) = radial_series(&s, 1e-12);
        let rref = reference(e, &ts);
        let err = rs.iter().zip(&rref).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / R0;
        let span = rs.iter().fold(0.0f64, |m, r| m.max((r - R0).abs())) / R0;
        println!("eps_p = {e}: max |R/R0 - 1| = {span:.3}, max |dR|/R0 = {err:e}");
        assert!(err <= 1e-8, "eps_p = {e}: {err:e}");
    }
}

/// y[0] at the times `ts` by classical RK4 with step h from y0, every step that crosses one of
/// `radii` (kinks of the right-hand side in y[0]) cut at the crossing (secant iteration on the
/// step length), so that no step straddles a kink: the reference keeps RK4's order through the
/// switches. Returns the values and the number of crossings.
pub fn rk4_cut_at(f: &dyn Fn(f64, [f64; 2]) -> [f64; 2], radii: &[f64], y0: [f64; 2], ts: &[f64], h: f64) -> (Vec<f64>, usize) {
    let side = |r: f64| radii.iter().map(|&x| r >= x).collect::<Vec<bool>>();
    let (mut t, mut y, mut out, mut switches) = (0.0, y0, Vec::new(), 0);
    for &target in ts {
        while t < target - 1e-18 {
            let step = h.min(target - t);
            let y1 = rk4_step2(t, y, step, &f);
            if side(y1[0]) == side(y[0]) {
                t += step;
                y = y1;
                continue;
            }
            // the first radius crossed: cut the step where R reaches it
            let x = radii.iter().copied().find(|&x| (y[0] >= x) != (y1[0] >= x)).expect("a radius is crossed");
            let g = |s: f64| rk4_step2(t, y, s, &f)[0] - x;
            let (mut a, mut b, mut ga, mut gb) = (0.0, step, y[0] - x, y1[0] - x);
            for _ in 0..60 {
                let c = b - gb * (b - a) / (gb - ga);
                let gc = g(c);
                (a, ga, b, gb) = (b, gb, c, gc);
                if gc.abs() < 1e-22 || (b - a).abs() < 1e-24 {
                    break;
                }
            }
            // land just past the crossing, on the new branch (a step that falls short is lengthened)
            let mut s = b.clamp(0.0, step);
            let mut y2 = rk4_step2(t, y, s, &f);
            let mut extra = 1e-9 * step;
            while (y2[0] >= x) == (y[0] >= x) && s < step {
                s = (s + extra).min(step);
                extra *= 2.0;
                y2 = rk4_step2(t, y, s, &f);
            }
            y = y2;
            t += s;
            switches += 1;
        }
        out.push(y[0]);
    }
    (out, switches)
}
