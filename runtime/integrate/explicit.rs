//! Explicit steppers: fixed-step RK4 ([`Rk4`], [`rk4_step`]) and adaptive embedded Runge–Kutta
//! ([`ExplicitRk`], driven by a [`ButcherTableau`]).
//!
//! Step-size control is Hairer's PI controller of `dopri5.f` (Hairer–Nørsett–Wanner I,
//! sec. II.4, eq. 4.13 and the "stabilized" variant of IV.2): h_new = h · clamp(safe ·
//! err^(−1/q + 0.75β) · err_old^β), β = 0.04, safe = 0.9, with err the RMS of the scaled local
//! error, sc_i = atol + rtol · max(|y_i|, |y_new,i|). The initial step follows `hinit` of the
//! same codes (HNW I, sec. II.4) with RMS norms.

use super::control::StepController;
use super::tableau::{ButcherTableau, DenseOutput, ErrorEstimator};
use super::{first_non_finite, IntegrateError, OdeSystem, Stats};

/// Consecutive non-finite attempts after which a run fails with [`IntegrateError::NonFinite`].
pub(crate) const MAX_NON_FINITE: u32 = 20;

/// `true` when `h` is too small to advance `t` meaningfully (or not a number).
pub(crate) fn step_too_small(t: f64, h: f64) -> bool {
    !(h > 8.0 * f64::EPSILON * t.abs()) || h < 1e-300
}

/// RMS norm of v / (atol_i + rtol |y|).
pub(crate) fn rms_scaled(v: &[f64], y: &[f64], rtol: f64, atol: &[f64]) -> f64 {
    let s: f64 = v.iter().zip(y).zip(atol).map(|((v, y), a)| (v / (a + rtol * y.abs())).powi(2)).sum();
    (s / v.len().max(1) as f64).sqrt()
}

/// f(t0, y0) into `f`, refusing a start where y0 or f is not finite (one rhs evaluation, not
/// counted here).
pub(crate) fn checked_rhs(sys: &dyn OdeSystem, t0: f64, y0: &[f64], f: &mut [f64]) -> Result<(), IntegrateError> {
    sys.rhs(t0, y0, f);
    match first_non_finite(y0).or_else(|| first_non_finite(f)) {
        Some(c) => Err(IntegrateError::NonFinite { t: t0, component: c }),
        None => Ok(()),
    }
}

/// The start of an implicit adaptive stepper: f(t0, y0) (checked), the [`initial_step`] for a
/// method of `order`, the two scratch vectors it used, and the stats of the two rhs calls.
pub(crate) struct Start {
    pub f0: Vec<f64>,
    pub h: f64,
    pub scratch: (Vec<f64>, Vec<f64>),
    pub stats: Stats,
}

#[allow(clippy::too_many_arguments)]
pub(crate) fn adaptive_start(
    sys: &dyn OdeSystem,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    order: f64,
    rtol: f64,
    atol: &[f64],
) -> Result<Start, IntegrateError> {
    let n = y0.len();
    let mut stats = Stats { rhs_evals: 1, ..Stats::default() };
    let mut f0 = vec![0.0; n];
    checked_rhs(sys, t0, y0, &mut f0)?;
    let (mut w1, mut w2) = (vec![0.0; n], vec![0.0; n]);
    let h = initial_step(sys, t0, y0, &f0, order, rtol, atol, (t_end - t0).abs(), &mut w1, &mut w2, &mut stats);
    Ok(Start { f0, h, scratch: (w1, w2), stats })
}

