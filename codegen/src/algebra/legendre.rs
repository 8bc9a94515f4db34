//! Legendre series Σ c_m P_m(x), exact. Products with x use the three-term recurrence
//! x P_m = ((m+1) P_{m+1} + m P_{m−1})/(2m+1), so a low-degree polynomial times P_k (or one of
//! its derivatives) costs O(degree · k) and two high-degree polynomials are never multiplied.

use super::{rat, Rat};
use num_traits::Zero;
use std::collections::HashMap;

/// Coefficients of P_0, P_1, … (trailing zeros trimmed).
pub type Series = Vec<Rat>;

pub fn trim(mut s: Series) -> Series {
    while s.last().is_some_and(|c| c.is_zero()) {
        s.pop();
    }
    s
}

/// x · S.
pub fn mul_x(s: &[Rat]) -> Series {
    let mut out = vec![Rat::zero(); s.len() + 1];
    for (m, c) in s.iter().enumerate() {
        if c.is_zero() {
            continue;
        }
        let den = rat(2 * m as i64 + 1);
        out[m + 1] += c * rat(m as i64 + 1) / &den;
        if m >= 1 {
            out[m - 1] += c * rat(m as i64) / &den;
        }
    }
    trim(out)
}

/// d/dx S, using P_m' = Σ_{l = m−1, m−3, …} (2l+1) P_l.
pub fn derivative(s: &[Rat]) -> Series {
    if s.len() <= 1 {
        return Vec::new();
    }
    let mut out = vec![Rat::zero(); s.len() - 1];
    let mut acc = [Rat::zero(), Rat::zero()];
    for l in (0..s.len() - 1).rev() {
        acc[(l + 1) % 2] += &s[l + 1];
        out[l] = &acc[(l + 1) % 2] * rat(2 * l as i64 + 1);
    }
    trim(out)
}

/// p(x) · S for a dense polynomial p (coefficients of x^0, x^1, …), by Horner.
pub fn poly_times(p: &[Rat], s: &[Rat]) -> Series {
    let mut out: Series = Vec::new();
    for c in p.iter().rev() {
        out = mul_x(&out);
        if !c.is_zero() {
            add_scaled(&mut out, s, c);
        }
    }
    trim(out)
}

/// out += c · s.
pub fn add_scaled(out: &mut Series, s: &[Rat], c: &Rat) {
    if out.len() < s.len() {
        out.resize(s.len(), Rat::zero());
    }
    for (o, v) in out.iter_mut().zip(s) {
        *o += v * c;
    }
}

/// Solve (1 − x²) G = N exactly. Fails when N is not divisible by 1 − x².
pub fn div_one_minus_x2(n: &[Rat]) -> Result<Series, String> {
    let n = trim(n.to_vec());
    if n.is_empty() {
        return Ok(Vec::new());
    }
    if n.len() < 3 {
        return Err("load has a factor 1/sin²Θ that does not cancel".into());
    }
    // (1 − x²) P_m = α_m P_{m+2} + β_m P_m + γ_m P_{m−2}
    let a = |m: i64| rat(m + 1) / rat(2 * m + 1);
    let b = |m: i64| if m <= 0 { Rat::zero() } else { rat(m) / rat(2 * m + 1) };
    let alpha = |m: i64| -(a(m) * a(m + 1));
    let beta = |m: i64| rat(1) - a(m) * b(m + 1) - if m >= 1 { b(m) * a(m - 1) } else { Rat::zero() };
    let gamma = |m: i64| -(b(m) * if m >= 1 { b(m - 1) } else { Rat::zero() });
    let top = n.len() - 1;
    let mut g = vec![Rat::zero(); top - 1];
    let get = |g: &Vec<Rat>, m: usize| g.get(m).cloned().unwrap_or_else(Rat::zero);
    for j in (2..=top).rev() {
        let jj = j as i64;
        let r = &n[j] - beta(jj) * get(&g, j) - gamma(jj + 2) * get(&g, j + 2);
        g[j - 2] = r / alpha(jj - 2);
    }
    for j in 0..2usize.min(n.len()) {
        let jj = j as i64;
        let r = &n[j] - beta(jj) * get(&g, j) - gamma(jj + 2) * get(&g, j + 2);
        if !r.is_zero() {
            return Err("load has a factor 1/sin²Θ that does not cancel".into());
        }
    }
    Ok(trim(g))
}

/// Tangential projection of T = sinΘ · G onto P^1_j = dP_j/dΘ, weight 2j(j+1)/(2j+1):
/// t_j = g_{j+1}/(2j+3) − g_{j−1}/(2j−1) (from (1−x²)P_j' = j(j+1)(P_{j−1} − P_{j+1})/(2j+1)).
pub fn tangential_coefficients(g: &[Rat]) -> Series {
    let get = |m: usize| g.get(m).cloned().unwrap_or_else(Rat::zero);
    let mut out = vec![Rat::zero(); g.len() + 2];
    for (j, o) in out.iter_mut().enumerate().skip(1) {
        let mut v = get(j + 1) / rat(2 * j as i64 + 3);
        v -= get(j - 1) / rat(2 * j as i64 - 1);
        *o = v;
    }
    trim(out)
}

/// Cache of the Legendre series of P_k^(i)(x).
#[derive(Default)]
pub struct Basis {
    cache: HashMap<(usize, u32), Series>,
}

impl Basis {
    pub fn get(&mut self, k: usize, i: u32) -> &Series {
        if !self.cache.contains_key(&(k, i)) {
            let s = if i == 0 {
                let mut v = vec![Rat::zero(); k + 1];
                v[k] = rat(1);
                v
            } else {
                derivative(&self.get(k, i - 1).clone())
            };
            self.cache.insert((k, i), s);
        }
        &self.cache[&(k, i)]
    }
    /// Forget the series of mode k (memory stays small for large KMAX).
    pub fn forget(&mut self, k: usize) {
        self.cache.retain(|(kk, _), _| *kk != k);
    }
}

/// Dense monomial coefficients of P_k(x) (for tests and the membrane cross-check).
pub fn legendre_poly(k: usize) -> Vec<Rat> {
    let mut p0 = vec![rat(1)];
    if k == 0 {
        return p0;
    }
    let mut p1 = vec![Rat::zero(), rat(1)];
    for n in 1..k {
        // (n+1) P_{n+1} = (2n+1) x P_n − n P_{n−1}
        let mut next = vec![Rat::zero(); n + 2];
        for (i, c) in p1.iter().enumerate() {
            next[i + 1] += c * rat(2 * n as i64 + 1);
        }
        for (i, c) in p0.iter().enumerate() {
            next[i] -= c * rat(n as i64);
        }
        for c in next.iter_mut() {
            *c /= rat(n as i64 + 1);
        }
        p0 = p1;
        p1 = next;
    }
    p1
}
