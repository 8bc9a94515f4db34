//! The kernels of [`super::batch`] with a node's q vectors as one `[V; Q]`, Q a constant (1 ≤ q ≤ 8,
//! M ≤ 32 modes; [`per_q`] chooses): the loops over a node's vectors unrolled, one bounds check
//! per sweep instead of a slice per node and vector. Per entry the operations and their order are
//! those of the general kernels in `batch` (kept for q > 8), so the results are the same to the
//! bit (a test below compares the two).

use super::batch::{add, cmul, mul, sub, L, V};

/// One node: modes 0 … 4Q − 1, Q vectors of L lanes.
pub type N<const Q: usize> = [V; Q];

/// `$fixed` with `const $Q: usize` equal to `$q` when 1 ≤ q ≤ 8, `$any` otherwise.
macro_rules! per_q {
    ($q:expr, $Q:ident => $fixed:expr, _ => $any:expr) => {
        match $q {
            1 => { const $Q: usize = 1; $fixed }
            2 => { const $Q: usize = 2; $fixed }
            3 => { const $Q: usize = 3; $fixed }
            4 => { const $Q: usize = 4; $fixed }
            5 => { const $Q: usize = 5; $fixed }
            6 => { const $Q: usize = 6; $fixed }
            7 => { const $Q: usize = 7; $fixed }
            8 => { const $Q: usize = 8; $fixed }
            _ => $any,
        }
    };
}
pub(super) use per_q;

/// `v` (node-major, q = Q vectors per node) as nodes.
#[inline(always)]
pub fn view<const Q: usize>(v: &[V]) -> &[N<Q>] {
    v.as_chunks::<Q>().0
}

#[inline(always)]
pub fn view_mut<const Q: usize>(v: &mut [V]) -> &mut [N<Q>] {
    v.as_chunks_mut::<Q>().0
}

/// [`super::batch`]'s real Thomas sweep: x ← (σI − L_k)⁻¹ x with the factors (−l, 1/β, γ).
#[inline(always)]
pub fn sweep_real<const Q: usize>(lower: &[V], ib: &[V], gamma: &[V], x: &mut [V]) {
    let x = view_mut::<Q>(x);
    forward_real::<Q>(lower, ib, gamma, x, |x, i| x[i]);
}

/// [`sweep_real`] of `src` into `x` (its old values not read; as long as `src`): the same
/// operations, without a copy of `src` first.
#[inline(always)]
pub fn sweep_real_from<const Q: usize>(lower: &[V], ib: &[V], gamma: &[V], src: &[V], x: &mut [V]) {
    let src = view::<Q>(src);
    let x = &mut view_mut::<Q>(x)[..src.len()];
    forward_real::<Q>(lower, ib, gamma, x, |_, i| src[i]);
}

/// The real sweeps' forward elimination over the nodes of `x`, node i's right-hand side
/// `rhs(x, i)` (read before node i is written), then [`back_real`].
#[inline(always)]
fn forward_real<const Q: usize>(lower: &[V], ib: &[V], gamma: &[V], x: &mut [N<Q>], rhs: impl Fn(&[N<Q>], usize) -> N<Q>) {
    let n = x.len();
    if n == 0 {
        return;
    }
    let (lower, ib) = (&view::<Q>(lower)[..n], &view::<Q>(ib)[..n]);
    let mut p = rhs(x, 0);
    for j in 0..Q {
        p[j] = mul(p[j], ib[0][j]);
    }
    x[0] = p;
    for i in 1..n {
        let mut c = rhs(x, i);
        for j in 0..Q {
            c[j] = mul(sub(c[j], mul(p[j], lower[i][j])), ib[i][j]);
        }
        x[i] = c;
        p = c;
    }
    back_real::<Q>(&view::<Q>(gamma)[..n], x, p);
}

/// The back substitution of the real sweeps: from the last node's `last`, node by node down,
/// cur −= γ(i + 1) · next.
#[inline(always)]
fn back_real<const Q: usize>(gamma: &[N<Q>], x: &mut [N<Q>], last: N<Q>) {
    let mut p = last;
    let n = x.len().min(gamma.len());
    for i in (0..n.saturating_sub(1)).rev() {
        let mut c = x[i];
        for j in 0..Q {
            c[j] = sub(c[j], mul(gamma[i + 1][j], p[j]));
        }
        x[i] = c;
        p = c;
    }
}

