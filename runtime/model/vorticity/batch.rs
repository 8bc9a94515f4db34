//! The batched kernels of the structured solve ([`super::structured`]): the M tridiagonal
//! systems σI − L_k of the vorticity blocks, solved side by side.
//!
//! Vectors are node-major (entry i of mode k at `i * M + k`), so that the M independent
//! recurrences of a Thomas sweep are the lanes of the inner loop, and *split*: real parts and
//! imaginary parts in separate arrays ([`Split`]), so that a complex product is four real
//! products over contiguous lanes (SIMD) instead of a shuffle per entry (issue 16, lever
//! "SIMD, split real/imaginary storage"). Per entry the operations and their order are those of
//! `num_complex` on interleaved values (a·b = (a.re b.re − a.im b.im, a.re b.im + a.im b.re)),
//! so the results are the interleaved loops' to the bit.
//!
//! The kernels are compiled for the build's baseline (x86-64: SSE2, two lanes per register);
//! an AVX build of them earned at most 1 % of the monolithic run and was removed (the SIMD policy,
//! docs/performance.md).

use super::nodes::{self, per_q};
use super::pool;
use super::tri::{self, TriRows};
use nalgebra::{Complex, ComplexField};
use std::rc::Rc;

/// A scalar of the structured solve, f64 or Complex<f64>.
pub trait Lane: ComplexField<RealField = f64> + Copy {
    /// Has an imaginary part.
    const CPLX: bool;
    fn parts(self) -> (f64, f64);
    fn from_parts(re: f64, im: f64) -> Self;
}

impl Lane for f64 {
    const CPLX: bool = false;
    #[inline(always)]
    fn parts(self) -> (f64, f64) {
        (self, 0.0)
    }
    #[inline(always)]
    fn from_parts(re: f64, _im: f64) -> Self {
        re
    }
}

impl Lane for Complex<f64> {
    const CPLX: bool = true;
    #[inline(always)]
    fn parts(self) -> (f64, f64) {
        (self.re, self.im)
    }
    #[inline(always)]
    fn from_parts(re: f64, im: f64) -> Self {
        Complex::new(re, im)
    }
}

/// Lanes per vector: four f64 (one AVX register, two SSE2 ones).
pub const L: usize = 4;
/// One vector of lanes: modes 4j … 4j + 3 of one node.
pub type V = [f64; L];

/// Lane-wise a·b (written out so the compiler emits one vector operation).
#[inline(always)]
pub fn mul(a: V, b: V) -> V {
    let mut r = [0.0; L];
    for q in 0..L {
        r[q] = a[q] * b[q];
    }
    r
}

#[inline(always)]
pub fn add(a: V, b: V) -> V {
    let mut r = [0.0; L];
    for q in 0..L {
        r[q] = a[q] + b[q];
    }
    r
}

#[inline(always)]
pub fn sub(a: V, b: V) -> V {
    let mut r = [0.0; L];
    for q in 0..L {
        r[q] = a[q] - b[q];
    }
    r
}

/// Vectors per node for M modes (the last one padded with zero lanes).
pub fn per_node(m: usize) -> usize {
    m.div_ceil(L)
}

/// A node-major vector stored split, in lanes: entry (i, k) at `[i·q + k/L][k % L]` with q =
/// [`per_node`]`(M)`; `re`, and `im` (empty for a real scalar). Padding lanes stay zero.
#[derive(Debug, Clone)]
pub struct Split {
    pub q: usize,
    pub re: Vec<V>,
    pub im: Vec<V>,
}

impl Split {
    /// Zeros for `nodes` nodes of `m` modes.
    pub fn zeros<T: Lane>(nodes: usize, m: usize) -> Self {
        let q = per_node(m);
        Split { q, re: vec![[0.0; L]; nodes * q], im: if T::CPLX { vec![[0.0; L]; nodes * q] } else { Vec::new() } }
    }

    #[inline(always)]
    pub fn get<T: Lane>(&self, i: usize, k: usize) -> T {
        let at = i * self.q + k / L;
        T::from_parts(self.re[at][k % L], if T::CPLX { self.im[at][k % L] } else { 0.0 })
    }

    #[inline(always)]
    pub fn set<T: Lane>(&mut self, i: usize, k: usize, v: T) {
        let at = i * self.q + k / L;
        let (re, im) = v.parts();
        self.re[at][k % L] = re;
        if T::CPLX {
            self.im[at][k % L] = im;
        }
    }
}

/// Thomas factors of the M tridiagonal matrices σI − L_k, node-major and split.
pub struct TriBatch {
    q: usize,
    /// −L_k's sub-diagonal (real; a real times complex product is 2 multiplications, not 4),
    /// shared with the Jacobian's [`TriRows`] (it does not depend on σ)
    lower: Rc<Vec<V>>,
    inv_beta: Split,
    gamma: Split,
}

