//! The Keller–Miksis radial equation (liquid compressibility, acoustic radiation damping;
//! issue 10; Keller & Miksis 1980, J. Acoust. Soc. Am. 68, 628, eq 2.6 in the form of
//! Prosperetti & Lezzi 1986): with P the pressure balance of the terms ([`super::effects`]) and
//! c the liquid's sound speed,
//!
//! ```text
//! (1 − Ṙ/c) R R̈ + (3/2)(1 − Ṙ/(3c)) Ṙ² = (1 + Ṙ/c) P/ρ + (R/(ρc)) dP/dt,
//! dP/dt = q + s R̈,   q = ∂P/∂t + ∂P/∂R Ṙ,   s = ∂P/∂Ṙ   (PressureRate)
//! ```
//! so that R̈ = N/D exactly (the equation is linear in R̈):
//! N = (1 + Ṙ/c) P/ρ + R q/(ρc) − (3/2)(1 − Ṙ/(3c)) Ṙ²,  D = (1 − Ṙ/c) R − R s/(ρc).
//! q contains −dp∞/dt (the drive's time derivative) and s the viscous −4η/R. c → ∞ gives the
//! incompressible eq 2.62. The shape-mode equations are unchanged (they stay incompressible:
//! docs/model.md, "Liquid and gas effects").

use super::effects::PressureRate;
use super::radial::RadialForm;

/// Keller–Miksis with sound speed c (nondimensional, c t*/R0).
#[derive(Debug, Clone, Copy)]
pub struct KellerMiksis {
    pub c: f64,
}

impl KellerMiksis {
    /// (N, D) of the module doc.
    #[inline]
    fn nd(&self, rho: f64, r: f64, rd: f64, p: f64, rate: &PressureRate) -> (f64, f64) {
        let c = self.c;
        let n = (1.0 + rd / c) * p / rho + r * rate.q / (rho * c) - 1.5 * (1.0 - rd / (3.0 * c)) * rd * rd;
        let d = (1.0 - rd / c) * r - r * rate.s / (rho * c);
        (n, d)
    }
}

impl RadialForm for KellerMiksis {
    fn name(&self) -> &'static str {
        "Keller-Miksis"
    }
    /// Without the rate (q = s = 0); the model always calls [`acceleration_rate`](Self::acceleration_rate).
    fn acceleration(&self, rho: f64, r: f64, rd: f64, pressure: f64) -> f64 {
        self.acceleration_rate(rho, r, rd, pressure, &PressureRate::default())
    }
    fn partials(&self, rho: f64, r: f64, rd: f64, pressure: f64) -> (f64, f64, f64) {
        let d = self.partials_rate(rho, r, rd, pressure, &PressureRate::default());
        (d[0], d[1], d[2])
    }
    fn needs_rate(&self) -> bool {
        true
    }
    #[inline]
    fn acceleration_rate(&self, rho: f64, r: f64, rd: f64, pressure: f64, rate: &PressureRate) -> f64 {
        let (n, d) = self.nd(rho, r, rd, pressure, rate);
        n / d
    }
    /// ∂(N/D)/∂x = (∂N/∂x − R̈ ∂D/∂x)/D for x = R, Ṙ, P, q, s.
    fn partials_rate(&self, rho: f64, r: f64, rd: f64, pressure: f64, rate: &PressureRate) -> [f64; 5] {
        let c = self.c;
        let (n, d) = self.nd(rho, r, rd, pressure, rate);
        let rdd = n / d;
        let n_x = [
            rate.q / (rho * c),
            pressure / (rho * c) - 3.0 * rd + 1.5 * rd * rd / c,
            (1.0 + rd / c) / rho,
            r / (rho * c),
            0.0,
        ];
        let d_x = [(1.0 - rd / c) - rate.s / (rho * c), -r / c, 0.0, 0.0, -r / (rho * c)];
        let mut out = [0.0; 5];
        for i in 0..5 {
            out[i] = (n_x[i] - rdd * d_x[i]) / d;
        }
        out
    }
}
