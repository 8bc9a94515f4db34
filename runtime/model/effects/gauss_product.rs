//! The bilinear Legendre sums of the second-order shell terms by Gauss–Legendre quadrature
//! (issue 12, "Performance"; docs/performance.md, branch `qmem`).
//!
//! A generated second-order load on target j (effects/quadratic_membrane.rs) is
//!
//!   F_j = Σ_T p_T Σ_{l,m} C(j, l, m) N_T(L_l, L_m, L_j)/D · first_T(l) · second_T(m),
//!
//! C(j, l, m) = (2j + 1)/2 ∫ P_l P_m P_j dx, N_T = Σ v · L_l^a L_m^b L_j^c (the generated closed
//! form), L_n = n(n + 1), D = 1 (normal) or L_j (tangential). Every monomial of N_T factors:
//! Σ_{l,m} C · L_l^a L_m^b L_j^c x_l y_m = L_j^c (2j + 1)/2 ∫ X_a Y_b P_j dx with the mode sums
//! X_a(x) = Σ_l L_l^a x_l P_l(x), Y_b likewise. So the loads are, exactly (the integrand is a
//! polynomial of degree ≤ 2 k_max + j_max, integrated by the Gauss–Legendre rule of that degree):
//!
//! 1. per rhs, the coefficient K of each distinct (load, L_j power, X_a, Y_b) *combination*, the
//!    prefactors p_T summed into it;
//! 2. the mode sums X_a, Y_b at the nodes;
//! 3. per (load, L_j power) *group* g(x) = Σ K X_a Y_b at the nodes;
//! 4. per output, Σ_groups L_j^c (2j + 1)/2 Σ_nodes w P_j g.
//!
//! At k ≤ 16 (8 modes, 13 nodes for the even modes) this is ≈ 3× fewer multiply-adds than the
//! (target, pair) rows of [`super::pair_rows`], which walk C · N per row and slot; the rows stay
//! the Jacobian's table. The result differs from the rows' by rounding only (tests below and
//! tests/suite/quadratic_membrane.rs). Nodes are in blocks of [`LANES`]; every step is lane-wise
//! or summed in a fixed order, and nothing is fused (no FMA), so the AVX / AVX-512 clones of the
//! kernel give the portable result bit for bit.

use std::cell::RefCell;

/// Nodes per block (one AVX-512 register, two AVX, four SSE2).
const LANES: usize = 8;
type Block = [f64; LANES];

/// One monomial of one table term: `value` · p_mono · L_l^a L_m^b L_j^power on output `set`,
/// first amplitude (kind, a) of mode l, second (kind, b) of mode m.
#[derive(Debug, Clone, Copy)]
pub struct Monomial {
    pub set: usize,
    pub power: i32,
    pub first: (usize, u32),
    pub second: (usize, u32),
    pub mono: usize,
    pub value: f64,
}

#[derive(Debug)]
pub struct GaussProduct {
    modes: usize,
    kinds: usize,
    blocks: usize,
    prefactors: usize,
    /// P_{k_l} at the nodes: (mode l, block) → LANES (padding nodes 0)
    legendre: Vec<f64>,
    /// the mode sums: (amplitude kind, power a), and L_l^a per (sum, mode l)
    sums: Vec<(usize, u32)>,
    lpow: Vec<f64>,
    /// combinations, grouped: group g is `group_start[g]..group_start[g + 1]`; each is a pair
    /// of mode sums, and its numerator value per prefactor (prefactor-major: i · combos + c)
    group_start: Vec<usize>,
    combo_sums: Vec<(usize, usize)>,
    combo_value: Vec<f64>,
    /// per output o, `out_start[o]..out_start[o + 1]`: (group, its weights L_j^c (2j+1)/2 w P_j
    /// per block)
    out_start: Vec<usize>,
    out_group: Vec<usize>,
    out_weight: Vec<f64>,
}

