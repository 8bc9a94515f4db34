//! The exact Jacobian of [`QuadraticCoupling`] walked over the pair rows (issue 12,
//! "Performance"; docs/performance.md): for output o (0 = P, 1 + i = G_n of mode index i)
//!
//!   Q_o = Σ_{rows (l ≤ m)} Σ_s c_s · pre_s · x_s · y_s,
//!
//! x_s = first(l), y_s = second(m) of the slot's table term (first(m), second(l) for a swapped
//! slot), first/second ∈ {a, ȧ, ä⁽¹⁾}; so ∂Q_o/∂x_s = c_s pre_s y_s, ∂Q_o/∂y_s = c_s pre_s x_s,
//! and the prefactor-free sums c_s x_s y_s give ∂Q_o/∂(R, Ṙ, R̈⁽¹⁾) through ∂pre/∂symbol; then
//! the chain rule through ∂ä⁽¹⁾/∂x and ∂R̈⁽¹⁾/∂x. Per row the three products of every slot are
//! formed at once from per-mode factor vectors (planned once per Jacobian, the slot's sides),
//! then added slot by slot into the per-mode derivatives in the order of the scalar walk this
//! replaces ([`QuadraticCoupling::add_jacobian_reference`], per non-zero coefficient a closure
//! call and two gathers): the same products and sums, so bit for bit its Jacobian (a test
//! below), and the run's step sequence and series.csv do not move.

use super::super::second_order::{FirstOrder, FirstOrderGradient};
use super::super::{At, LoadJacobian, MAX_MODES};
use crate::model::layout::StateLayout;
use super::{QuadraticCoupling, MAX_SLOTS};

impl QuadraticCoupling {
    /// [`SecondOrderTerm::add_jacobian`](super::super::second_order::SecondOrderTerm::add_jacobian)
    /// (module doc).
    pub(super) fn jacobian_rows(&self, at: &At<'_>, first: &FirstOrder<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian) {
        self.jacobian_body(at, first, grad, jac);
    }

    #[inline(always)]
    fn jacobian_body(&self, at: &At<'_>, first: &FirstOrder<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian) {
        match self.rows.stride() {
            4 => self.jacobian_s::<4>(at, first, grad, jac),
            8 => self.jacobian_s::<8>(at, first, grad, jac),
            12 => self.jacobian_s::<12>(at, first, grad, jac),
            _ => self.jacobian_s::<16>(at, first, grad, jac),
        }
    }

    /// ∂prefactor/∂(R, Ṙ, R̈⁽¹⁾) per table term (R through p_g(R) too): ∂/∂symbol = power · the
    /// prefactor with that power lowered by one.
    pub(super) fn prefactor_gradients(&self, s: &[f64; 7], r: f64) -> [[f64; 3]; MAX_SLOTS] {
        let mut dpre = [[0.0; 3]; MAX_SLOTS];
        for (d, (_, _, e)) in dpre.iter_mut().zip(&self.kinds) {
            let dsym = |i: usize| if e[i] == 0 { 0.0 } else { e[i] as f64 * Self::prefactor(&{ let mut f = *e; f[i] -= 1; f }, s) };
            *d = [dsym(2) + dsym(5) * (-3.0 * self.kappa * s[5] / r), dsym(3), dsym(4)];
        }
        dpre
    }

