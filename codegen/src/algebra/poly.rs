//! Sparse multivariate Laurent polynomials with exact rational coefficients.
//!
//! Symbols are names. Internal symbols start with `#` (never a spec identifier):
//! `#x` = cos Θ, `#s` = sin Θ (material angle); `#r`, `#ct`, `#st` = r, cos θ, sin θ (field
//! point); `#P0`, `#P1`, … = the i-th x-derivative of P_k(x) (mode-shape markers); `#a`, `#b` =
//! the amplitudes a_k, b_k; `#ad`, `#bd` = their rates ȧ_k, ḃ_k; `#v` = the virtual variation of
//! `vary` (terms of order #v² are dropped), `#h0`, `#h1`, … = its test function η and η', η'', ….
//! Canonical form: for each trigonometric pair (c, s) the exponent of c
//! is 0 or 1 (c² is rewritten as 1 − s²); s may carry any integer power.

use super::{rat, Rat};
use num_traits::{One, Zero};
use std::collections::BTreeMap;

/// The infinitesimal of a first variation (`vary`): kept to first order.
pub const VIRTUAL: &str = "#v";

/// Trigonometric pairs (cos, sin) reduced with cos² = 1 − sin².
pub const TRIG_PAIRS: [(&str, &str); 2] = [("#x", "#s"), ("#ct", "#st")];

/// A monomial Π symbol^power: sorted by symbol, no zero powers.
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default)]
pub struct Mono(pub Vec<(String, i32)>);

impl Mono {
    pub fn one() -> Mono {
        Mono(Vec::new())
    }
    pub fn var(name: &str, power: i32) -> Mono {
        Mono::one().with(name, power)
    }
    pub fn is_one(&self) -> bool {
        self.0.is_empty()
    }
    /// Power of `name` (0 when absent).
    pub fn power(&self, name: &str) -> i32 {
        self.0.iter().find(|(s, _)| s == name).map_or(0, |(_, p)| *p)
    }
    /// The monomial with the power of `name` set to `power`.
    pub fn with(&self, name: &str, power: i32) -> Mono {
        let mut v: Vec<(String, i32)> = self.0.iter().filter(|(s, _)| s != name).cloned().collect();
        if power != 0 {
            v.push((name.to_string(), power));
            v.sort();
        }
        Mono(v)
    }
    pub fn mul(&self, o: &Mono) -> Mono {
        let mut m: BTreeMap<&str, i32> = BTreeMap::new();
        for (s, p) in self.0.iter().chain(o.0.iter()) {
            *m.entry(s.as_str()).or_insert(0) += p;
        }
        Mono(m.into_iter().filter(|(_, p)| *p != 0).map(|(s, p)| (s.to_string(), p)).collect())
    }
    pub fn pow(&self, n: i32) -> Mono {
        Mono(self.0.iter().filter(|_| n != 0).map(|(s, p)| (s.clone(), p * n)).collect())
    }
    /// Keep only the symbols for which `keep` is true.
    pub fn filter(&self, keep: impl Fn(&str) -> bool) -> Mono {
        Mono(self.0.iter().filter(|(s, _)| keep(s)).cloned().collect())
    }
    /// Human-readable text, e.g. `mu0*chi_s*H2^2*R0^2/(a^2*R^2)` (without coefficient).
    pub fn text(&self) -> String {
        let part = |v: Vec<String>| v.join("*");
        let fmt = |(s, p): &(String, i32)| if p.abs() == 1 { s.clone() } else { format!("{s}^{}", p.abs()) };
        let num: Vec<String> = self.0.iter().filter(|(_, p)| *p > 0).map(fmt).collect();
        let den: Vec<String> = self.0.iter().filter(|(_, p)| *p < 0).map(fmt).collect();
        let n = if num.is_empty() { "1".to_string() } else { part(num) };
        match den.len() {
            0 => n,
            1 => format!("{n}/{}", den[0]),
            _ => format!("{n}/({})", part(den)),
        }
    }
}

/// Σ coefficient · monomial, canonical (see module docs), zero coefficients removed.
#[derive(Clone, PartialEq, Eq, Debug, Default)]
pub struct Poly {
    pub terms: BTreeMap<Mono, Rat>,
}

