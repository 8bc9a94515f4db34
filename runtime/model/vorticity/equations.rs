//! The mode equations of the full model (FORMULATION §4.2; paper eqs 2.64, 2.65, 2.67 corrected),
//! shared by the staggered and the monolithic schemes. Given the vorticity integrals they give
//! ä_k, ḃ_k and the wall vorticity T_w,k, which is eliminated algebraically from the corrected
//! tangential stress balance (TS) with the trapezoid weight w_0 of the wall node:
//!
//! T_w = [2(k+2)ȧ/(k+1) + 2(1−k)Ṙa/((k+1)R) − 2Ĩ_int − R G_t/η] / (1 + 2w_0)      (TS, audit 3, 4)
//! Ĩ   = w_0 T_w + Ĩ_int,   J = R ∫(y⁻³ − 1) y^{−k} T dy
//! ḃ   = Ṙb/R − ȧ/(k+1) − 2Ṙa/((k+1)R) + Ĩ                                          (NS, 2.67)
//! ä   = −[3Ṙȧ − (k−1)R̈a]/R − (k+1)/(ρR)[2η(k+2)ȧ/R + 4η(k−1)Ṙa/R² + kηT_w/R
//!        + kρṘJ/R − 2ηk(k+1)Ĩ/R + G_n]                                              (N, 2.64 × (k+1)/(ρR), audit 5)

use super::ModeCoupling;
use crate::model::effects::MAX_MODES;
use crate::model::layout::StateLayout;
use nalgebra::DMatrix;

/// Everything the mode equations need at one instant, for all M modes (index m ↔ k = orders[m]).
pub struct ModeInputs<'a> {
    pub r: f64,
    pub rdot: f64,
    pub rddot: f64,
    pub a: &'a [f64],
    pub adot: &'a [f64],
    pub b: &'a [f64],
    /// G_n,k and G_t,k (FORMULATION §4.1) at this state.
    pub gn: &'a [f64],
    pub gt: &'a [f64],
    /// Ĩ_int,k = Σ_{i≥1} W_i T_i (without the wall node).
    pub i_int: &'a [f64],
    /// ∫(y⁻³ − 1) y^{−k} T dy, so that J_k = R · j_over_r[m].
    pub j_over_r: &'a [f64],
    /// Trapezoid weight w_0 of the wall node (same for every mode: y_0 = 1).
    pub w0: f64,
    /// `Some`: use these wall values instead of solving (TS) (the paper's literal lagged
    /// staggered step, [`super::staggered::WallCoupling::Lagged`]).
    pub tw_fixed: Option<&'a [f64]>,
}

/// The outputs: ä_k, ḃ_k and T_w,k.
pub struct ModeRates<'a> {
    pub add: &'a mut [f64],
    pub bdot: &'a mut [f64],
    pub tw: &'a mut [f64],
}

pub use crate::model::equations::wall_source;
use crate::model::equations::{self as eqs, Wall};

/// The vorticity wall terms of one mode (module doc): T_w from (TS) with the trapezoid weight
/// of the wall node (or fixed), Ĩ = w_0 T_w + Ĩ_int, J = R ∫(y⁻³−1)y^{−k}T dy.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn wall(k: f64, rho: f64, eta: f64, r: f64, rdot: f64, src: f64, i_int: f64, j_over_r: f64, w0: f64, tw_fixed: Option<f64>) -> Wall {
    let tw = match tw_fixed {
        Some(v) => v,
        None => (src - 2.0 * i_int) / (1.0 + 2.0 * w0),
    };
    let itil = w0 * tw + i_int;
    let j = r * j_over_r;
    Wall { tw, itil, normal: [k * eta * tw / r, k * rho * rdot * j / r, -(2.0 * eta * k * (k + 1.0) * itil / r)] }
}

/// T_w, Ĩ, J and their exact partials with respect to the local variables
/// ([`crate::model::equations::var`]), for the structured Jacobian of the monolithic system.
pub fn wall_linear(r: f64, src: f64, d_src: &[f64; 5], i_int: f64, j_over_r: f64, w0: f64) -> eqs::WallLinear {
    use eqs::var::*;
    let den = 1.0 + 2.0 * w0;
    let tw = (src - 2.0 * i_int) / den;
    let mut w = eqs::WallLinear { tw, itil: w0 * tw + i_int, j: r * j_over_r, ..Default::default() };
    for (x, &d) in [R, RD, A, AD, GT].iter().zip(d_src) {
        w.d_tw[*x] = d / den;
    }
    w.d_tw[IINT] = -2.0 / den;
    for x in 0..N {
        w.d_itil[x] = w0 * w.d_tw[x];
    }
    w.d_itil[IINT] += 1.0;
    w.d_j[R] = j_over_r;
    w.d_j[JR] = r;
    w
}

