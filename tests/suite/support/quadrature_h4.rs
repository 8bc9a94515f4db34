//! An independent f64 check of the general-angle coil table `COIL_H4` (derivations/coil_h4.rs).
//!
//! Same method as [`super::quadrature`] (which covers the paper's coil and dipole), for the
//! Boridy field with its n = 2 and n = 4 terms (eq. 2.30):
//! h_r = Σ H_n (r/a)^(n−1) P_n(cos θ), h_θ = Σ (H_n/n) (r/a)^(n−1) P^1_n(cos θ), n = 2, 4,
//! P^1_n = dP_n/dθ (Condon–Shortley, FORMULATION §1). Nothing is shared with codegen: h and its
//! derivatives are written here by hand, the force is eq. (2.33) in components, the surface,
//! exact stretches, exact normal/tangent and Gauss–Legendre projection are as in
//! [`super::quadrature`], and the linear part is a 6-point central difference.
//!
//! The force is a quadratic form in (H2, H4): F = H2² F₂₂ + H2H4 F₂₄ + H4² F₄₄. A component is
//! isolated by polarization: F₂₂ = F(1, 0), F₄₄ = F(0, 1), F₂₄ = F(1, 1) − F(1, 0) − F(0, 1).
//! Units (docs/architecture.md): component c has ℋ_c = μ0χ_s (H-product) R0²/(4 a^(2p) R²)
//! with p = 1, 2, 3 for H2², H2H4, H4² and the force ∝ r^m, m = 2p − 1: zero-order loads are
//! ℋ_c R^m · value, couplings ℋ_c R^(m−1) · value.

use super::quadrature::{gauss_legendre, legendre_and_derivative, node_count, Projection, STEP};

/// One product of the Boridy amplitudes: a component of the `COIL_H4` table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum H4Component {
    /// H2² (the paper's coil, m = 1).
    H2H2,
    /// H2·H4 (m = 3).
    H2H4,
    /// H4² (m = 5).
    H4H4,
}

impl H4Component {
    pub const ALL: [H4Component; 3] = [H4Component::H2H2, H4Component::H2H4, H4Component::H4H4];

    /// (power of H2, power of H4) of the component's monomial.
    pub fn powers(self) -> (i32, i32) {
        match self {
            H4Component::H2H2 => (2, 0),
            H4Component::H2H4 => (1, 1),
            H4Component::H4H4 => (0, 2),
        }
    }

    /// r-power m of the zero-order force (F ∝ r^m).
    pub fn r_power(self) -> i32 {
        match self {
            H4Component::H2H2 => 1,
            H4Component::H2H4 => 3,
            H4Component::H4H4 => 5,
        }
    }
}

/// Physical values the check is evaluated at (deliberately not 1; results in units of ℋ_c
/// must not depend on them).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SettingH4 {
    pub r: f64,
    pub r0: f64,
    pub mu0_chi: f64,
    pub h2: f64,
    pub h4: f64,
    pub a: f64,
}

impl Default for SettingH4 {
    fn default() -> Self {
        SettingH4 { r: 1.3, r0: 1.1, mu0_chi: 0.7, h2: 1.9, h4: -0.8, a: 2.3 }
    }
}

impl SettingH4 {
    /// ℋ_c = μ0χ_s H2^p2 H4^p4 R0²/(4 a^(m+1) R²): H_n (r/a)^(n−1) makes the force ∝ r^m/a^(m+1).
    pub fn prefactor(&self, c: H4Component) -> f64 {
        let (p2, p4) = c.powers();
        let m = c.r_power();
        self.mu0_chi * self.h2.powi(p2) * self.h4.powi(p4) * self.r0 * self.r0
            / (4.0 * self.a.powi(m + 1) * self.r * self.r)
    }

