//! The monolithic full model: the method of lines (FORMULATION §4.2, "integrate monolithically").
//! Every interior T node is an ODE state; T_w is eliminated algebraically from (TS) at every
//! evaluation, so the system is an explicit ODE (not a DAE) of size 2 + M(3 + n − 2).
//!
//! State layout (mode-major, so a mode's unknowns are contiguous; [`StateLayout::monolithic`]):
//! `[R, Ṙ, (a_k, ȧ_k, b_k, T_k,1 … T_k,n−2) for k = 2, 4, …, N]`.
//!
//! Jacobian structure: per mode, the T block is tridiagonal except for its first row (T_w
//! contains Ĩ_int = Σ W_i T_i) and the (ȧ, b) rows (they see Ĩ and J, integrals over the whole
//! block); R and Ṙ couple to every row, and the field couples mode k to k ± 2. The Jacobian is
//! therefore not banded (see docs/vorticity.md for the structured solve the implicit integrator
//! needs); [`OdeSystem::bandwidth`] reports `None`.

use super::equations::{coupled_mode_rates, LoadScratch, ModeInputs, ModeRates};
use super::operator::{ModeOperator, SharedRows};
use super::{FullState, Grid, ModeCoupling};
use crate::integrate::OdeSystem;
use crate::model::layout::StateLayout;
use std::cell::RefCell;

/// The full model as one ODE system.
pub struct Monolithic<'c> {
    coupling: &'c dyn ModeCoupling,
    pub grid: Grid,
    layout: StateLayout,
    ops: Vec<ModeOperator>,
    scratch: RefCell<Scratch>,
    /// The reduced state and its rates, reused by every `rhs` call (no allocation per call).
    reduced_buf: RefCell<ReducedBuf>,
}

struct ReducedBuf {
    z: Vec<f64>,
    p: Vec<f64>,
    fz: Vec<f64>,
    tw: Vec<f64>,
}

#[derive(Default)]
struct Scratch {
    loads: LoadScratch,
    a: Vec<f64>,
    adot: Vec<f64>,
    b: Vec<f64>,
    add: Vec<f64>,
    bdot: Vec<f64>,
    tw: Vec<f64>,
    /// The operator rows shared by every mode (`ModeOperator::shared_rows`).
    shared: SharedRows,
}

impl<'c> Monolithic<'c> {
    pub fn new(coupling: &'c dyn ModeCoupling, grid: Grid) -> Self {
        let m = coupling.orders().len();
        let ops = coupling.orders().iter().map(|&k| ModeOperator::new(&grid, k)).collect();
        let z = || vec![0.0; m];
        let scratch = Scratch {
            loads: LoadScratch::new(m),
            a: z(),
            adot: z(),
            b: z(),
            add: z(),
            bdot: z(),
            tw: z(),
            shared: SharedRows::default(),
        };
        let layout = StateLayout::monolithic(m, grid.interior());
        let zl = layout.boundary_layer();
        let reduced_buf = ReducedBuf { z: vec![0.0; zl.dim()], p: vec![0.0; 2 * m], fz: vec![0.0; zl.dim()], tw: z() };
        Self { coupling, grid, layout, ops, scratch: RefCell::new(scratch), reduced_buf: RefCell::new(reduced_buf) }
    }

    /// The state layout: mode blocks of 3 + n − 2 ([`StateLayout::monolithic`]).
    #[inline]
    pub fn layout(&self) -> StateLayout {
        self.layout
    }

    /// Packs a [`FullState`] into the ODE state vector.
    pub fn pack(&self, s: &FullState) -> Vec<f64> {
        let l = self.layout;
        let mut y = vec![0.0; l.dim()];
        y[l.r()] = s.r;
        y[l.rdot()] = s.rdot;
        for m in 0..l.modes() {
            y[l.a(m)] = s.a[m];
            y[l.adot(m)] = s.adot[m];
            y[l.b(m)] = s.b[m];
            y[l.node_range(m)].copy_from_slice(&s.t_nodes[m]);
        }
        y
    }

    /// Unpacks an ODE state vector at time t.
    pub fn unpack(&self, t: f64, y: &[f64]) -> FullState {
        let l = self.layout;
        let m = l.modes();
        let mut s = FullState::new(t, y[l.r()], y[l.rdot()], vec![0.0; m], vec![0.0; m], vec![0.0; m], l.nodes());
        for mi in 0..m {
            s.a[mi] = y[l.a(mi)];
            s.adot[mi] = y[l.adot(mi)];
            s.b[mi] = y[l.b(mi)];
            s.t_nodes[mi].copy_from_slice(&y[l.node_range(mi)]);
        }
        s
    }

