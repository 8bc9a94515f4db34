//! The boundary-layer closure (paper §3, eqs 3.1–3.2; FORMULATION §4.3): the mode equations of
//! [`super::equations`] with Ĩ_k = δ_k T_w/R, J_k = 0, as an explicit ODE.
//!
//! State y = [R, Ṙ, (a_k, ȧ_k, b_k) for k = 2, 4, …, N], dimension 2 + 3M, with
//! δ_k = min(√(ν/ω), R/(2k)) (eq 3.1; ω per FORMULATION audit 13). Eliminating T_w from (TS):
//!
//! ```text
//! T_w = [2(k+2)ȧ/(k+1) + 2(1−k)Ṙa/((k+1)R) − R G_t/η] / (1 + 2δ/R)     (corrected 2.65, audit 3–4)
//! ḃ   = Ṙb/R − ȧ/(k+1) − 2Ṙa/((k+1)R) + δ T_w/R                          (2.67 with 3.1)
//! ä   = −[3Ṙȧ − (k−1)R̈a]/R − (k+1)/(ρR)[2η(k+2)ȧ/R + 4η(k−1)Ṙa/R²
//!        + (kηT_w/R)(1 − 2(k+1)δ/R) + G_n]                                 (2.64 × (k+1)/(ρR), audit 2, 5)
//! ```
//! R̈ enters ä_k, so the radial equation (§4.1) is evaluated first. With second-pass terms
//! (the quadratic coupling, [`super::effects::second_order`]) R̈ and the mode rates are evaluated
//! a second time, from the loads completed with the first-order R̈, ä. The exact Jacobian and
//! the linear mode system A(t) are in [`super::linearize`].

use super::effects::second_order::{FirstOrder, MaterialLoads};
use super::effects::{zeroed, BdotLoads, Loads, MAX_MODES};
use super::equations::{mode_rates, mode_shift, wall_source, Equations, Wall, WallLinear};
use super::layout::StateLayout;
use super::params::Params;

/// Per-mode constants.
#[derive(Debug, Clone, Copy)]
pub struct ModeConst {
    /// k as f64
    pub k: f64,
    /// √(ν/ω) (nondimensional): the viscous length of δ_k before the R/(2k) cap.
    pub viscous_length: f64,
}

impl ModeConst {
    /// δ_k = min(√(ν/ω), R/(2k)) (eq 3.1).
    #[inline]
    pub fn delta(&self, r: f64) -> f64 {
        self.viscous_length.min(r / (2.0 * self.k))
    }
    /// dδ_k/dR (0 on the √(ν/ω) branch, 1/(2k) on the cap).
    #[inline]
    pub fn delta_dr(&self, r: f64) -> f64 {
        if self.viscous_length <= r / (2.0 * self.k) {
            0.0
        } else {
            1.0 / (2.0 * self.k)
        }
    }

    /// The boundary-layer wall terms from the (TS) source A (module doc).
    #[inline]
    pub fn wall(&self, eta: f64, r: f64, src: f64) -> Wall {
        let k = self.k;
        let delta = self.delta(r);
        let tw = src / (1.0 + 2.0 * delta / r);
        Wall { tw, itil: delta * tw / r, normal: [(k * eta * tw / r) * (1.0 - 2.0 * (k + 1.0) * delta / r), 0.0, 0.0] }
    }

    /// T_w, Ĩ = δT_w/R, J = 0 and their partials, from A and ∂A/∂(R, Ṙ, a, ȧ, G_t).
    pub fn wall_linear(&self, r: f64, src: f64, d_src: &[f64; 5]) -> WallLinear {
        use super::equations::var::*;
        let (delta, dd) = (self.delta(r), self.delta_dr(r));
        let den = 1.0 + 2.0 * delta / r;
        let den_r = 2.0 * (dd * r - delta) / (r * r);
        let tw = src / den;
        let mut w = WallLinear { tw, itil: delta * tw / r, ..WallLinear::default() };
        for (x, &d) in [R, RD, A, AD, GT].iter().zip(d_src) {
            w.d_tw[*x] = d / den;
        }
        w.d_tw[R] -= src * den_r / (den * den);
        for x in 0..N {
            w.d_itil[x] = delta * w.d_tw[x] / r;
        }
        w.d_itil[R] += (dd / r - delta / (r * r)) * tw;
        w
    }
}

