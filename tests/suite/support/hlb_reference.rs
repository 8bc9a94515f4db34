//! The independent reference of the HLB parametric-instability check (tests/suite/hlb_parametric.rs,
//! whose module doc describes it; examples/hlb_threshold_table.rs prints its threshold table):
//! the radial equations (magbubble's Keller–Miksis form, HLB's Rayleigh–Plesset with the radiation
//! term and a hard core) and the n = 2 mode equation ä + B ȧ − A a = 0 (magbubble's and HLB's
//! (B, A)), integrated with the tests' own Dormand–Prince ([`super::dopri_ref`]); the Floquet
//! multiplier of the orbit reached from rest and the threshold where it crosses 1.

#![allow(dead_code)] // the threshold scan and the hard-core radial form serve the example

use super::dopri_ref::dopri5;
use std::f64::consts::PI;

pub const RHO: f64 = 1000.0;
pub const ETA: f64 = 1e-3;
pub const NU: f64 = ETA / RHO;
pub const SIGMA: f64 = 0.073;
pub const C: f64 = 1481.0;
pub const P0: f64 = 101325.0;
pub const F: f64 = 26.5e3;
pub const KAPPA: f64 = 1.0;
pub const N: f64 = 2.0;
/// Transient before the Floquet period, in drive periods (the orbit's R(T) − R(0) is checked).
pub const TRANSIENT: usize = 40;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Radial {
    Km,
    HlbRp,
}
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    Magbubble,
    Hlb,
}

#[derive(Clone, Copy, Debug)]
pub struct Case {
    pub r0: f64,
    pub eps: f64,
    pub radial: Radial,
    pub shape: Shape,
}

pub fn omega() -> f64 {
    2.0 * PI * F
}

impl Case {
    /// R̈ [m/s²] at (t, R, Ṙ) in SI.
    pub fn rddot(&self, t: f64, r: f64, v: f64) -> f64 {
        let (w, r0) = (omega(), self.r0);
        let pg0 = P0 + 2.0 * SIGMA / r0;
        let pinf = P0 * (1.0 + self.eps * (w * t).cos());
        let dpinf = -P0 * self.eps * w * (w * t).sin();
        match self.radial {
            Radial::Km => {
                let pg = pg0 * (r0 / r).powf(3.0 * KAPPA);
                let p = pg - pinf - 2.0 * SIGMA / r - 4.0 * ETA * v / r;
                let q = -3.0 * KAPPA * pg * v / r - dpinf + 2.0 * SIGMA * v / (r * r) + 4.0 * ETA * v * v / (r * r);
                let s = -4.0 * ETA / r;
                let num = (1.0 + v / C) * p / RHO + r * q / (RHO * C) - 1.5 * (1.0 - v / (3.0 * C)) * v * v;
                num / ((1.0 - v / C) * r - r * s / (RHO * C))
            }
            Radial::HlbRp => {
                let h3 = (r0 / 8.86).powi(3);
                let pg = pg0 * ((r0.powi(3) - h3) / (r.powi(3) - h3)).powf(KAPPA);
                let dpg = -3.0 * KAPPA * pg * r * r * v / (r.powi(3) - h3);
                let rhs = pg - pinf + r * dpg / C - 4.0 * ETA * v / r - 2.0 * SIGMA / r;
                (rhs / RHO - 1.5 * v * v) / r
            }
        }
    }

    /// (B, A) of ä + B ȧ − A a = 0 at (R, Ṙ, R̈).
    pub fn coefficients(&self, r: f64, v: f64, acc: f64) -> (f64, f64) {
        let delta = (NU / omega()).sqrt().min(r / (2.0 * N));
        let beta = (N - 1.0) * (N + 1.0) * (N + 2.0);
        let (b_visc, a_visc) = match self.shape {
            Shape::Magbubble => {
                let (d, e) = (1.0 + 2.0 * delta / r, 1.0 - 2.0 * (N + 1.0) * delta / r);
                ((N + 1.0) * (N + 2.0) + N * (N + 2.0) * e / d, (N - 1.0) * (2.0 * (N + 1.0) - N * e / d))
            }
            Shape::Hlb => (
                (N + 2.0) * (2.0 * N + 1.0) - 2.0 * N * (N + 2.0).powi(2) * delta / r,
                (N - 1.0) * (N + 2.0) + 2.0 * N * (N + 2.0) * (N - 1.0) * delta / r,
            ),
        };
        let b = 3.0 * v / r + 2.0 * NU / (r * r) * b_visc;
        let a = (N - 1.0) * acc / r - beta * SIGMA / (RHO * r.powi(3)) - 2.0 * NU * v / r.powi(3) * a_visc;
        (b, a)
    }

