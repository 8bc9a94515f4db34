//! The matrix exponential of the Magnus steps ([`super::floquet`]): scaling and squaring with
//! the [m/m] Padé approximants m ∈ {3, 5, 7, 9, 13} chosen by the 1-norm alone (Higham, SIAM J.
//! Matrix Anal. Appl. 26, 2005, Algorithm 2.3; θ_m from its Table 2.3).
//!
//! nalgebra's `exp` refines the degree choice with norm estimates of high matrix powers
//! (Al-Mohy & Higham 2009), which for the 24 × 24 blocks of a Floquet step costs more than the
//! approximant itself (issue 16, row 3). The 2005 choice may scale once more than needed for a
//! very non-normal matrix; the result agrees with nalgebra's to 1e-13 relative (unit test).

use nalgebra::allocator::Allocator;
use nalgebra::{DMatrix, DefaultAllocator, Dim, OMatrix};

const THETA: [(usize, f64); 4] =
    [(3, 1.495585217958292e-2), (5, 2.539398330063230e-1), (7, 9.504178996162932e-1), (9, 2.097847961257068)];
const THETA_13: f64 = 5.371920351148152;

const B3: [f64; 4] = [120.0, 60.0, 12.0, 1.0];
const B5: [f64; 6] = [30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0];
const B7: [f64; 8] = [17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0];
const B9: [f64; 10] =
    [17643225600.0, 8821612800.0, 2075673600.0, 302702400.0, 30270240.0, 2162160.0, 110880.0, 3960.0, 90.0, 1.0];
const B13: [f64; 14] = [
    64764752532480000.0,
    32382376266240000.0,
    7771770303897600.0,
    1187353796428800.0,
    129060195264000.0,
    10559470521600.0,
    670442572800.0,
    33522128640.0,
    1323241920.0,
    40840800.0,
    960960.0,
    16380.0,
    182.0,
    1.0,
];

fn norm1<D: Dim>(a: &OMatrix<f64, D, D>) -> f64
where
    DefaultAllocator: Allocator<D, D>,
{
    a.column_iter().map(|c| c.iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max)
}

/// exp(A) for a square matrix with finite entries.
pub fn expm(a: &DMatrix<f64>) -> DMatrix<f64> {
    expm_generic(a)
}

/// [`expm`] for any nalgebra dimension: the fixed sizes (the 3 × 3 mode blocks of a Floquet
/// step without a field) stay on the stack.
pub fn expm_generic<D: Dim>(a: &OMatrix<f64, D, D>) -> OMatrix<f64, D, D>
where
    DefaultAllocator: Allocator<D, D>,
{
    let (d, _) = a.shape_generic();
    let mut work = ExpmWork::new(d);
    let mut out = OMatrix::<f64, D, D>::zeros_generic(d, d);
    expm_into(a, &mut work, &mut out);
    out
}

/// The buffers of [`expm_into`] (powers of A, the Padé numerator and denominator): a Floquet
/// block keeps one across its Magnus steps, so a step of a dense block allocates nothing.
pub struct ExpmWork<D: Dim>
where
    DefaultAllocator: Allocator<D, D>,
{
    a2: OMatrix<f64, D, D>,
    a4: OMatrix<f64, D, D>,
    a6: OMatrix<f64, D, D>,
    t: OMatrix<f64, D, D>,
    u: OMatrix<f64, D, D>,
    v: OMatrix<f64, D, D>,
}

impl<D: Dim> ExpmWork<D>
where
    DefaultAllocator: Allocator<D, D>,
{
    pub fn new(d: D) -> Self {
        let z = || OMatrix::<f64, D, D>::zeros_generic(d, d);
        ExpmWork { a2: z(), a4: z(), a6: z(), t: z(), u: z(), v: z() }
    }
}

/// x ← Σ x + m_i c_i over `terms`, left to right (elementwise).
fn add_scaled<D: Dim>(x: &mut OMatrix<f64, D, D>, terms: &[(&OMatrix<f64, D, D>, f64)])
where
    DefaultAllocator: Allocator<D, D>,
{
    for (m, c) in terms {
        x.zip_apply(*m, |a, b| *a += b * c);
    }
}

