//! DEV STAND-IN for `crate::integrate::{solve, Method, Output, Control, Stats, Solution,
//! IntegrateError}` (helper H3, branch `integrate`), with the same API, so that the model and
//! its tests can run before the real integrators are merged. RK4 (fixed step, hits every
//! sample time) and Dormand–Prince 5(4) (adaptive, cubic Hermite output); Dop853 and Radau5
//! fall back to Dopri5 here. Replaced by `crate::integrate` at merge; must not reach `main`.
#![allow(dead_code)]

use crate::integrate::OdeSystem;
use crate::scene::{IntegratorSettings, Method as SceneMethod};

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    Rk4 { dt: f64 },
    Dopri5 { rtol: f64, atol: f64 },
    Dop853 { rtol: f64, atol: f64 },
    Radau5 { rtol: f64, atol: f64 },
}

impl Method {
    pub fn from_settings(s: &IntegratorSettings, time_scale: f64) -> Method {
        match s.method {
            SceneMethod::Rk4 => Method::Rk4 { dt: s.dt / time_scale },
            SceneMethod::Dopri5 => Method::Dopri5 { rtol: s.rtol, atol: s.atol },
            SceneMethod::Dop853 => Method::Dop853 { rtol: s.rtol, atol: s.atol },
            SceneMethod::Radau5 => Method::Radau5 { rtol: s.rtol, atol: s.atol },
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Output {
    Steps,
    Every(f64),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    Continue,
    Stop,
}

#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct Stats {
    pub steps: u64,
    pub rejected: u64,
    pub rhs_evals: u64,
}

#[derive(Debug, Clone)]
pub struct Solution {
    pub t: f64,
    pub y: Vec<f64>,
    pub stats: Stats,
    pub stopped: bool,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IntegrateError {
    #[error("step size too small ({h:e}) at t = {t:e}")]
    StepSizeTooSmall { t: f64, h: f64 },
    #[error("more than {max_steps} steps before t = {t:e}")]
    TooManySteps { t: f64, max_steps: u64 },
    #[error("non-finite state at t = {t:e}")]
    NonFinite { t: f64 },
}

pub fn solve(
    sys: &dyn OdeSystem,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    method: &Method,
    output: Output,
    max_steps: u64,
    observer: &mut dyn FnMut(f64, &[f64]) -> Control,
) -> Result<Solution, IntegrateError> {
    match *method {
        Method::Rk4 { dt } => rk4(sys, t0, y0, t_end, dt, output, max_steps, observer),
        Method::Dopri5 { rtol, atol } | Method::Dop853 { rtol, atol } | Method::Radau5 { rtol, atol } => {
            dopri5(sys, t0, y0, t_end, rtol, atol, output, max_steps, observer)
        }
    }
}

fn rk4(
    sys: &dyn OdeSystem,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    dt: f64,
    output: Output,
    max_steps: u64,
    observer: &mut dyn FnMut(f64, &[f64]) -> Control,
) -> Result<Solution, IntegrateError> {
    let n = y0.len();
    let mut y = y0.to_vec();
    let (mut k1, mut k2, mut k3, mut k4, mut tmp) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut stats = Stats::default();
    let mut t = t0;
    if observer(t, &y) == Control::Stop {
        return Ok(Solution { t, y, stats, stopped: true });
    }
    let interval = match output {
        Output::Every(s) => s,
        Output::Steps => dt,
    };
    let mut seg = 0u64;
    while t < t_end * (1.0 - 1e-14) {
        seg += 1;
        let t_next = (t0 + seg as f64 * interval).min(t_end);
        let m = ((t_next - t) / dt).ceil().max(1.0) as u64;
        let h = (t_next - t) / m as f64;
        for _ in 0..m {
            sys.rhs(t, &y, &mut k1);
            for i in 0..n { tmp[i] = y[i] + 0.5 * h * k1[i]; }
            sys.rhs(t + 0.5 * h, &tmp, &mut k2);
            for i in 0..n { tmp[i] = y[i] + 0.5 * h * k2[i]; }
            sys.rhs(t + 0.5 * h, &tmp, &mut k3);
            for i in 0..n { tmp[i] = y[i] + h * k3[i]; }
            sys.rhs(t + h, &tmp, &mut k4);
            for i in 0..n { y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]); }
            t += h;
            stats.steps += 1;
            stats.rhs_evals += 4;
            if stats.steps > max_steps {
                return Err(IntegrateError::TooManySteps { t, max_steps });
            }
            if y.iter().any(|v| !v.is_finite()) {
                return Err(IntegrateError::NonFinite { t });
            }
        }
        t = t_next;
        if observer(t, &y) == Control::Stop {
            return Ok(Solution { t, y, stats, stopped: true });
        }
    }
    Ok(Solution { t, y, stats, stopped: false })
}

const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0],
    [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0],
    [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0],
];
const E: [f64; 7] = [
    71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0,
];

