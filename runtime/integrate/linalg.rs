//! LU factorisation with partial pivoting, dense and banded, for real and complex matrices
//! (Radau5's E₁ = γ/h I − J and E₂ = (α + iβ)/h I − J). Own code rather than nalgebra's `LU`
//! so that refactorisation is allocation-free and the band variant shares the interface.

use nalgebra::Complex;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// The scalars the factorisations work on: f64 and Complex<f64>.
pub(crate) trait Scalar:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> + Neg<Output = Self>
{
    const ZERO: Self;
    /// |x|₁-like magnitude for pivoting.
    fn mag(self) -> f64;
    fn from_real(x: f64) -> Self;
    /// self · x for a real x (2 products for a complex self, not 4: the same value).
    fn scale(self, x: f64) -> Self;
    /// The fastest dense LU of an owned n × n row-major matrix of this scalar, as
    /// [`super::reduced`] factors its reduced matrix: [`super::split_lu::RealLu`] for f64, the
    /// split-storage [`super::split_lu::SplitLu`] for complex (both the same factors to the bit as
    /// [`ShiftedLu`], vectorisable loops).
    type DenseLu: std::fmt::Debug + 'static;
    /// Factors `a` (n × n, row-major); `Err(column)` when singular.
    fn dense_factor(n: usize, a: Vec<Self>) -> Result<Self::DenseLu, usize>;
    /// Solves with the factors of [`dense_factor`](Self::dense_factor), in place.
    fn dense_solve(lu: &Self::DenseLu, x: &mut [Self]);
}

impl Scalar for f64 {
    const ZERO: Self = 0.0;
    fn mag(self) -> f64 {
        self.abs()
    }
    fn from_real(x: f64) -> Self {
        x
    }
    fn scale(self, x: f64) -> Self {
        self * x
    }
    type DenseLu = super::split_lu::RealLu;
    fn dense_factor(n: usize, a: Vec<f64>) -> Result<Self::DenseLu, usize> {
        super::split_lu::RealLu::factor(n, a)
    }
    fn dense_solve(lu: &Self::DenseLu, x: &mut [f64]) {
        lu.solve(x);
    }
}

impl Scalar for Complex<f64> {
    const ZERO: Self = Complex { re: 0.0, im: 0.0 };
    fn mag(self) -> f64 {
        self.re.abs() + self.im.abs()
    }
    fn from_real(x: f64) -> Self {
        Complex { re: x, im: 0.0 }
    }
    fn scale(self, x: f64) -> Self {
        Complex { re: self.re * x, im: self.im * x }
    }
    type DenseLu = super::split_lu::SplitLu;
    fn dense_factor(n: usize, a: Vec<Self>) -> Result<Self::DenseLu, usize> {
        super::split_lu::SplitLu::factor(n, &a)
    }
    fn dense_solve(lu: &Self::DenseLu, x: &mut [Self]) {
        lu.solve(x);
    }
}

/// LU of `shift·I − J` for a row-major n×n `J`, dense or banded (lower ml, upper mu).
#[derive(Debug, Clone)]
pub(crate) struct ShiftedLu<T: Scalar> {
    n: usize,
    band: Option<(usize, usize)>,
    /// Dense: row-major n×n. Band: row i holds columns i−ml ..= i+ml+mu (width 2ml+mu+1).
    a: Vec<T>,
    /// Band: multipliers, ml per column. Dense: the columns of L below the diagonal and of U
    /// above it, each contiguous (`l[k * n + i]` = L_ik for i > k, = U_ik for i < k), so that
    /// both substitutions of [`solve`](Self::solve) are contiguous column sweeps.
    l: Vec<T>,
    /// Dense: 1 / U_kk.
    inv_diag: Vec<T>,
    piv: Vec<usize>,
}

/// Partial pivoting's row for column k: the first row i in k..n of the largest `mag(i)`;
/// `Err(k)` when that magnitude is zero or not finite (the column is singular). Shared by
/// every dense LU here and in `model::vorticity::dense`.
#[inline(always)]
pub(crate) fn pivot_row(k: usize, n: usize, mag: impl Fn(usize) -> f64) -> Result<usize, usize> {
    let mut p = k;
    let mut best = mag(k);
    for i in k + 1..n {
        let m = mag(i);
        if m > best {
            best = m;
            p = i;
        }
    }
    if !(best > 0.0) || !best.is_finite() {
        return Err(k);
    }
    Ok(p)
}

