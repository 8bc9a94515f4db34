//! Keys that do nothing, and values outside a model's validity (issue 29 item 10): a warning
//! naming the key, or an error where the result would be meaningless.

use super::super::error::Issue;
use super::super::raw::RawScene;
use super::super::schema::fmt_num;
use super::super::types::{time_scale, Scene, ShellLaw};

/// What the raw scene gave explicitly (the validated scene has every default filled in).
pub(super) struct Given {
    shear_modulus: Option<f64>,
    area_dilatation: Option<f64>,
    polytropic_exponent: Option<f64>,
}

impl Given {
    pub(super) fn of(raw: &RawScene) -> Given {
        let sh = raw.shell.as_ref();
        Given {
            shear_modulus: sh.and_then(|s| s.shear_modulus),
            area_dilatation: sh.and_then(|s| s.area_dilatation),
            polytropic_exponent: raw.gas.as_ref().and_then(|g| g.polytropic_exponent),
        }
    }
}

/// Mach number R0/(t* c) above which Keller–Miksis (first order in Ṙ/c) is refused: the
/// velocity scale of the wall is then at least the speed of sound.
pub const KM_MACH_ERROR: f64 = 1.0;
/// Above this R0/(t* c) a warning: the O(Ṙ/c) corrections are no longer small.
pub const KM_MACH_WARNING: f64 = 0.1;

/// The errors and the warnings of a scene whose keys are each valid.
pub(super) fn check(given: &Given, scene: &Scene) -> (Vec<Issue>, Vec<String>) {
    let (mut errors, mut warnings) = (Vec::new(), Vec::new());
    if scene.shell.law == ShellLaw::MooneyRivlin {
        for (key, v) in [("shell.shear_modulus", given.shear_modulus), ("shell.area_dilatation", given.area_dilatation)] {
            // a value equal to the schema default (as `scene new` writes every key) is no news
            let default = match super::super::schema::param(key).map(|p| p.default) {
                Some(super::super::schema::DefaultValue::Float(d)) => Some(d),
                _ => None,
            };
            if let Some(v) = v.filter(|v| Some(*v) != default) {
                warnings.push(format!(
                    "`{key}` = {} does nothing under shell.law = \"mooney-rivlin\" (a Skalak key: set shell.law = \"skalak\", or remove it)",
                    fmt_num(v)
                ));
            }
        }
    }
    let thermal = match scene.gas.thermal {
        super::super::types::Thermal::Prosperetti { .. } => Some("prosperetti"),
        super::super::types::Thermal::Reduced { .. } => Some("reduced"),
        super::super::types::Thermal::Polytropic => None,
    };
    if let (Some(name), Some(k)) = (thermal, given.polytropic_exponent) {
        warnings.push(format!(
            "`gas.polytropic_exponent` = {} does nothing under gas.thermal = \"{name}\" (the gas follows from gas.heat_capacity_ratio and gas.thermal_diffusivity)",
            fmt_num(k)
        ));
    }
    if let Some(c) = scene.liquid.sound_speed {
        let r0 = scene.bubble.radius;
        let u = r0 / time_scale(&scene.liquid, r0, &scene.shell);
        let mach = u / c;
        let what = format!(
            "Keller-Miksis is first order in dR/dt / c, and the wall's velocity scale R0/t* = {} m/s gives Mach {}",
            fmt_num(u),
            fmt_num(mach)
        );
        if mach >= KM_MACH_ERROR {
            errors.push(Issue::new("liquid.sound_speed", Some(fmt_num(c)), format!("{what}: the equation is meaningless here (need c well above {} m/s)", fmt_num(u / KM_MACH_WARNING))));
        } else if mach > KM_MACH_WARNING {
            warnings.push(format!("`liquid.sound_speed` = {}: {what}, not small (c above {} m/s keeps it below {})", fmt_num(c), fmt_num(u / KM_MACH_WARNING), KM_MACH_WARNING));
        }
    }
    (errors, warnings)
}
