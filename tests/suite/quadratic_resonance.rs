//! Quadratic coupling at the 2:1 internal resonance of a free bubble, 2ω_n = ω0 (issue 12,
//! "one published second-order result"; docs/second-order-literature.md).
//!
//! The published statements (reachable here only through the abstracts, see the doc):
//! Longuet-Higgins (1991, J. Fluid Mech. 224, 531) — the monopole emission of a shape mode is
//! amplified when 2σ_n approaches the breathing frequency ω; Ffowcs Williams & Guo (1991, J. Fluid
//! Mech. 224, 507, as summarised in that abstract) — near this resonance a slow (secular) transfer
//! of energy between the shape oscillation and the volumetric mode diminishes the shape
//! amplitude; Harkin, Kaper & Nadim (2013, Phys. Fluids 25, 062101) — a pure shape distortion
//! excites significant volume pulsations in 2:1 internal resonance, the energy going back and
//! forth between the shape and the volume mode. The numbers are checked against the closed form of
//! the second-order virial identity (docs/model.md, "Against the literature"): with
//! a_n = εR0 cos ω_n t its volume equation ρR0²V̈ + ρR0²ω0²(V − V0) = πγε²R0²(n−1)(n+2)/(2n+1) ·
//! [3 − (4n−1) cos 2ω_n t] is forced exactly at resonance when 2ω_n = ω0, so
//!
//!   R_v − R0 ∋ −(n−1)(n+2)(4n−1)γε²/(8(2n+1)ρω0R0²) · t sin ω0 t,
//!
//! a secular growth at a rate fixed by the coefficients (no free parameter). The resonant radius
//! for κ = 1.4, γ = 0.072 N/m, p0 = 101325 Pa, p_v = 0 (p_g0 = p0 + 2γ/R0):
//! 4(n−1)(n+1)(n+2)γ/R0 = 3κp0 + (6κ − 2)γ/R0.

use crate::support::quadrature::{gauss_legendre, legendre_and_derivative};
use magbubble::model::layout::StateLayout;
use magbubble::integrate::{solve, Control, Method, Output};
use magbubble::model::Model;
use magbubble::scene::load;

const GAMMA: f64 = 0.072;
const KAPPA: f64 = 1.4;
const P0: f64 = 101325.0;

/// The radius at which 2ω_n = ω0 for the scene's equilibrium rule (see the module doc).
fn resonant_radius(n: usize) -> f64 {
    let l = ((n - 1) * (n + 1) * (n + 2)) as f64;
    GAMMA * (4.0 * l - 6.0 * KAPPA + 2.0) / (3.0 * KAPPA * P0)
}

/// A nondimensional undriven run (R0 = 1) started from rest at a_n = εR0.
struct Run {
    t: Vec<f64>,
    /// R_v/R0 − 1, R_v the radius of the exact volume (2π/3)∫(R + Σa_kP_k)³dx
    rv: Vec<f64>,
    /// a_n/R0
    a: Vec<f64>,
    omega0: f64,
    omega_n: f64,
    /// the closed-form coefficient of t sin ω0 t in R_v/R0 (module doc)
    secular: f64,
}

fn run(n: usize, eps: f64, coupling: &str, duration: f64, dt: f64) -> Run {
    let r0 = resonant_radius(n);
    let sets = [
        format!("bubble.radius={r0:e}"),
        format!("bubble.initial.a={{{n} = {:e}}}", eps * r0),
        format!("shell.surface_tension={GAMMA}"),
        format!("gas.polytropic_exponent={KAPPA}"),
        format!("liquid.ambient_pressure={P0}"),
        format!("modes.max_order={}", 2 * n),
        format!("modes.coupling=\"{coupling}\""),
    ];
    let mut o: Vec<&str> = sets.iter().map(String::as_str).collect();
    o.extend_from_slice(&["drive.amplitude=0.0", "gas.vapour_pressure=0.0", "liquid.viscosity=1e-12"]);
    let s = load("scenes/free_bubble.toml", &o).unwrap();
    let m = Model::from_scene(&s).unwrap();
    let (p, sc) = (m.params(), m.scales());
    let gamma = GAMMA / (sc.pressure * sc.length);
    let nf = n as f64;
    let omega0 = ((p.three_kappa * p.pg0 - 2.0 * gamma) / p.rho).sqrt();
    let omega_n = ((nf - 1.0) * (nf + 1.0) * (nf + 2.0) * gamma / p.rho).sqrt();
    let secular = -(nf - 1.0) * (nf + 2.0) * (4.0 * nf - 1.0) * gamma * eps * eps / (8.0 * (2.0 * nf + 1.0) * p.rho * omega0);
    let (x, w) = gauss_legendre(4 * n + 8);
    let basis: Vec<Vec<f64>> = m.orders().iter().map(|&k| x.iter().map(|&xi| legendre_and_derivative(k, xi).0).collect()).collect();
    let at = m.orders().iter().position(|&k| k == n).expect("mode n is simulated");
    let (t_end, steps) = (duration / sc.time, (duration / dt).round());
    let mut out = Run { t: Vec::new(), rv: Vec::new(), a: Vec::new(), omega0, omega_n, secular };
    let l = StateLayout::reduced(m.orders().len());
    solve(m.system(), 0.0, m.initial_state(), t_end, &Method::Dop853 { rtol: 1e-11, atol: 1e-14 }, Output::Every(t_end / steps), 50_000_000, &mut |t, y| {
        let volume: f64 = (0..x.len())
            .map(|q| w[q] * (y[0] + basis.iter().enumerate().map(|(i, b)| y[l.a(i)] * b[q]).sum::<f64>()).powi(3))
            .sum::<f64>()
            * 2.0
            * std::f64::consts::PI
            / 3.0;
        out.t.push(t);
        out.rv.push((3.0 * volume / (4.0 * std::f64::consts::PI)).cbrt() - 1.0);
        out.a.push(y[l.a(at)]);
        Control::Continue
    })
    .expect("integrates");
    out
}

