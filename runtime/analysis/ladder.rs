//! The cheap-first Magnus ladder of the critical search (analysis/critical.rs, issue 16) as an
//! entry point of its own, for the callers that need only part of what
//! [`super::critical::critical_point`] and [`super::stability::floquet`] compute: the paper
//! figures (figs 5–11; issue 16 row 5, docs/stability.md "Cost of the stability curves").
//!
//! On one prepared orbit ([`Prepared`]) the monodromy is computed with n/64, n/32, n/16, n/8,
//! n/4 and n/2 Magnus steps per drive period (n = `magnus_steps`, 400: 6, 12, 25, 50, 100, 200;
//! critical.rs starts at n/32). At a rung m after m′ the fourth-order error of μ(m) is
//! estimated as d·r, d = |μ(m) − μ(m′)|, r = 1/((m/m′)⁴ − 1) (1/15 for doubled rungs), and the
//! Richardson value μ(m) + (μ(m) − μ(m′))·r is offered to a judge ([`climb`]), which accepts
//! it, asks for the next rung, or asks for the n-step computation at once. Two judges:
//! * [`verdict`]: the critical search's rule (critical.rs `floquet_eval`): the first rung where
//!   |max|μ| − 1| > 8d (≈ 120 × the estimated error) and d < 1e-3 max|μ|, else the pair n/4,
//!   n/2 if d < 1e-3 max|μ| there, else the n-step value (a pair that far apart is not in the
//!   O(h⁴) regime: its Richardson value can even be negative) — unless the pair's exponents
//!   decide ([`log_decided`]: |ln μ| > 8 |Δ ln μ|, the same rule on ln μ, accepted with the
//!   Richardson value of ln μ, [`Next::AcceptLog`]). The 6-step rung decides the points far from the threshold (the stable-throughout high
//!   frequencies, where 6 and 12 steps agree to ~1e-8) at half the cost of the 12/25 pair;
//! * [`converged`]: the figures' max-multiplier panel: the first Richardson value whose
//!   estimated error d·r is ≤ [`MULTIPLIER_TOLERANCE`] relative; where the rungs up to n/2
//!   cannot reach it (predicted from the O(h⁴) decay: d·r·(m/(n/2))⁴ still above it — the
//!   resonant points, whose n-step value itself differs from 2n steps by up to 1.3e-5), the
//!   n-step value as before.
//!
//! [`critical_outcome`] is [`super::critical::critical_point`] without the multipliers of the
//! bracket ends (recomputed there with n steps when their estimated error exceeds 1e-7, which
//! a figure never plots): the same scan and bracket search on these verdicts.

use super::bisect::{self, Eval, Outcome, Verdict};
use super::critical::CriticalOptions;
use super::floquet::Spectrum;
use super::stability::{base_model, prepare, Criterion, FloquetOptions, Prepared, StabilityError};
use crate::scene::Scene;

/// The fewest Magnus steps per drive period of a rung.
const MIN_RUNG: usize = 6;

/// Estimated relative error of μ(m) below which [`max_multiplier`] keeps the Richardson value:
/// far below the panel's resolution (a plotted value moves by less than 1e-7 of itself).
pub const MULTIPLIER_TOLERANCE: f64 = 1e-7;

/// One decided pair of rungs.
#[derive(Debug, Clone)]
pub struct Rung {
    /// Magnus steps per drive period of this rung and of the one before.
    pub steps: usize,
    pub previous: usize,
    /// The spectrum at `steps`.
    pub spectrum: Spectrum,
    /// max|μ| at `previous` (the spectrum's own at the n-step computation).
    pub coarse: f64,
    /// |μ(steps) − μ(previous)|.
    pub difference: f64,
    /// The Richardson value μ(m) + (μ(m) − μ(m′))·r.
    pub value: f64,
    /// The estimated error of μ(steps), d·r (0 for the n-step computation).
    pub error: f64,
    /// The Richardson value of the pair offered just before this one, as (its `steps`, its
    /// `value`), when that pair ended at this pair's `previous` rung (for an O(h⁶) estimate of
    /// this value's own error, critical.rs `kept_error`); `None` otherwise.
    pub before: Option<(usize, f64)>,
}