impl Drop for TriBatch {
    /// The factor vectors kept for the next factorisation ([`pool`]).
    fn drop(&mut self) {
        for s in [&mut self.inv_beta, &mut self.gamma] {
            pool::give(std::mem::take(&mut s.re));
            pool::give(std::mem::take(&mut s.im));
        }
    }
}

impl TriBatch {
    /// The factors of σI − L_k from the transposed rows ([`super::tri`]); `None` on a zero pivot.
    pub fn new<T: Lane>(sigma: T, rows: &TriRows) -> Option<Self> {
        let q = rows.q;
        let [(ibr, ibi), (gr, gi)] = tri::factors(sigma, rows)?;
        Some(Self { q, lower: Rc::clone(&rows.neg_lower), inv_beta: Split { q, re: ibr, im: ibi }, gamma: Split { q, re: gr, im: gi } })
    }

    /// x ← (σI − L_k)⁻¹ x for every mode k at once (x node-major, split like the factors).
    pub fn solve(&self, x: &mut Split) {
        self.solve_body(x);
    }

    #[inline(always)]
    pub(super) fn solve_body(&self, x: &mut Split) {
        let q = self.q;
        if q == 0 {
            return;
        }
        let (ib, gm) = (&self.inv_beta, &self.gamma);
        if x.im.is_empty() {
            per_q!(q, Q => nodes::sweep_real::<Q>(&self.lower, &ib.re, &gm.re, &mut x.re),
                   _ => sweep_real(q, &self.lower, &ib.re, &gm.re, &mut x.re));
        } else {
            per_q!(q, Q => nodes::sweep_complex::<Q>(&self.lower, [&ib.re, &ib.im], [&gm.re, &gm.im], [&mut x.re, &mut x.im]),
                   _ => sweep_complex(q, &self.lower, [&ib.re, &ib.im], [&gm.re, &gm.im], [&mut x.re, &mut x.im]));
        }
    }
}

impl TriBatch {
    /// (σI − L_k)⁻¹ `src` for a real right-hand side (node-major, q vectors per node) as a new
    /// split vector: for complex factors the imaginary parts are pushed by the sweep (no zeroed
    /// buffer), and `src` is read by the forward sweep (no copy first).
    pub fn solve_real_rhs(&self, src: &[V]) -> Split {
        self.solve_real_rhs_body(src)
    }

    #[inline(always)]
    fn solve_real_rhs_body(&self, src: &[V]) -> Split {
        let (q, ib, gm) = (self.q, &self.inv_beta, &self.gamma);
        // every entry is written by the sweeps: spare vectors of dropped factorisations
        let n = src.len();
        let mut x = Split { q, re: pool::take(n), im: if ib.im.is_empty() { Vec::new() } else { pool::take(n) } };
        if ib.im.is_empty() {
            per_q!(q, Q => nodes::sweep_real_from::<Q>(&self.lower, &ib.re, &gm.re, src, &mut x.re), _ => {
                x.re.copy_from_slice(src);
                self.solve_body(&mut x);
            });
        } else {
            per_q!(q, Q => nodes::sweep_complex_real_rhs::<Q>(&self.lower, [&ib.re, &ib.im], [&gm.re, &gm.im], src, &mut x.re, &mut x.im), _ => {
                x.re.copy_from_slice(src);
                x.im.fill([0.0; L]);
                self.solve_body(&mut x);
            });
        }
        x
    }
}

#[inline(always)]
pub(super) fn sweep_real(q: usize, lower: &[V], ib: &[V], gamma: &[V], x: &mut [V]) {
    let nodes = x.len() / q;
    if nodes == 0 {
        return;
    }
    for (v, b) in x[..q].iter_mut().zip(&ib[..q]) {
        *v = mul(*v, *b);
    }
    for i in 1..nodes {
        let (prev, cur) = x[(i - 1) * q..(i + 1) * q].split_at_mut(q);
        let (l, b) = (&lower[i * q..(i + 1) * q], &ib[i * q..(i + 1) * q]);
        for (((c, &p), &l), &b) in cur.iter_mut().zip(prev.iter()).zip(l).zip(b) {
            *c = mul(sub(*c, mul(p, l)), b);
        }
    }
    for i in (0..nodes - 1).rev() {
        let (cur, next) = x[i * q..(i + 2) * q].split_at_mut(q);
        let g = &gamma[(i + 1) * q..(i + 2) * q];
        for ((c, &nx), &g) in cur.iter_mut().zip(next.iter()).zip(g) {
            *c = sub(*c, mul(g, nx));
        }
    }
}

/// (a.re, a.im) · (b.re, b.im) lane-wise, as `num_complex`: (a.re b.re − a.im b.im, a.re b.im + a.im b.re).
#[inline(always)]
pub fn cmul(ar: V, ai: V, br: V, bi: V) -> (V, V) {
    (sub(mul(ar, br), mul(ai, bi)), add(mul(ar, bi), mul(ai, br)))
}

