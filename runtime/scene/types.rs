//! The validated scene: every value resolved (defaults applied), in SI units, and checked.
//!
//! This is the contract between the scene parser (`scene::raw` → `TryFrom`) and the model.
//! Defaults are those of FORMULATION.md (table "Conventions that the paper leaves open").

use serde::Serialize;
use std::collections::BTreeMap;

pub use super::drive::{Component, Drive, DriveFile, Echo, Envelope};

/// A fully resolved, validated scene. Construct it with `Scene::try_from(RawScene)`
/// (see `scene::parse`), never by hand outside tests.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scene {
    pub bubble: Bubble,
    pub shell: Shell,
    pub gas: Gas,
    pub liquid: Liquid,
    /// `None`: p∞ = p0 (no acoustic drive).
    pub drive: Option<Drive>,
    /// `None`: no magnetic field (no magnetic term is assembled).
    pub field: Option<Field>,
    pub modes: Modes,
    pub vorticity: VorticityGrid,
    pub run: Run,
    /// Keys that do nothing and values at the edge of a model's validity (issue 29 item 10):
    /// one sentence each, naming the key; the commands print them.
    #[serde(skip)]
    pub warnings: Vec<String>,
    /// `None`: no echo recorded.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub echo: Option<Echo>,
    /// `None`: a single bubble (no `[population]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub population: Option<Population>,
}

/// `[population]`: a size distribution resolved into its bins (docs/population.md).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Population {
    pub distribution: Distribution,
    /// The quadrature nodes: radius [m] and weight (the weights sum to 1).
    pub bins: Vec<PopulationBin>,
    /// Bubbles per millilitre (`None`: not given; `attenuation` needs it).
    pub concentration_per_ml: Option<f64>,
    /// Numeric scene keys scaled ∝ the bin's radius.
    pub scale_with_radius: Vec<String>,
}

/// `population.distribution`.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Distribution {
    Lognormal { median_radius: f64, geometric_std: f64 },
    File { path: std::path::PathBuf },
}

/// One bin of a population.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PopulationBin {
    pub radius: f64,
    pub weight: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Bubble {
    /// R0 [m], the reference (natural) radius.
    pub radius: f64,
    pub initial: Initial,
}

/// Initial state. Default: at rest, R = R0, a_k = b_k = 0.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Initial {
    /// R(0) [m]
    pub radius: f64,
    /// Ṙ(0) [m/s]
    pub velocity: f64,
    /// a_k(0) [m], keyed by k (even, 2 ≤ k ≤ max_order)
    pub a: BTreeMap<usize, f64>,
    /// ȧ_k(0) [m/s]
    pub a_velocity: BTreeMap<usize, f64>,
    /// b_k(0) [m]
    pub b: BTreeMap<usize, f64>,
    /// How the shape modes not set in `a` start (`bubble.initial.seed`).
    pub seed: Seed,
}

