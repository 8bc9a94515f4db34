//! The boundary-layer system's sensitivity equations in one pass (issue 32, docs/model.md
//! "Fitting"; the generic system is [`crate::integrate::sensitivity`]): from ONE linearisation at
//! (t, y) ([`super::linearize`]) the rhs f, and for each direction S_j
//!
//!   J·S_j + ∂f/∂θ_j,
//!
//! where ∂f/∂θ_j comes from what the parameter does to the loads at fixed state ([`LoadRate`]):
//! a parameter held by terms changes P (and, for Keller–Miksis, the rate's q and s), G_n, G_t and
//! the ḃ-load coefficients, and f depends on it only through them, so ∂f/∂θ is the same linear
//! form of the loads' derivatives as J·S is of the gradients' products with S (the chain rule:
//! ∂R̈/∂θ = ∂R̈/∂P ∂P/∂θ + ∂R̈/∂q ∂q/∂θ + ∂R̈/∂s ∂s/∂θ, then each mode's (ä, ḃ) rows,
//! [`RowForm`]). The loads' derivatives are formed from the terms that hold the parameter, by
//! their own functions ([`LoadRate::add_difference`]): no rhs of a changed model.
//!
//! f is the rhs's own arithmetic (the same loads, R̈ and mode rates, bit for bit) when
//! [`BoundaryLayerSystem::fused_sensitivities`] holds: no second-pass terms and no ḃ in R̈.

use super::boundary_layer::BoundaryLayerSystem;
use super::effects::{zeroed, At, BdotLoads, Loads, PressureRate, Term, MAX_MODES};
use super::equations::{var, Equations};
use super::layout::StateLayout;
use super::linearize::{Lin, RowForm};

/// ∂/∂θ of the loads at fixed state (t, z): P, the rate's (q, s) (compressible form), G_n, G_t
/// and the ḃ-load coefficients (cn, ct) per mode.
#[derive(Debug, Clone)]
pub struct LoadRate {
    pub pressure: f64,
    pub q: f64,
    pub s: f64,
    pub gn: [f64; MAX_MODES],
    pub gt: [f64; MAX_MODES],
    pub cn: [f64; MAX_MODES],
    pub ct: [f64; MAX_MODES],
}

impl Default for LoadRate {
    fn default() -> Self {
        let z = [0.0; MAX_MODES];
        LoadRate { pressure: 0.0, q: 0.0, s: 0.0, gn: z, gt: z, cn: z, ct: z }
    }
}

impl LoadRate {
    /// Zero for the first `modes` modes (the rest is not read).
    pub fn clear(&mut self, modes: usize) {
        (self.pressure, self.q, self.s) = (0.0, 0.0, 0.0);
        for v in [&mut self.gn, &mut self.gt, &mut self.cn, &mut self.ct] {
            v[..modes].fill(0.0);
        }
    }

    /// Adds (share of `plus` − share of `base`)/dθ at `at`: a term's share of P, G_n, G_t, of the
    /// rate (q, s) when `eq`'s radial form needs it, and of the ḃ-load coefficients — each from
    /// the term's own [`Term::add`], [`Term::add_rate`], [`Term::add_bdot_loads`]. Exact up to
    /// rounding for a term affine in the parameter (`plus` is the term at θ + dθ).
    pub fn add_difference(&mut self, eq: &Equations, plus: &dyn Term, base: &dyn Term, at: &At<'_>, dtheta: f64) {
        let m = eq.orders().len();
        // the two shares' per-mode loads (G_n, G_t, cn, ct each) in one stack block, zeroed
        // only where used
        let mut block = [std::mem::MaybeUninit::<f64>::uninit(); 8 * MAX_MODES];
        let z = zeroed(&mut block[..8 * m]);
        let (a, b) = z.split_at_mut(4 * m);
        let ra = share(eq, plus, at, m, a);
        let rb = share(eq, base, at, m, b);
        let d = |x: f64, y: f64| (x - y) / dtheta;
        self.pressure += d(ra[0], rb[0]);
        self.q += d(ra[1], rb[1]);
        self.s += d(ra[2], rb[2]);
        for (k, out) in [&mut self.gn, &mut self.gt, &mut self.cn, &mut self.ct].into_iter().enumerate() {
            let (x, y) = (&a[k * m..(k + 1) * m], &b[k * m..(k + 1) * m]);
            for j in 0..m {
                out[j] += d(x[j], y[j]);
            }
        }
    }
}

