//! The integrator a run uses (issue 34, "the default integrator chooses itself"; issue 29
//! item 5's RK4 residue), from a stiffness estimate at the initial state (docs/user-guide.md,
//! "Which integrator for which need"; measurements in docs/performance.md, "Automatic
//! integrator choice").
//!
//! - ρ: the spectral radius of the exact Jacobian ∂f/∂y at (0, y0) ([`super::linearize`];
//!   finite differences for a system without one) on the active components
//!   ([`active_components`]), eigenvalues of the real Schur form.
//! - h_exp: the step an explicit method takes for the requested tolerance, measured (docs/
//!   performance.md, "Automatic integrator choice"): DOP853 takes about [`DOP853_STEPS`]
//!   steps per period of the fastest forcing at rtol 1e-6, scaled as rtol^(1/8).
//! - `auto`: DOP853 when ρ·h_exp ≤ [`RADAU5_PAYS`], otherwise Radau5. Above
//!   [`DOP853_STABILITY`] (the stability bound Hairer's DOP853 tests against) the explicit step
//!   is limited by stability, but Radau5 costs more per unit time: it pays only once the limit
//!   shrinks DOP853's step by more than that factor (measured, [`RADAU5_PAYS`]).
//! - `rk4` without `run.integrator.dt`: Δt = min(1e−3 t*, [`RK4_MARGIN`]·2.785/ρ), inside
//!   RK4's stability interval with a margin of 2 (the state's stiffness grows as R shrinks).
//!
//! An explicitly chosen method runs exactly as before (no estimate is computed).

use super::Model;
use crate::integrate::{FdJacobian, Method, Stats};
use crate::scene::{IntegratorSettings, Method as SceneMethod};
use nalgebra::DMatrix;
use serde::Serialize;

/// |hλ| on DOP853's stability boundary along the negative real axis (Hairer's DOP853 flags
/// stiffness at h·ρ > 6.1).
pub const DOP853_STABILITY: f64 = 6.1;
/// ρ·h_exp above which Radau5 is cheaper than a stability-limited DOP853: 2.5 × [`DOP853_STABILITY`].
/// Measured (callgrind instructions of whole runs, DOP853 ÷ Radau5, docs/performance.md
/// "Automatic integrator choice"): on the shipped scenes with 6.1 < ρh ≤ 41 the ratio is 0.65 at
/// ρh 8.0 (supplementary/r1um), 0.93 at 14.5 (hard/reduced_collapse), 1.16 at 18.0
/// (hard/dual_frequency_modes), 2.04 / 1.22 / 2.46 at 30.0 / 37.7 / 41.3; read as
/// (ρh/6.1)/F, Radau5's cost per unit time is F ≈ 2.0–2.8 times DOP853's unlimited one
/// (hann_burst, stiff only in its burst, 5.0). No shipped scene lies between 5.0 and 7.9.
pub const RADAU5_PAYS: f64 = 2.5 * DOP853_STABILITY;
/// RK4's stability interval on the negative real axis, [−2.785, 0].
pub const RK4_STABILITY: f64 = 2.785;
/// Fraction of RK4's stability interval a default Δt uses.
pub const RK4_MARGIN: f64 = 0.5;
/// DOP853's accepted steps per period of the fastest forcing at rtol 1e−6 (measured on the
/// radial 5 µm bubble at 1 MHz, ε 0.1: 348 steps over 50 periods; 748 at rtol 1e-9, 203 at
/// 1e-4, as rtol^(1/8) predicts: docs/performance.md, "Automatic integrator choice").
pub const DOP853_STEPS: f64 = 7.0;

/// Which integrator ran and why: summary.json's `integrator` object.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IntegratorChoice {
    /// The method that ran ("dop853", "radau5", "rk4", …).
    pub method: String,
    /// "auto" (chosen from the estimate) or "scene" (`run.integrator.method` given).
    pub chosen: String,
    pub reason: String,
    /// ρ(∂f/∂y) at the initial state [1/s] (`null` when not estimated).
    pub spectral_radius_per_s: Option<f64>,
    /// The state components the estimate saw (the rest stay exactly zero: [`active_components`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub active_components: Option<usize>,
    /// The step DOP853 would take for the requested tolerance [s] (auto only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub explicit_step_s: Option<f64>,
    /// The fixed step of RK4 [s], and whether the scene gave it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dt_s: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dt_given: Option<bool>,
}

/// ∂f/∂y at (t, y), row-major: the system's exact Jacobian, or forward differences.
fn jacobian(model: &Model, t: f64, y: &[f64]) -> Vec<f64> {
    let sys = model.system();
    let n = sys.dim();
    let mut jac = vec![0.0; n * n];
    if !sys.jacobian(t, y, &mut jac) {
        let mut f0 = vec![0.0; n];
        sys.rhs(t, y, &mut f0);
        FdJacobian::new(n).evaluate(sys, t, y, &f0, &mut jac, &mut Stats::default());
    }
    jac
}

