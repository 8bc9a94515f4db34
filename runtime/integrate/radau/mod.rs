//! Radau IIA, 3 stages, order 5, for stiff systems — the scheme of Hairer's RADAU5
//! (Hairer & Wanner, *Solving ODEs II*, 2nd ed., sec. IV.8; code `radau5.f`).
//!
//! Stage increments Z = (Z₁, Z₂, Z₃), Z_i = h Σ_j a_ij f(t + c_j h, y + Z_j), are solved by a
//! simplified Newton iteration with the Jacobian J frozen. In the coordinates W = (T⁻¹ ⊗ I) Z,
//! where T⁻¹ A⁻¹ T = diag(γ, [[α, −β], [β, α]]), the 3n×3n Newton matrix splits into one real
//! system (γ/h I − J) and one complex system ((α + iβ)/h I − J) of size n (HW II, eq. IV.8.16).
//! T is computed here from the exact tableau (not typed in) and checked by a test.
//!
//! Error estimate (HW II, eq. IV.8.19–8.20): err = (γ/h I − J)⁻¹ (f(t, y) + (e·Z)/h), with the
//! "filtered" re-evaluation after a rejection or on the first step. Step size: Hairer's
//! controller with Gustafsson's predictive correction; J is reused while the Newton contraction
//! θ stays below [`THET`], and the LU factors too while h_new/h ∈ [`QUOT1`, `QUOT2`]. As in
//! `radau5.f`, the user tolerances are mapped to rtol' = 0.1 rtol^(2/3), atol' = rtol'·atol/rtol,
//! because the embedded estimate is of order 3.

mod consts;
mod kernels;

use super::explicit::{adaptive_start, step_too_small, Start, MAX_NON_FINITE};
use super::control::StepController;
use super::linear::NewtonMatrix;
use super::{IntegrateError, OdeSystem, Stats};
use consts::RadauConsts;
use kernels::first_non_finite;
use nalgebra::Complex;

/// Maximum Newton iterations per step (RADAU5's NIT).
const NIT: usize = 7;
/// Jacobian is recomputed when the Newton contraction exceeds this (RADAU5's THET; its default
/// is 0.001, and Hairer advises ~0.1 when Jacobians are costly). Ours cost 2 + 3M rhs calls (BL,
/// finite differences) or a structured build (vorticity); measured on the two run workloads of
/// docs/performance.md, 0.03 needs 4× fewer Jacobians and 25–35 % fewer LU factorisations than
/// 0.001 for the same tolerance (0.01–0.1 all alike).
const THET: f64 = 0.03;
/// h and the LU factors are kept when the proposed h_new/h lies in [QUOT1, QUOT2] (RADAU5's
/// WORK(5), WORK(6); defaults 1 and 1.2, "for large full systems 0.99 and 2 might be good").
/// Measured on the two run workloads of docs/performance.md: [0.9, 1.5] needs 47 % / 41 % fewer
/// LU factorisations than [1, 1.2] (BL 1,148 → 611, monolithic 961 → 567) for 4–5 % more steps,
/// with the same error against a tight-tolerance solution.
const QUOT1: f64 = 0.9;
const QUOT2: f64 = 1.5;
const SAFE: f64 = 0.9;
/// Bounds of h / h_new: h_new ∈ [h/5, 8h] (RADAU5's FACL, FACR).
const FACL: f64 = 5.0;
const FACR: f64 = 0.125;

enum Newton {
    Converged,
    /// Converging too slowly for this h: retry with h·factor.
    Slow(f64),
    Failed,
    NonFinite(usize),
}

#[derive(Clone, Copy, PartialEq)]
enum LastFailure {
    None,
    Newton,
    Singular,
    NonFinite(usize),
}

