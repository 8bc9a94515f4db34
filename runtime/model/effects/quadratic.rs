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
//! product first(l)·second(m), or for an asymmetric term also first(m)·second(l)
//! ([`super::pair_rows`]: the slot products once per pair, prefactor included, then one
//! contiguous dot product per output); a mode's left and right factors are gathered from
//! [a, ȧ, ä⁽¹⁾, 0] by the slots' sides (planned once). No allocation. The radial-only terms (the gas at the
//! exact volume) are a short scalar list. The Jacobian is exact (chain rule through R̈⁽¹⁾, ä⁽¹⁾
//! and p_g(R)) and walks the same rows: per output the derivatives with respect to the 3M
//! amplitudes and the prefactor symbols, then the chain rule once.

mod jacobian;

use super::pair_rows::PairRows;
use super::second_order::{FirstOrder, FirstOrderGradient, SecondOrderTerm};
use super::{At, LoadJacobian, Loads, MAX_MODES};
use crate::model::layout::StateLayout;
use crate::coefficients::quadratic::{Term as QTerm, FREE_BUBBLE};

/// Symbols of the prefactors, in this order.
const SYMBOLS: [&str; 7] = ["rho", "gamma", "R", "Rd", "Rdd", "pg", "kappa"];
/// Largest number of slots and of table terms; the free-bubble table has 8 slots on the mode
/// rows.
const MAX_SLOTS: usize = 16;