#[allow(clippy::too_many_arguments)]
fn dopri5(
    sys: &dyn OdeSystem,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    rtol: f64,
    atol: f64,
    output: Output,
    max_steps: u64,
    observer: &mut dyn FnMut(f64, &[f64]) -> Control,
) -> Result<Solution, IntegrateError> {
    let n = y0.len();
    let mut y = y0.to_vec();
    let mut k = vec![vec![0.0; n]; 7];
    let mut tmp = vec![0.0; n];
    let mut ynew = vec![0.0; n];
    let mut yout = vec![0.0; n];
    let mut stats = Stats::default();
    let mut t = t0;
    if observer(t, &y) == Control::Stop {
        return Ok(Solution { t, y, stats, stopped: true });
    }
    sys.rhs(t, &y, &mut k[0]);
    stats.rhs_evals += 1;
    let mut h = (t_end - t0) * 1e-6;
    let mut next_out = match output {
        Output::Every(s) => t0 + s,
        Output::Steps => f64::INFINITY,
    };
    let mut n_out = 1u64;
    while t < t_end {
        if stats.steps + stats.rejected > max_steps {
            return Err(IntegrateError::TooManySteps { t, max_steps });
        }
        if t + h > t_end {
            h = t_end - t;
        }
        for s in 1..7 {
            for i in 0..n {
                let mut acc = y[i];
                for j in 0..s {
                    acc += h * A[s][j] * k[j][i];
                }
                tmp[i] = acc;
            }
            let (head, tail) = k.split_at_mut(s);
            let _ = head;
            sys.rhs(t + C[s] * h, &tmp, &mut tail[0]);
            if s == 6 {
                ynew.copy_from_slice(&tmp);
            }
        }
        stats.rhs_evals += 6;
        let mut err = 0.0f64;
        for i in 0..n {
            let mut e = 0.0;
            for s in 0..7 {
                e += E[s] * k[s][i];
            }
            let sc = atol + rtol * y[i].abs().max(ynew[i].abs());
            err += (h * e / sc).powi(2);
        }
        let err = (err / n as f64).sqrt();
        if !err.is_finite() {
            h *= 0.1;
            stats.rejected += 1;
            if h.abs() < 1e-14 * t.abs().max(1.0) {
                return Err(IntegrateError::NonFinite { t });
            }
            continue;
        }
        if err <= 1.0 {
            // dense output (cubic Hermite) for the samples in (t, t+h]
            let t1 = t + h;
            while next_out <= t1 * (1.0 + 1e-14) && next_out <= t_end * (1.0 + 1e-14) {
                let th = ((next_out - t) / h).clamp(0.0, 1.0);
                let (h00, h10, h01, h11) = (
                    2.0 * th.powi(3) - 3.0 * th * th + 1.0,
                    th.powi(3) - 2.0 * th * th + th,
                    -2.0 * th.powi(3) + 3.0 * th * th,
                    th.powi(3) - th * th,
                );
                for i in 0..n {
                    yout[i] = h00 * y[i] + h10 * h * k[0][i] + h01 * ynew[i] + h11 * h * k[6][i];
                }
                if observer(next_out, &yout) == Control::Stop {
                    return Ok(Solution { t: next_out, y: yout, stats, stopped: true });
                }
                n_out += 1;
                next_out = match output {
                    Output::Every(s) => t0 + n_out as f64 * s,
                    Output::Steps => f64::INFINITY,
                };
            }
            t = t1;
            y.copy_from_slice(&ynew);
            let last = k[6].clone();
            k[0].copy_from_slice(&last);
            stats.steps += 1;
            if matches!(output, Output::Steps) && observer(t, &y) == Control::Stop {
                return Ok(Solution { t, y, stats, stopped: true });
            }
            let fac = (0.9 * err.max(1e-10).powf(-0.2)).clamp(0.2, 5.0);
            h *= fac;
        } else {
            stats.rejected += 1;
            h *= (0.9 * err.powf(-0.2)).clamp(0.1, 1.0);
        }
        if h.abs() < 1e-14 * t.abs().max(1.0) {
            return Err(IntegrateError::StepSizeTooSmall { t, h });
        }
    }
    Ok(Solution { t, y, stats, stopped: false })
}
