//! The Thomas factors of the M tridiagonal matrices σI − L_k ([`super::batch::TriBatch`]) computed
//! node after node with the modes as lanes, from the rows of L_k transposed once per Jacobian
//! ([`TriRows`]) instead of gathered mode by mode in every factorisation.
//!
//! Per entry the operations and their order are those of the scalar recurrence on `T` (f64 or
//! `num_complex::Complex<f64>`): β_0 = σ − d_0, γ_i = (1/β_{i−1})·(−u_{i−1}),
//! β_i = (σ − d_i) − γ_i·(−l_i), and 1/β as `num_complex` divides, ((1·c + 0·d)/|β|²,
//! (0·c − 1·d)/|β|²) for β = c + i d; so the factors are the scalar ones to the bit (a test below
//! compares them with the mode-by-mode recurrence).

use super::batch::{add, mul, sub, Lane, L, V};
use super::operator::Rows;
use super::pool;
use std::rc::Rc;

/// The rows of the M matrices L_k node-major in lanes (entry (i, k) at `[i·q + k/L][k % L]`,
/// padding lanes zero): −l_i (the sub-diagonal, zero at node 0), d_i, and −u_{i−1} (the
/// super-diagonal of the node before, zero at node 0).
pub struct TriRows {
    pub m: usize,
    pub q: usize,
    pub neg_lower: Rc<Vec<V>>,
    pub diag: Vec<V>,
    pub neg_upper_prev: Vec<V>,
}

impl TriRows {
    /// Built node after node with pushes (every vector written once, no zeroed buffer).
    pub fn new(rows: &[Rows], ni: usize) -> Self {
        let m = rows.len();
        let q = m.div_ceil(L);
        let n = ni * q;
        let (mut neg_lower, mut diag, mut neg_upper_prev) = (Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n));
        for i in 0..ni {
            for v in 0..q {
                let (mut l, mut d, mut u) = ([0.0; L], [0.0; L], [0.0; L]);
                for (j, r) in rows[v * L..m.min((v + 1) * L)].iter().enumerate() {
                    d[j] = r.diag[i];
                    if i > 0 {
                        (l[j], u[j]) = (-r.lower[i], -r.upper[i - 1]);
                    }
                }
                neg_lower.push(l);
                diag.push(d);
                neg_upper_prev.push(u);
            }
        }
        Self { m, q, neg_lower: Rc::new(neg_lower), diag, neg_upper_prev }
    }
}

#[inline(always)]
fn div(a: V, b: V) -> V {
    let mut r = [0.0; L];
    for q in 0..L {
        r[q] = a[q] / b[q];
    }
    r
}

/// (1/β, γ) node-major and split (`im` parts empty for a real σ), or `None` when some β of a
/// mode is zero. Padding lanes are zero.
pub fn factors<T: Lane>(sigma: T, rows: &TriRows) -> Option<[(Vec<V>, Vec<V>); 2]> {
    factors_body(sigma, rows)
}