/// One radial-only coefficient (l, l → j = 0), scalar: value · prefactor(term) ·
/// amp_l[first] · amp_m[second].
#[derive(Debug, Clone, Copy)]
struct Entry {
    l: usize,
    m: usize,
    term: usize,
    value: f64,
    /// where amp_l[first], amp_m[second] are in [a, ȧ, ä⁽¹⁾] per mode, then one 0 (3 nm)
    flat: (usize, usize),
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
    /// per table term, the symbols its prefactor multiplies into the numerator, then into the
    /// denominator, one entry per power in SYMBOLS order ([`prefactor`](Self::prefactor)'s
    /// products): `steps[s.0..s.1]`, `steps[s.1..s.2]` for `s = step_at[t]`
    steps: Vec<usize>,
    step_at: Vec<(usize, usize, usize)>,
    slots: Vec<Slot>,
    /// per slot, where its two factors are in [a_l, ȧ_l, ä_l, a_m, ȧ_m, ä_m] (the scalar
    /// Jacobian walk the tests compare against reads it)
    #[cfg_attr(not(test), allow(dead_code))]
    gather: Vec<(usize, usize)>,
    /// per slot, which of (a, ȧ, ä) of mode l and of mode m it multiplies (3: padding, a zero)
    sides: [(usize, usize); MAX_SLOTS],
    /// the (output, pair) rows: output 0 radial, 1 + i mode index i
    rows: PairRows,
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
        let mut radial_only = Vec::new();
        for (term, t) in FREE_BUBBLE.iter().enumerate().filter(|(_, t)| t.radial_only) {
            for (l, &kl) in ks.iter().enumerate() {
                for (m, &km) in ks.iter().enumerate() {
                    let v = t.value(0, kl, km);
                    if v != 0.0 {
                        let (first, second) = (t.first.order(), t.second.order());
                        let at = |i: usize, f: usize| if f < 3 { StateLayout::x_a(i) + f } else { StateLayout::x_dim(nm) };
                        radial_only.push(Entry { l, m, term, value: v, flat: (at(l, first), at(m, second)) });
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
        let gather: Vec<(usize, usize)> = slots.iter().map(|s| if s.swap { (3 + s.first, s.second) } else { (s.first, 3 + s.second) }).collect();
        // outputs: 0 = radial (j = 0), 1 + i = mode index i
        let outs: Vec<usize> = std::iter::once(0).chain(ks.iter().copied()).collect();
        let rows = PairRows::new(nm, outs.len(), slots.len(), |o, l, m, c| {
            let (kj, kl, km) = (outs[o], ks[l], ks[m]);
            if kj < kl.abs_diff(km) || kj > kl + km {
                return false;
            }
            for (cs, slot) in c.iter_mut().zip(&slots) {
                let t = &FREE_BUBBLE[slot.term];
                // l = m: the swapped product is the same one
                if slot.swap && l == m {
                    continue;
                }
                let (x, y) = if slot.swap { (km, kl) } else { (kl, km) };
                *cs = t.value(kj, x, y);
                // symmetric product, l < m: the (m, l) coefficient folds in
                if slot.first == slot.second && l != m {
                    *cs += t.value(kj, km, kl);
                }
            }
            true
        });
        let mut sides = [(3, 3); MAX_SLOTS];
        for (sd, &(x, y)) in sides.iter_mut().zip(&gather) {
            // one factor of each mode: (l side, m side)
            *sd = if x < 3 { (x, y - 3) } else { (y, x - 3) };
        }
        let (mut steps, mut step_at) = (Vec::new(), Vec::new());
        for (_, _, e) in &kinds {
            let a = steps.len();
            let each = |sign: i32| e.iter().enumerate().filter(move |(_, p)| p.signum() == sign).flat_map(|(i, p)| std::iter::repeat_n(i, p.unsigned_abs() as usize));
            steps.extend(each(1));
            let b = steps.len();
            steps.extend(each(-1));
            step_at.push((a, b, steps.len()));
        }
        Self { rho, gamma, kappa: three_kappa / 3.0, pg0, r0, orders: orders.to_vec(), kinds, steps, step_at, slots, gather, sides, rows, radial_only }
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

    /// Π_i s_i^{e_i} (small integer powers, by repeated products).
    fn prefactor(e: &[i32; 7], s: &[f64; 7]) -> f64 {
        let (mut num, mut den) = (1.0, 1.0);
        for (&p, &v) in e.iter().zip(s) {
            Self::raise(p, v, &mut num, &mut den);
        }
        num / den
    }

    /// [`prefactor`](Self::prefactor) of table term `t` from its planned steps (the same
    /// products in the same order: the numerator's and the denominator's are independent).
    #[inline(always)]
    fn prefactor_of(&self, t: usize, s: &[f64; 7]) -> f64 {
        let (a, b, c) = self.step_at[t];
        let (num, den) = self.steps[a..c].split_at(b - a);
        num.iter().fold(1.0, |x, &i| x * s[i]) / den.iter().fold(1.0, |x, &i| x * s[i])
    }

    /// num · v^p (p > 0) or den · v^|p| (p < 0), by repeated products.
    #[inline(always)]
    fn raise(p: i32, v: f64, num: &mut f64, den: &mut f64) {
        let x = if p > 0 { num } else { den };
        for _ in 0..p.unsigned_abs() {
            *x *= v;
        }
    }

    /// The amplitudes [a, ȧ, ä⁽¹⁾] per mode index and the prefactor of each table term.
    fn state(&self, at: &At<'_>, first: &FirstOrder<'_>) -> ([[f64; 3]; MAX_MODES], [f64; MAX_SLOTS], [f64; 7]) {
        let mut amp = [[0.0; 3]; MAX_MODES];
        for (i, a) in amp.iter_mut().enumerate().take(self.orders.len()) {
            *a = [at.a(i), at.adot(i), first.add[i]];
        }
        let s = self.symbols(at.r(), at.rdot(), first.rdd);
        let mut tp = [0.0; MAX_SLOTS];
        for (t, p) in tp.iter_mut().enumerate().take(self.kinds.len()) {
            *p = self.prefactor_of(t, &s);
        }
        (amp, tp, s)
    }
}

impl QuadraticCoupling {
    /// The pair rows' factors of every mode index i: left_s = pre_s · amp_i[f_s], right_s =
    /// amp_i[g_s], amp = [a, ȧ, ä⁽¹⁾, 0], (f_s, g_s) the slot's sides (padding: 3, a zero).
    fn factors(&self, z: &[f64], add: &[f64], pre: &[f64; MAX_SLOTS], left: &mut [f64], right: &mut [f64]) {
        let st = self.rows.stride();
        let l = StateLayout::reduced(add.len());
        for (i, (lv, rv)) in left.chunks_exact_mut(st).zip(right.chunks_exact_mut(st)).enumerate().take(add.len()) {
            let a4 = [z[l.a(i)], z[l.adot(i)], add[i], 0.0];
            for (((x, y), &(f, g)), p) in lv.iter_mut().zip(rv.iter_mut()).zip(&self.sides).zip(pre) {
                (*x, *y) = (p * a4[f & 3], a4[g & 3]);
            }
        }
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
        let sym = self.symbols(at.r(), at.rdot(), first.rdd);
        let mut tp = [0.0; MAX_SLOTS];
        for (t, p) in tp.iter_mut().enumerate().take(self.kinds.len()) {
            *p = self.prefactor_of(t, &sym);
        }
        let mut pre = [0.0; MAX_SLOTS];
        for (p, slot) in pre.iter_mut().zip(&self.slots) {
            *p = tp[slot.term];
        }
        let l = StateLayout::reduced(n);
        let (z, add) = (&at.z[..l.dim()], &first.add[..n]);
        // [a, ȧ, ä⁽¹⁾] of each mode index in a row (x's layout, ä⁽¹⁾ in b's place), then one 0
        // (the entries' `flat`)
        let mut amp = [0.0; StateLayout::x_dim(MAX_MODES) + 1];
        amp[..StateLayout::x_dim(n)].copy_from_slice(&z[l.shape()]);
        for (i, &x) in add.iter().enumerate() {
            amp[StateLayout::x_b(i)] = x;
        }
        let amp = &amp[..=StateLayout::x_dim(n)];
        let mut out = [0.0; MAX_MODES + 1];
        for e in &self.radial_only {
            out[0] += e.value * tp[e.term] * amp[e.flat.0] * amp[e.flat.1];
        }
        self.rows.eval(&mut out[..=n], |left, right| self.factors(z, add, &pre, left, right));
        loads.pressure += out[0];
        for (g, q) in loads.gn.iter_mut().zip(&out[1..=n]) {
            *g += q;
        }
    }
    /// Exact (chain rule through R̈⁽¹⁾, ä⁽¹⁾ and p_g(R)), assembled row by row from the pair
    /// rows ([`jacobian`]).
    fn add_jacobian(&self, at: &At<'_>, first: &FirstOrder<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian) {
        self.jacobian_rows(at, first, grad, jac);
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
        assert_eq!(q.rows.pairs().len(), 36);
        assert_eq!(q.rows.stride(), 8);
    }

    /// The planned prefactor steps are the exponent-wise products bit for bit.
    #[test]
    fn prefactor_steps_are_the_products() {
        let q = QuadraticCoupling::new(1.0, 0.1, 4.2, 1.0, 1.0, &[2.0, 4.0]);
        for k in 0..5 {
            let s: [f64; 7] = std::array::from_fn(|i| (0.7 * (i + 7 * k) as f64 + 0.3).sin() * 10f64.powi(i as i32 - 3));
            for (t, (_, _, e)) in q.kinds.iter().enumerate() {
                assert_eq!(q.prefactor_of(t, &s).to_bits(), QuadraticCoupling::prefactor(e, &s).to_bits(), "term {t}");
            }
        }
    }
}
