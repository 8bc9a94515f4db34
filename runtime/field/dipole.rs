//! Two dipoles placed symmetrically (paper eqs 2.34–2.38): h_a = 6 M x / z⁴ e_ρ near the bubble.
//! The field is static; its loads come from the generated `DIPOLE` table (symbols M, z).

use super::{dipole_table, FieldError, FieldSource, TimeLaw, MU0};
use crate::scene::Dipole;

pub(super) fn source(d: &Dipole, chi_s: f64, r0: f64, c1: f64) -> Result<FieldSource, FieldError> {
    if !(d.distance.is_finite() && d.distance > 0.0) {
        return Err(FieldError::NonPositive { key: "dipole.distance", value: d.distance });
    }
    // M_n = 12 μ0 χ_s M² R0² / (z⁸ c1)  (eq 5.7 with χ → χ_s, FORMULATION audit 15)
    let mn = 12.0 * MU0 * chi_s * d.moment * d.moment * r0 * r0 / (d.distance.powi(8) * c1);
    Ok(FieldSource {
        table: dipole_table(),
        kind: "dipole",
        symbols: vec![("mu0", MU0), ("chi_s", chi_s), ("M", d.moment), ("z", d.distance), ("R0", r0)],
        law: TimeLaw::Static,
        label: "dipole field".to_string(),
        group: ("mn", mn),
    })
}
