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
//!
//! Two outputs with the same pair list (the membrane's normal and tangential loads on P_j and
//! P¹_j: the same C(j, l, m) ≠ 0) are *twins*: one row per pair holds both outputs' coefficients,
//! so the kernel reads the row's offset and products once for both (at stride ≤ 16, where both
//! outputs' partial sums stay in registers). Each output's sums and their order are the ones it
//! has alone, so twinning changes no bit.

use std::cell::RefCell;

/// The rows of one term: `stride` slots per pair (a multiple of 4).
#[derive(Debug)]
pub struct PairRows {
    stride: usize,
    modes: usize,
    /// the unordered pairs l ≤ m (mode indices), in the layout of w
    pairs: Vec<(usize, usize)>,
    /// the outputs, one or two (twins, module doc) per group, in evaluation order
    groups: Vec<Group>,
    /// (group, half) of each output
    out_at: Vec<(usize, usize)>,
    /// pair index of each group row
    row_pair: Vec<usize>,
    /// offset of each group row's products in w: pair index · stride
    row_off: Vec<u32>,
    /// per group, its rows' coefficients: row · width · stride + half · stride + slot, from
    /// `coef_at` on (64-byte aligned: the wide loads of a row do not straddle cache lines)
    coef_buf: Vec<f64>,
    coef_at: usize,
    /// number of (output, pair) rows
    len: usize,
}

/// Outputs that share one pair list (module doc).
#[derive(Debug, Clone, Copy)]
struct Group {
    /// the outputs (`outs[1]` only when `width` is 2)
    outs: [usize; 2],
    width: usize,
    /// its rows: `rows.0..rows.1` of `row_pair`
    rows: (usize, usize),
    /// where its coefficients start in `coef`
    coef: usize,
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
/// as the portable kernel adds its four partial sums; a twin group (module doc) runs both
/// outputs' sums in one pass over its rows. One body for AVX and AVX-512, so the two cannot
/// drift apart (the bit-for-bit test in pair_rows_tests.rs covers both).
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
            let (coef, off, op) = (self.coef().as_ptr(), self.row_off.as_ptr(), out.as_mut_ptr());
            // the accumulators' sum, in the portable kernel's order, added to output o
            let fold = |acc: [_; V], o: usize| {
                let mut $sum = _mm256_setzero_pd();
                for $a in acc {
                    $fold;
                }
                let mut v = [0.0f64; 4];
                _mm256_storeu_pd(v.as_mut_ptr(), $sum);
                *op.add(o) += (v[0] + v[1]) + (v[2] + v[3]);
            };
            for g in &self.groups {
                let ((r0, r1), cp) = (g.rows, coef.add(g.coef));
                let mut acc = [$zero(); V];
                let mut r = r0;
                if g.width == 2 {
                    // twins: row r holds output 0's coefficients, then output 1's
                    let mut twin = [$zero(); V];
                    while r + 2 <= r1 {
                        let (w0, w1) = (wp.add(*off.add(r) as usize), wp.add(*off.add(r + 1) as usize));
                        let c0 = cp.add((r - r0) * 2 * s);
                        let c1 = c0.add(2 * s);
                        for v in 0..V {
                            let (x0, x1) = ($load(w0.add($lanes * v)), $load(w1.add($lanes * v)));
                            let (t0, t1) = ($mul($load(c0.add($lanes * v)), x0), $mul($load(c1.add($lanes * v)), x1));
                            acc[v] = $add(acc[v], $add(t0, t1));
                            let (t0, t1) = ($mul($load(c0.add(s + $lanes * v)), x0), $mul($load(c1.add(s + $lanes * v)), x1));
                            twin[v] = $add(twin[v], $add(t0, t1));
                        }
                        r += 2;
                    }
                    if r < r1 {
                        let (w0, c0) = (wp.add(*off.add(r) as usize), cp.add((r - r0) * 2 * s));
                        for v in 0..V {
                            let x0 = $load(w0.add($lanes * v));
                            acc[v] = $add(acc[v], $mul($load(c0.add($lanes * v)), x0));
                            twin[v] = $add(twin[v], $mul($load(c0.add(s + $lanes * v)), x0));
                        }
                    }
                    fold(acc, g.outs[0]);
                    fold(twin, g.outs[1]);
                    continue;
                }
                // two row pairs per trip (half the loop control), then one; each row pair adds
                // c0 w0 + c1 w1 to the accumulators, the portable kernel's sums in its order
                while r + 4 <= r1 {
                    for q in [r, r + 2] {
                        let (w0, w1) = (wp.add(*off.add(q) as usize), wp.add(*off.add(q + 1) as usize));
                        let (c0, c1) = (cp.add((q - r0) * s), cp.add((q + 1 - r0) * s));
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
                    let (c0, c1) = (cp.add((r - r0) * s), cp.add((r + 1 - r0) * s));
                    for (v, a) in acc.iter_mut().enumerate() {
                        let t0 = $mul($load(c0.add($lanes * v)), $load(w0.add($lanes * v)));
                        let t1 = $mul($load(c1.add($lanes * v)), $load(w1.add($lanes * v)));
                        *a = $add(*a, $add(t0, t1));
                    }
                    r += 2;
                }
                if r < r1 {
                    let (w0, c0) = (wp.add(*off.add(r) as usize), cp.add((r - r0) * s));
                    for (v, a) in acc.iter_mut().enumerate() {
                        *a = $add(*a, $mul($load(c0.add($lanes * v)), $load(w0.add($lanes * v))));
                    }
                }
                fold(acc, g.outs[0]);
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
        // per output: its pairs and their coefficients
        let mut each: Vec<(Vec<usize>, Vec<f64>)> = Vec::with_capacity(outputs);
        let mut c = vec![0.0; stride];
        for o in 0..outputs {
            let (mut ps, mut cs) = (Vec::new(), Vec::new());
            for (p, &(l, m)) in pairs.iter().enumerate() {
                c.fill(0.0);
                if fill(o, l, m, &mut c[..slots]) && c.iter().any(|&x| x != 0.0) {
                    ps.push(p);
                    cs.extend_from_slice(&c);
                }
            }
            each.push((ps, cs));
        }
        // twins (module doc): an output and the first later one with the same pairs, while both
        // outputs' accumulators fit in the AVX registers
        let mut grouped = vec![false; outputs];
        let (mut groups, mut out_at, mut row_pair, mut coef) = (Vec::new(), vec![(0, 0); outputs], Vec::new(), Vec::new());
        for o in 0..outputs {
            if grouped[o] {
                continue;
            }
            let twin = (stride <= 16 && !each[o].0.is_empty()).then(|| (o + 1..outputs).find(|&t| !grouped[t] && each[t].0 == each[o].0)).flatten();
            let (r0, c0) = (row_pair.len(), coef.len());
            for (i, &p) in each[o].0.iter().enumerate() {
                row_pair.push(p);
                coef.extend_from_slice(&each[o].1[i * stride..(i + 1) * stride]);
                if let Some(t) = twin {
                    coef.extend_from_slice(&each[t].1[i * stride..(i + 1) * stride]);
                }
            }
            out_at[o] = (groups.len(), 0);
            grouped[o] = true;
            if let Some(t) = twin {
                out_at[t] = (groups.len(), 1);
                grouped[t] = true;
            }
            groups.push(Group { outs: [o, twin.unwrap_or(o)], width: 1 + usize::from(twin.is_some()), rows: (r0, row_pair.len()), coef: c0 });
        }
        let len = each.iter().map(|(ps, _)| ps.len()).sum();
        let row_off = row_pair.iter().map(|&p| u32::try_from(p * stride).expect("PairRows: pair table too large")).collect();
        let (coef_buf, coef_at) = aligned(&coef);
        Self { stride, modes, pairs, groups, out_at, row_pair, row_off, coef_buf, coef_at, len }
    }

    /// Slots per pair as laid out (a multiple of 4, padding included).
    pub fn stride(&self) -> usize {
        self.stride
    }
    #[cfg(test)]
    pub fn pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }
    /// The coefficients of every group, in order (`Group::coef` into it).
    fn coef(&self) -> &[f64] {
        let n: usize = self.groups.iter().map(|g| (g.rows.1 - g.rows.0) * g.width).sum();
        &self.coef_buf[self.coef_at..self.coef_at + n * self.stride]
    }