/// Least squares of y on the given basis functions of t (normal equations, Gauss elimination).
fn fit(t: &[f64], y: &[f64], basis: &[&dyn Fn(f64) -> f64]) -> Vec<f64> {
    let k = basis.len();
    let mut a = vec![vec![0.0; k + 1]; k];
    for (&ti, &yi) in t.iter().zip(y) {
        let f: Vec<f64> = basis.iter().map(|b| b(ti)).collect();
        for r in 0..k {
            for c in 0..k {
                a[r][c] += f[r] * f[c];
            }
            a[r][k] += f[r] * yi;
        }
    }
    for c in 0..k {
        let piv = (c..k).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs())).unwrap();
        a.swap(c, piv);
        for r in 0..k {
            if r != c {
                let f = a[r][c] / a[c][c];
                for q in c..=k {
                    a[r][q] -= f * a[c][q];
                }
            }
        }
    }
    (0..k).map(|r| a[r][k] / a[r][r]).collect()
}

/// The fitted coefficients of t cos ω0 t and t sin ω0 t in R_v/R0 over [0, t_fit] (nondimensional),
/// with a constant and the free cos ω0 t, sin ω0 t of the initial condition in the fit.
fn secular_fit(r: &Run, t_fit: f64) -> (f64, f64) {
    let m = r.t.iter().take_while(|&&t| t <= t_fit).count();
    let w0 = r.omega0;
    let c = fit(&r.t[..m], &r.rv[..m], &[&|_| 1.0, &|t| (w0 * t).cos(), &|t| (w0 * t).sin(), &|t| t * (w0 * t).cos(), &|t| t * (w0 * t).sin()]);
    (c[3], c[4])
}

#[test]
fn a_shape_mode_at_the_two_to_one_resonance_drives_a_secularly_growing_monopole() {
    // fit over 20 µs for n = 2 (ten periods of ω0) and 200 µs for n = 4 (R0 = 60 µm)
    let mut dev = Vec::new();
    for (n, eps, t_fit) in [(2usize, 1e-2, 20e-6), (2, 2e-2, 20e-6), (4, 2e-2, 200e-6)] {
        let q = run(n, eps, "quadratic", t_fit, t_fit / 2000.0);
        let l = run(n, eps, "linear", t_fit, t_fit / 2000.0);
        let t_end = *q.t.last().unwrap();
        assert!(((q.omega0 - 2.0 * q.omega_n) / q.omega0).abs() < 1e-9, "n = {n}: not at the 2:1 resonance ({}, {})", q.omega0, q.omega_n);
        let (qc, qs) = secular_fit(&q, t_end);
        let (lc, ls) = secular_fit(&l, t_end);
        eprintln!(
            "n = {n}, eps = {eps}: t sin(w0 t) coefficient of R_v/R0: theory {:.5e}, quadratic {qs:.5e} (ratio {:.4}, t cos part {:.1e}), linear {ls:.1e} (t cos {lc:.1e})",
            q.secular,
            qs / q.secular,
            qc / q.secular
        );
        // neglected: the shape mode's own depletion and O(ε²) detuning over the fit window
        // (measured 0.26 % at ε = 0.01, 0.9 % at ε = 0.02, 1.2 % for n = 4)
        assert!((qs / q.secular - 1.0).abs() < 0.02, "n = {n}, eps = {eps}: secular rate {qs} against {}", q.secular);
        assert!((qc / q.secular).abs() < 0.02, "n = {n}, eps = {eps}: the growth is not in phase with the forcing ({qc})");
        // linear coupling: R does not respond, R_v only carries the shape's own volume
        assert!(ls.abs().max(lc.abs()) < 0.01 * q.secular.abs(), "n = {n}: linear coupling should show no secular monopole ({lc}, {ls})");
        if n == 2 {
            dev.push((qs / q.secular - 1.0).abs());
        }
    }
    // the deviation is of higher order in ε: halving ε reduces it (measured ×3.5)
    assert!(dev[0] < 0.5 * dev[1], "the deviation does not shrink with ε: {dev:?}");
}

