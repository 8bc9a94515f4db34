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
//!   that fails the check falls back to differences;
//! * **finite differences** otherwise (the gas exponent, R0 through p_g0, the boundary layer's
//!   ω-dependent thickness …): central differences at h = 1e-3 |p| and h/2, Richardson
//!   extrapolated (error O(h⁴)).
//!
//! The initial state's derivative ∂Y0/∂p_j (R0 also sets R(0)) is the same Richardson quotient
//! of Y0 (exact for an affine dependence). Derivatives are taken with respect to θ_j with
//! p_j = p_j⁰ + s_j θ_j, s_j = |p_j⁰| (1 when p_j⁰ = 0): S_j has the size of the state.

use crate::integrate::sensitivity::ParameterRates;
use crate::model::{layout::StateLayout, Model};
use crate::scene::SceneTemplate;
use serde::Serialize;

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
    /// F at p ± h, p ± h/2 (θ-step `dtheta` = h/s): Richardson.
    Central { at: [Converted; 4], dtheta: f64 },
}

/// The model's [`ParameterRates`] at the current values, and the initial sensitivities.
pub struct ModelRates {
    rates: Vec<Rate>,
    /// ∂Y0/∂θ_j.
    pub s0: Vec<Vec<f64>>,
    /// How each ∂f/∂p_j is formed.
    pub derivative: Vec<Derivative>,
    work: std::cell::RefCell<Vec<f64>>,
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

impl ModelRates {
    /// The rates of `keys` at `values` (all fitted keys are set in every model; `base` is the model
    /// at `values`).
    pub fn new(template: &SceneTemplate, keys: &[&str], values: &[f64], base: &Model) -> anyhow::Result<ModelRates> {
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
            s0.push(richardson(&y[0], &y[1], &y[2], &y[3], h / s));
            let linear = if LINEAR_KEYS.contains(&key) {
                // p ± s/2 (p/2 stays in a positive key's range)
                match (build(j, p + 0.5 * s), build(j, p - 0.5 * s)) {
                    (Ok(plus), Ok(minus)) => affine_at_probes(base, &plus, &minus).then_some(plus),
                    _ => None,
                }
            } else {
                None
            };
            match linear {
                Some(plus) => {
                    rates.push(Rate::Forward { plus, dtheta: 0.5 });
                    derivative.push(Derivative::Exact);
                }
                None => {
                    rates.push(Rate::Central { at, dtheta: h / s });
                    derivative.push(Derivative::FiniteDifference);
                }
            }
        }
        let n = base.initial_state().len();
        Ok(ModelRates { rates, s0, derivative, work: std::cell::RefCell::new(vec![0.0; 4 * n]) })
    }
}

/// (4 D(h/2) − D(h))/3 with D(h) = (y⁺ − y⁻)/(2h): the central quotient extrapolated to O(h⁴).
fn richardson(plus: &[f64], minus: &[f64], half_plus: &[f64], half_minus: &[f64], h: f64) -> Vec<f64> {
    (0..plus.len())
        .map(|i| {
            let d1 = (plus[i] - minus[i]) / (2.0 * h);
            let d2 = (half_plus[i] - half_minus[i]) / h;
            (4.0 * d2 - d1) / 3.0
        })
        .collect()
}

/// Whether F is affine in the parameter at probe states (the initial state and three states
/// away from it, at t = 0 and inside the run): the second difference F⁺ − 2F + F⁻ vanishes to
/// 1e-9 of the first difference and 1e-13 of |F|.
fn affine_at_probes(base: &Model, plus: &Converted, minus: &Converted) -> bool {
    let y0 = base.initial_state();
    let n = y0.len();
    let probes: Vec<(f64, Vec<f64>)> = (0..4)
        .map(|k| {
            let y: Vec<f64> = y0
                .iter()
                .enumerate()
                .map(|(i, &v)| if k == 0 { v } else { v * (1.0 + 0.07 * k as f64) + 0.013 * (k * (i + 1)) as f64 * if i == 0 { 0.0 } else { 1.0 } })
                .collect();
            (0.37 * k as f64, y)
        })
        .collect();
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

impl ParameterRates for ModelRates {
    fn count(&self) -> usize {
        self.rates.len()
    }

    fn rate(&self, j: usize, t: f64, y: &[f64], f0: &[f64], out: &mut [f64]) {
        match &self.rates[j] {
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
                let r = richardson(a, b, c, d, *dtheta);
                out.copy_from_slice(&r);
            }
        }
    }
}