/// What a judge makes of a rung.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Next {
    Accept,
    /// Accept the Richardson value of ln max|μ| instead of max|μ|'s ([`verdict`]: a pair too far
    /// apart relative to μ, whose exponent is decided).
    AcceptLog,
    Climb,
    /// Skip the remaining rungs: compute n steps.
    Full,
}

/// The ladder's rungs for `n` steps: n/64, n/32, n/16, n/8, n/4, n/2, those of at least
/// [`MIN_RUNG`] steps (6, 12, 25, 50, 100, 200 of 400; 6, 12, 25, 50 of the `--quick` 100);
/// empty below 64 steps (then only n itself).
pub fn rungs(n: usize) -> Vec<usize> {
    if n < 64 {
        return Vec::new();
    }
    let mut r: Vec<usize> = [64, 32, 16, 8, 4, 2].iter().map(|d| n / d).filter(|&m| m >= MIN_RUNG).collect();
    r.dedup();
    r
}

/// The spectra already computed on one prepared orbit, by step count (`None`: the monodromy
/// overflowed), for [`climb_with`].
pub type Computed = Vec<(usize, Option<Spectrum>)>;

/// Climbs the ladder on `prep` until `judge` accepts a rung; the n-step spectrum (error 0) when
/// it asks for it or no rung is accepted. A rung whose monodromy overflows (a coarse step on a
/// fast-growing system) is skipped, and the next one starts a new pair.
pub fn climb(prep: &Prepared, n: usize, judge: impl Fn(&Rung) -> Next) -> Result<Rung, StabilityError> {
    climb_with(prep, n, judge, &mut Vec::new())
}

/// [`climb`] with the spectra of `computed` (of the same orbit and step counts: the monodromy is
/// deterministic, so a rung taken from it is the one computed again) and the ones it computes
/// added to it. The critical search keeps those of each evaluation, so that the climb of a bracket
/// end to its reporting tolerance (critical.rs `end_judge`) continues where the verdict's climb
/// stopped instead of starting again from the first rung.
pub fn climb_with(prep: &Prepared, n: usize, judge: impl Fn(&Rung) -> Next, computed: &mut Computed) -> Result<Rung, StabilityError> {
    let mut spectrum = |m: usize| -> Option<Spectrum> {
        if let Some((_, s)) = computed.iter().find(|c| c.0 == m) {
            return s.clone();
        }
        let s = prep.spectrum(m).ok();
        computed.push((m, s.clone()));
        s
    };
    let ladder = rungs(n);
    let mut coarse: Option<(usize, Spectrum)> = None;
    let mut before: Option<(usize, f64)> = None;
    for &m in &ladder {
        let Some(fine) = spectrum(m) else {
            (coarse, before) = (None, None);
            continue;
        };
        let Some((mc, coarse_spec)) = coarse.replace((m, fine.clone())) else { continue };
        let d = (fine.max_modulus - coarse_spec.max_modulus).abs();
        let r = 1.0 / ((m as f64 / mc as f64).powi(4) - 1.0);
        let value = fine.max_modulus + (fine.max_modulus - coarse_spec.max_modulus) * r;
        let coarse_mu = coarse_spec.max_modulus;
        let rung = Rung { steps: m, previous: mc, spectrum: fine, coarse: coarse_mu, difference: d, value, error: d * r, before: before.filter(|b| b.0 == mc) };
        match judge(&rung) {
            Next::Accept => return Ok(rung),
            Next::AcceptLog => {
                // ln μ(m) + (ln μ(m) − ln μ(m'))·r, and the distance of μ(m) to it as the error
                let (l, lc) = (rung.spectrum.max_modulus.ln(), coarse_mu.ln());
                let value = (l + (l - lc) * r).exp();
                let error = (value - rung.spectrum.max_modulus).abs();
                return Ok(Rung { value, error, ..rung });
            }
            Next::Climb => before = Some((m, value)),
            Next::Full => break,
        }
    }
    let n = n.max(1);
    let spectrum = match computed.iter().find(|c| c.0 == n) {
        Some((_, Some(s))) => s.clone(),
        _ => {
            let s = prep.spectrum(n)?;
            computed.push((n, Some(s.clone())));
            s
        }
    };
    let value = spectrum.max_modulus;
    Ok(Rung { steps: n, previous: n, spectrum, coarse: value, difference: 0.0, value, error: 0.0, before: None })
}

