//! ∂f/∂p of the model for any numeric scene key (docs/model.md, "Fitting"): the
//! [`ParameterRates`] of the sensitivity equations ([`crate::integrate::sensitivity`]).
//!
//! A scene key can change the model's units (R0 sets the length, c1 the time t* and pressure
//! scales), so every model is evaluated in the units of the base model (the one at the current
//! values): a model built with p_j changed is converted, state and time, into the base units,
//!
//!   F_p(t, Y) = D f_p(t T/T_p, D⁻¹ Y) T/T_p,   D = diag(L_p/L for lengths, (L_p/T_p)/(L/T) for
//!   velocities),
//!
//! and ∂f/∂p_j is formed from F_p:
//!
//! * **exact** where F_p is affine in p_j (the linear loads: a shell modulus, a viscosity of a
//!   radial run, the drive amplitude …): a forward difference quotient with a large step is
//!   exact up to rounding. Affinity is decided per scene from the physics' structure and checked
//!   numerically at probe states (a second difference at h = p/2 below 1e-9 of the first); a key
//!   that fails the check falls back to differences. For the boundary-layer system the quotient
//!   is taken of the loads of the terms that hold the parameter alone, not of a whole rhs: the
//!   model at p + h is built in the base model's units, its terms that differ from the base's
//!   at the probes are the parameter's, and ∂f/∂p is the chain rule of their loads' quotient
//!   ([`crate::model::sensitivity`], one pass with f and J·S) — confirmed at the probes against
//!   the whole rhs's quotient (1e-9), else the whole rhs's quotient is kept;
//! * **finite differences** otherwise (the gas exponent, R0 through p_g0, the boundary layer's
//!   ω-dependent thickness …): central differences at h = 1e-3 |p| and h/2, Richardson
//!   extrapolated (error O(h⁴)).
//!
//! The initial state's derivative ∂Y0/∂p_j (R0 also sets R(0)) is the same Richardson quotient
//! of Y0 (exact for an affine dependence). Derivatives are taken with respect to θ_j with
//! p_j = p_j⁰ + s_j θ_j, s_j = |p_j⁰| (1 when p_j⁰ = 0): S_j has the size of the state.

use crate::integrate::sensitivity::ParameterRates;
use crate::model::effects::At;
use crate::model::sensitivity::{LoadRate, ProductWork};
use crate::model::{layout::StateLayout, BoundaryLayerSystem, Model, Scales};
use crate::scene::SceneTemplate;
use serde::Serialize;
use std::cell::RefCell;

/// How ∂f/∂p of one parameter was formed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Derivative {
    /// Affine in the rhs: an exact difference quotient.
    Exact,
    /// Richardson-extrapolated central differences of the rhs.
    FiniteDifference,
}

/// A model at changed parameter values, evaluated in the base model's units.
pub(crate) struct Converted {
    pub model: Model,
    /// D per state component.
    factor: Vec<f64>,
    /// T/T_p
    time: f64,
    y: std::cell::RefCell<(Vec<f64>, Vec<f64>)>,
}

impl Converted {
    pub fn new(model: Model, base: &Model) -> Converted {
        let (l, t) = (base.scales().length, base.time_scale());
        let (lp, tp) = (model.scales().length, model.time_scale());
        let lay = StateLayout::reduced(base.orders().len());
        let mut factor = vec![lp / l; lay.dim()];
        factor[lay.rdot()] = (lp / tp) / (l / t);
        for m in 0..lay.modes() {
            factor[lay.adot(m)] = (lp / tp) / (l / t);
        }
        let n = factor.len();
        Converted { model, factor, time: t / tp, y: std::cell::RefCell::new((vec![0.0; n], vec![0.0; n])) }
    }

