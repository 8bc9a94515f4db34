//! The exact Jacobian of the frame mapping ([`FrameMap`]; issue 12, "Performance";
//! docs/performance.md). With K_n the symmetric matrix K(n, ·, ·) the shift's sums are
//! bilinear forms, d_n = aᵀK_n b, s_n = ȧᵀK_n b + aᵀK_n ḃ, so the derivatives of the material
//! shift z^L − z (R^L, a^L: d_n/R; Ṙ^L, ȧ^L: s_n/R − Ṙ d_n/R²) are K-products per target n and
//! mode index i:
//!
//!   ∂(a^L − a)_n/∂a_i = (K_n b)_i/R,  ∂/∂b_i = (K_n a)_i/R,  ∂/∂R = −d_n/R²;
//!   ∂(ȧ^L − ȧ)_n/∂ȧ_i = (K_n b)_i/R,  ∂/∂a_i = (K_n ḃ)_i/R − Ṙ(K_n b)_i/R²,
//!   ∂/∂b_i = (K_n ȧ)_i/R − Ṙ(K_n a)_i/R²,  ∂/∂ḃ_i = (K_n a)_i/R,  ∂/∂R, ∂/∂Ṙ from d_n, s_n.
//!
//! They are formed in one pass over the K entries, four lanes per entry, each lane the same
//! per-entry term the entry-by-entry walk this replaces added into its dense row (K(n, i, j) =
//! K(n, j, i) exactly, so the walk's sum over l into a b_k column is this sum over the partner
//! in the same order): bit for bit its Jacobian ([`FrameMap::jacobian_reference`], kept for
//! the test below), so the run's step sequence and series.csv do not move. The frame change
//! and J(z^L)'s share are walked as before.

use std::cell::RefCell;

use super::super::second_order::{FirstOrder, FirstOrderGradient};
use super::super::{At, LoadJacobian};
use super::{rows, FrameMap};

/// The Jacobian's work space (per thread, grown once).
#[derive(Default)]
struct Scratch {
    dsh: Vec<f64>,
    /// the reference walk's per-target ḃ coefficients
    #[cfg_attr(not(test), allow(dead_code))]
    v: Vec<f64>,
    df: Vec<f64>,
    dfr: Vec<f64>,
    /// the non-zero columns of each row of df: `nzc[nz_start[l]..nz_start[l + 1]]`
    nzc: Vec<usize>,
    nz_start: Vec<usize>,
    jl: Option<LoadJacobian>,
    /// the shift's derivatives per (target, mode index), module doc
    kp: Vec<[f64; 4]>,
}

/// out += w · ∂ḃ⁽¹⁾_k/∂x (`dbd` row k of `rows`, columns beyond it zero; `at` reads one entry so).
fn add_scaled(out: &mut [f64], w: f64, rows: &[f64], k: usize, at: &impl Fn(usize, usize) -> f64) {
    let nc = out.len();
    match rows.get(k * nc..(k + 1) * nc) {
        Some(g) => {
            for (o, x) in out.iter_mut().zip(g) {
                *o += w * x;
            }
        }
        None => {
            for (col, o) in out.iter_mut().enumerate() {
                *o += w * at(k, col);
            }
        }
    }
}

/// `v` resized to `n` zeros.
fn zeroed(v: &mut Vec<f64>, n: usize) -> &mut [f64] {
    v.clear();
    v.resize(n, 0.0);
    v
}


thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

impl FrameMap {
    /// [`SecondOrderTerm::add_jacobian`](super::super::second_order::SecondOrderTerm::add_jacobian)
    /// in the per-thread work space (module doc).
    pub(super) fn jacobian(&self, at: &At<'_>, first: &FirstOrder<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian) {
        SCRATCH.with(|s| {
            let ws = &mut *s.borrow_mut();
            self.jacobian_with(at, first, grad, jac, ws);
        });
    }