impl Poly {
    pub fn zero() -> Poly {
        Poly::default()
    }
    pub fn constant(c: Rat) -> Poly {
        Poly::term(Mono::one(), c)
    }
    pub fn var(name: &str) -> Poly {
        Poly::term(Mono::var(name, 1), rat(1))
    }
    pub fn term(m: Mono, c: Rat) -> Poly {
        let mut p = Poly::zero();
        p.add_term(m, c);
        p.normalize()
    }
    pub fn is_zero(&self) -> bool {
        self.terms.is_empty()
    }
    /// The single term, if the polynomial is one monomial.
    pub fn single(&self) -> Option<(&Mono, &Rat)> {
        if self.terms.len() == 1 {
            self.terms.iter().next()
        } else {
            None
        }
    }
    fn add_term(&mut self, m: Mono, c: Rat) {
        if c.is_zero() {
            return;
        }
        let e = self.terms.entry(m).or_insert_with(Rat::zero);
        *e += c;
        if e.is_zero() {
            self.terms.retain(|_, v| !v.is_zero());
        }
    }
    pub fn add(&self, o: &Poly) -> Poly {
        let mut r = self.clone();
        for (m, c) in &o.terms {
            r.add_term(m.clone(), c.clone());
        }
        r
    }
    pub fn sub(&self, o: &Poly) -> Poly {
        self.add(&o.neg())
    }
    pub fn neg(&self) -> Poly {
        self.scale(&rat(-1))
    }
    pub fn scale(&self, k: &Rat) -> Poly {
        if k.is_zero() {
            return Poly::zero();
        }
        Poly { terms: self.terms.iter().map(|(m, c)| (m.clone(), c * k)).collect() }
    }
    pub fn mul_mono(&self, m: &Mono, c: &Rat) -> Poly {
        let mut r = Poly::zero();
        for (tm, tc) in &self.terms {
            let p = tm.mul(m);
            if p.power(VIRTUAL) < 2 {
                r.add_term(p, tc * c);
            }
        }
        r.normalize()
    }
    pub fn mul(&self, o: &Poly) -> Poly {
        let mut r = Poly::zero();
        for (m1, c1) in &self.terms {
            for (m2, c2) in &o.terms {
                let m = m1.mul(m2);
                // first order in the virtual variation of `vary`
                if m.power(VIRTUAL) < 2 {
                    r.add_term(m, c1 * c2);
                }
            }
        }
        r.normalize()
    }
    pub fn powi(&self, n: u32) -> Poly {
        let mut r = Poly::constant(rat(1));
        for _ in 0..n {
            r = r.mul(self);
        }
        r
    }
    /// ∂/∂name.
    pub fn diff(&self, name: &str) -> Poly {
        let mut r = Poly::zero();
        for (m, c) in &self.terms {
            let p = m.power(name);
            if p != 0 {
                r.add_term(m.with(name, p - 1), c * rat(p as i64));
            }
        }
        r.normalize()
    }
    /// Does any term contain `name`?
    pub fn has(&self, name: &str) -> bool {
        self.terms.keys().any(|m| m.power(name) != 0)
    }
    /// Rewrite c^e (e ≥ 2) as c^(e mod 2) (1 − s²)^(e div 2) for every trigonometric pair.
    pub fn normalize(mut self) -> Poly {
        for (c, s) in TRIG_PAIRS {
            if !self.terms.keys().any(|m| m.power(c) >= 2) {
                continue;
            }
            let mut r = Poly::zero();
            for (m, coef) in std::mem::take(&mut self.terms) {
                let e = m.power(c);
                if e < 2 {
                    r.add_term(m, coef);
                    continue;
                }
                let q = e / 2;
                let base = m.with(c, e % 2);
                let s0 = m.power(s);
                // (1 − s²)^q = Σ_i C(q,i) (−1)^i s^(2i)
                let mut binom = Rat::one();
                for i in 0..=q {
                    let sign = if i % 2 == 0 { rat(1) } else { rat(-1) };
                    r.add_term(base.with(s, s0 + 2 * i), &coef * &binom * sign);
                    binom = binom * rat((q - i) as i64) / rat((i + 1) as i64);
                }
            }
            self = r;
        }
        self
    }
}

impl Poly {
    /// (p0, p1) with self = p0 + #v·p1 (first order in the virtual variation).
    pub fn split_virtual(&self) -> (Poly, Poly) {
        let mut p0 = Poly::zero();
        let mut p1 = Poly::zero();
        for (m, c) in &self.terms {
            match m.power(VIRTUAL) {
                0 => p0.add_term(m.clone(), c.clone()),
                _ => p1.add_term(m.with(VIRTUAL, 0), c.clone()),
            }
        }
        (p0, p1)
    }
}
