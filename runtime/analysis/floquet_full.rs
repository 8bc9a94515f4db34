//! Floquet on the full vorticity model (issue 13 part 4; paper §4 with the closure of §2.4–2.5,
//! FORMULATION §4.2 and §4.6): the monodromy of the linear (a, ȧ, b, T)_k system of the method
//! of lines ([`crate::model::vorticity::monolithic`]) along a prescribed radial orbit R(t), Ṙ(t)
//! with a = b = T = 0.
//!
//! x' = A(t) x with A(t) the shape block of the monolithic Jacobian at (R(t), Ṙ(t), 0)
//! ([`StructuredJacobian::shape_only`]). A is stiff (the vorticity diffusion on the grid), and
//! its slow diffusion modes have multipliers near 1 (ν k(k+1)/R0² ≈ 6·10⁴ s⁻¹ against a 1 µs
//! period), so the whole monodromy is computed, not a few dominant vectors. The scheme is the
//! L-stable, stiffly accurate 5-stage SDIRK of order 4 (Hairer & Wanner, Solving ODEs II,
//! Table IV.6.5; γ = 1/4): every stage W_i = u_i + hγ A(t_n + c_i h) W_i is one structured solve
//! of (σI − A) W_i = σ u_i, σ = 1/(hγ) — the bordered tridiagonal-in-y factorisation the
//! implicit integrators use (O(M·n) per column), never a dense product of the full state. The
//! fourth-order Magnus scheme of [`super::floquet`] needs exp(Ω) of the (3 + n − 2)-square
//! block and is not used here.
//!
//! Without a field the modes do not couple: each k is its own block of X(T), propagated as the
//! one-mode monolithic system with the other modes held at zero (exact: their loads on mode k
//! vanish). With a field (k ± 2 couplings) the shape state is one block.
//!
//! Not on the run loop ([`crate::integrate::run_loop`]): the SDIRK advances every column of X
//! with the same five stage factorisations per step (one factorisation serves all columns),
//! which a per-state stepper cannot share.

use super::floquet::{FloquetError, Monodromy};
use crate::model::vorticity::monolithic::Monolithic;
use crate::model::vorticity::scene::SceneCoupling;
use crate::model::vorticity::structured::{StructuredJacobian, StructuredLu};
use crate::model::vorticity::Grid;
use crate::integrate::OdeSystem;
use crate::model::effects::LoadJacobian;
use crate::model::layout::StateLayout;
use crate::model::vorticity::ModeCoupling;
use nalgebra::DMatrix;
use std::cell::RefCell;

/// The full model's shape system of one scene: its coupling (radial equation and loads of the
/// boundary-layer model of the same scene), the vorticity grid, and whether modes couple.
pub struct FullShape<'a> {
    pub coupling: SceneCoupling<'a>,
    pub grid: Grid,
    /// `true`: the loads couple k to k ± 2 (a field); the shape state is then one block.
    pub coupled: bool,
}

/// SDIRK4 (Hairer & Wanner Table IV.6.5), γ = 1/4, stiffly accurate (b = last row of a).
const GAMMA: f64 = 0.25;
const C: [f64; 5] = [0.25, 0.75, 11.0 / 20.0, 0.5, 1.0];
const A: [[f64; 4]; 5] = [
    [0.0, 0.0, 0.0, 0.0],
    [0.5, 0.0, 0.0, 0.0],
    [17.0 / 50.0, -1.0 / 25.0, 0.0, 0.0],
    [371.0 / 1360.0, -137.0 / 2720.0, 15.0 / 544.0, 0.0],
    [25.0 / 24.0, -49.0 / 48.0, 125.0 / 16.0, -85.0 / 12.0],
];

