//! The systems behind the Floquet analysis ([`super::prepare`]): the radial equation alone
//! (whose periodic orbit is shot for), the orbit sampled for the shape system, and the linear
//! (a, ȧ, b) boundary-layer system along a prescribed R(t) (paper §4; FORMULATION §4.6).

use crate::analysis::floquet::LinearPeriodic;
use crate::analysis::periodic::{PeriodicOrbit, RkFlow, Switching};
use super::StabilityError;
use crate::integrate::OdeSystem;
use crate::model::layout::StateLayout;
use crate::model::{BoundaryLayerSystem, Model};
use nalgebra::DMatrix;

/// The radial equation alone at a_k = b_k = 0 (M0 evaluated with zero shape amplitudes): the
/// system whose periodic orbit [`super::floquet`] shoots for. State [R, Ṙ], nondimensional.
pub struct Radial<'a> {
    bl: &'a BoundaryLayerSystem,
    full: usize,
    /// (t, R, Ṙ, R̈) of the last [`OdeSystem::jacobian`] call: the exact gradient computes R̈
    /// too, and the variational RK4 of the orbit search asks for the Jacobian and then the rhs
    /// at the same point ([`crate::analysis::periodic::RkFlow::advance_variational`]), so the rhs reuses
    /// it (bit-identical: the same loads and the same radial form).
    last: std::cell::Cell<[f64; 4]>,
}

impl<'a> Radial<'a> {
    /// The radial system of a model with shape modes (`None` for a radial-only model).
    pub fn of(model: &'a Model) -> Option<Self> {
        model.boundary_layer().map(|bl| Radial::new(bl, bl.dim()))
    }

    pub(super) fn new(bl: &'a BoundaryLayerSystem, full: usize) -> Self {
        Radial { bl, full, last: std::cell::Cell::new([f64::NAN; 4]) }
    }
}

impl Radial<'_> {
    /// `f` of the model state z = [R, Ṙ, 0, …] (a stack buffer: the rhs runs ~10⁵ times per
    /// orbit, and zeroing only what k ≤ 36 needs saves a memset of the largest size); `None`
    /// beyond the largest supported state.
    #[inline]
    pub(super) fn at_rest_shape<T>(&self, y: &[f64], f: impl FnOnce(&[f64]) -> T) -> Option<T> {
        fn fill<const L: usize, T>(full: usize, y: &[f64], f: impl FnOnce(&[f64]) -> T) -> T {
            let mut z = [0.0; L];
            z[0] = y[0];
            z[1] = y[1];
            f(&z[..full])
        }
        match self.full {
            n if n <= 56 => Some(fill::<56, T>(n, y, f)),
            n if n <= StateLayout::reduced(64).dim() => Some(fill::<{ StateLayout::reduced(64).dim() }, T>(n, y, f)),
            _ => None,
        }
    }
}

impl OdeSystem for Radial<'_> {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        let [tl, rl, rdl, rddl] = self.last.get();
        dy[1] = if tl == t && rl == y[0] && rdl == y[1] {
            rddl
        } else {
            self.at_rest_shape(y, |z| self.bl.radial_acceleration(t, z)).unwrap_or(f64::NAN)
        };
    }
    /// Exact: [[0, 1], ∂R̈/∂(R, Ṙ)] at a_k = b_k = 0 ([`crate::model::equations::Equations::radial_gradient`]).
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut [f64]) -> bool {
        let Some((rdd, g)) = self.at_rest_shape(y, |z| self.bl.equations().radial_gradient(t, z)) else { return false };
        self.last.set([t, y[0], y[1], rdd]);
        jac[..4].copy_from_slice(&[0.0, 1.0, g[0], g[1]]);
        true
    }
}

/// R(t), Ṙ(t) on one orbit period, by cubic Hermite interpolation of RK4 grid values; on a kinked
/// law also between the grid points and the located branch switches inside their interval
/// (y and the one-sided f there: the interpolant has no kink inside a piece).
pub(super) struct SampledOrbit {
    t0: f64,
    h: f64,
    period: f64,
    pub(super) y: Vec<[f64; 2]>,
    f: Vec<[f64; 2]>,
    switches: Vec<SampledSwitch>,
    /// The branch at t0 (see [`BranchTimes`]).
    start_branch: u8,
}

