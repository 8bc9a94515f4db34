//! The matrix exponential of the Magnus steps ([`super::floquet`]): scaling and squaring with
//! the [m/m] Padé approximants m ∈ {3, 5, 7, 9, 13} chosen by the 1-norm alone (Higham, SIAM J.
//! Matrix Anal. Appl. 26, 2005, Algorithm 2.3; θ_m from its Table 2.3).
//!
//! nalgebra's `exp` refines the degree choice with norm estimates of high matrix powers
//! (Al-Mohy & Higham 2009), which for the 24 × 24 blocks of a Floquet step costs more than the
//! approximant itself (issue 16, row 3). The 2005 choice may scale once more than needed for a
//! very non-normal matrix; the result agrees with nalgebra's to 1e-13 relative (unit test).

use nalgebra::allocator::Allocator;
use nalgebra::{DMatrix, DefaultAllocator, Dim, OMatrix, OVector};

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
    let n = a.nrows().max(1);
    a.as_slice().chunks_exact(n).map(|c| c.iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max)
}

/// exp(A) for a square matrix with finite entries.
pub fn expm(a: &DMatrix<f64>) -> DMatrix<f64> {
    expm_generic(a)
}

/// [`expm`] for any nalgebra dimension: the fixed sizes (the 3 × 3 mode blocks of a Floquet
/// step without a field) stay on the stack.
pub fn expm_generic<D: Dim>(a: &OMatrix<f64, D, D>) -> OMatrix<f64, D, D>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    let (d, _) = a.shape_generic();
    let mut work = ExpmWork::new(d);
    let mut out = OMatrix::<f64, D, D>::zeros_generic(d, d);
    expm_into(a, &mut work, &mut out);
    out
}

/// The buffers of [`expm_into`] (the balanced matrix, powers of A, the Padé numerator and
/// denominator) and the balancing of the previous call: a Floquet block keeps one across its
/// Magnus steps, so a step of a dense block allocates nothing and its balancing starts from the
/// previous step's.
pub struct ExpmWork<D: Dim>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    bal: OMatrix<f64, D, D>,
    /// D = diag(scale), powers of 2; `rsum`, `csum`, `l` are per-row/column buffers.
    scale: OVector<f64, D>,
    rsum: OVector<f64, D>,
    csum: OVector<f64, D>,
    l: OVector<f64, D>,
    pade: PadeWork<D>,
}

struct PadeWork<D: Dim>
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
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    pub fn new(d: D) -> Self {
        let z = || OMatrix::<f64, D, D>::zeros_generic(d, d);
        let v = |x: f64| OVector::<f64, D>::from_element_generic(d, nalgebra::Const::<1>, x);
        let pade = PadeWork { a2: z(), a4: z(), a6: z(), t: z(), u: z(), v: z() };
        ExpmWork { bal: z(), scale: v(1.0), rsum: v(0.0), csum: v(0.0), l: v(0.0), pade }
    }
}

/// One sweep of balancing by a diagonal similarity (Parlett & Reinsch 1969; LAPACK dgebal
/// without the permutations) on the column-major n × n `b`: for each i in turn, column i is
/// multiplied and row i divided by the power of 2 f that best equalises their off-diagonal
/// 1-norms, when that lowers their sum by 5 %; `scale[i]` is multiplied by f. Powers of 2 make
/// the similarity exact. One sweep per call: a Floquet block's next step continues from this
/// one's D ([`expm_into`]), so the sweeps of successive steps converge together.
#[inline(always)]
fn balance_sweep(n: usize, b: &mut [f64], scale: &mut [f64], rsum: &mut [f64], csum: &mut [f64]) {
    rsum.fill(0.0);
    for j in 0..n {
        let col = &b[j * n..(j + 1) * n];
        let mut c = 0.0;
        for (r, x) in rsum.iter_mut().zip(col) {
            *r += x.abs();
            c += x.abs();
        }
        csum[j] = c - col[j].abs();
    }
    for i in 0..n {
        rsum[i] -= b[i * n + i].abs();
    }
    for i in 0..n {
        let (c, r) = (csum[i], rsum[i]);
        if !(c > 0.0 && r > 0.0 && (c + r).is_finite()) {
            continue;
        }
        let (mut f, mut cc, mut rr) = (1.0, c, r);
        while cc < 0.5 * rr && f < 1e100 {
            (f, cc, rr) = (f * 2.0, cc * 2.0, rr * 0.5);
        }
        while cc >= 2.0 * rr && f > 1e-100 {
            (f, cc, rr) = (f * 0.5, cc * 0.5, rr * 2.0);
        }
        if f == 1.0 || cc + rr >= 0.95 * (c + r) {
            continue;
        }
        scale[i] *= f;
        let g = 1.0 / f; // exact: f is a power of 2
        // column i × f (the other rows' sums change by |b_ki| (f − 1)), row i × 1/f (the other
        // columns' by |b_ik| (1/f − 1))
        for (k, x) in b[i * n..(i + 1) * n].iter_mut().enumerate() {
            rsum[k] += x.abs() * (f - 1.0);
            *x *= f;
        }
        for k in 0..n {
            let x = &mut b[k * n + i];
            csum[k] += x.abs() * (g - 1.0);
            *x *= g;
        }
        // b_ii went through both (unchanged); its own sums are the ones tested
        rsum[i] = rr;
        csum[i] = cc;
    }
}

