//! The shell effects beyond the elastic law, each off unless its scene key is set (issue 11,
//! issue 10 part 2). Every coefficient is generated (`coefficients::membrane::<law>`, from
//! derivations/shell/):
//!
//! * surface tension γ (`surface_tension.rs`, tension form): −2γ/R in the radial balance,
//!   (k−1)(k+2)γ/R² a_k on G_n,k, nothing on b_k or G_t;
//! * Helfrich bending k_b (`bending.rs`, first variation of (k_b/2)∫(κ1+κ2)² dA):
//!   (k−1)k(k+1)(k+2)k_b/R⁴ a_k on G_n,k, no radial load;
//! * surface dilatational and shear viscosity κ_s, μ_s (`viscous.rs`): −4κ_sṘ/R² in the radial
//!   balance and shape loads in a, b, ȧ and ḃ_k; ḃ_k is not a state variable but an output of
//!   (NS) and its closure, which the boundary-layer system solves for exactly ([`ShellViscosity`],
//!   [`BdotLoads`]; the vorticity closure refuses them).
//!
//! Nondimensional as everything else (FORMULATION §4.5): γ like c1 (N/m), k_b in units of
//! pressure·length³, κ_s of pressure·length·time.

use super::{At, BdotLoads, LoadJacobian, Loads, PressureRate, Term};
use crate::coefficients::membrane::{bending, surface_tension, viscous};
use crate::model::params::Scales;
use crate::scene::Shell;

type S0 = fn(f64, f64, f64) -> f64;
type Sk = fn(f64, f64, f64, f64) -> f64;

/// A one-constant shell law's generated loads (S0, S1, S2, S11, S12 and their R-derivatives).
#[derive(Clone, Copy)]
pub struct Table {
    pub s: (S0, [Sk; 4]),
    pub dr: (S0, [Sk; 4]),
}

impl std::fmt::Debug for Table {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Table")
    }
}

/// Surface tension, tension form (the paper's form gives it a spurious tangential load).
pub fn surface_tension_table() -> Table {
    use surface_tension::tension as t;
    Table { s: (t::s0, [t::s1, t::s2, t::s11, t::s12]), dr: (t::s0_dr, [t::s1_dr, t::s2_dr, t::s11_dr, t::s12_dr]) }
}

/// Helfrich bending (both forms are the same: a shape energy has no tangential load).
pub fn bending_table() -> Table {
    use bending::tension as t;
    Table { s: (t::s0, [t::s1, t::s2, t::s11, t::s12]), dr: (t::s0_dr, [t::s1_dr, t::s2_dr, t::s11_dr, t::s12_dr]) }
}

/// A shell effect with one constant: −S0 in P, S1 a + S2 b in G_n, S11 a + S12 b in G_t.
#[derive(Debug, Clone)]
pub struct OneConstant {
    pub name: &'static str,
    pub label: String,
    pub table: Table,
    /// the constant, nondimensional
    pub value: f64,
    pub r0: f64,
    pub orders: Vec<f64>,
}

