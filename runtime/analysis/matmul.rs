//! The small dense product C = A·B of the Magnus steps ([`super::floquet`]) and their matrix
//! exponential ([`super::expm`]): column-major slices, the caller's buffers, no packing and no
//! allocation (nalgebra's dynamic `gemm` goes through `matrixmultiply`, which packs both
//! operands into freshly allocated buffers on every call: 32 % of a population's instructions
//! for its 24 × 24 products, docs/performance.md "Populations").
//!
//! Each entry is one sum in a fixed order, c_ij = (…(a_i0 b_0j + a_i1 b_1j) …) + a_i,k−1 b_k−1,j
//! (the order of nalgebra's product of fixed-size matrices), whatever the tile it falls in
//! and whatever the instruction set: the tiles hold 8 × 4 or 24 × 4 (4 × 4, 1 × 4, … at the
//! edges) running sums in registers across p, plain multiplies
//! and adds (no FMA) that the compiler vectorises along the column. So the SSE2 build and the
//! AVX and AVX-512 ones ([`product`], under `crate::simd`'s `expm` kernel) give the same bits.

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OMatrix};

/// A product C (m × n) ← A (m × k) · B (k × n) on column-major slices.
pub type Product = fn(usize, usize, usize, &[f64], &[f64], &mut [f64]);

/// The product for the SIMD policy in force ([`crate::simd`], kernel `expm`): the AVX-512F build
/// of the loops (24-row tiles), the AVX build, or the portable one; the same bits from each. A
/// caller making many products (a monodromy, an exponential) asks once.
pub fn product() -> Product {
    #[cfg(target_arch = "x86_64")]
    if crate::simd::avx(crate::simd::Kernel::Expm) {
        return if crate::simd::avx512(crate::simd::Kernel::Expm) { mul_avx512 } else { mul_avx };
    }
    mul_portable
}

/// C ← A·B with [`product`]'s kernel (asked for at each call).
pub fn mul(m: usize, k: usize, n: usize, a: &[f64], b: &[f64], c: &mut [f64]) {
    product()(m, k, n, a, b, c)
}

/// c ← a·b for square nalgebra matrices: by `mul` for a dynamic size, by nalgebra's own loops
/// (unrolled on the stack) for a fixed one (the 1–3-state blocks of a field-free Floquet step).
#[inline(always)]
pub fn square<D: Dim>(mul: Product, c: &mut OMatrix<f64, D, D>, a: &OMatrix<f64, D, D>, b: &OMatrix<f64, D, D>)
where
    DefaultAllocator: Allocator<D, D>,
{
    if D::try_to_usize().is_some() {
        c.gemm(1.0, a, b, 0.0);
    } else {
        let n = a.nrows();
        mul(n, n, n, a.as_slice(), b.as_slice(), c.as_mut_slice());
    }
}

/// The tallest row tile for 16 vector registers (SSE2, AVX: 8 × 4 running sums in 16 or 8
/// registers) and for AVX-512's 32 (24 × 4 in 12): taller tiles keep more independent sums
/// in flight per loaded column of A.
const NARROW: usize = 8;
const WIDE: usize = 24;

fn mul_portable(m: usize, k: usize, n: usize, a: &[f64], b: &[f64], c: &mut [f64]) {
    mul_body::<NARROW>(m, k, n, a, b, c)
}

#[cfg(target_arch = "x86_64")]
fn mul_avx(m: usize, k: usize, n: usize, a: &[f64], b: &[f64], c: &mut [f64]) {
    #[target_feature(enable = "avx")]
    fn body(m: usize, k: usize, n: usize, a: &[f64], b: &[f64], c: &mut [f64]) {
        mul_body::<NARROW>(m, k, n, a, b, c)
    }
    // SAFETY: `product` returns this only when the CPU supports AVX (`simd::avx`); the body
    // is safe code.
    unsafe { body(m, k, n, a, b, c) }
}

#[cfg(target_arch = "x86_64")]
fn mul_avx512(m: usize, k: usize, n: usize, a: &[f64], b: &[f64], c: &mut [f64]) {
    #[target_feature(enable = "avx512f")]
    fn body(m: usize, k: usize, n: usize, a: &[f64], b: &[f64], c: &mut [f64]) {
        mul_body::<WIDE>(m, k, n, a, b, c)
    }
    // SAFETY: `product` returns this only when the CPU supports AVX-512F (`simd::avx512`);
    // the body is safe code.
    unsafe { body(m, k, n, a, b, c) }
}

