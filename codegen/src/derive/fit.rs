//! Closed forms found from exact values, then verified on values not used in the fit.
//!
//! Couplings: v(k) = p(k) / (c · Π (2k + c_i)). Candidate factors (2k + c), c odd in −13..=17,
//! are kept when |2k + c| (or its square) divides the reduced denominator of v(k) for most k;
//! subsets of the kept factors are tried by increasing size; for each, D(k)·v(k) on the first
//! points is tested for being a polynomial (Newton divided differences), and the polynomial is
//! then checked exactly on every remaining k.

use crate::algebra::{rat, Rat};
use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{One, Signed, Zero};

/// Candidate constants c of the factors (2k + c).
const CANDIDATES: [i64; 16] = [-13, -11, -9, -7, -5, -3, -1, 1, 3, 5, 7, 9, 11, 13, 15, 17];
/// Largest multiplicity of one factor.
const MAX_MULTIPLICITY: u32 = 2;
/// Points used to find the form; every other point verifies it.
const FIT_POINTS: usize = 14;
/// At least this many points must be left to verify a fit.
const MIN_CHECKS: usize = 3;

/// v(k) = numer(k) / (den_const · Π (2k + c)) for k ≥ k0.
#[derive(Clone, Debug, PartialEq)]
pub struct ClosedForm {
    pub k0: i64,
    /// Integer coefficients of the numerator, ascending powers of k.
    pub numer: Vec<BigInt>,
    pub den_const: BigInt,
    pub den_factors: Vec<i64>,
}

impl ClosedForm {
    pub fn eval(&self, k: i64) -> Rat {
        let kk = BigInt::from(k);
        let mut num = BigInt::zero();
        for c in self.numer.iter().rev() {
            num = num * &kk + c;
        }
        let mut den = self.den_const.clone();
        for c in &self.den_factors {
            den *= BigInt::from(2 * k + c);
        }
        Rat::new(num, den)
    }

    /// e.g. `(-13*k^2 - 13*k + 6)/((2*k - 1)*(2*k + 3))`.
    pub fn text(&self) -> String {
        let num = poly_text(&self.numer, "k");
        let mut den: Vec<String> = Vec::new();
        if !self.den_const.is_one() {
            den.push(self.den_const.to_string());
        }
        for c in &self.den_factors {
            den.push(match c.signum() {
                -1 => format!("(2*k - {})", -c),
                _ => format!("(2*k + {c})"),
            });
        }
        let terms = self.numer.iter().filter(|c| !c.is_zero()).count();
        let num = if terms > 1 && !den.is_empty() { format!("({num})") } else { num };
        let text = match den.len() {
            0 => num,
            1 => format!("{num}/{}", den[0]),
            _ => format!("{num}/({})", den.join("*")),
        };
        if self.k0 > 0 {
            format!("{text}  [k >= {}]", self.k0)
        } else {
            text
        }
    }
}

/// Text of Σ c_i v^i, descending powers.
pub fn poly_text(coeffs: &[BigInt], v: &str) -> String {
    let mut s = String::new();
    for (i, c) in coeffs.iter().enumerate().rev() {
        if c.is_zero() {
            continue;
        }
        let mag = c.abs();
        let body = match (i, mag.is_one()) {
            (0, _) => mag.to_string(),
            (1, true) => v.to_string(),
            (1, false) => format!("{mag}*{v}"),
            (_, true) => format!("{v}^{i}"),
            (_, false) => format!("{mag}*{v}^{i}"),
        };
        if s.is_empty() {
            s = if c.is_negative() { format!("-{body}") } else { body };
        } else {
            s += if c.is_negative() { " - " } else { " + " };
            s += &body;
        }
    }
    if s.is_empty() {
        "0".into()
    } else {
        s
    }
}

/// Newton divided-difference coefficients f[x0], f[x0,x1], ….
fn divided_differences(xs: &[Rat], ys: &[Rat]) -> Vec<Rat> {
    let mut dd = ys.to_vec();
    for l in 1..xs.len() {
        for i in (l..xs.len()).rev() {
            dd[i] = (&dd[i] - &dd[i - 1]) / (&xs[i] - &xs[i - l]);
        }
    }
    dd
}

