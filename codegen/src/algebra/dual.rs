//! First-order (dual) numbers z + ε e with polynomial parts: the linearization in the mode
//! amplitudes a_k, b_k. The first-order part carries the amplitude symbols `#a`/`#b`, so
//! ε² terms are dropped by construction (ε e · ε e' is never formed).

use super::poly::{Mono, Poly, VIRTUAL};
use super::{rat, Rat};
use num_traits::Signed;
use std::collections::BTreeMap;

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Dual {
    /// Zero-order part (the sphere).
    pub z: Poly,
    /// First-order part (linear in the amplitudes).
    pub e: Poly,
}

impl Dual {
    pub fn new(z: Poly, e: Poly) -> Dual {
        Dual { z, e }
    }
    pub fn zero_order(z: Poly) -> Dual {
        Dual { z, e: Poly::zero() }
    }
    pub fn constant(c: Rat) -> Dual {
        Dual::zero_order(Poly::constant(c))
    }
    pub fn add(&self, o: &Dual) -> Dual {
        Dual::new(self.z.add(&o.z), self.e.add(&o.e))
    }
    pub fn sub(&self, o: &Dual) -> Dual {
        Dual::new(self.z.sub(&o.z), self.e.sub(&o.e))
    }
    pub fn neg(&self) -> Dual {
        Dual::new(self.z.neg(), self.e.neg())
    }
    pub fn mul(&self, o: &Dual) -> Dual {
        Dual::new(self.z.mul(&o.z), self.z.mul(&o.e).add(&self.e.mul(&o.z)))
    }
    pub fn scale(&self, k: &Rat) -> Dual {
        Dual::new(self.z.scale(k), self.e.scale(k))
    }
    /// (z + εe)^n = z^n + ε n z^(n−1) e. For n ≤ 0, z must be a single monomial (plus, inside
    /// `vary`, a first-order virtual part #v·z1).
    pub fn powi(&self, n: i32) -> Result<Dual, String> {
        if n == 0 {
            return Ok(Dual::constant(rat(1)));
        }
        let zp = |p: i32| -> Result<Poly, String> {
            if p >= 0 {
                Ok(self.z.powi(p as u32))
            } else {
                self.neg_power(p)
            }
        };
        let zn = zp(n)?;
        let e = if self.e.is_zero() { Poly::zero() } else { zp(n - 1)?.mul(&self.e).scale(&rat(n as i64)) };
        Ok(Dual::new(zn, e))
    }
    /// z^p for p < 0: (m + #v z1)^p = m^p + #v p m^(p−1) z1.
    fn neg_power(&self, p: i32) -> Result<Poly, String> {
        let (z0, z1) = self.z.split_virtual();
        let (m, c) = Dual::zero_order(z0).monomial("raise to a negative power")?;
        let base = Poly::term(m.pow(p), rat_pow(&c, p));
        if z1.is_zero() {
            return Ok(base);
        }
        let prev = Poly::term(m.pow(p - 1), rat_pow(&c, p - 1)).scale(&rat(p as i64));
        Ok(base.add(&prev.mul(&z1).mul(&Poly::var(VIRTUAL))))
    }
    fn monomial(&self, what: &str) -> Result<(Mono, Rat), String> {
        match self.z.single() {
            Some((m, c)) => Ok((m.clone(), c.clone())),
            None if self.z.is_zero() => Err(format!("cannot {what}: its zero-order part is 0")),
            None => Err(format!(
                "cannot {what}: its zero-order part has {} terms (only a single monomial can be inverted)",
                self.z.terms.len()
            )),
        }
    }
    pub fn inv(&self) -> Result<Dual, String> {
        self.powi(-1).map_err(|e| e.replace("raise to a negative power", "divide by it"))
    }
    pub fn div(&self, o: &Dual) -> Result<Dual, String> {
        Ok(self.mul(&o.inv()?))
    }
    /// √(z + εe) = √z + ε e/(2√z); z must be a monomial with even powers and a square coefficient
    /// (plus, inside `vary`, a virtual part: √(m + #v z1) = √m + #v z1/(2√m)).
    pub fn sqrt(&self) -> Result<Dual, String> {
        let (z0, z1) = self.z.split_virtual();
        let (m, c) = Dual::zero_order(z0).monomial("take the square root")?;
        let bad = || format!("cannot take the square root of `{}`: not an exact square", m.text());
        if m.0.iter().any(|(_, p)| p % 2 != 0) || c.is_negative() {
            return Err(bad());
        }
        let (n, d) = (c.numer().sqrt(), c.denom().sqrt());
        if &(&n * &n) != c.numer() || &(&d * &d) != c.denom() {
            return Err(bad());
        }
        let root0 = Poly::term(Mono(m.0.iter().map(|(s, p)| (s.clone(), p / 2)).collect()), Rat::new(n, d));
        let half_inv0 = Dual::zero_order(root0.clone()).inv()?.z.scale(&super::ratio(1, 2));
        let root = root0.add(&z1.mul(&half_inv0).mul(&Poly::var(VIRTUAL)));
        let inv2 = Dual::zero_order(root.clone()).inv()?.scale(&super::ratio(1, 2));
        Ok(Dual::new(root, self.e.mul(&inv2.z)))
    }
    /// Time derivative at fixed Θ: R → Ṙ (`Rd`), a_k → ȧ_k (`#ad`), b_k → ḃ_k (`#bd`); every
    /// other symbol is constant. ε-parts stay first order (ȧ, ḃ and Ṙ·a, Ṙ·b).
    pub fn rate(&self) -> Dual {
        let rd = Poly::var(RATE_R);
        let e = self.e.diff("R").mul(&rd).add(&self.e.diff("#a").mul(&Poly::var("#ad"))).add(&self.e.diff("#b").mul(&Poly::var("#bd")));
        Dual::new(self.z.diff("R").mul(&rd), e)
    }
    /// ∂/∂name of both parts (name is a plain symbol).
    pub fn diff(&self, name: &str) -> Dual {
        Dual::new(self.z.diff(name), self.e.diff(name))
    }
    /// d/dΘ along the material meridian: d(cosΘ) = −sinΘ, d(sinΘ) = cosΘ, d P_k^(i)(x) = −sinΘ P_k^(i+1)(x).
    pub fn d_theta(&self) -> Dual {
        Dual::new(d_theta(&self.z), d_theta(&self.e))
    }
    /// Substitute the symbols of `map` by dual values (other symbols stay).
    pub fn subst(&self, map: &BTreeMap<String, Dual>) -> Result<Dual, String> {
        let z = subst_poly(&self.z, map)?;
        let e = subst_poly(&self.e, map)?;
        // the first-order part of self is already first order: keep only the zero order of its image
        Ok(Dual::new(z.z, z.e.add(&e.z)))
    }
}