/// The components a run can move: those non-zero at y0, those the rhs moves at the probe
/// times, and every component whose rate depends on one of these (closed under J's non-zeros,
/// J evaluated with the active components made non-zero, so that couplings proportional to an
/// amplitude count). The rest stay exactly zero in floating point too (their rates are sums of
/// products with zero amplitudes): they can be neither inaccurate nor unstable, and their
/// eigenvalues (a shape mode that nothing seeds or forces) do not make a run stiff.
pub fn active_components(model: &Model, y0: &[f64], probes: &[f64]) -> Vec<bool> {
    let sys = model.system();
    let n = sys.dim();
    let mut active: Vec<bool> = y0.iter().map(|&v| v != 0.0).collect();
    active[..2.min(n)].iter_mut().for_each(|a| *a = true);
    let mut f = vec![0.0; n];
    for &t in probes {
        sys.rhs(t, y0, &mut f);
        active.iter_mut().zip(&f).for_each(|(a, &v)| *a |= v != 0.0);
    }
    loop {
        // a state with every active amplitude non-zero (1e-3 R0 where y0 has zero)
        let yp: Vec<f64> = y0.iter().zip(&active).map(|(&v, &a)| if a && v == 0.0 { 1e-3 } else { v }).collect();
        let mut grew = false;
        for &t in probes {
            let jac = jacobian(model, t, &yp);
            for i in 0..n {
                if !active[i] && (0..n).any(|j| active[j] && jac[i * n + j] != 0.0) {
                    active[i] = true;
                    grew = true;
                }
            }
        }
        if !grew {
            return active;
        }
    }
}

/// ρ(J) at (t, y) on the `active` components ([`active_components`]), model units (1/t*);
/// NaN when the eigenvalues do not converge or J is not finite.
pub fn spectral_radius(model: &Model, t: f64, y: &[f64], active: &[bool]) -> f64 {
    let n = y.len();
    let jac = jacobian(model, t, y);
    let idx: Vec<usize> = (0..n).filter(|&i| active[i]).collect();
    let m = DMatrix::from_fn(idx.len(), idx.len(), |r, c| jac[idx[r] * n + idx[c]]);
    let eig = crate::analysis::floquet::eigenvalues(&m);
    eig.iter().map(|l| l.norm()).fold(0.0, |a: f64, b| if b.is_nan() || a.is_nan() { f64::NAN } else { a.max(b) })
}

/// The stiffness estimate at the initial state: (ρ [1/t*], active components, of n).
fn estimate(model: &Model, t_end: f64) -> (f64, usize) {
    let y0 = model.initial_state();
    let w = forcing_rate(model, y0);
    // probe times over the first forcing periods and the run (irrational fractions, so that a
    // sin(ωt) forcing is not probed at its zeros)
    let span = (4.0 * std::f64::consts::PI / w).min(t_end).max(0.0);
    let probes: Vec<f64> = [0.0, 0.1234, 0.3183, 0.5772, 0.7071, 0.9135].iter().map(|f| f * span).collect();
    let active = active_components(model, y0, &probes);
    (spectral_radius(model, 0.0, y0, &active), active.iter().filter(|&&a| a).count())
}

/// The fastest forcing's angular frequency (model units): the drive's, or without one the
/// radial oscillation's (|λ| of the radial 2 × 2 block of J at y0).
fn forcing_rate(model: &Model, y: &[f64]) -> f64 {
    if let Some((_, w)) = model.params().drive {
        return w;
    }
    let n = y.len();
    let jac = jacobian(model, 0.0, y);
    // [[0, 1], [j10, j11]]: λ² − j11 λ − j10 = 0, |λ|² = −j10 for a complex pair
    let (j10, j11) = (jac[n], jac[n + 1]);
    let disc = j11 * j11 + 4.0 * j10;
    if disc < 0.0 { (-j10).sqrt() } else { (j11.abs() + disc.sqrt()) / 2.0 }
}

