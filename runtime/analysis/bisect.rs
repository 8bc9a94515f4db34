//! Critical parameter by bracketing and root finding on a stability predicate.
//!
//! Assumptions (documented in docs/stability.md):
//! * the predicate answers, for a parameter value p in [lo, hi], stable / unstable / undefined
//!   (no reference state exists there, e.g. no stable periodic orbit: [`Verdict::Undefined`]),
//!   deterministically, optionally with a signed *margin* (> 0 unstable, < 0 stable; for
//!   Floquet ln max|μ|) continuous in p;
//! * the quantity wanted is the *first* point where stability ends when p increases from `lo`
//!   (the boundary seen from the stable, small-forcing side);
//! * an unstable window narrower than the scan spacing (hi − lo)/scan may be missed, so the
//!   critical value is an upper bound at that resolution.
//!
//! Procedure: test `lo` (not stable there → [`Outcome::UnstableAtBottom`] or
//! [`Outcome::NoOrbitAtBottom`]); scan the grid lo + i (hi − lo)/scan, i = 1…scan, for the first
//! point that is not stable (none → [`Outcome::StableThroughout`]); then shrink the bracket between
//! it and the last stable grid point until it is ≤ `tol`. With margins at both ends the new point
//! is the regula-falsi point with the Anderson–Björck scaling of an end kept twice in a row
//! (Anderson & Björck, BIT 13, 1973; Galdino 2011 compares it with Illinois), kept ≥ tol/2 inside
//! the bracket so that one more evaluation across the root can close it; without margins, or
//! when two steps together did not halve the bracket, it is the midpoint. The result is the same
//! first crossing that plain bisection finds (same scan), in fewer evaluations for a smooth
//! margin. (Before 2026-12-06 it was Illinois with a bisection after every step that did not
//! halve the bracket: on the population benchmark's 8 × 4 cut, 9.9 evaluations per point against
//! 8.4 now; the margin ln max|μ| is flat on the stable side until the tongue opens, so regula
//! falsi approaches from one side and single steps rarely halve the bracket.)

use serde::Serialize;

/// Result of [`critical`] / [`critical_search`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "outcome", rename_all = "snake_case")]
pub enum Outcome {
    /// Stable at `stable`, unstable at `unstable`, |unstable − stable| ≤ tol; `value` is the midpoint.
    Critical { value: f64, stable: f64, unstable: f64, evaluations: usize },
    /// Stable at `stable`, no reference state (no stable orbit) at `no_orbit`, bracket ≤ tol:
    /// stability ends because the state it is measured about disappears — not an instability.
    NoOrbit { value: f64, stable: f64, no_orbit: f64, evaluations: usize },
    /// Stable at every scanned point up to and including the top of the range.
    StableThroughout { top: f64, evaluations: usize },
    /// Already unstable at the bottom of the range.
    UnstableAtBottom { bottom: f64, evaluations: usize },
    /// No reference state at the bottom of the range.
    NoOrbitAtBottom { bottom: f64, evaluations: usize },
}

impl Outcome {
    /// The critical value, or `None` when the range holds no stable/unstable transition.
    pub fn value(&self) -> Option<f64> {
        match self {
            Outcome::Critical { value, .. } => Some(*value),
            _ => None,
        }
    }
    pub fn evaluations(&self) -> usize {
        match self {
            Outcome::Critical { evaluations, .. }
            | Outcome::NoOrbit { evaluations, .. }
            | Outcome::StableThroughout { evaluations, .. }
            | Outcome::UnstableAtBottom { evaluations, .. }
            | Outcome::NoOrbitAtBottom { evaluations, .. } => *evaluations,
        }
    }
    /// The CSV name of the outcome.
    pub fn name(&self) -> &'static str {
        match self {
            Outcome::Critical { .. } => "critical",
            Outcome::NoOrbit { .. } => "no_orbit",
            Outcome::StableThroughout { .. } => "stable_throughout",
            Outcome::UnstableAtBottom { .. } => "unstable_at_bottom",
            Outcome::NoOrbitAtBottom { .. } => "no_orbit_at_bottom",
        }
    }
}

/// What the predicate says about one parameter value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    Stable,
    Unstable,
    /// No reference state (e.g. no stable periodic orbit) at this value.
    Undefined,
}

/// A predicate's answer: the verdict and, if known, a signed margin (> 0 unstable, < 0 stable).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Eval {
    pub verdict: Verdict,
    pub margin: Option<f64>,
}