/// Up to this many shape modes the boundary-layer Newton matrices are factored with the
/// position rows eliminated, densely (1 + 2M unknowns); above, as a bordered band. Measured with
/// callgrind on `run scenes/coil_static.toml --set drive.amplitude=0.2` (docs/performance.md,
/// "branch runs"): M = 8 (k ≤ 16) 350·10⁶ against 396·10⁶ instructions, M = 12 556 against 576,
/// M = 16 834 against 752.
const POSITION_ROWS_MAX_MODES: usize = 12;

/// Radial + shape modes with the boundary-layer closure, with the terms of the scene.
#[derive(Debug)]
pub struct BoundaryLayerSystem {
    pub(crate) eq: Equations,
    pub(crate) modes: Vec<ModeConst>,
    /// R̈ needs ḃ_k (Keller–Miksis with a field, [`Equations::needs_bdot`]): the rhs then
    /// evaluates (NS) first — ḃ does not depend on R̈ — and R̈ with it.
    pub(crate) bdot_radial: bool,
    /// Some shape loads are proportional to ḃ_k (shell viscosity, [`Equations::has_bdot_loads`]):
    /// [`apply_bdot_loads`](Self::apply_bdot_loads) solves (NS) for ḃ_k first.
    pub(crate) bdot_loads: bool,
    /// The absolute-tolerance weight of each mode's (a_k, ȧ_k, b_k) ([`crate::integrate::OdeSystem::error_scale`],
    /// docs/integrators.md "Error weights"); R and Ṙ have weight 1.
    pub(crate) shape_weights: Vec<f64>,
    /// The reduced thermal model's ṗ_b (`gas.thermal = "reduced"`, docs/model.md "Reduced
    /// thermal model"): p_b in the gas slot after the mode blocks
    /// ([`StateLayout::with_gas`]); it enters R̈ through P (the gas term) and the mode rows only
    /// through R̈. `None` for every other gas.
    pub(crate) gas: Option<super::effects::reduced_gas::ReducedGas>,
}

/// Per mode, what [`BoundaryLayerSystem::apply_bdot_loads`] found: the coefficients
/// (cn, ct, ∂cn/∂R, ∂ct/∂R) of the ḃ_k loads and ḃ_k itself.
pub(crate) type BdotMode = [f64; 5];

impl BoundaryLayerSystem {
    /// δ_k = min(√(ν/ω), R/(2k)) (eq 3.1).
    #[inline]
    pub fn delta(&self, m: usize, r: f64) -> f64 {
        self.modes[m].delta(r)
    }

    pub fn equations(&self) -> &Equations {
        &self.eq
    }

    pub fn params(&self) -> &Params {
        &self.eq.params
    }

    pub fn modes(&self) -> &[ModeConst] {
        &self.modes
    }

    /// The state layout, y = [R, Ṙ, (a_k, ȧ_k, b_k)_k] (then p_b with the reduced thermal model).
    #[inline]
    pub fn layout(&self) -> StateLayout {
        let l = StateLayout::reduced(self.modes.len());
        if self.gas.is_some() {
            l.with_gas()
        } else {
            l
        }
    }

    /// ṗ_b into its slot of `dy` (the reduced thermal model; no-op without it).
    #[inline]
    fn gas_rate(&self, y: &[f64], dy: &mut [f64]) {
        if let Some(g) = &self.gas {
            dy[g.index] = g.rate(y[0], y[1], y[g.index]);
        }
    }

