//! Quadratic coupling against the second-order theory of a freely oscillating gas bubble
//! (issue 12, "one published second-order result"; docs/model.md, "Quadratic mode coupling",
//! "Against the literature").
//!
//! Benjamin (1989, J. Fluid Mech. 203, 419) recovered the second-order results of
//! Longuet-Higgins (1989, J. Fluid Mech. 201, 525) — a shape oscillation increases the mean
//! volume, lowers the mean gas pressure, and radiates a monopole at twice its frequency — from a
//! virial equation. For a bubble in an unbounded inviscid liquid, with the surface markers as
//! coordinates (T homogeneous of degree 3 in the positions, Σ p·ẋ = 2T) the exact identity is
//!
//!   dG/dt = 5T + 3(p_g − p∞)V − 2γA,   G = −ρ∮ φ x·n dS,
//!
//! (RP check: G = 4πρR⁴Ṙ). Its time average at second order, with a_n = ε R cos ω_n t and
//! Lamb's ω_n, gives the mean gas pressure below the Laplace pressure at the volume-equivalent
//! radius by 3(n−1)(n+2)γε²/(4(2n+1)R) (·1/R² in ε = a/R):
//!
//!   ⟨p_g⟩ − p∞ − 2γ/R_v = −3(n−1)(n+2)γε²/(4(2n+1)R).
//!
//! Both are evaluated here with the oracle's exact-surface potential (support::potential_flow),
//! independent of codegen: (1) the instantaneous identity along a run — its residual is O(ε³)
//! with quadratic coupling (the neglected cubic forces of the radial row, against O(1) weights)
//! and O(ε²) with linear coupling (halving ε: ÷8 or more against ÷4), undriven and — so that the
//! ρṘ²a², ρṘȧa and ρR̈a² terms of the radial row count — driven into an O(1) pulsation; (2) over a long run, the
//! Hann-weighted mean of p_g − p∞ − 2γ/R_v, the mean volume it implies, and the 2ω_n component
//! of R_v (the monopole) against their closed forms, n = 2 and n = 4. The monopole's closed form
//! follows from the identity at second order with R_v = R0 + δ(t): for a_n = εR0 cos ω_n t
//!
//!   ρR0²V̈ + (3κp_g0 − 2γ/R0)(V − V0) = π(n−1)(n+2)γε²R0²/(2n+1) · [3 − (4n−1) cos 2ω_n t],
//!
//! whose mean is the one above and whose 2ω_n part gives
//! δ = −(n−1)(n+2)(4n−1)γε²/(4(2n+1)ρR0²(ω0² − 4ω_n²)) cos 2ω_n t, ω0² = (3κp_g0 − 2γ/R0)/(ρR0²).

use crate::support::potential_flow::{Flow, Mode, Oracle, Virial};
use magbubble::model::layout::StateLayout;
use magbubble::integrate::{solve, Control, Method, Output};
use magbubble::model::Model;
use magbubble::scene::load;

const R0: f64 = 5e-6;
const GAMMA: f64 = 0.072;