impl Eval {
    pub fn from_bool(unstable: bool) -> Self {
        Eval { verdict: if unstable { Verdict::Unstable } else { Verdict::Stable }, margin: None }
    }
}

/// When the bracket is small enough.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Tolerance {
    /// unstable − stable ≤ x (in the parameter's unit).
    Absolute(f64),
    /// unstable − stable ≤ x · stable (relative to the critical value; at 0.5 MHz the critical
    /// ε_p is ≈ 0.0039, so an absolute 1e-3 would be 25 % of it). Floor: 1e-12 (hi − lo).
    Relative(f64),
}

impl Tolerance {
    fn value(&self) -> f64 {
        match *self {
            Tolerance::Absolute(x) | Tolerance::Relative(x) => x,
        }
    }
    fn width(&self, good: f64, lo: f64, hi: f64) -> f64 {
        match *self {
            Tolerance::Absolute(x) => x,
            Tolerance::Relative(x) => (x * good.abs()).max(1e-12 * (hi - lo)),
        }
    }
}

/// Invalid bracketing settings, or an error of the predicate itself.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BisectError<E> {
    #[error("the search range must satisfy lo < hi with finite ends (got [{lo}, {hi}])")]
    BadRange { lo: f64, hi: f64 },
    #[error("the bisection tolerance must be finite and > 0 (got {tol})")]
    BadTolerance { tol: f64 },
    #[error("the scan needs at least one interval (got {scan})")]
    BadScan { scan: usize },
    #[error("{error}")]
    Predicate { error: E },
}

/// Finds the first p in [lo, hi] where `unstable(p)` turns true (plain bisection; see the
/// module doc).
pub fn critical<E>(
    lo: f64,
    hi: f64,
    scan: usize,
    tol: f64,
    mut unstable: impl FnMut(f64) -> Result<bool, E>,
) -> Result<Outcome, BisectError<E>> {
    critical_search(lo, hi, scan, Tolerance::Absolute(tol), |p| unstable(p).map(Eval::from_bool))
}

