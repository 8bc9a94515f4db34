//! The Jacobian ∂f/∂y for the implicit method: analytic when the system provides it, otherwise
//! forward differences (Hairer's RADAU5: δ_j = sqrt(u · max(1e−5, |y_j|)), u the unit round-off).
//! With `OdeSystem::bandwidth() = Some((ml, mu))` the columns j ≡ g (mod ml + mu + 1) are
//! perturbed together (Curtis–Powell–Reid grouping): ml + mu + 1 rhs calls instead of n.

use super::{OdeSystem, Stats};

/// Workspace of the finite-difference Jacobian.
#[derive(Debug, Clone)]
pub(crate) struct FdJacobian {
    y_pert: Vec<f64>,
    f_pert: Vec<f64>,
    delta: Vec<f64>,
}

impl FdJacobian {
    pub(crate) fn new(n: usize) -> Self {
        FdJacobian { y_pert: vec![0.0; n], f_pert: vec![0.0; n], delta: vec![0.0; n] }
    }

    /// Fills the row-major `jac` at (t, y) given f0 = f(t, y). Entries outside the band are
    /// set to zero in the banded case. Counts rhs calls and one Jacobian evaluation in `stats`.
    pub(crate) fn evaluate(&mut self, sys: &dyn OdeSystem, t: f64, y: &[f64], f0: &[f64], jac: &mut [f64], stats: &mut Stats) {
        stats.jac_evals += 1;
        if sys.jacobian(t, y, jac) {
            return;
        }
        let n = y.len();
        let band = sys.bandwidth().filter(|&(ml, mu)| ml + mu + 1 < n);
        for j in 0..n {
            self.delta[j] = (f64::EPSILON * y[j].abs().max(1e-5)).sqrt();
        }
        match band {
            None => {
                self.y_pert.copy_from_slice(y);
                for j in 0..n {
                    let d = self.delta[j];
                    self.y_pert[j] = y[j] + d;
                    // The exact increment (y + d) − y, so the quotient divides by what was added.
                    let d = self.y_pert[j] - y[j];
                    sys.rhs(t, &self.y_pert, &mut self.f_pert);
                    stats.rhs_evals += 1;
                    for i in 0..n {
                        jac[i * n + j] = (self.f_pert[i] - f0[i]) / d;
                    }
                    self.y_pert[j] = y[j];
                }
            }
            Some((ml, mu)) => {
                jac.iter_mut().for_each(|v| *v = 0.0);
                let groups = ml + mu + 1;
                for g in 0..groups {
                    self.y_pert.copy_from_slice(y);
                    for j in (g..n).step_by(groups) {
                        self.y_pert[j] = y[j] + self.delta[j];
                    }
                    sys.rhs(t, &self.y_pert, &mut self.f_pert);
                    stats.rhs_evals += 1;
                    for j in (g..n).step_by(groups) {
                        let d = self.y_pert[j] - y[j];
                        // Column j is non-zero on rows j − mu ..= j + ml.
                        for i in j.saturating_sub(mu)..=(j + ml).min(n - 1) {
                            jac[i * n + j] = (self.f_pert[i] - f0[i]) / d;
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// f_i = −2 y_i² + y_{i−1} + 3 y_{i+1}³ : tridiagonal (ml = mu = 1).
    struct Tri(bool);
    impl OdeSystem for Tri {
        fn dim(&self) -> usize {
            9
        }
        fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
            let n = y.len();
            for i in 0..n {
                let l = if i > 0 { y[i - 1] } else { 0.0 };
                let r = if i + 1 < n { y[i + 1] } else { 0.0 };
                dy[i] = -2.0 * y[i] * y[i] + l + 3.0 * r * r * r;
            }
        }
        fn bandwidth(&self) -> Option<(usize, usize)> {
            self.0.then_some((1, 1))
        }
    }

    #[test]
    fn banded_grouping_matches_dense_with_fewer_calls() {
        let y: Vec<f64> = (0..9).map(|i| 0.5 + 0.1 * i as f64).collect();
        let mut f0 = vec![0.0; 9];
        Tri(false).rhs(0.0, &y, &mut f0);
        let (mut jd, mut jb) = (vec![0.0; 81], vec![0.0; 81]);
        let (mut sd, mut sb) = (Stats::default(), Stats::default());
        FdJacobian::new(9).evaluate(&Tri(false), 0.0, &y, &f0, &mut jd, &mut sd);
        FdJacobian::new(9).evaluate(&Tri(true), 0.0, &y, &f0, &mut jb, &mut sb);
        assert_eq!(sd.rhs_evals, 9);
        assert_eq!(sb.rhs_evals, 3);
        for i in 0..9 {
            for j in 0..9 {
                let exact = if i == j {
                    -4.0 * y[i]
                } else if j + 1 == i {
                    1.0
                } else if j == i + 1 {
                    9.0 * y[j] * y[j]
                } else {
                    0.0
                };
                assert!((jd[i * 9 + j] - exact).abs() < 1e-6 * (1.0 + exact.abs()), "dense ({i},{j})");
                assert!((jb[i * 9 + j] - exact).abs() < 1e-6 * (1.0 + exact.abs()), "band ({i},{j})");
            }
        }
    }
}
