//! The full model assembled from a scene (`modes.viscous = "vorticity"`): the radial equation,
//! membrane and magnetic loads come from the boundary-layer model of the same scene (its
//! nondimensional parameters, FORMULATION §4.5), the viscous closure is replaced by the
//! vorticity PDE on the scene's grid, integrated by the scene's `vorticity.scheme`.

use super::implicit::{integrate, ImplicitSettings};
use super::linear::{damped_spectrum_boundary_layer, damped_spectrum_full, DampedMode};
use super::monolithic::Monolithic;
use super::staggered::Staggered;
use super::{FullState, Grid, GridError, ModeCoupling, VorticityError};
use crate::integrate::Stats;
use crate::model::{BoundaryLayerSystem, Model, ModelError, RunReport, RunStatus};
use crate::scene::{Run, Scene, Viscous, VorticityScheme};
use serde::Serialize;
use std::cell::RefCell;
use std::time::Instant;

/// Why the full model of a scene cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FullModelError {
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error(transparent)]
    Grid(#[from] GridError),
    #[error("modes.max_order = 0: the vorticity closure needs at least one shape mode")]
    NoModes,
}

/// The rest of the model, seen by the vorticity closure (nondimensional).
pub struct SceneCoupling<'m> {
    bl: &'m BoundaryLayerSystem,
    orders: &'m [usize],
    y: RefCell<Vec<f64>>,
}

impl SceneCoupling<'_> {
    /// Fills the boundary-layer state layout [R, Ṙ, (a, ȧ, b)_k] the load code reads.
    fn fill(&self, r: f64, rdot: f64, a: &[f64], b: &[f64]) -> std::cell::RefMut<'_, Vec<f64>> {
        let mut y = self.y.borrow_mut();
        y[0] = r;
        y[1] = rdot;
        for m in 0..a.len() {
            y[2 + 3 * m] = a[m];
            y[3 + 3 * m] = 0.0;
            y[4 + 3 * m] = b[m];
        }
        y
    }
}

impl ModeCoupling for SceneCoupling<'_> {
    fn orders(&self) -> &[usize] {
        self.orders
    }
    fn density(&self) -> f64 {
        self.bl.params().rho
    }
    fn viscosity(&self) -> f64 {
        self.bl.params().eta
    }
    fn radial_acceleration(&self, t: f64, r: f64, rdot: f64, a: &[f64], b: &[f64]) -> f64 {
        let y = self.fill(r, rdot, a, b);
        self.bl.radial_acceleration(t, &y)
    }
    /// G_n,k, G_t,k from the scene's terms (FORMULATION §4.1; [`crate::model::effects`]).
    fn shape_loads(&self, t: f64, r: f64, a: &[f64], b: &[f64], gn: &mut [f64], gt: &mut [f64]) {
        let y = self.fill(r, 0.0, a, b);
        self.bl.equations().loads(t, &y, gn, gt);
    }
    fn loads(&self, t: f64, r: f64, rdot: f64, a: &[f64], b: &[f64], gn: &mut [f64], gt: &mut [f64]) -> f64 {
        let y = self.fill(r, rdot, a, b);
        let eq = self.bl.equations();
        let p = eq.loads(t, &y, gn, gt);
        eq.acceleration_at(t, &y, p)
    }
}

/// How to integrate the full model (times in units of t*).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SchemeSettings {
    pub scheme: VorticityScheme,
    /// Fixed step of the staggered scheme.
    pub dt: f64,
    /// Tolerances of the monolithic scheme.
    pub rtol: f64,
    pub atol: f64,
    pub t_end: f64,
    /// Output interval.
    pub sample: f64,
    pub max_steps: u64,
}

/// A scene's full model.
pub struct FullModel {
    model: Model,
    pub grid: Grid,
    pub scheme: VorticityScheme,
}

impl FullModel {
    /// Assembles the full model of `scene` whatever its `modes.viscous` says.
    pub fn from_scene(scene: &Scene) -> Result<Self, FullModelError> {
        if scene.modes.max_order == 0 {
            return Err(FullModelError::NoModes);
        }
        let mut bl_scene = scene.clone();
        bl_scene.modes.viscous = Viscous::BoundaryLayer;
        let model = Model::from_scene(&bl_scene)?;
        if model.boundary_layer().is_none() {
            return Err(FullModelError::NoModes);
        }
        let v = &scene.vorticity;
        let grid = Grid::new(v.y_max, v.points, v.stretching)?;
        Ok(Self { model, grid, scheme: v.scheme })
    }

