//! The dense LUs of the position-row reduction ([`super::reduced`]): Radau5's complex Newton
//! matrix (α + iβ)/h I − J with partial pivoting in split storage (real parts and imaginary
//! parts in two arrays, [`SplitLu`]), and the real γ/h I − J ([`RealLu`]).
//!
//! The same algorithm as the dense [`super::linalg::ShiftedLu`] (LINPACK-style row swaps of
//! columns k.., the multipliers kept in place, the columns of L and U copied for contiguous
//! substitutions), with every complex product and difference written out in the same
//! operations in the same order as `num_complex` forms them (re = a.re b.re − a.im b.im,
//! im = a.re b.im + a.im b.re), so the factors and solutions are the same to the bit. What
//! changes is the layout: the inner loops become real axpys over contiguous slices, which the
//! compiler vectorises (with the build's baseline instructions) where the interleaved `Complex`
//! loops stayed scalar.

use super::linalg::Scalar;
use nalgebra::Complex;
use std::cell::RefCell;

/// LU factors of a dense n × n complex matrix (module doc).
#[derive(Debug)]
pub(crate) struct SplitLu {
    n: usize,
    /// Column k of L below the diagonal and of U above it, contiguous: `lr[k * n + i]`,
    /// `li[k * n + i]` (the layout of `ShiftedLu`'s `l`).
    lr: Vec<f64>,
    li: Vec<f64>,
    /// 1 / U_kk.
    inv_diag: Vec<Complex<f64>>,
    piv: Vec<usize>,
    /// The right-hand side in split form during a solve (no allocation per solve).
    scratch: RefCell<(Vec<f64>, Vec<f64>)>,
}

/// x − m·y for complex x = (xr, xi), m = (mr, mi), y = (yr, yi), over slices (`num_complex`'s
/// operations: (xr − (mr yr − mi yi), xi − (mr yi + mi yr))).
#[inline(always)]
fn axpy(xr: &mut [f64], xi: &mut [f64], (mr, mi): (f64, f64), yr: &[f64], yi: &[f64]) {
    let len = xr.len().min(xi.len()).min(yr.len()).min(yi.len());
    let (xr, xi, yr, yi) = (&mut xr[..len], &mut xi[..len], &yr[..len], &yi[..len]);
    for j in 0..len {
        let (pr, pi) = (mr * yr[j] - mi * yi[j], mr * yi[j] + mi * yr[j]);
        xr[j] -= pr;
        xi[j] -= pi;
    }
}

/// x − y·m for a complex scalar m and slices y (the substitutions: the column entry times b_k;
/// `num_complex`'s (yr mr − yi mi, yr mi + yi mr)).
#[inline(always)]
fn axpy_col(xr: &mut [f64], xi: &mut [f64], yr: &[f64], yi: &[f64], (mr, mi): (f64, f64)) {
    let len = xr.len().min(xi.len()).min(yr.len()).min(yi.len());
    let (xr, xi, yr, yi) = (&mut xr[..len], &mut xi[..len], &yr[..len], &yi[..len]);
    for j in 0..len {
        let (pr, pi) = (yr[j] * mr - yi[j] * mi, yr[j] * mi + yi[j] * mr);
        xr[j] -= pr;
        xi[j] -= pi;
    }
}

impl SplitLu {
    /// Factors the row-major n × n matrix `a`; `Err(k)` when singular at column k.
    pub(crate) fn factor(n: usize, a: &[Complex<f64>]) -> Result<Self, usize> {
        assert_eq!(a.len(), n * n, "SplitLu: n × n");
        let mut ar: Vec<f64> = a.iter().map(|z| z.re).collect();
        let mut ai: Vec<f64> = a.iter().map(|z| z.im).collect();
        let mut piv = vec![0; n];
        for k in 0..n {
            let p = super::linalg::pivot_row(k, n, |i| ar[i * n + k].abs() + ai[i * n + k].abs())?;
            piv[k] = p;
            if p != k {
                for j in k..n {
                    ar.swap(k * n + j, p * n + j);
                    ai.swap(k * n + j, p * n + j);
                }
            }
            let pivot = Complex::new(ar[k * n + k], ai[k * n + k]);
            let (rtop, rbottom) = ar.split_at_mut((k + 1) * n);
            let (itop, ibottom) = ai.split_at_mut((k + 1) * n);
            let (rkr, rki) = (&rtop[k * n + k + 1..(k + 1) * n], &itop[k * n + k + 1..(k + 1) * n]);
            for (rr, ri) in rbottom.chunks_exact_mut(n).zip(ibottom.chunks_exact_mut(n)) {
                let m = Complex::new(rr[k], ri[k]) / pivot;
                rr[k] = m.re;
                ri[k] = m.im;
                if m.mag() != 0.0 {
                    axpy(&mut rr[k + 1..], &mut ri[k + 1..], (m.re, m.im), rkr, rki);
                }
            }
        }
        let one = Complex::new(1.0, 0.0);
        let inv_diag = (0..n).map(|k| one / Complex::new(ar[k * n + k], ai[k * n + k])).collect();
        let (mut lr, mut li) = (Vec::with_capacity(n * n), Vec::with_capacity(n * n));
        for k in 0..n {
            lr.extend((0..n).map(|i| ar[i * n + k]));
            li.extend((0..n).map(|i| ai[i * n + k]));
        }
        Ok(SplitLu { n, lr, li, inv_diag, piv, scratch: RefCell::new((vec![0.0; n], vec![0.0; n])) })
    }