    /// Wall vorticity T_w,k at state y (from TS, FORMULATION §4.2).
    pub fn wall_vorticity(&self, t: f64, y: &[f64]) -> Vec<f64> {
        let mut dy = vec![0.0; y.len()];
        self.rhs(t, y, &mut dy);
        self.scratch.borrow().tw.clone()
    }
}

impl Monolithic<'_> {
    /// The "reduced" right-hand side: the ODE part f_z and the wall values T_w from
    /// z = [R, Ṙ, (a_k, ȧ_k, b_k)_k] (length 2 + 3M) and the vorticity functionals
    /// p = [Ĩ_int,k (M), ∫(y⁻³−1)y^{−k}T dy (M)]. The T nodes enter the ODE part only through p,
    /// which is what the structured linear solve ([`super::structured`]) exploits.
    pub fn reduced(&self, t: f64, z: &[f64], p: &[f64], fz: &mut [f64], tw: &mut [f64]) {
        let mut guard = self.scratch.borrow_mut();
        let sc = &mut *guard;
        let (m, zl) = (self.ops.len(), self.layout.boundary_layer());
        let (r, rdot) = (z[zl.r()], z[zl.rdot()]);
        for mi in 0..m {
            sc.a[mi] = z[zl.a(mi)];
            sc.adot[mi] = z[zl.adot(mi)];
            sc.b[mi] = z[zl.b(mi)];
        }
        let rddot = sc.loads.eval(self.coupling, t, r, rdot, &sc.a, &sc.adot, &sc.b);
        fz[zl.r()] = rdot;
        fz[zl.rdot()] = rddot;
        let inputs = ModeInputs {
            r,
            rdot,
            rddot,
            a: &sc.a,
            adot: &sc.adot,
            b: &sc.b,
            gn: &sc.loads.gn,
            gt: &sc.loads.gt,
            i_int: &p[..m],
            j_over_r: &p[m..2 * m],
            w0: self.ops.first().map_or(0.0, |o| o.w0()),
            tw_fixed: None,
        };
        // with second-pass loads (issue 12) R̈ of the completed radial balance
        fz[zl.rdot()] = coupled_mode_rates(self.coupling, t, &inputs, ModeRates { add: &mut sc.add, bdot: &mut sc.bdot, tw });
        for mi in 0..m {
            fz[zl.a(mi)] = sc.adot[mi];
            fz[zl.adot(mi)] = sc.add[mi];
            fz[zl.b(mi)] = sc.bdot[mi];
        }
    }

    /// Splits a state into z (ODE part) and p (vorticity functionals).
    pub fn split(&self, y: &[f64], z: &mut [f64], p: &mut [f64]) {
        let (m, l) = (self.ops.len(), self.layout);
        l.gather_amplitudes(y, z);
        for (mi, op) in self.ops.iter().enumerate() {
            (p[mi], p[m + mi]) = op.functionals_lanes(&y[l.node_range(mi)]);
        }
    }

    /// The mode operators (one per k).
    pub fn operators(&self) -> &[ModeOperator] {
        &self.ops
    }

    /// The coupling.
    pub fn coupling(&self) -> &dyn ModeCoupling {
        self.coupling
    }
}

impl OdeSystem for Monolithic<'_> {
    fn dim(&self) -> usize {
        self.layout.dim()
    }

    /// The bordered-tridiagonal structure of J ([`super::structured`]): implicit steppers solve
    /// σI − J in O(M·n).
    fn structured_jacobian(&self, t: f64, y: &[f64]) -> Option<Box<dyn crate::integrate::linear::StructuredJacobian>> {
        Some(Box::new(super::structured::Hook(super::structured::StructuredJacobian::new(self, t, y))))
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let l = self.layout;
        let mut buf = self.reduced_buf.borrow_mut();
        let ReducedBuf { z, p, fz, tw } = &mut *buf;
        self.split(y, z, p);
        self.reduced(t, z, p, fz, tw);
        dy[..StateLayout::RADIAL].copy_from_slice(&fz[..StateLayout::RADIAL]);
        let mut guard = self.scratch.borrow_mut();
        let sc = &mut *guard;
        sc.tw.copy_from_slice(tw);
        let (r, rdot) = (y[l.r()], y[l.rdot()]);
        let nu = self.coupling.viscosity() / self.coupling.density();
        if let Some(op) = self.ops.first() {
            op.shared_rows(r, rdot, nu, &mut sc.shared);
        }
        let zl = l.boundary_layer();
        for (mi, op) in self.ops.iter().enumerate() {
            dy[l.amplitudes(mi)].copy_from_slice(&fz[zl.amplitudes(mi)]);
            op.apply_shared(&sc.shared, tw[mi], &y[l.node_range(mi)], &mut dy[l.node_range(mi)]);
        }
    }
}