    #[inline(always)]
    fn jacobian_s<const S: usize>(&self, at: &At<'_>, first: &FirstOrder<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian) {
        assert!(S == self.rows.stride() && S <= MAX_SLOTS && self.slots.len() <= S, "quadratic Jacobian stride");
        let nm = self.orders.len();
        let n = jac.n;
        let (amp, tp, s) = self.state(at, first);
        let dpre = self.prefactor_gradients(&s, at.r());
        // per slot: its prefactor, whether it is the swapped product first(m)·second(l), and
        // (term, first, second) masked to their array sizes (no bounds checks below)
        let (mut pre, mut swap, mut plan) = ([0.0; S], [false; S], [(0usize, 0usize, 0usize); S]);
        for (q, slot) in self.slots.iter().enumerate() {
            (pre[q], swap[q]) = (tp[slot.term], slot.swap);
            plan[q] = (slot.term & (MAX_SLOTS - 1), slot.first & 3, slot.second & 3);
        }
        // per mode: its factor on the l side (u[f_q]) and on the m side (u[g_q]) of each slot
        let (mut lf, mut rf) = ([[0.0; S]; MAX_MODES], [[0.0; S]; MAX_MODES]);
        for i in 0..nm {
            let u = [amp[i][0], amp[i][1], amp[i][2], 0.0];
            for (q, &(f, g)) in self.sides.iter().enumerate().take(S) {
                (lf[i][q], rf[i][q]) = (u[f & 3], u[g & 3]);
            }
        }
        let mut d = [[0.0; 4]; MAX_MODES];
        for o in 0..=nm {
            // Σ value · first · second per table term (no prefactor), and ∂Q_o/∂(a, ȧ, ä⁽¹⁾)_i
            let mut bare = [0.0; MAX_SLOTS];
            d[..nm].fill([0.0; 4]);
            if o == 0 {
                for e in &self.radial_only {
                    let (f, g, _) = self.kinds[e.term];
                    let (x, y) = (amp[e.l][f], amp[e.m][g]);
                    bare[e.term] += e.value * x * y;
                    let cp = e.value * tp[e.term];
                    d[e.l][f] += cp * y;
                    d[e.m][g] += cp * x;
                }
            }
            for ((l, m), c) in self.rows.rows(o) {
                let c: &[f64; S] = c.try_into().expect("stride slots");
                // the product's factors x = first, y = second, its share of the bare sum and
                // its two derivatives, all slots at once
                let (mut tb, mut tx, mut ty) = ([0.0; S], [0.0; S], [0.0; S]);
                for q in 0..S {
                    let (x, y) = if swap[q] { (rf[m][q], lf[l][q]) } else { (lf[l][q], rf[m][q]) };
                    let cp = c[q] * pre[q];
                    (tb[q], tx[q], ty[q]) = (c[q] * x * y, cp * x, cp * y);
                }
                // added slot by slot in the walk's order (the same sums, bit for bit), into
                // the row's two modes' derivatives held apart (one when l = m)
                let two = usize::from(l != m);
                let mut acc = [d[l], d[m]];
                for q in 0..S {
                    if c[q] != 0.0 {
                        let (term, f, g) = plan[q];
                        let (i, k) = if swap[q] { (two, 0) } else { (0, two) };
                        bare[term] += tb[q];
                        acc[i][f] += ty[q];
                        acc[k][g] += tx[q];
                    }
                }
                d[m] = acc[1];
                d[l] = acc[0];
            }
            let row: &mut [f64] = if o == 0 { &mut jac.pressure[..] } else { &mut jac.gn[(o - 1) * n..o * n] };
            add_output_row(row, &bare, &dpre, &d[..nm], grad.drdd, grad.dadd);
        }
    }

    /// The scalar walk the row assembly replaces: per output, per row, per non-zero
    /// coefficient, the product's derivatives (kept to test the assembly against).
    #[cfg(test)]
    pub(super) fn add_jacobian_reference(&self, at: &At<'_>, first: &FirstOrder<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian) {
        let nm = self.orders.len();
        let n = jac.n;
        let (amp, tp, s) = self.state(at, first);
        let dpre = self.prefactor_gradients(&s, at.r());
        for o in 0..=nm {
            let mut bare = [0.0; MAX_SLOTS];
            let mut d = [[0.0; 3]; MAX_MODES];
            let mut put = |term: usize, c: f64, (i, f): (usize, usize), (k, g): (usize, usize)| {
                let (x, y) = (amp[i][f], amp[k][g]);
                bare[term] += c * x * y;
                let cp = c * tp[term];
                d[i][f] += cp * y;
                d[k][g] += cp * x;
            };
            if o == 0 {
                for e in &self.radial_only {
                    let (f, g, _) = self.kinds[e.term];
                    put(e.term, e.value, (e.l, f), (e.m, g));
                }
            }
            for ((l, m), c) in self.rows.rows(o) {
                for ((slot, &(x, y)), &cs) in self.slots.iter().zip(&self.gather).zip(c) {
                    if cs != 0.0 {
                        let at = |v: usize| if v < 3 { (l, v) } else { (m, v - 3) };
                        put(slot.term, cs, at(x), at(y));
                    }
                }
            }
            let row: &mut [f64] = if o == 0 { &mut jac.pressure[..] } else { &mut jac.gn[(o - 1) * n..o * n] };
            add_output_row(row, &bare, &dpre, &d[..nm], grad.drdd, grad.dadd);
        }
    }
}

