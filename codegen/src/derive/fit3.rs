//! Closed forms in three integer variables (the quadratic coupling of modes l, m on target j):
//! v(l, m, j) = N(l, m, j) for a polynomial N of the smallest total degree that fits every
//! point exactly. Found by Gaussian elimination modulo the prime 2^61 − 1 and rational
//! reconstruction of the coefficients, then verified exactly (rationals) on every point, so a
//! form that is returned is exact on all the data; the caller keeps points back to verify it
//! beyond the fit.

use crate::algebra::Rat;
use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{One, Signed, ToPrimitive, Zero};

const P: u64 = (1 << 61) - 1;

fn mulm(a: u64, b: u64) -> u64 {
    ((a as u128 * b as u128) % P as u128) as u64
}

fn powm(mut a: u64, mut e: u64) -> u64 {
    let mut r = 1;
    while e > 0 {
        if e & 1 == 1 {
            r = mulm(r, a);
        }
        a = mulm(a, a);
        e >>= 1;
    }
    r
}

fn inv(a: u64) -> u64 {
    powm(a, P - 2)
}

fn to_mod(r: &Rat) -> Option<u64> {
    let p = BigInt::from(P);
    let n = r.numer().mod_floor(&p).to_u64()?;
    let d = r.denom().mod_floor(&p).to_u64()?;
    (d != 0).then(|| mulm(n, inv(d)))
}

/// a/b ≡ x (mod P) with |a|, b ≤ √(P/2) (Wang's reconstruction by the extended Euclid).
fn reconstruct(x: u64) -> Option<Rat> {
    let bound = ((P / 2) as f64).sqrt() as i128;
    let (mut r0, mut r1) = (P as i128, x as i128);
    let (mut t0, mut t1) = (0i128, 1i128);
    while r1 > bound {
        let q = r0 / r1;
        (r0, r1) = (r1, r0 - q * r1);
        (t0, t1) = (t1, t0 - q * t1);
    }
    if t1 == 0 || t1.abs() > bound {
        return None;
    }
    Some(Rat::new(BigInt::from(r1), BigInt::from(t1)))
}

/// Exponents (a, b, c) of l^a m^b j^c with a + b + c ≤ deg, in a fixed order.
pub fn monomials(deg: u32) -> Vec<[u32; 3]> {
    let mut v = Vec::new();
    for t in 0..=deg {
        for a in (0..=t).rev() {
            for b in (0..=t - a).rev() {
                v.push([a, b, t - a - b]);
            }
        }
    }
    v
}

/// A polynomial in (l, m, j) with exact coefficients.
#[derive(Clone, Debug, PartialEq)]
pub struct Poly3 {
    pub terms: Vec<([u32; 3], Rat)>,
}

impl Poly3 {
    pub fn eval(&self, x: [i64; 3]) -> Rat {
        let mut s = Rat::zero();
        for (e, c) in &self.terms {
            let mut v = c.clone();
            for (xi, ei) in x.iter().zip(e) {
                v *= Rat::from_integer(BigInt::from(*xi).pow(*ei));
            }
            s += v;
        }
        s
    }
    pub fn eval_f64(&self, x: [f64; 3]) -> f64 {
        self.terms.iter().map(|(e, c)| crate::algebra::rat_f64(c) * x[0].powi(e[0] as i32) * x[1].powi(e[1] as i32) * x[2].powi(e[2] as i32)).sum()
    }
    /// e.g. `2*l^2 + 2*m^2 - 4` (vars l, m, j).
    pub fn text(&self) -> String {
        if self.terms.is_empty() {
            return "0".into();
        }
        let mut s = String::new();
        for (i, (e, c)) in self.terms.iter().enumerate() {
            let neg = c.is_negative();
            let a = c.abs();
            let mut factors: Vec<String> = Vec::new();
            let coef = crate::algebra::rat_text(&a);
            let unit = a.is_one();
            for (name, p) in ["l", "m", "j"].iter().zip(e) {
                match p {
                    0 => {}
                    1 => factors.push(name.to_string()),
                    _ => factors.push(format!("{name}^{p}")),
                }
            }
            let body = match (unit, factors.is_empty()) {
                (true, true) => "1".to_string(),
                (true, false) => factors.join("*"),
                (false, true) => coef,
                (false, false) => format!("{coef}*{}", factors.join("*")),
            };
            s += &match (i, neg) {
                (0, false) => body,
                (0, true) => format!("-{body}"),
                (_, false) => format!(" + {body}"),
                (_, true) => format!(" - {body}"),
            };
        }
        s
    }
}