    /// The Jacobian in the work space `ws` (module doc).
    #[inline(always)]
    fn jacobian_with(&self, at: &At<'_>, first: &FirstOrder<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian, ws: &mut Scratch) {
        let (z, m, nc, lay) = (at.z, self.modes, jac.n, jac.layout());
        let nz = z.len();
        let (r, rd) = (z[0], z[1]);
        let (bd, f1) = self.first(at, first);
        let dbd = |i: usize, col: usize| grad.dbd.get(i * nc + col).copied().unwrap_or(0.0);
        let sums = self.sums(at, first);
        let (d, s) = (&sums.d, &sums.s);
        let zl = self.material(z, d, s);
        // the shift's derivatives per (target n, mode index i), summed over the partner j in the
        // entry order: [(c b_j)/R, (c ḃ_j)/R − Ṙ c b_j/R², (c a_j)/R, (c ȧ_j)/R − Ṙ c a_j/R²],
        // c = K(n, i, j) = K(n, j, i) (module doc)
        let mut u = [[0.0; 4]; super::MAX_MODES];
        for (i, ui) in u.iter_mut().enumerate().take(m) {
            *ui = [at.b(i), bd[i], at.a(i), at.adot(i)];
        }
        ws.kp.clear();
        ws.kp.resize((m + 1) * m, [0.0; 4]);
        let kp = &mut ws.kp[..];
        for &(n, l, k, c) in &self.entries {
            let (o, x) = (&mut kp[n * m + l], &u[k]);
            let rc = rd * c;
            let t = [c * x[0] / r, c * x[1] / r - rc * x[0] / (r * r), c * x[2] / r, c * x[3] / r - rc * x[2] / (r * r)];
            for q in 0..4 {
                o[q] += t[q];
            }
        }
        let kp = &*kp;
        // dsh[q][col] = ∂(z^L − z)_q/∂x_col (only the rows of the targets' values and rates)
        let dsh = zeroed(&mut ws.dsh, nz * nc);
        for n in 0..=m {
            let (p, q) = rows(n);
            let (rp, rq) = (p * nc, q * nc);
            for l in 0..m {
                let (x, ia, iad, ib) = (&kp[n * m + l], lay.a(l), lay.adot(l), lay.b(l));
                dsh[rp + ia] = x[0];
                dsh[rp + ib] = x[2];
                dsh[rq + iad] = x[0];
                dsh[rq + ia] = x[1];
                dsh[rq + ib] = x[3];
            }
            dsh[rp] -= d[n] / (r * r);
            dsh[rq] += -s[n] / (r * r) + 2.0 * rd * d[n] / (r * r * r);
            dsh[rq + 1] -= d[n] / (r * r);
            // through ḃ⁽¹⁾: the coefficient of ḃ_k in the rate, Σ_l K a_l / R
            for k in 0..m {
                let w = kp[n * m + k][2];
                if w != 0.0 {
                    add_scaled(&mut dsh[rq..rq + nc], w, grad.dbd, k, &dbd);
                }
            }
        }
        self.finish(at, grad, jac, ws, &bd, &f1, &zl[..nz]);
    }

