//! The keys of `shell.law = "sarkar"` (issue 31; docs/model.md, "Lipid shells: Sarkar"): the
//! exponential elasticity model of Paul et al. 2010 — E0^s (`shell.elasticity`, required),
//! α^s (`shell.elasticity_decay`), γ0 (`shell.reference_tension`) — and the unstrained radius R_E
//! resolved from them; its own keys refused under any other law.

use super::super::raw::RawShell;
use super::super::schema::fmt_num;
use super::super::types::Sarkar;
use super::check::Check;

/// Under a law other than Sarkar's: each Sarkar-only key given is an error.
pub(super) fn refuse_keys(c: &mut Check, rs: &RawShell, law: &str) {
    for (key, v) in [("shell.elasticity_decay", rs.elasticity_decay), ("shell.reference_tension", rs.reference_tension)] {
        if let Some(v) = v {
            c.push(key, Some(fmt_num(v)), format!("a key of shell.law = \"sarkar\", but shell.law = \"{law}\": it would do nothing (remove it or set shell.law)"));
        }
    }
}

/// β0 = R0²/R_E² − 1 ≤ 0 with γ0 + E0 β0 e^{−α β0} = 0 (no net tension at rest): Newton's method
/// from β = 0, safeguarded by bisection on (−1, 0], where the function is increasing
/// (derivative E0(1 − αβ)e^{−αβ} > 0). `None` if no root lies in (−1, 0].
pub fn unstrained_beta(e0: f64, alpha: f64, gamma0: f64) -> Option<f64> {
    let f = |b: f64| gamma0 + e0 * b * (-alpha * b).exp();
    if gamma0 == 0.0 {
        return Some(0.0);
    }
    let (mut lo, mut hi) = (-1.0, 0.0);
    if !(f(lo) < 0.0) {
        return None;
    }
    let mut b = 0.0;
    for _ in 0..200 {
        let fb = f(b);
        if fb == 0.0 {
            return Some(b);
        }
        if fb < 0.0 { lo = b } else { hi = b }
        let d = e0 * (1.0 - alpha * b) * (-alpha * b).exp();
        let mut next = b - fb / d;
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if (next - b).abs() <= 1e-16 {
            return Some(next);
        }
        b = next;
    }
    Some(b)
}

/// The Sarkar constants of a scene whose law is `sarkar`, every problem pushed to `c`.
pub(super) fn build(c: &mut Check, rs: &RawShell, r0: f64) -> Sarkar {
    for (key, v) in [("shell.shear_modulus", rs.shear_modulus), ("shell.area_dilatation", rs.area_dilatation)] {
        if let Some(v) = v.filter(|&v| key == "shell.shear_modulus" || v != 1.0) {
            c.push(key, Some(fmt_num(v)), "a key of shell.law = \"skalak\", but shell.law = \"sarkar\": it would do nothing");
        }
    }
    let e0 = match rs.elasticity {
        Some(x) => c.float("shell.elasticity", Some(x)),
        None => {
            c.push("shell.elasticity", None, "required with shell.law = \"sarkar\" (E0^s [N/m])");
            f64::NAN
        }
    };
    let alpha = c.float_or("shell.elasticity_decay", rs.elasticity_decay, 0.0);
    let gamma0 = c.float_or("shell.reference_tension", rs.reference_tension, 0.0);
    let mut re = f64::NAN;
    if e0 > 0.0 && alpha >= 0.0 && gamma0 >= 0.0 {
        match unstrained_beta(e0, alpha, gamma0) {
            Some(b) => re = r0 / (1.0 + b).sqrt(),
            None => c.push(
                "shell.reference_tension",
                Some(fmt_num(gamma0)),
                format!(
                    "no unstrained radius R_E: gamma0 + E0 beta exp(-alpha beta) stays positive for every R0 < R_E (gamma0 must be below E0 e^alpha = {} N/m)",
                    fmt_num(e0 * alpha.exp())
                ),
            ),
        }
    }
    Sarkar { elasticity: e0, elasticity_decay: alpha, reference_tension: gamma0, unstrained_radius: re }
}