/// `bubble.initial.seed`: how the shape modes start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Seed {
    /// As `bubble.initial.a`, `b` give them (unset: 0).
    #[default]
    Given,
    /// Every a_k not set in `a`: its equipartition amplitude √(k_B T/K_k) (docs/model.md,
    /// "Thermal seed"; [`crate::model::thermal`]).
    Thermal,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MembraneForm {
    /// Divergence of the Cauchy stress (eqs 2.26–2.29), the paper's form. Default.
    Paper,
    /// Divergence of the tension εσ/α (FORMULATION §2, audit 9): adds ΔS¹₁, ΔS¹₂ ∝ σ̂0.
    Tension,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Shell {
    /// c1 = ε C1 [N/m]
    pub c1: f64,
    /// c2 = ε C2 [N/m]
    pub c2: f64,
    /// ε [m]
    pub thickness: f64,
    /// χ (dimensionless); χ_s = ε χ [m] enters the loads.
    pub susceptibility: f64,
    pub form: MembraneForm,
    /// The elastic law (`shell.law`, issue 11). Mooney–Rivlin (c1, c2) by default.
    #[serde(skip_serializing_if = "ShellLaw::is_mooney_rivlin")]
    pub law: ShellLaw,
    /// k_b [J]: Helfrich bending stiffness (0 = off).
    #[serde(skip_serializing_if = "is_zero")]
    pub bending_modulus: f64,
    /// μ_s [Pa s m]: surface shear viscosity (0 = off).
    #[serde(skip_serializing_if = "is_zero")]
    pub shear_viscosity: f64,
    /// κ_s [kg/s]: surface dilatational viscosity (0 = off).
    #[serde(skip_serializing_if = "is_zero")]
    pub dilatational_viscosity: f64,
    /// γ [N/m]: isotropic surface tension (0 = off).
    #[serde(skip_serializing_if = "is_zero")]
    pub surface_tension: f64,
}

impl Shell {
    /// A Mooney–Rivlin shell with no other shell effect (hand-built scenes, tests).
    pub fn mooney_rivlin(c1: f64, c2: f64, thickness: f64, susceptibility: f64, form: MembraneForm) -> Self {
        Shell {
            c1,
            c2,
            thickness,
            susceptibility,
            form,
            law: ShellLaw::MooneyRivlin,
            bending_modulus: 0.0,
            shear_viscosity: 0.0,
            dilatational_viscosity: 0.0,
            surface_tension: 0.0,
        }
    }
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// The elastic law of the shell (derivations/shell/, `shell.law`).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case", tag = "name")]
pub enum ShellLaw {
    /// Eq 2.24 with `shell.c1`, `shell.c2`.
    MooneyRivlin,
    /// Skalak et al. 1973: W = (G_s/4)[I1² + 2I1 − 2I2 + C I2²].
    Skalak {
        /// G_s [N/m]
        shear_modulus: f64,
        /// C [–]; small strain: K = G_s(1 + 2C).
        area_dilatation: f64,
    },
    /// Marmottant et al. 2005, buckled / elastic / ruptured (docs/model.md, "Lipid shells").
    Marmottant(Lipid),
    /// The same with a smooth tension of width `smoothing`.
    MarmottantSmooth(Lipid),
    /// Paul, Katiyar, Sarkar, Chatterjee, Shi & Forsberg 2010, the exponential elasticity model
    /// (docs/model.md, "Lipid shells: Sarkar").
    Sarkar(Sarkar),
    /// Church 1995 in Hoff et al. 2000's thin-shell form: radial only (docs/model.md,
    /// "Shells: Church–Hoff").
    ChurchHoff {
        /// G_s [Pa], the shell material's shear modulus
        modulus: f64,
        /// η_s [Pa s]
        viscosity: f64,
    },
    /// A measured tension σ(A/A0) (`shell.tension_file`), monotone PCHIP between its knots
    /// (docs/model.md, "Lipid shells: tension curve").
    TensionCurve(TensionCurve),
}

/// The knots of a measured tension curve, checked (scene/validate/tension_curve.rs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TensionCurve {
    /// The CSV read.
    pub file: String,
    /// A/A0 [–], strictly increasing.
    pub area_ratio: Vec<f64>,
    /// σ [N/m], non-decreasing.
    pub tension: Vec<f64>,
}

/// The constants of the exponential elasticity model, resolved.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Sarkar {
    /// E0^s [N/m]
    pub elasticity: f64,
    /// α^s [–]
    pub elasticity_decay: f64,
    /// γ0 [N/m]
    pub reference_tension: f64,
    /// R_E [m]: the unstrained radius, where the net tension γ0 + E^s β vanishes at R0
    pub unstrained_radius: f64,
}

/// The constants of a Marmottant shell, resolved (R_b and σ(R0) both, from whichever was given).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Lipid {
    /// χ [N/m]
    pub elasticity: f64,
    /// R_b [m]
    pub buckling_radius: f64,
    /// σ(R0) [N/m] of the kinked law
    pub initial_tension: f64,
    /// σ_r [N/m]
    pub rupture_tension: f64,
    /// s [N/m] (marmottant-smooth only)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub smoothing: Option<f64>,
}

impl ShellLaw {
    pub fn is_mooney_rivlin(&self) -> bool {
        matches!(self, ShellLaw::MooneyRivlin)
    }
    /// An isotropic area-only law (Marmottant, Sarkar): it replaces the Mooney–Rivlin membrane
    /// (runtime/model/effects/lipid.rs).
    pub fn is_area_law(&self) -> bool {
        matches!(self, ShellLaw::Marmottant(_) | ShellLaw::MarmottantSmooth(_) | ShellLaw::Sarkar(_) | ShellLaw::TensionCurve(_))
    }
    /// A law with its own term in place of the Mooney–Rivlin membrane (an area law, Church–Hoff).
    pub fn replaces_membrane(&self) -> bool {
        self.is_area_law() || matches!(self, ShellLaw::ChurchHoff { .. })
    }
    /// The Marmottant constants, for either Marmottant law.
    pub fn lipid(&self) -> Option<&Lipid> {
        match self {
            ShellLaw::Marmottant(l) | ShellLaw::MarmottantSmooth(l) => Some(l),
            _ => None,
        }
    }
}

