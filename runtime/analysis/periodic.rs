//! Periodic orbits of driven ODEs by shooting (FORMULATION §4.6 step 1, audit 14), and the common
//! period of several drives.
//!
//! The period map P_m(y) = φ(t0 + mT; t0, y) is evaluated with a fixed-step classical RK4
//! ([`RkFlow`]): a fixed step count makes P_m a smooth function of y, so its finite-difference
//! Jacobian is clean (an adaptive step-size controller would add step-selection noise to it).
//! Newton on P_m(y) − y = 0 runs from the state reached after a transient. The multiples
//! m = 1, 2, 4 … of the drive period are tried in order and the first orbit that converges and is
//! stable (all eigenvalues of DP_m inside the unit circle) is returned with its m: a period-2
//! response is detected, not assumed away. The eigenvalues of DP_m are reported too.

use crate::integrate::OdeSystem;
use nalgebra::{Complex, DMatrix, DVector};

/// Errors of the orbit search. They carry the numbers that went wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PeriodicError {
    #[error("the drive period must be finite and > 0 (got {period})")]
    BadPeriod { period: f64 },
    #[error("the state became non-finite at t = {t} (blow-up of the driven system)")]
    NonFinite { t: f64 },
    #[error("no stable periodic orbit with period m·T for m in {multiples:?}: {attempts}")]
    NoStableOrbit { multiples: Vec<usize>, attempts: String },
    #[error("frequencies {frequencies:?} Hz have no common period with denominators ≤ {max_denominator} within relative tolerance {tolerance}")]
    Incommensurate { frequencies: Vec<f64>, max_denominator: u64, tolerance: f64 },
    #[error("frequency {value} Hz must be finite and > 0")]
    BadFrequency { value: f64 },
}

/// Fixed-step classical RK4 flow of an [`OdeSystem`], `steps_per_period` steps per `period`.
pub struct RkFlow<'a> {
    pub sys: &'a dyn OdeSystem,
    pub period: f64,
    pub steps_per_period: usize,
}

impl RkFlow<'_> {
    /// Advances `y` from t0 over `periods` whole periods; returns the final time.
    pub fn advance(&self, t0: f64, y: &mut [f64], periods: usize) -> Result<f64, PeriodicError> {
        self.advance_observed(t0, y, periods, |_, _, _| {})
    }

    /// As [`advance`](Self::advance), calling `obs(t, y, f(t, y))` at every grid point
    /// (including the first and the last).
    pub fn advance_observed(
        &self,
        t0: f64,
        y: &mut [f64],
        periods: usize,
        mut obs: impl FnMut(f64, &[f64], &[f64]),
    ) -> Result<f64, PeriodicError> {
        let n = y.len();
        let h = self.period / self.steps_per_period as f64;
        let (mut k1, mut k2, mut k3, mut k4, mut tmp) =
            (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let total = periods * self.steps_per_period;
        for s in 0..total {
            let t = t0 + s as f64 * h;
            self.sys.rhs(t, y, &mut k1);
            obs(t, y, &k1);
            for i in 0..n {
                tmp[i] = y[i] + 0.5 * h * k1[i];
            }
            self.sys.rhs(t + 0.5 * h, &tmp, &mut k2);
            for i in 0..n {
                tmp[i] = y[i] + 0.5 * h * k2[i];
            }
            self.sys.rhs(t + 0.5 * h, &tmp, &mut k3);
            for i in 0..n {
                tmp[i] = y[i] + h * k3[i];
            }
            self.sys.rhs(t + h, &tmp, &mut k4);
            for i in 0..n {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
            if y.iter().any(|v| !v.is_finite()) {
                return Err(PeriodicError::NonFinite { t: t + h });
            }
        }
        let t = t0 + total as f64 * h;
        self.sys.rhs(t, y, &mut k1);
        obs(t, y, &k1);
        Ok(t)
    }
}

/// Settings of [`find_orbit`].
#[derive(Debug, Clone, PartialEq)]
pub struct ShootingOptions {
    /// Drive periods integrated before Newton starts.
    pub transient_periods: usize,
    /// Multiples m of the drive period to try, in order.
    pub multiples: Vec<usize>,
    /// Convergence: ‖P_m(y) − y‖∞ ≤ tol · max(1, ‖y‖∞).
    pub tol: f64,
    pub max_iterations: usize,
    /// RK4 steps per drive period.
    pub steps_per_period: usize,
}

impl Default for ShootingOptions {
    fn default() -> Self {
        Self { transient_periods: 20, multiples: vec![1, 2, 4], tol: 1e-10, max_iterations: 20, steps_per_period: 1000 }
    }
}

/// A periodic orbit of a driven system.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicOrbit {
    /// Phase origin: the orbit passes through `y0` at `t0` (t0 is a whole number of drive periods).
    pub t0: f64,
    pub y0: Vec<f64>,
    pub drive_period: f64,
    /// The orbit's period is `multiple` drive periods.
    pub multiple: usize,
    pub newton_iterations: usize,
    /// ‖P_m(y0) − y0‖∞ at the end.
    pub residual: f64,
    /// Eigenvalues of DP_m (the orbit's own Floquet multipliers; stable: all |λ| < 1).
    pub multipliers: Vec<Complex<f64>>,
}