thread_local! {
    /// Scratch: K, the sums' mode coefficients, the sums and the groups at the nodes.
    static SCRATCH: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
}

/// The n-point Gauss–Legendre rule on [−1, 1]: (nodes, weights), by Newton's method on P_n.
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let (mut x, mut w) = (vec![0.0; n], vec![0.0; n]);
    for i in 0..n.div_ceil(2) {
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            let (p, d) = legendre_and_derivative(n, z);
            dp = d;
            let dz = p / d;
            z -= dz;
            if dz.abs() <= 1e-16 {
                break;
            }
        }
        let (_, d) = legendre_and_derivative(n, z);
        if d != 0.0 {
            dp = d;
        }
        x[i] = -z;
        x[n - 1 - i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
        w[n - 1 - i] = w[i];
    }
    (x, w)
}

/// (P_n(x), P_n′(x)) by the three-term recurrence.
fn legendre_and_derivative(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 1..n {
        let p2 = ((2 * k + 1) as f64 * x * p1 - k as f64 * p0) / (k + 1) as f64;
        (p0, p1) = (p1, p2);
    }
    (p1, n as f64 * (x * p1 - p0) / (x * x - 1.0))
}

/// P_k(x).
fn legendre(k: usize, x: f64) -> f64 {
    legendre_and_derivative(k, x).0
}

impl GaussProduct {
    /// `orders`: k of each mode index; `outputs`: (set, j) of each output; `kinds` amplitude
    /// kinds, `prefactors` prefactors; `terms`: every monomial of every table term.
    pub fn new(orders: &[usize], outputs: &[(usize, usize)], kinds: usize, prefactors: usize, terms: &[Monomial]) -> Self {
        let n = orders.len();
        let kmax = orders.iter().copied().max().unwrap_or(0);
        let jmax = outputs.iter().map(|o| o.1).max().unwrap_or(0);
        let degree = 2 * kmax + jmax;
        let (x, w) = gauss_legendre(degree / 2 + 1);
        // all even: the integrands are even, so the nodes x ≥ 0 (weights doubled but at x = 0)
        let even = orders.iter().chain(outputs.iter().map(|o| &o.1)).all(|k| k % 2 == 0);
        let nodes: Vec<(f64, f64)> = if even {
            x.iter().zip(&w).filter(|(x, _)| **x >= 0.0).map(|(&x, &w)| (x, if x > 0.0 { 2.0 * w } else { w })).collect()
        } else {
            x.iter().copied().zip(w.iter().copied()).collect()
        };
        let blocks = nodes.len().div_ceil(LANES).max(1);
        // padding nodes: P = 0 and weight 0
        let at_nodes = |f: &dyn Fn(f64, f64) -> f64| -> Vec<f64> {
            let mut v = vec![0.0; blocks * LANES];
            for (vi, (x, w)) in v.iter_mut().zip(&nodes) {
                *vi = f(*x, *w);
            }
            v
        };
        let legendre_nodes: Vec<f64> = orders.iter().flat_map(|&k| at_nodes(&|x, _| legendre(k, x))).collect();
        let big = |k: usize| (k * (k + 1)) as f64;
        // mode sums and combinations, in order of first appearance
        let mut sums: Vec<(usize, u32)> = Vec::new();
        let mut index = |s: (usize, u32)| sums.iter().position(|x| *x == s).unwrap_or_else(|| {
            sums.push(s);
            sums.len() - 1
        });
        type Key = (usize, i32, usize, usize);
        let mut combos: Vec<(Key, Vec<f64>)> = Vec::new();
        for t in terms {
            assert!(t.first.0 < kinds && t.second.0 < kinds && t.mono < prefactors, "GaussProduct: term out of range");
            let (mut f, mut s) = (index(t.first), index(t.second));
            if f > s {
                // X_a Y_b = Y_b X_a: one combination
                std::mem::swap(&mut f, &mut s);
            }
            let key = (t.set, t.power, f, s);
            let c = match combos.iter().position(|(k, _)| *k == key) {
                Some(c) => c,
                None => {
                    combos.push((key, vec![0.0; prefactors]));
                    combos.len() - 1
                }
            };
            combos[c].1[t.mono] += t.value;
        }
        // groups (set, power) in order of first appearance, each's combinations together
        let mut groups: Vec<(usize, i32)> = Vec::new();
        for (k, _) in &combos {
            if !groups.contains(&(k.0, k.1)) {
                groups.push((k.0, k.1));
            }
        }
        let (mut group_start, mut combo_sums, mut ordered) = (vec![0], Vec::new(), Vec::new());
        for g in &groups {
            for (k, v) in combos.iter().filter(|(k, _)| (k.0, k.1) == *g) {
                combo_sums.push((k.2, k.3));
                ordered.push(v.clone());
            }
            group_start.push(combo_sums.len());
        }
        let nc = ordered.len();
        let mut combo_value = vec![0.0; prefactors * nc];
        for (c, v) in ordered.iter().enumerate() {
            for (i, x) in v.iter().enumerate() {
                combo_value[i * nc + c] = *x;
            }
        }
        let lpow = sums.iter().flat_map(|&(_, a)| orders.iter().map(move |&k| big(k).powi(a as i32))).collect();
        let (mut out_start, mut out_group, mut out_weight) = (vec![0], Vec::new(), Vec::new());
        for &(set, j) in outputs {
            for (g, &(s, power)) in groups.iter().enumerate() {
                if s != set || (power < 0 && j == 0) {
                    continue;
                }
                let scale = big(j).powi(power) * (2 * j + 1) as f64 / 2.0;
                out_group.push(g);
                out_weight.extend(at_nodes(&|x, w| scale * w * legendre(j, x)));
            }
            out_start.push(out_group.len());
        }
        Self { modes: n, kinds, blocks, prefactors, legendre: legendre_nodes, sums, lpow, group_start, combo_sums, combo_value, out_start, out_group, out_weight }
    }