/// Evaluates (TS), (NS), (N) for every mode (the equations of [`crate::model::equations`]).
pub fn mode_rates(orders: &[usize], rho: f64, eta: f64, x: &ModeInputs<'_>, out: ModeRates<'_>) {
    let (r, rdot, rddot) = (x.r, x.rdot, x.rddot);
    for (m, &k) in orders.iter().enumerate() {
        let kf = k as f64;
        let (a, adot, b) = (x.a[m], x.adot[m], x.b[m]);
        let src = wall_source(kf, eta, r, rdot, a, adot, x.gt[m]);
        let w = wall(kf, rho, eta, r, rdot, src, x.i_int[m], x.j_over_r[m], x.w0, x.tw_fixed.map(|f| f[m]));
        out.tw[m] = w.tw;
        let (add, bd) = eqs::mode_rates(kf, rho, eta, r, rdot, rddot, a, adot, b, x.gn[m], &w);
        out.add[m] = add;
        out.bdot[m] = bd;
    }
}

/// [`mode_rates`] with the coupling's second pass (issue 12; [`ModeCoupling::has_second_order`]):
/// the first pass with the ordinary loads (`x.gn`, `x.gt`, `x.rddot` = R̈⁽¹⁾) gives ä⁽¹⁾, the
/// coupling adds the second-pass loads given R̈⁽¹⁾, ä⁽¹⁾, and (TS), (NS), (N) are evaluated again
/// with the completed loads and R̈ — the two passes of the boundary-layer system
/// (model/boundary_layer.rs) with this closure's wall terms. Returns R̈ (x.rddot, and exactly
/// [`mode_rates`], without second-pass loads).
pub fn coupled_mode_rates(c: &dyn ModeCoupling, t: f64, x: &ModeInputs<'_>, out: ModeRates<'_>) -> f64 {
    let (orders, rho, eta) = (c.orders(), c.density(), c.viscosity());
    let ModeRates { add, bdot, tw } = out;
    mode_rates(orders, rho, eta, x, ModeRates { add: &mut *add, bdot: &mut *bdot, tw: &mut *tw });
    if !c.has_second_order() {
        return x.rddot;
    }
    let m = orders.len();
    let (mut add1, mut gn, mut gt) = ([0.0; MAX_MODES], [0.0; MAX_MODES], [0.0; MAX_MODES]);
    add1[..m].copy_from_slice(add);
    gn[..m].copy_from_slice(x.gn);
    gt[..m].copy_from_slice(x.gt);
    let rdd = c.second_order(t, x.r, x.rdot, x.a, x.adot, x.b, x.rddot, &add1[..m], &mut gn[..m], &mut gt[..m]);
    let x2 = ModeInputs { rddot: rdd, gn: &gn[..m], gt: &gt[..m], ..*x };
    mode_rates(orders, rho, eta, &x2, ModeRates { add, bdot, tw });
    rdd
}

/// The loads at a state completed by the coupling's second pass, the first-order ä⁽¹⁾ from the
/// closure at the vorticity integrals given (`x.gn`, `x.gt`, `x.rddot` are not read): writes
/// G_n, G_t into `gn`, `gt` and returns R̈. Without second-pass loads: the ordinary loads.
pub fn completed_loads(c: &dyn ModeCoupling, t: f64, x: &ModeInputs<'_>, gn: &mut [f64], gt: &mut [f64]) -> f64 {
    let rdd = c.loads(t, x.r, x.rdot, x.a, x.adot, x.b, gn, gt);
    if !c.has_second_order() {
        return rdd;
    }
    let m = c.orders().len();
    let (mut add, mut bdot, mut tw) = ([0.0; MAX_MODES], [0.0; MAX_MODES], [0.0; MAX_MODES]);
    let x1 = ModeInputs { rddot: rdd, gn, gt, ..*x };
    mode_rates(c.orders(), c.density(), c.viscosity(), &x1, ModeRates { add: &mut add[..m], bdot: &mut bdot[..m], tw: &mut tw[..m] });
    c.second_order(t, x.r, x.rdot, x.a, x.adot, x.b, rdd, &add[..m], gn, gt)
}