/// An inviscid, undriven free bubble with a_n(0) = ε R0 sampled every `dt` [s] for `duration` [s]:
/// `extra` scene overrides (a drive); `rk4`: classical RK4 on the sample grid instead of DOP853
/// with its cubic Hermite dense output (docs/integrators.md), whose interpolation error,
/// ~h⁴|y⁗|/384 ≈ 10⁻⁵ of an O(1) pulsation, would swamp the identity's O(ε³) residual. Returns (γ̄, p0, samples of (t, Virial, p∞(t)), the gas
/// stiffness 3κp_g0 − 2γ̄ at R0, ρ̄), nondimensional.
fn run(n: usize, eps: f64, coupling: &str, duration: f64, dt: f64, extra: &[&str], rk4: bool) -> (f64, f64, Vec<(f64, Virial, f64)>, f64, f64) {
    let a = format!("bubble.initial.a={{{n} = {:e}}}", eps * R0);
    let c = format!("modes.coupling=\"{coupling}\"");
    let k = format!("modes.max_order={}", 2 * n);
    let g = format!("shell.surface_tension={GAMMA}");
    let mut o: Vec<&str> = vec![&g, "drive.amplitude=0.0", "gas.vapour_pressure=0.0", "liquid.viscosity=1e-12", &k, &a, &c];
    o.extend_from_slice(extra);
    let s = load("scenes/free_bubble.toml", &o).unwrap();
    let m = Model::from_scene(&s).unwrap();
    let (p, sc) = (m.params(), m.scales());
    let gamma = GAMMA / (sc.pressure * sc.length);
    let oracle = Oracle::new(16);
    let mut out = Vec::new();
    let t_end = duration / sc.time;
    let steps = (duration / dt).round();
    solve(m.system(), 0.0, m.initial_state(), t_end, &if rk4 { Method::Rk4 { dt: t_end / steps } } else { Method::Dop853 { rtol: 1e-13, atol: 1e-16 } }, Output::Every(t_end / steps), 50_000_000, &mut |t, y| {
        let flow = Flow { rho: p.rho, gamma, pg: 0.0, kappa: p.three_kappa / 3.0, p_inf: p.p0, radial: [y[0], y[1], 0.0] };
        let l = StateLayout::reduced(m.orders().len());
        let modes: Vec<Mode> = m.orders().iter().enumerate().map(|(i, &k)| Mode { n: k, amp: [y[l.a(i)], y[l.adot(i)], 0.0] }).collect();
        out.push((t, oracle.virial(&flow, p.pg0, p.r0, &modes), p.p_inf(t)));
        Control::Continue
    })
    .expect("integrates");
    (gamma, p.p0, out, p.three_kappa * p.pg0 - 2.0 * gamma, p.rho)
}

/// (max_t |G(t) − G(0) − ∫₀ᵗ (5T + 3(p_g − p∞)V − 2γA)|, max_t |G(t) − G(0)|), the integral by
/// Simpson's rule on pairs of samples.
fn virial_residual(n: usize, eps: f64, coupling: &str, dt: f64, extra: &[&str], rk4: bool) -> (f64, f64) {
    let (gamma, _, s, _, _) = run(n, eps, coupling, 6e-6, dt, extra, rk4);
    let rhs = |(_, v, p_inf): &(f64, Virial, f64)| 5.0 * v.kinetic + 3.0 * (v.pgas - p_inf) * v.volume - 2.0 * gamma * v.area;
    let (g0, mut integral, mut worst, mut scale) = (s[0].1.g, 0.0, 0.0_f64, 0.0_f64);
    for i in (2..s.len()).step_by(2) {
        let h = s[i].0 - s[i - 2].0;
        integral += h / 6.0 * (rhs(&s[i - 2]) + 4.0 * rhs(&s[i - 1]) + rhs(&s[i]));
        worst = worst.max((s[i].1.g - g0 - integral).abs());
        scale = scale.max((s[i].1.g - g0).abs());
    }
    (worst, scale)
}

#[test]
fn virial_identity_holds_to_third_order_with_quadratic_coupling_and_second_with_linear() {
    let (q1, s1) = virial_residual(2, 2e-2, "quadratic", 5e-9, &[], false);
    let (q2, s2) = virial_residual(2, 1e-2, "quadratic", 5e-9, &[], false);
    let (l1, _) = virial_residual(2, 2e-2, "linear", 5e-9, &[], false);
    let (l2, _) = virial_residual(2, 1e-2, "linear", 5e-9, &[], false);
    eprintln!("scale max|G − G0|: {s1:.3e} (eps 2e-2), {s2:.3e} (eps 1e-2)");
    eprintln!("quadratic: residual {q1:.3e}, {q2:.3e}, ratio {:.2}; /scale {:.2e}", q1 / q2, q1 / s1);
    eprintln!("linear:    residual {l1:.3e}, {l2:.3e}, ratio {:.2}; /scale {:.2e}", l1 / l2, l1 / s1);
    // O(ε³) or better against O(ε²): ≥ 8 and about 4 on halving ε (measured 9.8: an O(ε⁴) part
    // of the residual is still visible at ε = 2e-2); the bounds separate them
    assert!(q1 / q2 > 6.5, "quadratic: residual ratio {} is not ≥ 8 (third order)", q1 / q2);
    assert!((3.2..5.0).contains(&(l1 / l2)), "linear: residual ratio {} is not ≈ 4", l1 / l2);
    assert!(q1 < 0.1 * l1, "quadratic coupling must satisfy the virial identity much better");
}

