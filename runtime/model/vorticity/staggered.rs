//! The paper's loosely coupled staggered scheme (§5, FORMULATION §4.2 steps 1–3), step t_n → t_{n+1}:
//!
//! 1. RK4 for (R, Ṙ, a, ȧ, b) over [t_n, t_{n+1}] with Ĩ_int,k and ∫(y⁻³−1)y^{−k}T dy frozen at T^n
//!    (lagged); T_w is computed inside the right-hand side from (TS) (FORMULATION's recommendation).
//! 2. Backward Euler for T^{n+1} (eq 5.3) with R^{n+1}, Ṙ^{n+1}: per mode a tridiagonal system
//!    bordered by the Dirichlet row T_0 = (A^{n+1} − 2 Σ_{i≥1} W_i T_i^{n+1})/(1 + 2w_0). The border
//!    is a rank-one update of the first row, solved by two Thomas sweeps and Sherman–Morrison —
//!    never a dense matrix.
//! 3. The integrals Ĩ_int, J are recomputed from T^{n+1} at the start of the next step.
//!
//! The lag makes the b_k ↔ T_w feedback explicit, which is only conditionally stable
//! (FORMULATION audit 12; measured limits in docs/vorticity.md).

use super::equations::{completed_loads, coupled_mode_rates, wall_source, LoadScratch, ModeInputs, ModeRates};
use super::operator::{backward_euler_pair, ModeOperator, Rows};
use super::{FullState, Grid, ModeCoupling, VorticityError};
use crate::integrate::{rk4_step, IntegrateError, OdeSystem, Rk4Workspace, Stats, Stepper};
use crate::model::layout::StateLayout;
use std::cell::RefCell;

/// Step 1's ODE: u = [R, Ṙ, a(M), ȧ(M), b(M)] ([`StateLayout::component_major`]) with the integrals lagged at T^n (and T_w too
/// with [`WallCoupling::Lagged`]); T_w of the last evaluation is left in `tw`.
struct LaggedOde<'a> {
    coupling: &'a dyn ModeCoupling,
    i_int: &'a [f64],
    j_over_r: &'a [f64],
    w0: f64,
    tw_fixed: Option<&'a [f64]>,
    loads: RefCell<&'a mut LoadScratch>,
    tw: RefCell<&'a mut Vec<f64>>,
}

impl OdeSystem for LaggedOde<'_> {
    fn dim(&self) -> usize {
        StateLayout::reduced(self.i_int.len()).dim()
    }
    fn rhs(&self, t: f64, u: &[f64], du: &mut [f64]) {
        let l = StateLayout::reduced(self.i_int.len());
        let [ia, iad, ib] = l.component_major();
        let (r, rdot) = (u[l.r()], u[l.rdot()]);
        let (a, adot, b) = (&u[ia.clone()], &u[iad.clone()], &u[ib]);
        let mut loads = self.loads.borrow_mut();
        let rddot = loads.eval(self.coupling, t, r, rdot, a, adot, b);
        du[l.r()] = rdot;
        du[l.rdot()] = rddot;
        du[ia].copy_from_slice(adot);
        let (_, rest) = du.split_at_mut(iad.start);
        let (add, bdot) = rest.split_at_mut(iad.len());
        let inputs = ModeInputs {
            r,
            rdot,
            rddot,
            a,
            adot,
            b,
            gn: &loads.gn,
            gt: &loads.gt,
            i_int: self.i_int,
            j_over_r: self.j_over_r,
            w0: self.w0,
            tw_fixed: self.tw_fixed,
        };
        let mut tw = self.tw.borrow_mut();
        // with second-pass loads (issue 12) R̈ of the completed radial balance
        du[l.rdot()] = coupled_mode_rates(self.coupling, t, &inputs, ModeRates { add, bdot, tw: &mut tw[..] });
    }
}

/// How step 1 treats the wall vorticity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WallCoupling {
    /// T_w from (TS) inside the RK right-hand side, with Ĩ_int, J lagged (FORMULATION §4.2,
    /// recommended; the default).
    #[default]
    InRhs,
    /// T_w frozen at T^n as well (the paper's wording, "the value of T_k at the previous time
    /// step being utilized").
    Lagged,
}