    /// (F_r, F_θ) of eq. (2.33) at (r, θ) for amplitudes (h2, h4) (the setting's a and μ0χ_s).
    pub fn force_with(&self, h2: f64, h4: f64, r: f64, theta: f64) -> (f64, f64) {
        let (s, c) = theta.sin_cos();
        let a = self.a;
        // P_2, P_4 and their θ-derivatives, written out.
        let p2 = 0.5 * (3.0 * c * c - 1.0);
        let p2_t = -3.0 * s * c; // P^1_2
        let p2_tt = -3.0 * (c * c - s * s); // dP^1_2/dθ
        let p4 = (35.0 * c.powi(4) - 30.0 * c * c + 3.0) / 8.0;
        let p4_t = -s * (35.0 * c.powi(3) - 15.0 * c) / 2.0; // P^1_4
        // d/dθ[−s(35c³ − 15c)/2] = −c(35c³ − 15c)/2 − s(−105c²s + 15s)/2
        let p4_tt = -c * (35.0 * c.powi(3) - 15.0 * c) / 2.0 + s * s * (105.0 * c * c - 15.0) / 2.0;
        let (g2, g4) = (h2 * r / a, h4 * (r / a).powi(3));
        let (g2_r, g4_r) = (h2 / a, 3.0 * h4 * r * r / a.powi(3));
        let hr = g2 * p2 + g4 * p4;
        let hr_r = g2_r * p2 + g4_r * p4;
        let hr_t = g2 * p2_t + g4 * p4_t;
        let ht = g2 / 2.0 * p2_t + g4 / 4.0 * p4_t;
        let ht_r = g2_r / 2.0 * p2_t + g4_r / 4.0 * p4_t;
        let ht_t = g2 / 2.0 * p2_tt + g4 / 4.0 * p4_tt;
        let fr = hr * hr_r + ht / r * hr_t - ht * ht / r;
        let ft = hr * ht_r + ht / r * ht_t + hr * ht / r;
        (self.mu0_chi * fr, self.mu0_chi * ft)
    }

    /// The force of one component (polarization of the quadratic form), with the setting's
    /// H2, H4 values in the monomial.
    pub fn force(&self, comp: H4Component, r: f64, theta: f64) -> (f64, f64) {
        let f = |h2: f64, h4: f64| self.force_with(h2, h4, r, theta);
        match comp {
            H4Component::H2H2 => f(self.h2, 0.0),
            H4Component::H4H4 => f(0.0, self.h4),
            H4Component::H2H4 => {
                let (u, v, w) = (f(self.h2, self.h4), f(self.h2, 0.0), f(0.0, self.h4));
                (u.0 - v.0 - w.0, u.1 - v.1 - w.1)
            }
        }
    }
}

/// Projects (F_n, F_t) of one component on the surface r = R + a P_k, θ = Θ + (b/R) P^1_k onto
/// P_j, P^1_j, j ≤ jmax (raw loads, not divided by ℋ_c).
fn project(set: &SettingH4, comp: H4Component, k: usize, a: f64, b: f64, jmax: usize) -> Projection {
    let (xs, ws) = gauss_legendre(node_count(k) + 4); // the H4² integrands are 4 degrees higher
    let kf = k as f64;
    let mut normal = vec![0.0; jmax + 1];
    let mut tangential = vec![0.0; jmax + 1];
    for (&x, &w) in xs.iter().zip(&ws) {
        let sin_t = (1.0 - x * x).sqrt();
        let (p, dp) = legendre_and_derivative(k, x);
        let p1 = -sin_t * dp;
        let dp1 = x * dp - kf * (kf + 1.0) * p;
        let r = set.r + a * p;
        let r_t = a * p1;
        let theta = x.acos() + b / set.r * p1;
        let theta_t = 1.0 + b / set.r * dp1;
        let g1 = (r_t * r_t + r * r * theta_t * theta_t).sqrt();
        let area = (g1 / set.r0) * (r * theta.sin() / (set.r0 * sin_t));
        let (fr, ft) = set.force(comp, r, theta);
        let f_n = (fr * r * theta_t - ft * r_t) / g1 / area;
        let f_t = (fr * r_t + ft * r * theta_t) / g1 / area;
        for j in 0..=jmax {
            let (pj, dpj) = legendre_and_derivative(j, x);
            let jf = j as f64;
            normal[j] += w * f_n * pj * (2.0 * jf + 1.0) / 2.0;
            if j > 0 {
                tangential[j] += w * f_t * (-sin_t * dpj) * (2.0 * jf + 1.0) / (2.0 * jf * (jf + 1.0));
            }
        }
    }
    Projection { normal, tangential }
}