    /// F_p(t, Y) into `out` (base units).
    pub fn rhs(&self, t: f64, y: &[f64], out: &mut [f64]) {
        let (yp, fp) = &mut *self.y.borrow_mut();
        for ((v, &y), &d) in yp.iter_mut().zip(y).zip(&self.factor) {
            *v = y / d;
        }
        self.model.system().rhs(t * self.time, yp, fp);
        for ((o, &f), &d) in out.iter_mut().zip(fp.iter()).zip(&self.factor) {
            *o = d * f * self.time;
        }
    }

    /// The model's initial state in base units.
    pub fn initial_state(&self) -> Vec<f64> {
        self.model.initial_state().iter().zip(&self.factor).map(|(y, d)| y * d).collect()
    }
}

/// ∂f/∂θ_j of one parameter.
enum Rate {
    /// F at p + h (θ-step `dtheta`): (F⁺ − f0)/dθ.
    Forward { plus: Converted, dtheta: f64 },
    /// The loads of the terms `terms` (indices into the model's terms) at p + h (the model
    /// `plus`, in base units) against the base's: [`LoadRate::add_difference`].
    Terms { plus: Model, terms: Vec<usize>, dtheta: f64 },
    /// F at p ± h, p ± h/2 (θ-step `dtheta` = h/s): Richardson.
    Central { at: [Converted; 4], dtheta: f64 },
}

/// The model's [`ParameterRates`] at the current values, and the initial sensitivities. Its
/// [`ParameterRates::augmented_rhs`] evaluates the base model's system: give the base model's
/// system to the sensitivity system it serves (fit/solve.rs does).
pub struct ModelRates<'a> {
    rates: Vec<Rate>,
    /// ∂Y0/∂θ_j.
    pub s0: Vec<Vec<f64>>,
    /// How each ∂f/∂p_j is formed.
    pub derivative: Vec<Derivative>,
    work: RefCell<Vec<f64>>,
    /// The base's boundary-layer system when its sensitivity rhs is one pass
    /// ([`BoundaryLayerSystem::fused_sensitivities`]), with that pass's buffers.
    fused: Option<(&'a BoundaryLayerSystem, RefCell<FusedWork>)>,
}

/// The one-pass rhs's buffers: the product's, the loads' derivatives per parameter, ∂f/∂θ.
struct FusedWork {
    product: ProductWork,
    loads: Vec<Option<LoadRate>>,
    dp: Vec<f64>,
}

/// Keys whose loads are linear in the value (the structure of the terms, model/effects/): the
/// candidates for an exact quotient, each confirmed per scene by [`affine_at_probes`].
const LINEAR_KEYS: &[&str] = &[
    "shell.c1",
    "shell.c2",
    "shell.surface_tension",
    "shell.shear_viscosity",
    "shell.dilatational_viscosity",
    "shell.bending_modulus",
    "shell.susceptibility",
    "shell.thickness",
    "liquid.viscosity",
    "liquid.ambient_pressure",
    "drive.amplitude",
    "gas.reference_pressure",
    "gas.vapour_pressure",
    "bubble.initial.radius",
    "bubble.initial.velocity",
];

/// The scale s_j of a parameter: |p| (1 when p = 0).
pub fn scale_of(p: f64) -> f64 {
    if p == 0.0 { 1.0 } else { p.abs() }
}