    /// Number of combinations (distinct (load, L_j power, mode-sum pair)).
    #[cfg(test)]
    pub fn combinations(&self) -> usize {
        self.combo_sums.len()
    }

    /// out[o] += output o, with prefactors `p` and amplitudes `amp` (kind-major: kind · modes + l).
    pub fn eval(&self, p: &[f64], amp: &[f64], out: &mut [f64]) {
        assert!(p.len() >= self.prefactors && amp.len() >= self.kinds * self.modes && out.len() + 1 >= self.out_start.len(), "GaussProduct::eval");
        let (nc, nf, nb, ng) = (self.combo_sums.len(), self.sums.len(), self.blocks, self.group_start.len() - 1);
        let len = nc + nf * self.modes + (nf + ng) * nb * LANES;
        SCRATCH.with(|cell| {
            let mut buf = cell.borrow_mut();
            if buf.len() < len {
                buf.resize(len, 0.0);
            }
            let s = &mut buf[..len];
            #[cfg(target_arch = "x86_64")]
            {
                if std::arch::is_x86_feature_detected!("avx512f") {
                    // SAFETY: the processor has AVX-512F (checked just above).
                    return unsafe { self.kernel_avx512(p, amp, s, out) };
                }
                if std::arch::is_x86_feature_detected!("avx") {
                    // SAFETY: the processor has AVX (checked just above).
                    return unsafe { self.kernel_avx(p, amp, s, out) };
                }
            }
            self.kernel(p, amp, s, out)
        })
    }

