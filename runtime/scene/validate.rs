//! `RawScene` → `Scene`: defaults applied from [`schema::SCHEMA`], every value range-checked,
//! cross-key rules enforced. All problems are collected, never just the first.

use super::error::Issues;
use super::raw::*;
use super::schema::{self, fmt_num};
use super::types::*;

mod check;
mod warn;
mod lipid;
mod sarkar;
mod tension_curve;
mod drive;
mod population;
mod field;
mod run;
use check::Check;
use field::{build_field, build_vorticity};
use run::build_run;

impl TryFrom<RawScene> for Scene {
    type Error = Issues;

    fn try_from(raw: RawScene) -> Result<Scene, Issues> {
        let mut c = Check::default();
        let given = warn::Given::of(&raw);
        let mut scene = build(&mut c, raw);
        if c.issues.is_empty() {
            // Each key is valid on its own: now what they give together.
            c.issues = super::derived::check(&scene);
        }
        if c.issues.is_empty() {
            let (errors, warnings) = warn::check(&given, &scene);
            c.issues = errors;
            scene.warnings = warnings;
        }
        if c.issues.is_empty() {
            Ok(scene)
        } else {
            Err(Issues(c.issues))
        }
    }
}

fn build(c: &mut Check, raw: RawScene) -> Scene {
    // Modes first: the initial mode maps are checked against max_order.
    let rm = raw.modes.unwrap_or_default();
    let max_order = c.int("modes.max_order", rm.max_order);
    let modes = Modes {
        max_order: usize::try_from(max_order).unwrap_or(0),
        viscous: match c.choice("modes.viscous", rm.viscous.as_deref()) {
            "vorticity" => Viscous::Vorticity,
            "boundary-layer" => Viscous::BoundaryLayer,
            other => unreachable!("schema choice {other}"),
        },
        boundary_layer_frequency: match c.choice(
            "modes.boundary_layer_frequency",
            rm.boundary_layer_frequency.as_deref(),
        ) {
            "natural" => BoundaryLayerFrequency::Natural,
            "auto" => BoundaryLayerFrequency::Auto,
            other => unreachable!("schema choice {other}"),
        },
        coupling: match c.choice("modes.coupling", rm.coupling.as_deref()) {
            "quadratic" => Coupling::Quadratic,
            "linear" => Coupling::Linear,
            other => unreachable!("schema choice {other}"),
        },
        credible_amplitude: c.float("modes.credible_amplitude", rm.credible_amplitude),
    };
    // Mode keys are compared with the largest *valid* order (an invalid one is reported already).
    let order_limit =
        if schema::param("modes.max_order").is_some_and(|p| p.range.admits(max_order as f64)) {
            modes.max_order
        } else {
            schema::MAX_ORDER_LIMIT
        };

    let rb = raw.bubble.unwrap_or_default();
    let r0 = c.float("bubble.radius", rb.radius);
    let ri = rb.initial.unwrap_or_default();
    let initial = Initial {
        radius: c.float_or("bubble.initial.radius", ri.radius, r0),
        velocity: c.float("bubble.initial.velocity", ri.velocity),
        a: c.modes("bubble.initial.a", ri.a, order_limit),
        a_velocity: c.modes("bubble.initial.a_velocity", ri.a_velocity, order_limit),
        b: c.modes("bubble.initial.b", ri.b, order_limit),
        seed: match c.choice("bubble.initial.seed", ri.seed.as_deref()) {
            "thermal" => Seed::Thermal,
            _ => Seed::Given,
        },
    };
    let bubble = Bubble {
        radius: r0,
        initial,
    };

    let rs = raw.shell.unwrap_or_default();
    let (c1, c2) = (c.float("shell.c1", rs.c1), c.float("shell.c2", rs.c2));
    let law_name = c.choice("shell.law", rs.law.as_deref());
    if !law_name.starts_with("marmottant") {
        lipid::refuse_keys(c, &rs, law_name);
    }
    if law_name != "sarkar" {
        sarkar::refuse_keys(c, &rs, law_name);
    }
    if law_name != "tension-curve" {
        tension_curve::refuse_key(c, &rs, law_name);
    }
    if law_name != "church-hoff" {
        for (key, v) in [("shell.modulus", rs.modulus), ("shell.viscosity", rs.viscosity)] {
            if let Some(v) = v {
                c.push(key, Some(fmt_num(v)), format!("a key of shell.law = \"church-hoff\", but shell.law = \"{law_name}\": it would do nothing (remove it or set shell.law)"));
            }
        }
    }
    let law = match law_name {
        "church-hoff" => church_hoff(c, &rs, modes.max_order),
        "sarkar" => ShellLaw::Sarkar(sarkar::build(c, &rs, r0)),
        "tension-curve" => ShellLaw::TensionCurve(tension_curve::build(c, &rs)),
        "marmottant" => ShellLaw::Marmottant(lipid::build(c, &rs, r0, false)),
        "marmottant-smooth" => ShellLaw::MarmottantSmooth(lipid::build(c, &rs, r0, true)),
        "skalak" => ShellLaw::Skalak {
            shear_modulus: c.float_or("shell.shear_modulus", rs.shear_modulus, 2.0 * (c1 + c2)),
            area_dilatation: c.float("shell.area_dilatation", rs.area_dilatation),
        },
        _ => {
            // range-checked, but unused by the Mooney–Rivlin law (`scene new` writes every key)
            c.float_or("shell.shear_modulus", rs.shear_modulus, 0.0);
            c.float("shell.area_dilatation", rs.area_dilatation);
            ShellLaw::MooneyRivlin
        }
    };
    let shell = Shell {
        c1,
        c2,
        thickness: c.float("shell.thickness", rs.thickness),
        susceptibility: c.float("shell.susceptibility", rs.susceptibility),
        form: match c.choice("shell.form", rs.form.as_deref()) {
            "tension" => MembraneForm::Tension,
            "paper" => MembraneForm::Paper,
            other => unreachable!("schema choice {other}"),
        },
        law,
        bending_modulus: c.float("shell.bending_modulus", rs.bending_modulus),
        shear_viscosity: c.float("shell.shear_viscosity", rs.shear_viscosity),
        dilatational_viscosity: c.float("shell.dilatational_viscosity", rs.dilatational_viscosity),
        surface_tension: c.float("shell.surface_tension", rs.surface_tension),
    };

    let rl = raw.liquid.unwrap_or_default();
    let liquid = Liquid {
        density: c.float("liquid.density", rl.density),
        viscosity: c.float("liquid.viscosity", rl.viscosity),
        ambient_pressure: c.float("liquid.ambient_pressure", rl.ambient_pressure),
        sound_speed: rl.sound_speed.map(|v| {
            c.range("liquid.sound_speed", v);
            v
        }),
        temperature: c.float("liquid.temperature", rl.temperature),
    };
    if shell.c1 == 0.0 && shell.c2 != 0.0 {
        c.push(
            "shell.c2",
            Some(fmt_num(shell.c2)),
            "must be 0 when shell.c1 = 0 (c1 = c2 = 0 is a free bubble; a membrane needs c1 > 0)",
        );
    }
    // A law's moduli stand on their own (issue 29 item 4): c1 = c2 = 0 means a free bubble, which
    // has no membrane, so under another law it would silently drop that law and its moduli.
    if let (ShellLaw::Skalak { shear_modulus, .. }, true) = (&shell.law, shell.c1 == 0.0 && shell.c2 == 0.0) {
        c.push(
            "shell.c1",
            Some(fmt_num(shell.c1)),
            format!(
                "shell.law = \"skalak\" (G_s = {} N/m) needs shell.c1 > 0: c1 sets the time scale t* of a membrane, and \
                 c1 = c2 = 0 is a free bubble, which has no membrane law (remove shell.law for a free bubble)",
                fmt_num(*shear_modulus)
            ),
        );
    }
    let rg = raw.gas.unwrap_or_default();
    let vapour_pressure = c.float("gas.vapour_pressure", rg.vapour_pressure);
    // Equilibrium at rest at R0 (docs/model.md, "Liquid and gas effects"): p_g0 = p0 − p_v
    // + 2γ/R0 (+ Ŝ0(R0); the membrane prestress is added by the model).
    let equilibrium = liquid.ambient_pressure - vapour_pressure + 2.0 * shell.surface_tension / r0;
    let gas = Gas {
        polytropic_exponent: c.float("gas.polytropic_exponent", rg.polytropic_exponent),
        reference_pressure: c.float_or("gas.reference_pressure", rg.reference_pressure, equilibrium),
        reference_pressure_given: rg.reference_pressure.is_some(),
        vapour_pressure,
        thermal: thermal(c, &rg, &modes),
    };
    if !gas.reference_pressure_given && !(equilibrium > 0.0) && vapour_pressure.is_finite() {
        c.push(
            "gas.vapour_pressure",
            Some(fmt_num(vapour_pressure)),
            format!(
                "the equilibrium gas pressure p0 - p_v + 2 gamma/R0 = {} Pa is not positive (lower p_v or give gas.reference_pressure)",
                fmt_num(equilibrium)
            ),
        );
    }

    let drive = drive::build(c, raw.drive);

    let field = build_field(c, raw.field, r0);
    if field.is_some() && shell.is_free() {
        c.push(
            "field",
            None,
            "a magnetic field acts on the nanoparticle-laden shell: a free bubble (shell.c1 = shell.c2 = 0) has none",
        );
    }
    // Keller–Miksis with a field needs ḃ_k in dM0/dt, which the boundary-layer system supplies
    // (runtime/model/boundary_layer.rs) and the vorticity model does not yet.
    if let (Some(cs), true, Viscous::Vorticity, true) = (liquid.sound_speed, field.is_some(), modes.viscous, modes.max_order > 0) {
        c.push(
            "liquid.sound_speed",
            Some(fmt_num(cs)),
            "Keller-Miksis with a magnetic field is supported with modes.viscous = \"boundary-layer\" only (dM0/dt needs the closure's db_k/dt, which the vorticity model does not provide yet)",
        );
    }
    let vorticity = build_vorticity(c, raw.vorticity);
    let run = build_run(c, raw.run, &bubble, &shell, &liquid);
    let echo = drive::build_echo(c, raw.echo, &bubble, &run);
    let population = population::build(c, raw.population, &bubble, &shell);

    // Shell viscosity (issue 11 part 3): the shape-mode viscous loads multiply ḃ_k, an output of
    // the tangential balance; the boundary-layer system solves for it (runtime/model/
    // boundary_layer.rs), the vorticity model does not yet.
    for (key, v) in [("shell.shear_viscosity", shell.shear_viscosity), ("shell.dilatational_viscosity", shell.dilatational_viscosity)] {
        if v > 0.0 && modes.max_order > 0 && modes.viscous == Viscous::Vorticity {
            c.push(
                key,
                Some(fmt_num(v)),
                "with modes.viscous = \"vorticity\": the shell-viscous shape loads multiply db_k/dt, which only the boundary-layer closure solves for yet (use modes.viscous = \"boundary-layer\")",
            );
        }
    }

    // Cross-key rules on the initial state.
    for (name, map) in [("a", &bubble.initial.a), ("b", &bubble.initial.b)] {
        for (k, x) in map {
            if r0 > 0.0 && run.blow_up_threshold > 0.0 && (x / r0).abs() > run.blow_up_threshold {
                c.push(
                    &format!("bubble.initial.{name}.{k}"),
                    Some(fmt_num(*x)),
                    format!(
                        "|{name}_{k}(0)|/R0 = {} already exceeds run.blow_up_threshold = {}",
                        fmt_num((x / r0).abs()),
                        fmt_num(run.blow_up_threshold)
                    ),
                );
            }
        }
    }

    Scene {
        bubble,
        shell,
        gas,
        liquid,
        drive,
        field,
        modes,
        vorticity,
        run,
        warnings: Vec::new(),
        echo,
        population,
    }
}