/// Output row `row` (length n) of the Jacobian from its sums: `bare` (Σ value · first · second
/// per table term) through the prefactors' gradients `dpre` (∂/∂R, ∂/∂Ṙ, ∂/∂R̈⁽¹⁾, the last via
/// R̈⁽¹⁾'s gradient `drdd`), and `d[i]` = ∂Q/∂(a, ȧ, ä⁽¹⁾)_i, the last via ä⁽¹⁾_i's gradient (row i
/// of `dadd`). Shared by the row assembly and its reference walk (the same adds in the same order).
#[inline(always)]
fn add_output_row<const N: usize>(row: &mut [f64], bare: &[f64; MAX_SLOTS], dpre: &[[f64; 3]; MAX_SLOTS], d: &[[f64; N]], drdd: &[f64], dadd: &[f64]) {
    let n = row.len();
    let g_add = |i: usize| &dadd[i * n..(i + 1) * n];
    let mut via = [0.0; 3];
    for (b, dp) in bare.iter().zip(dpre) {
        for (v, x) in via.iter_mut().zip(dp) {
            *v += b * x;
        }
    }
    row[0] += via[0];
    row[1] += via[1];
    if via[2] != 0.0 {
        for (rj, gj) in row.iter_mut().zip(drdd) {
            *rj += via[2] * gj;
        }
    }
    let l = StateLayout::reduced(d.len());
    for (i, di) in d.iter().enumerate() {
        row[l.a(i)] += di[0];
        row[l.adot(i)] += di[1];
        if di[2] != 0.0 {
            for (rj, gj) in row.iter_mut().zip(g_add(i)) {
                *rj += di[2] * gj;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::second_order::{MaterialLoads, SecondOrderTerm};
    use super::*;

    /// The row walk is the scalar walk bit for bit on random states (k = 2 … 16 and
    /// k = 2 … 32, random first-order accelerations and gradients), and not trivially zero.
    #[test]
    fn row_assembly_is_the_scalar_walk() {
        for nm in [8usize, 16] {
            let orders: Vec<f64> = (1..=nm).map(|i| 2.0 * i as f64).collect();
            let q = QuadraticCoupling::new(1.0, 0.07, 4.2, 1.3, 1.0, &orders);
            let n = StateLayout::reduced(nm).dim();
            for seed in 0..20u64 {
                let v = |i: usize| (0.37 * i as f64 + 0.91 * seed as f64 + 0.1).sin();
                let mut z: Vec<f64> = (0..n).map(|i| 1e-2 * v(i)).collect();
                (z[0], z[1]) = (1.0 + 0.4 * v(1000), 0.5 * v(1001));
                let add: Vec<f64> = (0..nm).map(|i| 1e-2 * v(100 + i)).collect();
                let bd = vec![0.0; nm];
                let drdd: Vec<f64> = (0..n).map(|i| v(300 + i)).collect();
                let dadd: Vec<f64> = (0..nm * n).map(|i| v(500 + i)).collect();
                let dbd = vec![0.0; nm * n];
                let mj = LoadJacobian::new(nm);
                let first = FirstOrder { rdd: 0.3 * v(2000), add: &add, bd: &bd, material: MaterialLoads::NONE };
                let grad = FirstOrderGradient { drdd: &drdd, dadd: &dadd, dbd: &dbd, material: &mj };
                let at = At { t: 0.0, z: &z };
                let (mut want, mut got) = (LoadJacobian::new(nm), LoadJacobian::new(nm));
                q.add_jacobian_reference(&at, &first, &grad, &mut want);
                q.add_jacobian(&at, &first, &grad, &mut got);
                let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&want.pressure), bits(&got.pressure), "nm {nm} seed {seed}: P row");
                assert_eq!(bits(&want.gn), bits(&got.gn), "nm {nm} seed {seed}: G_n rows");
                assert!(want.pressure.iter().chain(&want.gn).filter(|x| **x != 0.0).count() > 2 * nm, "a non-trivial Jacobian");
                assert_eq!(want.gt, got.gt);
            }
        }
    }
}