    /// The part both assemblies share, with `ws.dsh` = ∂(z^L − z)/∂x filled: J(z^L)'s share,
    /// ∂[L(z^L) − L(z)]/∂x, and the frame change's, ∂fr_n (the same operations in the same
    /// order for both, so the reference test compares the shift's derivatives alone).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn finish(&self, at: &At<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian, ws: &mut Scratch, bd: &[f64], f1: &[f64], zl: &[f64]) {
        let (z, m, nc, lay) = (at.z, self.modes, jac.n, jac.layout());
        let nz = z.len();
        let r = z[0];
        let dbd = |i: usize, col: usize| grad.dbd.get(i * nc + col).copied().unwrap_or(0.0);
        // J(z) is the core's; J(z^L) here
        let j0 = grad.material;
        let jl = ws.jl.get_or_insert_with(|| LoadJacobian::new(m));
        if jl.modes() != m {
            *jl = LoadJacobian::new(m);
        }
        self.lagrangian_jacobian(at.t, zl, jl);
        // ∂[L(z^L) − L(z)]/∂x = J(z^L)(E + ∂(z^L − z)/∂x) − J(z)E, per output row
        let dsh = &ws.dsh[..];
        let shifted = |src: &[f64], src0: &[f64], out: &mut [f64]| {
            for col in 0..nz {
                out[col] += src[col] - src0[col];
            }
            for (qi, &g) in src.iter().enumerate() {
                if g != 0.0 {
                    for (o, x) in out.iter_mut().zip(&dsh[qi * nc..(qi + 1) * nc]) {
                        *o += g * x;
                    }
                }
            }
        };
        shifted(&jl.pressure, &j0.pressure, &mut jac.pressure[..nc]);
        for i in 0..m {
            shifted(jl.gn_row(i), j0.gn_row(i), &mut jac.gn[i * nc..(i + 1) * nc]);
            shifted(jl.gt_row(i), j0.gt_row(i), &mut jac.gt[i * nc..(i + 1) * nc]);
        }
        // the frame change fr_n = −(1/R) Σ K F_l b_k, F_l = G_n,l(z) + cn_l ḃ_l
        let (cn, cn_r) = self.bdot_normal(at);
        let df = zeroed(&mut ws.df, m * nc);
        for l in 0..m {
            let row = &mut df[l * nc..(l + 1) * nc];
            row[..nz].copy_from_slice(j0.gn_row(l));
            row[0] += cn_r[l] * bd[l];
            // cn = 0 (no ḃ loads) adds zeros only
            if cn[l] != 0.0 {
                add_scaled(row, cn[l], grad.dbd, l, &dbd);
            }
        }
        // the non-zero columns of each ∂F_l (the rest add zeros only)
        ws.nzc.clear();
        ws.nz_start.clear();
        for l in 0..m {
            ws.nz_start.push(ws.nzc.len());
            ws.nzc.extend(df[l * nc..(l + 1) * nc].iter().enumerate().filter(|(_, x)| **x != 0.0).map(|(c, _)| c));
        }
        ws.nz_start.push(ws.nzc.len());
        // ∂fr_n = −(K/R)(b_k ∂F_l + F_l ∂b_k) + (K F_l b_k/R²) ∂R, per entry
        let dfr = zeroed(&mut ws.dfr, (m + 1) * nc);
        for &(n, l, k, c) in &self.entries {
            let (f, bk) = (f1[l], at.b(k));
            let row = &mut dfr[n * nc..(n + 1) * nc];
            row[lay.b(k)] -= c * f / r;
            row[0] += c * f * bk / (r * r);
            let (dl, w) = (&df[l * nc..(l + 1) * nc], c * bk / r);
            for &col in &ws.nzc[ws.nz_start[l]..ws.nz_start[l + 1]] {
                row[col] -= w * dl[col];
            }
        }
        for col in 0..nc {
            jac.pressure[col] -= dfr[col];
        }
        for i in 0..m {
            for col in 0..nc {
                jac.gn[i * nc + col] += dfr[(1 + i) * nc + col];
            }
        }
    }
}

