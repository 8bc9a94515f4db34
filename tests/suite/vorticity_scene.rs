//! The full model on driven scenes: staggered and monolithic schemes agree within their error
//! estimates; the vorticity stays finite and bounded at ε_p = 0.9 (large |Ṙ|, upwinding active);
//! the damped spectrum of a scene matches the exact dispersion relation.

use magbubble::model::vorticity::linear::{initial_guess, linear_modes};
use magbubble::model::vorticity::scene::{damped_spectrum, FullModel, SchemeSettings};
use magbubble::model::vorticity::FullState;
use magbubble::scene::*;
use std::collections::BTreeMap;

/// The paper's bubble (R0 = 10 µm, c1 = 0.1, c2 = 0.12 N/m, water, κ = 1.4) driven at
/// f_d = 1 MHz, shape modes 2 and 4, the vorticity closure on a `points` grid; a_2(0) = `a2`.
fn scene(amplitude: f64, a2: f64, points: usize) -> Scene {
    let (r0, p0) = (10e-6, 101325.0);
    let mut a = BTreeMap::new();
    if a2 != 0.0 {
        a.insert(2, a2);
    }
    Scene {
        bubble: Bubble { radius: r0, initial: Initial { radius: r0, velocity: 0.0, a, a_velocity: BTreeMap::new(), b: BTreeMap::new(), seed: Default::default() } },
        shell: Shell::mooney_rivlin(0.1, 0.12, 20e-9, 1.0, MembraneForm::Paper),
        gas: Gas { polytropic_exponent: 1.4, reference_pressure: p0, reference_pressure_given: true, vapour_pressure: 0.0, thermal: Thermal::Polytropic },
        liquid: Liquid { density: 1000.0, viscosity: 1e-3, ambient_pressure: p0, sound_speed: None, temperature: 293.15 },
        drive: Some(Drive::cosine(amplitude, 1e6)),
        field: None,
        modes: Modes { max_order: 4, viscous: Viscous::Vorticity, boundary_layer_frequency: BoundaryLayerFrequency::Auto, coupling: Coupling::Linear, credible_amplitude: 0.1 },
        vorticity: VorticityGrid { y_max: 3.0, points, stretching: 20.0, scheme: VorticityScheme::Monolithic },
        run: Run {
            duration: 10e-6,
            sample_interval: 1e-7,
            integrator: IntegratorSettings { method: Method::Radau5, rtol: 1e-6, atol: 1e-9, dt: 2.236e-9, dt_given: true, max_steps: 50_000_000 },
            blow_up_threshold: 0.5,
            max_output_bytes: 1e9,
        },
        warnings: Vec::new(),
        echo: None,
        population: None,
    }
}

/// Runs a scheme and returns the samples (nondimensional states).
fn samples(fm: &FullModel, scheme: VorticityScheme, dt: f64, rtol: f64, t_end: f64, every: f64) -> Vec<FullState> {
    let mut out = vec![];
    let settings = SchemeSettings { scheme, dt, rtol, atol: 1e-12, t_end, sample: every, max_steps: 10_000_000 };
    fm.run_nondim(&settings, &mut |s| {
        out.push(s.clone());
        true
    })
    .expect("run completes");
    out
}

fn max_diff(a: &[FullState], b: &[FullState], f: impl Fn(&FullState) -> f64) -> f64 {
    a.iter().zip(b).map(|(x, y)| (f(x) - f(y)).abs()).fold(0.0, f64::max)
}

#[test]
fn staggered_and_monolithic_agree_within_their_error_estimates() {
    // a_2(0) ≠ 0 so that the shape modes move without a field
    let sc = scene(0.5, 1e-8, 101);
    let fm = FullModel::from_scene(&sc).unwrap();
    let ts = fm.base().time_scale();
    let (t_end, every) = (sc.run.duration / ts, sc.run.sample_interval / ts);
    // staggered: error estimate from a step-halving pair (first order: e(dt) ≈ |x_dt − x_dt/2|)
    let s1 = samples(&fm, VorticityScheme::Staggered, 1e-3, 0.0, t_end, every);
    let s2 = samples(&fm, VorticityScheme::Staggered, 5e-4, 0.0, t_end, every);
    let m = samples(&fm, VorticityScheme::Monolithic, 0.0, 1e-8, t_end, every);
    assert_eq!(s2.len(), m.len());
    let scale = m.iter().map(|s| s.a[0].abs()).fold(0.0, f64::max);
    let est = max_diff(&s1, &s2, |s| s.a[0]);
    let diff = max_diff(&s2, &m, |s| s.a[0]);
    println!("a2: max |a2| = {scale:.3e}; staggered estimate {est:.3e} (dt' 1e-3 vs 5e-4); |staggered(5e-4) − monolithic| = {diff:.3e}");
    assert!(est < 0.2 * scale, "staggered step pair differs by {est} (scale {scale})");
    // first order: the error of the finer run is about the difference of the pair
    assert!(diff < 2.0 * est, "staggered(5e-4) vs monolithic {diff} exceeds 2× the staggered estimate {est}");
    let rd = max_diff(&s2, &m, |s| s.r);
    assert!(rd < 1e-6, "R differs by {rd} R0");
    // first order: the Richardson extrapolation 2·x(dt/2) − x(dt) is much closer to the monolithic run
    let rich = s1.iter().zip(&s2).zip(&m).map(|((a, b), c)| (2.0 * b.a[0] - a.a[0] - c.a[0]).abs()).fold(0.0, f64::max);
    println!("Richardson-extrapolated staggered vs monolithic: {rich:.3e}");
    assert!(rich < 0.2 * est, "Richardson {rich} vs estimate {est}");
}