/// Initial step (Hairer's HINIT): h₀ = 0.01 ‖y‖/‖f‖, then h₁ from a second-derivative estimate
/// with h₁^order · max(‖f'‖, ‖f‖) = 0.01; h = min(100 h₀, h₁, h_max). Uses one rhs evaluation,
/// counted in `stats`. `work` has length n.
#[allow(clippy::too_many_arguments)]
pub(crate) fn initial_step(
    sys: &dyn OdeSystem,
    t0: f64,
    y0: &[f64],
    f0: &[f64],
    order: f64,
    rtol: f64,
    atol: &[f64],
    h_max: f64,
    work: &mut [f64],
    f1: &mut [f64],
    stats: &mut Stats,
) -> f64 {
    let dnf = rms_scaled(f0, y0, rtol, atol);
    let dny = rms_scaled(y0, y0, rtol, atol);
    let mut h = if dnf <= 1e-5 || dny <= 1e-5 { 1e-6 } else { 0.01 * dny / dnf };
    h = h.min(h_max);
    for i in 0..y0.len() {
        work[i] = y0[i] + h * f0[i];
    }
    sys.rhs(t0 + h, work, f1);
    stats.rhs_evals += 1;
    for i in 0..y0.len() {
        work[i] = f1[i] - f0[i];
    }
    let der2 = rms_scaled(work, y0, rtol, atol) / h;
    let der12 = der2.max(dnf);
    let h1 = if !(der12 > 1e-15) { (h * 1e-3).max(1e-6) } else { (0.01 / der12).powf(1.0 / order) };
    let h = (100.0 * h).min(h1).min(h_max);
    if h.is_finite() && h > 0.0 {
        h
    } else {
        1e-6_f64.min(h_max)
    }
}

/// Cubic Hermite interpolation on [t0, t0 + h] from y and f at both ends (3rd order).
pub(crate) fn hermite(t0: f64, h: f64, y0: &[f64], f0: &[f64], y1: &[f64], f1: &[f64], t: f64, out: &mut [f64]) {
    let th = (t - t0) / h;
    for i in 0..out.len() {
        out[i] = hermite_at(th, h, y0[i], f0[i], y1[i], f1[i]);
    }
}

/// One component of [`hermite`] at θ = (t − t0)/h.
#[inline(always)]
fn hermite_at(th: f64, h: f64, y0: f64, f0: f64, y1: f64, f1: f64) -> f64 {
    let dy = y1 - y0;
    (1.0 - th) * y0 + th * y1 + th * (th - 1.0) * ((1.0 - 2.0 * th) * dy + (th - 1.0) * h * f0 + th * h * f1)
}

/// Workspace of [`rk4_step`] (4 stage vectors and one argument vector).
#[derive(Debug, Clone)]
pub struct Rk4Workspace {
    k: [Vec<f64>; 4],
    arg: Vec<f64>,
}

impl Rk4Workspace {
    pub fn new(n: usize) -> Self {
        Rk4Workspace { k: std::array::from_fn(|_| vec![0.0; n]), arg: vec![0.0; n] }
    }
}

/// One classical RK4 step from (t, y) with step h into `y_out`, for code that owns its loop
/// (e.g. the staggered vorticity scheme). Makes exactly 4 calls to `sys.rhs`; allocation-free.
pub fn rk4_step(sys: &dyn OdeSystem, t: f64, y: &[f64], h: f64, y_out: &mut [f64], ws: &mut Rk4Workspace) {
    let [k1, rest @ ..] = &mut ws.k;
    sys.rhs(t, y, k1);
    rk4_from_k1(sys, t, y, h, k1, rest, &mut ws.arg, y_out);
}

/// RK4 with k1 = f(t, y) given; 3 rhs calls.
#[allow(clippy::too_many_arguments)]
fn rk4_from_k1(sys: &dyn OdeSystem, t: f64, y: &[f64], h: f64, k1: &[f64], k: &mut [Vec<f64>], arg: &mut [f64], y_out: &mut [f64]) {
    let [k2, k3, k4] = k else { unreachable!("three stage vectors") };
    let n = y.len();
    for i in 0..n {
        arg[i] = y[i] + 0.5 * h * k1[i];
    }
    sys.rhs(t + 0.5 * h, arg, k2);
    for i in 0..n {
        arg[i] = y[i] + 0.5 * h * k2[i];
    }
    sys.rhs(t + 0.5 * h, arg, k3);
    for i in 0..n {
        arg[i] = y[i] + h * k3[i];
    }
    sys.rhs(t + h, arg, k4);
    for i in 0..n {
        y_out[i] = y[i] + h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
    }
}