/// x ← Σ x + m_i c_i over `terms`, left to right (elementwise).
#[inline(always)]
fn add_scaled<D: Dim>(x: &mut OMatrix<f64, D, D>, terms: &[(&OMatrix<f64, D, D>, f64)])
where
    DefaultAllocator: Allocator<D, D>,
{
    for (m, c) in terms {
        for (a, b) in x.as_mut_slice().iter_mut().zip(m.as_slice()) {
            *a += b * c;
        }
    }
}

/// x ← Σ m_i c_i over `terms`, left to right (elementwise).
#[inline(always)]
fn set_scaled<D: Dim>(x: &mut OMatrix<f64, D, D>, first: (&OMatrix<f64, D, D>, f64), rest: &[(&OMatrix<f64, D, D>, f64)])
where
    DefaultAllocator: Allocator<D, D>,
{
    for (a, b) in x.as_mut_slice().iter_mut().zip(first.0.as_slice()) {
        *a = b * first.1;
    }
    add_scaled(x, rest);
}

/// x_ii ← x_ii + c.
#[inline(always)]
fn add_diagonal<D: Dim>(x: &mut OMatrix<f64, D, D>, c: f64)
where
    DefaultAllocator: Allocator<D, D>,
{
    for i in 0..x.nrows() {
        x[(i, i)] += c;
    }
}

/// `out` ← exp(A) (see the module doc), with the buffers of `w`; every product is one gemm.
/// A is balanced first ([`balance_sweep`], continuing from the previous call's D):
/// exp(A) = D exp(D⁻¹AD) D⁻¹. With AVX (`crate::simd`, kernel `expm`) the elementwise loops
/// and the Padé solve run 4 wide (the same operations in the same order: the result does not
/// depend on it).
pub fn expm_into<D: Dim>(a: &OMatrix<f64, D, D>, w: &mut ExpmWork<D>, out: &mut OMatrix<f64, D, D>)
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    #[cfg(target_arch = "x86_64")]
    if a.nrows() > 4 && crate::simd::avx(crate::simd::Kernel::Expm) {
        // SAFETY: the CPU supports AVX (`simd::avx` checked); the body is safe code.
        return unsafe { expm_into_avx(a, w, out) };
    }
    expm_body(a, w, out)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn expm_into_avx<D: Dim>(a: &OMatrix<f64, D, D>, w: &mut ExpmWork<D>, out: &mut OMatrix<f64, D, D>)
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    expm_body(a, w, out)
}

#[inline(always)]
fn expm_body<D: Dim>(a: &OMatrix<f64, D, D>, w: &mut ExpmWork<D>, out: &mut OMatrix<f64, D, D>)
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    let n = a.nrows();
    let (sc, inv) = (w.scale.as_mut_slice(), w.l.as_mut_slice());
    for (v, s) in inv.iter_mut().zip(sc.iter()) {
        *v = 1.0 / s; // exact: powers of 2
    }
    for ((bc, ac), dj) in w.bal.as_mut_slice().chunks_exact_mut(n).zip(a.as_slice().chunks_exact(n)).zip(sc.iter()) {
        for ((b, x), di) in bc.iter_mut().zip(ac).zip(inv.iter()) {
            *b = x * dj * di;
        }
    }
    balance_sweep(n, w.bal.as_mut_slice(), sc, w.rsum.as_mut_slice(), w.csum.as_mut_slice());
    pade_exp(&w.bal, &mut w.pade, w.l.as_mut_slice(), out);
    let sc = w.scale.as_slice();
    for (oc, dj) in out.as_mut_slice().chunks_exact_mut(n).zip(sc.iter()) {
        let g = 1.0 / dj;
        for (o, di) in oc.iter_mut().zip(sc.iter()) {
            *o *= di * g;
        }
    }
}

