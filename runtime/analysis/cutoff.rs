//! Certified thresholds (issue 31 part 5; docs/stability.md, "The cutoff: `--modes auto`"):
//! the critical value of one stability point with the mode cutoff N (`modes.max_order`) raised
//! in steps (doubled from the scene's N up to a limit) until the critical value moves by less
//! than the bracket tolerance, or the report that it does not converge — which mode leads at
//! the last N, and whether the shell's membrane tension goes negative on the radial orbit (the
//! mechanism of the Mooney–Rivlin membrane's −k³ normal stiffness, docs/stability.md).
//!
//! **Error bar** (`critical_error`): the root sum of squares of
//! * the bracket width |unstable − stable| of the last search;
//! * the Floquet step estimate: |ln max|μ|(2n) − ln max|μ|(n)| at the bracket's stable end
//!   (n = `magnus_steps`), turned into the parameter's unit by the slope of ln max|μ| across
//!   the bracket, (ln μ_u − ln μ_s)/(u − s) (the time-series criterion has no such estimate: 0);
//! * the last cutoff step |ε_c(N) − ε_c(N_prev)|.

use super::bisect::Outcome;
use super::critical::{critical_point, CriticalOptions, CriticalPoint};
use super::stability::{base_model, floquet, Criterion, StabilityError};
use crate::scene::{Scene, ShellLaw};
use serde::Serialize;

/// How the cutoff is raised.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct CutoffOptions {
    /// Largest N tried (even, ≤ the coefficient tables' k_max).
    pub limit: usize,
}

impl Default for CutoffOptions {
    fn default() -> Self {
        Self { limit: crate::scene::schema::MAX_ORDER_LIMIT }
    }
}

/// One rung of the cutoff ladder: N and the search's outcome there.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CutoffRung {
    pub max_order: usize,
    pub point: CriticalPoint,
}

/// The certified point: the last rung's point and the verdict on the cutoff.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CutoffPoint {
    /// The point at the last N tried (`max_order_used`).
    pub point: CriticalPoint,
    pub max_order_used: usize,
    /// The critical value (or the outcome without one) moved by less than the bracket
    /// tolerance between the last two N.
    pub cutoff_converged: bool,
    /// The error bar of the module doc (NaN without a critical value).
    pub critical_error: f64,
    /// The smallest membrane tension [N/m] of the shell law on the radial orbit at the stable
    /// end of the last search (`None`: no shell law with a tension, or no orbit).
    pub min_tension: Option<f64>,
    pub rungs: Vec<CutoffRung>,
}

/// The extra CSV columns of a `--modes auto` point (before `note`).
pub const CUTOFF_HEADER: [&str; 4] = ["max_order_used", "cutoff_converged", "critical_error", "min_tension"];

impl CutoffPoint {
    /// [`CriticalPoint::fields`] with [`CUTOFF_HEADER`]'s fields inserted before `note`, and the
    /// verdict on a cutoff that does not converge prepended to the note.
    pub fn fields(&self) -> Vec<String> {
        let mut f = self.point.fields();
        let note = f.pop().unwrap_or_default();
        f.push(self.max_order_used.to_string());
        f.push(self.cutoff_converged.to_string());
        f.push(format!("{:.8e}", self.critical_error));
        f.push(format!("{:.8e}", self.min_tension.unwrap_or(f64::NAN)));
        let mut notes = Vec::new();
        if !self.cutoff_converged {
            notes.push(self.divergence_note());
        }
        if !note.is_empty() {
            notes.push(note);
        }
        f.push(notes.join("; "));
        f
    }

    /// Why the cutoff is not certified: the critical values per N, the leading mode, the sign of
    /// the tension on the orbit.
    pub fn divergence_note(&self) -> String {
        let values: Vec<String> = self
            .rungs
            .iter()
            .map(|r| format!("N={}: {}", r.max_order, r.point.outcome.value().map_or(r.point.outcome.name().to_string(), |v| format!("{v:.6e}"))))
            .collect();
        let mode = if self.point.mode.is_empty() { "none".to_string() } else { self.point.mode.clone() };
        let tension = match self.min_tension {
            Some(t) if t < 0.0 => format!("membrane tension negative on the orbit (min {t:.3e} N/m)"),
            Some(t) => format!("membrane tension non-negative on the orbit (min {t:.3e} N/m)"),
            None => "no membrane tension".to_string(),
        };
        format!("cutoff not converged up to N={} ({}); mode {mode} leads; {tension}", self.max_order_used, values.join(", "))
    }
}

