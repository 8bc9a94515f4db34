//! The loads of the model, one effect per file, each a [`Term`] (issue 16 part 1).
//!
//! The mode equations ([`super::equations`], FORMULATION §4.1–4.3) see the physics only through
//! two sums, evaluated once per right-hand side:
//!
//! * the radial pressure balance P = p_in − p∞(t) − 4ηṘ/R − Ŝ0(R) + M0 + … (the right-hand side
//!   of eq 2.62 corrected, FORMULATION §4.1), which the radial form ([`super::radial::RadialForm`])
//!   turns into R̈;
//! * the shape loads G_n,k = Ŝ1 a_k + Ŝ2 b_k − M_n,k + … and G_t,k = Ŝ11 a_k + Ŝ12 b_k − M_t,k + …
//!   (FORMULATION §4.1), which enter (N), (TS) of the mode equations.
//!
//! Every term adds its share to both ([`Term::add`]) and its exact derivatives with respect to the
//! state ([`Term::add_jacobian`]), so the implicit integrators, Floquet's A(t) and the natural
//! frequencies use the same analytic linear structure. A scene assembles only the terms it asks
//! for ([`super::Model::from_scene`]); the order of the list is the order of the
//! sums (kept so that the assembled model reproduces the hand-written one bit for bit).
//!
//! Adding an effect = one more file here implementing [`Term`], plus one line in the assembly
//! (docs/architecture.md, "Adding an effect").

pub mod drive;
pub mod gas;
pub mod lipid;
pub mod lipid_quadratic;
pub mod church_hoff;
pub mod sarkar;
pub mod reduced_gas;
pub mod tension_curve;
pub mod thermal_damping;
pub mod magnetic;
pub mod membrane;
pub mod quadratic;
pub mod quadratic_bending;
pub mod quadratic_frame;
pub mod quadratic_membrane;
pub mod quadratic_shell_viscosity;
pub mod second_order;
pub mod shell;
pub mod vapour;
pub mod viscosity;

mod frame_sweep;
mod pair_rows;

use super::layout::StateLayout;

/// Largest number of shape modes (k = 2, 4, …, KMAX); bounds the stack buffers of a rhs.
pub const MAX_MODES: usize = crate::coefficients::KMAX / 2 + 1;

/// Largest boundary-layer state, 2 + 3·[`MAX_MODES`] and the reduced thermal model's gas slot
/// ([`StateLayout::with_gas`]); bounds the stack buffers of a state.
pub const MAX_DIM: usize = StateLayout::reduced(MAX_MODES).with_gas().dim();

/// `buf` filled with zeros, as a slice of f64: a stack buffer of a rhs zeroed only where it is
/// used (not its whole MAX_MODES capacity).
pub fn zeroed(buf: &mut [std::mem::MaybeUninit<f64>]) -> &mut [f64] {
    for x in buf.iter_mut() {
        x.write(0.0);
    }
    // SAFETY: every element was initialised just above; MaybeUninit<f64> has f64's layout.
    unsafe { std::slice::from_raw_parts_mut(buf.as_mut_ptr().cast::<f64>(), buf.len()) }
}

/// Where the terms are evaluated: time and the reduced state
/// z = [R, Ṙ, (a_k, ȧ_k, b_k) for k = 2, 4, …, N] (the boundary-layer state layout; the full
/// vorticity model passes its ODE part in the same layout). Nondimensional (FORMULATION §4.5).
#[derive(Debug, Clone, Copy)]
pub struct At<'a> {
    pub t: f64,
    pub z: &'a [f64],
}

impl At<'_> {
    /// The layout of z (the boundary-layer layout, whose offsets do not depend on the mode
    /// count: the accessors below compile to fixed offsets).
    #[inline]
    pub fn layout(&self) -> StateLayout {
        StateLayout::reduced(self.z.len().saturating_sub(StateLayout::RADIAL) / StateLayout::AMPLITUDES)
    }
    #[inline]
    pub fn r(&self) -> f64 {
        self.z[self.layout().r()]
    }
    #[inline]
    pub fn rdot(&self) -> f64 {
        self.z[self.layout().rdot()]
    }
    /// a_k of mode index m (k = 2(m+1)).
    #[inline]
    pub fn a(&self, m: usize) -> f64 {
        self.z[self.layout().a(m)]
    }
    /// ȧ_k of mode index m.
    #[inline]
    pub fn adot(&self, m: usize) -> f64 {
        self.z[self.layout().adot(m)]
    }
    /// b_k of mode index m.
    #[inline]
    pub fn b(&self, m: usize) -> f64 {
        self.z[self.layout().b(m)]
    }
}

