//! Independent f64 oracle of the shell laws (tests only; shares no code or formula with codegen):
//! the energy E (hyperelastic: ∫ W(λ1, λ2) dA0; shape: ∫ w(κ1, κ2) dA) and the Rayleigh
//! dissipation D = ½ ∫ τ:D dA of a surface perturbed by one mode k,
//!
//!   r = R + a P_k(cos Θ),  θ = Θ + (b/R) P^1_k(cos Θ)      (eq 2.14),
//!
//! by Gauss–Legendre quadrature in x = cos Θ, with the meridian written in Cartesian
//! coordinates (ρ = r sin θ, z = r cos θ), and its derivatives by finite differences.
//!
//! Link to the tables. With F = S_n n̂ + S_t t̂ the load in the restoring sense (δE = ∫ F·δx dA),
//! ∂x/∂a = P_k e_r, ∂x/∂b = (r/R) P^1_k e_θ, linearized at the sphere (S_n = S0 + (S1 a + S2 b) P_k,
//! S_t = (S11 a + S12 b) P^1_k), per radian of azimuth, with N = 2/(2k+1), n = k(k+1):
//!
//!   ∂E/∂R (a = b = 0) = 2R² S0,
//!   ∂²E/∂a² = N (R² S1 + 2R S0),   ∂²E/∂a∂b = N (R² S2 − nR S0) = nN (R² S11 − R S0),
//!   ∂²E/∂b² = nN R² S12                               (only the tension form is variational).
//!
//! The same relations hold for D with the rate coefficients (∂²D/∂ȧ² = N R² S1d, …) and, with
//! ∂/∂ȧ ∂/∂a etc., for the Ṙ-terms of a viscous law.

/// P_k(x) and its x-derivatives up to order 3.
fn legendre(k: usize, x: f64) -> [f64; 4] {
    let (mut p0, mut p1) = (1.0, x);
    if k == 0 {
        p1 = 1.0;
    }
    for n in 1..k {
        let p2 = ((2 * n + 1) as f64 * x * p1 - n as f64 * p0) / (n + 1) as f64;
        p0 = p1;
        p1 = p2;
    }
    let (p, pm1) = if k == 0 { (1.0, 0.0) } else { (p1, p0) };
    let kk = k as f64;
    let nn = kk * (kk + 1.0);
    let w = 1.0 - x * x;
    let d1 = if k == 0 { 0.0 } else { kk * (pm1 - x * p) / w };
    let d2 = (2.0 * x * d1 - nn * p) / w;
    let d3 = (4.0 * x * d2 + (2.0 - nn) * d1) / w;
    [p, d1, d2, d3]
}

/// f(Θ) = P_k(cos Θ) and its Θ-derivatives up to order 3.
fn mode(k: usize, th: f64) -> [f64; 4] {
    let (s, c) = th.sin_cos();
    let [p, d1, d2, d3] = legendre(k, c);
    [p, -s * d1, s * s * d2 - c * d1, -s * s * s * d3 + 3.0 * s * c * d2 + s * d1]
}

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton on P_n).
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            for _ in 0..100 {
                let [p, d, _, _] = legendre(n, x);
                let dx = p / d;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let [_, d, _, _] = legendre(n, x);
            (x, 2.0 / ((1.0 - x * x) * d * d))
        })
        .collect()
}

/// The state of the perturbed surface: R, R0, mode k with amplitudes a, b, and rates.
#[derive(Clone, Copy, Debug)]
pub struct Surface {
    pub r: f64,
    pub r0: f64,
    pub k: usize,
    pub a: f64,
    pub b: f64,
    pub rd: f64,
    pub ad: f64,
    pub bd: f64,
}

/// Local geometry at one material angle.
pub struct Point {
    pub lambda1: f64,
    pub lambda2: f64,
    pub kappa1: f64,
    pub kappa2: f64,
    /// dA/dΘ per radian of azimuth (ρ |g1|)
    pub area: f64,
    /// principal rates of deformation λ̇_i/λ_i
    pub d1: f64,
    pub d2: f64,
}

