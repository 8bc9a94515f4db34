//! Second-pass terms (issue 12): loads that need the *first-order accelerations* R̈⁽¹⁾, ä_k⁽¹⁾
//! of the state — the quadratic mode coupling contains R̈ a_l a_m and ä_l a_m
//! (docs/model.md, "Quadratic mode coupling"). To second order it suffices to take them from the
//! linear equations themselves, so the equations core ([`crate::model::equations::Equations`],
//! [`crate::model::BoundaryLayerSystem`]) evaluates the ordinary terms ([`super::Term`]) and the
//! radial and mode equations once (R̈⁽¹⁾, ä⁽¹⁾: already part of every rhs), hands them to the
//! second-pass terms, adds what they return to P, G_n,k, G_t,k and re-evaluates R̈ and the mode
//! rates from the completed loads. Nothing is evaluated twice; for the Jacobian the core hands
//! over the exact gradients ∂R̈⁽¹⁾/∂z, ∂ä⁽¹⁾/∂z of the linear rows as well (chain rule).
//!
//! The core also hands over the first-order loads of the *material-frame* terms (the membrane
//! law, bending, shell viscosity: [`crate::model::Equations::material_loads`]) and their
//! Jacobian — already part of its first pass — which the frame mapping converts to the state's
//! Eulerian amplitudes ([`super::quadratic_frame`]).

use super::{At, LoadJacobian, Loads};

/// The material-frame terms' share of P, G_n,k, G_t,k at the state (first order, their ḃ
/// loads not included): what the frame mapping calls L(z).
#[derive(Debug, Clone, Copy)]
pub struct MaterialLoads<'a> {
    pub pressure: f64,
    pub gn: &'a [f64],
    pub gt: &'a [f64],
}

impl MaterialLoads<'static> {
    /// No material-frame loads (for a second-pass term that does not read them).
    pub const NONE: Self = Self { pressure: 0.0, gn: &[], gt: &[] };
}

/// The first-order accelerations at the state: R̈⁽¹⁾ = form(P of the ordinary terms) and
/// ä_k⁽¹⁾ of (N) with those loads, one per mode index; and the first-order ḃ_k⁽¹⁾ of (NS) and its
/// closure (not a state variable: the shell-viscous loads hold it, effects/quadratic_shell_viscosity.rs).
#[derive(Debug, Clone, Copy)]
pub struct FirstOrder<'a> {
    pub rdd: f64,
    pub add: &'a [f64],
    pub bd: &'a [f64],
    /// The material-frame terms' loads at the state ([`MaterialLoads`]).
    pub material: MaterialLoads<'a>,
}

/// Their exact gradients over the n = `jac.n` columns of the Jacobian they are used for:
/// `drdd[j] = ∂R̈⁽¹⁾/∂x_j`, `dadd[m * n + j] = ∂ä_m⁽¹⁾/∂x_j`, `dbd[m * n + j] = ∂ḃ_m⁽¹⁾/∂x_j`,
/// x = z (n = z.len()) for the boundary-layer system; the full vorticity model appends its
/// vorticity functionals, on which ä⁽¹⁾ depends, as further columns (n > z.len(),
/// model/vorticity/equations.rs).
#[derive(Debug, Clone, Copy)]
pub struct FirstOrderGradient<'a> {
    pub drdd: &'a [f64],
    pub dadd: &'a [f64],
    pub dbd: &'a [f64],
    /// ∂/∂z of the material-frame terms' loads ([`MaterialLoads`]), z.len() columns.
    pub material: &'a LoadJacobian,
}

/// A load evaluated after the first-order accelerations are known (module doc). Same contract
/// as [`super::Term`] for `add` / `add_jacobian` (shares added to P and, for m < `gn.len()`, to
/// G_n, G_t; exact derivatives), except that the loads may be any smooth function of the state
/// and of the first-order accelerations.
pub trait SecondOrderTerm: std::fmt::Debug {
    fn name(&self) -> &'static str;
    /// Entry of the run summary's `active_effects`.
    fn label(&self) -> Option<String> {
        None
    }
    /// Half-width, in modes, of the coupling of the shape loads (as [`super::Term::band`]).
    fn band(&self) -> usize;
    fn add(&self, at: &At<'_>, first: &FirstOrder<'_>, loads: &mut Loads<'_>);
    /// Adds ∂/∂z of the loads, the first-order accelerations' dependence on z included through
    /// `grad`, into the jac.n ≥ z.len() columns of `jac`: the explicit z-derivatives in the
    /// first z.len(), the chain rule through `grad` in all of them ([`FirstOrderGradient`]).
    fn add_jacobian(&self, at: &At<'_>, first: &FirstOrder<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian);
}
