//! The exact linear structure of the boundary-layer system (issue 16 part 2): its Jacobian
//! ∂f/∂y for the implicit integrators, and the linear mode system x' = A(t) x + g(t) along a
//! prescribed R(t) for Floquet and the spectra — assembled from the terms' analytic gradients
//! ([`super::effects::Term::add_jacobian`]), the radial form's partials and the closure's
//! partials ([`super::equations::mode_partials`]). No rhs differencing, no unit-vector probing.
//!
//! Sparsity ([`JacobianPattern`]): with y = [R, Ṙ, (a, ȧ, b)_k], the Jacobian is an "arrow" —
//! column 0 (R) is full, row 1 (R̈) sees R, Ṙ and the amplitudes the radial loads depend on
//! (a_2, b_2 with a field; with Keller–Miksis also, through ḃ_2, the band of mode 2), every ä and ḃ row sees R, Ṙ and, through R̈, row 1's columns — plus a
//! block band: mode k's rows see the (a, ȧ, b) of modes k ± 2j for j ≤ `band` (0 without a
//! field: 3×3 diagonal blocks; 1 for the paper's coil and the dipole).

use super::boundary_layer::{BdotMode, BoundaryLayerSystem};
use super::effects::second_order::{FirstOrder, FirstOrderGradient, MaterialLoads};
use super::effects::{LoadJacobian, Loads, MAX_DIM, MAX_MODES};
use super::layout::StateLayout;
use super::equations::{mode_partials, var, wall_source, wall_source_partials};
use nalgebra::{DMatrix, DVector};

/// Which entries of the boundary-layer Jacobian can be non-zero (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct JacobianPattern {
    pub modes: usize,
    /// Half-width in modes of the mode-to-mode coupling.
    pub band: usize,
    /// How many leading modes R̈ sees (`band`; twice that when R̈ sees ḃ: Keller–Miksis with a
    /// field).
    pub radial: usize,
}

impl JacobianPattern {
    /// Whether ∂f_i/∂y_j may be non-zero.
    pub fn may_be_nonzero(&self, i: usize, j: usize) -> bool {
        let l = StateLayout::reduced(self.modes);
        let (radial, block) = (|x: usize| x < StateLayout::RADIAL, |x: usize| l.mode_of(x));
        if i == l.r() {
            return j == l.rdot();
        }
        // R̈ sees R, Ṙ and the amplitudes within the band of the zero-order (P_0) row.
        if i == l.rdot() {
            return radial(j) || block(j) < self.radial;
        }
        // a_k' = ȧ_k
        if l.is_a(i) {
            return j == l.adot(block(i));
        }
        // ä, ḃ rows: R, Ṙ, the band, and row 1's columns through R̈
        radial(j) || block(i).abs_diff(block(j)) <= self.band || block(j) < self.radial
    }
}

/// Mode m's (ä, ḃ) rows as a linear form ([`BoundaryLayerSystem::row_form`]): row =
/// d[RDD]·∇R̈ + d[GN]·∇G_n + d[GT]·∇G_t + d[R]·e_R + d[RD]·e_Ṙ + d[A]·e_a + d[AD]·e_ȧ + d[B]·e_b
/// (+ the ḃ loads' R column and the implicit ḃ correction when `c` is set).
pub(super) struct RowForm {
    pub(super) da: [f64; var::N],
    pub(super) db: [f64; var::N],
    pub(super) c: Option<[f64; 5]>,
    pub(super) cn_r_b: f64,
    pub(super) ct_r_b: f64,
    /// a, ȧ, b of the mode in the state.
    pub(super) idx: [usize; 3],
}

