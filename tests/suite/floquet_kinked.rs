//! Floquet on a kinked lipid law (issue 31; docs/stability.md, "Floquet on a kinked law"): the
//! period map's RK4 steps and the monodromy's Magnus steps split at the orbit's branch switches
//! (analysis/periodic/switches.rs, analysis/floquet/magnus.rs), so the multipliers converge with the
//! step count at the methods' order 4.
//!
//! Before (measured on coil_marmottant.toml at 1 MHz, ε_p = 0.330964811, orbit at 400 RK4 steps,
//! `floquet --steps n`): max|μ| = 0.999728, 1.000002, 0.999885, 0.999883, 0.999912 for n = 100 …
//! 1600, and `stability` called that point unstable with max|μ| = 0.99989 < 1.

use magbubble::analysis::stability::{base_model, critical_point, prepare, CriticalOptions, Criterion, FloquetOptions, StabilityError};
use magbubble::analysis::bisect::Outcome;
use magbubble::scene::Scene;

/// The bracket end of the old `stability` run whose verdict was inconsistent.
const EPS: f64 = 0.330964811;

fn marmottant(eps: f64, extra: &[&str]) -> Scene {
    let mut set = vec![format!("drive.amplitude={eps}")];
    set.extend(extra.iter().map(|s| s.to_string()));
    magbubble::scene::load("scenes/coil_marmottant.toml", &set).unwrap()
}

/// max|μ| with `orbit` RK4 steps per period for the radial orbit and `magnus` Magnus steps, and
/// the number of branch switches located on the orbit.
fn max_mu(scene: &Scene, orbit: usize, magnus: usize) -> (f64, usize) {
    let mut opts = FloquetOptions::default();
    opts.shooting.steps_per_period = orbit;
    let model = base_model(scene).unwrap();
    let prep = prepare(&model, scene, &opts).unwrap();
    let switches = prep.orbit().unwrap().switches.len();
    (prep.spectrum(magnus).unwrap().max_modulus, switches)
}

/// Successive differences of a sequence and their ratios.
fn differences(mu: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let d: Vec<f64> = mu.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    let r = d.windows(2).map(|w| w[0] / w[1]).collect();
    (d, r)
}

/// Both step counts at n (the orbit's RK4 and the Magnus steps): the differences between
/// successive doublings shrink by ≈ 2⁴. Measured (n = 100 … 1600): differences 8.1e-8, 8.1e-9,
/// 1.1e-9, 7.0e-11, ratios 10.0, 7.4, 15.7 (the errors against the extrapolated value: ratios
/// 9.7, 7.9, 15.7, 15.9; the orbit is buckled 28 % of its period). Before the mend the differences did not
/// shrink at all (2.7e-4, 1.2e-4, 2.3e-6, 2.9e-5 with the Magnus steps alone).
#[test]
fn the_multipliers_converge_at_order_4_with_both_step_counts() {
    let s = marmottant(EPS, &[]);
    let ns = [100, 200, 400, 800, 1600];
    let (mu, sw): (Vec<f64>, Vec<usize>) = ns.iter().map(|&n| max_mu(&s, n, n)).unzip();
    let (d, r) = differences(&mu);
    println!("orbit and Magnus at n = {ns:?}: max|μ| = {mu:?}\n  switches {sw:?}, differences {d:?}, ratios {r:.2?}");
    // R crosses R_b twice per period (the orbit buckles once; it stays below R_r)
    assert!(sw.iter().all(|&k| k == 2), "{sw:?}");
    // O(h⁴): 16 per doubling once asymptotic; ≥ 12 (order ≥ 3.58) at 400 → 800 → 1600, and no
    // doubling below 6 before
    assert!(r.iter().all(|&x| x > 6.0), "differences {d:?}, ratios {r:?}");
    assert!(r[2] > 12.0, "differences {d:?}, ratios {r:?}");
    // the spread over 200 … 1600 steps is the 200-step error, ≈ 9e-9 (bound 3e-8): far below the
    // 2.7e-4 of the old code and the 1e-3 relative bracket tolerance's reach (slope ≈ 2 per unit ε_p)
    let spread = mu[1..].iter().fold(f64::NEG_INFINITY, |m, &x| m.max(x)) - mu[1..].iter().fold(f64::INFINITY, |m, &x| m.min(x));
    assert!(spread < 3e-8, "spread {spread:e}");
}

/// Each step count alone, the other at 400: the orbit's RK4 (ratios 15.9, 17.0, 12.9 measured)
/// and the Magnus steps (11.3, 8.2, 15.8; the split parts of the steps around a switch change
/// with n, so the constant of h⁴ does too).
#[test]
fn each_method_alone_converges_at_its_order() {
    let s = marmottant(EPS, &[]);
    let ns = [100, 200, 400, 800, 1600];
    let orbit: Vec<f64> = ns.iter().map(|&n| max_mu(&s, n, 400).0).collect();
    let magnus: Vec<f64> = ns.iter().map(|&n| max_mu(&s, 400, n).0).collect();
    let ((d_o, r_o), (d_m, r_m)) = (differences(&orbit), differences(&magnus));
    println!("orbit at n, Magnus 400: differences {d_o:?}, ratios {r_o:.2?}");
    println!("orbit 400, Magnus at n: differences {d_m:?}, ratios {r_m:.2?}");
    assert!(r_o.iter().all(|&x| x > 12.0), "RK4 orbit: {d_o:?} {r_o:?}");
    assert!(r_m.iter().all(|&x| x > 6.0) && r_m[2] > 12.0, "Magnus: {d_m:?} {r_m:?}");
    // the same orbit at 400 steps in both lists
    assert_eq!(orbit[2], magnus[2]);
}

