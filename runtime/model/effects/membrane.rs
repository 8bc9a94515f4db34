//! The lipid shell (Mooney–Rivlin, ε-scaled: FORMULATION §2, §4.1, audit 1): −Ŝ0(R) in the
//! radial balance and Ŝ1 a_k + Ŝ2 b_k, Ŝ11 a_k + Ŝ12 b_k in G_n,k, G_t,k. The coefficients and
//! their R-derivatives are the generated ones (`coefficients::membrane`, from derivations/),
//! chosen by `shell.form`; they depend on R and k only and are evaluated once per mode per call,
//! all modes in one call of `Membrane::modes` in the right-hand side.

use super::{At, LoadJacobian, Loads, PressureRate, Term};
use crate::model::params::Membrane;

#[derive(Debug, Clone)]
pub struct MembraneTerm {
    pub law: Membrane,
    pub r0: f64,
    pub c1: f64,
    pub c2: f64,
    /// k of each mode index.
    pub orders: Vec<f64>,
}

/// Ŝ1, Ŝ2, Ŝ11, Ŝ12 of one mode at one R (FORMULATION §4.1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModeStiffness {
    pub s1: f64,
    pub s2: f64,
    pub s11: f64,
    pub s12: f64,
}

impl MembraneTerm {
    /// Ŝ1, Ŝ2, Ŝ11, Ŝ12 of mode k at R.
    #[inline]
    pub fn stiffness(&self, r: f64, k: f64) -> ModeStiffness {
        let (law, r0, c1, c2) = (&self.law, self.r0, self.c1, self.c2);
        ModeStiffness {
            s1: (law.s1)(r, r0, c1, c2, k),
            s2: (law.s2)(r, r0, c1, c2, k),
            s11: (law.s11)(r, r0, c1, c2, k),
            s12: (law.s12)(r, r0, c1, c2, k),
        }
    }
    /// Their R-derivatives.
    pub fn stiffness_dr(&self, r: f64, k: f64) -> ModeStiffness {
        let (law, r0, c1, c2) = (&self.law, self.r0, self.c1, self.c2);
        ModeStiffness {
            s1: (law.s1_dr)(r, r0, c1, c2, k),
            s2: (law.s2_dr)(r, r0, c1, c2, k),
            s11: (law.s11_dr)(r, r0, c1, c2, k),
            s12: (law.s12_dr)(r, r0, c1, c2, k),
        }
    }
}

impl Term for MembraneTerm {
    fn name(&self) -> &'static str {
        "membrane"
    }
    #[inline]
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>) {
        let r = at.r();
        loads.pressure -= (self.law.s0)(r, self.r0, self.c1, self.c2);
        let nm = loads.gn.len();
        // the modes' Ŝ1, Ŝ2, Ŝ11, Ŝ12 eight at a time (`Membrane::modes`: the powers of R once
        // per call; a small stack buffer)
        const CHUNK: usize = 8;
        for (c, ks) in self.orders[..nm].chunks(CHUNK).enumerate() {
            let mut s = [[0.0; 4]; CHUNK];
            (self.law.modes)(r, self.r0, self.c1, self.c2, ks, &mut s[..ks.len()]);
            for (j, s) in s[..ks.len()].iter().enumerate() {
                let m = c * CHUNK + j;
                let (a, b) = (at.a(m), at.b(m));
                loads.gn[m] += s[0] * a + s[1] * b;
                loads.gt[m] += s[2] * a + s[3] * b;
            }
        }
    }
    fn add_pressure_gradient(&self, at: &At<'_>, dp: &mut [f64; 2]) {
        dp[0] -= (self.law.s0_dr)(at.r(), self.r0, self.c1, self.c2);
    }
    fn add_jacobian(&self, at: &At<'_>, jac: &mut LoadJacobian) {
        let r = at.r();
        let n = jac.n;
        jac.pressure[0] -= (self.law.s0_dr)(r, self.r0, self.c1, self.c2);
        // the modes' Ŝ and Ŝ′ eight at a time, as in `add` (`Membrane::modes`, `modes_dr`: the
        // same generated functions, the same values as `stiffness`, `stiffness_dr` per mode)
        const CHUNK: usize = 8;
        let lay = jac.layout();
        for (c, ks) in self.orders[..jac.modes()].chunks(CHUNK).enumerate() {
            let (mut s, mut d) = ([[0.0; 4]; CHUNK], [[0.0; 4]; CHUNK]);
            (self.law.modes)(r, self.r0, self.c1, self.c2, ks, &mut s[..ks.len()]);
            (self.law.modes_dr)(r, self.r0, self.c1, self.c2, ks, &mut d[..ks.len()]);
            for (j, (s, d)) in s[..ks.len()].iter().zip(&d[..ks.len()]).enumerate() {
                let m = c * CHUNK + j;
                let (a, b) = (at.a(m), at.b(m));
                let (ia, ib) = (lay.a(m), lay.b(m));
                let (gn, gt) = (&mut jac.gn[m * n..(m + 1) * n], &mut jac.gt[m * n..(m + 1) * n]);
                gn[0] += d[0] * a + d[1] * b;
                gt[0] += d[2] * a + d[3] * b;
                gn[ia] += s[0];
                gn[ib] += s[1];
                gt[ia] += s[2];
                gt[ib] += s[3];
            }
        }
    }
    /// P = −Ŝ0(R): q = −Ŝ0′(R) Ṙ (generated Ŝ0′), s = 0. ∂q/∂R = −Ŝ0″(R) Ṙ: codegen emits no
    /// second derivative, so Ŝ0″ is the central difference of the generated Ŝ0′ (step 1e-5 R,
    /// relative error ~1e-10): the one non-analytic entry of the Keller–Miksis Jacobian.
    fn add_rate(&self, at: &At<'_>, rate: &mut PressureRate) -> bool {
        let (r, rd) = (at.r(), at.rdot());
        let d1 = |x: f64| (self.law.s0_dr)(x, self.r0, self.c1, self.c2);
        let h = 1e-5 * r;
        let d2 = (d1(r + h) - d1(r - h)) / (2.0 * h);
        rate.q -= d1(r) * rd;
        rate.dq[0] -= d2 * rd;
        rate.dq[1] -= d1(r);
        true
    }
}
