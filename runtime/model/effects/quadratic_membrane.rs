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

use super::{a_index, At, LoadJacobian, Loads, Term};
use crate::coefficients::quadratic_lookup::ppp;
use crate::coefficients::quadratic_membrane::{Ab, Form, Law, LAWS};
use crate::coefficients::Load;

/// Largest number of distinct prefactor monomials of one law and form.
pub const MAXP: usize = 8;

/// Where an entry lands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Row {
    /// −P (the normal load on P_0)
    Pressure,
    Normal(usize),
    Tangential(usize),
}

#[derive(Debug, Clone)]
struct Entry {
    row: Row,
    /// state index of the first amplitude (mode l) and of the second (mode m)
    x: usize,
    y: usize,
    /// coefficient of each prefactor monomial (index into `monos`)
    coef: Vec<f64>,
}

#[derive(Debug)]
pub struct QuadraticMembrane {
    law: &'static str,
    /// Exponents of (R, R0, symbol 1, symbol 2) of each distinct prefactor.
    monos: Vec<[i32; 4]>,
    /// Values of (R0, symbol 1, symbol 2).
    consts: [f64; 3],
    entries: Vec<Entry>,
    modes: usize,
}

/// C(j, l, m) N(L_l, L_m, L_j)/D of one table term.
fn value(t: &crate::coefficients::quadratic_membrane::Term, j: usize, l: usize, m: usize) -> f64 {
    if t.load == Load::Tangential && j == 0 {
        return 0.0;
    }
    let c = ppp(l, m, j) * (2.0 * j as f64 + 1.0) / 2.0;
    if c == 0.0 {
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
    /// as the linear membrane term takes them. None if the table has more than [`MAXP`] distinct
    /// prefactors for this form (the rhs keeps them on the stack).
    pub fn new(law: &'static Law, form: Form, r0: f64, args: (f64, f64), orders: &[f64]) -> Option<Self> {
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
        let ks: Vec<usize> = orders.iter().map(|&k| k as usize).collect();
        let n = ks.len();
        let mut entries: Vec<Entry> = Vec::new();
        let mut at: std::collections::HashMap<(Row, usize, usize), usize> = std::collections::HashMap::new();
        let idx = |i: usize, a: Ab| a_index(i) + if a == Ab::A { 0 } else { 2 };
        for (t, mono) in &kinds {
            for (l, &kl) in ks.iter().enumerate() {
                for (m, &km) in ks.iter().enumerate() {
                    let targets = std::iter::once((Row::Pressure, 0usize)).chain(ks.iter().enumerate().map(|(j, &kj)| (if t.load == Load::Normal { Row::Normal(j) } else { Row::Tangential(j) }, kj)));
                    for (row, kj) in targets {
                        if row == Row::Pressure && t.load == Load::Tangential {
                            continue;
                        }
                        let v = value(t, kj, kl, km);
                        if v == 0.0 {
                            continue;
                        }
                        let (x, y) = (idx(l, t.first), idx(m, t.second));
                        let i = *at.entry((row, x, y)).or_insert_with(|| {
                            entries.push(Entry { row, x, y, coef: vec![0.0; MAXP] });
                            entries.len() - 1
                        });
                        entries[i].coef[*mono] += v;
                    }
                }
            }
        }
        if monos.len() > MAXP {
            return None;
        }
        for e in &mut entries {
            e.coef.truncate(monos.len());
        }
        Some(Self { law: law.name, monos, consts: [r0, args.0, args.1], entries, modes: n })
    }

    /// Number of nonzero (row, l, m) entries.
    pub fn entries(&self) -> usize {
        self.entries.len()
    }

    /// Prefactor values and their R-derivatives at R.
    fn prefactors(&self, r: f64) -> ([f64; MAXP], [f64; MAXP]) {
        let (mut p, mut d) = ([0.0; MAXP], [0.0; MAXP]);
        for (i, e) in self.monos.iter().enumerate() {
            let c = self.consts.iter().zip(&e[1..]).fold(1.0, |acc, (v, k)| if *k == 0 { acc } else { acc * v.powi(*k) });
            p[i] = c * r.powi(e[0]);
            d[i] = c * e[0] as f64 * r.powi(e[0] - 1);
        }
        (p, d)
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
        let (p, _) = self.prefactors(at.r());
        let np = self.monos.len();
        let (ng, nt) = (loads.gn.len(), loads.gt.len());
        for e in &self.entries {
            let c: f64 = e.coef.iter().zip(&p[..np]).map(|(a, b)| a * b).sum();
            let v = c * at.z[e.x] * at.z[e.y];
            match e.row {
                Row::Pressure => loads.pressure -= v,
                Row::Normal(j) if j < ng => loads.gn[j] += v,
                Row::Tangential(j) if j < nt => loads.gt[j] += v,
                _ => {}
            }
        }
    }
    fn add_jacobian(&self, at: &At<'_>, jac: &mut LoadJacobian) {
        let (p, d) = self.prefactors(at.r());
        let np = self.monos.len();
        let n = jac.n;
        for e in &self.entries {
            let c: f64 = e.coef.iter().zip(&p[..np]).map(|(a, b)| a * b).sum();
            let cr: f64 = e.coef.iter().zip(&d[..np]).map(|(a, b)| a * b).sum();
            let (x, y) = (at.z[e.x], at.z[e.y]);
            let (row, sign): (&mut [f64], f64) = match e.row {
                Row::Pressure => (&mut jac.pressure[..], -1.0),
                Row::Normal(j) => (&mut jac.gn[j * n..(j + 1) * n], 1.0),
                Row::Tangential(j) => (&mut jac.gt[j * n..(j + 1) * n], 1.0),
            };
            row[0] += sign * cr * x * y;
            row[e.x] += sign * c * y;
            row[e.y] += sign * c * x;
        }
    }
}