/// Amplitudes (at ω0 of R_v/R0, at ω_n of a_n/R0) in windows of ten periods of ω0, half-overlapping.
fn envelopes(r: &Run) -> Vec<(f64, f64, f64)> {
    let (w0, wn) = (r.omega0, r.omega_n);
    let width = 20.0 * std::f64::consts::PI / w0;
    let mut out = Vec::new();
    let mut start = 0;
    while let Some(&t0) = r.t.get(start) {
        let end = start + r.t[start..].iter().take_while(|&&t| t < t0 + width).count();
        if r.t.last().map_or(true, |&t| t < t0 + width) {
            break;
        }
        let c = fit(&r.t[start..end], &r.rv[start..end], &[&|_| 1.0, &|t| (w0 * t).cos(), &|t| (w0 * t).sin()]);
        let s = fit(&r.t[start..end], &r.a[start..end], &[&|t| (wn * t).cos(), &|t| (wn * t).sin()]);
        out.push((t0, c[1].hypot(c[2]), s[0].hypot(s[1])));
        start += r.t[start..].iter().take_while(|&&t| t < t0 + width / 2.0).count();
    }
    out
}

#[test]
fn the_energy_goes_back_and_forth_between_shape_and_volume_mode_with_quadratic_coupling_only() {
    let eps = 2e-2;
    let q = run(2, eps, "quadratic", 1000e-6, 1e-8);
    let l = run(2, eps, "linear", 1000e-6, 1e-8);
    // second-order energies, ½Mω²A² each: shape M = 4πρR0³/((n+1)(2n+1)), breathing 4πρR0³;
    // at 2ω_2 = ω0 the breathing share is (n+1)(2n+1)(ω0/ω_2)²B²/A0² = 60 B²/ε²
    let share = |b: f64, s: f64| ((s / eps).powi(2), 60.0 * (b / eps).powi(2));
    let eq = envelopes(&q);
    let (i_min, &(t_min, _, s_min)) = eq.iter().enumerate().min_by(|x, y| x.1 .2.total_cmp(&y.1 .2)).unwrap();
    let &(t_back, _, s_back) = eq[i_min..].iter().max_by(|x, y| x.2.total_cmp(&y.2)).unwrap();
    let (e_lo, e_hi) = eq.iter().map(|&(_, b, s)| share(b, s)).map(|(x, y)| x + y).fold((f64::MAX, f64::MIN), |(lo, hi), e| (lo.min(e), hi.max(e)));
    let sc = q.t.last().unwrap() / 1000e-6;
    eprintln!(
        "quadratic: shape amplitude falls to {:.4} ε at {:.0} µs and returns to {:.4} ε at {:.0} µs; shape + breathing energy / initial in [{e_lo:.4}, {e_hi:.4}]",
        s_min / eps,
        t_min / sc * 1e6,
        s_back / eps,
        t_back / sc * 1e6
    );
    assert!(s_min < 0.2 * eps, "the shape mode does not give its energy to the volume mode (min {})", s_min / eps);
    assert!(s_back > 0.9 * eps, "the energy does not come back to the shape mode ({})", s_back / eps);
    // measured within [0.9964, 0.9979]: the rest is in a_4, the O(ε³) terms and the windows' leakage
    assert!(e_lo > 0.98 && e_hi < 1.01, "second-order energy not conserved across the exchange: [{e_lo}, {e_hi}]");
    let el = envelopes(&l);
    let s_dev = el.iter().map(|e| (e.2 / eps - 1.0).abs()).fold(0.0, f64::max);
    let b_max = el.iter().map(|e| e.1).fold(0.0, f64::max);
    eprintln!("linear: shape amplitude within {s_dev:.1e} of ε; R_v at ω0 at most {:.4} ε² (the shape's own volume: 0.1 ε²)", b_max / (eps * eps));
    assert!(s_dev < 1e-3, "linear coupling: the shape amplitude changes by {s_dev}");
    assert!(b_max < 0.11 * eps * eps, "linear coupling: R_v grows at ω0 ({})", b_max / (eps * eps));
}