    /// The boundary-layer model of the same scene (scales, output conversion, blow-up classifier).
    pub fn base(&self) -> &Model {
        &self.model
    }

    pub fn coupling(&self) -> SceneCoupling<'_> {
        let bl = self.model.boundary_layer().expect("checked in from_scene");
        SceneCoupling { bl, orders: self.model.orders(), y: RefCell::new(vec![0.0; 2 + 3 * self.model.orders().len()]) }
    }

    /// Nondimensional initial state (T = 0).
    pub fn initial_state(&self) -> FullState {
        let y0 = self.model.initial_state();
        let m = self.model.orders().len();
        let pick = |c: usize| (0..m).map(|i| y0[2 + 3 * i + c]).collect::<Vec<f64>>();
        FullState::new(0.0, y0[0], y0[1], pick(0), pick(1), pick(2), self.grid.interior())
    }

    /// The boundary-layer layout [R, Ṙ, (a, ȧ, b)_k] of a full state (for output and blow-up).
    pub fn bl_layout(s: &FullState) -> Vec<f64> {
        let mut z = vec![s.r, s.rdot];
        for m in 0..s.a.len() {
            z.extend_from_slice(&[s.a[m], s.adot[m], s.b[m]]);
        }
        z
    }

    /// Runs with `settings` (nondimensional times): `observer(state)` at t = 0 and every
    /// multiple of `sample` up to `t_end`; it returns `false` to stop.
    pub fn run_nondim(&self, settings: &SchemeSettings, observer: &mut dyn FnMut(&FullState) -> bool) -> Result<Stats, VorticityError> {
        let SchemeSettings { scheme, dt, rtol, atol, t_end, sample, max_steps } = *settings;
        let c = self.coupling();
        let init = self.initial_state();
        if !observer(&init) {
            return Ok(Stats::default());
        }
        match scheme {
            VorticityScheme::Staggered => {
                let mut st = Staggered::new(&c, self.grid.clone(), dt)?;
                let mut s = init;
                let mut steps = 0u64;
                let mut n = 1u64;
                while s.t < t_end * (1.0 - 1e-12) {
                    let target = (n as f64 * sample).min(t_end);
                    steps += st.run(&mut s, target, |_, _| true)?;
                    n += 1;
                    if steps > max_steps {
                        return Err(VorticityError::NonFinite { t: s.t, what: format!("step limit {max_steps} reached") });
                    }
                    if !observer(&s) {
                        break;
                    }
                }
                let m = c.orders().len() as u64;
                Ok(Stats { steps, rejected: 0, rhs_evals: 4 * steps, jac_evals: 0, lu_decompositions: steps * m })
            }
            VorticityScheme::Monolithic => {
                let sys = Monolithic::new(&c, self.grid.clone());
                let mut y = sys.pack(&init);
                let settings = ImplicitSettings { rtol, atol, h0: 0.0, max_steps, output_interval: sample };
                let st = integrate(&sys, 0.0, &mut y, t_end, &settings, |t, y| observer(&sys.unpack(t, y)))?;
                Ok(Stats {
                    steps: st.accepted,
                    rejected: st.rejected,
                    rhs_evals: st.rhs_evals,
                    jac_evals: st.accepted + st.rejected,
                    lu_decompositions: st.factorizations,
                })
            }
        }
    }

    /// Runs with the scene's run settings, like [`Model::run`]: `observer(t [s], row)` with
    /// row = (R, a2, b2, …) [m] at every sample; blow-up is classified by the same rule.
    pub fn run(&self, run: &Run, observer: &mut dyn FnMut(f64, &[f64])) -> RunReport {
        let start = Instant::now();
        let ts = self.model.time_scale();
        let names = self.model.state_names();
        let mut row = vec![0.0; names.len()];
        let mut max_abs = vec![0.0f64; names.len()];
        let mut last_t = 0.0;
        let mut blow: Option<(f64, String)> = None;
        let mut obs = |s: &FullState| -> bool {
            let z = Self::bl_layout(s);
            self.model.to_si_into(&z, &mut row);
            last_t = s.t * ts;
            for (m, v) in max_abs.iter_mut().zip(&row) {
                *m = m.max(v.abs());
            }
            observer(s.t * ts, &row);
            match self.model.blow_up(&z) {
                Some(mode) => {
                    blow = Some((s.t * ts, mode));
                    false
                }
                None => true,
            }
        };
        let it = &run.integrator;
        let settings = SchemeSettings {
            scheme: self.scheme,
            dt: it.dt / ts,
            rtol: it.rtol,
            atol: it.atol,
            t_end: run.duration / ts,
            sample: run.sample_interval / ts,
            max_steps: it.max_steps,
        };
        let result = self.run_nondim(&settings, &mut obs);
        let (status, stats) = match result {
            Ok(stats) => (
                match blow.take() {
                    Some((t, mode)) => RunStatus::BlowUp { t, mode },
                    None => RunStatus::Completed,
                },
                stats,
            ),
            // a non-finite state is a blow-up (a result), other failures are failures
            Err(VorticityError::NonFinite { t, what }) if !what.contains("limit") => {
                (RunStatus::BlowUp { t: t * ts, mode: format!("nonfinite ({what})") }, Stats::default())
            }
            Err(e) => (RunStatus::Failed { reason: e.to_string() }, Stats::default()),
        };
        let mut effects = self.model.active_effects();
        for e in effects.iter_mut() {
            *e = e.replace("(boundary layer)", "(vorticity)");
        }
        let (y, n) = (&self.grid.y, self.grid.len());
        effects.push(format!(
            "vorticity grid y_max = {}, {} points, stretching {:.3}, {:?} scheme",
            y[n - 1],
            n,
            (y[n - 1] - y[n - 2]) / self.grid.h0(),
            self.scheme
        ));
        RunReport {
            status,
            t_end: last_t,
            stats,
            wall_seconds: start.elapsed().as_secs_f64(),
            max_abs: names.iter().cloned().zip(max_abs).collect(),
            final_state: names.iter().cloned().zip(row.iter().copied()).collect(),
            active_effects: effects,
            state_dimension: 2 + self.model.orders().len() * (3 + self.grid.interior()),
            groups: self.model.groups(),
        }
    }
}

