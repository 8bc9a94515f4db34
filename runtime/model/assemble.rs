//! [`Model::from_scene`]: the scene nondimensionalized once ([`super::params`], FORMULATION
//! §4.5) and assembled into its equations with only the effects it calls for (the module doc of
//! [`super`]): the radial form, the boundary-layer or vorticity shape system, the shell law's
//! terms (membrane, Skalak, lipid laws, bending, surface tension), the quadratic coupling and the
//! field's loads.

use super::*;

impl Model {
    pub fn from_scene(scene: &Scene) -> Result<Model, ModelError> {
        Self::from_scene_in(scene, Scales::from_scene(scene), crate::drive::Piece::default())
    }

    /// The model of `scene` in the units of `base` and on `base`'s drive piece (the fit's models at
    /// changed parameter values, whose terms are compared with `base`'s: fit/sensitivities.rs).
    /// `scene` must have `base`'s R0 (the length unit: R̄0 = 1).
    pub(crate) fn from_scene_like(scene: &Scene, base: &Model) -> Result<Model, ModelError> {
        debug_assert_eq!(scene.bubble.radius, base.scales.length);
        Self::from_scene_in(scene, base.scales, base.piece.clone())
    }

    fn from_scene_in(scene: &Scene, scales: Scales, piece: crate::drive::Piece) -> Result<Model, ModelError> {
        let mut params = Params::from_scene(scene, &scales);
        let orders: Vec<usize> = scene.modes.orders().collect();
        if scene.modes.max_order > KMAX {
            return Err(ModelError::TooManyModes { max_order: scene.modes.max_order, kmax: KMAX });
        }
        if !orders.is_empty() && scene.modes.viscous == Viscous::Vorticity {
            return Err(ModelError::Unsupported {
                key: "modes.viscous",
                value: "vorticity".into(),
                reason: "the full vorticity model is built by model::vorticity::FullModel (model::simulate dispatches to it)",
            });
        }
        let thermal_seed = match scene.bubble.initial.seed {
            crate::scene::Seed::Thermal => Some(thermal::amplitudes(scene)?),
            crate::scene::Seed::Given => None,
        };
        let source = scene
            .field
            .as_ref()
            .map(|f| FieldSource::from_scene(f, &scene.shell, scene.bubble.radius))
            .transpose()?;
        let loads = source
            .as_ref()
            .map(|s| MagneticLoads::new(s, orders.len(), scales.length, scales.pressure, scales.time))
            .transpose()?;
        let kf: Vec<f64> = orders.iter().map(|&k| k as f64).collect();
        // The terms in summation order: P = p_in (+ p_v) − p∞ − 4ηṘ/R − Ŝ0 + M0, G = Ŝ·(a, b) − M.
        // Vapour and membrane only when the scene has them (issue 10: free when absent).
        let mut terms: Vec<Box<dyn Term>> =
            vec![Box::new(effects::gas::PolytropicGas { pg0: params.pg0, r0: params.r0, three_kappa: params.three_kappa })];
        if params.pv != 0.0 {
            terms.push(Box::new(effects::vapour::VapourPressure { pv: params.pv }));
        }
        // the drive in the model's units (docs/model.md, "Drives")
        let wave = scene
            .drive
            .as_ref()
            .and_then(|d| crate::drive::Waveform::from_scene(d, scene.liquid.ambient_pressure))
            .map(|w| w.scaled(scales.time, scales.pressure));
        terms.push(Box::new(effects::drive::FarField { p0: params.p0, wave: wave.clone(), piece: piece.clone() }));
        terms.push(Box::new(effects::viscosity::LiquidViscosity { eta: params.eta }));
        // issue 31 part 2: Prosperetti's thermal damping (its μ_th once the stiffness is known)
        let thermal_at = matches!(scene.gas.thermal, crate::scene::Thermal::Prosperetti { .. }).then(|| {
            terms.push(Box::new(effects::thermal_damping::ThermalDamping { mu: 0.0, label: String::new() }));
            terms.len() - 1
        });
        // the material-frame terms, marked for the quadratic frame mapping (model/material.rs)
        let mut material = Vec::new();
        if !scene.shell.is_free() && !scene.shell.law.replaces_membrane() {
            terms.push(Box::new(membrane_term(&params, &kf)));
            material.push(terms.len() - 1);
        }
        // issue 31: a Marmottant law replaces the membrane (c1 keeps setting t*); one law, its
        // clones in every term share the run's branch (model/events.rs)
        let lipid = effects::lipid::LipidLaw::from_scene(&scene.shell.law, &scales);
        if let Some(t) = lipid.as_ref().and_then(|l| effects::lipid::term(&scene.shell.law, l, &kf)) {
            terms.push(Box::new(t));
            material.push(terms.len() - 1);
        }
        // issue 31: Church–Hoff, radial only
        if let Some(t) = effects::church_hoff::term(&scene.shell, &scales, params.r0) {
            if !orders.is_empty() {
                return Err(ModelError::Unsupported {
                    key: "modes.max_order",
                    value: scene.modes.max_order.to_string(),
                    reason: "shell.law = \"church-hoff\" is radial only (its shape-mode loads are not derived): set modes.max_order = 0",
                });
            }
            terms.push(Box::new(t));
        }
        // issue 11 / issue 10 part 2: only the shell effects the scene switches on (γ, then the
        // material-frame ones: the summation order of the whole list)
        let gamma = crate::scene::Shell { bending_modulus: 0.0, shear_viscosity: 0.0, dilatational_viscosity: 0.0, ..scene.shell.clone() };
        terms.extend(effects::shell::terms(&gamma, &scales, params.r0, &kf));
        let first = terms.len();
        terms.extend(effects::shell::terms(&material_shell(&scene.shell), &scales, params.r0, &kf));
        material.extend(first..terms.len());
        if let (Some(l), Some(s)) = (loads, &source) {
            terms.push(Box::new(effects::magnetic::MagneticTerm { loads: l, label: s.label.clone() }));
        }
        if let Some(i) = thermal_at {
            effects::thermal_damping::assemble(scene, &scales, &mut params, &mut terms, i)?;
        }
        // issue 31 part 2: the reduced thermal model, p_b in the gas slot after the mode blocks
        // (with shape modes: the boundary-layer linear coupling; validation refuses the
        // quadratic coupling and the vorticity model with it)
        let lay = match scene.gas.thermal {
            crate::scene::Thermal::Reduced { .. } => layout::StateLayout::reduced(orders.len()).with_gas(),
            _ => layout::StateLayout::reduced(orders.len()),
        };
        let reduced_gas = match lay.p_b() {
            Some(i) => effects::thermal_damping::assemble_reduced(scene, &scales, &mut params, &mut terms, i)?,
            None => None,
        };
        if reduced_gas.is_some() && scene.modes.coupling == Coupling::Quadratic && !orders.is_empty() {
            return Err(ModelError::Unsupported {
                key: "gas.thermal",
                value: "\"reduced\"".into(),
                reason: effects::reduced_gas::WITH_QUADRATIC,
            });
        }
        // issue 12: the quadratic coupling, a second-pass term (nothing is assembled for `linear`)
        let mut second: Vec<Box<dyn effects::second_order::SecondOrderTerm>> = Vec::new();
        if scene.modes.coupling == Coupling::Quadratic && !orders.is_empty() {
            check_quadratic(scene)?;
            let gamma = scene.shell.surface_tension / (scales.pressure * scales.length);
            second.push(Box::new(effects::quadratic::QuadraticCoupling::new(params.rho, gamma, params.three_kappa, params.pg0, params.r0, &kf)));
            if let Some(law) = &lipid {
                // issue 31: the kinked Marmottant law's, branch by branch
                let t = effects::lipid_quadratic::LipidQuadratic::new(law.clone(), &kf).ok_or(ModelError::Unsupported {
                    key: "shell.law",
                    value: "marmottant-smooth".into(),
                    reason: "modes.coupling = quadratic: the smooth law's second-order loads need W‴ (not derived); use shell.law = \"marmottant\"",
                })?;
                terms.push(Box::new(t));
            } else if !scene.shell.is_free() {
                // the membrane's second-order loads need no accelerations: an ordinary term
                terms.push(Box::new(quadratic_membrane_term(scene, &params, &kf)?));
            }
            quadratic_shell_terms(scene, &scales, params.r0, &kf, &mut terms, &mut second)?;
            // the membrane's loads are material-frame: mapped to the state's Eulerian amplitudes
            if let Some(t) = frame_map(scene, &params, &scales, &kf, lipid.as_ref()) {
                second.push(Box::new(t));
            }
        }
        let form: Box<dyn RadialForm> = match params.sound_speed {
            None => Box::new(radial::Incompressible),
            Some(c) => Box::new(keller_miksis::KellerMiksis { c }),
        };
        let material = if second.is_empty() { Vec::new() } else { (0..terms.len()).map(|i| material.contains(&i)).collect() };
        let eq = Equations { params, orders: kf, form, terms, second, material };
        if eq.form().needs_rate() {
            let z = vec![1.0; lay.dim()];
            if let Some(t) = eq.terms().find(|t| !t.add_rate(&effects::At { t: 0.0, z: &z }, &mut Default::default())) {
                return Err(ModelError::Unsupported {
                    key: "liquid.sound_speed",
                    value: format!("{} m/s", scene.liquid.sound_speed.unwrap_or(f64::NAN)),
                    reason: match t.name() {
                        "magnetic" => "Keller-Miksis needs dP/dt, and the magnetic load M0 has no time derivative yet (remove [field] or liquid.sound_speed)",
                        _ => "Keller-Miksis needs dP/dt, and a term of this scene does not provide it",
                    },
                });
            }
        }

        let mut effects = vec![match params.sound_speed {
            None => "radial".to_string(),
            Some(_) => "radial (Keller-Miksis)".to_string(),
        }];
        if scene.shell.is_free() {
            effects.push("free bubble (no membrane)".to_string());
        }
        let system = if orders.is_empty() {
            let fused = super::radial_fused::FusedRadial::of(&eq);
            System::Radial(RadialSystem { eq, gas: reduced_gas.as_ref().map(|g| g.0), fused })
        } else {
            let nu = params.eta / params.rho;
            // ω_k of the full stiffness of the assembled laws (issue 31 part 3; model/natural.rs)
            let omega_k = natural::omega_k(&eq);
            let modes = orders
                .iter()
                .enumerate()
                .map(|(m, &k)| {
                    let kf = k as f64;
                    // FORMULATION audit 13: ω = ω_d when driven (Auto), ω_k of §4.4 otherwise.
                    let omega = match (scene.modes.boundary_layer_frequency, params.drive) {
                        (BoundaryLayerFrequency::Auto, Some((_, w))) => w,
                        _ => omega_k[m],
                    };
                    ModeConst { k: kf, viscous_length: (nu / omega).sqrt() }
                })
                .collect();
            effects.push(format!("shape modes k=2..{} (boundary layer)", scene.modes.max_order));
            let mut bl = BoundaryLayerSystem { bdot_radial: eq.needs_bdot(), bdot_loads: eq.has_bdot_loads(), eq, modes, shape_weights: Vec::new(), gas: reduced_gas.as_ref().map(|g| g.0) };
            let forced = thermal::static_response(&bl);
            bl.shape_weights = thermal::weights(scene, thermal_seed.as_ref(), scales.time, &forced);
            System::BoundaryLayer(bl)
        };
        effects.extend(self_labels(eq_of(&system)));
        effects.extend(reduced_gas.map(|g| g.1));

        let mut y0 = vec![0.0; lay.dim()];
        y0[lay.r()] = scene.bubble.initial.radius / scales.length;
        if let Some(i) = lay.p_b() {
            // the gas starts at the wall temperature T0 (T̄ = T0) with its mass at rest:
            // p_b(0) = p_g0 (R0/R(0))³ (docs/model.md, "Reduced thermal model")
            let p = eq_of(&system).params.pg0;
            y0[i] = p * (eq_of(&system).params.r0 / y0[lay.r()]).powi(3);
        }
        y0[lay.rdot()] = scene.bubble.initial.velocity * scales.time / scales.length;
        for (m, &k) in orders.iter().enumerate() {
            let g = |m: &std::collections::BTreeMap<usize, f64>| m.get(&k).copied().unwrap_or(0.0);
            y0[lay.a(m)] = match (&thermal_seed, scene.bubble.initial.a.get(&k)) {
                (Some(th), None) => th[&k],
                _ => g(&scene.bubble.initial.a),
            } / scales.length;
            y0[lay.adot(m)] = g(&scene.bubble.initial.a_velocity) * scales.time / scales.length;
            y0[lay.b(m)] = g(&scene.bubble.initial.b) / scales.length;
        }
        let r0 = scene.bubble.radius;
        let (c1, c2) = (scene.shell.c1, scene.shell.c2);
        let groups = Groups {
            t_star: scales.time,
            reynolds: if c1 == 0.0 {
                r0 * (scene.liquid.density * scene.liquid.ambient_pressure).sqrt() / scene.liquid.viscosity
            } else {
                (2.0 * scene.liquid.density * c1 * r0).sqrt() / scene.liquid.viscosity
            },
            p: (c1 != 0.0).then(|| scene.liquid.ambient_pressure * r0 / c1),
            alpha: (c1 != 0.0).then(|| c2 / c1),
            p_g0_pa: eq_of(&system).params.pg0 * scales.pressure,
            p_g0_rule: if scene.gas.reference_pressure_given { "override" } else { "equilibrium" },
            mach: scene.liquid.sound_speed.map(|c| scales.length / (c * scales.time)),
            rn: source.as_ref().filter(|s| s.group.0 == "rn").map(|s| s.group.1),
            mn: source.as_ref().filter(|s| s.group.0 == "mn").map(|s| s.group.1),
            omega_d_star: params.drive.map(|(_, w)| w),
        };
        let credible = eq_of(&system).has_second_order().then_some(scene.modes.credible_amplitude);
        let t_end = scene.run.duration / scales.time;
        let kinked = lipid.filter(|l| l.is_kinked()).map(|l| (l, Default::default()));
        Ok(Model { scales, system, layout: lay, orders, y0, groups, effects, blow_up_threshold: scene.run.blow_up_threshold, credible, wave, t_end, kinked, piece })
    }
}

