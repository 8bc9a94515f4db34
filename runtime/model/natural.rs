//! The ω_k of the boundary-layer thickness δ_k = min(√(ν/ω), R/(2k)) when the rule is ω = ω_k
//! (FORMULATION audit 13; issue 31 part 3): the quasi-static natural frequency of §4.4 from the
//! full stiffness of the assembled laws — membrane law (Mooney–Rivlin, Skalak, Marmottant),
//! surface tension, bending — not the Mooney–Rivlin closed form alone:
//!
//!   ω_k² = (k+1)/(ρR0) (A − B A_a/B_b),  A = ∂G_n/∂a_k, B = ∂G_n/∂b_k, A_a = ∂G_t/∂a_k,
//!   B_b = ∂G_t/∂b_k at rest at R0 (t = 0),
//!
//! ω_k² = (k+1)A/(ρR0) when B_b = 0 (no tangential load: a free bubble). The field is left out
//! (audit 13: its shift of ω_k is ~1e-4 and it couples k ± 2), so that without a field this is
//! the ω_k `magbubble modes` prints. A mode with ω_k² ≤ 0 (no restoring stiffness) gets ω = 0:
//! √(ν/ω) is infinite and δ_k is the cap R/(2k).

use super::effects::{At, LoadJacobian};
use super::layout::StateLayout;
use super::equations::Equations;

/// ω_k (nondimensional) of each mode of `eq`, as the module doc says.
pub fn omega_k(eq: &Equations) -> Vec<f64> {
    let n = eq.orders().len();
    let lay = StateLayout::reduced(n);
    let mut z = vec![0.0; lay.dim()];
    z[lay.r()] = eq.params().r0;
    let mut lj = LoadJacobian::new(n);
    let at = At { t: 0.0, z: &z };
    for t in eq.terms().filter(|t| t.name() != "magnetic") {
        t.add_jacobian(&at, &mut lj);
    }
    let p = eq.params();
    eq.orders()
        .iter()
        .enumerate()
        .map(|(m, &k)| {
            let ia = lay.a(m);
            let (gn, gt) = (lj.gn_row(m), lj.gt_row(m));
            let stiffness = if gt[lay.b(m)] != 0.0 { gn[ia] - gn[lay.b(m)] * gt[ia] / gt[lay.b(m)] } else { gn[ia] };
            ((k + 1.0) / (p.rho * p.r0) * stiffness).max(0.0).sqrt()
        })
        .collect()
}
