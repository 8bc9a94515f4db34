//! The full model: toroidal vorticity T_k(y, t) of every shape mode on y = r/R ∈ [1, Y_max]
//! (paper §2.4–2.5 and §5, eqs 2.52, 2.64–2.67, 5.1–5.3; FORMULATION §4.2, audit items 3, 4, 5,
//! 11, 12), coupled to the radial equation and the mode equations.
//!
//! Two time discretisations:
//! - [`staggered`]: the paper's loosely coupled scheme (§5): RK4 for (R, Ṙ, a, ȧ, b) with lagged
//!   vorticity integrals, then backward Euler for T with upwind artificial diffusion, one
//!   bordered tridiagonal (Thomas + Sherman–Morrison) solve per mode and step.
//! - [`monolithic`]: the method of lines, every interior T node an ODE state and T_w eliminated
//!   algebraically, as one [`crate::integrate::OdeSystem`] for an implicit integrator.
//!
//! [`linear`] linearises the full model at R0 (the damped spectrum) and compares it with the
//! exact dispersion relation of [`crate::model::dispersion`].
//!
//! The vorticity part only needs, from the rest of the model, R̈ and the loads G_n,k, G_t,k at a
//! state: the [`ModeCoupling`] trait. Units are whatever the coupling uses consistently (SI, or
//! the nondimensional form of FORMULATION §4.5 with ρ = 1, η = 1/Re); nothing here assumes either.

pub mod batch;
mod copies;
mod dense;
mod dense_rows;
pub mod equations;
pub mod grid;
pub mod linear;
pub mod monolithic;
mod nodes;
mod pool;
pub mod operator;
pub mod staggered;
pub mod structured;
mod tri;
pub mod scene;

pub use grid::{Grid, GridError};

use thiserror::Error;

/// What the vorticity closure needs from the rest of the model (radial equation, membrane and
/// magnetic loads). Mode index m ↔ k = `orders()[m]`; slices `a`, `b` have length M.
pub trait ModeCoupling {
    /// The shape-mode orders k = 2, 4, …, N.
    fn orders(&self) -> &[usize];
    /// ρ of the liquid (in the coupling's units).
    fn density(&self) -> f64;
    /// η of the liquid (in the coupling's units).
    fn viscosity(&self) -> f64;
    /// R̈ from the corrected radial equation (2.62, FORMULATION §4.1). The whole state is passed
    /// (a term may depend on any of it, e.g. quadratic couplings on ȧ_k).
    #[allow(clippy::too_many_arguments)]
    fn radial_acceleration(&self, t: f64, r: f64, rdot: f64, a: &[f64], adot: &[f64], b: &[f64]) -> f64;
    /// G_n,k = Ŝ1 a_k + Ŝ2 b_k − M_n,k and G_t,k = Ŝ11 a_k + Ŝ12 b_k − M_t,k (FORMULATION §4.1),
    /// plus any further term (they may depend on Ṙ and ȧ_k, e.g. shell viscosity).
    #[allow(clippy::too_many_arguments)]
    fn shape_loads(&self, t: f64, r: f64, rdot: f64, a: &[f64], adot: &[f64], b: &[f64], gn: &mut [f64], gt: &mut [f64]);
    /// ∂G_n,k/∂a_k, ∂G_n,k/∂b_k, ∂G_t,k/∂a_k, ∂G_t,k/∂b_k of every mode at (t, R) — the diagonal
    /// of the loads' exact linear structure (membrane and magnetic diagonal), for the per-k spectra.
    fn mode_stiffness(&self, t: f64, r: f64) -> Vec<[f64; 4]>;
    /// Exact gradients over z = [R, Ṙ, (a, ȧ, b)_k]: ∂R̈/∂z into `drdd` (length 2 + 3M) and
    /// ∂G_n, ∂G_t/∂z into `jac` (the structured Jacobian of the monolithic system).
    fn linearize(&self, t: f64, z: &[f64], drdd: &mut [f64], jac: &mut crate::model::effects::LoadJacobian);
    /// Both at once: writes the loads and returns R̈ (a coupling built on the model's terms
    /// evaluates them once).
    #[allow(clippy::too_many_arguments)]
    fn loads(&self, t: f64, r: f64, rdot: f64, a: &[f64], adot: &[f64], b: &[f64], gn: &mut [f64], gt: &mut [f64]) -> f64 {
        self.shape_loads(t, r, rdot, a, adot, b, gn, gt);
        self.radial_acceleration(t, r, rdot, a, adot, b)
    }
    /// Whether the coupling has second-pass loads (the quadratic mode coupling, issue 12;
    /// [`crate::model::effects::second_order`]): loads that need the first-order R̈⁽¹⁾, ä⁽¹⁾.
    /// The closure then evaluates its mode equations twice ([`equations::coupled_mode_rates`]).
    fn has_second_order(&self) -> bool {
        false
    }
    /// The second pass at (t, R, Ṙ, a, ȧ, b): given the first-order R̈⁽¹⁾ = `rdd` (of
    /// [`loads`](Self::loads)) and ä⁽¹⁾ = `add` (the closure's (N) with those loads), adds the
    /// second-pass shares ΔG_n, ΔG_t to `gn`, `gt` (the ordinary loads on entry) and returns R̈
    /// of the completed radial balance. Default: none (returns `rdd`).
    #[allow(clippy::too_many_arguments)]
    fn second_order(&self, _t: f64, _r: f64, _rdot: f64, _a: &[f64], _adot: &[f64], _b: &[f64], rdd: f64, _add: &[f64], _gn: &mut [f64], _gt: &mut [f64]) -> f64 {
        rdd
    }
    /// Exact derivatives of [`second_order`](Self::second_order) at z = [R, Ṙ, (a, ȧ, b)_k] over
    /// the columns of `jac`: jac.n ≥ z.len(), z first, then any further variables the first-order
    /// accelerations depend on (the monolithic system's vorticity functionals p). `grad` holds
    /// ∂R̈⁽¹⁾ and ∂ä⁽¹⁾ over the same columns. Overwrites `jac` with ∂ΔP, ∂ΔG_n, ∂ΔG_t and `drdd`
    /// (length jac.n) with ∂R̈/∂(columns) of the completed R̈. Default: none (ΔG = 0, R̈ = R̈⁽¹⁾).
    fn second_order_jacobian(
        &self,
        _t: f64,
        _z: &[f64],
        _rdd: f64,
        _add: &[f64],
        grad: &crate::model::effects::second_order::FirstOrderGradient<'_>,
        jac: &mut crate::model::effects::LoadJacobian,
        drdd: &mut [f64],
    ) {
        jac.clear();
        drdd.copy_from_slice(grad.drdd);
    }
}