/// The complex sweep, split storage (re, im).
#[inline(always)]
pub fn sweep_complex<const Q: usize>(lower: &[V], ib: [&[V]; 2], gamma: [&[V]; 2], x: [&mut [V]; 2]) {
    let [xr, xi] = x;
    let (xr, xi) = (view_mut::<Q>(xr), view_mut::<Q>(xi));
    let n = xr.len();
    if n == 0 {
        return;
    }
    let xi = &mut xi[..n];
    let lower = &view::<Q>(lower)[..n];
    let (br, bi) = (&view::<Q>(ib[0])[..n], &view::<Q>(ib[1])[..n]);
    let (gr, gi) = (&view::<Q>(gamma[0])[..n], &view::<Q>(gamma[1])[..n]);
    let (mut pr, mut pi) = (xr[0], xi[0]);
    for j in 0..Q {
        (pr[j], pi[j]) = cmul(pr[j], pi[j], br[0][j], bi[0][j]);
    }
    (xr[0], xi[0]) = (pr, pi);
    for i in 1..n {
        let (mut cr, mut ci) = (xr[i], xi[i]);
        for j in 0..Q {
            // (cur − prev·l) · (1/β)
            let l = lower[i][j];
            let (a, b) = (sub(cr[j], mul(pr[j], l)), sub(ci[j], mul(pi[j], l)));
            (cr[j], ci[j]) = cmul(a, b, br[i][j], bi[i][j]);
        }
        (xr[i], xi[i]) = (cr, ci);
        (pr, pi) = (cr, ci);
    }
    back_complex::<Q>((gr, gi), (xr, xi), (pr, pi));
}

/// [`sweep_complex`] of a real right-hand side `src` into (`xr`, `xi`) (their old values not
/// read; as long as `src`), with the same operations on a zero imaginary input (`0 − p·l`, the
/// literal zero as a stored one would be: the same bits) — no zeroed buffer to read and no copy
/// of `src`.
#[inline(always)]
pub fn sweep_complex_real_rhs<const Q: usize>(lower: &[V], ib: [&[V]; 2], gamma: [&[V]; 2], src: &[V], xr: &mut [V], xi: &mut [V]) {
    let src = view::<Q>(src);
    let n = src.len();
    let (xr, xi) = (&mut view_mut::<Q>(xr)[..n], &mut view_mut::<Q>(xi)[..n]);
    if n == 0 {
        return;
    }
    let lower = &view::<Q>(lower)[..n];
    let (br, bi) = (&view::<Q>(ib[0])[..n], &view::<Q>(ib[1])[..n]);
    let zero = [0.0; super::batch::L];
    let (mut pr, mut pi) = (src[0], [zero; Q]);
    for j in 0..Q {
        (pr[j], pi[j]) = cmul(pr[j], pi[j], br[0][j], bi[0][j]);
    }
    (xr[0], xi[0]) = (pr, pi);
    for i in 1..n {
        let (mut cr, mut ci) = (src[i], [zero; Q]);
        for j in 0..Q {
            let l = lower[i][j];
            let (a, b) = (sub(cr[j], mul(pr[j], l)), sub(ci[j], mul(pi[j], l)));
            (cr[j], ci[j]) = cmul(a, b, br[i][j], bi[i][j]);
        }
        (xr[i], xi[i]) = (cr, ci);
        (pr, pi) = (cr, ci);
    }
    let (gr, gi) = (&view::<Q>(gamma[0])[..n], &view::<Q>(gamma[1])[..n]);
    back_complex::<Q>((gr, gi), (xr, xi), (pr, pi));
}