impl Model {
    /// The integrator for the settings `s` over a run of `duration` [s], with the record of the
    /// choice. An explicit `run.integrator.method` is used as given (RK4's Δt from the scene,
    /// or from ρ when the scene does not give it).
    pub fn choose_integrator(&self, s: &IntegratorSettings) -> (Method, IntegratorChoice) {
        let ts = self.time_scale();
        let given = |m: Method, reason: &str| IntegratorChoice {
            method: m.name().into(),
            chosen: "scene".into(),
            reason: reason.into(),
            spectral_radius_per_s: None,
            active_components: None,
            explicit_step_s: None,
            dt_s: None,
            dt_given: None,
        };
        match s.method {
            SceneMethod::Auto => {
                let (rho, active) = estimate(self, self.t_end);
                let w = forcing_rate(self, self.initial_state());
                let h = 2.0 * std::f64::consts::PI / w / DOP853_STEPS * (s.rtol / 1e-6).powf(1.0 / 8.0);
                let ratio = rho * h;
                let stiff = !(ratio <= RADAU5_PAYS);
                let (m, verdict) = if stiff {
                    (Method::Radau5 { rtol: s.rtol, atol: s.atol }, "stiff: the explicit step would be cut by stability more than Radau5 costs, Radau5")
                } else if ratio > DOP853_STABILITY {
                    (Method::Dop853 { rtol: s.rtol, atol: s.atol }, "mildly stiff: stability cuts the explicit step by less than Radau5 costs, DOP853")
                } else {
                    (Method::Dop853 { rtol: s.rtol, atol: s.atol }, "non-stiff: DOP853")
                };
                let reason = format!(
                    "spectral radius {:.3e} /s × DOP853's step for rtol {:e} ({:.3e} s) = {:.3} {} {RADAU5_PAYS} (DOP853's stability bound {DOP853_STABILITY} × {}, Radau5's measured cost per unit time) → {verdict}",
                    rho / ts,
                    s.rtol,
                    h * ts,
                    ratio,
                    if stiff { ">" } else { "≤" },
                    RADAU5_PAYS / DOP853_STABILITY,
                );
                let choice = IntegratorChoice {
                    method: m.name().into(),
                    chosen: "auto".into(),
                    reason,
                    spectral_radius_per_s: Some(rho / ts),
                    active_components: Some(active),
                    explicit_step_s: Some(h * ts),
                    dt_s: None,
                    dt_given: None,
                };
                (m, choice)
            }
            SceneMethod::Rk4 if !s.dt_given => {
                let (rho, active) = estimate(self, self.t_end);
                let stable = RK4_MARGIN * RK4_STABILITY / rho;
                let dt = s.dt / ts;
                let (dt, reason) = if stable < dt {
                    (stable, format!(
                        "run.integrator.dt not given: {RK4_MARGIN} × RK4's stability interval {RK4_STABILITY} / spectral radius {:.3e} /s (below 1e-3 t*)",
                        rho / ts
                    ))
                } else {
                    (dt, format!("run.integrator.dt not given: 1e-3 t* (inside RK4's stability interval: spectral radius {:.3e} /s)", rho / ts))
                };
                let m = Method::Rk4 { dt };
                let mut c = given(m, &reason);
                c.spectral_radius_per_s = Some(rho / ts);
                c.active_components = Some(active);
                c.dt_s = Some(dt * ts);
                c.dt_given = Some(false);
                (m, c)
            }
            _ => {
                let m = super::method_of(s, ts);
                let mut c = given(m, "run.integrator.method given");
                if let Method::Rk4 { dt } = m {
                    c.dt_s = Some(dt * ts);
                    c.dt_given = Some(true);
                }
                (m, c)
            }
        }
    }
}

/// The full model's integrator record: `auto` stays on Radau5 here (the vorticity system is
/// stiff by construction: its diffusion eigenvalues grow as the grid's 1/h², issue 34).
pub fn full_model_choice(s: &crate::scene::IntegratorSettings, method: &Method, scheme: crate::scene::VorticityScheme) -> crate::model::IntegratorChoice {
    let auto = s.method == crate::scene::Method::Auto;
    let (name, reason) = match scheme {
        crate::scene::VorticityScheme::Staggered => ("rk4", "the staggered vorticity scheme: RK4 for the modes, Crank-Nicolson for the vorticity, at run.integrator.dt".to_string()),
        crate::scene::VorticityScheme::Monolithic if auto => (method.name(), "the full (vorticity) model is stiff by construction (diffusion on the grid): Radau5".to_string()),
        crate::scene::VorticityScheme::Monolithic => (method.name(), "run.integrator.method given".to_string()),
    };
    crate::model::IntegratorChoice {
        method: name.into(),
        chosen: if auto { "auto" } else { "scene" }.into(),
        reason,
        spectral_radius_per_s: None,
        active_components: None,
        explicit_step_s: None,
        dt_s: None,
        dt_given: None,
    }
}

/// The integrator a run of `scene` uses and why, without running it (the `accuracy` study's
/// plot and report).
pub fn choice_of_scene(scene: &crate::scene::Scene) -> Result<IntegratorChoice, super::ModelError> {
    if scene.modes.viscous == crate::scene::Viscous::Vorticity && scene.modes.max_order > 0 {
        let s = &scene.run.integrator;
        let ts = super::params::Scales::from_scene(scene).time;
        return Ok(full_model_choice(s, &super::method_of(s, ts), scene.vorticity.scheme));
    }
    Ok(Model::from_scene(scene)?.choose_integrator(&scene.run.integrator).1)
}
