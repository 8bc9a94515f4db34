//! The sparse bilinear sums shared by the quadratic terms (issue 12, "Performance";
//! docs/performance.md): out_o = Σ_{pairs l ≤ m} Σ_s c_o(l, m, s) · w_s(l, m), where the *slots*
//! s of a pair are the products the term needs (a_l a_m, a_l b_m, …, each times a prefactor) and
//! only the (output, pair) rows the selection rules allow (|l − m| ≤ j ≤ l + m, l + m + j even)
//! are stored, grouped by output.
//!
//! Every slot is a product of a factor of mode l and a factor of mode m, so the caller gives, per
//! mode, its left factors (prefactors included) and its right factors (`stride` each); the
//! products w(l, m) = left(l) ⊙ right(m) are formed once per evaluation (they are shared by every
//! output of a pair, no gathers) and [`PairRows::eval`] runs one contiguous dot product per output — the
//! coefficients are read once, in order, into independent partial sums (AVX where the processor
//! has it: the same sums in the same order, so bit for bit the SSE2 result). The Jacobian walks
//! the same rows ([`PairRows::rows`]), so rhs and Jacobian share one table and one sparsity.

use std::cell::RefCell;

/// The rows of one term: `stride` slots per pair (a multiple of 4).
#[derive(Debug)]
pub struct PairRows {
    stride: usize,
    modes: usize,
    /// the unordered pairs l ≤ m (mode indices), in the layout of w
    pairs: Vec<(usize, usize)>,
    /// rows of output o: `out_start[o]..out_start[o + 1]`
    out_start: Vec<usize>,
    /// pair index of each row
    row_pair: Vec<usize>,
    /// row · stride + slot
    coef: Vec<f64>,
}

thread_local! {
    /// Scratch for w (no allocation per evaluation once grown).
    static SCRATCH: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
}

impl PairRows {
    /// `modes` mode indices, `outputs` outputs, `slots` products per pair; `fill(o, l, m, c)`
    /// writes the coefficients of output o on pair (l ≤ m) into `c` (length `slots`, zeroed) and
    /// returns false when the selection rules exclude the row (the closure need not look at it).
    /// A row is kept when a coefficient is non-zero.
    pub fn new(modes: usize, outputs: usize, slots: usize, mut fill: impl FnMut(usize, usize, usize, &mut [f64]) -> bool) -> Self {
        let stride = slots.div_ceil(4).max(1) * 4;
        let pairs: Vec<(usize, usize)> = (0..modes).flat_map(|l| (l..modes).map(move |m| (l, m))).collect();
        let (mut out_start, mut row_pair, mut coef) = (vec![0], Vec::new(), Vec::new());
        let mut c = vec![0.0; stride];
        for o in 0..outputs {
            for (p, &(l, m)) in pairs.iter().enumerate() {
                c.fill(0.0);
                if fill(o, l, m, &mut c[..slots]) && c.iter().any(|&x| x != 0.0) {
                    row_pair.push(p);
                    coef.extend_from_slice(&c);
                }
            }
            out_start.push(row_pair.len());
        }
        Self { stride, modes, pairs, out_start, row_pair, coef }
    }