impl<'a> ModelRates<'a> {
    /// The rates of `keys` at `values` (all fitted keys are set in every model; `base` is the model
    /// at `values`).
    pub fn new(template: &SceneTemplate, keys: &[&str], values: &[f64], base: &'a Model) -> anyhow::Result<ModelRates<'a>> {
        let build = |j: usize, v: f64| -> anyhow::Result<Converted> {
            let mut set: Vec<(&str, f64)> = keys.iter().copied().zip(values.iter().copied()).collect();
            set[j].1 = v;
            let scene = template.with(&set).map_err(|e| anyhow::anyhow!("{} = {v:e}: {e}", keys[j]))?;
            let model = Model::from_scene(&scene).map_err(|e| anyhow::anyhow!("{} = {v:e}: {e}", keys[j]))?;
            Ok(Converted::new(model, base))
        };
        let mut rates = Vec::new();
        let mut s0 = Vec::new();
        let mut derivative = Vec::new();
        for (j, (&key, &p)) in keys.iter().zip(values).enumerate() {
            let s = scale_of(p);
            let h = 1e-3 * s;
            let at = [build(j, p + h)?, build(j, p - h)?, build(j, p + 0.5 * h)?, build(j, p - 0.5 * h)?];
            let y: Vec<Vec<f64>> = at.iter().map(Converted::initial_state).collect();
            let mut ds0 = vec![0.0; y[0].len()];
            richardson(&y[0], &y[1], &y[2], &y[3], h / s, &mut ds0);
            s0.push(ds0);
            let linear = if LINEAR_KEYS.contains(&key) {
                // p ± s/2 (p/2 stays in a positive key's range)
                match (build(j, p + 0.5 * s), build(j, p - 0.5 * s)) {
                    (Ok(plus), Ok(minus)) => affine_at_probes(base, &plus, &minus).then_some(plus),
                    _ => None,
                }
            } else {
                None
            };
            // the same quotient from the terms that hold the parameter, when it is the same
            let linear = linear.map(|plus| {
                let mut set: Vec<(&str, f64)> = keys.iter().copied().zip(values.iter().copied()).collect();
                set[j].1 = p + 0.5 * s;
                let like = template.with(&set).ok().filter(|sc| Scales::from_scene(sc).length == base.scales().length);
                match like.and_then(|sc| Model::from_scene_like(&sc, base).ok()).and_then(|m| term_wise(base, m, &plus, 0.5)) {
                    Some(rate) => rate,
                    None => Rate::Forward { plus, dtheta: 0.5 },
                }
            });
            match linear {
                Some(rate) => {
                    rates.push(rate);
                    derivative.push(Derivative::Exact);
                }
                None => {
                    rates.push(Rate::Central { at, dtheta: h / s });
                    derivative.push(Derivative::FiniteDifference);
                }
            }
        }
        let n = base.initial_state().len();
        let fused = base.boundary_layer().filter(|bl| bl.fused_sensitivities()).map(|bl| {
            let w = FusedWork { product: bl.product_work(), loads: (0..rates.len()).map(|_| None).collect(), dp: vec![0.0; n] };
            (bl, RefCell::new(w))
        });
        Ok(ModelRates { rates, s0, derivative, work: RefCell::new(vec![0.0; 4 * n]), fused })
    }
}

impl ModelRates<'_> {
    /// Whether ∂f/∂θ_j is formed from the loads of the terms that hold parameter j (in the
    /// one-pass rhs) rather than from a whole rhs of a changed model.
    pub fn from_terms(&self, j: usize) -> bool {
        matches!(self.rates[j], Rate::Terms { .. })
    }
}

/// The probe states of [`affine_at_probes`]: the initial state and three states away from it,
/// at t = 0 and inside the run.
fn probes(base: &Model) -> Vec<(f64, Vec<f64>)> {
    let y0 = base.initial_state();
    (0..4)
        .map(|k| {
            let y: Vec<f64> = y0
                .iter()
                .enumerate()
                .map(|(i, &v)| if k == 0 { v } else { v * (1.0 + 0.07 * k as f64) + 0.013 * (k * (i + 1)) as f64 * if i == 0 { 0.0 } else { 1.0 } })
                .collect();
            (0.37 * k as f64, y)
        })
        .collect()
}

