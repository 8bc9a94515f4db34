//! Checks on what a scene's keys give together (issue 15 classes 2, 5 and 6), run once every
//! key is valid on its own:
//!
//! - **derived quantities**: the time scale t* and the nondimensional groups the model computes
//!   (FORMULATION §4.5) must be finite and at most 1e12 in magnitude (a frequency, viscosity or
//!   susceptibility of 1e308 passes its own range but overflows the equations); the scales the
//!   equations divide by or raise to large powers (Re, R(0)/R0, 3κ) also at least 1e-12. The problem is
//!   reported on the key the user set: of the keys a group is made of, the one farthest (in
//!   decades) from its default;
//! - **budgets**: a fixed-step run needs `run.duration / run.integrator.dt` steps, an adaptive
//!   one at least one step per period of its fastest forcing; more than
//!   `run.integrator.max_steps` is refused before anything runs;
//! - **output size**: `series.csv` has `duration / sample_interval + 1` rows of `max_order + 2`
//!   numbers; an estimated size above `run.max_output_bytes` is refused.

use super::error::Issue;
use super::schema::{self, fmt_num, fmt_sig, DefaultValue};
use super::types::*;
use std::f64::consts::PI;

/// Bounds of a nondimensional group: beyond them double precision has no meaning left.
const GROUP_MAX: f64 = 1e12;
/// Characters per number in series.csv (`-1.2345678901234567e-10,`, the longest form).
pub const BYTES_PER_VALUE: f64 = 24.0;

/// Vacuum permeability [H/m].
const MU0: f64 = 4e-7 * PI;

/// Estimated size of series.csv [bytes] and its row count.
pub fn output_estimate(s: &Scene) -> (f64, f64) {
    let rows = (s.run.duration / s.run.sample_interval).floor() + 1.0;
    let columns = s.modes.max_order as f64 + 2.0;
    (rows, rows * columns * BYTES_PER_VALUE)
}