/// The smallest elastic membrane tension [N/m] of the scene's shell law over R in
/// [r_min, r_max] (m; 257 samples: the laws are functions of R alone, and the orbit passes
/// every R in between), from the law's radial load σ = Ŝ0 R/2 (docs/model.md, "The membrane",
/// "Lipid shells"). `None` for a free bubble and for the radial-only Church–Hoff shell.
pub fn min_tension(scene: &Scene, r_min: f64, r_max: f64) -> Result<Option<f64>, StabilityError> {
    if scene.shell.is_free() || matches!(scene.shell.law, ShellLaw::ChurchHoff { .. }) || !(r_min.is_finite() && r_max.is_finite()) {
        return Ok(None);
    }
    let model = base_model(scene)?;
    let sc = *model.scales();
    let p = *model.params();
    let lipid = crate::model::effects::lipid::LipidLaw::from_scene(&scene.shell.law, &sc);
    let s0 = |r: f64| match &lipid {
        Some(l) => l.s0(r).0,
        None => (p.membrane.s0)(r, p.r0, p.membrane_args.0, p.membrane_args.1),
    };
    let n = 256;
    let min = (0..=n)
        .map(|i| {
            let r = (r_min + (r_max - r_min) * i as f64 / n as f64) / sc.length;
            s0(r) * r / 2.0 * sc.pressure * sc.length
        })
        .fold(f64::INFINITY, f64::min);
    Ok(Some(min))
}

/// Whether two rungs agree to the bracket tolerance: both critical within `width`, or both the
/// same outcome without a critical value.
fn agree(a: &CriticalPoint, b: &CriticalPoint, width: f64) -> bool {
    match (a.outcome.value(), b.outcome.value()) {
        (Some(x), Some(y)) => (x - y).abs() < width,
        (None, None) => a.outcome.name() == b.outcome.name(),
        _ => false,
    }
}

/// The bracket tolerance in the parameter's unit at a critical value `c`.
fn tolerance_width(opts: &CriticalOptions, c: f64) -> f64 {
    if opts.relative_tol {
        (opts.tol * c.abs()).max(1e-12 * (opts.hi - opts.lo))
    } else {
        opts.tol
    }
}

/// The cutoff ladder of the scene's N, 2N, 4N … up to `cutoff.limit` (the limit itself last).
pub fn ladder(start: usize, limit: usize) -> Vec<usize> {
    let mut n = start.max(2);
    let mut v = vec![n];
    while n < limit {
        n = (2 * n).min(limit);
        v.push(n);
    }
    v
}

/// The critical value of `scene_at(p, N)` with N raised until it converges (module doc);
/// `start` is the scene's `modes.max_order`.
pub fn critical_point_auto(
    scene_at: &dyn Fn(f64, usize) -> Result<Scene, StabilityError>,
    start: usize,
    opts: &CriticalOptions,
    cutoff: &CutoffOptions,
) -> Result<CutoffPoint, StabilityError> {
    let mut rungs: Vec<CutoffRung> = Vec::new();
    let mut converged = false;
    for n in ladder(start, cutoff.limit) {
        let at = |p: f64| scene_at(p, n);
        let point = critical_point(&at, opts)?;
        if let Some(prev) = rungs.last() {
            let width = tolerance_width(opts, point.outcome.value().unwrap_or(0.0));
            converged = agree(&prev.point, &point, width);
        }
        rungs.push(CutoffRung { max_order: n, point });
        if converged {
            break;
        }
    }
    let last = rungs.last().expect("the ladder has at least one rung").clone();
    let used = last.max_order;
    let (bracket, stable_end) = match last.point.outcome {
        Outcome::Critical { stable, unstable, .. } => ((unstable - stable).abs(), Some((stable, unstable))),
        Outcome::NoOrbit { stable, no_orbit, .. } => ((no_orbit - stable).abs(), Some((stable, f64::NAN))),
        Outcome::StableThroughout { top, .. } => (f64::NAN, Some((top, f64::NAN))),
        _ => (f64::NAN, None),
    };
    // the orbit at the stable end: its R range, and the Floquet steps-vs-2×steps estimate
    let mut floquet_term = 0.0;
    let mut min_t = None;
    if let Some((s, u)) = stable_end {
        let scene = scene_at(s, used)?;
        if opts.criterion == Criterion::Floquet {
            let mut fo = opts.floquet.clone();
            fo.convergence_check = true;
            if let Ok(rep) = floquet(&scene, &fo) {
                min_t = min_tension(&scene, rep.r_min_m, rep.r_max_m)?;
                let (mus, muu) = (last.point.max_multiplier_stable, last.point.max_multiplier_unstable);
                let slope = (muu.ln() - mus.ln()) / (u - s);
                if let Some(c) = &rep.convergence {
                    let d = (c.max_multiplier_2x_steps.ln() - rep.max_multiplier.ln()).abs();
                    floquet_term = if d == 0.0 { 0.0 } else { d / slope.abs() };
                }
            }
        } else {
            // the series criterion has no orbit: the tension at rest (R0)
            min_t = min_tension(&scene, scene.bubble.radius, scene.bubble.radius)?;
        }
    }
    let step = match (rungs.len() >= 2).then(|| (rungs[rungs.len() - 2].point.outcome.value(), last.point.outcome.value())) {
        Some((Some(a), Some(b))) => (a - b).abs(),
        Some(_) => f64::NAN,
        None => 0.0,
    };
    let critical_error = if last.point.outcome.value().is_some() {
        (bracket * bracket + floquet_term * floquet_term + step * step).sqrt()
    } else {
        f64::NAN
    };
    Ok(CutoffPoint { point: last.point, max_order_used: used, cutoff_converged: converged, critical_error, min_tension: min_t, rungs })
}
