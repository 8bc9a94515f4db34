//! Work–precision: what accuracy costs in time (issue 6, part 1).
//!
//! Every run goes through [`crate::model::simulate`] on a copy of the scene with changed run
//! settings, so the numbers are those a user gets from `magbubble run`.
//!
//! * **Samples.** All runs are sampled every Δ = duration / `samples` (dense output between
//!   steps for the adaptive methods — the error measured is the error of the output a user gets).
//!   RK4 steps are Δ/m for integer m, so its samples are grid values (no interpolation error).
//! * **Reference.** RK4 with Δt = Δ/m ≤ `reference_dt_star`·t* (default 1e-4 t*, ten times
//!   finer than the finest rung). Its own error is estimated by Richardson extrapolation:
//!   ‖y_Δt − y_2Δt‖ / (2⁴ − 1), using a second reference run at twice the step. For the full
//!   vorticity model (`modes.viscous = "vorticity"`) the reference is the monolithic scheme at
//!   rtol 1e-10, and its error estimate the difference to rtol 1e-9. When the RK4 reference fails
//!   at once (unstable at its step: a stiff scene, e.g. a Skalak shell with C = 1e3), Radau5 at
//!   rtol 1e-11 is the reference, its error estimate the difference to rtol 8e-11.
//! * **Error metric.** e_R = maxᵢ |R(tᵢ) − R_ref(tᵢ)| / R0, e_a = maxᵢ max_k |a_k(tᵢ) − a_k,ref(tᵢ)| / R0,
//!   e = max(e_R, e_a). A run that ends before the reference (blow-up, failure) has e = ∞ and
//!   is left out of the fits.
//! * **Blow-up scenes.** If the reference blows up at t_b, the study is re-run over
//!   [0, 0.9 t_b] (the duration is shortened; every rung then must reproduce a finite run).
//! * **Observed order.** `order_dt` = slope of log e against log Δt (fixed-step rungs);
//!   `order_work` = −slope of log e against log (rhs evaluations) for every ladder.
//! * **Wall time.** Median over `repeats` runs of the same settings.

pub use super::convergence::log_slope;
use crate::integrate::Stats;
use crate::model::{params::Scales, simulate, ModelError, RunStatus};
use crate::scene::{Method, Scene, Viscous, VorticityScheme};
use serde::Serialize;

/// Errors of an accuracy study.
#[derive(Debug, thiserror::Error)]
pub enum AccuracyError {
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error("the reference run ({what}) did not complete: {status}")]
    Reference { what: String, status: String },
    #[error("{what} = {value}: {reason}")]
    Setting { what: &'static str, value: String, reason: &'static str },
    /// The caller's cancel flag was raised (between two simulations).
    #[error("cancelled")]
    Cancelled,
}

/// What to run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AccuracyOptions {
    /// Simulated time [s] (`None`: the scene's `run.duration`).
    pub duration: Option<f64>,
    /// Number of output samples compared.
    pub samples: usize,
    /// RK4 (and staggered) steps in units of t*.
    pub dt_star: Vec<f64>,
    /// Relative tolerances of the adaptive methods (atol = 1e-3 · rtol on the nondimensional state).
    pub rtols: Vec<f64>,
    /// Reference RK4 step in units of t*.
    pub reference_dt_star: f64,
    /// Largest shape orders N of the mode ladder (empty: none).
    pub mode_ladder: Vec<usize>,
    /// Vorticity grid points of the grid ladder (full model only).
    pub grid_ladder: Vec<usize>,
    /// Repeats per setting; the wall time reported is their median.
    pub repeats: usize,
}

