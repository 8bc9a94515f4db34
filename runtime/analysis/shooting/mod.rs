//! The periodic-orbit search (FORMULATION §4.6 step 1; issue 13 part 1): a stable periodic
//! orbit of a driven system, of minimal period m·T, independent of where the search starts.
//!
//! 1. **Transient**: the system is integrated (adaptive Dormand–Prince 8(5,3), rtol 1e-4) for at least
//!    `transient_periods` drive periods and at least `transient_time`; the caller derives the
//!    latter from the slowest decay rate of the unforced system (for the bubble: the radial
//!    damping 2ν/R0², 1/γ ≈ 50 µs at R0 = 10 µm), not from a count of drive periods.
//! 2. **Newton** on G(y) = P_m(y) − y from the end of the transient, with the exact derivative of
//!    the discrete map ([`RkFlow::advance_variational`]) and a backtracking line search.
//! 3. **Minimal period**: a converged fixed point of P_m that already closes after d | m periods
//!    is the period-d orbit (its multipliers are those of P_d, not their (m/d)-th powers).
//! 4. **Restarts**: when an orbit is unstable with a real multiplier μ < −1 (a flip: the stable
//!    response has twice its period), Newton on P_2m restarts from y* ± s·v along the flip
//!    eigenvector v, with y* and every point of every orbit found so far *deflated*
//!    (Farrell, Birkisson & Funke, SIAM J. Sci. Comput. 37, 2015: the residual is multiplied by
//!    Π(1/‖y − y_i‖² + 1), so Newton cannot return to a known orbit).
//!
//! The multiples `multiples` (default 1, 2, 4, 8) are tried in order; the first stable orbit is
//! returned with its minimal multiple. The error lists every attempt with its multipliers.
//!
//! Step 2 (the Newton phases on the period map) is [`newton`]; this module holds the search
//! around it.

use super::periodic::{PeriodicError, RkFlow, Switch, Switching};
use crate::integrate::{self, Control, Method, OdeSystem, Output};
use nalgebra::{Complex, DMatrix};

mod newton;
use newton::Shot;

/// Settings of [`find_orbit`].
#[derive(Debug, Clone, PartialEq)]
pub struct ShootingOptions {
    /// Drive periods integrated before Newton starts (at least).
    pub transient_periods: usize,
    /// Transient duration in the system's time unit (at least; 0: only `transient_periods`).
    pub transient_time: f64,
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
        Self {
            transient_periods: 20,
            transient_time: 0.0,
            multiples: vec![1, 2, 4, 8],
            tol: 1e-10,
            max_iterations: 20,
            steps_per_period: 1000,
        }
    }
}

/// A periodic orbit of a driven system.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicOrbit {
    /// Phase origin: the orbit passes through `y0` at `t0` (t0 is a whole number of drive periods).
    pub t0: f64,
    pub y0: Vec<f64>,
    pub drive_period: f64,
    /// The orbit's minimal period is `multiple` drive periods.
    pub multiple: usize,
    pub newton_iterations: usize,
    /// ‖P_m(y0) − y0‖∞ at the end.
    pub residual: f64,
    /// Eigenvalues of DP_m (the orbit's own Floquet multipliers; stable: all |λ| < 1).
    pub multipliers: Vec<Complex<f64>>,
    /// How the orbit was reached ("transient", "flip restart from the period-1 orbit …").
    pub found_by: String,
    /// y and f(t, y) (2·dim values each) at every RK4 grid point t0 + j·T/steps, j = 0 …
    /// multiple·steps, of the map evaluation that converged: the orbit sampled on the grid
    /// (stability.rs reads it instead of integrating the orbit once more).
    pub grid: Vec<f64>,
    /// On a kinked law ([`find_orbit_switched`]): the branch at t0 ([`Switching::branch`]; 0
    /// without) and the branch switches located over the period, in time order.
    pub start_branch: u8,
    pub switches: Vec<Switch>,
}

impl PeriodicOrbit {
    pub fn period(&self) -> f64 {
        self.multiple as f64 * self.drive_period
    }
    pub fn max_multiplier(&self) -> f64 {
        self.multipliers.iter().map(|z| z.norm()).fold(0.0, f64::max)
    }
}

/// DP_m at the orbit, kept for the flip restart.
struct Found {
    orbit: PeriodicOrbit,
    jac: DMatrix<f64>,
    /// Every point of the orbit at the phase t0 + j·T, j < multiple (all fixed points of P_km).
    points: Vec<Vec<f64>>,
}