/// A failure of a full-model run, with where and when.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum VorticityError {
    #[error(transparent)]
    Grid(#[from] GridError),
    #[error("time step dt = {0} must be finite and > 0")]
    TimeStep(f64),
    #[error("non-finite state at t = {t} ({what}); the scheme is unstable at this time step or the solution blew up")]
    NonFinite { t: f64, what: String },
    #[error(transparent)]
    Integrate(#[from] crate::integrate::IntegrateError),
    #[error("singular tridiagonal system in the vorticity update of mode k = {k} at t = {t}")]
    Singular { k: usize, t: f64 },
}

/// The state of the full model at one instant, mode-major.
#[derive(Debug, Clone, PartialEq)]
pub struct FullState {
    pub t: f64,
    pub r: f64,
    pub rdot: f64,
    pub a: Vec<f64>,
    pub adot: Vec<f64>,
    pub b: Vec<f64>,
    /// T_k on the interior nodes y_1 … y_{n−2} for each mode (T_0 = T_w, T_{n−1} = 0).
    pub t_nodes: Vec<Vec<f64>>,
}

impl FullState {
    /// At rest at radius `r` with zero vorticity (T(y, 0) = 0), shapes `a`, `b`.
    pub fn new(t: f64, r: f64, rdot: f64, a: Vec<f64>, adot: Vec<f64>, b: Vec<f64>, interior: usize) -> Self {
        let m = a.len();
        Self { t, r, rdot, a, adot, b, t_nodes: vec![vec![0.0; interior]; m] }
    }

    /// First non-finite quantity, if any.
    pub fn non_finite(&self) -> Option<String> {
        if !self.r.is_finite() || !self.rdot.is_finite() {
            return Some(format!("R = {}, Ṙ = {}", self.r, self.rdot));
        }
        for m in 0..self.a.len() {
            if !(self.a[m].is_finite() && self.adot[m].is_finite() && self.b[m].is_finite()) {
                return Some(format!("shape mode index {m}"));
            }
            if self.t_nodes[m].iter().any(|v| !v.is_finite()) {
                return Some(format!("vorticity of mode index {m}"));
            }
        }
        None
    }
}