impl Term for OneConstant {
    fn name(&self) -> &'static str {
        self.name
    }
    fn label(&self) -> Option<String> {
        Some(self.label.clone())
    }
    #[inline]
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>) {
        let (r, v, r0) = (at.r(), self.value, self.r0);
        let (s0, [s1, s2, s11, s12]) = self.table.s;
        loads.pressure -= s0(r, r0, v);
        for m in 0..loads.gn.len() {
            let k = self.orders[m];
            let (a, b) = (at.a(m), at.b(m));
            loads.gn[m] += s1(r, r0, v, k) * a + s2(r, r0, v, k) * b;
            loads.gt[m] += s11(r, r0, v, k) * a + s12(r, r0, v, k) * b;
        }
    }
    fn add_pressure_gradient(&self, at: &At<'_>, dp: &mut [f64; 2]) {
        dp[0] -= (self.table.dr.0)(at.r(), self.r0, self.value);
    }
    fn add_jacobian(&self, at: &At<'_>, jac: &mut LoadJacobian) {
        let (r, v, r0, n) = (at.r(), self.value, self.r0, jac.n);
        let (s0, [s1, s2, s11, s12]) = self.table.s;
        let (d0, [d1, d2, d11, d12]) = self.table.dr;
        let _ = s0;
        jac.pressure[0] -= d0(r, r0, v);
        for m in 0..jac.modes() {
            let k = self.orders[m];
            let (a, b) = (at.a(m), at.b(m));
            let (ia, ib) = (jac.layout().a(m), jac.layout().b(m));
            let gn = &mut jac.gn[m * n..(m + 1) * n];
            gn[0] += d1(r, r0, v, k) * a + d2(r, r0, v, k) * b;
            gn[ia] += s1(r, r0, v, k);
            gn[ib] += s2(r, r0, v, k);
            let gt = &mut jac.gt[m * n..(m + 1) * n];
            gt[0] += d11(r, r0, v, k) * a + d12(r, r0, v, k) * b;
            gt[ia] += s11(r, r0, v, k);
            gt[ib] += s12(r, r0, v, k);
        }
    }
    /// P ∋ −Ŝ0(R): q = −Ŝ0′(R) Ṙ (generated Ŝ0′; for γ, d/dt(−2γ/R) = 2γṘ/R²), s = 0,
    /// ∂q/∂Ṙ = −Ŝ0′(R). ∂q/∂R = −Ŝ0″(R) Ṙ, exact from Ŝ0″ = −2Ŝ0′/R, which holds because both
    /// tables have Ŝ0 ∝ 1/R (tension: 2γ/R; bending: 0) — checked in tests/suite/lamb_km.rs.
    fn add_rate(&self, at: &At<'_>, rate: &mut PressureRate) -> bool {
        let (r, rd) = (at.r(), at.rdot());
        let d1 = (self.table.dr.0)(r, self.r0, self.value);
        rate.q -= d1 * rd;
        rate.dq[0] -= -2.0 * d1 / r * rd;
        rate.dq[1] -= d1;
        true
    }
}

/// The viscous (Kelvin–Voigt) shell, tension form (generated: `membrane::viscous::tension`,
/// derivations/shell/viscous.rs; the variational form, oracle-checked): −Ŝ0 = −4κ_sṘ/R² in P and,
/// per mode, G_n,k ∋ S1 a + S2 b + S1D ȧ + S2D ḃ, G_t,k ∋ S11 a + S12 b + S11D ȧ + S12D ḃ, with
/// S1…S12 ∝ Ṙ and the D coefficients functions of R. The ḃ parts are [`BdotLoads`] (the closure
/// solves for ḃ); the rest is an ordinary load, linear in Ṙ, a, ȧ, b.
#[derive(Debug, Clone)]
pub struct ShellViscosity {
    pub kappa_s: f64,
    pub mu_s: f64,
    pub r0: f64,
    pub orders: Vec<f64>,
}