/// Ascending coefficients of the interpolating polynomial of degree ≤ deg through the first
/// deg + 1 points, if it matches every point.
pub fn fit_poly(xs: &[Rat], ys: &[Rat], max_deg: usize) -> Option<Vec<Rat>> {
    let n = xs.len().min(max_deg + 1 + MIN_CHECKS);
    if n < MIN_CHECKS + 1 {
        return None;
    }
    let dd = divided_differences(&xs[..n], &ys[..n]);
    let deg = dd.iter().rposition(|c| !c.is_zero()).unwrap_or(0);
    if deg + MIN_CHECKS > n - 1 + 1 || deg > max_deg {
        return None;
    }
    // expand the Newton form
    let mut p: Vec<Rat> = vec![dd[deg].clone()];
    for l in (0..deg).rev() {
        let mut next = vec![Rat::zero(); p.len() + 1];
        for (i, c) in p.iter().enumerate() {
            next[i + 1] += c;
            next[i] -= c * &xs[l];
        }
        next[0] += &dd[l];
        p = next;
    }
    let ok = xs.iter().zip(ys).all(|(x, y)| &eval_poly(&p, x) == y);
    ok.then_some(p)
}

pub fn eval_poly(p: &[Rat], x: &Rat) -> Rat {
    p.iter().rev().fold(Rat::zero(), |acc, c| acc * x + c)
}

/// Find and verify a closed form of the exact values `points` (k, v(k)), k consecutive.
pub fn fit_rational(points: &[(i64, Rat)]) -> Option<ClosedForm> {
    for drop in 0..=3 {
        let pts = points.get(drop..)?;
        if pts.len() < FIT_POINTS + MIN_CHECKS {
            return None;
        }
        let xs: Vec<Rat> = pts.iter().map(|(k, _)| rat(*k)).collect();
        let cands = candidate_factors(pts);
        for size in 0..=cands.len() {
            let mut found = None;
            combinations(cands.len(), size, &mut |idx| {
                if found.is_some() {
                    return;
                }
                let factors: Vec<i64> = idx.iter().map(|&i| cands[i]).collect();
                let d = |k: i64| factors.iter().fold(rat(1), |acc, c| acc * rat(2 * k + c));
                let ws: Vec<Rat> = pts[..FIT_POINTS].iter().map(|(k, v)| v * d(*k)).collect();
                let Some(p) = fit_poly(&xs[..FIT_POINTS], &ws, FIT_POINTS - 1 - MIN_CHECKS) else { return };
                if pts.iter().all(|(k, v)| eval_poly(&p, &rat(*k)) == v * d(*k)) {
                    found = Some(normalize(p, factors, pts[0].0, points[0].0));
                }
            });
            if found.is_some() {
                return found;
            }
        }
    }
    None
}

/// Factors (2k + c) whose value f (or f²) divides the reduced denominator of v(k) up to a small
/// cofactor (≤ 32: a numerator can cancel only primes of a fixed integer) for at least 80% of the
/// points with |2k + c| > 32, repeated by multiplicity. A spurious c fails for most k, because
/// |2k + c| then has a prime factor that is not in the denominator.
fn candidate_factors(pts: &[(i64, Rat)]) -> Vec<i64> {
    let mut out = Vec::new();
    for c in CANDIDATES {
        for mult in 1..=MAX_MULTIPLICITY {
            let (mut hits, mut total) = (0, 0);
            for (k, v) in pts {
                let f = (2 * k + c).abs();
                if f <= 32 {
                    continue;
                }
                total += 1;
                let fp = BigInt::from(f).pow(mult);
                let cofactor = &fp / fp.gcd(v.denom());
                if cofactor <= BigInt::from(32) {
                    hits += 1;
                }
            }
            if total > 0 && hits * 5 >= total * 4 {
                out.push(c);
            } else {
                break;
            }
        }
    }
    out
}

fn normalize(p: Vec<Rat>, den_factors: Vec<i64>, first_k: i64, start: i64) -> ClosedForm {
    let lcm = p.iter().fold(BigInt::one(), |acc, c| acc.lcm(c.denom()));
    let mut numer: Vec<BigInt> = p.iter().map(|c| (c * Rat::from_integer(lcm.clone())).to_integer()).collect();
    let g = numer.iter().fold(lcm.clone(), |acc, c| acc.gcd(c));
    for c in numer.iter_mut() {
        *c = &*c / &g;
    }
    while numer.len() > 1 && numer.last().is_some_and(|c| c.is_zero()) {
        numer.pop();
    }
    ClosedForm { k0: if first_k > start { first_k } else { 0 }, numer, den_const: lcm / g, den_factors }
}

/// Call `f` with every increasing index tuple of length `size` from 0..n.
fn combinations(n: usize, size: usize, f: &mut dyn FnMut(&[usize])) {
    fn rec(start: usize, n: usize, left: usize, cur: &mut Vec<usize>, f: &mut dyn FnMut(&[usize])) {
        if left == 0 {
            f(cur);
            return;
        }
        for i in start..n {
            cur.push(i);
            rec(i + 1, n, left - 1, cur, f);
            cur.pop();
        }
    }
    rec(0, n, size, &mut Vec::new(), f);
}
