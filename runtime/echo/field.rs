//! The scattered pressure p_s = p − p∞ at a point (r, θ) of the liquid (docs/model.md, "Echo"):
//!
//! * far field (eq E2): p_s = ρ V̈(t_e) / (4π r), t_e = t − (r − R0)/c with Keller–Miksis
//!   (t_e = t in an incompressible liquid);
//! * near field (eq E3), the unsteady Bernoulli equation p_s = −ρ (∂φ/∂t + ½|∇φ|²) with
//!   φ = −Q/r − Σ_k C_k r^{−(k+1)} P_k(cos θ), Q = V̇/(4π) (the exact volume flux) and
//!   C_k = R^{k+2} (ȧ_k + 2Ṙ a_k/R)/(k+1) (the linear kinematic condition of mode k).
//!
//! Everything in SI; the state's accelerations come from the model's right-hand side.

use super::volume::{legendre_all, VolumeRule};
use std::f64::consts::PI;

/// One instant of the bubble in SI: (R, Ṙ, R̈) and per order (a_k, ȧ_k, ä_k).
#[derive(Debug, Clone)]
pub struct Kinematics {
    pub r: [f64; 3],
    pub a: Vec<[f64; 3]>,
}

/// The far- and near-field formulas for fixed orders and liquid density.
#[derive(Debug, Clone)]
pub struct Field {
    pub rho: f64,
    pub orders: Vec<usize>,
    rule: VolumeRule,
}

impl Field {
    pub fn new(rho: f64, orders: &[usize]) -> Field {
        Field { rho, orders: orders.to_vec(), rule: VolumeRule::new(orders) }
    }

    /// (V, V̇, V̈) of the instant (eq E1).
    pub fn volume(&self, k: &Kinematics) -> (f64, f64, f64) {
        self.rule.rates(k.r, &k.a)
    }

    /// ρ V̈ / (4π r) (eq E2; the caller evaluates it at the retarded time).
    pub fn far(&self, k: &Kinematics, r: f64) -> f64 {
        self.far_of(self.volume(k).2, r)
    }

    /// ρ V̈ / (4π r) for a given V̈.
    pub fn far_of(&self, vdd: f64, r: f64) -> f64 {
        self.rho * vdd / (4.0 * PI * r)
    }

    /// The spherical part of [`Field::far`], ρ (R²R̈ + 2RṘ²)/r: what the shape modes add is the
    /// difference.
    pub fn far_spherical(&self, k: &Kinematics, r: f64) -> f64 {
        let [x, v, acc] = k.r;
        self.rho * (x * x * acc + 2.0 * x * v * v) / r
    }

    /// −ρ (∂φ/∂t + ½|∇φ|²) at (r, θ) (eq E3).
    pub fn near(&self, k: &Kinematics, r: f64, theta: f64) -> f64 {
        let (_, dv, ddv) = self.volume(k);
        let (q, dq) = (dv / (4.0 * PI), ddv / (4.0 * PI));
        let [big_r, rd, rdd] = k.r;
        let x = theta.cos();
        let kmax = self.orders.iter().copied().max().unwrap_or(0);
        let (p, dp) = legendre_with_derivative(kmax, x);
        let mut phi_t = -dq / r;
        let mut phi_r = q / (r * r);
        let mut phi_theta = 0.0; // (1/r) ∂φ/∂θ
        for (&order, &[a, ad, add]) in self.orders.iter().zip(&k.a) {
            let kf = order as f64;
            let g = ad + 2.0 * rd * a / big_r;
            let dg = add + 2.0 * rdd * a / big_r + 2.0 * rd * ad / big_r - 2.0 * rd * rd * a / (big_r * big_r);
            let c = big_r.powf(kf + 2.0) * g / (kf + 1.0);
            let dc = ((kf + 2.0) * big_r.powf(kf + 1.0) * rd * g + big_r.powf(kf + 2.0) * dg) / (kf + 1.0);
            let rk1 = r.powf(-(kf + 1.0));
            phi_t -= dc * rk1 * p[order];
            phi_r += (kf + 1.0) * c * rk1 / r * p[order];
            // ∂P_k(cos θ)/∂θ = −sin θ P_k'(x); φ_k = −C r^{−(k+1)} P_k
            phi_theta += c * rk1 / r * theta.sin() * dp[order];
        }
        -self.rho * (phi_t + 0.5 * (phi_r * phi_r + phi_theta * phi_theta))
    }
}

/// (P_k(x), P_k'(x)) for k = 0..=kmax.
fn legendre_with_derivative(kmax: usize, x: f64) -> (Vec<f64>, Vec<f64>) {
    let p = legendre_all(kmax, x);
    let mut dp = vec![0.0; kmax + 1];
    // P_k' = k P_{k−1} + x P_{k−1}'
    for k in 1..=kmax {
        dp[k] = k as f64 * p[k - 1] + x * dp[k - 1];
    }
    (p, dp)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sphere: the near field is ρ(R²R̈ + 2RṘ²)/r − ρR⁴Ṙ²/(2r⁴), the far field its first term.
    #[test]
    fn sphere_near_and_far() {
        let f = Field::new(1000.0, &[2]);
        let k = Kinematics { r: [1e-5, 2.0, -3e6], a: vec![[0.0; 3]] };
        let r = 3e-5;
        let far = 1000.0 * (1e-10 * -3e6 + 2.0 * 1e-5 * 4.0) / r;
        assert!((f.far(&k, r) - far).abs() < 1e-12 * far.abs());
        let near = far - 0.5 * 1000.0 * (1e-10 * 2.0f64).powi(2) / r.powi(4);
        assert!((f.near(&k, r, 0.7) - near).abs() < 1e-12 * near.abs());
    }
}