impl FrameMap {
    /// The entry-by-entry assembly the K-product one replaces (kept to test it against).
    #[cfg(test)]
    fn jacobian_reference(&self, at: &At<'_>, first: &FirstOrder<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian, ws: &mut Scratch) {
        let (z, m, nc, lay) = (at.z, self.modes, jac.n, jac.layout());
        let nz = z.len();
        let (r, rd) = (z[0], z[1]);
        let (bd, f1) = self.first(at, first);
        let dbd = |i: usize, col: usize| grad.dbd.get(i * nc + col).copied().unwrap_or(0.0);
        let sums = self.sums(at, first);
        let (d, s) = (&sums.d, &sums.s);
        let zl = self.material(z, d, s);
        // dsh[q][col] = ∂(z^L − z)_q/∂x_col
        let dsh = zeroed(&mut ws.dsh, nz * nc);
        // v[n][k] = Σ_l K a_l / R: the coefficient of ḃ_k in the rate of target n
        let v = zeroed(&mut ws.v, (m + 1) * m);
        for &(n, l, k, c) in &self.entries {
            let (p, q) = rows(n);
            let (ia, iad, ib) = (lay.a(l), lay.adot(l), lay.b(k));
            let (al, adl, bk) = (z[ia], z[iad], z[ib]);
            dsh[p * nc + ia] += c * bk / r;
            dsh[p * nc + ib] += c * al / r;
            dsh[q * nc + iad] += c * bk / r;
            dsh[q * nc + ib] += c * adl / r - rd * c * al / (r * r);
            dsh[q * nc + ia] += c * bd[k] / r - rd * c * bk / (r * r);
            v[n * m + k] += c * al / r;
        }
        for n in 0..=m {
            let (p, q) = rows(n);
            dsh[p * nc] -= d[n] / (r * r);
            dsh[q * nc] += -s[n] / (r * r) + 2.0 * rd * d[n] / (r * r * r);
            dsh[q * nc + 1] -= d[n] / (r * r);
            for k in 0..m {
                let w = v[n * m + k];
                if w != 0.0 {
                    add_scaled(&mut dsh[q * nc..(q + 1) * nc], w, grad.dbd, k, &dbd);
                }
            }
        }
        self.finish(at, grad, jac, ws, &bd, &f1, &zl[..nz]);
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::membrane::MembraneTerm;
    use super::super::super::second_order::{MaterialLoads, SecondOrderTerm};
    use super::super::super::shell::ShellViscosity;
    use super::super::super::Term;
    use super::*;
    use crate::model::params::Membrane;
    use crate::scene::{MembraneForm, ShellLaw};

    /// The K-product assembly is the entry-by-entry walk bit for bit on random states
    /// (k = 2 … 16; Mooney–Rivlin membrane and shell viscosity, so ḃ loads too), with random
    /// first-order ḃ and gradients.
    #[test]
    fn k_product_assembly_is_the_entry_walk() {
        let nm = 8;
        let orders: Vec<f64> = (1..=nm).map(|i| 2.0 * i as f64).collect();
        let mr = MembraneTerm { law: Membrane::for_law(&ShellLaw::MooneyRivlin, MembraneForm::Tension), r0: 1.0, c1: 0.9, c2: 0.3, orders: orders.clone() };
        let visc = ShellViscosity { kappa_s: 0.3, mu_s: 0.2, r0: 1.0, orders: orders.clone() };
        let lagrangian: Vec<Box<dyn Term>> = vec![Box::new(mr), Box::new(visc)];
        let fm = FrameMap::new(lagrangian, &orders).expect("frame map");
        let n = crate::model::layout::StateLayout::reduced(nm).dim();
        for seed in 0..20u64 {
            let v = |i: usize| (0.37 * i as f64 + 0.91 * seed as f64 + 0.1).sin();
            let mut z: Vec<f64> = (0..n).map(|i| 1e-2 * v(i)).collect();
            (z[0], z[1]) = (1.0 + 0.3 * v(1000), 0.5 * v(1001));
            let add: Vec<f64> = (0..nm).map(|i| 1e-2 * v(100 + i)).collect();
            let bd: Vec<f64> = (0..nm).map(|i| 1e-2 * v(200 + i)).collect();
            let drdd: Vec<f64> = (0..n).map(|i| v(300 + i)).collect();
            let dadd: Vec<f64> = (0..nm * n).map(|i| v(500 + i)).collect();
            let dbd: Vec<f64> = (0..nm * n).map(|i| v(900 + i)).collect();
            let (p0, gn0, gt0) = fm.lagrangian_loads(0.0, &z);
            let mut mj = LoadJacobian::new(nm);
            fm.lagrangian_jacobian(0.0, &z, &mut mj);
            let material = MaterialLoads { pressure: p0, gn: &gn0[..nm], gt: &gt0[..nm] };
            let first = FirstOrder { rdd: 0.3 * v(2000), add: &add, bd: &bd, material };
            let grad = FirstOrderGradient { drdd: &drdd, dadd: &dadd, dbd: &dbd, material: &mj };
            let at = At { t: 0.0, z: &z };
            let (mut want, mut got) = (LoadJacobian::new(nm), LoadJacobian::new(nm));
            SCRATCH.with(|s| fm.jacobian_reference(&at, &first, &grad, &mut want, &mut s.borrow_mut()));
            fm.add_jacobian(&at, &first, &grad, &mut got);
            let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&want.pressure), bits(&got.pressure), "seed {seed}: P row");
            assert_eq!(bits(&want.gn), bits(&got.gn), "seed {seed}: G_n rows");
            assert_eq!(bits(&want.gt), bits(&got.gt), "seed {seed}: G_t rows");
            assert!(want.gn.iter().filter(|x| **x != 0.0).count() > 4 * nm, "a non-trivial Jacobian");
        }
    }
}
