//! Lipid monolayers whose energy depends on the area alone (issue 31; docs/model.md, "Lipid
//! shells: Marmottant"): Marmottant et al. 2005 (JASA 118, 3499, eq 1) and its smooth variant.
//!
//! The tension (force per current length) is a function τ(J) of the area ratio J = A/A0 =
//! (R/R0)² of the spherical state: buckled τ = 0 (R < R_b), elastic τ = χ(R²/R_b² − 1),
//! ruptured τ = σ_r (R > R_r = R_b √(1 + σ_r/χ), reversibly: the variant of APECSS,
//! `src/interface.c`, `apecss_interface_surfacetension_marmottant`). As an energy per reference
//! area W(J) with W′ = τ, the linear loads of any such law are linear in (W′, W″) at J: the
//! generated tables of `derivations/shell/marmottant.rs` (W = chib J²/2 − chi J, tension form)
//! with chi = Jτ′ − τ, chib = τ′ give them exactly — S0 = 2τ/R, S1 = (n − 2)τ/R² + 4τ′/R0²,
//! S2 = −2nτ′/R0², S11 = −2τ′/R0², S12 = nτ′/R0². Their R-derivative adds the chain rule through
//! (chi, chib) with τ″, which vanishes inside each branch of the kinked law.
//!
//! The branch switches are kinks of τ at R = R_b and R = R_r: [`LipidLaw::branch_margins`] gives
//! their signed margins at a state, the event functions of a run (`model/events.rs`,
//! `BranchEvent`): the run loop locates each crossing on the dense output and restarts the
//! stepper there, and inside a run the law is evaluated on the branch the run is on
//! ([`BranchState`], set at the crossings), its formula continued a little beyond the kink —
//! never re-decided from R inside a step (docs/model.md, "Lipid shells: Marmottant", "Branch
//! switches"). Outside a run (modes, Floquet, Jacobians at a given state) the branch is R's.

use super::{At, LoadJacobian, Loads, PressureRate, Term};
use crate::model::layout::StateLayout;
use crate::coefficients::membrane::marmottant::tension as m;
use crate::model::params::Scales;
use crate::scene::{Lipid, ShellLaw};
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Arc;

/// A branch of the kinked law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Branch {
    /// R < R_b: τ = 0.
    Buckled,
    /// R_b ≤ R ≤ R_r: τ = χ(R²/R_b² − 1).
    Elastic,
    /// R > R_r: τ = σ_r.
    Ruptured,
}

impl Branch {
    pub const ALL: [Branch; 3] = [Branch::Buckled, Branch::Elastic, Branch::Ruptured];

    fn code(self) -> u8 {
        self as u8 + 1
    }
}

/// The branch a run is on, shared by every clone of a law (the linear term, the quadratic
/// loads, the frame mapping): empty outside a run (each evaluation takes R's branch); set by
/// the run's events (`model/events.rs`) inside one.
#[derive(Debug, Clone, Default)]
pub struct BranchState(Arc<AtomicU8>);

impl BranchState {
    /// The branch set by the run, if any.
    #[inline]
    pub fn get(&self) -> Option<Branch> {
        match self.0.load(Ordering::Relaxed) {
            1 => Some(Branch::Buckled),
            2 => Some(Branch::Elastic),
            3 => Some(Branch::Ruptured),
            _ => None,
        }
    }

    /// Sets the branch (`None`: R's branch at each evaluation again).
    pub fn set(&self, b: Option<Branch>) {
        self.0.store(b.map_or(0, Branch::code), Ordering::Relaxed);
    }

    /// The raw branch (an opaque code: 0 = none set, R's branch at each evaluation; a
    /// Marmottant branch or a tension curve's segment otherwise), to restore it with
    /// [`BranchState::set_code`] (the Floquet analysis on a kinked law, analysis/periodic).
    #[inline]
    pub fn code(&self) -> u8 {
        self.0.load(Ordering::Relaxed)
    }

    /// Sets the raw branch [`BranchState::code`] returned.
    #[inline]
    pub fn set_code(&self, code: u8) {
        self.0.store(code, Ordering::Relaxed);
    }

    /// The segment of a tension curve set by the run (its code − 1), if any.
    #[inline]
    fn segment(&self) -> Option<usize> {
        (self.0.load(Ordering::Relaxed) as usize).checked_sub(1)
    }

