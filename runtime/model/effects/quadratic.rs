//! Second-order (quadratic) mode coupling of a free bubble (issue 12; docs/model.md, "Quadratic
//! mode coupling"): Q_0 added to the radial balance P and Q_j added to G_n,j, from the generated
//! table `coefficients::quadratic::FREE_BUBBLE` (codegen, derivations/quadratic.rs):
//!
//!   Q_j = Σ_T Σ_{l,m} value_T(j, l, m) · prefactor_T(ρ, γ, R, Ṙ, R̈, p_g, κ) · first_T(l) · second_T(m),
//!
//! first/second ∈ {a, ȧ, ä}. The accelerations in Q are needed to first order only (R̈ to zero
//! order): a second-pass term ([`super::second_order`]) — the equations core hands over the
//! R̈⁽¹⁾, ä_l⁽¹⁾ of the linear equations it has just evaluated (their viscous parts change Q by
//! O(νε²), the order of the viscous second-order terms that are not derived either).
//!
//! Cost (issue 12: ≤ 3× the linear rhs at k ≤ 16; docs/performance.md): only the coefficients
//! the selection rules allow (|l − m| ≤ j ≤ l + m, l + m + j even) are stored, per unordered pair
//! l ≤ m (symmetric products folded), each with one coefficient per *slot* — a table term's
//! product first(l)·second(m), or for an asymmetric term also first(m)·second(l). Per rhs and
//! pair: the slot products once (prefactor included, kept in registers), then one short dot
//! product per allowed target, into four partial sums per target (AVX where the processor has
//! it: the same sums in the same order). No allocation. The radial-
//! only terms (the gas at the exact volume) are a short scalar list. The Jacobian is exact
//! (chain rule through R̈⁽¹⁾, ä⁽¹⁾ and p_g(R)).

use super::second_order::{FirstOrder, FirstOrderGradient, SecondOrderTerm};
use super::{a_index, At, LoadJacobian, Loads, MAX_MODES};
use crate::coefficients::quadratic::{Term as QTerm, FREE_BUBBLE};

/// Symbols of the prefactors, in this order.
const SYMBOLS: [&str; 7] = ["rho", "gamma", "R", "Rd", "Rdd", "pg", "kappa"];
/// Largest number of slots (padded to a multiple of 4) and of table terms; the free-bubble
/// table has 8 slots on the mode rows.
const MAX_SLOTS: usize = 16;

/// One coefficient (l, m → target), for the Jacobian and the radial-only terms.
#[derive(Debug, Clone, Copy)]
struct Entry {
    /// mode index of the target, or None for the radial balance (j = 0)
    target: Option<usize>,
    l: usize,
    m: usize,
    term: usize,
    value: f64,
}

/// One product of the rhs: table term `term`, first(l)·second(m), or first(m)·second(l) when
/// `swap` (l ≤ m the pair).
#[derive(Debug, Clone, Copy)]
struct Slot {
    term: usize,
    first: usize,
    second: usize,
    swap: bool,
}

/// The rows of one pair (index into `pairs`): `start..end` into `row_out` and `coef` (stride
/// `stride`).
#[derive(Debug, Clone, Copy)]
struct Group {
    pair: usize,
    start: usize,
    end: usize,
}

#[derive(Debug)]
pub struct QuadraticCoupling {
    rho: f64,
    gamma: f64,
    kappa: f64,
    /// p_g(R) = pg0 (r0/R)^{3κ}: the polytropic part of p_in
    pg0: f64,
    r0: f64,
    orders: Vec<f64>,
    /// (first, second, exponents of SYMBOLS) per table term
    kinds: Vec<(usize, usize, [i32; 7])>,
    entries: Vec<Entry>,
    slots: Vec<Slot>,
    /// per slot, where its two factors are in [a_l, ȧ_l, ä_l, a_m, ȧ_m, ä_m]
    gather: Vec<(usize, usize)>,
    /// slots rounded up to a multiple of 4
    stride: usize,
    /// the unordered pairs l ≤ m that have a row
    pairs: Vec<(usize, usize)>,
    groups: Vec<Group>,
    /// output of each row (0 radial, 1 + i mode index i)
    row_out: Vec<usize>,
    coef: Vec<f64>,
    /// the radial-only terms (j = 0, l = m), scalar
    radial_only: Vec<Entry>,
}