impl Surface {
    pub fn at(&self, th: f64) -> Point {
        let [f, f1, f2, f3] = mode(self.k, th);
        let r = self.r + self.a * f;
        let (r1, r2) = (self.a * f1, self.a * f2);
        // θ = Θ + β P^1_k, P^1_k = f1
        let beta = self.b / self.r;
        let (t, t1, t2) = (th + beta * f1, 1.0 + beta * f2, beta * f3);
        let (st, ct) = t.sin_cos();
        // meridian (ρ, z) = r (sin θ, cos θ) and its Θ-derivatives
        let rho1 = r1 * st + r * ct * t1;
        let z1 = r1 * ct - r * st * t1;
        let rho2 = r2 * st + 2.0 * r1 * ct * t1 - r * st * t1 * t1 + r * ct * t2;
        let z2 = r2 * ct - 2.0 * r1 * st * t1 - r * ct * t1 * t1 - r * st * t2;
        let g = (rho1 * rho1 + z1 * z1).sqrt();
        let rho = r * st;
        let kappa1 = (z1 * rho2 - rho1 * z2) / g.powi(3);
        let kappa2 = -z1 / (g * rho);
        let lambda1 = g / self.r0;
        let lambda2 = rho / (self.r0 * th.sin());
        // rates at fixed Θ: ṙ = Ṙ + ȧ f, θ̇ = β̇ f1 with β̇ = ḃ/R − bṘ/R²
        let (rdot, rdot1) = (self.rd + self.ad * f, self.ad * f1);
        let bdot = self.bd / self.r - self.b * self.rd / (self.r * self.r);
        let (tdot, tdot1) = (bdot * f1, bdot * f2);
        // |g1|² = r1² + r² t1² (polar form of the same tangent)
        let gdot = (r1 * rdot1 + r * t1 * (rdot * t1 + r * tdot1)) / g;
        let d1 = gdot / g;
        let d2 = rdot / r + ct / st * tdot;
        Point { lambda1, lambda2, kappa1, kappa2, area: rho * g, d1, d2 }
    }

    /// ∫_0^π F(point, Θ) dΘ by Gauss–Legendre in x = cos Θ (dΘ = dx / sin Θ).
    pub fn integrate(&self, f: impl Fn(&Point, f64) -> f64) -> f64 {
        let nodes = gauss_legendre(2 * self.k + 40);
        nodes
            .iter()
            .map(|&(x, w)| {
                let th = x.acos();
                w * f(&self.at(th), th) / th.sin()
            })
            .sum()
    }
}

/// 8th-order central-difference weights for f' and f'' on the points −4…4.
pub const D1: [f64; 9] = [1.0 / 280.0, -4.0 / 105.0, 0.2, -0.8, 0.0, 0.8, -0.2, 4.0 / 105.0, -1.0 / 280.0];
pub const D2: [f64; 9] =
    [-1.0 / 560.0, 8.0 / 315.0, -0.2, 1.6, -205.0 / 72.0, 1.6, -0.2, 8.0 / 315.0, -1.0 / 560.0];

/// ∂²f/∂x² at 0 with step h.
pub fn second(f: impl Fn(f64) -> f64, h: f64) -> f64 {
    D2.iter().enumerate().map(|(i, c)| c * f((i as f64 - 4.0) * h)).sum::<f64>() / (h * h)
}

/// ∂f/∂x at 0 with step h.
pub fn first(f: impl Fn(f64) -> f64, h: f64) -> f64 {
    D1.iter().enumerate().filter(|(_, c)| **c != 0.0).map(|(i, c)| c * f((i as f64 - 4.0) * h)).sum::<f64>() / h
}

/// ∂²f/∂x∂y at 0 with steps h, g.
pub fn mixed(f: impl Fn(f64, f64) -> f64, h: f64, g: f64) -> f64 {
    first(|x| first(|y| f(x, y), g), h)
}

/// Steps in a and b on the scales the response varies on (R/(k+1), R/(k(k+1)+2)).
pub fn steps(r: f64, k: usize, factor: f64) -> (f64, f64) {
    let kk = k as f64;
    (factor * r / (kk + 1.0), factor * r / (kk * (kk + 1.0) + 2.0))
}
