//! The exact Jacobian of [`QuadraticCoupling`] assembled from the pair rows directly (issue 12,
//! "Performance"; docs/performance.md): for output o (0 = P, 1 + i = G_n of mode index i)
//!
//!   Q_o = Σ_{rows (l ≤ m)} Σ_s c_s · pre_s · u_l[f_s] · u_m[g_s],   u = [a, ȧ, ä⁽¹⁾],
//!
//! (f_s, g_s) the slot's sides ([`QuadraticCoupling::sides`]), so per row the derivatives
//! ∂Q_o/∂u_l[f_s] = c_s pre_s u_m[g_s] and ∂Q_o/∂u_m[g_s] = c_s pre_s u_l[f_s] are two slot
//! vectors, c ⊙ (pre ⊙ right(m)) and c ⊙ (pre ⊙ left(l)), added into one slot vector per
//! (output, mode, side); and the prefactor-free sums c_s u_l[f_s] u_m[g_s] per slot give
//! ∂Q_o/∂(R, Ṙ, R̈⁽¹⁾) through ∂pre/∂symbol. The slot vectors are folded onto (a, ȧ, ä⁽¹⁾)
//! once per (output, mode), then the chain rule through ∂ä⁽¹⁾/∂x and ∂R̈⁽¹⁾/∂x as before.
//! The same derivatives as the scalar walk it replaces ([`QuadraticCoupling::add_jacobian_reference`],
//! kept for the test below), summed slot-wise: equal to round-off. One pass over each row's
//! coefficients with fixed-size slot vectors (compiled with AVX where the processor has it;
//! no FMA), instead of a closure call per non-zero coefficient.

use super::super::second_order::{FirstOrder, FirstOrderGradient};
use super::super::{a_index, At, LoadJacobian, MAX_MODES};
use super::{QuadraticCoupling, MAX_SLOTS};

