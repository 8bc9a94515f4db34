//! Exact dispersion relation of a viscous shape mode of the membrane-coated bubble at rest at R0
//! (Prosperetti 1977 method, with magbubble's boundary conditions: FORMULATION §4.2 (N), the
//! corrected tangential stress balance (TS, audit 3) with the membrane Ŝ11/Ŝ12 terms, and the
//! no-slip condition (NS, eq 2.67)).
//!
//! Derivation. Linearise at R = R0, Ṙ = R̈ = 0 with G_n = S1 a + S2 b, G_t = S11 a + S12 b (the
//! ε-scaled membrane coefficients at R0, magnetic diagonal included) and seek e^{st}. The vorticity
//! equation 2.52 becomes T'' − (q² + k(k+1)/r²) T = 0, q² = s/ν, whose solution decaying at
//! infinity is the Riccati–Bessel function T(r) = T_w · r k_k(qr) / (R k_k(qR)) (k_n the modified
//! spherical Bessel function of the second kind, Re q > 0). With d/dx[x^{1−k} k_{k−1}] = −x^{1−k} k_k,
//!
//!   Ĩ = R^{k−1} ∫_R^∞ s^{−k} T ds = φ T_w,   φ(s) = k_{k−1}(x) / (x k_k(x)),  x = qR.
//!
//! (For |x| ≫ k, φ → 1/x = δ/R with δ = √(ν/s): the boundary-layer closure.) The three linear
//! equations for (a, b, T_w) then have the determinant [`LinearMode::determinant`]:
//!
//!   (N)  [s² + (k+1)/(ρR)(2η(k+2)s/R + S1)] a + (k+1)S2/(ρR) b + (k+1)kη(1 − 2(k+1)φ)/(ρR²) T_w = 0
//!   (TS) [−2(k+2)s/(k+1) + R S11/η] a + (R S12/η) b + (1 + 2φ) T_w = 0
//!   (NS) s/(k+1) a + s b − φ T_w = 0
//!
//! whose roots s = −γ ± iω are the damped shape modes. The same determinant with φ from the
//! discretised vorticity operator gives the eigenvalues of the method-of-lines system exactly
//! (see [`super::vorticity::linear`]), and with φ = δ_k/R it is the boundary-layer closure.

use nalgebra::Complex;

/// Complex number type of this module.
pub type C64 = Complex<f64>;

/// The linear, per-mode coefficients at R0 (any consistent units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearMode {
    pub k: usize,
    pub rho: f64,
    pub eta: f64,
    pub r0: f64,
    /// ∂G_n/∂a_k, ∂G_n/∂b_k, ∂G_t/∂a_k, ∂G_t/∂b_k at R0.
    pub s1: f64,
    pub s2: f64,
    pub s11: f64,
    pub s12: f64,
}

impl LinearMode {
    /// Inviscid natural frequency squared, (k+1)/(ρR0)(S1 − S2 S11/S12) (corrected 3.10, §4.4).
    pub fn omega2_inviscid(&self) -> f64 {
        (self.k as f64 + 1.0) / (self.rho * self.r0) * (self.s1 - self.s2 * self.s11 / self.s12)
    }

    /// Determinant of the (N, TS, NS) system at growth rate s with Ĩ = φ T_w.
    pub fn determinant(&self, s: C64, phi: C64) -> C64 {
        let k = self.k as f64;
        let (rho, eta, r) = (self.rho, self.eta, self.r0);
        let c = (k + 1.0) / (rho * r);
        let one = C64::new(1.0, 0.0);
        let m = [
            [
                s * s + (s * (2.0 * eta * (k + 2.0) / r) + self.s1) * c,
                C64::new(c * self.s2, 0.0),
                (one - phi * (2.0 * (k + 1.0))) * (c * k * eta / r),
            ],
            [s * (-2.0 * (k + 2.0) / (k + 1.0)) + r * self.s11 / eta, C64::new(r * self.s12 / eta, 0.0), one + phi * 2.0],
            [s / (k + 1.0), s, -phi],
        ];
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    }