/// The two sums of one evaluation. `gn`, `gt` have one entry per mode the caller wants; empty
/// slices ask for the radial pressure alone (a term then skips its shape loads).
#[derive(Debug)]
pub struct Loads<'a> {
    /// P: the pressure balance of the radial equation (FORMULATION §4.1), R̈ = form(P).
    pub pressure: f64,
    pub gn: &'a mut [f64],
    pub gt: &'a mut [f64],
}

/// Exact derivatives of the two sums with respect to z (dimension n = 2 + 3M), dense:
/// `pressure[j] = ∂P/∂z_j`, `gn[m * n + j] = ∂G_n,k/∂z_j`, `gt` likewise.
///
/// The structure is sparse and known (docs/architecture.md, "Jacobian structure"): P depends on
/// R, Ṙ and (with a field) on a_2, b_2; G_k on R, Ṙ and on modes k, k ± 2 (the field's band);
/// the dense storage is for simplicity (it is filled once per Jacobian, not per rhs).
#[derive(Debug, Clone, PartialEq)]
pub struct LoadJacobian {
    pub n: usize,
    pub pressure: Vec<f64>,
    pub gn: Vec<f64>,
    pub gt: Vec<f64>,
}

impl LoadJacobian {
    /// Zero derivatives for M modes.
    pub fn new(modes: usize) -> Self {
        let n = StateLayout::reduced(modes).dim();
        Self { n, pressure: vec![0.0; n], gn: vec![0.0; modes * n], gt: vec![0.0; modes * n] }
    }
    pub fn modes(&self) -> usize {
        self.layout().modes()
    }
    /// The layout of the columns (the boundary-layer layout).
    pub fn layout(&self) -> StateLayout {
        StateLayout::reduced((self.n - StateLayout::RADIAL) / StateLayout::AMPLITUDES)
    }
    pub fn clear(&mut self) {
        self.pressure.fill(0.0);
        self.gn.fill(0.0);
        self.gt.fill(0.0);
    }
    /// Row of ∂G_n,k/∂z for mode index m.
    pub fn gn_row(&self, m: usize) -> &[f64] {
        &self.gn[m * self.n..(m + 1) * self.n]
    }
    pub fn gt_row(&self, m: usize) -> &[f64] {
        &self.gt[m * self.n..(m + 1) * self.n]
    }
}

/// What a compressible radial form needs of the pressure balance's time derivative (Keller–
/// Miksis, issue 10; [`super::radial::RadialForm::needs_rate`]): along the motion,
/// dP/dt = q + s R̈ with
///
/// * q = ∂P/∂t + ∂P/∂R Ṙ (everything but the R̈ part; the shape amplitudes are not summed here:
///   a term whose pressure depends on them does not provide a rate, [`Term::add_rate`]),
/// * s = ∂P/∂Ṙ (the viscous −4ηṘ/R gives s = −4η/R),
///
/// and their exact derivatives with respect to (R, Ṙ), for the exact Jacobian.
///
/// A pressure that depends on the shape amplitudes (the magnetic M0 on a_2, b_2, …) adds
/// Σ ∂P/∂a_m ȧ_m to q (ȧ is a state variable) and the exact ∂q/∂(a, ȧ, b) to `dq_shape`; its
/// Σ ∂P/∂b_m ḃ_m part is kept apart in `db` because ḃ_m is not a state variable but an output of
/// the tangential closure (NS): the model adds it where it knows ḃ
/// ([`super::equations::Equations::acceleration_with`], the boundary-layer system) and takes
/// ḃ = 0 (frozen shape) where the shape is prescribed (a radial equation on its own).
#[derive(Debug, PartialEq, Default)]
pub struct PressureRate<'s> {
    pub q: f64,
    pub s: f64,
    /// (∂q/∂R, ∂q/∂Ṙ)
    pub dq: [f64; 2],
    /// (∂s/∂R, ∂s/∂Ṙ)
    pub ds: [f64; 2],
    /// The shape part (∂q/∂(a, ȧ, b), ∂P/∂b, ∂²P/∂b∂R), only when asked for
    /// ([`PressureRate::with_shape`]): R̈ with the shape frozen (a radial run, every Keller–Miksis
    /// rhs) needs q and s alone, and 1.3 kB of zeros written and copied per rhs were 14 % of a
    /// radial run (issue 34). Without it a term adds its shape terms to `q` only. The buffer is
    /// the caller's (a stack [`ShapeRate`]): a boxed one cost a malloc, memset and free per rhs
    /// of Keller–Miksis with a field and shape modes (+2.8 % instructions).
    pub shape: Option<&'s mut ShapeRate>,
}