/// Zero-order loads of a component in units of ℋ_c R^m, j ≤ 10.
pub fn zero_order(set: &SettingH4, comp: H4Component) -> Projection {
    let raw = project(set, comp, 0, 0.0, 0.0, 10);
    let unit = set.prefactor(comp) * set.r.powi(comp.r_power());
    Projection {
        normal: raw.normal.iter().map(|v| v / unit).collect(),
        tangential: raw.tangential.iter().map(|v| v / unit).collect(),
    }
}

/// Linear response of a component to a_k (`amp_b = false`) or b_k of source mode k ≥ 1,
/// projected on j ≤ k + 6, in units of ℋ_c R^(m−1). Step as in [`super::quadrature`].
pub fn linear_response(set: &SettingH4, comp: H4Component, k: usize, amp_b: bool) -> Projection {
    let jmax = k + 6;
    let kf = k as f64;
    let h = if amp_b { STEP * set.r / (kf * (kf + 1.0) + 2.0) } else { STEP * set.r / (kf + 1.0) };
    let at = |eps: f64| if amp_b { project(set, comp, k, 0.0, eps, jmax) } else { project(set, comp, k, eps, 0.0, jmax) };
    let diffs: Vec<Projection> = (1..=3)
        .map(|i| {
            let (p, m) = (at(i as f64 * h), at(-(i as f64) * h));
            Projection {
                normal: p.normal.iter().zip(&m.normal).map(|(u, v)| u - v).collect(),
                tangential: p.tangential.iter().zip(&m.tangential).map(|(u, v)| u - v).collect(),
            }
        })
        .collect();
    let unit = set.prefactor(comp) * set.r.powi(comp.r_power() - 1) * 60.0 * h;
    let combine = |sel: fn(&Projection) -> &Vec<f64>| -> Vec<f64> {
        (0..=jmax).map(|j| (45.0 * sel(&diffs[0])[j] - 9.0 * sel(&diffs[1])[j] + sel(&diffs[2])[j]) / unit).collect()
    };
    Projection { normal: combine(|p| &p.normal), tangential: combine(|p| &p.tangential) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn h2_component_is_the_paper_coil_force() {
        // F = μ0χ H2² r/(4a²) [(3cos²θ+1) e_r − 3 sinθ cosθ e_θ] (eq. 2.33 for eq. 2.32).
        let s = SettingH4::default();
        let (r, th) = (0.9, 0.7);
        let (fr, ft) = s.force(H4Component::H2H2, r, th);
        let c = s.mu0_chi * s.h2 * s.h2 * r / (4.0 * s.a * s.a);
        assert!((fr - c * (3.0 * th.cos().powi(2) + 1.0)).abs() < 1e-14);
        assert!((ft - c * (-3.0 * th.sin() * th.cos())).abs() < 1e-14);
    }

    #[test]
    fn h_field_is_curl_free() {
        // ∇×h = 0: ∂_r(r h_θ) = ∂_θ h_r (a check of the hand-written h and derivatives).
        let s = SettingH4::default();
        let h = |r: f64, t: f64| {
            let (sn, c) = t.sin_cos();
            let p2 = 0.5 * (3.0 * c * c - 1.0);
            let p4 = (35.0 * c.powi(4) - 30.0 * c * c + 3.0) / 8.0;
            let p2t = -3.0 * sn * c;
            let p4t = -sn * (35.0 * c.powi(3) - 15.0 * c) / 2.0;
            let (g2, g4) = (s.h2 * r / s.a, s.h4 * (r / s.a).powi(3));
            (g2 * p2 + g4 * p4, g2 / 2.0 * p2t + g4 / 4.0 * p4t)
        };
        let (r, t, e) = (0.8, 1.1, 1e-5);
        let d_rht = ((r + e) * h(r + e, t).1 - (r - e) * h(r - e, t).1) / (2.0 * e);
        let d_thr = (h(r, t + e).0 - h(r, t - e).0) / (2.0 * e);
        assert!((d_rht - d_thr).abs() < 1e-8, "{d_rht} vs {d_thr}");
    }
}
