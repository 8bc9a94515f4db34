//! The linearly implicit Rosenbrock pair of Shampine & Reichelt (1997, *The MATLAB ODE Suite*,
//! SIAM J. Sci. Comput. 18, sec. 3; MATLAB `ode23s`): order 2 with a third-order error
//! estimate, L-stable, a W-method (order 2 kept with an approximate J).
//!
//! Step from (t, y) with h: W = I − h d J, d = 1/(2 + √2), e32 = 6 + √2, T ≈ ∂f/∂t,
//! F0 = f(t, y), k1 = W⁻¹(F0 + h d T), F1 = f(t + h/2, y + h k1/2), k2 = W⁻¹(F1 − k1) + k1,
//! y1 = y + h k2, F2 = f(t + h, y1), k3 = W⁻¹[F2 − e32(k2 − F1) − 2(k1 − F0) + h d T],
//! err = h(k1 − 2k2 + k3)/6. Dense output (`ntrp23s`): y(t + θh) = y + h(θ(1−θ)k1 + θ(θ−2d)k2)/(1−2d).
//!
//! Every solve with W is a solve with σI − J, σ = 1/(hd), through the linear-solver hook
//! ([`super::linear`]): the system's structured solve when it has one. J is reused for
//! [`JAC_MAX_AGE`] steps (re-evaluated after a rejection with an older J), W is refactored only
//! when h changes; step control is the shared I controller of order 3 ([`super::control`],
//! safety 0.8, h_new/h ∈ [0.2, 5], h kept when the proposal is within [1, 1.2]).

use super::control::StepController;
use super::explicit::{adaptive_start, step_too_small, Start, MAX_NON_FINITE};
use super::linear::NewtonMatrix;
use super::{first_non_finite, IntegrateError, OdeSystem, Stats};
use nalgebra::Complex;

/// Steps a Jacobian is reused for.
pub const JAC_MAX_AGE: u32 = 2;
const SAFE: f64 = 0.8;

/// The Rosenbrock ode23s stepper (see the module documentation).
#[derive(Debug)]
pub struct Rosenbrock23 {
    rtol: f64,
    /// atol·w_i ([`super::atol_vector`]).
    atol: Vec<f64>,
    t: f64,
    t_prev: f64,
    h: f64,
    h_last: f64,
    y: Vec<f64>,
    y_prev: Vec<f64>,
    f0: Vec<f64>,
    ft: Vec<f64>,
    k: [Vec<f64>; 3],
    /// k1, k2 of the last accepted step (dense output).
    k_prev: [Vec<f64>; 2],
    f1: Vec<f64>,
    f2: Vec<f64>,
    y1: Vec<f64>,
    tmp: Vec<f64>,
    nm: NewtonMatrix,
    /// σ of the current factorisation (NaN: none).
    lu_sigma: f64,
    /// Steps since J was evaluated (`None`: no J).
    jac_age: Option<u32>,
    control: StepController,
    stats: Stats,
}

const D: f64 = 0.292_893_218_813_452_4; // 1/(2 + √2)

impl Rosenbrock23 {
    pub fn new(sys: &dyn OdeSystem, t0: f64, y0: &[f64], t_end: f64, rtol: f64, atol: f64) -> Result<Self, IntegrateError> {
        let n = y0.len();
        let atol = super::atol_vector(sys, atol, n);
        let Start { f0, h, scratch: (w1, w2), stats } = adaptive_start(sys, t0, y0, t_end, 3.0, rtol, &atol)?;
        let v = || vec![0.0; n];
        Ok(Rosenbrock23 {
            rtol,
            atol,
            t: t0,
            t_prev: t0,
            h,
            h_last: 0.0,
            y: y0.to_vec(),
            y_prev: y0.to_vec(),
            f0,
            ft: v(),
            k: [v(), v(), v()],
            k_prev: [v(), v()],
            f1: v(),
            f2: w2,
            y1: w1,
            tmp: v(),
            nm: NewtonMatrix::new(n, false),
            lu_sigma: f64::NAN,
            jac_age: None,
            control: StepController::pi(3.0, 0.0, (0.2, 5.0)),
            stats,
        })
    }

    fn refresh_jacobian(&mut self, sys: &dyn OdeSystem) -> Result<(), IntegrateError> {
        let r = self.nm.evaluate(sys, self.t, &self.y, &self.f0, &mut self.stats);
        self.jac_age = Some(0);
        self.lu_sigma = f64::NAN;
        r.map_err(|c| IntegrateError::NonFinite { t: self.t, component: c })
    }

    /// W⁻¹ v = σ (σI − J)⁻¹ v.
    fn wsolve(nm: &NewtonMatrix, sigma: f64, v: &mut [f64]) {
        nm.solve(v);
        v.iter_mut().for_each(|x| *x *= sigma);
    }
}

impl super::Stepper for Rosenbrock23 {
    super::stepper_state!();

