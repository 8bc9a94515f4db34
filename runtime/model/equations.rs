//! The model's equations, written once (paper eqs 2.62–2.67, FORMULATION §4.1–4.3): the loads as
//! a list of [`Term`]s ([`super::effects`]), the radial equation's form
//! ([`super::radial::RadialForm`]) and the mode equations with the viscous closure as an input
//! (the wall terms [`Wall`]: boundary layer, [`super::boundary_layer`], or the vorticity
//! integrals, [`super::vorticity::equations`]).
//!
//! Per mode k (n = k(k+1)), with the tangential-stress source
//! A = 2(k+2)ȧ/(k+1) + 2(1−k)Ṙa/((k+1)R) − R G_t/η of (TS):
//!
//! ```text
//! (TS) T_w = closure(A, …)                                               (corrected 2.65, audit 3–4)
//! (NS) ḃ   = Ṙb/R − ȧ/(k+1) − 2Ṙa/((k+1)R) + Ĩ                           (2.67)
//! (N)  ä   = −[3Ṙȧ − (k−1)R̈a]/R − (k+1)/(ρR)[2η(k+2)ȧ/R + 4η(k−1)Ṙa/R²
//!             + kηT_w/R + kρṘJ/R − 2ηk(k+1)Ĩ/R + G_n]                      (2.64 × (k+1)/(ρR), audit 2, 5)
//! ```
//! Boundary layer (eq 3.1, §4.3): Ĩ = δT_w/R, J = 0, T_w = A/(1 + 2δ/R). Vorticity (§4.2):
//! Ĩ = w_0T_w + Ĩ_int, J = R∫(y⁻³−1)y^{−k}T dy, T_w = (A − 2Ĩ_int)/(1 + 2w_0).
//! The linearisation of the same expressions ([`WallLinear`], [`mode_partials`]) gives the exact
//! Jacobian and A(t) ([`super::linearize`]).
//!
//! Two passes (issue 12): the ordinary terms give P, G and with them the first-order R̈⁽¹⁾,
//! ä⁽¹⁾; second-pass terms ([`super::effects::second_order`], the quadratic coupling) add their
//! loads given those, and R̈ and the mode rates are evaluated again from the completed loads.

use super::effects::second_order::{FirstOrder, FirstOrderGradient, SecondOrderTerm};
use super::effects::{At, BdotLoads, LoadJacobian, Loads, PressureRate, ShapeRate, Term};
use super::params::Params;
use super::radial::RadialForm;
use super::layout::StateLayout;

/// The assembled loads and the radial form of one scene (nondimensional).
#[derive(Debug)]
pub struct Equations {
    pub(crate) params: Params,
    /// k of each mode index.
    pub(crate) orders: Vec<f64>,
    pub(crate) form: Box<dyn RadialForm>,
    /// In summation order (docs/architecture.md, "Adding an effect").
    pub(crate) terms: Vec<Box<dyn Term>>,
    /// Second-pass terms (the quadratic coupling): loads that need the first-order R̈, ä
    /// ([`super::effects::second_order`]); empty for a linear scene.
    pub(crate) second: Vec<Box<dyn SecondOrderTerm>>,
    /// Per term of `terms`, whether its loads are material-frame ([`super::material`]); empty
    /// for a linear scene.
    pub(crate) material: Vec<bool>,
}

impl Equations {
    pub fn params(&self) -> &Params {
        &self.params
    }
    /// k of each mode index.
    pub fn orders(&self) -> &[f64] {
        &self.orders
    }
    pub fn terms(&self) -> impl Iterator<Item = &dyn Term> {
        self.terms.iter().map(|t| t.as_ref())
    }
    /// Whether a term (ordinary or second-pass) called `name` is assembled.
    pub fn has(&self, name: &str) -> bool {
        self.terms.iter().any(|t| t.name() == name) || self.second.iter().any(|t| t.name() == name)
    }
    /// The active-effect labels of the assembled terms, ordinary then second-pass.
    pub fn labels(&self) -> Vec<String> {
        self.terms.iter().filter_map(|t| t.label()).chain(self.second.iter().filter_map(|t| t.label())).collect()
    }
    /// Half-width, in modes, of the shape-load coupling over all terms (the Jacobian's band).
    pub fn band(&self) -> usize {
        self.terms.iter().map(|t| t.band()).chain(self.second.iter().map(|t| t.band())).max().unwrap_or(0)
    }
    /// Whether second-pass terms are assembled ([`super::effects::second_order`]).
    pub fn has_second_order(&self) -> bool {
        !self.second.is_empty()
    }

