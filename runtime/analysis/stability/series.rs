//! The time-series criterion of stability (docs/stability.md): the nonlinear boundary-layer
//! model from a seeded shape perturbation over a fixed number of drive periods.

use crate::analysis::periodic;
use super::{drive_frequencies, StabilityError};
use crate::model::{Model, RunStatus};
use crate::scene::Scene;
use serde::Serialize;

/// Settings of the time-series criterion (docs/stability.md).
#[derive(Debug, Clone, PartialEq)]
pub struct SeriesOptions {
    /// Drive periods simulated.
    pub periods: usize,
    /// Initial a_k = seed · R0 for every simulated k whose a_k(0) is zero (unset or 0): a mode
    /// that starts at zero is otherwise seeded only by the coupling, possibly never, and its
    /// instability is not seen (issue 29 item 2).
    pub seed: f64,
    /// Unstable when the last quarter's peak exceeds `growth` × the third quarter's peak.
    pub growth: f64,
    /// The period [s] the window counts when the scene has nothing periodic (ε_p = 0 drops the
    /// drive, docs/scenes.md): a critical search sets the period of the diagram's frequency
    /// there ([`super::critical_point`]). `None`: such a scene is an error.
    pub period_s: Option<f64>,
}

impl Default for SeriesOptions {
    fn default() -> Self {
        Self { periods: 400, seed: 1e-6, growth: 2.0, period_s: None }
    }
}

/// What the time-series criterion needs and a scene may lack (the message of
/// [`series_unstable`] and of the checks before a diagram).
pub const NEEDS_PERIODIC: &str = "the time-series criterion counts drive periods and this scene has nothing periodic \
     (drive.amplitude = 0 removes the drive; no alternating coil current or oscillating coil distance)";

/// The common period [s] of everything periodic in `scene`, `None` when nothing is.
pub fn series_period(scene: &Scene) -> Result<Option<f64>, StabilityError> {
    let freqs = drive_frequencies(scene);
    if freqs.is_empty() {
        return Ok(None);
    }
    Ok(Some(periodic::common_period(&freqs, 1000, 1e-9)?))
}

/// The time-series verdict of one run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SeriesVerdict {
    pub unstable: bool,
    /// "blow_up", "growth" or "bounded" (or "failed: …").
    pub reason: String,
    /// Mode with the largest late/early ratio (or the blown-up one).
    pub mode: String,
    /// Peak ratio late/early of that mode.
    pub ratio: f64,
}

/// Time-series criterion: run the nonlinear boundary-layer model for `periods` drive periods
/// from a_k(0) = seed·R0; **unstable** iff the run is classified blow-up (threshold of
/// `run.blow_up_threshold`, or R ≤ 0, or non-finite) or, for some shape amplitude (a_k or b_k),
/// max|x| over the last quarter of the run exceeds `growth` × max|x| over the third quarter.
/// The first half is discarded: the seed first decays (its projection on the stable Floquet
/// directions dies out, by ~7 decades in 50 periods at 1.2 MHz) and the radial start-up
/// transient lasts hundreds of periods, so an early window can hide growth that Floquet sees
/// (tests/stability_series_window.rs). Detection limit: |μ| > growth^(4/periods) per period
/// (2^(1/100) = 1.0069 with the default 400 periods).
///
/// Every a_k that starts at zero is seeded with `seed`·R0 (the scene's nonzero seeds are
/// kept): a mode left at zero is fed only through the coupling, and the criterion was blind
/// to it (issue 29: every shipped scene seeds a_2 alone; at 1 MHz without a field the
/// critical ε_p was 0.763 in a_2 where Floquet gives 0.490 in a_4).
pub fn series_unstable(scene: &Scene, opts: &SeriesOptions) -> Result<SeriesVerdict, StabilityError> {
    let mut scene = scene.clone();
    let tp = match (series_period(&scene)?, opts.period_s) {
        (Some(tp), _) => tp,
        (None, Some(tp)) if tp.is_finite() && tp > 0.0 => tp,
        _ => return Err(StabilityError::Scene(NEEDS_PERIODIC.into())),
    };
    let r0 = scene.bubble.radius;
    for k in scene.modes.orders() {
        let a = scene.bubble.initial.a.entry(k).or_insert(0.0);
        if *a == 0.0 {
            *a = opts.seed * r0;
        }
    }
    let duration = opts.periods as f64 * tp;
    scene.run.duration = duration;
    scene.run.sample_interval = tp / 16.0;
    let model = Model::from_scene(&scene)?;
    let names = model.state_names();
    let cols = names.len();
    let (mut early, mut late) = (vec![0.0f64; cols], vec![0.0f64; cols]);
    let report = model.run(&scene.run, &mut |t, row| {
        let w = if t >= 0.75 * duration {
            &mut late
        } else if t >= 0.5 * duration {
            &mut early
        } else {
            return;
        };
        for (m, v) in w.iter_mut().zip(row) {
            *m = m.max(v.abs());
        }
    });
    match report.status {
        RunStatus::BlowUp { mode, .. } => {
            Ok(SeriesVerdict { unstable: true, reason: "blow_up".into(), mode, ratio: f64::INFINITY })
        }
        RunStatus::Failed { reason } => {
            Ok(SeriesVerdict { unstable: true, reason: format!("failed: {reason}"), mode: String::new(), ratio: f64::NAN })
        }
        RunStatus::OutOfCredibleRange { mode, .. } => {
            Ok(SeriesVerdict { unstable: true, reason: "out_of_credible_range".into(), mode, ratio: f64::INFINITY })
        }
        RunStatus::Completed => {
            let (mut best, mut ratio) = (1, 0.0);
            for c in 1..cols {
                let r = late[c] / early[c].max(f64::MIN_POSITIVE);
                if r > ratio {
                    (best, ratio) = (c, r);
                }
            }
            let unstable = ratio > opts.growth;
            Ok(SeriesVerdict {
                unstable,
                reason: if unstable { "growth".into() } else { "bounded".into() },
                mode: names.get(best).cloned().unwrap_or_default(),
                ratio,
            })
        }
    }
}
