//! Triple products of Legendre functions, exact (second-order mode coupling, issue 12).
//!
//! x = cos θ, P^1_n = dP_n/dθ (Condon–Shortley, docs/model.md §1), L_n = n(n+1):
//!
//! * ∫_{−1}^{1} P_l P_m P_j dx from the Adams–Neumann linearization
//!   P_l P_m = Σ_r [A_{l−r} A_r A_{m−r} / A_{l+m−r}] (2l+2m−4r+1)/(2l+2m−2r+1) P_{l+m−2r},
//!   A_r = (2r−1)!!/r!, with j = l+m−2r (so the integral is 2/(2j+1) times that coefficient);
//! * ∫ P^1_l P^1_m P_j dx = ½(L_l + L_m − L_j) ∫ P_l P_m P_j dx (∇P_l·∇P_m on the sphere, by
//!   2∇f·∇g = Δ(fg) − fΔg − gΔf and ΔP_n = −L_n P_n);
//! * ∫ P_l P^1_m P^1_j dx = ½(L_m + L_j − L_l) ∫ P_l P_m P_j dx (the same identity, roles swapped).
//!
//! Selection rules: nonzero only if |l − m| ≤ j ≤ l + m and l + m + j is even (for the even-mode
//! set every index is even). The identities are checked against exact products of dense
//! polynomials and against Gauss–Legendre quadrature (tests/suite/codegen_quadratic.rs).

use super::{rat, Rat};
use num_traits::Zero;

/// Is (l, m, j) allowed by the selection rules?
pub fn allowed(l: usize, m: usize, j: usize) -> bool {
    let (l, m, j) = (l as i64, m as i64, j as i64);
    (l - m).abs() <= j && j <= l + m && (l + m + j) % 2 == 0
}

/// A_r = (2r−1)!!/r! for r = 0..n (A_0 = 1).
pub fn adams(n: usize) -> Vec<Rat> {
    let mut a = vec![rat(1)];
    for r in 1..=n {
        let next = &a[r - 1] * rat(2 * r as i64 - 1) / rat(r as i64);
        a.push(next);
    }
    a
}

/// Exact triple integrals for all indices up to `nmax` (A_r cached once).
#[derive(Clone, Debug)]
pub struct Triple {
    a: Vec<Rat>,
}

impl Triple {
    /// Integrals with l, m, j ≤ nmax.
    pub fn new(nmax: usize) -> Triple {
        Triple { a: adams(2 * nmax + 2) }
    }

    /// Coefficient of P_j in P_l P_m (0 when not allowed).
    pub fn product_coefficient(&self, l: usize, m: usize, j: usize) -> Rat {
        if !allowed(l, m, j) {
            return Rat::zero();
        }
        let r = (l + m - j) / 2;
        let a = &self.a;
        let n = (2 * (l + m) - 4 * r + 1) as i64;
        let d = (2 * (l + m) - 2 * r + 1) as i64;
        &a[l - r] * &a[r] * &a[m - r] / &a[l + m - r] * rat(n) / rat(d)
    }

    /// ∫_{−1}^{1} P_l P_m P_j dx.
    pub fn ppp(&self, l: usize, m: usize, j: usize) -> Rat {
        self.product_coefficient(l, m, j) * rat(2) / rat(2 * j as i64 + 1)
    }

    /// ∫_{−1}^{1} P^1_l P^1_m P_j dx = ½(L_l + L_m − L_j) ∫ P_l P_m P_j dx.
    pub fn p1p1p(&self, l: usize, m: usize, j: usize) -> Rat {
        let c = casimir(l) + casimir(m) - casimir(j);
        self.ppp(l, m, j) * rat(c) / rat(2)
    }

    /// ∫_{−1}^{1} P_l P^1_m P^1_j dx = ½(L_m + L_j − L_l) ∫ P_l P_m P_j dx.
    pub fn pp1p1(&self, l: usize, m: usize, j: usize) -> Rat {
        let c = casimir(m) + casimir(j) - casimir(l);
        self.ppp(l, m, j) * rat(c) / rat(2)
    }
}

