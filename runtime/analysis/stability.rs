//! Floquet stability of a driven bubble (paper §4; FORMULATION §4.6, audit 14) and the
//! time-series criterion, for one scene, plus the critical-parameter search of one point of a
//! stability diagram (paper §5.2, figs 5–11). Definitions in docs/stability.md.
//!
//! **Floquet (default, `Variant::Orbit`)**: (1) the periodic radial orbit R(t) with a_k = b_k = 0
//! by shooting ([`periodic::find_orbit`]; a period-m response is detected and reported); (2) the
//! monodromy of the linear (a_k, ȧ_k, b_k) boundary-layer system with the periodic coefficients
//! R(t), Ṙ(t), R̈(t) over the orbit's period ([`floquet::monodromy`]); unstable iff max|μ| > 1.
//! The magnetic forcing ℋ2, ℋ¹2 is inhomogeneous and does not enter (§4.6 step 2).
//!
//! **`Variant::Paper`** (paper §4, for reproduction): R linearised about R0 with the products
//! r·a_k dropped, so the coefficients are those at R = R0, Ṙ = 0, and R̈(t) comes from eq 2.62 at
//! R = R0, Ṙ = 0 with p∞(t) substituted: R̈ = (p_g0 − p∞(t) − Ŝ0(R0) + M0)/(ρR0). This ignores the
//! radial resonance (audit 14).
//!
//! **Closure**: with `modes.viscous = "vorticity"` the shape system is the full model's
//! (a, ȧ, b, T)_k along the same radial orbit ([`super::floquet_full`], issue 13 part 4); the
//! orbit, the multiples and the report are the same as for the boundary layer.
//!
//! **Time series**: the nonlinear boundary-layer model from a seeded shape perturbation over a
//! fixed number of drive periods; see [`series_unstable`].

use super::floquet;
use super::periodic::{self, PeriodicOrbit, ShootingOptions};
use crate::integrate::OdeSystem;
use crate::model::{Model, ModelError};
use super::floquet_full::FullShape;
use crate::model::vorticity::scene::SceneCoupling;
use crate::scene::{Current, Field, Scene, Viscous};
use serde::Serialize;

mod series;
mod systems;
pub use series::{series_period, series_unstable, SeriesOptions, SeriesVerdict, NEEDS_PERIODIC};
pub use systems::Radial;
use systems::{radial_damping_rate, SampledOrbit, ShapeSystem};

/// Errors of a stability computation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StabilityError {
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error("radial orbit: {0}")]
    Orbit(#[from] periodic::PeriodicError),
    #[error("monodromy: {0}")]
    Floquet(#[from] floquet::FloquetError),
    #[error("modes.max_order = 0: a Floquet analysis needs shape modes (set modes.max_order ≥ 2)")]
    NoShapeModes,
    #[error("scene: {0}")]
    Scene(String),
}

/// Which linear periodic system is analysed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Variant {
    /// The periodic radial orbit by shooting (FORMULATION §4.6).
    Orbit,
    /// The paper's §4: R linearised about R0, p∞ substituted into R̈.
    Paper,
}

/// Numerical settings of [`floquet`].
#[derive(Debug, Clone, PartialEq)]
pub struct FloquetOptions {
    pub variant: Variant,
    pub shooting: ShootingOptions,
    /// Transient before the orbit search, in radial decay times 1/γ, γ = −½ ∂R̈/∂Ṙ at (R0, 0)
    /// (= 2ν/R0²: 1/γ ≈ 50 µs at R0 = 10 µm in water). `shooting.transient_periods` is a floor.
    pub transient_decay_times: f64,
    /// Magnus steps per drive period for the monodromy.
    pub magnus_steps: usize,
    /// Also compute the monodromy with 2 × `magnus_steps` and report the difference of max|μ|
    /// ([`FloquetReport::convergence`]).
    pub convergence_check: bool,
    /// Largest denominator q accepted for the ratio of two drive frequencies.
    pub max_denominator: u64,
    pub commensurate_tolerance: f64,
}

impl Default for FloquetOptions {
    fn default() -> Self {
        Self {
            variant: Variant::Orbit,
            shooting: ShootingOptions { transient_periods: 10, steps_per_period: 400, ..ShootingOptions::default() },
            transient_decay_times: 1.0,
            magnus_steps: 400,
            convergence_check: false,
            max_denominator: 1000,
            commensurate_tolerance: 1e-9,
        }
    }
}

