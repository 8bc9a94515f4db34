//! Second-order (bilinear) bending loads (issue 12, scope 1: the membrane; docs/model.md,
//! "Quadratic mode coupling"): the part of the Helfrich bending load (derivations/shell/
//! bending.rs, w = (k_b/2)(κ1 + κ2)² per deformed area, loads by the first variation of
//! derivations/shape.rs) that is bilinear in the mode amplitudes, from the generated table
//! `coefficients::quadratic_membrane` law `bending` (codegen derive/jet2.rs evaluates `vary` on
//! the exact kinematics to the bilinear order; derive/quadratic_membrane.rs projects on P_j at
//! the material angle and fits the closed forms C(j,l,m)·N(L_l, L_m, L_j) with prefactor k_b/R⁵).
//!
//! A shape energy has no tangential load (shape.rs), so only −P (on P_0) and G_n,j receive a
//! share; the table has a_l a_m and a_l b_m terms (b moves the material points along the
//! meridian, which changes the Eulerian shape at second order: r(θ) ≈ R + aP − a b P′P¹/R).
//! The loads depend on R and the amplitudes only, so this is an ordinary [`Term`] with the
//! quadratic membrane's evaluation and exact Jacobian ([`QuadraticMembrane`]); both membrane
//! forms are the same for a shape energy (the tension form's table is used).

use super::quadratic_membrane::QuadraticMembrane;
use super::{At, LoadJacobian, Loads, Term};
use crate::coefficients::quadratic_membrane::{Ab, Form};

#[derive(Debug)]
pub struct QuadraticBending {
    inner: QuadraticMembrane,
}

impl QuadraticBending {
    /// `kb`: the bending modulus, nondimensional as the linear bending term's (k_b/(p* L*³));
    /// `orders`: k of each mode index. None if the generated table has no `bending` law, or one
    /// with rate amplitudes (a shape energy has none), or too many prefactors.
    pub fn new(kb: f64, r0: f64, orders: &[f64]) -> Option<Self> {
        let law = QuadraticMembrane::law("bending")?;
        let rates = law.terms.iter().any(|t| matches!(t.first, Ab::Ad | Ab::Bd) || matches!(t.second, Ab::Ad | Ab::Bd) || t.prefactor.iter().any(|(s, _)| *s == "Rd"));
        if rates || law.symbols != ["kb"] {
            return None;
        }
        QuadraticMembrane::new(law, Form::Tension, r0, (kb, 0.0), orders).map(|inner| Self { inner })
    }
}

impl Term for QuadraticBending {
    fn name(&self) -> &'static str {
        "quadratic bending"
    }
    fn label(&self) -> Option<String> {
        Some("quadratic bending loads".into())
    }
    fn band(&self) -> usize {
        self.inner.band()
    }
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>) {
        self.inner.add(at, loads)
    }
    fn add_jacobian(&self, at: &At<'_>, jac: &mut LoadJacobian) {
        self.inner.add_jacobian(at, jac)
    }
}