/// The exact ∂(f_z, T_w)/∂z ((nz + M) × nz) and ∂(f_z, T_w)/∂p ((nz + M) × 2M) of the reduced
/// function of the monolithic system ([`super::monolithic::Monolithic::reduced`]): z = [R, Ṙ,
/// (a, ȧ, b)_k], p = [Ĩ_int,k (M), ∫(y⁻³−1)y^{−k}T dy (M)], rows f_z then T_w,k. From the
/// coupling's load gradients, the closure's partials and [`crate::model::equations::mode_partials`].
///
/// With second-pass loads (issue 12) the rows of the first pass give ∂ä⁽¹⁾/∂(z, p), the
/// coupling's [`ModeCoupling::second_order_jacobian`] the completed R̈ and loads over (z, p) (ä⁽¹⁾
/// depends on p, so R̈ and G_n do too: row 1 and the mode rows gain p columns), and the rows are
/// assembled again from those — the Jacobian of the two-pass rhs, exactly. The quadratic loads
/// couple every pair of modes, which fills gz and gp; both are dense already (the structured
/// solve's small dense system, [`super::structured`]), so the structure is unchanged.
pub fn reduced_jacobian(c: &dyn ModeCoupling, t: f64, z: &[f64], p: &[f64], w0: f64, gz: &mut DMatrix<f64>, gp: &mut DMatrix<f64>) {
    let m = c.orders().len();
    let l = StateLayout::reduced(m);
    let nz = l.dim();
    let (r, rd) = (z[l.r()], z[l.rdot()]);
    let pick = |at: fn(StateLayout, usize) -> usize| (0..m).map(|i| z[at(l, i)]).collect::<Vec<f64>>();
    let (a, ad, b) = (pick(StateLayout::a), pick(StateLayout::adot), pick(StateLayout::b));
    let mut ls = LoadScratch::new(m);
    let rdd = ls.eval(c, t, r, rd, &a, &ad, &b);
    let mut lj = crate::model::effects::LoadJacobian::new(m);
    let mut drdd = vec![0.0; nz];
    c.linearize(t, z, &mut drdd, &mut lj);
    let first = Pass { rdd, drdd: &drdd, gn: &ls.gn, gt: &ls.gt, lj: &lj };
    fill_rows(c, z, p, w0, &first, gz, gp);
    if !c.has_second_order() {
        return;
    }
    // ä⁽¹⁾ and its rows over (z, p), from the first pass
    let ne = nz + 2 * m;
    let (mut add, mut bdot, mut tw) = (vec![0.0; m], vec![0.0; m], vec![0.0; m]);
    let x = ModeInputs { r, rdot: rd, rddot: rdd, a: &a, adot: &ad, b: &b, gn: &ls.gn, gt: &ls.gt, i_int: &p[..m], j_over_r: &p[m..], w0, tw_fixed: None };
    mode_rates(c.orders(), c.density(), c.viscosity(), &x, ModeRates { add: &mut add, bdot: &mut bdot, tw: &mut tw });
    let mut grad_rdd = vec![0.0; ne];
    grad_rdd[..nz].copy_from_slice(&drdd);
    let mut dadd = vec![0.0; m * ne];
    for mi in 0..m {
        let row = &mut dadd[mi * ne..(mi + 1) * ne];
        for j in 0..nz {
            row[j] = gz[(l.adot(mi), j)];
        }
        for q in 0..2 * m {
            row[nz + q] = gp[(l.adot(mi), q)];
        }
    }
    let (mut gn, mut gt) = (ls.gn.clone(), ls.gt.clone());
    let rdd2 = c.second_order(t, r, rd, &a, &ad, &b, rdd, &add, &mut gn, &mut gt);
    let mut sj = crate::model::effects::LoadJacobian { n: ne, pressure: vec![0.0; ne], gn: vec![0.0; m * ne], gt: vec![0.0; m * ne] };
    let mut drdd2 = vec![0.0; ne];
    // ∂ḃ⁽¹⁾: no second-pass term of the vorticity closure reads ḃ⁽¹⁾ (scene/validate.rs refuses the
    // shell viscosities with it), so its gradient is zero.
    let dbd = vec![0.0; m * ne];
    // the material-frame terms' Jacobian: the coupling's own (SceneCoupling fills it)
    let none = crate::model::effects::LoadJacobian::new(0);
    let grad = crate::model::effects::second_order::FirstOrderGradient { drdd: &grad_rdd, dadd: &dadd, dbd: &dbd, material: &none };
    c.second_order_jacobian(t, z, rdd, &add, &grad, &mut sj, &mut drdd2);
    // the completed load rows: the ordinary terms' (z columns) plus the second pass's
    for mi in 0..m {
        for j in 0..nz {
            sj.gn[mi * ne + j] += lj.gn[mi * nz + j];
            sj.gt[mi * ne + j] += lj.gt[mi * nz + j];
        }
    }
    let second = Pass { rdd: rdd2, drdd: &drdd2, gn: &gn, gt: &gt, lj: &sj };
    fill_rows(c, z, p, w0, &second, gz, gp);
}