impl FullShape<'_> {
    /// Length of one mode's block (a, ȧ, b, T_1 … T_{n−2}).
    pub fn block_len(&self) -> usize {
        3 + self.grid.interior()
    }

    /// Dimension of the shape state, M (3 + n − 2).
    pub fn dim(&self) -> usize {
        self.coupling_orders() * self.block_len()
    }

    fn coupling_orders(&self) -> usize {
        self.coupling.orders().len()
    }

    /// The blocks of X(T) over the shape state (index m·nb + j ↔ mode m, local j).
    pub fn blocks(&self) -> Vec<Vec<usize>> {
        let (m, nb) = (self.coupling_orders(), self.block_len());
        if self.coupled {
            vec![(0..m * nb).collect()]
        } else {
            (0..m).map(|i| (i * nb..(i + 1) * nb).collect()).collect()
        }
    }

    /// Monodromy X(t0 + period) (X(t0) = I) of the shape system along `radial(t) = (R, Ṙ)`
    /// (nondimensional), with `steps` SDIRK4 steps.
    pub fn monodromy(
        &self,
        radial: &dyn Fn(f64) -> (f64, f64),
        t0: f64,
        period: f64,
        steps: usize,
    ) -> Result<Monodromy, FloquetError> {
        self.monodromy_on(&Orbit { radial, breaks: &[], on_branch: &|_, f| f() }, t0, period, steps)
    }

    /// [`FullShape::monodromy`] along an orbit with a kinked law's branch switches: the SDIRK
    /// steps split at `orbit.breaks` (times mod period, [`super::floquet::LinearPeriodic::breaks`])
    /// and each part's stage Jacobians evaluated on the orbit's branch at its midpoint
    /// (docs/stability.md, "Floquet on a kinked law").
    pub fn monodromy_on(&self, orbit: &Orbit<'_>, t0: f64, period: f64, steps: usize) -> Result<Monodromy, FloquetError> {
        super::floquet::check_period_and_steps(period, steps)?;
        let blocks = self.blocks();
        let matrices = if self.coupled {
            let sys = Monolithic::new(&self.coupling, self.grid.clone());
            vec![propagate(&sys, orbit, t0, period, steps)?]
        } else {
            (0..self.coupling_orders())
                .map(|m| {
                    let one = OneMode::new(&self.coupling, m);
                    let sys = Monolithic::new(&one, self.grid.clone());
                    propagate(&sys, orbit, t0, period, steps)
                })
                .collect::<Result<Vec<_>, _>>()?
        };
        for (b, m) in matrices.iter().enumerate() {
            if m.iter().any(|v| !v.is_finite()) {
                return Err(FloquetError::NonFiniteMonodromy { block: b });
            }
        }
        Ok(Monodromy { dim: self.dim(), blocks, matrices })
    }
}

/// The radial orbit the full shape system runs along: (R, Ṙ) at t, the times where A(t) jumps
/// (reduced mod the period; empty for a smooth law), and `on_branch(t, f)`: `f` run with the
/// law on the orbit's branch at t.
pub struct Orbit<'o> {
    pub radial: &'o dyn Fn(f64) -> (f64, f64),
    pub breaks: &'o [f64],
    pub on_branch: &'o dyn Fn(f64, &mut dyn FnMut()),
}

/// X(t0 + period) over the whole shape state of `sys` (every mode it holds), X(t0) = I.
fn propagate(
    sys: &Monolithic<'_>,
    orbit: &Orbit<'_>,
    t0: f64,
    period: f64,
    steps: usize,
) -> Result<DMatrix<f64>, FloquetError> {
    let (n, lay) = (sys.dim(), sys.layout());
    let s0 = lay.shape().start; // shape state = monolithic state without R, Ṙ
    let ns = lay.shape().len();
    let mut x = DMatrix::<f64>::identity(ns, ns);
    let mut y = vec![0.0; n];
    let (mut w, mut u) = (vec![0.0; n], vec![0.0; n]);
    let mut k = vec![vec![0.0; n]; 5];
    let mut lus: Vec<StructuredLu<f64>> = Vec::with_capacity(5);
    let breaks = super::floquet::break_times(orbit.breaks, t0, period);
    let mut step = |t: f64, h: f64| -> Result<(), FloquetError> {
        let sigma = 1.0 / (h * GAMMA);
        lus.clear();
        // the stages on one branch: the part's (its last stage lies on its end, a switch)
        let mut stages = Ok(());
        (orbit.on_branch)(t + 0.5 * h, &mut || {
            stages = (|| {
                for c in C {
                    let tc = t + c * h;
                    let (r, rd) = (orbit.radial)(tc);
                    if !(r.is_finite() && rd.is_finite()) {
                        return Err(FloquetError::NonFiniteMatrix { t: tc, row: 0, col: 1 });
                    }
                    y[lay.r()] = r;
                    y[lay.rdot()] = rd;
                    let jac = StructuredJacobian::shape_only(sys, tc, &y);
                    lus.push(jac.factor(sigma).ok_or(FloquetError::SingularStage { t: tc })?);
                }
                Ok(())
            })();
        });
        stages?;
        for col in 0..ns {
            let xn = x.column(col);
            for (st, lu) in lus.iter().enumerate() {
                // u_i = x_n + h Σ_{j<i} a_ij K_j (R, Ṙ rows stay 0)
                for i in 0..ns {
                    let mut v = xn[i];
                    for (j, a) in A[st].iter().enumerate().take(st) {
                        v += h * a * k[j][s0 + i];
                    }
                    u[s0 + i] = v;
                }
                w.iter_mut().zip(&u).for_each(|(wi, ui)| *wi = sigma * ui);
                lu.solve(&mut w);
                for i in lay.shape() {
                    k[st][i] = (w[i] - u[i]) * sigma;
                }
            }
            // stiffly accurate: x_{n+1} = W_5
            for i in 0..ns {
                x[(i, col)] = w[s0 + i];
            }
        }
        Ok(())
    };
    super::floquet::split_steps(t0, period, steps, &breaks, &mut step)?;
    Ok(x)
}

