//! The small dense LU of the structured solve (the (z, π) system of [`super::structured`]):
//! partial pivoting (largest |re| + |im| in the column, whole rows swapped), stored *split* (real
//! and imaginary parts in separate arrays, as [`super::batch`]), so the row updates and the forward
//! substitution are lane-wise loops the compiler vectorises. Per entry the operations and their
//! order are those of `num_complex` on interleaved values (a·b = (a.re b.re − a.im b.im,
//! a.re b.im + a.im b.re), then x − a·b), so the results are the interleaved LU's to the bit
//! (the forward substitution column by column subtracts, from each entry, the same products in
//! the same order as the row-by-row one).

use super::batch::Lane;
use super::dense_rows as rows;
use std::marker::PhantomData;

/// LU factors of an n × n matrix, row-major, split.
pub struct DenseLu<T> {
    n: usize,
    /// U on and above the diagonal, row-major (the multipliers of L below it, not read).
    ur: Vec<f64>,
    ui: Vec<f64>,
    /// L's multipliers column by column, packed: column j (rows j+1 … n−1) from
    /// `j·n − j(j+1)/2` on.
    lr: Vec<f64>,
    li: Vec<f64>,
    /// 1 / U_ii
    dr: Vec<f64>,
    di: Vec<f64>,
    /// At step k, row k was swapped with row `piv[k]` ≥ k.
    piv: Vec<usize>,
    _t: PhantomData<T>,
}

impl<T: Lane> DenseLu<T> {
    /// Factors the row-major n × n `a`; `None` when a pivot is zero or not finite.
    pub fn new(n: usize, a: &[T]) -> Option<Self> {
        Self::new_body(n, a)
    }

    #[inline(always)]
    fn new_body(n: usize, a: &[T]) -> Option<Self> {
        let (mut ur, mut ui): (Vec<f64>, Vec<f64>) = (a.iter().map(|x| x.parts().0).collect(), if T::CPLX { a.iter().map(|x| x.parts().1).collect() } else { Vec::new() });
        let mut piv = vec![0; n];
        let (mut dr, mut di) = (vec![0.0; n], vec![0.0; if T::CPLX { n } else { 0 }]);
        for k in 0..n {
            let norm1 = |i: usize| if T::CPLX { ur[i * n + k].abs() + ui[i * n + k].abs() } else { ur[i * n + k].abs() };
            let p = crate::integrate::pivot_row(k, n, norm1).ok()?;
            piv[k] = p;
            if p != k {
                for j in 0..n {
                    ur.swap(k * n + j, p * n + j);
                    if T::CPLX {
                        ui.swap(k * n + j, p * n + j);
                    }
                }
            }
            let pivot = T::from_parts(ur[k * n + k], if T::CPLX { ui[k * n + k] } else { 0.0 });
            let inv = T::one() / pivot;
            let (inv_r, inv_i) = inv.parts();
            dr[k] = inv_r;
            if T::CPLX {
                di[k] = inv_i;
            }
            eliminate::<T>(n, k, inv, &mut ur, &mut ui);
        }
        // L's multipliers column-major (for the column-oriented forward substitution)
        let lower = |a: &[f64]| -> Vec<f64> {
            let mut l = Vec::with_capacity(n * n.saturating_sub(1) / 2);
            for j in 0..n {
                l.extend((j + 1..n).map(|i| a[i * n + j]));
            }
            l
        };
        let (lr, li) = (lower(&ur), if T::CPLX { lower(&ui) } else { Vec::new() });
        Some(Self { n, ur, ui, lr, li, dr, di, piv, _t: PhantomData })
    }

    /// x ← A⁻¹ x, x split (`xi` empty for a real T).
    pub fn solve(&self, xr: &mut [f64], xi: &mut [f64]) {
        self.solve_body(xr, xi)
    }

    #[inline(always)]
    fn solve_body(&self, xr: &mut [f64], xi: &mut [f64]) {
        let n = self.n;
        let (xr, xi) = (&mut xr[..n], &mut xi[..if T::CPLX { n } else { 0 }]);
        for (k, &p) in self.piv.iter().enumerate() {
            xr.swap(k, p);
            if T::CPLX {
                xi.swap(k, p);
            }
        }
        forward::<T>(n, &self.lr, &self.li, xr, xi);
        // back substitution row by row: s = x_i − Σ_{j>i} U_ij x_j in the order of j
        for i in (0..n).rev() {
            let row = i * n + i + 1..(i + 1) * n;
            if T::CPLX {
                let (ur, ui) = (&self.ur[row.clone()], &self.ui[row]);
                let (tr, ti) = (&xr[i + 1..], &xi[i + 1..]);
                let (sr, si) = rows::complex((xr[i], xi[i]), (ur, ui), (tr, ti));
                (xr[i], xi[i]) = (sr * self.dr[i] - si * self.di[i], sr * self.di[i] + si * self.dr[i]);
            } else {
                let s = rows::real(xr[i], &self.ur[row], &xr[i + 1..]);
                xr[i] = s * self.dr[i];
            }
        }
    }
}

