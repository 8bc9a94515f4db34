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

use super::second_order::{FirstOrder, FirstOrderGradient, SecondOrderTerm};
use super::{a_index, At, BdotLoads, LoadJacobian, Loads, Term, MAX_MODES};
use crate::coefficients::quadratic::P1P1P;

/// ∫ P¹_l P¹_m P_j dx of the generated tensor (0 outside the selection rules).
fn p1p1p(l: usize, m: usize, j: usize) -> f64 {
    let key = (l.min(m) as u16, l.max(m) as u16, j as u16);
    P1P1P.binary_search_by(|e| (e.0, e.1, e.2).cmp(&key)).map_or(0.0, |i| P1P1P[i].3)
}

#[derive(Debug)]
pub struct FrameMap {
    /// The linear loads derived in the material frame (membrane law, bending, shell viscosity).
    lagrangian: Vec<Box<dyn Term>>,
    /// (target n: 0 = P_0, 1 + i = mode index i; l; m; K(n, l, m)) over ordered mode pairs.
    entries: Vec<(usize, usize, usize, f64)>,
    /// The same entries grouped by the ordered pair (l, m): the pair's (z index of a_l, z index
    /// of b_m, l, m) and the range of its (n, K) in `targets`, so that the rhs forms each pair's
    /// products once and scatters them to the targets the selection rules allow.
    pairs: Vec<(usize, usize, usize, usize, usize, usize)>,
    targets: Vec<(usize, f64)>,
    modes: usize,
}

/// The (value, rate) rows of target n in z: R, Ṙ for n = 0, a, ȧ of mode n − 1 otherwise.
fn rows(n: usize) -> (usize, usize) {
    if n == 0 { (0, 1) } else { (a_index(n - 1), a_index(n - 1) + 1) }
}

impl FrameMap {
    /// `lagrangian`: the scene's linear terms whose loads are derived in the material frame;
    /// `orders`: k of each mode index. None without such terms (nothing to map).
    pub fn new(lagrangian: Vec<Box<dyn Term>>, orders: &[f64]) -> Option<Self> {
        if lagrangian.is_empty() || orders.is_empty() {
            return None;
        }
        let ks: Vec<usize> = orders.iter().map(|&k| k as usize).collect();
        let mut entries = Vec::new();
        for n in 0..=ks.len() {
            let kn = if n == 0 { 0 } else { ks[n - 1] };
            for (l, &kl) in ks.iter().enumerate() {
                for (m, &km) in ks.iter().enumerate() {
                    let c = (2 * kn + 1) as f64 / 2.0 * p1p1p(kl, km, kn);
                    if c != 0.0 {
                        entries.push((n, l, m, c));
                    }
                }
            }
        }
        let (mut pairs, mut targets) = (Vec::new(), Vec::new());
        for l in 0..ks.len() {
            for m in 0..ks.len() {
                let start = targets.len();
                targets.extend(entries.iter().filter(|e| e.1 == l && e.2 == m).map(|e| (e.0, e.3)));
                if targets.len() > start {
                    pairs.push((a_index(l), a_index(m) + 2, l, m, start, targets.len()));
                }
            }
        }
        Some(Self { lagrangian, entries, pairs, targets, modes: ks.len() })
    }

    /// Σ over the Lagrangian terms: (P, G_n, G_t) at z.
    fn linear(&self, t: f64, z: &[f64]) -> (f64, [f64; MAX_MODES], [f64; MAX_MODES]) {
        let (mut gn, mut gt) = ([0.0; MAX_MODES], [0.0; MAX_MODES]);
        let m = self.modes;
        let mut l = Loads { pressure: 0.0, gn: &mut gn[..m], gt: &mut gt[..m] };
        for term in &self.lagrangian {
            term.add(&At { t, z }, &mut l);
        }
        let p = l.pressure;
        (p, gn, gt)
    }

    /// The normal ḃ coefficients cn and ∂cn/∂R of the Lagrangian terms at z.
    fn bdot_normal(&self, at: &At<'_>) -> ([f64; MAX_MODES], [f64; MAX_MODES]) {
        let m = self.modes;
        let (mut cn, mut ct, mut cn_r, mut ct_r) = ([0.0; MAX_MODES], [0.0; MAX_MODES], [0.0; MAX_MODES], [0.0; MAX_MODES]);
        let mut c = BdotLoads { cn: &mut cn[..m], ct: &mut ct[..m], cn_r: &mut cn_r[..m], ct_r: &mut ct_r[..m] };
        for term in self.lagrangian.iter().filter(|t| t.has_bdot_loads()) {
            term.add_bdot_loads(at, &mut c);
        }
        (cn, cn_r)
    }

    /// Σ K a_l b_m and Σ K (ȧ_l b_m + a_l ḃ_m) per target (the shift times R).
    fn sums(&self, z: &[f64], bd: &[f64]) -> ([f64; MAX_MODES + 1], [f64; MAX_MODES + 1]) {
        let (mut d, mut s) = ([0.0; MAX_MODES + 1], [0.0; MAX_MODES + 1]);
        for &(ia, ib, _, m, t0, t1) in &self.pairs {
            let (al, adl, bm) = (z[ia], z[ia + 1], z[ib]);
            let (x, y) = (al * bm, adl * bm + al * bd.get(m).copied().unwrap_or(0.0));
            for &(n, c) in &self.targets[t0..t1] {
                d[n] += c * x;
                s[n] += c * y;
            }
        }
        (d, s)
    }

