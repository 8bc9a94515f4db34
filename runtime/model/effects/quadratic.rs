//! Second-order (quadratic) mode coupling of a free bubble (issue 12; docs/model.md, "Quadratic
//! mode coupling"): Q_0 added to the radial balance P and Q_j added to G_n,j, from the generated
//! table `coefficients::quadratic::FREE_BUBBLE` (codegen, derivations/quadratic.rs):
//!
//!   Q_j = Σ_T Σ_{l,m} value_T(j, l, m) · prefactor_T(ρ, γ, R, Ṙ, R̈, p_g, κ) · first_T(l) · second_T(m),
//!
//! first/second ∈ {a, ȧ, ä}. The accelerations in Q are needed to first order only (R̈ to zero
//! order): they are taken from the inviscid linear equations of the runtime itself —
//! R̈⁽⁰⁾ = form(P_in), P_in the pressure of the gas, vapour, far-field and surface-tension terms,
//! and ä_l⁽¹⁾ = the mode equation (N) with η = 0 and G_n of the surface tension
//! ([`crate::model::equations::mode_rates`]). Dropping the viscous parts there changes Q by
//! O(νε²), the order of the viscous second-order terms that are not derived either.
//! The Jacobian is exact for these expressions (chain rule through R̈⁽⁰⁾ and ä⁽¹⁾).

use super::{a_index, At, LoadJacobian, Loads, Term, MAX_MODES};
use crate::coefficients::quadratic::{Term as QTerm, FREE_BUBBLE};
use crate::model::equations::{mode_partials, mode_rates, var, Wall, WallLinear};
use crate::model::radial::{Incompressible, RadialForm};

/// Symbols of the prefactors, in this order.
const SYMBOLS: [&str; 7] = ["rho", "gamma", "R", "Rd", "Rdd", "pg", "kappa"];

#[derive(Debug, Clone, Copy)]
struct Entry {
    /// mode index of the target, or None for the radial balance (j = 0)
    target: Option<usize>,
    l: usize,
    m: usize,
    term: usize,
    value: f64,
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
    /// The terms that give the zero-order R̈ and the first-order ä: gas, vapour, far field,
    /// surface tension (not the viscosity).
    inner: Vec<Box<dyn Term>>,
    /// (first, second, exponents of SYMBOLS) per table term
    kinds: Vec<(usize, usize, [i32; 7])>,
    entries: Vec<Entry>,
    /// The same coefficients dense, for the rhs: row 0 = radial balance, row 1 + j = mode j;
    /// column T·M² + l·M + m (T the table term).
    dense: Vec<f64>,
}

impl QuadraticCoupling {
    /// `orders`: k of each mode index; `inner`: the terms of the linear inviscid free bubble.
    pub fn new(rho: f64, gamma: f64, three_kappa: f64, pg0: f64, r0: f64, orders: &[f64], inner: Vec<Box<dyn Term>>) -> Self {
        let kinds = FREE_BUBBLE
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
        let mut entries = Vec::new();
        for (term, t) in FREE_BUBBLE.iter().enumerate() {
            for (l, &kl) in ks.iter().enumerate() {
                for (m, &km) in ks.iter().enumerate() {
                    let radial = t.value(0, kl, km);
                    if radial != 0.0 {
                        entries.push(Entry { target: None, l, m, term, value: radial });
                    }
                    for (j, &kj) in ks.iter().enumerate() {
                        let v = t.value(kj, kl, km);
                        if v != 0.0 {
                            entries.push(Entry { target: Some(j), l, m, term, value: v });
                        }
                    }
                }
            }
        }
        let nm = ks.len();
        let cols = FREE_BUBBLE.len() * nm * nm;
        let mut dense = vec![0.0; (nm + 1) * cols];
        for e in &entries {
            let row = e.target.map_or(0, |j| j + 1);
            dense[row * cols + e.term * nm * nm + e.l * nm + e.m] += e.value;
        }
        Self { rho, gamma, kappa: three_kappa / 3.0, pg0, r0, orders: orders.to_vec(), inner, kinds, entries, dense }
    }

    /// Number of nonzero coefficients (l, m → j).
    pub fn entries(&self) -> usize {
        self.entries.len()
    }

    fn inner_loads(&self, at: &At<'_>, gn: &mut [f64]) -> f64 {
        let mut gt = [0.0; MAX_MODES];
        gn.fill(0.0);
        let mut l = Loads { pressure: 0.0, gn, gt: &mut gt[..self.orders.len()] };
        for t in &self.inner {
            t.add(at, &mut l);
        }
        l.pressure
    }

    /// Symbol values (SYMBOLS order) and R̈⁽⁰⁾.
    fn symbols(&self, r: f64, rd: f64, rdd: f64) -> [f64; 7] {
        let pg = self.pg0 * (self.r0 / r).powf(3.0 * self.kappa);
        [self.rho, self.gamma, r, rd, rdd, pg, self.kappa]
    }

    fn prefactor(e: &[i32; 7], s: &[f64; 7]) -> f64 {
        e.iter().zip(s).fold(1.0, |acc, (p, v)| if *p == 0 { acc } else { acc * v.powi(*p) })
    }
}

