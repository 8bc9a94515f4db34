//! An adaptive linearly implicit integrator for the monolithic system: the Rosenbrock pair of
//! Shampine & Reichelt (1997, MATLAB `ode23s`; order 2 with a third-order error estimate,
//! L-stable), with every linear solve done by the structured factorisation of
//! [`super::structured`] — O(M·n) per step instead of a dense LU of the (2 + M(n+1))-square
//! Newton matrix. It exists because the shared Radau5 (`integrate::Radau5`) factors dense or
//! banded matrices only, and this Jacobian is neither (docs/vorticity.md).
//!
//! Step: W = I − h d J, d = 1/(2 + √2), e32 = 6 + √2, T = ∂f/∂t,
//! k1 = W⁻¹(F0 + h d T), F1 = f(t + h/2, y + h k1/2), k2 = W⁻¹(F1 − k1) + k1, y1 = y + h k2,
//! F2 = f(t + h, y1), k3 = W⁻¹[F2 − e32(k2 − F1) − 2(k1 − F0) + h d T], err = h(k1 − 2k2 + k3)/6.
//!
//! The pair is a W-method (Wolfbrandt's, modified by Shampine): it keeps order 2 with an
//! approximate J, so J is re-differenced only every [`JAC_MAX_AGE`] steps or after a rejection,
//! and W is refactored only when h changes (a proposed growth below 20 % keeps h).

use super::monolithic::Monolithic;
use super::structured::StructuredJacobian;
use super::VorticityError;
use crate::integrate::OdeSystem;

/// Steps a Jacobian is reused for.
pub const JAC_MAX_AGE: u32 = 2;

/// Tolerances and limits (time in the coupling's unit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImplicitSettings {
    pub rtol: f64,
    pub atol: f64,
    /// Initial step (0: 10⁻⁴ of the span).
    pub h0: f64,
    /// Call the observer at t0 + i·interval (and at t_end) with the solution interpolated by the
    /// method's continuous extension (Shampine & Reichelt, `ntrp23s`); 0: after every accepted
    /// step.
    pub output_interval: f64,
    pub max_steps: u64,
}

/// Counters of one run.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct ImplicitStats {
    pub accepted: u64,
    pub rejected: u64,
    pub rhs_evals: u64,
    pub factorizations: u64,
}