impl RowForm {
    /// The rows' response to a change x of R̈ alone (no load, no state column): the gas slot's
    /// column, whose p_b reaches the mode rows only through R̈ — the product's row applied to
    /// that direction ([`BoundaryLayerSystem::jacobian_product_into`]).
    fn through_rdd(&self, x: f64) -> (f64, f64) {
        let (mut va, mut vb) = (self.da[var::RDD] * x, self.db[var::RDD] * x);
        if let Some(c) = self.c {
            vb /= 1.0 - self.db[var::GN] * c[0] - self.db[var::GT] * c[1];
            va += (self.da[var::GN] * c[0] + self.da[var::GT] * c[1]) * vb;
        }
        (va, vb)
    }
}

/// The linearisation at (t, y): the loads, R̈ and their gradients. Its buffers are reused by
/// [`BoundaryLayerSystem::lin_into`] (the sensitivity rhs, model/sensitivity.rs, keeps one).
pub(super) struct Lin {
    pub(super) lj: LoadJacobian,
    /// P (the ordinary terms').
    pub(super) p: f64,
    pub(super) rdd: f64,
    /// ∂R̈/∂z over the load columns (R, Ṙ and the mode blocks: the layout without the gas slot).
    pub(super) drdd: Vec<f64>,
    /// ∂R̈/∂p_b with the reduced thermal model (0 without it): the gas slot's column, which the
    /// loads do not have (the radial form's ∂R̈/∂P + ∂R̈/∂q · ∂ṗ_b/∂p_b).
    pub(super) drdd_pb: f64,
    /// ṗ_b's row: ∂ṗ_b/∂(R, Ṙ, p_b) (the reduced thermal model; zero without it).
    pub(super) gas_row: [f64; 3],
    pub(super) gn: [f64; MAX_MODES],
    pub(super) gt: [f64; MAX_MODES],
    /// The ḃ_k loads per mode when there are any ([`BoundaryLayerSystem::apply_bdot_loads`];
    /// `gn`, `gt` then include them).
    pub(super) bdot: Option<Vec<BdotMode>>,
    /// The radial form's ∂R̈/∂(R, Ṙ, P, q, s) ([`super::equations::Equations::acceleration_gradient_at`];
    /// zero when R̈ is prescribed or with ḃ in R̈).
    pub(super) form: [f64; 5],
}

impl Lin {
    /// Zero buffers for M modes.
    pub(super) fn new(modes: usize) -> Lin {
        let n = StateLayout::reduced(modes).dim();
        Lin { lj: LoadJacobian::new(modes), p: 0.0, rdd: 0.0, drdd: vec![0.0; n], gn: [0.0; MAX_MODES], gt: [0.0; MAX_MODES], drdd_pb: 0.0, gas_row: [0.0; 3], bdot: None, form: [0.0; 5] }
    }
}

impl BoundaryLayerSystem {
    /// The Jacobian's sparsity (see the module doc).
    pub fn jacobian_pattern(&self) -> JacobianPattern {
        let band = self.eq.band();
        // through ḃ of the modes M0 sees, R̈ reaches one band further (KM with a field)
        JacobianPattern { modes: self.modes.len(), band, radial: if self.bdot_radial { 2 * band } else { band } }
    }

    fn lin(&self, t: f64, y: &[f64], rdd: Option<f64>) -> Lin {
        let mut l = Lin::new(self.modes.len());
        self.lin_into(t, y, rdd, &mut l);
        l
    }

