//! The discretised vorticity operator of one mode k (paper eqs 5.1–5.3, FORMULATION §4.2):
//!
//! ∂T/∂t = (ν/R²) ∂²T/∂y² + (Ṙ/R)(y − y⁻²) ∂T/∂y − [νk(k+1)/(R²y²) − 2Ṙ/(R y³)] T
//!
//! Diffusion and convection are second-order central differences on the non-uniform grid;
//! convection gets the paper's first-order upwind artificial diffusion |Ṙ|(y − y⁻²)Δy/(2R)
//! (eq 5.3, with Δy the local mean spacing). Row i (1 ≤ i ≤ n−2) reads
//! dT_i/dt = l_i T_{i−1} + d_i T_i + u_i T_{i+1}, with T_0 = T_w and T_{n−1} = 0.

use super::grid::Grid;
use nalgebra::ComplexField;

/// The three diagonals of the operator on the n−2 interior nodes. `lower[0]` multiplies the
/// wall value T_w (it is the coupling of the first interior node to the wall).
#[derive(Debug, Clone, Default)]
pub struct Rows {
    pub lower: Vec<f64>,
    pub diag: Vec<f64>,
    pub upper: Vec<f64>,
}

/// The time-dependent factors (ν/R², Ṙ/R, |Ṙ|/R) in which the operator rows are affine
/// ([`ModeOperator`]'s `affine`): one place for rows, their products and the shared rows.
#[derive(Debug, Clone, Copy)]
struct Weights {
    nu_r2: f64,
    rr: f64,
    ra: f64,
}

impl Weights {
    #[inline]
    fn at(r: f64, rdot: f64, nu: f64) -> Self {
        let rr = rdot / r;
        Weights { nu_r2: nu / (r * r), rr, ra: rr.abs() }
    }

    /// The row entry with affine coefficients `k`: ν/R² k₀ + Ṙ/R k₁ + |Ṙ|/R k₂.
    #[inline]
    fn of(self, k: &[f64; 3]) -> f64 {
        self.nu_r2 * k[0] + self.rr * k[1] + self.ra * k[2]
    }
}

/// Per-grid geometric factors that do not change in time (set once per grid and mode).
#[derive(Debug, Clone)]
pub struct ModeOperator {
    /// Mode number k.
    pub k: usize,
    /// Weights W_i = w_i y_i^{−k}: Ĩ_k = Σ W_i T_i (FORMULATION §4.2). W_0 = w_0.
    pub wi: Vec<f64>,
    /// Weights for J_k / R: Σ w_i (y_i^{−3} − 1) y_i^{−k} T_i (vanishes at the wall).
    pub wj: Vec<f64>,
    // finite-difference stencils on interior nodes
    d2: Vec<[f64; 3]>,
    d1: Vec<[f64; 3]>,
    /// Local mean spacing (h− + h+)/2 of the artificial diffusion.
    dy: Vec<f64>,
    /// y − y⁻², 1/y², 1/y³ at interior nodes.
    conv: Vec<f64>,
    inv_y2: Vec<f64>,
    inv_y3: Vec<f64>,
    /// The rows are affine in (ν/R², Ṙ/R, |Ṙ|/R) (y − y⁻² ≥ 0 on the grid, so |c| = |Ṙ/R|(y − y⁻²)):
    /// per interior node, the coefficients of the three for (lower, diag, upper), so that
    /// [`rows`](Self::rows) is 9 products per node instead of re-assembling the stencils.
    affine: Vec<[[f64; 3]; 3]>,
    /// The diagonal's coefficients without the mode's reaction term νk(k+1)/(R²y²) (the same for
    /// every mode; [`shared_rows`](Self::shared_rows)).
    diag0: Vec<[f64; 3]>,
}

/// The rows of [`ModeOperator::rows`] at one (R, Ṙ, ν) without the mode's own term
/// −νk(k+1)/(R²y²) of the diagonal: the same for every mode, so the right-hand side builds them
/// once and each mode adds its term ([`ModeOperator::apply_shared`]).
#[derive(Debug, Clone, Default)]
pub struct SharedRows {
    pub lower: Vec<f64>,
    pub diag: Vec<f64>,
    pub upper: Vec<f64>,
    /// ν/R²
    pub nu_r2: f64,
}

