//! The frame mapping of the second-order model (issue 12; docs/model.md, "Quadratic mode
//! coupling", "One frame for the state"): the membrane's loads are derived for *material*
//! (Lagrangian) amplitudes and projected at the material angle Θ, the free-bubble terms for
//! *Eulerian* amplitudes and projected at the polar angle θ. The state holds the Eulerian ones —
//! r = f(θ) = R + Σ_n a_n P_n(cos θ), R and a_n as the free-bubble derivation defines them, b_n the
//! material displacement θ = Θ + Σ b_n P¹_n(cos Θ)/R — and this term converts the membrane's
//! linear loads to it, to second order:
//!
//! * **amplitudes**: the material point Θ sits at θ(Θ), so f(θ(Θ)) = r(Θ) and the material
//!   amplitudes are, with P¹_n = dP_n/dθ and K(n, l, m) = (2n+1)/2 ∫ P¹_l P¹_m P_n dx,
//!
//!     a_n^L = a_n + Σ_{l,m} K(n, l, m) a_l b_m / R    (n = 0: R^L = R + Σ K(0, l, l) a_l b_l / R),
//!
//!   their rates by d/dt (ḃ_m the first-order ḃ⁽¹⁾ of (NS), as for the shell-viscous loads); the
//!   linear Lagrangian loads L (membrane, bending, shell viscosity) enter as L(z^L) − L(z);
//! * **normal projection**: a load F(Θ) = Σ_l F_l P_l(cos Θ) seen at the polar angle is
//!   F(θ − β) = F(θ) − F′(θ)β, β = Σ b_m P¹_m/R, so its coefficient on P_j(cos θ) is
//!   F_j − Σ_{l,m} K(j, l, m) F_l b_m / R (F_l the first-order normal load, its ḃ part included;
//!   the sphere's load is constant in angle and does not move).
//!
//! The tangential equations (TS), (NS) keep the material projection: their other terms are the
//! linear viscous closure and kinematics, whose second-order parts are not derived (docs/model.md,
//! "Neglected terms"), so only the membrane's tangential load carries second-order terms there
//! and it gets the amplitude shift alone. K comes from the generated tensor
//! `coefficients::quadratic::P1P1P` (exact rationals, codegen). The Jacobian is exact.
//!
//! Cost (issue 12, "Performance"; docs/performance.md): L(z) is the equations core's — the
//! material-frame terms' share of its first pass ([`FirstOrder::material`], model/material.rs)
//! — so the rhs evaluates the linear loads once, at z^L. K is symmetric in (l, m), so the three
//! sums Σ K a_l b_m, Σ K (ȧ_l b_m + a_l ḃ_m), Σ K F_l b_m over ordered pairs are one sweep over
//! the (target, unordered pair l ≤ m) rows the selection rules allow, planned once pair by pair
//! as runs of consecutive targets (effects/frame_sweep.rs: each pair's three symmetric products
//! formed once in one 4-lane register, the diagonal pairs' K halved, no per-row index). The
//! rhs's factors, z^L and L(z^L) and the Jacobian's work space are kept per thread (no
//! allocation, no MAX_MODES arrays zeroed per call).

use std::cell::RefCell;

mod jacobian;

use super::frame_sweep::{Factors, FrameRows};
use super::second_order::{FirstOrder, FirstOrderGradient, SecondOrderTerm};
use super::{At, BdotLoads, LoadJacobian, Loads, Term, MAX_DIM, MAX_MODES};
use crate::model::layout::StateLayout;
use crate::coefficients::quadratic::P1P1P;

/// ∫ P¹_l P¹_m P_j dx of the generated tensor (0 outside the selection rules).
fn p1p1p(l: usize, m: usize, j: usize) -> f64 {
    let key = (l.min(m) as u16, l.max(m) as u16, j as u16);
    P1P1P.binary_search_by(|e| (e.0, e.1, e.2).cmp(&key)).map_or(0.0, |i| P1P1P[i].3)
}

