//! The equations as an [`OdeSystem`](crate::integrate::OdeSystem), assembled from a [`Scene`]
//! with only the effects it calls for (issue 3, parts 2–3):
//!
//! * no field → no magnetic term is assembled or evaluated ([`Model::magnetic_evaluations`] = 0);
//! * `max_order = 0` → the two-state radial equation alone ([`RadialSystem`]);
//! * no drive (absent or ε_p = 0) → p∞ = p0, no drive term;
//! * static current, fixed distance → the magnetic time factor is computed once.
//!
//! The scene is nondimensionalized once, here ([`params`], FORMULATION §4.5); the integrators
//! see plain numbers. Equations: [`radial`] (FORMULATION §4.1) and [`boundary_layer`] (§4.3).
//! [`simulate`] runs a scene and reports a [`RunReport`].

pub mod blow_up;
pub mod boundary_layer;
pub mod dispersion;
pub mod effects;
pub mod equations;
pub mod keller_miksis;
pub mod layout;
pub mod linearize;
pub mod natural;
mod material;
pub mod params;
pub mod radial;
mod events;
pub mod thermal;
mod executor;
pub(crate) use executor::RunSession;
mod simulate;
pub mod stiffness;
pub mod vorticity;

pub use boundary_layer::BoundaryLayerSystem;
pub use events::{BlowUpEvent, BranchEvent, BranchFractions, BRANCH_TOLERANCE};
pub use equations::Equations;
pub use linearize::JacobianPattern;
pub use params::{Groups, Params, Scales};
pub use radial::{RadialForm, RadialSystem};
pub use stiffness::IntegratorChoice;
pub use simulate::{method_of, simulate, Failure, Row, RunReport, RunStatus};

use crate::coefficients::KMAX;
use crate::field::{loads::MagneticLoads, FieldError, FieldSource};
use effects::Term;
use crate::integrate::OdeSystem;
use crate::scene::{BoundaryLayerFrequency, Coupling, Scene, Viscous};
use boundary_layer::ModeConst;

/// Errors assembling a model from a (validated) scene.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    #[error(transparent)]
    Field(#[from] FieldError),
    #[error("modes.max_order = {max_order}: the generated tables stop at k = {kmax} (rebuild with MAGBUBBLE_KMAX)")]
    TooManyModes { max_order: usize, kmax: usize },
    /// The full vorticity model could not be assembled (grid or scene error).
    #[error("full vorticity model: {0}")]
    FullModel(String),
    #[error("{key} = {value}: {reason}")]
    Unsupported { key: &'static str, value: String, reason: &'static str },
    #[error("bubble.initial.seed = \"thermal\": {0}")]
    Seed(String),
}

/// The assembled system: exactly the terms the scene needs.
#[derive(Debug)]
pub enum System {
    Radial(RadialSystem),
    BoundaryLayer(BoundaryLayerSystem),
}

/// A scene turned into equations, with its scales, initial state and bookkeeping.
#[derive(Debug)]
pub struct Model {
    scales: Scales,
    system: System,
    orders: Vec<usize>,
    y0: Vec<f64>,
    groups: Groups,
    effects: Vec<String>,
    blow_up_threshold: f64,
    /// `modes.credible_amplitude` when the quadratic coupling is assembled (issue 12).
    credible: Option<f64>,
    /// The drive p_a(t) (model units), when the scene has one.
    wave: Option<crate::drive::Waveform>,
    /// `run.duration` (model units).
    t_end: f64,
    /// The kinked Marmottant law (issue 31), whose branch switches are events of a run, and the
    /// time a run spends on each branch (model/events.rs).
    kinked: Option<(effects::lipid::LipidLaw, std::sync::Mutex<events::BranchClock>)>,
    /// The drive's piece being integrated, shared with the drive term ([`Model::enter_piece`]).
    piece: crate::drive::Piece,
}