impl Term for ShellViscosity {
    fn name(&self) -> &'static str {
        "shell viscosity"
    }
    fn label(&self) -> Option<String> {
        Some(if self.orders.is_empty() && self.mu_s == 0.0 {
            "shell dilatational viscosity (radial)".into()
        } else {
            "shell viscosity (radial and shape modes)".into()
        })
    }
    #[inline]
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>) {
        use viscous::tension as v;
        let (r, rd, r0, mu, ks) = (at.r(), at.rdot(), self.r0, self.mu_s, self.kappa_s);
        loads.pressure -= v::s0(r, r0, rd, mu, ks);
        for m in 0..loads.gn.len() {
            let k = self.orders[m];
            let (a, ad, b) = (at.a(m), at.adot(m), at.b(m));
            loads.gn[m] += v::s1(r, r0, rd, mu, ks, k) * a + v::s2(r, r0, rd, mu, ks, k) * b + v::s1d(r, r0, rd, mu, ks, k) * ad;
            loads.gt[m] += v::s11(r, r0, rd, mu, ks, k) * a + v::s12(r, r0, rd, mu, ks, k) * b + v::s11d(r, r0, rd, mu, ks, k) * ad;
        }
    }
    fn add_pressure_gradient(&self, at: &At<'_>, dp: &mut [f64; 2]) {
        use viscous::tension as v;
        let (r, rd, r0, mu, ks) = (at.r(), at.rdot(), self.r0, self.mu_s, self.kappa_s);
        dp[0] -= v::s0_dr(r, r0, rd, mu, ks);
        dp[1] -= v::s0(r, r0, 1.0, mu, ks);
    }
    fn add_jacobian(&self, at: &At<'_>, jac: &mut LoadJacobian) {
        use viscous::tension as v;
        let (r, rd, r0, mu, ks, n) = (at.r(), at.rdot(), self.r0, self.mu_s, self.kappa_s, jac.n);
        jac.pressure[0] -= v::s0_dr(r, r0, rd, mu, ks);
        // S0, S1, S2, S11, S12 are linear in Ṙ (every monomial carries Rd once): ∂/∂Ṙ = value at Ṙ = 1
        jac.pressure[1] -= v::s0(r, r0, 1.0, mu, ks);
        for m in 0..jac.modes() {
            let k = self.orders[m];
            let (a, ad, b) = (at.a(m), at.adot(m), at.b(m));
            let l = jac.layout();
            let (ia, iad, ib) = (l.a(m), l.adot(m), l.b(m));
            let gn = &mut jac.gn[m * n..(m + 1) * n];
            gn[0] += v::s1_dr(r, r0, rd, mu, ks, k) * a + v::s2_dr(r, r0, rd, mu, ks, k) * b + v::s1d_dr(r, r0, rd, mu, ks, k) * ad;
            gn[1] += v::s1(r, r0, 1.0, mu, ks, k) * a + v::s2(r, r0, 1.0, mu, ks, k) * b;
            gn[ia] += v::s1(r, r0, rd, mu, ks, k);
            gn[iad] += v::s1d(r, r0, rd, mu, ks, k);
            gn[ib] += v::s2(r, r0, rd, mu, ks, k);
            let gt = &mut jac.gt[m * n..(m + 1) * n];
            gt[0] += v::s11_dr(r, r0, rd, mu, ks, k) * a + v::s12_dr(r, r0, rd, mu, ks, k) * b + v::s11d_dr(r, r0, rd, mu, ks, k) * ad;
            gt[1] += v::s11(r, r0, 1.0, mu, ks, k) * a + v::s12(r, r0, 1.0, mu, ks, k) * b;
            gt[ia] += v::s11(r, r0, rd, mu, ks, k);
            gt[iad] += v::s11d(r, r0, rd, mu, ks, k);
            gt[ib] += v::s12(r, r0, rd, mu, ks, k);
        }
    }
    /// P ∋ −Ŝ0(R, Ṙ) with Ŝ0 linear in Ṙ (generated): dP/dt = −Ŝ0_R Ṙ − Ŝ0(R, 1) R̈, so
    /// q = −Ŝ0_R(R, Ṙ) Ṙ = −Ŝ0_R(R, 1) Ṙ², s = −Ŝ0(R, 1) (= −4κ_s/R²); ∂q/∂Ṙ = −2Ŝ0_R(R, Ṙ),
    /// ∂s/∂R = −Ŝ0_R(R, 1), ∂s/∂Ṙ = 0, and ∂q/∂R = −Ŝ0_RR Ṙ exact from Ŝ0_RR = −3Ŝ0_R/R, which
    /// holds because the generated Ŝ0 ∝ Ṙ/R² (checked in tests/suite/km_effects.rs).
    fn add_rate(&self, at: &At<'_>, rate: &mut PressureRate) -> bool {
        use viscous::tension::{s0, s0_dr};
        let (r, rd, k, mu) = (at.r(), at.rdot(), self.kappa_s, self.mu_s);
        let d1 = s0_dr(r, self.r0, rd, mu, k);
        rate.q -= d1 * rd;
        rate.s -= s0(r, self.r0, 1.0, mu, k);
        rate.dq[0] -= -3.0 * d1 / r * rd;
        rate.dq[1] -= 2.0 * d1;
        rate.ds[0] -= s0_dr(r, self.r0, 1.0, mu, k);
        true
    }
    fn has_bdot_loads(&self) -> bool {
        !self.orders.is_empty()
    }
    /// cn = S2D, ct = S12D (functions of R only).
    fn add_bdot_loads(&self, at: &At<'_>, c: &mut BdotLoads<'_>) {
        use viscous::tension as v;
        let (r, rd, r0, mu, ks) = (at.r(), at.rdot(), self.r0, self.mu_s, self.kappa_s);
        for m in 0..c.cn.len() {
            let k = self.orders[m];
            c.cn[m] += v::s2d(r, r0, rd, mu, ks, k);
            c.ct[m] += v::s12d(r, r0, rd, mu, ks, k);
            c.cn_r[m] += v::s2d_dr(r, r0, rd, mu, ks, k);
            c.ct_r[m] += v::s12d_dr(r, r0, rd, mu, ks, k);
        }
    }
}