    /// [`kernel`](Self::kernel) compiled for AVX (the same operations: bit for bit its result).
    ///
    /// # Safety
    /// AVX available.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn kernel_avx(&self, p: &[f64], amp: &[f64], s: &mut [f64], out: &mut [f64]) {
        self.kernel(p, amp, s, out)
    }

    /// [`kernel`](Self::kernel) compiled for AVX-512F.
    ///
    /// # Safety
    /// AVX-512F available.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    unsafe fn kernel_avx512(&self, p: &[f64], amp: &[f64], s: &mut [f64], out: &mut [f64]) {
        self.kernel(p, amp, s, out)
    }

    /// Steps 1–4 of the module doc; `s` the scratch.
    #[inline(always)]
    fn kernel(&self, p: &[f64], amp: &[f64], s: &mut [f64], out: &mut [f64]) {
        let (n, nb) = (self.modes, self.blocks);
        let (nc, nf) = (self.combo_sums.len(), self.sums.len());
        let (k, rest) = s.split_at_mut(nc);
        let (coef, rest) = rest.split_at_mut(nf * n);
        let (f, g) = rest.split_at_mut(nf * nb * LANES);
        // 1. K_c = Σ_i value_{c,i} p_i (i in order)
        k.fill(0.0);
        for (i, &pi) in p[..self.prefactors].iter().enumerate() {
            for (kc, v) in k.iter_mut().zip(&self.combo_value[i * nc..(i + 1) * nc]) {
                *kc += v * pi;
            }
        }
        // 2. the mode sums X_a = Σ_l (L_l^a x_l) P_l at the nodes (l in order)
        for ((c, lp), &(kind, _)) in coef.chunks_exact_mut(n).zip(self.lpow.chunks_exact(n)).zip(&self.sums) {
            for ((ci, li), x) in c.iter_mut().zip(lp).zip(&amp[kind * n..(kind + 1) * n]) {
                *ci = li * x;
            }
        }
        for (fs, c) in f.chunks_exact_mut(nb * LANES).zip(coef.chunks_exact(n)) {
            for (b, fv) in fs.chunks_exact_mut(LANES).enumerate() {
                let mut acc = [0.0; LANES];
                for (l, &cl) in c.iter().enumerate() {
                    let pl = block(&self.legendre, l * nb + b);
                    for i in 0..LANES {
                        acc[i] += cl * pl[i];
                    }
                }
                fv.copy_from_slice(&acc);
            }
        }
        let f: &[f64] = f;
        // 3. g = Σ K_c X Y per group (combinations in order)
        for (gs, r) in g.chunks_exact_mut(nb * LANES).zip(self.group_start.windows(2)) {
            for (b, gv) in gs.chunks_exact_mut(LANES).enumerate() {
                let mut acc = [0.0; LANES];
                for (&(x, y), &kc) in self.combo_sums[r[0]..r[1]].iter().zip(&k[r[0]..r[1]]) {
                    let (xv, yv) = (block(f, x * nb + b), block(f, y * nb + b));
                    for i in 0..LANES {
                        acc[i] += kc * (xv[i] * yv[i]);
                    }
                }
                gv.copy_from_slice(&acc);
            }
        }
        let g: &[f64] = g;
        // 4. the projections (groups, then blocks, in order; the lanes summed pairwise)
        for (o, x) in out.iter_mut().enumerate().take(self.out_start.len() - 1) {
            let mut acc = [0.0; LANES];
            for e in self.out_start[o]..self.out_start[o + 1] {
                let gi = self.out_group[e];
                for b in 0..nb {
                    let (wv, gv) = (block(&self.out_weight, e * nb + b), block(g, gi * nb + b));
                    for i in 0..LANES {
                        acc[i] += wv[i] * gv[i];
                    }
                }
            }
            *x += ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
        }
    }
}