/// One term's share of the loads at (t, z): [P, q, s] returned, G_n, G_t, cn, ct into the four
/// consecutive blocks of length m of `buf` (zero on entry).
fn share(eq: &Equations, term: &dyn Term, at: &At<'_>, m: usize, buf: &mut [f64]) -> [f64; 3] {
    let (gn, rest) = buf.split_at_mut(m);
    let (gt, rest) = rest.split_at_mut(m);
    let (cn, ct) = rest.split_at_mut(m);
    let mut l = Loads { pressure: 0.0, gn, gt };
    term.add(at, &mut l);
    let mut out = [l.pressure, 0.0, 0.0];
    if eq.form().needs_rate() {
        let mut rate = PressureRate::default();
        term.add_rate(at, &mut rate);
        (out[1], out[2]) = (rate.q, rate.s);
    }
    if term.has_bdot_loads() {
        let (mut cn_r, mut ct_r) = ([0.0; MAX_MODES], [0.0; MAX_MODES]);
        let mut c = BdotLoads { cn, ct, cn_r: &mut cn_r[..m], ct_r: &mut ct_r[..m] };
        term.add_bdot_loads(at, &mut c);
    }
    out
}

/// The buffers of [`BoundaryLayerSystem::sensitivity_rhs`], reused from call to call.
pub struct ProductWork {
    lin: Lin,
    forms: Vec<RowForm>,
}

impl BoundaryLayerSystem {
    /// Whether [`sensitivity_rhs`](Self::sensitivity_rhs) applies: no second-pass terms (the
    /// quadratic coupling) and no ḃ in R̈ (Keller–Miksis with a field).
    pub fn fused_sensitivities(&self) -> bool {
        // (the reduced thermal model's ṗ_b is not in the fused rhs; the fit refuses it anyway)
        !self.eq.has_second_order() && !self.bdot_radial && self.gas.is_none()
    }

    /// Work buffers for [`sensitivity_rhs`](Self::sensitivity_rhs).
    pub fn product_work(&self) -> ProductWork {
        ProductWork { lin: Lin::new(self.modes.len()), forms: Vec::with_capacity(self.modes.len()) }
    }

    /// f(t, y) into `dy` (the rhs's values bit for bit) and, for the p directions of `s` (blocks of
    /// length n), J·S_j + ∂f/∂θ_j into the blocks of `out`, with ∂f/∂θ_j from the loads'
    /// derivatives `rates[j]` (`None` or absent: J·S_j alone). Needs
    /// [`fused_sensitivities`](Self::fused_sensitivities).
    #[allow(clippy::too_many_arguments)]
    pub fn sensitivity_rhs(&self, t: f64, y: &[f64], s: &[f64], rates: &[Option<LoadRate>], w: &mut ProductWork, dy: &mut [f64], out: &mut [f64]) {
        debug_assert!(self.fused_sensitivities());
        let m = self.modes.len();
        let l = &mut w.lin;
        self.lin_into(t, y, None, l);
        // the rhs (boundary_layer.rs): ḃ loads in gn, gt, R̈ from P, then the mode rates
        dy[0] = y[1];
        dy[1] = l.rdd;
        self.mode_rates(y[0], y[1], l.rdd, &l.gn[..m], &l.gt[..m], y, dy);
        w.forms.clear();
        for j in 0..m {
            w.forms.push(self.row_form(y, l, j));
        }
        self.apply_product(l, &w.forms, s, rates, out);
    }