    /// Writes (ȧ_k, ä_k, ḃ_k) for every mode into `dy[2..]`, for given R, Ṙ, R̈ and loads G_n,k,
    /// G_t,k (the radial entries of `y` are not read). Affine in the mode amplitudes.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub fn mode_rates(&self, r: f64, rd: f64, rdd: f64, gn: &[f64], gt: &[f64], y: &[f64], dy: &mut [f64]) {
        let (rho, eta) = (self.eq.params.rho, self.eq.params.eta);
        let l = self.layout();
        for (m, mc) in self.modes.iter().enumerate() {
            let k = mc.k;
            let (a, ad, b) = (y[l.a(m)], y[l.adot(m)], y[l.b(m)]);
            let w = mc.wall(eta, r, wall_source(k, eta, r, rd, a, ad, gt[m]));
            let (add, bd) = mode_rates(k, rho, eta, r, rd, rdd, a, ad, b, gn[m], &w);
            dy[l.a(m)] = ad;
            dy[l.adot(m)] = add;
            dy[l.b(m)] = bd;
        }
    }

    /// With shape loads cn ḃ_k, ct ḃ_k (shell viscosity): solves (NS) for ḃ_k exactly and adds
    /// them to `gn`, `gt` (which hold the loads of the state on entry), writing (cn, ct, cn_r,
    /// ct_r, ḃ) per mode into `out`. (NS) with the boundary layer reads ḃ = E + cA, E =
    /// Ṙb/R − ȧ/(k+1) − 2Ṙa/((k+1)R), c = δ/(R + 2δ) (Ĩ = δT_w/R, T_w = A/(1 + 2δ/R)), and
    /// A = A0 − R ct ḃ/η (A0 of the state's G_t): ḃ = (E + cA0)/(1 + cR ct/η), one linear equation
    /// per mode (the ḃ loads are mode-diagonal). No-op (returns false) without such loads.
    pub(crate) fn apply_bdot_loads(&self, t: f64, y: &[f64], gn: &mut [f64], gt: &mut [f64], out: &mut [BdotMode]) -> bool {
        if !self.bdot_loads {
            return false;
        }
        let m = self.modes.len();
        let (mut cn, mut ct, mut cnr, mut ctr) = ([0.0; MAX_MODES], [0.0; MAX_MODES], [0.0; MAX_MODES], [0.0; MAX_MODES]);
        let mut c = BdotLoads { cn: &mut cn[..m], ct: &mut ct[..m], cn_r: &mut cnr[..m], ct_r: &mut ctr[..m] };
        self.eq.bdot_loads(t, y, &mut c);
        for j in 0..m {
            let bd = self.solve_bdot(y, j, gt[j], ct[j]);
            gn[j] += cn[j] * bd;
            gt[j] += ct[j] * bd;
            out[j] = [cn[j], ct[j], cnr[j], ctr[j], bd];
        }
        true
    }

    /// ḃ of mode index j from (NS) with the ḃ load ct·ḃ on G_t, `gt` the rest of G_t
    /// ([`apply_bdot_loads`](Self::apply_bdot_loads)).
    #[inline]
    fn solve_bdot(&self, y: &[f64], j: usize, gt: f64, ct: f64) -> f64 {
        let (r, rd, eta) = (y[0], y[1], self.eq.params.eta);
        let mc = &self.modes[j];
        let (k, l) = (mc.k, self.layout());
        let (a, ad, b) = (y[l.a(j)], y[l.adot(j)], y[l.b(j)]);
        let e = rd * b / r - ad / (k + 1.0) - 2.0 * rd * a / ((k + 1.0) * r);
        let delta = mc.delta(r);
        let cw = delta / (r + 2.0 * delta);
        (e + cw * wall_source(k, eta, r, rd, a, ad, gt)) / (1.0 + cw * r * ct / eta)
    }

    /// After a second pass changed G_n, G_t (which hold c·ḃ of `modes` on entry): ḃ solved
    /// again with the completed G_t, the ḃ loads replaced, `modes[j][4]` updated (issue 12: the
    /// change of ḃ is second order, and the linear ḃ load times it is a second-order load).
    pub(crate) fn resolve_bdot(&self, y: &[f64], gn: &mut [f64], gt: &mut [f64], modes: &mut [BdotMode]) {
        for (j, c) in modes.iter_mut().enumerate() {
            let (cn, ct, old) = (c[0], c[1], c[4]);
            let rest = gt[j] - ct * old;
            let bd = self.solve_bdot(y, j, rest, ct);
            gn[j] += cn * (bd - old);
            gt[j] = rest + ct * bd;
            c[4] = bd;
        }
    }

    /// R̈ at state y (M0 included), nondimensional, with the shape frozen (ḃ = 0 in dP/dt for
    /// Keller–Miksis with a field: the radial equation along a prescribed shape; the coupled
    /// rhs uses the closure's ḃ).
    pub fn radial_acceleration(&self, t: f64, y: &[f64]) -> f64 {
        self.eq.radial_acceleration(t, y)
    }

    /// The rhs with second-pass terms (the quadratic coupling): the first pass as for a linear
    /// scene, with the material-frame terms' share of the loads apart, then the second pass.
    fn rhs_with_second_order(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let (r, rd) = (y[0], y[1]);
        let m = self.modes.len();
        // the call's eight per-mode buffers in one block, zeroed only where used (m each): G_n,
        // G_t; the material-frame terms' share apart (the frame mapping's L(z)); ä⁽¹⁾, ḃ⁽¹⁾; the
        // second-order loads
        let mut block = [std::mem::MaybeUninit::<f64>::uninit(); 8 * MAX_MODES];
        let zeros = zeroed(&mut block[..8 * m]);
        let (gn, rest) = zeros.split_at_mut(m);
        let (gt, rest) = rest.split_at_mut(m);
        let (mgn, rest) = rest.split_at_mut(m);
        let (mgt, rest) = rest.split_at_mut(m);
        let (add, rest) = rest.split_at_mut(m);
        let (bd, rest) = rest.split_at_mut(m);
        let (dgn, dgt) = rest.split_at_mut(m);
        let (p, pm) = self.eq.loads_split(t, y, gn, gt, mgn, mgt);
        // the ḃ-load store only when there are such loads (no 1.3 kB zeroed per call without)
        let mut store;
        let bmodes: &mut [BdotMode] = if self.bdot_loads {
            store = [[0.0; 5]; MAX_MODES];
            self.apply_bdot_loads(t, y, gn, gt, &mut store);
            &mut store
        } else {
            &mut []
        };
        let rdd = self.first_acceleration(t, y, p, gn, gt, dy);
        dy[0] = rd;
        dy[1] = rdd;
        self.mode_rates(r, rd, rdd, gn, gt, y, dy);
        // issue 12: the second pass with the first-order R̈, ä just computed; R̈ from the
        // completed P, and ä shifted exactly by ΔR̈, ΔG_n ((N) is affine in both,
        // [`mode_shift`]) — or the mode rates again if a tangential load changed (with ḃ loads,
        // ḃ solved again with the completed G_t: [`resolve_bdot`](Self::resolve_bdot); the
        // rate, Keller–Miksis, is refused with second-pass terms)
        let lay = self.layout();
        for j in 0..m {
            add[j] = dy[lay.adot(j)];
            bd[j] = dy[lay.b(j)];
        }
        let mut l = Loads { pressure: 0.0, gn: dgn, gt: dgt };
        let material = MaterialLoads { pressure: pm, gn: mgn, gt: mgt };
        self.eq.add_second_order(t, y, &FirstOrder { rdd, add, bd, material }, &mut l);
        let rdd2 = self.eq.acceleration_at(t, y, p + l.pressure);
        dy[1] = rdd2;
        if dgt.iter().all(|&x| x == 0.0) {
            let rho = self.eq.params.rho;
            for (j, mc) in self.modes.iter().enumerate() {
                let (s_rdd, s_gn) = mode_shift(mc.k, rho, r, y[lay.a(j)]);
                dy[lay.adot(j)] += s_rdd * (rdd2 - rdd) + s_gn * dgn[j];
            }
        } else {
            for j in 0..m {
                gn[j] += dgn[j];
                gt[j] += dgt[j];
            }
            if self.bdot_loads {
                self.resolve_bdot(y, gn, gt, &mut bmodes[..m]);
            }
            self.mode_rates(r, rd, rdd2, gn, gt, y, dy);
        }
    }
}

