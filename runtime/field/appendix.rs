//! The paper's Appendix A (coil) and Appendix B (dipole), typed once, here only.
//!
//! **This module exists only for the cross-check.** The runtime never uses these formulas:
//! every coefficient the model uses comes from the generated tables
//! ([`crate::coefficients`]), which codegen derives from the physics. The printed appendices
//! contain slips (FORMULATION.md §0); `tests/coefficients_crosscheck.rs` asserts the exact list
//! of entries where they disagree with the derivation, and `docs/derivation-notes.md` explains
//! each one.
//!
//! Units. Every coupling is returned as the printed rational function of k, i.e. in units of
//! the prefactor ℋ of the appendix. For the dipole the printed ℋ = −36μ0χ_sM²R0²/(z⁸R) has the
//! wrong dimension (a load per unit amplitude needs 1/R², like the coil's); the values here are
//! read in units of the dimension-corrected ℋ = −36μ0χ_sM²R0²/(z⁸R²) (issue 2). The zero-order
//! terms ℋ0, ℋ2, ℋ^1_2 are returned in units of ℋR (the corrected ℋ), which is how the printed
//! formulas (all ∝ 1/R) read once divided by it.

/// The two fields of the paper whose loads have the structure of eq. (2.40).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PaperField {
    /// Two coils, H2 term only (eqs. 2.30–2.33), Appendix A.
    Coil,
    /// Two dipoles far away (eqs. 2.34–2.38), Appendix B.
    Dipole,
}

impl PaperField {
    /// Both fields, coil first.
    pub const ALL: [PaperField; 2] = [PaperField::Coil, PaperField::Dipole];

    /// The name used by the generated tables and the CLI: "coil" or "dipole".
    pub fn name(self) -> &'static str {
        match self {
            PaperField::Coil => "coil",
            PaperField::Dipole => "dipole",
        }
    }
}

/// What a coupling of eq. (2.40) is: which load it lands on, which amplitude it multiplies and
/// which source mode (source = target k + offset).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CouplingId {
    /// "F1".."F6" (normal, 𝓕_i) or "F1t".."F6t" (tangential, 𝓕^1_i).
    pub name: &'static str,
    /// `true`: tangential load, projected on P^1_j; `false`: normal load, projected on P_j.
    pub tangential: bool,
    /// `true`: multiplies b_{k+offset}; `false`: multiplies a_{k+offset}.
    pub amp_b: bool,
    /// F1, F2: 0; F3, F4: +2; F5, F6: −2.
    pub offset: i32,
}

const fn id(name: &'static str, tangential: bool, amp_b: bool, offset: i32) -> CouplingId {
    CouplingId { name, tangential, amp_b, offset }
}

/// The twelve couplings of eq. (2.40), in the order F1..F6, F1t..F6t.
pub const COUPLINGS: [CouplingId; 12] = [
    id("F1", false, false, 0),
    id("F2", false, true, 0),
    id("F3", false, false, 2),
    id("F4", false, true, 2),
    id("F5", false, false, -2),
    id("F6", false, true, -2),
    id("F1t", true, false, 0),
    id("F2t", true, true, 0),
    id("F3t", true, false, 2),
    id("F4t", true, true, 2),
    id("F5t", true, false, -2),
    id("F6t", true, true, -2),
];

/// The coupling called `name` ("F1".."F6t"), if any.
pub fn coupling_id(name: &str) -> Option<CouplingId> {
    COUPLINGS.iter().copied().find(|c| c.name == name)
}

/// Relative tolerance (absolute below magnitude 1) beyond which a derived value "differs" from
/// the printed one. Exact tables against exact formulas differ only by f64 rounding (~1e-15).
pub const DIFFERS_TOL: f64 = 1e-9;

/// Target modes k ≤ `kmax` at which the paper prints coupling `c` (the sums of eq. 2.40): F3, F4
/// (and F^1_3, F^1_4) from k = 0, F1, F2 (and partners) from k = 2, F5, F6 (and partners) from
/// k = 4. The derived and printed values are compared on this range.
pub fn printed_range(c: &CouplingId, kmax: usize) -> std::ops::RangeInclusive<usize> {
    let first = match c.offset {
        2 => 0,
        0 => 2,
        _ => 4,
    };
    first..=kmax
}

/// Whether `derived` (target k → value in units of ℋ, `None` where it does not exist) differs
/// from the printed formula at some k of [`printed_range`]. A k where either side is absent or
/// the printed formula is not finite is skipped.
pub fn differs(field: PaperField, c: &CouplingId, kmax: usize, derived: impl Fn(usize) -> Option<f64>) -> bool {
    printed_range(c, kmax).any(|k| {
        let printed = coupling(field, c.name, k as f64).filter(|v| v.is_finite());
        match (derived(k), printed) {
            (Some(d), Some(p)) => (d - p).abs() > DIFFERS_TOL * p.abs().max(1.0),
            _ => false,
        }
    })
}

/// Zero-order terms as printed, in units of ℋR (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ZeroOrder {
    /// ℋ0, on P_0.
    pub h0: f64,
    /// ℋ2, on P_2.
    pub h2: f64,
    /// ℋ^1_2, on P^1_2.
    pub h1_2: f64,
}

/// The prefactor ℋ exactly as printed in the appendix.
pub fn printed_prefactor(field: PaperField) -> &'static str {
    match field {
        PaperField::Coil => "mu0*chi_s*H2^2*R0^2/(4*R^2*a^2)",
        PaperField::Dipole => "-36*mu0*chi_s*M^2*R0^2/(z^8*R)",
    }
}