impl QuadraticCoupling {
    /// [`SecondOrderTerm::add_jacobian`](super::super::second_order::SecondOrderTerm::add_jacobian)
    /// (module doc).
    pub(super) fn jacobian_rows(&self, at: &At<'_>, first: &FirstOrder<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: AVX is available (checked just above); the body is safe code.
            unsafe { self.jacobian_avx(at, first, grad, jac) };
            return;
        }
        self.jacobian_body(at, first, grad, jac);
    }

    /// [`jacobian_body`](Self::jacobian_body) compiled with AVX (the same operations).
    ///
    /// # Safety
    /// AVX available.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn jacobian_avx(&self, at: &At<'_>, first: &FirstOrder<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian) {
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
        assert!(S == self.rows.stride() && S <= MAX_SLOTS, "quadratic Jacobian stride");
        let nm = self.orders.len();
        let n = jac.n;
        let (amp, tp, s) = self.state(at, first);
        let dpre = self.prefactor_gradients(&s, at.r());
        // per mode: the bare left / right factors u[f_s], u[g_s], and the same times pre_s
        let (mut l0, mut r0, mut pl, mut pr) = ([[0.0; S]; MAX_MODES], [[0.0; S]; MAX_MODES], [[0.0; S]; MAX_MODES], [[0.0; S]; MAX_MODES]);
        let mut pre = [0.0; S];
        for (p, slot) in pre.iter_mut().zip(&self.slots) {
            *p = tp[slot.term];
        }
        for i in 0..nm {
            let u = [amp[i][0], amp[i][1], amp[i][2], 0.0];
            for (q, &(f, g)) in self.sides.iter().enumerate().take(S) {
                (l0[i][q], r0[i][q]) = (u[f & 3], u[g & 3]);
                (pl[i][q], pr[i][q]) = (pre[q] * l0[i][q], pre[q] * r0[i][q]);
            }
        }
        let g_add = |i: usize| &grad.dadd[i * n..(i + 1) * n];
        for o in 0..=nm {
            // dl[i]: ∂Q_o/∂u_i[f_s] per slot (mode i on the left), dr[i]: on the right; t: the
            // prefactor-free sums per slot
            let (mut dl, mut dr, mut t) = ([[0.0; S]; MAX_MODES], [[0.0; S]; MAX_MODES], [0.0; S]);
            for ((l, m), c) in self.rows.rows(o) {
                let c: &[f64; S] = c.try_into().expect("stride slots");
                let (xl, ym, al, am) = (&pl[l], &pr[m], &l0[l], &r0[m]);
                for q in 0..S {
                    dl[l][q] += c[q] * ym[q];
                    dr[m][q] += c[q] * xl[q];
                    t[q] += c[q] * al[q] * am[q];
                }
            }
            let mut bare = [0.0; MAX_SLOTS];
            let mut d = [[0.0; 4]; MAX_MODES];
            for (q, slot) in self.slots.iter().enumerate() {
                bare[slot.term] += t[q];
            }
            for i in 0..nm {
                for (q, &(f, g)) in self.sides.iter().enumerate().take(S) {
                    d[i][f & 3] += dl[i][q];
                    d[i][g & 3] += dr[i][q];
                }
            }
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
            let row: &mut [f64] = if o == 0 { &mut jac.pressure[..] } else { &mut jac.gn[(o - 1) * n..o * n] };
            let mut via = [0.0; 3];
            for (b, dp) in bare.iter().zip(&dpre) {
                for (v, x) in via.iter_mut().zip(dp) {
                    *v += b * x;
                }
            }
            row[0] += via[0];
            row[1] += via[1];
            if via[2] != 0.0 {
                for (rj, gj) in row.iter_mut().zip(grad.drdd) {
                    *rj += via[2] * gj;
                }
            }
            for (i, di) in d.iter().enumerate().take(nm) {
                row[a_index(i)] += di[0];
                row[a_index(i) + 1] += di[1];
                if di[2] != 0.0 {
                    for (rj, gj) in row.iter_mut().zip(g_add(i)) {
                        *rj += di[2] * gj;
                    }
                }
            }
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
        let g_add = |i: usize| &grad.dadd[i * n..(i + 1) * n];
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
            let mut via = [0.0; 3];
            for (b, dp) in bare.iter().zip(&dpre) {
                for (v, x) in via.iter_mut().zip(dp) {
                    *v += b * x;
                }
            }
            row[0] += via[0];
            row[1] += via[1];
            if via[2] != 0.0 {
                for (rj, gj) in row.iter_mut().zip(grad.drdd) {
                    *rj += via[2] * gj;
                }
            }
            for (i, di) in d.iter().enumerate().take(nm) {
                row[a_index(i)] += di[0];
                row[a_index(i) + 1] += di[1];
                if di[2] != 0.0 {
                    for (rj, gj) in row.iter_mut().zip(g_add(i)) {
                        *rj += di[2] * gj;
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::second_order::{MaterialLoads, SecondOrderTerm};
    use super::*;

    /// The row assembly equals the scalar walk to round-off on random states (k = 2 … 16 and
    /// k = 2 … 32, random first-order accelerations and gradients), entry by entry relative to
    /// the largest entry of its row.
    #[test]
    fn row_assembly_is_the_scalar_walk() {
        for nm in [8usize, 16] {
            let orders: Vec<f64> = (1..=nm).map(|i| 2.0 * i as f64).collect();
            let q = QuadraticCoupling::new(1.0, 0.07, 4.2, 1.3, 1.0, &orders);
            let n = 2 + 3 * nm;
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
                let rows = std::iter::once((&want.pressure[..], &got.pressure[..])).chain((0..nm).map(|i| (want.gn_row(i), got.gn_row(i))));
                for (k, (w, g)) in rows.enumerate() {
                    let scale = w.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                    assert!(scale > 0.0, "row {k} is zero");
                    for (j, (x, y)) in w.iter().zip(g).enumerate() {
                        assert!((x - y).abs() <= 1e-13 * scale, "nm {nm} seed {seed} row {k} col {j}: {y} against {x}");
                    }
                }
                assert_eq!(want.gt, got.gt);
            }
        }
    }
}