/// The exact polynomial of smallest total degree ≤ `max_deg` through every point, if any.
pub fn fit_poly3(points: &[([i64; 3], Rat)], max_deg: u32) -> Option<Poly3> {
    fit_poly3_in(points, max_deg, [true; 3])
}

/// [`fit_poly3`] with only the variables marked in `vars` (e.g. l alone for data on l = m, j = 0).
pub fn fit_poly3_in(points: &[([i64; 3], Rat)], max_deg: u32, vars: [bool; 3]) -> Option<Poly3> {
    if points.iter().all(|(_, v)| v.is_zero()) {
        return Some(Poly3 { terms: Vec::new() });
    }
    let data: Vec<([u64; 3], u64)> = points
        .iter()
        .map(|(x, v)| Some(([x[0].rem_euclid(P as i64) as u64, x[1].rem_euclid(P as i64) as u64, x[2].rem_euclid(P as i64) as u64], to_mod(v)?)))
        .collect::<Option<_>>()?;
    for deg in 0..=max_deg {
        let mons: Vec<[u32; 3]> = monomials(deg).into_iter().filter(|e| (0..3).all(|i| vars[i] || e[i] == 0)).collect();
        let n = mons.len();
        if points.len() < n {
            return None;
        }
        // rows [monomials | value], eliminated mod P
        let mut rows: Vec<Vec<u64>> = data
            .iter()
            .map(|(x, v)| {
                let mut r: Vec<u64> = mons.iter().map(|e| mulm(mulm(powm(x[0], e[0] as u64), powm(x[1], e[1] as u64)), powm(x[2], e[2] as u64))).collect();
                r.push(*v);
                r
            })
            .collect();
        let mut pivots = Vec::new();
        let mut row = 0;
        for col in 0..n {
            let Some(p) = (row..rows.len()).find(|&i| rows[i][col] != 0) else { continue };
            rows.swap(row, p);
            let iv = inv(rows[row][col]);
            for x in rows[row].iter_mut() {
                *x = mulm(*x, iv);
            }
            let pr = rows[row].clone();
            for (i, r) in rows.iter_mut().enumerate() {
                if i != row && r[col] != 0 {
                    let f = r[col];
                    for (x, y) in r.iter_mut().zip(&pr) {
                        *x = (*x + P - mulm(f, *y)) % P;
                    }
                }
            }
            pivots.push(col);
            row += 1;
        }
        let consistent = rows[row..].iter().all(|r| r[n] == 0);
        if !consistent {
            continue;
        }
        if pivots.len() < n {
            // not enough independent points to pin this degree down
            return None;
        }
        let mut terms = Vec::new();
        for (i, &col) in pivots.iter().enumerate() {
            let c = reconstruct(rows[i][n])?;
            if !c.is_zero() {
                terms.push((mons[col], c));
            }
        }
        let p = Poly3 { terms };
        // exact verification on every point
        return points.iter().all(|(x, v)| &p.eval(*x) == v).then_some(p);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::{rat, ratio};

    #[test]
    fn recovers_a_known_polynomial_exactly() {
        let f = |l: i64, m: i64, j: i64| ratio(3 * l * l * m - 7 * j * j * j + 5, 4) + rat(l * m * j);
        let pts: Vec<([i64; 3], Rat)> = (1..6).flat_map(|l| (1..6).flat_map(move |m| (0..6).map(move |j| ([l, m, j], f(l, m, j))))).collect();
        let p = fit_poly3(&pts, 5).expect("fits");
        assert_eq!(p.eval([17, 23, 9]), f(17, 23, 9));
        assert!(p.terms.len() == 4, "{}", p.text());
    }
}