impl AccuracyOptions {
    /// The full study (minutes per scene).
    pub fn full() -> Self {
        Self {
            duration: None,
            samples: 1000,
            dt_star: vec![16e-3, 8e-3, 4e-3, 2e-3, 1e-3],
            rtols: vec![1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9],
            reference_dt_star: 1e-4,
            mode_ladder: vec![4, 8, 16, 32],
            grid_ladder: vec![51, 101, 201, 401],
            repeats: 3,
        }
    }
    /// The quick study used by tests: 5 µs, three rungs per ladder.
    pub fn quick() -> Self {
        Self {
            duration: Some(5e-6),
            samples: 200,
            dt_star: vec![8e-3, 4e-3, 2e-3],
            rtols: vec![1e-4, 1e-6, 1e-8],
            reference_dt_star: 2e-4,
            mode_ladder: vec![4, 8],
            grid_ladder: vec![51, 101],
            repeats: 1,
        }
    }
}

/// One rung of a ladder.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Rung {
    /// Δt [s] for fixed-step methods, rtol for adaptive ones.
    pub setting: f64,
    pub e_r: f64,
    pub e_a: f64,
    /// max(e_R, e_a).
    pub error: f64,
    /// Median wall time [s].
    pub wall_seconds: f64,
    pub stats: Stats,
    /// "completed", "blow_up at … s (mode)", "failed: …".
    pub status: String,
}

/// One integrator (or scheme) over its ladder.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ladder {
    /// "rk4", "dopri5", "dop853", "radau5", "staggered", "monolithic".
    pub method: String,
    /// "dt_s" or "rtol".
    pub setting_name: String,
    pub rungs: Vec<Rung>,
    pub order_dt: Option<f64>,
    /// `None` also when the work barely changes along the ladder (see [`order_vs_work`]).
    pub order_work: Option<f64>,
    /// max/min rhs evaluations over the rungs with a finite error (NaN with none).
    pub work_ratio: f64,
}

/// One rung of the mode ladder (or the grid ladder): cost and change against the largest.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SizeRung {
    /// N (largest shape order) or the number of grid points.
    pub size: usize,
    pub wall_seconds: f64,
    pub stats: Stats,
    /// max |R − R_largest| / R0.
    pub delta_r: f64,
    /// max |a2 − a2,largest| / R0.
    pub delta_a2: f64,
    pub status: String,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AccuracyReport {
    /// How the reference was made.
    pub reference: String,
    /// Estimated error of the reference (same metric as the rungs).
    pub reference_error: f64,
    pub reference_wall_seconds: f64,
    /// Compared time span [s] (shortened when the reference blows up).
    pub duration: f64,
    pub sample_interval: f64,
    pub t_star: f64,
    pub ladders: Vec<Ladder>,
    /// Settings used for the mode and grid ladders.
    pub size_ladder_method: String,
    /// The integrator the scene's own settings run (issue 34: under `auto`, which method the
    /// stiffness estimate chose and why).
    pub integrator: crate::model::IntegratorChoice,
    pub modes: Vec<SizeRung>,
    pub grid: Vec<SizeRung>,
}

/// A sampled run: t [s] and rows (R, a2, b2, …) [m].
struct Trajectory {
    rows: Vec<Vec<f64>>,
    status: RunStatus,
    stats: Stats,
    wall: f64,
}

/// Counts the runs of a study for its progress report: `f(done, total)` after every run.
struct Tally<'a> {
    done: std::cell::Cell<usize>,
    total: std::cell::Cell<usize>,
    f: &'a dyn Fn(usize, usize),
    /// Checked before every simulation: once set, the study ends with [`AccuracyError::Cancelled`].
    cancel: Option<&'a std::sync::atomic::AtomicBool>,
}

impl Tally<'_> {
    fn tick(&self) {
        self.done.set(self.done.get() + 1);
        self.total.set(self.total.get().max(self.done.get()));
        (self.f)(self.done.get(), self.total.get());
    }
    /// One more run than planned (the reference is run again, shortened or implicit).
    fn extend(&self) {
        self.total.set(self.total.get() + 1);
    }
}