impl QuadraticCoupling {
    /// `orders`: k of each mode index.
    pub fn new(rho: f64, gamma: f64, three_kappa: f64, pg0: f64, r0: f64, orders: &[f64]) -> Self {
        let kinds: Vec<(usize, usize, [i32; 7])> = FREE_BUBBLE
            .iter()
            .map(|t: &QTerm| {
                let mut e = [0; 7];
                for (s, p) in t.prefactor {
                    let i = SYMBOLS.iter().position(|x| x == s).expect("generated prefactor symbols are the documented ones");
                    e[i] = *p;
                }
                (t.first.order(), t.second.order(), e)
            })
            .collect();
        assert!(kinds.len() <= MAX_SLOTS, "the quadratic table has more terms than MAX_SLOTS");
        let ks: Vec<usize> = orders.iter().map(|&k| k as usize).collect();
        let nm = ks.len();
        // outputs: 0 = radial (j = 0), 1 + i = mode index i
        let outs: Vec<usize> = std::iter::once(0).chain(ks.iter().copied()).collect();
        let mut entries = Vec::new();
        for (term, t) in FREE_BUBBLE.iter().enumerate() {
            for (l, &kl) in ks.iter().enumerate() {
                for (m, &km) in ks.iter().enumerate() {
                    for (out, &kj) in outs.iter().enumerate() {
                        let v = t.value(kj, kl, km);
                        if v != 0.0 {
                            entries.push(Entry { target: out.checked_sub(1), l, m, term, value: v });
                        }
                    }
                }
            }
        }
        let mut slots = Vec::new();
        for (term, &(f, g, _)) in kinds.iter().enumerate().filter(|(t, _)| !FREE_BUBBLE[*t].radial_only) {
            slots.push(Slot { term, first: f, second: g, swap: false });
            if f != g {
                slots.push(Slot { term, first: f, second: g, swap: true });
            }
        }
        assert!(slots.len() <= MAX_SLOTS, "the quadratic table has more products than MAX_SLOTS");
        let stride = slots.len().div_ceil(4) * 4;
        let gather = slots.iter().map(|s| if s.swap { (3 + s.first, s.second) } else { (s.first, 3 + s.second) }).collect();
        let pairs: Vec<(usize, usize)> = (0..nm).flat_map(|l| (l..nm).map(move |m| (l, m))).collect();
        let (mut groups, mut row_out, mut coef) = (Vec::new(), Vec::new(), Vec::new());
        for (p, &(l, m)) in pairs.iter().enumerate() {
            let start = row_out.len();
            for (out, &kj) in outs.iter().enumerate() {
                let mut c = vec![0.0; stride];
                for (s, slot) in slots.iter().enumerate() {
                    let t = &FREE_BUBBLE[slot.term];
                    let (x, y) = if slot.swap { (ks[m], ks[l]) } else { (ks[l], ks[m]) };
                    c[s] = t.value(kj, x, y);
                    // symmetric product, l < m: the (m, l) coefficient folds in
                    if slot.first == slot.second && l != m {
                        c[s] += t.value(kj, ks[m], ks[l]);
                    }
                    // l = m: the swapped product is the same one
                    if slot.swap && l == m {
                        c[s] = 0.0;
                    }
                }
                if c.iter().any(|&x| x != 0.0) {
                    row_out.push(out);
                    coef.extend(c);
                }
            }
            if row_out.len() > start {
                groups.push(Group { pair: p, start, end: row_out.len() });
            }
        }
        let radial_only = entries.iter().filter(|e| FREE_BUBBLE[e.term].radial_only).copied().collect();
        Self {
            rho,
            gamma,
            kappa: three_kappa / 3.0,
            pg0,
            r0,
            orders: orders.to_vec(),
            kinds,
            entries,
            slots,
            gather,
            stride,
            pairs,
            groups,
            row_out,
            coef,
            radial_only,
        }
    }

    /// Number of nonzero coefficients (l, m → j), ordered pairs, all table terms.
    pub fn entries(&self) -> usize {
        self.entries.len()
    }

    /// Number of (unordered pair, target) rows the rhs evaluates.
    pub fn sparse_rows(&self) -> usize {
        self.row_out.len()
    }