/// `modes.coupling = "quadratic"`: only what its second-order terms are derived for (issue 12).
fn check_quadratic(scene: &Scene) -> Result<(), ModelError> {
    let refuse = |reason: &'static str| Err(ModelError::Unsupported { key: "modes.coupling", value: "quadratic".into(), reason });
    let sh = &scene.shell;
    if let crate::scene::ShellLaw::MarmottantSmooth(_) = sh.law {
        return refuse("the smooth Marmottant law's second-order loads need W‴ (not derived); use shell.law = \"marmottant\"");
    }
    if let crate::scene::ShellLaw::Sarkar(_) = sh.law {
        return refuse("the Sarkar law's second-order loads need W‴ (not derived)");
    }
    if !sh.is_free() && effects::quadratic_membrane::QuadraticMembrane::law(law_name(&sh.law)).is_none() {
        return refuse("the second-order membrane loads of this shell.law are not derived (derivations/shell/ laws with a strain energy W are)");
    }
    // bending and the shell viscosities: their second-order loads are derived (derivations/
    // shell/bending.rs by `vary`, viscous.rs by `rate`; quadratic_shell_terms)
    // A field is allowed: its loads stay linear. Their second-order part, measured by quadrature
    // (tests/suite/quadratic_magnetic.rs), is ≤ 1.7e-3 of the membrane's at the paper's
    // strongest fields (docs/model.md, "Quadratic mode coupling").
    if scene.liquid.sound_speed.is_some() {
        return refuse("the quadratic terms are derived for an incompressible liquid (remove liquid.sound_speed)");
    }
    // Either viscous closure: the vorticity model (model::vorticity) adds the same second-pass
    // terms to its mode equations (model::vorticity::equations::coupled_mode_rates).
    Ok(())
}

