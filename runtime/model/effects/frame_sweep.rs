//! The three frame sums of the second-order frame mapping ([`super::quadratic_frame`]; issue 12,
//! "Performance"; docs/performance.md), per target n:
//!
//!   d_n = Σ K a_l b_m,   s_n = Σ K (ȧ_l b_m + a_l ḃ_m),   f_n = Σ K F_l b_m
//!
//! over the ordered mode pairs, K(n, l, m) symmetric in (l, m). The plan, made once: per
//! unordered pair l ≤ m (in pair order) its *runs* of consecutive targets the selection rules
//! allow (one run per pair for the even mode set k = 2, 4, …: the targets |l − m| ≤ j ≤ l + m,
//! j even, are consecutive indices), each run with its K broadcast to 4 lanes (the diagonal
//! pairs' K halved: their symmetric products count l = m twice). The sweep forms a pair's
//! products once, in one register, from the per-mode factors u = [a, ȧ, F, a] and
//! v = [b, b, b, ḃ]: u_l v_m + u_m v_l = [a_l b_m + a_m b_l, ȧ_l b_m + ȧ_m b_l, F_l b_m + F_m b_l,
//! a_l ḃ_m + a_m ḃ_l], the last lane added onto the second; and adds K·w into the 4-lane sum of
//! each target of its run: no per-row index, no bounds checks, one stream of coefficients. Every
//! target's sum receives its terms in pair order, each pair's products summed in the same
//! order, so the result is bit for bit that of the per-target row sweep it replaces.
//!
//! With few targets (at most [`DENSE_MAX`]: every target's 4-lane sum fits in an AVX register)
//! the AVX sweep runs *dense*: per pair, K·w added into every target's register, K = 0 where the
//! selection rules exclude the target (no runs, no loads and stores of the sums). A sum starts
//! at +0 and so, rounding to nearest, is never −0; adding 0·w = ±0 to it changes no bit while w
//! is finite. A non-finite w makes its pair's real targets non-finite, so when any sum comes out
//! non-finite the sparse sweep runs instead: either way the result is the sparse sweep's, bit for
//! bit.

/// One run: pair (l, m) (mode indices), targets `n0 .. n0 + len`.
#[derive(Debug, Clone, Copy)]
struct Run {
    l: u32,
    m: u32,
    n0: u32,
    len: u32,
}

/// The planned rows of the three sums (module doc).
#[derive(Debug)]
pub struct FrameRows {
    modes: usize,
    runs: Vec<Run>,
    /// per row (run by run, target by target) K, broadcast
    k: Vec<[f64; 4]>,
    /// the dense plan (module doc; empty above [`DENSE_MAX`] targets): per pair with runs, in
    /// pair order, its factor offsets (4l, 4m) ...
    dense_pairs: Vec<[u32; 2]>,
    /// ... and K of every target 0..=modes, broadcast (0 outside its runs)
    dense_k: Vec<[f64; 4]>,
}

/// Most targets (modes + 1) of the dense AVX sweep (module doc).
const DENSE_MAX: usize = 12;

/// The per-mode factors of a sweep: `u[i] = [a, ȧ, F, a]`, `v[i] = [b, b, b, ḃ]` (ḃ = ḃ⁽¹⁾).
pub struct Factors<'a> {
    pub u: &'a [[f64; 4]],
    pub v: &'a [[f64; 4]],
}

