//! Newton on the period map (step 2 of the parent module's search): a coarse phase on a quarter
//! of the RK4 steps, one chord step onto the fine map, Newton with the exact derivative of the
//! discrete map, deflation of known orbits and step halving.

use super::{distance, scale, Found, PeriodicOrbit, ShootingOptions};
use crate::analysis::periodic::{PeriodicError, RkFlow, Switch};
use nalgebra::{DMatrix, DVector};

/// Residual tolerance of the coarse phase of [`Shot::newton`] (relative, as `ShootingOptions::tol`).
const COARSE_TOL: f64 = 1e-7;
/// The coarse phase needs at least this many RK4 steps per drive period.
const COARSE_MIN_STEPS: usize = 50;

/// One orbit search's fixed data: the flow, the start time t0, the period multiple m and the
/// options (what every phase of the Newton search shares).
#[derive(Clone, Copy)]
pub(super) struct Shot<'f, 'a> {
    pub(super) flow: &'f RkFlow<'a>,
    pub(super) t0: f64,
    pub(super) m: usize,
    pub(super) opts: &'f ShootingOptions,
}

impl Shot<'_, '_> {
    /// Newton on G(y) = P_m(y) − y (see [`Shot::newton_on`]); without deflation it first converges on
    /// the map of a quarter of the RK4 steps (each iteration a quarter of the cost) to
    /// [`COARSE_TOL`], whose fixed point lies within the RK4 error of the fine one, so the fine
    /// Newton needs one or two iterations from there (issue 16). The result is the fine map's fixed
    /// point to `opts.tol` either way; where either phase fails, the fine Newton runs from the
    /// original start. With
    /// known orbits deflated the coarse phase is skipped: the coarse image of a deflated orbit is
    /// not itself deflated.
    pub(super) fn newton(&self, y_start: &[f64], deflate: &[Vec<f64>]) -> Result<Found, PeriodicError> {
        let flow = self.flow;
        let coarse_steps = flow.steps_per_period / 4;
        if !deflate.is_empty() || coarse_steps < COARSE_MIN_STEPS {
            return self.newton_on(y_start, deflate);
        }
        let coarse = RkFlow { steps_per_period: coarse_steps, ..*flow };
        let coarse_opts = ShootingOptions { tol: self.opts.tol.max(COARSE_TOL), ..self.opts.clone() };
        match (Shot { flow: &coarse, opts: &coarse_opts, ..*self }).newton_on(y_start, deflate) {
            Ok(f) => self.chord_then_newton(&f).or_else(|_| self.newton_on(y_start, deflate)),
            Err(_) => self.newton_on(y_start, deflate),
        }
    }

    /// The fine phase of [`Shot::newton`] from the coarse fixed point y_c: one chord step
    /// y₁ = y_c + (J_c − I)⁻¹ (y_c − P_m(y_c)) with the coarse map's Jacobian J_c (P_m here the fine
    /// map, evaluated without its derivative), then Newton on the fine map from y₁, whose first
    /// (variational) evaluation usually meets `opts.tol` already: |y₁ − y*| ≈ ‖J_f − J_c‖·|y_c − y*|,
    /// both factors of the order of the coarse map's RK4 error (issue 16: the fine Newton evaluated
    /// the variational map twice, the second time only to verify the residual). The multipliers are
    /// those of the fine map at the converged point, as before; the chord step counts as an iteration.
    fn chord_then_newton(&self, coarse: &Found) -> Result<Found, PeriodicError> {
        let Shot { flow, t0, m, .. } = *self;
        let yc = &coarse.orbit.y0;
        let n = yc.len();
        let mut p = yc.clone();
        flow.advance(t0, &mut p, m)?;
        let mut a = coarse.jac.clone();
        for i in 0..n {
            a[(i, i)] -= 1.0;
        }
        let g = DVector::from_iterator(n, yc.iter().zip(&p).map(|(yi, pi)| yi - pi));
        let delta = a.lu().solve(&g).ok_or(PeriodicError::SingularShooting { multiple: m })?;
        let y1: Vec<f64> = yc.iter().zip(delta.iter()).map(|(a, d)| a + d).collect();
        let mut f = self.newton_on(&y1, &[])?;
        f.orbit.newton_iterations += 1;
        Ok(f)
    }