/// The critical search's judge (module doc; critical.rs `floquet_eval`).
pub fn verdict(n: usize) -> impl Fn(&Rung) -> Next {
    move |r: &Rung| {
        let mu = r.spectrum.max_modulus;
        let asymptotic = r.difference < 1e-3 * mu;
        let decided = (mu - 1.0).abs() > 8.0 * r.difference && asymptotic;
        if decided || (r.steps == n / 2 && asymptotic) {
            Next::Accept
        } else if !asymptotic && log_decided(mu, r.coarse) {
            Next::AcceptLog
        } else if r.steps >= n / 2 {
            // the pair n/4, n/2 still far apart (a fast-growing mode on a violent orbit: 1e38
            // against 1e33): its Richardson value can have any sign, so the n-step value decides
            Next::Full
        } else {
            Next::Climb
        }
    }
}

/// The same rule on the exponent: |ln μ| > 8 |ln μ − ln μ'| for the rungs' μ = μ(m), μ' = μ(m')
/// (both > 0). ln μ's error is μ's relative error, O(h⁴) like μ's; a pair whose exponents
/// agree to an eighth of the exponent's distance from 0 decides the verdict even when μ
/// itself is far from the O(h⁴) regime (μ ≫ 1: 1.2e30 after 2.0e31 at 200/100 steps, whose
/// linear Richardson value is negative; the log-Richardson value keeps the sign of ln μ, since
/// the correction (ln μ − ln μ')·r is below |ln μ|/120).
fn log_decided(mu: f64, coarse: f64) -> bool {
    if !(mu > 0.0 && coarse > 0.0 && mu.is_finite() && coarse.is_finite()) {
        return false;
    }
    let (l, lc) = (mu.ln(), coarse.ln());
    l.abs() > 8.0 * (l - lc).abs()
}

/// The max-multiplier panel's judge (module doc), relative tolerance `tol`.
pub fn converged(n: usize, tol: f64) -> impl Fn(&Rung) -> Next {
    move |r: &Rung| {
        let scale = tol * r.spectrum.max_modulus.abs();
        if r.error <= scale {
            Next::Accept
        } else if r.steps >= n / 2 || r.error * (r.steps as f64 / (n / 2) as f64).powi(4) > scale {
            Next::Full
        } else {
            Next::Climb
        }
    }
}

/// max|μ| over the orbit's period of `scene` within [`MULTIPLIER_TOLERANCE`] (module doc).
pub fn max_multiplier(scene: &Scene, opts: &FloquetOptions) -> Result<f64, StabilityError> {
    let model = base_model(scene)?;
    let prep = prepare(&model, scene, opts)?;
    let n = opts.magnus_steps.max(1);
    Ok(climb(&prep, n, converged(n, MULTIPLIER_TOLERANCE))?.value)
}

/// One Floquet evaluation of the critical search: the verdict with the margin ln max|μ|, and
/// the mode carrying the largest multiplier ("" where there is no orbit). The population's
/// window check (api/population.rs) asks it too: the verdict at the top of the range on the
/// cheap rungs, as the search decides its own points.
pub fn evaluate(scene: &Scene, opts: &FloquetOptions) -> Result<(Eval, String), StabilityError> {
    let model = base_model(scene)?;
    let prep = match prepare(&model, scene, opts) {
        Ok(prep) => prep,
        Err(StabilityError::Orbit(_)) => return Ok((Eval { verdict: Verdict::Undefined, margin: None }, String::new())),
        Err(e) => return Err(e),
    };
    let n = opts.magnus_steps.max(1);
    let rung = climb(&prep, n, verdict(n))?;
    let mode = prep.report(&rung.spectrum, n, None, opts.variant).mode;
    let verdict = if rung.value > 1.0 { Verdict::Unstable } else { Verdict::Stable };
    Ok((Eval { verdict, margin: Some(rung.value.ln()) }, format!("a{mode}")))
}