    /// Sets a tension curve's segment (the scene allows at most 250 knots: codes ≤ 252).
    fn set_segment(&self, seg: usize) {
        self.0.store(u8::try_from(seg + 1).unwrap_or(u8::MAX), Ordering::Relaxed);
    }
}

/// The Marmottant tension law of a scene, nondimensional (FORMULATION §4.5: tensions like c1).
/// Clones share the run's [`BranchState`].
#[derive(Debug, Clone)]
pub struct LipidLaw {
    /// χ
    pub chi: f64,
    /// J_b = (R_b/R0)²
    pub jb: f64,
    /// σ_r
    pub sigma_r: f64,
    /// s of the smooth variant (None: the kinked law)
    pub smoothing: Option<f64>,
    /// R0 (1 in model units)
    pub r0: f64,
    /// The branch of a run (kinked law only).
    pub branch: BranchState,
    /// `shell.law = "sarkar"`: its τ(J) (effects/sarkar.rs) instead of Marmottant's.
    pub sarkar: Option<super::sarkar::SarkarTension>,
    /// `shell.law = "tension-curve"`: the measured τ(J) (effects/tension_curve.rs); its knots
    /// are the run's branch switches, its segment the run's branch.
    pub curve: Option<Arc<super::tension_curve::CurveTension>>,
}

/// softplus(z) = ln(1 + e^z), without overflow.
fn softplus(z: f64) -> f64 {
    z.max(0.0) + (-z.abs()).exp().ln_1p()
}

/// The logistic function 1/(1 + e^−z) = (1 + tanh(z/2))/2.
fn logistic(z: f64) -> f64 {
    0.5 * (1.0 + (0.5 * z).tanh())
}

impl LipidLaw {
    /// The law of a scene's `shell.law`, if it is an area-only law (Marmottant, Sarkar).
    pub fn from_scene(law: &ShellLaw, sc: &Scales) -> Option<Self> {
        let t = |v: f64| v / (sc.pressure * sc.length);
        if let ShellLaw::Sarkar(p) = law {
            let sarkar = super::sarkar::SarkarTension {
                e0: t(p.elasticity),
                alpha: p.elasticity_decay,
                gamma0: t(p.reference_tension),
                je: (p.unstrained_radius / sc.length).powi(2),
            };
            // the Marmottant fields unused: τ is the EEM's (a smooth law, no branches)
            let (chi, jb, sigma_r, smoothing) = (sarkar.e0, sarkar.je, f64::INFINITY, None);
            return Some(Self { chi, jb, sigma_r, smoothing, r0: 1.0, branch: BranchState::default(), sarkar: Some(sarkar), curve: None });
        }
        if let ShellLaw::TensionCurve(c) = law {
            let curve = super::tension_curve::CurveTension::new(c.area_ratio.clone(), c.tension.iter().map(|&s| t(s)).collect());
            // the Marmottant fields unused: τ is the curve's
            let (chi, jb) = (curve.slope.iter().fold(0.0, |m: f64, &d| m.max(d)), c.area_ratio[0]);
            return Some(Self { chi, jb, sigma_r: f64::INFINITY, smoothing: None, r0: 1.0, branch: BranchState::default(), sarkar: None, curve: Some(Arc::new(curve)) });
        }
        let l: &Lipid = law.lipid()?;
        Some(Self {
            chi: t(l.elasticity),
            jb: (l.buckling_radius / sc.length).powi(2),
            sigma_r: t(l.rupture_tension),
            smoothing: l.smoothing.map(t),
            r0: 1.0,
            branch: BranchState::default(),
            sarkar: None,
            curve: None,
        })
    }

    /// R_b, R_r in model units.
    pub fn radii(&self) -> (f64, f64) {
        let rb = self.jb.sqrt() * self.r0;
        (rb, rb * (1.0 + self.sigma_r / self.chi).sqrt())
    }

    /// The signed branch margins at radius `r` (model units): [R − R_b, R − R_r]. A sign change
    /// of either is a branch switch of the kinked law (buckled below R_b, ruptured above R_r);
    /// for the smooth law they mark the centres of its two blends. The event functions the
    /// run loop locates (`model/events.rs`, `BranchEvent`).
    pub fn branch_margins(&self, r: f64) -> [f64; 2] {
        let (rb, rr) = self.radii();
        [r - rb, r - rr]
    }