#[inline(always)]
pub(super) fn sweep_complex(q: usize, lower: &[V], ib: [&[V]; 2], gamma: [&[V]; 2], x: [&mut [V]; 2]) {
    let [xr, xi] = x;
    let nodes = xr.len() / q;
    if nodes == 0 {
        return;
    }
    for (((vr, vi), &br), &bi) in xr[..q].iter_mut().zip(xi[..q].iter_mut()).zip(&ib[0][..q]).zip(&ib[1][..q]) {
        (*vr, *vi) = cmul(*vr, *vi, br, bi);
    }
    for i in 1..nodes {
        let (pr, cr) = xr[(i - 1) * q..(i + 1) * q].split_at_mut(q);
        let (pi, ci) = xi[(i - 1) * q..(i + 1) * q].split_at_mut(q);
        let r = i * q..(i + 1) * q;
        let (l, br, bi) = (&lower[r.clone()], &ib[0][r.clone()], &ib[1][r]);
        let it = cr.iter_mut().zip(ci.iter_mut()).zip(pr.iter()).zip(pi.iter()).zip(l).zip(br).zip(bi);
        for ((((((cr, ci), &pr), &pi), &l), &br), &bi) in it {
            // (cur − prev·l) · (1/β)
            let (a, b) = (sub(*cr, mul(pr, l)), sub(*ci, mul(pi, l)));
            (*cr, *ci) = cmul(a, b, br, bi);
        }
    }
    for i in (0..nodes - 1).rev() {
        let (cr, nr) = xr[i * q..(i + 2) * q].split_at_mut(q);
        let (ci, ni) = xi[i * q..(i + 2) * q].split_at_mut(q);
        let r = (i + 1) * q..(i + 2) * q;
        let (gr, gi) = (&gamma[0][r.clone()], &gamma[1][r]);
        for (((((cr, ci), &nr), &ni), &gr), &gi) in cr.iter_mut().zip(ci.iter_mut()).zip(nr.iter()).zip(ni.iter()).zip(gr).zip(gi) {
            // cur −= γ · next
            let (pr, pi) = cmul(gr, gi, nr, ni);
            *cr = sub(*cr, pr);
            *ci = sub(*ci, pi);
        }
    }
}

/// Per mode, (Σ_i v(i, k) w0(i, k), Σ_i v(i, k) w1(i, k)) summed in the order of i (real weights
/// `w`, node-major in lanes like `v`): `acc` = [kind 0 re, kind 1 re, kind 0 im, kind 1 im], each
/// q vectors (the imaginary ones untouched for a real `v`).
#[inline(always)]
pub fn dots2(v: &Split, w: [&[V]; 2], acc: [&mut [V]; 4]) {
    per_q!(v.q, Q => {
        let [a0r, a1r, a0i, a1i] = acc;
        let [r0, r1] = nodes::dots2::<Q>(&v.re, w[0], w[1]);
        a0r.copy_from_slice(&r0);
        a1r.copy_from_slice(&r1);
        if v.im.is_empty() {
            a0i.fill([0.0; L]);
            a1i.fill([0.0; L]);
        } else {
            let [i0, i1] = nodes::dots2::<Q>(&v.im, w[0], w[1]);
            a0i.copy_from_slice(&i0);
            a1i.copy_from_slice(&i1);
        }
    }, _ => dots2_any(v, w, acc))
}

/// [`dots2`] for any q (the kernels of [`nodes`] are for q ≤ 8).
#[inline(always)]
pub fn dots2_any(v: &Split, w: [&[V]; 2], acc: [&mut [V]; 4]) {
    let q = v.q;
    let [a0r, a1r, a0i, a1i] = acc;
    for a in [&mut *a0r, &mut *a1r, &mut *a0i, &mut *a1i] {
        a.fill([0.0; L]);
    }
    if q == 0 {
        return;
    }
    let pairs = v.re.chunks_exact(q).zip(w[0].chunks_exact(q)).zip(w[1].chunks_exact(q));
    for ((vi, wa), wb) in pairs {
        for ((((a0, a1), &x), &c0), &c1) in a0r.iter_mut().zip(a1r.iter_mut()).zip(vi).zip(wa).zip(wb) {
            *a0 = add(*a0, mul(x, c0));
            *a1 = add(*a1, mul(x, c1));
        }
    }
    if v.im.is_empty() {
        return;
    }
    let pairs = v.im.chunks_exact(q).zip(w[0].chunks_exact(q)).zip(w[1].chunks_exact(q));
    for ((vi, wa), wb) in pairs {
        for ((((a0, a1), &x), &c0), &c1) in a0i.iter_mut().zip(a1i.iter_mut()).zip(vi).zip(wa).zip(wb) {
            *a0 = add(*a0, mul(x, c0));
            *a1 = add(*a1, mul(x, c1));
        }
    }
}
