//! The keys of the Marmottant laws (issue 31; docs/model.md, "Lipid shells: Marmottant"): read
//! under `shell.law = "marmottant" | "marmottant-smooth"`, refused under any other law (a key that
//! would do nothing is an error naming it), R_b and σ(R0) resolved from whichever was given.

use super::super::raw::RawShell;
use super::super::schema::fmt_num;
use super::super::types::Lipid;
use super::check::Check;

/// Water's surface tension, the default rupture tension σ_r [N/m].
pub(super) const RUPTURE_DEFAULT: f64 = 0.072;
/// Default tension width s of `marmottant-smooth` [N/m].
pub(super) const SMOOTHING_DEFAULT: f64 = 0.005;

/// The Marmottant keys a scene gives, with their values.
fn given(rs: &RawShell) -> [(&'static str, Option<f64>); 5] {
    [
        ("shell.elasticity", rs.elasticity),
        ("shell.buckling_radius", rs.buckling_radius),
        ("shell.initial_tension", rs.initial_tension),
        ("shell.rupture_tension", rs.rupture_tension),
        ("shell.smoothing", rs.smoothing),
    ]
}

/// Under a law other than Marmottant's: each Marmottant key given is an error.
pub(super) fn refuse_keys(c: &mut Check, rs: &RawShell, law: &str) {
    for (key, v) in given(rs) {
        // χ is also E0^s of the Sarkar law (validate/sarkar.rs)
        if key == "shell.elasticity" && (law == "sarkar" || law == "church-hoff") {
            continue;
        }
        if let Some(v) = v {
            c.push(key, Some(fmt_num(v)), format!("a key of shell.law = \"marmottant\" / \"marmottant-smooth\", but shell.law = \"{law}\": it would do nothing (remove it or set shell.law)"));
        }
    }
}

/// The Marmottant constants of a scene whose law is `marmottant` (`smooth` false) or
/// `marmottant-smooth`, every problem pushed to `c`.
pub(super) fn build(c: &mut Check, rs: &RawShell, r0: f64, smooth: bool) -> Lipid {
    let law = if smooth { "marmottant-smooth" } else { "marmottant" };
    for (key, v) in [("shell.shear_modulus", rs.shear_modulus), ("shell.area_dilatation", rs.area_dilatation)] {
        // `scene new` writes area_dilatation = 1 (its default): only a changed value is refused
        if let Some(v) = v.filter(|&v| key == "shell.shear_modulus" || v != 1.0) {
            c.push(key, Some(fmt_num(v)), format!("a key of shell.law = \"skalak\", but shell.law = \"{law}\": it would do nothing"));
        }
    }
    let chi = match rs.elasticity {
        Some(x) => c.float("shell.elasticity", Some(x)),
        None => {
            c.push("shell.elasticity", None, format!("required with shell.law = \"{law}\" (the elastic modulus chi [N/m])"));
            f64::NAN
        }
    };
    let sigma_r = c.float_or("shell.rupture_tension", rs.rupture_tension, RUPTURE_DEFAULT);
    let smoothing = if smooth {
        Some(c.float_or("shell.smoothing", rs.smoothing, SMOOTHING_DEFAULT))
    } else {
        if let Some(s) = rs.smoothing {
            c.push("shell.smoothing", Some(fmt_num(s)), "a key of shell.law = \"marmottant-smooth\", but shell.law = \"marmottant\" (the kinked law): it would do nothing");
        }
        None
    };
    let (rb, sigma0) = match (rs.buckling_radius, rs.initial_tension) {
        (Some(rb), Some(s0)) => {
            c.range("shell.buckling_radius", rb);
            c.range("shell.initial_tension", s0);
            let why = if rb > r0 && s0 > 0.0 {
                format!(
                    "inconsistent: R_b = {} m > R0 = {} m means the shell is buckled at rest (sigma(R0) = 0), but shell.initial_tension = {} N/m; give exactly one of the two",
                    fmt_num(rb),
                    fmt_num(r0),
                    fmt_num(s0)
                )
            } else {
                "give exactly one of shell.buckling_radius and shell.initial_tension (each determines the other: R_b = R0/sqrt(1 + sigma(R0)/chi))".to_string()
            };
            c.push("shell.buckling_radius", Some(fmt_num(rb)), why);
            (rb, s0)
        }
        (Some(rb), None) => {
            c.range("shell.buckling_radius", rb);
            (rb, (chi * ((r0 / rb).powi(2) - 1.0)).max(0.0))
        }
        (None, Some(s0)) => {
            c.range("shell.initial_tension", s0);
            (r0 / (1.0 + s0 / chi).sqrt(), s0)
        }
        (None, None) => (r0, 0.0),
    };
    if sigma0 >= sigma_r && chi > 0.0 && sigma_r > 0.0 {
        let (key, v) = match rs.initial_tension {
            Some(s) => ("shell.initial_tension", s),
            None => ("shell.buckling_radius", rb),
        };
        c.push(
            key,
            Some(fmt_num(v)),
            format!(
                "the shell would be ruptured at rest: sigma(R0) = {} N/m >= shell.rupture_tension = {} N/m",
                fmt_num(sigma0),
                fmt_num(sigma_r)
            ),
        );
    }
    Lipid { elasticity: chi, buckling_radius: rb, initial_tension: sigma0, rupture_tension: sigma_r, smoothing }
}