/// Fixed-step classical RK4 on the grid t0 + i·dt (4 rhs calls per step: f at the end of a step
/// is the next k1 and also serves the Hermite dense output).
#[derive(Debug, Clone)]
pub struct Rk4 {
    dt: f64,
    t0: f64,
    i: u64,
    t: f64,
    t_prev: f64,
    y: Vec<f64>,
    f: Vec<f64>,
    y_prev: Vec<f64>,
    f_prev: Vec<f64>,
    ws: Rk4Workspace,
    stats: Stats,
}

impl Rk4 {
    pub fn new(sys: &dyn OdeSystem, t0: f64, y0: &[f64], dt: f64) -> Result<Self, IntegrateError> {
        let n = y0.len();
        let mut f = vec![0.0; n];
        checked_rhs(sys, t0, y0, &mut f)?;
        Ok(Rk4 {
            dt,
            t0,
            i: 0,
            t: t0,
            t_prev: t0,
            y: y0.to_vec(),
            y_prev: y0.to_vec(),
            f_prev: f.clone(),
            f,
            ws: Rk4Workspace::new(n),
            stats: Stats { rhs_evals: 1, ..Stats::default() },
        })
    }
}

impl super::Stepper for Rk4 {
    super::stepper_state!();
    fn step(&mut self, sys: &dyn OdeSystem, t_stop: f64) -> Result<(), IntegrateError> {
        let t_grid = self.t0 + (self.i + 1) as f64 * self.dt;
        let t_next = if t_grid >= t_stop - 1e-9 * self.dt { t_stop } else { t_grid };
        let h = t_next - self.t;
        if step_too_small(self.t, h) {
            return Err(IntegrateError::StepSizeTooSmall { t: self.t, h });
        }
        std::mem::swap(&mut self.y, &mut self.y_prev);
        std::mem::swap(&mut self.f, &mut self.f_prev);
        let [_, rest @ ..] = &mut self.ws.k;
        rk4_from_k1(sys, self.t, &self.y_prev, h, &self.f_prev, rest, &mut self.ws.arg, &mut self.y);
        sys.rhs(t_next, &self.y, &mut self.f);
        self.stats.rhs_evals += 4;
        self.stats.steps += 1;
        if let Some(c) = first_non_finite(&self.y).or_else(|| first_non_finite(&self.f)) {
            return Err(IntegrateError::NonFinite { t: t_next, component: c });
        }
        self.t_prev = self.t;
        self.t = t_next;
        if t_grid - t_next <= 1e-9 * self.dt {
            self.i += 1;
        }
        Ok(())
    }
    fn restart(&mut self, sys: &dyn OdeSystem, t: f64, y: &[f64], _t_end: f64) -> Result<(), IntegrateError> {
        checked_rhs(sys, t, y, &mut self.f)?;
        self.stats.rhs_evals += 1;
        self.y.copy_from_slice(y);
        self.y_prev.copy_from_slice(y);
        self.f_prev.copy_from_slice(&self.f);
        self.t = t;
        self.t_prev = t;
        // the grid t0 + i·dt carries on: i is the last grid point not after t
        let i = ((t - self.t0) / self.dt).floor().max(0.0) as u64;
        self.i = if self.t0 + (i + 1) as f64 * self.dt <= t + 1e-9 * self.dt { i + 1 } else { i };
        Ok(())
    }
    fn interpolate(&self, t: f64, out: &mut [f64]) {
        hermite(self.t_prev, self.t - self.t_prev, &self.y_prev, &self.f_prev, &self.y, &self.f, t, out);
    }
}

/// acc = Σ_j w_j k_j over the `(w_j, k_j)` in their order, zero weights skipped: for each
/// component the additions `0 + w_1 k_1[m] + w_2 k_2[m] + …` of a component-by-component loop,
/// in the same order (the same bits), made stage by stage over contiguous slices.
#[inline(always)]
fn combine<'k>(acc: &mut [f64], terms: impl Iterator<Item = (f64, &'k [f64])>) {
    acc.fill(0.0);
    for (w, k) in terms {
        if w != 0.0 {
            for (a, &x) in acc.iter_mut().zip(k) {
                *a += w * x;
            }
        }
    }
}