impl ModeOperator {
    pub fn new(grid: &Grid, k: usize) -> Self {
        let n = grid.len();
        let y = &grid.y;
        let wi: Vec<f64> = (0..n).map(|i| grid.w[i] * y[i].powi(-(k as i32))).collect();
        let wj: Vec<f64> = (0..n).map(|i| wi[i] * (y[i].powi(-3) - 1.0)).collect();
        let mut d2 = Vec::with_capacity(n - 2);
        let mut d1 = Vec::with_capacity(n - 2);
        let mut dy = Vec::with_capacity(n - 2);
        let mut conv = Vec::with_capacity(n - 2);
        let mut inv_y2 = Vec::with_capacity(n - 2);
        let mut inv_y3 = Vec::with_capacity(n - 2);
        for i in 1..n - 1 {
            let hm = y[i] - y[i - 1];
            let hp = y[i + 1] - y[i];
            let s = hm + hp;
            d2.push([2.0 / (hm * s), -2.0 / (hm * hp), 2.0 / (hp * s)]);
            d1.push([-hp / (hm * s), (hp - hm) / (hm * hp), hm / (hp * s)]);
            dy.push(0.5 * s);
            conv.push(y[i] - y[i].powi(-2));
            inv_y2.push(y[i].powi(-2));
            inv_y3.push(y[i].powi(-3));
        }
        let kk = (k * (k + 1)) as f64;
        let affine = (0..n - 2)
            .map(|i| {
                let ([a2, b2, c2], [a1, b1, c1]) = (d2[i], d1[i]);
                let art = 0.5 * conv[i] * dy[i];
                [
                    [a2, conv[i] * a1, art * a2],
                    [b2 - kk * inv_y2[i], conv[i] * b1 + 2.0 * inv_y3[i], art * b2],
                    [c2, conv[i] * c1, art * c2],
                ]
            })
            .collect();
        let diag0 = (0..n - 2)
            .map(|i| {
                let ([_, b2, _], [_, b1, _]) = (d2[i], d1[i]);
                [b2, conv[i] * b1 + 2.0 * inv_y3[i], 0.5 * conv[i] * dy[i] * b2]
            })
            .collect();
        Self { k, wi, wj, d2, d1, dy, conv, inv_y2, inv_y3, affine, diag0 }
    }

    /// Number of interior unknowns n − 2.
    pub fn interior(&self) -> usize {
        self.d2.len()
    }

    /// Fills the operator rows at radius `r`, wall velocity `rdot`, kinematic viscosity `nu`.
    pub fn rows(&self, r: f64, rdot: f64, nu: f64, out: &mut Rows) {
        let m = self.interior();
        out.lower.resize(m, 0.0);
        out.diag.resize(m, 0.0);
        out.upper.resize(m, 0.0);
        let w = Weights::at(r, rdot, nu);
        let (lower, diag, upper) = (&mut out.lower[..m], &mut out.diag[..m], &mut out.upper[..m]);
        for (i, [l, d, u]) in self.affine.iter().enumerate() {
            lower[i] = w.of(l);
            diag[i] = w.of(d);
            upper[i] = w.of(u);
        }
    }

    /// out_i = l_i T_{i−1} + d_i T_i + u_i T_{i+1} over the interior nodes `t` (T_{−1} = T_w = `tw`,
    /// T_n−2 = 0) with the rows of [`rows`](Self::rows) at (r, rdot, nu), without storing them:
    /// the same products in the same order, in one branch-free pass.
    pub fn apply(&self, r: f64, rdot: f64, nu: f64, tw: f64, t: &[f64], out: &mut [f64]) {
        let m = self.interior();
        let (t, out) = (&t[..m], &mut out[..m]);
        let w = Weights::at(r, rdot, nu);
        let row = |a: &[[f64; 3]; 3], left: f64, mid: f64, right: f64| w.of(&a[0]) * left + w.of(&a[1]) * mid + w.of(&a[2]) * right;
        if m < 2 {
            if m == 1 {
                out[0] = row(&self.affine[0], tw, t[0], 0.0);
            }
            return;
        }
        out[0] = row(&self.affine[0], tw, t[0], t[1]);
        for ((o, w), a) in out[1..m - 1].iter_mut().zip(t.windows(3)).zip(&self.affine[1..m - 1]) {
            *o = row(a, w[0], w[1], w[2]);
        }
        out[m - 1] = row(&self.affine[m - 1], t[m - 2], t[m - 1], 0.0);
    }