    /// The linearisation at (t, y) into `l`'s buffers (no allocation once `l` has been used,
    /// but with ḃ in R̈: Keller–Miksis with a field); `rdd`: R̈ prescribed.
    pub(super) fn lin_into(&self, t: f64, y: &[f64], rdd: Option<f64>, l: &mut Lin) {
        let m = self.modes.len();
        // the load columns (no gas slot: p_b enters R̈ alone, through `drdd_pb`)
        let (n, lay) = (StateLayout::reduced(m).dim(), self.layout());
        l.gas_row = self.gas.map_or([0.0; 3], |g| g.rate_partials(y[0], y[1], y[g.index]).1);
        let dpb_rate = self.gas.map(|_| l.gas_row[2]);
        l.drdd_pb = 0.0;
        self.eq.load_jacobian(t, y, &mut l.lj);
        let p = self.eq.loads(t, y, &mut l.gn[..m], &mut l.gt[..m]);
        l.p = p;
        if self.bdot_loads {
            let b = l.bdot.get_or_insert_with(|| vec![[0.0; 5]; m]);
            self.apply_bdot_loads(t, y, &mut l.gn[..m], &mut l.gt[..m], b);
        } else {
            l.bdot = None;
        }
        let prescribed = rdd.is_some();
        match rdd {
            Some(v) => {
                l.rdd = v;
                l.drdd.fill(0.0);
                l.form = [0.0; 5];
            }
            None if self.bdot_radial => {
                // ḃ and its rows first (they do not depend on R̈), then R̈ with them
                l.rdd = 0.0;
                l.drdd.fill(0.0);
                let mut dy = vec![0.0; n];
                self.mode_rates(y[0], y[1], 0.0, &l.gn[..m], &l.gt[..m], y, &mut dy);
                let bd: Vec<f64> = (0..m).map(|j| dy[lay.b(j)]).collect();
                let (mut dbd, mut scratch) = (vec![0.0; m * n], vec![0.0; n]);
                for j in 0..m {
                    self.mode_rows(y, l, j, &mut scratch, &mut dbd[j * n..(j + 1) * n]);
                }
                let mut g = vec![0.0; n];
                let d = self.eq.acceleration_gradient_with(t, y, p, &l.lj.pressure, Some((&bd, &dbd)), &mut g);
                l.drdd = g;
                l.form = [0.0; 5];
                l.rdd = self.eq.acceleration_with(t, y, p, &bd);
                // ∂R̈/∂p_b: through P (∂P/∂p_b = 1) and, for Keller–Miksis, the rate's ṗ_b
                l.drdd_pb = dpb_rate.map_or(0.0, |r| d[2] + d[3] * r);
                return;
            }
            None => {
                l.form = self.eq.acceleration_gradient_at(t, y, p, &l.lj.pressure, &mut l.drdd);
                l.rdd = self.eq.acceleration_at(t, y, p);
            }
        }
        if let (false, Some(r)) = (prescribed, dpb_rate) {
            // ∂R̈/∂p_b from the form's partials (as above)
            l.drdd_pb = l.form[2] + l.form[3] * r;
        }
        if self.eq.has_second_order() && !prescribed {
            self.second_pass(t, y, p, l);
        }
    }

    /// With second-pass terms (issue 12): the first-order ä and their rows from `l` (the
    /// ordinary terms'), the second-pass loads and derivatives added, R̈ and its gradient again
    /// from the completed P — so that [`mode_rows`](Self::mode_rows) differentiates the
    /// two-pass rhs exactly.
    fn second_pass(&self, t: f64, y: &[f64], p: f64, l: &mut Lin) {
        let (m, n) = (self.modes.len(), y.len());
        let mut dy = vec![0.0; n];
        self.mode_rates(y[0], y[1], l.rdd, &l.gn[..m], &l.gt[..m], y, &mut dy);
        let lay = self.layout();
        let add: Vec<f64> = (0..m).map(|j| dy[lay.adot(j)]).collect();
        let bd: Vec<f64> = (0..m).map(|j| dy[lay.b(j)]).collect();
        let (mut dadd, mut dbd) = (vec![0.0; m * n], vec![0.0; m * n]);
        for j in 0..m {
            let (ra, rb) = (&mut dadd[j * n..(j + 1) * n], &mut dbd[j * n..(j + 1) * n]);
            self.mode_rows(y, l, j, ra, rb);
        }
        // the material-frame terms' loads and Jacobian (the frame mapping's L(z), J(z))
        let (mut mgn, mut mgt, mut mj) = (vec![0.0; m], vec![0.0; m], LoadJacobian::new(m));
        let pm = self.eq.material_loads(t, y, &mut mgn, &mut mgt);
        self.eq.material_jacobian(t, y, &mut mj);
        let material = MaterialLoads { pressure: pm, gn: &mgn, gt: &mgt };
        let first = FirstOrder { rdd: l.rdd, add: &add, bd: &bd, material };
        let mut lj = l.lj.clone();
        self.eq.add_second_order_jacobian(t, y, &first, &FirstOrderGradient { drdd: &l.drdd, dadd: &dadd, dbd: &dbd, material: &mj }, &mut lj);
        let mut loads = Loads { pressure: p, gn: &mut l.gn[..m], gt: &mut l.gt[..m] };
        self.eq.add_second_order(t, y, &first, &mut loads);
        let p = loads.pressure;
        // ḃ loads: ḃ solved again with the completed G_t (as the rhs), the rows below then
        // differentiate that solution by the implicit-function rule
        if let Some(b) = l.bdot.as_mut() {
            self.resolve_bdot(y, &mut l.gn[..m], &mut l.gt[..m], b);
        }
        l.lj = lj;
        l.p = p;
        l.form = self.eq.acceleration_gradient_at(t, y, p, &l.lj.pressure, &mut l.drdd);
        l.rdd = self.eq.acceleration_at(t, y, p);
    }