/// Σ a_i b_i with four partial sums (vectorizes).
#[inline]
fn dot4(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = ca.remainder().iter().zip(cb.remainder()).map(|(x, y)| x * y).sum();
    for (x, y) in ca.zip(cb) {
        for i in 0..4 {
            acc[i] += x[i] * y[i];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

impl Term for QuadraticCoupling {
    fn name(&self) -> &'static str {
        "quadratic coupling"
    }
    fn label(&self) -> Option<String> {
        Some("quadratic mode coupling (free bubble)".to_string())
    }
    fn band(&self) -> usize {
        self.orders.len()
    }
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>) {
        let n = self.orders.len();
        let (r, rd) = (at.r(), at.rdot());
        let mut gn_in = [0.0; MAX_MODES];
        let p_in = self.inner_loads(at, &mut gn_in[..n]);
        let rdd = Incompressible.acceleration(self.rho, r, rd, p_in);
        let wall = Wall { tw: 0.0, itil: 0.0, normal: [0.0; 3] };
        let mut amp = [[0.0; 3]; MAX_MODES];
        for (i, a) in amp.iter_mut().enumerate().take(n) {
            let (x, xd) = (at.a(i), at.adot(i));
            let (add, _) = mode_rates(self.orders[i], self.rho, 0.0, r, rd, rdd, x, xd, at.b(i), gn_in[i], &wall);
            *a = [x, xd, add];
        }
        let s = self.symbols(r, rd, rdd);
        // w[T·M² + l·M + m] = prefactor_T · first_T(l) · second_T(m); Q = dense · w
        let nn = n * n;
        let mut w = vec![0.0; self.kinds.len() * nn];
        for (t, (f, g, e)) in self.kinds.iter().enumerate() {
            let p = Self::prefactor(e, &s);
            let block = &mut w[t * nn..(t + 1) * nn];
            for l in 0..n {
                let x = p * amp[l][*f];
                for m in 0..n {
                    block[l * n + m] = x * amp[m][*g];
                }
            }
        }
        let cols = w.len();
        let dot = |row: usize| dot4(&self.dense[row * cols..(row + 1) * cols], &w);
        loads.pressure += dot(0);
        for j in 0..loads.gn.len().min(n) {
            loads.gn[j] += dot(j + 1);
        }
    }
    fn add_jacobian(&self, at: &At<'_>, jac: &mut LoadJacobian) {
        let nm = self.orders.len();
        let n = jac.n;
        let (r, rd) = (at.r(), at.rdot());
        // the inner terms: values and exact gradients
        let mut gn_in = vec![0.0; nm];
        let p_in = self.inner_loads(at, &mut gn_in);
        let mut lj = LoadJacobian::new(nm);
        for t in &self.inner {
            t.add_jacobian(at, &mut lj);
        }
        let rdd = Incompressible.acceleration(self.rho, r, rd, p_in);
        let (d_r, d_rd, d_p) = Incompressible.partials(self.rho, r, rd, p_in);
        let mut g_rdd: Vec<f64> = lj.pressure.iter().map(|x| d_p * x).collect();
        g_rdd[0] += d_r;
        g_rdd[1] += d_rd;
        // amplitudes and their gradients: a, ȧ unit vectors, ä⁽¹⁾ by the chain rule through (N)
        let wall = Wall { tw: 0.0, itil: 0.0, normal: [0.0; 3] };
        let mut amp = vec![[0.0; 3]; nm];
        let mut g_add = vec![vec![0.0; n]; nm];
        for i in 0..nm {
            let ia = a_index(i);
            let (x, xd, b) = (at.a(i), at.adot(i), at.b(i));
            let k = self.orders[i];
            let (add, _) = mode_rates(k, self.rho, 0.0, r, rd, rdd, x, xd, b, gn_in[i], &wall);
            amp[i] = [x, xd, add];
            let (d, _) = mode_partials(k, self.rho, 0.0, r, rd, rdd, x, xd, b, gn_in[i], &WallLinear::default());
            let g = &mut g_add[i];
            for j in 0..n {
                g[j] = d[var::RDD] * g_rdd[j] + d[var::GN] * lj.gn[i * n + j];
            }
            g[0] += d[var::R];
            g[1] += d[var::RD];
            g[ia] += d[var::A];
            g[ia + 1] += d[var::AD];
            g[ia + 2] += d[var::B];
        }
        // prefactors and their gradients (through R, Ṙ explicitly, R̈⁽⁰⁾ and p_g(R))
        let s = self.symbols(r, rd, rdd);
        let mut pre = Vec::new();
        let mut g_pre = Vec::new();
        for (_, _, e) in &self.kinds {
            let p = Self::prefactor(e, &s);
            let mut g = vec![0.0; n];
            // ∂/∂symbol = power · p / value
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
                    for j in 0..n {
                        row[j] += p * other * g_add[amp_i][j];
                    }
                } else {
                    row[unit(amp_i, ord)] += p * other;
                }
            }
        }
    }
}