/// `gas.thermal` and its keys (issue 31 part 2): a thermal key under the polytropic gas is an
/// error naming it; `reduced` with shape modes takes the boundary-layer closure and the linear
/// coupling (the quadratic coupling and the vorticity model refused, with the reason).
fn thermal(c: &mut Check, rg: &super::raw::RawGas, modes: &Modes) -> Thermal {
    use crate::model::effects::reduced_gas::{WITH_QUADRATIC, WITH_VORTICITY};
    let name = c.choice("gas.thermal", rg.thermal.as_deref());
    let d = c.float_or("gas.thermal_diffusivity", rg.thermal_diffusivity, 2.0e-5);
    let g = c.float_or("gas.heat_capacity_ratio", rg.heat_capacity_ratio, 1.4);
    match name {
        "prosperetti" => Thermal::Prosperetti { thermal_diffusivity: d, heat_capacity_ratio: g },
        "reduced" => {
            if modes.max_order > 0 && modes.coupling == Coupling::Quadratic {
                c.push("modes.coupling", Some("\"quadratic\"".into()), WITH_QUADRATIC);
            }
            if modes.max_order > 0 && modes.viscous == Viscous::Vorticity {
                c.push("modes.viscous", Some("\"vorticity\"".into()), WITH_VORTICITY);
            }
            Thermal::Reduced { thermal_diffusivity: d, heat_capacity_ratio: g }
        }
        _ => {
            for (key, v) in [("gas.thermal_diffusivity", rg.thermal_diffusivity), ("gas.heat_capacity_ratio", rg.heat_capacity_ratio)] {
                if let Some(v) = v {
                    c.push(key, Some(fmt_num(v)), "a thermal-model key under gas.thermal = \"polytropic\": set gas.thermal = \"prosperetti\" or \"reduced\", or remove it");
                }
            }
            Thermal::Polytropic
        }
    }
}