impl PeriodicOrbit {
    pub fn period(&self) -> f64 {
        self.multiple as f64 * self.drive_period
    }
    pub fn max_multiplier(&self) -> f64 {
        self.multipliers.iter().map(|z| z.norm()).fold(0.0, f64::max)
    }
}

/// Finds a stable periodic orbit of `sys` driven with period `drive_period` (see the module doc).
pub fn find_orbit(
    sys: &dyn OdeSystem,
    t0: f64,
    y0: &[f64],
    drive_period: f64,
    opts: &ShootingOptions,
) -> Result<PeriodicOrbit, PeriodicError> {
    if !(drive_period.is_finite() && drive_period > 0.0) {
        return Err(PeriodicError::BadPeriod { period: drive_period });
    }
    let flow = RkFlow { sys, period: drive_period, steps_per_period: opts.steps_per_period.max(1) };
    let mut y = y0.to_vec();
    let t_start = flow.advance(t0, &mut y, opts.transient_periods)?;
    let mut attempts = Vec::new();
    for &m in &opts.multiples {
        match newton(&flow, t_start, &y, m.max(1), opts) {
            Ok(orbit) if orbit.max_multiplier() < 1.0 => return Ok(orbit),
            Ok(orbit) => attempts.push(format!(
                "m={m}: converged (residual {:.2e}) but unstable, max |λ| = {:.4}",
                orbit.residual,
                orbit.max_multiplier()
            )),
            Err(e) => attempts.push(format!("m={m}: {e}")),
        }
    }
    Err(PeriodicError::NoStableOrbit { multiples: opts.multiples.clone(), attempts: attempts.join("; ") })
}

/// Newton on G(y) = P_m(y) − y with a forward-difference Jacobian and step halving.
fn newton(
    flow: &RkFlow,
    t0: f64,
    y_start: &[f64],
    m: usize,
    opts: &ShootingOptions,
) -> Result<PeriodicOrbit, PeriodicError> {
    let n = y_start.len();
    let map = |y: &[f64]| -> Result<Vec<f64>, PeriodicError> {
        let mut z = y.to_vec();
        flow.advance(t0, &mut z, m)?;
        Ok(z)
    };
    let residual = |y: &[f64], p: &[f64]| -> f64 {
        y.iter().zip(p).map(|(a, b)| (b - a).abs()).fold(0.0, f64::max)
    };
    let scale = |y: &[f64]| y.iter().map(|v| v.abs()).fold(1.0, f64::max);
    let mut y = y_start.to_vec();
    let mut p = map(&y)?;
    let mut r = residual(&y, &p);
    let mut iterations = 0;
    loop {
        let jac = jacobian(&map, &y, &p)?;
        if r <= opts.tol * scale(&y) {
            let multipliers = crate::analysis::floquet::eigenvalues(&jac);
            return Ok(PeriodicOrbit {
                t0,
                y0: y,
                drive_period: flow.period,
                multiple: m,
                newton_iterations: iterations,
                residual: r,
                multipliers,
            });
        }
        if iterations >= opts.max_iterations {
            return Err(PeriodicError::NoStableOrbit {
                multiples: vec![m],
                attempts: format!("Newton did not converge in {iterations} iterations (residual {r:.3e})"),
            });
        }
        iterations += 1;
        // (DP − I) δ = −(P − y)
        let mut a = jac;
        for i in 0..n {
            a[(i, i)] -= 1.0;
        }
        let g = DVector::from_iterator(n, y.iter().zip(&p).map(|(yi, pi)| yi - pi));
        let Some(delta) = a.lu().solve(&g) else {
            return Err(PeriodicError::NoStableOrbit {
                multiples: vec![m],
                attempts: "singular shooting Jacobian (a multiplier equal to 1)".into(),
            });
        };
        let mut lambda = 1.0;
        loop {
            let trial: Vec<f64> = y.iter().zip(delta.iter()).map(|(a, d)| a + lambda * d).collect();
            let accepted = match map(&trial) {
                Ok(pt) => {
                    let rt = residual(&trial, &pt);
                    if rt < r || lambda < 1.0 / 64.0 {
                        y = trial;
                        p = pt;
                        r = rt;
                        true
                    } else {
                        false
                    }
                }
                Err(e) if lambda < 1.0 / 64.0 => return Err(e),
                Err(_) => false,
            };
            if accepted {
                break;
            }
            lambda *= 0.5;
        }
    }
}