/// Adaptive explicit Runge–Kutta with an embedded error estimate (Dopri5, Dop853).
#[derive(Debug, Clone)]
pub struct ExplicitRk {
    tab: ButcherTableau,
    rtol: f64,
    /// atol·w_i ([`super::atol_vector`]).
    atol: Vec<f64>,
    t: f64,
    t_prev: f64,
    h: f64,
    y: Vec<f64>,
    y_prev: Vec<f64>,
    f_prev: Vec<f64>,
    y_new: Vec<f64>,
    arg: Vec<f64>,
    f_new: Vec<f64>,
    /// Stage derivatives; k[0] = f(t, y) at the current point.
    k: Vec<Vec<f64>>,
    /// Dense-output coefficients of the last step: Dopri5's r1..r5 of `contd5`, computed with
    /// the step; Dop853's y0, r1..r7 of `contd8` with its three extra stages in `extra`,
    /// computed by [`Stepper::prepare_dense`](super::Stepper::prepare_dense) when `dense_ready`
    /// is false.
    rcont: Vec<Vec<f64>>,
    extra: Vec<Vec<f64>>,
    dense_ready: bool,
    /// Size of the last accepted step.
    h_last: f64,
    /// PI step control (dopri5.f: β = 0.04, safe = 0.9).
    control: StepController,
    /// Fixed step (no error control) when set; see [`ExplicitRk::with_fixed_step`].
    fixed: Option<f64>,
    stats: Stats,
}

impl ExplicitRk {
    /// `t_end` bounds the initial step. The tableau must carry an error estimator.
    pub fn new(
        sys: &dyn OdeSystem,
        tab: ButcherTableau,
        t0: f64,
        y0: &[f64],
        t_end: f64,
        rtol: f64,
        atol: f64,
    ) -> Result<Self, IntegrateError> {
        assert!(tab.error.is_some(), "adaptive stepping needs an error estimator");
        let n = y0.len();
        let s = tab.stages();
        let mut k = vec![vec![0.0; n]; s];
        let mut stats = Stats { rhs_evals: 1, ..Stats::default() };
        checked_rhs(sys, t0, y0, &mut k[0])?;
        let mut arg = vec![0.0; n];
        let mut f_new = vec![0.0; n];
        let atol = super::atol_vector(sys, atol, n);
        let h = initial_step(sys, t0, y0, &k[0], tab.order as f64, rtol, &atol, (t_end - t0).abs(), &mut arg, &mut f_new, &mut stats);
        let (nd, ne) = match tab.dense {
            DenseOutput::Dopri5 { .. } => (5, 0),
            DenseOutput::Dop853 => (8, 3),
            DenseOutput::Hermite => (0, 0),
        };
        Ok(ExplicitRk {
            rtol,
            atol,
            t: t0,
            t_prev: t0,
            h,
            y: y0.to_vec(),
            y_prev: y0.to_vec(),
            f_prev: k[0].clone(),
            y_new: vec![0.0; n],
            arg,
            f_new,
            k,
            rcont: vec![vec![0.0; n]; nd],
            extra: vec![vec![0.0; n]; ne],
            dense_ready: false,
            h_last: 0.0,
            control: StepController::pi(tab.controller_order, 0.04, tab.step_ratio),
            fixed: None,
            stats,
            tab,
        })
    }

    /// Step size proposed for the next attempt.
    pub fn h(&self) -> f64 {
        self.h
    }

    /// Turns off error control: every step has size `h` (the last one shortened to land on
    /// `t_stop`). For convergence-order measurements and step-size ladders.
    pub fn with_fixed_step(mut self, h: f64) -> Self {
        self.fixed = Some(h);
        self.h = h;
        self
    }

    /// Computes all stages but the first, y_new and the scaled error norm for step h.
    ///
    /// The radial states (n = 2, 3) get the same code with n a constant, so the compiler unrolls
    /// the component loops and hoists their bounds checks (issue 34: the stepper was 4.8 k
    /// instructions per DOP853 step of a 2-component state); the arithmetic, and so every bit, is
    /// the same.
    fn attempt(&mut self, sys: &dyn OdeSystem, h: f64) -> f64 {
        match self.y.len() {
            2 => self.attempt_n(sys, h, 2),
            3 => self.attempt_n(sys, h, 3),
            n => self.attempt_n(sys, h, n),
        }
    }

