//! Second-order (bilinear) membrane loads (issue 12, scope 1; docs/model.md, "Quadratic mode
//! coupling"): the part of the membrane's F_n and F_t that is bilinear in the mode amplitudes
//! (a_l, b_l)·(a_m, b_m), with its exact dependence on R, from the generated table
//! `coefficients::quadratic_membrane` (codegen, derive/quadratic_membrane.rs: the law's W through
//! derivations/hyperelastic.rs and membrane.rs on the exact kinematics, projected on P_j and
//! P¹_j at the material angle as the linear S1, S2, S11, S12 are):
//!
//!   F_j⁽²⁾ = Σ_T Σ_{l,m} C(j,l,m) N_T(L_l, L_m, L_j)/D · prefactor_T(R, R0, law symbols) · first_T(l) · second_T(m).
//!
//! Signs as the linear membrane term (effects/membrane.rs): the normal load on P_0 is subtracted
//! from the radial balance P (as Ŝ0), on P_j (j ≥ 2) added to G_n,j (as Ŝ1 a + Ŝ2 b); the
//! tangential load on P¹_j is added to G_t,j (as Ŝ11 a + Ŝ12 b). The Jacobian is exact.
//!
//! Cost (issue 12, docs/performance.md): only the (load, pair l ≤ m) rows the selection rules
//! allow are stored ([`super::pair_rows`]); a pair's slots are the four products a_l a_m,
//! a_l b_m, a_m b_l, b_l b_m (symmetric ones folded) times each distinct prefactor, formed once
//! per rhs. The Jacobian walks the same rows.

use super::pair_rows::PairRows;
use super::{zeroed, At, LoadJacobian, Loads, Term, MAX_DIM};
use crate::model::layout::StateLayout;
use crate::coefficients::quadratic_lookup::ppp;
use crate::coefficients::quadratic_membrane::{Ab, Form, Law, LAWS};
use crate::coefficients::Load;

/// Largest number of distinct prefactor monomials of one law and form.
pub const MAXP: usize = 8;

/// The products of a pair l ≤ m, in slot order (slot = prefactor · 4 + product).
const PRODUCTS: usize = 4;

#[derive(Debug)]
pub struct QuadraticMembrane {
    law: &'static str,
    /// Exponents of (R, R0, symbol 1, symbol 2) of each distinct prefactor.
    monos: Vec<[i32; 4]>,
    /// The constant part (R0 and the law's symbols) of each prefactor.
    constant: [f64; MAXP],
    /// outputs: 0 = −P, 1 + j = G_n,j, 1 + M + j = G_t,j
    rows: PairRows,
    modes: usize,
}

/// Product slot (0 a_l a_m, 1 a_l b_m, 2 a_m b_l, 3 b_l b_m) of first(x)·second(y), the ordered
/// pair (x, y) being (l, m) when `forward`, else (m, l).
fn product(first: Ab, second: Ab, forward: bool) -> usize {
    match (first, second) {
        (Ab::A, Ab::A) => 0,
        (Ab::B, Ab::B) => 3,
        // a_x b_y
        (Ab::A, Ab::B) => if forward { 1 } else { 2 },
        // b_x a_y = a_y b_x
        (Ab::B, Ab::A) => if forward { 2 } else { 1 },
        // Rate amplitudes belong to the viscous shell's table (effects/quadratic_shell_viscosity.rs);
        // `new` refuses a law that has them, so no row is built for them.
        (Ab::Ad | Ab::Bd, _) | (_, Ab::Ad | Ab::Bd) => unreachable!("QuadraticMembrane::new refuses laws with rate amplitudes"),
    }
}

/// C(j, l, m) = (2j + 1)/2 ∫ P_l P_m P_j: the coefficient of P_j in P_l P_m (0 outside the
/// selection rules).
pub(super) fn projection(j: usize, l: usize, m: usize) -> f64 {
    ppp(l, m, j) * (2.0 * j as f64 + 1.0) / 2.0
}

/// C(j, l, m) N(L_l, L_m, L_j)/D of one table term, `c` = C(j, l, m) ≠ 0.
pub(super) fn value(t: &crate::coefficients::quadratic_membrane::Term, c: f64, j: usize, l: usize, m: usize) -> f64 {
    if t.load == Load::Tangential && j == 0 {
        return 0.0;
    }
    let big = |n: usize| (n * (n + 1)) as f64;
    let x = [big(l), big(m), big(j)];
    let n: f64 = t.numerator.iter().map(|(e, v)| v * x[0].powi(e[0] as i32) * x[1].powi(e[1] as i32) * x[2].powi(e[2] as i32)).sum();
    match t.load {
        Load::Normal => c * n,
        Load::Tangential => c * n / x[2],
    }
}