    /// Solves A x = b in place (the substitutions of `ShiftedLu::solve`, dense branch).
    pub(crate) fn solve(&self, b: &mut [Complex<f64>]) {
        let n = self.n;
        let mut guard = self.scratch.borrow_mut();
        let (br, bi) = &mut *guard;
        let (br, bi) = (&mut br[..n], &mut bi[..n]);
        for (j, z) in b[..n].iter().enumerate() {
            br[j] = z.re;
            bi[j] = z.im;
        }
        let (lr, li, piv) = (&self.lr[..n * n], &self.li[..n * n], &self.piv[..n]);
        for k in 0..n {
            br.swap(k, piv[k]);
            bi.swap(k, piv[k]);
            let bk = (br[k], bi[k]);
            let col = k * n + k + 1..(k + 1) * n;
            axpy_col(&mut br[k + 1..], &mut bi[k + 1..], &lr[col.clone()], &li[col], bk);
        }
        for k in (0..n).rev() {
            let z = Complex::new(br[k], bi[k]) * self.inv_diag[k];
            br[k] = z.re;
            bi[k] = z.im;
            let col = k * n..k * n + k;
            axpy_col(&mut br[..k], &mut bi[..k], &lr[col.clone()], &li[col], (z.re, z.im));
        }
        for (j, z) in b[..n].iter_mut().enumerate() {
            *z = Complex::new(br[j], bi[j]);
        }
    }
}

/// The real dense LU of [`super::reduced`]: the algorithm of the dense [`super::linalg::ShiftedLu`]
/// for f64, operation for operation (so the same factors and solutions to the bit).
#[derive(Debug)]
pub(crate) struct RealLu {
    n: usize,
    /// Column k of L below the diagonal and of U above it, contiguous (`l[k * n + i]`).
    l: Vec<f64>,
    inv_diag: Vec<f64>,
    piv: Vec<usize>,
}

impl RealLu {
    /// Factors the row-major n × n matrix `a` (taken over); `Err(k)` when singular at column k.
    pub(crate) fn factor(n: usize, mut a: Vec<f64>) -> Result<Self, usize> {
        assert_eq!(a.len(), n * n, "RealLu: n × n");
        let (mut piv, mut inv_diag, mut l) = (vec![0; n], Vec::new(), Vec::new());
        super::linalg::dense_factor(n, &mut a, &mut piv, &mut inv_diag, &mut l)?;
        Ok(RealLu { n, l, inv_diag, piv })
    }

    /// Solves A x = b in place.
    pub(crate) fn solve(&self, b: &mut [f64]) {
        super::linalg::dense_solve(self.n, &self.l, &self.piv, &self.inv_diag, b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::linalg::ShiftedLu;

    /// The split factorisation and solve give the dense `ShiftedLu<Complex>` results to the bit.
    #[test]
    fn same_bits_as_the_interleaved_lu() {
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut rnd = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x % 20001) as f64 / 10000.0 - 1.0
        };
        for n in [1, 2, 5, 17, 25] {
            let a: Vec<Complex<f64>> = (0..n * n).map(|_| Complex::new(rnd(), rnd())).collect();
            let b: Vec<Complex<f64>> = (0..n).map(|_| Complex::new(rnd(), rnd())).collect();
            let split = SplitLu::factor(n, &a).expect("regular");
            let dense = ShiftedLu::<Complex<f64>>::factor_owned(n, a.clone()).expect("regular");
            let (mut xs, mut xd) = (b.clone(), b.clone());
            split.solve(&mut xs);
            dense.solve(&mut xd);
            for (s, d) in xs.iter().zip(&xd) {
                assert_eq!((s.re.to_bits(), s.im.to_bits()), (d.re.to_bits(), d.im.to_bits()), "n = {n}");
            }
        }
        // the real LU against the dense ShiftedLu<f64>
        for n in [1, 2, 5, 17, 25] {
            let a: Vec<f64> = (0..n * n).map(|_| rnd()).collect();
            let b: Vec<f64> = (0..n).map(|_| rnd()).collect();
            let real = RealLu::factor(n, a.clone()).expect("regular");
            let dense = ShiftedLu::<f64>::factor_owned(n, a).expect("regular");
            let (mut xs, mut xd) = (b.clone(), b);
            real.solve(&mut xs);
            dense.solve(&mut xd);
            for (s, d) in xs.iter().zip(&xd) {
                assert_eq!(s.to_bits(), d.to_bits(), "real, n = {n}");
            }
        }
        assert_eq!(RealLu::factor(2, vec![0.0; 4]).err(), Some(0));
        let singular = vec![Complex::new(0.0, 0.0); 4];
        assert_eq!(SplitLu::factor(2, &singular).err(), Some(0));
    }
}