/// The outcome of [`super::critical::critical_point`] and its first unstable mode ("" if none),
/// without the bracket ends' multipliers (module doc). Floquet criterion only.
pub fn critical_outcome(
    scene_at: &dyn Fn(f64) -> Result<Scene, StabilityError>,
    opts: &CriticalOptions,
) -> Result<(Outcome, String), StabilityError> {
    if opts.criterion != Criterion::Floquet {
        return Err(StabilityError::Scene("ladder::critical_outcome: Floquet criterion only".into()));
    }
    let mut seen: Vec<(f64, String)> = Vec::new();
    let tolerance = if opts.relative_tol { bisect::Tolerance::Relative(opts.tol) } else { bisect::Tolerance::Absolute(opts.tol) };
    let outcome = bisect::critical_search(opts.lo, opts.hi, opts.scan, tolerance, |p| {
        let (eval, mode) = evaluate(&scene_at(p)?, &opts.floquet)?;
        seen.push((p, mode));
        Ok(eval)
    })
    .map_err(|e| match e {
        bisect::BisectError::Predicate { error } => error,
        other => StabilityError::Scene(other.to_string()),
    })?;
    let unstable = match outcome {
        Outcome::Critical { unstable, .. } => Some(unstable),
        Outcome::NoOrbit { no_orbit, .. } => Some(no_orbit),
        Outcome::UnstableAtBottom { bottom, .. } | Outcome::NoOrbitAtBottom { bottom, .. } => Some(bottom),
        Outcome::StableThroughout { .. } => None,
    };
    let mode = unstable.and_then(|u| seen.iter().rev().find(|e| e.0 == u)).map(|e| e.1.clone()).unwrap_or_default();
    Ok((outcome, mode))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Complex;

    fn rung(steps: usize, previous: usize, mu: f64, difference: f64) -> Rung {
        let r = 1.0 / ((steps as f64 / previous as f64).powi(4) - 1.0);
        let spectrum = Spectrum { multipliers: vec![Complex::new(mu, 0.0)], max_modulus: mu, block: 0, components: vec![(0, 1.0)] };
        Rung { steps, previous, spectrum, coarse: mu - difference, difference, value: mu + difference * r, error: difference * r, before: None }
    }

    #[test]
    fn rungs_of_the_full_and_the_quick_step_counts() {
        assert_eq!(rungs(400), vec![6, 12, 25, 50, 100, 200]);
        assert_eq!(rungs(100), vec![6, 12, 25, 50]);
        assert!(rungs(63).is_empty());
    }

    #[test]
    fn verdicts_need_a_clear_margin_and_an_asymptotic_pair() {
        let judge = verdict(400);
        assert_eq!(judge(&rung(12, 6, 0.6, 1e-8)), Next::Accept);
        // |μ − 1| = 1e-4 < 8d: climb
        assert_eq!(judge(&rung(12, 6, 1.0001, 1e-4)), Next::Climb);
        // far from 1 but the rungs still differ by more than 1e-3 of μ: decided on the exponent
        // when the exponents agree (13.816 after 13.806) …
        assert_eq!(judge(&rung(25, 12, 1e6, 1e4)), Next::AcceptLog);
        // … climb when they do not (13.8 after 20.7)
        let mut far = rung(25, 12, 1e6, 1e9 - 1e6);
        far.coarse = 1e9;
        assert_eq!(judge(&far), Next::Climb);
        // the last rung decides whatever the margin, when its pair is asymptotic
        assert_eq!(judge(&rung(200, 100, 1.0001, 1e-4)), Next::Accept);
        // … and when it is not, the n-step value does: 9.7e32 after 1.2e38 has a Richardson
        // value of −7.7e36, which read as "stable" (benches/population.toml, R0 8.68 µm, 500 kHz,
        // ε_p 1: `stability` said stable_throughout with max|μ| 4.9e32 at the bracket's top)
        let mut wild = rung(200, 100, 9.7e32, 1.15e38);
        wild.value = 9.7e32 + (9.7e32 - 1.15e38) / 15.0; // μ(n/2) + (μ(n/2) − μ(n/4))·r
        wild.coarse = 1.15e38;
        assert!(wild.value < 0.0);
        assert_eq!(judge(&wild), Next::Full);
    }

    #[test]
    fn a_pair_far_apart_in_mu_decides_on_its_exponent() {
        let judge = verdict(400);
        // the window check at ε_p = 1 (benches/population.toml, R0 9.5 µm, 500 kHz): 2.05e31 at
        // 100 steps, 1.22e30 at 200: the linear Richardson value is negative, the exponents
        // 71.99 and 69.28 agree to 2.7 < 69.3/8
        let mut r = rung(200, 100, 1.2216299351e30, 2.0473535288e31 - 1.2216299351e30);
        r.coarse = 2.0473535288e31;
        r.value = r.spectrum.max_modulus - r.difference / 15.0;
        assert!(r.value < 0.0);
        assert_eq!(judge(&r), Next::AcceptLog);
        // 4.6e39 at 50, 2.0e31 at 100: exponents 91.3 and 72.0 do not agree to 72/8: climb
        let mut r = rung(100, 50, 2.0473535288e31, 4.6257149339e39 - 2.0473535288e31);
        r.coarse = 4.6257149339e39;
        assert_eq!(judge(&r), Next::Climb);
        // a strongly stable point: 1e-12 after 1.1e-12 (exponents −27.6, −27.5)
        let mut r = rung(12, 6, 1e-12, 1e-13);
        r.coarse = 1.1e-12;
        assert_eq!(judge(&r), Next::AcceptLog);
        // near the threshold the exponent rule adds nothing: 1.5 after 1.52 is decided by μ's
        // own rule once the pair is asymptotic, and 1.02 after 1.2 (exponents 0.0198, 0.182) is not decided
        let mut r = rung(25, 12, 1.02, 0.18);
        r.coarse = 1.2;
        assert_eq!(judge(&r), Next::Climb);
    }

    /// climb with AcceptLog returns the log-Richardson value, of the sign of ln μ(m).
    #[test]
    fn the_log_richardson_value_keeps_the_verdict() {
        let (mu, coarse) = (1.2216299351e30f64, 2.0473535288e31f64);
        let r = 1.0 / 15.0;
        let value = (mu.ln() + (mu.ln() - coarse.ln()) * r).exp();
        assert!(value > 1.0 && value < mu, "{value:e}");
        assert!(log_decided(mu, coarse) && !log_decided(mu, 1e40) && !log_decided(f64::NAN, 1.0) && !log_decided(1.0, 0.0));
    }

    #[test]
    fn the_panel_stops_at_its_tolerance_or_goes_to_the_full_count() {
        let judge = converged(400, 1e-7);
        // estimated error 1e-9/15 relative: accept
        assert_eq!(judge(&rung(12, 6, 0.5, 1e-9)), Next::Accept);
        // 1e-5/15 now, ≈ 9e-12 predicted at 200 steps: climb
        assert_eq!(judge(&rung(12, 6, 1.0, 1e-5)), Next::Climb);
        // 1e2/17.8 relative to 2e12 at 25 steps: 200 steps cannot reach 1e-7, go to 400 at once
        assert_eq!(judge(&rung(25, 12, 2e12, 2e14)), Next::Full);
        // not reached at n/2: the full count
        assert_eq!(judge(&rung(200, 100, 1.0, 1e-5)), Next::Full);
    }
}
