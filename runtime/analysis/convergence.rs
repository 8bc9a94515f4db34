//! Time-step convergence of the staggered full model (paper §5.1, fig 3, eq 5.4):
//!
//! e_s = max_k ‖a_k(t′) − ā_k(t′)‖₂ / ‖ā_k(t′)‖₂,   e_f = max_k ‖T_k(t_end) − T̄_k(t_end)‖₂ / ‖T̄_k(t_end)‖₂
//!
//! against a reference run with a fine step (paper: 100 µs, Δt′ = 1.7·10⁻⁴). The time series are
//! compared at common sample times (multiples of the coarsest step; every step of the ladder is
//! an integer multiple of the reference step so the samples coincide exactly), the vorticity on
//! the grid nodes at the end. The observed orders are least-squares slopes of log e against log Δt.
//!
//! The runs count steps of the staggered scheme directly (not the run loop,
//! [`crate::integrate::run_loop`]): every rung must stay on exact multiples of the reference
//! step, and the scheme's own `step` keeps Δt unshortened where the loop's landing on `t_stop`
//! could cut a step by rounding.

use crate::model::vorticity::staggered::Staggered;
use crate::model::vorticity::{FullState, Grid, ModeCoupling, VorticityError};
use serde::Serialize;

/// One rung of the ladder.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ConvergenceRow {
    /// Step in the coupling's time unit.
    pub dt: f64,
    pub e_s: f64,
    pub e_f: f64,
    /// Shape mode with the largest e_s.
    pub worst_k_s: usize,
    /// Wall-clock seconds of this run.
    pub seconds: f64,
    /// Steps of the staggered scheme: the run's work, a count that does not vary between runs.
    pub steps: u64,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConvergenceReport {
    pub reference_dt: f64,
    pub rows: Vec<ConvergenceRow>,
    /// Observed orders (slopes); `None` with fewer than two finite positive errors.
    pub order_s: Option<f64>,
    pub order_f: Option<f64>,
}

/// a_k at the sample times and T_k at the end of one staggered run.
struct RunRecord {
    a: Vec<Vec<f64>>,
    t_end: Vec<Vec<f64>>,
    seconds: f64,
}

fn record(
    c: &dyn ModeCoupling,
    grid: &Grid,
    init: &FullState,
    dt: f64,
    steps: u64,
    sample_every: u64,
) -> Result<RunRecord, VorticityError> {
    let start = std::time::Instant::now();
    let mut st = Staggered::new(c, grid.clone(), dt)?;
    let mut s = init.clone();
    let m = s.a.len();
    let mut a = vec![vec![]; m];
    for n in 1..=steps {
        st.step(&mut s)?;
        if n % sample_every == 0 {
            for (mi, v) in a.iter_mut().enumerate() {
                v.push(s.a[mi]);
            }
        }
    }
    Ok(RunRecord { a, t_end: s.t_nodes.clone(), seconds: start.elapsed().as_secs_f64() })
}

fn rel_l2(x: &[f64], r: &[f64]) -> f64 {
    let num: f64 = x.iter().zip(r).map(|(a, b)| (a - b) * (a - b)).sum();
    let den: f64 = r.iter().map(|b| b * b).sum();
    if den == 0.0 {
        if num == 0.0 { 0.0 } else { f64::INFINITY }
    } else {
        (num / den).sqrt()
    }
}

/// Least-squares slope of log e against log dt over the finite, positive errors ([`log_slope`]).
pub fn observed_order(dt: &[f64], e: &[f64]) -> Option<f64> {
    log_slope(dt, e)
}

/// Least-squares slope of log y against log x over finite positive points (`None` with < 2).
pub fn log_slope(x: &[f64], y: &[f64]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = x
        .iter()
        .zip(y)
        .filter(|(x, y)| x.is_finite() && y.is_finite() && **x > 0.0 && **y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// Runs the reference (step `reference_dt`) and every `multiples[i] · reference_dt` up to
/// `t_end` from `init`, and measures e_s, e_f. `t_end` is rounded down to a multiple of the
/// coarsest step. A rung that fails (unstable) gets infinite errors and is left out of the fit.
pub fn convergence_study(
    c: &dyn ModeCoupling,
    grid: &Grid,
    init: &FullState,
    t_end: f64,
    reference_dt: f64,
    multiples: &[u64],
) -> Result<ConvergenceReport, VorticityError> {
    let coarsest = multiples.iter().copied().max().unwrap_or(1).max(1);
    let ref_steps_total = ((t_end / reference_dt) as u64 / coarsest) * coarsest;
    let reference = record(c, grid, init, reference_dt, ref_steps_total, coarsest)?;
    let mut rows = vec![];
    for &mult in multiples {
        let dt = reference_dt * mult as f64;
        let steps = ref_steps_total / mult;
        let run = record(c, grid, init, dt, steps, coarsest / mult);
        let row = match run {
            Ok(run) => {
                let (mut e_s, mut worst) = (0.0f64, 0usize);
                for (mi, k) in c.orders().iter().enumerate() {
                    let e = rel_l2(&run.a[mi], &reference.a[mi]);
                    if e > e_s || e.is_nan() {
                        e_s = e;
                        worst = *k;
                    }
                }
                let e_f = (0..c.orders().len())
                    .map(|mi| rel_l2(&run.t_end[mi], &reference.t_end[mi]))
                    .fold(0.0f64, f64::max);
                ConvergenceRow { dt, e_s, e_f, worst_k_s: worst, seconds: run.seconds, steps }
            }
            Err(_) => ConvergenceRow { dt, e_s: f64::INFINITY, e_f: f64::INFINITY, worst_k_s: 0, seconds: f64::NAN, steps },
        };
        rows.push(row);
    }
    let dts: Vec<f64> = rows.iter().map(|r| r.dt).collect();
    let order_s = observed_order(&dts, &rows.iter().map(|r| r.e_s).collect::<Vec<_>>());
    let order_f = observed_order(&dts, &rows.iter().map(|r| r.e_f).collect::<Vec<_>>());
    Ok(ConvergenceReport { reference_dt, rows, order_s, order_f })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn order_of_a_power_law_is_its_exponent() {
        let dt = [1.0, 0.5, 0.25];
        let e: Vec<f64> = dt.iter().map(|d: &f64| 3.0 * d.powf(1.7)).collect();
        assert!((observed_order(&dt, &e).unwrap() - 1.7).abs() < 1e-12);
        assert_eq!(observed_order(&[1.0], &[1.0]), None);
    }
}