#[test]
fn virial_identity_holds_for_a_pulsating_bubble_where_the_r_dot_terms_count() {
    // undriven, Ṙ = O(ε²) and the terms ρṘ²a², ρṘȧa, ρR̈a² of the radial row are O(ε⁴): driven
    // near its breathing resonance (ε_p = 0.2, 500 kHz) the bubble pulsates at finite amplitude
    // and every term of the row enters the identity at O(ε²)
    let drive = ["drive.amplitude=0.2", "drive.frequency_hz=5e5"];
    let (q1, s1) = virial_residual(2, 2e-2, "quadratic", 1.25e-9, &drive, true);
    let (q2, s2) = virial_residual(2, 1e-2, "quadratic", 1.25e-9, &drive, true);
    let (l1, _) = virial_residual(2, 2e-2, "linear", 1.25e-9, &drive, true);
    let (l2, _) = virial_residual(2, 1e-2, "linear", 1.25e-9, &drive, true);
    let (q3, _) = virial_residual(2, 5e-3, "quadratic", 1.25e-9, &drive, true);
    let (floor, _) = virial_residual(2, 0.0, "quadratic", 1.25e-9, &drive, true);
    eprintln!("driven, scale max|G − G0|: {s1:.3e} (eps 2e-2), {s2:.3e} (eps 1e-2); a = 0: residual {floor:.3e}");
    eprintln!("driven, quadratic: residual {q1:.3e}, {q2:.3e}, {q3:.3e} (eps 5e-3), ratios {:.2}, {:.2}", q1 / q2, q2 / q3);
    eprintln!("driven, linear:    residual {l1:.3e}, {l2:.3e}, ratio {:.2}", l1 / l2);
    assert!(floor < 0.01 * q3, "the integration's own residual {floor} is not negligible");
    assert!(q1 / q2 > 6.5 && q2 / q3 > 6.5, "quadratic: residual ratios {}, {} are not ≥ 8 (third order)", q1 / q2, q2 / q3);
    assert!((3.2..5.0).contains(&(l1 / l2)), "linear: residual ratio {} is not ≈ 4", l1 / l2);
    assert!(q1 < 0.01 * l1, "quadratic coupling must satisfy the virial identity much better");
}

/// What the long run gives, nondimensional (R0 = 1), with its closed-form predictions.
struct Means {
    /// (⟨p_g⟩ − p∞ − 2γ/R_v)/(γ̄ε²)
    excess: f64,
    /// ⟨R_v − R0⟩/ε²
    volume: f64,
    /// γ̄/(3κp_g0 − 2γ̄): a mean excess e implies ⟨R_v − R0⟩ = −e·γ̄/(3κp_g0 − 2γ̄) through the gas
    /// law p_g0 (R0/R_v)^{3κ} (the oscillation of the volume enters at O(ε⁴))
    compliance: f64,
    /// the cos 2ω_n t and sin 2ω_n t components of R_v/ε² (ω_n Lamb's at R0)
    monopole: (f64, f64),
    /// the closed form of the cos 2ω_n t component:
    /// −(n−1)(n+2)(4n−1)γ̄ / (4(2n+1)ρ̄(ω0² − 4ω_n²)), ω0² = (3κp_g0 − 2γ̄)/ρ̄
    monopole_theory: f64,
}

/// Hann-weighted means and 2ω_n components over a 60 µs run (≥ 25 periods of 2ω_n and ω0).
fn means(n: usize, eps: f64, coupling: &str) -> Means {
    let (gamma, p_inf, s, stiffness, rho) = run(n, eps, coupling, 60e-6, 1e-8, &[], false);
    let nf = n as f64;
    let omega = ((nf - 1.0) * (nf + 1.0) * (nf + 2.0) * gamma / rho).sqrt();
    let t_end = s.last().unwrap().0;
    let (mut w_sum, mut e_sum, mut r_sum, mut c_sum, mut s_sum) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (t, v, _) in &s {
        let w = (std::f64::consts::PI * t / t_end).sin().powi(2);
        let rv = (3.0 * v.volume / (4.0 * std::f64::consts::PI)).cbrt();
        w_sum += w;
        e_sum += w * (v.pgas - p_inf - 2.0 * gamma / rv);
        r_sum += w * (rv - 1.0);
        c_sum += 2.0 * w * (rv - 1.0) * (2.0 * omega * t).cos();
        s_sum += 2.0 * w * (rv - 1.0) * (2.0 * omega * t).sin();
    }
    let e2 = eps * eps;
    let omega0_sq = stiffness / rho;
    Means {
        excess: e_sum / w_sum / (gamma * e2),
        volume: r_sum / w_sum / e2,
        compliance: gamma / stiffness,
        monopole: (c_sum / w_sum / e2, s_sum / w_sum / e2),
        monopole_theory: -(nf - 1.0) * (nf + 2.0) * (4.0 * nf - 1.0) * gamma / (4.0 * (2.0 * nf + 1.0) * rho * (omega0_sq - 4.0 * omega * omega)),
    }
}

