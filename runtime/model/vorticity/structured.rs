//! Structured linear algebra for implicit integration of the monolithic system: solves
//! (σI − J) x = b, σ real or complex, in O(M·n) work instead of a dense O((M n)³) LU.
//!
//! Structure of J (see [`super::monolithic`]): the ODE part z = [R, Ṙ, (a, ȧ, b)_k] sees the
//! vorticity only through the 2M functionals p = P T (Ĩ_int,k and ∫(y⁻³−1)y^{−k}T dy); the T rows
//! of mode k are tridiagonal (L_k) plus the wall term l_0 T_w,k on the first row, where
//! T_w,k(z, p) is the algebraic wall value, plus the dependence of L_k on R and Ṙ. Introducing
//! π = P x_T as unknowns, x_T,k = D_k⁻¹(b_T,k + c_k s_k + r_R,k x_R + r_Ṙ,k x_Ṙ) with D_k = σI − L_k,
//! c_k = l_0 e_1 and s_k = δT_w,k; what is left is a dense system of size (2 + 3M) + 2M in (x_z, π).
//!
//! The pieces of J come from the model itself, exactly: the derivatives of the reduced function
//! (f_z, T_w)(z, p) in z and p from the terms' gradients and the closure's partials
//! ([`super::equations::reduced_jacobian`]), L_k from the operator and its R, Ṙ derivatives from
//! [`super::operator::ModeOperator::rows_derivatives`]. Nothing is differenced.

use super::batch::{add, cmul, dots2, mul, per_node, Lane, Split, TriBatch, L, V};
use super::copies::{copy_in, copy_in_any, copy_out, copy_out_any};
use super::dense::DenseLu;
use super::dense_rows;
use super::equations::reduced_jacobian;
use super::monolithic::Monolithic;
use super::nodes::{self, per_q};
use super::operator::Rows;
use super::tri::TriRows;
use crate::integrate::linear::{self, Factorization};
use crate::integrate::OdeSystem;
use crate::model::layout::StateLayout;
use nalgebra::{Complex, DMatrix};
use std::rc::Rc;

/// J at one (t, y), in structured form.
pub struct StructuredJacobian {
    m: usize,     // number of modes M
    nz: usize,    // 2 + 3M
    ni: usize,    // interior nodes per mode
    nb: usize,    // block length 3 + ni
    /// the monolithic state's layout (`nb`, `ni` and `m` are its block, nodes and modes)
    layout: StateLayout,
    /// ∂(f_z, T_w)/∂z: (nz + M) × nz
    gz: DMatrix<f64>,
    /// ∂(f_z, T_w)/∂p: (nz + M) × 2M
    gp: DMatrix<f64>,
    /// the T rows of J (L_k) node-major in lanes, for the Thomas factors of every factorisation
    tri_rows: TriRows,
    /// ∂(T rows)/∂R and ∂/∂Ṙ at fixed T, T_w, node-major in lanes (module `batch`)
    r_r: Vec<V>,
    r_rd: Vec<V>,
    /// c_k = l_0 e_1 node-major in lanes (the wall term's column of the T rows)
    c: Vec<V>,
    /// P rows per mode: weights of Ĩ_int and of ∫(y⁻³−1)y^{−k}T dy on the interior nodes
    /// node-major in lanes, as [`TriBatch`]
    pw: [Vec<V>; 2],
    /// [gz | gp] row-major, (nz + M) × (nz + 2M) (the rows of the (z, π) system, contiguous)
    g: Vec<f64>,
}

/// [gz | gp] row-major.
fn row_major(gz: &DMatrix<f64>, gp: &DMatrix<f64>) -> Vec<f64> {
    let mut g = Vec::with_capacity(gz.nrows() * (gz.ncols() + gp.ncols()));
    for i in 0..gz.nrows() {
        g.extend(gz.row(i).iter().chain(gp.row(i).iter()));
    }
    g
}

