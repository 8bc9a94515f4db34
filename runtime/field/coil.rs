//! Two opposed coils (paper eqs 2.30–2.33, Boridy expansion).
//!
//! H_2n = −(I/a) N1 sin θc P¹_2n(cos θc) (eq 2.31) with P¹_n(cos θ) = dP_n(cos θ)/dθ, the
//! Condon–Shortley phase of FORMULATION §1: P¹_2(x) = −3x√(1−x²),
//! P¹_4(x) = −√(1−x²)(35x³ − 15x)/2. At the default θc = acos√(3/7), P¹_4 = 0, so H_4 = 0.

use super::{coil_table, current_law, FieldError, FieldSource, TimeLaw, MU0};
use crate::scene::Coil;

/// P¹_2(x) = dP_2(cos θ)/dθ at x = cos θ (Condon–Shortley phase).
pub fn p1_2(x: f64) -> f64 {
    -3.0 * x * (1.0 - x * x).max(0.0).sqrt()
}

/// P¹_4(x) = dP_4(cos θ)/dθ at x = cos θ (Condon–Shortley phase).
pub fn p1_4(x: f64) -> f64 {
    -(1.0 - x * x).max(0.0).sqrt() * (35.0 * x.powi(3) - 15.0 * x) / 2.0
}

/// H_2 [A/m] of eq 2.31 for current `i` [A], distance `a` [m], `turns` N1, angle `theta` θc.
pub fn h2(i: f64, a: f64, turns: f64, theta: f64) -> f64 {
    -(i / a) * turns * theta.sin() * p1_2(theta.cos())
}

/// H_4 [A/m] of eq 2.31.
pub fn h4(i: f64, a: f64, turns: f64, theta: f64) -> f64 {
    -(i / a) * turns * theta.sin() * p1_4(theta.cos())
}

pub(super) fn source(c: &Coil, chi_s: f64, r0: f64, c1: f64) -> Result<FieldSource, FieldError> {
    if !(c.distance.is_finite() && c.distance > 0.0) {
        return Err(FieldError::NonPositive { key: "coil.distance", value: c.distance });
    }
    let (i_ref, current_omega) = current_law(&c.current);
    let h2v = h2(i_ref, c.distance, c.turns, c.angle);
    let h4v = if c.include_h4 { h4(i_ref, c.distance, c.turns, c.angle) } else { 0.0 };
    let distance = c
        .distance_oscillation
        .as_ref()
        .filter(|o| o.amplitude != 0.0)
        .map(|o| (o.amplitude, 2.0 * std::f64::consts::PI * o.frequency_hz));
    let law = if current_omega.is_none() && distance.is_none() {
        TimeLaw::Static
    } else {
        TimeLaw::Varying { current_omega, distance }
    };
    let label = match (current_omega.is_some(), distance.is_some()) {
        (false, false) => "coil field (static current)",
        (true, false) => "coil field (alternating current)",
        (false, true) => "coil field (static current, oscillating distance)",
        (true, true) => "coil field (alternating current, oscillating distance)",
    };
    // Rn = μ0 χ_s H2² R0² / (2 c1 a²)  (paper §5.4)
    let rn = MU0 * chi_s * h2v * h2v * r0 * r0 / (2.0 * c1 * c.distance * c.distance);
    Ok(FieldSource {
        table: coil_table(c.include_h4),
        kind: "coil",
        symbols: vec![
            ("mu0", MU0),
            ("chi_s", chi_s),
            ("H2", h2v),
            ("H4", h4v),
            ("a", c.distance),
            ("R0", r0),
        ],
        law,
        label: label.to_string(),
        group: ("rn", rn),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_angle_is_root_of_p14_and_h2_matches_formulation() {
        let theta = (3.0f64 / 7.0).sqrt().acos();
        assert!(p1_4(theta.cos()).abs() < 1e-14);
        // FORMULATION: a = 0.1 m, I = 100 kA, N1 = 1000 → H2 ≈ 1.1e9 A/m.
        let h = h2(100e3, 0.1, 1000.0, theta);
        assert!((h - 1.1223e9).abs() / 1.1223e9 < 1e-3, "H2 = {h}");
        // P¹_2 is dP2/dθ: compare with a finite difference of P2(cos θ).
        let p2 = |t: f64| 0.5 * (3.0 * t.cos().powi(2) - 1.0);
        let d = (p2(0.7 + 1e-6) - p2(0.7 - 1e-6)) / 2e-6;
        assert!((d - p1_2(0.7f64.cos())).abs() < 1e-8);
        let p4 = |t: f64| {
            let x = t.cos();
            (35.0 * x.powi(4) - 30.0 * x * x + 3.0) / 8.0
        };
        let d = (p4(0.7 + 1e-6) - p4(0.7 - 1e-6)) / 2e-6;
        assert!((d - p1_4(0.7f64.cos())).abs() < 1e-8);
    }
}