/// [`Rate::Terms`] for a parameter whose whole-rhs quotient `conv` (θ-step `dtheta`) is exact,
/// from `plus`, the model at θ + dθ in base units: when the two systems differ in their terms'
/// loads only (the same terms, liquid, closure, ḃ loads) and the terms' quotient through the
/// chain rule equals the whole rhs's at every probe to 1e-9 (module doc). `None`: keep `conv`.
fn term_wise(base: &Model, plus: Model, conv: &Converted, dtheta: f64) -> Option<Rate> {
    let (b, q) = (base.boundary_layer()?, plus.boundary_layer()?);
    let (eb, eq) = (b.equations(), q.equations());
    let (pb, pq) = (eb.params(), eq.params());
    let same = b.fused_sensitivities()
        && q.fused_sensitivities()
        && eb.terms.len() == eq.terms.len()
        && eb.terms.iter().zip(&eq.terms).all(|(x, y)| x.name() == y.name() && x.has_bdot_loads() == y.has_bdot_loads())
        && (pb.rho, pb.eta, pb.sound_speed) == (pq.rho, pq.eta, pq.sound_speed)
        && b.modes().iter().zip(q.modes()).all(|(x, y)| (x.k, x.viscous_length) == (y.k, y.viscous_length));
    if !same {
        return None;
    }
    let probes = probes(base);
    // the terms that hold the parameter: those whose share differs at a probe
    let terms: Vec<usize> = (0..eb.terms.len())
        .filter(|&i| {
            probes.iter().any(|(t, y)| {
                let mut r = LoadRate::default();
                r.add_difference(eb, eq.terms[i].as_ref(), eb.terms[i].as_ref(), &At { t: *t, z: y }, dtheta);
                let m = eb.orders().len();
                [r.pressure, r.q, r.s].iter().chain(&r.gn[..m]).chain(&r.gt[..m]).chain(&r.cn[..m]).chain(&r.ct[..m]).any(|&v| v != 0.0)
            })
        })
        .collect();
    if terms.is_empty() {
        return None;
    }
    let rate = Rate::Terms { plus, terms, dtheta };
    let n = base.initial_state().len();
    let mut w = b.product_work();
    let (mut f, mut fp, mut d, zero) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let agree = probes.iter().all(|(t, y)| {
        let lr = [Some(load_rate(&rate, b, *t, y))];
        b.sensitivity_rhs(*t, y, &zero, &lr, &mut w, &mut f, &mut d);
        conv.rhs(*t, y, &mut fp);
        (0..n).all(|i| {
            let quotient = (fp[i] - f[i]) / dtheta;
            let size = f[i].abs().max(fp[i].abs());
            quotient.is_finite() && (d[i] - quotient).abs() <= 1e-9 * quotient.abs() + 1e-13 * size
        })
    });
    agree.then_some(rate)
}

/// The loads' derivatives of a [`Rate::Terms`] at (t, y) (`b`: the base's system).
fn load_rate(rate: &Rate, b: &BoundaryLayerSystem, t: f64, y: &[f64]) -> LoadRate {
    let mut r = LoadRate::default();
    add_load_rate(rate, b, t, y, &mut r);
    r
}

fn add_load_rate(rate: &Rate, b: &BoundaryLayerSystem, t: f64, y: &[f64], r: &mut LoadRate) {
    if let Rate::Terms { plus, terms, dtheta } = rate {
        let (eb, eq) = (b.equations(), plus.equations());
        let at = At { t, z: y };
        for &i in terms {
            r.add_difference(eb, eq.terms[i].as_ref(), eb.terms[i].as_ref(), &at, *dtheta);
        }
    }
}

/// (4 D(h/2) − D(h))/3 with D(h) = (y⁺ − y⁻)/(2h): the central quotient extrapolated to O(h⁴),
/// into `out` (no allocation: it runs in every rhs of a sensitivity solve with such a key).
fn richardson(plus: &[f64], minus: &[f64], half_plus: &[f64], half_minus: &[f64], h: f64, out: &mut [f64]) {
    for (i, o) in out.iter_mut().enumerate() {
        let d1 = (plus[i] - minus[i]) / (2.0 * h);
        let d2 = (half_plus[i] - half_minus[i]) / h;
        *o = (4.0 * d2 - d1) / 3.0;
    }
}

