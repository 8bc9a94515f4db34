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
    /// offset of each row's products in w: pair index · stride
    row_off: Vec<u32>,
    /// row · stride + slot, from `coef_at` on (64-byte aligned: the wide loads of a row do not
    /// straddle cache lines)
    coef_buf: Vec<f64>,
    coef_at: usize,
}

thread_local! {
    /// Scratch for w (no allocation per evaluation once grown).
    static SCRATCH: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
}

/// `v` copied into a buffer at a 64-byte aligned start (the buffer is never reallocated, so the
/// start stays aligned): (buffer, start).
fn aligned(v: &[f64]) -> (Vec<f64>, usize) {
    let mut buf = vec![0.0; v.len() + 8];
    let at = buf.as_ptr().align_offset(64).min(8);
    buf[at..at + v.len()].copy_from_slice(v);
    (buf, at)
}

/// One x86-64 kernel of [`PairRows::apply`] for a vector width of `lanes` f64 (the intrinsics of
/// that width given by name): the pair products, then per output two rows at a time into `V`
/// register accumulators, folded by `|sum, a| …` into one 4-lane sum (AVX) whose lanes are added
/// as the portable kernel adds its four partial sums. One body for AVX and AVX-512, so the two
/// cannot drift apart (the bit-for-bit test below covers both).
macro_rules! simd_kernel {
    ($(#[$doc:meta])* $name:ident, $feature:literal, lanes $lanes:literal, $zero:ident, $load:ident, $store:ident, $mul:ident, $add:ident,
     |$sum:ident, $a:ident| $fold:expr) => {
        $(#[$doc])*
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $feature)]
        unsafe fn $name<const V: usize>(&self, left: &[f64], right: &[f64], w: &mut [f64], out: &mut [f64]) {
            use std::arch::x86_64::*;
            let s = $lanes * V;
            debug_assert_eq!(s, self.stride);
            let (lp, rp, wp) = (left.as_ptr(), right.as_ptr(), w.as_mut_ptr());
            for (p, &(l, m)) in self.pairs.iter().enumerate() {
                let (x, y, d) = (lp.add(l * s), rp.add(m * s), wp.add(p * s));
                for v in 0..V {
                    $store(d.add($lanes * v), $mul($load(x.add($lanes * v)), $load(y.add($lanes * v))));
                }
            }
            let wp = w.as_ptr();
            let (cp, off) = (self.coef().as_ptr(), self.row_off.as_ptr());
            for (o, x) in out.iter_mut().enumerate().take(self.out_start.len() - 1) {
                let (r0, r1) = (self.out_start[o], self.out_start[o + 1]);
                let mut acc = [$zero(); V];
                let mut r = r0;
                // two row pairs per trip (half the loop control), then one; each row pair adds
                // c0 w0 + c1 w1 to the accumulators, the portable kernel's sums in its order
                while r + 4 <= r1 {
                    for q in [r, r + 2] {
                        let (w0, w1) = (wp.add(*off.add(q) as usize), wp.add(*off.add(q + 1) as usize));
                        let (c0, c1) = (cp.add(q * s), cp.add((q + 1) * s));
                        for (v, a) in acc.iter_mut().enumerate() {
                            let t0 = $mul($load(c0.add($lanes * v)), $load(w0.add($lanes * v)));
                            let t1 = $mul($load(c1.add($lanes * v)), $load(w1.add($lanes * v)));
                            *a = $add(*a, $add(t0, t1));
                        }
                    }
                    r += 4;
                }
                if r + 2 <= r1 {
                    let (w0, w1) = (wp.add(*off.add(r) as usize), wp.add(*off.add(r + 1) as usize));
                    let (c0, c1) = (cp.add(r * s), cp.add((r + 1) * s));
                    for (v, a) in acc.iter_mut().enumerate() {
                        let t0 = $mul($load(c0.add($lanes * v)), $load(w0.add($lanes * v)));
                        let t1 = $mul($load(c1.add($lanes * v)), $load(w1.add($lanes * v)));
                        *a = $add(*a, $add(t0, t1));
                    }
                    r += 2;
                }
                if r < r1 {
                    let (w0, c0) = (wp.add(*off.add(r) as usize), cp.add(r * s));
                    for (v, a) in acc.iter_mut().enumerate() {
                        *a = $add(*a, $mul($load(c0.add($lanes * v)), $load(w0.add($lanes * v))));
                    }
                }
                let mut $sum = _mm256_setzero_pd();
                for $a in acc {
                    $fold;
                }
                let mut v = [0.0f64; 4];
                _mm256_storeu_pd(v.as_mut_ptr(), $sum);
                *x += (v[0] + v[1]) + (v[2] + v[3]);
            }
        }
    };
}

