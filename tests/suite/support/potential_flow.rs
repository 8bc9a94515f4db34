//! An independent f64 evaluation of the dynamic boundary condition of a free bubble on a
//! *finitely* deformed surface (issue 12, the oracle of the quadratic tables). It shares no code
//! and no formula with codegen's perturbation expansion:
//!
//! 1. The surface r = f(θ, t) = R(t) + Σ_n a_n(t) P_n(cos θ) at finite amplitudes, moved along
//!    the quadratic trajectories R(t+s) = R + Ṙs + R̈s²/2, a(t+s) = a + ȧs + äs²/2.
//! 2. The potential φ = −R²Ṙ/r + Σ_{n ≤ N} c_n r^{−(n+1)} P_n solved from the kinematic
//!    condition φ_r − φ_θ f_θ/r² = ∂f/∂t on the exact surface, by Galerkin projection on
//!    P_0…P_N with Gauss–Legendre quadrature (a dense linear solve, no expansion in the amplitudes).
//! 3. ∂φ/∂t at fixed r from ċ_n, an 8th-order central difference of c_n(t+s) in s.
//! 4. The residual F(θ) = ρ(φ_t + ½|∇φ|²) + p_g(R)(V_R/V)^κ − γ(κ1 + κ2) − p∞ on r = f(θ): exact
//!    curvatures of the surface of revolution, volume by quadrature, projected on P_j.
//!
//! The bilinear coefficients then follow from second differences in the amplitudes
//! (tests/suite/quadratic_oracle.rs).

use super::quadrature::{gauss_legendre, legendre_and_derivative};
use super::shell_energy::D1;

/// The physical setting (nondimensional).
#[derive(Clone, Copy, Debug)]
pub struct Flow {
    pub rho: f64,
    pub gamma: f64,
    pub pg: f64,
    pub kappa: f64,
    pub p_inf: f64,
    /// (R, Ṙ, R̈)
    pub radial: [f64; 3],
}

/// One shape mode: n and (a, ȧ, ä).
#[derive(Clone, Copy, Debug)]
pub struct Mode {
    pub n: usize,
    pub amp: [f64; 3],
}

/// P_n, P_n', P_n'' at x (P'' from the Legendre equation; x is never ±1 at Gauss nodes).
fn legendre2(n: usize, x: f64) -> (f64, f64, f64) {
    let (p, d) = legendre_and_derivative(n, x);
    let nn = (n * (n + 1)) as f64;
    (p, d, (2.0 * x * d - nn * p) / (1.0 - x * x))
}

/// Solve A c = b (dense, partial pivoting).
fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    for k in 0..n {
        let p = (k..n).max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs())).unwrap();
        a.swap(k, p);
        b.swap(k, p);
        for i in k + 1..n {
            let f = a[i][k] / a[k][k];
            if f != 0.0 {
                for c in k..n {
                    a[i][c] -= f * a[k][c];
                }
                b[i] -= f * b[k];
            }
        }
    }
    let mut x = vec![0.0; n];
    for k in (0..n).rev() {
        let s: f64 = (k + 1..n).map(|c| a[k][c] * x[c]).sum();
        x[k] = (b[k] - s) / a[k][k];
    }
    x
}

pub struct Oracle {
    /// multipoles 0..=nmax (also the largest mode and target)
    pub nmax: usize,
    nodes: Vec<(f64, f64)>,
    /// (P_k, P_k', P_k'') at every node, k ≤ nmax
    basis: Vec<Vec<(f64, f64, f64)>>,
}

impl Oracle {
    pub fn new(nmax: usize) -> Oracle {
        let (x, w) = gauss_legendre(2 * nmax + 48);
        let basis = x.iter().map(|&x| (0..=nmax).map(|k| legendre2(k, x)).collect()).collect();
        Oracle { nmax, nodes: x.into_iter().zip(w).collect(), basis }
    }