    fn step(&mut self, sys: &dyn OdeSystem, t_stop: f64) -> Result<(), IntegrateError> {
        let n = self.y.len();
        let e32 = 6.0 + 2f64.sqrt();
        if self.jac_age.is_none_or(|a| a >= JAC_MAX_AGE) {
            self.refresh_jacobian(sys)?;
        }
        // T = ∂f/∂t by a forward difference
        let dt_t = f64::EPSILON.sqrt() * self.t.abs().max(self.h);
        sys.rhs(self.t + dt_t, &self.y, &mut self.ft);
        self.stats.rhs_evals += 1;
        for i in 0..n {
            self.ft[i] = (self.ft[i] - self.f0[i]) / dt_t;
        }
        let mut non_finite = 0u32;
        loop {
            let mut h = self.h;
            let last = self.t + h >= t_stop;
            if last {
                h = t_stop - self.t;
            }
            if step_too_small(self.t, h) {
                return Err(IntegrateError::StepSizeTooSmall { t: self.t, h });
            }
            let sigma = 1.0 / (h * D);
            if self.lu_sigma != sigma {
                if !self.nm.factor(sigma, Complex::new(0.0, 0.0), &mut self.stats) {
                    return Err(IntegrateError::SingularMatrix { t: self.t });
                }
                self.lu_sigma = sigma;
            }
            let [k1, k2, k3] = &mut self.k;
            for i in 0..n {
                k1[i] = self.f0[i] + h * D * self.ft[i];
            }
            Self::wsolve(&self.nm, sigma, k1);
            for i in 0..n {
                self.tmp[i] = self.y[i] + 0.5 * h * k1[i];
            }
            sys.rhs(self.t + 0.5 * h, &self.tmp, &mut self.f1);
            for i in 0..n {
                k2[i] = self.f1[i] - k1[i];
            }
            Self::wsolve(&self.nm, sigma, k2);
            for i in 0..n {
                k2[i] += k1[i];
                self.y1[i] = self.y[i] + h * k2[i];
            }
            sys.rhs(self.t + h, &self.y1, &mut self.f2);
            for i in 0..n {
                k3[i] = self.f2[i] - e32 * (k2[i] - self.f1[i]) - 2.0 * (k1[i] - self.f0[i]) + h * D * self.ft[i];
            }
            Self::wsolve(&self.nm, sigma, k3);
            self.stats.rhs_evals += 2;
            let mut sum = 0.0;
            for i in 0..n {
                let e = h / 6.0 * (k1[i] - 2.0 * k2[i] + k3[i]);
                let sc = self.atol[i] + self.rtol * self.y[i].abs().max(self.y1[i].abs());
                sum += (e / sc).powi(2);
            }
            let err = (sum / n.max(1) as f64).sqrt();
            if !err.is_finite() || first_non_finite(&self.f2).is_some() {
                self.stats.rejected += 1;
                non_finite += 1;
                if non_finite >= MAX_NON_FINITE {
                    let c = first_non_finite(&self.y1).or_else(|| first_non_finite(&self.f2)).unwrap_or(0);
                    return Err(IntegrateError::NonFinite { t: self.t, component: c });
                }
                self.h = 0.25 * h;
                continue;
            }
            if err <= 1.0 {
                let h_new = self.control.accept(h, err, SAFE);
                let t_new = if last { t_stop } else { self.t + h };
                std::mem::swap(&mut self.y_prev, &mut self.y);
                std::mem::swap(&mut self.y, &mut self.y1);
                std::mem::swap(&mut self.f0, &mut self.f2);
                std::mem::swap(&mut self.k_prev[0], &mut self.k[0]);
                std::mem::swap(&mut self.k_prev[1], &mut self.k[1]);
                self.t_prev = self.t;
                self.t = t_new;
                self.h_last = h;
                self.stats.steps += 1;
                self.jac_age = self.jac_age.map(|a| a + 1);
                if !StepController::keeps(h_new / h) {
                    self.h = h_new;
                }
                return Ok(());
            }
            self.stats.rejected += 1;
            self.h = self.control.reject(h, err, SAFE);
            if self.jac_age.is_some_and(|a| a >= 1) {
                // a stale Jacobian may be the cause: re-evaluate it
                self.refresh_jacobian(sys)?;
            }
        }
    }

    fn restart(&mut self, sys: &dyn OdeSystem, t: f64, y: &[f64], t_end: f64) -> Result<(), IntegrateError> {
        let Start { f0, h, stats, .. } = adaptive_start(sys, t, y, t_end, 3.0, self.rtol, &self.atol)?;
        self.stats.rhs_evals += stats.rhs_evals;
        self.f0 = f0;
        self.h = h;
        self.h_last = 0.0;
        self.y.copy_from_slice(y);
        self.y_prev.copy_from_slice(y);
        self.k_prev.iter_mut().for_each(|k| k.fill(0.0));
        self.t = t;
        self.t_prev = t;
        self.lu_sigma = f64::NAN;
        self.jac_age = None;
        self.control = StepController::pi(3.0, 0.0, (0.2, 5.0));
        Ok(())
    }

    fn interpolate(&self, t: f64, out: &mut [f64]) {
        let h = self.h_last.max(f64::MIN_POSITIVE);
        let th = (t - self.t_prev) / h;
        let c = 1.0 / (1.0 - 2.0 * D);
        let (w1, w2) = (th * (1.0 - th) * c, th * (th - 2.0 * D) * c);
        for i in 0..out.len() {
            out[i] = self.y_prev[i] + h * (w1 * self.k_prev[0][i] + w2 * self.k_prev[1][i]);
        }
    }
}