#[derive(Debug)]
pub struct FrameMap {
    /// The linear loads derived in the material frame (membrane law, bending, shell viscosity):
    /// evaluated here at z^L; at z they are the core's ([`FirstOrder::material`]).
    lagrangian: Vec<Box<dyn Term>>,
    /// Whether a Lagrangian term has ḃ loads (the shell viscosity).
    bdot: bool,
    /// (target n: 0 = P_0, 1 + i = mode index i; l; m; K(n, l, m)) over ordered mode pairs
    /// (the Jacobian's list).
    entries: Vec<(usize, usize, usize, f64)>,
    /// The three sums' rows, planned once (effects/frame_sweep.rs).
    rows: FrameRows,
    modes: usize,
}

/// The (value, rate) rows of target n in z: R, Ṙ for n = 0, a, ȧ of mode n − 1 otherwise.
fn rows(n: usize) -> (usize, usize) {
    let l = StateLayout::reduced(n);
    if n == 0 { (l.r(), l.rdot()) } else { (l.a(n - 1), l.adot(n - 1)) }
}

/// The rhs's work space (per thread, grown once): the sweep's per-mode factors and sums, z^L
/// and L(z^L).
#[derive(Default)]
struct Work {
    u: Vec<[f64; 4]>,
    v: Vec<[f64; 4]>,
    /// [d_n, s_n, f_n, ·] per target
    sums: Vec<[f64; 4]>,
    zl: Vec<f64>,
    gn: Vec<f64>,
    gt: Vec<f64>,
}

thread_local! {
    static WORK: RefCell<Work> = RefCell::new(Work::default());
}

/// The sweep's per-mode factors `u` = [a, ȧ, F, a], `v` = [b, b, b, ḃ] (ḃ = ḃ⁽¹⁾, 0 past its
/// length; F = G_n + cn ḃ, 0 past G_n's length) from the state's modes `zs` ([a, ȧ, b] each).
#[inline(always)]
fn sweep_factors<'a>(zs: impl Iterator<Item = &'a [f64]>, g: &[f64], bd: &[f64], cn: impl Fn(usize) -> f64, u: &mut [[f64; 4]], v: &mut [[f64; 4]]) {
    for (i, ((u, v), zk)) in u.iter_mut().zip(v.iter_mut()).zip(zs).enumerate() {
        let b = bd.get(i).copied().unwrap_or(0.0);
        let f = match g.get(i) {
            Some(g) => g + cn(i) * b,
            None => 0.0,
        };
        let (a, ad, bk) = (zk[StateLayout::A], zk[StateLayout::ADOT], zk[StateLayout::B]);
        (*u, *v) = ([a, ad, f, a], [bk, bk, bk, b]);
    }
}

/// The per-target sums of [`FrameMap::sums`].
struct Sums {
    /// Σ K a_l b_m
    d: [f64; MAX_MODES + 1],
    /// Σ K (ȧ_l b_m + a_l ḃ_m)
    s: [f64; MAX_MODES + 1],
    /// Σ K F_l b_m
    f: [f64; MAX_MODES + 1],
}

impl FrameMap {
    /// `lagrangian`: the scene's linear terms whose loads are derived in the material frame
    /// (the same ones the assembly marks for the core, model/material.rs); `orders`: k of each
    /// mode index. None without such terms (nothing to map).
    pub fn new(lagrangian: Vec<Box<dyn Term>>, orders: &[f64]) -> Option<Self> {
        if lagrangian.is_empty() || orders.is_empty() {
            return None;
        }
        let ks: Vec<usize> = orders.iter().map(|&k| k as usize).collect();
        let kn = |n: usize| if n == 0 { 0 } else { ks[n - 1] };
        let coef = |n: usize, l: usize, m: usize| (2 * kn(n) + 1) as f64 / 2.0 * p1p1p(ks[l], ks[m], kn(n));
        let mut entries = Vec::new();
        for n in 0..=ks.len() {
            for l in 0..ks.len() {
                for m in 0..ks.len() {
                    let c = coef(n, l, m);
                    if c != 0.0 {
                        entries.push((n, l, m, c));
                    }
                }
            }
        }
        let rows = FrameRows::new(ks.len(), coef);
        let bdot = lagrangian.iter().any(|t| t.has_bdot_loads());
        Some(Self { lagrangian, bdot, entries, rows, modes: ks.len() })
    }

    /// Number of (target, unordered pair) rows of the three sums.
    pub fn sparse_rows(&self) -> usize {
        self.rows.len()
    }