    /// [`attempt`](Self::attempt) for n = `self.y.len()`.
    #[inline(always)]
    fn attempt_n(&mut self, sys: &dyn OdeSystem, h: f64, n: usize) -> f64 {
        debug_assert_eq!(n, self.y.len());
        let s = self.tab.stages();
        // stage by stage, each component's sum in the tableau's order (so the same bits as a sum
        // per component): acc_m = Σ_j a_ij k_j[m], then y[m] + h acc_m
        let y = &self.y[..n];
        for i in 1..s {
            let (done, rest) = self.k.split_at_mut(i);
            let acc = &mut self.arg[..n];
            combine(acc, done.iter().zip(&self.tab.a[i]).map(|(k, &a)| (a, &k[..n])));
            for (x, &ym) in acc.iter_mut().zip(y) {
                *x = ym + h * *x;
            }
            sys.rhs(self.t + self.tab.c[i] * h, &self.arg, &mut rest[0]);
        }
        self.stats.rhs_evals += (s - 1) as u64;
        let acc = &mut self.y_new[..n];
        combine(acc, self.k.iter().zip(&self.tab.b).map(|(k, &b)| (b, &k[..n])));
        for (x, &ym) in acc.iter_mut().zip(y) {
            *x = ym + h * *x;
        }
        let sc = |m: usize, y: &[f64], y_new: &[f64], rtol: f64, atol: &[f64]| atol[m] + rtol * y[m].abs().max(y_new[m].abs());
        match self.tab.error.as_ref().expect("checked in new") {
            // the error sums stage by stage too (each component's sum in the same order), into
            // the scratch vectors the stages are done with
            ErrorEstimator::Embedded { e } => {
                let acc = &mut self.arg[..n];
                combine(acc, self.k.iter().zip(e).map(|(k, &ej)| (ej, &k[..n])));
                let mut sum = 0.0;
                for m in 0..n {
                    sum += (h * acc[m] / sc(m, &self.y, &self.y_new, self.rtol, &self.atol)).powi(2);
                }
                (sum / n as f64).sqrt()
            }
            ErrorEstimator::Dop853 { e5, bhh } => {
                let (acc5, accb) = (&mut self.arg[..n], &mut self.f_new[..n]);
                acc5.fill(0.0);
                accb.fill(0.0);
                for ((kj, &e), &b) in self.k.iter().zip(e5).zip(&self.tab.b).take(s) {
                    for ((x5, xb), &k) in acc5.iter_mut().zip(accb.iter_mut()).zip(&kj[..n]) {
                        *x5 += e * k;
                        *xb += b * k;
                    }
                }
                let (mut s5, mut s3) = (0.0, 0.0);
                for m in 0..n {
                    let acc3 = accb[m] - bhh.iter().map(|&(j, w)| w * self.k[j][m]).sum::<f64>();
                    let scm = sc(m, &self.y, &self.y_new, self.rtol, &self.atol);
                    s5 += (acc5[m] / scm).powi(2);
                    s3 += (acc3 / scm).powi(2);
                }
                let deno = if s5 + 0.01 * s3 > 0.0 { s5 + 0.01 * s3 } else { 1.0 };
                h.abs() * s5 * (1.0 / (n as f64 * deno)).sqrt()
            }
        }
    }

    fn non_finite_component(&self) -> usize {
        first_non_finite(&self.y_new).or_else(|| self.k.iter().find_map(|k| first_non_finite(k))).unwrap_or(0)
    }
}

impl super::Stepper for ExplicitRk {
    super::stepper_state!();

