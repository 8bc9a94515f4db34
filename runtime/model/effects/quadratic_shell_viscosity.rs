//! Second-order (bilinear) loads of the viscous (Kelvin–Voigt) shell (issue 12, scope 1: the
//! membrane; docs/model.md, "Quadratic mode coupling"): the part of the surface viscous stress's
//! F_n, F_t (derivations/shell/viscous.rs, τ = (κ_s − μ_s)(tr D)I + 2μ_s D through
//! derivations/membrane.rs, tension form as the linear term) that is bilinear in the mode
//! amplitudes, from the generated table `coefficients::quadratic_membrane` law `viscous` (codegen
//! derive/jet2.rs takes `rate` at a material point to the bilinear order).
//!
//! Every term holds one rate: Ṙ·x_l·y_m (prefactor ∝ Ṙ) or x_l·ẏ_m with ẏ ∈ {ȧ, ḃ}, x ∈ {a, b}.
//! ḃ_m is not a state variable but the output of (NS) and its closure; in a term that is already
//! bilinear it is needed to first order only, so this is a second-pass term
//! ([`super::second_order`]) that takes the first-order ḃ⁽¹⁾ the core has just evaluated
//! ([`FirstOrder::bd`]; the error is O(ε³), the order of the terms not derived). The Jacobian is
//! exact for that rhs: through ∂ḃ⁽¹⁾/∂z ([`FirstOrderGradient::dbd`]), Ṙ and the prefactors' R.
//!
//! Signs as the linear viscous term (effects/shell.rs) and the quadratic membrane: the normal
//! load on P_0 is subtracted from P, on P_j added to G_n,j; the tangential load on P¹_j is added
//! to G_t,j.

use super::second_order::{FirstOrder, FirstOrderGradient, SecondOrderTerm};
use super::{At, LoadJacobian, Loads};
use crate::coefficients::quadratic_membrane::{Ab, Form, Law, Term as Table};
use crate::coefficients::Load;

/// Largest number of distinct prefactor monomials (the viscous table has 4).
const MAXP: usize = 8;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Row {
    /// −P (the normal load on P_0)
    Pressure,
    Normal(usize),
    Tangential(usize),
}

/// An amplitude factor: the kind and the mode index.
#[derive(Debug, Clone, Copy)]
struct Factor {
    kind: Ab,
    mode: usize,
}

#[derive(Debug, Clone)]
struct Entry {
    row: Row,
    x: Factor,
    y: Factor,
    /// index of the prefactor monomial and the coefficient C·N/D
    mono: usize,
    value: f64,
}

#[derive(Debug)]
pub struct QuadraticShellViscosity {
    /// exponents of (R, R0, Rd, mu_s, kappa_s) per distinct prefactor
    monos: Vec<[i32; 5]>,
    /// (R0, mu_s, kappa_s)
    consts: [f64; 3],
    entries: Vec<Entry>,
    modes: usize,
}

/// C(j, l, m) N(L_l, L_m, L_j)/D of one table term (the generated table's closed form), as the
/// membrane's second-order term evaluates it.
fn value(t: &Table, j: usize, l: usize, m: usize) -> f64 {
    let c = super::quadratic_membrane::projection(j, l, m);
    if c == 0.0 {
        return 0.0;
    }
    super::quadratic_membrane::value(t, c, j, l, m)
}