/// One mode m of a coupling whose loads do not couple modes (no field): the other modes held at
/// zero, so the monolithic system of mode m alone is its exact block (the per-mode solves then
/// cost O(n), not O(M·n)).
struct OneMode<'c> {
    inner: &'c dyn ModeCoupling,
    m: usize,
    order: [usize; 1],
    total: usize,
    buf: RefCell<OneBuf>,
}

struct OneBuf {
    a: Vec<f64>,
    adot: Vec<f64>,
    b: Vec<f64>,
    gn: Vec<f64>,
    gt: Vec<f64>,
    z: Vec<f64>,
    drdd: Vec<f64>,
    jac: LoadJacobian,
}

impl<'c> OneMode<'c> {
    fn new(inner: &'c dyn ModeCoupling, m: usize) -> Self {
        let total = inner.orders().len();
        let zero = || vec![0.0; total];
        let buf = OneBuf {
            a: zero(),
            adot: zero(),
            b: zero(),
            gn: zero(),
            gt: zero(),
            z: vec![0.0; StateLayout::reduced(total).dim()],
            drdd: vec![0.0; StateLayout::reduced(total).dim()],
            jac: LoadJacobian::new(total),
        };
        Self { inner, m, order: [inner.orders()[m]], total, buf: RefCell::new(buf) }
    }
    fn spread(&self, b: &mut OneBuf, a: &[f64], adot: &[f64], bb: &[f64]) {
        b.a[self.m] = a[0];
        b.adot[self.m] = adot[0];
        b.b[self.m] = bb[0];
    }
}

impl ModeCoupling for OneMode<'_> {
    fn orders(&self) -> &[usize] {
        &self.order
    }
    fn density(&self) -> f64 {
        self.inner.density()
    }
    fn viscosity(&self) -> f64 {
        self.inner.viscosity()
    }
    fn radial_acceleration(&self, t: f64, r: f64, rdot: f64, a: &[f64], adot: &[f64], b: &[f64]) -> f64 {
        let mut g = self.buf.borrow_mut();
        self.spread(&mut g, a, adot, b);
        self.inner.radial_acceleration(t, r, rdot, &g.a, &g.adot, &g.b)
    }
    fn shape_loads(&self, t: f64, r: f64, rdot: f64, a: &[f64], adot: &[f64], b: &[f64], gn: &mut [f64], gt: &mut [f64]) {
        self.loads(t, r, rdot, a, adot, b, gn, gt);
    }
    fn loads(&self, t: f64, r: f64, rdot: f64, a: &[f64], adot: &[f64], b: &[f64], gn: &mut [f64], gt: &mut [f64]) -> f64 {
        let mut guard = self.buf.borrow_mut();
        let g = &mut *guard;
        self.spread(g, a, adot, b);
        let rdd = self.inner.loads(t, r, rdot, &g.a, &g.adot, &g.b, &mut g.gn, &mut g.gt);
        gn[0] = g.gn[self.m];
        gt[0] = g.gt[self.m];
        rdd
    }
    fn mode_stiffness(&self, t: f64, r: f64) -> Vec<[f64; 4]> {
        vec![self.inner.mode_stiffness(t, r)[self.m]]
    }
    fn linearize(&self, t: f64, z: &[f64], drdd: &mut [f64], jac: &mut LoadJacobian) {
        let mut guard = self.buf.borrow_mut();
        let g = &mut *guard;
        // z holds this one mode (index 0), g.z every mode of the inner coupling
        let (one, all) = (StateLayout::reduced(1), StateLayout::reduced(self.total));
        let (radial, mine, its) = (0..StateLayout::RADIAL, all.amplitudes(self.m), one.amplitudes(0));
        g.z.fill(0.0);
        g.z[radial.clone()].copy_from_slice(&z[radial.clone()]);
        g.z[mine.clone()].copy_from_slice(&z[its.clone()]);
        self.inner.linearize(t, &g.z, &mut g.drdd, &mut g.jac);
        debug_assert_eq!(g.jac.modes(), self.total);
        let pick = |full: &[f64], out: &mut [f64]| {
            out[radial.clone()].copy_from_slice(&full[radial.clone()]);
            out[its.clone()].copy_from_slice(&full[mine.clone()]);
        };
        pick(&g.drdd, drdd);
        pick(&g.jac.pressure, &mut jac.pressure);
        pick(g.jac.gn_row(self.m), &mut jac.gn[..one.dim()]);
        pick(g.jac.gt_row(self.m), &mut jac.gt[..one.dim()]);
    }
}