    /// Newton on G(y) = P_m(y) − y with the exact DP_m, the known fixed points `deflate` deflated,
    /// and step halving on the (deflated) residual.
    fn newton_on(&self, y_start: &[f64], deflate: &[Vec<f64>]) -> Result<Found, PeriodicError> {
        let Shot { flow, t0, m, opts } = *self;
        let n = y_start.len();
        // P_m(y), DP_m(y) and the grid of the evaluation ([`PeriodicOrbit::grid`])
        // (and the branch at t0 and the switches, on a kinked law)
        type Eval = (Vec<f64>, DMatrix<f64>, (Vec<f64>, u8, Vec<Switch>));
        let eval = |y: &[f64]| -> Result<Eval, PeriodicError> {
            let mut z = y.to_vec();
            let mut phi = DMatrix::identity(n, n);
            let mut grid = Vec::with_capacity(2 * n * (m * flow.steps_per_period + 1));
            let mut record = |_: f64, y: &[f64], f: &[f64]| {
                grid.extend_from_slice(y);
                grid.extend_from_slice(f);
            };
            let mut switches = Vec::new();
            let mut start = 0;
            if let Some(sw) = flow.switching {
                // the branch the flow enters at t0 (Switching::enter), read back as its code
                let saved = sw.branch();
                sw.enter(t0, y);
                start = sw.branch();
                sw.set_branch(saved);
            }
            flow.advance_variational_observed(t0, &mut z, &mut phi, m, Some(&mut record), Some(&mut switches))?;
            Ok((z, phi, (grid, start, switches)))
        };
        // η(y) = Π (1/d_i² + 1), d_i = ‖y − y_i‖₂ / scale; the merit is η‖G‖∞.
        let d2 = |y: &[f64], yi: &[f64]| {
            let s = scale(yi);
            y.iter().zip(yi).map(|(a, b)| ((a - b) / s).powi(2)).sum::<f64>()
        };
        let eta = |y: &[f64]| deflate.iter().map(|yi| 1.0 / d2(y, yi) + 1.0).product::<f64>();
        let mut y = y_start.to_vec();
        let (mut p, mut jac, mut grid) = eval(&y)?;
        let mut r = distance(&y, &p);
        let mut iterations = 0;
        loop {
            if r <= opts.tol * scale(&y) {
                let points = (0..m.max(1))
                    .scan(y.clone(), |z, j| {
                        let here = z.clone();
                        if j + 1 < m {
                            flow.advance(t0, z, 1).ok()?;
                        }
                        Some(here)
                    })
                    .collect();
                let multipliers = crate::analysis::floquet::eigenvalues(&jac);
                let orbit = PeriodicOrbit {
                    t0,
                    y0: y,
                    drive_period: flow.period,
                    multiple: m,
                    newton_iterations: iterations,
                    residual: r,
                    multipliers,
                    found_by: String::new(),
                    grid: grid.0,
                    start_branch: grid.1,
                    switches: grid.2,
                };
                return Ok(Found { orbit, jac, points });
            }
            if iterations >= opts.max_iterations {
                return Err(PeriodicError::NotConverged { multiple: m, iterations, residual: r });
            }
            iterations += 1;
            let mut a = jac.clone();
            for i in 0..n {
                a[(i, i)] -= 1.0;
            }
            let g = DVector::from_iterator(n, y.iter().zip(&p).map(|(yi, pi)| yi - pi));
            let Some(delta) = a.lu().solve(&g) else {
                return Err(PeriodicError::SingularShooting { multiple: m });
            };
            // Deflated step δ = τ δ0, τ = 1 / (1 − ∇ln η · δ0) (Farrell et al. 2015, eq. 3.7).
            let grad_dot: f64 = deflate
                .iter()
                .map(|yi| {
                    let s = scale(yi);
                    let dd = d2(&y, yi);
                    let dot: f64 = y.iter().zip(yi).zip(delta.iter()).map(|((a, b), d)| (a - b) / (s * s) * d).sum();
                    -2.0 * dot / (dd * (1.0 + dd))
                })
                .sum();
            let tau = 1.0 / (1.0 - grad_dot);
            let tau = if tau.is_finite() { tau } else { 1.0 };
            let merit = eta(&y) * r;
            let mut lambda = 1.0;
            loop {
                let trial: Vec<f64> = y.iter().zip(delta.iter()).map(|(a, d)| a + lambda * tau * d).collect();
                let last = lambda < 1.0 / 64.0;
                match eval(&trial) {
                    Ok((pt, jt, gt)) => {
                        let rt = distance(&trial, &pt);
                        if eta(&trial) * rt < merit || last {
                            (y, p, jac, r, grid) = (trial, pt, jt, rt, gt);
                            break;
                        }
                    }
                    Err(e) if last => return Err(e),
                    Err(_) => {}
                }
                lambda *= 0.5;
            }
        }
    }
}