#[test]
fn mean_pressure_volume_and_monopole_of_a_shape_oscillation_match_second_order_theory() {
    for n in [2usize, 4] {
        let nf = n as f64;
        let theory = -3.0 * (nf - 1.0) * (nf + 2.0) / (4.0 * (2.0 * nf + 1.0));
        let q = means(n, 1e-2, "quadratic");
        let l = means(n, 1e-2, "linear");
        let rv_theory = -theory * q.compliance;
        eprintln!(
            "n = {n}: (⟨p_g⟩ − p∞ − 2γ/R_v)/(γε²/R): theory {theory:.4}, quadratic {:.4}, linear {:.4}; ⟨R_v − R0⟩/(ε²R0): theory {rv_theory:.4}, quadratic {:.4}, linear {:.4}",
            q.excess, l.excess, q.volume, l.volume
        );
        eprintln!(
            "n = {n}: R_v at 2ω_n, /(ε²R0): theory cos {:.5}, quadratic cos {:.5} sin {:.1e}, linear cos {:.5} sin {:.1e}",
            q.monopole_theory, q.monopole.0, q.monopole.1, l.monopole.0, l.monopole.1
        );
        // neglected: O(ε²) relative (the means of the cubic terms vanish for a_n ∝ cos), the
        // window's leakage of the ω0 oscillation and of the drift of the mode's phase (Hann,
        // ≥ 7 periods of their beat: ≲ 1e-3) and η = 1e-12 Pa s; 3 % leaves room for the leakage
        assert!((q.excess - theory).abs() < 0.03 * theory.abs(), "n = {n}: quadratic {} against {theory}", q.excess);
        assert!((l.excess - theory).abs() > 0.2 * theory.abs(), "n = {n}: linear coupling should miss it ({})", l.excess);
        // the mean volume increases (Longuet-Higgins 1989, Benjamin 1989), by the amount the mean
        // pressure implies
        assert!(q.volume > 0.0 && (q.volume - rv_theory).abs() < 0.03 * rv_theory, "n = {n}: ⟨R_v − R0⟩ {} against {rv_theory}", q.volume);
        // the monopole at twice the shape frequency (Longuet-Higgins 1989), amplitude ∝ ε²
        // amplitude and phase against cos 2ω_n t: the phase drifts by the mode's own O(ε²)
        // frequency shift, ≈ ε²ω_n T ≈ 0.04 rad over the run for n = 4 (bound 0.1 rad)
        let (c, s) = q.monopole;
        let mt = q.monopole_theory;
        let (amp, phase) = (c.hypot(s) * c.signum(), s.atan2(c.abs()));
        eprintln!("n = {n}: 2ω_n amplitude {amp:.5} (theory {mt:.5}), phase {phase:.3} rad");
        assert!((amp - mt).abs() < 0.03 * mt.abs() && phase.abs() < 0.1, "n = {n}: 2ω_n component ({c}, {s}) against {mt}");
        // with linear coupling R does not respond: R_v oscillates only by the shape's own volume,
        // a²/((2n+1)R0), whose 2ω_n part ε²/(2(2n+1)) is not the theory's
        // (n = 2: 0.1 against 0.116; asserted: it misses by more than 3× the bound above)
        assert!((l.monopole.0 - mt).abs() > 0.1 * mt.abs(), "n = {n}: linear coupling should miss the monopole ({})", l.monopole.0);
    }
}