    fn step(&mut self, sys: &dyn OdeSystem, t_stop: f64) -> Result<(), IntegrateError> {
        const SAFE: f64 = 0.9;
        let mut rejected_once = false;
        let mut non_finite_run = 0u32;
        loop {
            let mut h = self.h;
            let last = self.t + 1.01 * h >= t_stop;
            if last {
                h = t_stop - self.t;
            }
            if step_too_small(self.t, h) {
                return Err(if non_finite_run > 0 {
                    IntegrateError::NonFinite { t: self.t, component: self.non_finite_component() }
                } else {
                    IntegrateError::StepSizeTooSmall { t: self.t, h }
                });
            }
            let err = self.attempt(sys, h);
            let finite = err.is_finite() && first_non_finite(&self.y_new).is_none();
            if !finite && self.fixed.is_some() {
                return Err(IntegrateError::NonFinite { t: self.t, component: self.non_finite_component() });
            }
            if !finite {
                non_finite_run += 1;
                self.stats.rejected += 1;
                if non_finite_run >= MAX_NON_FINITE {
                    return Err(IntegrateError::NonFinite { t: self.t, component: self.non_finite_component() });
                }
                self.h = 0.2 * h;
                rejected_once = true;
                continue;
            }
            if err <= 1.0 || self.fixed.is_some() {
                let proposed = self.control.accept(h, err, SAFE);
                let mut h_new = self.fixed.unwrap_or(proposed);
                if rejected_once {
                    h_new = h_new.min(h);
                }
                let t_new = if last { t_stop } else { self.t + h };
                // Dense output of the step, from the stages before they are overwritten.
                if let DenseOutput::Dopri5 { d } = &self.tab.dense {
                    let s = self.tab.stages();
                    for m in 0..self.y.len() {
                        let dy = self.y_new[m] - self.y[m];
                        let bspl = h * self.k[0][m] - dy;
                        self.rcont[0][m] = self.y[m];
                        self.rcont[1][m] = dy;
                        self.rcont[2][m] = bspl;
                        self.rcont[3][m] = dy - h * self.k[s - 1][m] - bspl;
                        self.rcont[4][m] = h * (0..s).map(|j| d[j] * self.k[j][m]).sum::<f64>();
                    }
                }
                std::mem::swap(&mut self.y_prev, &mut self.y);
                std::mem::swap(&mut self.y, &mut self.y_new);
                std::mem::swap(&mut self.f_prev, &mut self.k[0]);
                if self.tab.fsal {
                    let s = self.tab.stages();
                    self.k.swap(0, s - 1);
                } else {
                    sys.rhs(t_new, &self.y, &mut self.f_new);
                    self.stats.rhs_evals += 1;
                    std::mem::swap(&mut self.k[0], &mut self.f_new);
                }
                if let Some(c) = first_non_finite(&self.k[0]) {
                    return Err(IntegrateError::NonFinite { t: t_new, component: c });
                }
                self.t_prev = self.t;
                self.t = t_new;
                self.h = h_new;
                self.h_last = h;
                self.dense_ready = false;
                self.stats.steps += 1;
                return Ok(());
            }
            non_finite_run = 0;
            rejected_once = true;
            self.stats.rejected += 1;
            self.h = self.control.reject(h, err, SAFE);
        }
    }

    fn restart(&mut self, sys: &dyn OdeSystem, t: f64, y: &[f64], t_end: f64) -> Result<(), IntegrateError> {
        checked_rhs(sys, t, y, &mut self.k[0])?;
        self.stats.rhs_evals += 1;
        self.y.copy_from_slice(y);
        self.y_prev.copy_from_slice(y);
        self.f_prev.copy_from_slice(&self.k[0]);
        self.t = t;
        self.t_prev = t;
        self.h = match self.fixed {
            Some(h) => h,
            None => {
                let order = self.tab.order as f64;
                initial_step(sys, t, y, &self.k[0], order, self.rtol, &self.atol, (t_end - t).abs(), &mut self.arg, &mut self.f_new, &mut self.stats)
            }
        };
        self.control = StepController::pi(self.tab.controller_order, 0.04, self.tab.step_ratio);
        self.dense_ready = false;
        Ok(())
    }

