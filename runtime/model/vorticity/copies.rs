//! The copies of the structured solve ([`super::structured`]) between the state layout (mode
//! after mode: b_T,k = T_1 … T_ni of mode k after its R-independent entries) and the node-major
//! split lanes of [`super::batch`] (entry (i, k) at `[i·q + k/L][k % L]`).
//!
//! The fixed-Q kernels move four modes at a time: node i's entries of the modes of one vector
//! are read from the four mode rows and written as one vector (and back), instead of one scalar
//! store per entry. Pure data movement, so the results are the entry-by-entry copies' to the bit
//! (a test below compares them).

use super::batch::{Lane, Split, L, V};
use super::nodes;
use crate::model::layout::StateLayout;

/// The T rows of the state `b` (2 + M·nb entries), mode by mode: `ni` entries from offset 3 of
/// each block of nb after R, Ṙ.
#[inline(always)]
fn t_rows<T>(b: &[T], nb: usize, ni: usize) -> impl Iterator<Item = &[T]> {
    const T0: usize = StateLayout::AMPLITUDES;
    b[StateLayout::RADIAL..].chunks_exact(nb).map(move |blk| &blk[T0..T0 + ni])
}

#[inline(always)]
fn t_rows_mut<T>(b: &mut [T], nb: usize, ni: usize) -> impl Iterator<Item = &mut [T]> {
    const T0: usize = StateLayout::AMPLITUDES;
    b[StateLayout::RADIAL..].chunks_exact_mut(nb).map(move |blk| &mut blk[T0..T0 + ni])
}

/// b_T,k (mode-major in the state `b`) into the node-major split copy `xt`, with the nodes as
/// `[V; Q]` ([`nodes`]); lanes past M are not written.
#[inline(always)]
pub fn copy_in<const Q: usize, T: Lane>(b: &[T], nb: usize, m: usize, xt: &mut Split) {
    let xr = nodes::view_mut::<Q>(&mut xt.re);
    let ni = xr.len();
    let xi = nodes::view_mut::<Q>(&mut xt.im);
    let mut rows = t_rows(b, nb, ni).take(m);
    for v in 0..Q {
        if (v + 1) * L <= m {
            let src: [&[T]; L] = std::array::from_fn(|_| rows.next().unwrap_or(&[]));
            let src = src.map(|s| &s[..ni]);
            if T::CPLX {
                let xi = &mut xi[..ni];
                for i in 0..ni {
                    let p: [(f64, f64); L] = std::array::from_fn(|j| src[j][i].parts());
                    xr[i][v] = p.map(|x| x.0);
                    xi[i][v] = p.map(|x| x.1);
                }
            } else {
                for i in 0..ni {
                    xr[i][v] = std::array::from_fn(|j| src[j][i].parts().0);
                }
            }
        } else {
            for (lane, src) in rows.by_ref().enumerate() {
                for (i, &x) in src.iter().enumerate() {
                    let (re, im) = x.parts();
                    xr[i][v][lane] = re;
                    if T::CPLX {
                        xi[i][v][lane] = im;
                    }
                }
            }
        }
    }
}

/// [`copy_in`] for any number of vectors per node, entry by entry.
#[inline(always)]
pub fn copy_in_any<T: Lane>(b: &[T], nb: usize, m: usize, xt: &mut Split) {
    let q = xt.q;
    let ni = xt.re.len() / q.max(1);
    for (k, src) in t_rows(b, nb, ni).take(m).enumerate() {
        let (v, lane) = (k / L, k % L);
        for (i, &x) in src.iter().enumerate() {
            let (re, im) = x.parts();
            xt.re[i * q + v][lane] = re;
            if T::CPLX {
                xt.im[i * q + v][lane] = im;
            }
        }
    }
}

