//! Independent f64 oracle of the exact (nonlinear) bending and shell-viscous loads on a surface
//! with finite mode amplitudes and rates (tests only; shares no code with codegen):
//!
//!   r = R + Σ a_n P_n(cos Θ),  θ = Θ + Σ (b_n/R) P^1_n(cos Θ)      (eq 2.14),
//!
//! with every quantity a truncated Taylor series in Θ about the node ([`J`]: exact Θ-derivatives
//! to the order needed, P_n by its three-term recurrence on series) that also carries its time
//! derivative at the material point (R → Ṙ, a → ȧ, b → ḃ: forward mode in t). Loads per unit
//! deformed area, as the tables:
//!
//! * Helfrich bending, zero spontaneous curvature, by the classical shape equation (Ou-Yang &
//!   Helfrich 1987), not by a variation: S_n = −k_b (Δ_s c + c³/2 − 2cK), c = κ1 + κ2,
//!   K = κ1κ2, Δ_s f = (1/(ρ|x_Θ|)) d/dΘ(ρ f_Θ/|x_Θ|); no tangential load;
//! * the Kelvin–Voigt viscous shell: d_i = λ̇_i/λ_i, τ1 = κ_s(d1 + d2) + μ_s(d1 − d2), τ2 likewise
//!   with d1 ↔ d2, σ_i = λ1λ2τ_i, and the equilibrium of eqs 2.26–2.28 in the tension form,
//!   F_n = (κ1σ1 + κ2σ2)/α, F_t = −(d(σ1/α)/ds + (ρ_s/ρ)(σ1 − σ2)/α), α = λ1λ2;
//!
//! projected by Gauss–Legendre quadrature on P_j (weight (2j+1)/2) and P^1_j (weight
//! (2j+1)/(2j(j+1))), as support::membrane_loads.

use super::membrane_loads::mode;
use super::shell_energy::gauss_legendre;

/// Taylor coefficients kept (orders 0 … N−1 in Θ − Θ_node).
const N: usize = 8;

/// f(Θ_node + h) = Σ v_k h^k, and its time derivative ḟ(Θ_node + h) = Σ d_k h^k.
#[derive(Clone, Copy, Debug)]
pub struct J {
    v: [f64; N],
    d: [f64; N],
}

fn conv(a: &[f64; N], b: &[f64; N]) -> [f64; N] {
    let mut c = [0.0; N];
    for i in 0..N {
        for k in 0..N - i {
            c[i + k] += a[i] * b[k];
        }
    }
    c
}

impl J {
    /// A constant with a time derivative.
    pub fn c(v: f64, d: f64) -> J {
        let mut j = J { v: [0.0; N], d: [0.0; N] };
        j.v[0] = v;
        j.d[0] = d;
        j
    }
    fn add(self, o: J) -> J {
        J { v: std::array::from_fn(|k| self.v[k] + o.v[k]), d: std::array::from_fn(|k| self.d[k] + o.d[k]) }
    }
    fn sub(self, o: J) -> J {
        self.add(o.scale(-1.0))
    }
    fn scale(self, s: f64) -> J {
        J { v: self.v.map(|x| x * s), d: self.d.map(|x| x * s) }
    }
    fn mul(self, o: J) -> J {
        let (a, b) = (conv(&self.d, &o.v), conv(&self.v, &o.d));
        J { v: conv(&self.v, &o.v), d: std::array::from_fn(|k| a[k] + b[k]) }
    }
    fn recip(self) -> J {
        let mut w = [0.0; N];
        w[0] = 1.0 / self.v[0];
        for k in 1..N {
            w[k] = -(1..=k).map(|i| self.v[i] * w[k - i]).sum::<f64>() / self.v[0];
        }
        J { v: w, d: conv(&self.d, &conv(&w, &w)).map(|x| -x) }
    }
    fn div(self, o: J) -> J {
        self.mul(o.recip())
    }
    fn sqrt(self) -> J {
        let mut s = [0.0; N];
        s[0] = self.v[0].sqrt();
        for k in 1..N {
            s[k] = (self.v[k] - (1..k).map(|i| s[i] * s[k - i]).sum::<f64>()) / (2.0 * s[0]);
        }
        let root = J { v: s, d: [0.0; N] };
        let half = root.scale(2.0).recip();
        J { v: s, d: conv(&self.d, &half.v) }
    }
    /// (sin u, cos u) by s′ = c u′, c′ = −s u′.
    fn sin_cos(self) -> (J, J) {
        let (mut s, mut c) = ([0.0; N], [0.0; N]);
        (s[0], c[0]) = self.v[0].sin_cos();
        for k in 1..N {
            let (mut ps, mut pc) = (0.0, 0.0);
            for i in 1..=k {
                ps += i as f64 * self.v[i] * c[k - i];
                pc -= i as f64 * self.v[i] * s[k - i];
            }
            s[k] = ps / k as f64;
            c[k] = pc / k as f64;
        }
        (J { v: s, d: conv(&c, &self.d) }, J { v: c, d: conv(&s, &self.d).map(|x| -x) })
    }
    /// d/dΘ (the highest coefficient is lost).
    fn dth(self) -> J {
        let sh = |a: &[f64; N]| std::array::from_fn(|k| if k + 1 < N { (k + 1) as f64 * a[k + 1] } else { 0.0 });
        J { v: sh(&self.v), d: sh(&self.d) }
    }
    /// The time derivative as a value (its own rate dropped: the loads are linear in the rates).
    fn rate(self) -> J {
        J { v: self.d, d: [0.0; N] }
    }
    fn value(self) -> f64 {
        self.v[0]
    }
}

