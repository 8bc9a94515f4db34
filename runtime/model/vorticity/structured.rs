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

use super::equations::reduced_jacobian;
use super::monolithic::Monolithic;
use super::operator::Rows;
use crate::integrate::linear::{self, Factorization};
use crate::integrate::OdeSystem;
use nalgebra::{Complex, ComplexField, DMatrix};
use std::rc::Rc;

/// J at one (t, y), in structured form.
pub struct StructuredJacobian {
    m: usize,     // number of modes M
    nz: usize,    // 2 + 3M
    ni: usize,    // interior nodes per mode
    nb: usize,    // block length 3 + ni
    /// ∂(f_z, T_w)/∂z: (nz + M) × nz
    gz: DMatrix<f64>,
    /// ∂(f_z, T_w)/∂p: (nz + M) × 2M
    gp: DMatrix<f64>,
    rows: Vec<Rows>,
    /// ∂(T rows)/∂R and ∂/∂Ṙ at fixed T, T_w (per mode, length ni)
    r_r: Vec<Vec<f64>>,
    r_rd: Vec<Vec<f64>>,
    /// P rows per mode: weights of Ĩ_int and of ∫(y⁻³−1)y^{−k}T dy on the interior nodes
    /// node-major (entry i of mode k at `i * M + k`, as [`TriBatch`])
    pw: [Vec<f64>; 2],
}

/// Thomas factors of the M tridiagonal matrices σI − L_k, stored node-major (entry i of mode k
/// at `i * m + k`), so that the M independent recurrences of a sweep run side by side in the
/// inner loop (issue 16, lever "batched tridiagonal solves"); per mode the operations and their
/// order are those of a single Thomas sweep.
struct TriBatch<T> {
    m: usize,
    /// −L_k's sub-diagonal (real; a real times complex product is 2 multiplications, not 4)
    lower: Vec<f64>,
    inv_beta: Vec<T>,
    gamma: Vec<T>,
}

/// Per mode k, acc[k] = Σ_i v[i·M + k] w[i·M + k] (summed in the order of i), node-major like
/// [`TriBatch`]; `acc` has length M.
fn dots<T: ComplexField<RealField = f64> + Copy>(v: &[T], w: &[f64], acc: &mut [T]) {
    let m = acc.len();
    acc.fill(T::zero());
    for (vi, wi) in v.chunks_exact(m.max(1)).zip(w.chunks_exact(m.max(1))) {
        for ((a, &x), &c) in acc.iter_mut().zip(vi).zip(wi) {
            *a = *a + x.scale(c);
        }
    }
}

/// [`dots`] with two weight vectors in one pass over `v` (the same sums).
fn dots2<T: ComplexField<RealField = f64> + Copy>(v: &[T], w: [&[f64]; 2], acc0: &mut [T], acc1: &mut [T]) {
    let m = acc0.len();
    acc0.fill(T::zero());
    acc1.fill(T::zero());
    for ((vi, wa), wb) in v.chunks_exact(m.max(1)).zip(w[0].chunks_exact(m.max(1))).zip(w[1].chunks_exact(m.max(1))) {
        for ((((a0, a1), &x), &c0), &c1) in acc0.iter_mut().zip(acc1.iter_mut()).zip(vi).zip(wa).zip(wb) {
            *a0 = *a0 + x.scale(c0);
            *a1 = *a1 + x.scale(c1);
        }
    }
}

impl<T: ComplexField<RealField = f64> + Copy> TriBatch<T> {
    fn new(sigma: T, rows: &[Rows], ni: usize) -> Option<Self> {
        // built entry after entry in node-major order (no zeroed buffers: every entry is written)
        let m = rows.len();
        let (mut lower, mut inv_beta, mut gamma): (Vec<f64>, Vec<T>, Vec<T>) = (Vec::with_capacity(ni * m), Vec::with_capacity(ni * m), Vec::with_capacity(ni * m));
        for i in 0..ni {
            for (k, r) in rows.iter().enumerate() {
                let at = i * m + k;
                let beta = if i == 0 {
                    lower.push(0.0);
                    gamma.push(T::zero());
                    sigma - T::from_real(r.diag[0])
                } else {
                    let l = -r.lower[i];
                    let g = inv_beta[at - m].scale(-r.upper[i - 1]);
                    lower.push(l);
                    gamma.push(g);
                    sigma - T::from_real(r.diag[i]) - g.scale(l)
                };
                if beta == T::zero() {
                    return None;
                }
                inv_beta.push(T::one() / beta);
            }
        }
        Some(Self { m, lower, inv_beta, gamma })
    }