    /// The rows shared by every mode at (r, rdot, nu) ([`SharedRows`]).
    pub fn shared_rows(&self, r: f64, rdot: f64, nu: f64, out: &mut SharedRows) {
        let m = self.interior();
        out.lower.resize(m, 0.0);
        out.diag.resize(m, 0.0);
        out.upper.resize(m, 0.0);
        let w = Weights::at(r, rdot, nu);
        out.nu_r2 = w.nu_r2;
        let it = out.lower.iter_mut().zip(out.diag.iter_mut()).zip(out.upper.iter_mut()).zip(&self.affine).zip(&self.diag0);
        for ((((l, d), u), [a, _, c]), d0) in it {
            *l = w.of(a);
            *d = w.of(d0);
            *u = w.of(c);
        }
    }

    /// [`apply`](Self::apply) from the [`SharedRows`] at (r, rdot, nu): row i is
    /// l_i T_{i−1} + (d_i − νk(k+1)/(R² y_i²)) T_i + u_i T_{i+1} (the same operator; the diagonal
    /// summed in another order, so equal to rounding). One pass the compiler vectorises.
    pub fn apply_shared(&self, rows: &SharedRows, tw: f64, t: &[f64], out: &mut [f64]) {
        self.apply_shared_body(rows, tw, t, out);
    }

    #[inline(always)]
    fn apply_shared_body(&self, rows: &SharedRows, tw: f64, t: &[f64], out: &mut [f64]) {
        let m = self.interior();
        let (t, out) = (&t[..m], &mut out[..m]);
        let kn = (self.k * (self.k + 1)) as f64 * rows.nu_r2;
        let (l, d, u, iy2) = (&rows.lower[..m], &rows.diag[..m], &rows.upper[..m], &self.inv_y2[..m]);
        let row = |i: usize, left: f64, right: f64| l[i] * left + (d[i] - kn * iy2[i]) * t[i] + u[i] * right;
        if m < 2 {
            if m == 1 {
                out[0] = row(0, tw, 0.0);
            }
            return;
        }
        out[0] = row(0, tw, t[1]);
        out[m - 1] = row(m - 1, t[m - 2], 0.0);
        let inner = out[1..m - 1].iter_mut().zip(&l[1..m - 1]).zip(&d[1..m - 1]).zip(&u[1..m - 1]).zip(&iy2[1..m - 1]);
        for (((((o, &l), &d), &u), &y2), ((&tl, &tc), &tr)) in inner.zip(t[..m - 2].iter().zip(&t[1..m - 1]).zip(&t[2..])) {
            *o = l * tl + (d - kn * y2) * tc + u * tr;
        }
    }

    /// ([`functionals`](Self::functionals)) summed in four interleaved partial sums (lanes the
    /// compiler vectorises; equal to rounding, not to the bit).
    pub fn functionals_lanes(&self, t: &[f64]) -> (f64, f64) {
        #[cfg(target_arch = "x86_64")]
        if crate::simd::avx(crate::simd::Kernel::VorticityFunctionals) {
            // SAFETY: the processor supports AVX (`simd::avx` checked); the loads and stores
            // inside are to [f64; 4] chunks and arrays.
            return unsafe { self.functionals_lanes_avx(t) };
        }
        self.functionals_lanes_body(t)
    }

