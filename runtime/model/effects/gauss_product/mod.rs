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

mod kernels;
#[cfg(test)]
mod tests;

/// Nodes per block (one AVX-512 register, two AVX, four SSE2).
const LANES: usize = 8;
/// Most blocks of a rule: 13 · 8 ≥ 97 nodes, the rule of k, j ≤ KMAX = 64 of any parity
/// (the kernels are instantiated per block count, `steps`).
const MAX_BLOCKS: usize = 13;

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
    /// kinds, `prefactors` prefactors; `terms`: every monomial of every table term. None if the
    /// rule needs more than [`MAX_BLOCKS`] blocks of nodes (orders beyond 64, a MAGBUBBLE_KMAX
    /// build).
    pub fn new(orders: &[usize], outputs: &[(usize, usize)], kinds: usize, prefactors: usize, terms: &[Monomial]) -> Option<Self> {
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
        if blocks > MAX_BLOCKS {
            return None;
        }
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
        // the kernels index the rows through these without checks
        let (nf, ng) = (sums.len(), groups.len());
        assert!(combo_sums.iter().all(|&(x, y)| x < nf && y < nf) && out_group.iter().all(|&g| g < ng), "GaussProduct indices");
        Some(Self { modes: n, kinds, blocks, prefactors, legendre: legendre_nodes, sums, lpow, group_start, combo_sums, combo_value, out_start, out_group, out_weight })
    }

    /// out[o] += output o, with prefactors `p` and amplitudes `amp` (kind-major: kind · modes + l).
    pub fn eval(&self, p: &[f64], amp: &[f64], out: &mut [f64]) {
        assert!(p.len() >= self.prefactors && amp.len() >= self.kinds * self.modes && out.len() + 1 >= self.out_start.len(), "GaussProduct::eval");
        let len = self.scratch_len();
        SCRATCH.with(|cell| {
            let mut buf = cell.borrow_mut();
            if buf.len() < len {
                buf.resize(len, 0.0);
            }
            let (k, coef, rows) = self.split(&mut buf[..len]);
            self.steps(p, amp, k, coef, rows, out)
        })
    }

    /// The scratch (length [`scratch_len`](Self::scratch_len)) as K, the sums' mode
    /// coefficients, and the rows at the nodes (the sums', then the groups').
    fn split<'s>(&self, s: &'s mut [f64]) -> (&'s mut [f64], &'s mut [f64], &'s mut [f64]) {
        let (k, rest) = s.split_at_mut(self.combo_sums.len());
        let (coef, rows) = rest.split_at_mut(self.sums.len() * self.modes);
        (k, coef, rows)
    }

    fn scratch_len(&self) -> usize {
        let rows = self.sums.len() + self.group_start.len() - 1;
        self.combo_sums.len() + self.sums.len() * self.modes + rows * self.blocks * LANES
    }

    /// Step 1, K_c = Σ_i value_{c,i} p_i (i in order), and the mode sums' coefficients L_l^a x_l
    /// (inlined into each kernel: lane-wise, so vectorised alike).
    #[inline(always)]
    fn prepare(&self, p: &[f64], amp: &[f64], k: &mut [f64], coef: &mut [f64]) {
        let (n, nc) = (self.modes, self.combo_sums.len());
        k.fill(0.0);
        for (&pi, v) in p[..self.prefactors].iter().zip(self.combo_value.chunks_exact(nc)) {
            for (kc, v) in k.iter_mut().zip(v) {
                *kc += v * pi;
            }
        }
        for ((c, lp), &(kind, _)) in coef.chunks_exact_mut(n).zip(self.lpow.chunks_exact(n)).zip(&self.sums) {
            for ((ci, li), x) in c.iter_mut().zip(lp).zip(&amp[kind * n..(kind + 1) * n]) {
                *ci = li * x;
            }
        }
    }

    /// Steps 1–4 by the widest kernel the processor has (all three the same operations).
    fn steps(&self, p: &[f64], amp: &[f64], k: &mut [f64], coef: &mut [f64], rows: &mut [f64], out: &mut [f64]) {
        self.check(k, coef, rows, out);
        #[cfg(target_arch = "x86_64")]
        {
            macro_rules! blocks {
                ($kernel:ident, $per:literal, $($b:literal)*) => {
                    match self.blocks {
                        // SAFETY: the feature is the one detected below; the lengths are
                        // the ones `check` asserted.
                        $($b => unsafe { self.$kernel::<$b, { $b * $per }>(p, amp, k, coef, rows, out) },)*
                        _ => unreachable!("GaussProduct::new bounds the blocks"),
                    }
                };
            }
            if std::arch::is_x86_feature_detected!("avx512f") {
                return blocks!(steps_avx512, 1, 1 2 3 4 5 6 7 8 9 10 11 12 13);
            }
            if std::arch::is_x86_feature_detected!("avx") {
                return blocks!(steps_avx, 2, 1 2 3 4 5 6 7 8 9 10 11 12 13);
            }
        }
        self.prepare(p, amp, k, coef);
        self.steps_portable(k, coef, rows, out)
    }
}
