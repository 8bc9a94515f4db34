//! The Floquet routine on the Mathieu equation y'' + (a − 2q cos 2t) y = 0 (period π).
//!
//! Characteristic values a_0(q), b_1(q), a_1(q) are computed here independently from the Hill
//! (Fourier) matrices, cross-checked against Abramowitz & Stegun table 20.1, and the monodromy
//! trace must equal +2 (a_0: π-periodic) or −2 (b_1, a_1: π-antiperiodic) to ≤ 1e-6, with
//! |trace| > 2 (unstable) and < 2 (stable) on the correct sides of each curve.

use magbubble::analysis::floquet::{monodromy, LinearPeriodic};
use nalgebra::{DMatrix, SymmetricEigen};
use std::f64::consts::PI;

struct Mathieu {
    a: f64,
    q: f64,
}

impl LinearPeriodic for Mathieu {
    fn dim(&self) -> usize {
        2
    }
    fn matrix(&self, t: f64, m: &mut DMatrix<f64>) {
        m[(0, 0)] = 0.0;
        m[(0, 1)] = 1.0;
        m[(1, 0)] = -(self.a - 2.0 * self.q * (2.0 * t).cos());
        m[(1, 1)] = 0.0;
    }
}

/// Which characteristic value.
#[derive(Clone, Copy, Debug)]
enum Kind {
    /// even, π-periodic: y = Σ A_2r cos 2rt (symmetrised by √2 on the first coupling)
    A0,
    /// odd, 2π-periodic: y = Σ B_{2r+1} sin (2r+1)t
    B1,
    /// even, 2π-periodic: y = Σ A_{2r+1} cos (2r+1)t
    A1,
}

/// Lowest eigenvalue of the truncated Hill matrix (the recurrences of A&S 20.2.5–20.2.11).
fn characteristic(kind: Kind, q: f64) -> f64 {
    let n = 40;
    let mut h = DMatrix::zeros(n, n);
    for r in 0..n {
        h[(r, r)] = match kind {
            Kind::A0 => (2 * r) as f64 * (2 * r) as f64,
            Kind::B1 | Kind::A1 => (2 * r + 1) as f64 * (2 * r + 1) as f64,
        };
        if r + 1 < n {
            let off = if matches!(kind, Kind::A0) && r == 0 { 2f64.sqrt() * q } else { q };
            h[(r, r + 1)] = off;
            h[(r + 1, r)] = off;
        }
    }
    match kind {
        Kind::B1 => h[(0, 0)] -= q,
        Kind::A1 => h[(0, 0)] += q,
        Kind::A0 => {}
    }
    SymmetricEigen::new(h).eigenvalues.iter().copied().fold(f64::INFINITY, f64::min)
}

fn trace(a: f64, q: f64) -> f64 {
    monodromy(&Mathieu { a, q }, 0.0, PI, 2000).unwrap().trace()
}

#[test]
fn hill_matrix_matches_abramowitz_stegun_table_20_1() {
    // Published values: A&S table 20.1 (q = 1: 10 decimals; q = 5: a_0, a_1) and the q = 25
    // example output of Zhang & Jin's CVA1 ("Computation of Special Functions", 1996; 9 decimals).
    let table = [
        (1.0, Kind::A0, -0.4551386041, 1e-9),
        (1.0, Kind::B1, -0.1102488169, 1e-9),
        (1.0, Kind::A1, 1.8591080725, 1e-9),
        (5.0, Kind::A0, -5.8000460208, 1e-9),
        (5.0, Kind::A1, 1.8581875415, 1e-9),
        (25.0, Kind::A0, -40.256779547, 1e-8),
        (25.0, Kind::B1, -40.256778985, 1e-8),
        (25.0, Kind::A1, -21.314899691, 1e-8),
    ];
    for (q, kind, value, tol) in table {
        let c = characteristic(kind, q);
        assert!((c - value).abs() < tol, "{kind:?}(q={q}) = {c}, published {value}");
    }
}

#[test]
fn monodromy_trace_is_pm2_on_the_transition_curves() {
    let mut worst: f64 = 0.0;
    for q in [0.5, 1.0, 2.0, 5.0, 10.0] {
        for (kind, sign) in [(Kind::A0, 2.0), (Kind::B1, -2.0), (Kind::A1, -2.0)] {
            let a = characteristic(kind, q);
            let tr = trace(a, q);
            let err = (tr - sign).abs();
            worst = worst.max(err);
            assert!(err <= 1e-6, "{kind:?}(q={q}) = {a}: trace {tr}, expected {sign}");
        }
    }
    eprintln!("Mathieu: worst |trace ∓ 2| on a0, b1, a1 for q ∈ {{0.5, 1, 2, 5, 10}}: {worst:.3e}");
}

#[test]
fn stable_and_unstable_on_the_correct_sides() {
    // For q > 0: unstable below a_0, stable on (a_0, b_1), unstable on (b_1, a_1), stable above a_1
    // (until b_2). Probe at 2 % of the gap (or 0.01) on either side.
    for q in [1.0, 2.0] {
        let (a0, b1, a1) =
            (characteristic(Kind::A0, q), characteristic(Kind::B1, q), characteristic(Kind::A1, q));
        let d = 0.02 * (b1 - a0).min(a1 - b1);
        let cases = [(a0 - d, true), (a0 + d, false), (b1 - d, false), (b1 + d, true), (a1 - d, true), (a1 + d, false)];
        for (a, unstable) in cases {
            let m = monodromy(&Mathieu { a, q }, 0.0, PI, 2000).unwrap();
            let tr = m.trace();
            let s = m.spectrum();
            assert_eq!(tr.abs() > 2.0, unstable, "q={q} a={a}: trace {tr}");
            // Area-preserving flow: det = 1, so max |μ| > 1 exactly when unstable.
            assert_eq!(s.max_modulus > 1.0 + 1e-9, unstable, "q={q} a={a}: max|μ| {}", s.max_modulus);
        }
    }
}