/// Radau IIA order-5 stepper (see the module documentation).
#[derive(Debug)]
pub struct Radau5 {
    k: RadauConsts,
    /// The user's (rtol, atol) (the initial step of a restart).
    user_tol: (f64, f64),
    rtol: f64,
    /// The internal atol'·w_i ([`super::super::atol_vector`]).
    atol: Vec<f64>,
    t: f64,
    t_prev: f64,
    h: f64,
    /// Size of the last accepted step (0 before the first).
    h_old: f64,
    y: Vec<f64>,
    f0: Vec<f64>,
    scal: Vec<f64>,
    z: [Vec<f64>; 3],
    w: [Vec<f64>; 3],
    fz: [Vec<f64>; 3],
    arg: Vec<f64>,
    rc: Vec<Complex<f64>>,
    err_v: Vec<f64>,
    f2: Vec<f64>,
    /// The terms of a scaled norm, before they are added in order (see [`kernels`]).
    sq: Vec<f64>,
    /// Collocation polynomial of the last step (RADAU5's CONT).
    cont: [Vec<f64>; 4],
    /// J and the LU factors of E₁ = γ/h I − J, E₂ = (α + iβ)/h I − J (dense, banded, or the
    /// system's structured solve; see [`super::linear`]).
    nm: NewtonMatrix,
    /// h of the current LU factors (NaN: none).
    lu_h: f64,
    jac_current: bool,
    need_jac: bool,
    first: bool,
    reject: bool,
    faccon: f64,
    /// Gustafsson's predictive step control of order 4 (the embedded estimate is O(h⁴)).
    control: StepController,
    /// Fixed step (no error control) when set; see [`Radau5::with_fixed_step`].
    fixed: Option<f64>,
    stats: Stats,
}

impl Radau5 {
    pub fn new(sys: &dyn OdeSystem, t0: f64, y0: &[f64], t_end: f64, rtol: f64, atol: f64) -> Result<Self, IntegrateError> {
        let n = y0.len();
        let atol_v = crate::integrate::atol_vector(sys, atol, n);
        let Start { f0, h, stats, .. } = adaptive_start(sys, t0, y0, t_end, 5.0, rtol, &atol_v)?;
        let rtol_i = 0.1 * rtol.powf(2.0 / 3.0);
        let atol_i: Vec<f64> = atol_v.iter().map(|a| rtol_i * a / rtol).collect();
        let scal = y0.iter().zip(&atol_i).map(|(y, a)| a + rtol_i * y.abs()).collect();
        let vecs = || std::array::from_fn(|_| vec![0.0; n]);
        Ok(Radau5 {
            k: RadauConsts::new(),
            user_tol: (rtol, atol),
            rtol: rtol_i,
            atol: atol_i,
            t: t0,
            t_prev: t0,
            h,
            h_old: 0.0,
            scal,
            y: y0.to_vec(),
            f0,
            z: vecs(),
            w: vecs(),
            fz: vecs(),
            arg: vec![0.0; n],
            rc: vec![Complex::new(0.0, 0.0); n],
            err_v: vec![0.0; n],
            f2: vec![0.0; n],
            sq: vec![0.0; n],
            cont: std::array::from_fn(|_| y0.to_vec()),
            nm: NewtonMatrix::new(n, true),
            lu_h: f64::NAN,
            jac_current: false,
            need_jac: true,
            first: true,
            reject: false,
            faccon: 1.0,
            control: StepController::predictive(4.0, (1.0 / FACL, 1.0 / FACR)),
            fixed: None,
            stats,
        })
    }

    /// Step size proposed for the next attempt.
    pub fn h(&self) -> f64 {
        self.h
    }

    /// Turns off error control: every step has size `h` (the last one shortened to land on
    /// `t_stop`); Newton iterates to convergence (up to 7 iterations) or the step fails with
    /// [`IntegrateError::NewtonFailed`]. For convergence-order measurements.
    pub fn with_fixed_step(mut self, h: f64) -> Self {
        self.fixed = Some(h);
        self.h = h;
        self
    }

    /// The scaled RMS norm of `err_v`.
    fn rms_err(&mut self) -> f64 {
        let s = kernels::scaled_sum_sq(&self.err_v, &self.scal, &mut self.sq);
        (s / self.err_v.len().max(1) as f64).sqrt()
    }