/// x ← Σ m_i c_i over `terms`, left to right (elementwise).
fn set_scaled<D: Dim>(x: &mut OMatrix<f64, D, D>, first: (&OMatrix<f64, D, D>, f64), rest: &[(&OMatrix<f64, D, D>, f64)])
where
    DefaultAllocator: Allocator<D, D>,
{
    x.zip_apply(first.0, |a, b| *a = b * first.1);
    add_scaled(x, rest);
}

/// x_ii ← x_ii + c.
fn add_diagonal<D: Dim>(x: &mut OMatrix<f64, D, D>, c: f64)
where
    DefaultAllocator: Allocator<D, D>,
{
    for i in 0..x.nrows() {
        x[(i, i)] += c;
    }
}

/// `out` ← exp(A) (see the module doc), with the buffers of `w`; every product is one gemm.
pub fn expm_into<D: Dim>(a: &OMatrix<f64, D, D>, w: &mut ExpmWork<D>, out: &mut OMatrix<f64, D, D>)
where
    DefaultAllocator: Allocator<D, D>,
{
    let eta = norm1(a);
    w.a2.gemm(1.0, a, a, 0.0);
    // Low degrees: U = A Σ b_{2j+1} A^{2j}, V = Σ b_{2j} A^{2j} (a4 holds the running power).
    for &(m, theta) in &THETA {
        if eta <= theta {
            let b: &[f64] = match m {
                3 => &B3,
                5 => &B5,
                7 => &B7,
                _ => &B9,
            };
            w.a4.fill_with_identity();
            w.t.fill(0.0);
            w.v.fill(0.0);
            add_diagonal(&mut w.t, b[1]);
            add_diagonal(&mut w.v, b[0]);
            for j in 1..=m / 2 {
                w.a6.gemm(1.0, &w.a4, &w.a2, 0.0);
                std::mem::swap(&mut w.a4, &mut w.a6);
                add_scaled(&mut w.t, &[(&w.a4, b[2 * j + 1])]);
                add_scaled(&mut w.v, &[(&w.a4, b[2 * j])]);
            }
            w.u.gemm(1.0, a, &w.t, 0.0);
            pade_solve(&mut w.u, &mut w.v);
            out.copy_from(&w.v);
            return;
        }
    }
    let s = if eta > THETA_13 { (eta / THETA_13).log2().ceil() as i32 } else { 0 };
    let scale = 0.5f64.powi(s);
    // out holds the scaled A until the end
    out.zip_apply(a, |o, x| *o = x * scale);
    w.a2.apply(|x| *x *= scale * scale);
    w.a4.gemm(1.0, &w.a2, &w.a2, 0.0);
    w.a6.gemm(1.0, &w.a4, &w.a2, 0.0);
    let b = &B13;
    let (a2, a4, a6) = (&w.a2, &w.a4, &w.a6);
    set_scaled(&mut w.t, (a6, b[13]), &[(a4, b[11]), (a2, b[9])]);
    w.v.gemm(1.0, a6, &w.t, 0.0);
    add_scaled(&mut w.v, &[(a6, b[7]), (a4, b[5]), (a2, b[3])]);
    add_diagonal(&mut w.v, b[1]);
    w.u.gemm(1.0, &*out, &w.v, 0.0);
    set_scaled(&mut w.t, (a6, b[12]), &[(a4, b[10]), (a2, b[8])]);
    w.v.gemm(1.0, a6, &w.t, 0.0);
    add_scaled(&mut w.v, &[(a6, b[6]), (a4, b[4]), (a2, b[2])]);
    add_diagonal(&mut w.v, b[0]);
    pade_solve(&mut w.u, &mut w.v);
    for _ in 0..s {
        w.t.gemm(1.0, &w.v, &w.v, 0.0);
        std::mem::swap(&mut w.t, &mut w.v);
    }
    out.copy_from(&w.v);
}

