//! Integrators, separate from the equations: every stepper sees only [`OdeSystem`].
//!
//! - [`Method::Rk4`]: classical fixed-step RK4 (the paper's scheme, sec. 4).
//! - [`Method::Dopri5`], [`Method::Dop853`]: adaptive explicit Runge–Kutta (Dormand–Prince 5(4)
//!   and Hairer's 8(5,3)), tableaus as data in [`tableau`].
//! - [`Method::Radau5`]: Radau IIA, 3 stages, order 5 (Hairer's RADAU5 scheme) for the stiff
//!   boundary-layer and vorticity systems (docs/model.md §4.3, audit item 12).
//! - [`Method::Rosenbrock23`]: Shampine & Reichelt's ode23s pair, linearly implicit.
//!
//! [`run_loop::run`] is the one integration loop every stepper runs in (budget, sampling,
//! observers, stop times, events, typed stop reasons); [`solve`] / [`drive`] are that loop with
//! sampling and a budget only; [`Stepper`] gives one step at a time (with `restart` and the
//! dense output);
//! [`rk4_step`] is a bare RK4 step for the staggered scheme; [`Variational`] turns a system into
//! its variational equations (state and fundamental matrix) for Floquet analysis.
//! See `docs/integrators.md` for the choices and the measurements.

/// The four state accessors of a [`Stepper`] (`t`, `y`, `t_prev`, `stats`) for a stepper that
/// keeps them in fields of those names; `stepper_state!(s.t)` reads the time from another field.
macro_rules! stepper_state {
    () => {
        stepper_state!(t);
    };
    ($($time:ident).+) => {
        fn t(&self) -> f64 {
            self.$($time).+
        }
        fn y(&self) -> &[f64] {
            &self.y
        }
        fn t_prev(&self) -> f64 {
            self.t_prev
        }
        fn stats(&self) -> $crate::integrate::Stats {
            self.stats
        }
    };
}
pub(crate) use stepper_state;

pub mod bordered;
mod control;
mod dop853_dense;
mod driver;
mod explicit;
mod jacobian;
pub(crate) use jacobian::FdJacobian;
mod linalg;
pub(crate) use linalg::pivot_row;
pub mod linear;
mod radau;
mod rosenbrock;
pub mod reduced;
pub mod run_loop;
mod split_lu;
pub mod tableau;
mod variational;
pub mod sensitivity;

pub use driver::{drive, solve, stepper, Stepper};
pub use explicit::{rk4_step, ExplicitRk, Rk4, Rk4Workspace};
pub(crate) use explicit::hermite;
pub use radau::Radau5;
pub use rosenbrock::Rosenbrock23;
pub use variational::Variational;

use serde::Serialize;

/// An explicit first-order ODE y' = f(t, y) of fixed dimension.
///
/// The model (`model::boundary_layer::BoundaryLayerSystem`, the monolithic vorticity system) and
/// the test problems implement this; the steppers (RK4, Dormand–Prince 5 and 8, Radau IIA,
/// Rosenbrock 2(3)) depend on nothing else.
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
    /// Optional product J·S with p directions at once (`s`, `out`: p blocks of length n)
    /// without forming J, exact as [`OdeSystem::jacobian`] (the forward sensitivities'
    /// product, [`sensitivity`]). Returns `false` when not provided (J is formed instead).
    fn jacobian_product(&self, _t: f64, _y: &[f64], _s: &[f64], _out: &mut [f64]) -> bool {
        false
    }
    /// Optional structured Jacobian at (t, y) with its own solve of σI − J (the linear-solver
    /// hook of the implicit steppers, [`linear`]). `None` (the default): the steppers use
    /// [`OdeSystem::jacobian`] or finite differences and a dense or banded LU.
    fn structured_jacobian(&self, _t: f64, _y: &[f64]) -> Option<Box<dyn linear::StructuredJacobian>> {
        None
    }
    /// Per-component weights w_i of the absolute tolerance: the adaptive steppers measure the
    /// error of component i against atol·w_i + rtol·|y_i| (docs/integrators.md, "Error
    /// weights"). A weight says how large the component naturally is relative to the
    /// nondimensional unit, so that atol means the same thing for every component. `None` (the
    /// default): w_i = 1.
    fn error_scale(&self) -> Option<Vec<f64>> {
        None
    }
}

/// The absolute tolerance of every component: atol·w_i with the system's
/// [`OdeSystem::error_scale`] w (all 1 without one).
pub(crate) fn atol_vector(sys: &dyn OdeSystem, atol: f64, n: usize) -> Vec<f64> {
    match sys.error_scale() {
        Some(w) => {
            assert_eq!(w.len(), n, "error_scale has one weight per component");
            w.iter().map(|w| atol * w).collect()
        }
        None => vec![atol; n],
    }
}