    /// Starting values of Z (and W = T⁻¹Z): zero on the first step, otherwise the collocation
    /// polynomial of the last step extrapolated (RADAU5, label 20).
    fn starting_values(&mut self, h: f64) {
        let [c1, c2, _] = self.k.c;
        if self.first || self.h_old == 0.0 {
            for i in 0..3 {
                self.z[i].iter_mut().for_each(|v| *v = 0.0);
                self.w[i].iter_mut().for_each(|v| *v = 0.0);
            }
            return;
        }
        let c3q = h / self.h_old;
        let q = [c1 * c3q, c2 * c3q, c3q];
        let (d1, d2) = (q.map(|q| q - (c1 - 1.0)), q.map(|q| q - (c2 - 1.0)));
        let [_, a1, a2, a3] = &self.cont;
        let [z0, z1, z2] = &mut self.z;
        let [w0, w1, w2] = &mut self.w;
        kernels::starting_values(q, d1, d2, &self.k.ti, [a1, a2, a3], [z0, z1, z2], [w0, w1, w2]);
    }

    /// Simplified Newton iteration for the stage values (RADAU5, label 40).
    fn newton(&mut self, sys: &dyn OdeSystem, h: f64) -> (Newton, usize, f64) {
        let n = self.y.len();
        let (fac1, alphn, betan) = (self.k.gamma / h, self.k.alpha / h, self.k.beta / h);
        let fnewt = (10.0 * f64::EPSILON / self.rtol).max(0.03f64.min(self.rtol.sqrt()));
        self.faccon = self.faccon.max(f64::EPSILON).powf(0.8);
        let mut theta = THET;
        let (mut dynold, mut thqold) = (0.0, 0.0);
        let mut newt = 0;
        loop {
            if newt >= NIT {
                return (Newton::Failed, newt, theta);
            }
            for i in 0..3 {
                kernels::add(&self.y, &self.z[i], &mut self.arg);
                sys.rhs(self.t + self.k.c[i] * h, &self.arg, &mut self.fz[i]);
            }
            self.stats.rhs_evals += 3;
            let [f0, f1, f2] = &self.fz;
            let [w0, w1, w2] = &self.w;
            if kernels::newton_rhs(&self.k.ti, [fac1, alphn, betan], [f0, f1, f2], [w0, w1, w2], &mut self.z[0], &mut self.rc) {
                let c = self.fz.iter().find_map(|f| first_non_finite(f)).unwrap_or(0);
                return (Newton::NonFinite(c), newt, theta);
            }
            newt += 1;
            self.nm.solve(&mut self.z[0]);
            self.nm.solve_complex(&mut self.rc);
            // The norm of the increments and the update W += ΔW, Z = T W in one pass: on an early
            // return below (slow or failed Newton) the step is retried and Z, W are set afresh
            // by `starting_values`, so updating them before the tests changes nothing.
            let [w0, w1, w2] = &mut self.w;
            let [z0, z1, z2] = &mut self.z;
            let sum = kernels::newton_update(&self.k.t, &self.scal, &self.rc, [w0, w1, w2], [z0, z1, z2], &mut self.sq);
            let dyno = (sum / (3 * n).max(1) as f64).sqrt();
            if !dyno.is_finite() {
                return (Newton::Failed, newt, theta);
            }
            if newt > 1 && newt < NIT {
                let thq = dyno / dynold;
                theta = if newt == 2 { thq } else { (thq * thqold).sqrt() };
                thqold = thq;
                if theta < 0.99 {
                    self.faccon = theta / (1.0 - theta);
                    let dyth = self.faccon * dyno * theta.powi((NIT - 1 - newt) as i32) / fnewt;
                    if dyth >= 1.0 && self.fixed.is_none() {
                        let qnewt = dyth.clamp(1e-4, 20.0);
                        let hhfac = 0.8 * qnewt.powf(-1.0 / (4.0 + (NIT - 1 - newt) as f64));
                        return (Newton::Slow(hhfac), newt, theta);
                    }
                } else {
                    return (Newton::Failed, newt, theta);
                }
            }
            dynold = dyno.max(f64::EPSILON);
            if self.faccon * dyno <= fnewt {
                return (Newton::Converged, newt, theta);
            }
        }
    }

