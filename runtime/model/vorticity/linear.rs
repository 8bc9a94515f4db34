//! The full model linearised at rest at R0 (Ṙ = R̈ = 0, a = b = 0): per mode k the states
//! (a, ȧ, b, T-nodes). Its eigenvalues are the roots of the determinant of
//! [`crate::model::dispersion`] with φ_d(s) = Ĩ/T_w of the *discretised* vorticity operator:
//! φ_d(s) = w_0 + Σ_{i≥1} W_i g_i with (sI − L) g = L_{1,wall} e_1 (one complex Thomas solve).
//! This gives the damped spectrum of the method-of-lines system exactly without a dense
//! eigen-decomposition of the (3 + n − 2)-square matrix.
//!
//! Mode-to-mode field couplings (k ± 2) are left out of the per-k spectrum; the magnetic
//! diagonal (ℋF1(k), ℋF2(k), …) is included through the linear loads.

use super::operator::{thomas, ModeOperator, Rows};
use super::{Grid, ModeCoupling};
use crate::model::dispersion::{secant, LinearMode, C64};

/// One damped shape mode s = −γ ± iω (time unit of the coupling, SI for scenes).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct DampedMode {
    pub k: usize,
    /// γ = −Re s [1/s]
    pub decay_per_s: f64,
    /// ω = Im s ≥ 0 [rad/s]
    pub omega_rad_s: f64,
}

impl DampedMode {
    pub fn from_root(k: usize, s: C64) -> Self {
        Self { k, decay_per_s: -s.re, omega_rad_s: s.im.abs() }
    }
}

/// Linear coefficients (S1, S2, S11, S12 with the magnetic diagonal) of every mode of a coupling
/// at (t, R0), from its exact linear structure ([`ModeCoupling::mode_stiffness`]).
pub fn linear_modes(c: &dyn ModeCoupling, t: f64, r0: f64) -> Vec<LinearMode> {
    c.orders()
        .iter()
        .zip(c.mode_stiffness(t, r0))
        .map(|(&k, [s1, s2, s11, s12])| LinearMode { k, rho: c.density(), eta: c.viscosity(), r0, s1, s2, s11, s12 })
        .collect()
}

/// φ_d(s) of the discrete operator on `grid` at rest at `r0`.
pub fn phi_discrete(op: &ModeOperator, rows: &Rows, s: C64) -> C64 {
    let n = op.interior();
    let lower: Vec<C64> = rows.lower.iter().map(|&v| C64::new(-v, 0.0)).collect();
    let upper: Vec<C64> = rows.upper.iter().map(|&v| C64::new(-v, 0.0)).collect();
    let diag: Vec<C64> = rows.diag.iter().map(|&v| s - v).collect();
    let mut g = vec![C64::new(0.0, 0.0); n];
    g[0] = C64::new(rows.lower[0], 0.0);
    let mut scratch = vec![C64::new(0.0, 0.0); n];
    if !thomas(&lower, &diag, &upper, &mut g, &mut scratch) {
        return C64::new(f64::NAN, f64::NAN);
    }
    let mut phi = C64::new(op.w0(), 0.0);
    for (gi, w) in g.iter().zip(&op.wi[1..]) {
        phi += gi * *w;
    }
    phi
}

/// The root of the discretised full model near `guess`.
pub fn full_root(mode: &LinearMode, grid: &Grid, guess: C64) -> Option<C64> {
    let op = ModeOperator::new(grid, mode.k);
    let mut rows = Rows::default();
    op.rows(mode.r0, 0.0, mode.eta / mode.rho, &mut rows);
    secant(|s| mode.determinant(s, phi_discrete(&op, &rows, s)), guess, 1e-13, 200)
}

/// The root of the boundary-layer closure (φ = δ/R0, FORMULATION §4.3) near `guess`.
pub fn boundary_layer_root(mode: &LinearMode, delta: f64, guess: C64) -> Option<C64> {
    let phi = C64::new(delta / mode.r0, 0.0);
    secant(|s| mode.determinant(s, phi), guess, 1e-13, 200)
}