    /// y' in the scaled state [R/R0, Ṙ/(R0ω), (a, ȧ/ω) per column], τ = ωt.
    pub fn rhs(&self, tau: f64, y: &[f64], dy: &mut [f64]) {
        let w = omega();
        let (r, v) = (y[0] * self.r0, y[1] * self.r0 * w);
        let acc = self.rddot(tau / w, r, v);
        dy[0] = y[1];
        dy[1] = acc / (self.r0 * w * w);
        let (b, a) = self.coefficients(r, v, acc);
        for c in (2..y.len()).step_by(2) {
            dy[c] = y[c + 1];
            dy[c + 1] = -b / w * y[c + 1] + a / (w * w) * y[c];
        }
    }

    /// max|μ| over one drive period after `TRANSIENT` periods from rest, and |R(T) − R(0)|/R0
    /// over that period (how periodic the orbit is).
    pub fn multiplier(&self) -> (f64, f64) {
        let f = |t: f64, y: &[f64], dy: &mut [f64]| self.rhs(t, y, dy);
        let (mut y, mut h) = (vec![1.0, 0.0], 1e-3);
        let tp = 2.0 * PI;
        dopri5(&f, 0.0, TRANSIENT as f64 * tp, &mut y, &mut h, 1e-11, 1e-13);
        let start = y[0];
        let mut z = vec![y[0], y[1], 1.0, 0.0, 0.0, 1.0];
        dopri5(&f, TRANSIENT as f64 * tp, (TRANSIENT + 1) as f64 * tp, &mut z, &mut h, 1e-11, 1e-13);
        let (m11, m21, m12, m22) = (z[2], z[3], z[4], z[5]);
        let (tr, det) = (m11 + m22, m11 * m22 - m12 * m21);
        let disc = tr * tr / 4.0 - det;
        let mu = if disc >= 0.0 { (tr / 2.0).abs() + disc.sqrt() } else { det.abs().sqrt() };
        (mu, (z[0] - start).abs())
    }
}

/// ε_p where max|μ| crosses `level` in [lo, hi] (bisection to `tol` relative; μ(lo) < level < μ(hi)).
pub fn threshold(mut case: Case, lo: f64, hi: f64, level: f64, tol: f64) -> f64 {
    let mut at = |e: f64| {
        case.eps = e;
        case.multiplier().0
    };
    let (mut a, mut b) = (lo, hi);
    assert!(at(a) < level && at(b) > level, "{case:?}: no crossing of {level} in [{lo}, {hi}]");
    while b - a > tol * b {
        let m = 0.5 * (a + b);
        if at(m) > level {
            b = m
        } else {
            a = m
        }
    }
    0.5 * (a + b)
}

pub fn scene_text(r0: f64) -> String {
    format!(
        "[bubble]\nradius = {r0:e}\n[shell]\nc1 = 0.0\nc2 = 0.0\nsurface_tension = {SIGMA}\n[liquid]\n\
         density = {RHO}\nviscosity = {ETA}\nambient_pressure = {P0}\nsound_speed = {C}\n[gas]\n\
         polytropic_exponent = {KAPPA}\n[drive]\namplitude = 1.0\nfrequency_hz = {F:e}\n[modes]\nmax_order = 2\n"
    )
}

/// The first crossing of max|μ| = 1 from below, scanning ε_p from 0.6 in steps of 0.02 and then
/// bisecting (1e-4 relative): the definition of magbubble's critical value.
pub fn first_threshold(case: Case) -> Option<f64> {
    let mut lo = 0.6;
    while lo < 1.5 {
        let hi = lo + 0.02;
        if (Case { eps: hi, ..case }).multiplier().0 > 1.0 {
            return Some(threshold(case, lo, hi, 1.0, 1e-4));
        }
        lo = hi;
    }
    None
}