    /// The number of branch switches of the law ([`LipidLaw::margin`]): R_b and R_r of the
    /// kinked Marmottant law, the knots of a tension curve, none for a smooth law.
    pub fn event_count(&self) -> usize {
        match &self.curve {
            Some(c) => c.j.len(),
            None if self.is_kinked() => 2,
            None => 0,
        }
    }

    /// The signed margin of switch `which` at radius `r` (model units): the kinked law's
    /// [`LipidLaw::branch_margins`], or J − J_which for a tension curve's knot.
    pub fn margin(&self, r: f64, which: usize) -> f64 {
        match &self.curve {
            Some(c) => (r / self.r0).powi(2) - c.j[which],
            None => self.branch_margins(r)[which],
        }
    }

    /// d/dt of [`LipidLaw::margin`] at radius `r` moving at `rdot` (model units): Ṙ, or
    /// 2RṘ/R0² for a tension curve's knot.
    pub fn margin_rate(&self, r: f64, rdot: f64) -> f64 {
        match &self.curve {
            Some(_) => 2.0 * r * rdot / (self.r0 * self.r0),
            None => rdot,
        }
    }

    /// The run enters radius `r`: its branch (a tension curve: its segment) becomes r's; returns
    /// the branch class for the run's clock (a curve: below its first knot buckled, above its
    /// last ruptured, elastic between).
    pub fn enter(&self, r: f64) -> Branch {
        if let Some(c) = &self.curve {
            let seg = c.segment_of((r / self.r0).powi(2));
            self.branch.set_segment(seg);
            return if seg == 0 {
                Branch::Buckled
            } else if seg >= c.j.len() {
                Branch::Ruptured
            } else {
                Branch::Elastic
            };
        }
        let b = self.branch_of(r);
        self.branch.set(Some(b));
        b
    }

    /// Whether the law has kinks (the kinked Marmottant law): its switches are events of a run.
    pub fn is_kinked(&self) -> bool {
        self.smoothing.is_none() && self.sarkar.is_none()
    }

    /// The branch of the kinked law at radius `r` (model units): buckled below R_b, ruptured
    /// above R_r (R = R_b is elastic, R = R_r elastic).
    pub fn branch_of(&self, r: f64) -> Branch {
        self.classify(self.chi * ((r / self.r0).powi(2) / self.jb - 1.0))
    }

    /// The branch of x = χ(J/J_b − 1).
    #[inline]
    fn classify(&self, x: f64) -> Branch {
        if x < 0.0 {
            Branch::Buckled
        } else if x <= self.sigma_r {
            Branch::Elastic
        } else {
            Branch::Ruptured
        }
    }

    /// The branch the law is evaluated on at radius `r`: the run's ([`BranchState`]) inside a
    /// run, otherwise R's.
    pub fn current_branch(&self, r: f64) -> Branch {
        self.branch.get().unwrap_or_else(|| self.branch_of(r))
    }

    /// τ(J), dτ/dJ, d²τ/dJ² (kinked law: on the run's branch, or J's outside a run).
    pub fn tension(&self, j: f64) -> [f64; 3] {
        if let Some(s) = &self.sarkar {
            return s.tension(j);
        }
        if let Some(c) = &self.curve {
            return c.eval(self.branch.segment().unwrap_or_else(|| c.segment_of(j)), j);
        }
        let (chi, sr) = (self.chi, self.sigma_r);
        let x = chi * (j / self.jb - 1.0);
        let xj = chi / self.jb;
        match self.smoothing {
            None => match self.branch.get().unwrap_or_else(|| self.classify(x)) {
                Branch::Buckled => [0.0, 0.0, 0.0],
                Branch::Elastic => [x, xj, 0.0],
                Branch::Ruptured => [sr, 0.0, 0.0],
            },
            Some(s) => {
                // τ = s[sp(x/s) − sp((x − σ_r)/s)]: dτ/dx = L(x/s) − L((x − σ_r)/s), a tanh blend
                let (z1, z2) = (x / s, (x - sr) / s);
                let (l1, l2) = (logistic(z1), logistic(z2));
                let tau = s * (softplus(z1) - softplus(z2));
                let d2 = (l1 * (1.0 - l1) - l2 * (1.0 - l2)) / s;
                [tau, xj * (l1 - l2), xj * xj * d2]
            }
        }
    }

