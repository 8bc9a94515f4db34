//! One point of a stability diagram (paper §5.2, figs 5–11): the critical value of a scene
//! parameter, by the scan + bracket search of [`super::bisect::critical_search`] on the Floquet
//! or the time-series criterion. Definitions in docs/stability.md.
//!
//! **Cost** (issue 16, rows 3–5). A Floquet evaluation first finds the radial orbit once
//! ([`prepare`]); the monodromy is then computed on the ladder of [`ladder::climb`] with the
//! [`ladder::verdict`] judge, the same as the figures' (n/64, n/32, n/16, n/8, n/4 and n/2 Magnus
//! steps per drive period, n = `magnus_steps`, 400: 6, 12, 25, 50, 100, 200). The
//! fourth-order scheme's error at a rung m is ≈ d·r, d = |μ(m) − μ(previous rung m')|,
//! r = 1/((m/m')⁴ − 1) (1/15 for doubled rungs); the first rung where |max|μ| − 1| exceeds 8d
//! (≈ 120 × that error) and d is below 1e-3 relative decides the verdict, and the Richardson
//! value μ(m) + (μ(m) − μ(m'))·r is kept. A point no
//! rung decides (|max|μ| − 1| within ~1e-6 of the threshold, or a multiplier so large that the
//! rungs still differ) takes the Richardson value of n/4 and n/2, whose distance to the n-step
//! value is ≈ d/240 (from the O(h⁴) error; measured at 0.5 MHz near ε_c: 2e-8 with the coil at k ≤ 16, 2.2e-7 without a field at k ≤ 32).
//! The margin ln max|μ| feeds the regula-falsi bracket search. The multipliers reported at the
//! two ends of the final bracket are computed further (on the orbit already found, continuing
//! from the rungs the verdict computed: [`ladder::climb_with`]) when
//! their estimated distance to the n-step value exceeds 1e-7 (d·r, or for a value kept at n/4
//! or n/2 steps the three-rung estimate of [`kept_error`]): up the ladder to the first rung
//! with that estimate ≤ 1e-7, or with n steps where no rung can reach it ([`end_judge`]), so
//! the CSV is that of an n-step computation to ≤ 1e-6.
//!
//! **No orbit**: where no stable periodic radial orbit exists (collapse, non-finite state, none
//! of period m·T for the tried m), the point is [`Verdict::Undefined`]; the search reports
//! `no_orbit` when stability ends that way — it is never counted as unstable.

use super::bisect::{self, Eval, Outcome, Verdict};
use super::ladder;
use super::periodic::PeriodicOrbit;
use super::stability::{base_model, prepare, prepare_on, series_period, series_unstable, Criterion, FloquetOptions, SeriesOptions, StabilityError, NEEDS_PERIODIC};
use crate::scene::Scene;
use serde::Serialize;

/// Settings of one point of a stability diagram.
#[derive(Debug, Clone, PartialEq)]
pub struct CriticalOptions {
    pub criterion: Criterion,
    /// Search range of the varied parameter.
    pub lo: f64,
    pub hi: f64,
    /// Coarse scan intervals before the bracket search, and the bracket tolerance (bisect.rs).
    pub scan: usize,
    pub tol: f64,
    /// `tol` relative to the critical value (the stable end of the bracket) instead of absolute.
    pub relative_tol: bool,
    pub floquet: FloquetOptions,
    pub series: SeriesOptions,
}

/// The schema entry of a key a critical value can be searched over (`stability --vary`): a
/// real number. An integer key would be asked for values between its integers, each point
/// failing on its own (issue 29 item 12), so it is refused before any work.
pub fn varied_param(key: &str) -> Result<&'static crate::scene::schema::Param, String> {
    let p = crate::scene::numeric_param(key)?;
    if p.kind == crate::scene::schema::Kind::Int {
        return Err(format!(
            "`{key}` takes integers, and a critical value is searched by bisection over real values; \
             vary a real-valued key and give the integer values with --family {key}=V1,V2,…"
        ));
    }
    Ok(p)
}

/// One point of a stability diagram.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CriticalPoint {
    pub outcome: Outcome,
    /// The mode that goes unstable at the unstable end of the bracket ("" if none).
    pub mode: String,
    /// max|μ| at the stable and at the unstable end (Floquet only; NaN otherwise).
    pub max_multiplier_stable: f64,
    pub max_multiplier_unstable: f64,
    /// Orbit multiple at the stable end (1, 2, 4 …).
    pub orbit_multiple: usize,
    /// Anything unusual (e.g. "at 7.3e-1: no stable periodic orbit …").
    pub note: String,
}

/// The header of [`CriticalPoint::fields`].
pub const CRITICAL_HEADER: [&str; 10] = [
    "critical",
    "outcome",
    "stable",
    "unstable",
    "mode",
    "max_multiplier_stable",
    "max_multiplier_unstable",
    "orbit_multiple",
    "evaluations",
    "note",
];