    /// x ← (σI − L_k)⁻¹ x for every mode k at once; x node-major (length ni·M).
    fn solve(&self, x: &mut [T]) {
        let m = self.m;
        let n = x.len();
        if n == 0 {
            return;
        }
        for (v, ib) in x[..m].iter_mut().zip(&self.inv_beta[..m]) {
            *v *= *ib;
        }
        for i in 1..n / m {
            let (prev, cur) = x[(i - 1) * m..(i + 1) * m].split_at_mut(m);
            let (l, ib) = (&self.lower[i * m..(i + 1) * m], &self.inv_beta[i * m..(i + 1) * m]);
            for k in 0..m {
                cur[k] = (cur[k] - prev[k].scale(l[k])) * ib[k];
            }
        }
        for i in (0..n / m - 1).rev() {
            let (cur, next) = x[i * m..(i + 2) * m].split_at_mut(m);
            let g = &self.gamma[(i + 1) * m..(i + 2) * m];
            for k in 0..m {
                cur[k] -= g[k] * next[k];
            }
        }
    }
}

/// LU with partial pivoting (largest |re| + |im| in the column, whole rows swapped) of the
/// small dense (z, π) system, row-major: own code instead of nalgebra's `LU` (issue 16: its
/// factorisation and solve were 12 % of the monolithic run at 42 × 42), no allocation per solve.
struct DenseLu<T> {
    n: usize,
    /// U on and above the diagonal, the multipliers of L below it (unit diagonal implied).
    a: Vec<T>,
    /// 1 / U_ii
    inv_diag: Vec<T>,
    /// At step k, row k was swapped with row `piv[k]` ≥ k.
    piv: Vec<usize>,
}

impl<T: ComplexField<RealField = f64> + Copy> DenseLu<T> {
    /// Factors the row-major n × n `a`; `None` when a pivot is zero or not finite.
    fn new(n: usize, mut a: Vec<T>) -> Option<Self> {
        let mut piv = vec![0; n];
        let mut inv_diag = vec![T::zero(); n];
        for k in 0..n {
            let (mut p, mut best) = (k, a[k * n + k].norm1());
            for i in k + 1..n {
                let v = a[i * n + k].norm1();
                if v > best {
                    best = v;
                    p = i;
                }
            }
            if !(best > 0.0 && best.is_finite()) {
                return None;
            }
            piv[k] = p;
            if p != k {
                for j in 0..n {
                    a.swap(k * n + j, p * n + j);
                }
            }
            let (top, bottom) = a.split_at_mut((k + 1) * n);
            let rk = &top[k * n + k..(k + 1) * n];
            let inv = T::one() / rk[0];
            inv_diag[k] = inv;
            for row in bottom.chunks_exact_mut(n) {
                let l = row[k] * inv;
                row[k] = l;
                if l != T::zero() {
                    for (x, &u) in row[k + 1..].iter_mut().zip(&rk[1..]) {
                        *x -= l * u;
                    }
                }
            }
        }
        Some(Self { n, a, inv_diag, piv })
    }

    /// x ← A⁻¹ x.
    fn solve(&self, x: &mut [T]) {
        let n = self.n;
        let x = &mut x[..n];
        for (k, &p) in self.piv.iter().enumerate() {
            x.swap(k, p);
        }
        for i in 1..n {
            let (done, rest) = x.split_at_mut(i);
            let mut s = rest[0];
            for (&l, &xj) in self.a[i * n..i * n + i].iter().zip(done.iter()) {
                s -= l * xj;
            }
            rest[0] = s;
        }
        for i in (0..n).rev() {
            let (head, tail) = x.split_at_mut(i + 1);
            let mut s = head[i];
            for (&u, &xj) in self.a[i * n + i + 1..(i + 1) * n].iter().zip(tail.iter()) {
                s -= u * xj;
            }
            head[i] = s * self.inv_diag[i];
        }
    }
}

/// The factorisation of σI − J (shares the Jacobian it was built from).
pub struct StructuredLu<T: ComplexField<RealField = f64> + Copy> {
    jac: Rc<StructuredJacobian>,
    tri: TriBatch<T>,
    /// D_k⁻¹ c_k, D_k⁻¹ r_R,k, D_k⁻¹ r_Ṙ,k, node-major like [`TriBatch`]
    u: [Vec<T>; 3],
    small: DenseLu<T>,
    /// The T_w,k rows of J in (z, π), row-major M × (nz + 2M): ∂T_w,k/∂z then ∂T_w,k/∂p
    /// (contiguous copies of the gz / gp rows, for s_k = δT_w,k in [`StructuredLu::solve`]).
    tw_rows: Vec<f64>,
    /// Scratch of [`StructuredLu::solve`] (no allocation per solve).
    scratch: std::cell::RefCell<Scratch<T>>,
}

