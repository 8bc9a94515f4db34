//! The full model assembled from a scene (`modes.viscous = "vorticity"`): the radial equation,
//! membrane and magnetic loads come from the boundary-layer model of the same scene (its
//! nondimensional parameters, FORMULATION §4.5), the viscous closure is replaced by the
//! vorticity PDE on the scene's grid, integrated by the scene's `vorticity.scheme`.

use super::linear::{damped_spectrum_boundary_layer, damped_spectrum_full, DampedMode};
use super::monolithic::Monolithic;
use super::staggered::{Staggered, StaggeredStepper};
use super::{FullState, Grid, GridError, ModeCoupling, VorticityError};
use crate::integrate::{drive, stepper, Control, IntegrateError, Method, OdeSystem, Output, Stats, Stepper};
use crate::model::executor::{execute, Plan};
use crate::model::effects::second_order::{FirstOrder, FirstOrderGradient, MaterialLoads};
use crate::model::effects::{LoadJacobian, Loads, MAX_MODES};
use crate::model::layout::StateLayout;
use crate::model::{method_of, BoundaryLayerSystem, Model, ModelError, RunReport};
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
    /// The model's second-pass terms are part of the coupling (issue 12; [`Self::linear`] drops them).
    second: bool,
}

impl<'m> SceneCoupling<'m> {
    /// The coupling of a boundary-layer model with shape modes (its radial equation and loads;
    /// `None` for a radial-only model).
    pub fn of(model: &'m Model) -> Option<Self> {
        let bl = model.boundary_layer()?;
        let orders = model.orders();
        Some(SceneCoupling { bl, orders, y: RefCell::new(vec![0.0; bl.layout().dim()]), second: bl.equations().has_second_order() })
    }

    /// The same coupling without the second-pass terms (the quadratic coupling, issue 12): the
    /// linear model, for the analyses that linearise about a = 0 (Floquet, FORMULATION §4.6).
    pub fn linear(mut self) -> Self {
        self.second = false;
        self
    }

    /// R̈ of P + ΔP minus R̈ of P, and its (∂/∂R, ∂/∂Ṙ, ∂/∂ΔP): exact because both radial forms
    /// without the pressure's rate are affine in P (model/radial.rs); the quadratic coupling with
    /// Keller–Miksis, whose R̈ needs dP/dt, is refused (model::check_quadratic).
    fn radial_shift(&self, r: f64, rd: f64, dp: f64) -> [f64; 4] {
        let (form, rho) = (self.bl.equations().form(), self.bl.params().rho);
        debug_assert!(!form.needs_rate(), "second-pass terms with a radial form that needs dP/dt");
        let (r0, rd0, _) = form.partials(rho, r, rd, 0.0);
        let (r1, rd1, p1) = form.partials(rho, r, rd, dp);
        [form.acceleration(rho, r, rd, dp) - form.acceleration(rho, r, rd, 0.0), r1 - r0, rd1 - rd0, p1]
    }