/// Which integrator, with its settings (in the model's nondimensional time).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Method {
    /// Classical RK4 with fixed step `dt` (the last step is shortened to land on `t_end`).
    Rk4 { dt: f64 },
    /// Dormand–Prince 5(4), PI step control, 4th-order dense output.
    Dopri5 { rtol: f64, atol: f64 },
    /// Dormand–Prince 8(5,3) (Hairer's DOP853 error estimator), its 7th-order dense output.
    Dop853 { rtol: f64, atol: f64 },
    /// Radau IIA order 5, simplified Newton; J analytic, structured or finite-difference.
    Radau5 { rtol: f64, atol: f64 },
    /// Rosenbrock ode23s (Shampine & Reichelt 1997), order 2(3), linearly implicit.
    Rosenbrock23 { rtol: f64, atol: f64 },
}

impl Method {
    /// Short name ("rk4", "dopri5", "dop853", "radau5", "rosenbrock23").
    pub fn name(&self) -> &'static str {
        match self {
            Method::Rk4 { .. } => "rk4",
            Method::Dopri5 { .. } => "dopri5",
            Method::Dop853 { .. } => "dop853",
            Method::Radau5 { .. } => "radau5",
            Method::Rosenbrock23 { .. } => "rosenbrock23",
        }
    }

    /// Checks the settings: `dt`, `rtol` > 0 and finite, `atol` ≥ 0 and finite.
    pub fn validate(&self) -> Result<(), IntegrateError> {
        let bad = |what: &'static str, value: f64, reason: &'static str| {
            Err(IntegrateError::InvalidSetting { what, value, reason })
        };
        match *self {
            Method::Rk4 { dt } if !(dt > 0.0 && dt.is_finite()) => bad("dt", dt, "must be positive and finite"),
            Method::Dopri5 { rtol, atol }
            | Method::Dop853 { rtol, atol }
            | Method::Radau5 { rtol, atol }
            | Method::Rosenbrock23 { rtol, atol } => {
                if !(rtol > 0.0 && rtol.is_finite()) {
                    bad("rtol", rtol, "must be positive and finite")
                } else if !(atol >= 0.0 && atol.is_finite()) {
                    bad("atol", atol, "must be non-negative and finite")
                } else {
                    Ok(())
                }
            }
            _ => Ok(()),
        }
    }
}

/// What an observer asks of the driver.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    Continue,
    Stop,
}

/// When the driver calls the observer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Output {
    /// At t0 and after every accepted step.
    Steps,
    /// At t0 + i·Δ (dense output, not a step constraint) and at t_end.
    Every(f64),
    /// At t0 + i·Δ and t_end, every step ending no later than the next sample (for schemes
    /// without a dense output of their order, e.g. the staggered vorticity scheme).
    Landing(f64),
}

/// Cost counters of a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct Stats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected attempts (error test failed, Newton failed or a non-finite stage).
    pub rejected: u64,
    /// Calls to `OdeSystem::rhs` made by the integrator (including finite-difference Jacobians).
    pub rhs_evals: u64,
    /// Jacobian evaluations (analytic or finite-difference).
    pub jac_evals: u64,
    /// LU factorisations (Radau5: one real + one complex matrix count as one, as in RADAU5's NDEC).
    pub lu_decompositions: u64,
}

/// End state of [`solve`].
#[derive(Debug, Clone)]
pub struct Solution {
    /// Time of `y`: `t_end`, or the time the observer stopped the run.
    pub t: f64,
    pub y: Vec<f64>,
    pub stats: Stats,
    /// `true` when the observer returned [`Control::Stop`].
    pub stopped: bool,
}

/// Why an integration failed. Every variant carries the time it happened.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IntegrateError {
    #[error("step size too small at t = {t:e}: h = {h:e} (the solution may blow up or the problem is too stiff for this method)")]
    StepSizeTooSmall { t: f64, h: f64 },
    #[error("maximum number of steps ({steps}) reached at t = {t:e}")]
    MaxSteps { t: f64, steps: u64 },
    #[error("non-finite value (NaN or Inf) in component {component} of the state or right-hand side at t = {t:e}")]
    NonFinite { t: f64, component: usize },
    #[error("Newton iteration of the implicit method failed repeatedly at t = {t:e} (singular or divergent)")]
    NewtonFailed { t: f64 },
    #[error("singular linear system of the method at t = {t:e}")]
    SingularMatrix { t: f64 },
    #[error("invalid integrator setting {what} = {value}: {reason}")]
    InvalidSetting { what: &'static str, value: f64, reason: &'static str },
    #[error("initial state has {got} components, the system has dimension {expected}")]
    DimensionMismatch { expected: usize, got: usize },
}

/// Index of the first non-finite entry.
pub(crate) fn first_non_finite(v: &[f64]) -> Option<usize> {
    v.iter().position(|x| !x.is_finite())
}
