//! The stability boundary in the accuracy study (issue 13 part 5): the error of the critical ε_p
//! at one drive frequency — the number a stability diagram shows (paper §5.2, figs 5–11) —
//! against what it costs, per numerical choice, each against its own converged reference:
//!
//! * `magnus`: boundary layer, Magnus steps per drive period (reference: `magnus_reference`);
//! * `modes`: boundary layer, mode cutoff N (reference: N = `mode_reference`);
//! * `grid`: full vorticity model, grid points (reference: `grid_reference` points);
//! * `sdirk`: full vorticity model, SDIRK4 steps per drive period (reference: `full_reference`);
//! * `closure`: the boundary-layer critical value (reference settings) against the full model's
//!   (reference settings) — the modelling error of the closure, not a numerical one.
//!
//! Every critical value is a bracket search ([`critical_point`]) with a relative tolerance
//! `tol` (default 1e-7, below every error reported). Error = |ε_c − ε_c,ref| / ε_c,ref; cost =
//! wall time of the search and its number of Floquet evaluations. A rung whose search does not
//! end in a stable/unstable transition (no orbit, stable throughout …) has error NaN and its
//! outcome named.

use super::critical::{critical_point, CriticalOptions};
use super::stability::{Criterion, FloquetOptions, SeriesOptions, StabilityError};
use crate::scene::{Scene, Viscous};
use serde::Serialize;
use std::time::Instant;

/// What to compute.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CriticalAccuracyOptions {
    pub frequency_hz: f64,
    /// Search range of ε_p.
    pub lo: f64,
    pub hi: f64,
    /// Relative bracket tolerance of every search.
    pub tol: f64,
    pub magnus_steps: Vec<usize>,
    pub magnus_reference: usize,
    pub mode_ladder: Vec<usize>,
    pub mode_reference: usize,
    /// Grid points of the full-model ladder (empty: no full-model ladders, no closure row).
    pub grid_ladder: Vec<usize>,
    pub grid_reference: usize,
    pub full_steps: Vec<usize>,
    pub full_reference: usize,
}

impl CriticalAccuracyOptions {
    /// The full study (tens of minutes with the full model at k ≤ 8).
    pub fn full(frequency_hz: f64) -> Self {
        Self {
            frequency_hz,
            lo: 0.0,
            hi: 1.0,
            tol: 1e-7,
            magnus_steps: vec![25, 50, 100, 200, 400],
            magnus_reference: 3200,
            mode_ladder: vec![4, 8, 12, 16, 24],
            mode_reference: 32,
            grid_ladder: vec![51, 101, 201],
            grid_reference: 401,
            full_steps: vec![16, 32, 64],
            full_reference: 256,
        }
    }
    /// A short study (tests, a first look): small ladders, k ≤ the scene's N. The Magnus rungs
    /// stop at 50: from 64 steps on the search's cheap-first ladder ends in a Richardson value
    /// (analysis/critical.rs) whose ε_c error at 100 steps (8e-8 on the test scene) is already
    /// below the bracket tolerance, which the study cannot resolve.
    pub fn quick(frequency_hz: f64) -> Self {
        Self {
            magnus_steps: vec![25, 50],
            magnus_reference: 800,
            mode_ladder: vec![2, 4],
            mode_reference: 8,
            grid_ladder: vec![21, 41],
            grid_reference: 81,
            full_steps: vec![16, 32],
            full_reference: 64,
            ..Self::full(frequency_hz)
        }
    }
}

/// One critical-value search.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CriticalRung {
    /// "magnus", "modes", "grid", "sdirk" or "closure".
    pub ladder: &'static str,
    /// "boundary-layer" or "vorticity".
    pub closure: &'static str,
    /// Steps, N or grid points (0 for the closure row).
    pub setting: usize,
    /// ε_c (NaN when the search ended otherwise; see `outcome`).
    pub critical: f64,
    /// |ε_c − ε_c,ref| / ε_c,ref.
    pub error: f64,
    pub wall_seconds: f64,
    pub evaluations: usize,
    pub outcome: &'static str,
}

/// The study's result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CriticalAccuracyReport {
    pub options: CriticalAccuracyOptions,
    /// The reference searches (error 0 by definition), one per ladder.
    pub references: Vec<CriticalRung>,
    pub rungs: Vec<CriticalRung>,
}

/// Settings of one search.
#[derive(Clone, Copy)]
struct Setting {
    closure: Viscous,
    max_order: usize,
    steps: usize,
    points: usize,
}