/// The shape part of a [`PressureRate`].
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeRate {
    /// ∂q/∂(a_m, ȧ_m, b_m) at index 3m, 3m + 1, 3m + 2 (zero unless P depends on the shape).
    pub dq_shape: [f64; StateLayout::x_dim(MAX_MODES)],
    /// ∂P/∂b_m: dP/dt ∋ Σ_m db[m] ḃ_m (see above).
    pub db: [f64; MAX_MODES],
    /// ∂db[m]/∂R (db depends on t and R only: the loads are affine in the amplitudes).
    pub db_dr: [f64; MAX_MODES],
}

impl Default for ShapeRate {
    fn default() -> Self {
        Self { dq_shape: [0.0; StateLayout::x_dim(MAX_MODES)], db: [0.0; MAX_MODES], db_dr: [0.0; MAX_MODES] }
    }
}

impl<'s> PressureRate<'s> {
    /// A zero rate that also collects the shape part, adding it to `shape` (pass a zero
    /// [`ShapeRate::default`]).
    pub fn with_shape(shape: &'s mut ShapeRate) -> Self {
        Self { shape: Some(shape), ..Self::default() }
    }
    /// Whether dP/dt has a ḃ part (some db[m] ≠ 0).
    pub fn has_bdot(&self) -> bool {
        self.shape.as_ref().is_some_and(|s| s.db.iter().any(|&x| x != 0.0))
    }
    /// ∂P/∂b_m (0 without the shape part).
    #[inline]
    pub fn db(&self, m: usize) -> f64 {
        self.shape.as_ref().map_or(0.0, |s| s.db[m])
    }
    /// ∂db[m]/∂R (0 without the shape part).
    #[inline]
    pub fn db_dr(&self, m: usize) -> f64 {
        self.shape.as_ref().map_or(0.0, |s| s.db_dr[m])
    }
    /// ∂q/∂(a, ȧ, b) at shape index `x` (0 without the shape part).
    #[inline]
    pub fn dq_shape(&self, x: usize) -> f64 {
        self.shape.as_ref().map_or(0.0, |s| s.dq_shape[x])
    }
}

/// Shape loads proportional to ḃ_k (the shell viscosity, issue 11 part 3): G_n,k ∋ cn[m] ḃ_k and
/// G_t,k ∋ ct[m] ḃ_k, mode-diagonal, the coefficients depending on (t, R) only (∂/∂R in `cn_r`,
/// `ct_r`). ḃ_k is an output of (NS) and its closure, so these loads make the closure implicit;
/// the boundary-layer system solves it exactly (runtime/model/boundary_layer.rs).
#[derive(Debug)]
pub struct BdotLoads<'a> {
    pub cn: &'a mut [f64],
    pub ct: &'a mut [f64],
    pub cn_r: &'a mut [f64],
    pub ct_r: &'a mut [f64],
}

/// A term as `Any`, for the statically dispatched radial rhs ([`super::radial_fused`]), which
/// copies the terms of the types it knows. Every `'static` type has it.
pub trait AsAny {
    fn as_any(&self) -> &dyn std::any::Any;
}