#[test]
fn vorticity_stays_finite_and_bounded_at_large_drive() {
    let sc = scene(0.9, 1e-8, 101);
    let fm = FullModel::from_scene(&sc).unwrap();
    let ts = fm.base().time_scale();
    let (t_end, every) = (sc.run.duration / ts, sc.run.sample_interval / ts);
    for scheme in [VorticityScheme::Monolithic, VorticityScheme::Staggered] {
        let out = samples(&fm, scheme, 2.5e-4, 1e-6, t_end, every);
        let max_rdot = out.iter().map(|s| s.rdot.abs()).fold(0.0, f64::max);
        let max_t = out.iter().flat_map(|s| s.t_nodes.iter().flatten()).map(|v| v.abs()).fold(0.0, f64::max);
        let max_a = out.iter().map(|s| s.a[0].abs()).fold(0.0, f64::max);
        // bound: the wall vorticity is ~ 2(k+2)|ȧ|/(k+1)/R; T inside the layer must not exceed
        // a few times the largest wall value
        let max_adot = out.iter().map(|s| s.adot[0].abs()).fold(0.0, f64::max);
        println!("{scheme:?}: max |Ṙ| = {max_rdot:.3} R0/t*, max |T| = {max_t:.3e}, max |a2| = {max_a:.3e}, max |ȧ2| = {max_adot:.3e}");
        assert!(max_rdot > 0.1, "the drive should produce a large wall velocity");
        assert!(out.iter().all(|s| s.non_finite().is_none()));
        assert!(max_t.is_finite() && max_t < 1e3 * (max_adot + max_a), "T = {max_t} not bounded by the mode motion");
        assert!(max_a < 0.5, "a2 blew up: {max_a}");
    }
}

#[test]
fn damped_spectrum_of_a_scene_matches_the_dispersion_relation() {
    let sc = scene(0.0, 0.0, 201);
    let full = damped_spectrum(&sc).unwrap();
    assert_eq!(full.closure, "vorticity");
    let mut bl_scene = sc.clone();
    bl_scene.modes.viscous = Viscous::BoundaryLayer;
    let bl = damped_spectrum(&bl_scene).unwrap();
    for (f, b) in full.shape.iter().zip(&bl.shape) {
        println!("k = {}: full γ = {:.4e} ω = {:.4e}; boundary layer γ = {:.4e} ω = {:.4e}", f.k, f.decay_per_s, f.omega_rad_s, b.decay_per_s, b.omega_rad_s);
        assert!(f.decay_per_s > 0.0 && f.omega_rad_s > 0.0);
        // the exact dispersion relation with the model's own linear loads at R0
        let fm = FullModel::from_scene(&sc).unwrap();
        let ts = fm.base().time_scale();
        let modes = linear_modes(&fm.coupling(), 0.0, 1.0);
        let m = modes.iter().find(|m| m.k == f.k).unwrap();
        let exact = m.exact_root(initial_guess(m)).unwrap() / ts;
        assert!((f.decay_per_s / -exact.re - 1.0).abs() < 5e-3, "γ {} vs exact {}", f.decay_per_s, -exact.re);
        assert!((f.omega_rad_s / exact.im - 1.0).abs() < 5e-3, "ω {} vs exact {}", f.omega_rad_s, exact.im);
        // and the boundary layer overdamps (FORMULATION audit 13)
        assert!(b.decay_per_s > f.decay_per_s);
        let k = f.k as f64;
        let w0 = (12.0 * 0.22 * (k - 1.0) * (k + 1.0) * (k + 2.0) / (1000.0 * 1e-15 * (2.0 * k * k + 2.0 * k - 1.0))).sqrt();
        assert!((f.omega_rad_s / w0 - 1.0).abs() < 0.3, "ω = {} vs undamped {w0}", f.omega_rad_s);
    }
}