impl BoundaryLayerSystem {
    /// R̈ of the first pass from the radial load `p`: with ḃ terms in the radial balance, the
    /// mode rates first (R̈ = 0 in them) for the ḃ it needs, else R̈ from `p` alone.
    #[inline(always)]
    fn first_acceleration(&self, t: f64, y: &[f64], p: f64, gn: &[f64], gt: &[f64], dy: &mut [f64]) -> f64 {
        if !self.bdot_radial {
            return self.eq.acceleration_at(t, y, p);
        }
        let m = self.modes.len();
        self.mode_rates(y[0], y[1], 0.0, gn, gt, y, dy);
        let mut bd = [0.0; MAX_MODES];
        for (j, b) in bd[..m].iter_mut().enumerate() {
            *b = dy[self.layout().b(j)];
        }
        self.eq.acceleration_with(t, y, p, &bd[..m])
    }
}

impl crate::integrate::OdeSystem for BoundaryLayerSystem {
    fn dim(&self) -> usize {
        self.layout().dim()
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        self.gas_rate(y, dy);
        if self.eq.has_second_order() {
            return self.rhs_with_second_order(t, y, dy);
        }
        // a linear scene: the first pass of `rhs_with_second_order` without the material-frame
        // buffers (the same operations; no 0.5 kB zeroed or moved per call)
        let (r, rd) = (y[0], y[1]);
        let m = self.modes.len();
        let (mut gn, mut gt) = ([0.0; MAX_MODES], [0.0; MAX_MODES]);
        let p = self.eq.loads(t, y, &mut gn[..m], &mut gt[..m]);
        if self.bdot_loads {
            let mut store = [[0.0; 5]; MAX_MODES];
            self.apply_bdot_loads(t, y, &mut gn[..m], &mut gt[..m], &mut store);
        }
        let rdd = self.first_acceleration(t, y, p, &gn[..m], &gt[..m], dy);
        dy[0] = rd;
        dy[1] = rdd;
        self.mode_rates(r, rd, rdd, &gn[..m], &gt[..m], y, dy);
    }