fn scale(y: &[f64]) -> f64 {
    y.iter().map(|v| v.abs()).fold(1.0, f64::max)
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// Finds a stable periodic orbit of `sys` driven with period `drive_period` (see the module doc).
pub fn find_orbit(
    sys: &dyn OdeSystem,
    t0: f64,
    y0: &[f64],
    drive_period: f64,
    opts: &ShootingOptions,
) -> Result<PeriodicOrbit, PeriodicError> {
    find_orbit_switched(sys, None, t0, y0, drive_period, opts)
}

/// [`find_orbit`] for a right-hand side with branch switches (a kinked law): the period map's
/// steps split at the located switches ([`RkFlow::switching`]; the transient only seeds Newton
/// and runs as before).
pub fn find_orbit_switched(
    sys: &dyn OdeSystem,
    switching: Option<&dyn Switching>,
    t0: f64,
    y0: &[f64],
    drive_period: f64,
    opts: &ShootingOptions,
) -> Result<PeriodicOrbit, PeriodicError> {
    if !(drive_period.is_finite() && drive_period > 0.0) {
        return Err(PeriodicError::BadPeriod { period: drive_period });
    }
    let flow = RkFlow { sys, period: drive_period, steps_per_period: opts.steps_per_period.max(1), switching };
    let (t_start, y) = transient(sys, t0, y0, drive_period, opts)?;
    let mut known: Vec<Found> = Vec::new();
    let mut attempts = Vec::new();
    for &m in &opts.multiples {
        let m = m.max(1);
        let mut starts: Vec<(Vec<f64>, String)> = vec![(y.clone(), "transient".into())];
        for k in known.iter().filter(|k| 2 * k.orbit.multiple == m) {
            if let Some((mu, v)) = flip_direction(&k.jac) {
                let sk = scale(&k.orbit.y0);
                for s in [1e-2, 1e-1, 1e-3] {
                    let start = k.orbit.y0.iter().zip(&v).map(|(a, b)| a + s * sk * b).collect();
                    starts.push((start, format!("flip restart from the period-{} orbit (μ = {mu:.6})", k.orbit.multiple)));
                }
            }
        }
        for (start, how) in starts {
            let deflate: Vec<Vec<f64>> = known.iter().flat_map(|k| k.points.iter().cloned()).collect();
            let found = Shot { flow: &flow, t0: t_start, m, opts }
                .newton(&start, &deflate)
                .and_then(|f| minimal_period(&flow, f, opts));
            match found {
                Ok(mut f) => {
                    let d = f.orbit.multiple;
                    if known.iter().any(|k| k.orbit.multiple == d && k.points.iter().any(|p| distance(p, &f.orbit.y0) <= 1e-6 * scale(p))) {
                        attempts.push(format!("m={m} from {how}: returned to the known period-{d} orbit"));
                        continue;
                    }
                    f.orbit.found_by = how.clone();
                    if f.orbit.max_multiplier() < 1.0 {
                        return Ok(f.orbit);
                    }
                    attempts.push(format!(
                        "m={m} from {how}: period-{d} orbit (residual {:.2e}) unstable, multipliers [{}]",
                        f.orbit.residual,
                        f.orbit.multipliers.iter().map(|z| format!("{:.6}{:+.6}i", z.re, z.im)).collect::<Vec<_>>().join(", ")
                    ));
                    known.push(f);
                }
                Err(e @ PeriodicError::NonFinite { .. }) if known.is_empty() && m == 1 => return Err(e),
                Err(e) => attempts.push(format!("m={m} from {how}: {e}")),
            }
        }
    }
    Err(PeriodicError::NoStableOrbit { multiples: opts.multiples.clone(), attempts: attempts.join("; ") })
}

/// Relative tolerance of the transient's DOP853 (issue 16: 1e-6 before). The transient only
/// selects the attractor and seeds Newton, which converges to `tol` whatever the seed's error;
/// its end is still e^−1 of the start-up deviation away from the orbit after one decay time,
/// far more than the integration error.
const TRANSIENT_RTOL: f64 = 1e-4;

/// The state after the transient (see the module doc), at a whole number of drive periods.
fn transient(
    sys: &dyn OdeSystem,
    t0: f64,
    y0: &[f64],
    period: f64,
    opts: &ShootingOptions,
) -> Result<(f64, Vec<f64>), PeriodicError> {
    let mut periods = opts.transient_periods;
    if opts.transient_time.is_finite() && opts.transient_time > 0.0 {
        periods = periods.max((opts.transient_time / period).ceil() as usize);
    }
    if periods == 0 {
        return Ok((t0, y0.to_vec()));
    }
    let t_end = t0 + periods as f64 * period;
    let method = Method::Dop853 { rtol: TRANSIENT_RTOL, atol: 1e-3 * TRANSIENT_RTOL };
    let max_steps = 20_000 * periods as u64 + 100_000;
    match integrate::solve(sys, t0, y0, t_end, &method, Output::Steps, max_steps, &mut |_, _| Control::Continue) {
        Ok(sol) => Ok((t_end, sol.y)),
        Err(e) => Err(match e {
            integrate::IntegrateError::NonFinite { t, .. } | integrate::IntegrateError::StepSizeTooSmall { t, .. } => {
                PeriodicError::NonFinite { t }
            }
            other => PeriodicError::Transient { reason: other.to_string() },
        }),
    }
}

/// The real eigenvalue μ < −1 of largest modulus of `jac` and its unit eigenvector, if any.
fn flip_direction(jac: &DMatrix<f64>) -> Option<(f64, Vec<f64>)> {
    let mu = crate::analysis::floquet::eigenvalues(jac)
        .into_iter()
        .filter(|z| z.im.abs() <= 1e-12 * z.norm().max(1.0) && z.re < -1.0)
        .map(|z| z.re)
        .fold(None, |b: Option<f64>, x| Some(b.map_or(x, |b| b.min(x))))?;
    let n = jac.nrows();
    let mut a = jac.clone();
    for i in 0..n {
        a[(i, i)] -= mu;
    }
    let svd = a.svd(false, true);
    let v_t = svd.v_t?;
    let (imin, _) = svd.singular_values.iter().enumerate().fold((0, f64::INFINITY), |b, (i, &s)| if s < b.1 { (i, s) } else { b });
    let v: Vec<f64> = v_t.row(imin).iter().copied().collect();
    let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    (norm > 0.0).then(|| (mu, v.iter().map(|x| x / norm).collect()))
}

/// A fixed point of P_m that closes after a proper divisor d of m is the period-d orbit.
fn minimal_period(flow: &RkFlow, f: Found, opts: &ShootingOptions) -> Result<Found, PeriodicError> {
    let m = f.orbit.multiple;
    for d in (1..m).filter(|d| m % d == 0) {
        let mut z = f.orbit.y0.clone();
        flow.advance(f.orbit.t0, &mut z, d)?;
        if distance(&z, &f.orbit.y0) <= 1e-7 * scale(&f.orbit.y0) {
            return Shot { flow, t0: f.orbit.t0, m: d, opts }.newton(&f.orbit.y0, &[]);
        }
    }
    Ok(f)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Forced Duffing x'' + 0.3x' − x + x³ = γ cos 1.2t: period 2 at γ = 0.28.
    struct Duffing(f64);
    impl OdeSystem for Duffing {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
            dy[0] = y[1];
            dy[1] = -0.3 * y[1] + y[0] - y[0].powi(3) + self.0 * (1.2 * t).cos();
        }
    }

    #[test]
    fn flip_restart_from_the_unstable_orbit() {
        let period = 2.0 * PI / 1.2;
        let opts = ShootingOptions { transient_periods: 0, ..ShootingOptions::default() };
        let flow = RkFlow { sys: &Duffing(0.28), period, steps_per_period: opts.steps_per_period, switching: None };
        // The unstable period-1 orbit (a multiplier < −1) …
        let one = Shot { flow: &flow, t0: 0.0, m: 1, opts: &opts }.newton(&[1.0, 0.0], &[]).unwrap();
        let (mu, v) = flip_direction(&one.jac).expect("a flip multiplier");
        assert!(mu < -1.0 && v.len() == 2);
        // … as the start point: plain Newton on P_2 stays there; the flip restart must leave.
        let orbit = find_orbit(&Duffing(0.28), 0.0, &one.orbit.y0, period, &opts).unwrap();
        assert_eq!(orbit.multiple, 2);
        assert!(orbit.found_by.starts_with("flip restart from the period-1 orbit"), "{}", orbit.found_by);
        assert!(orbit.max_multiplier() < 1.0);
    }
}