impl Model {
    pub fn from_scene(scene: &Scene) -> Result<Model, ModelError> {
        let scales = Scales::from_scene(scene);
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
        let piece = crate::drive::Piece::default();
        terms.push(Box::new(effects::drive::FarField { p0: params.p0, wave: wave.clone(), piece: piece.clone() }));
        terms.push(Box::new(effects::viscosity::LiquidViscosity { eta: params.eta }));
        // issue 31 part 2: Prosperetti's thermal damping (its μ_th once the stiffness is known)
        let thermal_at = (!scene.gas.thermal.is_polytropic()).then(|| {
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
            let z = vec![1.0; layout::StateLayout::reduced(orders.len()).dim()];
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
            System::Radial(RadialSystem { eq })
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
            let mut bl = BoundaryLayerSystem { bdot_radial: eq.needs_bdot(), bdot_loads: eq.has_bdot_loads(), eq, modes, shape_weights: Vec::new() };
            let forced = thermal::static_response(&bl);
            bl.shape_weights = thermal::weights(scene, thermal_seed.as_ref(), scales.time, &forced);
            System::BoundaryLayer(bl)
        };
        effects.extend(self_labels(eq_of(&system)));

        let lay = layout::StateLayout::reduced(orders.len());
        let mut y0 = vec![0.0; lay.dim()];
        y0[lay.r()] = scene.bubble.initial.radius / scales.length;
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
        Ok(Model { scales, system, orders, y0, groups, effects, blow_up_threshold: scene.run.blow_up_threshold, credible, wave, t_end, kinked, piece })
    }

    /// The equations, as the integrators see them.
    pub fn system(&self) -> &dyn OdeSystem {
        match &self.system {
            System::Radial(s) => s,
            System::BoundaryLayer(s) => s,
        }
    }

    /// The assembled system (for analyses that need more than `OdeSystem`).
    pub fn assembled(&self) -> &System {
        &self.system
    }

    /// The boundary-layer system, if the scene has shape modes (for the linear analyses:
    /// [`BoundaryLayerSystem::linear_modes`], the exact A(t)).
    pub fn boundary_layer(&self) -> Option<&BoundaryLayerSystem> {
        match &self.system {
            System::BoundaryLayer(s) => Some(s),
            System::Radial(_) => None,
        }
    }

    pub fn params(&self) -> &Params {
        &self.equations().params
    }

    /// The assembled terms and radial form.
    pub fn equations(&self) -> &Equations {
        match &self.system {
            System::Radial(s) => &s.eq,
            System::BoundaryLayer(s) => &s.eq,
        }
    }

    /// Nondimensional initial state.
    pub fn initial_state(&self) -> &[f64] {
        &self.y0
    }

    /// t* [s]: nondimensional time × t* = seconds.
    pub fn time_scale(&self) -> f64 {
        self.scales.time
    }

    pub fn scales(&self) -> &Scales {
        &self.scales
    }

    /// The drive p_a(t) in model units (p̄, t/t*), when the scene has one (docs/model.md, "Drives").
    pub fn drive(&self) -> Option<&crate::drive::Waveform> {
        self.wave.as_ref()
    }

    /// The known discontinuity times of a run (model units, sorted, inside (0, run.duration)):
    /// the drive's burst edges and file knots, where p∞ or dp∞/dt jumps
    /// ([`crate::drive::Waveform::stop_times`]). No step crosses one: the run loop
    /// ([`crate::integrate::run_loop`]) lands on it and restarts the stepper there; empty for a
    /// continuous drive.
    pub fn stop_times(&self) -> Vec<f64> {
        self.wave.as_ref().map_or_else(Vec::new, |w| w.stop_times(0.0, self.t_end))
    }

    /// A run now integrates the drive's piece [from, to] (model units): the run's start or a
    /// stop time ([`Model::stop_times`]) to the next stop time or the run's end; the drive term
    /// evaluates p_a on that piece, its ends included (docs/model.md, "Drives"). `None`: no
    /// run, p_a decided from t. The run executor calls it; a caller driving the run loop itself
    /// must too.
    pub fn enter_piece(&self, piece: Option<(f64, f64)>) {
        match piece {
            Some((from, to)) => self.piece.enter(from, to),
            None => self.piece.clear(),
        }
    }

    /// The simulated shape orders k = 2, 4, …, N.
    pub fn orders(&self) -> &[usize] {
        &self.orders
    }

    /// Names of the output row ([`to_si`](Self::to_si)): R, a2, b2, a4, b4, …
    pub fn state_names(&self) -> Vec<String> {
        let mut v = vec!["R".to_string()];
        for k in &self.orders {
            v.push(format!("a{k}"));
            v.push(format!("b{k}"));
        }
        v
    }

    /// Names of the full (integrated) state: R, Rdot, a2, a2dot, b2, …
    pub fn full_state_names(&self) -> Vec<String> {
        let mut v = vec!["R".to_string(), "Rdot".to_string()];
        for k in &self.orders {
            v.push(format!("a{k}"));
            v.push(format!("a{k}dot"));
            v.push(format!("b{k}"));
        }
        v
    }

    /// The output row in SI units [m]: R, a2, b2, a4, b4, …
    pub fn to_si(&self, y: &[f64]) -> Vec<f64> {
        let mut row = vec![0.0; 1 + 2 * self.orders.len()];
        self.to_si_into(y, &mut row);
        row
    }

    /// [`to_si`](Self::to_si) into a buffer of length 1 + 2M.
    pub fn to_si_into(&self, y: &[f64], row: &mut [f64]) {
        let (l, lay) = (self.scales.length, layout::StateLayout::reduced(self.orders.len()));
        row[0] = y[lay.r()] * l;
        for m in 0..self.orders.len() {
            row[1 + 2 * m] = y[lay.a(m)] * l;
            row[2 + 2 * m] = y[lay.b(m)] * l;
        }
    }

    /// What the assembled system contains, e.g. "radial", "shape modes k=2..16 (boundary layer)",
    /// "acoustic drive", "coil field (static current)".
    pub fn active_effects(&self) -> Vec<String> {
        self.effects.clone()
    }

    pub fn groups(&self) -> Groups {
        self.groups.clone()
    }

    /// Number of magnetic-load evaluations so far (0 when the scene has no field).
    pub fn magnetic_evaluations(&self) -> u64 {
        self.equations().evaluations("magnetic")
    }

    /// The blow-up classifier ([`blow_up::classify`]) at this scene's threshold.
    pub fn blow_up(&self, y: &[f64]) -> Option<String> {
        blow_up::classify(y, &self.orders, self.blow_up_threshold)
    }

    /// The stop event function: the blow-up's ([`blow_up::margin`]) at this scene's threshold
    /// and, for a quadratic run, the credible range's ([`blow_up::range_margin`]); a run stops
    /// where it turns positive ([`stop_status`](Self::stop_status) says why).
    pub fn blow_up_margin(&self, y: &[f64]) -> f64 {
        let g = blow_up::margin(y, &self.orders, self.blow_up_threshold);
        match self.credible {
            Some(b) => g.max(blow_up::range_margin(y, &self.orders, b)),
            None => g,
        }
    }

    /// Why a run stops at state y (nondimensional) and time t [s]: a blow-up if the classifier
    /// finds one, otherwise a quadratic run's amplitude out of the credible range.
    pub fn stop_status(&self, t: f64, y: &[f64]) -> RunStatus {
        if let Some(mode) = self.blow_up(y) {
            return RunStatus::BlowUp { t, mode };
        }
        match self.credible.and_then(|b| blow_up::out_of_range(y, &self.orders, b).map(|m| (b, m))) {
            Some((bound, mode)) => RunStatus::OutOfCredibleRange { t, mode, bound },
            None => RunStatus::BlowUp { t, mode: "R".into() },
        }
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

fn eq_of(system: &System) -> &Equations {
    match system {
        System::Radial(s) => &s.eq,
        System::BoundaryLayer(s) => &s.eq,
    }
}

/// The active-effect labels of the assembled terms, in order (e.g. "acoustic drive", the field).
fn self_labels(eq: &Equations) -> Vec<String> {
    eq.labels()
}