/// Whether F is affine in the parameter at the probe states ([`probes`]): the second difference
/// F⁺ − 2F + F⁻ vanishes to 1e-9 of the first difference and 1e-13 of |F|.
fn affine_at_probes(base: &Model, plus: &Converted, minus: &Converted) -> bool {
    let n = base.initial_state().len();
    let probes = probes(base);
    let (mut f, mut fp, mut fm) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    probes.iter().all(|(t, y)| {
        base.system().rhs(*t, y, &mut f);
        plus.rhs(*t, y, &mut fp);
        minus.rhs(*t, y, &mut fm);
        (0..n).all(|i| {
            let second = (fp[i] - 2.0 * f[i] + fm[i]).abs();
            let first = (fp[i] - fm[i]).abs();
            let size = f[i].abs().max(fp[i].abs()).max(fm[i].abs());
            second.is_finite() && second <= 1e-9 * first + 1e-13 * size
        })
    })
}

impl ParameterRates for ModelRates<'_> {
    fn count(&self) -> usize {
        self.rates.len()
    }

    /// One pass of the base's boundary-layer system ([`BoundaryLayerSystem::sensitivity_rhs`]):
    /// f, J·S and the [`Rate::Terms`] parameters' ∂f/∂θ; the others' rates added after.
    fn augmented_rhs(&self, t: f64, y: &[f64], s: &[f64], dy: &mut [f64], ds: &mut [f64]) -> bool {
        let Some((b, work)) = &self.fused else {
            return false;
        };
        let w = &mut *work.borrow_mut();
        let m = b.modes().len();
        for (rate, lr) in self.rates.iter().zip(w.loads.iter_mut()) {
            if let Rate::Terms { .. } = rate {
                let r = lr.get_or_insert_with(LoadRate::default);
                r.clear(m);
                add_load_rate(rate, b, t, y, r);
            }
        }
        b.sensitivity_rhs(t, y, s, &w.loads, &mut w.product, dy, ds);
        let n = y.len();
        for (j, rate) in self.rates.iter().enumerate() {
            if !matches!(rate, Rate::Terms { .. }) {
                self.rate(j, t, y, dy, &mut w.dp);
                ds[j * n..(j + 1) * n].iter_mut().zip(&w.dp).for_each(|(o, d)| *o += d);
            }
        }
        true
    }

    fn rate(&self, j: usize, t: f64, y: &[f64], f0: &[f64], out: &mut [f64]) {
        match &self.rates[j] {
            Rate::Terms { .. } => {
                // outside the one pass (a caller forming f and J·S itself): the chain rule at
                // J·0, i.e. the one pass with a zero direction
                let (b, work) = self.fused.as_ref().expect("Terms rates only with the one-pass system");
                let w = &mut *work.borrow_mut();
                let n = y.len();
                let lr = [Some(load_rate(&self.rates[j], b, t, y))];
                // the zero direction and f in the rates' scratch (4n, unused by this branch)
                let scratch = &mut *self.work.borrow_mut();
                let (zero, rest) = scratch.split_at_mut(n);
                zero.fill(0.0);
                b.sensitivity_rhs(t, y, zero, &lr, &mut w.product, &mut rest[..n], out);
            }
            Rate::Forward { plus, dtheta } => {
                plus.rhs(t, y, out);
                for (o, f) in out.iter_mut().zip(f0) {
                    *o = (*o - f) / dtheta;
                }
            }
            Rate::Central { at, dtheta } => {
                let w = &mut *self.work.borrow_mut();
                let n = y.len();
                let (a, rest) = w.split_at_mut(n);
                let (b, rest) = rest.split_at_mut(n);
                let (c, d) = rest.split_at_mut(n);
                at[0].rhs(t, y, a);
                at[1].rhs(t, y, b);
                at[2].rhs(t, y, c);
                at[3].rhs(t, y, d);
                richardson(a, b, c, d, *dtheta, out);
            }
        }
    }
}