    /// [`kernel`](Self::kernel) for this table's stride; with AVX where the processor has it
    /// (the same four partial sums in the same order: bit for bit the SSE2 result).
    fn kernel_dispatch(&self, amp: &[[f64; 3]; MAX_MODES], pre: &[f64; MAX_SLOTS], out: &mut [f64; MAX_MODES + 1]) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: the processor supports AVX (checked just above).
            unsafe { self.kernel_avx(amp, pre, out) };
            return;
        }
        self.kernel_any(amp, pre, out)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn kernel_avx(&self, amp: &[[f64; 3]; MAX_MODES], pre: &[f64; MAX_SLOTS], out: &mut [f64; MAX_MODES + 1]) {
        self.kernel_any(amp, pre, out)
    }

    #[inline(always)]
    fn kernel_any(&self, amp: &[[f64; 3]; MAX_MODES], pre: &[f64; MAX_SLOTS], out: &mut [f64; MAX_MODES + 1]) {
        match self.stride {
            4 => self.kernel::<4>(amp, pre, out),
            8 => self.kernel::<8>(amp, pre, out),
            12 => self.kernel::<12>(amp, pre, out),
            _ => self.kernel::<MAX_SLOTS>(amp, pre, out), // 16: more slots are refused in `new`
        }
    }

    /// The sparse bilinear sums (module doc) with the stride `S` known at compile time.
    #[inline(always)]
    fn kernel<const S: usize>(&self, amp: &[[f64; 3]; MAX_MODES], pre: &[f64; MAX_SLOTS], out: &mut [f64; MAX_MODES + 1]) {
        debug_assert_eq!(S, self.stride);
        let (mut gx, mut gy, mut ps) = ([0usize; S], [0usize; S], [0.0; S]);
        for (s, &(x, y)) in self.gather.iter().enumerate() {
            (gx[s], gy[s], ps[s]) = (x, y, pre[s]);
        }
        // four partial sums per output (0 radial, 1 + i mode index i)
        let mut acc = [[0.0f64; 4]; MAX_MODES + 1];
        for g in &self.groups {
            let (l, m) = self.pairs[g.pair];
            let (al, am) = (&amp[l], &amp[m]);
            let lm = [al[0], al[1], al[2], am[0], am[1], am[2]];
            let mut w = [0.0; S];
            for s in 0..S {
                w[s] = ps[s] * lm[gx[s]] * lm[gy[s]];
            }
            let coef = &self.coef[g.start * S..g.end * S];
            for (c, &o) in coef.chunks_exact(S).zip(&self.row_out[g.start..g.end]) {
                let a = &mut acc[o];
                let mut v = *a;
                for s in 0..S {
                    v[s % 4] += c[s] * w[s];
                }
                *a = v;
            }
        }
        for (o, a) in out.iter_mut().zip(&acc) {
            *o += (a[0] + a[1]) + (a[2] + a[3]);
        }
    }

    /// Symbol values (SYMBOLS order).
    fn symbols(&self, r: f64, rd: f64, rdd: f64) -> [f64; 7] {
        let pg = self.pg0 * (self.r0 / r).powf(3.0 * self.kappa);
        [self.rho, self.gamma, r, rd, rdd, pg, self.kappa]
    }

    /// Π_i s_i^{e_i} (small integer powers, by repeated products).
    fn prefactor(e: &[i32; 7], s: &[f64; 7]) -> f64 {
        let (mut num, mut den) = (1.0, 1.0);
        for (&p, &v) in e.iter().zip(s) {
            for _ in 0..p.unsigned_abs() {
                if p > 0 {
                    num *= v;
                } else {
                    den *= v;
                }
            }
        }
        num / den
    }
}