/// The symbol of Ṙ in loads that depend on rates (emitted as the argument `rd`).
pub const RATE_R: &str = "Rd";

/// Name of the i-th Θ-derivative of the test function of `vary`.
pub fn jet(i: u32) -> String {
    format!("#h{i}")
}

/// Derivative order of a test-function symbol.
pub fn jet_order(name: &str) -> Option<u32> {
    name.strip_prefix("#h").and_then(|d| d.parse().ok())
}

/// Name of the mode-shape marker for the i-th x-derivative of P_k.
pub fn marker(i: u32) -> String {
    format!("#P{i}")
}

/// Derivative order of a marker symbol.
pub fn marker_order(name: &str) -> Option<u32> {
    name.strip_prefix("#P").and_then(|d| d.parse().ok())
}

fn d_theta(p: &Poly) -> Poly {
    let x = Poly::var("#x");
    let s = Poly::var("#s");
    let mut r = p.diff("#x").mul(&s.neg()).add(&p.diff("#s").mul(&x));
    let mut markers: Vec<u32> = p.terms.keys().flat_map(|m| m.0.iter().filter_map(|(n, _)| marker_order(n))).collect();
    markers.sort();
    markers.dedup();
    for i in markers {
        let next = Poly::var(&marker(i + 1)).mul(&s).neg();
        r = r.add(&p.diff(&marker(i)).mul(&next));
    }
    // the test function of `vary`: d η^(i)/dΘ = η^(i+1)
    let mut jets: Vec<u32> = p.terms.keys().flat_map(|m| m.0.iter().filter_map(|(n, _)| jet_order(n))).collect();
    jets.sort();
    jets.dedup();
    for i in jets {
        r = r.add(&p.diff(&jet(i)).mul(&Poly::var(&jet(i + 1))));
    }
    r
}

fn subst_poly(p: &Poly, map: &BTreeMap<String, Dual>) -> Result<Dual, String> {
    let mut out = Dual::default();
    let mut cache: BTreeMap<(String, i32), Dual> = BTreeMap::new();
    for (m, c) in &p.terms {
        let rest = m.filter(|s| !map.contains_key(s));
        let mut t = Dual::zero_order(Poly::term(rest, c.clone()));
        for (s, pw) in &m.0 {
            if let Some(v) = map.get(s) {
                let key = (s.clone(), *pw);
                if !cache.contains_key(&key) {
                    cache.insert(key.clone(), v.powi(*pw)?);
                }
                t = t.mul(&cache[&key]);
            }
        }
        out = out.add(&t);
    }
    Ok(out)
}

/// c^p for any integer p (c ≠ 0 when p < 0).
pub fn rat_pow(c: &Rat, p: i32) -> Rat {
    let mut r = rat(1);
    for _ in 0..p.unsigned_abs() {
        r *= c;
    }
    if p < 0 {
        r = num_traits::Inv::inv(r);
    }
    r
}
