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

/// The exact ∂(f_z, T_w)/∂z ((nz + M) × nz) and ∂(f_z, T_w)/∂p ((nz + M) × 2M) of the reduced
/// function of the monolithic system ([`super::monolithic::Monolithic::reduced`]): z = [R, Ṙ,
/// (a, ȧ, b)_k], p = [Ĩ_int,k (M), ∫(y⁻³−1)y^{−k}T dy (M)], rows f_z then T_w,k. From the
/// coupling's load gradients, the closure's partials and [`crate::model::equations::mode_partials`].
pub fn reduced_jacobian(c: &dyn ModeCoupling, t: f64, z: &[f64], p: &[f64], w0: f64, gz: &mut DMatrix<f64>, gp: &mut DMatrix<f64>) {
    use eqs::var::*;
    let orders = c.orders();
    let m = orders.len();
    let nz = 2 + 3 * m;
    let (rho, eta) = (c.density(), c.viscosity());
    let (r, rd) = (z[0], z[1]);
    let pick = |o: usize| (0..m).map(|i| z[2 + 3 * i + o]).collect::<Vec<f64>>();
    let (a, ad, b) = (pick(0), pick(1), pick(2));
    let mut ls = LoadScratch::new(m);
    let rdd = ls.eval(c, t, r, rd, &a, &ad, &b);
    let mut lj = crate::model::effects::LoadJacobian::new(m);
    let mut drdd = vec![0.0; nz];
    c.linearize(t, z, &mut drdd, &mut lj);
    gz.fill(0.0);
    gp.fill(0.0);
    gz[(0, 1)] = 1.0;
    for j in 0..nz {
        gz[(1, j)] = drdd[j];
    }
    for (mi, &k) in orders.iter().enumerate() {
        let kf = k as f64;
        let i = 2 + 3 * mi;
        gz[(i, i + 1)] = 1.0;
        let (gn, gt) = (ls.gn[mi], ls.gt[mi]);
        let src = wall_source(kf, eta, r, rd, a[mi], ad[mi], gt);
        let d_src = eqs::wall_source_partials(kf, eta, r, rd, a[mi], gt);
        let w = wall_linear(r, src, &d_src, p[mi], p[m + mi], w0);
        let (da, db) = eqs::mode_partials(kf, rho, eta, r, rd, rdd, a[mi], ad[mi], b[mi], gn, &w);
        let (gn_row, gt_row) = (lj.gn_row(mi), lj.gt_row(mi));
        for (row, d) in [(i + 1, &da), (i + 2, &db), (nz + mi, &w.d_tw)] {
            for j in 0..nz {
                gz[(row, j)] = d[RDD] * drdd[j] + d[GN] * gn_row[j] + d[GT] * gt_row[j];
            }
            gz[(row, 0)] += d[R];
            gz[(row, 1)] += d[RD];
            gz[(row, i)] += d[A];
            gz[(row, i + 1)] += d[AD];
            gz[(row, i + 2)] += d[B];
            gp[(row, mi)] = d[IINT];
            gp[(row, m + mi)] = d[JR];
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