/// Block i of `v`.
#[inline(always)]
fn block(v: &[f64], i: usize) -> &Block {
    v[i * LANES..(i + 1) * LANES].try_into().expect("a block")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coefficients::quadratic_lookup::ppp;

    /// C(j, l, m) = (2j + 1)/2 ∫ P_l P_m P_j from the generated exact table.
    fn projection(j: usize, l: usize, m: usize) -> f64 {
        ppp(l, m, j) * (2.0 * j as f64 + 1.0) / 2.0
    }

    /// (2j + 1)/2 ∫ P_l P_m P_j by the Adams–Neumann closed form (any parities): with
    /// 2s = l + m + j even, 2/(2s + 1) · A(s − l) A(s − m) A(s − j)/A(s), A(k) = (2k)!/(2^k k!)².
    fn adams(j: usize, l: usize, m: usize) -> f64 {
        let s2 = l + m + j;
        if s2 % 2 == 1 || j > l + m || l > m + j || m > l + j {
            return 0.0;
        }
        let s = s2 / 2;
        let a = |k: usize| (1..=k).fold(1.0, |acc, i| acc * (2 * i - 1) as f64 / (2 * i) as f64);
        (2.0 * j as f64 + 1.0) / 2.0 * 2.0 / (2 * s + 1) as f64 * a(s - l) * a(s - m) * a(s - j) / a(s)
    }

    /// The rule integrates P_l P_m P_j exactly (to rounding) for every l, m, j of the mode set:
    /// the generated triple products at k ≤ 32 even (half the nodes), the closed form at k ≤ 12
    /// all (every node).
    #[test]
    fn the_rule_gives_the_generated_triple_products() {
        for orders in [(1..=16).map(|i| 2 * i).collect::<Vec<usize>>(), (1..=12).collect()] {
            let even = orders.iter().all(|k| k % 2 == 0);
            let outputs: Vec<(usize, usize)> = std::iter::once(0).chain(orders.iter().copied()).map(|j| (0, j)).collect();
            let one = [Monomial { set: 0, power: 0, first: (0, 0), second: (1, 0), mono: 0, value: 1.0 }];
            let g = GaussProduct::new(&orders, &outputs, 2, 1, &one);
            let n = orders.len();
            let mut worst: f64 = 0.0;
            for l in 0..n {
                for m in 0..n {
                    let mut amp = vec![0.0; 2 * n];
                    (amp[l], amp[n + m]) = (1.0, 1.0);
                    let mut out = vec![0.0; outputs.len()];
                    g.eval(&[1.0], &amp, &mut out);
                    for (&(_, j), got) in outputs.iter().zip(&out) {
                        let want = if even { projection(j, orders[l], orders[m]) } else { adams(j, orders[l], orders[m]) };
                        worst = worst.max((got - want).abs());
                    }
                }
            }
            // rounding of a sum over ≤ 49 nodes of O(1) terms
            assert!(worst <= 1e-14, "orders {orders:?}: worst |Δ C| {worst:e}");
        }
        // and the rule is the smallest exact one: one node fewer misses the top degree
        let cube = |n: usize| {
            let (x, w) = gauss_legendre(n);
            x.iter().zip(&w).map(|(&x, &w)| w * legendre(32, x).powi(3)).sum::<f64>() * 65.0 / 2.0
        };
        let exact = projection(32, 32, 32);
        assert!((adams(32, 32, 32) - exact).abs() <= 1e-15, "the closed form against the table");
        assert!((cube(49) - exact).abs() <= 1e-14, "49 nodes: {} against {exact}", cube(49));
        assert!((cube(48) - exact).abs() > 1e-6, "48 nodes: {} against {exact}", cube(48));
    }

    /// The four steps equal the plain sum Σ_{l,m} C · v p L_l^a L_m^b L_j^c x_l y_m, with powers
    /// of L_j from −1 to 3, symmetric and asymmetric kinds, two output sets and three prefactors.
    #[test]
    fn eval_is_the_plain_sum() {
        let orders: Vec<usize> = (1..=8).map(|i| 2 * i).collect();
        let n = orders.len();
        let mut outputs: Vec<(usize, usize)> = std::iter::once(0).chain(orders.iter().copied()).map(|j| (0, j)).collect();
        outputs.extend(orders.iter().map(|&j| (1, j)));
        let mut terms = Vec::new();
        for (i, (set, power, fk, fa, sk, sa)) in [(0, 0, 0, 0, 0, 1), (0, 1, 0, 2, 1, 0), (0, 2, 1, 1, 1, 1), (1, -1, 1, 3, 1, 0), (1, 0, 0, 1, 1, 2), (1, 3, 0, 0, 1, 0), (0, 0, 1, 0, 0, 0), (1, -1, 0, 0, 0, 2)].into_iter().enumerate() {
            terms.push(Monomial { set, power, first: (fk, fa), second: (sk, sa), mono: i % 3, value: 0.5 + 0.37 * i as f64 * if i % 2 == 0 { 1.0 } else { -1.0 } });
        }
        let g = GaussProduct::new(&orders, &outputs, 2, 3, &terms);
        let p = [1.3, -0.7, 2.1];
        let amp: Vec<f64> = (0..2 * n).map(|i| ((i as f64) * 0.77).sin() * 1e-2).collect();
        let mut out = vec![0.25; outputs.len()];
        g.eval(&p, &amp, &mut out);
        let big = |k: usize| (k * (k + 1)) as f64;
        for (o, &(set, j)) in outputs.iter().enumerate() {
            let (mut want, mut scale) = (0.25, 0.25f64);
            for t in terms.iter().filter(|t| t.set == set && !(t.power < 0 && j == 0)) {
                for l in 0..n {
                    for m in 0..n {
                        let v = projection(j, orders[l], orders[m]) * t.value * p[t.mono] * big(orders[l]).powi(t.first.1 as i32) * big(orders[m]).powi(t.second.1 as i32) * big(j).powi(t.power) * amp[t.first.0 * n + l] * amp[t.second.0 * n + m];
                        want += v;
                        scale += v.abs();
                    }
                }
            }
            assert!((out[o] - want).abs() <= 1e-14 * scale, "output {o} ({set}, {j}): {} against {want} (scale {scale:e})", out[o]);
        }
    }

    /// The AVX and AVX-512 clones give the portable kernel's result bit for bit.
    #[test]
    fn the_clones_are_the_portable_kernel_bit_for_bit() {
        let orders: Vec<usize> = (1..=16).map(|i| 2 * i).collect();
        let n = orders.len();
        let outputs: Vec<(usize, usize)> = std::iter::once(0).chain(orders.iter().copied()).map(|j| (0, j)).chain(orders.iter().map(|&j| (1, j))).collect();
        let terms: Vec<Monomial> = (0..24)
            .map(|i| Monomial { set: i % 2, power: (i % 4) as i32 - 1, first: (i % 2, (i % 3) as u32), second: ((i / 2) % 2, (i % 4) as u32), mono: i % 2, value: ((i as f64) * 1.3).cos() })
            .collect();
        let g = GaussProduct::new(&orders, &outputs, 2, 2, &terms);
        let amp: Vec<f64> = (0..2 * n).map(|i| ((i as f64) * 0.41).cos() * 1e-3).collect();
        let p = [0.9, -1.7];
        let mut dispatched = vec![0.5; outputs.len()];
        g.eval(&p, &amp, &mut dispatched);
        let len = g.combinations() + g.sums.len() * n + (g.sums.len() + g.group_start.len() - 1) * g.blocks * LANES;
        let mut s = vec![0.0; len];
        let mut portable = vec![0.5; outputs.len()];
        g.kernel(&p, &amp, &mut s, &mut portable);
        #[allow(unused_mut)]
        let mut clones = vec![dispatched];
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx") {
            let mut avx = vec![0.5; outputs.len()];
            // SAFETY: AVX checked just above.
            unsafe { g.kernel_avx(&p, &amp, &mut s, &mut avx) };
            clones.push(avx);
        }
        for c in &clones {
            for (a, b) in portable.iter().zip(c) {
                assert_eq!(a.to_bits(), b.to_bits(), "{a} against {b}");
            }
        }
    }
}