impl Shell {
    /// c1 = c2 = 0: a free gas bubble, no membrane term (issue 10).
    pub fn is_free(&self) -> bool {
        self.c1 == 0.0 && self.c2 == 0.0
    }
}

/// t* [s] (FORMULATION §4.5): √(ρR0³/(2c1)) with a membrane; R0 √(ρ/p0) for a free bubble
/// (c1 = 0), whose only stiffness scale is the liquid's (docs/model.md, "A free gas bubble").
pub fn time_scale(liquid: &Liquid, r0: f64, shell: &Shell) -> f64 {
    if shell.c1 == 0.0 {
        r0 * (liquid.density / liquid.ambient_pressure).sqrt()
    } else {
        (liquid.density * r0.powi(3) / (2.0 * shell.c1)).sqrt()
    }
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Gas {
    /// κ: p_in = p_g0 (R0/R)^{3κ}
    pub polytropic_exponent: f64,
    /// p_g0 [Pa]: the given `gas.reference_pressure`, or the equilibrium rule
    /// p0 − p_v + 2γ/R0 (+ the membrane prestress Ŝ0(R0), zero for the shipped laws, whose
    /// unstressed radius is R0; the model adds it: `Groups::p_g0_pa` is the value used).
    pub reference_pressure: f64,
    /// Whether `gas.reference_pressure` was given (an override of the equilibrium rule).
    pub reference_pressure_given: bool,
    /// p_v [Pa], 0 = no vapour term.
    pub vapour_pressure: f64,
    /// `gas.thermal` (issue 31 part 2): the polytropic law alone (default; not written into
    /// summary.json, which keeps its bytes), Prosperetti's linear thermal damping or the reduced
    /// heat-transfer model.
    #[serde(skip_serializing_if = "Thermal::is_polytropic")]
    pub thermal: Thermal,
}

/// The gas's heat exchange (`gas.thermal`; docs/model.md, "Thermal damping").
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default)]
#[serde(rename_all = "kebab-case", tag = "name")]
pub enum Thermal {
    /// p_in = p_g0 (R0/R)^{3κ} with `gas.polytropic_exponent`.
    #[default]
    Polytropic,
    /// Prosperetti 1977's linear theory at one frequency: κ_eff(ω) and −4μ_th(ω)Ṙ/R
    /// (runtime/model/effects/thermal_damping.rs).
    Prosperetti {
        /// D [m²/s], `gas.thermal_diffusivity`
        thermal_diffusivity: f64,
        /// γ, `gas.heat_capacity_ratio`
        heat_capacity_ratio: f64,
    },
    /// The reduced heat-transfer model of Preston, Colonius & Brennen 2007: p_b a state
    /// variable (runtime/model/effects/reduced_gas.rs); radial only.
    Reduced {
        /// D [m²/s], `gas.thermal_diffusivity`
        thermal_diffusivity: f64,
        /// γ, `gas.heat_capacity_ratio`
        heat_capacity_ratio: f64,
    },
}