/// L_n = n(n+1).
pub fn casimir(n: usize) -> i64 {
    (n * (n + 1)) as i64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::legendre::legendre_poly;
    use crate::algebra::rat_f64;

    /// Gauss–Legendre nodes and weights (Newton on P_n), f64: an independent quadrature.
    fn gauss(n: usize) -> Vec<(f64, f64)> {
        (0..n)
            .map(|i| {
                let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
                let mut dp = 0.0;
                for _ in 0..100 {
                    let (p, d) = legendre_f64(n, x);
                    dp = d;
                    let dx = p / d;
                    x -= dx;
                    if dx.abs() < 1e-16 {
                        break;
                    }
                }
                (x, 2.0 / ((1.0 - x * x) * dp * dp))
            })
            .collect()
    }

    /// (P_n(x), P_n'(x)) by the three-term recurrence.
    fn legendre_f64(n: usize, x: f64) -> (f64, f64) {
        let (mut p0, mut p1) = (1.0, x);
        if n == 0 {
            return (1.0, 0.0);
        }
        for k in 1..n {
            let p2 = ((2 * k + 1) as f64 * x * p1 - k as f64 * p0) / (k + 1) as f64;
            p0 = p1;
            p1 = p2;
        }
        (p1, n as f64 * (x * p1 - p0) / (x * x - 1.0))
    }

    /// P^1_n(cos θ) = −sin θ P_n'(x).
    fn p1_f64(n: usize, x: f64) -> f64 {
        -(1.0 - x * x).sqrt() * legendre_f64(n, x).1
    }

    #[test]
    fn triple_integrals_match_gauss_quadrature() {
        let t = Triple::new(32);
        let g = gauss(64);
        let mut worst: f64 = 0.0;
        for l in 0..=20 {
            for m in 0..=20 {
                for j in 0..=40 {
                    let q = |f: &dyn Fn(f64) -> f64| g.iter().map(|(x, w)| w * f(*x)).sum::<f64>();
                    let p = |n: usize, x: f64| legendre_f64(n, x).0;
                    let ppp = q(&|x| p(l, x) * p(m, x) * p(j, x));
                    let p1p1p = q(&|x| p1_f64(l, x) * p1_f64(m, x) * p(j, x));
                    let pp1p1 = q(&|x| p(l, x) * p1_f64(m, x) * p1_f64(j, x));
                    let scale = 1.0 + (casimir(l) + casimir(m) + casimir(j)) as f64;
                    for (exact, num) in [(t.ppp(l, m, j), ppp), (t.p1p1p(l, m, j), p1p1p), (t.pp1p1(l, m, j), pp1p1)] {
                        let e = rat_f64(&exact);
                        worst = worst.max((e - num).abs() / scale);
                        if !allowed(l, m, j) {
                            assert_eq!(e, 0.0);
                        }
                    }
                }
            }
        }
        assert!(worst < 1e-13, "worst scaled difference {worst:e}");
    }

    /// The exact identities against exact dense-polynomial products (no Adams formula).
    #[test]
    fn triple_integrals_match_exact_polynomial_products() {
        let t = Triple::new(12);
        let mul = |a: &[Rat], b: &[Rat]| {
            let mut out = vec![Rat::zero(); a.len() + b.len() - 1];
            for (i, x) in a.iter().enumerate() {
                for (k, y) in b.iter().enumerate() {
                    out[i + k] += x * y;
                }
            }
            out
        };
        let int = |p: &[Rat]| p.iter().enumerate().filter(|(i, _)| i % 2 == 0).map(|(i, c)| c * rat(2) / rat(i as i64 + 1)).fold(Rat::zero(), |a, b| a + b);
        let deriv = |p: &[Rat]| if p.len() < 2 { vec![Rat::zero()] } else { p.iter().enumerate().skip(1).map(|(i, c)| c * rat(i as i64)).collect::<Vec<_>>() };
        let one_minus_x2 = [rat(1), Rat::zero(), rat(-1)];
        for l in 0..=8 {
            for m in 0..=8 {
                for j in 0..=16 {
                    let (pl, pm, pj) = (legendre_poly(l), legendre_poly(m), legendre_poly(j));
                    assert_eq!(int(&mul(&mul(&pl, &pm), &pj)), t.ppp(l, m, j), "ppp {l} {m} {j}");
                    // P^1_l P^1_m = (1 − x²) P_l' P_m'
                    let d = mul(&mul(&deriv(&pl), &deriv(&pm)), &one_minus_x2);
                    assert_eq!(int(&mul(&d, &pj)), t.p1p1p(l, m, j), "p1p1p {l} {m} {j}");
                    let d = mul(&mul(&deriv(&pm), &deriv(&pj)), &one_minus_x2);
                    assert_eq!(int(&mul(&d, &pl)), t.pp1p1(l, m, j), "pp1p1 {l} {m} {j}");
                }
            }
        }
    }
}
