//! An independent numerical derivation of the magnetic loads of eq. (2.40), in f64.
//!
//! This is the cross-check of the exact tables that codegen derives (issue 2). It shares no
//! code and no formula with codegen: it evaluates the force of the *field* on a *finitely*
//! perturbed surface and extracts the linear part numerically.
//!
//! 1. Field h and its derivatives, written directly from eq. (2.32) (coil, H2 term) and
//!    eq. (2.36) (dipole, h = 6Mρ/z⁴ e_ρ, ρ = r sinθ, in spherical components).
//! 2. Force F = μ0χ_s (∇h)·h with the component formulas of eq. (2.33), at the deformed point.
//! 3. Surface r = R + a P_k(cosΘ), θ = Θ + (b/R) P^1_k(cosΘ) (eq. 2.14), P^1_k = dP_k/dΘ
//!    (Condon–Shortley, FORMULATION §1). Stretches are the *exact* ones of eq. (2.20), first
//!    expressions: λ1 = √(r_Θ² + r²θ_Θ²)/R0, λ2 = r sinθ/(R0 sinΘ). The normal and tangent are
//!    the exact unit vectors of the deformed meridian (outward, and towards increasing Θ); they
//!    reduce to eq. (2.21) at linear order, so F_n = F·n̂/(λ1λ2), F_t = F·t̂/(λ1λ2) reduce to
//!    eq. (2.39).
//! 4. Gauss–Legendre projection in x = cosΘ on P_j (norm 2/(2j+1)) and P^1_j
//!    (norm 2j(j+1)/(2j+1)). With `k + 16` nodes the linear integrands (polynomials of degree
//!    ≤ 2k + 5) are integrated exactly.
//! 5. The linear part: a 6-point central difference in the amplitude (error O(h⁶)), with
//!    h = [`STEP`]·R/(k+1) for a_k and [`STEP`]·R/(k(k+1)+2) for b_k: a_k enters through
//!    r_Θ = a_k P^1_k (scale R/k), b_k through θ_Θ = 1 + (b_k/R) dP^1_k/dΘ (scale R/k²).
//!
//! Results are in units of the prefactor ℋ of docs/architecture.md: coil
//! ℋ = μ0χ_sH2²R0²/(4a²R²), dipole ℋ = −36μ0χ_sM²R0²/(z⁸R²) (the appendix's, dimension
//! corrected). Both forces are ∝ r (m = 1): zero-order loads are ℋR·value, couplings ℋ·value.

use magbubble::field::appendix::{CouplingId, PaperField};

/// Amplitude step for the 6-point central difference, in units of R/(k+1) (a_k) and
/// R/(k(k+1)+2) (b_k).
///
/// Chosen from a scan against the exact tables (docs/derivation-notes.md): worst relative error
/// over all couplings, k ≤ 32: 2.8e-8 at 5e-2 (truncation), 1.2e-10 at 2e-2, 4.7e-12 at 1e-2,
/// 1.3e-11 at 5e-3, 7.5e-11 at 1e-3 (round-off).
pub const STEP: f64 = 1e-2;

/// Physical values the check is evaluated at. The results, in units of ℋ, must not depend on
/// them; a test varies them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setting {
    /// Current radius R.
    pub r: f64,
    /// Reference radius R0.
    pub r0: f64,
    /// μ0χ_s.
    pub mu0_chi: f64,
    /// Coil: H2 and a (eq. 2.32).
    pub h2: f64,
    pub a: f64,
    /// Dipole: M and z (eq. 2.36).
    pub m: f64,
    pub z: f64,
}

impl Default for Setting {
    /// Deliberately not 1: R ≠ R0 exercises the area factor and the R-scaling of ℋ.
    fn default() -> Self {
        Setting { r: 1.3, r0: 1.1, mu0_chi: 0.7, h2: 1.9, a: 2.3, m: 0.8, z: 1.7 }
    }
}

impl Setting {
    /// ℋ of docs/architecture.md for `field`.
    pub fn prefactor(&self, field: PaperField) -> f64 {
        let rr = self.r0 * self.r0 / (self.r * self.r);
        match field {
            PaperField::Coil => self.mu0_chi * self.h2 * self.h2 * rr / (4.0 * self.a * self.a),
            PaperField::Dipole => -36.0 * self.mu0_chi * self.m * self.m * rr / self.z.powi(8),
        }
    }