    /// The generated tables' (chi, chib) at R and their R-derivatives: chi = Jτ′ − τ, chib = τ′.
    /// The law is evaluated here; [`LipidLaw::stiffness_with`] and
    /// [`LipidLaw::stiffness_dr_with`] take them, so the modes of one state share one evaluation.
    #[inline]
    pub fn args(&self, r: f64) -> ((f64, f64), (f64, f64)) {
        let r0 = self.r0;
        let j = (r / r0) * (r / r0);
        let [tau, tj, tjj] = self.tension(j);
        let dj = 2.0 * r / (r0 * r0);
        ((j * tj - tau, tj), (dj * j * tjj, dj * tjj))
    }

    /// Ŝ0 and its exact R-derivative.
    pub fn s0(&self, r: f64) -> (f64, f64) {
        self.s0_with(self.args(r), r)
    }

    /// [`LipidLaw::s0`] from the [`LipidLaw::args`] at R.
    #[inline]
    pub fn s0_with(&self, args: ((f64, f64), (f64, f64)), r: f64) -> (f64, f64) {
        let ((u, v), (du, dv)) = args;
        let r0 = self.r0;
        (m::s0(r, r0, u, v), m::s0_dr(r, r0, u, v) + du * m::s0(r, r0, 1.0, 0.0) + dv * m::s0(r, r0, 0.0, 1.0))
    }

    /// (Ŝ1, Ŝ2, Ŝ11, Ŝ12) of mode k at R.
    pub fn stiffness(&self, r: f64, k: f64) -> [f64; 4] {
        self.stiffness_with(self.args(r), r, k)
    }

    /// [`LipidLaw::stiffness`] from the [`LipidLaw::args`] at R.
    #[inline]
    pub fn stiffness_with(&self, args: ((f64, f64), (f64, f64)), r: f64, k: f64) -> [f64; 4] {
        let ((u, v), _) = args;
        let r0 = self.r0;
        [m::s1(r, r0, u, v, k), m::s2(r, r0, u, v, k), m::s11(r, r0, u, v, k), m::s12(r, r0, u, v, k)]
    }

    /// Their exact R-derivatives.
    pub fn stiffness_dr(&self, r: f64, k: f64) -> [f64; 4] {
        self.stiffness_dr_with(self.args(r), r, k)
    }

    /// [`LipidLaw::stiffness_dr`] from the [`LipidLaw::args`] at R.
    pub fn stiffness_dr_with(&self, args: ((f64, f64), (f64, f64)), r: f64, k: f64) -> [f64; 4] {
        let ((u, v), (du, dv)) = args;
        let r0 = self.r0;
        let chain = |f: fn(f64, f64, f64, f64, f64) -> f64, fdr: fn(f64, f64, f64, f64, f64) -> f64| {
            let mut d = fdr(r, r0, u, v, k);
            if du != 0.0 || dv != 0.0 {
                d += du * f(r, r0, 1.0, 0.0, k) + dv * f(r, r0, 0.0, 1.0, k);
            }
            d
        };
        [chain(m::s1, m::s1_dr), chain(m::s2, m::s2_dr), chain(m::s11, m::s11_dr), chain(m::s12, m::s12_dr)]
    }
}

/// The Marmottant shell as a load: −Ŝ0(R) in P, Ŝ1 a + Ŝ2 b in G_n, Ŝ11 a + Ŝ12 b in G_t, the
/// coefficients of the branch R is on.
#[derive(Debug, Clone)]
pub struct LipidTerm {
    pub law: LipidLaw,
    /// k of each mode index.
    pub orders: Vec<f64>,
    pub label: String,
}

impl LipidTerm {
    /// [`Term::add`] with the law's [`LipidLaw::args`] and Ŝ0 at R given: −Ŝ0 in P, the modes'
    /// Ŝ1 a + Ŝ2 b and Ŝ11 a + Ŝ12 b (the law evaluated once for all of them).
    #[inline]
    fn add_with_s0(&self, at: &At<'_>, loads: &mut Loads<'_>, args: ((f64, f64), (f64, f64)), s0: f64) {
        let r = at.r();
        loads.pressure -= s0;
        for m in 0..loads.gn.len() {
            let [s1, s2, s11, s12] = self.law.stiffness_with(args, r, self.orders[m]);
            let (a, b) = (at.a(m), at.b(m));
            loads.gn[m] += s1 * a + s2 * b;
            loads.gt[m] += s11 * a + s12 * b;
        }
    }
}