#[inline(always)]
fn factors_body<T: Lane>(sigma: T, rows: &TriRows) -> Option<[(Vec<V>, Vec<V>); 2]> {
    let (m, q) = (rows.m, rows.q);
    let n = rows.diag.len();
    let cap = if T::CPLX { n } else { 0 };
    // every entry is written below: spare vectors of dropped factorisations ([`pool`])
    let (mut ibr, mut ibi, mut gr, mut gi) = (pool::take(n), pool::take(cap), pool::take(n), pool::take(cap));
    let (ibr_s, ibi_s, gr_s, gi_s) = (&mut ibr[..n], &mut ibi[..cap], &mut gr[..n], &mut gi[..cap]);
    let (sr, si) = sigma.parts();
    let (sr, si, zero, one) = ([sr; L], [si; L], [0.0; L], [1.0; L]);
    // lanes of the last vector past M: not checked, stored as zero
    let live = m - (q.max(1) - 1) * L;
    let (lower, diag, upper) = (&rows.neg_lower[..n], &rows.diag[..n], &rows.neg_upper_prev[..n]);
    // a zero β is looked for in every live lane, the result reported after the loop (the
    // factors computed past it are dropped)
    let (mut zero_pivot, mut v) = (false, 0);
    for at in 0..n {
        let d = diag[at];
        let (mut br, mut bi) = (sub(sr, d), sub(si, zero));
        let (mut g_r, mut g_i) = (zero, zero);
        if at >= q {
            let (u, l) = (upper[at], lower[at]);
            g_r = mul(ibr_s[at - q], u);
            br = sub(br, mul(g_r, l));
            if T::CPLX {
                g_i = mul(ibi_s[at - q], u);
                bi = sub(bi, mul(g_i, l));
            }
        }
        let (mut inv_r, mut inv_i);
        let mut zero_lane: [bool; L];
        if T::CPLX {
            let ns = add(mul(br, br), mul(bi, bi));
            inv_r = div(add(mul(one, br), mul(zero, bi)), ns);
            inv_i = div(sub(mul(zero, br), mul(one, bi)), ns);
            zero_lane = std::array::from_fn(|j| (br[j] == 0.0) & (bi[j] == 0.0));
        } else {
            inv_r = div(one, br);
            inv_i = zero;
            zero_lane = std::array::from_fn(|j| br[j] == 0.0);
        }
        // v: the vector of `at` in its node
        if v + 1 == q {
            for j in live..L {
                (inv_r[j], inv_i[j], g_r[j], g_i[j], zero_lane[j]) = (0.0, 0.0, 0.0, 0.0, false);
            }
            v = 0;
        } else {
            v += 1;
        }
        zero_pivot |= zero_lane.iter().fold(false, |a, &z| a | z);
        ibr_s[at] = inv_r;
        gr_s[at] = g_r;
        if T::CPLX {
            ibi_s[at] = inv_i;
            gi_s[at] = g_i;
        }
    }
    if zero_pivot {
        for v in [ibr, ibi, gr, gi] {
            pool::give(v);
        }
        return None;
    }
    Some([(ibr, ibi), (gr, gi)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Complex;

    /// The scalar recurrence, mode by mode (the factorisation this module replaced).
    fn scalar<T: Lane>(sigma: T, rows: &[Rows], ni: usize) -> Option<[(Vec<V>, Vec<V>); 2]> {
        let q = rows.len().div_ceil(L);
        let n = ni * q;
        let (mut ibr, mut ibi, mut gr, mut gi) = (vec![[0.0; L]; n], vec![[0.0; L]; n], vec![[0.0; L]; n], vec![[0.0; L]; n]);
        for (k, r) in rows.iter().enumerate() {
            let (v, lane) = (k / L, k % L);
            for i in 0..ni {
                let beta = if i == 0 {
                    sigma - T::from_real(r.diag[0])
                } else {
                    let at = (i - 1) * q + v;
                    let prev = T::from_parts(ibr[at][lane], ibi[at][lane]);
                    let g = prev.scale(-r.upper[i - 1]);
                    (gr[i * q + v][lane], gi[i * q + v][lane]) = g.parts();
                    sigma - T::from_real(r.diag[i]) - g.scale(-r.lower[i])
                };
                if beta == T::zero() {
                    return None;
                }
                (ibr[i * q + v][lane], ibi[i * q + v][lane]) = (T::one() / beta).parts();
            }
        }
        if !T::CPLX {
            (ibi, gi) = (Vec::new(), Vec::new());
        }
        Some([(ibr, ibi), (gr, gi)])
    }

    fn bits(v: &[V]) -> Vec<u64> {
        v.iter().flatten().map(|x| x.to_bits()).collect()
    }

    /// The lane-wise factors are the scalar recurrence's to the bit, for M with and without
    /// padding lanes, real and complex σ; a zero pivot is reported.
    #[test]
    fn lane_factors_match_the_scalar_recurrence_bit_for_bit() {
        let ni = 23;
        for m in [1, 3, 4, 7, 8, 9] {
            let rows: Vec<Rows> = (0..m)
                .map(|k| {
                    let f = |s: f64| (0..ni).map(|i| ((i * 7 + k * 3) as f64 * s).sin() * (1.0 + k as f64)).collect();
                    Rows { lower: f(0.37), diag: (0..ni).map(|i| -3.0 - ((i + k) as f64 * 0.11).cos()).collect(), upper: f(0.53) }
                })
                .collect();
            let tr = TriRows::new(&rows, ni);
            let c = Complex::new(1.7, 2.3);
            let (a, b) = (factors(c, &tr).expect("regular"), scalar(c, &rows, ni).expect("regular"));
            for (x, y) in a.iter().zip(&b) {
                assert_eq!((bits(&x.0), bits(&x.1)), (bits(&y.0), bits(&y.1)), "complex, M = {m}");
            }
            let (a, b) = (factors(0.9, &tr).expect("regular"), scalar(0.9, &rows, ni).expect("regular"));
            for (x, y) in a.iter().zip(&b) {
                assert_eq!((bits(&x.0), bits(&x.1)), (bits(&y.0), bits(&y.1)), "real, M = {m}");
            }
            let sigma = rows[m - 1].diag[0];
            assert!(factors(sigma, &tr).is_none() && scalar(sigma, &rows, ni).is_none(), "zero pivot, M = {m}");
        }
    }
}
