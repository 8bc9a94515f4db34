//! The rows of the back substitution of [`super::dense`]: s − Σ_j u_j t_j over j in ascending
//! order, one subtraction after the other (the order the results depend on). Complex, split:
//! s.re −= u.re t.re − u.im t.im and s.im −= u.re t.im + u.im t.re (the `num_complex` product).
//! (An AVX form that formed four products at a time earned at most 1 % of the monolithic run and
//! was removed by the SIMD policy, docs/performance.md.)

/// s − Σ_j u_j t_j, complex split.
#[inline(always)]
pub fn complex(s: (f64, f64), u: (&[f64], &[f64]), t: (&[f64], &[f64])) -> (f64, f64) {
    let ((mut sr, mut si), (ur, ui), (tr, ti)) = (s, u, t);
    let n = ur.len().min(ui.len()).min(tr.len()).min(ti.len());
    let (ur, ui, tr, ti) = (&ur[..n], &ui[..n], &tr[..n], &ti[..n]);
    for j in 0..n {
        sr -= ur[j] * tr[j] - ui[j] * ti[j];
        si -= ur[j] * ti[j] + ui[j] * tr[j];
    }
    (sr, si)
}

/// s − Σ_j u_j t_j, real.
#[inline(always)]
pub fn real(mut s: f64, u: &[f64], t: &[f64]) -> f64 {
    let n = u.len().min(t.len());
    let (u, t) = (&u[..n], &t[..n]);
    for j in 0..n {
        s -= u[j] * t[j];
    }
    s
}

/// Σ_j u_j t_j from +0 in ascending order (real).
#[inline(always)]
pub fn dot(u: &[f64], t: &[f64]) -> f64 {
    let n = u.len().min(t.len());
    let (u, t) = (&u[..n], &t[..n]);
    let mut s = 0.0;
    for j in 0..n {
        s += u[j] * t[j];
    }
    s
}