/// `out` ← exp(A) by scaling, Padé and squaring (module doc); `l` is a length-n buffer.
#[inline(always)]
fn pade_exp<D: Dim>(a: &OMatrix<f64, D, D>, w: &mut PadeWork<D>, l: &mut [f64], out: &mut OMatrix<f64, D, D>)
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
            w.t.fill(0.0);
            w.v.fill(0.0);
            add_diagonal(&mut w.t, b[1]);
            add_diagonal(&mut w.v, b[0]);
            w.a4.copy_from(&w.a2);
            for j in 1..=m / 2 {
                if j > 1 {
                    w.a6.gemm(1.0, &w.a4, &w.a2, 0.0);
                    std::mem::swap(&mut w.a4, &mut w.a6);
                }
                add_scaled(&mut w.t, &[(&w.a4, b[2 * j + 1])]);
                add_scaled(&mut w.v, &[(&w.a4, b[2 * j])]);
            }
            w.u.gemm(1.0, a, &w.t, 0.0);
            pade_solve(a.nrows(), w.u.as_mut_slice(), w.v.as_mut_slice(), l);
            out.copy_from(&w.v);
            return;
        }
    }
    let s = if eta > THETA_13 { (eta / THETA_13).log2().ceil() as i32 } else { 0 };
    let scale = 0.5f64.powi(s);
    // out holds the scaled A until the end
    for (o, x) in out.as_mut_slice().iter_mut().zip(a.as_slice()) {
        *o = x * scale;
    }
    for x in w.a2.as_mut_slice() {
        *x *= scale * scale;
    }
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
    pade_solve(a.nrows(), w.u.as_mut_slice(), w.v.as_mut_slice(), l);
    for _ in 0..s {
        w.t.gemm(1.0, &w.v, &w.v, 0.0);
        std::mem::swap(&mut w.t, &mut w.v);
    }
    out.copy_from(&w.v);
}

/// q ← (V − U)⁻¹ (V + U) for column-major n × n p = U, q = V, by Gauss–Jordan elimination
/// with partial pivoting on [V − U | V + U] (p is overwritten): at each pivot c every later
/// column of P and every column of Q loses f times column c of P (its pivot entry zeroed, the
/// rows kept in `l`), f its entry in the pivot row divided by the pivot. Every inner loop runs
/// down a whole contiguous column (vectorised; 1.5 n³ multiply-adds, against 4/3 n³ for LU and
/// two triangular solves in short column pieces).
#[inline(always)]
fn pade_solve(n: usize, p: &mut [f64], q: &mut [f64], l: &mut [f64]) {
    for (pi, qi) in p.iter_mut().zip(q.iter_mut()) {
        (*pi, *qi) = (*qi - *pi, *qi + *pi);
    }
    for c in 0..n {
        let col = &p[c * n..(c + 1) * n];
        let piv = (c..n).fold(c, |b, r| if col[r].abs() > col[b].abs() { r } else { b });
        if piv != c {
            for k in c..n {
                p.swap(k * n + piv, k * n + c);
            }
            for k in 0..n {
                q.swap(k * n + piv, k * n + c);
            }
        }
        let d = p[c * n + c];
        l.copy_from_slice(&p[c * n..(c + 1) * n]);
        l[c] = 0.0;
        let eliminate = |x: &mut [f64]| {
            let f = x[c] / d;
            for (xi, li) in x.iter_mut().zip(l.iter()) {
                *xi -= li * f;
            }
            x[c] = f;
        };
        p[(c + 1) * n..].chunks_exact_mut(n).for_each(eliminate);
        q.chunks_exact_mut(n).for_each(eliminate);
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

    /// A badly scaled oscillator block (ȧ' = −ω² a − γ ȧ + c b, a stiff b row) as in a Floquet
    /// step of the coupled modes: balancing (continued over calls with one `ExpmWork`, as a
    /// monodromy does) leaves exp(A) equal to nalgebra's, whose 1-norm choice squares more.
    #[test]
    fn balanced_exponential_of_a_badly_scaled_oscillator() {
        let mut work = ExpmWork::new(nalgebra::Dyn(6));
        let mut out = DMatrix::zeros(6, 6);
        for step in 0..12 {
            let h = 1e-4 * (1.0 + step as f64);
            let mut a = DMatrix::zeros(6, 6);
            for (m, (w, g)) in [(2e3, 30.0), (7e2, 9.0)].into_iter().enumerate() {
                // two shape modes' (a, ȧ, b) rows of A(t)
                use crate::model::layout::StateLayout as L;
                let (ia, iad, ib) = (L::x_a(m), L::x_adot(m), L::x_b(m));
                a[(ia, iad)] = 1.0;
                a[(iad, ia)] = -w * w;
                a[(iad, iad)] = -g;
                a[(iad, ib)] = 4e2;
                a[(ib, ia)] = 5.0;
                a[(ib, ib)] = -4e3;
                a[(iad, L::x_a((m + 1) % 2))] = 0.3 * w * w; // the k ± 2 coupling
            }
            let a = a * h;
            expm_into(&a, &mut work, &mut out);
            let theirs = a.clone().exp();
            let err = (&out - &theirs).norm() / theirs.norm();
            assert!(err < 1e-12, "h = {h}: relative difference {err:e}");
        }
        // the scaling found is not the identity (the test exercises the balanced path)
        assert!(work.scale.iter().any(|&s| s != 1.0));
    }
}