/// Forward-difference Jacobian of `map` at y (p = map(y)).
fn jacobian(
    map: &impl Fn(&[f64]) -> Result<Vec<f64>, PeriodicError>,
    y: &[f64],
    p: &[f64],
) -> Result<DMatrix<f64>, PeriodicError> {
    let n = y.len();
    let mut jac = DMatrix::zeros(n, n);
    for j in 0..n {
        let h = 1e-7 * y[j].abs().max(1e-3);
        let mut yj = y.to_vec();
        yj[j] += h;
        let pj = map(&yj)?;
        for i in 0..n {
            jac[(i, j)] = (pj[i] - p[i]) / h;
        }
    }
    Ok(jac)
}

/// The smallest T > 0 such that f·T is an integer for every f in `frequencies` (Hz), where each
/// ratio f_i/f_0 is matched by a fraction p/q with q ≤ `max_denominator` within relative
/// `tolerance`. Example: 1 MHz and 0.5 MHz → 2 µs; 1 MHz and 1.777 MHz → 1 ms (q = 1000).
pub fn common_period(frequencies: &[f64], max_denominator: u64, tolerance: f64) -> Result<f64, PeriodicError> {
    let Some((&f0, rest)) = frequencies.split_first() else {
        return Err(PeriodicError::BadFrequency { value: f64::NAN });
    };
    for &f in frequencies {
        if !(f.is_finite() && f > 0.0) {
            return Err(PeriodicError::BadFrequency { value: f });
        }
    }
    // T = L / f0 with L the smallest integer such that L · p_i/q_i is an integer for all i:
    // L = lcm of the q_i / gcd(p_i, q_i) (fractions reduced).
    let mut l: u64 = 1;
    for &f in rest {
        let ratio = f / f0;
        let Some((_p, q)) = (1..=max_denominator).find_map(|q| {
            let p = (ratio * q as f64).round();
            ((p / q as f64 - ratio).abs() <= tolerance * ratio && p >= 1.0).then_some((p as u64, q))
        }) else {
            return Err(PeriodicError::Incommensurate {
                frequencies: frequencies.to_vec(),
                max_denominator,
                tolerance,
            });
        };
        l = lcm(l, q);
    }
    Ok(l as f64 / f0)
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 { a } else { gcd(b, a % b) }
}
fn lcm(a: u64, b: u64) -> u64 {
    a / gcd(a, b) * b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn common_periods() {
        let t = common_period(&[1e6, 0.5e6], 1000, 1e-9).unwrap();
        assert!((t - 2e-6).abs() < 1e-18);
        let t = common_period(&[1e6, 1.5e6], 1000, 1e-9).unwrap();
        assert!((t - 2e-6).abs() < 1e-18, "{t}");
        let t = common_period(&[1e6, 1.777e6], 1000, 1e-12).unwrap();
        assert!((t - 1e-3).abs() < 1e-15, "{t}");
        let t = common_period(&[2e6], 10, 1e-9).unwrap();
        assert!((t - 0.5e-6).abs() < 1e-18);
        // three drives: 1, 2/3, 1/4 MHz → lcm(3, 4) = 12 µs
        let t = common_period(&[1e6, 2e6 / 3.0, 0.25e6], 100, 1e-9).unwrap();
        assert!((t - 12e-6).abs() < 1e-15, "{t}");
        assert!(matches!(
            common_period(&[1e6, std::f64::consts::SQRT_2 * 1e6], 100, 1e-9),
            Err(PeriodicError::Incommensurate { .. })
        ));
        assert!(matches!(common_period(&[1e6, -1.0], 100, 1e-9), Err(PeriodicError::BadFrequency { .. })));
    }
}