/// The printed ℋ0, ℋ2, ℋ^1_2 divided by ℋR.
///
/// Coil (App. A): ℋ0 = ℋ2 = μ0χ_sH2²R0²/(2Ra²) = 2ℋR, ℋ^1_2 = μ0χ_sH2²R0²/(4Ra²) = ℋR.
/// Dipole (App. B): ℋ0 = 24μ0χ_sM²R0²/(z⁸R) = −(2/3)ℋR, ℋ2 = −24(…) = (2/3)ℋR,
/// ℋ^1_2 = −12(…) = (1/3)ℋR, with ℋ = −36μ0χ_sM²R0²/(z⁸R²).
pub fn zero_order(field: PaperField) -> ZeroOrder {
    match field {
        PaperField::Coil => ZeroOrder { h0: 2.0, h2: 2.0, h1_2: 1.0 },
        PaperField::Dipole => ZeroOrder { h0: 24.0 / -36.0, h2: -24.0 / -36.0, h1_2: -12.0 / -36.0 },
    }
}

/// The printed coupling `name` at target mode k, in units of ℋ; `None` if `name` is not one
/// of the twelve. The formulas are evaluated for any k (the caller decides where a coupling
/// exists); a pole of a printed formula (k = 1/2, 3/2 …) gives ±inf or NaN as f64 does.
pub fn coupling(field: PaperField, name: &str, k: f64) -> Option<f64> {
    Some(match field {
        PaperField::Coil => coil(name, k)?,
        PaperField::Dipole => dipole(name, k)?,
    })
}

/// Appendix A, eqs. (A.2)–(A.4).
fn coil(name: &str, k: f64) -> Option<f64> {
    let k2 = k * k;
    let k3 = k2 * k;
    let k4 = k3 * k;
    let d0 = (2.0 * k - 1.0) * (2.0 * k + 3.0);
    let dp = (2.0 * k + 3.0) * (2.0 * k + 5.0);
    let dm = (2.0 * k - 1.0) * (2.0 * k - 3.0);
    Some(match name {
        "F1" => (-13.0 * k2 - 13.0 * k + 6.0) / d0,
        "F2" => 10.0 * k2 * (k2 + 2.0 * k + 1.0) / d0,
        "F3" => -3.0 * (k3 + 7.0 * k2 + 14.0 * k + 8.0) / dp,
        "F4" => 3.0 * (k4 + 10.0 * k3 + 35.0 * k2 + 50.0 * k + 24.0) / dp,
        "F5" => -3.0 * k * (2.0 * k3 - 5.0 * k2 + 8.0 * k - 5.0) / dm,
        "F6" => 3.0 * k * (2.0 * k4 - k3 - 16.0 * k2 + 25.0 * k - 10.0) / dm,
        "F1t" => 5.0 * (2.0 * k2 + 2.0 * k - 3.0) / d0,
        "F2t" => 3.0 * (k2 + k + 3.0) / d0,
        "F3t" => 3.0 * (k2 + 6.0 * k + 8.0) / dp,
        "F4t" => -3.0 * k * (k3 + 9.0 * k2 + 26.0 * k + 24.0) / dp,
        "F5t" => 3.0 * (k2 - 4.0 * k + 3.0) / dm,
        "F6t" => 3.0 * (k3 - 6.0 * k2 + 11.0 * k - 6.0) / dm,
        _ => return None,
    })
}

/// Appendix B, eqs. (B.2)–(B.4).
fn dipole(name: &str, k: f64) -> Option<f64> {
    let k2 = k * k;
    let k3 = k2 * k;
    let k4 = k3 * k;
    let d0 = 4.0 * k2 + 4.0 * k - 3.0;
    let dp = 4.0 * k2 + 16.0 * k + 15.0;
    let dp3 = 8.0 * k3 + 36.0 * k2 + 46.0 * k + 15.0;
    let dm = 4.0 * k2 - 8.0 * k + 3.0;
    Some(match name {
        "F1" => (k2 - 2.0) / d0,
        "F2" => -k * (k3 + 2.0 * k2 - k - 3.0) / d0,
        "F3" => -(k3 + 7.0 * k2 + 14.0 * k + 8.0) / dp,
        "F4" => (k4 + 10.0 * k3 + 35.0 * k2 + 50.0 * k + 24.0) / dp,
        "F5" => -k * (k2 - 2.0 * k + 1.0) / dm,
        "F6" => k * (k3 - 2.0 * k2 - k + 2.0) / dm,
        "F1t" => -(2.0 * k2 + 2.0 * k + 1.0) / d0,
        "F2t" => (k2 + k + 3.0) / d0,
        "F3t" => (2.0 * k3 + 13.0 * k2 + 26.0 * k + 16.0) / dp3,
        "F4t" => -(2.0 * k4 + 23.0 * k3 + 89.0 * k2 + 138.0 * k + 72.0) / dp3,
        "F5t" => (k2 - 6.0 * k + 7.0) / dm,
        "F6t" => (k3 - 6.0 * k2 + 15.0 * k - 14.0) / dm,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_coupling_name_has_a_printed_formula_for_both_fields() {
        for field in PaperField::ALL {
            for c in COUPLINGS {
                let v = coupling(field, c.name, 6.0).expect(c.name);
                assert!(v.is_finite(), "{} {}: {v}", field.name(), c.name);
            }
            assert_eq!(coupling(field, "F7", 6.0), None);
        }
    }

    #[test]
    fn printed_values_at_k2_read_as_typed() {
        // Spot values computed by hand from the printed fractions.
        assert_eq!(coupling(PaperField::Coil, "F1", 2.0), Some(-72.0 / 21.0));
        assert_eq!(coupling(PaperField::Dipole, "F1t", 2.0), Some(-13.0 / 21.0));
        assert_eq!(coupling(PaperField::Dipole, "F5t", 4.0), Some(-1.0 / 35.0));
    }
}