/// The loops, with row tiles of `TALL` rows first ([`NARROW`] or [`WIDE`]; the bits do not
/// depend on it), inlined into each instruction set's build.
#[inline(always)]
fn mul_body<const TALL: usize>(m: usize, k: usize, n: usize, a: &[f64], b: &[f64], c: &mut [f64]) {
    assert!(a.len() == m * k && b.len() == k * n && c.len() == m * n, "matmul: {m}×{k} · {k}×{n} with slices {}, {}, {}", a.len(), b.len(), c.len());
    if m == 0 {
        return;
    }
    let mut j = 0;
    while j + 4 <= n {
        columns::<TALL, 4>(m, k, a, b, c, j);
        j += 4;
    }
    while j < n {
        columns::<TALL, 1>(m, k, a, b, c, j);
        j += 1;
    }
}

/// Columns j0 … j0 + C − 1 of C, in row tiles of `TALL` rows, then 8, 4 and 1.
#[inline(always)]
fn columns<const TALL: usize, const C: usize>(m: usize, k: usize, a: &[f64], b: &[f64], c: &mut [f64], j0: usize) {
    let mut i = 0;
    while TALL > 8 && i + TALL <= m {
        tile::<TALL, C>(m, k, a, b, c, i, j0);
        i += TALL;
    }
    while i + 8 <= m {
        tile::<8, C>(m, k, a, b, c, i, j0);
        i += 8;
    }
    while i + 4 <= m {
        tile::<4, C>(m, k, a, b, c, i, j0);
        i += 4;
    }
    while i < m {
        tile::<1, C>(m, k, a, b, c, i, j0);
        i += 1;
    }
}

/// C[i0 .. i0 + R, j0 .. j0 + C] with R × C running sums over p.
#[inline(always)]
fn tile<const R: usize, const C: usize>(m: usize, k: usize, a: &[f64], b: &[f64], c: &mut [f64], i0: usize, j0: usize) {
    let bcols: [&[f64]; C] = std::array::from_fn(|jj| &b[(j0 + jj) * k..(j0 + jj + 1) * k]);
    let mut acc = [[0.0f64; R]; C];
    let mut cols = a.chunks_exact(m).enumerate();
    if let Some((_, acol)) = cols.next() {
        let ap: &[f64; R] = acol[i0..i0 + R].try_into().expect("R rows");
        for jj in 0..C {
            let bv = bcols[jj][0];
            for r in 0..R {
                acc[jj][r] = ap[r] * bv;
            }
        }
    }
    for (p, acol) in cols {
        let ap: &[f64; R] = acol[i0..i0 + R].try_into().expect("R rows");
        for jj in 0..C {
            let bv = bcols[jj][p];
            for r in 0..R {
                acc[jj][r] += ap[r] * bv;
            }
        }
    }
    for (jj, col) in acc.iter().enumerate() {
        c[(j0 + jj) * m + i0..(j0 + jj) * m + i0 + R].copy_from_slice(col);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    fn pseudo(r: usize, c: usize, seed: f64) -> DMatrix<f64> {
        let mut x = seed;
        DMatrix::from_fn(r, c, |_, _| {
            x = (x * 9301.0 + 0.49297).fract();
            x - 0.5
        })
    }

    /// Every shape the tiles split differently (edges of 8, 4, 1 rows and 4, 1 columns): each
    /// entry equals the plain sequential sum bit for bit, and nalgebra's product to rounding.
    #[test]
    fn equals_the_sequential_sum_in_every_tile_shape() {
        for (m, k, n) in [(24, 24, 24), (21, 21, 21), (1, 1, 1), (3, 5, 2), (13, 7, 9), (8, 3, 4), (30, 24, 5)] {
            let (a, b) = (pseudo(m, k, 0.1234), pseudo(k, n, 0.5678));
            let run = |f: Product| {
                let mut c = vec![f64::NAN; m * n];
                f(m, k, n, a.as_slice(), b.as_slice(), &mut c);
                c
            };
            let c = run(product());
            let portable = run(mul_portable);
            let wide = run(|m, k, n, a, b, c| mul_body::<WIDE>(m, k, n, a, b, c));
            let reference = &a * &b;
            for i in 0..m {
                for j in 0..n {
                    let s = (1..k).fold(a[(i, 0)] * b[(0, j)], |s, p| s + a[(i, p)] * b[(p, j)]);
                    assert_eq!(c[j * m + i].to_bits(), s.to_bits(), "{m}×{k}·{k}×{n} at ({i}, {j})");
                    assert_eq!(portable[j * m + i].to_bits(), s.to_bits());
                    assert_eq!(wide[j * m + i].to_bits(), s.to_bits());
                    assert!((s - reference[(i, j)]).abs() <= 1e-14 * (k as f64), "({i}, {j})");
                }
            }
        }
    }
}
