//! Steps 2–4 of [`GaussProduct`] (module doc): the mode sums at the nodes, the groups, the
//! projections. Nodes in blocks of [`LANES`]; one portable kernel and, from one macro body, an
//! AVX (two registers per block) and an AVX-512 kernel (one), with the same products and sums
//! in the same order lane by lane and no FMA, so bit for bit the portable result. (Left to
//! itself, the compiler vectorised the projections' loop two lanes per register with shuffles
//! around the final reduction, and kept iterator overhead in the target-feature clones.)
//!
//! Each output is one partial sum per lane (groups in order, each's blocks in order), then lane
//! i + 4 added onto lane i and those four summed pairwise.

use super::{GaussProduct, LANES};

impl GaussProduct {
    /// The bounds every kernel relies on (the SIMD ones read without further checks).
    pub(super) fn check(&self, k: &[f64], coef: &[f64], rows: &[f64], out: &[f64]) {
        let w = self.blocks * LANES;
        let (nf, ng) = (self.sums.len(), self.group_start.len() - 1);
        assert!(k.len() >= self.combo_sums.len() && coef.len() >= nf * self.modes, "GaussProduct scratch");
        assert!(rows.len() >= (nf + ng) * w && self.legendre.len() >= self.modes * w, "GaussProduct rows");
        assert!(out.len() + 1 >= self.out_start.len(), "GaussProduct outputs");
        assert_eq!(self.out_weight.len(), self.out_group.len() * w, "GaussProduct weights");
        // the combinations' and entries' row indices are checked once, in `new`
    }

    /// The portable kernel.
    pub(super) fn steps_portable(&self, k: &[f64], coef: &[f64], rows: &mut [f64], out: &mut [f64]) {
        let (n, w, nf) = (self.modes, self.blocks * LANES, self.sums.len());
        let (f, g) = rows.split_at_mut(nf * w);
        // 2. X_a = Σ_l c_l P_l (l in order)
        for (fv, c) in f.chunks_exact_mut(w).zip(coef.chunks_exact(n)) {
            fv.fill(0.0);
            for (&cl, pl) in c.iter().zip(self.legendre.chunks_exact(w)) {
                for (a, p) in fv.iter_mut().zip(pl) {
                    *a += cl * p;
                }
            }
        }
        let f: &[f64] = f;
        // 3. g = Σ K_c (X ⊙ Y) (combinations in order)
        for (gv, r) in g.chunks_exact_mut(w).zip(self.group_start.windows(2)) {
            gv.fill(0.0);
            for (&(x, y), &kc) in self.combo_sums[r[0]..r[1]].iter().zip(&k[r[0]..r[1]]) {
                for ((a, xv), yv) in gv.iter_mut().zip(&f[x * w..(x + 1) * w]).zip(&f[y * w..(y + 1) * w]) {
                    *a += kc * (xv * yv);
                }
            }
        }
        // 4. the projections
        for (x, r) in out.iter_mut().zip(self.out_start.windows(2)) {
            let mut v = [0.0; LANES];
            for e in r[0]..r[1] {
                let gi = self.out_group[e];
                for (wb, gb) in self.out_weight[e * w..(e + 1) * w].chunks_exact(LANES).zip(g[gi * w..(gi + 1) * w].chunks_exact(LANES)) {
                    for i in 0..LANES {
                        v[i] += wb[i] * gb[i];
                    }
                }
            }
            let u = [v[0] + v[4], v[1] + v[5], v[2] + v[6], v[3] + v[7]];
            *x += (u[0] + u[1]) + (u[2] + u[3]);
        }
    }
}

