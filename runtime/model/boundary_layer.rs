//! The boundary-layer model (paper §3, eqs 3.1–3.2; FORMULATION §4.3) as an explicit ODE.
//!
//! State y = [R, Ṙ, (a_k, ȧ_k, b_k) for k = 2, 4, …, N], dimension 2 + 3M. Per mode, with
//! δ_k = min(√(ν/ω), R/(2k)) (eq 3.1; ω per FORMULATION audit 13), G_n = Ŝ1 a + Ŝ2 b − M_n,k,
//! G_t = Ŝ11 a + Ŝ12 b − M_t,k (εF^mem, audit 1):
//!
//! ```text
//! T_w = [2(k+2)ȧ/(k+1) + 2(1−k)Ṙa/((k+1)R) − R G_t/η] / (1 + 2δ/R)     (corrected 2.65, audit 3–4)
//! ḃ   = Ṙb/R − ȧ/(k+1) − 2Ṙa/((k+1)R) + δ T_w/R                          (2.67 with 3.1)
//! ä   = −[3Ṙȧ − (k−1)R̈a]/R − (k+1)/(ρR)[2η(k+2)ȧ/R + 4η(k−1)Ṙa/R²
//!        + (kηT_w/R)(1 − 2(k+1)δ/R) + G_n]                                 (2.64 × (k+1)/(ρR), audit 2, 5)
//! ```
//! R̈ enters ä_k, so the radial equation (§4.1) is evaluated first.

use nalgebra::{DMatrix, DVector};

use super::params::Params;
use super::radial::radial_acceleration;
use crate::field::loads::{Factors, MagneticLoads};
use crate::integrate::OdeSystem;

/// Per-mode constants.
#[derive(Debug, Clone, Copy)]
pub struct ModeConst {
    /// k as f64
    pub k: f64,
    /// √(ν/ω) (nondimensional): the viscous length of δ_k before the R/(2k) cap.
    pub viscous_length: f64,
}

/// Radial + shape modes with the boundary-layer closure, optionally with magnetic loads.
#[derive(Debug)]
pub struct BoundaryLayerSystem {
    pub(crate) params: Params,
    pub(crate) modes: Vec<ModeConst>,
    pub(crate) loads: Option<MagneticLoads>,
}

impl BoundaryLayerSystem {
    /// δ_k = min(√(ν/ω), R/(2k)) (eq 3.1).
    #[inline]
    pub fn delta(&self, m: usize, r: f64) -> f64 {
        let mc = self.modes[m];
        mc.viscous_length.min(r / (2.0 * mc.k))
    }

    /// Writes (ȧ_k, ä_k, ḃ_k) for every mode into `dy[2..]`, for given R, Ṙ, R̈ (the radial
    /// entries of `y` are not read). Linear in the mode amplitudes.
    #[inline]
    pub fn mode_rates(&self, t: f64, r: f64, rd: f64, rdd: f64, f: Option<&Factors>, y: &[f64], dy: &mut [f64]) {
        let p = &self.params;
        let mem = &p.membrane;
        let _ = t;
        for (m, mc) in self.modes.iter().enumerate() {
            let k = mc.k;
            let i = 2 + 3 * m;
            let (a, ad, b) = (y[i], y[i + 1], y[i + 2]);
            let (mn, mt) = match (f, &self.loads) {
                (Some(f), Some(l)) => (l.normal(f, m, y), l.tangential(f, m, y)),
                _ => (0.0, 0.0),
            };
            let gn = (mem.s1)(r, p.r0, p.c1, p.c2, k) * a + (mem.s2)(r, p.r0, p.c1, p.c2, k) * b - mn;
            let gt = (mem.s11)(r, p.r0, p.c1, p.c2, k) * a + (mem.s12)(r, p.r0, p.c1, p.c2, k) * b - mt;
            let delta = mc.viscous_length.min(r / (2.0 * k));
            let kp1 = k + 1.0;
            let tw = (2.0 * (k + 2.0) * ad / kp1 + 2.0 * (1.0 - k) * rd * a / (kp1 * r) - r * gt / p.eta)
                / (1.0 + 2.0 * delta / r);
            let bd = rd * b / r - ad / kp1 - 2.0 * rd * a / (kp1 * r) + delta * tw / r;
            let add = -(3.0 * rd * ad - (k - 1.0) * rdd * a) / r
                - kp1 / (p.rho * r)
                    * (2.0 * p.eta * (k + 2.0) * ad / r
                        + 4.0 * p.eta * (k - 1.0) * rd * a / (r * r)
                        + (k * p.eta * tw / r) * (1.0 - 2.0 * kp1 * delta / r)
                        + gn);
            dy[i] = ad;
            dy[i + 1] = add;
            dy[i + 2] = bd;
        }
    }

    /// The linear mode system at prescribed (t, R, Ṙ, R̈): x' = A x + g with
    /// x = (a_k, ȧ_k, b_k)_k (dimension 3M, state order), nondimensional. For the Floquet and
    /// frequency analyses (FORMULATION §4.6): R(t) is prescribed, so M0's coupling to a_2, b_2
    /// is not part of it. g holds the magnetic forcing ℋ2, ℋ¹2 (zero without a field).
    pub fn linear_modes(&self, t: f64, r: f64, rd: f64, rdd: f64) -> (DMatrix<f64>, DVector<f64>) {
        let n = 3 * self.modes.len();
        let mut y = vec![0.0; 2 + n];
        y[0] = r;
        y[1] = rd;
        let mut dy = vec![0.0; 2 + n];
        let f = self.loads.as_ref().map(|l| l.factors(t, r));
        self.mode_rates(t, r, rd, rdd, f.as_ref(), &y, &mut dy);
        let g = DVector::from_column_slice(&dy[2..]);
        let mut a = DMatrix::zeros(n, n);
        for j in 0..n {
            y[2 + j] = 1.0;
            self.mode_rates(t, r, rd, rdd, f.as_ref(), &y, &mut dy);
            for i in 0..n {
                a[(i, j)] = dy[2 + i] - g[i];
            }
            y[2 + j] = 0.0;
        }
        (a, g)
    }

    /// R̈ at state y (M0 included), nondimensional.
    pub fn radial_acceleration(&self, t: f64, y: &[f64]) -> f64 {
        let m0 = match &self.loads {
            None => 0.0,
            Some(l) => l.radial(&l.factors(t, y[0]), y),
        };
        radial_acceleration(&self.params, t, y[0], y[1], m0)
    }
}

impl OdeSystem for BoundaryLayerSystem {
    fn dim(&self) -> usize {
        2 + 3 * self.modes.len()
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let (r, rd) = (y[0], y[1]);
        let (f, m0) = match &self.loads {
            None => (None, 0.0),
            Some(l) => {
                let f = l.factors(t, r);
                let m0 = l.radial(&f, y);
                (Some(f), m0)
            }
        };
        let rdd = radial_acceleration(&self.params, t, r, rd, m0);
        dy[0] = rd;
        dy[1] = rdd;
        self.mode_rates(t, r, rd, rdd, f.as_ref(), y, dy);
    }
}