/// A branch switch of the sampled orbit: its phase t − t0 in [0, period), its grid interval, y,
/// f on the branch left and on the branch entered, and the branch entered.
#[derive(Clone, Copy)]
struct SampledSwitch {
    phase: f64,
    interval: usize,
    y: [f64; 2],
    f_before: [f64; 2],
    f_after: [f64; 2],
    branch: u8,
}

/// The cubic Hermite interpolant on [ta, ta + h] from (y, f) at both ends, at phase p.
#[inline]
fn hermite(ta: f64, h: f64, ya: [f64; 2], fa: [f64; 2], yb: [f64; 2], fb: [f64; 2], p: f64) -> (f64, f64) {
    let u = (p - ta) / h;
    let (h00, h10, h01, h11) = ((1.0 + 2.0 * u) * (1.0 - u).powi(2), u * (1.0 - u).powi(2), u * u * (3.0 - 2.0 * u), u * u * (u - 1.0));
    let v = |c: usize| h00 * ya[c] + h10 * h * fa[c] + h01 * yb[c] + h11 * h * fb[c];
    (v(0), v(1))
}

impl SampledOrbit {
    /// From the orbit's own grid ([`PeriodicOrbit::grid`], the same RK4 steps) when it has one
    /// of this step count, else by integrating the orbit once (with `switching`, the kinked
    /// law's branch switches of the same period map).
    pub(super) fn new(
        sys: &dyn OdeSystem,
        switching: Option<&dyn Switching>,
        orbit: &PeriodicOrbit,
        steps_per_period: usize,
    ) -> Result<Self, StabilityError> {
        let h = orbit.drive_period / steps_per_period as f64;
        let mut out = if orbit.y0.len() == 2 && orbit.grid.len() == 4 * (orbit.multiple * steps_per_period + 1) {
            let y = orbit.grid.chunks_exact(4).map(|c| [c[0], c[1]]).collect();
            let f = orbit.grid.chunks_exact(4).map(|c| [c[2], c[3]]).collect();
            let mut o = Self { t0: orbit.t0, h, period: orbit.period(), y, f, switches: Vec::new(), start_branch: orbit.start_branch };
            o.set_switches(&orbit.switches);
            o
        } else {
            let flow = RkFlow { sys, period: orbit.drive_period, steps_per_period, switching };
            let (mut y, mut f, mut log) = (Vec::new(), Vec::new(), Vec::new());
            let mut state = orbit.y0.clone();
            flow.advance_recorded(
                orbit.t0,
                &mut state,
                orbit.multiple,
                |_, y_, f_| {
                    y.push([y_[0], y_[1]]);
                    f.push([f_[0], f_[1]]);
                },
                &mut log,
            )?;
            let mut o = Self { t0: orbit.t0, h, period: orbit.period(), y, f, switches: Vec::new(), start_branch: orbit.start_branch };
            o.set_switches(&log);
            o
        };
        out.switches.sort_by(|a, b| a.phase.total_cmp(&b.phase));
        Ok(out)
    }

    fn set_switches(&mut self, log: &[crate::analysis::periodic::Switch]) {
        let last = self.y.len() - 2;
        self.switches = log
            .iter()
            .map(|w| {
                let phase = (w.t - self.t0).rem_euclid(self.period);
                let two = |v: &[f64]| [v[0], v[1]];
                SampledSwitch {
                    phase,
                    interval: ((phase / self.h).floor() as usize).min(last),
                    y: two(&w.y),
                    f_before: two(&w.f_before),
                    f_after: two(&w.f_after),
                    branch: w.branch,
                }
            })
            .collect();
    }

    /// (R, Ṙ) at t (periodic continuation).
    pub(super) fn at(&self, t: f64) -> (f64, f64) {
        let s = (t - self.t0).rem_euclid(self.period) / self.h;
        let i = (s.floor() as usize).min(self.y.len() - 2);
        if !self.switches.is_empty() {
            if let Some(v) = self.at_switched((t - self.t0).rem_euclid(self.period), i) {
                return v;
            }
        }
        let u = s - i as f64;
        let (h00, h10, h01, h11) =
            ((1.0 + 2.0 * u) * (1.0 - u).powi(2), u * (1.0 - u).powi(2), u * u * (3.0 - 2.0 * u), u * u * (u - 1.0));
        let v = |c: usize| {
            h00 * self.y[i][c] + h10 * self.h * self.f[i][c] + h01 * self.y[i + 1][c] + h11 * self.h * self.f[i + 1][c]
        };
        (v(0), v(1))
    }