/// The back substitution of the complex sweeps: from the last node's (re, im) `last`, node by
/// node down, cur −= γ(i + 1) · next (split storage).
#[inline(always)]
fn back_complex<const Q: usize>(gamma: (&[N<Q>], &[N<Q>]), x: (&mut [N<Q>], &mut [N<Q>]), last: (N<Q>, N<Q>)) {
    let ((gr, gi), (xr, xi), (mut pr, mut pi)) = (gamma, x, last);
    for i in (0..xr.len().saturating_sub(1)).rev() {
        let (mut cr, mut ci) = (xr[i], xi[i]);
        for j in 0..Q {
            // cur −= γ · next
            let (qr, qi) = cmul(gr[i + 1][j], gi[i + 1][j], pr[j], pi[j]);
            cr[j] = sub(cr[j], qr);
            ci[j] = sub(ci[j], qi);
        }
        (xr[i], xi[i]) = (cr, ci);
        (pr, pi) = (cr, ci);
    }
}

/// Per mode (Σ_i v(i, k) w0(i, k), Σ_i v(i, k) w1(i, k)), summed in the order of i from zero.
#[inline(always)]
pub fn dots2<const Q: usize>(v: &[V], w0: &[V], w1: &[V]) -> [N<Q>; 2] {
    let v = view::<Q>(v);
    let n = v.len();
    let (w0, w1) = (&view::<Q>(w0)[..n], &view::<Q>(w1)[..n]);
    let (mut a0, mut a1) = ([[0.0; L]; Q], [[0.0; L]; Q]);
    for i in 0..n {
        for j in 0..Q {
            a0[j] = add(a0[j], mul(v[i][j], w0[i][j]));
            a1[j] = add(a1[j], mul(v[i][j], w1[i][j]));
        }
    }
    [a0, a1]
}

/// x += c·s + r·x0 + d·x1 per node (s per mode, x0 and x1 the same in every lane), complex:
/// `x`, `s`, `x0`, `x1` as (re, im) and `u` = [c, r, d], each (re, im).
#[inline(always)]
pub fn combine_complex<const Q: usize>(x: [&mut [V]; 2], u: [[&[V]; 2]; 3], s: [&[V]; 2], x0: [V; 2], x1: [V; 2]) {
    let [xr, xi] = x;
    let (xr, xi) = (view_mut::<Q>(xr), view_mut::<Q>(xi));
    let n = xr.len();
    let xi = &mut xi[..n];
    let [c, r, d] = u.map(|p| p.map(|v| &view::<Q>(v)[..n]));
    let (sr, si) = (view::<Q>(s[0])[0], view::<Q>(s[1])[0]);
    let ([x0r, x0i], [x1r, x1i]) = (x0, x1);
    for i in 0..n {
        for j in 0..Q {
            let (csr, csi) = cmul(c[0][i][j], c[1][i][j], sr[j], si[j]);
            let (rxr, rxi) = cmul(r[0][i][j], r[1][i][j], x0r, x0i);
            let (dxr, dxi) = cmul(d[0][i][j], d[1][i][j], x1r, x1i);
            xr[i][j] = add(xr[i][j], add(add(csr, rxr), dxr));
            xi[i][j] = add(xi[i][j], add(add(csi, rxi), dxi));
        }
    }
}

