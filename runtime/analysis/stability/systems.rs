//! The systems behind the Floquet analysis ([`super::prepare`]): the radial equation alone
//! (whose periodic orbit is shot for), the orbit sampled for the shape system, and the linear
//! (a, ȧ, b) boundary-layer system along a prescribed R(t) (paper §4; FORMULATION §4.6).

use crate::analysis::floquet::LinearPeriodic;
use crate::analysis::periodic::{PeriodicOrbit, RkFlow};
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

/// R(t), Ṙ(t) on one orbit period, by cubic Hermite interpolation of RK4 grid values.
pub(super) struct SampledOrbit {
    t0: f64,
    h: f64,
    period: f64,
    pub(super) y: Vec<[f64; 2]>,
    f: Vec<[f64; 2]>,
}

impl SampledOrbit {
    /// From the orbit's own grid ([`PeriodicOrbit::grid`], the same RK4 steps) when it has one
    /// of this step count, else by integrating the orbit once.
    pub(super) fn new(sys: &dyn OdeSystem, orbit: &PeriodicOrbit, steps_per_period: usize) -> Result<Self, StabilityError> {
        let h = orbit.drive_period / steps_per_period as f64;
        if orbit.y0.len() == 2 && orbit.grid.len() == 4 * (orbit.multiple * steps_per_period + 1) {
            let y = orbit.grid.chunks_exact(4).map(|c| [c[0], c[1]]).collect();
            let f = orbit.grid.chunks_exact(4).map(|c| [c[2], c[3]]).collect();
            return Ok(Self { t0: orbit.t0, h, period: orbit.period(), y, f });
        }
        let flow = RkFlow { sys, period: orbit.drive_period, steps_per_period };
        let (mut y, mut f) = (Vec::new(), Vec::new());
        let mut state = orbit.y0.clone();
        flow.advance_observed(orbit.t0, &mut state, orbit.multiple, |_, y_, f_| {
            y.push([y_[0], y_[1]]);
            f.push([f_[0], f_[1]]);
        })?;
        Ok(Self { t0: orbit.t0, h, period: orbit.period(), y, f })
    }

    /// (R, Ṙ) at t (periodic continuation).
    pub(super) fn at(&self, t: f64) -> (f64, f64) {
        let s = (t - self.t0).rem_euclid(self.period) / self.h;
        let i = (s.floor() as usize).min(self.y.len() - 2);
        let u = s - i as f64;
        let (h00, h10, h01, h11) =
            ((1.0 + 2.0 * u) * (1.0 - u).powi(2), u * (1.0 - u).powi(2), u * u * (3.0 - 2.0 * u), u * u * (u - 1.0));
        let v = |c: usize| {
            h00 * self.y[i][c] + h10 * self.h * self.f[i][c] + h01 * self.y[i + 1][c] + h11 * self.h * self.f[i + 1][c]
        };
        (v(0), v(1))
    }
}

/// The linear (a, ȧ, b) system along a prescribed R(t).
pub(super) struct ShapeSystem<'a> {
    bl: &'a BoundaryLayerSystem,
    n: usize,
    pub(super) radial: Box<dyn Fn(f64) -> (f64, f64, f64) + 'a>,
    /// The forcing column of [`BoundaryLayerSystem::linear_modes_into`] (not used: the forcing
    /// is inhomogeneous), kept so that A(t) is assembled without an allocation.
    forcing: std::cell::RefCell<nalgebra::DVector<f64>>,
}

impl<'a> ShapeSystem<'a> {
    pub(super) fn new(bl: &'a BoundaryLayerSystem, n: usize, radial: Box<dyn Fn(f64) -> (f64, f64, f64) + 'a>) -> Self {
        ShapeSystem { bl, n, radial, forcing: std::cell::RefCell::new(nalgebra::DVector::zeros(n)) }
    }
}

impl LinearPeriodic for ShapeSystem<'_> {
    fn dim(&self) -> usize {
        self.n
    }
    /// A(t), assembled exactly from the model's linear structure
    /// ([`BoundaryLayerSystem::linear_modes_into`]).
    fn matrix(&self, t: f64, a: &mut DMatrix<f64>) {
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