    /// φ of the exact (continuous, unbounded) vorticity field: k_{k−1}(x)/(x k_k(x)), x = R0 √(s/ν).
    pub fn phi_exact(&self, s: C64) -> C64 {
        let nu = self.eta / self.rho;
        let x = (s / nu).sqrt() * self.r0; // principal branch: Re x ≥ 0
        bessel_k_ratio(self.k, x) / x
    }

    /// Exact damped root near `guess` (s = −γ + iω with ω > 0).
    pub fn exact_root(&self, guess: C64) -> Option<C64> {
        secant(|s| self.determinant(s, self.phi_exact(s)), guess, 1e-13, 100)
    }
}

/// k_{n−1}(x)/k_n(x) for the modified spherical Bessel functions of the second kind
/// (the common factor (π/2) e^{−x}/x cancels): k_n ∝ Σ_{j=0}^{n} (n+j)!/(j!(n−j)!) (2x)^{−j}.
pub fn bessel_k_ratio(n: usize, x: C64) -> C64 {
    let poly = |n: usize| -> C64 {
        // Horner in u = 1/(2x), coefficients c_j = (n+j)!/(j!(n−j)!)
        let u = C64::new(1.0, 0.0) / (x * 2.0);
        let coeff = |j: usize| -> f64 {
            let mut c = 1.0;
            for i in (n - j + 1)..=(n + j) {
                c *= i as f64;
            }
            for i in 1..=j {
                c /= i as f64;
            }
            c
        };
        let mut acc = C64::new(0.0, 0.0);
        for j in (0..=n).rev() {
            acc = acc * u + coeff(j);
        }
        acc
    };
    poly(n - 1) / poly(n)
}

/// Complex secant iteration for f(s) = 0 from `guess` (second point a relative 1e-4 away).
/// Stops when the step is below `tol`·|s|. Returns `None` if it does not converge or goes non-finite.
pub fn secant(f: impl Fn(C64) -> C64, guess: C64, tol: f64, max_iter: usize) -> Option<C64> {
    let mut s0 = guess;
    let mut s1 = guess * C64::new(1.0 + 1e-4, 1e-4);
    let mut f0 = f(s0);
    let mut f1 = f(s1);
    for _ in 0..max_iter {
        let den = f1 - f0;
        if den.norm() == 0.0 {
            return if f1.norm() == 0.0 { Some(s1) } else { None };
        }
        let s2 = s1 - f1 * (s1 - s0) / den;
        if !(s2.re.is_finite() && s2.im.is_finite()) {
            return None;
        }
        if (s2 - s1).norm() <= tol * s2.norm() {
            return Some(s2);
        }
        s0 = s1;
        f0 = f1;
        s1 = s2;
        f1 = f(s1);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bessel_ratio_matches_closed_forms() {
        // k_0 ∝ e^{-x}/x, k_1 ∝ e^{-x}(1 + 1/x)/x, k_2 ∝ e^{-x}(1 + 3/x + 3/x²)/x
        let x = C64::new(2.3, 0.7);
        let k0 = C64::new(1.0, 0.0);
        let k1 = C64::new(1.0, 0.0) + x.inv();
        let k2 = C64::new(1.0, 0.0) + x.inv() * 3.0 + (x * x).inv() * 3.0;
        assert!((bessel_k_ratio(1, x) - k0 / k1).norm() < 1e-14);
        assert!((bessel_k_ratio(2, x) - k1 / k2).norm() < 1e-14);
    }

    #[test]
    fn inviscid_limit_gives_the_corrected_natural_frequency() {
        let m = LinearMode { k: 2, rho: 1000.0, eta: 1e-9, r0: 1e-5, s1: 2.0e9, s2: -1.0e9, s11: -1.0e9, s12: 1.5e9 };
        let w = m.omega2_inviscid().sqrt();
        let root = m.exact_root(C64::new(0.0, w)).unwrap();
        assert!((root.im / w - 1.0).abs() < 1e-3, "{root} vs {w}");
        assert!(root.re < 0.0 && -root.re < 1e-2 * w);
    }
}