    /// (R, Ṙ) at phase p of grid interval i when switches lie inside it (`None`: none do): the
    /// Hermite piece between the grid points and switches around p.
    fn at_switched(&self, p: f64, i: usize) -> Option<(f64, f64)> {
        let lo = self.switches.partition_point(|w| w.interval < i);
        let hi = self.switches.partition_point(|w| w.interval <= i);
        if lo == hi {
            return None;
        }
        let (mut ta, mut ya, mut fa) = (i as f64 * self.h, self.y[i], self.f[i]);
        for w in &self.switches[lo..hi] {
            if p < w.phase {
                return Some(hermite(ta, w.phase - ta, ya, fa, w.y, w.f_before, p));
            }
            (ta, ya, fa) = (w.phase, w.y, w.f_after);
        }
        Some(hermite(ta, (i + 1) as f64 * self.h - ta, ya, fa, self.y[i + 1], self.f[i + 1], p))
    }

    /// The orbit's branches over its period (`None`: no switch located on it).
    pub(super) fn branch_times(&self) -> Option<BranchTimes> {
        (!self.switches.is_empty()).then(|| BranchTimes {
            t0: self.t0,
            period: self.period,
            start: self.start_branch,
            switches: self.switches.iter().map(|w| (w.phase, w.branch)).collect(),
        })
    }
}

/// Which branch of a kinked law the orbit is on at each phase: `start` from t0, then the branch
/// each switch (phase, branch) enters.
pub(super) struct BranchTimes {
    t0: f64,
    period: f64,
    start: u8,
    switches: Vec<(f64, u8)>,
}

impl BranchTimes {
    /// The branch at time t (periodic continuation).
    fn at(&self, t: f64) -> u8 {
        let p = (t - self.t0).rem_euclid(self.period);
        let k = self.switches.partition_point(|w| w.0 <= p);
        if k == 0 { self.start } else { self.switches[k - 1].1 }
    }

    /// The switch times reduced to [0, period) (`LinearPeriodic::breaks`).
    fn breaks(&self) -> Vec<f64> {
        let mut b: Vec<f64> = self.switches.iter().map(|w| (self.t0 + w.0).rem_euclid(self.period)).collect();
        b.sort_by(f64::total_cmp);
        b
    }
}

/// The branch `code` set on `sw` while the guard lives, the previous one restored on drop.
pub(super) struct OnBranch<'a> {
    sw: &'a dyn Switching,
    saved: u8,
}

impl<'a> OnBranch<'a> {
    fn new(sw: &'a dyn Switching, code: u8) -> Self {
        let saved = sw.branch();
        sw.set_branch(code);
        OnBranch { sw, saved }
    }
}

impl Drop for OnBranch<'_> {
    fn drop(&mut self) {
        self.sw.set_branch(self.saved);
    }
}

/// The linear (a, ȧ, b) system along a prescribed R(t).
pub(super) struct ShapeSystem<'a> {
    bl: &'a BoundaryLayerSystem,
    n: usize,
    pub(super) radial: Box<dyn Fn(f64) -> (f64, f64, f64) + 'a>,
    /// On a kinked law whose switches the orbit crosses: the law and the orbit's branch at each
    /// time. A(t) and R̈ are evaluated on it (as in a run), and the Magnus steps split at its
    /// switches ([`LinearPeriodic::breaks`]).
    branches: Option<(&'a dyn Switching, BranchTimes)>,
    /// The forcing column of [`BoundaryLayerSystem::linear_modes_into`] (not used: the forcing
    /// is inhomogeneous), kept so that A(t) is assembled without an allocation.
    forcing: std::cell::RefCell<nalgebra::DVector<f64>>,
}

impl<'a> ShapeSystem<'a> {
    pub(super) fn new(bl: &'a BoundaryLayerSystem, n: usize, radial: Box<dyn Fn(f64) -> (f64, f64, f64) + 'a>) -> Self {
        ShapeSystem { bl, n, radial, branches: None, forcing: std::cell::RefCell::new(nalgebra::DVector::zeros(n)) }
    }

    /// The shape system on a kinked law's branches along the orbit (see `branches`).
    pub(super) fn on_branches(mut self, sw: &'a dyn Switching, times: BranchTimes) -> Self {
        self.branches = Some((sw, times));
        self
    }

    /// The law on the orbit's branch at t while the guard lives (`None`: a smooth law).
    pub(super) fn enter(&self, t: f64) -> Option<OnBranch<'a>> {
        self.branches.as_ref().map(|(sw, times)| OnBranch::new(*sw, times.at(t)))
    }
}

