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
pub mod sensitivity;
mod radial_fused;
mod assemble;
mod events;
pub mod thermal;
mod executor;
pub(crate) use executor::RunSession;
mod simulate;
pub mod stiffness;
pub mod vorticity;

pub use boundary_layer::BoundaryLayerSystem;
pub use events::{BlowUpEvent, BranchEvent, BranchFractions};
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
    /// The state's offsets (the gas slot with the reduced thermal model).
    layout: layout::StateLayout,
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

    /// The offsets of the integrated state ([`layout::StateLayout`]; the gas slot p_b with
    /// `gas.thermal = "reduced"`).
    pub fn layout(&self) -> layout::StateLayout {
        self.layout
    }

    /// Names of the output row ([`to_si`](Self::to_si)): R, a2, b2, a4, b4, … (and p_b with the
    /// reduced thermal model).
    pub fn state_names(&self) -> Vec<String> {
        let mut v = vec!["R".to_string()];
        for k in &self.orders {
            v.push(format!("a{k}"));
            v.push(format!("b{k}"));
        }
        if self.layout.p_b().is_some() {
            v.push("p_b".to_string());
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
        if self.layout.p_b().is_some() {
            v.push("p_b".to_string());
        }
        v
    }

    /// The output row in SI units: R, a2, b2, a4, b4, … [m] (and p_b [Pa] with the reduced
    /// thermal model).
    pub fn to_si(&self, y: &[f64]) -> Vec<f64> {
        let mut row = vec![0.0; self.state_names().len()];
        self.to_si_into(y, &mut row);
        row
    }

    /// [`to_si`](Self::to_si) into a buffer of length 1 + 2M (+ 1 with p_b).
    pub fn to_si_into(&self, y: &[f64], row: &mut [f64]) {
        let (l, lay) = (self.scales.length, self.layout);
        row[0] = y[lay.r()] * l;
        for m in 0..self.orders.len() {
            row[1 + 2 * m] = y[lay.a(m)] * l;
            row[2 + 2 * m] = y[lay.b(m)] * l;
        }
        if let Some(i) = lay.p_b() {
            row[1 + 2 * self.orders.len()] = y[i] * self.scales.pressure;
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

/// Refuses an analysis that does not handle the reduced thermal model's gas slot p_b
/// (`gas.thermal = "reduced"`, docs/model.md "Reduced thermal model"), naming `gas.thermal`
/// and why (`what`).
pub fn refuse_reduced_thermal(scene: &Scene, what: &'static str) -> Result<(), ModelError> {
    match scene.gas.thermal {
        crate::scene::Thermal::Reduced { .. } => Err(ModelError::Unsupported { key: "gas.thermal", value: "\"reduced\"".into(), reason: what }),
        _ => Ok(()),
    }
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