impl Term for LipidTerm {
    fn name(&self) -> &'static str {
        "marmottant"
    }
    fn label(&self) -> Option<String> {
        Some(self.label.clone())
    }
    #[inline]
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>) {
        let args = self.law.args(at.r());
        self.add_with_s0(at, loads, args, self.law.s0_with(args, at.r()).0);
    }
    /// P's rate −Ŝ0′(R)Ṙ from the Ŝ0 evaluation the loads use: one evaluation of the law where
    /// `add_with_rate` makes five (`add_rate`'s gradient is a central difference).
    fn add_with_rate_value(&self, at: &At<'_>, loads: &mut Loads<'_>, rate: &mut PressureRate) -> bool {
        let args = self.law.args(at.r());
        let (s0, d1) = self.law.s0_with(args, at.r());
        self.add_with_s0(at, loads, args, s0);
        rate.q -= d1 * at.rdot();
        true
    }
    fn add_pressure_gradient(&self, at: &At<'_>, dp: &mut [f64; 2]) {
        dp[0] -= self.law.s0(at.r()).1;
    }
    fn add_jacobian(&self, at: &At<'_>, jac: &mut LoadJacobian) {
        let (r, n) = (at.r(), jac.n);
        let args = self.law.args(r);
        jac.pressure[0] -= self.law.s0_with(args, r).1;
        let lay = StateLayout::reduced(jac.modes());
        for m in 0..jac.modes() {
            let k = self.orders[m];
            let (s, d) = (self.law.stiffness_with(args, r, k), self.law.stiffness_dr_with(args, r, k));
            let (a, b) = (at.a(m), at.b(m));
            let (ia, ib) = (lay.a(m), lay.b(m));
            let gn = &mut jac.gn[m * n..(m + 1) * n];
            gn[0] += d[0] * a + d[1] * b;
            gn[ia] += s[0];
            gn[ib] += s[1];
            let gt = &mut jac.gt[m * n..(m + 1) * n];
            gt[0] += d[2] * a + d[3] * b;
            gt[ia] += s[2];
            gt[ib] += s[3];
        }
    }
    /// P ∋ −Ŝ0(R): q = −Ŝ0′(R) Ṙ, s = 0; ∂q/∂R = −Ŝ0″ Ṙ by the central difference of the exact
    /// Ŝ0′ (as effects/membrane.rs; across a kink of the law it is the mean of the two sides).
    fn add_rate(&self, at: &At<'_>, rate: &mut PressureRate) -> bool {
        let (r, rd) = (at.r(), at.rdot());
        let d1 = |x: f64| self.law.s0(x).1;
        let h = 1e-5 * r;
        rate.q -= d1(r) * rd;
        rate.dq[0] -= (d1(r + h) - d1(r - h)) / (2.0 * h) * rd;
        rate.dq[1] -= d1(r);
        true
    }
}

/// The scene's Marmottant term on the law `l` (a clone: it shares the law's run branch).
pub fn term(law: &ShellLaw, l: &LipidLaw, orders: &[f64]) -> Option<LipidTerm> {
    let l = l.clone();
    if let ShellLaw::Sarkar(p) = law {
        let label = format!(
            "sarkar shell (exponential elasticity) E0 = {} N/m, alpha = {}, gamma0 = {} N/m, R_E = {} m",
            p.elasticity, p.elasticity_decay, p.reference_tension, p.unstrained_radius
        );
        return Some(LipidTerm { law: l, orders: orders.to_vec(), label });
    }
    if let ShellLaw::TensionCurve(c) = law {
        let (a, s) = (&c.area_ratio, &c.tension);
        let label = format!(
            "tension-curve shell ({}: {} knots, A/A0 {}..{}, sigma {}..{} N/m, PCHIP)",
            c.file,
            a.len(),
            a[0],
            a[a.len() - 1],
            s[0],
            s[s.len() - 1]
        );
        return Some(LipidTerm { law: l, orders: orders.to_vec(), label });
    }
    let p = law.lipid()?;
    let name = if p.smoothing.is_some() { "marmottant-smooth" } else { "marmottant" };
    Some(LipidTerm {
        law: l,
        orders: orders.to_vec(),
        label: format!(
            "{name} shell chi = {} N/m, R_b = {} m, sigma(R0) = {} N/m, sigma_r = {} N/m{}",
            p.elasticity,
            p.buckling_radius,
            p.initial_tension,
            p.rupture_tension,
            p.smoothing.map(|s| format!(", s = {s} N/m")).unwrap_or_default()
        ),
    })
}