/// Every problem of the scene's derived quantities, budgets and output size.
pub fn check(s: &Scene) -> Vec<Issue> {
    let mut issues = Vec::new();
    let (r0, rho, c1_key) = (s.bubble.radius, s.liquid.density, s.shell.c1);
    // A free bubble (c1 = 0, issue 10): t* = R0 sqrt(rho/p0), pressure scale p0 (= 2c1/R0 with
    // c1 → p0 R0/2), so the groups below are checked with that stand-in for c1.
    let c1 = if c1_key == 0.0 { s.liquid.ambient_pressure * r0 / 2.0 } else { c1_key };
    let t_star = super::types::time_scale(&s.liquid, r0, &s.shell);
    let ts_keys = [("bubble.radius", r0), ("liquid.density", rho), ("shell.c1", c1_key)];
    if !(t_star.is_finite() && t_star > 0.0) {
        issues.push(blame(&ts_keys, format!("gives the time scale t* = sqrt(rho R0^3/(2 c1)) = {} s", fmt_sig(t_star))));
        return issues;
    }
    let kappa = s.gas.polytropic_exponent;
    if 3.0 * kappa > 1e3 {
        issues.push(blame(&[("gas.polytropic_exponent", kappa)], "gives (R0/R)^(3 kappa) with 3 kappa > 1000, which overflows for any |R/R0 - 1| > 0.7 %".into()));
    }
    // `scale`: the group is a scale the equations divide by or raise to large powers (Re, R(0)/R0,
    // 3κ), bounded on both sides; every other group is an additive load or a rate, where a tiny
    // value is exact in double precision (only negligible), so only its size is bounded (the
    // review of issue 15: c2 = 1e-14 N/m, Ṙ(0) = 1e-20 m/s, ε = 1e-20 m or p0 = 1e-8 Pa were
    // refused as "cannot be evaluated").
    let mut group = |name: &str, value: f64, scale: bool, keys: &[(&'static str, f64)]| {
        let ok = value.is_finite() && value.abs() <= GROUP_MAX && (!scale || value.abs() >= 1.0 / GROUP_MAX);
        if !ok {
            let bound = if scale { "outside [1e-12, 1e12]" } else { "above 1e12 in magnitude" };
            issues.push(blame(
                keys,
                format!("gives {name} = {}, {bound}: the equations cannot be evaluated in double precision", fmt_sig(value)),
            ));
        }
    };
    let eta = s.liquid.viscosity;
    group("Re = sqrt(2 rho c1 R0)/eta", (2.0 * rho * c1 * r0).sqrt() / eta, true,
        &[("liquid.viscosity", eta), ("liquid.density", rho), ("shell.c1", c1_key), ("bubble.radius", r0)]);
    let p0 = s.liquid.ambient_pressure;
    group("P = p0 R0/c1", p0 * r0 / c1, false, &[("liquid.ambient_pressure", p0), ("bubble.radius", r0), ("shell.c1", c1_key)]);
    let pg0 = s.gas.reference_pressure;
    // p_g0 defaults to p0: checked on its own only when it differs (else P said it).
    if pg0 != p0 {
        group("p_g0 R0/c1", pg0 * r0 / c1, false, &[("gas.reference_pressure", pg0), ("bubble.radius", r0), ("shell.c1", c1_key)]);
    }
    group("alpha = c2/c1", s.shell.c2 / c1, false, &[("shell.c2", s.shell.c2), ("shell.c1", c1_key)]);
    group("the gas exponent 3 kappa", 3.0 * kappa, true, &[("gas.polytropic_exponent", kappa)]);
    let eps = s.shell.thickness;
    group("eps/R0", eps / r0, false, &[("shell.thickness", eps), ("bubble.radius", r0)]);
    let ri = s.bubble.initial.radius;
    group("R(0)/R0", ri / r0, true, &[("bubble.initial.radius", ri), ("bubble.radius", r0)]);
    let v = s.bubble.initial.velocity;
    group("dR/dt(0) t*/R0", v * t_star / r0, false, &[("bubble.initial.velocity", v), ("bubble.radius", r0)]);
    let dur = s.run.duration;
    group("run.duration/t*", dur / t_star, false, &[("run.duration", dur)]);
    // Forcing frequencies (per t*) and the fastest one, for the adaptive budget.
    let mut f_max: f64 = 0.0;
    let mut freq = |key: &'static str, f: f64, issues_group: &mut dyn FnMut(&str, f64, bool, &[(&'static str, f64)])| {
        issues_group("2 pi f t*", 2.0 * PI * f * t_star, false, &[(key, f)]);
        f_max = f_max.max(f);
    };
    if let Some(d) = &s.drive {
        freq("drive.frequency_hz", d.frequency_hz, &mut group);
        for c in &d.components {
            freq("drive.components.frequency_hz", c.frequency_hz, &mut group);
        }
        group("eps_p p0 R0/c1", d.amplitude * p0 * r0 / c1, false, &[("drive.amplitude", d.amplitude), ("liquid.ambient_pressure", p0)]);
    }
    let chi = s.shell.susceptibility;
    match &s.field {
        Some(Field::Coil(c)) => {
            let current = match c.current {
                Current::Static { value } => ("field.coil.current", value),
                Current::Cosine { amplitude, frequency_hz } => {
                    freq("field.coil.current.frequency_hz", frequency_hz, &mut group);
                    ("field.coil.current.amplitude", amplitude)
                }
            };
            if let Some(o) = &c.distance_oscillation {
                freq("field.coil.distance_oscillation.frequency_hz", o.frequency_hz, &mut group);
            }
            let h = c.turns * current.1 / c.distance;
            group("the magnetic stress mu0 |chi| eps H^2 / c1 (H = N1 I / a)", MU0 * chi.abs() * eps * h * h / c1, false,
                &[("shell.susceptibility", chi), current, ("field.coil.turns", c.turns), ("field.coil.distance", c.distance), ("shell.thickness", eps)]);
        }
        Some(Field::Dipole(d)) => {
            let h = d.moment / d.distance.powi(3);
            group("the magnetic stress mu0 |chi| eps H^2 / c1 (H = M / z^3)", MU0 * chi.abs() * eps * h * h / c1, false,
                &[("shell.susceptibility", chi), ("field.dipole.moment", d.moment), ("field.dipole.distance", d.distance), ("shell.thickness", eps)]);
        }
        None => {}
    }
    drop(group);
    if !issues.is_empty() {
        return issues;
    }
    budget(s, f_max, &mut issues);
    let (rows, bytes) = output_estimate(s);
    let limit = s.run.max_output_bytes;
    if bytes > limit {
        issues.push(Issue::new(
            "run.sample_interval",
            Some(fmt_num(s.run.sample_interval)),
            format!(
                "series.csv would have {} rows of {} numbers, about {}, above run.max_output_bytes = {} bytes \
                 (raise run.sample_interval, or run.max_output_bytes if you mean it)",
                fmt_sig(rows),
                s.modes.max_order + 2,
                human_bytes(bytes),
                fmt_num(limit)
            ),
        ));
    }
    issues
}