    /// The force (F_r, F_θ) per unit volume at (r, θ): eq. (2.33), with h from (2.32) or (2.36).
    pub fn force(&self, field: PaperField, r: f64, theta: f64) -> (f64, f64) {
        let (s, c) = theta.sin_cos();
        // (h_r, ∂_r h_r, ∂_θ h_r, h_θ, ∂_r h_θ, ∂_θ h_θ)
        let (hr, hr_r, hr_t, ht, ht_r, ht_t) = match field {
            PaperField::Coil => {
                let g = self.h2 / (2.0 * self.a);
                (
                    g * r * (3.0 * c * c - 1.0),
                    g * (3.0 * c * c - 1.0),
                    g * r * (-6.0 * c * s),
                    -3.0 * g * r * s * c,
                    -3.0 * g * s * c,
                    -3.0 * g * r * (c * c - s * s),
                )
            }
            PaperField::Dipole => {
                // h = K ρ e_ρ, ρ = r sinθ, e_ρ = sinθ e_r + cosθ e_θ.
                let kk = 6.0 * self.m / self.z.powi(4);
                (
                    kk * r * s * s,
                    kk * s * s,
                    kk * r * 2.0 * s * c,
                    kk * r * s * c,
                    kk * s * c,
                    kk * r * (c * c - s * s),
                )
            }
        };
        let fr = hr * hr_r + ht / r * hr_t - ht * ht / r;
        let ft = hr * ht_r + ht / r * ht_t + hr * ht / r;
        (self.mu0_chi * fr, self.mu0_chi * ft)
    }
}

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton on P_n, converged to round-off).
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n {
        let mut xi = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            let (p, d) = legendre_and_derivative(n, xi);
            dp = d;
            let dx = p / d;
            xi -= dx;
            if dx.abs() <= 1e-16 * xi.abs().max(1.0) {
                break;
            }
        }
        let (_, d) = legendre_and_derivative(n, xi);
        if d != 0.0 {
            dp = d;
        }
        x[i] = xi;
        w[i] = 2.0 / ((1.0 - xi * xi) * dp * dp);
    }
    (x, w)
}

/// (P_n(x), P_n'(x)) by the three-term recurrence and P'_{n+1} = P'_{n−1} + (2n+1)P_n.
pub fn legendre_and_derivative(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    let (mut d0, mut d1) = (0.0, 1.0);
    if n == 0 {
        return (1.0, 0.0);
    }
    for j in 1..n {
        let jf = j as f64;
        let p2 = ((2.0 * jf + 1.0) * x * p1 - jf * p0) / (jf + 1.0);
        let d2 = d0 + (2.0 * jf + 1.0) * p1;
        (p0, p1, d0, d1) = (p1, p2, d1, d2);
    }
    (p1, d1)
}

/// Projections of one load pair on P_j and P^1_j, j = 0..=jmax, in the units the caller divides by.
#[derive(Debug, Clone, PartialEq)]
pub struct Projection {
    /// Coefficient of P_j in F_n.
    pub normal: Vec<f64>,
    /// Coefficient of P^1_j in F_t (index 0 is 0: P^1_0 ≡ 0).
    pub tangential: Vec<f64>,
}

/// The perturbation of one mode: `a` or `b` amplitude (in units of length) on mode `k`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Perturbation {
    k: usize,
    a: f64,
    b: f64,
}