/// The factorisation of σI − J (shares the Jacobian it was built from).
pub struct StructuredLu<T: Lane> {
    jac: Rc<StructuredJacobian>,
    tri: TriBatch,
    /// D_k⁻¹ c_k, D_k⁻¹ r_R,k, D_k⁻¹ r_Ṙ,k, node-major and split like [`TriBatch`]
    u: [Split; 3],
    small: DenseLu<T>,
    /// The T_w,k rows of J in (z, π), row-major M × (nz + 2M): ∂T_w,k/∂z then ∂T_w,k/∂p
    /// (contiguous copies of the gz / gp rows, for s_k = δT_w,k in [`StructuredLu::solve`]).
    tw_rows: Vec<f64>,
    /// Scratch of [`StructuredLu::solve`] (no allocation per solve).
    scratch: std::cell::RefCell<Scratch>,
}

struct Scratch {
    /// node-major T part
    xt: Split,
    /// right-hand side and solution of the small dense system, split (`rhs_i` empty for a real T)
    rhs_r: Vec<f64>,
    rhs_i: Vec<f64>,
    /// the 2M functionals P·xt in lanes: real parts of the two kinds, then imaginary parts
    d: Vec<V>,
    /// per mode s_k = δT_w,k in lanes: real parts, then imaginary parts
    s: Vec<V>,
}

thread_local! {
    /// Scratch of dropped factorisations, for the next ones (Radau5 refactors σI − J 561 times
    /// in the monolithic run: no zeroed node-major buffer per factorisation).
    static SPARE: std::cell::RefCell<Vec<Scratch>> = const { std::cell::RefCell::new(Vec::new()) };
}

impl Scratch {
    /// A spare scratch of the right shape (every entry a solve reads is written by that solve
    /// first: `xt` by the copy in, the lanes past M stay zero), else a zeroed one.
    fn take<T: Lane>(ni: usize, m: usize, ns: usize) -> Self {
        let q = per_node(m);
        let fits = |s: &Scratch| s.xt.q == q && s.xt.re.len() == ni * q && s.xt.im.len() == if T::CPLX { ni * q } else { 0 } && s.rhs_r.len() == ns && s.rhs_i.len() == if T::CPLX { ns } else { 0 };
        let spare = SPARE.with(|p| {
            let mut p = p.borrow_mut();
            let at = p.iter().position(fits)?;
            Some(p.swap_remove(at))
        });
        spare.unwrap_or_else(|| Scratch { xt: Split::zeros::<T>(ni, m), rhs_r: vec![0.0; ns], rhs_i: vec![0.0; if T::CPLX { ns } else { 0 }], d: vec![[0.0; L]; 4 * q], s: vec![[0.0; L]; 2 * q] })
    }
}

impl<T: Lane> Drop for StructuredLu<T> {
    fn drop(&mut self) {
        for u in &mut self.u {
            super::pool::give(std::mem::take(&mut u.re));
            super::pool::give(std::mem::take(&mut u.im));
        }
        let s = std::mem::replace(self.scratch.get_mut(), Scratch { xt: Split { q: 0, re: Vec::new(), im: Vec::new() }, rhs_r: Vec::new(), rhs_i: Vec::new(), d: Vec::new(), s: Vec::new() });
        // at most a few kept (a real and a complex factorisation alive at once, one of each spare)
        let _ = SPARE.try_with(|p| {
            let mut p = p.borrow_mut();
            if p.len() < 4 {
                p.push(s);
            }
        });
    }
}

impl StructuredJacobian {
    /// Builds J of `sys` at (t, y) by structured differencing.
    pub fn new(sys: &Monolithic<'_>, t: f64, y: &[f64]) -> Rc<Self> {
        Rc::new(Self::build(sys, t, y))
    }