impl FrameRows {
    /// `modes` mode indices, targets 0..=modes; `coef(n, l, m)` = K(n, l, m) (0 outside the
    /// selection rules).
    pub fn new(modes: usize, coef: impl Fn(usize, usize, usize) -> f64) -> Self {
        let (mut runs, mut k) = (Vec::new(), Vec::new());
        let (mut dense_pairs, mut dense_k) = (Vec::new(), Vec::new());
        let u = |x: usize| u32::try_from(x).expect("frame rows: index fits u32");
        for l in 0..modes {
            for m in l..modes {
                let first = k.len();
                let mut n = 0;
                while n <= modes {
                    if coef(n, l, m) == 0.0 {
                        n += 1;
                        continue;
                    }
                    let n0 = n;
                    while n <= modes && coef(n, l, m) != 0.0 {
                        let c = coef(n, l, m);
                        k.push([if l == m { c / 2.0 } else { c }; 4]);
                        n += 1;
                    }
                    runs.push(Run { l: u(l), m: u(m), n0: u(n0), len: u(n - n0) });
                }
                if k.len() > first && modes < DENSE_MAX {
                    // the same K, halved on the diagonal, as the runs'
                    dense_pairs.push([u(4 * l), u(4 * m)]);
                    dense_k.extend((0..=modes).map(|n| match coef(n, l, m) {
                        0.0 => [0.0; 4],
                        c => [if l == m { c / 2.0 } else { c }; 4],
                    }));
                }
            }
        }
        Self { modes, runs, k, dense_pairs, dense_k }
    }

    /// Number of (target, unordered pair) rows.
    pub fn len(&self) -> usize {
        self.k.len()
    }

    /// out[n] = [d_n, s_n, f_n, ·] for n = 0..=modes (`out` overwritten there; the last lane
    /// is a by-product).
    pub fn sweep(&self, f: &Factors<'_>, out: &mut [[f64; 4]]) {
        let m = self.modes;
        // the bounds the kernels rely on (the AVX one reads without further checks)
        assert!(f.u.len() >= m && f.v.len() >= m && out.len() > m, "frame rows: factor lengths");
        #[cfg(target_arch = "x86_64")]
        if crate::simd::avx(crate::simd::Kernel::FrameSweep) {
            // SAFETY: (both kernels) AVX is available (`simd::avx` checked); every pair's
            // l, m < modes, every run's n0 + len ≤ modes + 1 and the dense table modes + 1
            // targets per pair (`new`), the lengths asserted above, Σ len = k.len().
            let dense = unsafe {
                match m + 1 {
                    1 => self.dense_avx::<1>(f, out),
                    2 => self.dense_avx::<2>(f, out),
                    3 => self.dense_avx::<3>(f, out),
                    4 => self.dense_avx::<4>(f, out),
                    5 => self.dense_avx::<5>(f, out),
                    6 => self.dense_avx::<6>(f, out),
                    7 => self.dense_avx::<7>(f, out),
                    8 => self.dense_avx::<8>(f, out),
                    9 => self.dense_avx::<9>(f, out),
                    10 => self.dense_avx::<10>(f, out),
                    11 => self.dense_avx::<11>(f, out),
                    DENSE_MAX => self.dense_avx::<DENSE_MAX>(f, out),
                    _ => false,
                }
            };
            if !dense {
                out[..=m].fill([0.0; 4]);
                // SAFETY: as above.
                unsafe { self.sweep_avx(f, out) };
            }
            return;
        }
        out[..=m].fill([0.0; 4]);
        self.sweep_portable(f, out);
    }