    /// Fills the boundary-layer state layout z = [R, Ṙ, (a, ȧ, b)_k] the terms read.
    fn fill(&self, r: f64, rdot: f64, a: &[f64], adot: &[f64], b: &[f64]) -> std::cell::RefMut<'_, Vec<f64>> {
        let (mut y, l) = (self.y.borrow_mut(), self.bl.layout());
        y[l.r()] = r;
        y[l.rdot()] = rdot;
        for m in 0..a.len() {
            y[l.a(m)] = a[m];
            y[l.adot(m)] = adot[m];
            y[l.b(m)] = b[m];
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
    fn radial_acceleration(&self, t: f64, r: f64, rdot: f64, a: &[f64], adot: &[f64], b: &[f64]) -> f64 {
        let y = self.fill(r, rdot, a, adot, b);
        self.bl.radial_acceleration(t, &y)
    }
    /// G_n,k, G_t,k from the scene's terms (FORMULATION §4.1; [`crate::model::effects`]).
    fn shape_loads(&self, t: f64, r: f64, rdot: f64, a: &[f64], adot: &[f64], b: &[f64], gn: &mut [f64], gt: &mut [f64]) {
        let y = self.fill(r, rdot, a, adot, b);
        self.bl.equations().loads(t, &y, gn, gt);
    }
    fn mode_stiffness(&self, t: f64, r: f64) -> Vec<[f64; 4]> {
        let m = self.orders.len();
        let zero = vec![0.0; m];
        let y = self.fill(r, 0.0, &zero, &zero, &zero);
        let mut lj = crate::model::effects::LoadJacobian::new(m);
        self.bl.equations().load_jacobian(t, &y, &mut lj);
        (0..m)
            .map(|i| {
                let (ia, ib) = (lj.layout().a(i), lj.layout().b(i));
                let (gn, gt) = (lj.gn_row(i), lj.gt_row(i));
                [gn[ia], gn[ib], gt[ia], gt[ib]]
            })
            .collect()
    }
    fn linearize(&self, t: f64, z: &[f64], drdd: &mut [f64], jac: &mut crate::model::effects::LoadJacobian) {
        let eq = self.bl.equations();
        eq.load_jacobian(t, z, jac);
        let p = eq.loads(t, z, &mut [], &mut []);
        eq.acceleration_gradient(z[0], z[1], p, &jac.pressure, drdd);
    }
    fn loads(&self, t: f64, r: f64, rdot: f64, a: &[f64], adot: &[f64], b: &[f64], gn: &mut [f64], gt: &mut [f64]) -> f64 {
        let y = self.fill(r, rdot, a, adot, b);
        let eq = self.bl.equations();
        let p = eq.loads(t, &y, gn, gt);
        eq.acceleration_at(t, &y, p)
    }
    fn has_second_order(&self) -> bool {
        self.second
    }
    /// The model's second-pass terms ([`crate::model::Equations::add_second_order`]) given the
    /// closure's first-order accelerations, as the boundary-layer system adds them.
    fn second_order(&self, t: f64, r: f64, rdot: f64, a: &[f64], adot: &[f64], b: &[f64], rdd: f64, add: &[f64], gn: &mut [f64], gt: &mut [f64]) -> f64 {
        if !self.second {
            return rdd;
        }
        let y = self.fill(r, rdot, a, adot, b);
        let mut l = Loads { pressure: 0.0, gn, gt };
        // ḃ⁽¹⁾: read only by the shell-viscous second-order term, which the scene validator refuses
        // with the vorticity closure (scene/validate.rs), so zeros stand for it here.
        let bd = [0.0; MAX_MODES];
        let eq = self.bl.equations();
        let (m, mut mgn, mut mgt) = (add.len(), [0.0; MAX_MODES], [0.0; MAX_MODES]);
        let pm = eq.material_loads(t, &y, &mut mgn[..m], &mut mgt[..m]);
        let material = MaterialLoads { pressure: pm, gn: &mgn[..m], gt: &mgt[..m] };
        eq.add_second_order(t, &y, &FirstOrder { rdd, add, bd: &bd[..m], material }, &mut l);
        rdd + self.radial_shift(r, rdot, l.pressure)[0]
    }
    fn second_order_jacobian(&self, t: f64, z: &[f64], rdd: f64, add: &[f64], grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian, drdd: &mut [f64]) {
        jac.clear();
        drdd.copy_from_slice(grad.drdd);
        if !self.second {
            return;
        }
        let eq = self.bl.equations();
        let m = self.orders.len();
        // ḃ⁽¹⁾: read only by the shell-viscous second-order term, which the scene validator refuses
        // with the vorticity closure (scene/validate.rs), so zeros stand for it here.
        let bd = [0.0; MAX_MODES];
        // the material-frame terms' loads and Jacobian (the frame mapping's L(z), J(z))
        let (mut mgn, mut mgt, mut mj) = ([0.0; MAX_MODES], [0.0; MAX_MODES], LoadJacobian::new(m));
        let pm = eq.material_loads(t, z, &mut mgn[..m], &mut mgt[..m]);
        eq.material_jacobian(t, z, &mut mj);
        let grad = &FirstOrderGradient { material: &mj, ..*grad };
        let first = FirstOrder { rdd, add, bd: &bd[..m], material: MaterialLoads { pressure: pm, gn: &mgn[..m], gt: &mgt[..m] } };
        let (mut gn, mut gt) = ([0.0; MAX_MODES], [0.0; MAX_MODES]);
        let mut l = Loads { pressure: 0.0, gn: &mut gn[..m], gt: &mut gt[..m] };
        eq.add_second_order(t, z, &first, &mut l);
        let [_, s_r, s_rd, s_p] = self.radial_shift(z[0], z[1], l.pressure);
        eq.add_second_order_jacobian(t, z, &first, grad, jac);
        for (d, x) in drdd.iter_mut().zip(&jac.pressure) {
            *d += s_p * x;
        }
        drdd[0] += s_r;
        drdd[1] += s_rd;
    }
}

/// How to integrate the full model (times in units of t*).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SchemeSettings {
    pub scheme: VorticityScheme,
    /// Fixed step of the staggered scheme.
    pub dt: f64,
    /// Tolerances of the monolithic scheme (integrated by Radau5 through the structured solve).
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
        crate::model::refuse_reduced_thermal(scene, crate::model::effects::reduced_gas::WITH_VORTICITY)?;
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
        SceneCoupling::of(&self.model).expect("checked in from_scene")
    }

    /// Nondimensional initial state (T = 0).
    pub fn initial_state(&self) -> FullState {
        let y0 = self.model.initial_state();
        let l = StateLayout::reduced(self.model.orders().len());
        let pick = |at: fn(StateLayout, usize) -> usize| (0..l.modes()).map(|i| y0[at(l, i)]).collect::<Vec<f64>>();
        FullState::new(0.0, y0[l.r()], y0[l.rdot()], pick(StateLayout::a), pick(StateLayout::adot), pick(StateLayout::b), self.grid.interior())
    }

    /// The boundary-layer layout [R, Ṙ, (a, ȧ, b)_k] of a full state (for output and blow-up).
    pub fn bl_layout(s: &FullState) -> Vec<f64> {
        let l = StateLayout::reduced(s.a.len());
        let mut z = vec![0.0; l.dim()];
        (z[l.r()], z[l.rdot()]) = (s.r, s.rdot);
        for m in 0..l.modes() {
            (z[l.a(m)], z[l.adot(m)], z[l.b(m)]) = (s.a[m], s.adot[m], s.b[m]);
        }
        z
    }

    /// The stepper of `scheme` at the initial state, on the monolithic layout of `sys`; `true`:
    /// it must land on the samples.
    fn scheme_stepper<'c>(
        &self,
        c: &'c SceneCoupling<'_>,
        sys: &Monolithic<'_>,
        scheme: VorticityScheme,
        method: &Method,
        dt: f64,
        t_end: f64,
    ) -> (Result<Box<dyn Stepper + 'c>, IntegrateError>, bool) {
        let init = self.initial_state();
        match scheme {
            VorticityScheme::Staggered => match Staggered::new(c, self.grid.clone(), dt) {
                Ok(st) => (Ok(Box::new(StaggeredStepper::new(st, init))), true),
                Err(_) => (Err(IntegrateError::InvalidSetting { what: "dt", value: dt, reason: "must be positive and finite" }), true),
            },
            VorticityScheme::Monolithic => (stepper(sys, method, 0.0, &sys.pack(&init), t_end), false),
        }
    }

    /// Runs with `settings` (nondimensional times): `observer(state)` at t = 0 and every
    /// multiple of `sample` up to `t_end`; it returns `false` to stop.
    pub fn run_nondim(&self, settings: &SchemeSettings, observer: &mut dyn FnMut(&FullState) -> bool) -> Result<Stats, VorticityError> {
        let SchemeSettings { scheme, dt, rtol, atol, t_end, sample, max_steps } = *settings;
        let c = self.coupling();
        let sys = Monolithic::new(&c, self.grid.clone());
        let method = Method::Radau5 { rtol, atol };
        let (st, land) = self.scheme_stepper(&c, &sys, scheme, &method, dt, t_end);
        let mut st = st?;
        let mut obs = |t: f64, y: &[f64]| if observer(&sys.unpack(t, y)) { Control::Continue } else { Control::Stop };
        // the staggered scheme steps to every sample
        let output = if land { Output::Landing(sample) } else { Output::Every(sample) };
        Ok(drive(&mut *st, &sys, t_end, output, max_steps, &mut obs)?.stats)
    }

    /// Runs with the scene's run settings on the run executor, like [`Model::run`]:
    /// `observer(t [s], row)` with row = (R, a2, b2, …) [m] at every sample; the monolithic
    /// scheme with the scene's `run.integrator` (Radau5 by default, through the structured solve).
    pub fn run(&self, run: &Run, observer: &mut dyn FnMut(f64, &[f64])) -> RunReport {
        let start = Instant::now();
        let ts = self.model.time_scale();
        let c = self.coupling();
        let sys = Monolithic::new(&c, self.grid.clone());
        let (lay, orders) = (sys.layout(), self.model.orders());
        let t_end = run.duration / ts;
        let method = method_of(&run.integrator, ts);
        let (st, land) = self.scheme_stepper(&c, &sys, self.scheme, &method, run.integrator.dt / ts, t_end);
        // the monolithic index of each boundary-layer component, in the boundary-layer order
        let layout: Vec<usize> = (0..lay.dim()).filter(|&i| lay.to_boundary_layer(i).is_some()).collect();
        let component_mode = |c: usize| {
            if c < StateLayout::RADIAL {
                return "R".to_string();
            }
            let mi = lay.mode_of(c);
            let k = orders.get(mi).copied().unwrap_or(0);
            match c {
                c if c == lay.a(mi) || c == lay.adot(mi) => format!("a{k}"),
                c if c == lay.b(mi) => format!("b{k}"),
                _ => format!("nonfinite (vorticity of mode k = {k})"),
            }
        };
        let plan = Plan {
            sys: &sys,
            t_end,
            sample: run.sample_interval / ts,
            max_steps: run.integrator.max_steps,
            land_on_samples: land,
            layout: &layout,
            component_mode: &component_mode,
        };
        let out = execute(&self.model, &plan, st, &mut |row| observer(row.t, row.si));
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
        let mut report = self.model.report(out, start, effects, sys.dim());
        report.integrator = Some(crate::model::stiffness::full_model_choice(&run.integrator, &method, self.scheme));
        report
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
            // a free bubble: no tangential stiffness, b_k is neutral (multiplier 1, eigenvalue 0
            // at rest) and the (a, ȧ) block alone carries the mode (analysis/stability.rs b_free)
            let free = scene.shell.is_free();
            if bl.equations().has_bdot_loads() || free {
                // shell viscosity: loads in ȧ and ḃ too, which the stiffness-only determinant
                // does not carry; the roots are the eigenvalues of each mode's block of the exact
                // linear system A at rest (the oscillatory pair; overdamped: the slowest real root)
                let (a, _) = bl.linear_modes(0.0, r0, 0.0, 0.0);
                let found = (0..fm.model.orders().len())
                    .map(|j| {
                        let size = if free { 2 } else { 3 };
                        let block = a.view((StateLayout::x_a(j), StateLayout::x_a(j)), (size, size)).clone_owned();
                        // bounded QR sweeps: nalgebra's unbounded iteration never returns on a non-finite block
                        let eig = match nalgebra::linalg::Schur::try_new(block, f64::EPSILON, 30 * size) {
                            Some(schur) => schur.complex_eigenvalues().iter().copied().collect::<Vec<_>>(),
                            None => Vec::new(),
                        };
                        let top = eig.iter().max_by(|x, y| x.im.total_cmp(&y.im)).copied();
                        let slowest = eig.iter().max_by(|x, y| x.re.total_cmp(&y.re)).copied();
                        top.filter(|s| s.im > 0.0).or(slowest).map(|s| super::linear::DampedMode::from_root(fm.model.orders()[j], s))
                    })
                    .collect();
                ("boundary-layer", found)
            } else {
                ("boundary-layer", damped_spectrum_boundary_layer(&c, 0.0, r0, |k, _| bl.delta(k / 2 - 1, r0)))
            }
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

