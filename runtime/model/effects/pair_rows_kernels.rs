//! The kernels of [`PairRows::apply`] (pair_rows.rs, module doc there): the portable one with
//! the stride known at compile time, and one body for AVX and AVX-512 ([`simd_kernel`]), all
//! with the same products, sums and order, so bit for bit the same result.

use super::PairRows;

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
        ///
        /// # Safety
        /// The processor has the feature; the slice lengths are those [`PairRows::apply`] asserts.
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $feature)]
        pub(super) unsafe fn $name<const V: usize>(&self, left: &[f64], right: &[f64], w: &mut [f64], out: &mut [f64]) {
            use std::arch::x86_64::*;
            // SAFETY: the caller's contract (`apply` asserts the slice lengths; `new` keeps every
            // pair, row offset and coefficient block in range), so every pointer below stays
            // inside `left`, `right`, `w`, the coefficients or `out`; the feature is enabled.
            unsafe {
                let s = $lanes * V;
                debug_assert_eq!(s, self.stride);
                let (lp, rp, wp) = (left.as_ptr(), right.as_ptr(), w.as_mut_ptr());
                // the pairs are l = 0, 1, … with m = l, l + 1, … (`new`): left(l) held in registers
                // over its pairs, no pair indices read
                debug_assert_eq!(self.pairs.len(), self.modes * (self.modes + 1) / 2);
                let mut d = wp;
                for l in 0..self.modes {
                    let x = lp.add(l * s);
                    let xv: [_; V] = std::array::from_fn(|v| $load(x.add($lanes * v)));
                    for m in l..self.modes {
                        let y = rp.add(m * s);
                        for v in 0..V {
                            $store(d.add($lanes * v), $mul(xv[v], $load(y.add($lanes * v))));
                        }
                        d = d.add(s);
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
                        // rows q, q + 1 into both outputs' accumulators
                        let pair = |q: usize, acc: &mut [_; V], twin: &mut [_; V]| {
                            let (w0, w1) = (wp.add(*off.add(q) as usize), wp.add(*off.add(q + 1) as usize));
                            let c0 = cp.add((q - r0) * 2 * s);
                            let c1 = c0.add(2 * s);
                            for v in 0..V {
                                let (x0, x1) = ($load(w0.add($lanes * v)), $load(w1.add($lanes * v)));
                                let (t0, t1) = ($mul($load(c0.add($lanes * v)), x0), $mul($load(c1.add($lanes * v)), x1));
                                acc[v] = $add(acc[v], $add(t0, t1));
                                let (t0, t1) = ($mul($load(c0.add(s + $lanes * v)), x0), $mul($load(c1.add(s + $lanes * v)), x1));
                                twin[v] = $add(twin[v], $add(t0, t1));
                            }
                        };
                        // two row pairs per trip (half the loop control), then one
                        while r + 4 <= r1 {
                            pair(r, &mut acc, &mut twin);
                            pair(r + 2, &mut acc, &mut twin);
                            r += 4;
                        }
                        if r + 2 <= r1 {
                            pair(r, &mut acc, &mut twin);
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
                    // rows q, q + 1: c0 w0 + c1 w1 added to the accumulators, the portable kernel's
                    // sums in its order
                    let pair = |q: usize, acc: &mut [_; V]| {
                        let (w0, w1) = (wp.add(*off.add(q) as usize), wp.add(*off.add(q + 1) as usize));
                        let (c0, c1) = (cp.add((q - r0) * s), cp.add((q + 1 - r0) * s));
                        for (v, a) in acc.iter_mut().enumerate() {
                            let t0 = $mul($load(c0.add($lanes * v)), $load(w0.add($lanes * v)));
                            let t1 = $mul($load(c1.add($lanes * v)), $load(w1.add($lanes * v)));
                            *a = $add(*a, $add(t0, t1));
                        }
                    };
                    // two row pairs per trip (half the loop control), then one
                    while r + 4 <= r1 {
                        pair(r, &mut acc);
                        pair(r + 2, &mut acc);
                        r += 4;
                    }
                    if r + 2 <= r1 {
                        pair(r, &mut acc);
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
        }
    };
}

impl PairRows {
    /// w = the pair products, then out_o += Σ_{rows r of o} coef_r · w[pair_r] (module doc).
    pub(super) fn apply(&self, left: &[f64], right: &[f64], w: &mut [f64], out: &mut [f64]) {
        let s = self.stride;
        // the bounds every kernel relies on (the AVX one reads without further checks)
        assert!(left.len() >= self.modes * s && right.len() >= self.modes * s, "PairRows factors");
        assert_eq!(w.len(), self.pairs.len() * s, "PairRows products");
        assert!(out.len() >= self.out_at.len(), "PairRows outputs");
        #[cfg(target_arch = "x86_64")]
        if s % 8 == 0 && crate::simd::avx512(crate::simd::Kernel::PairRows512) && crate::simd::avx(crate::simd::Kernel::PairRows) {
            // SAFETY: the processor supports AVX-512F (`simd::avx512` checked); lengths and offsets
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
        if crate::simd::avx(crate::simd::Kernel::PairRows) {
            // SAFETY: the processor supports AVX (`simd::avx` checked); the slice lengths are
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
    pub(super) fn apply_s<const S: usize>(&self, left: &[f64], right: &[f64], w: &mut [f64], out: &mut [f64]) {
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