/// The dense LU of [`ShiftedLu`] (and of `split_lu::RealLu`, which shares it): partial pivoting
/// on the row-major n × n `a` in place, the pivots in `piv`, then the column copies `l` and
/// 1/U_kk in `inv_diag` that [`dense_solve`] reads; `Err(k)` when singular at column k.
#[inline(always)]
pub(crate) fn dense_factor<T: Scalar>(n: usize, a: &mut [T], piv: &mut [usize], inv_diag: &mut Vec<T>, l: &mut Vec<T>) -> Result<(), usize> {
    for k in 0..n {
        let p = pivot_row(k, n, |i| a[i * n + k].mag())?;
        piv[k] = p;
        // LINPACK style: only columns k.. are swapped, so the multipliers of earlier
        // columns stay where the interleaved forward substitution of `solve` expects them.
        if p != k {
            for j in k..n {
                a.swap(k * n + j, p * n + j);
            }
        }
        let pivot = a[k * n + k];
        // Row k (columns k+1..) against every later row: contiguous slices, no index checks
        // in the inner loop (the same operations in the same order as the indexed loop).
        let (top, bottom) = a.split_at_mut((k + 1) * n);
        let rk = &top[k * n + k + 1..(k + 1) * n];
        for row in bottom.chunks_exact_mut(n) {
            let m = row[k] / pivot;
            row[k] = m;
            if m.mag() != 0.0 {
                for (x, &y) in row[k + 1..].iter_mut().zip(rk) {
                    *x = *x - m * y;
                }
            }
        }
    }
    // the column copies of the substitutions (the doc of `l`; its diagonal is not read)
    let one = T::from_real(1.0);
    inv_diag.clear();
    inv_diag.extend((0..n).map(|k| one / a[k * n + k]));
    l.clear();
    l.reserve(n * n);
    for k in 0..n {
        l.extend((0..n).map(|i| a[i * n + k]));
    }
    Ok(())
}

/// The dense solve of [`ShiftedLu`] (and of `split_lu::RealLu`, which shares it): `l` holds
/// column k of L below the diagonal at `l[k n + k + 1 .. (k + 1) n]` and column k of U above it
/// at `l[k n .. k n + k]`, `inv_diag` = 1/U_kk. Forward: b[k+1..] −= L[k+1.., k] b_k; backward:
/// b_k /= U_kk, b[..k] −= U[..k, k] b_k (column sweeps over contiguous copies: axpys, no strided
/// access).
#[inline(always)]
pub(crate) fn dense_solve<T: Scalar>(n: usize, l: &[T], piv: &[usize], inv_diag: &[T], b: &mut [T]) {
    let b = &mut b[..n];
    let (l, piv, inv_diag) = (&l[..n * n], &piv[..n], &inv_diag[..n]);
    for k in 0..n {
        b.swap(k, piv[k]);
        let (head, tail) = b.split_at_mut(k + 1);
        let bk = head[k];
        for (x, &m) in tail.iter_mut().zip(&l[k * n + k + 1..(k + 1) * n]) {
            *x = *x - m * bk;
        }
    }
    for k in (0..n).rev() {
        let (head, tail) = b.split_at_mut(k);
        let bk = tail[0] * inv_diag[k];
        tail[0] = bk;
        for (x, &u) in head.iter_mut().zip(&l[k * n..k * n + k]) {
            *x = *x - u * bk;
        }
    }
}

impl<T: Scalar> ShiftedLu<T> {
    pub(crate) fn new(n: usize, band: Option<(usize, usize)>) -> Self {
        // A band wider than the matrix is just a dense matrix.
        let band = band.filter(|&(ml, mu)| 2 * ml + mu + 1 < n);
        let size = match band {
            None => n * n,
            Some((ml, mu)) => n * (2 * ml + mu + 1),
        };
        let lsize = band.map_or(n * n, |(ml, _)| n * ml);
        let dsize = if band.is_some() { 0 } else { n };
        ShiftedLu { n, band, a: vec![T::ZERO; size], l: vec![T::ZERO; lsize], inv_diag: vec![T::ZERO; dsize], piv: vec![0; n] }
    }