struct Scratch<T: ComplexField<RealField = f64> + Copy> {
    /// node-major T part
    xt: Vec<T>,
    /// right-hand side and solution of the small dense system
    rhs: Vec<T>,
    /// the 2M functionals P·xt (π ordering), and per mode s_k = δT_w,k
    d: Vec<T>,
    s: Vec<T>,
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
        j.r_r.iter_mut().chain(j.r_rd.iter_mut()).for_each(|v| v.fill(0.0));
        Rc::new(j)
    }

    fn build(sys: &Monolithic<'_>, t: f64, y: &[f64]) -> Self {
        let ops = sys.operators();
        let m = ops.len();
        let nz = 2 + 3 * m;
        let ni = sys.grid.interior();
        let nb = 3 + ni;
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
        let mut r_r = Vec::with_capacity(m);
        let mut r_rd = Vec::with_capacity(m);
        let mut pw = [vec![0.0; ni * m], vec![0.0; ni * m]];
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
            let tn = &y[2 + mi * nb + 3..2 + (mi + 1) * nb];
            let tw = tw_all[mi];
            let mut base = Rows::default();
            op.rows(r, rd, nu, &mut base);
            let (mut d_r, mut d_rd) = (Rows::default(), Rows::default());
            op.rows_derivatives(r, rd, nu, &mut d_r, &mut d_rd);
            rows.push(base);
            r_r.push(apply(&d_r, tw, tn));
            r_rd.push(apply(&d_rd, tw, tn));
            for i in 0..ni {
                pw[0][i * m + mi] = op.wi[1 + i];
                pw[1][i * m + mi] = op.wj[1 + i];
            }
        }
        Self { m, nz, ni, nb, gz, gp, rows, r_r, r_rd, pw }
    }

    /// Factors σI − J. `None` if singular.
    pub fn factor<T: ComplexField<RealField = f64> + Copy>(self: &Rc<Self>, sigma: T) -> Option<StructuredLu<T>> {
        let (m, nz, ni) = (self.m, self.nz, self.ni);
        let ns = nz + 2 * m;
        // row-major ns × ns (the own dense LU below)
        let mut s = vec![T::zero(); ns * ns];
        for i in 0..nz {
            for j in 0..nz {
                s[i * ns + j] = -T::from_real(self.gz[(i, j)]);
            }
            s[i * ns + i] += sigma;
            for q in 0..2 * m {
                s[i * ns + nz + q] = -T::from_real(self.gp[(i, q)]);
            }
        }
        let tri = TriBatch::new(sigma, &self.rows, ni)?;
        let mut uc = vec![T::zero(); ni * m];
        for k in 0..m.min(uc.len()) {
            uc[k] = T::from_real(self.rows[k].lower[0]);
        }
        let node_major = |v: &[Vec<f64>]| -> Vec<T> { (0..ni * m).map(|at| T::from_real(v[at % m][at / m])).collect() };
        let mut ur = node_major(&self.r_r);
        let mut urd = node_major(&self.r_rd);
        tri.solve(&mut uc);
        tri.solve(&mut ur);
        tri.solve(&mut urd);
        for (kind, w) in self.pw.iter().enumerate() {
            let (mut pu_all, mut pr_all, mut prd_all) = (vec![T::zero(); m], vec![T::zero(); m], vec![T::zero(); m]);
            dots(&uc, w, &mut pu_all);
            dots(&ur, w, &mut pr_all);
            dots(&urd, w, &mut prd_all);
            for k in 0..m {
                let q = kind * m + k; // π ordering = p ordering
                let (pu, pr, prd) = (pu_all[k], pr_all[k], prd_all[k]);
                let row = nz + q;
                let tw_row = nz + k; // row of T_w,k in gz/gp
                for j in 0..nz {
                    s[row * ns + j] = -pu.scale(self.gz[(tw_row, j)]);
                }
                s[row * ns] -= pr;
                s[row * ns + 1] -= prd;
                for q2 in 0..2 * m {
                    s[row * ns + nz + q2] = -pu.scale(self.gp[(tw_row, q2)]);
                }
                s[row * ns + row] += T::one();
            }
        }
        let small = DenseLu::new(ns, s)?;
        let mut tw_rows = vec![0.0; m * ns];
        for (k, r) in tw_rows.chunks_exact_mut(ns.max(1)).enumerate() {
            for j in 0..nz {
                r[j] = self.gz[(nz + k, j)];
            }
            for q in 0..2 * m {
                r[nz + q] = self.gp[(nz + k, q)];
            }
        }
        let scratch = std::cell::RefCell::new(Scratch { xt: vec![T::zero(); ni * m], rhs: vec![T::zero(); ns], d: vec![T::zero(); 2 * m], s: vec![T::zero(); m] });
        Some(StructuredLu { jac: Rc::clone(self), tri, u: [uc, ur, urd], small, tw_rows, scratch })
    }
}