    /// Adds the second-pass terms' loads to `loads` (which holds the ordinary terms' P, G_n,
    /// G_t on entry), given the first-order accelerations at (t, z).
    #[inline]
    pub fn add_second_order(&self, t: f64, z: &[f64], first: &FirstOrder<'_>, loads: &mut Loads<'_>) {
        let at = At { t, z };
        for term in &self.second {
            term.add(&at, first, loads);
        }
    }

    /// Adds the second-pass terms' exact derivatives to `jac` (the ordinary terms' on entry).
    pub fn add_second_order_jacobian(&self, t: f64, z: &[f64], first: &FirstOrder<'_>, grad: &FirstOrderGradient<'_>, jac: &mut LoadJacobian) {
        let at = At { t, z };
        for term in &self.second {
            term.add_jacobian(&at, first, grad, jac);
        }
    }
    pub fn form(&self) -> &dyn RadialForm {
        self.form.as_ref()
    }

    /// The radial pressure balance P at (t, z) and, for m < gn.len(), G_n,k, G_t,k, of the
    /// ordinary terms (the second-pass terms, [`add_second_order`](Self::add_second_order),
    /// are added by the system once it knows the first-order accelerations).
    #[inline]
    pub fn loads(&self, t: f64, z: &[f64], gn: &mut [f64], gt: &mut [f64]) -> f64 {
        gn.fill(0.0);
        gt.fill(0.0);
        let at = At { t, z };
        let mut l = Loads { pressure: 0.0, gn, gt };
        for term in &self.terms {
            term.add(&at, &mut l);
        }
        l.pressure
    }

    /// Whether a term has shape loads proportional to ḃ_k ([`BdotLoads`]: the shell viscosity).
    pub fn has_bdot_loads(&self) -> bool {
        self.terms.iter().any(|t| t.has_bdot_loads())
    }

    /// The ḃ_k coefficients of the shape loads at (t, z), summed over the terms (overwritten).
    pub fn bdot_loads(&self, t: f64, z: &[f64], c: &mut BdotLoads<'_>) {
        for x in [&mut *c.cn, &mut *c.ct, &mut *c.cn_r, &mut *c.ct_r] {
            x.fill(0.0);
        }
        let at = At { t, z };
        for term in self.terms.iter().filter(|t| t.has_bdot_loads()) {
            term.add_bdot_loads(&at, c);
        }
    }

    /// R̈ from P (the radial form).
    #[inline]
    pub fn acceleration(&self, r: f64, rd: f64, pressure: f64) -> f64 {
        self.form.acceleration(self.params.rho, r, rd, pressure)
    }

    /// R̈ at (t, z) (shape loads not evaluated).
    pub fn radial_acceleration(&self, t: f64, z: &[f64]) -> f64 {
        if !self.form.needs_rate() {
            let p = self.loads(t, z, &mut [], &mut []);
            return self.acceleration_at(t, z, p);
        }
        // P and its rate in one pass ([`Term::add_with_rate`]): the same sums as `loads` and
        // `radial_rate`, term by term in the same order
        let at = At { t, z };
        let mut l = Loads { pressure: 0.0, gn: &mut [], gt: &mut [] };
        let mut rate = PressureRate::default();
        for term in &self.terms {
            term.add_with_rate(&at, &mut l, &mut rate);
        }
        self.form.acceleration_rate(self.params.rho, z[0], z[1], l.pressure, &rate)
    }