impl Thermal {
    pub fn is_polytropic(&self) -> bool {
        *self == Thermal::Polytropic
    }
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Liquid {
    /// ρ [kg/m³]
    pub density: f64,
    /// η [Pa s]
    pub viscosity: f64,
    /// p0 [Pa]
    pub ambient_pressure: f64,
    /// c [m/s]: `Some` → Keller–Miksis radial equation; `None` → incompressible (eq 2.62).
    pub sound_speed: Option<f64>,
    /// T [K]: the thermal seed's temperature (`liquid.temperature`).
    pub temperature: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Field {
    Coil(Coil),
    Dipole(Dipole),
}

/// Two opposed coils (eqs 2.30–2.33), H_2n = −(I/a) N1 sin θc P¹_2n(cos θc) (2.31).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Coil {
    /// N1
    pub turns: f64,
    /// a [m] (mean distance when it oscillates)
    pub distance: f64,
    /// θc [rad]; default acos(sqrt(3/7)), the positive root of P¹_4, so H_4 = 0.
    pub angle: f64,
    pub current: Current,
    /// a(t) = a (1 + β cos 2π f3 t)
    pub distance_oscillation: Option<Oscillation>,
    /// Keep the H_4 term of the Boridy expansion (only matters when θc is not a root of P¹_4).
    pub include_h4: bool,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Current {
    /// I [A]
    Static { value: f64 },
    /// I(t) = I0 cos(2π f2 t)
    Cosine { amplitude: f64, frequency_hz: f64 },
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Oscillation {
    /// β (dimensionless, small)
    pub amplitude: f64,
    pub frequency_hz: f64,
}

/// Two dipoles placed symmetrically (eqs 2.34–2.38).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Dipole {
    /// M [A m²]
    pub moment: f64,
    /// z [m]
    pub distance: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Viscous {
    /// FORMULATION §4.3: J_k ≈ 0, Ĩ_k ≈ δ_k T_w / R.
    BoundaryLayer,
    /// FORMULATION §4.2: the toroidal-vorticity PDE per mode.
    Vorticity,
}

/// Which frequency sets the boundary-layer thickness δ_k = min(√(ν/ω), R/(2k)) (audit 13).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BoundaryLayerFrequency {
    /// ω = ω_d when driven, ω_k otherwise (the default).
    Auto,
    /// ω = ω_k (natural frequency of mode k) always.
    Natural,
}

/// Order of the shape-mode equations in the amplitudes (issue 12).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Coupling {
    /// The linear mode equations (the paper's; the default).
    Linear,
    /// Plus the second-order (quadratic) mode coupling of a free bubble (docs/model.md).
    Quadratic,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Modes {
    /// Largest even shape mode N; 0 = radial only. Modes are k = 2, 4, …, N.
    pub max_order: usize,
    pub viscous: Viscous,
    pub boundary_layer_frequency: BoundaryLayerFrequency,
    pub coupling: Coupling,
    /// Quadratic coupling: the run stops as `out_of_credible_range` when max_k |a_k|/R0 exceeds
    /// this (issue 12; default 0.1).
    pub credible_amplitude: f64,
}

impl Modes {
    /// The simulated shape modes k = 2, 4, …, N.
    pub fn orders(&self) -> impl Iterator<Item = usize> {
        (2..=self.max_order).step_by(2)
    }
    /// M = N/2, the number of shape modes.
    pub fn count(&self) -> usize {
        self.max_order / 2
    }
}

/// The radial grid of the vorticity PDE, y = r/R ∈ [1, Y_max] (FORMULATION §4.2).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VorticityGrid {
    pub y_max: f64,
    /// Number of grid points including both ends.
    pub points: usize,
    /// Ratio of the last to the first spacing (1 = uniform; > 1 clusters at the wall).
    pub stretching: f64,
    /// `staggered` (the paper's §5 scheme) or `monolithic` (method of lines, implicit).
    pub scheme: VorticityScheme,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum VorticityScheme {
    Staggered,
    Monolithic,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Chosen per run from a stiffness estimate at the initial state (the default; issue 34,
    /// `model::stiffness`): DOP853 when non-stiff, Radau5 when stiff.
    Auto,
    /// Classical fixed-step RK4 (the paper's).
    Rk4,
    /// Dormand–Prince 5(4), adaptive.
    Dopri5,
    /// Dormand–Prince 8(5,3), adaptive.
    Dop853,
    /// Radau IIA, 3 stages, order 5, implicit (stiff).
    Radau5,
    /// Rosenbrock ode23s (Shampine & Reichelt), order 2, linearly implicit (stiff).
    Rosenbrock23,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IntegratorSettings {
    pub method: Method,
    pub rtol: f64,
    pub atol: f64,
    /// Fixed step Δt [s] for RK4 (and the staggered vorticity scheme); initial step hint otherwise.
    pub dt: f64,
    /// Whether the scene gave `run.integrator.dt` (otherwise RK4 takes a stable default from
    /// the spectral radius, `model::stiffness`).
    pub dt_given: bool,
    /// Hard cap on the number of steps (a run that needs more fails with a clear reason).
    pub max_steps: u64,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Run {
    /// [s]
    pub duration: f64,
    /// Output sampling interval [s].
    pub sample_interval: f64,
    pub integrator: IntegratorSettings,
    /// A run is classified `blow_up` when max_k |a_k|/R0 or |b_k|/R0 exceeds this (or R leaves (0, ∞)).
    pub blow_up_threshold: f64,
    /// Largest estimated size of series.csv [bytes] (checked by validation, `scene::derived`).
    pub max_output_bytes: f64,
}