/// One mode of the surface, with rates.
#[derive(Clone, Copy, Debug, Default)]
pub struct Mode {
    pub n: usize,
    pub a: f64,
    pub ad: f64,
    pub b: f64,
    pub bd: f64,
}

/// P_n(cos Θ) as a series about the node (three-term recurrence on series).
fn legendre(n: usize, x: J) -> J {
    let (mut p0, mut p1) = (J::c(1.0, 0.0), x);
    if n == 0 {
        return p0;
    }
    for k in 1..n {
        let p2 = x.mul(p1).scale((2 * k + 1) as f64).sub(p0.scale(k as f64)).scale(1.0 / (k + 1) as f64);
        p0 = p1;
        p1 = p2;
    }
    p1
}

/// The deformed meridian at a node: ρ, its Θ-derivatives as series, |x_Θ|, κ1, κ2, λ1, λ2.
struct Surface {
    rho: J,
    rho1: J,
    g: J,
    k1: J,
    k2: J,
    l1: J,
    l2: J,
}

fn surface(r: f64, rd: f64, r0: f64, modes: &[Mode], th: f64) -> Surface {
    let mut t = J::c(th, 0.0);
    t.v[1] = 1.0;
    let (s0, x) = t.sin_cos();
    let big_r = J::c(r, rd);
    let (mut rr, mut theta) = (big_r, t);
    for m in modes {
        let p = legendre(m.n, x);
        rr = rr.add(J::c(m.a, m.ad).mul(p));
        theta = theta.add(J::c(m.b, m.bd).div(big_r).mul(p.dth()));
    }
    let (st, ct) = theta.sin_cos();
    let (rho, z) = (rr.mul(st), rr.mul(ct));
    let (rho1, z1) = (rho.dth(), z.dth());
    let (rho2, z2) = (rho1.dth(), z1.dth());
    let g = rho1.mul(rho1).add(z1.mul(z1)).sqrt();
    let k1 = z1.mul(rho2).sub(rho1.mul(z2)).div(g.mul(g).mul(g));
    let k2 = z1.div(g.mul(rho)).scale(-1.0);
    let l1 = g.scale(1.0 / r0);
    let l2 = rho.div(s0).scale(1.0 / r0);
    Surface { rho, rho1, g, k1, k2, l1, l2 }
}

/// Bending normal load S_n at material angle Θ (module doc).
pub fn bending(kb: f64, r: f64, modes: &[Mode], th: f64) -> f64 {
    let s = surface(r, 0.0, 1.0, modes, th);
    let c = s.k1.add(s.k2);
    let k = s.k1.mul(s.k2);
    let lap = s.rho.mul(c.dth()).div(s.g).dth().div(s.rho.mul(s.g));
    let shape = lap.add(c.mul(c).mul(c).scale(0.5)).sub(c.mul(k).scale(2.0));
    -kb * shape.value()
}

/// Viscous (F_n, F_t tension form) at material angle Θ (module doc).
pub fn viscous(mu: f64, kappa: f64, r: f64, rd: f64, r0: f64, modes: &[Mode], th: f64) -> (f64, f64) {
    let s = surface(r, rd, r0, modes, th);
    let d1 = s.l1.rate().div(s.l1);
    let d2 = s.l2.rate().div(s.l2);
    let (sum, diff) = (d1.add(d2).scale(kappa), d1.sub(d2).scale(mu));
    let alpha = s.l1.mul(s.l2);
    let (sig1, sig2) = (alpha.mul(sum.add(diff)), alpha.mul(sum.sub(diff)));
    let fn_ = s.k1.mul(sig1).add(s.k2.mul(sig2)).div(alpha).value();
    let rho_s = s.rho1.div(s.g);
    let ft = sig1.div(alpha).dth().div(s.g).add(rho_s.div(s.rho).mul(sig1.sub(sig2)).div(alpha)).scale(-1.0).value();
    (fn_, ft)
}

/// Projections for j = 0..=jmax of a load (F_n, F_t) given at material angles: (on P_j, on P^1_j).
pub fn projected(nmax: usize, jmax: usize, load: impl Fn(f64) -> (f64, f64)) -> Vec<[f64; 2]> {
    let nodes = gauss_legendre(3 * (nmax + jmax) + 60);
    let mut out = vec![[0.0; 2]; jmax + 1];
    for &(x, w) in &nodes {
        let th = x.acos();
        let (fn_, ft) = load(th);
        for (j, o) in out.iter_mut().enumerate() {
            let [p, p1, _, _] = mode(j, th);
            o[0] += w * fn_ * p;
            o[1] += w * ft * p1;
        }
    }
    for (j, o) in out.iter_mut().enumerate() {
        let jj = j as f64;
        o[0] *= (2.0 * jj + 1.0) / 2.0;
        o[1] *= if j == 0 { 0.0 } else { (2.0 * jj + 1.0) / (2.0 * jj * (jj + 1.0)) };
    }
    out
}