/// One x86-64 kernel for `NB` blocks of `V` registers of `$lanes` f64 in all (V = NB · 8/lanes),
/// `|$acc| $fold` the per-lane partial sums of an output (8/lanes registers) folded to one
/// 4-lane register (lane i + lane i + 4).
macro_rules! simd_steps {
    ($(#[$doc:meta])* $name:ident, $feature:literal, lanes $lanes:literal, $zero:ident, $set1:ident, $load:ident, $store:ident, $mul:ident, $add:ident,
     |$acc:ident| $fold:expr) => {
        impl GaussProduct {
            $(#[$doc])*
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = $feature)]
            pub(super) unsafe fn $name<const NB: usize, const V: usize>(&self, p: &[f64], amp: &[f64], k: &mut [f64], coef: &mut [f64], rows: &mut [f64], out: &mut [f64]) {
                use std::arch::x86_64::*;
                // 1. (and the sums' coefficients)
                self.prepare(p, amp, k, coef);
                const PER: usize = LANES / $lanes;
                debug_assert_eq!(NB * PER, V);
                debug_assert_eq!(NB, self.blocks);
                let (n, w, nf, ng) = (self.modes, NB * LANES, self.sums.len(), self.group_start.len() - 1);
                let (lp, cp, kp) = (self.legendre.as_ptr(), coef.as_ptr(), k.as_ptr());
                let fp = rows.as_mut_ptr();
                let gp = fp.add(nf * w);
                // 2. X_a = Σ_l c_l P_l
                for s in 0..nf {
                    let mut acc = [$zero(); V];
                    for l in 0..n {
                        let (c, p) = ($set1(*cp.add(s * n + l)), lp.add(l * w));
                        for (v, a) in acc.iter_mut().enumerate() {
                            *a = $add(*a, $mul(c, $load(p.add(v * $lanes))));
                        }
                    }
                    for (v, a) in acc.iter().enumerate() {
                        $store(fp.add(s * w + v * $lanes), *a);
                    }
                }
                // 3. g = Σ K_c (X ⊙ Y)
                let (starts, sums) = (self.group_start.as_ptr(), self.combo_sums.as_ptr());
                for gi in 0..ng {
                    let mut acc = [$zero(); V];
                    for c in *starts.add(gi)..*starts.add(gi + 1) {
                        let (x, y) = *sums.add(c);
                        let (kc, xp, yp) = ($set1(*kp.add(c)), fp.add(x * w), fp.add(y * w));
                        for (v, a) in acc.iter_mut().enumerate() {
                            *a = $add(*a, $mul(kc, $mul($load(xp.add(v * $lanes)), $load(yp.add(v * $lanes)))));
                        }
                    }
                    for (v, a) in acc.iter().enumerate() {
                        $store(gp.add(gi * w + v * $lanes), *a);
                    }
                }
                // 4. the projections
                let (os, og, wp) = (self.out_start.as_ptr(), self.out_group.as_ptr(), self.out_weight.as_ptr());
                for o in 0..self.out_start.len() - 1 {
                    let mut $acc = [$zero(); PER];
                    for e in *os.add(o)..*os.add(o + 1) {
                        let (we, ge) = (wp.add(e * w), gp.add(*og.add(e) * w));
                        for b in 0..NB {
                            for (v, a) in $acc.iter_mut().enumerate() {
                                let i = b * LANES + v * $lanes;
                                *a = $add(*a, $mul($load(we.add(i)), $load(ge.add(i))));
                            }
                        }
                    }
                    let mut u = [0.0f64; 4];
                    _mm256_storeu_pd(u.as_mut_ptr(), $fold);
                    *out.get_unchecked_mut(o) += (u[0] + u[1]) + (u[2] + u[3]);
                }
            }
        }
    };
}

simd_steps! {
    /// The AVX kernel (module doc).
    ///
    /// # Safety
    /// AVX available; the slices as [`check`](GaussProduct::check) asserts.
    steps_avx, "avx", lanes 4, _mm256_setzero_pd, _mm256_set1_pd, _mm256_loadu_pd, _mm256_storeu_pd, _mm256_mul_pd, _mm256_add_pd,
    |acc| _mm256_add_pd(acc[0], acc[1])
}

simd_steps! {
    /// The AVX-512 kernel (module doc).
    ///
    /// # Safety
    /// AVX-512F available; the slices as [`check`](GaussProduct::check) asserts.
    steps_avx512, "avx512f", lanes 8, _mm512_setzero_pd, _mm512_set1_pd, _mm512_loadu_pd, _mm512_storeu_pd, _mm512_mul_pd, _mm512_add_pd,
    |acc| _mm256_add_pd(_mm512_castpd512_pd256(acc[0]), _mm512_extractf64x4_pd::<1>(acc[0]))
}