/// The second-order loads of bending (an ordinary term) and of the shell viscosities (a
/// second-pass term: they hold the first-order ḃ), when the scene switches them on (issue 12).
fn quadratic_shell_terms(
    scene: &Scene,
    sc: &Scales,
    r0: f64,
    kf: &[f64],
    terms: &mut Vec<Box<dyn Term>>,
    second: &mut Vec<Box<dyn effects::second_order::SecondOrderTerm>>,
) -> Result<(), ModelError> {
    let refuse = |key: &'static str, value: f64, reason: &'static str| ModelError::Unsupported { key, value: value.to_string(), reason };
    let sh = &scene.shell;
    if sh.bending_modulus != 0.0 {
        let kb = sh.bending_modulus / (sc.pressure * sc.length.powi(3));
        let t = effects::quadratic_bending::QuadraticBending::new(kb, r0, kf)
            .ok_or_else(|| refuse("shell.bending_modulus", sh.bending_modulus, "modes.coupling = quadratic: the generated tables have no second-order bending loads"))?;
        terms.push(Box::new(t));
    }
    if sh.shear_viscosity != 0.0 || sh.dilatational_viscosity != 0.0 {
        let unit = sc.pressure * sc.length * sc.time;
        let t = effects::quadratic_shell_viscosity::QuadraticShellViscosity::new(sh.shear_viscosity / unit, sh.dilatational_viscosity / unit, r0, kf).ok_or_else(|| {
            refuse("shell.shear_viscosity", sh.shear_viscosity, "modes.coupling = quadratic: the generated tables have no second-order shell-viscous loads")
        })?;
        second.push(Box::new(t));
    }
    Ok(())
}