/// Tolerance of the convergence estimate: |max|μ|(2n) − max|μ|(n)| above it times
/// max(1, max|μ|) is a warning.
pub const CONVERGENCE_TOLERANCE: f64 = 1e-6;

/// max|μ| with n and 2n Magnus steps per drive period.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Convergence {
    pub steps: usize,
    pub max_multiplier_2x_steps: f64,
    /// |max|μ|(2n) − max|μ|(n)|.
    pub difference: f64,
    pub converged: bool,
}

/// The Floquet verdict on one scene (SI units).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FloquetReport {
    /// The period of the monodromy [s]: the orbit's period (multiple × drive period); one time
    /// scale t* for a scene with nothing periodic (the shape system is then constant).
    pub period_s: f64,
    /// The common period of every drive [s] (acoustic, current, coil distance); `None` (JSON
    /// null) when the scene has no drive (issue 15 class 9: t* is not a drive period).
    pub drive_period_s: Option<f64>,
    /// The radial orbit's minimal period in drive periods (1, 2, 4 …; 1 for the paper variant).
    pub orbit_multiple: usize,
    /// max|μ| over the orbit's period (`period_s`).
    pub max_multiplier: f64,
    /// max|μ|^(1/orbit_multiple): the growth per drive period (per t* without a drive).
    pub max_multiplier_per_drive_period: f64,
    pub unstable: bool,
    /// The shape mode k carrying the largest multiplier (largest share of its eigenvector).
    pub mode: usize,
    /// All multipliers, [re, im].
    pub multipliers: Vec<[f64; 2]>,
    /// Multipliers of the radial orbit itself (DP_m), [re, im]; empty for the paper variant.
    pub radial_multipliers: Vec<[f64; 2]>,
    /// min and max of R(t) over the orbit [m].
    pub r_min_m: f64,
    pub r_max_m: f64,
    /// How the radial orbit was found (transient, flip restart …); "" for the paper variant.
    pub orbit_found_by: String,
    /// Magnus steps per drive period used for `max_multiplier`.
    pub magnus_steps: usize,
    /// Transient before the orbit search [s].
    pub transient_s: f64,
    pub convergence: Option<Convergence>,
    pub variant: Variant,
    /// The viscous closure of the shape system: "boundary-layer" or "vorticity" (issue 13 part 4).
    pub closure: &'static str,
}

/// The boundary-layer model of `scene` whatever its `modes.viscous` says: the radial equation
/// and the loads the full model shares (the closure is chosen in [`prepare`]).
pub fn base_model(scene: &Scene) -> Result<Model, StabilityError> {
    crate::model::refuse_reduced_thermal(scene, "Floquet's radial orbit and A(t) do not carry the reduced model's p_b: use gas.thermal = \"prosperetti\" (its small-amplitude limit)")?;
    if scene.modes.viscous == Viscous::BoundaryLayer {
        return Ok(Model::from_scene(scene)?);
    }
    let mut bl = scene.clone();
    bl.modes.viscous = Viscous::BoundaryLayer;
    Ok(Model::from_scene(&bl)?)
}

/// Frequencies [Hz] of everything periodic in the scene (drive with ε_p ≠ 0, alternating
/// current, oscillating coil distance).
pub fn drive_frequencies(scene: &Scene) -> Vec<f64> {
    let mut f = Vec::new();
    if let Some(d) = scene.drive.as_ref().filter(|d| d.amplitude != 0.0) {
        f.push(d.frequency_hz);
    }
    if let Some(d) = scene.drive.as_ref().filter(|d| d.file.is_none()) {
        f.extend(d.components.iter().filter(|c| c.amplitude != 0.0).map(|c| c.frequency_hz));
    }
    if let Some(Field::Coil(c)) = &scene.field {
        if let Current::Cosine { frequency_hz, .. } = c.current {
            f.push(frequency_hz);
        }
        if let Some(o) = c.distance_oscillation.as_ref().filter(|o| o.amplitude != 0.0) {
            f.push(o.frequency_hz);
        }
    }
    f
}

