//! The exact volume of the represented surface r_s(θ, t) = R + Σ_k a_k P_k(cos θ) and its first
//! two time derivatives (docs/model.md, "Echo", eq E1):
//!
//! V = (2π/3) ∫_{−1}^{1} r_s³ dx,  V̇ = 2π ∫ r_s² ṙ_s dx,  V̈ = 2π ∫ (2 r_s ṙ_s² + r_s² r̈_s) dx,
//!
//! x = cos θ. The integrands are polynomials in x of degree ≤ 3N (N the largest order), so an
//! n-point Gauss–Legendre rule with 2n − 1 ≥ 3N integrates them exactly (to round-off): the a_k²
//! (and a_k³) terms through which the shape modes reach the far field are all kept.

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton on P_n from the Chebyshev guess).
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let (mut x, mut w) = (vec![0.0; n], vec![0.0; n]);
    for i in 0..n {
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        for _ in 0..100 {
            let (p, dp) = legendre_and_derivative(n, z);
            let dz = p / dp;
            z -= dz;
            if dz.abs() < 1e-16 {
                break;
            }
        }
        let (_, dp) = legendre_and_derivative(n, z);
        x[i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
    (x, w)
}

/// (P_n(x), P_n'(x)) by the three-term recurrence.
fn legendre_and_derivative(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
        p0 = p1;
        p1 = p2;
    }
    (p1, n as f64 * (x * p1 - p0) / (x * x - 1.0))
}

/// P_k(x) for k = 0..=kmax.
pub fn legendre_all(kmax: usize, x: f64) -> Vec<f64> {
    let mut p = vec![1.0; kmax + 1];
    if kmax >= 1 {
        p[1] = x;
    }
    for k in 2..=kmax {
        p[k] = ((2 * k - 1) as f64 * x * p[k - 1] - (k - 1) as f64 * p[k - 2]) / k as f64;
    }
    p
}

/// The quadrature of eq E1 for fixed orders.
#[derive(Debug, Clone)]
pub struct VolumeRule {
    w: Vec<f64>,
    /// P_k(x_i) per node, per order (row i: the orders in the model's order)
    p: Vec<Vec<f64>>,
}

/// (V, V̇, V̈).
pub type VolumeRates = (f64, f64, f64);

impl VolumeRule {
    pub fn new(orders: &[usize]) -> VolumeRule {
        let n_max = orders.iter().copied().max().unwrap_or(0);
        let n = (3 * n_max + 2) / 2 + 1;
        let (x, w) = gauss_legendre(n.max(2));
        let p = x.iter().map(|&xi| {
            let all = legendre_all(n_max, xi);
            orders.iter().map(|&k| all[k]).collect()
        }).collect();
        VolumeRule { w, p }
    }

    /// V, V̇, V̈ from (R, Ṙ, R̈) and per order (a_k, ȧ_k, ä_k).
    pub fn rates(&self, r: [f64; 3], a: &[[f64; 3]]) -> VolumeRates {
        use std::f64::consts::PI;
        let (mut v, mut dv, mut ddv) = (0.0, 0.0, 0.0);
        for (w, p) in self.w.iter().zip(&self.p) {
            let (mut s, mut ds, mut dds) = (r[0], r[1], r[2]);
            for (pk, ak) in p.iter().zip(a) {
                s += ak[0] * pk;
                ds += ak[1] * pk;
                dds += ak[2] * pk;
            }
            v += w * s * s * s;
            dv += w * s * s * ds;
            ddv += w * (2.0 * s * ds * ds + s * s * dds);
        }
        (2.0 * PI / 3.0 * v, 2.0 * PI * dv, 2.0 * PI * ddv)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_is_exact_to_its_degree() {
        let (x, w) = gauss_legendre(7);
        for d in 0..=13 {
            let q: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(d)).sum();
            let exact = if d % 2 == 1 { 0.0 } else { 2.0 / (d as f64 + 1.0) };
            assert!((q - exact).abs() < 1e-14, "x^{d}: {q} vs {exact}");
        }
    }

    /// A sphere: V = 4πR³/3, V̈ = 4π(R²R̈ + 2RṘ²).
    #[test]
    fn sphere() {
        let rule = VolumeRule::new(&[2, 4]);
        let (v, dv, ddv) = rule.rates([1.3, 0.4, -2.0], &[[0.0; 3], [0.0; 3]]);
        let pi = std::f64::consts::PI;
        assert!((v - 4.0 * pi / 3.0 * 1.3f64.powi(3)).abs() < 1e-13);
        assert!((dv - 4.0 * pi * 1.69 * 0.4).abs() < 1e-13);
        assert!((ddv - 4.0 * pi * (1.69 * -2.0 + 2.0 * 1.3 * 0.16)).abs() < 1e-13);
    }
}
