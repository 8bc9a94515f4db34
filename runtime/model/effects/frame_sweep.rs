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
}

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
        for l in 0..modes {
            for m in l..modes {
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
                    let u = |x: usize| u32::try_from(x).expect("frame rows: index fits u32");
                    runs.push(Run { l: u(l), m: u(m), n0: u(n0), len: u(n - n0) });
                }
            }
        }
        Self { modes, runs, k }
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
        out[..=m].fill([0.0; 4]);
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: AVX is available (checked just above); every run's l, m < modes and
            // n0 + len ≤ modes + 1 (`new`), the lengths asserted above, Σ len = k.len().
            unsafe { self.sweep_avx(f, out) };
            return;
        }
        self.sweep_portable(f, out);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The AVX sweep is the portable one bit for bit, and both are the ordered-pair sums.
    #[test]
    fn avx_sweep_is_the_portable_one_and_the_sums() {
        let modes = 7;
        // a K with gaps in the targets (two runs for some pairs) and diagonal pairs
        let coef = |n: usize, l: usize, m: usize| if (n + l + m) % 3 == 0 { 0.0 } else { 0.1 + (n * 7 + l * 3 + m * 3) as f64 * 0.013 };
        let rows = FrameRows::new(modes, coef);
        let v = |i: usize, s: f64| (s * i as f64 + 0.3).sin();
        let u: Vec<[f64; 4]> = (0..modes).map(|i| [v(i, 1.1), v(i, 0.7), v(i, 2.3), v(i, 1.1)]).collect();
        let (b, bd): (Vec<f64>, Vec<f64>) = (0..modes).map(|i| (v(i, 1.7), v(i, 0.4))).unzip();
        let w: Vec<[f64; 4]> = (0..modes).map(|i| [b[i], b[i], b[i], bd[i]]).collect();
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
}