    /// Rows of (ä, ḃ) of mode index m as gradients over y (length n): `out_a`, `out_b`.
    /// Over the load columns (the gas slot's column: [`RowForm::through_rdd`]).
    fn mode_rows(&self, y: &[f64], l: &Lin, m: usize, out_a: &mut [f64], out_b: &mut [f64]) {
        self.mode_rows_in(y, l, m, 0..l.drdd.len(), out_a, out_b)
    }

    /// The linear form of mode m's (ä, ḃ) rows over the gradients they combine (the partials
    /// of docs/model.md's mode equations at (t, y)): what [`mode_rows_in`](Self::mode_rows_in)
    /// writes out column by column and [`jacobian_product_into`](Self::jacobian_product_into)
    /// applies to a direction.
    pub(super) fn row_form(&self, y: &[f64], l: &Lin, m: usize) -> RowForm {
        let p = &self.eq.params;
        let mc = &self.modes[m];
        let (r, rd) = (y[0], y[1]);
        let lay = self.layout();
        let (ia, iad, ib) = (lay.a(m), lay.adot(m), lay.b(m));
        let (a, ad, b) = (y[ia], y[iad], y[ib]);
        let (gn, gt) = (l.gn[m], l.gt[m]);
        let src = wall_source(mc.k, p.eta, r, rd, a, ad, gt);
        let w = mc.wall_linear(r, src, &wall_source_partials(mc.k, p.eta, r, rd, a, gt));
        let (da, db) = mode_partials(mc.k, p.rho, p.eta, r, rd, l.rdd, a, ad, b, gn, &w);
        // ḃ loads (cn, ct, cn_r, ct_r, ḃ): at fixed ḃ they add ḃ·(cn_r, ct_r) to the R column
        let c = l.bdot.as_ref().map(|v| v[m]);
        let (cn_r_b, ct_r_b) = c.map_or((0.0, 0.0), |c| (c[2] * c[4], c[3] * c[4]));
        RowForm { da, db, c, cn_r_b, ct_r_b, idx: [ia, iad, ib] }
    }

