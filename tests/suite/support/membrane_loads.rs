//! Independent f64 oracle of the exact (nonlinear) membrane loads on a surface with several
//! finite mode amplitudes (tests only; shares no code with codegen):
//!
//!   r = R + Σ a_n P_n(cos Θ),  θ = Θ + Σ (b_n/R) P^1_n(cos Θ)      (eq 2.14),
//!
//! the meridian in Cartesian form ρ = r sin θ, z = r cos θ with exact Θ-derivatives (no finite
//! differences), stretches λ1 = |x_Θ|/R0, λ2 = ρ/(R0 sin Θ), curvatures of the meridian and of the
//! parallel, the stresses σ_i = λ_i ∂W/∂λ_i of a strain energy (written out by hand here, with
//! forward-mode dual numbers for their Θ-derivative), and the equilibrium of eqs 2.26–2.28:
//!
//!   F_n = (κ1σ1 + κ2σ2)/α,  α = λ1λ2,
//!   paper:   F_t = −(dσ1/ds + (ρ_s/ρ)(σ1 − σ2))/α,
//!   tension: F_t = −(d(σ1/α)/ds + (ρ_s/ρ)(σ1 − σ2)/α),
//!
//! projected by Gauss–Legendre quadrature in x = cos Θ on P_j (weight (2j+1)/2) and on
//! P^1_j = −sin Θ P_j'(x) (weight (2j+1)/(2j(j+1))).

use super::shell_energy::gauss_legendre;

/// A forward-mode dual number v + ε d.
#[derive(Clone, Copy, Debug)]
pub struct D(pub f64, pub f64);

impl std::ops::Add for D {
    type Output = D;
    fn add(self, o: D) -> D {
        D(self.0 + o.0, self.1 + o.1)
    }
}
impl std::ops::Sub for D {
    type Output = D;
    fn sub(self, o: D) -> D {
        D(self.0 - o.0, self.1 - o.1)
    }
}
impl std::ops::Mul for D {
    type Output = D;
    fn mul(self, o: D) -> D {
        D(self.0 * o.0, self.0 * o.1 + self.1 * o.0)
    }
}
impl D {
    pub fn c(v: f64) -> D {
        D(v, 0.0)
    }
    pub fn powi(self, n: i32) -> D {
        D(self.0.powi(n), n as f64 * self.0.powi(n - 1) * self.1)
    }
}

/// A hyperelastic law: (σ1, σ2) of (λ1, λ2).
#[derive(Clone, Copy, Debug)]
pub enum Law {
    /// eq 2.24: W = C1(λ1² + λ2² + (λ1λ2)⁻² − 3) + C2(λ1⁻² + λ2⁻² + (λ1λ2)² − 3)
    MooneyRivlin { c1: f64, c2: f64 },
    /// W = (G_s/4)(I1² + 2I1 − 2I2 + C I2²), I1 = λ1² + λ2² − 2, I2 = λ1²λ2² − 1
    Skalak { gs: f64, c: f64 },
}

impl Law {
    /// σ1 = λ1 ∂W/∂λ1 (σ2 by symmetry, swapping the arguments).
    fn sigma1(&self, l1: D, l2: D) -> D {
        match *self {
            Law::MooneyRivlin { c1, c2 } => {
                // λ1 ∂W/∂λ1 = 2C1(λ1² − λ1⁻²λ2⁻²) + 2C2(−λ1⁻² + λ1²λ2²)
                D::c(2.0 * c1) * (l1.powi(2) - l1.powi(-2) * l2.powi(-2)) + D::c(2.0 * c2) * (l1.powi(2) * l2.powi(2) - l1.powi(-2))
            }
            Law::Skalak { gs, c } => {
                let i1 = l1.powi(2) + l2.powi(2) - D::c(2.0);
                let i2 = l1.powi(2) * l2.powi(2) - D::c(1.0);
                // λ1 ∂/∂λ1: I1 → 2λ1², I2 → 2λ1²λ2²
                let (di1, di2) = (D::c(2.0) * l1.powi(2), D::c(2.0) * l1.powi(2) * l2.powi(2));
                D::c(gs / 4.0) * (D::c(2.0) * i1 * di1 + D::c(2.0) * di1 - D::c(2.0) * di2 + D::c(2.0 * c) * i2 * di2)
            }
        }
    }
}

/// P_n(cos Θ) and its Θ-derivatives up to order 3.
pub fn mode(n: usize, th: f64) -> [f64; 4] {
    let (s, c) = th.sin_cos();
    let (mut p0, mut p1) = (1.0, c);
    for k in 1..n {
        let p2 = ((2 * k + 1) as f64 * c * p1 - k as f64 * p0) / (k + 1) as f64;
        p0 = p1;
        p1 = p2;
    }
    let (p, pm1) = if n == 0 { (1.0, 0.0) } else { (p1, p0) };
    let (nf, w) = (n as f64, s * s);
    let ll = nf * (nf + 1.0);
    let d1 = if n == 0 { 0.0 } else { nf * (pm1 - c * p) / w };
    let d2 = (2.0 * c * d1 - ll * p) / w;
    let d3 = (4.0 * c * d2 + (2.0 - ll) * d1) / w;
    [p, -s * d1, s * s * d2 - c * d1, -s * s * s * d3 + 3.0 * s * c * d2 + s * d1]
}