/// [`combine_complex`] for real values.
#[inline(always)]
pub fn combine_real<const Q: usize>(x: &mut [V], u: [&[V]; 3], s: &[V], x0: V, x1: V) {
    let x = view_mut::<Q>(x);
    let n = x.len();
    let [c, r, d] = u.map(|v| &view::<Q>(v)[..n]);
    let s = view::<Q>(s)[0];
    for i in 0..n {
        for j in 0..Q {
            x[i][j] = add(x[i][j], add(add(mul(c[i][j], s[j]), mul(r[i][j], x0)), mul(d[i][j], x1)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::batch::{self, dots2_any, Split};
    use super::super::structured::{combine_complex_any, combine_real_any};
    use super::*;

    /// Deterministic values in (−1, 1) (no zeros, distinct per position).
    fn fill(n: usize, seed: u64) -> Vec<V> {
        let mut s = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
        (0..n)
            .map(|_| {
                std::array::from_fn(|_| {
                    s ^= s << 13;
                    s ^= s >> 7;
                    s ^= s << 17;
                    (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 0.999
                })
            })
            .collect()
    }

    fn bits(v: &[V]) -> Vec<u64> {
        v.iter().flatten().map(|x| x.to_bits()).collect()
    }

    /// Every fixed-Q kernel gives the general kernel's result to the bit.
    #[test]
    fn fixed_kernels_match_the_general_ones_bit_for_bit() {
        for q in 1..=8 {
            let nodes = 13;
            let n = nodes * q;
            let (lower, ibr, ibi, gr, gi) = (fill(n, 1), fill(n, 2), fill(n, 3), fill(n, 4), fill(n, 5));
            let (xr, xi) = (fill(n, 6), fill(n, 7));
            let (w0, w1) = (fill(n, 8), fill(n, 9));
            let u: Vec<Vec<V>> = (10..16).map(|s| fill(n, s)).collect();
            let (sr, si) = (fill(q, 16), fill(q, 17));
            let (x0, x1) = ([[0.3; L], [-0.7; L]], [[1.1; L], [0.2; L]]);
            per_q!(q, Q => {
                let (mut a, mut b) = (xr.clone(), xr.clone());
                sweep_real::<Q>(&lower, &ibr, &gr, &mut a);
                batch::sweep_real(q, &lower, &ibr, &gr, &mut b);
                assert_eq!(bits(&a), bits(&b), "real sweep, q = {q}");
                let (mut ar, mut ai, mut br, mut bi) = (xr.clone(), xi.clone(), xr.clone(), xi.clone());
                sweep_complex::<Q>(&lower, [&ibr, &ibi], [&gr, &gi], [&mut ar, &mut ai]);
                batch::sweep_complex(q, &lower, [&ibr, &ibi], [&gr, &gi], [&mut br, &mut bi]);
                assert_eq!((bits(&ar), bits(&ai)), (bits(&br), bits(&bi)), "complex sweep, q = {q}");
                let (mut ar, mut ai, mut br, mut bi) = (xr.clone(), vec![[0.0; L]; n], vec![[9.0; L]; n], vec![[-9.0; L]; n]);
                sweep_complex::<Q>(&lower, [&ibr, &ibi], [&gr, &gi], [&mut ar, &mut ai]);
                sweep_complex_real_rhs::<Q>(&lower, [&ibr, &ibi], [&gr, &gi], &xr, &mut br, &mut bi);
                assert_eq!((bits(&ar), bits(&ai)), (bits(&br), bits(&bi)), "complex sweep of a real rhs, q = {q}");
                let (mut a, mut b) = (xr.clone(), vec![[9.0; L]; n]);
                sweep_real::<Q>(&lower, &ibr, &gr, &mut a);
                sweep_real_from::<Q>(&lower, &ibr, &gr, &xr, &mut b);
                assert_eq!(bits(&a), bits(&b), "real sweep from a source, q = {q}");
                let v = Split { q, re: xr.clone(), im: xi.clone() };
                let mut acc = vec![[0.0; L]; 4 * q];
                let (p, r) = acc.split_at_mut(2 * q);
                let ((a0, a1), (a2, a3)) = (p.split_at_mut(q), r.split_at_mut(q));
                dots2_any(&v, [&w0, &w1], [a0, a1, a2, a3]);
                let [r0, r1] = dots2::<Q>(&xr, &w0, &w1);
                let [i0, i1] = dots2::<Q>(&xi, &w0, &w1);
                assert_eq!(bits(&acc), bits(&[r0, r1, i0, i1].concat()), "dots, q = {q}");
                let uc = [[&u[0][..], &u[1][..]], [&u[2][..], &u[3][..]], [&u[4][..], &u[5][..]]];
                let (mut ar, mut ai, mut br, mut bi) = (xr.clone(), xi.clone(), xr.clone(), xi.clone());
                combine_complex::<Q>([&mut ar, &mut ai], uc, [&sr, &si], x0, x1);
                combine_complex_any(q, [&mut br, &mut bi], uc, [&sr, &si], x0, x1);
                assert_eq!((bits(&ar), bits(&ai)), (bits(&br), bits(&bi)), "complex combination, q = {q}");
                let ur = [&u[0][..], &u[2][..], &u[4][..]];
                let (mut a, mut b) = (xr.clone(), xr.clone());
                combine_real::<Q>(&mut a, ur, &sr, x0[0], x1[0]);
                combine_real_any(q, &mut b, ur, &sr, x0[0], x1[0]);
                assert_eq!(bits(&a), bits(&b), "real combination, q = {q}");
            }, _ => unreachable!("q ≤ 8"));
        }
    }
}