    #[cfg(test)]
    pub fn stride(&self) -> usize {
        self.stride
    }
    #[cfg(test)]
    pub fn pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }
    /// Number of stored (output, pair) rows.
    pub fn len(&self) -> usize {
        self.row_pair.len()
    }

    /// The rows of output o: (pair (l, m), the `stride` coefficients).
    pub fn rows(&self, o: usize) -> impl Iterator<Item = ((usize, usize), &[f64])> + '_ {
        let r = self.out_start[o]..self.out_start[o + 1];
        self.row_pair[r.clone()].iter().zip(self.coef[r.start * self.stride..r.end * self.stride].chunks_exact(self.stride)).map(|(&p, c)| (self.pairs[p], c))
    }

    /// out_o += Σ rows of o · w, w(l, m) = left(l) ⊙ right(m), with `factors(left, right)`
    /// writing every entry of left and right (modes × `stride` each, padding included: a
    /// padding slot's factors are 0). `out.len()` outputs.
    pub fn eval(&self, out: &mut [f64], factors: impl FnOnce(&mut [f64], &mut [f64])) {
        let s = self.stride;
        let (nm, np) = (self.modes * s, self.pairs.len() * s);
        SCRATCH.with(|cell| {
            let mut buf = cell.borrow_mut();
            if buf.len() < 2 * nm + np {
                buf.resize(2 * nm + np, 0.0);
            }
            let (lr, w) = buf.split_at_mut(2 * nm);
            let (left, right) = lr.split_at_mut(nm);
            factors(left, right);
            self.apply(left, right, &mut w[..np], out);
        });
    }

    /// w = the pair products, then out_o += Σ_{rows r of o} coef_r · w[pair_r] (module doc).
    fn apply(&self, left: &[f64], right: &[f64], w: &mut [f64], out: &mut [f64]) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: the processor supports AVX (checked just above).
            unsafe { self.apply_avx(left, right, w, out) };
            return;
        }
        self.apply_any(left, right, w, out)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn apply_avx(&self, left: &[f64], right: &[f64], w: &mut [f64], out: &mut [f64]) {
        self.apply_any(left, right, w, out)
    }

    #[inline(always)]
    fn apply_any(&self, left: &[f64], right: &[f64], w: &mut [f64], out: &mut [f64]) {
        match self.stride {
            4 => self.apply_s::<4>(left, right, w, out),
            8 => self.apply_s::<8>(left, right, w, out),
            12 => self.apply_s::<12>(left, right, w, out),
            16 => self.apply_s::<16>(left, right, w, out),
            20 => self.apply_s::<20>(left, right, w, out),
            24 => self.apply_s::<24>(left, right, w, out),
            28 => self.apply_s::<28>(left, right, w, out),
            _ => self.apply_s::<32>(left, right, w, out),
        }
    }

    /// With the stride `S` known at compile time: per output two rows at a time into one
    /// partial sum per slot (S/4 independent vector chains), summed in a fixed order.
    #[inline(always)]
    fn apply_s<const S: usize>(&self, left: &[f64], right: &[f64], w: &mut [f64], out: &mut [f64]) {
        assert_eq!(S, self.stride, "PairRows stride");
        let factor = |v: &[f64], i: usize| -> [f64; S] { v[i * S..(i + 1) * S].try_into().expect("S slots") };
        for (&(l, m), wp) in self.pairs.iter().zip(w.chunks_exact_mut(S)) {
            let (x, y) = (factor(left, l), factor(right, m));
            for s in 0..S {
                wp[s] = x[s] * y[s];
            }
        }
        let w: &[f64] = w;
        let at = |p: usize| -> &[f64; S] { w[p * S..(p + 1) * S].try_into().expect("S slots") };
        for (o, x) in out.iter_mut().enumerate().take(self.out_start.len() - 1) {
            let (r0, r1) = (self.out_start[o], self.out_start[o + 1]);
            let (pairs, coef) = (&self.row_pair[r0..r1], &self.coef[r0 * S..r1 * S]);
            let mut acc = [0.0f64; S];
            let (pp, cc) = (pairs.chunks_exact(2), coef.chunks_exact(2 * S));
            let (p_rest, c_rest) = (pp.remainder(), cc.remainder());
            for (p, c) in pp.zip(cc) {
                let (c0, c1) = c.split_at(S);
                let (c0, c1): (&[f64; S], &[f64; S]) = (c0.try_into().expect("S"), c1.try_into().expect("S"));
                let (w0, w1) = (at(p[0]), at(p[1]));
                for s in 0..S {
                    acc[s] += c0[s] * w0[s] + c1[s] * w1[s];
                }
            }
            if let (Some(&p), Ok(c0)) = (p_rest.first(), <&[f64; S]>::try_from(c_rest)) {
                let w0 = at(p);
                for s in 0..S {
                    acc[s] += c0[s] * w0[s];
                }
            }
            let mut v = [0.0f64; 4];
            for s in 0..S {
                v[s % 4] += acc[s];
            }
            *x += (v[0] + v[1]) + (v[2] + v[3]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sparse sums equal the plain double loop over every (output, pair, slot).
    #[test]
    fn eval_is_the_plain_sum() {
        let (modes, outputs, slots) = (5, 4, 6);
        let coef = |o: usize, l: usize, m: usize, s: usize| if (l + m + o) % 3 == 0 { 0.0 } else { (1 + o + 2 * l + 3 * m + 5 * s) as f64 * 0.01 };
        let rows = PairRows::new(modes, outputs, slots, |o, l, m, c| {
            for (s, x) in c.iter_mut().enumerate() {
                *x = coef(o, l, m, s);
            }
            true
        });
        assert_eq!(rows.stride(), 8);
        let mut out = vec![0.0; outputs];
        // prod(l, m, s) = left_s(l) · right_s(m)
        let (lf, rf) = (|l: usize, s: usize| 1.0 + 0.1 * (l * 7 + s) as f64, |m: usize, s: usize| ((m * 3 + s) as f64).sin());
        let prod = |l: usize, m: usize, s: usize| lf(l, s) * rf(m, s);
        rows.eval(&mut out, |left, right| {
            for (i, (lv, rv)) in left.chunks_exact_mut(8).zip(right.chunks_exact_mut(8)).enumerate() {
                for s in 0..8 {
                    (lv[s], rv[s]) = if s < slots { (lf(i, s), rf(i, s)) } else { (0.0, 0.0) };
                }
            }
        });
        for (o, &got) in out.iter().enumerate() {
            let mut want = 0.0;
            for &(l, m) in rows.pairs() {
                for s in 0..slots {
                    want += coef(o, l, m, s) * prod(l, m, s);
                }
            }
            assert!((got - want).abs() <= 1e-14 * want.abs().max(1.0), "output {o}: {got} against {want}");
        }
    }
}