/// v ← (V − U)⁻¹ (V + U) by Gaussian elimination with partial pivoting, column-oriented on the
/// column-major storage (every inner loop runs down a contiguous column); u is overwritten.
fn pade_solve<D: Dim>(u: &mut OMatrix<f64, D, D>, v: &mut OMatrix<f64, D, D>)
where
    DefaultAllocator: Allocator<D, D>,
{
    let n = u.nrows();
    let (p, q) = (u.as_mut_slice(), v.as_mut_slice());
    for (pi, qi) in p.iter_mut().zip(q.iter_mut()) {
        (*pi, *qi) = (*qi - *pi, *qi + *pi);
    }
    for c in 0..n {
        let piv = (c..n).fold(c, |b, r| if p[c * n + r].abs() > p[c * n + b].abs() { r } else { b });
        if piv != c {
            for k in 0..n {
                p.swap(k * n + piv, k * n + c);
                q.swap(k * n + piv, k * n + c);
            }
        }
        let d = p[c * n + c];
        for r in c + 1..n {
            p[c * n + r] /= d;
        }
        // Column c holds the multipliers l_r (r > c); update every later column of P and all of Q.
        let (left, right) = p.split_at_mut((c + 1) * n);
        let l = &left[c * n + c + 1..c * n + n];
        for col in right.chunks_exact_mut(n) {
            let f = col[c];
            if f != 0.0 {
                for (x, li) in col[c + 1..].iter_mut().zip(l) {
                    *x -= li * f;
                }
            }
        }
        for col in q.chunks_exact_mut(n) {
            let f = col[c];
            if f != 0.0 {
                for (x, li) in col[c + 1..].iter_mut().zip(l) {
                    *x -= li * f;
                }
            }
        }
    }
    // Back substitution with U (upper part of P), for every column of Q at each pivot c: per
    // column the operations and their order are those of a column-by-column substitution, but
    // the n divisions of one pivot are independent (no chain of dependent divisions).
    for c in (0..n).rev() {
        let d = p[c * n + c];
        let u = &p[c * n..c * n + c];
        for col in q.chunks_exact_mut(n) {
            let x = col[c] / d;
            col[c] = x;
            if x != 0.0 {
                for (v, ur) in col[..c].iter_mut().zip(u) {
                    *v -= ur * x;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_nalgebra_over_every_degree() {
        // A deterministic pseudo-random matrix scaled through every θ range (and beyond θ_13).
        let n = 24;
        let mut x = 0.123456789f64;
        let base = DMatrix::from_fn(n, n, |_, _| {
            x = (x * 9301.0 + 0.49297).fract();
            x - 0.5
        });
        for scale in [1e-4, 1e-2, 0.05, 0.2, 0.5, 2.0, 20.0, 200.0] {
            let a = &base * (scale / norm1(&base)) * 4.0;
            let ours = expm(&a);
            let theirs = a.clone().exp();
            let err = (&ours - &theirs).norm() / theirs.norm();
            assert!(err < 1e-13, "‖A‖₁ = {}: relative difference {err:e}", norm1(&a));
        }
        // The stack-allocated 3 × 3 path (the mode blocks of a field-free Floquet step).
        let b3 = nalgebra::Matrix3::from_fn(|i, j| base[(i, j)]);
        for scale in [1e-3, 0.1, 1.0, 5.0, 60.0] {
            let a = b3 * (scale / norm1(&b3));
            let (ours, theirs) = (expm_generic(&a), a.exp());
            let err = (ours - theirs).norm() / theirs.norm();
            assert!(err < 1e-13, "3 × 3, ‖A‖₁ = {scale}: relative difference {err:e}");
        }
        // A diagonal matrix with a stiff entry (exp(−30) after 3 squarings: 4e-14 relative).
        let d = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![-30.0, 0.5, 1e-3]));
        let e = expm(&d);
        for (i, l) in [-30.0f64, 0.5, 1e-3].iter().enumerate() {
            assert!((e[(i, i)] - l.exp()).abs() <= 1e-13 * l.exp(), "{} vs {}", e[(i, i)], l.exp());
        }
    }
}
