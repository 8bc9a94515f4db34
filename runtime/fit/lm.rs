//! Levenberg–Marquardt with box bounds (Madsen, Nielsen & Tingleff, *Methods for non-linear
//! least squares problems*, 2004, sec. 3.2: the damping update of Nielsen 1999; Marquardt's
//! diagonal scaling; steps projected onto the bounds).
//!
//! Own code rather than the `levenberg-marquardt` crate (a MINPACK port) or `argmin`: the
//! residuals and the Jacobian here come from different solves (a plain solve for a trial point,
//! one sensitivity solve for the Jacobian only once a step is accepted), a trial point may be
//! infeasible (the model blows up before the data end, or the scene refuses the value) and must
//! count as a rejected step, and the bounds are part of the problem; the MINPACK port has no
//! bounds and asks residuals and Jacobian at the same point through one trait, and argmin's
//! Gauss–Newton/trust-region solvers bring a framework of their own for 100 lines of algebra.

use nalgebra::{DMatrix, DVector};

/// What the optimiser needs of the problem (weighted residuals r_i = (model − data)/σ_i).
pub trait Problem {
    /// The residuals at u; `None`: an infeasible point (a rejected step).
    fn residuals(&mut self, u: &[f64]) -> Option<Vec<f64>>;
    /// The Jacobian ∂r/∂u (rows: residuals) at an accepted u; `None`: could not be formed.
    fn jacobian(&mut self, u: &[f64]) -> Option<DMatrix<f64>>;
    /// Residuals and Jacobian at the start point (`None`: infeasible). Default: both calls; a
    /// problem whose Jacobian solve also gives the residuals overrides it (one solve saved).
    fn residuals_and_jacobian(&mut self, u: &[f64]) -> Option<(Vec<f64>, Option<DMatrix<f64>>)> {
        let r = self.residuals(u)?;
        Some((r, self.jacobian(u)))
    }
    /// Checked between iterations: `true` stops (cancelled).
    fn cancelled(&self) -> bool {
        false
    }
}

/// How the optimisation ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Status {
    Converged,
    MaxIterations,
    Failed(String),
}

/// The end point.
#[derive(Debug, Clone)]
pub struct Outcome {
    pub u: Vec<f64>,
    /// Residuals and Jacobian at `u` (the Jacobian `None` when it failed there).
    pub r: Vec<f64>,
    pub jac: Option<DMatrix<f64>>,
    pub cost: f64,
    pub iterations: usize,
    pub status: Status,
}

/// Settings.
#[derive(Debug, Clone)]
pub struct Options {
    pub max_iterations: usize,
    /// Bounds of u (±∞ when open).
    pub low: Vec<f64>,
    pub high: Vec<f64>,
    /// Converged when a step changes every u_i by less than this (relative to 1 + |u_i|) or
    /// the cost by less than this relative.
    pub tolerance: f64,
    /// Converged when the predicted decrease of the cost is below this many noise variances
    /// s² = 2 cost/(m − p): a step of less than √(2·this) standard errors (the fit uses 5e-5:
    /// 1e-2 standard errors, statistically nothing; on the 100 µs bench it saves one of 6–9
    /// iterations against 1e-3, the values moving by < 0.01 standard errors).
    pub noise_fraction: f64,
    /// Secant steps (Madsen, Nielsen & Tingleff 2004, sec. 3.4): after an accepted step whose
    /// gain ratio ϱ > 1/4, the Jacobian is Broyden's rank-one update
    /// J + (r_new − r − Jδ)δᵀ/(δᵀδ) instead of a new exact one, at most this many times in a
    /// row (0: always exact). The exact Jacobian is formed again after a poor or rejected step
    /// and always before convergence is declared, so the end point and its covariance rest on an
    /// exact Jacobian.
    pub secant_steps: usize,
}

fn cost(r: &[f64]) -> f64 {
    0.5 * r.iter().map(|v| v * v).sum::<f64>()
}