/// Floquet needs a periodic drive (docs/model.md, "Drives"): a burst, a train or a file is an
/// error pointing at the time-series criterion; a continuous drive's tones must have a common
/// period (ratios p/q with q ≤ `max_denominator` within relative `commensurate_tolerance`).
pub fn periodic_drive(scene: &Scene, opts: &FloquetOptions) -> Result<(), StabilityError> {
    let Some(d) = &scene.drive else { return Ok(()) };
    if let Some(w) = crate::drive::Waveform::from_scene(d, scene.liquid.ambient_pressure) {
        w.periodic_omegas().map_err(|e| StabilityError::Scene(e.to_string()))?;
    }
    for (i, c) in d.components.iter().enumerate().filter(|(_, c)| c.amplitude != 0.0) {
        let pair = [d.frequency_hz, c.frequency_hz];
        if periodic::common_period(&pair, opts.max_denominator, opts.commensurate_tolerance).is_err() {
            return Err(StabilityError::Scene(format!(
                "drive.components[{i}].frequency_hz = {:e} Hz is incommensurate with drive.frequency_hz = {:e} Hz (no ratio p/q with q <= {} within relative {:e}): Floquet needs a common period; use `stability --method series`",
                c.frequency_hz, d.frequency_hz, opts.max_denominator, opts.commensurate_tolerance
            )));
        }
    }
    Ok(())
}

/// Whether `criterion` can be evaluated on `scene` at all (assembled model, shape modes for
/// Floquet, something periodic for the time series): checked once before a sweep, so that a
/// scene the criterion cannot judge is one error, not a CSV of error rows.
pub fn check_scene(scene: &Scene, criterion: Criterion) -> Result<(), StabilityError> {
    check_model(scene, criterion)?;
    if criterion == Criterion::Series && !forced(scene) {
        return Err(StabilityError::Scene(NEEDS_PERIODIC.into()));
    }
    Ok(())
}

/// [`check_scene`] for a search range whose ends are `lo` and `hi`: the time series needs
/// something periodic at one end only, since a point without (ε_p = 0) is watched over the
/// other end's period ([`critical_point`]).
pub fn check_range(lo: &Scene, hi: &Scene, criterion: Criterion) -> Result<(), StabilityError> {
    check_model(lo, criterion)?;
    check_model(hi, criterion)?;
    if criterion == Criterion::Series && !forced(lo) && !forced(hi) {
        return Err(StabilityError::Scene(format!("{NEEDS_PERIODIC} at either end of the range")));
    }
    Ok(())
}

/// Whether something drives the scene for the time-series criterion: a periodic forcing
/// ([`drive_frequencies`]) or a measured waveform (`drive.file`, which the series criterion
/// follows whatever its shape).
fn forced(scene: &Scene) -> bool {
    !drive_frequencies(scene).is_empty() || scene.drive.as_ref().is_some_and(|d| d.file.is_some())
}

fn check_model(scene: &Scene, criterion: Criterion) -> Result<(), StabilityError> {
    let model = base_model(scene)?;
    if criterion == Criterion::Series && scene.modes.viscous == Viscous::Vorticity {
        return Err(StabilityError::Scene(
            "the time-series criterion runs the boundary-layer model only; with modes.viscous = \"vorticity\" use --criterion floquet".into(),
        ));
    }
    match criterion {
        Criterion::Floquet => {
            periodic_drive(scene, &FloquetOptions::default())?;
            model.boundary_layer().map(|_| ()).ok_or(StabilityError::NoShapeModes)
        }
        Criterion::Series => Ok(()),
    }
}

/// The periodic problem behind [`floquet`]: the radial orbit (found once) and the linear shape
/// system along it, so the monodromy can be evaluated at several step counts.
pub struct Prepared<'a> {
    model: &'a Model,
    shape: ShapeSystem<'a>,
    /// `Some`: the full vorticity model's shape system along the same orbit.
    full: Option<FullShape<'a>>,
    /// Orbit period (nondimensional) and its multiple of the drive period.
    period: f64,
    multiple: usize,
    /// `None`: nothing periodic in the scene.
    drive_period_s: Option<f64>,
    radial_multipliers: Vec<[f64; 2]>,
    r_range: (f64, f64),
    found_by: String,
    transient: f64,
    /// The radial orbit (`None` for the paper variant).
    orbit: Option<PeriodicOrbit>,
}

/// Finds the radial orbit of `scene` and sets up its shape system.
pub fn prepare<'a>(model: &'a Model, scene: &Scene, opts: &FloquetOptions) -> Result<Prepared<'a>, StabilityError> {
    prepare_on(model, scene, opts, None)
}