impl CriticalPoint {
    pub fn fields(&self) -> Vec<String> {
        use Outcome::*;
        let (crit, s, u) = match self.outcome {
            Critical { value, stable, unstable, .. } => (value, stable, unstable),
            NoOrbit { stable, .. } => (f64::NAN, stable, f64::NAN),
            StableThroughout { top, .. } => (f64::NAN, top, f64::NAN),
            UnstableAtBottom { bottom, .. } => (f64::NAN, f64::NAN, bottom),
            NoOrbitAtBottom { .. } => (f64::NAN, f64::NAN, f64::NAN),
        };
        vec![
            format!("{crit:.8e}"),
            self.outcome.name().into(),
            format!("{s:.8e}"),
            format!("{u:.8e}"),
            self.mode.clone(),
            format!("{:.8e}", self.max_multiplier_stable),
            format!("{:.8e}", self.max_multiplier_unstable),
            self.orbit_multiple.to_string(),
            self.outcome.evaluations().to_string(),
            self.note.clone(),
        ]
    }
}

/// The estimated distance of a kept Richardson value `mu` (rungs mc < m) to the n-step value,
/// for the decision to recompute a bracket end's multipliers with n steps (module doc).
/// `e4` = d·r is the estimated error of μ(m) itself. With only two rungs that is all there is
/// (the Richardson value's own O(h⁶) error is not estimated: at 25/50 steps it reached 6e-7,
/// far above (d/15)(m/n)⁴). With the Richardson value `previous` = (mc, R(mc)) of the pair
/// before, the symmetric Magnus scheme's even error expansion gives R's O(h⁶) error
/// |R(m) − R(mc)| / ((m/mc)⁶ − 1), counted twice, plus the n-step value's own O(h⁴) error
/// e4·(m/n)⁴. The caller passes `previous` only for m ≥ n/4 (100 of 400 steps): below that
/// the rungs are not yet asymptotic (coil, 1.63 MHz near ε_c: μ(25 → 50 → 100 → 200) moved by
/// +4.1e-6, −2.4e-7, +1.4e-7, and R(25), R(50) agreed to 3e-6 while R(50) was 3.5e-7 from
/// the 400-step value).
fn kept_error(e4: f64, m: usize, n: usize, previous: Option<(usize, f64)>, mu: f64) -> f64 {
    match previous {
        Some((mc, rc)) => {
            let e6 = (mu - rc).abs() / ((m as f64 / mc as f64).powi(6) - 1.0);
            2.0 * e6 + e4 * (m as f64 / n as f64).powi(4)
        }
        None => e4,
    }
}

/// Estimated distance to the n-step value above which a bracket end's multiplier is computed
/// further (module doc).
const END_TOLERANCE: f64 = 1e-7;

/// The judge of a bracket end whose kept value is not within [`END_TOLERANCE`]: the first rung
/// whose Richardson value [`kept_error`] estimates within it (the same estimate that keeps the
/// values of the search itself), or the n-step value at once where the O(h⁴) decay of the
/// error says the rungs up to n/2 cannot reach it (as [`ladder::converged`]). Before, every such
/// end was recomputed with n steps: 33 of the 64 points of the coil curve, 40 % of its Magnus
/// steps.
fn end_judge(n: usize) -> impl Fn(&ladder::Rung) -> ladder::Next {
    move |r: &ladder::Rung| {
        let e = kept_error(r.error, r.steps, n, r.before.filter(|_| r.steps >= n / 4), r.value);
        if e <= END_TOLERANCE {
            ladder::Next::Accept
        } else if r.steps >= n / 2 || r.error * (r.steps as f64 / (n / 2) as f64).powi(4) > END_TOLERANCE {
            ladder::Next::Full
        } else {
            ladder::Next::Climb
        }
    }
}

/// One evaluated parameter value.
struct Seen {
    p: f64,
    mode: String,
    mu: f64,
    /// Estimated error of `mu` (0 when computed with the full step count).
    mu_error: f64,
    multiple: usize,
    note: String,
    /// The radial orbit and the ladder's spectra on it, reused when the multipliers of a
    /// bracket end are computed further.
    orbit: Option<PeriodicOrbit>,
    rungs: ladder::Computed,
}

/// Floquet verdict at one scene with the cheap-first step counts of the module doc.
fn floquet_eval(scene: &Scene, opts: &FloquetOptions, p: f64) -> Result<(Eval, Seen), StabilityError> {
    let model = base_model(scene)?;
    let prep = match prepare(&model, scene, opts) {
        Ok(prep) => prep,
        Err(StabilityError::Orbit(e)) => {
            let seen = Seen { p, mode: String::new(), mu: f64::NAN, mu_error: 0.0, multiple: 0, note: format!("at {p:.6e}: {e}"), orbit: None, rungs: Vec::new() };
            return Ok((Eval { verdict: Verdict::Undefined, margin: None }, seen));
        }
        Err(e) => return Err(e),
    };
    let n = opts.magnus_steps.max(1);
    // the ladder n/64, …, n/2 with the verdict judge, shared with the figures (ladder.rs)
    let mut rungs = Vec::new();
    let rung = ladder::climb_with(&prep, n, ladder::verdict(n), &mut rungs)?;
    let mu = rung.value;
    let mu_error = if rung.steps == n {
        0.0
    } else {
        kept_error(rung.error, rung.steps, n, rung.before.filter(|_| rung.steps >= n / 4), mu)
    };
    let spec = rung.spectrum;
    let report = prep.report(&spec, n, None, opts.variant);
    let verdict = if mu > 1.0 { Verdict::Unstable } else { Verdict::Stable };
    let orbit = prep.orbit().cloned();
    let seen = Seen { p, mode: format!("a{}", report.mode), mu, mu_error, multiple: report.orbit_multiple, note: String::new(), orbit, rungs };
    Ok((Eval { verdict, margin: Some(mu.ln()) }, seen))
}