    /// The state at time offset s along the quadratic trajectories: (R, Ṙ, [(n, a, ȧ)]).
    fn at(flow: &Flow, modes: &[Mode], s: f64) -> (f64, f64, Vec<(usize, f64, f64)>) {
        let [r, rd, rdd] = flow.radial;
        let m = modes.iter().map(|m| (m.n, m.amp[0] + m.amp[1] * s + 0.5 * m.amp[2] * s * s, m.amp[1] + m.amp[2] * s)).collect();
        (r + rd * s + 0.5 * rdd * s * s, rd + rdd * s, m)
    }

    /// Multipole coefficients c_0..c_N at time offset s.
    fn multipoles(&self, flow: &Flow, modes: &[Mode], s: f64) -> Vec<f64> {
        let (r0, rd, m) = Self::at(flow, modes, s);
        let n1 = self.nmax + 1;
        let mut a = vec![vec![0.0; n1]; n1];
        let mut b = vec![0.0; n1];
        for (&(x, w), pk) in self.nodes.iter().zip(&self.basis) {
            let (mut f, mut g, mut ft) = (r0, 0.0, rd);
            for &(n, an, adn) in &m {
                let (p, d, _) = pk[n];
                f += an * p;
                g += an * d;
                ft += adn * p;
            }
            let rhs = ft - r0 * r0 * rd / (f * f);
            for k in 0..n1 {
                let wk = w * pk[k].0;
                b[k] += wk * rhs;
                for n in 0..n1 {
                    // φ_r − φ_θ f_θ / r², φ_θ f_θ = (1 − x²) P_n' g c_n r^{−(n+1)}
                    let rn = f.powi(-(n as i32) - 1);
                    a[k][n] += wk * (-(n as f64 + 1.0) * rn / f * pk[n].0 - (1.0 - x * x) * pk[n].1 * g * rn / (f * f));
                }
            }
        }
        solve(a, b)
    }

    /// (2j+1)/2 ∫ F P_j dx for j = 0..=jmax.
    pub fn residual(&self, flow: &Flow, modes: &[Mode], jmax: usize) -> Vec<f64> {
        let c = self.multipoles(flow, modes, 0.0);
        let tau = 1e-2;
        let mut cd = vec![0.0; c.len()];
        for (i, wgt) in D1.iter().enumerate() {
            if *wgt == 0.0 {
                continue;
            }
            let ci = self.multipoles(flow, modes, (i as f64 - 4.0) * tau);
            for (o, v) in cd.iter_mut().zip(ci) {
                *o += wgt * v / tau;
            }
        }
        let [r0, rd, rdd] = flow.radial;
        // volume ratio V/V_R = ½∫ f³ dx / R³
        let mut vol = 0.0;
        let mut pts = Vec::new();
        for (&(x, w), pk) in self.nodes.iter().zip(&self.basis) {
            let (mut f, mut g, mut dg) = (r0, 0.0, 0.0);
            for m in modes {
                let (p, d, dd) = pk[m.n];
                f += m.amp[0] * p;
                g += m.amp[0] * d;
                dg += m.amp[0] * dd;
            }
            vol += 0.5 * w * f * f * f;
            pts.push((x, w, f, g, dg, pk));
        }
        let pgas = flow.pg * (r0 * r0 * r0 / vol).powf(flow.kappa);
        let mut out = vec![0.0; jmax + 1];
        for &(x, w, f, g, dg, pk) in &pts {
            let s2 = 1.0 - x * x;
            let (mut phi_r, mut phi_th_over_s, mut phi_t) = (r0 * r0 * rd / (f * f), 0.0, -(2.0 * r0 * rd * rd + r0 * r0 * rdd) / f);
            for n in 0..=self.nmax {
                let (p, d, _) = pk[n];
                let rn = f.powi(-(n as i32) - 1);
                phi_r -= (n as f64 + 1.0) * c[n] * rn / f * p;
                phi_th_over_s -= c[n] * rn * d; // φ_θ = −sinθ Σ c r^{−(n+1)} P_n'
                phi_t += cd[n] * rn * p;
            }
            let grad2 = phi_r * phi_r + s2 * phi_th_over_s * phi_th_over_s / (f * f);
            // r = f(θ): f_θ = −sinθ g, f_θθ = −x g + (1 − x²) g'
            let w2 = f * f + s2 * g * g;
            let k1 = (f * f + 2.0 * s2 * g * g - f * (-x * g + s2 * dg)) / w2.powf(1.5);
            let k2 = (f + x * g) / (f * w2.sqrt());
            let fval = flow.rho * (phi_t + 0.5 * grad2) + pgas - flow.gamma * (k1 + k2) - flow.p_inf;
            for (j, o) in out.iter_mut().enumerate() {
                *o += (2.0 * j as f64 + 1.0) / 2.0 * w * fval * pk[j].0;
            }
        }
        out
    }
}