/// Steps the run needs at least, against `run.integrator.max_steps`.
fn budget(s: &Scene, f_max: f64, issues: &mut Vec<Issue>) {
    let it = &s.run.integrator;
    let fixed = it.method == Method::Rk4
        || (s.modes.viscous == Viscous::Vorticity && s.vorticity.scheme == VorticityScheme::Staggered);
    let max = it.max_steps as f64;
    if fixed {
        let steps = (s.run.duration / it.dt).ceil();
        if steps > max {
            issues.push(Issue::new(
                "run.integrator.dt",
                Some(fmt_num(it.dt)),
                format!(
                    "a fixed step over run.duration = {} s takes {} steps, more than run.integrator.max_steps = {}",
                    fmt_num(s.run.duration),
                    fmt_sig(steps),
                    it.max_steps
                ),
            ));
        }
    } else if s.run.duration * f_max > max {
        issues.push(Issue::new(
            "run.duration",
            Some(fmt_num(s.run.duration)),
            format!(
                "covers {} periods of the fastest forcing ({} Hz), at least one step each: more than \
                 run.integrator.max_steps = {}",
                fmt_sig(s.run.duration * f_max),
                fmt_num(f_max),
                it.max_steps
            ),
        ));
    }
}

/// The issue on the key (of `keys`) farthest from its default in decades: the one the user set.
pub(super) fn blame(keys: &[(&'static str, f64)], reason: String) -> Issue {
    let distance = |&(key, v): &(&str, f64)| -> f64 {
        let default = match schema::param(key).map(|p| p.default) {
            Some(DefaultValue::Float(d)) if d != 0.0 => d.abs(),
            _ => 1.0,
        };
        if v == 0.0 || !v.is_finite() {
            f64::INFINITY
        } else {
            (v.abs() / default).log10().abs()
        }
    };
    let (key, value) = keys
        .iter()
        .copied()
        .max_by(|a, b| distance(a).total_cmp(&distance(b)))
        .expect("a derived quantity has keys");
    let others: Vec<String> = keys
        .iter()
        .filter(|(k, _)| *k != key)
        .map(|(k, v)| format!("{k} = {}", fmt_num(*v)))
        .collect();
    let with = if others.is_empty() { String::new() } else { format!(" (with {})", others.join(", ")) };
    Issue::new(key, Some(fmt_num(value)), format!("{reason}{with}"))
}

/// 1.2 GB, 35 MB, 800 kB.
pub fn human_bytes(b: f64) -> String {
    for (unit, scale) in [("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)] {
        if b >= scale {
            return format!("{:.1} {unit}", b / scale);
        }
    }
    format!("{b:.0} bytes")
}