    /// J restricted to the shape variables (a, ȧ, b, T)_k with R, Ṙ held on a prescribed
    /// orbit: the R, Ṙ rows and columns are zeroed, so (σI − J)x = b with b_R = b_Ṙ = 0 gives
    /// x_R = x_Ṙ = 0 and the shape part of x solves the shape block of σI − J (the linear system
    /// of the full-model Floquet analysis, [`crate::analysis::floquet_full`]).
    pub fn shape_only(sys: &Monolithic<'_>, t: f64, y: &[f64]) -> Rc<Self> {
        let mut j = Self::build(sys, t, y);
        for c in 0..j.gz.ncols() {
            j.gz[(0, c)] = 0.0;
            j.gz[(1, c)] = 0.0;
        }
        for r in 0..j.gz.nrows() {
            j.gz[(r, 0)] = 0.0;
            j.gz[(r, 1)] = 0.0;
        }
        for c in 0..j.gp.ncols() {
            j.gp[(0, c)] = 0.0;
            j.gp[(1, c)] = 0.0;
        }
        j.r_r.fill([0.0; L]);
        j.r_rd.fill([0.0; L]);
        j.g = row_major(&j.gz, &j.gp);
        Rc::new(j)
    }

    fn build(sys: &Monolithic<'_>, t: f64, y: &[f64]) -> Self {
        let ops = sys.operators();
        let layout = sys.layout();
        let (m, nz) = (layout.modes(), layout.boundary_layer().dim());
        let (ni, nb) = (layout.nodes(), layout.block());
        let mut z = vec![0.0; nz];
        let mut p = vec![0.0; 2 * m];
        sys.split(y, &mut z, &mut p);
        let mut gz = DMatrix::zeros(nz + m, nz);
        let mut gp = DMatrix::zeros(nz + m, 2 * m);
        let w0 = ops.first().map_or(0.0, |o| o.w0());
        reduced_jacobian(sys.coupling(), t, &z, &p, w0, &mut gz, &mut gp);
        let mut tw_all = vec![0.0; m];
        let mut fz = vec![0.0; nz];
        sys.reduced(t, &z, &p, &mut fz, &mut tw_all);
        let c = sys.coupling();
        let nu = c.viscosity() / c.density();
        let (r, rd) = (y[0], y[1]);
        let mut rows = Vec::with_capacity(m);
        let q = per_node(m);
        let mut r_r = vec![[0.0; L]; ni * q];
        let mut r_rd = vec![[0.0; L]; ni * q];
        let mut pw = [vec![[0.0; L]; ni * q], vec![[0.0; L]; ni * q]];
        let apply = |rw: &Rows, tw: f64, tn: &[f64]| -> Vec<f64> {
            (0..ni)
                .map(|i| {
                    let left = if i == 0 { tw } else { tn[i - 1] };
                    let right = if i + 1 < ni { tn[i + 1] } else { 0.0 };
                    rw.lower[i] * left + rw.diag[i] * tn[i] + rw.upper[i] * right
                })
                .collect()
        };
        for (mi, op) in ops.iter().enumerate() {
            let tn = &y[layout.node_range(mi)];
            let tw = tw_all[mi];
            let mut base = Rows::default();
            op.rows(r, rd, nu, &mut base);
            let (mut d_r, mut d_rd) = (Rows::default(), Rows::default());
            op.rows_derivatives(r, rd, nu, &mut d_r, &mut d_rd);
            rows.push(base);
            for (i, (x, y)) in apply(&d_r, tw, tn).into_iter().zip(apply(&d_rd, tw, tn)).enumerate() {
                r_r[i * q + mi / L][mi % L] = x;
                r_rd[i * q + mi / L][mi % L] = y;
            }
            for i in 0..ni {
                pw[0][i * q + mi / L][mi % L] = op.wi[1 + i];
                pw[1][i * q + mi / L][mi % L] = op.wj[1 + i];
            }
        }
        let g = row_major(&gz, &gp);
        let tri_rows = TriRows::new(&rows, ni);
        let mut c = vec![[0.0; L]; ni * q];
        if ni > 0 {
            for (k, rw) in rows.iter().enumerate() {
                c[k / L][k % L] = rw.lower[0];
            }
        }
        Self { m, nz, ni, nb, layout, gz, gp, tri_rows, c, r_r, r_rd, pw, g }
    }