/// Minimises ½‖r(u)‖² from `u0` (inside the bounds).
pub fn minimise(problem: &mut dyn Problem, u0: &[f64], opt: &Options) -> Outcome {
    let p = u0.len();
    let mut u: Vec<f64> = u0.iter().zip(opt.low.iter().zip(&opt.high)).map(|(&v, (&l, &h))| v.clamp(l, h)).collect();
    let fail = |u: Vec<f64>, why: &str, it: usize| Outcome { u, r: Vec::new(), jac: None, cost: f64::INFINITY, iterations: it, status: Status::Failed(why.into()) };
    let Some((mut r, jac)) = problem.residuals_and_jacobian(&u) else { return fail(u, "the model cannot be evaluated at the start values", 0) };
    let Some(mut jac) = jac else { return fail(u, "the sensitivities cannot be formed at the start values", 0) };
    let mut c = cost(&r);
    // Marquardt: the damping multiplies diag(JᵀJ), so λ is dimensionless
    let mut lambda = 1e-3;
    let mut nu = 2.0;
    // secant updates since the last exact Jacobian (0: `jac` is exact at u)
    let mut secant = 0usize;
    for it in 1..=opt.max_iterations {
        if problem.cancelled() {
            return Outcome { u, r, jac: Some(jac), cost: c, iterations: it - 1, status: Status::Failed("cancelled".into()) };
        }
        let a = jac.transpose() * &jac;
        let g = jac.transpose() * DVector::from_column_slice(&r);
        let dmax = (0..p).map(|i| a[(i, i)]).fold(0.0, f64::max);
        // what ends this iteration: a new point, a refreshed Jacobian, or the end
        let mut next = Next::Stuck;
        for _ in 0..40 {
            let mut m = a.clone();
            for i in 0..p {
                m[(i, i)] += lambda * a[(i, i)].max(1e-12 * dmax).max(1e-300);
            }
            let Some(step) = m.cholesky().map(|ch| ch.solve(&(-&g))) else {
                lambda *= nu;
                nu *= 2.0;
                continue;
            };
            let trial: Vec<f64> = (0..p).map(|i| (u[i] + step[i]).clamp(opt.low[i], opt.high[i])).collect();
            let delta = DVector::from_iterator(p, (0..p).map(|i| trial[i] - u[i]));
            let predicted = -(g.dot(&delta)) - 0.5 * delta.dot(&(&a * &delta));
            let s2 = 2.0 * c / (r.len().saturating_sub(p).max(1)) as f64;
            let tiny = (0..p).all(|i| delta[i].abs() <= opt.tolerance * (1.0 + u[i].abs()));
            if tiny || (predicted >= 0.0 && predicted <= opt.noise_fraction * s2 && lambda <= 1.0) {
                next = Next::Converged;
                break;
            }
            let Some(r_new) = problem.residuals(&trial) else {
                lambda *= nu;
                nu *= 2.0;
                continue;
            };
            let c_new = cost(&r_new);
            let actual = c - c_new;
            if actual > 0.0 && predicted > 0.0 {
                let rho = actual / predicted;
                let j_new = if rho > 0.25 && secant < opt.secant_steps {
                    // Broyden: J + (r_new − r − Jδ)δᵀ/(δᵀδ)
                    let y = DVector::from_iterator(r.len(), r_new.iter().zip(&r).map(|(a, b)| a - b)) - &jac * &delta;
                    secant += 1;
                    &jac + y * delta.transpose() / delta.norm_squared()
                } else {
                    let Some(j) = problem.jacobian(&trial) else {
                        lambda *= nu;
                        nu *= 2.0;
                        continue;
                    };
                    secant = 0;
                    j
                };
                u = trial;
                r = r_new;
                jac = j_new;
                lambda *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
                nu = 2.0;
                let small = actual <= opt.tolerance * c;
                c = c_new;
                next = if small { Next::Converged } else { Next::Moved };
                break;
            }
            // no decrease: with a secant Jacobian, form the exact one before damping further
            if secant > 0 {
                next = Next::Refresh;
                break;
            }
            // a step at the level of the solver's noise is convergence
            if predicted >= 0.0 && predicted <= opt.tolerance * c {
                next = Next::Converged;
                break;
            }
            lambda *= nu;
            nu *= 2.0;
        }
        // convergence and failure are only declared on an exact Jacobian
        if secant > 0 && matches!(next, Next::Converged | Next::Stuck | Next::Refresh) {
            match problem.jacobian(&u) {
                Some(j) => {
                    jac = j;
                    secant = 0;
                    continue;
                }
                None => return Outcome { u, r, jac: None, cost: c, iterations: it, status: Status::Failed("the sensitivities cannot be formed at the end point".into()) },
            }
        }
        match next {
            Next::Moved | Next::Refresh => {}
            Next::Converged => return Outcome { u, r, jac: Some(jac), cost: c, iterations: it, status: Status::Converged },
            Next::Stuck => {
                return Outcome {
                    u,
                    r,
                    jac: Some(jac),
                    cost: c,
                    iterations: it,
                    status: Status::Failed(format!("no step reduces the misfit (damping λ = {lambda:e}): a bound, a blow-up or solver noise blocks every direction")),
                }
            }
        }
    }
    if secant > 0 {
        jac = match problem.jacobian(&u) {
            Some(j) => j,
            None => return Outcome { u, r, jac: None, cost: c, iterations: opt.max_iterations, status: Status::Failed("the sensitivities cannot be formed at the end point".into()) },
        };
    }
    Outcome { u, r, jac: Some(jac), cost: c, iterations: opt.max_iterations, status: Status::MaxIterations }
}

