//! The radial equation (paper eq 2.62, corrected: FORMULATION §4.1): its *form* turns the
//! pressure balance P = p_in − p∞(t) − 4ηṘ/R − Ŝ0(R) + M0 + … (the sum of the terms,
//! [`super::effects`]) into R̈. Today's form is the incompressible Rayleigh–Plesset one,
//! ρ(R R̈ + 3/2 Ṙ²) = P. The compressible form (Keller–Miksis, issue 10,
//! [`super::keller_miksis`]) multiplies P by (1 + Ṙ/c) and adds (R/c) dP/dt: it asks for the
//! pressure's rate ([`RadialForm::needs_rate`], [`PressureRate`] from the terms).

use super::effects::PressureRate;
use super::equations::Equations;
use crate::integrate::OdeSystem;

/// How R̈ follows from the pressure balance P.
pub trait RadialForm: std::fmt::Debug {
    fn name(&self) -> &'static str;
    /// R̈ at (R, Ṙ) given P.
    fn acceleration(&self, rho: f64, r: f64, rd: f64, pressure: f64) -> f64;
    /// (∂R̈/∂R, ∂R̈/∂Ṙ, ∂R̈/∂P) at (R, Ṙ, P).
    fn partials(&self, rho: f64, r: f64, rd: f64, pressure: f64) -> (f64, f64, f64);
    /// Whether R̈ depends on dP/dt = q + s R̈ ([`PressureRate`]); `false`: only P is evaluated
    /// and [`acceleration`](Self::acceleration), [`partials`](Self::partials) are used.
    fn needs_rate(&self) -> bool {
        false
    }
    /// R̈ given P and its rate (forms with [`needs_rate`](Self::needs_rate)).
    fn acceleration_rate(&self, rho: f64, r: f64, rd: f64, pressure: f64, _rate: &PressureRate) -> f64 {
        self.acceleration(rho, r, rd, pressure)
    }
    /// Explicit (∂R̈/∂R, ∂R̈/∂Ṙ, ∂R̈/∂P, ∂R̈/∂q, ∂R̈/∂s) at (R, Ṙ, P, q, s).
    fn partials_rate(&self, rho: f64, r: f64, rd: f64, pressure: f64, _rate: &PressureRate) -> [f64; 5] {
        let (a, b, c) = self.partials(rho, r, rd, pressure);
        [a, b, c, 0.0, 0.0]
    }
}

/// Incompressible liquid: R̈ = P/(ρR) − 3Ṙ²/(2R) (eq 2.62).
#[derive(Debug, Clone, Copy, Default)]
pub struct Incompressible;

impl RadialForm for Incompressible {
    fn name(&self) -> &'static str {
        "incompressible"
    }
    #[inline]
    fn acceleration(&self, rho: f64, r: f64, rd: f64, pressure: f64) -> f64 {
        pressure / (rho * r) - 1.5 * rd * rd / r
    }
    fn partials(&self, rho: f64, r: f64, rd: f64, pressure: f64) -> (f64, f64, f64) {
        (-pressure / (rho * r * r) + 1.5 * rd * rd / (r * r), -3.0 * rd / r, 1.0 / (rho * r))
    }
}

/// Radial motion alone (max_order = 0): y = [R, Ṙ], or y = [R, Ṙ, p_b] with the reduced
/// thermal model (`gas`: the gas slot of [`super::layout::StateLayout::with_gas`];
/// docs/model.md, "Reduced thermal model"). With a field, only the zero-order magnetic load ℋ0
/// acts (there are no a_2, b_2).
#[derive(Debug)]
pub struct RadialSystem {
    pub(crate) eq: Equations,
    /// The reduced thermal model's ṗ_b (the same law as the gas term `eq.terms[0]`).
    pub(crate) gas: Option<super::effects::reduced_gas::ReducedGas>,
    /// R̈ with the terms dispatched statically (Keller–Miksis scenes whose terms all have a
    /// kernel; the same bits as `eq.radial_acceleration`: [`super::radial_fused`]).
    pub(crate) fused: Option<super::radial_fused::FusedRadial>,
}

impl RadialSystem {
    pub fn equations(&self) -> &Equations {
        &self.eq
    }
}

impl OdeSystem for RadialSystem {
    fn dim(&self) -> usize {
        2 + usize::from(self.gas.is_some())
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = match &self.fused {
            Some(f) => f.acceleration(t, y),
            None => self.eq.radial_acceleration(t, y),
        };
        if let Some(g) = &self.gas {
            dy[2] = g.rate(y[0], y[1], y[2]);
        }
    }
    fn bandwidth(&self) -> Option<(usize, usize)> {
        match self.gas {
            None => Some((1, 1)),
            // ṗ_b depends on R: the 3 × 3 Jacobian is dense
            Some(_) => None,
        }
    }
    /// Exact: [[0, 1], ∂R̈/∂(R, Ṙ)] from the terms' gradients and the radial form; with the gas
    /// slot, ∂R̈/∂p_b (P ∋ p_b, and the rate's q ∋ ṗ_b for Keller–Miksis) and ṗ_b's row.
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut [f64]) -> bool {
        let mut lj = super::effects::LoadJacobian::new(0);
        self.eq.load_jacobian(t, y, &mut lj);
        let p = self.eq.loads(t, y, &mut [], &mut []);
        let mut g = [0.0; 2];
        let form = self.eq.acceleration_gradient_at(t, y, p, &lj.pressure, &mut g);
        let Some(gas) = &self.gas else {
            jac[..4].copy_from_slice(&[0.0, 1.0, g[0], g[1]]);
            return true;
        };
        let (_, d) = gas.rate_partials(y[0], y[1], y[2]);
        // ∂R̈/∂p_b: through P (∂P/∂p_b = 1) and, for Keller–Miksis, the rate's q ∋ ṗ_b
        let g2 = form[2] + form[3] * d[2];
        jac[..9].copy_from_slice(&[0.0, 1.0, 0.0, g[0], g[1], g2, d[0], d[1], d[2]]);
        true
    }
}