/// Starting point of the root searches: the inviscid frequency, or a weakly damped guess when
/// the quasi-static stiffness is not positive (then the mode is statically unstable and the
/// search starts on the real axis).
pub fn initial_guess(mode: &LinearMode) -> C64 {
    let w2 = mode.omega2_inviscid();
    if w2 > 0.0 {
        C64::new(-1e-3 * w2.sqrt(), w2.sqrt())
    } else {
        C64::new((-w2).sqrt(), 0.0)
    }
}

/// Damped spectrum of the full model, one mode per k (the least damped oscillatory root near
/// the inviscid frequency). The search is continued from the exact (continuous) root, which is
/// close to the discrete one for a converged grid.
pub fn damped_spectrum_full(c: &dyn ModeCoupling, grid: &Grid, t: f64, r0: f64) -> Vec<Option<DampedMode>> {
    linear_modes(c, t, r0)
        .iter()
        .map(|m| {
            let g = initial_guess(m);
            let g = m.exact_root(g).unwrap_or(g);
            full_root(m, grid, g).map(|s| DampedMode::from_root(m.k, s))
        })
        .collect()
}

/// Damped spectrum of the boundary-layer closure; `delta(k, ω_k)` gives δ_k.
pub fn damped_spectrum_boundary_layer(
    c: &dyn ModeCoupling,
    t: f64,
    r0: f64,
    delta: impl Fn(usize, f64) -> f64,
) -> Vec<Option<DampedMode>> {
    linear_modes(c, t, r0)
        .iter()
        .map(|m| {
            let g = initial_guess(m);
            let d = delta(m.k, g.im.abs());
            boundary_layer_root(m, d, g).map(|s| DampedMode::from_root(m.k, s))
        })
        .collect()
}

/// A coupling that is the linearisation at R0 itself: R held at R0 (R̈ = 0; without field or
/// drive the radial equation has R ≡ R0 as its solution, and a, b do not enter it), loads
/// G_n = S1 a + S2 b, G_t = S11 a + S12 b per mode. Used for the free-decay checks.
pub struct LinearCoupling {
    pub orders: Vec<usize>,
    pub modes: Vec<LinearMode>,
}

impl LinearCoupling {
    pub fn new(modes: Vec<LinearMode>) -> Self {
        Self { orders: modes.iter().map(|m| m.k).collect(), modes }
    }
}

impl ModeCoupling for LinearCoupling {
    fn orders(&self) -> &[usize] {
        &self.orders
    }
    fn density(&self) -> f64 {
        self.modes.first().map_or(1.0, |m| m.rho)
    }
    fn viscosity(&self) -> f64 {
        self.modes.first().map_or(1.0, |m| m.eta)
    }
    fn radial_acceleration(&self, _t: f64, _r: f64, _rdot: f64, _a: &[f64], _adot: &[f64], _b: &[f64]) -> f64 {
        0.0
    }
    fn linearize(&self, _t: f64, _z: &[f64], drdd: &mut [f64], jac: &mut crate::model::effects::LoadJacobian) {
        drdd.fill(0.0);
        jac.clear();
        let (n, l) = (jac.n, jac.layout());
        for (m, md) in self.modes.iter().enumerate() {
            let (ia, ib) = (l.a(m), l.b(m));
            jac.gn[m * n + ia] = md.s1;
            jac.gn[m * n + ib] = md.s2;
            jac.gt[m * n + ia] = md.s11;
            jac.gt[m * n + ib] = md.s12;
        }
    }
    fn mode_stiffness(&self, _t: f64, _r: f64) -> Vec<[f64; 4]> {
        self.modes.iter().map(|m| [m.s1, m.s2, m.s11, m.s12]).collect()
    }
    fn shape_loads(&self, _t: f64, _r: f64, _rdot: f64, a: &[f64], _adot: &[f64], b: &[f64], gn: &mut [f64], gt: &mut [f64]) {
        for (m, md) in self.modes.iter().enumerate() {
            gn[m] = md.s1 * a[m] + md.s2 * b[m];
            gt[m] = md.s11 * a[m] + md.s12 * b[m];
        }
    }
}