/// Projects (F_n, F_t) on the perturbed surface onto P_j, P^1_j for j = 0..=jmax, with `nodes`
/// Gauss–Legendre points. Loads are raw (not divided by ℋ).
fn project(
    set: &Setting,
    field: PaperField,
    pert: Perturbation,
    jmax: usize,
    nodes: &(Vec<f64>, Vec<f64>),
) -> Projection {
    let (xs, ws) = nodes;
    let kf = pert.k as f64;
    let mut normal = vec![0.0; jmax + 1];
    let mut tangential = vec![0.0; jmax + 1];
    for (&x, &w) in xs.iter().zip(ws) {
        let sin_t = (1.0 - x * x).sqrt();
        let big_theta = x.acos();
        let (p, dp) = legendre_and_derivative(pert.k, x);
        let p1 = -sin_t * dp; // P^1_k = dP_k/dΘ
        let dp1 = x * dp - kf * (kf + 1.0) * p; // dP^1_k/dΘ (Legendre's equation)
        let r = set.r + pert.a * p;
        let r_t = pert.a * p1;
        let theta = big_theta + pert.b / set.r * p1;
        let theta_t = 1.0 + pert.b / set.r * dp1;
        let g1 = (r_t * r_t + r * r * theta_t * theta_t).sqrt();
        let lambda1 = g1 / set.r0;
        let lambda2 = r * theta.sin() / (set.r0 * sin_t);
        let (fr, ft) = set.force(field, r, theta);
        // n̂ = (rθ_Θ e_r − r_Θ e_θ)/|g1|, t̂ = (r_Θ e_r + rθ_Θ e_θ)/|g1|.
        let area = lambda1 * lambda2;
        let f_n = (fr * r * theta_t - ft * r_t) / g1 / area;
        let f_t = (fr * r_t + ft * r * theta_t) / g1 / area;
        let (mut q0, mut q1) = (1.0, x); // P_j(x)
        let (mut d0, mut d1) = (0.0, 1.0); // P_j'(x)
        for j in 0..=jmax {
            let (pj, dpj) = match j {
                0 => (q0, d0),
                _ => (q1, d1),
            };
            let jf = j as f64;
            normal[j] += w * f_n * pj * (2.0 * jf + 1.0) / 2.0;
            if j > 0 {
                let p1j = -sin_t * dpj;
                tangential[j] += w * f_t * p1j * (2.0 * jf + 1.0) / (2.0 * jf * (jf + 1.0));
            }
            if j >= 1 {
                let q2 = ((2.0 * jf + 1.0) * x * q1 - jf * q0) / (jf + 1.0);
                let d2 = d0 + (2.0 * jf + 1.0) * q1;
                (q0, q1, d0, d1) = (q1, q2, d1, d2);
            }
        }
    }
    Projection { normal, tangential }
}

/// Number of Gauss–Legendre nodes used for source mode k (exact for degree ≤ 2k + 31).
pub fn node_count(k: usize) -> usize {
    k + 16
}

/// Zero-order loads in units of ℋR: (coefficients of P_j in F_n, of P^1_j in F_t), j ≤ 6.
pub fn zero_order(set: &Setting, field: PaperField) -> Projection {
    let nodes = gauss_legendre(node_count(0));
    let raw = project(set, field, Perturbation { k: 0, a: 0.0, b: 0.0 }, 6, &nodes);
    let unit = set.prefactor(field) * set.r;
    Projection {
        normal: raw.normal.iter().map(|v| v / unit).collect(),
        tangential: raw.tangential.iter().map(|v| v / unit).collect(),
    }
}

/// The linear response to the amplitude a_k (`amp_b = false`) or b_k (`amp_b = true`) of source
/// mode k ≥ 1, projected on j = 0..=k+4, in units of ℋ (per unit amplitude, i.e. ℋR^(m−1)
/// with m = 1). Entry j of `normal` is the coupling of target j to source k on P_j.
pub fn linear_response(set: &Setting, field: PaperField, k: usize, amp_b: bool, step: f64) -> Projection {
    let jmax = k + 4;
    let nodes = gauss_legendre(node_count(k));
    let kf = k as f64;
    // The response varies on the scale a ~ R/k (a enters through r_Θ = a P^1_k) and
    // b ~ R/k² (b enters through θ_Θ = 1 + (b/R) dP^1_k/dΘ).
    let h = if amp_b { step * set.r / (kf * (kf + 1.0) + 2.0) } else { step * set.r / (kf + 1.0) };
    let at = |eps: f64| {
        let pert = if amp_b { Perturbation { k, a: 0.0, b: eps } } else { Perturbation { k, a: eps, b: 0.0 } };
        project(set, field, pert, jmax, &nodes)
    };
    // f'(0) ≈ [45(f₁ − f₋₁) − 9(f₂ − f₋₂) + (f₃ − f₋₃)]/(60h), error O(h⁶).
    let odd: Vec<Projection> = (1..=3).map(|i| {
        let (p, m) = (at(i as f64 * h), at(-(i as f64) * h));
        Projection {
            normal: p.normal.iter().zip(&m.normal).map(|(u, v)| u - v).collect(),
            tangential: p.tangential.iter().zip(&m.tangential).map(|(u, v)| u - v).collect(),
        }
    }).collect();
    let unit = set.prefactor(field) * 60.0 * h;
    let combine = |sel: fn(&Projection) -> &Vec<f64>| -> Vec<f64> {
        (0..=jmax)
            .map(|j| (45.0 * sel(&odd[0])[j] - 9.0 * sel(&odd[1])[j] + sel(&odd[2])[j]) / unit)
            .collect()
    };
    Projection { normal: combine(|p| &p.normal), tangential: combine(|p| &p.tangential) }
}