impl<T: ComplexField<RealField = f64> + Copy> StructuredLu<T> {
    /// Solves (σI − J) x = b in place (state layout of the monolithic system).
    pub fn solve(&self, b: &mut [T]) {
        let j = &*self.jac;
        let (m, nz, nb) = (j.m, j.nz, j.nb);
        let mut guard = self.scratch.borrow_mut();
        let Scratch { xt, rhs, d, s } = &mut *guard;
        // D_k⁻¹ b_T,k, all modes at once on the node-major copy (node after node: contiguous
        // stores, indexed loads; strided iterators cost more than the indexing)
        for (i, xr) in xt.chunks_exact_mut(m.max(1)).enumerate() {
            for (k, x) in xr.iter_mut().enumerate() {
                *x = b[5 + k * nb + i];
            }
        }
        self.tri.solve(xt);
        rhs[0] = b[0];
        rhs[1] = b[1];
        for k in 0..m {
            for c in 0..3 {
                rhs[2 + 3 * k + c] = b[2 + k * nb + c];
            }
        }
        let (d0, d1) = d.split_at_mut(m);
        dots2(xt, [&j.pw[0], &j.pw[1]], d0, d1);
        for (q, &dq) in d.iter().enumerate() {
            rhs[nz + q] = dq;
        }
        self.small.solve(rhs);
        let x = &rhs[..];
        b[0] = x[0];
        b[1] = x[1];
        let ns = x.len();
        for (k, (sk, row)) in s.iter_mut().zip(self.tw_rows.chunks_exact(ns.max(1))).enumerate() {
            for c in 0..3 {
                b[2 + k * nb + c] = x[2 + 3 * k + c];
            }
            // s_k = δT_w,k (∂T_w,k/∂z · x_z, then ∂T_w,k/∂p · π, in that order)
            *sk = T::zero();
            for (&xj, &g) in x.iter().zip(row) {
                *sk += xj.scale(g);
            }
        }
        let [uc, ur, urd] = &self.u;
        let (x0, x1) = (x[0], x[1]);
        // node after node: contiguous loads of the node-major vectors, indexed stores into b
        // (the same products and sums per entry as mode after mode)
        let rows = xt.chunks_exact(m.max(1)).zip(uc.chunks_exact(m.max(1))).zip(ur.chunks_exact(m.max(1))).zip(urd.chunks_exact(m.max(1)));
        for (i, (((xr, cr), rr), rdr)) in rows.enumerate() {
            for (k, ((((&xv, &c), &r), &rd), &sk)) in xr.iter().zip(cr).zip(rr).zip(rdr).zip(s.iter()).enumerate() {
                b[5 + k * nb + i] = xv + (c * sk + r * x0 + rd * x1);
            }
        }
    }
}

/// The structured Jacobian as the integrators' linear-solver hook
/// ([`crate::integrate::linear`]): Radau5 and the Rosenbrock pair factor σI − J through it.
pub struct Hook(pub Rc<StructuredJacobian>);

impl<T: ComplexField<RealField = f64> + Copy> Factorization<T> for StructuredLu<T> {
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

#[cfg(test)]
mod tests {
    use super::DenseLu;
    use nalgebra::Complex;

    /// The small dense LU solves A x = b for a complex matrix that needs pivoting (zero diagonal),
    /// and reports a singular one.
    #[test]
    fn dense_lu_solves_with_pivoting() {
        let n = 7;
        let a: Vec<Complex<f64>> = (0..n * n)
            .map(|i| {
                let (r, c) = (i / n, i % n);
                if r == c { Complex::new(0.0, 0.0) } else { Complex::new(((r * 7 + c * 13) % 11) as f64 - 5.0, (r + 2 * c) as f64 * 0.1) }
            })
            .collect();
        let b: Vec<Complex<f64>> = (0..n).map(|i| Complex::new((i as f64).sin(), 1.0)).collect();
        let lu = DenseLu::new(n, a.clone()).expect("invertible");
        let mut x = b.clone();
        lu.solve(&mut x);
        for r in 0..n {
            let ax: Complex<f64> = (0..n).map(|c| a[r * n + c] * x[c]).sum();
            assert!((ax - b[r]).norm() < 1e-12, "row {r}: {ax} vs {}", b[r]);
        }
        let mut sing = vec![1.0f64; 9];
        sing[8] = 1.0;
        assert!(DenseLu::new(3, sing).is_none(), "rank 1");
    }
}
