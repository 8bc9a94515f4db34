//! `[run]` → [`Run`]: the duration, the sampling, the integrator settings and the default step
//! 1e-3 t* (docs/model.md §4.5), with the key to blame when that default is longer than the run.

use super::super::raw::*;
use super::super::schema::{self, fmt_num};
use super::super::types::*;
use super::Check;

pub(super) fn build_run(
    c: &mut Check,
    raw: Option<RawRun>,
    bubble: &Bubble,
    shell: &Shell,
    liquid: &Liquid,
) -> Run {
    let rr = raw.unwrap_or_default();
    let duration = c.float("run.duration", rr.duration);
    let sample_interval = c.float("run.sample_interval", rr.sample_interval);
    if sample_interval > duration && duration > 0.0 {
        c.push(
            "run.sample_interval",
            Some(fmt_num(sample_interval)),
            format!("must not exceed run.duration = {}", fmt_num(duration)),
        );
    }
    let blow_up_threshold = c.float("run.blow_up_threshold", rr.blow_up_threshold);
    let ri = rr.integrator.unwrap_or_default();
    // t* = sqrt(rho R0^3 / (2 c1)), FORMULATION sec 4.5 (free bubble: R0 sqrt(rho/p0)).
    let t_star = time_scale(liquid, bubble.radius, shell);
    let dt = c.float_or("run.integrator.dt", ri.dt, schema::DT_OVER_TSTAR * t_star);
    if ri.dt.is_none() && !(t_star.is_finite() && t_star > 0.0) {
        // Not the user's run.integrator.dt: the time scale it defaults to (scene::derived says which key).
    } else if ri.dt.is_none() && dt > duration && duration > 0.0 {
        // The default step is longer than the run: blame the key that made it so.
        c.issues.push(super::super::derived::blame(
            &[
                ("run.duration", duration),
                ("bubble.radius", bubble.radius),
                ("liquid.density", liquid.density),
                ("shell.c1", shell.c1),
            ],
            format!(
                "gives the default run.integrator.dt = 1e-3 t* = {} s (t* = sqrt(rho R0^3/(2 c1))), longer than \
                 run.duration = {} s; set run.integrator.dt",
                schema::fmt_sig(dt),
                fmt_num(duration)
            ),
        ));
    } else if dt > duration && duration > 0.0 {
        c.push(
            "run.integrator.dt",
            Some(fmt_num(dt)),
            format!("must not exceed run.duration = {}", fmt_num(duration)),
        );
    }
    let integrator = IntegratorSettings {
        method: match c.choice("run.integrator.method", ri.method.as_deref()) {
            "auto" => Method::Auto,
            "rk4" => Method::Rk4,
            "dopri5" => Method::Dopri5,
            "dop853" => Method::Dop853,
            "radau5" => Method::Radau5,
            "rosenbrock23" => Method::Rosenbrock23,
            other => unreachable!("schema choice {other}"),
        },
        rtol: c.float("run.integrator.rtol", ri.rtol),
        atol: c.float("run.integrator.atol", ri.atol),
        dt,
        dt_given: ri.dt.is_some(),
        max_steps: u64::try_from(c.int("run.integrator.max_steps", ri.max_steps)).unwrap_or(0),
    };
    Run {
        duration,
        sample_interval,
        integrator,
        blow_up_threshold,
        max_output_bytes: c.float("run.max_output_bytes", rr.max_output_bytes),
    }
}