    /// J·S_j (+ ∂f/∂θ_j from `rates[j]`) from the linearisation `l` and its row forms: each row of
    /// the Jacobian is a combination of a few gradients (R̈'s, mode m's G_n and G_t) plus single
    /// columns ([`RowForm`]), so (row·S) is that combination of the gradients' products with S,
    /// O(M·n) per direction; the parameter's part is the same combination of the loads'
    /// derivatives (module doc).
    pub(super) fn apply_product(&self, l: &Lin, forms: &[RowForm], s: &[f64], rates: &[Option<LoadRate>], out: &mut [f64]) {
        use var::*;
        // the state's length (with the reduced thermal model's gas slot, one more than the
        // load columns of `l.drdd`)
        let n = self.layout().dim();
        // the gradients' products over their non-zero columns only ([`super::JacobianPattern`]):
        // R̈'s over R, Ṙ and the modes the radial loads see, G_k's over R, Ṙ and the modes of
        // the band around k (the same sums as over all columns, less the zero terms)
        let (pat, lay) = (self.jacobian_pattern(), self.layout());
        let radial = 0..lay.blocks(0..pat.radial).end;
        let band = |m: usize| lay.blocks(m.saturating_sub(pat.band)..(m + pat.band + 1).min(forms.len()));
        let dot = |g: &[f64], v: &[f64], cols: std::ops::Range<usize>| {
            let mut acc = 0.0;
            if cols.start >= StateLayout::RADIAL {
                acc += g[0] * v[0];
                acc += g[1] * v[1];
            }
            let (g, v) = (&g[cols.clone()], &v[cols]);
            for c in 0..g.len().min(v.len()) {
                acc += g[c] * v[c];
            }
            acc
        };
        for (j, (sj, oj)) in s.chunks_exact(n).zip(out.chunks_exact_mut(n)).enumerate() {
            let rate = rates.get(j).and_then(Option::as_ref);
            let mut rdd = dot(&l.drdd, sj, radial.clone());
            if let Some(r) = rate {
                rdd += l.form[2] * r.pressure + l.form[3] * r.q + l.form[4] * r.s;
            }
            if let Some(g) = &self.gas {
                // the gas slot: its column (through R̈) and ṗ_b's row
                let i = g.index;
                rdd += l.drdd_pb * sj[i];
                oj[i] = l.gas_row[0] * sj[0] + l.gas_row[1] * sj[1] + l.gas_row[2] * sj[i];
            }
            oj[0] = sj[1];
            oj[1] = rdd;
            for (m, f) in forms.iter().enumerate() {
                let [ia, iad, ib] = f.idx;
                let (mut gn, mut gt) = (dot(l.lj.gn_row(m), sj, band(m)), dot(l.lj.gt_row(m), sj, band(m)));
                if let Some(r) = rate {
                    // at fixed ḃ the ḃ loads change by (∂cn/∂θ, ∂ct/∂θ)·ḃ
                    let bd = f.c.map_or(0.0, |c| c[4]);
                    gn += r.gn[m] + r.cn[m] * bd;
                    gt += r.gt[m] + r.ct[m] * bd;
                }
                let row = |d: &[f64; var::N]| {
                    d[RDD] * rdd + d[GN] * gn + d[GT] * gt + (d[R] + d[GN] * f.cn_r_b + d[GT] * f.ct_r_b) * sj[0] + d[RD] * sj[1] + d[A] * sj[ia] + d[AD] * sj[iad] + d[B] * sj[ib]
                };
                let (mut va, mut vb) = (row(&f.da), row(&f.db));
                if let Some(c) = f.c {
                    vb /= 1.0 - f.db[GN] * c[0] - f.db[GT] * c[1];
                    va += (f.da[GN] * c[0] + f.da[GT] * c[1]) * vb;
                }
                oj[ia] = sj[iad];
                oj[iad] = va;
                oj[ib] = vb;
            }
        }
    }
}