    /// [`mode_rows`](Self::mode_rows) in the columns `cols` only (the rest of `out_a`, `out_b`
    /// untouched): either all columns from 0, or a range of shape columns (≥ 2) holding mode m's.
    fn mode_rows_in(&self, y: &[f64], l: &Lin, m: usize, cols: std::ops::Range<usize>, out_a: &mut [f64], out_b: &mut [f64]) {
        use var::*;
        let RowForm { da, db, c, cn_r_b, ct_r_b, idx: [ia, iad, ib] } = self.row_form(y, l, m);
        let (gn_row, gt_row) = (l.lj.gn_row(m), l.lj.gt_row(m));
        debug_assert!(cols.start == 0 || (cols.start >= StateLayout::RADIAL && cols.contains(&ia) && cols.contains(&ib)));
        for (out, d) in [(&mut *out_a, &da), (&mut *out_b, &db)] {
            for j in cols.clone() {
                out[j] = d[RDD] * l.drdd[j] + d[GN] * gn_row[j] + d[GT] * gt_row[j];
            }
            if cols.start == 0 {
                out[0] += d[R] + d[GN] * cn_r_b + d[GT] * ct_r_b;
                out[1] += d[RD];
            }
            out[ia] += d[A];
            out[iad] += d[AD];
            out[ib] += d[B];
        }
        // and through ḃ itself: ḃ = ḃ_std(…, G_n0 + cn ḃ, G_t0 + ct ḃ) is solved exactly, so
        // dḃ = (partial row)/(1 − ∂ḃ_std/∂G_n cn − ∂ḃ_std/∂G_t ct), and ä gains (∂ä/∂G·c) dḃ
        if let Some(c) = c {
            let den = 1.0 - db[GN] * c[0] - db[GT] * c[1];
            let via = da[GN] * c[0] + da[GT] * c[1];
            for j in cols {
                out_b[j] /= den;
                out_a[j] += via * out_b[j];
            }
        }
    }

    /// J·S for p directions at once without forming J (the sensitivity equations' product,
    /// [`crate::integrate::sensitivity`]): `s` and `out` hold p blocks of length n. Each row of
    /// [`jacobian_into`](Self::jacobian_into) is a combination of a few gradients (R̈'s, mode
    /// m's G_n and G_t) plus single columns ([`RowForm`]), so (row·S) is that combination of
    /// the gradients' products with S: O(M·n) per direction instead of O(n²), the same
    /// numbers as the dense product up to the order of the additions.
    pub fn jacobian_product_into(&self, t: f64, y: &[f64], s: &[f64], out: &mut [f64]) {
        let l = self.lin(t, y, None);
        let forms: Vec<RowForm> = (0..self.modes.len()).map(|m| self.row_form(y, &l, m)).collect();
        self.apply_product(&l, &forms, s, &[], out);
    }

    /// The exact Jacobian ∂f/∂y at (t, y), row-major `jac[i * n + j]` (n = 2 + 3M).
    pub fn jacobian_into(&self, t: f64, y: &[f64], jac: &mut [f64]) {
        let n = y.len();
        let l = self.lin(t, y, None);
        jac[..n * n].fill(0.0);
        jac[1] = 1.0;
        jac[n..n + l.drdd.len()].copy_from_slice(&l.drdd);
        let lay = self.layout();
        for m in 0..self.modes.len() {
            // a' = ȧ; the ä and ḃ rows (adjacent) from mode_rows
            jac[lay.a(m) * n + lay.adot(m)] = 1.0;
            let (ra, rest) = jac[lay.adot(m) * n..(lay.b(m) + 1) * n].split_at_mut(n);
            self.mode_rows(y, &l, m, ra, rest);
        }
        // the gas slot: its column (R̈'s, and the mode rows' through R̈) and ṗ_b's row
        if let Some(g) = &self.gas {
            let (i, d) = (g.index, l.gas_row);
            jac[n + i] = l.drdd_pb;
            for m in 0..self.modes.len() {
                let (va, vb) = self.row_form(y, &l, m).through_rdd(l.drdd_pb);
                jac[lay.adot(m) * n + i] = va;
                jac[lay.b(m) * n + i] = vb;
            }
            jac[i * n] = d[0];
            jac[i * n + 1] = d[1];
            jac[i * n + i] = d[2];
        }
    }