fn run_once(scene: &Scene, tally: &Tally) -> Result<Trajectory, AccuracyError> {
    if tally.cancel.is_some_and(|c| c.load(std::sync::atomic::Ordering::Relaxed)) {
        return Err(AccuracyError::Cancelled);
    }
    let mut rows = vec![];
    let rep = simulate(scene, &mut |_, row| rows.push(row.to_vec()));
    tally.tick();
    let rep = rep?;
    Ok(Trajectory { rows, status: rep.status, stats: rep.stats, wall: rep.wall_seconds })
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Runs `repeats` times; the first trajectory with the median wall time.
fn run_timed(scene: &Scene, repeats: usize, tally: &Tally) -> Result<Trajectory, AccuracyError> {
    let mut first = run_once(scene, tally)?;
    let mut walls = vec![first.wall];
    for _ in 1..repeats.max(1) {
        walls.push(run_once(scene, tally)?.wall);
    }
    first.wall = median(&mut walls);
    Ok(first)
}

fn status_text(s: &RunStatus) -> String {
    match s {
        RunStatus::Completed => "completed".into(),
        RunStatus::BlowUp { t, mode } => format!("blow_up at {t:.4e} s ({mode})"),
        RunStatus::Failed { reason } => format!("failed: {reason}"),
        RunStatus::OutOfCredibleRange { t, mode, bound } => format!("out_of_credible_range at {t:.4e} s ({mode}, |a|/R0 > {bound})"),
    }
}

/// (e_R, e_a) of `run` against `reference` (rows R, a2, b2, a4, …); ∞ if `run` has fewer samples.
fn errors(run: &[Vec<f64>], reference: &[Vec<f64>], r0: f64) -> (f64, f64) {
    if run.len() < reference.len() {
        return (f64::INFINITY, f64::INFINITY);
    }
    let (mut e_r, mut e_a) = (0.0f64, 0.0f64);
    for (x, r) in run.iter().zip(reference) {
        let d = |i: usize| {
            let v = (x[i] - r[i]).abs() / r0;
            if v.is_nan() { f64::INFINITY } else { v }
        };
        e_r = e_r.max(d(0));
        for i in (1..r.len().min(x.len())).step_by(2) {
            e_a = e_a.max(d(i));
        }
    }
    (e_r, e_a)
}

/// Smallest max/min ratio of the work (rhs evaluations) along a ladder for an order against
/// work to be reported: with less the slope divides by a log-work spread near 0 and prints
/// meaningless orders (issue 15 class 9: "vs work 695.88" over a 1 % change in work).
pub const MIN_WORK_RATIO: f64 = 2.0;

/// Observed order against work, −slope of log e against log work (module docs), and the work
/// ratio max/min over the rungs with a finite positive error; the order is `None` when that
/// ratio is below [`MIN_WORK_RATIO`].
pub fn order_vs_work(work: &[f64], err: &[f64]) -> (Option<f64>, f64) {
    let used: Vec<f64> =
        work.iter().zip(err).filter(|(w, e)| w.is_finite() && e.is_finite() && **w > 0.0 && **e > 0.0).map(|(w, _)| *w).collect();
    let ratio = if used.is_empty() {
        f64::NAN
    } else {
        used.iter().cloned().fold(f64::NEG_INFINITY, f64::max) / used.iter().cloned().fold(f64::INFINITY, f64::min)
    };
    let order = if ratio >= MIN_WORK_RATIO { log_slope(work, err).map(|s| -s) } else { None };
    (order, ratio)
}

/// Fixed step Δ/m with m the smallest integer such that Δ/m ≤ target (samples land on steps).
fn aligned_dt(sample: f64, target: f64) -> f64 {
    sample / (sample / target).ceil().max(1.0)
}

/// Builds the scene copies for each rung and measures them.
fn ladder(
    base: &Scene,
    method: &str,
    settings: &[f64],
    fixed_step: bool,
    reference: &[Vec<f64>],
    repeats: usize,
    configure: &dyn Fn(&mut Scene, f64),
    tally: &Tally,
) -> Result<Ladder, AccuracyError> {
    let r0 = base.bubble.radius;
    let mut rungs = vec![];
    for &s in settings {
        let mut sc = base.clone();
        configure(&mut sc, s);
        let tr = run_timed(&sc, repeats, tally)?;
        let (e_r, mut e_a) = errors(&tr.rows, reference, r0);
        if base.modes.max_order == 0 {
            e_a = 0.0;
        }
        let mut error = e_r.max(e_a);
        if matches!(tr.status, RunStatus::Failed { .. }) {
            error = f64::INFINITY;
        }
        rungs.push(Rung { setting: s, e_r, e_a, error, wall_seconds: tr.wall, stats: tr.stats, status: status_text(&tr.status) });
    }
    let err: Vec<f64> = rungs.iter().map(|r| r.error).collect();
    let work: Vec<f64> = rungs.iter().map(|r| r.stats.rhs_evals as f64).collect();
    let set: Vec<f64> = rungs.iter().map(|r| r.setting).collect();
    Ok(Ladder {
        method: method.into(),
        setting_name: if fixed_step { "dt_s".into() } else { "rtol".into() },
        order_dt: if fixed_step { log_slope(&set, &err) } else { None },
        order_work: order_vs_work(&work, &err).0,
        work_ratio: order_vs_work(&work, &err).1,
        rungs,
    })
}

fn set_adaptive(sc: &mut Scene, m: Method, rtol: f64) {
    sc.run.integrator.method = m;
    sc.run.integrator.rtol = rtol;
    sc.run.integrator.atol = 1e-3 * rtol;
}

/// The mode-ladder sizes actually run: even N ≥ 2 up to the coefficient tables' KMAX.
fn mode_sizes(opts: &AccuracyOptions) -> Vec<usize> {
    opts.mode_ladder.iter().copied().filter(|&n| n >= 2 && n % 2 == 0 && n <= crate::coefficients::KMAX).collect()
}

/// How many simulations [`accuracy_study`] runs on `scene` (one more per re-run of the
/// reference, which is not known in advance): the reference and its error estimate, every
/// rung of every ladder and every size `repeats` times.
pub fn planned_runs(scene: &Scene, opts: &AccuracyOptions) -> usize {
    let full = scene.modes.viscous == Viscous::Vorticity && scene.modes.max_order > 0;
    let adaptive = if full { 1 } else { 3 };
    let rungs = opts.dt_star.len() + adaptive * opts.rtols.len();
    let modes = if scene.modes.max_order > 0 { mode_sizes(opts).len() } else { 0 };
    let grid = if full { opts.grid_ladder.len() } else { 0 };
    2 + opts.repeats.max(1) * (rungs + modes + grid)
}

/// Runs the whole study on `scene` (see the module docs).
pub fn accuracy_study(scene: &Scene, opts: &AccuracyOptions) -> Result<AccuracyReport, AccuracyError> {
    accuracy_study_with(scene, opts, &|_, _| {})
}

/// [`accuracy_study`], calling `progress(done, total)` after every simulation (total starts
/// at [`planned_runs`]; it grows by one when the reference has to be run again).
pub fn accuracy_study_with(
    scene: &Scene,
    opts: &AccuracyOptions,
    progress: &dyn Fn(usize, usize),
) -> Result<AccuracyReport, AccuracyError> {
    accuracy_study_cancellable(scene, opts, progress, None)
}

/// [`accuracy_study_with`] that stops before the next simulation once `cancel` is set
/// ([`AccuracyError::Cancelled`]; the simulation in flight finishes first).
pub fn accuracy_study_cancellable(
    scene: &Scene,
    opts: &AccuracyOptions,
    progress: &dyn Fn(usize, usize),
    cancel: Option<&std::sync::atomic::AtomicBool>,
) -> Result<AccuracyReport, AccuracyError> {
    let tally = Tally { done: 0.into(), total: planned_runs(scene, opts).into(), f: progress, cancel };
    let tally = &tally;
    if opts.samples < 2 {
        return Err(AccuracyError::Setting { what: "samples", value: opts.samples.to_string(), reason: "need at least 2" });
    }
    let t_star = Scales::from_scene(scene).time;
    let mut duration = opts.duration.unwrap_or(scene.run.duration);
    if !(duration.is_finite() && duration > 0.0) {
        return Err(AccuracyError::Setting { what: "duration", value: duration.to_string(), reason: "must be a positive time [s]" });
    }
    let full = scene.modes.viscous == Viscous::Vorticity && scene.modes.max_order > 0;
    let mut base = scene.clone();
    // `stiff`: the RK4 reference failed at once (unstable at its step: a stiff scene such as
    // scenes/hard/skalak_c1000.toml), so Radau5 at rtol 1e-11 is the reference instead
    let configure_reference = |sc: &mut Scene, sample: f64, factor: f64, stiff: bool| {
        if full {
            sc.vorticity.scheme = VorticityScheme::Monolithic;
            set_adaptive(sc, Method::Radau5, 1e-10 * factor.powi(3));
        } else if stiff {
            set_adaptive(sc, Method::Radau5, 1e-11 * factor.powi(3));
        } else {
            sc.run.integrator.method = Method::Rk4;
            sc.run.integrator.dt = aligned_dt(sample, opts.reference_dt_star * t_star) * factor;
            sc.run.integrator.dt_given = true;
        }
    };
    let reference_what = |stiff: bool| {
        if full {
            "full model, monolithic scheme, rtol 1e-10".to_string()
        } else if stiff {
            format!("Radau5, rtol 1e-11 (RK4 at dt <= {:e} t* was unstable: a stiff scene)", opts.reference_dt_star)
        } else {
            format!("RK4, dt <= {:e} t* on the sample grid", opts.reference_dt_star)
        }
    };
    // the reference, shortened to 0.9 t_b if it blows up
    let mut reference;
    let mut stiff = false;
    let mut first_try = true;
    loop {
        if !std::mem::take(&mut first_try) {
            tally.extend();
        }
        base.run.duration = duration;
        base.run.sample_interval = duration / opts.samples as f64;
        base.run.integrator.max_steps = base.run.integrator.max_steps.max(200_000_000);
        let mut sc = base.clone();
        configure_reference(&mut sc, base.run.sample_interval, 1.0, stiff);
        reference = run_timed(&sc, 1, tally)?;
        match &reference.status {
            RunStatus::Completed => break,
            RunStatus::BlowUp { t, .. } if *t > 10.0 * base.run.sample_interval => duration = 0.9 * t,
            _ if !full && !stiff => stiff = true,
            other => {
                return Err(AccuracyError::Reference { what: reference_what(stiff), status: status_text(other) });
            }
        }
    }
    let sample = base.run.sample_interval;
    let r0 = scene.bubble.radius;
    // the reference's own error
    let mut sc = base.clone();
    configure_reference(&mut sc, sample, 2.0, stiff);
    let coarse = run_once(&sc, tally)?;
    let (er, ea) = errors(&coarse.rows, &reference.rows, r0);
    let reference_error = if full || stiff { er.max(ea) } else { er.max(ea) / 15.0 };

    let mut ladders = vec![];
    let dts: Vec<f64> = opts.dt_star.iter().map(|d| aligned_dt(sample, d * t_star)).collect();
    let rep = opts.repeats;
    if full {
        ladders.push(ladder(&base, "staggered", &dts, true, &reference.rows, rep, &|sc, dt| {
            sc.vorticity.scheme = VorticityScheme::Staggered;
            sc.run.integrator.dt = dt;
            sc.run.integrator.dt_given = true;
        }, tally)?);
        ladders.push(ladder(&base, "monolithic", &opts.rtols, false, &reference.rows, rep, &|sc, r| {
            sc.vorticity.scheme = VorticityScheme::Monolithic;
            set_adaptive(sc, Method::Radau5, r);
        }, tally)?);
    } else {
        ladders.push(ladder(&base, "rk4", &dts, true, &reference.rows, rep, &|sc, dt| {
            sc.run.integrator.method = Method::Rk4;
            sc.run.integrator.dt = dt;
            sc.run.integrator.dt_given = true;
        }, tally)?);
        for (name, m) in [("dopri5", Method::Dopri5), ("dop853", Method::Dop853), ("radau5", Method::Radau5)] {
            ladders.push(ladder(&base, name, &opts.rtols, false, &reference.rows, rep, &|sc, r| set_adaptive(sc, m, r), tally)?);
        }
    }

    // size ladders with the scene's own integrator settings
    let integrator = crate::model::stiffness::choice_of_scene(&base)?;
    let size_ladder_method = if full {
        format!(
            "full model, {:?} scheme, rtol {:e} atol {:e} (dt {:e} s for staggered)",
            base.vorticity.scheme, base.run.integrator.rtol, base.run.integrator.atol, base.run.integrator.dt
        )
    } else {
        format!(
            "{} ({}) rtol {:e} atol {:e} (dt {:e} s for fixed-step)",
            integrator.method,
            integrator.chosen, base.run.integrator.rtol, base.run.integrator.atol, base.run.integrator.dt
        )
    };
    let size = |configure: &dyn Fn(&mut Scene, usize), sizes: &[usize]| -> Result<Vec<SizeRung>, AccuracyError> {
        let mut runs = vec![];
        for &n in sizes {
            let mut sc = base.clone();
            configure(&mut sc, n);
            runs.push((n, run_timed(&sc, rep, tally)?));
        }
        let Some((_, last)) = runs.last() else { return Ok(vec![]) };
        let last_rows = last.rows.clone();
        Ok(runs
            .into_iter()
            .map(|(n, tr)| {
                let (mut dr, mut da) = (0.0f64, 0.0f64);
                if tr.rows.len() < last_rows.len() {
                    (dr, da) = (f64::INFINITY, f64::INFINITY);
                }
                for (x, r) in tr.rows.iter().zip(&last_rows) {
                    dr = dr.max((x[0] - r[0]).abs() / r0);
                    if x.len() > 1 && r.len() > 1 {
                        da = da.max((x[1] - r[1]).abs() / r0);
                    }
                }
                SizeRung { size: n, wall_seconds: tr.wall, stats: tr.stats, delta_r: dr, delta_a2: da, status: status_text(&tr.status) }
            })
            .collect())
    };
    let modes = if scene.modes.max_order > 0 {
        size(&|sc, n| sc.modes.max_order = n, &mode_sizes(opts))?
    } else {
        vec![]
    };
    let grid = if full { size(&|sc, n| sc.vorticity.points = n, &opts.grid_ladder)? } else { vec![] };

    Ok(AccuracyReport {
        reference: reference_what(stiff),
        reference_error,
        reference_wall_seconds: reference.wall,
        duration,
        sample_interval: sample,
        t_star,
        ladders,
        size_ladder_method,
        integrator,
        modes,
        grid,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_of_a_power_law_is_its_exponent() {
        let x = [1.0, 0.5, 0.25, f64::INFINITY];
        let y: Vec<f64> = x.iter().map(|d: &f64| 3.0 * d.powf(4.0)).collect();
        assert!((log_slope(&x, &y).unwrap() - 4.0).abs() < 1e-12);
        assert_eq!(log_slope(&[1.0], &[1.0]), None);
    }

    #[test]
    fn aligned_steps_divide_the_sample_interval() {
        let dt = aligned_dt(1.0, 0.3);
        assert!((1.0 / dt - 4.0).abs() < 1e-12);
        assert_eq!(aligned_dt(1.0, 5.0), 1.0);
    }

    #[test]
    fn a_shorter_run_has_infinite_error() {
        let r = vec![vec![1.0, 0.1, 0.0]; 3];
        assert_eq!(errors(&r[..2], &r, 1.0).0, f64::INFINITY);
        let mut x = r.clone();
        x[1][1] = 0.3;
        let (er, ea) = errors(&x, &r, 2.0);
        assert_eq!(er, 0.0);
        assert!((ea - 0.1).abs() < 1e-15);
    }
}