/// The staggered integrator of one coupling on one grid with a fixed step.
pub struct Staggered<'c> {
    coupling: &'c dyn ModeCoupling,
    pub grid: Grid,
    ops: Vec<ModeOperator>,
    dt: f64,
    // scratch
    loads: LoadScratch,
    i_int: Vec<f64>,
    j_over_r: Vec<f64>,
    rows: Rows,
    rhs: Vec<f64>,
    z: Vec<f64>,
    scratch: Vec<f64>,
    u0: Vec<f64>,
    u1: Vec<f64>,
    rk4: Rk4Workspace,
    tw: Vec<f64>,
    tw_lagged: Vec<f64>,
    wall: WallCoupling,
}

impl<'c> Staggered<'c> {
    /// `dt` in the coupling's time unit.
    pub fn new(coupling: &'c dyn ModeCoupling, grid: Grid, dt: f64) -> Result<Self, VorticityError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(VorticityError::TimeStep(dt));
        }
        let m = coupling.orders().len();
        let ops: Vec<ModeOperator> = coupling.orders().iter().map(|&k| ModeOperator::new(&grid, k)).collect();
        let ni = grid.interior();
        let dim = StateLayout::reduced(m).dim();
        Ok(Self {
            coupling,
            grid,
            ops,
            dt,
            loads: LoadScratch::new(m),
            i_int: vec![0.0; m],
            j_over_r: vec![0.0; m],
            rows: Rows::default(),
            rhs: vec![0.0; ni],
            z: vec![0.0; ni],
            scratch: vec![0.0; ni],
            u0: vec![0.0; dim],
            u1: vec![0.0; dim],
            rk4: Rk4Workspace::new(dim),
            tw: vec![0.0; m],
            tw_lagged: vec![0.0; m],
            wall: WallCoupling::InRhs,
        })
    }

    /// Chooses the treatment of T_w in step 1 (default [`WallCoupling::InRhs`]).
    pub fn with_wall(mut self, wall: WallCoupling) -> Self {
        self.wall = wall;
        self
    }

    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// A state at rest at the initial conditions given, T = 0.
    pub fn initial_state(&self, t: f64, r: f64, rdot: f64, a: Vec<f64>, adot: Vec<f64>, b: Vec<f64>) -> FullState {
        FullState::new(t, r, rdot, a, adot, b, self.grid.interior())
    }

    /// Wall vorticity T_w,k of the last right-hand side evaluation.
    pub fn wall_vorticity(&self) -> &[f64] {
        &self.tw
    }

    /// One step t_n → t_n + dt.
    pub fn step(&mut self, s: &mut FullState) -> Result<(), VorticityError> {
        let m = self.ops.len();
        let dt = self.dt;
        // step 3 of the previous step / step 0: the lagged integrals from T^n
        for (mi, op) in self.ops.iter().enumerate() {
            self.i_int[mi] = op.i_interior(&s.t_nodes[mi]);
            self.j_over_r[mi] = op.j_over_r(&s.t_nodes[mi]);
        }
        // step 1: classical RK4 (the shared one) on the ODE part
        let l = StateLayout::reduced(m);
        let [ia, iad, ib] = l.component_major();
        let mut u0 = std::mem::take(&mut self.u0);
        let mut u1 = std::mem::take(&mut self.u1);
        u0[l.r()] = s.r;
        u0[l.rdot()] = s.rdot;
        u0[ia.clone()].copy_from_slice(&s.a);
        u0[iad.clone()].copy_from_slice(&s.adot);
        u0[ib.clone()].copy_from_slice(&s.b);
        debug_assert_eq!(u0.len(), l.dim());
        let (w0, tw_fixed) = wall_inputs(&self.ops, self.wall, &self.tw_lagged);
        let ode = LaggedOde {
            coupling: self.coupling,
            i_int: &self.i_int,
            j_over_r: &self.j_over_r,
            w0,
            tw_fixed,
            loads: RefCell::new(&mut self.loads),
            tw: RefCell::new(&mut self.tw),
        };
        rk4_step(&ode, s.t, &u0, dt, &mut u1, &mut self.rk4);
        std::mem::swap(&mut u0, &mut u1);
        s.t += dt;
        s.r = u0[l.r()];
        s.rdot = u0[l.rdot()];
        s.a.copy_from_slice(&u0[ia]);
        s.adot.copy_from_slice(&u0[iad]);
        s.b.copy_from_slice(&u0[ib]);
        self.u0 = u0;
        self.u1 = u1;
        if let Some(what) = s.non_finite() {
            return Err(VorticityError::NonFinite { t: s.t, what });
        }
        // step 2: backward Euler for T with the new R, Ṙ, a, ȧ, b
        let eta = self.coupling.viscosity();
        let nu = eta / self.coupling.density();
        if self.coupling.has_second_order() {
            // (TS) with the loads completed by the second pass (issue 12), its first-order ä at
            // the integrals lagged at T^n as in step 1
            let (w0, tw_fixed) = wall_inputs(&self.ops, self.wall, &self.tw_lagged);
            let x = ModeInputs {
                r: s.r,
                rdot: s.rdot,
                rddot: 0.0,
                a: &s.a,
                adot: &s.adot,
                b: &s.b,
                gn: &[],
                gt: &[],
                i_int: &self.i_int,
                j_over_r: &self.j_over_r,
                w0,
                tw_fixed,
            };
            completed_loads(self.coupling, s.t, &x, &mut self.loads.gn, &mut self.loads.gt);
        } else {
            self.coupling.shape_loads(s.t, s.r, s.rdot, &s.a, &s.adot, &s.b, &mut self.loads.gn, &mut self.loads.gt);
        }
        for mi in 0..m {
            let op = &self.ops[mi];
            let kf = op.k as f64;
            op.rows(s.r, s.rdot, nu, &mut self.rows);
            let w0 = op.w0();
            let src = wall_source(kf, eta, s.r, s.rdot, s.a[mi], s.adot[mi], self.loads.gt[mi]);
            let ni = op.interior();
            // (I − dt L) T^{n+1} = T^n, with T_0 = (src − 2 Σ W_j T_j)/(1 + 2 w0): the wall term
            // of row 1 moves to the right-hand side, the Σ W_j T_j part is a rank-one border
            // beta·e_1 W^T of the matrix (Sherman–Morrison).
            self.rhs[..ni].copy_from_slice(&s.t_nodes[mi]);
            let l1 = dt * self.rows.lower[0];
            self.rhs[0] += l1 * src / (1.0 + 2.0 * w0);
            let beta = 2.0 * l1 / (1.0 + 2.0 * w0);
            let wi = &op.wi[1..=ni];
            let ok = backward_euler_pair(&self.rows, dt, &mut self.rhs, &mut self.z, &mut self.scratch);
            let (ok1, ok2) = (ok, true);
            let wx: f64 = wi.iter().zip(&self.rhs).map(|(w, x)| w * x).sum();
            let wz: f64 = wi.iter().zip(&self.z).map(|(w, x)| w * x).sum();
            let den = 1.0 + beta * wz;
            if !(ok1 && ok2) || den == 0.0 {
                return Err(VorticityError::Singular { k: op.k, t: s.t });
            }
            let f = beta * wx / den;
            for i in 0..ni {
                s.t_nodes[mi][i] = self.rhs[i] - f * self.z[i];
            }
            let i_int = op.i_interior(&s.t_nodes[mi]);
            self.tw[mi] = (src - 2.0 * i_int) / (1.0 + 2.0 * w0);
            self.tw_lagged[mi] = self.tw[mi];
        }
        if let Some(what) = s.non_finite() {
            return Err(VorticityError::NonFinite { t: s.t, what });
        }
        Ok(())
    }

    /// Runs to `t_end` (the last step is shortened to land on it). `observer(state)` is called
    /// after every step; returning `false` stops the run. For studies that read the wall
    /// vorticity after every step (tests); scene runs drive [`StaggeredStepper`] on the run loop
    /// ([`crate::integrate::run_loop`]).
    pub fn run(
        &mut self,
        s: &mut FullState,
        t_end: f64,
        mut observer: impl FnMut(&FullState, &[f64]) -> bool,
    ) -> Result<u64, VorticityError> {
        let dt = self.dt;
        let mut steps = 0u64;
        while s.t < t_end - 1e-12 * dt {
            let h = (t_end - s.t).min(dt);
            if h < dt {
                self.dt = h;
            }
            let res = self.step(s);
            self.dt = dt;
            res?;
            steps += 1;
            if !observer(s, &self.tw) {
                break;
            }
        }
        Ok(steps)
    }
}