impl Oracle {
    /// Total energy of the free bubble at the state (R, Ṙ, modes (a, ȧ)) on the exact surface:
    /// kinetic energy of the potential flow −(ρ/2)∮ φ ∂φ/∂n dS = −πρ∫ φ f² ∂f/∂t dx (the
    /// kinematic condition), surface energy γA, gas internal energy p_g V/(κ−1) with
    /// p_g = p_g0 (V0/V)^κ, and the work p∞V against the far field (p∞ constant).
    pub fn energy(&self, flow: &Flow, pg0: f64, r_ref: f64, modes: &[Mode]) -> f64 {
        let v = self.virial(flow, pg0, r_ref, modes);
        v.kinetic + flow.gamma * v.area + v.pgas * v.volume / (flow.kappa - 1.0) + flow.p_inf * v.volume
    }
}

/// The terms of the virial identity of a free bubble at one state (quadratic_virial.rs).
#[derive(Clone, Copy, Debug)]
pub struct Virial {
    /// G = −ρ∮ φ x·n dS = −2πρ∫ φ f³ dx (n out of the bubble): Σ p·x over the surface markers
    pub g: f64,
    /// kinetic energy of the liquid, −πρ∫ φ f² ∂f/∂t dx
    pub kinetic: f64,
    pub area: f64,
    pub volume: f64,
    /// p_g = p_g0 (V0/V)^κ at the exact volume
    pub pgas: f64,
}

impl Oracle {
    /// G, T, A, V, p_g at the state (R, Ṙ, modes (a, ȧ)) on the exact surface, with the same
    /// multipole solve as `energy`. For the exact dynamics dG/dt = 5T + 3(p_g − p∞)V − 2γA.
    pub fn virial(&self, flow: &Flow, pg0: f64, r_ref: f64, modes: &[Mode]) -> Virial {
        let c = self.multipoles(flow, modes, 0.0);
        let (r0, rd) = (flow.radial[0], flow.radial[1]);
        let pi = std::f64::consts::PI;
        let (mut g_sum, mut ke, mut area, mut vol) = (0.0, 0.0, 0.0, 0.0);
        for (&(x, w), pk) in self.nodes.iter().zip(&self.basis) {
            let (mut f, mut g, mut ft) = (r0, 0.0, rd);
            for m in modes {
                let (p, d, _) = pk[m.n];
                f += m.amp[0] * p;
                g += m.amp[0] * d;
                ft += m.amp[1] * p;
            }
            let mut phi = -r0 * r0 * rd / f;
            for (n, cn) in c.iter().enumerate() {
                phi += cn * f.powi(-(n as i32) - 1) * pk[n].0;
            }
            g_sum -= 2.0 * pi * flow.rho * w * phi * f * f * f;
            ke -= pi * flow.rho * w * phi * f * f * ft;
            area += 2.0 * pi * w * f * (f * f + (1.0 - x * x) * g * g).sqrt();
            vol += 2.0 * pi / 3.0 * w * f * f * f;
        }
        let v0 = 4.0 * pi / 3.0 * r_ref.powi(3);
        Virial { g: g_sum, kinetic: ke, area, volume: vol, pgas: pg0 * (v0 / vol).powf(flow.kappa) }
    }
}