    /// [`functionals_lanes_body`](Self::functionals_lanes_body) with the two 4-lane sums in two
    /// AVX registers, written out (the compiler's own vectorisation of the body split them into
    /// halves with a shuffle per product); the same lane-wise products and sums.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    fn functionals_lanes_avx(&self, t: &[f64]) -> (f64, f64) {
        use std::arch::x86_64::*;
        let n = t.len().min(self.wi.len() - 1);
        let (t, wi, wj) = (&t[..n], &self.wi[1..n + 1], &self.wj[1..n + 1]);
        let (mut si, mut sj) = (_mm256_setzero_pd(), _mm256_setzero_pd());
        for ((c, a), b) in t.as_chunks::<4>().0.iter().zip(wi.as_chunks::<4>().0).zip(wj.as_chunks::<4>().0) {
            // SAFETY: each pointer is to a [f64; 4] (unaligned loads).
            let (c, a, b) = unsafe { (_mm256_loadu_pd(c.as_ptr()), _mm256_loadu_pd(a.as_ptr()), _mm256_loadu_pd(b.as_ptr())) };
            si = _mm256_add_pd(si, _mm256_mul_pd(c, a));
            sj = _mm256_add_pd(sj, _mm256_mul_pd(c, b));
        }
        let (mut si4, mut sj4) = ([0.0; 4], [0.0; 4]);
        // SAFETY: stores into [f64; 4] arrays.
        unsafe {
            _mm256_storeu_pd(si4.as_mut_ptr(), si);
            _mm256_storeu_pd(sj4.as_mut_ptr(), sj);
        }
        let tail = n - n % 4;
        let (mut ri, mut rj) = ((si4[0] + si4[1]) + (si4[2] + si4[3]), (sj4[0] + sj4[1]) + (sj4[2] + sj4[3]));
        for q in tail..n {
            ri += t[q] * wi[q];
            rj += t[q] * wj[q];
        }
        (ri, rj)
    }

    #[inline(always)]
    fn functionals_lanes_body(&self, t: &[f64]) -> (f64, f64) {
        let n = t.len().min(self.wi.len() - 1);
        let (t, wi, wj) = (&t[..n], &self.wi[1..n + 1], &self.wj[1..n + 1]);
        use super::batch::{add, mul, V};
        let (mut si, mut sj): (V, V) = ([0.0; 4], [0.0; 4]);
        let chunks = t.chunks_exact(4).zip(wi.chunks_exact(4)).zip(wj.chunks_exact(4));
        for ((c, a), b) in chunks {
            let (c, a, b): (&V, &V, &V) = (c.try_into().unwrap_or(&[0.0; 4]), a.try_into().unwrap_or(&[0.0; 4]), b.try_into().unwrap_or(&[0.0; 4]));
            si = add(si, mul(*c, *a));
            sj = add(sj, mul(*c, *b));
        }
        let tail = n - n % 4;
        let (mut ri, mut rj) = ((si[0] + si[1]) + (si[2] + si[3]), (sj[0] + sj[1]) + (sj[2] + sj[3]));
        for q in tail..n {
            ri += t[q] * wi[q];
            rj += t[q] * wj[q];
        }
        (ri, rj)
    }

    /// The exact ∂/∂R and ∂/∂Ṙ of [`rows`](Self::rows) (for the structured Jacobian). |Ṙ| in the
    /// artificial diffusion has no derivative at Ṙ = 0; there the one-sided (Ṙ → 0⁺) one is used.
    pub fn rows_derivatives(&self, r: f64, rdot: f64, nu: f64, d_r: &mut Rows, d_rd: &mut Rows) {
        let m = self.interior();
        for o in [&mut *d_r, &mut *d_rd] {
            o.lower.resize(m, 0.0);
            o.diag.resize(m, 0.0);
            o.upper.resize(m, 0.0);
        }
        let kk = (self.k * (self.k + 1)) as f64;
        let rr = rdot / r;
        // (∂/∂R, ∂/∂Ṙ) of ν/R² and of Ṙ/R
        let nu_r2_d = [-2.0 * nu / (r * r * r), 0.0];
        let rr_d = [-rdot / (r * r), 1.0 / r];
        for i in 0..m {
            let c = rr * self.conv[i];
            let [a2, b2, c2] = self.d2[i];
            let [a1, b1, c1] = self.d1[i];
            for (v, out) in [&mut *d_r, &mut *d_rd].into_iter().enumerate() {
                let dc = rr_d[v] * self.conv[i];
                let dabs = if c > 0.0 {
                    dc
                } else if c < 0.0 {
                    -dc
                } else {
                    dc.abs()
                };
                let ddiff = nu_r2_d[v] + 0.5 * dabs * self.dy[i];
                let dreact = nu_r2_d[v] * kk * self.inv_y2[i] - 2.0 * rr_d[v] * self.inv_y3[i];
                out.lower[i] = ddiff * a2 + dc * a1;
                out.diag[i] = ddiff * b2 + dc * b1 - dreact;
                out.upper[i] = ddiff * c2 + dc * c1;
            }
        }
    }

    /// Ĩ_int = Σ_{i≥1} W_i T_i over the interior nodes `t` (T_{n−1} = 0 contributes nothing).
    pub fn i_interior(&self, t: &[f64]) -> f64 {
        t.iter().zip(&self.wi[1..]).map(|(t, w)| t * w).sum()
    }

    /// ∫_1^{Y_max} (y⁻³ − 1) y^{−k} T dy over the interior nodes (the wall term is zero), so
    /// that J_k = R · this (FORMULATION §4.2).
    pub fn j_over_r(&self, t: &[f64]) -> f64 {
        t.iter().zip(&self.wj[1..]).map(|(t, w)| t * w).sum()
    }

    /// ([`i_interior`](Self::i_interior), [`j_over_r`](Self::j_over_r)) in one pass over `t`:
    /// the same two sums in the same order (bit-identical), the two dependency chains side by
    /// side.
    pub fn functionals(&self, t: &[f64]) -> (f64, f64) {
        let (mut si, mut sj) = (-0.0, -0.0);
        for ((t, wi), wj) in t.iter().zip(&self.wi[1..]).zip(&self.wj[1..]) {
            si += t * wi;
            sj += t * wj;
        }
        (si, sj)
    }

    /// Trapezoid weight of the wall node, w_0 = h_0/2.
    pub fn w0(&self) -> f64 {
        self.wi[0]
    }
}