/// The staggered scheme as a [`Stepper`] for the run executor, on the monolithic state layout
/// `[R, Ṙ, (a_k, ȧ_k, b_k, T_k,1 … T_k,n−2)_k]` ([`super::monolithic`]). Steps of `dt` (the last
/// one shortened to land on `t_stop`); the interpolant between two steps is linear (the
/// executor lands on every sample, so it is used only to time a blow-up inside a step).
/// Cost counted per step: 4 evaluations of the ODE part, M tridiagonal factorisations.
/// The wall inputs of (TS) for the mode rates: the first mode's w₀ and, with the lagged wall,
/// the wall vorticity of the previous step (a free function: the callers hold `&mut` borrows of
/// other fields of [`Staggered`] at the same time).
fn wall_inputs<'a>(ops: &[ModeOperator], wall: WallCoupling, tw_lagged: &'a [f64]) -> (f64, Option<&'a [f64]>) {
    let w0 = ops.first().map_or(0.0, |o| o.w0());
    let tw_fixed = match wall {
        WallCoupling::InRhs => None,
        WallCoupling::Lagged => Some(tw_lagged),
    };
    (w0, tw_fixed)
}

pub struct StaggeredStepper<'c> {
    st: Staggered<'c>,
    s: FullState,
    t_prev: f64,
    y: Vec<f64>,
    y_prev: Vec<f64>,
    stats: Stats,
}