impl QuadraticMembrane {
    /// The generated law `name`, if its second-order loads are derived.
    pub fn law(name: &str) -> Option<&'static Law> {
        LAWS.iter().find(|l| l.name == name)
    }

    /// `orders`: k of each mode index; `args`: the law's two symbols (ε-scaled, nondimensional),
    /// as the linear membrane term takes them. None if the law has rate amplitudes (ȧ, ḃ, Ṙ: the viscous shell) or the table has more than [`MAXP`] distinct
    /// prefactors for this form (the rhs keeps them on the stack).
    pub fn new(law: &'static Law, form: Form, r0: f64, args: (f64, f64), orders: &[f64]) -> Option<Self> {
        let rate = |a: Ab| matches!(a, Ab::Ad | Ab::Bd);
        if law.terms.iter().any(|t| rate(t.first) || rate(t.second) || t.prefactor.iter().any(|(s, _)| *s == "Rd")) {
            return None;
        }
        let mut monos: Vec<[i32; 4]> = Vec::new();
        let mut kinds = Vec::new();
        for t in law.terms.iter().filter(|t| t.form == form) {
            let mut e = [0; 4];
            for (s, p) in t.prefactor {
                let i = match *s {
                    "R" => 0,
                    "R0" => 1,
                    s => 2 + law.symbols.iter().position(|x| *x == s).expect("generated prefactor symbols are the law's"),
                };
                e[i] = *p;
            }
            let i = monos.iter().position(|x| *x == e).unwrap_or_else(|| {
                monos.push(e);
                monos.len() - 1
            });
            if i >= MAXP {
                return None;
            }
            kinds.push((t, i));
        }
        if monos.len() > MAXP {
            return None;
        }
        let ks: Vec<usize> = orders.iter().map(|&k| k as usize).collect();
        let n = ks.len();
        let np = monos.len();
        let rows = PairRows::new(n, 1 + 2 * n, PRODUCTS * np, |o, l, m, c| {
            let (load, kj) = match o {
                0 => (Load::Normal, 0),
                o if o <= n => (Load::Normal, ks[o - 1]),
                o => (Load::Tangential, ks[o - 1 - n]),
            };
            let (kl, km) = (ks[l], ks[m]);
            if kj < kl.abs_diff(km) || kj > kl + km {
                return false;
            }
            // C(j, l, m) is symmetric in (l, m)
            let cj = projection(kj, kl, km);
            if cj == 0.0 {
                return false;
            }
            for (t, mono) in kinds.iter().filter(|(t, _)| t.load == load) {
                c[mono * PRODUCTS + product(t.first, t.second, true)] += value(t, cj, kj, kl, km);
                if l != m {
                    // the ordered pair (m, l): a symmetric product folds in, an asymmetric one
                    // is the other slot
                    c[mono * PRODUCTS + product(t.first, t.second, false)] += value(t, cj, kj, km, kl);
                }
            }
            true
        });
        let consts = [r0, args.0, args.1];
        let mut constant = [0.0; MAXP];
        for (c, e) in constant.iter_mut().zip(&monos) {
            *c = consts.iter().zip(&e[1..]).fold(1.0, |acc, (v, k)| if *k == 0 { acc } else { acc * v.powi(*k) });
        }
        Some(Self { law: law.name, monos, constant, rows, modes: n })
    }

    /// Number of stored (load, pair) rows.
    pub fn sparse_rows(&self) -> usize {
        self.rows.len()
    }

    /// The prefactor values c·R^e at R (what the rhs needs; [`prefactors`](Self::prefactors) adds
    /// the R-derivatives for the Jacobian).
    fn values(&self, r: f64) -> [f64; MAXP] {
        let mut p = [0.0; MAXP];
        for (i, (e, c)) in self.monos.iter().zip(&self.constant).enumerate() {
            p[i] = c * (r.powi(e[0] - 1) * r);
        }
        p
    }

    /// Prefactor values ([`values`](Self::values)) and their R-derivatives at R.
    fn prefactors(&self, r: f64) -> ([f64; MAXP], [f64; MAXP]) {
        let mut d = [0.0; MAXP];
        for (i, (e, c)) in self.monos.iter().zip(&self.constant).enumerate() {
            d[i] = c * e[0] as f64 * r.powi(e[0] - 1);
        }
        (self.values(r), d)
    }
}

