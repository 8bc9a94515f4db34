//! Critical parameter by bracketing and bisection of a stability predicate.
//!
//! Assumptions (documented in docs/stability.md):
//! * the predicate answers "unstable?" for a parameter value p in [lo, hi] and is deterministic;
//! * the quantity wanted is the *first* instability met when p increases from `lo`
//!   (the stability boundary seen from the stable, small-forcing side);
//! * instability is monotone-ish: above the first unstable point the answer may flicker (stable
//!   tongues of Mathieu-type diagrams), which does not matter because only the first crossing
//!   is searched; an unstable window narrower than the scan spacing (hi − lo)/scan may be
//!   missed, so the critical value is an upper bound at that resolution.
//!
//! Procedure: test `lo` (unstable there → [`Outcome::UnstableAtBottom`]); scan the grid
//! lo + i (hi − lo)/scan, i = 1…scan, for the first unstable point (none → [`Outcome::StableThroughout`]);
//! bisect between it and the last stable grid point until the bracket is ≤ `tol`.

use serde::Serialize;

/// Result of [`critical`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "outcome", rename_all = "snake_case")]
pub enum Outcome {
    /// Stable at `stable`, unstable at `unstable`, |unstable − stable| ≤ tol; `value` is the midpoint.
    Critical { value: f64, stable: f64, unstable: f64, evaluations: usize },
    /// Stable at every scanned point up to and including the top of the range.
    StableThroughout { top: f64, evaluations: usize },
    /// Already unstable at the bottom of the range.
    UnstableAtBottom { bottom: f64, evaluations: usize },
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
            | Outcome::StableThroughout { evaluations, .. }
            | Outcome::UnstableAtBottom { evaluations, .. } => *evaluations,
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

/// Finds the first p in [lo, hi] where `unstable(p)` turns true (see the module doc).
/// Errors of the predicate are passed through as [`BisectError::Predicate`].
pub fn critical<E>(
    lo: f64,
    hi: f64,
    scan: usize,
    tol: f64,
    mut unstable: impl FnMut(f64) -> Result<bool, E>,
) -> Result<Outcome, BisectError<E>> {
    let mut unstable = |p| unstable(p).map_err(|error| BisectError::Predicate { error });
    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
        return Err(BisectError::BadRange { lo, hi });
    }
    if !(tol.is_finite() && tol > 0.0) {
        return Err(BisectError::BadTolerance { tol });
    }
    if scan == 0 {
        return Err(BisectError::BadScan { scan });
    }
    let mut evaluations = 1;
    if unstable(lo)? {
        return Ok(Outcome::UnstableAtBottom { bottom: lo, evaluations });
    }
    let mut stable = lo;
    let mut first_unstable = None;
    for i in 1..=scan {
        let p = if i == scan { hi } else { lo + (hi - lo) * i as f64 / scan as f64 };
        evaluations += 1;
        if unstable(p)? {
            first_unstable = Some(p);
            break;
        }
        stable = p;
    }
    let Some(mut bad) = first_unstable else {
        return Ok(Outcome::StableThroughout { top: hi, evaluations });
    };
    while bad - stable > tol {
        let mid = 0.5 * (stable + bad);
        evaluations += 1;
        if unstable(mid)? {
            bad = mid;
        } else {
            stable = mid;
        }
    }
    Ok(Outcome::Critical { value: 0.5 * (stable + bad), stable, unstable: bad, evaluations })
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
    fn predicate_errors_pass_through() {
        let r = critical(0.0, 1.0, 4, 1e-3, |p| if p > 0.5 { Err("boom") } else { Ok(false) });
        assert!(matches!(r, Err(BisectError::Predicate { error: "boom" })));
    }
}