/// Half the second derivative in a_k of the loads of source mode k (the a_k² coefficient of the
/// second-order magnetic load, not in the tables: issue 12 measures its size), j = 0..=2k+2, in
/// units of ℋ/R (8th-order central difference, step STEP·R/(k+1)).
pub fn second_order_response(set: &Setting, field: PaperField, k: usize) -> Projection {
    let jmax = 2 * k + 2;
    let nodes = gauss_legendre(4 * k + 60);
    let h = 2.0 * STEP * set.r / (k as f64 + 1.0);
    let at: Vec<Projection> = (0..9).map(|i| project(set, field, Perturbation { k, a: (i as f64 - 4.0) * h, b: 0.0 }, jmax, &nodes)).collect();
    let unit = 2.0 * set.prefactor(field) / set.r * h * h;
    let w = crate::support::shell_energy::D2;
    let combine = |sel: fn(&Projection) -> &Vec<f64>| -> Vec<f64> { (0..=jmax).map(|j| w.iter().zip(&at).map(|(c, p)| c * sel(p)[j]).sum::<f64>() / unit).collect() };
    Projection { normal: combine(|p| &p.normal), tangential: combine(|p| &p.tangential) }
}

/// The coupling `id` at target mode k in units of ℋ, or `None` where it does not exist
/// (source mode k + offset < 1, or a tangential load on j = 0, where P^1_0 ≡ 0).
pub fn coupling(set: &Setting, field: PaperField, id: &CouplingId, k: usize) -> Option<f64> {
    let source = k as i64 + id.offset as i64;
    if source < 1 || (id.tangential && k == 0) {
        return None;
    }
    let resp = linear_response(set, field, source as usize, id.amp_b, STEP);
    Some(if id.tangential { resp.tangential[k] } else { resp.normal[k] })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        let (x, w) = gauss_legendre(10);
        for deg in 0..20 {
            let num: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(deg)).sum();
            let exact = if deg % 2 == 0 { 2.0 / (deg as f64 + 1.0) } else { 0.0 };
            assert!((num - exact).abs() < 1e-14, "degree {deg}: {num} vs {exact}");
        }
    }

    #[test]
    fn derivative_of_p_k_matches_finite_difference() {
        for k in [0, 1, 2, 5, 17] {
            let x = 0.37;
            let (_, d) = legendre_and_derivative(k, x);
            let h = 1e-6;
            let fd = (legendre_and_derivative(k, x + h).0 - legendre_and_derivative(k, x - h).0) / (2.0 * h);
            assert!((d - fd).abs() < 1e-6 * (1.0 + d.abs()), "k={k}: {d} vs {fd}");
        }
    }

    #[test]
    fn coil_force_is_the_printed_2_33() {
        // F_r = μ0χ H2² r/(4a²)(3cos²θ+1), F_θ = μ0χ H2² r/(4a²)(−3 sinθ cosθ).
        let s = Setting::default();
        let (r, th) = (0.9, 0.7);
        let (fr, ft) = s.force(PaperField::Coil, r, th);
        let c = s.mu0_chi * s.h2 * s.h2 * r / (4.0 * s.a * s.a);
        assert!((fr - c * (3.0 * th.cos().powi(2) + 1.0)).abs() < 1e-14);
        assert!((ft - c * (-3.0 * th.sin() * th.cos())).abs() < 1e-14);
    }

    #[test]
    fn dipole_force_is_the_printed_2_37() {
        // 36μ0χM²ρ/z⁸ e_ρ with ρ = r sinθ, e_ρ = sinθ e_r + cosθ e_θ.
        let s = Setting::default();
        let (r, th) = (0.9, 0.7);
        let (fr, ft) = s.force(PaperField::Dipole, r, th);
        let c = 36.0 * s.mu0_chi * s.m * s.m * r * th.sin() / s.z.powi(8);
        assert!((fr - c * th.sin()).abs() < 1e-14);
        assert!((ft - c * th.cos()).abs() < 1e-14);
    }
}