    /// The linear mode system at prescribed (t, R, Ṙ, R̈): x' = A x + g with x = (a_k, ȧ_k, b_k)_k
    /// (dimension 3M, state order), nondimensional. For the Floquet and frequency analyses
    /// (FORMULATION §4.6): R(t) is prescribed, so M0's coupling to a_2, b_2 is not part of it.
    /// g holds the magnetic forcing ℋ2, ℋ¹2 (zero without a field). Exact: the equations are
    /// affine in x at fixed (R, Ṙ, R̈). Linear only: second-pass terms (the quadratic coupling,
    /// issue 12) are left out — they and their derivatives vanish at x = 0, about which Floquet
    /// and the stability analyses linearise.
    pub fn linear_modes(&self, t: f64, r: f64, rd: f64, rdd: f64) -> (DMatrix<f64>, DVector<f64>) {
        let n = StateLayout::x_dim(self.modes.len());
        let (mut a, mut g) = (DMatrix::zeros(n, n), DVector::zeros(n));
        self.linear_modes_into(t, r, rd, rdd, &mut a, &mut g);
        (a, g)
    }

    /// The diagonal 3 × 3 blocks of [`linear_modes`](Self::linear_modes)'s A: mode m's (a, ȧ, b)
    /// rows in its own columns, column-major in `out[m]` (the same operations as the dense
    /// assembly, entry for entry). Without a field (pattern band 0) they are all of A, and
    /// assembling them costs O(M) instead of O(M²) (issue 16: the Floquet monodromy's blocks).
    pub fn linear_mode_blocks_into(&self, t: f64, r: f64, rd: f64, rdd: f64, out: &mut [[f64; 9]]) {
        let (nm, lay) = (self.modes.len(), self.layout());
        let n = lay.dim();
        let mut y = [0.0; MAX_DIM];
        let y = &mut y[..n];
        y[lay.r()] = r;
        y[lay.rdot()] = rd;
        let l = self.lin(t, y, Some(rdd));
        let (mut ra, mut rb) = ([0.0; MAX_DIM], [0.0; MAX_DIM]);
        for (m, o) in out.iter_mut().enumerate().take(nm) {
            let (ia, iad, ib) = (lay.a(m), lay.adot(m), lay.b(m));
            self.mode_rows_in(y, &l, m, lay.amplitudes(m), &mut ra[..n], &mut rb[..n]);
            *o = [0.0, ra[ia], rb[ia], 1.0, ra[iad], rb[iad], 0.0, ra[ib], rb[ib]];
        }
    }

    /// [`linear_modes`](Self::linear_modes) into sized buffers (A: 3M × 3M, g: 3M).
    pub fn linear_modes_into(&self, t: f64, r: f64, rd: f64, rdd: f64, a: &mut DMatrix<f64>, g: &mut DVector<f64>) {
        let lay = self.layout();
        let n = lay.dim();
        // stack buffers (no allocation per call: Floquet assembles A(t) twice per Magnus step)
        let mut y = [0.0; MAX_DIM];
        let y = &mut y[..n];
        y[lay.r()] = r;
        y[lay.rdot()] = rd;
        let l = self.lin(t, y, Some(rdd));
        let mut dy = [0.0; MAX_DIM];
        self.mode_rates(r, rd, rdd, &l.gn[..self.modes.len()], &l.gt[..self.modes.len()], y, &mut dy[..n]);
        g.copy_from_slice(&dy[lay.shape()]);
        a.as_mut_slice().fill(0.0);
        let (mut ra, mut rb) = ([0.0; MAX_DIM], [0.0; MAX_DIM]);
        // R̈ is prescribed, so mode k's rows see only the modes of the terms' band (module doc)
        let (mm, band) = (self.modes.len(), self.jacobian_pattern().band);
        for m in 0..mm {
            let (xa, xad, xb) = (StateLayout::x_a(m), StateLayout::x_adot(m), StateLayout::x_b(m));
            a[(xa, xad)] = 1.0;
            let cols = lay.blocks(m.saturating_sub(band)..(m + band + 1).min(mm));
            self.mode_rows_in(y, &l, m, cols.clone(), &mut ra[..n], &mut rb[..n]);
            for j in cols {
                a[(xad, StateLayout::x_of(j))] = ra[j];
                a[(xb, StateLayout::x_of(j))] = rb[j];
            }
        }
    }
}