    /// Number of stored (output, pair) rows.
    pub fn len(&self) -> usize {
        self.len
    }

    /// The rows of output o: (pair (l, m), the `stride` coefficients).
    pub fn rows(&self, o: usize) -> impl Iterator<Item = ((usize, usize), &[f64])> + '_ {
        let (gi, half) = self.out_at[o];
        let g = self.groups[gi];
        let (s, n) = (self.stride, g.rows.1 - g.rows.0);
        let coef = &self.coef()[g.coef..g.coef + n * g.width * s];
        self.row_pair[g.rows.0..g.rows.1].iter().zip(coef.chunks_exact(g.width * s)).map(move |(&p, c)| (self.pairs[p], &c[half * s..(half + 1) * s]))
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
        assert!(out.len() >= self.out_at.len(), "PairRows outputs");
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
        let coef = self.coef();
        for g in &self.groups {
            let (r0, r1) = g.rows;
            // row r's coefficients of output `half` of the group
            let c = |r: usize, half: usize| -> &[f64; S] {
                let i = g.coef + ((r - r0) * g.width + half) * S;
                coef[i..i + S].try_into().expect("S slots")
            };
            for half in 0..g.width {
                let mut acc = [0.0f64; S];
                let mut r = r0;
                while r + 2 <= r1 {
                    let (c0, c1, w0, w1) = (c(r, half), c(r + 1, half), at(r), at(r + 1));
                    for s in 0..S {
                        acc[s] += c0[s] * w0[s] + c1[s] * w1[s];
                    }
                    r += 2;
                }
                if r < r1 {
                    let (c0, w0) = (c(r, half), at(r));
                    for s in 0..S {
                        acc[s] += c0[s] * w0[s];
                    }
                }
                let mut v = [0.0f64; 4];
                for s in 0..S {
                    v[s % 4] += acc[s];
                }
                out[g.outs[half]] += (v[0] + v[1]) + (v[2] + v[3]);
            }
        }
    }
}

#[cfg(test)]
#[path = "pair_rows_tests.rs"]
mod tests;