    /// The pressure's rate (q, s and their (R, Ṙ)-gradients) summed over the terms, and whether
    /// every term provides it ([`Term::add_rate`]).
    /// With the shape part ([`PressureRate::with_shape`]).
    /// `shape` is the caller's buffer for the shape part (a zero [`ShapeRate::default`]).
    pub fn rate<'s>(&self, t: f64, z: &[f64], shape: &'s mut ShapeRate) -> (PressureRate<'s>, bool) {
        self.rate_into(t, z, PressureRate::with_shape(shape))
    }

    /// q, s and their (R, Ṙ)-gradients alone: what R̈ with the shape frozen needs.
    #[inline]
    pub fn radial_rate(&self, t: f64, z: &[f64]) -> PressureRate<'static> {
        self.rate_into(t, z, PressureRate::default()).0
    }

    #[inline]
    fn rate_into<'s>(&self, t: f64, z: &[f64], mut rate: PressureRate<'s>) -> (PressureRate<'s>, bool) {
        let at = At { t, z };
        let mut all = true;
        for term in &self.terms {
            all &= term.add_rate(&at, &mut rate);
        }
        (rate, all)
    }

    /// R̈ at (t, z) from P: the radial form, with the pressure's rate when it needs it
    /// (Keller–Miksis). Incompressible: exactly [`acceleration`](Self::acceleration).
    #[inline]
    pub fn acceleration_at(&self, t: f64, z: &[f64], pressure: f64) -> f64 {
        if !self.form.needs_rate() {
            return self.acceleration(z[0], z[1], pressure);
        }
        let rate = self.radial_rate(t, z);
        self.form.acceleration_rate(self.params.rho, z[0], z[1], pressure, &rate)
    }

    /// R̈ at (t, z) from P along the motion whose ḃ_k (the closure's, not a state variable) is
    /// `bdot`: the rate's Σ ∂P/∂b_k ḃ_k part included ([`PressureRate`]). For a form without the
    /// rate, or a rate without a ḃ part, exactly [`acceleration_at`](Self::acceleration_at).
    #[inline]
    pub fn acceleration_with(&self, t: f64, z: &[f64], pressure: f64, bdot: &[f64]) -> f64 {
        if !self.form.needs_rate() {
            return self.acceleration(z[0], z[1], pressure);
        }
        let mut shape = ShapeRate::default();
        let (mut rate, _) = self.rate(t, z, &mut shape);
        for (m, bd) in bdot.iter().enumerate() {
            rate.q += rate.db(m) * bd;
        }
        self.form.acceleration_rate(self.params.rho, z[0], z[1], pressure, &rate)
    }

    /// Whether R̈ along the motion needs ḃ (a compressible form and a pressure depending on b:
    /// Keller–Miksis with a field). Evaluated at a generic state.
    pub fn needs_bdot(&self) -> bool {
        if !self.form.needs_rate() {
            return false;
        }
        // (with the gas slot: the reduced thermal model's rate reads p_b)
        let z = vec![1.0; StateLayout::reduced(self.orders.len()).with_gas().dim()];
        self.rate(0.0, &z, &mut ShapeRate::default()).0.has_bdot()
    }

    /// R̈ and its exact ∂R̈/∂(R, Ṙ) at (t, z) with the shape amplitudes of z held fixed (the
    /// radial equation along a frozen shape, as [`radial_acceleration`](Self::radial_acceleration)):
    /// the terms' pressure gradients ([`Term::add_pressure_gradient`]) through the radial form.
    pub fn radial_gradient(&self, t: f64, z: &[f64]) -> (f64, [f64; 2]) {
        // P as `loads` sums it (the same order, the same value) and its gradient, one call per term
        let at = At { t, z };
        let (mut p, mut dp) = (0.0, [0.0; 2]);
        for term in &self.terms {
            term.add_pressure_and_gradient(&at, &mut p, &mut dp);
        }
        let mut g = [0.0; 2];
        self.acceleration_gradient_at(t, z, p, &dp, &mut g);
        (self.acceleration_at(t, z, p), g)
    }

    /// ∂R̈/∂z (length of `grad`) at (t, z) given P and its gradient: the chain rule through P and,
    /// for a form that needs it, through the rate (q, s); the shape frozen (ḃ = 0, as
    /// [`acceleration_at`](Self::acceleration_at)).
    /// Returns the radial form's partials ∂R̈/∂(R, Ṙ, P, q, s) at (t, z), the chain rule's factors
    /// (q, s: the pressure's rate; zero for a form without it).
    pub fn acceleration_gradient_at(&self, t: f64, z: &[f64], pressure: f64, dp: &[f64], grad: &mut [f64]) -> [f64; 5] {
        self.acceleration_gradient_with(t, z, pressure, dp, None, grad)
    }

    /// ∂R̈/∂z of [`acceleration_with`](Self::acceleration_with): with `bdot = Some((ḃ, ∂ḃ/∂z))`
    /// (∂ḃ_m/∂z_j at `dbdot[m * n + j]`, n = z.len()) the ḃ part's chain rule is included.
    /// Returns the radial form's partials, as [`acceleration_gradient_at`](Self::acceleration_gradient_at).
    pub fn acceleration_gradient_with(
        &self,
        t: f64,
        z: &[f64],
        pressure: f64,
        dp: &[f64],
        bdot: Option<(&[f64], &[f64])>,
        grad: &mut [f64],
    ) -> [f64; 5] {
        if !self.form.needs_rate() {
            let (a, b, c) = self.acceleration_gradient(z[0], z[1], pressure, dp, grad);
            return [a, b, c, 0.0, 0.0];
        }
        let mut shape = ShapeRate::default();
        let (mut rate, _) = self.rate(t, z, &mut shape);
        if let Some((bd, _)) = bdot {
            for (m, x) in bd.iter().enumerate() {
                rate.q += rate.db(m) * x;
            }
        }
        let d = self.form.partials_rate(self.params.rho, z[0], z[1], pressure, &rate);
        for (g, x) in grad.iter_mut().zip(dp) {
            *g = d[2] * x;
        }
        for j in 0..2 {
            grad[j] += d[j] + d[3] * rate.dq[j] + d[4] * rate.ds[j];
        }
        let n = grad.len();
        for j in StateLayout::RADIAL..n {
            grad[j] += d[3] * rate.dq_shape(StateLayout::x_of(j));
        }
        if let Some((bd, dbd)) = bdot {
            for (m, x) in bd.iter().enumerate() {
                grad[0] += d[3] * rate.db_dr(m) * x;
                if rate.db(m) != 0.0 {
                    for j in 0..n {
                        grad[j] += d[3] * rate.db(m) * dbd[m * n + j];
                    }
                }
            }
        }
        d
    }

    /// Exact ∂P/∂z, ∂G_n/∂z, ∂G_t/∂z at (t, z) for `jac.modes()` modes (overwritten).
    pub fn load_jacobian(&self, t: f64, z: &[f64], jac: &mut LoadJacobian) {
        jac.clear();
        let at = At { t, z };
        for term in &self.terms {
            term.add_jacobian(&at, jac);
        }
    }

    /// ∂R̈/∂z (length of `grad`) given P and its gradient (radial form's chain rule); returns the
    /// form's partials (∂R̈/∂R, ∂R̈/∂Ṙ, ∂R̈/∂P).
    pub fn acceleration_gradient(&self, r: f64, rd: f64, pressure: f64, dp: &[f64], grad: &mut [f64]) -> (f64, f64, f64) {
        let (d_r, d_rd, d_p) = self.form.partials(self.params.rho, r, rd, pressure);
        for (g, d) in grad.iter_mut().zip(dp) {
            *g = d_p * d;
        }
        grad[0] += d_r;
        grad[1] += d_rd;
        (d_r, d_rd, d_p)
    }

    /// Number of evaluations a counting term made (the magnetic field: one per rhs).
    pub fn evaluations(&self, name: &str) -> u64 {
        self.terms.iter().filter(|t| t.name() == name).map(|t| t.evaluations()).sum()
    }
}