/// Integrates from (t0, y0) to t_end; `observer(t, y)` after every accepted step (return
/// `false` to stop). `y0` is overwritten with the final state.
pub fn integrate(
    sys: &Monolithic<'_>,
    t0: f64,
    y: &mut [f64],
    t_end: f64,
    s: &ImplicitSettings,
    mut observer: impl FnMut(f64, &[f64]) -> bool,
) -> Result<ImplicitStats, VorticityError> {
    let n = sys.dim();
    let d = 1.0 / (2.0 + 2f64.sqrt());
    let e32 = 6.0 + 2f64.sqrt();
    let mut st = ImplicitStats::default();
    let mut t = t0;
    let mut f0 = vec![0.0; n];
    sys.rhs(t, y, &mut f0);
    st.rhs_evals += 1;
    let span = t_end - t0;
    let mut h = if s.h0 > 0.0 { s.h0 } else { 1e-4 * span };
    let (mut k1, mut k2, mut k3) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (mut f1, mut f2, mut ft, mut ytmp, mut y1) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut n_out = 1u64;
    let mut yout = vec![0.0; n];
    let mut jac: Option<std::rc::Rc<StructuredJacobian>> = None;
    let mut lu: Option<(f64, super::structured::StructuredLu<f64>)> = None;
    let mut jac_age = 0u32;
    while t < t_end {
        if st.accepted + st.rejected >= s.max_steps {
            return Err(VorticityError::NonFinite { t, what: format!("step limit {} reached", s.max_steps) });
        }
        let mut landing = h >= t_end - t;
        if landing {
            h = t_end - t;
        }
        if jac.is_none() || jac_age >= JAC_MAX_AGE {
            jac = Some(StructuredJacobian::new(sys, t, y));
            st.rhs_evals += (2 + 5 * sys.operators().len()) as u64;
            jac_age = 0;
            lu = None;
        }
        jac_age += 1;
        let dt_t = (f64::EPSILON.sqrt()) * t.abs().max(h);
        sys.rhs(t + dt_t, y, &mut ft);
        st.rhs_evals += 1;
        for i in 0..n {
            ft[i] = (ft[i] - f0[i]) / dt_t;
        }
        loop {
            let sigma = 1.0 / (h * d);
            if lu.as_ref().is_none_or(|(s0, _)| *s0 != sigma) {
                let j = jac.as_ref().expect("set above");
                lu = Some((sigma, j.factor(sigma).ok_or(VorticityError::Singular { k: 0, t })?));
                st.factorizations += 1;
            }
            let lu_now = &lu.as_ref().expect("set above").1;
            // W⁻¹ v = σ (σI − J)⁻¹ v
            let wsolve = |v: &mut [f64]| {
                lu_now.solve(v);
                v.iter_mut().for_each(|x| *x *= sigma);
            };
            for i in 0..n {
                k1[i] = f0[i] + h * d * ft[i];
            }
            wsolve(&mut k1);
            for i in 0..n {
                ytmp[i] = y[i] + 0.5 * h * k1[i];
            }
            sys.rhs(t + 0.5 * h, &ytmp, &mut f1);
            for i in 0..n {
                k2[i] = f1[i] - k1[i];
            }
            wsolve(&mut k2);
            for i in 0..n {
                k2[i] += k1[i];
                y1[i] = y[i] + h * k2[i];
            }
            sys.rhs(t + h, &y1, &mut f2);
            for i in 0..n {
                k3[i] = f2[i] - e32 * (k2[i] - f1[i]) - 2.0 * (k1[i] - f0[i]) + h * d * ft[i];
            }
            wsolve(&mut k3);
            st.rhs_evals += 2;
            let mut sum = 0.0;
            let mut finite = true;
            for i in 0..n {
                let e = h / 6.0 * (k1[i] - 2.0 * k2[i] + k3[i]);
                let sc = s.atol + s.rtol * y[i].abs().max(y1[i].abs());
                let r = e / sc;
                finite &= r.is_finite();
                sum += r * r;
            }
            let err = (sum / n as f64).sqrt();
            if !finite {
                st.rejected += 1;
                h *= 0.25;
                landing = false;
                if h < 1e-14 * span {
                    return Err(VorticityError::NonFinite { t, what: "implicit step: non-finite stage".into() });
                }
                continue;
            }
            let fac = (0.8 * err.powf(-1.0 / 3.0)).clamp(0.2, 5.0);
            if err <= 1.0 {
                let t_new = if landing { t_end } else { t + h };
                if s.output_interval > 0.0 {
                    // dense output at the sample times in (t, t_new)
                    let c = 1.0 / (1.0 - 2.0 * d);
                    loop {
                        let ts = t0 + n_out as f64 * s.output_interval;
                        if ts >= t_new * (1.0 - 1e-14) || ts >= t_end {
                            break;
                        }
                        let th = (ts - t) / h;
                        let (w1, w2) = (th * (1.0 - th) * c, th * (th - 2.0 * d) * c);
                        for i in 0..n {
                            yout[i] = y[i] + h * (w1 * k1[i] + w2 * k2[i]);
                        }
                        n_out += 1;
                        if !observer(ts, &yout) {
                            return Ok(st);
                        }
                    }
                }
                t = t_new;
                y.copy_from_slice(&y1);
                f0.copy_from_slice(&f2);
                st.accepted += 1;
                if !(1.0..1.2).contains(&fac) {
                    h *= fac;
                }
                break;
            }
            st.rejected += 1;
            h *= fac.min(0.9);
            landing = false;
            if jac_age > 1 {
                // a stale Jacobian may be the cause: re-difference it
                jac = Some(StructuredJacobian::new(sys, t, y));
                st.rhs_evals += (2 + 5 * sys.operators().len()) as u64;
                jac_age = 1;
                lu = None;
            }
            if h < 1e-14 * span {
                return Err(VorticityError::NonFinite { t, what: format!("implicit step size underflow (h = {h:e})") });
            }
        }
        let at_sample = s.output_interval > 0.0 && (t0 + n_out as f64 * s.output_interval - t).abs() <= 1e-12 * t.abs().max(1.0);
        if s.output_interval <= 0.0 || t >= t_end || at_sample {
            if at_sample {
                n_out += 1;
            }
            if !observer(t, y) {
                break;
            }
        }
    }
    Ok(st)
}