/// Runs a scene with the full model (the counterpart of `model::simulate` for
/// `modes.viscous = "vorticity"`).
pub fn simulate_full(scene: &Scene, observer: &mut dyn FnMut(f64, &[f64])) -> Result<RunReport, FullModelError> {
    let fm = FullModel::from_scene(scene)?;
    Ok(fm.run(&scene.run, observer))
}

/// The linear damped spectrum of a scene (issue 4 part 6), SI units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DampedSpectrum {
    /// "boundary-layer" or "vorticity"
    pub closure: &'static str,
    pub shape: Vec<DampedMode>,
}

/// Eigenvalues s = −γ ± iω of the linearisation at R0 with the scene's viscous closure:
/// boundary layer: the (a, ȧ, b) system of FORMULATION §4.3 (δ_k by the scene's rule); vorticity:
/// the (a, ȧ, b, T-nodes) system on the scene's grid ([`super::linear`]). Field couplings
/// k ± 2 are left out (per-k spectrum); the magnetic diagonal is included. A mode whose root is
/// not found is reported with NaN (null in JSON).
pub fn damped_spectrum(scene: &Scene) -> Result<DampedSpectrum, FullModelError> {
    let fm = FullModel::from_scene(scene)?;
    let c = fm.coupling();
    let ts = fm.model.time_scale();
    let r0 = 1.0; // nondimensional R0
    let (closure, found) = match scene.modes.viscous {
        Viscous::Vorticity => ("vorticity", damped_spectrum_full(&c, &fm.grid, 0.0, r0)),
        Viscous::BoundaryLayer => {
            let bl = fm.model.boundary_layer().expect("checked in from_scene");
            ("boundary-layer", damped_spectrum_boundary_layer(&c, 0.0, r0, |k, _| bl.delta(k / 2 - 1, r0)))
        }
    };
    let shape = found
        .into_iter()
        .zip(fm.model.orders())
        .map(|(d, &k)| match d {
            Some(d) => DampedMode { k, decay_per_s: d.decay_per_s / ts, omega_rad_s: d.omega_rad_s / ts },
            None => DampedMode { k, decay_per_s: f64::NAN, omega_rad_s: f64::NAN },
        })
        .collect();
    Ok(DampedSpectrum { closure, shape })
}
