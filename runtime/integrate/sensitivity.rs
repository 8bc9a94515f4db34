//! Forward sensitivities: the state y (n) and its derivatives S_j = ∂y/∂θ_j with respect to p
//! parameters, integrated together (docs/model.md, "Fitting"):
//!
//!   y' = f(t, y),   S_j' = J(t, y) S_j + ∂f/∂θ_j (t, y),   S_j(0) = ∂y0/∂θ_j,
//!
//! J·S the system's product without forming J when it has one
//! ([`OdeSystem::jacobian_product`]), else through J (analytic when it has one, else forward
//! differences as the implicit steppers take it) and ∂f/∂θ_j from a [`ParameterRates`] (the model's: fit/sensitivities.rs).
//! Like [`super::Variational`] this is one system of dimension n·(1 + p) for any
//! [`Method`](super::Method) on the one run loop.
//!
//! **Implicit steppers.** The Newton matrix of the augmented system is block lower triangular
//! with J on every diagonal block; the off-diagonal blocks (∂(J S)/∂y: second derivatives) are
//! dropped, the "simultaneous corrector" of Maly & Petzold (1996): the simplified Newton
//! iteration converges to the same solution (the iteration matrix only changes its rate), and
//! σI − J_aug factors as (1 + p) solves with ONE factorisation of σI − J (the base system's
//! structured one when it has it).
//!
//! **Error control.** Every component is controlled (the sensitivities are as accurate as the
//! state); S_j is scaled by the caller (θ_j = p_j/|p_j|: S_j has the size of y) and takes the
//! state's error weights.

use super::jacobian::FdJacobian;
use super::linalg::{Scalar, ShiftedLu};
use super::linear::{Factorization, StructuredJacobian};
use super::{OdeSystem, Stats};
use nalgebra::Complex;
use std::cell::RefCell;

/// ∂f/∂θ_j of a system: what the parameters do to the right-hand side.
pub trait ParameterRates {
    /// p, the number of parameters.
    fn count(&self) -> usize;
    /// ∂f/∂θ_j at (t, y) into `out` (length n), with f0 = f(t, y) of the base system.
    fn rate(&self, j: usize, t: f64, y: &[f64], f0: &[f64], out: &mut [f64]);
    /// The whole augmented rhs in one pass, when the rates can form it with the system they
    /// belong to (the one given to [`Sensitivity::new`]): f(t, y) into `dy` and
    /// J·S_j + ∂f/∂θ_j into the blocks of `ds`. `false` (the default): not provided, the
    /// caller forms f, J·S and each [`rate`](Self::rate).
    fn augmented_rhs(&self, _t: f64, _y: &[f64], _s: &[f64], _dy: &mut [f64], _ds: &mut [f64]) -> bool {
        false
    }
}

/// The system of dimension n·(1 + p) made of `sys` and its sensitivity equations.
pub struct Sensitivity<'a> {
    sys: &'a dyn OdeSystem,
    rates: &'a dyn ParameterRates,
    n: usize,
    p: usize,
    work: RefCell<Work>,
}

struct Work {
    jac: Vec<f64>,
    dp: Vec<f64>,
    fd: FdJacobian,
    stats: Stats,
}

impl<'a> Sensitivity<'a> {
    pub fn new(sys: &'a dyn OdeSystem, rates: &'a dyn ParameterRates) -> Self {
        let (n, p) = (sys.dim(), rates.count());
        let work = Work { jac: vec![0.0; n * n], dp: vec![0.0; n], fd: FdJacobian::new(n), stats: Stats::default() };
        Sensitivity { sys, rates, n, p, work: RefCell::new(work) }
    }

    /// [y0, S_1(0), …, S_p(0)]: `s0[j]` is ∂y0/∂θ_j.
    pub fn initial_state(&self, y0: &[f64], s0: &[Vec<f64>]) -> Vec<f64> {
        let mut s = Vec::with_capacity(self.n * (1 + self.p));
        s.extend_from_slice(y0);
        for j in 0..self.p {
            s.extend_from_slice(&s0[j]);
        }
        s
    }

    /// S_j from a combined state.
    pub fn block<'s>(&self, state: &'s [f64], j: usize) -> &'s [f64] {
        &state[self.n * (1 + j)..self.n * (2 + j)]
    }

    /// Calls made to the inner system's `rhs` (finite-difference Jacobians included).
    pub fn inner_rhs_evals(&self) -> u64 {
        self.work.borrow().stats.rhs_evals
    }
}