    /// The exact Jacobian (dense, row-major), assembled from the terms' gradients
    /// ([`super::linearize`]); its sparsity is [`BoundaryLayerSystem::jacobian_pattern`].
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut [f64]) -> bool {
        self.jacobian_into(t, y, jac);
        true
    }

    /// J·S from the same gradients without the dense J ([`Self::jacobian_product_into`]).
    fn jacobian_product(&self, t: f64, y: &[f64], s: &[f64], out: &mut [f64]) -> bool {
        self.jacobian_product_into(t, y, s, out);
        true
    }

    fn error_scale(&self) -> Option<Vec<f64>> {
        let mut w = vec![1.0, 1.0];
        for &s in &self.shape_weights {
            w.extend([s, s, s]);
        }
        if self.gas.is_some() {
            // p_b (in units of the model's pressure scale, O(1) like R and Ṙ)
            w.push(1.0);
        }
        Some(w)
    }

    /// The exact Jacobian in the form the implicit steppers' linear solves use
    /// ([`crate::integrate::linear`]). Up to [`POSITION_ROWS_MAX_MODES`] modes, and whenever the
    /// bordered split cannot pay (the quadratic coupling: band = M): the position rows R' = Ṙ,
    /// a_k' = ȧ_k eliminated and the remaining 1 + 2M unknowns factored dense
    /// ([`crate::integrate::reduced`]). Above, the bordered band along the
    /// [`JacobianPattern`](super::linearize::JacobianPattern): border R, Ṙ and the `band` lowest
    /// modes (R̈ depends on them, every mode row depends on R̈), interior the block band of the
    /// mode couplings, half-width 3·band + 2 ([`crate::integrate::bordered`]). `None` (the
    /// caller's dense LU) when J is not finite.
    fn structured_jacobian(&self, t: f64, y: &[f64]) -> Option<Box<dyn crate::integrate::linear::StructuredJacobian>> {
        use crate::integrate::{bordered::BorderedBand, linear::StructuredJacobian, reduced::PositionRows};
        let (n, l) = (y.len(), self.layout());
        let band = self.jacobian_pattern().band;
        // the border: R, Ṙ and the `band` lowest modes; the half-width: a mode row reaches
        // `band` blocks away, from its a to the last b (3·band + 2)
        let border = l.blocks(0..band).end;
        let w = l.b(band) - l.a(0);
        // (the gas slot's column is full: p_b enters R̈, and R̈ every mode row)
        let bordered_pays = self.gas.is_none() && border < n && n - border > 2 * w + 1;
        let mut jac = vec![0.0; n * n];
        self.jacobian_into(t, y, &mut jac);
        if !bordered_pays || l.modes() <= POSITION_ROWS_MAX_MODES {
            PositionRows::new(&jac, n).map(|b| Box::new(b) as Box<dyn StructuredJacobian>)
        } else {
            BorderedBand::new(&jac, n, border, w, w).map(|b| Box::new(b) as Box<dyn StructuredJacobian>)
        }
    }
}