fn search(base: &Scene, o: &CriticalAccuracyOptions, s: Setting) -> Result<(CriticalRung, f64), StabilityError> {
    let mut scene = base.clone();
    scene.modes.viscous = s.closure;
    scene.modes.max_order = s.max_order;
    scene.vorticity.points = s.points;
    let drive = scene.drive.as_mut().ok_or_else(|| StabilityError::Scene("the critical-ε_p study needs a [drive] section".into()))?;
    drive.frequency_hz = o.frequency_hz;
    let opts = CriticalOptions {
        criterion: Criterion::Floquet,
        lo: o.lo,
        hi: o.hi,
        scan: 8,
        tol: o.tol,
        relative_tol: true,
        floquet: FloquetOptions { magnus_steps: s.steps, ..FloquetOptions::default() },
        series: SeriesOptions::default(),
    };
    let at = |p: f64| {
        let mut sc = scene.clone();
        if let Some(d) = sc.drive.as_mut() {
            d.amplitude = p;
        }
        Ok(sc)
    };
    let start = Instant::now();
    let point = critical_point(&at, &opts)?;
    let wall = start.elapsed().as_secs_f64();
    let critical = point.outcome.value().unwrap_or(f64::NAN);
    let closure = if s.closure == Viscous::Vorticity { "vorticity" } else { "boundary-layer" };
    let rung = CriticalRung {
        ladder: "",
        closure,
        setting: 0,
        critical,
        error: f64::NAN,
        wall_seconds: wall,
        evaluations: point.outcome.evaluations(),
        outcome: point.outcome.name(),
    };
    Ok((rung, critical))
}

/// Runs the study on `scene` (its N, grid and closure settings are the ladders' fixed values).
pub fn critical_accuracy(
    scene: &Scene,
    o: &CriticalAccuracyOptions,
    progress: &mut dyn FnMut(&CriticalRung),
) -> Result<CriticalAccuracyReport, StabilityError> {
    if !(o.frequency_hz.is_finite() && o.frequency_hz > 0.0) {
        return Err(StabilityError::Scene(format!("frequency {} Hz: must be finite and > 0", o.frequency_hz)));
    }
    if scene.modes.max_order < 2 {
        return Err(StabilityError::NoShapeModes);
    }
    let bl = Setting {
        closure: Viscous::BoundaryLayer,
        max_order: scene.modes.max_order,
        steps: FloquetOptions::default().magnus_steps,
        points: scene.vorticity.points,
    };
    let full = Setting { closure: Viscous::Vorticity, steps: o.full_reference, points: o.grid_reference, ..bl };
    type Ladder<'a> = (&'static str, Setting, Vec<(usize, Setting)>);
    let mut ladders: Vec<Ladder> = vec![
        ("magnus", Setting { steps: o.magnus_reference, ..bl }, o.magnus_steps.iter().map(|&n| (n, Setting { steps: n, ..bl })).collect()),
        ("modes", Setting { max_order: o.mode_reference, ..bl }, o.mode_ladder.iter().map(|&n| (n, Setting { max_order: n, ..bl })).collect()),
    ];
    if !o.grid_ladder.is_empty() {
        ladders.push(("grid", full, o.grid_ladder.iter().map(|&n| (n, Setting { points: n, ..full })).collect()));
        ladders.push(("sdirk", full, o.full_steps.iter().map(|&n| (n, Setting { steps: n, ..full })).collect()));
    }
    let (mut references, mut rungs) = (Vec::new(), Vec::new());
    // The full model's reference serves two ladders: searched once.
    let mut cache: Vec<((Viscous, usize, usize, usize), (CriticalRung, f64))> = Vec::new();
    let mut search = |s: Setting| -> Result<(CriticalRung, f64), StabilityError> {
        let key = (s.closure, s.max_order, s.steps, s.points);
        if let Some((_, hit)) = cache.iter().find(|(k, _)| *k == key) {
            return Ok(hit.clone());
        }
        let found = search(scene, o, s)?;
        cache.push((key, found.clone()));
        Ok(found)
    };
    let mut full_ref = None;
    let mut bl_ref = None;
    for (name, reference, settings) in ladders {
        let (mut r, c_ref) = search(reference)?;
        r.ladder = name;
        r.setting = match name {
            "magnus" | "sdirk" => reference.steps,
            "modes" => reference.max_order,
            _ => reference.points,
        };
        r.error = 0.0;
        progress(&r);
        if name == "magnus" {
            bl_ref = Some(c_ref);
        }
        if name == "grid" {
            full_ref = Some(c_ref);
        }
        references.push(r);
        for (value, s) in settings {
            let (mut r, c) = search(s)?;
            r.ladder = name;
            r.setting = value;
            r.error = ((c - c_ref) / c_ref).abs();
            progress(&r);
            rungs.push(r);
        }
    }
    if let (Some(b), Some(f)) = (bl_ref, full_ref) {
        let r = CriticalRung {
            ladder: "closure",
            closure: "boundary-layer",
            setting: 0,
            critical: b,
            error: ((b - f) / f).abs(),
            wall_seconds: f64::NAN,
            evaluations: 0,
            outcome: "critical",
        };
        progress(&r);
        rungs.push(r);
    }
    Ok(CriticalAccuracyReport { options: o.clone(), references, rungs })
}