    /// Factors σI − J. `None` if singular.
    pub fn factor<T: Lane>(self: &Rc<Self>, sigma: T) -> Option<StructuredLu<T>> {
        let (m, nz, ni) = (self.m, self.nz, self.ni);
        let ns = nz + 2 * m;
        // row-major ns × ns (the own dense LU below), built row after row (every entry written
        // once: no zeroed buffer); the π rows are written below
        let mut s = Vec::with_capacity(ns * ns);
        for (i, row) in self.g.chunks_exact(ns.max(1)).take(nz).enumerate() {
            s.extend(row.iter().map(|&v| -T::from_real(v)));
            s[i * ns + i] += sigma;
        }
        s.resize(ns * ns, T::zero());
        let tri = TriBatch::new(sigma, &self.tri_rows)?;
        let q = per_node(m);
        // c_k, r_R,k, r_Ṙ,k are real: read by the sweeps, their imaginary parts written by them
        let (uc, ur, urd) = (tri.solve_real_rhs(&self.c), tri.solve_real_rhs(&self.r_r), tri.solve_real_rhs(&self.r_rd));
        // P·u for the two kinds of functional at once: [kind 0 re, kind 1 re, kind 0 im, kind 1 im]
        let pw = [&self.pw[0][..], &self.pw[1][..]];
        let dot = |v: &Split| {
            let mut acc = vec![[0.0; L]; 4 * q];
            let (a01, a23) = acc.split_at_mut(2 * q);
            let (a0, a1) = a01.split_at_mut(q);
            let (a2, a3) = a23.split_at_mut(q);
            dots2(v, pw, [a0, a1, a2, a3]);
            acc
        };
        let (pu_all, pr_all, prd_all) = (dot(&uc), dot(&ur), dot(&urd));
        let at = |v: &[V], kind: usize, k: usize| T::from_parts(v[kind * q + k / L][k % L], if T::CPLX { v[(2 + kind) * q + k / L][k % L] } else { 0.0 });
        for kind in 0..2 {
            for k in 0..m {
                let q = kind * m + k; // π ordering = p ordering
                let (pu, pr, prd) = (at(&pu_all, kind, k), at(&pr_all, kind, k), at(&prd_all, kind, k));
                let row = nz + q;
                let tw_row = &self.g[(nz + k) * ns..(nz + k + 1) * ns]; // row of T_w,k in [gz | gp]
                for (x, &g) in s[row * ns..(row + 1) * ns].iter_mut().zip(tw_row) {
                    *x = -pu.scale(g);
                }
                s[row * ns] -= pr;
                s[row * ns + 1] -= prd;
                s[row * ns + row] += T::one();
            }
        }
        let small = DenseLu::new(ns, &s)?;
        let tw_rows = self.g[nz * ns..(nz + m) * ns].to_vec();
        let scratch = std::cell::RefCell::new(Scratch::take::<T>(ni, m, ns));
        Some(StructuredLu { jac: Rc::clone(self), tri, u: [uc, ur, urd], small, tw_rows, scratch })
    }
}

impl<T: Lane> StructuredLu<T> {
    /// Solves (σI − J) x = b in place (state layout of the monolithic system).
    pub fn solve(&self, b: &mut [T]) {
        self.solve_body(b);
    }