    /// Scaled error estimate of the converged step (RADAU5's ESTRAD).
    fn error_estimate(&mut self, sys: &dyn OdeSystem, h: f64) -> f64 {
        let hee = self.k.dd.map(|d| d / h);
        let [z0, z1, z2] = &self.z;
        kernels::error_rhs(hee, [z0, z1, z2], &self.f0, &mut self.f2, &mut self.err_v);
        self.nm.solve(&mut self.err_v);
        let mut err = self.rms_err().max(1e-10);
        if err >= 1.0 && (self.first || self.reject) {
            kernels::add(&self.y, &self.err_v, &mut self.arg);
            sys.rhs(self.t, &self.arg, &mut self.err_v);
            self.stats.rhs_evals += 1;
            kernels::add_assign(&mut self.err_v, &self.f2);
            self.nm.solve(&mut self.err_v);
            err = self.rms_err().max(1e-10);
        }
        err
    }

    fn fail(&self, last: LastFailure, h: f64) -> IntegrateError {
        match last {
            LastFailure::None => IntegrateError::StepSizeTooSmall { t: self.t, h },
            LastFailure::Newton | LastFailure::Singular => IntegrateError::NewtonFailed { t: self.t },
            LastFailure::NonFinite(c) => IntegrateError::NonFinite { t: self.t, component: c },
        }
    }

    /// After a rejected attempt: the Jacobian is recomputed unless it is already current.
    fn after_reject(&mut self) {
        self.reject = true;
        self.stats.rejected += 1;
        if !self.jac_current {
            self.need_jac = true;
        }
    }
}

impl super::Stepper for Radau5 {
    super::stepper_state!();

    fn step(&mut self, sys: &dyn OdeSystem, t_stop: f64) -> Result<(), IntegrateError> {
        let mut last_failure = LastFailure::None;
        let (mut singular, mut failures) = (0u32, 0u32);
        loop {
            let mut h = self.h;
            let last = self.t + 1.0001 * h >= t_stop;
            if last {
                h = t_stop - self.t;
            }
            if step_too_small(self.t, h) {
                return Err(self.fail(last_failure, h));
            }
            if failures >= MAX_NON_FINITE {
                return Err(self.fail(last_failure, h));
            }
            if self.need_jac {
                let evaluated = self.nm.evaluate(sys, self.t, &self.y, &self.f0, &mut self.stats);
                self.need_jac = false;
                self.jac_current = true;
                self.lu_h = f64::NAN;
                if let Err(c) = evaluated {
                    return Err(IntegrateError::NonFinite { t: self.t, component: c });
                }
            }
            if self.lu_h != h {
                let (fac1, alphn, betan) = (self.k.gamma / h, self.k.alpha / h, self.k.beta / h);
                let ok = self.nm.factor(fac1, Complex::new(alphn, betan), &mut self.stats);
                if !ok {
                    self.lu_h = f64::NAN;
                    singular += 1;
                    last_failure = LastFailure::Singular;
                    if singular >= 5 {
                        return Err(IntegrateError::NewtonFailed { t: self.t });
                    }
                    self.h = 0.5 * h;
                    self.after_reject();
                    continue;
                }
                self.lu_h = h;
            }
            self.starting_values(h);
            let (outcome, newt, theta) = self.newton(sys, h);
            if self.fixed.is_some() {
                match outcome {
                    Newton::Converged | Newton::Slow(_) => {}
                    Newton::Failed => return Err(IntegrateError::NewtonFailed { t: self.t }),
                    Newton::NonFinite(c) => return Err(IntegrateError::NonFinite { t: self.t, component: c }),
                }
            }
            match outcome {
                Newton::Converged => {}
                Newton::Slow(fac) => {
                    self.h = fac * h;
                    self.after_reject();
                    continue;
                }
                Newton::Failed | Newton::NonFinite(_) => {
                    last_failure = match outcome {
                        Newton::NonFinite(c) => LastFailure::NonFinite(c),
                        _ => LastFailure::Newton,
                    };
                    failures += 1;
                    self.h = 0.5 * h;
                    self.after_reject();
                    continue;
                }
            }
            let err = if self.fixed.is_some() { 0.0 } else { self.error_estimate(sys, h) };
            if !err.is_finite() {
                last_failure = LastFailure::NonFinite(first_non_finite(&self.err_v).unwrap_or(0));
                failures += 1;
                self.h = 0.5 * h;
                self.after_reject();
                continue;
            }
            // Safety factor lowered when Newton needed many iterations (RADAU5's FAC).
            let cfac = SAFE * (1 + 2 * NIT) as f64;
            let fac = SAFE.min(cfac / (newt + 2 * NIT) as f64);
            if err < 1.0 {
                self.first = false;
                let proposed = self.control.accept(h, err, fac);
                let mut h_new = self.fixed.unwrap_or(proposed);
                let t_new = if last { t_stop } else { self.t + h };
                let [c1, c2, _] = self.k.c;
                let [z0, z1, z2] = &self.z;
                let [k0, k1, k2, k3] = &mut self.cont;
                let y_bad = kernels::accept(c1, c2, (&self.atol, self.rtol), [z0, z1, z2], &mut self.y, [k0, k1, k2, k3], &mut self.scal);
                sys.rhs(t_new, &self.y, &mut self.f0);
                self.stats.rhs_evals += 1;
                let bad = if y_bad { first_non_finite(&self.y) } else { None };
                if let Some(c) = bad.or_else(|| first_non_finite(&self.f0)) {
                    return Err(IntegrateError::NonFinite { t: t_new, component: c });
                }
                self.t_prev = self.t;
                self.t = t_new;
                self.h_old = h;
                self.stats.steps += 1;
                if self.reject {
                    h_new = h_new.min(h);
                }
                self.reject = false;
                self.jac_current = false;
                let qt = h_new / h;
                if self.fixed.is_some() {
                    self.h = h_new;
                    if theta > THET {
                        self.need_jac = true;
                    }
                } else if theta <= THET && (QUOT1..=QUOT2).contains(&qt) && !last {
                    self.h = h;
                } else {
                    self.h = h_new;
                    if theta > THET {
                        self.need_jac = true;
                    }
                }
                return Ok(());
            }
            self.h = if self.first { 0.1 * h } else { self.control.reject(h, err, fac) };
            self.after_reject();
        }
    }