/// The period [s] of the time-series window at a point with nothing periodic (ε_p = 0): that of
/// the range's upper end, else of its lower end (issue 29 item 1: the default range 0:1 starts
/// at ε_p = 0, where the drive is removed).
fn range_period(scene_at: &dyn Fn(f64) -> Result<Scene, StabilityError>, opts: &CriticalOptions) -> Result<f64, StabilityError> {
    for p in [opts.hi, opts.lo] {
        if let Some(tp) = series_period(&scene_at(p)?)? {
            return Ok(tp);
        }
    }
    Err(StabilityError::Scene(format!("{} at either end of the range {}:{}", NEEDS_PERIODIC, opts.lo, opts.hi)))
}

/// The critical value of the parameter `scene_at(p)` varies (see the module doc).
pub fn critical_point(
    scene_at: &dyn Fn(f64) -> Result<Scene, StabilityError>,
    opts: &CriticalOptions,
) -> Result<CriticalPoint, StabilityError> {
    let mut seen: Vec<Seen> = Vec::new();
    let tolerance = if opts.relative_tol { bisect::Tolerance::Relative(opts.tol) } else { bisect::Tolerance::Absolute(opts.tol) };
    let outcome = bisect::critical_search(opts.lo, opts.hi, opts.scan, tolerance, |p| {
        let scene = scene_at(p)?;
        let (eval, s) = match opts.criterion {
            Criterion::Floquet => floquet_eval(&scene, &opts.floquet, p)?,
            Criterion::Series => {
                let mut so = opts.series.clone();
                if so.period_s.is_none() && series_period(&scene)?.is_none() {
                    // ε_p = 0 removes the drive: watch over the period the other points have
                    so.period_s = Some(range_period(scene_at, opts)?);
                }
                let v = series_unstable(&scene, &so)?;
                let note = if v.reason.starts_with("failed") { v.reason.clone() } else { String::new() };
                let s = Seen { p, mode: v.mode, mu: f64::NAN, mu_error: 0.0, multiple: 0, note, orbit: None, rungs: Vec::new() };
                (Eval::from_bool(v.unstable), s)
            }
        };
        seen.push(s);
        Ok(eval)
    })
    .map_err(|e| match e {
        bisect::BisectError::Predicate { error } => error,
        other => StabilityError::Scene(other.to_string()),
    })?;
    use Outcome::*;
    let (s, u) = match outcome {
        Critical { stable, unstable, .. } => (Some(stable), Some(unstable)),
        NoOrbit { stable, no_orbit, .. } => (Some(stable), Some(no_orbit)),
        StableThroughout { top, .. } => (Some(top), None),
        UnstableAtBottom { bottom, .. } | NoOrbitAtBottom { bottom, .. } => (None, Some(bottom)),
    };
    // The multipliers at the bracket ends, at the full step count when the cheap value's
    // estimated error is above 1e-7.
    let end = |p: Option<f64>| -> Result<Option<(String, f64, usize)>, StabilityError> {
        let Some(e) = p.and_then(|p| seen.iter().rev().find(|e| e.p == p)) else { return Ok(None) };
        let mut mu = e.mu;
        if e.mu_error > END_TOLERANCE {
            // = floquet(scene).max_multiplier to END_TOLERANCE, on the orbit already found
            let scene = scene_at(e.p)?;
            let model = base_model(&scene)?;
            let prep = prepare_on(&model, &scene, &opts.floquet, e.orbit.as_ref())?;
            let n = opts.floquet.magnus_steps.max(1);
            mu = ladder::climb_with(&prep, n, end_judge(n), &mut e.rungs.clone())?.value;
        }
        Ok(Some((e.mode.clone(), mu, e.multiple)))
    };
    let (es, eu) = (end(s)?, end(u)?);
    let note: Vec<String> = seen.iter().filter(|e| !e.note.is_empty()).map(|e| e.note.clone()).take(1).collect();
    Ok(CriticalPoint {
        outcome,
        mode: eu.as_ref().map(|e| e.0.clone()).unwrap_or_default(),
        max_multiplier_stable: es.as_ref().map_or(f64::NAN, |e| e.1),
        max_multiplier_unstable: eu.as_ref().map_or(f64::NAN, |e| e.1),
        orbit_multiple: es.map_or(0, |e| e.2),
        note: note.join(" "),
    })
}