    #[inline(always)]
    fn solve_body(&self, b: &mut [T]) {
        let j = &*self.jac;
        let (m, nz, nb, lay) = (j.m, j.nz, j.nb, j.layout);
        let zl = lay.boundary_layer();
        let q = per_node(m);
        let mut guard = self.scratch.borrow_mut();
        let Scratch { xt, rhs_r, rhs_i, d, s } = &mut *guard;
        // D_k⁻¹ b_T,k, all modes at once on the node-major copy (mode after mode: contiguous
        // loads from b, strided stores into the copy)
        per_q!(q, Q => copy_in::<Q, T>(b, nb, m, xt), _ => copy_in_any(b, nb, m, xt));
        self.tri.solve_body(xt);
        let mut put = |i: usize, v: T| {
            let (re, im) = v.parts();
            rhs_r[i] = re;
            if T::CPLX {
                rhs_i[i] = im;
            }
        };
        put(0, b[0]);
        put(1, b[1]);
        for k in 0..m {
            let (zk, yk) = (zl.a(k), lay.a(k));
            for c in 0..StateLayout::AMPLITUDES {
                put(zk + c, b[yk + c]);
            }
        }
        {
            let (d01, d23) = d.split_at_mut(2 * q);
            let (d0, d1) = d01.split_at_mut(q);
            let (d2, d3) = d23.split_at_mut(q);
            dots2(xt, [&j.pw[0], &j.pw[1]], [d0, d1, d2, d3]);
        }
        for kind in 0..2 {
            for k in 0..m {
                let (v, lane) = ((kind * q) + k / L, k % L);
                rhs_r[nz + kind * m + k] = d[v][lane];
                if T::CPLX {
                    rhs_i[nz + kind * m + k] = d[2 * q + v][lane];
                }
            }
        }
        self.small.solve(rhs_r, rhs_i);
        let (xr, xi) = (&rhs_r[..], &rhs_i[..]);
        let x = |i: usize| T::from_parts(xr[i], if T::CPLX { xi[i] } else { 0.0 });
        b[0] = x(0);
        b[1] = x(1);
        let ns = xr.len();
        for (k, row) in self.tw_rows.chunks_exact(ns.max(1)).enumerate() {
            let (zk, yk) = (zl.a(k), lay.a(k));
            for c in 0..StateLayout::AMPLITUDES {
                b[yk + c] = x(zk + c);
            }
            // s_k = δT_w,k (∂T_w,k/∂z · x_z, then ∂T_w,k/∂p · π, in that order)
            s[k / L][k % L] = dense_rows::dot(xr, row);
            if T::CPLX {
                s[q + k / L][k % L] = dense_rows::dot(xi, row);
            }
        }
        let [uc, ur, urd] = &self.u;
        let ((x0r, x0i), (x1r, x1i)) = (x(0).parts(), x(1).parts());
        let ([x0r, x0i], [x1r, x1i]) = ([[x0r; L], [x0i; L]], [[x1r; L], [x1i; L]]);
        // x_T = D⁻¹b_T + u_c s + u_R x_R + u_Ṙ x_Ṙ on the node-major copy, node after node (the
        // modes as lanes; per entry the products and sums of `xv + (c·s + r·x0 + rd·x1)`)
        let (sr, si) = s.split_at(q);
        if T::CPLX {
            let u = [[&uc.re[..], &uc.im[..]], [&ur.re[..], &ur.im[..]], [&urd.re[..], &urd.im[..]]];
            per_q!(q, Q => nodes::combine_complex::<Q>([&mut xt.re, &mut xt.im], u, [sr, si], [x0r, x0i], [x1r, x1i]),
                   _ => combine_complex_any(q, [&mut xt.re, &mut xt.im], u, [sr, si], [x0r, x0i], [x1r, x1i]));
        } else {
            let u = [&uc.re[..], &ur.re[..], &urd.re[..]];
            per_q!(q, Q => nodes::combine_real::<Q>(&mut xt.re, u, sr, x0r, x1r), _ => combine_real_any(q, &mut xt.re, u, sr, x0r, x1r));
        }
        per_q!(q, Q => copy_out::<Q, T>(xt, nb, m, b), _ => copy_out_any(xt, nb, m, b));
    }
}