    /// DOP853: the three extra stages and r1 … r7 of the last step (3 rhs calls, once a step).
    fn prepare_dense(&mut self, sys: &dyn OdeSystem) {
        if self.tab.dense != DenseOutput::Dop853 || self.dense_ready {
            return;
        }
        let (n, h) = (self.y.len(), self.h_last);
        // k_j, j = 0 … 15: k1 = f_prev, the step's stages, k13 = f(t, y) (now k[0]), the extras.
        // The sums run stage by stage over all components (`combine`: per component the same
        // additions in the same order as a component-by-component loop, so the same bits, but
        // in loops over contiguous slices)
        let rows = super::dop853_dense::extra_rows();
        let mut acc = std::mem::take(&mut self.y_new);
        for e in 0..3 {
            let (done, rest) = self.extra.split_at_mut(e);
            let kj = |j: usize| -> &[f64] {
                match j {
                    0 => &self.f_prev,
                    12 => &self.k[0],
                    13.. => &done[j - 13],
                    _ => &self.k[j],
                }
            };
            combine(&mut acc, rows[e].iter().enumerate().map(|(j, &a)| (a, kj(j))));
            for ((x, &y0), &a) in self.arg.iter_mut().zip(&self.y_prev).zip(&acc) {
                *x = y0 + h * a;
            }
            sys.rhs(self.t_prev + super::dop853_dense::C[e] * h, &self.arg, &mut rest[0]);
        }
        self.stats.rhs_evals += 3;
        let kj = |j: usize| -> &[f64] {
            match j {
                0 => &self.f_prev,
                12 => &self.k[0],
                13.. => &self.extra[j - 13],
                _ => &self.k[j],
            }
        };
        let mut rc = std::mem::take(&mut self.rcont);
        for m in 0..n {
            let dy = self.y[m] - self.y_prev[m];
            let bspl = h * self.f_prev[m] - dy;
            rc[0][m] = self.y_prev[m];
            rc[1][m] = dy;
            rc[2][m] = bspl;
            rc[3][m] = dy - h * self.k[0][m] - bspl;
        }
        for (r, d) in super::dop853_dense::D.iter().enumerate() {
            combine(&mut acc, d.iter().enumerate().map(|(j, &dj)| (dj, kj(j))));
            for (o, &a) in rc[4 + r].iter_mut().zip(&acc) {
                *o = h * a;
            }
        }
        self.rcont = rc;
        self.y_new = acc;
        self.dense_ready = true;
    }

    fn interpolate(&self, t: f64, out: &mut [f64]) {
        self.dense_components(t, out.iter_mut().enumerate());
    }

    /// Without interpolating the other components (the default would, into a fresh vector):
    /// the event bisections evaluate R and Ṙ alone, tens of times per located switch.
    fn interpolate_at(&self, t: f64, idx: &[usize], out: &mut [f64]) {
        self.dense_components(t, idx.iter().copied().zip(out.iter_mut()));
    }
}

impl ExplicitRk {
    /// The dense output of component m at t into each (m, out) pair, the same formula per
    /// component for all of them and for a selection.
    #[inline(always)]
    fn dense_components<'o>(&self, t: f64, pairs: impl Iterator<Item = (usize, &'o mut f64)>) {
        let h = self.t - self.t_prev;
        match &self.tab.dense {
            DenseOutput::Dopri5 { .. } => {
                let th = (t - self.t_prev) / h;
                let th1 = 1.0 - th;
                let r = &self.rcont;
                for (m, o) in pairs {
                    *o = r[0][m] + th * (r[1][m] + th1 * (r[2][m] + th * (r[3][m] + th1 * r[4][m])));
                }
            }
            DenseOutput::Dop853 if self.dense_ready => {
                let th = (t - self.t_prev) / self.h_last;
                for (m, o) in pairs {
                    *o = super::dop853_dense::eval(&self.rcont, th, m);
                }
            }
            // Dop853 without `prepare_dense` (a caller stepping by hand): the cubic Hermite
            DenseOutput::Dop853 | DenseOutput::Hermite => {
                let th = (t - self.t_prev) / h;
                for (m, o) in pairs {
                    *o = hermite_at(th, h, self.y_prev[m], self.f_prev[m], self.y[m], self.k[0][m]);
                }
            }
        }
    }
}
