//! Integrators, separate from the equations: every stepper sees only [`OdeSystem`].

/// An explicit first-order ODE y' = f(t, y) of fixed dimension.
///
/// The model (`model::BubbleSystem`) and the test problems implement this; the steppers
/// (RK4, Dormand–Prince, Radau IIA) depend on nothing else.
pub trait OdeSystem {
    /// Dimension of the state.
    fn dim(&self) -> usize;
    /// Writes f(t, y) into `dy` (`dy.len() == y.len() == self.dim()`).
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]);
    /// Lower and upper bandwidth of ∂f/∂y when it is banded after the ordering of the state
    /// (used by implicit methods to build a finite-difference Jacobian with fewer evaluations
    /// and to factor it as a band). `None`: dense.
    fn bandwidth(&self) -> Option<(usize, usize)> {
        None
    }
    /// Optional analytic Jacobian, row-major `jac[i * n + j] = ∂f_i/∂y_j`.
    /// Returns `false` when not provided (the integrator then differences `rhs`).
    fn jacobian(&self, _t: f64, _y: &[f64], _jac: &mut [f64]) -> bool {
        false
    }
}