/// One mode of the surface.
#[derive(Clone, Copy, Debug)]
pub struct Amp {
    pub n: usize,
    pub a: f64,
    pub b: f64,
}

/// (F_n, F_t paper, F_t tension) at material angle Θ.
pub fn loads(law: Law, r: f64, r0: f64, modes: &[Amp], th: f64) -> (f64, f64, f64) {
    let (mut rr, mut r1, mut r2) = (r, 0.0, 0.0);
    let (mut t, mut t1, mut t2) = (th, 1.0, 0.0);
    for md in modes {
        let f = mode(md.n, th);
        rr += md.a * f[0];
        r1 += md.a * f[1];
        r2 += md.a * f[2];
        let beta = md.b / r;
        t += beta * f[1];
        t1 += beta * f[2];
        t2 += beta * f[3];
    }
    loads_on(law, r0, [rr, r1, r2, t, t1, t2], th)
}

/// (F_n, F_t paper, F_t tension) at material angle Θ of a surface given by its material
/// parametrisation: g = [r, r′, r″, θ, θ′, θ″] at Θ (′ = d/dΘ).
pub fn loads_on(law: Law, r0: f64, g: [f64; 6], th: f64) -> (f64, f64, f64) {
    let [rr, r1, r2, t, t1, t2] = g;
    let (st, ct) = t.sin_cos();
    let rho = rr * st;
    let rho1 = r1 * st + rr * ct * t1;
    let z1 = r1 * ct - rr * st * t1;
    let rho2 = r2 * st + 2.0 * r1 * ct * t1 - rr * st * t1 * t1 + rr * ct * t2;
    let z2 = r2 * ct - 2.0 * r1 * st * t1 - rr * ct * t1 * t1 - rr * st * t2;
    let g = (rho1 * rho1 + z1 * z1).sqrt();
    let g1 = (rho1 * rho2 + z1 * z2) / g;
    let kappa1 = (z1 * rho2 - rho1 * z2) / g.powi(3);
    let kappa2 = -z1 / (g * rho);
    let (s0, c0) = th.sin_cos();
    // λ1, λ2 and their Θ-derivatives as duals
    let l1 = D(g / r0, g1 / r0);
    let l2 = D(rho / (r0 * s0), (rho1 * s0 - rho * c0) / (r0 * s0 * s0));
    let (sig1, sig2) = (law.sigma1(l1, l2), law.sigma1(l2, l1));
    let alpha = l1 * l2;
    let fn_ = (kappa1 * sig1.0 + kappa2 * sig2.0) / alpha.0;
    let rho_s = rho1 / g;
    let paper = -(sig1.1 / g + rho_s / rho * (sig1.0 - sig2.0)) / alpha.0;
    // (σ1/α)' = (σ1' α − σ1 α')/α²
    let q1 = (sig1.1 * alpha.0 - sig1.0 * alpha.1) / (alpha.0 * alpha.0);
    let tension = -(q1 / g + rho_s / rho * (sig1.0 - sig2.0) / alpha.0);
    (fn_, paper, tension)
}

/// Projections of the loads for j = 0..=jmax: (normal on P_j, paper F_t on P^1_j, tension F_t on P^1_j).
pub fn projected(law: Law, r: f64, r0: f64, modes: &[Amp], jmax: usize) -> Vec<[f64; 3]> {
    let nmax = modes.iter().map(|m| m.n).max().unwrap_or(0);
    let nodes = gauss_legendre(3 * (nmax + jmax) + 60);
    let mut out = vec![[0.0; 3]; jmax + 1];
    for &(x, w) in &nodes {
        let th = x.acos();
        let (fn_, fp, ft) = loads(law, r, r0, modes, th);
        for (j, o) in out.iter_mut().enumerate() {
            let [p, p1, _, _] = mode(j, th);
            o[0] += w * fn_ * p;
            o[1] += w * fp * p1;
            o[2] += w * ft * p1;
        }
    }
    normalise_projections(&mut out);
    out
}

/// Turns the quadrature sums ∫ f P_j dx, ∫ f P¹_j dx of [`projected`]'s layout (normal, then
/// two tangential columns) into Legendre coefficients: × (2j + 1)/2 for P_j and
/// × (2j + 1)/(2j(j + 1)) for P¹_j (0 for j = 0, where P¹_0 = 0).
pub fn normalise_projections(out: &mut [[f64; 3]]) {
    for (j, o) in out.iter_mut().enumerate() {
        let jj = j as f64;
        o[0] *= (2.0 * jj + 1.0) / 2.0;
        let tn = if j == 0 { 0.0 } else { (2.0 * jj + 1.0) / (2.0 * jj * (jj + 1.0)) };
        o[1] *= tn;
        o[2] *= tn;
    }
}