/// The frame mapping of the material-frame linear loads (membrane law, bending, shell
/// viscosity; not γ, whose second order is the free bubble's, nor the field, whose second order
/// is left out), when the scene has any (issue 12; effects/quadratic_frame.rs).
fn frame_map(scene: &Scene, params: &Params, sc: &Scales, kf: &[f64], lipid: Option<&effects::lipid::LipidLaw>) -> Option<effects::quadratic_frame::FrameMap> {
    let mut lagrangian: Vec<Box<dyn Term>> = Vec::new();
    if !scene.shell.is_free() && !scene.shell.law.replaces_membrane() {
        lagrangian.push(Box::new(membrane_term(params, kf)));
    }
    if let Some(t) = lipid.and_then(|l| effects::lipid::term(&scene.shell.law, l, kf)) {
        lagrangian.push(Box::new(t));
    }
    lagrangian.extend(effects::shell::terms(&material_shell(&scene.shell), sc, params.r0, kf));
    effects::quadratic_frame::FrameMap::new(lagrangian, kf)
}

/// The shell effects whose loads are material-frame: all but γ.
fn material_shell(shell: &crate::scene::Shell) -> crate::scene::Shell {
    crate::scene::Shell { surface_tension: 0.0, ..shell.clone() }
}

/// The linear membrane term of the scene's law (−Ŝ0 in the radial balance, Ŝ·(a, b) in G_n and
/// G_t; effects/membrane.rs): one of the model's terms, and one of the material-frame loads of
/// the quadratic frame mapping.
fn membrane_term(params: &Params, kf: &[f64]) -> effects::membrane::MembraneTerm {
    effects::membrane::MembraneTerm {
        law: params.membrane,
        r0: params.r0,
        c1: params.membrane_args.0,
        c2: params.membrane_args.1,
        orders: kf.to_vec(),
    }
}