impl LinearPeriodic for ShapeSystem<'_> {
    fn dim(&self) -> usize {
        self.n
    }
    /// A(t), assembled exactly from the model's linear structure
    /// ([`BoundaryLayerSystem::linear_modes_into`]).
    fn matrix(&self, t: f64, a: &mut DMatrix<f64>) {
        let _on = self.enter(t);
        let (r, rd, rdd) = (self.radial)(t);
        self.bl.linear_modes_into(t, r, rd, rdd, a, &mut self.forcing.borrow_mut());
    }
    /// Without a field each block lies within one mode's (a, ȧ, b): assembled from the mode
    /// blocks directly ([`BoundaryLayerSystem::linear_mode_blocks_into`], the same entries as
    /// [`matrix`](Self::matrix)).
    fn block_matrices(&self, t: f64, blocks: &[Vec<usize>], out: &mut [DMatrix<f64>]) {
        if self.bl.jacobian_pattern().band > 0 {
            return self.matrix(t, &mut out[0]);
        }
        let _on = self.enter(t);
        let (r, rd, rdd) = (self.radial)(t);
        let mut mb = [[0.0; 9]; crate::model::effects::MAX_MODES];
        self.bl.linear_mode_blocks_into(t, r, rd, rdd, &mut mb[..self.bl.modes().len()]);
        // x's entries by (mode, entry of its (a, ȧ, b)); the blocks are 3 × 3 column-major
        let (mode, entry) = (StateLayout::x_mode, StateLayout::x_entry);
        for (idx, o) in blocks.iter().zip(out) {
            let m = mode(idx[0]);
            for (bj, &j) in idx.iter().enumerate() {
                for (bi, &i) in idx.iter().enumerate() {
                    debug_assert!(mode(i) == m && mode(j) == m, "a block spans two modes");
                    o[(bi, bj)] = mb[m][entry(j) * StateLayout::AMPLITUDES + entry(i)];
                }
            }
        }
    }
    fn breaks(&self) -> Vec<f64> {
        self.branches.as_ref().map_or_else(Vec::new, |(_, times)| times.breaks())
    }
    fn blocks(&self) -> Vec<Vec<usize>> {
        if self.bl.jacobian_pattern().band > 0 {
            vec![(0..self.n).collect()]
        } else if self.b_free() {
            (0..self.bl.modes().len()).flat_map(|m| [vec![StateLayout::x_a(m), StateLayout::x_adot(m)], vec![StateLayout::x_b(m)]]).collect()
        } else {
            (0..self.bl.modes().len()).map(|m| vec![StateLayout::x_a(m), StateLayout::x_adot(m), StateLayout::x_b(m)]).collect()
        }
    }
}

impl ShapeSystem<'_> {
    /// Whether no b_k feeds back into the (a, ȧ) rows (a free bubble: surface tension and bending
    /// have no tangential stiffness, S2 = S12 = 0, no field). A(t) is then block lower-triangular,
    /// the (a, ȧ) blocks carry the shape's multipliers, and each b_k block only relabels material
    /// points: ḃ = Ṙb/R + (terms in a, ȧ) gives the multiplier R(T)/R(0) = 1 on any orbit, neutral
    /// and not a shape instability. Checked on A at a generic (t, R, Ṙ, R̈).
    pub(super) fn b_free(&self) -> bool {
        if self.bl.jacobian_pattern().band > 0 {
            return false;
        }
        let (a, _) = self.bl.linear_modes(0.1, 1.1, 0.3, -0.2);
        let is_b = |i: usize| StateLayout::x_entry(i) == StateLayout::B;
        (0..self.bl.modes().len()).all(|m| (0..self.n).all(|i| is_b(i) || a[(i, StateLayout::x_b(m))] == 0.0))
    }
}

/// −½ ∂R̈/∂Ṙ at (R0, Ṙ = 0), t = 0: the radial damping rate γ (nondimensional).
pub(super) fn radial_damping_rate(radial: &Radial) -> f64 {
    let (mut fp, mut fm) = ([0.0; 2], [0.0; 2]);
    let h = 1e-6;
    radial.rhs(0.0, &[1.0, h], &mut fp);
    radial.rhs(0.0, &[1.0, -h], &mut fm);
    -0.5 * (fp[1] - fm[1]) / (2.0 * h)
}