impl QuadraticShellViscosity {
    /// The generated `viscous` law, if its second-order loads are derived.
    pub fn law() -> Option<&'static Law> {
        crate::coefficients::quadratic_membrane::LAWS.iter().find(|l| l.name == "viscous")
    }

    /// `mu_s`, `kappa_s` nondimensional as the linear term's; `orders`: k of each mode index.
    /// None if the table is missing, has a symbol other than R, R0, Rd, mu_s, kappa_s, or more
    /// than [`MAXP`] prefactors.
    pub fn new(mu_s: f64, kappa_s: f64, r0: f64, orders: &[f64]) -> Option<Self> {
        let law = Self::law()?;
        let mut monos: Vec<[i32; 5]> = Vec::new();
        let mut kinds = Vec::new();
        for t in law.terms.iter().filter(|t| t.form == Form::Tension) {
            let mut e = [0; 5];
            for (s, p) in t.prefactor {
                let i = ["R", "R0", "Rd", "mu_s", "kappa_s"].iter().position(|x| x == s)?;
                e[i] = *p;
            }
            if e[2] > 1 {
                return None;
            }
            let i = monos.iter().position(|x| *x == e).unwrap_or_else(|| {
                monos.push(e);
                monos.len() - 1
            });
            kinds.push((t, i));
        }
        if monos.len() > MAXP {
            return None;
        }
        let ks: Vec<usize> = orders.iter().map(|&k| k as usize).collect();
        let mut entries = Vec::new();
        for (t, mono) in &kinds {
            for (l, &kl) in ks.iter().enumerate() {
                for (m, &km) in ks.iter().enumerate() {
                    let rows = std::iter::once((Row::Pressure, 0usize))
                        .filter(|_| t.load == Load::Normal)
                        .chain(ks.iter().enumerate().map(|(j, &kj)| (if t.load == Load::Normal { Row::Normal(j) } else { Row::Tangential(j) }, kj)));
                    for (row, kj) in rows {
                        let v = value(t, kj, kl, km);
                        if v != 0.0 {
                            entries.push(Entry { row, x: Factor { kind: t.first, mode: l }, y: Factor { kind: t.second, mode: m }, mono: *mono, value: v });
                        }
                    }
                }
            }
        }
        Some(Self { monos, consts: [r0, mu_s, kappa_s], entries, modes: ks.len() })
    }

    /// Prefactor values and their derivatives in R and in Ṙ.
    fn prefactors(&self, r: f64, rd: f64) -> ([f64; MAXP], [f64; MAXP], [f64; MAXP]) {
        let (mut p, mut dr, mut drd) = ([0.0; MAXP], [0.0; MAXP], [0.0; MAXP]);
        for (i, e) in self.monos.iter().enumerate() {
            let c = [(self.consts[0], e[1]), (self.consts[1], e[3]), (self.consts[2], e[4])]
                .iter()
                .fold(1.0, |acc, (v, k)| if *k == 0 { acc } else { acc * v.powi(*k) });
            let (rp, rdp) = (r.powi(e[0]), if e[2] == 0 { 1.0 } else { rd });
            p[i] = c * rp * rdp;
            dr[i] = c * e[0] as f64 * r.powi(e[0] - 1) * rdp;
            drd[i] = if e[2] == 0 { 0.0 } else { c * rp };
        }
        (p, dr, drd)
    }

    /// The value of a factor at the state, and its state index (None for ḃ, from the first pass).
    #[inline]
    fn factor(f: Factor, at: &At<'_>, first: &FirstOrder<'_>) -> (f64, Option<usize>) {
        let l = at.layout();
        match f.kind {
            Ab::A => (at.a(f.mode), Some(l.a(f.mode))),
            Ab::Ad => (at.adot(f.mode), Some(l.adot(f.mode))),
            Ab::B => (at.b(f.mode), Some(l.b(f.mode))),
            Ab::Bd => (first.bd[f.mode], None),
        }
    }

    /// Number of nonzero (row, l, m, term) entries.
    pub fn entries(&self) -> usize {
        self.entries.len()
    }
}

impl SecondOrderTerm for QuadraticShellViscosity {
    fn name(&self) -> &'static str {
        "quadratic shell viscosity"
    }
    fn label(&self) -> Option<String> {
        Some("quadratic shell-viscous loads".into())
    }
    fn band(&self) -> usize {
        self.modes
    }
    fn add(&self, at: &At<'_>, first: &FirstOrder<'_>, loads: &mut Loads<'_>) {
        let (p, _, _) = self.prefactors(at.r(), at.rdot());
        let (ng, nt) = (loads.gn.len(), loads.gt.len());
        for e in &self.entries {
            let (x, _) = Self::factor(e.x, at, first);
            let (y, _) = Self::factor(e.y, at, first);
            let v = e.value * p[e.mono] * x * y;
            match e.row {
                Row::Pressure => loads.pressure -= v,
                Row::Normal(j) if j < ng => loads.gn[j] += v,
                Row::Tangential(j) if j < nt => loads.gt[j] += v,
                _ => {}
            }
        }
    }
    fn add_jacobian(&self, at: &At<'_>, first: &FirstOrder<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian) {
        let (p, dr, drd) = self.prefactors(at.r(), at.rdot());
        let n = jac.n;
        let nm = jac.modes();
        for e in &self.entries {
            let (row, sign): (&mut [f64], f64) = match e.row {
                Row::Pressure => (&mut jac.pressure[..], -1.0),
                Row::Normal(j) if j < nm => (&mut jac.gn[j * n..(j + 1) * n], 1.0),
                Row::Tangential(j) if j < nm => (&mut jac.gt[j * n..(j + 1) * n], 1.0),
                _ => continue,
            };
            let (x, ix) = Self::factor(e.x, at, first);
            let (y, iy) = Self::factor(e.y, at, first);
            let c = sign * e.value;
            row[0] += c * dr[e.mono] * x * y;
            row[1] += c * drd[e.mono] * x * y;
            let pc = c * p[e.mono];
            for (idx, f, other) in [(ix, e.x, y), (iy, e.y, x)] {
                match idx {
                    Some(i) => row[i] += pc * other,
                    None => {
                        for (rj, gj) in row.iter_mut().zip(&grad.dbd[f.mode * n..(f.mode + 1) * n]) {
                            *rj += pc * other * gj;
                        }
                    }
                }
            }
        }
    }
}