impl SecondOrderTerm for QuadraticCoupling {
    fn name(&self) -> &'static str {
        "quadratic coupling"
    }
    fn label(&self) -> Option<String> {
        Some("quadratic mode coupling (fluid)".to_string())
    }
    fn band(&self) -> usize {
        self.orders.len()
    }
    fn add(&self, at: &At<'_>, first: &FirstOrder<'_>, loads: &mut Loads<'_>) {
        let n = self.orders.len();
        let mut amp = [[0.0; 3]; MAX_MODES];
        for (i, a) in amp.iter_mut().enumerate().take(n) {
            *a = [at.a(i), at.adot(i), first.add[i]];
        }
        let s = self.symbols(at.r(), at.rdot(), first.rdd);
        let mut tp = [0.0; MAX_SLOTS];
        for (p, (_, _, e)) in tp.iter_mut().zip(&self.kinds) {
            *p = Self::prefactor(e, &s);
        }
        let mut pre = [0.0; MAX_SLOTS];
        for (p, slot) in pre.iter_mut().zip(&self.slots) {
            *p = tp[slot.term];
        }
        let mut out = [0.0; MAX_MODES + 1];
        for e in &self.radial_only {
            let (f, g, _) = self.kinds[e.term];
            out[0] += e.value * tp[e.term] * amp[e.l][f] * amp[e.m][g];
        }
        self.kernel_dispatch(&amp, &pre, &mut out);
        loads.pressure += out[0];
        for (g, q) in loads.gn.iter_mut().zip(&out[1..=n]) {
            *g += q;
        }
    }
    fn add_jacobian(&self, at: &At<'_>, first: &FirstOrder<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian) {
        let nm = self.orders.len();
        let n = jac.n;
        let (r, rd, rdd) = (at.r(), at.rdot(), first.rdd);
        let g_rdd = grad.drdd;
        let amp: Vec<[f64; 3]> = (0..nm).map(|i| [at.a(i), at.adot(i), first.add[i]]).collect();
        let g_add = |i: usize| &grad.dadd[i * n..(i + 1) * n];
        // prefactors and their gradients (through R, Ṙ explicitly, R̈⁽¹⁾ and p_g(R))
        let s = self.symbols(r, rd, rdd);
        let mut pre = Vec::new();
        let mut g_pre = Vec::new();
        for (_, _, e) in &self.kinds {
            let p = Self::prefactor(e, &s);
            let mut g = vec![0.0; n];
            // ∂/∂symbol = power · prefactor with that power lowered by one
            let dsym = |i: usize| if e[i] == 0 { 0.0 } else { e[i] as f64 * Self::prefactor(&{ let mut f = *e; f[i] -= 1; f }, &s) };
            g[0] += dsym(2) + dsym(5) * (-3.0 * self.kappa * s[5] / r);
            g[1] += dsym(3);
            let dr = dsym(4);
            if dr != 0.0 {
                for j in 0..n {
                    g[j] += dr * g_rdd[j];
                }
            }
            pre.push(p);
            g_pre.push(g);
        }
        let unit = |i: usize, o: usize| a_index(i) + o;
        for e in &self.entries {
            let (f, g, _) = self.kinds[e.term];
            let (x, y) = (amp[e.l][f], amp[e.m][g]);
            let row: &mut [f64] = match e.target {
                None => &mut jac.pressure[..],
                Some(j) => &mut jac.gn[j * n..(j + 1) * n],
            };
            let c = e.value;
            for j in 0..n {
                row[j] += c * g_pre[e.term][j] * x * y;
            }
            let p = c * pre[e.term];
            // ∂x, ∂y
            for (amp_i, ord, other) in [(e.l, f, y), (e.m, g, x)] {
                if ord == 2 {
                    for (rj, gj) in row.iter_mut().zip(g_add(amp_i)) {
                        *rj += p * other * gj;
                    }
                } else {
                    row[unit(amp_i, ord)] += p * other;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The selection rules leave only the allowed (pair, target) rows: for k = 2..16, 36 pairs
    /// l ≤ m, their targets |l − m| ≤ j ≤ min(l + m, 16) (and j = 0 for l = m).
    #[test]
    fn sparse_rows_are_the_selection_rules() {
        let orders: Vec<f64> = (1..=8).map(|i| 2.0 * i as f64).collect();
        let q = QuadraticCoupling::new(1.0, 0.1, 4.2, 1.0, 1.0, &orders);
        let mut expected = 0;
        for l in (2..=16).step_by(2) {
            for m in (l..=16).step_by(2) {
                expected += usize::from(l == m) + (2..=16).step_by(2).filter(|&j| m - l <= j && j <= l + m).count();
            }
        }
        assert_eq!(q.sparse_rows(), expected);
        assert_eq!(q.pairs.len(), 36);
        assert_eq!(q.stride, 8);
    }
}
