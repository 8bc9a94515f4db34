//! The rows of the back substitution of [`super::dense`]: s − Σ_j u_j t_j over j in ascending
//! order, one subtraction after the other (the order the results depend on). The AVX forms
//! compute four products u_j t_j at once and then subtract them one by one in the same order,
//! so they are the scalar loops' to the bit (IEEE products and differences are the same in a
//! vector lane; a test compares them). Complex, split: s.re −= u.re t.re − u.im t.im and
//! s.im −= u.re t.im + u.im t.re (the `num_complex` product), with (re, im) as one 2-lane register.

/// s − Σ_j u_j t_j, complex split; `AVX` only from a function compiled with AVX.
#[inline(always)]
pub fn complex<const AVX: bool>(s: (f64, f64), u: (&[f64], &[f64]), t: (&[f64], &[f64])) -> (f64, f64) {
    #[cfg(target_arch = "x86_64")]
    if AVX {
        // SAFETY: `AVX` is set only inside functions compiled with AVX, called after the runtime check.
        return unsafe { complex_avx(s, u, t) };
    }
    complex_scalar(s, u, t, 0)
}

/// From entry `from` on, one by one.
#[inline(always)]
fn complex_scalar(s: (f64, f64), u: (&[f64], &[f64]), t: (&[f64], &[f64]), from: usize) -> (f64, f64) {
    let ((mut sr, mut si), (ur, ui), (tr, ti)) = (s, u, t);
    let n = ur.len().min(ui.len()).min(tr.len()).min(ti.len());
    let (ur, ui, tr, ti) = (&ur[..n], &ui[..n], &tr[..n], &ti[..n]);
    for j in from..n {
        sr -= ur[j] * tr[j] - ui[j] * ti[j];
        si -= ur[j] * ti[j] + ui[j] * tr[j];
    }
    (sr, si)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
fn complex_avx(s: (f64, f64), u: (&[f64], &[f64]), t: (&[f64], &[f64])) -> (f64, f64) {
    use std::arch::x86_64::*;
    let ((ur, ui), (tr, ti)) = (u, t);
    let n = ur.len().min(ui.len()).min(tr.len()).min(ti.len());
    let mut acc = _mm_set_pd(s.1, s.0);
    let mut j = 0;
    while j + 4 <= n {
        // SAFETY: j + 4 ≤ n ≤ each slice's length.
        let (a, b, c, d) = unsafe { (_mm256_loadu_pd(ur.as_ptr().add(j)), _mm256_loadu_pd(ui.as_ptr().add(j)), _mm256_loadu_pd(tr.as_ptr().add(j)), _mm256_loadu_pd(ti.as_ptr().add(j))) };
        let pr = _mm256_sub_pd(_mm256_mul_pd(a, c), _mm256_mul_pd(b, d));
        let pi = _mm256_add_pd(_mm256_mul_pd(a, d), _mm256_mul_pd(b, c));
        // (re, im) of the products j, j + 2 and j + 1, j + 3
        let (even, odd) = (_mm256_unpacklo_pd(pr, pi), _mm256_unpackhi_pd(pr, pi));
        acc = _mm_sub_pd(acc, _mm256_castpd256_pd128(even));
        acc = _mm_sub_pd(acc, _mm256_castpd256_pd128(odd));
        acc = _mm_sub_pd(acc, _mm256_extractf128_pd::<1>(even));
        acc = _mm_sub_pd(acc, _mm256_extractf128_pd::<1>(odd));
        j += 4;
    }
    let s = (_mm_cvtsd_f64(acc), _mm_cvtsd_f64(_mm_unpackhi_pd(acc, acc)));
    complex_scalar(s, u, t, j)
}

/// s − Σ_j u_j t_j, real; `AVX` only from a function compiled with AVX.
#[inline(always)]
pub fn real<const AVX: bool>(s: f64, u: &[f64], t: &[f64]) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if AVX {
        // SAFETY: as in [`complex`].
        return unsafe { real_avx(s, u, t) };
    }
    real_scalar(s, u, t, 0)
}