/// Finds the first p in [lo, hi] where `eval(p)` stops being stable (see the module doc).
/// Errors of the predicate are passed through as [`BisectError::Predicate`].
pub fn critical_search<E>(
    lo: f64,
    hi: f64,
    scan: usize,
    tolerance: Tolerance,
    mut eval: impl FnMut(f64) -> Result<Eval, E>,
) -> Result<Outcome, BisectError<E>> {
    let mut eval = |p| eval(p).map_err(|error| BisectError::Predicate { error });
    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
        return Err(BisectError::BadRange { lo, hi });
    }
    let tol = tolerance.value();
    if !(tol.is_finite() && tol > 0.0) {
        return Err(BisectError::BadTolerance { tol });
    }
    if scan == 0 {
        return Err(BisectError::BadScan { scan });
    }
    let mut evaluations = 1;
    let e_lo = eval(lo)?;
    match e_lo.verdict {
        Verdict::Unstable => return Ok(Outcome::UnstableAtBottom { bottom: lo, evaluations }),
        Verdict::Undefined => return Ok(Outcome::NoOrbitAtBottom { bottom: lo, evaluations }),
        Verdict::Stable => {}
    }
    let (mut good, mut g_good) = (lo, e_lo.margin);
    let mut first_bad = None;
    for i in 1..=scan {
        let p = if i == scan { hi } else { lo + (hi - lo) * i as f64 / scan as f64 };
        evaluations += 1;
        let e = eval(p)?;
        if e.verdict != Verdict::Stable {
            first_bad = Some((p, e));
            break;
        }
        (good, g_good) = (p, e.margin);
    }
    let Some((mut bad, e_bad)) = first_bad else {
        return Ok(Outcome::StableThroughout { top: hi, evaluations });
    };
    let (mut bad_verdict, mut g_bad) = (e_bad.verdict, e_bad.margin.filter(|_| e_bad.verdict == Verdict::Unstable));
    // The ends' margins as regula falsi uses them (Anderson–Björck scaled), which end moved
    // last, and the bracket widths before the last two steps (a bisection starts afresh).
    let (mut s_good, mut s_bad) = (g_good, g_bad);
    let mut last_moved_good: Option<bool> = None;
    let mut widths = [f64::INFINITY; 2];
    while bad - good > tolerance.width(good, lo, hi) {
        let tol = tolerance.width(good, lo, hi);
        let width = bad - good;
        // two steps that together did not halve the bracket are followed by a bisection
        let stalled = width > 0.5 * widths[1];
        let p = match (s_good, s_bad) {
            (Some(gs), Some(gb)) if !stalled && gs < 0.0 && gb > 0.0 => {
                let x = good + width * (-gs) / (gb - gs);
                let guard = (0.5 * tol).min(0.25 * width);
                x.clamp(good + guard, bad - guard)
            }
            _ => 0.5 * (good + bad),
        };
        evaluations += 1;
        let e = eval(p)?;
        let moved_good = e.verdict == Verdict::Stable;
        // Anderson–Björck: the end kept a second time in a row has its margin scaled by
        // m = 1 − g(p)/g(replaced end), or by ½ where m ≤ 0 (or a margin is missing)
        let factor = |new: Option<f64>, replaced: Option<f64>| match (new, replaced) {
            (Some(gn), Some(go)) if go != 0.0 && 1.0 - gn / go > 0.0 => 1.0 - gn / go,
            _ => 0.5,
        };
        if moved_good {
            if last_moved_good == Some(true) {
                s_bad = s_bad.map(|v| v * factor(e.margin, g_good));
            }
            (good, g_good, s_good) = (p, e.margin, e.margin);
        } else {
            let margin = e.margin.filter(|_| e.verdict == Verdict::Unstable);
            if last_moved_good == Some(false) {
                s_good = s_good.map(|v| v * factor(margin, g_bad));
            }
            (bad, bad_verdict, g_bad, s_bad) = (p, e.verdict, margin, margin);
        }
        last_moved_good = Some(moved_good);
        widths = if stalled { [f64::INFINITY; 2] } else { [width, widths[0]] };
    }
    let value = 0.5 * (good + bad);
    Ok(match bad_verdict {
        Verdict::Undefined => Outcome::NoOrbit { value, stable: good, no_orbit: bad, evaluations },
        _ => Outcome::Critical { value, stable: good, unstable: bad, evaluations },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::convert::Infallible;

    fn run(lo: f64, hi: f64, f: impl Fn(f64) -> bool) -> Outcome {
        critical::<Infallible>(lo, hi, 8, 1e-6, |p| Ok(f(p))).unwrap()
    }

    #[test]
    fn finds_a_threshold_within_tolerance() {
        let o = run(0.0, 1.0, |p| p > 0.3721);
        let v = o.value().unwrap();
        assert!((v - 0.3721).abs() <= 1e-6, "{o:?}");
        if let Outcome::Critical { stable, unstable, .. } = o {
            assert!(stable <= 0.3721 && unstable > 0.3721 && unstable - stable <= 1e-6);
        }
    }

    #[test]
    fn edge_cases_are_reported_not_guessed() {
        assert!(matches!(run(0.0, 1.0, |_| false), Outcome::StableThroughout { top, .. } if top == 1.0));
        assert!(matches!(run(0.0, 1.0, |_| true), Outcome::UnstableAtBottom { bottom, .. } if bottom == 0.0));
        // Threshold exactly at the top of the range: unstable only at hi.
        let o = run(0.0, 1.0, |p| p >= 1.0);
        assert!((o.value().unwrap() - 1.0).abs() <= 1e-6);
    }

    #[test]
    fn first_crossing_from_below_with_a_stable_tongue_above() {
        // Unstable on (0.2, 0.5) and again above 0.8: the first crossing 0.2 is the answer.
        let o = run(0.0, 1.0, |p| (p > 0.2 && p < 0.5) || p > 0.8);
        assert!((o.value().unwrap() - 0.2).abs() <= 1e-6);
    }

    #[test]
    fn bad_settings_are_errors() {
        let r = critical::<Infallible>(1.0, 0.0, 8, 1e-3, |_| Ok(false));
        assert!(matches!(r, Err(BisectError::BadRange { .. })));
        let r = critical::<Infallible>(0.0, 1.0, 8, 0.0, |_| Ok(false));
        assert!(matches!(r, Err(BisectError::BadTolerance { .. })));
        let r = critical::<Infallible>(0.0, 1.0, 0, 1e-3, |_| Ok(false));
        assert!(matches!(r, Err(BisectError::BadScan { .. })));
    }

    #[test]
    fn secant_search_finds_the_same_crossing_in_fewer_evaluations() {
        // A smooth margin with its root at 0.3721 (ln of a growing multiplier).
        let margin = |p: f64| (0.2 + 2.0 * p * p).ln() - (0.2f64 + 2.0 * 0.3721 * 0.3721).ln();
        let eval = |p: f64| Eval { verdict: if margin(p) > 0.0 { Verdict::Unstable } else { Verdict::Stable }, margin: Some(margin(p)) };
        let fast = critical_search::<Infallible>(0.0, 1.0, 8, Tolerance::Absolute(1e-6), |p| Ok(eval(p))).unwrap();
        let slow = run(0.0, 1.0, |p| margin(p) > 0.0);
        let (Outcome::Critical { value: v, stable, unstable, .. }, Some(w)) = (fast, slow.value()) else { panic!("{fast:?}") };
        assert!(stable <= 0.3721 && unstable > 0.3721 && unstable - stable <= 1e-6, "{fast:?}");
        assert!((v - w).abs() <= 1e-6);
        assert!(fast.evaluations() < slow.evaluations(), "{fast:?} vs {slow:?}");
    }

    /// The shape of the Floquet margin near a tongue: ln max|μ| flat at the damping (a complex
    /// pair of modulus √det) until the pair meets on the real axis at p₀, then rising like
    /// √(p − p₀) (the population benchmark's first bin at 500 kHz: flat at μ = 0.228 up to
    /// ε_p ≈ 0.035, μ = 1 at 0.0408, 2.45 at 0.051): the hard case of regula falsi (√ onset,
    /// flat end). The search still brackets the root within tol, in fewer evaluations than
    /// bisection (12 against 14 here; on the benchmark's real margins, which are closer to
    /// linear near the root, 8.5 per point against 9.8 with the former Illinois steps).
    #[test]
    fn a_margin_flat_on_the_stable_side() {
        let (p0, root) = (0.035f64, 0.0408f64);
        let c = (1.0 - 0.228) / (root - p0).sqrt();
        let mu = |p: f64| if p <= p0 { 0.228 } else { 0.228 + c * (p - p0).sqrt() };
        let eval = |p: f64| {
            let g = mu(p).ln();
            Eval { verdict: if g > 0.0 { Verdict::Unstable } else { Verdict::Stable }, margin: Some(g) }
        };
        let tol = Tolerance::Relative(1e-3);
        let fast = critical_search::<Infallible>(0.0, 1.0, 8, tol, |p| Ok(eval(p))).unwrap();
        let slow = critical_search::<Infallible>(0.0, 1.0, 8, tol, |p| Ok(Eval { margin: None, ..eval(p) })).unwrap();
        let Outcome::Critical { stable, unstable, evaluations, .. } = fast else { panic!("{fast:?}") };
        assert!(stable <= root && unstable > root && unstable - stable <= 1e-3 * stable, "{fast:?}");
        eprintln!("evaluations: {evaluations} (bisection: {})", slow.evaluations());
        assert!(evaluations < slow.evaluations(), "{fast:?} vs bisection {slow:?}");
    }

    #[test]
    fn relative_tolerance_scales_with_the_critical_value() {
        let o = critical_search::<Infallible>(0.0, 1.0, 8, Tolerance::Relative(1e-3), |p| Ok(Eval::from_bool(p > 0.0039))).unwrap();
        let Outcome::Critical { stable, unstable, .. } = o else { panic!("{o:?}") };
        assert!(stable <= 0.0039 && unstable > 0.0039 && unstable - stable <= 1e-3 * stable, "{o:?}");
    }

    #[test]
    fn undefined_points_are_their_own_outcome() {
        // Stable below 0.41, no reference state above: never called unstable.
        let e = |p: f64| Eval { verdict: if p > 0.41 { Verdict::Undefined } else { Verdict::Stable }, margin: None };
        let o = critical_search::<Infallible>(0.0, 1.0, 8, Tolerance::Absolute(1e-6), |p| Ok(e(p))).unwrap();
        let Outcome::NoOrbit { value, stable, no_orbit, .. } = o else { panic!("{o:?}") };
        assert!((value - 0.41).abs() <= 1e-6 && stable <= 0.41 && no_orbit > 0.41);
        assert_eq!(o.name(), "no_orbit");
        let o = critical_search::<Infallible>(0.0, 1.0, 8, Tolerance::Absolute(1e-6), |_| Ok(Eval { verdict: Verdict::Undefined, margin: None })).unwrap();
        assert!(matches!(o, Outcome::NoOrbitAtBottom { .. }));
    }

    #[test]
    fn predicate_errors_pass_through() {
        let r = critical(0.0, 1.0, 4, 1e-3, |p| if p > 0.5 { Err("boom") } else { Ok(false) });
        assert!(matches!(r, Err(BisectError::Predicate { error: "boom" })));
    }
}