/// The derivations/shell/ file stem of a law.
fn law_name(law: &crate::scene::ShellLaw) -> &'static str {
    match law {
        crate::scene::ShellLaw::MooneyRivlin => "mooney_rivlin",
        crate::scene::ShellLaw::Skalak { .. } => "skalak",
        // branch-wise use of the spec's tables (effects/lipid_quadratic.rs); the smooth law is
        // refused by check_quadratic
        crate::scene::ShellLaw::Marmottant(_) => "marmottant",
        crate::scene::ShellLaw::MarmottantSmooth(_) | crate::scene::ShellLaw::Sarkar(_) | crate::scene::ShellLaw::ChurchHoff { .. } | crate::scene::ShellLaw::TensionCurve(_) => "",
    }
}

/// The second-order membrane loads of the scene's law and form (issue 12).
fn quadratic_membrane_term(scene: &Scene, params: &Params, kf: &[f64]) -> Result<effects::quadratic_membrane::QuadraticMembrane, ModelError> {
    use crate::coefficients::quadratic_membrane::Form;
    let refuse = |reason: &'static str| ModelError::Unsupported { key: "modes.coupling", value: "quadratic".into(), reason };
    let law = effects::quadratic_membrane::QuadraticMembrane::law(law_name(&scene.shell.law))
        .ok_or_else(|| refuse("the second-order membrane loads of this shell.law are not derived"))?;
    let form = match scene.shell.form {
        crate::scene::MembraneForm::Paper => Form::Paper,
        crate::scene::MembraneForm::Tension => Form::Tension,
    };
    effects::quadratic_membrane::QuadraticMembrane::new(law, form, params.r0, params.membrane_args, kf)
        .ok_or_else(|| refuse("the law's second-order table has more prefactors than the runtime term holds"))
}