    /// The material state z^L (R^L, Ṙ^L, a^L, ȧ^L, b) of z.
    fn material(&self, z: &[f64], d: &[f64], s: &[f64]) -> [f64; 2 + 3 * MAX_MODES] {
        let (r, rd) = (z[0], z[1]);
        let mut zl = [0.0; 2 + 3 * MAX_MODES];
        zl[..z.len()].copy_from_slice(z);
        for n in 0..=self.modes {
            let (p, v) = rows(n);
            zl[p] += d[n] / r;
            zl[v] += s[n] / r - rd * d[n] / (r * r);
        }
        zl
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
        let (z, m, r) = (at.z, self.modes, at.z[0]);
        let (d, s) = self.sums(z, first.bd);
        let zl = self.material(z, &d, &s);
        let (p0, gn0, gt0) = self.linear(at.t, z);
        let (pl, gnl, gtl) = self.linear(at.t, &zl[..z.len()]);
        let (cn, _) = self.bdot_normal(at);
        let mut f1 = [0.0; MAX_MODES];
        for i in 0..m {
            f1[i] = gn0[i] + cn[i] * first.bd.get(i).copied().unwrap_or(0.0);
        }
        // frame change −Σ K F_l b_m / R of the normal load on P_n
        let mut fr = [0.0; MAX_MODES + 1];
        for &(_, ib, l, _, t0, t1) in &self.pairs {
            let x = f1[l] * z[ib];
            for &(n, c) in &self.targets[t0..t1] {
                fr[n] -= c * x;
            }
        }
        // the normal load on P_0 is subtracted from P (as Ŝ0), on P_j added to G_n,j
        loads.pressure += pl - p0 - fr[0] / r;
        for i in 0..loads.gn.len().min(m) {
            loads.gn[i] += gnl[i] - gn0[i] + fr[1 + i] / r;
            loads.gt[i] += gtl[i] - gt0[i];
        }
    }
    fn add_jacobian(&self, at: &At<'_>, first: &FirstOrder<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian) {
        let (z, m, nc) = (at.z, self.modes, jac.n);
        let nz = z.len();
        let (r, rd) = (z[0], z[1]);
        let bd = |i: usize| first.bd.get(i).copied().unwrap_or(0.0);
        let dbd = |i: usize, col: usize| grad.dbd.get(i * nc + col).copied().unwrap_or(0.0);
        let (d, s) = self.sums(z, first.bd);
        let zl = self.material(z, &d, &s);
        // dsh[q][col] = ∂(z^L − z)_q/∂x_col
        let mut dsh = vec![0.0; nz * nc];
        // v[n][k] = Σ_l K a_l / R: the coefficient of ḃ_k in the rate of target n
        let mut v = vec![0.0; (m + 1) * m];
        for &(n, l, k, c) in &self.entries {
            let (p, q) = rows(n);
            let (ia, ib) = (a_index(l), a_index(k) + 2);
            let (al, adl, bk) = (z[ia], z[ia + 1], z[ib]);
            dsh[p * nc + ia] += c * bk / r;
            dsh[p * nc + ib] += c * al / r;
            dsh[q * nc + ia + 1] += c * bk / r;
            dsh[q * nc + ib] += c * adl / r - rd * c * al / (r * r);
            dsh[q * nc + ia] += c * bd(k) / r - rd * c * bk / (r * r);
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
                    for col in 0..nc {
                        dsh[q * nc + col] += w * dbd(k, col);
                    }
                }
            }
        }
        let (mut j0, mut jl) = (LoadJacobian::new(m), LoadJacobian::new(m));
        for term in &self.lagrangian {
            term.add_jacobian(&At { t: at.t, z }, &mut j0);
            term.add_jacobian(&At { t: at.t, z: &zl[..nz] }, &mut jl);
        }
        // ∂[L(z^L) − L(z)]/∂x = J(z^L)(E + ∂(z^L − z)/∂x) − J(z)E, per output row
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
        let (gn0, (cn, cn_r)) = (self.linear(at.t, z).1, self.bdot_normal(at));
        let mut df = vec![0.0; m * nc];
        for l in 0..m {
            let row = &mut df[l * nc..(l + 1) * nc];
            row[..nz].copy_from_slice(j0.gn_row(l));
            row[0] += cn_r[l] * bd(l);
            for (col, x) in row.iter_mut().enumerate() {
                *x += cn[l] * dbd(l, col);
            }
        }
        // ∂fr_n = −(K/R)(b_k ∂F_l + F_l ∂b_k) + (K F_l b_k/R²) ∂R, per entry
        let mut dfr = vec![0.0; (m + 1) * nc];
        for &(n, l, k, c) in &self.entries {
            let (f, bk) = (gn0[l] + cn[l] * bd(l), z[a_index(k) + 2]);
            let row = &mut dfr[n * nc..(n + 1) * nc];
            row[a_index(k) + 2] -= c * f / r;
            row[0] += c * f * bk / (r * r);
            for (o, x) in row.iter_mut().zip(&df[l * nc..(l + 1) * nc]) {
                *o -= c * bk / r * x;
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
