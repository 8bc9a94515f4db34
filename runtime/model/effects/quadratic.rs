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
//! Cost (issue 12: ≤ 3× the linear rhs at k ≤ 16): only the coefficients allowed by the
//! selection rules (|l − m| ≤ j ≤ l + m, l + m + j even) are stored, per unordered pair l ≤ m
//! (symmetric products folded), each with one coefficient per *slot* — a table term's product
//! first(l)·second(m), or for an asymmetric term also first(m)·second(l). Per rhs: the slot
//! products once per pair (prefactor included), then per allowed target j one short dot
//! product. No allocation. The Jacobian is exact (chain rule through R̈⁽¹⁾, ä⁽¹⁾ and p_g(R)).

use super::second_order::{FirstOrder, FirstOrderGradient, SecondOrderTerm};
use super::{a_index, At, LoadJacobian, Loads, MAX_MODES};
use crate::coefficients::quadratic::{Term as QTerm, FREE_BUBBLE};

/// Symbols of the prefactors, in this order.
const SYMBOLS: [&str; 7] = ["rho", "gamma", "R", "Rd", "Rdd", "pg", "kappa"];
/// Largest number of slots (padded to a multiple of 4); the free-bubble table has 9.
const MAX_SLOTS: usize = 16;

/// One coefficient (l, m → target), for the Jacobian.
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

/// The allowed targets of one pair l ≤ m: rows (0 radial, 1 + j mode j) and coefficients
/// `coef[t·stride + slot]` for t in `start..end`.
#[derive(Debug, Clone, Copy)]
struct Pair {
    l: usize,
    m: usize,
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
    /// slots rounded up to a multiple of 4
    stride: usize,
    pairs: Vec<Pair>,
    rows: Vec<usize>,
    coef: Vec<f64>,
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
        let ks: Vec<usize> = orders.iter().map(|&k| k as usize).collect();
        let nm = ks.len();
        // targets: row 0 = radial (j = 0), row 1 + i = mode index i
        let targets: Vec<(usize, usize)> = std::iter::once((0, 0)).chain(ks.iter().enumerate().map(|(i, &k)| (i + 1, k))).collect();
        let mut entries = Vec::new();
        for (term, t) in FREE_BUBBLE.iter().enumerate() {
            for (l, &kl) in ks.iter().enumerate() {
                for (m, &km) in ks.iter().enumerate() {
                    for &(row, kj) in &targets {
                        let v = t.value(kj, kl, km);
                        if v != 0.0 {
                            entries.push(Entry { target: row.checked_sub(1), l, m, term, value: v });
                        }
                    }
                }
            }
        }
        let mut slots = Vec::new();
        for (term, &(f, g, _)) in kinds.iter().enumerate() {
            slots.push(Slot { term, first: f, second: g, swap: false });
            if f != g {
                slots.push(Slot { term, first: f, second: g, swap: true });
            }
        }
        assert!(slots.len() <= MAX_SLOTS, "the quadratic table has more products than MAX_SLOTS");
        let stride = slots.len().div_ceil(4) * 4;
        let (mut pairs, mut rows, mut coef) = (Vec::new(), Vec::new(), Vec::new());
        for l in 0..nm {
            for m in l..nm {
                let start = rows.len();
                for &(row, kj) in &targets {
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
                        rows.push(row);
                        coef.extend(c);
                    }
                }
                if rows.len() > start {
                    pairs.push(Pair { l, m, start, end: rows.len() });
                }
            }
        }
        Self { rho, gamma, kappa: three_kappa / 3.0, pg0, r0, orders: orders.to_vec(), kinds, entries, slots, stride, pairs, rows, coef }
    }

    /// Number of nonzero coefficients (l, m → j), ordered pairs, all table terms.
    pub fn entries(&self) -> usize {
        self.entries.len()
    }

    /// Number of (unordered pair, target) rows the rhs evaluates.
    pub fn sparse_rows(&self) -> usize {
        self.rows.len()
    }

    /// Symbol values (SYMBOLS order).
    fn symbols(&self, r: f64, rd: f64, rdd: f64) -> [f64; 7] {
        let pg = self.pg0 * (self.r0 / r).powf(3.0 * self.kappa);
        [self.rho, self.gamma, r, rd, rdd, pg, self.kappa]
    }

    fn prefactor(e: &[i32; 7], s: &[f64; 7]) -> f64 {
        e.iter().zip(s).fold(1.0, |acc, (p, v)| if *p == 0 { acc } else { acc * v.powi(*p) })
    }
}

impl SecondOrderTerm for QuadraticCoupling {
    fn name(&self) -> &'static str {
        "quadratic coupling"
    }
    fn label(&self) -> Option<String> {
        Some("quadratic mode coupling (free bubble)".to_string())
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
        let mut pre = [0.0; MAX_SLOTS];
        for (p, slot) in pre.iter_mut().zip(&self.slots) {
            *p = Self::prefactor(&self.kinds[slot.term].2, &s);
        }
        // four partial sums per row (0 radial, 1 + j mode j)
        let mut acc = [[0.0f64; 4]; MAX_MODES + 1];
        let st = self.stride;
        for pair in &self.pairs {
            let (al, am) = (&amp[pair.l], &amp[pair.m]);
            let mut w = [0.0; MAX_SLOTS];
            for ((w, slot), p) in w.iter_mut().zip(&self.slots).zip(&pre) {
                let (x, y) = if slot.swap { (am[slot.first], al[slot.second]) } else { (al[slot.first], am[slot.second]) };
                *w = p * x * y;
            }
            let w = &w[..st];
            for t in pair.start..pair.end {
                let c = &self.coef[t * st..(t + 1) * st];
                let a = &mut acc[self.rows[t]];
                for (cc, ww) in c.chunks_exact(4).zip(w.chunks_exact(4)) {
                    for i in 0..4 {
                        a[i] += cc[i] * ww[i];
                    }
                }
            }
        }
        let sum = |a: &[f64; 4]| (a[0] + a[1]) + (a[2] + a[3]);
        loads.pressure += sum(&acc[0]);
        for j in 0..loads.gn.len().min(n) {
            loads.gn[j] += sum(&acc[j + 1]);
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