    /// Factors shift·I − J. Returns `Err(k)` when the matrix is singular at column k.
    pub(crate) fn factor(&mut self, shift: T, jac: &[f64], scale: impl Fn(f64) -> T) -> Result<(), usize> {
        let n = self.n;
        match self.band {
            None => {
                for i in 0..n {
                    for j in 0..n {
                        self.a[i * n + j] = -scale(jac[i * n + j]);
                    }
                    self.a[i * n + i] = self.a[i * n + i] + shift;
                }
                self.factor_dense()
            }
            Some((ml, mu)) => {
                let w = 2 * ml + mu + 1;
                for i in 0..n {
                    for c in 0..w {
                        self.a[i * w + c] = T::ZERO;
                    }
                    let j0 = i.saturating_sub(ml);
                    let j1 = (i + mu).min(n - 1);
                    for j in j0..=j1 {
                        self.a[i * w + j + ml - i] = -scale(jac[i * n + j]);
                    }
                    self.a[i * w + ml] = self.a[i * w + ml] + shift;
                }
                self.factor_band(ml, mu)
            }
        }
    }

    /// Factors the dense matrix with entries `entry(i, j)` (a dense `ShiftedLu` only).
    pub(crate) fn factor_matrix(&mut self, entry: impl Fn(usize, usize) -> T) -> Result<(), usize> {
        debug_assert!(self.band.is_none(), "factor_matrix: dense only");
        let n = self.n;
        for i in 0..n {
            for j in 0..n {
                self.a[i * n + j] = entry(i, j);
            }
        }
        self.factor_dense()
    }

    /// A dense `ShiftedLu` factoring the row-major n × n matrix `a` itself (taken over, no
    /// zeroed buffers); `Err(k)` when singular at column k.
    #[cfg(test)]
    pub(crate) fn factor_owned(n: usize, a: Vec<T>) -> Result<Self, usize> {
        assert_eq!(a.len(), n * n, "factor_owned: n × n");
        let mut lu = ShiftedLu { n, band: None, a, l: Vec::new(), inv_diag: Vec::new(), piv: vec![0; n] };
        lu.factor_dense()?;
        Ok(lu)
    }

    fn factor_dense(&mut self) -> Result<(), usize> {
        dense_factor(self.n, &mut self.a, &mut self.piv, &mut self.inv_diag, &mut self.l)
    }

    fn factor_band(&mut self, ml: usize, mu: usize) -> Result<(), usize> {
        let n = self.n;
        let w = 2 * ml + mu + 1;
        let idx = |i: usize, j: usize| i * w + j + ml - i;
        let a = &mut self.a;
        for k in 0..n {
            let last_row = (k + ml).min(n - 1);
            let last_col = (k + ml + mu).min(n - 1);
            let mut p = k;
            let mut best = a[idx(k, k)].mag();
            for i in k + 1..=last_row {
                let m = a[idx(i, k)].mag();
                if m > best {
                    best = m;
                    p = i;
                }
            }
            self.piv[k] = p;
            if !(best > 0.0) || !best.is_finite() {
                return Err(k);
            }
            if p != k {
                for j in k..=last_col {
                    a.swap(idx(k, j), idx(p, j));
                }
            }
            let pivot = a[idx(k, k)];
            // Row i holds columns i − ml .. in order, so columns k+1..=last_col of rows k and i
            // are contiguous slices.
            let (top, bottom) = a.split_at_mut((k + 1) * w);
            let rk = &top[idx(k, k + 1)..=idx(k, last_col)];
            for i in k + 1..=last_row {
                let row = &mut bottom[(i - k - 1) * w..(i - k) * w];
                let c0 = k + ml - i; // column k in row i
                let m = row[c0] / pivot;
                self.l[k * ml + (i - k - 1)] = m;
                row[c0] = T::ZERO;
                if m.mag() != 0.0 {
                    for (x, &y) in row[c0 + 1..=c0 + last_col - k].iter_mut().zip(rk) {
                        *x = *x - m * y;
                    }
                }
            }
        }
        Ok(())
    }