/// (TS)'s source A = 2(k+2)ȧ/(k+1) + 2(1−k)Ṙa/((k+1)R) − R G_t/η (corrected 2.65).
#[inline]
pub fn wall_source(k: f64, eta: f64, r: f64, rdot: f64, a: f64, adot: f64, gt: f64) -> f64 {
    2.0 * (k + 2.0) * adot / (k + 1.0) + 2.0 * (1.0 - k) * rdot * a / ((k + 1.0) * r) - r * gt / eta
}

/// ∂A/∂(R, Ṙ, a, ȧ, G_t).
#[inline]
pub fn wall_source_partials(k: f64, eta: f64, r: f64, rdot: f64, a: f64, gt: f64) -> [f64; 5] {
    let c = 2.0 * (1.0 - k) / (k + 1.0);
    [-c * rdot * a / (r * r) - gt / eta, c * a / r, c * rdot / r, 2.0 * (k + 2.0) / (k + 1.0), -r / eta]
}

/// What a closure gives the mode equations: T_w, Ĩ and the wall part of the bracket of (N),
/// `normal` = [kηT_w/R, kρṘJ/R, −2ηk(k+1)Ĩ/R], added in this order (a closure may fold them:
/// the boundary layer writes the first and third as one product and has J = 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wall {
    pub tw: f64,
    pub itil: f64,
    pub normal: [f64; 3],
}

/// (NS) and (N): (ä_k, ḃ_k).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn mode_rates(k: f64, rho: f64, eta: f64, r: f64, rd: f64, rdd: f64, a: f64, ad: f64, b: f64, gn: f64, w: &Wall) -> (f64, f64) {
    let kp1 = k + 1.0;
    let bd = rd * b / r - ad / kp1 - 2.0 * rd * a / (kp1 * r) + w.itil;
    let bracket = 2.0 * eta * (k + 2.0) * ad / r + 4.0 * eta * (k - 1.0) * rd * a / (r * r)
        + w.normal[0]
        + w.normal[1]
        + w.normal[2]
        + gn;
    let add = -(3.0 * rd * ad - (k - 1.0) * rdd * a) / r - kp1 / (rho * r) * bracket;
    (add, bd)
}

