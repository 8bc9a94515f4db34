//! Variational equations for Floquet analysis: the state y (n) and the fundamental matrix Φ
//! (n×n, column-major) integrated together, y' = f(t, y), Φ' = J(t, y) Φ, Φ(t0) = I. After one
//! period Φ is the monodromy matrix. One integration with any [`Method`](super::Method) gives
//! all n columns at the cost of one Jacobian (analytic, or n + 1 rhs calls, fewer when banded)
//! per right-hand side of the big system.

use super::jacobian::FdJacobian;
use super::{OdeSystem, Stats};
use std::cell::RefCell;

/// The system of dimension n·(n+1) made of `sys` and its variational equations.
pub struct Variational<'a> {
    sys: &'a dyn OdeSystem,
    n: usize,
    work: RefCell<Work>,
}

struct Work {
    jac: Vec<f64>,
    f0: Vec<f64>,
    fd: FdJacobian,
    stats: Stats,
}

impl<'a> Variational<'a> {
    pub fn new(sys: &'a dyn OdeSystem) -> Self {
        let n = sys.dim();
        Variational { sys, n, work: RefCell::new(Work { jac: vec![0.0; n * n], f0: vec![0.0; n], fd: FdJacobian::new(n), stats: Stats::default() }) }
    }

    /// [y0, vec(I)]: the initial state of the combined system.
    pub fn initial_state(&self, y0: &[f64]) -> Vec<f64> {
        let n = self.n;
        let mut s = vec![0.0; n * (n + 1)];
        s[..n].copy_from_slice(y0);
        for c in 0..n {
            s[n + c * n + c] = 1.0;
        }
        s
    }

    /// Φ from a combined state, column-major: `phi[c * n + r] = Φ_rc`.
    pub fn fundamental<'s>(&self, state: &'s [f64]) -> &'s [f64] {
        &state[self.n..]
    }

    /// Calls made to the inner system's `rhs` (including finite-difference Jacobians).
    pub fn inner_rhs_evals(&self) -> u64 {
        self.work.borrow().stats.rhs_evals
    }
}

impl OdeSystem for Variational<'_> {
    fn dim(&self) -> usize {
        self.n * (self.n + 1)
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let n = self.n;
        let w = &mut *self.work.borrow_mut();
        let (x, phi) = y.split_at(n);
        let (dx, dphi) = dy.split_at_mut(n);
        self.sys.rhs(t, x, dx);
        w.stats.rhs_evals += 1;
        w.f0.copy_from_slice(dx);
        w.fd.evaluate(self.sys, t, x, &w.f0, &mut w.jac, &mut w.stats);
        for c in 0..n {
            let col = &phi[c * n..(c + 1) * n];
            for r in 0..n {
                let row = &w.jac[r * n..(r + 1) * n];
                dphi[c * n + r] = row.iter().zip(col).map(|(a, b)| a * b).sum();
            }
        }
    }
}