/// [`prepare`] on a radial orbit already found for the same scene and options (the orbit search
/// is deterministic, so the result is the same as [`prepare`]'s; the critical search reuses the
/// orbits of its bracket ends, analysis/critical.rs). `None`: search it.
pub fn prepare_on<'a>(
    model: &'a Model,
    scene: &Scene,
    opts: &FloquetOptions,
    known: Option<&PeriodicOrbit>,
) -> Result<Prepared<'a>, StabilityError> {
    let bl = model.boundary_layer().ok_or(StabilityError::NoShapeModes)?;
    let ts = model.time_scale();
    periodic_drive(scene, opts)?;
    let freqs = drive_frequencies(scene);
    // Nothing periodic: A is constant; report the multipliers over one t*.
    let drive_period_s = if freqs.is_empty() {
        ts
    } else {
        periodic::common_period(&freqs, opts.max_denominator, opts.commensurate_tolerance)?
    };
    let tp = drive_period_s / ts; // nondimensional
    let drive_period_s = (!freqs.is_empty()).then_some(drive_period_s);
    let full = bl.dim();
    let n = full - crate::model::layout::StateLayout::RADIAL; // the shape part x
    let full_shape = match scene.modes.viscous {
        Viscous::BoundaryLayer => None,
        Viscous::Vorticity => {
            let v = &scene.vorticity;
            let grid = crate::model::vorticity::Grid::new(v.y_max, v.points, v.stretching)
                .map_err(|e| StabilityError::Scene(format!("vorticity grid: {e}")))?;
            // linear (issue 12): Floquet linearises about a = 0 without the second-pass terms
            let coupling = SceneCoupling::of(model).ok_or(StabilityError::NoShapeModes)?.linear();
            Some(FullShape { coupling, grid, coupled: bl.jacobian_pattern().band > 0 })
        }
    };
    match opts.variant {
        Variant::Orbit => {
            let radial = Radial::new(bl, full);
            let y0 = &model.initial_state()[..2];
            let gamma = radial_damping_rate(&radial);
            let mut shooting = opts.shooting.clone();
            if gamma.is_finite() && gamma > 0.0 {
                shooting.transient_time = opts.transient_decay_times / gamma;
            }
            // a kinked law: its branch switches located in the orbit's steps and the Magnus steps
            // (docs/stability.md, "Floquet on a kinked law")
            let switching: Option<&dyn periodic::Switching> = (!model.branch_events().is_empty()).then_some(model);
            let orbit = match known {
                Some(o) => o.clone(),
                None => periodic::find_orbit_switched(&radial, switching, 0.0, y0, tp, &shooting)?,
            };
            let sampled = SampledOrbit::new(&radial, switching, &orbit, shooting.steps_per_period)?;
            let branches = sampled.branch_times().zip(switching);
            let r_range = sampled.y.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| (lo.min(y[0]), hi.max(y[0])));
            let transient = (shooting.transient_periods as f64 * tp).max((shooting.transient_time / tp).ceil() * tp);
            let f = move |t: f64| {
                let (r, rd) = sampled.at(t);
                let rdd = radial.at_rest_shape(&[r, rd], |z| bl.radial_acceleration(t, z)).unwrap_or(f64::NAN);
                (r, rd, rdd)
            };
            let mut shape = ShapeSystem::new(bl, n, Box::new(f));
            if let Some((times, sw)) = branches {
                shape = shape.on_branches(sw, times);
            }
            Ok(Prepared {
                model,
                shape,
                full: full_shape,
                period: orbit.period(),
                multiple: orbit.multiple,
                drive_period_s,
                radial_multipliers: orbit.multipliers.iter().map(|z| [z.re, z.im]).collect(),
                r_range,
                found_by: orbit.found_by.clone(),
                transient,
                orbit: Some(orbit),
            })
        }
        Variant::Paper => {
            let zeros = vec![0.0; full];
            let f = move |t: f64| {
                let mut z = zeros.clone();
                z[0] = 1.0;
                (1.0, 0.0, bl.radial_acceleration(t, &z))
            };
            Ok(Prepared {
                model,
                shape: ShapeSystem::new(bl, n, Box::new(f)),
                full: full_shape,
                period: tp,
                multiple: 1,
                drive_period_s,
                radial_multipliers: Vec::new(),
                r_range: (1.0, 1.0),
                found_by: String::new(),
                transient: 0.0,
                orbit: None,
            })
        }
    }
}