/// How one iteration of [`minimise`] ended.
enum Next {
    /// An accepted step.
    Moved,
    /// No decrease with a secant Jacobian: form the exact one and try again.
    Refresh,
    Converged,
    /// No step reduces the misfit.
    Stuck,
}

/// (JᵀJ)⁻¹, `None` when singular.
pub fn covariance(jac: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let a = jac.transpose() * jac;
    // scaled for the conditioning: D⁻¹ (D⁻¹ A D⁻¹)⁻¹ D⁻¹ with D = √diag(A)
    let d: Vec<f64> = (0..a.nrows()).map(|i| a[(i, i)].sqrt()).collect();
    if d.iter().any(|&v| !(v > 0.0 && v.is_finite())) {
        return None;
    }
    let s = DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)] / (d[i] * d[j]));
    let inv = s.try_inverse()?;
    Some(DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| inv[(i, j)] / (d[i] * d[j])))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// r_i = u0 e^{u1 x_i} − d_i on 40 points, d from (2, −1.5) with a deterministic
    /// perturbation; counts the exact Jacobians formed.
    struct Exponential {
        x: Vec<f64>,
        d: Vec<f64>,
        jacobians: usize,
    }

    impl Exponential {
        fn new() -> Self {
            let x: Vec<f64> = (0..40).map(|i| i as f64 / 20.0).collect();
            let d = x.iter().enumerate().map(|(i, &x)| 2.0 * (-1.5 * x).exp() + 1e-3 * ((i * 7 % 11) as f64 - 5.0)).collect();
            Exponential { x, d, jacobians: 0 }
        }
        fn exact(&self, u: &[f64]) -> DMatrix<f64> {
            DMatrix::from_fn(self.x.len(), 2, |i, j| if j == 0 { (u[1] * self.x[i]).exp() } else { u[0] * self.x[i] * (u[1] * self.x[i]).exp() })
        }
    }

    impl Problem for Exponential {
        fn residuals(&mut self, u: &[f64]) -> Option<Vec<f64>> {
            Some(self.x.iter().zip(&self.d).map(|(&x, &d)| u[0] * (u[1] * x).exp() - d).collect())
        }
        fn jacobian(&mut self, u: &[f64]) -> Option<DMatrix<f64>> {
            self.jacobians += 1;
            Some(self.exact(u))
        }
    }

    fn options(secant_steps: usize) -> Options {
        Options { max_iterations: 200, low: vec![f64::NEG_INFINITY; 2], high: vec![f64::INFINITY; 2], tolerance: 1e-12, noise_fraction: 0.0, secant_steps }
    }

    #[test]
    fn secant_steps_reach_the_exact_minimum_with_fewer_jacobians_and_end_on_an_exact_one() {
        let (mut exact, mut secant) = (Exponential::new(), Exponential::new());
        let a = minimise(&mut exact, &[1.0, -0.5], &options(0));
        let b = minimise(&mut secant, &[1.0, -0.5], &options(3));
        assert_eq!((&a.status, &b.status), (&Status::Converged, &Status::Converged));
        for j in 0..2 {
            assert!((a.u[j] - b.u[j]).abs() <= 1e-8 * a.u[j].abs(), "u{j}: exact {} vs secant {}", a.u[j], b.u[j]);
        }
        // the reported Jacobian (the covariance's) is the exact one at the end point
        assert_eq!(b.jac.as_ref().unwrap(), &secant.exact(&b.u));
        assert!(secant.jacobians < exact.jacobians, "secant {} vs exact {} Jacobians", secant.jacobians, exact.jacobians);
    }
}