    fn restart(&mut self, sys: &dyn OdeSystem, t: f64, y: &[f64], t_end: f64) -> Result<(), IntegrateError> {
        let (rtol, atol) = self.user_tol;
        let atol_v = crate::integrate::atol_vector(sys, atol, y.len());
        let Start { f0, h, stats, .. } = adaptive_start(sys, t, y, t_end, 5.0, rtol, &atol_v)?;
        self.stats.rhs_evals += stats.rhs_evals;
        self.f0 = f0;
        self.h = self.fixed.unwrap_or(h);
        self.h_old = 0.0;
        self.y.copy_from_slice(y);
        for ((s, v), a) in self.scal.iter_mut().zip(y).zip(&self.atol) {
            *s = a + self.rtol * v.abs();
        }
        self.cont.iter_mut().for_each(|c| c.copy_from_slice(y));
        self.t = t;
        self.t_prev = t;
        self.lu_h = f64::NAN;
        self.jac_current = false;
        self.need_jac = true;
        self.first = true;
        self.reject = false;
        self.faccon = 1.0;
        self.control = StepController::predictive(4.0, (1.0 / FACL, 1.0 / FACR));
        Ok(())
    }

    fn interpolate(&self, t: f64, out: &mut [f64]) {
        let [c1, c2, _] = self.k.c;
        let s = (t - self.t) / self.h_old.max(f64::MIN_POSITIVE);
        let [k0, k1, k2, k3] = &self.cont;
        kernels::interpolate(c1, c2, s, [k0, k1, k2, k3], out);
    }

    fn interpolate_at(&self, t: f64, idx: &[usize], out: &mut [f64]) {
        let [c1, c2, _] = self.k.c;
        let s = (t - self.t) / self.h_old.max(f64::MIN_POSITIVE);
        let [k0, k1, k2, k3] = &self.cont;
        for (o, &m) in out.iter_mut().zip(idx) {
            *o = k0[m] + s * (k1[m] + (s - (c2 - 1.0)) * (k2[m] + (s - (c1 - 1.0)) * k3[m]));
        }
    }
}
