//! Periodic orbits of driven ODEs (FORMULATION §4.6 step 1, audit 14): the fixed-step period map
//! [`RkFlow`] with its exact derivative, the orbit search (in [`super::shooting`], re-exported
//! here), and the common period of several drives.
//!
//! **Why the period map does not run on the run loop** ([`crate::integrate::run_loop`], which
//! the shooting's transient and every time integration use): P_m is a fixed map of y — a fixed
//! grid of `steps_per_period` steps per period, no step control, no samples, no budget, no
//! events — and Newton needs its derivative to the bit of the discrete map, the Jacobian at every
//! RK4 stage (the 2-state radial orbit on stack arrays). The loop's [`crate::integrate::Rk4`]
//! on [`crate::integrate::Variational`] integrates the same equations but sums the stages in
//! another order (and from another grid expression), so the shipped `floquet`/`stability`
//! results would move in their last bits. A drive with
//! discontinuities inside a period needs its stop times on this grid (whole steps).
//!
//! The period map P_m(y) = φ(t0 + mT; t0, y) is evaluated with a fixed-step classical RK4: a
//! fixed step count makes P_m a smooth function of y. Its Jacobian DP_m is the RK4 solution of
//! the variational equations Φ' = J(t, y) Φ integrated with the same steps
//! ([`RkFlow::advance_variational`]), i.e. the derivative of the discrete map itself — not a
//! finite difference of P_m, whose step on a small component (Ṙ ≈ 0) cost 2–5e-5 in the radial
//! multipliers (issue 13 part 2).
//!
//! **Kinked laws** ([`Switching`], issue 31): where the right-hand side switches branch at
//! state-dependent events (the kinked Marmottant law's R_b and R_r, a tension curve's knots), a
//! grid step that crosses one is split at the located crossing, as the run loop does
//! (switches.rs; docs/stability.md, "Floquet on a kinked law"); the grid itself is unchanged.

use crate::integrate::OdeSystem;
use nalgebra::DMatrix;

mod switches;
mod tangent;
pub use switches::{Switch, Switching};
use tangent::{Buf, DynTangent, FixedTangent, NoTangent, Tangent, NODES};

pub use super::shooting::{find_orbit, find_orbit_switched, PeriodicOrbit, ShootingOptions};

/// Errors of the orbit search. They carry the numbers that went wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PeriodicError {
    #[error("the drive period must be finite and > 0 (got {period})")]
    BadPeriod { period: f64 },
    #[error("the state became non-finite at t = {t} (blow-up of the driven system)")]
    NonFinite { t: f64 },
    #[error("no stable periodic orbit with period m·T for m in {multiples:?}: {attempts}")]
    NoStableOrbit { multiples: Vec<usize>, attempts: String },
    #[error("the transient before the orbit search failed: {reason}")]
    Transient { reason: String },
    #[error("Newton on P_{multiple}(y) = y did not converge in {iterations} iterations (residual {residual:.3e})")]
    NotConverged { multiple: usize, iterations: usize, residual: f64 },
    #[error("singular shooting Jacobian for m = {multiple} (a multiplier equal to 1)")]
    SingularShooting { multiple: usize },
    #[error("frequencies {frequencies:?} Hz have no common period with denominators ≤ {max_denominator} within relative tolerance {tolerance}")]
    Incommensurate { frequencies: Vec<f64>, max_denominator: u64, tolerance: f64 },
    #[error("frequency {value} Hz must be finite and > 0")]
    BadFrequency { value: f64 },
}

/// What the period map calls at every grid point: (t, y, f(t, y)).
pub type Observer<'o> = dyn FnMut(f64, &[f64], &[f64]) + 'o;

/// Fixed-step classical RK4 flow of an [`OdeSystem`], `steps_per_period` steps per `period`.
pub struct RkFlow<'a> {
    pub sys: &'a dyn OdeSystem,
    pub period: f64,
    pub steps_per_period: usize,
    /// The branch switches of a kinked law, located inside the steps (`None`: a smooth system,
    /// the plain grid).
    pub switching: Option<&'a dyn Switching>,
}