impl<T: std::any::Any> AsAny for T {
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// One load of the model. See the module doc; implementors are the files of this directory.
///
/// Contract:
/// * [`add`](Term::add) adds the term's share to `loads.pressure` and, for m < `loads.gn.len()`,
///   to `loads.gn[m]`, `loads.gt[m]`. It may depend on t, R, Ṙ and on every mode amplitude
///   (a, ȧ, b): the shape loads of a first-order term are linear in (a, ȧ, b) (R-dependent
///   coefficients, any coupling k ± 2j), the pressure may be any smooth function. The
///   second-order terms of `modes.coupling = "quadratic"` (quadratic.rs, quadratic_membrane.rs,
///   lipid_quadratic.rs, …) are `Term`s too and add products of two amplitudes; the linear
///   analyses (Floquet's A(t), natural frequencies) see the first-order terms only. Per-(t, R) constants are
///   computed once per call (a term loops over the modes itself).
/// * [`add_jacobian`](Term::add_jacobian) adds the exact partial derivatives of the same
///   quantities with respect to z (property-tested against finite differences: tests/suite/
///   equations_jacobian.rs).
pub trait Term: std::fmt::Debug + AsAny {
    /// Short identifier ("membrane", "magnetic", …).
    fn name(&self) -> &'static str;
    /// Entry of the run summary's `active_effects`, if the term is worth listing.
    fn label(&self) -> Option<String> {
        None
    }
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>);
    fn add_jacobian(&self, at: &At<'_>, jac: &mut LoadJacobian);
    /// Adds the exact ∂P/∂R, ∂P/∂Ṙ of the term's share of the radial pressure at `at` (the
    /// shape amplitudes held fixed) to `dp`: the 2 × 2 radial Jacobian of the periodic-orbit
    /// search (runtime/analysis/periodic/) without a full [`LoadJacobian`]. The default takes
    /// them from [`add_jacobian`](Term::add_jacobian) over z's modes; a term overrides it with
    /// the same expressions (equality property-tested: tests/suite/pressure_gradient.rs).
    fn add_pressure_gradient(&self, at: &At<'_>, dp: &mut [f64; 2]) {
        let mut jac = LoadJacobian::new(at.z.len().saturating_sub(2) / 3);
        self.add_jacobian(at, &mut jac);
        dp[0] += jac.pressure[0];
        dp[1] += jac.pressure[1];
    }
    /// [`add`](Term::add) of the radial pressure alone (no shape loads) into `p` and
    /// [`add_pressure_gradient`](Term::add_pressure_gradient) into `dp` in one call, for the
    /// orbit search's exact radial Jacobian ([`super::equations::Equations::radial_gradient`]),
    /// which needs both at every stage. The default calls the two; a term whose value and
    /// gradient share costly factors (the gas's power, the field's prefactors) overrides it with
    /// the same expressions, so the sums are the same to the bit.
    fn add_pressure_and_gradient(&self, at: &At<'_>, p: &mut f64, dp: &mut [f64; 2]) {
        let mut loads = Loads { pressure: *p, gn: &mut [], gt: &mut [] };
        self.add(at, &mut loads);
        *p = loads.pressure;
        self.add_pressure_gradient(at, dp);
    }
    /// Half-width, in modes, of the coupling of the shape loads (0: mode k sees only itself;
    /// 1: k ± 2). Describes the Jacobian's band (docs/architecture.md, "Jacobian structure").
    fn band(&self) -> usize {
        0
    }
    /// Evaluations so far, for terms that count them (the magnetic field; 0 otherwise).
    fn evaluations(&self) -> u64 {
        0
    }
    /// Adds the term's share of the pressure's rate ([`PressureRate`]) and returns `true`; the
    /// default returns `false` ("not provided"), and a scene that combines such a term with a
    /// radial form that needs the rate (Keller–Miksis) is refused when the model is assembled.
    fn add_rate(&self, _at: &At<'_>, _rate: &mut PressureRate) -> bool {
        false
    }
    /// [`add`](Term::add) and [`add_rate`](Term::add_rate) in one call, for the Keller–Miksis
    /// rhs, which needs both at every stage ([`super::equations::Equations::radial_acceleration`]).
    /// The default calls the two; a term whose value and rate share a costly factor (the gas's
    /// power: 20 % of a radial run, issue 34) overrides it with the same expressions, so the
    /// sums are the same to the bit.
    #[inline]
    fn add_with_rate(&self, at: &At<'_>, loads: &mut Loads<'_>, rate: &mut PressureRate) -> bool {
        self.add(at, loads);
        self.add_rate(at, rate)
    }
    /// [`add_with_rate`](Term::add_with_rate) for a caller that reads only the rate's values q
    /// and s, not their gradients dq, ds (the fused radial rhs, `model/radial_fused.rs`): a term
    /// whose gradients cost evaluations of their own may leave them out; q, s and the loads are
    /// the same bits. Default: `add_with_rate`.
    fn add_with_rate_value(&self, at: &At<'_>, loads: &mut Loads<'_>, rate: &mut PressureRate) -> bool {
        self.add_with_rate(at, loads, rate)
    }
    /// Whether the term has shape loads proportional to ḃ_k ([`BdotLoads`]; default: none).
    fn has_bdot_loads(&self) -> bool {
        false
    }
    /// Adds the term's ḃ_k coefficients (for m < `c.cn.len()`); called only when
    /// [`has_bdot_loads`](Term::has_bdot_loads). Not part of [`add`](Term::add) or
    /// [`add_jacobian`](Term::add_jacobian), which see the state z only.
    fn add_bdot_loads(&self, _at: &At<'_>, _c: &mut BdotLoads<'_>) {}
}