    /// Solves (shift·I − J) x = b in place.
    pub(crate) fn solve(&self, b: &mut [T]) {
        let n = self.n;
        match self.band {
            None => {
                dense_solve(n, &self.l, &self.piv, &self.inv_diag, b);
            }
            Some((ml, mu)) => {
                // The same operations in the same order as the indexed loops, on pre-cut
                // slices (no bounds checks or inclusive ranges in the inner loops).
                let w = 2 * ml + mu + 1;
                let b = &mut b[..n];
                let (a, l, piv) = (&self.a[..n * w], &self.l[..n * ml], &self.piv[..n]);
                for k in 0..n {
                    b.swap(k, piv[k]);
                    let bk = b[k];
                    let len = ml.min(n - 1 - k);
                    for (x, &m) in b[k + 1..k + 1 + len].iter_mut().zip(&l[k * ml..k * ml + len]) {
                        *x = *x - m * bk;
                    }
                }
                for k in (0..n).rev() {
                    let len = (ml + mu).min(n - 1 - k);
                    // row k from its diagonal: columns k ..= k + len
                    let row = &a[k * w + ml..k * w + ml + 1 + len];
                    let mut s = b[k];
                    for (&u, &x) in row[1..].iter().zip(&b[k + 1..k + 1 + len]) {
                        s = s - u * x;
                    }
                    b[k] = s / row[0];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn banded_matrix(n: usize, ml: usize, mu: usize) -> Vec<f64> {
        let mut j = vec![0.0; n * n];
        for r in 0..n {
            for c in 0..n {
                if (r as isize - c as isize) <= ml as isize && (c as isize - r as isize) <= mu as isize {
                    // Deterministic, non-symmetric, needs pivoting (small diagonal).
                    j[r * n + c] = ((r * 7 + c * 13) % 11) as f64 - 5.0 + if r == c { 0.01 } else { 0.0 };
                }
            }
        }
        j
    }

    fn residual<T: Scalar>(n: usize, shift: T, jac: &[f64], x: &[T], b: &[T], scale: impl Fn(f64) -> T) -> f64 {
        (0..n)
            .map(|i| {
                let mut s = shift * x[i];
                for j in 0..n {
                    s = s - scale(jac[i * n + j]) * x[j];
                }
                (s - b[i]).mag()
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn dense_and_band_solve_real_and_complex() {
        let n = 17;
        for (ml, mu) in [(1, 1), (2, 3), (0, 2), (4, 0)] {
            let jac = banded_matrix(n, ml, mu);
            let b: Vec<f64> = (0..n).map(|i| (i as f64).sin() + 1.0).collect();
            for band in [None, Some((ml, mu))] {
                let mut lu = ShiftedLu::<f64>::new(n, band);
                lu.factor(0.3, &jac, |x| x).unwrap();
                let mut x = b.clone();
                lu.solve(&mut x);
                assert!(residual(n, 0.3, &jac, &x, &b, |x| x) < 1e-10, "real {band:?}");

                let shift = Complex::new(0.3, -2.0);
                let bc: Vec<Complex<f64>> = b.iter().map(|&v| Complex::new(v, -v)).collect();
                let mut lu = ShiftedLu::<Complex<f64>>::new(n, band);
                lu.factor(shift, &jac, |x| Complex::new(x, 0.0)).unwrap();
                let mut x = bc.clone();
                lu.solve(&mut x);
                assert!(residual(n, shift, &jac, &x, &bc, |x| Complex::new(x, 0.0)) < 1e-10, "complex {band:?}");
            }
        }
    }

    #[test]
    fn singular_is_reported() {
        let jac = vec![1.0, 0.0, 0.0, 1.0];
        let mut lu = ShiftedLu::<f64>::new(2, None);
        assert_eq!(lu.factor(1.0, &jac, |x| x), Err(0));
    }
}