/// The shell effects `shell` switches on, in a fixed order (none by default).
pub fn terms(shell: &Shell, sc: &Scales, r0: f64, orders: &[f64]) -> Vec<Box<dyn Term>> {
    let tension = |v: f64| v / (sc.pressure * sc.length);
    let mut out: Vec<Box<dyn Term>> = Vec::new();
    if shell.surface_tension != 0.0 {
        out.push(Box::new(OneConstant {
            name: "surface tension",
            label: format!("surface tension gamma = {} N/m", shell.surface_tension),
            table: surface_tension_table(),
            value: tension(shell.surface_tension),
            r0,
            orders: orders.to_vec(),
        }));
    }
    if shell.bending_modulus != 0.0 {
        out.push(Box::new(OneConstant {
            name: "bending",
            label: format!("bending k_b = {} J", shell.bending_modulus),
            table: bending_table(),
            value: shell.bending_modulus / (sc.pressure * sc.length.powi(3)),
            r0,
            orders: orders.to_vec(),
        }));
    }
    if shell.dilatational_viscosity != 0.0 || shell.shear_viscosity != 0.0 {
        let unit = sc.pressure * sc.length * sc.time; // κ_s [kg/s] and μ_s [Pa s m] alike
        out.push(Box::new(ShellViscosity {
            kappa_s: shell.dilatational_viscosity / unit,
            mu_s: shell.shear_viscosity / unit,
            r0,
            orders: orders.to_vec(),
        }));
    }
    out
}

/// (Ŝ1, Ŝ2, Ŝ11, Ŝ12) of the shell effects `shell` switches on (γ, k_b, a Marmottant law), for any mode k at R
/// (the odd modes of `modes`, which the model does not assemble).
pub fn extra_stiffness(shell: &Shell, sc: &Scales, r0: f64, r: f64, k: f64) -> [f64; 4] {
    let mut out = [0.0; 4];
    let mut add = |table: Table, v: f64| {
        for (o, f) in out.iter_mut().zip(table.s.1) {
            *o += f(r, r0, v, k);
        }
    };
    if shell.surface_tension != 0.0 {
        add(surface_tension_table(), shell.surface_tension / (sc.pressure * sc.length));
    }
    if shell.bending_modulus != 0.0 {
        add(bending_table(), shell.bending_modulus / (sc.pressure * sc.length.powi(3)));
    }
    if let Some(l) = super::lipid::LipidLaw::from_scene(&shell.law, sc) {
        for (o, s) in out.iter_mut().zip(l.stiffness(r, k)) {
            *o += s;
        }
    }
    out
}