/// (∂ä/∂R̈, ∂ä/∂G_n) of (N) = ((k−1)a/R, −(k+1)/(ρR)): (N) is affine in R̈ and G_n and (NS)
/// depends on neither, so a change ΔR̈, ΔG_n changes ä by exactly these times them (the second
/// pass of a quadratic scene, [`super::effects::second_order`]).
#[inline]
pub fn mode_shift(k: f64, rho: f64, r: f64, a: f64) -> (f64, f64) {
    ((k - 1.0) * a / r, -(k + 1.0) / (rho * r))
}

/// Local variables of the mode equations, in the order of the partial-derivative arrays.
pub mod var {
    pub const R: usize = 0;
    pub const RD: usize = 1;
    pub const RDD: usize = 2;
    pub const A: usize = 3;
    pub const AD: usize = 4;
    pub const B: usize = 5;
    pub const GN: usize = 6;
    pub const GT: usize = 7;
    /// Vorticity closure: Ĩ_int and ∫(y⁻³−1)y^{−k}T dy (zero for the boundary layer).
    pub const IINT: usize = 8;
    pub const JR: usize = 9;
    pub const N: usize = 10;
}

/// A closure's wall values and their exact partials with respect to the local variables
/// ([`var`]; the R̈, b, G_n entries are zero for both closures).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WallLinear {
    pub tw: f64,
    pub itil: f64,
    pub j: f64,
    pub d_tw: [f64; var::N],
    pub d_itil: [f64; var::N],
    pub d_j: [f64; var::N],
}

/// Exact ∂(ä, ḃ)/∂(local variables) of (N), (NS) in their generic form (module doc).
#[allow(clippy::too_many_arguments)]
pub fn mode_partials(
    k: f64,
    rho: f64,
    eta: f64,
    r: f64,
    rd: f64,
    rdd: f64,
    a: f64,
    ad: f64,
    b: f64,
    gn: f64,
    w: &WallLinear,
) -> ([f64; var::N], [f64; var::N]) {
    use var::*;
    let kp1 = k + 1.0;
    let (ck, cj, ci) = (k * eta / r, k * rho * rd / r, -2.0 * eta * k * kp1 / r);
    let bracket = 2.0 * eta * (k + 2.0) * ad / r + 4.0 * eta * (k - 1.0) * rd * a / (r * r)
        + ck * w.tw
        + cj * w.j
        + ci * w.itil
        + gn;
    // ∂bracket/∂x: the wall part first, then the explicit terms.
    let mut db = [0.0; N];
    for x in 0..N {
        db[x] = ck * w.d_tw[x] + cj * w.d_j[x] + ci * w.d_itil[x];
    }
    db[R] += -2.0 * eta * (k + 2.0) * ad / (r * r) - 8.0 * eta * (k - 1.0) * rd * a / (r * r * r)
        - (ck * w.tw + cj * w.j + ci * w.itil) / r;
    db[RD] += 4.0 * eta * (k - 1.0) * a / (r * r) + k * rho * w.j / r;
    db[A] += 4.0 * eta * (k - 1.0) * rd / (r * r);
    db[AD] += 2.0 * eta * (k + 2.0) / r;
    db[GN] += 1.0;
    let c = kp1 / (rho * r);
    let mut dadd = [0.0; N];
    for x in 0..N {
        dadd[x] = -c * db[x];
    }
    dadd[R] += (3.0 * rd * ad - (k - 1.0) * rdd * a) / (r * r) + c * bracket / r;
    dadd[RD] += -3.0 * ad / r;
    dadd[RDD] += (k - 1.0) * a / r;
    dadd[A] += (k - 1.0) * rdd / r;
    dadd[AD] += -3.0 * rd / r;
    let mut dbd = w.d_itil;
    dbd[R] += -rd * b / (r * r) + 2.0 * rd * a / (kp1 * r * r);
    dbd[RD] += b / r - 2.0 * a / (kp1 * r);
    dbd[A] += -2.0 * rd / (kp1 * r);
    dbd[AD] += -1.0 / kp1;
    dbd[B] += rd / r;
    (dadd, dbd)
}
