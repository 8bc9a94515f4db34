//! Step 4 of [`GaussProduct`]: out_o += Σ_{groups of o} Σ_nodes (L_j^c (2j + 1)/2 w P_j) · g.
//! Each output is one partial sum per lane of a node block (groups in order, each's blocks in
//! order), then lane i + 4 added onto lane i and those four summed pairwise. The AVX and AVX-512
//! kernels are that order with explicit intrinsics (left to itself, the compiler vectorised the
//! portable loop across the lanes' reduction, two lanes per register with shuffles), no FMA: bit
//! for bit the portable result.

use super::{GaussProduct, LANES};

impl GaussProduct {
    /// The bounds every kernel relies on: `g` holds every group's blocks, `out` every output.
    fn check(&self, g: &[f64], out: &[f64]) {
        let w = self.blocks * LANES;
        assert!(g.len() >= (self.group_start.len() - 1) * w, "GaussProduct groups");
        assert!(out.len() + 1 >= self.out_start.len(), "GaussProduct outputs");
        assert_eq!(self.out_weight.len(), self.out_group.len() * w, "GaussProduct weights");
    }

    /// The portable step 4.
    pub(super) fn project(&self, g: &[f64], out: &mut [f64]) {
        self.check(g, out);
        let w = self.blocks * LANES;
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

    /// Step 4 with two AVX registers per block (lanes 0–3, 4–7).
    ///
    /// # Safety
    /// AVX available.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    pub(super) unsafe fn project_avx(&self, g: &[f64], out: &mut [f64]) {
        use std::arch::x86_64::*;
        self.check(g, out);
        let (nb, w) = (self.blocks, self.blocks * LANES);
        let (wp, gp) = (self.out_weight.as_ptr(), g.as_ptr());
        for (x, r) in out.iter_mut().zip(self.out_start.windows(2)) {
            let (mut lo, mut hi) = (_mm256_setzero_pd(), _mm256_setzero_pd());
            for (e, &gi) in self.out_group.iter().enumerate().take(r[1]).skip(r[0]) {
                // SAFETY: entry e < out_group.len() and group gi < groups (`new`), so both rows
                // are in range (`check`).
                let (we, ge) = (wp.add(e * w), gp.add(gi * w));
                for b in 0..nb {
                    let (wb, gb) = (we.add(b * LANES), ge.add(b * LANES));
                    lo = _mm256_add_pd(lo, _mm256_mul_pd(_mm256_loadu_pd(wb), _mm256_loadu_pd(gb)));
                    hi = _mm256_add_pd(hi, _mm256_mul_pd(_mm256_loadu_pd(wb.add(4)), _mm256_loadu_pd(gb.add(4))));
                }
            }
            let mut u = [0.0f64; 4];
            _mm256_storeu_pd(u.as_mut_ptr(), _mm256_add_pd(lo, hi));
            *x += (u[0] + u[1]) + (u[2] + u[3]);
        }
    }

    /// Step 4 with one AVX-512 register per block.
    ///
    /// # Safety
    /// AVX-512F available.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    pub(super) unsafe fn project_avx512(&self, g: &[f64], out: &mut [f64]) {
        use std::arch::x86_64::*;
        self.check(g, out);
        let (nb, w) = (self.blocks, self.blocks * LANES);
        let (wp, gp) = (self.out_weight.as_ptr(), g.as_ptr());
        for (x, r) in out.iter_mut().zip(self.out_start.windows(2)) {
            let mut acc = _mm512_setzero_pd();
            for (e, &gi) in self.out_group.iter().enumerate().take(r[1]).skip(r[0]) {
                // SAFETY: as in `project_avx`.
                let (we, ge) = (wp.add(e * w), gp.add(gi * w));
                for b in 0..nb {
                    acc = _mm512_add_pd(acc, _mm512_mul_pd(_mm512_loadu_pd(we.add(b * LANES)), _mm512_loadu_pd(ge.add(b * LANES))));
                }
            }
            let mut u = [0.0f64; 4];
            _mm256_storeu_pd(u.as_mut_ptr(), _mm256_add_pd(_mm512_castpd512_pd256(acc), _mm512_extractf64x4_pd::<1>(acc)));
            *x += (u[0] + u[1]) + (u[2] + u[3]);
        }
    }
}