    /// Σ over the Lagrangian terms: (P, G_n, G_t) at z (the core hands over those at the state;
    /// this is L at the material state z^L, and for a caller without a core, L(z)).
    pub fn lagrangian_loads(&self, t: f64, z: &[f64]) -> (f64, [f64; MAX_MODES], [f64; MAX_MODES]) {
        let (mut gn, mut gt) = ([0.0; MAX_MODES], [0.0; MAX_MODES]);
        let m = self.modes;
        let p = self.lagrangian_into(t, z, &mut gn[..m], &mut gt[..m]);
        (p, gn, gt)
    }

    /// [`lagrangian_loads`](Self::lagrangian_loads) into `gn`, `gt` (overwritten): P returned.
    fn lagrangian_into(&self, t: f64, z: &[f64], gn: &mut [f64], gt: &mut [f64]) -> f64 {
        gn.fill(0.0);
        gt.fill(0.0);
        let mut l = Loads { pressure: 0.0, gn, gt };
        for term in &self.lagrangian {
            term.add(&At { t, z }, &mut l);
        }
        l.pressure
    }

    /// ∂/∂z of [`lagrangian_loads`](Self::lagrangian_loads) (`jac` overwritten).
    pub fn lagrangian_jacobian(&self, t: f64, z: &[f64], jac: &mut LoadJacobian) {
        jac.clear();
        for term in &self.lagrangian {
            term.add_jacobian(&At { t, z }, jac);
        }
    }

    /// The normal ḃ coefficients cn and ∂cn/∂R of the Lagrangian terms at z (zero without ḃ
    /// loads).
    fn bdot_normal(&self, at: &At<'_>) -> ([f64; MAX_MODES], [f64; MAX_MODES]) {
        let m = self.modes;
        let (mut cn, mut ct, mut cn_r, mut ct_r) = ([0.0; MAX_MODES], [0.0; MAX_MODES], [0.0; MAX_MODES], [0.0; MAX_MODES]);
        if self.bdot {
            let mut c = BdotLoads { cn: &mut cn[..m], ct: &mut ct[..m], cn_r: &mut cn_r[..m], ct_r: &mut ct_r[..m] };
            for term in self.lagrangian.iter().filter(|t| t.has_bdot_loads()) {
                term.add_bdot_loads(at, &mut c);
            }
        }
        (cn, cn_r)
    }

    /// Per target, Σ K a_l b_m, Σ K (ȧ_l b_m + a_l ḃ_m) and Σ K F_l b_m over the ordered pairs
    /// into `w.sums` (F_l = G_n,l(z) + cn_l ḃ_l the first-order normal loads, ḃ = ḃ⁽¹⁾ padded
    /// with zeros to the mode count), and the material state z^L into `w.zl`.
    fn sums_into(&self, at: &At<'_>, first: &FirstOrder<'_>, w: &mut Work) {
        let (z, m) = (at.z, self.modes);
        if w.sums.len() <= m {
            *w = Work { u: vec![[0.0; 4]; m], v: vec![[0.0; 4]; m], sums: vec![[0.0; 4]; m + 1], ..Work::default() };
        }
        let (g, zs) = (first.material.gn, z[StateLayout::reduced(m).shape()].chunks_exact(StateLayout::AMPLITUDES));
        let (u, v) = (&mut w.u[..m], &mut w.v[..m]);
        // F_l; without ḃ loads cn = 0 (the same sum)
        if self.bdot {
            let cn = self.bdot_normal(at).0;
            sweep_factors(zs, g, first.bd, |i| cn[i], u, v);
        } else {
            sweep_factors(zs, g, first.bd, |_| 0.0, u, v);
        }
        self.rows.sweep(&Factors { u: &w.u, v: &w.v }, &mut w.sums);
        let (r, rd) = (z[0], z[1]);
        w.zl.clear();
        w.zl.extend_from_slice(z);
        // target 0: R, Ṙ; target 1 + i: a, ȧ of mode i
        let shift = |x: &mut f64, xd: &mut f64, o: &[f64; 4]| {
            let (d, s) = (o[0], o[1]);
            *x += d / r;
            *xd += s / r - rd * d / (r * r);
        };
        let (head, modes) = w.zl.split_at_mut(StateLayout::RADIAL);
        let [x, xd] = head else { unreachable!("the state has R and Ṙ") };
        shift(x, xd, &w.sums[0]);
        for (zk, o) in modes[..StateLayout::x_dim(m)].chunks_exact_mut(StateLayout::AMPLITUDES).zip(&w.sums[1..=m]) {
            let [a, ad, _] = zk else { unreachable!("three entries per mode") };
            shift(a, ad, o);
        }
    }