/// Step k of the elimination: rows below k get their multiplier l = a_ik / a_kk (stored in
/// place) and a_ij −= l a_kj for j > k (skipped when l = 0).
#[inline(always)]
fn eliminate<T: Lane>(n: usize, k: usize, inv: T, ur: &mut [f64], ui: &mut [f64]) {
    let (top_r, bottom_r) = ur.split_at_mut((k + 1) * n);
    let rkr = &top_r[k * n + k + 1..(k + 1) * n];
    if T::CPLX {
        let (top_i, bottom_i) = ui.split_at_mut((k + 1) * n);
        let rki = &top_i[k * n + k + 1..(k + 1) * n];
        for (row_r, row_i) in bottom_r.chunks_exact_mut(n).zip(bottom_i.chunks_exact_mut(n)) {
            let l = T::from_parts(row_r[k], row_i[k]) * inv;
            let (l_r, l_i) = l.parts();
            (row_r[k], row_i[k]) = (l_r, l_i);
            if l != T::zero() {
                let (xr, xi) = (&mut row_r[k + 1..], &mut row_i[k + 1..]);
                let m = xr.len().min(rkr.len());
                let (xr, xi, ur, ui) = (&mut xr[..m], &mut xi[..m], &rkr[..m], &rki[..m]);
                for j in 0..m {
                    let (pr, pi) = (l_r * ur[j] - l_i * ui[j], l_r * ui[j] + l_i * ur[j]);
                    xr[j] -= pr;
                    xi[j] -= pi;
                }
            }
        }
    } else {
        let inv = inv.parts().0;
        for row in bottom_r.chunks_exact_mut(n) {
            let l = row[k] * inv;
            row[k] = l;
            if l != 0.0 {
                let x = &mut row[k + 1..];
                let m = x.len().min(rkr.len());
                let (x, u) = (&mut x[..m], &rkr[..m]);
                for j in 0..m {
                    x[j] -= l * u[j];
                }
            }
        }
    }
}

/// Forward substitution with the unit lower factor, column by column: x_i −= L_ij x_j for
/// i > j, j ascending (for each x_i the products of the row-by-row order, in that order).
#[inline(always)]
fn forward<T: Lane>(n: usize, lr: &[f64], li: &[f64], xr: &mut [f64], xi: &mut [f64]) {
    for j in 0..n.saturating_sub(1) {
        let start = j * n - j * (j + 1) / 2;
        let col = start..start + (n - j - 1);
        let (head_r, tail_r) = xr.split_at_mut(j + 1);
        let xjr = head_r[j];
        if T::CPLX {
            let (head_i, tail_i) = xi.split_at_mut(j + 1);
            let xji = head_i[j];
            let (cr, ci) = (&lr[col.clone()], &li[col]);
            let m = tail_r.len().min(cr.len()).min(ci.len()).min(tail_i.len());
            let (tr, ti, cr, ci) = (&mut tail_r[..m], &mut tail_i[..m], &cr[..m], &ci[..m]);
            for i in 0..m {
                tr[i] -= cr[i] * xjr - ci[i] * xji;
                ti[i] -= cr[i] * xji + ci[i] * xjr;
            }
        } else {
            let c = &lr[col];
            let m = tail_r.len().min(c.len());
            let (t, c) = (&mut tail_r[..m], &c[..m]);
            for i in 0..m {
                t[i] -= c[i] * xjr;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::DenseLu;
    use nalgebra::Complex;

    /// The split LU solves A x = b for a complex matrix that needs pivoting (zero diagonal),
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
        let lu = DenseLu::new(n, &a).expect("invertible");
        let (mut xr, mut xi): (Vec<f64>, Vec<f64>) = (b.iter().map(|x| x.re).collect(), b.iter().map(|x| x.im).collect());
        lu.solve(&mut xr, &mut xi);
        for r in 0..n {
            let ax: Complex<f64> = (0..n).map(|c| a[r * n + c] * Complex::new(xr[c], xi[c])).sum();
            assert!((ax - b[r]).norm() < 1e-12, "row {r}: {ax} vs {}", b[r]);
        }
        let ar: Vec<f64> = a.iter().map(|x| x.re + 2.0).collect();
        let lu = DenseLu::new(n, &ar).expect("invertible");
        let mut x: Vec<f64> = (0..n).map(|i| (i as f64).cos()).collect();
        let want = x.clone();
        lu.solve(&mut x, &mut []);
        for r in 0..n {
            let ax: f64 = (0..n).map(|c| ar[r * n + c] * x[c]).sum();
            assert!((ax - want[r]).abs() < 1e-12, "real row {r}");
        }
        let sing = vec![1.0f64; 9];
        assert!(DenseLu::new(3, &sing).is_none(), "rank 1");
    }
}