/// `shell.law = "church-hoff"`: G_s required, η_s default 0; radial only (shape modes refused).
fn church_hoff(c: &mut Check, rs: &RawShell, max_order: usize) -> ShellLaw {
    let modulus = match rs.modulus {
        Some(g) => c.float("shell.modulus", Some(g)),
        None => {
            c.push("shell.modulus", None, "required with shell.law = \"church-hoff\" (the shell's shear modulus G_s [Pa])");
            f64::NAN
        }
    };
    let viscosity = c.float_or("shell.viscosity", rs.viscosity, 0.0);
    for (key, v) in [("shell.shear_modulus", rs.shear_modulus), ("shell.elasticity", rs.elasticity)] {
        if let Some(v) = v {
            c.push(key, Some(fmt_num(v)), "not a key of shell.law = \"church-hoff\" (its modulus is shell.modulus [Pa]): it would do nothing");
        }
    }
    if max_order > 0 {
        c.push(
            "modes.max_order",
            Some(max_order.to_string()),
            "shell.law = \"church-hoff\" is radial only (Church's solid shell resists shape change by its shear stiffness, which is not an isotropic surface energy; its shape-mode loads are not derived): set modes.max_order = 0",
        );
    }
    ShellLaw::ChurchHoff { modulus, viscosity }
}