/// The node-major `xt` back into b_T,k.
#[inline(always)]
pub fn copy_out<const Q: usize, T: Lane>(xt: &Split, nb: usize, m: usize, b: &mut [T]) {
    let xr = nodes::view::<Q>(&xt.re);
    let ni = xr.len();
    let xi = nodes::view::<Q>(&xt.im);
    let mut rows = t_rows_mut(b, nb, ni).take(m);
    for v in 0..Q {
        if (v + 1) * L <= m {
            let mut dst: [&mut [T]; L] = std::array::from_fn(|_| rows.next().unwrap_or(&mut []));
            for d in dst.iter_mut() {
                *d = &mut std::mem::take(d)[..ni];
            }
            if T::CPLX {
                let xi = &xi[..ni];
                for i in 0..ni {
                    let (r, im): (V, V) = (xr[i][v], xi[i][v]);
                    for j in 0..L {
                        dst[j][i] = T::from_parts(r[j], im[j]);
                    }
                }
            } else {
                for i in 0..ni {
                    let r: V = xr[i][v];
                    for j in 0..L {
                        dst[j][i] = T::from_parts(r[j], 0.0);
                    }
                }
            }
        } else {
            for (lane, dst) in rows.by_ref().enumerate() {
                for (i, o) in dst.iter_mut().enumerate() {
                    *o = T::from_parts(xr[i][v][lane], if T::CPLX { xi[i][v][lane] } else { 0.0 });
                }
            }
        }
    }
}

/// [`copy_out`] for any number of vectors per node, entry by entry.
#[inline(always)]
pub fn copy_out_any<T: Lane>(xt: &Split, nb: usize, m: usize, b: &mut [T]) {
    let q = xt.q;
    let ni = xt.re.len() / q.max(1);
    for (k, dst) in t_rows_mut(b, nb, ni).take(m).enumerate() {
        let (v, lane) = (k / L, k % L);
        for (i, o) in dst.iter_mut().enumerate() {
            *o = T::from_parts(xt.re[i * q + v][lane], if T::CPLX { xt.im[i * q + v][lane] } else { 0.0 });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::nodes::per_q;
    use super::*;
    use nalgebra::Complex;

    /// The four-mode copies give the entry-by-entry ones' result to the bit, both ways, for M
    /// with and without a partial last vector (padding lanes untouched), real and complex.
    #[test]
    fn vector_copies_match_the_entry_copies() {
        let ni = 11;
        for m in [1usize, 4, 7, 8, 9, 13] {
            let (lay, q) = (StateLayout::monolithic(m, ni), m.div_ceil(L));
            let (n, nb) = (lay.dim(), lay.block());
            let bc: Vec<Complex<f64>> = (0..n).map(|i| Complex::new(i as f64 * 0.5 - 3.0, (i as f64).sin())).collect();
            let br: Vec<f64> = bc.iter().map(|c| c.im).collect();
            let fresh = |cplx: bool| Split { q, re: vec![[7.0; L]; ni * q], im: if cplx { vec![[-7.0; L]; ni * q] } else { Vec::new() } };
            let bits = |s: &Split| s.re.iter().chain(&s.im).flatten().map(|x| x.to_bits()).collect::<Vec<u64>>();
            per_q!(q, Q => {
                let (mut a, mut b) = (fresh(true), fresh(true));
                copy_in::<Q, _>(&bc, nb, m, &mut a);
                copy_in_any(&bc, nb, m, &mut b);
                assert_eq!(bits(&a), bits(&b), "complex in, M = {m}");
                let (mut oa, mut ob) = (vec![Complex::new(1.5, 2.5); n], vec![Complex::new(1.5, 2.5); n]);
                copy_out::<Q, _>(&a, nb, m, &mut oa);
                copy_out_any(&a, nb, m, &mut ob);
                assert_eq!(oa, ob, "complex out, M = {m}");
                let nodes = |b: &[Complex<f64>]| (0..m).flat_map(|k| b[lay.node_range(k)].to_vec()).collect::<Vec<_>>();
                assert_eq!(nodes(&oa), nodes(&bc), "round trip, M = {m}");
                let (mut a, mut b) = (fresh(false), fresh(false));
                copy_in::<Q, _>(&br, nb, m, &mut a);
                copy_in_any(&br, nb, m, &mut b);
                assert_eq!(bits(&a), bits(&b), "real in, M = {m}");
                let (mut oa, mut ob) = (vec![0.25; n], vec![0.25; n]);
                copy_out::<Q, _>(&a, nb, m, &mut oa);
                copy_out_any(&a, nb, m, &mut ob);
                assert_eq!(oa, ob, "real out, M = {m}");
            }, _ => unreachable!("q ≤ 8"));
        }
    }
}
