//! Second-order loads of the kinked Marmottant law (issue 31; `modes.coupling = "quadratic"`).
//! On each branch the law is the polynomial energy W = chib J²/2 − chi J of
//! derivations/shell/marmottant.rs with constant symbols — elastic (χ, χ/J_b), ruptured
//! (−σ_r, 0), buckled W = const (no load) — so the spec's generated second-order loads
//! (`coefficients::quadratic_membrane`, law `marmottant`, tension form; effects/
//! quadratic_membrane.rs) are exact branch by branch. The branch is the run's (R's outside a
//! run), as for the linear loads (effects/lipid.rs). The smooth law is not polynomial (its loads need W‴): refused.

use super::lipid::{Branch, LipidLaw};
use super::quadratic_membrane::QuadraticMembrane;
use super::{At, LoadJacobian, Loads, Term};
use crate::coefficients::quadratic_membrane::Form;

#[derive(Debug)]
pub struct LipidQuadratic {
    law: LipidLaw,
    elastic: QuadraticMembrane,
    ruptured: QuadraticMembrane,
    modes: usize,
}

impl LipidQuadratic {
    /// None for the smooth law, or if the generated table is missing.
    pub fn new(law: LipidLaw, orders: &[f64]) -> Option<Self> {
        if !law.is_kinked() || law.curve.is_some() {
            return None;
        }
        let table = QuadraticMembrane::law("marmottant")?;
        let make = |args: (f64, f64)| QuadraticMembrane::new(table, Form::Tension, law.r0, args, orders);
        let (elastic, ruptured) = (make((law.chi, law.chi / law.jb))?, make((-law.sigma_r, 0.0))?);
        Some(Self { law, elastic, ruptured, modes: orders.len() })
    }

    /// The branch's loads at R (None: buckled): the run's branch inside a run.
    fn branch(&self, r: f64) -> Option<&QuadraticMembrane> {
        match self.law.current_branch(r) {
            Branch::Buckled => None,
            Branch::Elastic => Some(&self.elastic),
            Branch::Ruptured => Some(&self.ruptured),
        }
    }
}

impl Term for LipidQuadratic {
    fn name(&self) -> &'static str {
        "quadratic membrane"
    }
    fn label(&self) -> Option<String> {
        Some("quadratic membrane loads (marmottant, by branch)".into())
    }
    fn band(&self) -> usize {
        self.modes
    }
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>) {
        if let Some(q) = self.branch(at.r()) {
            q.add(at, loads);
        }
    }
    fn add_jacobian(&self, at: &At<'_>, jac: &mut LoadJacobian) {
        if let Some(q) = self.branch(at.r()) {
            q.add_jacobian(at, jac);
        }
    }
}
