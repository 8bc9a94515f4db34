//! `floquet`: Floquet stability of the periodic orbit of a driven scene (docs/model.md §4.6;
//! the paper's §4 with [`Variant::Paper`]).

use super::scene::Scene;
use crate::analysis::stability::{floquet as floquet_of, FloquetOptions, FloquetReport, StabilityError, CONVERGENCE_TOLERANCE};
pub use crate::analysis::stability::Variant;
use serde::{Serialize, Serializer};

/// What `floquet` and `stability --method floquet` say for a scene with quadratic coupling
/// (issue 12): they stay linear.
pub const LINEAR_ONLY: &str = "modes.coupling = quadratic: Floquet analysis is linear — it linearises the shape modes about the spherical orbit (a = 0), where the quadratic terms and their derivatives vanish, so these multipliers are those of the linear model";

/// Fewest Magnus steps per drive period accepted: below it the fourth-order scheme is not in
/// its asymptotic range on these orbits (issue 13: 1 step gave max|μ| = 0.22, "stable", where
/// the converged value is 1.78).
pub const MIN_STEPS: usize = 16;

/// A Floquet analysis and how it was made. Serialises to what `floquet --json` prints (the
/// report's fields, `"status": "ok"`, `warnings`, `parameters`; keys sorted).
#[derive(Debug, Clone)]
pub struct FloquetResult {
    pub report: FloquetReport,
    /// The analysis stays linear under quadratic coupling; max|μ| not converged in `steps`.
    pub warnings: Vec<String>,
    pub scene_file: String,
    pub overrides: Vec<String>,
    pub scene: crate::scene::Scene,
    pub options: FloquetOptions,
}

/// Why `floquet` failed: `kind` is `invalid_argument`, `no_orbit`, `no_shape_modes` or `failed`
/// (the CLI adds `scene` for a scene that does not load).
#[derive(Debug)]
pub struct Failure {
    pub kind: &'static str,
    pub error: anyhow::Error,
}

/// The status object `floquet --json` prints on failure (keys sorted, as it always printed).
#[derive(Debug, Clone, Serialize)]
pub struct FailureReport {
    pub kind: String,
    pub message: String,
    pub scene_file: String,
    pub status: &'static str,
}

impl Failure {
    /// The status object (`"status": "error"`, kind, message, scene file).
    pub fn report(&self, scene_file: &str) -> FailureReport {
        FailureReport { status: "error", kind: self.kind.to_string(), message: format!("{:#}", self.error), scene_file: scene_file.to_string() }
    }
}

/// Refuses fewer than [`MIN_STEPS`] Magnus steps per drive period.
pub fn check_steps(steps: usize) -> Result<(), Failure> {
    if steps < MIN_STEPS {
        return Err(Failure {
            kind: "invalid_argument",
            error: anyhow::anyhow!("--steps {steps}: at least {MIN_STEPS} Magnus steps per drive period are needed"),
        });
    }
    Ok(())
}

/// Floquet multipliers of `scene` with `steps` Magnus steps per drive period (and twice as
/// many for the convergence check, a warning when they differ).
pub fn floquet(scene: &Scene, variant: Variant, steps: usize) -> Result<FloquetResult, Failure> {
    check_steps(steps)?;
    let sc = scene.scene();
    let opts = FloquetOptions { variant, magnus_steps: steps, convergence_check: true, ..FloquetOptions::default() };
    let r = floquet_of(sc, &opts).map_err(|e| {
        let kind = match e {
            StabilityError::Orbit(_) => "no_orbit",
            StabilityError::NoShapeModes => "no_shape_modes",
            _ => "failed",
        };
        Failure { kind, error: anyhow::Error::new(e).context(format!("Floquet analysis of {}", scene.origin())) }
    })?;
    let mut warnings = Vec::new();
    if sc.modes.coupling == crate::scene::Coupling::Quadratic {
        warnings.push(LINEAR_ONLY.to_string());
    }
    if let Some(c) = r.convergence.as_ref().filter(|c| !c.converged) {
        warnings.push(format!(
            "max|μ| not converged to {CONVERGENCE_TOLERANCE:e} (relative above 1): {} with {} steps, {} with {} (difference {:.2e}); raise --steps",
            r.max_multiplier,
            c.steps,
            c.max_multiplier_2x_steps,
            2 * c.steps,
            c.difference
        ));
    }
    Ok(FloquetResult {
        report: r,
        warnings,
        scene_file: scene.origin().to_string(),
        overrides: scene.overrides().to_vec(),
        scene: sc.clone(),
        options: opts,
    })
}

impl FloquetResult {
    /// The serialised tree (keys sorted: `floquet --json` has always printed them so).
    fn tree(&self) -> Result<serde_json::Value, serde_json::Error> {
        let opts = &self.options;
        let mut v = serde_json::to_value(&self.report)?;
        v["status"] = "ok".into();
        v["warnings"] = self.warnings.clone().into();
        v["parameters"] = serde_json::json!({
            "scene_file": self.scene_file,
            "overrides": self.overrides,
            "scene": self.scene,
            "shooting_steps_per_period": opts.shooting.steps_per_period,
            "newton_tolerance": opts.shooting.tol,
            "orbit_multiples_tried": opts.shooting.multiples,
            "transient_decay_times": opts.transient_decay_times,
        });
        Ok(v)
    }
}

impl Serialize for FloquetResult {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.tree().map_err(serde::ser::Error::custom)?.serialize(s)
    }
}