impl RkFlow<'_> {
    /// Advances `y` from t0 over `periods` whole periods; returns the final time.
    pub fn advance(&self, t0: f64, y: &mut [f64], periods: usize) -> Result<f64, PeriodicError> {
        self.integrate_any(t0, y, &mut NoTangent, periods, None, None)
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
        self.integrate_any(t0, y, &mut NoTangent, periods, Some(&mut obs), None)
    }

    /// As [`advance_observed`](Self::advance_observed), also appending every located branch
    /// switch to `log` (nothing without [`RkFlow::switching`]).
    pub fn advance_recorded(
        &self,
        t0: f64,
        y: &mut [f64],
        periods: usize,
        mut obs: impl FnMut(f64, &[f64], &[f64]),
        log: &mut Vec<Switch>,
    ) -> Result<f64, PeriodicError> {
        self.integrate_any(t0, y, &mut NoTangent, periods, Some(&mut obs), Some(log))
    }

    /// As [`advance`](Self::advance), also propagating Φ (n × n) by the variational equations
    /// Φ' = J(t, y)Φ with the same RK4 stages: on return Φ ← DP·Φ, the derivative of the
    /// discrete map. J is the system's analytic Jacobian when it has one, else a central
    /// difference with step 1e-6·max(|y_j|, ‖y‖∞, 1e-8) (exact for terms quadratic in y_j).
    pub fn advance_variational(
        &self,
        t0: f64,
        y: &mut [f64],
        phi: &mut DMatrix<f64>,
        periods: usize,
    ) -> Result<f64, PeriodicError> {
        self.advance_variational_observed(t0, y, phi, periods, None, None)
    }

    /// As [`advance_variational`](Self::advance_variational), calling `obs(t, y, f(t, y))` at
    /// every grid point (including the first and the last) as [`advance_observed`](Self::advance_observed)
    /// does: the same RK4 steps, so the same values; every located branch switch appended to
    /// `log`. At a switch Φ is continued without a saltation term: the switches of the laws
    /// behind [`Switching`] leave f continuous (a kink of τ(R), not a jump), so f⁺ = f⁻ and the
    /// saltation matrix is I (integrate/run_loop.rs).
    pub fn advance_variational_observed(
        &self,
        t0: f64,
        y: &mut [f64],
        phi: &mut DMatrix<f64>,
        periods: usize,
        obs: Option<&mut Observer<'_>>,
        log: Option<&mut Vec<Switch>>,
    ) -> Result<f64, PeriodicError> {
        let n = y.len();
        if n == 2 {
            // the radial orbit search: Φ on stack arrays (the 2 × 2 products through `DMatrix`
            // were about a quarter of its variational cost)
            let mut tan = FixedTangent::<2>::new(phi);
            let r = self.integrate::<_, [f64; 2]>(t0, y, &mut tan, periods, obs, log);
            tan.store(phi);
            return r;
        }
        let mut tan = DynTangent::new(phi);
        self.integrate::<_, Vec<f64>>(t0, y, &mut tan, periods, obs, log)
    }

    /// [`integrate`](Self::integrate) with the stage buffers on the stack for the radial orbit
    /// search (n = 2), on the heap otherwise.
    fn integrate_any<T: Tangent>(
        &self,
        t0: f64,
        y: &mut [f64],
        tan: &mut T,
        periods: usize,
        obs: Option<&mut Observer<'_>>,
        log: Option<&mut Vec<Switch>>,
    ) -> Result<f64, PeriodicError> {
        match y.len() {
            2 => self.integrate::<T, [f64; 2]>(t0, y, tan, periods, obs, log),
            _ => self.integrate::<T, Vec<f64>>(t0, y, tan, periods, obs, log),
        }
    }

    /// The one RK4 loop of the period map: y by the classical stages, the tangent `tan` (none,
    /// or Φ) by the same stages with the Jacobian at each stage point, `obs` at every grid point;
    /// on a kinked law the grid steps split at the switches (switches.rs), each logged.
    fn integrate<T: Tangent, B: Buf>(
        &self,
        t0: f64,
        y_io: &mut [f64],
        tan: &mut T,
        periods: usize,
        mut obs: Option<&mut Observer<'_>>,
        log: Option<&mut Vec<Switch>>,
    ) -> Result<f64, PeriodicError> {
        let n = y_io.len();
        let h = self.period / self.steps_per_period as f64;
        let total = periods * self.steps_per_period;
        let mut y = B::zeros(n);
        y.as_mut().copy_from_slice(y_io);
        let mut ky: [B; 4] = std::array::from_fn(|_| B::zeros(n));
        let mut tmp = B::zeros(n);
        if let Some(sw) = self.switching {
            // the law on the branch the steps are on, as in a run; back to what it was after
            let saved = sw.branch();
            let r = self.integrate_switched(sw, t0, &mut y, tan, total, h, &mut ky, &mut tmp, obs.as_deref_mut(), log);
            y_io.copy_from_slice(y.as_ref());
            let r = r.map(|()| self.last_point(t0 + total as f64 * h, y_io, ky[0].as_mut(), obs));
            sw.set_branch(saved);
            return r;
        }
        for s in 0..total {
            let t = t0 + s as f64 * h;
            self.rk4_step(t, h, &mut y, &mut ky, &mut tmp, tan, obs.as_deref_mut());
            if y.as_ref().iter().any(|v| !v.is_finite()) || !tan.is_finite() {
                y_io.copy_from_slice(y.as_ref());
                return Err(PeriodicError::NonFinite { t: t + h });
            }
        }
        y_io.copy_from_slice(y.as_ref());
        Ok(self.last_point(t0 + total as f64 * h, y_io, ky[0].as_mut(), obs))
    }

    /// `obs` at the last grid point t (its f into `f`); returns t.
    fn last_point(&self, t: f64, y: &[f64], f: &mut [f64], obs: Option<&mut Observer<'_>>) -> f64 {
        if let Some(o) = obs {
            self.sys.rhs(t, y, f);
            o(t, y, f);
        }
        t
    }

    /// One classical RK4 step of y (and the tangent) from t by h; `obs(t, y, f(t, y))` after
    /// the first stage. The slopes stay in `ky`.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn rk4_step<T: Tangent, B: Buf>(
        &self,
        t: f64,
        h: f64,
        y: &mut B,
        ky: &mut [B; 4],
        tmp: &mut B,
        tan: &mut T,
        mut obs: Option<&mut Observer<'_>>,
    ) {
        for (st, &(c, from)) in NODES.iter().enumerate() {
            if st == 0 {
                tmp.as_mut().copy_from_slice(y.as_ref());
            } else {
                for ((x, &yi), &k) in tmp.as_mut().iter_mut().zip(y.as_ref()).zip(ky[from].as_ref()) {
                    *x = yi + c * h * k;
                }
            }
            tan.stage(st, c * h, from);
            // the Jacobian first: a system whose exact Jacobian computes f too may keep it
            // for the rhs call at the same point (stability::Radial)
            tan.jacobian(self.sys, t + c * h, tmp.as_ref());
            self.sys.rhs(t + c * h, tmp.as_ref(), ky[st].as_mut());
            tan.product(st);
            if st == 0 {
                if let Some(o) = obs.as_mut() {
                    o(t, y.as_ref(), ky[0].as_ref());
                }
            }
        }
        let [k0, k1, k2, k3] = &*ky;
        let ks = k0.as_ref().iter().zip(k1.as_ref()).zip(k2.as_ref()).zip(k3.as_ref());
        for (yi, (((a, b), c), d)) in y.as_mut().iter_mut().zip(ks) {
            *yi += h / 6.0 * (a + 2.0 * b + 2.0 * c + d);
        }
        tan.accumulate(h);
    }
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