#[inline(always)]
fn real_scalar(mut s: f64, u: &[f64], t: &[f64], from: usize) -> f64 {
    let n = u.len().min(t.len());
    let (u, t) = (&u[..n], &t[..n]);
    for j in from..n {
        s -= u[j] * t[j];
    }
    s
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
fn real_avx(s: f64, u: &[f64], t: &[f64]) -> f64 {
    use std::arch::x86_64::*;
    let n = u.len().min(t.len());
    let mut acc = _mm_set_sd(s);
    let mut j = 0;
    while j + 4 <= n {
        // SAFETY: j + 4 ≤ n ≤ both lengths.
        let p = _mm256_mul_pd(unsafe { _mm256_loadu_pd(u.as_ptr().add(j)) }, unsafe { _mm256_loadu_pd(t.as_ptr().add(j)) });
        let (lo, hi) = (_mm256_castpd256_pd128(p), _mm256_extractf128_pd::<1>(p));
        acc = _mm_sub_sd(acc, lo);
        acc = _mm_sub_sd(acc, _mm_unpackhi_pd(lo, lo));
        acc = _mm_sub_sd(acc, hi);
        acc = _mm_sub_sd(acc, _mm_unpackhi_pd(hi, hi));
        j += 4;
    }
    real_scalar(_mm_cvtsd_f64(acc), u, t, j)
}

/// Σ_j u_j t_j from +0 in ascending order (real); `AVX` only from a function compiled with AVX.
#[inline(always)]
pub fn dot<const AVX: bool>(u: &[f64], t: &[f64]) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if AVX {
        // SAFETY: as in [`complex`].
        return unsafe { dot_avx(u, t) };
    }
    dot_scalar(0.0, u, t, 0)
}

#[inline(always)]
fn dot_scalar(mut s: f64, u: &[f64], t: &[f64], from: usize) -> f64 {
    let n = u.len().min(t.len());
    let (u, t) = (&u[..n], &t[..n]);
    for j in from..n {
        s += u[j] * t[j];
    }
    s
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
fn dot_avx(u: &[f64], t: &[f64]) -> f64 {
    use std::arch::x86_64::*;
    let n = u.len().min(t.len());
    let mut acc = _mm_set_sd(0.0);
    let mut j = 0;
    while j + 4 <= n {
        // SAFETY: j + 4 ≤ n ≤ both lengths.
        let p = _mm256_mul_pd(unsafe { _mm256_loadu_pd(u.as_ptr().add(j)) }, unsafe { _mm256_loadu_pd(t.as_ptr().add(j)) });
        let (lo, hi) = (_mm256_castpd256_pd128(p), _mm256_extractf128_pd::<1>(p));
        acc = _mm_add_sd(acc, lo);
        acc = _mm_add_sd(acc, _mm_unpackhi_pd(lo, lo));
        acc = _mm_add_sd(acc, hi);
        acc = _mm_add_sd(acc, _mm_unpackhi_pd(hi, hi));
        j += 4;
    }
    dot_scalar(_mm_cvtsd_f64(acc), u, t, j)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The AVX rows and dots equal the scalar ones to the bit, for every length 0 … 45 (remainders).
    #[test]
    fn avx_rows_match_the_scalar_rows() {
        if !crate::simd::test_can_run(crate::simd::Level::Avx2Fma, "dense rows: AVX against scalar") {
            return;
        }
        let f = |n: usize, s: f64| (0..n).map(|j| ((j as f64 + 1.0) * s).sin() * 10f64.powi(j as i32 % 7 - 3)).collect::<Vec<f64>>();
        for n in 0..46 {
            let (ur, ui, tr, ti) = (f(n, 0.7), f(n, 1.3), f(n, 2.1), f(n, 0.4));
            let (a, b) = (complex::<false>((0.3, -1.1), (&ur, &ui), (&tr, &ti)), complex::<true>((0.3, -1.1), (&ur, &ui), (&tr, &ti)));
            assert_eq!((a.0.to_bits(), a.1.to_bits()), (b.0.to_bits(), b.1.to_bits()), "complex, n = {n}");
            let (a, b) = (real::<false>(0.3, &ur, &tr), real::<true>(0.3, &ur, &tr));
            assert_eq!(a.to_bits(), b.to_bits(), "real, n = {n}");
            let (a, b) = (dot::<false>(&ur, &tr), dot::<true>(&ur, &tr));
            assert_eq!(a.to_bits(), b.to_bits(), "dot, n = {n}");
            let plain = ur.iter().zip(&tr).fold(0.0, |s, (&u, &t)| s + t * u);
            assert_eq!(a.to_bits(), plain.to_bits(), "dot as the plain sum, n = {n}");
        }
    }
}