    /// d_n, s_n and f_n of [`sums_into`](Self::sums_into) (for the Jacobian).
    fn sums(&self, at: &At<'_>, first: &FirstOrder<'_>) -> Sums {
        WORK.with(|cell| {
            let w = &mut *cell.borrow_mut();
            self.sums_into(at, first, w);
            let mut out = Sums { d: [0.0; MAX_MODES + 1], s: [0.0; MAX_MODES + 1], f: [0.0; MAX_MODES + 1] };
            for (n, o) in w.sums[..=self.modes].iter().enumerate() {
                (out.d[n], out.s[n], out.f[n]) = (o[0], o[1], o[2]);
            }
            out
        })
    }

    /// The material state z^L (R^L, Ṙ^L, a^L, ȧ^L, b) of z.
    fn material(&self, z: &[f64], d: &[f64], s: &[f64]) -> [f64; MAX_DIM] {
        let (r, rd) = (z[0], z[1]);
        let mut zl = [0.0; MAX_DIM];
        zl[..z.len()].copy_from_slice(z);
        for n in 0..=self.modes {
            let (p, v) = rows(n);
            zl[p] += d[n] / r;
            zl[v] += s[n] / r - rd * d[n] / (r * r);
        }
        zl
    }

    /// ḃ⁽¹⁾ padded to the mode count, and the first-order normal loads F_l = G_n,l(z) + cn_l ḃ_l.
    fn first(&self, at: &At<'_>, first: &FirstOrder<'_>) -> ([f64; MAX_MODES], [f64; MAX_MODES]) {
        let m = self.modes;
        let mut bd = [0.0; MAX_MODES];
        for (x, y) in bd[..m].iter_mut().zip(first.bd) {
            *x = *y;
        }
        let (cn, _) = self.bdot_normal(at);
        let mut f1 = [0.0; MAX_MODES];
        for ((f, g), (c, b)) in f1[..m].iter_mut().zip(first.material.gn).zip(cn.iter().zip(&bd)) {
            *f = g + c * b;
        }
        (bd, f1)
    }
}

impl SecondOrderTerm for FrameMap {
    fn name(&self) -> &'static str {
        "quadratic frame"
    }
    fn label(&self) -> Option<String> {
        Some("membrane loads mapped to the Eulerian amplitudes (second order)".into())
    }
    fn band(&self) -> usize {
        self.modes
    }
    fn add(&self, at: &At<'_>, first: &FirstOrder<'_>, loads: &mut Loads<'_>) {
        let (m, r) = (self.modes, at.z[0]);
        WORK.with(|cell| {
            let w = &mut *cell.borrow_mut();
            self.sums_into(at, first, w);
            let Work { sums, zl, gn, gt, .. } = w;
            gn.resize(m, 0.0);
            gt.resize(m, 0.0);
            let (gnl, gtl) = (&mut gn[..m], &mut gt[..m]);
            let pl = self.lagrangian_into(at.t, zl, gnl, gtl);
            let l0 = &first.material;
            // L(z^L) − L(z), and the frame change −Σ K F_l b_m / R of the normal load on P_n:
            // on P_0 subtracted from P (as Ŝ0), on P_j added to G_n,j
            loads.pressure += pl - l0.pressure + sums[0][2] / r;
            for i in 0..loads.gn.len().min(m) {
                loads.gn[i] += gnl[i] - l0.gn[i] - sums[1 + i][2] / r;
                loads.gt[i] += gtl[i] - l0.gt[i];
            }
        });
    }
    fn add_jacobian(&self, at: &At<'_>, first: &FirstOrder<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian) {
        self.jacobian(at, first, grad, jac);
    }
}