impl OdeSystem for Sensitivity<'_> {
    fn dim(&self) -> usize {
        self.n * (1 + self.p)
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let n = self.n;
        let w = &mut *self.work.borrow_mut();
        let (x, s) = y.split_at(n);
        let (dx, ds) = dy.split_at_mut(n);
        w.stats.rhs_evals += 1;
        if self.rates.augmented_rhs(t, x, s, dx, ds) {
            return;
        }
        self.sys.rhs(t, x, dx);
        // J·S: the system's own product when it has one, else through the (dense) J
        if !self.sys.jacobian_product(t, x, s, ds) {
            w.fd.evaluate(self.sys, t, x, dx, &mut w.jac, &mut w.stats);
            for j in 0..self.p {
                let col = &s[j * n..(j + 1) * n];
                for (r, out) in ds[j * n..(j + 1) * n].iter_mut().enumerate() {
                    let row = &w.jac[r * n..(r + 1) * n];
                    *out = row.iter().zip(col).map(|(a, b)| a * b).sum::<f64>();
                }
            }
        }
        for j in 0..self.p {
            self.rates.rate(j, t, x, dx, &mut w.dp);
            ds[j * n..(j + 1) * n].iter_mut().zip(&w.dp).for_each(|(o, d)| *o += d);
        }
    }

    fn error_scale(&self) -> Option<Vec<f64>> {
        self.sys.error_scale().map(|w| w.iter().copied().cycle().take(self.dim()).collect())
    }

    /// Block diagonal: σI − J on every block (see the module doc).
    fn structured_jacobian(&self, t: f64, y: &[f64]) -> Option<Box<dyn StructuredJacobian>> {
        let n = self.n;
        let x = &y[..n];
        let inner = match self.sys.structured_jacobian(t, x) {
            Some(inner) => Inner::Structured(inner),
            None => {
                let w = &mut *self.work.borrow_mut();
                let mut f0 = vec![0.0; n];
                self.sys.rhs(t, x, &mut f0);
                w.fd.evaluate(self.sys, t, x, &f0, &mut w.jac, &mut w.stats);
                if w.jac.iter().any(|v| !v.is_finite()) {
                    return None;
                }
                Inner::Dense(w.jac.clone())
            }
        };
        Some(Box::new(BlockDiagonal { inner, n, blocks: 1 + self.p }))
    }
}

enum Inner {
    Structured(Box<dyn StructuredJacobian>),
    /// Row-major J of a system without a structured form.
    Dense(Vec<f64>),
}

/// σI − J_aug ≈ diag(σI − J, …, σI − J).
struct BlockDiagonal {
    inner: Inner,
    n: usize,
    blocks: usize,
}

struct Blocks<T> {
    f: Box<dyn Factorization<T>>,
    n: usize,
    blocks: usize,
}

impl<T> Factorization<T> for Blocks<T> {
    fn solve(&self, b: &mut [T]) {
        for k in 0..self.blocks {
            self.f.solve(&mut b[k * self.n..(k + 1) * self.n]);
        }
    }
}

struct Dense<T: Scalar>(ShiftedLu<T>);

impl<T: Scalar> Factorization<T> for Dense<T> {
    fn solve(&self, b: &mut [T]) {
        self.0.solve(b)
    }
}

fn dense<T: Scalar + 'static>(jac: &[f64], n: usize, sigma: T) -> Option<Box<dyn Factorization<T>>> {
    let mut lu = ShiftedLu::<T>::new(n, None);
    lu.factor(sigma, jac, T::from_real).ok()?;
    Some(Box::new(Dense(lu)))
}

impl StructuredJacobian for BlockDiagonal {
    fn rhs_equivalents(&self) -> u64 {
        match &self.inner {
            Inner::Structured(s) => s.rhs_equivalents(),
            Inner::Dense(_) => 1,
        }
    }
    fn factor(&self, sigma: f64) -> Option<Box<dyn Factorization<f64>>> {
        let f = match &self.inner {
            Inner::Structured(s) => s.factor(sigma)?,
            Inner::Dense(j) => dense(j, self.n, sigma)?,
        };
        Some(Box::new(Blocks { f, n: self.n, blocks: self.blocks }))
    }
    fn factor_complex(&self, sigma: Complex<f64>) -> Option<Box<dyn Factorization<Complex<f64>>>> {
        let f = match &self.inner {
            Inner::Structured(s) => s.factor_complex(sigma)?,
            Inner::Dense(j) => dense(j, self.n, sigma)?,
        };
        Some(Box::new(Blocks { f, n: self.n, blocks: self.blocks }))
    }
}