impl Prepared<'_> {
    /// The monodromy's spectrum with `steps` Magnus steps per drive period.
    pub fn spectrum(&self, steps: usize) -> Result<floquet::Spectrum, StabilityError> {
        let steps = steps.max(1) * self.multiple;
        match &self.full {
            None => {
                let mut mono = floquet::monodromy(&self.shape, 0.0, self.period, steps)?;
                if self.shape.b_free() {
                    // the neutral b_k blocks of a free bubble are not part of the verdict (ShapeSystem::b_free)
                    use crate::model::layout::StateLayout;
                    let is_b = |i: usize| StateLayout::x_entry(i) == StateLayout::B;
                    let keep: Vec<bool> = mono.blocks.iter().map(|b| !(b.len() == 1 && is_b(b[0]))).collect();
                    let mut k = keep.iter();
                    mono.blocks.retain(|_| *k.next().unwrap());
                    let mut k = keep.iter();
                    mono.matrices.retain(|_| *k.next().unwrap());
                }
                Ok(mono.spectrum())
            }
            Some(full) => {
                let radial = |t: f64| {
                    let (r, rd, _) = (self.shape.radial)(t);
                    (r, rd)
                };
                use super::floquet::LinearPeriodic;
                let breaks = self.shape.breaks();
                let on_branch = |t: f64, f: &mut dyn FnMut()| {
                    let _on = self.shape.enter(t);
                    f()
                };
                let orbit = super::floquet_full::Orbit { radial: &radial, breaks: &breaks, on_branch: &on_branch };
                Ok(full.monodromy_on(&orbit, 0.0, self.period, steps)?.spectrum())
            }
        }
    }

    /// The radial orbit the shape system runs along (`None` for the paper variant).
    pub fn orbit(&self) -> Option<&PeriodicOrbit> {
        self.orbit.as_ref()
    }

    /// The orbit's minimal period in drive periods.
    pub fn multiple(&self) -> usize {
        self.multiple
    }

    /// The report of a spectrum computed with `steps` (see [`floquet`]).
    pub fn report(&self, spec: &floquet::Spectrum, steps: usize, convergence: Option<Convergence>, variant: Variant) -> FloquetReport {
        let ts = self.model.time_scale();
        let length = self.model.scales().length;
        // Mode: the k whose (a, ȧ, b) components hold the largest share of the critical eigenvector.
        let orders = self.model.orders();
        let stride = self.full.as_ref().map_or(3, |f| f.block_len());
        let mut share = vec![0.0; orders.len()];
        for &(i, w) in &spec.components {
            share[i / stride] += w;
        }
        let m = share.iter().enumerate().fold(0, |b, (i, &w)| if w > share[b] { i } else { b });
        FloquetReport {
            period_s: self.period * ts,
            drive_period_s: self.drive_period_s,
            orbit_multiple: self.multiple,
            max_multiplier: spec.max_modulus,
            max_multiplier_per_drive_period: spec.max_modulus.powf(1.0 / self.multiple as f64),
            unstable: spec.max_modulus > 1.0,
            mode: orders[m],
            multipliers: spec.multipliers.iter().map(|z| [z.re, z.im]).collect(),
            radial_multipliers: self.radial_multipliers.clone(),
            r_min_m: self.r_range.0 * length,
            r_max_m: self.r_range.1 * length,
            orbit_found_by: self.found_by.clone(),
            magnus_steps: steps,
            transient_s: self.transient * ts,
            convergence,
            variant,
            closure: if self.full.is_some() { "vorticity" } else { "boundary-layer" },
        }
    }
}

/// Floquet analysis of `scene` (see the module doc).
pub fn floquet(scene: &Scene, opts: &FloquetOptions) -> Result<FloquetReport, StabilityError> {
    let model = base_model(scene)?;
    let prep = prepare(&model, scene, opts)?;
    let spec = prep.spectrum(opts.magnus_steps)?;
    let convergence = if opts.convergence_check {
        let fine = prep.spectrum(2 * opts.magnus_steps.max(1))?;
        let difference = (fine.max_modulus - spec.max_modulus).abs();
        Some(Convergence {
            steps: opts.magnus_steps,
            max_multiplier_2x_steps: fine.max_modulus,
            difference,
            converged: difference <= CONVERGENCE_TOLERANCE * spec.max_modulus.max(1.0),
        })
    } else {
        None
    };
    Ok(prep.report(&spec, opts.magnus_steps, convergence, opts.variant))
}

/// Which stability criterion a diagram uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Criterion {
    Floquet,
    Series,
}

pub use super::critical::{critical_point, varied_param, CriticalOptions, CriticalPoint, CRITICAL_HEADER};