    /// The dense sweep (module doc) over `T` = modes + 1 targets into `out[..T]`; false (and
    /// `out` to be overwritten by the sparse sweep) when a sum is not finite.
    ///
    /// # Safety
    /// AVX available; `T` = modes + 1; the lengths [`sweep`](Self::sweep) asserts; `self` built
    /// by [`new`](Self::new).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn dense_avx<const T: usize>(&self, f: &Factors<'_>, out: &mut [[f64; 4]]) -> bool {
        use std::arch::x86_64::*;
        // SAFETY: the caller's contract (# Safety): every pair's l, m < modes and the dense table
        // holds T targets per pair (`new`), so each 4-lane load and store is inside `f.u`, `f.v`,
        // `dense_k` and `out`; AVX is enabled on this function.
        unsafe {
            let (up, vp) = (f.u.as_ptr().cast::<f64>(), f.v.as_ptr().cast::<f64>());
            let mut kp = self.dense_k.as_ptr().cast::<f64>();
            let mut acc = [_mm256_setzero_pd(); T];
            for &[l, m] in &self.dense_pairs {
                let (l, m) = (l as usize, m as usize);
                // the pair's products as in `sweep_avx`
                let x = _mm256_add_pd(_mm256_mul_pd(_mm256_loadu_pd(up.add(l)), _mm256_loadu_pd(vp.add(m))), _mm256_mul_pd(_mm256_loadu_pd(up.add(m)), _mm256_loadu_pd(vp.add(l))));
                let w = _mm256_blend_pd::<0b0010>(x, _mm256_add_pd(x, _mm256_permute2f128_pd::<0x01>(x, x)));
                for (t, a) in acc.iter_mut().enumerate() {
                    *a = _mm256_add_pd(*a, _mm256_mul_pd(_mm256_loadu_pd(kp.add(4 * t)), w));
                }
                kp = kp.add(4 * T);
            }
            // x − x is 0 for finite x, NaN otherwise
            let mut bad = _mm256_setzero_pd();
            let op = out.as_mut_ptr().cast::<f64>();
            for (t, a) in acc.iter().enumerate() {
                bad = _mm256_add_pd(bad, _mm256_sub_pd(*a, *a));
                _mm256_storeu_pd(op.add(4 * t), *a);
            }
            _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_UNORD_Q>(bad, bad)) == 0
        }
    }

    /// A pair's products, lane by lane (module doc).
    #[inline(always)]
    fn pair(ul: &[f64; 4], um: &[f64; 4], vl: &[f64; 4], vm: &[f64; 4]) -> [f64; 4] {
        let mut w: [f64; 4] = std::array::from_fn(|i| ul[i] * vm[i] + um[i] * vl[i]);
        w[1] += w[3];
        w
    }

    /// The sweep lane by lane (mul, then add: no FMA).
    fn sweep_portable(&self, f: &Factors<'_>, out: &mut [[f64; 4]]) {
        let mut k = self.k.iter();
        for r in &self.runs {
            let (l, m) = (r.l as usize, r.m as usize);
            let w = Self::pair(&f.u[l], &f.u[m], &f.v[l], &f.v[m]);
            for (o, c) in out[r.n0 as usize..(r.n0 + r.len) as usize].iter_mut().zip(&mut k) {
                for i in 0..4 {
                    o[i] += c[i] * w[i];
                }
            }
        }
    }

    /// [`sweep_portable`](Self::sweep_portable) in one AVX register per pair and target: the
    /// same products and sums per lane, so bit for bit its result.
    ///
    /// # Safety
    /// AVX available; the lengths [`sweep`](Self::sweep) asserts; `self` built by
    /// [`new`](Self::new).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn sweep_avx(&self, f: &Factors<'_>, out: &mut [[f64; 4]]) {
        use std::arch::x86_64::*;
        // SAFETY: the caller's contract (# Safety): every run's pair and targets are inside the
        // factors and `out` (`new`, the lengths `sweep` asserts), Σ len = k.len(); AVX is enabled.
        unsafe {
            let (up, vp) = (f.u.as_ptr().cast::<f64>(), f.v.as_ptr().cast::<f64>());
            let (op, mut kp) = (out.as_mut_ptr(), self.k.as_ptr());
            for r in &self.runs {
                let (l, m) = (4 * r.l as usize, 4 * r.m as usize);
                let x = _mm256_add_pd(_mm256_mul_pd(_mm256_loadu_pd(up.add(l)), _mm256_loadu_pd(vp.add(m))), _mm256_mul_pd(_mm256_loadu_pd(up.add(m)), _mm256_loadu_pd(vp.add(l))));
                // lane 1 += lane 3: [x2, x3, x0, x1] added, lane 1 of the sum taken
                let w = _mm256_blend_pd::<0b0010>(x, _mm256_add_pd(x, _mm256_permute2f128_pd::<0x01>(x, x)));
                let o = op.add(r.n0 as usize).cast::<f64>();
                for t in 0..r.len as usize {
                    let (ot, kt) = (o.add(4 * t), kp.add(t).cast::<f64>());
                    _mm256_storeu_pd(ot, _mm256_add_pd(_mm256_loadu_pd(ot), _mm256_mul_pd(_mm256_loadu_pd(kt), w)));
                }
                kp = kp.add(r.len as usize);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A K with gaps in the targets (two runs for some pairs) and diagonal pairs.
    fn coef(n: usize, l: usize, m: usize) -> f64 {
        if (n + l + m) % 3 == 0 { 0.0 } else { 0.1 + (n * 7 + l * 3 + m * 3) as f64 * 0.013 }
    }

    fn factors(modes: usize) -> (Vec<[f64; 4]>, Vec<f64>, Vec<f64>, Vec<[f64; 4]>) {
        let v = |i: usize, s: f64| (s * i as f64 + 0.3).sin();
        let u: Vec<[f64; 4]> = (0..modes).map(|i| [v(i, 1.1), v(i, 0.7), v(i, 2.3), v(i, 1.1)]).collect();
        let (b, bd): (Vec<f64>, Vec<f64>) = (0..modes).map(|i| (v(i, 1.7), v(i, 0.4))).unzip();
        let w: Vec<[f64; 4]> = (0..modes).map(|i| [b[i], b[i], b[i], bd[i]]).collect();
        (u, b, bd, w)
    }

    /// The AVX sweep is the portable one bit for bit, and both are the ordered-pair sums.
    #[test]
    fn avx_sweep_is_the_portable_one_and_the_sums() {
        let modes = 7;
        let rows = FrameRows::new(modes, coef);
        let (u, b, bd, w) = factors(modes);
        let f = Factors { u: &u, v: &w };
        // the portable sweep adds into zeros; `sweep` overwrites
        let (mut p, mut s) = (vec![[0.0; 4]; modes + 1], vec![[9.0; 4]; modes + 1]);
        rows.sweep_portable(&f, &mut p);
        rows.sweep(&f, &mut s);
        for (x, y) in p.iter().zip(&s) {
            assert_eq!(x.map(f64::to_bits), y.map(f64::to_bits));
        }
        for n in 0..=modes {
            let (mut d, mut r, mut g) = (0.0, 0.0, 0.0);
            for l in 0..modes {
                for m in 0..modes {
                    let c = coef(n, l.min(m), l.max(m));
                    d += c * u[l][0] * b[m];
                    r += c * (u[l][1] * b[m] + u[l][0] * bd[m]);
                    g += c * u[l][2] * b[m];
                }
            }
            for (x, y) in [(d, s[n][0]), (r, s[n][1]), (g, s[n][2])] {
                assert!((x - y).abs() <= 1e-13 * (1.0 + x.abs()), "n = {n}: {x} against {y}");
            }
        }
    }

    /// The dense AVX sweep (every mode count it takes, one beyond) is the sparse AVX sweep bit
    /// for bit, zero sums included; with a non-finite factor `sweep` gives the sparse result.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn dense_sweep_is_the_sparse_one() {
        if !crate::simd::test_can_run(crate::simd::Level::Avx2Fma, "frame sweep: dense AVX against sparse AVX") {
            return;
        }
        for modes in 1..=DENSE_MAX {
            // every third mode zero: sums of zero terms, and cancelling ones
            let (mut u, _, _, mut w) = factors(modes);
            for i in (0..modes).step_by(3) {
                u[i] = [0.0, -0.0, 0.0, -0.0];
            }
            if modes > 2 {
                u[1] = [-u[0][0], u[0][1], -u[0][2], u[0][3]];
                w[1] = w[0];
            }
            let rows = FrameRows::new(modes, coef);
            let check = |u: &[[f64; 4]], w: &[[f64; 4]]| {
                let f = Factors { u, v: w };
                let (mut sparse, mut s) = (vec![[0.0; 4]; modes + 1], vec![[9.0; 4]; modes + 1]);
                // SAFETY: AVX (checked above); lengths as `sweep` asserts.
                unsafe { rows.sweep_avx(&f, &mut sparse) };
                rows.sweep(&f, &mut s);
                for (x, y) in sparse.iter().zip(&s) {
                    assert_eq!(x.map(f64::to_bits), y.map(f64::to_bits), "{modes} modes");
                }
            };
            check(&u, &w);
            let mut bad = u.clone();
            bad[modes - 1][0] = f64::INFINITY;
            check(&bad, &w);
            bad[modes - 1][0] = f64::NAN;
            check(&bad, &w);
        }
    }
}
