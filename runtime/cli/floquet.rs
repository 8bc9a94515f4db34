//! `magbubble floquet SCENE [--json] [--variant orbit|paper] [--steps N]`: Floquet stability of
//! the driven scene (FORMULATION §4.6; paper §4 with `--variant paper`).

use crate::analysis::stability::{floquet, FloquetOptions, StabilityError, Variant, CONVERGENCE_TOLERANCE};
use crate::scene::Scene;
use std::path::{Path, PathBuf};

/// Arguments of `magbubble floquet`.
#[derive(Debug, clap::Args)]
pub struct FloquetArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    #[arg(long)]
    pub json: bool,
    /// `orbit`: shoot the periodic radial orbit (default); `paper`: R linearised, p∞ substituted.
    #[arg(long, value_enum, default_value = "orbit")]
    pub variant: VariantArg,
    /// Magnus steps per drive period (≥ 16); the result also carries max|μ| with twice as many
    /// (`convergence`) and a warning when the two differ by more than 1e-6.
    #[arg(long, default_value_t = 400)]
    pub steps: usize,
    /// Override a scene key, KEY=VALUE (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

/// `--variant` (the command line's spelling of [`Variant`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum VariantArg {
    /// The periodic radial orbit by shooting (FORMULATION §4.6).
    Orbit,
    /// The paper's §4: R linearised about R0, p∞ substituted into R̈.
    Paper,
}

impl From<VariantArg> for Variant {
    fn from(v: VariantArg) -> Variant {
        match v {
            VariantArg::Orbit => Variant::Orbit,
            VariantArg::Paper => Variant::Paper,
        }
    }
}

/// What `floquet` and `stability --method floquet` say for a scene with quadratic coupling
/// (issue 12): they stay linear.
pub(crate) const LINEAR_ONLY: &str = "modes.coupling = quadratic: Floquet analysis is linear — it linearises the shape modes about the spherical orbit (a = 0), where the quadratic terms and their derivatives vanish, so these multipliers are those of the linear model";

/// Loads a scene with `--set` overrides.
// MERGE(scene): becomes `crate::scene::load(path, overrides)` when the scene branch lands.
pub(crate) fn load_scene(path: &Path, overrides: &[String]) -> anyhow::Result<Scene> {
    Ok(crate::scene::load(path, overrides)?)
}

/// Fewest Magnus steps per drive period `--steps` accepts: below it the fourth-order scheme is
/// not in its asymptotic range on these orbits (issue 13: 1 step gave max|μ| = 0.22, "stable",
/// where the converged value is 1.78).
pub const MIN_STEPS: usize = 16;

/// `magbubble floquet`. With `--json` stdout is always one JSON object: the report with
/// `"status": "ok"`, or `{"status": "error", "kind", "message"}` on failure (exit code 1 then).
pub fn run(args: &FloquetArgs) -> anyhow::Result<()> {
    let file = args.scene.display().to_string();
    let result = floquet_json(&file, &args.set, args.variant.into(), args.steps, || load_scene(&args.scene, &args.set));
    if args.json {
        let value = match &result {
            Ok(v) => v.clone(),
            Err((kind, e)) => error_json(kind, e, &file),
        };
        outln!("{}", serde_json::to_string_pretty(&value)?);
    }
    let v = result.map_err(|(_, e)| e)?;
    if !args.json {
        let f = |k: &str| v[k].as_f64().unwrap_or(f64::NAN);
        let period = match v["drive_period_s"].as_f64() {
            Some(dp) => format!("period {:.6e} s ({} × drive period {dp:.6e} s)", f("period_s"), v["orbit_multiple"]),
            None => format!("no drive (nothing periodic): multipliers over one time scale t* = {:.6e} s", f("period_s")),
        };
        let per = if v["drive_period_s"].is_null() { "per t*" } else { "per drive period" };
        outln!(
            "{period}, max |μ| = {:.6} ({:.6} {per}), {} (mode k = {}), R in [{:.4e}, {:.4e}] m",
            f("max_multiplier"),
            f("max_multiplier_per_drive_period"),
            if v["unstable"].as_bool() == Some(true) { "UNSTABLE" } else { "stable" },
            v["mode"],
            f("r_min_m"),
            f("r_max_m"),
        );
    }
    // After stdout, so a closed pipe ends the command before anything reaches stderr.
    for w in v["warnings"].as_array().into_iter().flatten() {
        eprintln!("warning: {}", w.as_str().unwrap_or_default());
    }
    Ok(())
}

/// Why `floquet` failed: the `kind` of the JSON status object (`invalid_argument`, `scene`,
/// `no_orbit`, `no_shape_modes`, `failed`) and the error.
pub type Failure = (&'static str, anyhow::Error);

/// The JSON status object `floquet --json` prints on failure.
pub fn error_json(kind: &str, e: &anyhow::Error, scene_file: &str) -> serde_json::Value {
    serde_json::json!({
        "status": "error",
        "kind": kind,
        "message": format!("{e:#}"),
        "scene_file": scene_file,
    })
}

/// The report `floquet --json` prints (`"status": "ok"`): the scene from `load` (the file
/// `scene_file` with `overrides`), `steps` Magnus steps per drive period. The one JSON builder
/// of the CLI and the Python package.
pub fn floquet_json(
    scene_file: &str,
    overrides: &[String],
    variant: Variant,
    steps: usize,
    load: impl FnOnce() -> anyhow::Result<Scene>,
) -> Result<serde_json::Value, Failure> {
    if steps < MIN_STEPS {
        return Err((
            "invalid_argument",
            anyhow::anyhow!("--steps {steps}: at least {MIN_STEPS} Magnus steps per drive period are needed"),
        ));
    }
    let scene = load().map_err(|e| ("scene", e))?;
    let opts = FloquetOptions { variant, magnus_steps: steps, convergence_check: true, ..FloquetOptions::default() };
    let r = floquet(&scene, &opts).map_err(|e| {
        let kind = match e {
            StabilityError::Orbit(_) => "no_orbit",
            StabilityError::NoShapeModes => "no_shape_modes",
            _ => "failed",
        };
        (kind, anyhow::Error::new(e).context(format!("Floquet analysis of {scene_file}")))
    })?;
    let mut warnings = Vec::new();
    if scene.modes.coupling == crate::scene::Coupling::Quadratic {
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
    let mut v = serde_json::to_value(&r).map_err(|e| ("failed", e.into()))?;
    v["status"] = "ok".into();
    v["warnings"] = warnings.into();
    v["parameters"] = serde_json::json!({
        "scene_file": scene_file,
        "overrides": overrides,
        "scene": scene,
        "shooting_steps_per_period": opts.shooting.steps_per_period,
        "newton_tolerance": opts.shooting.tol,
        "orbit_multiples_tried": opts.shooting.multiples,
        "transient_decay_times": opts.transient_decay_times,
    });
    Ok(v)
}
