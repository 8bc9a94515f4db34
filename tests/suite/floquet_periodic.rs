//! Shooting for periodic orbits on the forced Duffing oscillator
//! x'' + δx' − x + x³ = γ cos ωt (δ = 0.3, ω = 1.2; Guckenheimer & Holmes §2.2), whose attractor
//! is period-1 at small γ and period-2 after the first period doubling. The multiple reported by
//! `find_orbit` is checked independently against a long brute-force integration.

use magbubble::analysis::periodic::{find_orbit, PeriodicError, RkFlow, ShootingOptions};
use magbubble::integrate::OdeSystem;
use std::f64::consts::PI;

struct Duffing {
    gamma: f64,
}
const DELTA: f64 = 0.3;
const OMEGA: f64 = 1.2;

impl OdeSystem for Duffing {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = -DELTA * y[1] + y[0] - y[0].powi(3) + self.gamma * (OMEGA * t).cos();
    }
}

/// Smallest m ≤ 8 with |y(t + mT) − y(t)| < 1e-6 after a long transient (brute force).
fn brute_force_multiple(gamma: f64) -> Option<usize> {
    let sys = Duffing { gamma };
    let period = 2.0 * PI / OMEGA;
    let flow = RkFlow { sys: &sys, period, steps_per_period: 1000, switching: None };
    let mut y = vec![1.0, 0.0];
    let t = flow.advance(0.0, &mut y, 600).unwrap();
    let mut z = y.clone();
    let mut t2 = t;
    for m in 1..=8 {
        t2 = flow.advance(t2, &mut z, 1).unwrap();
        if (z[0] - y[0]).abs().max((z[1] - y[1]).abs()) < 1e-6 {
            return Some(m);
        }
    }
    None
}

#[test]
fn detects_period_one_and_period_two() {
    let period = 2.0 * PI / OMEGA;
    for (gamma, expected) in [(0.20, 1), (0.28, 2)] {
        let brute = brute_force_multiple(gamma);
        assert_eq!(brute, Some(expected), "brute-force multiple at γ = {gamma}");
        let orbit =
            find_orbit(&Duffing { gamma }, 0.0, &[1.0, 0.0], period, &ShootingOptions::default()).unwrap();
        assert_eq!(orbit.multiple, expected, "γ = {gamma}: {orbit:?}");
        assert!(orbit.residual <= 1e-9);
        assert!(orbit.max_multiplier() < 1.0);
        // The orbit really closes: integrate it once more.
        let flow = RkFlow { sys: &Duffing { gamma }, period, steps_per_period: 1000, switching: None };
        let mut y = orbit.y0.clone();
        flow.advance(orbit.t0, &mut y, orbit.multiple).unwrap();
        assert!((y[0] - orbit.y0[0]).abs() < 1e-8 && (y[1] - orbit.y0[1]).abs() < 1e-8);
    }
}

#[test]
fn the_reported_multiple_is_minimal() {
    // Searching only m = 4 at γ = 0.28 converges to a fixed point of P_4 that is the period-2
    // orbit: it must be reported as period 2 with the multipliers of P_2 (not their squares).
    let period = 2.0 * PI / OMEGA;
    let sys = Duffing { gamma: 0.28 };
    let two = find_orbit(&sys, 0.0, &[1.0, 0.0], period, &ShootingOptions::default()).unwrap();
    let opts = ShootingOptions { multiples: vec![4], ..ShootingOptions::default() };
    let four = find_orbit(&sys, 0.0, &[1.0, 0.0], period, &opts).unwrap();
    assert_eq!(four.multiple, 2, "{four:?}");
    assert!((four.max_multiplier() - two.max_multiplier()).abs() < 1e-8, "{} vs {}", four.max_multiplier(), two.max_multiplier());
    // And at γ = 0.2 a fixed point of P_2 is the period-1 orbit.
    let opts = ShootingOptions { multiples: vec![2], ..ShootingOptions::default() };
    assert_eq!(find_orbit(&Duffing { gamma: 0.2 }, 0.0, &[1.0, 0.0], period, &opts).unwrap().multiple, 1);
}

#[test]
fn period_one_is_refused_when_it_is_unstable() {
    // At γ = 0.28 the period-1 orbit exists but has a multiplier below −1; shooting restricted
    // to m = 1 must say so instead of returning it.
    let period = 2.0 * PI / OMEGA;
    let opts = ShootingOptions { multiples: vec![1], ..ShootingOptions::default() };
    let err = find_orbit(&Duffing { gamma: 0.28 }, 0.0, &[1.0, 0.0], period, &opts).unwrap_err();
    assert!(matches!(err, PeriodicError::NoStableOrbit { .. }), "{err}");
}

#[test]
fn blow_up_is_an_error_not_a_panic() {
    struct Explode;
    impl OdeSystem for Explode {
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
            dy[0] = y[0] * y[0];
        }
    }
    let err = find_orbit(&Explode, 0.0, &[1.0], 2.0, &ShootingOptions::default()).unwrap_err();
    assert!(matches!(err, PeriodicError::NonFinite { .. }), "{err}");
}