/// Solves the tridiagonal system `lower[i] x[i−1] + diag[i] x[i] + upper[i] x[i+1] = rhs[i]`
/// in place (Thomas algorithm; `lower[0]` and `upper[n−1]` are ignored). `scratch` has length n.
/// Generic over real and complex scalars (the dispersion relation uses complex shifts).
/// Returns `false` on a zero pivot.
pub fn thomas<T: ComplexField + Copy>(
    lower: &[T],
    diag: &[T],
    upper: &[T],
    rhs: &mut [T],
    scratch: &mut [T],
) -> bool {
    let n = rhs.len();
    if n == 0 {
        return true;
    }
    let mut beta = diag[0];
    if beta == T::zero() {
        return false;
    }
    rhs[0] /= beta;
    for i in 1..n {
        scratch[i] = upper[i - 1] / beta;
        beta = diag[i] - lower[i] * scratch[i];
        if beta == T::zero() {
            return false;
        }
        rhs[i] = (rhs[i] - lower[i] * rhs[i - 1]) / beta;
    }
    for i in (0..n - 1).rev() {
        let next = rhs[i + 1];
        rhs[i] -= scratch[i + 1] * next;
    }
    true
}

/// Backward-Euler solve of `(I − dt·L) x = rhs` for L's rows, together with `(I − dt·L) z = e_1`
/// in the same sweep (the two solutions Sherman–Morrison needs for the bordered first row).
/// On return `rhs` holds x and `z` holds z. Returns `false` on a zero pivot.
pub fn backward_euler_pair(rows: &Rows, dt: f64, rhs: &mut [f64], z: &mut [f64], scratch: &mut [f64]) -> bool {
    let n = rhs.len();
    if n == 0 {
        return true;
    }
    let mut beta = 1.0 - dt * rows.diag[0];
    if beta == 0.0 {
        return false;
    }
    let mut inv = 1.0 / beta;
    rhs[0] *= inv;
    z[0] = inv;
    for i in 1..n {
        let li = -dt * rows.lower[i];
        scratch[i] = -dt * rows.upper[i - 1] * inv;
        beta = 1.0 - dt * rows.diag[i] - li * scratch[i];
        if beta == 0.0 {
            return false;
        }
        inv = 1.0 / beta;
        rhs[i] = (rhs[i] - li * rhs[i - 1]) * inv;
        z[i] = -li * z[i - 1] * inv;
    }
    for i in (0..n - 1).rev() {
        rhs[i] -= scratch[i + 1] * rhs[i + 1];
        z[i] -= scratch[i + 1] * z[i + 1];
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fused pass gives the two functionals of the separate sums, to the bit.
    #[test]
    fn functionals_are_the_two_sums() {
        let grid = Grid::new(4.0, 41, 8.0).unwrap();
        for k in [2, 5, 16] {
            let op = ModeOperator::new(&grid, k);
            let t: Vec<f64> = (0..op.interior()).map(|i| (0.3 * i as f64).cos() * 1e-3).collect();
            let (i, j) = op.functionals(&t);
            assert_eq!((i.to_bits(), j.to_bits()), (op.i_interior(&t).to_bits(), op.j_over_r(&t).to_bits()), "k = {k}");
        }
    }

    /// The AVX kernel of the four-lane functionals gives the portable one's sums to the bit.
    #[test]
    fn lane_functionals_avx_matches_the_portable_body() {
        let grid = Grid::new(4.0, 43, 8.0).unwrap();
        for k in [2, 7, 16] {
            let op = ModeOperator::new(&grid, k);
            let t: Vec<f64> = (0..op.interior()).map(|i| (0.37 * i as f64).sin() * 1e-3).collect();
            let (i, j) = op.functionals_lanes_body(&t);
            let (a, b) = op.functionals_lanes(&t);
            assert_eq!((a.to_bits(), b.to_bits()), (i.to_bits(), j.to_bits()), "k = {k}");
        }
    }

    #[test]
    fn thomas_solves_a_random_diagonally_dominant_system() {
        let n = 7;
        let lower: Vec<f64> = (0..n).map(|i| 0.3 + 0.1 * i as f64).collect();
        let upper: Vec<f64> = (0..n).map(|i| -0.2 + 0.05 * i as f64).collect();
        let diag: Vec<f64> = (0..n).map(|i| 2.0 + 0.3 * i as f64).collect();
        let x: Vec<f64> = (0..n).map(|i| (i as f64).sin() + 1.0).collect();
        let mut rhs: Vec<f64> = (0..n)
            .map(|i| {
                let mut v = diag[i] * x[i];
                if i > 0 {
                    v += lower[i] * x[i - 1];
                }
                if i + 1 < n {
                    v += upper[i] * x[i + 1];
                }
                v
            })
            .collect();
        let mut s = vec![0.0; n];
        assert!(thomas(&lower, &diag, &upper, &mut rhs, &mut s));
        for i in 0..n {
            assert!((rhs[i] - x[i]).abs() < 1e-13, "{i}: {} vs {}", rhs[i], x[i]);
        }
    }

    #[test]
    fn operator_is_second_order_on_a_smooth_profile() {
        // Apply the operator (Ṙ ≠ 0, so convection and artificial diffusion act) to
        // T = exp(−(y−1)) and compare with the exact right-hand side; the artificial
        // diffusion is first order, so compare the rdot = 0 case for second order.
        let exact = |y: f64, nu: f64, r: f64, k: f64| {
            let t = (-(y - 1.0) * 3.0).exp();
            nu / (r * r) * 9.0 * t - nu * k * (k + 1.0) / (r * r * y * y) * t
        };
        let mut errs = vec![];
        for &n in &[41usize, 81] {
            let g = Grid::new(3.0, n, 5.0).unwrap();
            let op = ModeOperator::new(&g, 4);
            let mut rows = Rows::default();
            op.rows(1.3, 0.0, 0.7, &mut rows);
            let t: Vec<f64> = g.y.iter().map(|y| (-(y - 1.0) * 3.0).exp()).collect();
            let mut e: f64 = 0.0;
            for i in 1..n - 1 {
                let v = rows.lower[i - 1] * t[i - 1] + rows.diag[i - 1] * t[i] + rows.upper[i - 1] * t[i + 1];
                e = e.max((v - exact(g.y[i], 0.7, 1.3, 4.0)).abs());
            }
            errs.push(e);
        }
        let order = (errs[0] / errs[1]).log2();
        assert!(order > 1.8 && order < 2.3, "observed order {order}, errors {errs:?}");
    }
}