/// The orbit's switches are located at R_b (within the RK4 error at the crossing: the location
/// is on the step's Hermite output, the state there from the RK4 step up to it), f is continuous
/// across them (the law's τ is), and a smooth law has none.
#[test]
fn the_switches_lie_at_the_buckling_radius_and_a_smooth_law_has_none() {
    let s = marmottant(EPS, &[]);
    let model = base_model(&s).unwrap();
    let prep = prepare(&model, &s, &FloquetOptions::default()).unwrap();
    let orbit = prep.orbit().unwrap();
    // σ(R0) = χ(R0²/R_b² − 1) = 0.02 N/m with χ = 1.31 N/m: R_b/R0 = 1/√(1 + 0.02/1.31)
    let rb_exact = 1.0 / (1.0 + 0.02 / 1.31f64).sqrt();
    for w in &orbit.switches {
        let dr = (w.y[0] - rb_exact).abs();
        let df = (w.f_after[1] - w.f_before[1]).abs() / w.f_before[1].abs().max(1e-300);
        println!("switch at t = {:.9}: R − R_b = {:.2e}, Ṙ = {:.3e}, relative f jump {df:.1e}, branch {}", w.t, w.y[0] - rb_exact, w.y[1], w.branch);
        assert!(dr < 1e-10, "R = {} vs R_b = {rb_exact}", w.y[0]);
        assert!(df < 1e-8, "f jumps across the switch: {df:e}");
    }
    println!("orbit period {:.6} (model units)", orbit.period());
    let times: Vec<f64> = orbit.switches.iter().map(|w| w.t).collect();
    assert!(times.windows(2).all(|w| w[1] > w[0]) && times.iter().all(|&t| t > orbit.t0 && t < orbit.t0 + orbit.period()));
    // the smooth variant: no switch, nothing located
    let smooth = marmottant(EPS, &["shell.law=\"marmottant-smooth\"", "shell.smoothing=0.01"]);
    let model = base_model(&smooth).unwrap();
    let prep = prepare(&model, &smooth, &FloquetOptions::default()).unwrap();
    assert!(prep.orbit().unwrap().switches.is_empty() && prep.orbit().unwrap().start_branch == 0);
}

/// `stability` at 1 MHz: each bracket end's verdict is that of its converged multiplier (1600
/// orbit and Magnus steps). Before the mend the bracket was 0.330856–0.330965 with
/// max|μ| = 0.99989 < 1 at its "unstable" end (the verdict of 12–25 Magnus steps across the
/// switches); now 0.331006–0.331315 (max|μ| 0.9999954 and 1.00064).
#[test]
fn the_bracket_ends_are_classified_by_their_converged_multipliers() {
    let at = |p: f64| -> Result<Scene, StabilityError> { Ok(marmottant(p, &[])) };
    let opts = CriticalOptions {
        criterion: Criterion::Floquet,
        lo: 0.0,
        hi: 1.0,
        scan: 8,
        tol: 1e-3,
        relative_tol: true,
        floquet: Default::default(),
        series: Default::default(),
    };
    let c = critical_point(&at, &opts).unwrap();
    let Outcome::Critical { stable, unstable, .. } = c.outcome else { panic!("{c:?}") };
    let (ms, mu) = (max_mu(&at(stable).unwrap(), 1600, 1600).0, max_mu(&at(unstable).unwrap(), 1600, 1600).0);
    println!("bracket {stable:.9}–{unstable:.9}, max|μ| {:.9} / {:.9}, at 1600 steps {ms:.9} / {mu:.9} ({})", c.max_multiplier_stable, c.max_multiplier_unstable, c.mode);
    assert!(c.max_multiplier_stable <= 1.0 && c.max_multiplier_unstable > 1.0, "{c:?}");
    assert!(ms <= 1.0 && mu > 1.0, "converged: {ms} / {mu}");
    // the reported multipliers are the converged ones to well within their distance from 1
    assert!((c.max_multiplier_stable - ms).abs() < 1e-7 && (c.max_multiplier_unstable - mu).abs() < 1e-7);
    // the old bracket's unstable end is stable
    let old = max_mu(&at(EPS).unwrap(), 1600, 1600).0;
    assert!(old < 1.0, "{old}");
    assert_eq!(c.mode, "a8");
}

/// A tension curve's knots are switches too (scenes/hard/tension_curve_kink.toml, ε_p 0.6,
/// 1 MHz, k ≤ 8: the orbit crosses knots at A/A0 = 0.98 … 1.04). `floquet --steps n` before the
/// mend: max|μ| = 2.439817, 2.438935, 2.439259, 2.439238, 2.439196 for n = 100 … 1600 (no
/// convergence); after (orbit and Magnus steps both n): differences 5.5e-6, 4.1e-7, 2.7e-8,
/// 1.7e-9 (ratios 13.4, 14.9, 15.7), 8 switches per period.
#[test]
fn a_tension_curve_converges_across_its_knots() {
    let s = magbubble::scene::load("scenes/hard/tension_curve_kink.toml", &[] as &[String]).unwrap();
    let ns = [100, 200, 400, 800, 1600];
    let (mu, sw): (Vec<f64>, Vec<usize>) = ns.iter().map(|&n| max_mu(&s, n, n)).unzip();
    let (d, r) = differences(&mu);
    println!("tension curve, orbit and Magnus at n = {ns:?}: max|μ| = {mu:?}\n  switches {sw:?}, differences {d:?}, ratios {r:.2?}");
    assert!(sw.iter().all(|&k| k >= 2 && k == sw[0]), "{sw:?}");
    assert!(r.iter().all(|&x| x > 10.0), "differences {d:?}, ratios {r:?}");
}