/// The factors of the pair products (slot i·4 + t, `np` = `p.len()` prefactors): left(k) =
/// p_i (a_k, a_k, b_k, b_k), right(k) = (a_k, b_k, a_k, b_k), for every mode k of `left`.
fn factors(at: &At<'_>, p: &[f64], left: &mut [f64], right: &mut [f64]) {
    let st = PRODUCTS * p.len();
    if st == 0 {
        return;
    }
    for (k, (lv, rv)) in left.chunks_exact_mut(st).zip(right.chunks_exact_mut(st)).enumerate() {
        let (a, b) = (at.a(k), at.b(k));
        for ((lc, rc), pi) in lv.chunks_exact_mut(PRODUCTS).zip(rv.chunks_exact_mut(PRODUCTS)).zip(p) {
            lc.copy_from_slice(&[pi * a, pi * a, pi * b, pi * b]);
            rc.copy_from_slice(&[a, b, a, b]);
        }
    }
}

impl Term for QuadraticMembrane {
    fn name(&self) -> &'static str {
        "quadratic membrane"
    }
    fn label(&self) -> Option<String> {
        Some(format!("quadratic membrane loads ({})", self.law))
    }
    fn band(&self) -> usize {
        self.modes
    }
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>) {
        let p = self.values(at.r());
        let n = self.modes;
        let np = self.monos.len();
        // the outputs' sums: zeros where used (not the whole MAX_MODES buffer)
        let mut buf = [std::mem::MaybeUninit::<f64>::uninit(); 1 + 2 * super::MAX_MODES];
        let out = zeroed(&mut buf[..1 + 2 * n]);
        // slot i·4 + t: p_i (a_l, a_l, b_l, b_l)_t · (a_m, b_m, a_m, b_m)_t
        self.rows.eval(out, |left, right| factors(at, &p[..np], left, right));
        loads.pressure -= out[0];
        for (g, o) in loads.gn.iter_mut().zip(&out[1..=n]) {
            *g += o;
        }
        for (g, o) in loads.gt.iter_mut().zip(&out[1 + n..]) {
            *g += o;
        }
    }
    fn add_jacobian(&self, at: &At<'_>, jac: &mut LoadJacobian) {
        let (p, d) = self.prefactors(at.r());
        let np = self.monos.len();
        self.jacobian_with(at, jac, |c| row_sums(c, &p[..np], &d[..np]));
    }
}

/// A row's prefactors summed per product: Σ_i c(i, t) p_i and Σ_i c(i, t) ∂p_i/∂R, from 0 in
/// prefactor order.
fn row_sums(c: &[f64], p: &[f64], d: &[f64]) -> ([f64; PRODUCTS], [f64; PRODUCTS]) {
    let (mut cp, mut cd) = ([0.0; PRODUCTS], [0.0; PRODUCTS]);
    for (ci, (pi, di)) in c.chunks_exact(PRODUCTS).zip(p.iter().zip(d)) {
        for t in 0..PRODUCTS {
            cp[t] += ci[t] * pi;
            cd[t] += ci[t] * di;
        }
    }
    (cp, cd)
}

impl QuadraticMembrane {
    /// The Jacobian's walk over the rows, `sums(c)` a row's [`row_sums`].
    #[inline(always)]
    fn jacobian_with(&self, at: &At<'_>, jac: &mut LoadJacobian, sums: impl Fn(&[f64]) -> ([f64; PRODUCTS], [f64; PRODUCTS])) {
        let (n, lay) = (jac.n, jac.layout());
        let nm = self.modes;
        for o in 0..1 + 2 * nm {
            let (row, sign): (&mut [f64], f64) = match o {
                0 => (&mut jac.pressure[..], -1.0),
                o if o <= nm => (&mut jac.gn[(o - 1) * n..o * n], 1.0),
                o => (&mut jac.gt[(o - 1 - nm) * n..(o - nm) * n], 1.0),
            };
            // ∂/∂R and ∂/∂z_x of the output, summed locally (no chain through memory)
            let (mut dr, mut dz) = (0.0, [0.0; MAX_DIM]);
            for ((l, m), c) in self.rows.rows(o) {
                let (ia, ib, ja, jb) = (lay.a(l), lay.b(l), lay.a(m), lay.b(m));
                // (x, y) state indices of each product
                let idx = [(ia, ja), (ia, jb), (ja, ib), (ib, jb)];
                // the prefactors summed per product: value and ∂/∂R
                let (cp, cd) = sums(c);
                for ((&(x, y), cp), cd) in idx.iter().zip(cp).zip(cd) {
                    let (vx, vy) = (at.z[x], at.z[y]);
                    dr += cd * vx * vy;
                    dz[x] += cp * vy;
                    dz[y] += cp * vx;
                }
            }
            row[0] += sign * dr;
            for (rj, dj) in row.iter_mut().zip(&dz).skip(StateLayout::RADIAL) {
                *rj += sign * dj;
            }
        }
    }
}