/// R̈, the loads and their gradients one pass of the mode equations sees: `drdd` and the rows
/// of `lj` over z and, past z.len(), over p.
struct Pass<'a> {
    rdd: f64,
    drdd: &'a [f64],
    gn: &'a [f64],
    gt: &'a [f64],
    lj: &'a crate::model::effects::LoadJacobian,
}

/// The rows of [`reduced_jacobian`] for the mode equations evaluated with `x`'s R̈ and loads
/// (gz, gp overwritten).
fn fill_rows(c: &dyn ModeCoupling, z: &[f64], p: &[f64], w0: f64, x: &Pass<'_>, gz: &mut DMatrix<f64>, gp: &mut DMatrix<f64>) {
    use eqs::var::*;
    let orders = c.orders();
    let m = orders.len();
    let l = StateLayout::reduced(m);
    let nz = l.dim();
    let extra = x.lj.n - nz;
    let (rho, eta) = (c.density(), c.viscosity());
    let (r, rd) = (z[l.r()], z[l.rdot()]);
    gz.fill(0.0);
    gp.fill(0.0);
    gz[(l.r(), l.rdot())] = 1.0;
    for j in 0..nz {
        gz[(l.rdot(), j)] = x.drdd[j];
    }
    for q in 0..extra {
        gp[(l.rdot(), q)] = x.drdd[nz + q];
    }
    for (mi, &k) in orders.iter().enumerate() {
        let kf = k as f64;
        let (ia, iad, ib) = (l.a(mi), l.adot(mi), l.b(mi));
        let (a, ad, b) = (z[ia], z[iad], z[ib]);
        gz[(ia, iad)] = 1.0;
        let (gn, gt) = (x.gn[mi], x.gt[mi]);
        let src = wall_source(kf, eta, r, rd, a, ad, gt);
        let d_src = eqs::wall_source_partials(kf, eta, r, rd, a, gt);
        let w = wall_linear(r, src, &d_src, p[mi], p[m + mi], w0);
        let (da, db) = eqs::mode_partials(kf, rho, eta, r, rd, x.rdd, a, ad, b, gn, &w);
        let (gn_row, gt_row) = (x.lj.gn_row(mi), x.lj.gt_row(mi));
        // the ä, ḃ rows and, past z, the T_w row of the mode
        for (row, d) in [(iad, &da), (ib, &db), (nz + mi, &w.d_tw)] {
            for j in 0..nz {
                gz[(row, j)] = d[RDD] * x.drdd[j] + d[GN] * gn_row[j] + d[GT] * gt_row[j];
            }
            gz[(row, l.r())] += d[R];
            gz[(row, l.rdot())] += d[RD];
            gz[(row, ia)] += d[A];
            gz[(row, iad)] += d[AD];
            gz[(row, ib)] += d[B];
            for q in 0..extra {
                gp[(row, q)] = d[RDD] * x.drdd[nz + q] + d[GN] * gn_row[nz + q] + d[GT] * gt_row[nz + q];
            }
            gp[(row, mi)] += d[IINT];
            gp[(row, m + mi)] += d[JR];
        }
    }
}

/// Scratch for one evaluation of the loads (avoids allocation in right-hand sides).
#[derive(Debug, Clone, Default)]
pub struct LoadScratch {
    pub gn: Vec<f64>,
    pub gt: Vec<f64>,
}

impl LoadScratch {
    pub fn new(m: usize) -> Self {
        Self { gn: vec![0.0; m], gt: vec![0.0; m] }
    }
    /// R̈ and the loads at (t, R, Ṙ, a, ȧ, b) (one evaluation of the terms).
    #[allow(clippy::too_many_arguments)]
    pub fn eval(&mut self, c: &dyn ModeCoupling, t: f64, r: f64, rdot: f64, a: &[f64], adot: &[f64], b: &[f64]) -> f64 {
        c.loads(t, r, rdot, a, adot, b, &mut self.gn, &mut self.gt)
    }
}