impl<'c> StaggeredStepper<'c> {
    pub fn new(st: Staggered<'c>, s: FullState) -> Self {
        let mut me = StaggeredStepper { t_prev: s.t, y: vec![], y_prev: vec![], stats: Stats::default(), st, s };
        me.y = me.packed();
        me.y_prev = me.y.clone();
        me
    }

    fn packed(&self) -> Vec<f64> {
        let s = &self.s;
        let mut y = vec![s.r, s.rdot];
        for m in 0..s.a.len() {
            y.extend_from_slice(&[s.a[m], s.adot[m], s.b[m]]);
            y.extend_from_slice(&s.t_nodes[m]);
        }
        y
    }
}

impl Stepper for StaggeredStepper<'_> {
    crate::integrate::stepper_state!(s.t);
    fn step(&mut self, _sys: &dyn OdeSystem, t_stop: f64) -> Result<(), IntegrateError> {
        let dt = self.st.dt;
        let h = (t_stop - self.s.t).min(dt);
        if !(h > 1e-12 * dt) {
            return Err(IntegrateError::StepSizeTooSmall { t: self.s.t, h });
        }
        let t0 = self.s.t;
        self.st.dt = h;
        let res = self.st.step(&mut self.s);
        self.st.dt = dt;
        self.stats.steps += 1;
        self.stats.rhs_evals += 4;
        self.stats.lu_decompositions += self.s.a.len() as u64;
        let y = self.packed();
        match res {
            Ok(()) => {}
            Err(VorticityError::Singular { t, .. }) => return Err(IntegrateError::SingularMatrix { t }),
            Err(_) => {
                let component = y.iter().position(|v| !v.is_finite()).unwrap_or(0);
                return Err(IntegrateError::NonFinite { t: t0, component });
            }
        }
        if t_stop - self.s.t <= 1e-12 * dt {
            self.s.t = t_stop;
        }
        self.t_prev = t0;
        self.y_prev = std::mem::replace(&mut self.y, y);
        Ok(())
    }
    /// The scheme carries no error history: the state is unpacked at (t, y) (the lagged wall
    /// vorticity of the previous step stays, as after any step).
    fn restart(&mut self, _sys: &dyn OdeSystem, t: f64, y: &[f64], _t_end: f64) -> Result<(), IntegrateError> {
        let s = &mut self.s;
        let nb = 3 + s.t_nodes.first().map_or(0, |v| v.len());
        s.t = t;
        s.r = y[0];
        s.rdot = y[1];
        for m in 0..s.a.len() {
            let b = &y[2 + m * nb..2 + (m + 1) * nb];
            (s.a[m], s.adot[m], s.b[m]) = (b[0], b[1], b[2]);
            s.t_nodes[m].copy_from_slice(&b[3..]);
        }
        self.t_prev = t;
        self.y.copy_from_slice(y);
        self.y_prev.copy_from_slice(y);
        Ok(())
    }
    fn interpolate(&self, t: f64, out: &mut [f64]) {
        let th = (t - self.t_prev) / (self.s.t - self.t_prev).max(f64::MIN_POSITIVE);
        for i in 0..out.len() {
            out[i] = (1.0 - th) * self.y_prev[i] + th * self.y[i];
        }
    }
}