/// x_T = D⁻¹b_T + u_c s + u_R x_R + u_Ṙ x_Ṙ on the node-major copy, node after node (the modes
/// as lanes; per entry the products and sums of `xv + (c·s + r·x0 + rd·x1)`), for any q.
#[inline(always)]
pub(super) fn combine_complex_any(q: usize, x: [&mut [V]; 2], u: [[&[V]; 2]; 3], s: [&[V]; 2], x0: [V; 2], x1: [V; 2]) {
    let [[cr, ci], [rr, ri], [dr, di]] = u;
    let ([sr, si], [x0r, x0i], [x1r, x1i]) = (s, x0, x1);
    let [xr, xi] = x;
    let q1 = q.max(1);
    let lanes = xr.chunks_exact_mut(q1).zip(xi.chunks_exact_mut(q1));
    let us = cr.chunks_exact(q1).zip(ci.chunks_exact(q1)).zip(rr.chunks_exact(q1).zip(ri.chunks_exact(q1))).zip(dr.chunks_exact(q1).zip(di.chunks_exact(q1)));
    for ((xr, xi), (((cr, ci), (rr, ri)), (dr, di))) in lanes.zip(us) {
        let it = xr.iter_mut().zip(xi.iter_mut()).zip(cr.iter().zip(ci)).zip(rr.iter().zip(ri)).zip(dr.iter().zip(di)).zip(sr.iter().zip(si));
        for (((((xr, xi), (&cr, &ci)), (&rr, &ri)), (&dr, &di)), (&sr, &si)) in it {
            let (csr, csi) = cmul(cr, ci, sr, si);
            let (rxr, rxi) = cmul(rr, ri, x0r, x0i);
            let (dxr, dxi) = cmul(dr, di, x1r, x1i);
            *xr = add(*xr, add(add(csr, rxr), dxr));
            *xi = add(*xi, add(add(csi, rxi), dxi));
        }
    }
}

/// [`combine_complex_any`] for real values.
#[inline(always)]
pub(super) fn combine_real_any(q: usize, x: &mut [V], u: [&[V]; 3], s: &[V], x0: V, x1: V) {
    let [cr, rr, dr] = u;
    let q1 = q.max(1);
    let us = cr.chunks_exact(q1).zip(rr.chunks_exact(q1)).zip(dr.chunks_exact(q1));
    for (xr, ((cr, rr), dr)) in x.chunks_exact_mut(q1).zip(us) {
        for ((((x, &c), &r), &d), &sv) in xr.iter_mut().zip(cr).zip(rr).zip(dr).zip(s) {
            *x = add(*x, add(add(mul(c, sv), mul(r, x0)), mul(d, x1)));
        }
    }
}

/// The structured Jacobian as the integrators' linear-solver hook
/// ([`crate::integrate::linear`]): Radau5 and the Rosenbrock pair factor σI − J through it.
pub struct Hook(pub Rc<StructuredJacobian>);

impl<T: Lane> Factorization<T> for StructuredLu<T> {
    fn solve(&self, b: &mut [T]) {
        StructuredLu::solve(self, b);
    }
}

impl linear::StructuredJacobian for Hook {
    /// 1 + (2 + 3M) + 2M evaluations of the reduced function (each O(M), cheaper than one rhs)
    /// and 2 of the operator rows per mode.
    fn rhs_equivalents(&self) -> u64 {
        (3 + 5 * self.0.m) as u64
    }
    fn factor(&self, sigma: f64) -> Option<Box<dyn Factorization<f64>>> {
        self.0.factor(sigma).map(|f| Box::new(f) as Box<dyn Factorization<f64>>)
    }
    fn factor_complex(&self, sigma: Complex<f64>) -> Option<Box<dyn Factorization<Complex<f64>>>> {
        self.0.factor(sigma).map(|f| Box::new(f) as Box<dyn Factorization<Complex<f64>>>)
    }
}

/// Dense J of `sys` by finite differences (for tests of the structured form on small grids).
pub fn dense_jacobian(sys: &Monolithic<'_>, t: f64, y: &[f64]) -> DMatrix<f64> {
    let n = sys.dim();
    let mut f0 = vec![0.0; n];
    sys.rhs(t, y, &mut f0);
    let mut jac = DMatrix::zeros(n, n);
    let mut f1 = vec![0.0; n];
    for j in 0..n {
        let mut yy = y.to_vec();
        let d = (f64::EPSILON * y[j].abs().max(1e-5)).sqrt();
        yy[j] += d;
        let d = yy[j] - y[j];
        sys.rhs(t, &yy, &mut f1);
        for i in 0..n {
            jac[(i, j)] = (f1[i] - f0[i]) / d;
        }
    }
    jac
}