impl PairRows {
    /// `modes` mode indices, `outputs` outputs, `slots` products per pair; `fill(o, l, m, c)`
    /// writes the coefficients of output o on pair (l ≤ m) into `c` (length `slots`, zeroed) and
    /// returns false when the selection rules exclude the row (the closure need not look at it).
    /// A row is kept when a coefficient is non-zero.
    pub fn new(modes: usize, outputs: usize, slots: usize, mut fill: impl FnMut(usize, usize, usize, &mut [f64]) -> bool) -> Self {
        let stride = slots.div_ceil(4).max(1) * 4;
        assert!(stride <= 32, "PairRows: at most 32 slots per pair");
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
        let row_off = row_pair.iter().map(|&p| u32::try_from(p * stride).expect("PairRows: pair table too large")).collect();
        let (coef_buf, coef_at) = aligned(&coef);
        Self { stride, modes, pairs, out_start, row_pair, row_off, coef_buf, coef_at }
    }

    /// Slots per pair as laid out (a multiple of 4, padding included).
    pub fn stride(&self) -> usize {
        self.stride
    }
    #[cfg(test)]
    pub fn pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }
    /// The coefficients, row · stride + slot.
    fn coef(&self) -> &[f64] {
        &self.coef_buf[self.coef_at..self.coef_at + self.row_pair.len() * self.stride]
    }

    /// Number of stored (output, pair) rows.
    pub fn len(&self) -> usize {
        self.row_pair.len()
    }

    /// The rows of output o: (pair (l, m), the `stride` coefficients).
    pub fn rows(&self, o: usize) -> impl Iterator<Item = ((usize, usize), &[f64])> + '_ {
        let r = self.out_start[o]..self.out_start[o + 1];
        self.row_pair[r.clone()].iter().zip(self.coef()[r.start * self.stride..r.end * self.stride].chunks_exact(self.stride)).map(|(&p, c)| (self.pairs[p], c))
    }

    /// out_o += Σ rows of o · w, w(l, m) = left(l) ⊙ right(m), with `factors(left, right)`
    /// writing every entry of left and right (modes × `stride` each, padding included: a
    /// padding slot's factors are 0). `out.len()` outputs.
    pub fn eval(&self, out: &mut [f64], factors: impl FnOnce(&mut [f64], &mut [f64])) {
        let s = self.stride;
        let (nm, np) = (self.modes * s, self.pairs.len() * s);
        SCRATCH.with(|cell| {
            let mut buf = cell.borrow_mut();
            if buf.len() < 2 * nm + np + 8 {
                buf.resize(2 * nm + np + 8, 0.0);
            }
            // a 64-byte aligned start (the wide loads of w do not straddle cache lines)
            let at = buf.as_ptr().align_offset(64).min(8);
            let (lr, w) = buf[at..].split_at_mut(2 * nm);
            let (left, right) = lr.split_at_mut(nm);
            factors(left, right);
            self.apply(left, right, &mut w[..np], out);
        });
    }

    /// w = the pair products, then out_o += Σ_{rows r of o} coef_r · w[pair_r] (module doc).
    fn apply(&self, left: &[f64], right: &[f64], w: &mut [f64], out: &mut [f64]) {
        let s = self.stride;
        // the bounds every kernel relies on (the AVX one reads without further checks)
        assert!(left.len() >= self.modes * s && right.len() >= self.modes * s, "PairRows factors");
        assert_eq!(w.len(), self.pairs.len() * s, "PairRows products");
        assert!(out.len() + 1 >= self.out_start.len(), "PairRows outputs");
        #[cfg(target_arch = "x86_64")]
        if s % 8 == 0 && std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the processor supports AVX-512F (checked just above); lengths and offsets
            // as for the AVX kernel below.
            unsafe {
                match s {
                    8 => self.apply_avx512::<1>(left, right, w, out),
                    16 => self.apply_avx512::<2>(left, right, w, out),
                    24 => self.apply_avx512::<3>(left, right, w, out),
                    _ => self.apply_avx512::<4>(left, right, w, out),
                }
            }
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: the processor supports AVX (checked just above); the slice lengths are
            // the ones asserted above, and every stored pair and row offset is in range (`new`).
            unsafe {
                match s {
                    4 => self.apply_avx::<1>(left, right, w, out),
                    8 => self.apply_avx::<2>(left, right, w, out),
                    12 => self.apply_avx::<3>(left, right, w, out),
                    16 => self.apply_avx::<4>(left, right, w, out),
                    20 => self.apply_avx::<5>(left, right, w, out),
                    24 => self.apply_avx::<6>(left, right, w, out),
                    28 => self.apply_avx::<7>(left, right, w, out),
                    _ => self.apply_avx::<8>(left, right, w, out),
                }
            }
            return;
        }
        match s {
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

    simd_kernel! {
        /// [`apply_s`](Self::apply_s) with `V` = stride/4 AVX registers per row: the same
        /// products, sums and order lane by lane (no FMA), so bit for bit its result; the
        /// accumulators stay in registers and the rows are read through their stored offsets.
        ///
        /// # Safety
        /// AVX available; `left`, `right`, `w`, `out` at least as long as [`apply`](Self::apply)
        /// asserts; `self` built by [`new`](Self::new) (pairs < modes, row offsets < pairs · stride).
        apply_avx, "avx", lanes 4, _mm256_setzero_pd, _mm256_loadu_pd, _mm256_storeu_pd, _mm256_mul_pd, _mm256_add_pd,
        |sum, a| sum = _mm256_add_pd(sum, a)
    }

    simd_kernel! {
        /// [`apply_avx`](Self::apply_avx) with `V` = stride/8 AVX-512 registers per row (half the
        /// loads and instructions): the same lane-wise products and sums, and the final sum over
        /// the partial sums in the 4-lane order of the other kernels (slots 0–3, 4–7, 8–11, …), so
        /// bit for bit their result.
        ///
        /// # Safety
        /// AVX-512F available; otherwise as [`apply_avx`](Self::apply_avx).
        apply_avx512, "avx512f", lanes 8, _mm512_setzero_pd, _mm512_loadu_pd, _mm512_storeu_pd, _mm512_mul_pd, _mm512_add_pd,
        |sum, a| {
            sum = _mm256_add_pd(sum, _mm512_castpd512_pd256(a));
            sum = _mm256_add_pd(sum, _mm512_extractf64x4_pd::<1>(a));
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
        let at = |r: usize| -> &[f64; S] {
            let o = self.row_off[r] as usize;
            w[o..o + S].try_into().expect("S slots")
        };
        for (o, x) in out.iter_mut().enumerate().take(self.out_start.len() - 1) {
            let (r0, r1) = (self.out_start[o], self.out_start[o + 1]);
            let coef = &self.coef()[r0 * S..r1 * S];
            let mut acc = [0.0f64; S];
            let cc = coef.chunks_exact(2 * S);
            let c_rest = cc.remainder();
            for (i, c) in cc.enumerate() {
                let (c0, c1) = c.split_at(S);
                let (c0, c1): (&[f64; S], &[f64; S]) = (c0.try_into().expect("S"), c1.try_into().expect("S"));
                let (w0, w1) = (at(r0 + 2 * i), at(r0 + 2 * i + 1));
                for s in 0..S {
                    acc[s] += c0[s] * w0[s] + c1[s] * w1[s];
                }
            }
            if let Ok(c0) = <&[f64; S]>::try_from(c_rest) {
                let w0 = at(r1 - 1);
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

    /// The AVX kernel is the portable one bit for bit (same products, sums and order), for
    /// every stride and for odd and even row counts per output.
    #[test]
    fn avx_kernel_is_the_portable_one_bit_for_bit() {
        for slots in [3, 8, 13, 16, 21, 32] {
            let (modes, outputs) = (6, 7);
            let rows = PairRows::new(modes, outputs, slots, |o, l, m, c| {
                for (s, x) in c.iter_mut().enumerate() {
                    *x = (((o * 31 + l * 7 + m * 3 + s) as f64) * 0.731).sin();
                }
                (o + l + m) % 3 != 1
            });
            let st = rows.stride();
            let left: Vec<f64> = (0..modes * st).map(|i| ((i as f64) * 1.37).cos() * 1e3).collect();
            let right: Vec<f64> = (0..modes * st).map(|i| ((i as f64) * 0.29).sin() * 1e-3).collect();
            let mut w = vec![0.0; rows.pairs().len() * st];
            let mut portable = vec![0.5; outputs];
            match st {
                4 => rows.apply_s::<4>(&left, &right, &mut w, &mut portable),
                8 => rows.apply_s::<8>(&left, &right, &mut w, &mut portable),
                16 => rows.apply_s::<16>(&left, &right, &mut w, &mut portable),
                24 => rows.apply_s::<24>(&left, &right, &mut w, &mut portable),
                _ => rows.apply_s::<32>(&left, &right, &mut w, &mut portable),
            }
            let mut dispatched = vec![0.5; outputs];
            rows.apply(&left, &right, &mut w, &mut dispatched);
            for (a, b) in portable.iter().zip(&dispatched) {
                assert_eq!(a.to_bits(), b.to_bits(), "stride {st}: {a} against {b}");
            }
            // the AVX kernel also where the dispatch above took AVX-512
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx") {
                let mut avx = vec![0.5; outputs];
                // SAFETY: AVX checked just above; the lengths are those apply asserts.
                unsafe {
                    match st {
                        4 => rows.apply_avx::<1>(&left, &right, &mut w, &mut avx),
                        8 => rows.apply_avx::<2>(&left, &right, &mut w, &mut avx),
                        16 => rows.apply_avx::<4>(&left, &right, &mut w, &mut avx),
                        24 => rows.apply_avx::<6>(&left, &right, &mut w, &mut avx),
                        _ => rows.apply_avx::<8>(&left, &right, &mut w, &mut avx),
                    }
                }
                for (a, b) in portable.iter().zip(&avx) {
                    assert_eq!(a.to_bits(), b.to_bits(), "stride {st} (AVX): {a} against {b}");
                }
            }
        }
    }
}
