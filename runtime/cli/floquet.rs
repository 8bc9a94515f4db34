//! `magbubble floquet SCENE [--json] [--variant orbit|paper] [--steps N]`: Floquet stability of
//! the driven scene (FORMULATION §4.6; paper §4 with `--variant paper`).

use crate::api::floquet::{check_steps, floquet, Failure, FloquetResult, Variant};
use crate::api::Scene;
use std::path::PathBuf;

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

/// `magbubble floquet`. With `--json` stdout is always one JSON object: the report with
/// `"status": "ok"`, or `{"status": "error", "kind", "message"}` on failure (exit code 1 then).
pub fn run(args: &FloquetArgs) -> anyhow::Result<()> {
    let file = args.scene.display().to_string();
    let result = check_steps(args.steps)
        .and_then(|()| Scene::load(&args.scene, &args.set).map_err(|e| Failure { kind: "scene", error: e.into() }))
        .and_then(|scene| floquet(&scene, args.variant.into(), args.steps));
    if args.json {
        match &result {
            Ok(r) => outln!("{}", serde_json::to_string_pretty(r)?),
            Err(f) => outln!("{}", serde_json::to_string_pretty(&f.report(&file))?),
        }
    }
    let r: FloquetResult = result.map_err(|f| f.error)?;
    if !args.json {
        let rep = &r.report;
        let period = match rep.drive_period_s {
            Some(dp) => format!("period {:.6e} s ({} × drive period {dp:.6e} s)", rep.period_s, rep.orbit_multiple),
            None => format!("no drive (nothing periodic): multipliers over one time scale t* = {:.6e} s", rep.period_s),
        };
        let per = if rep.drive_period_s.is_none() { "per t*" } else { "per drive period" };
        outln!(
            "{period}, max |μ| = {:.6} ({:.6} {per}), {} (mode k = {}), R in [{:.4e}, {:.4e}] m",
            rep.max_multiplier,
            rep.max_multiplier_per_drive_period,
            if rep.unstable { "UNSTABLE" } else { "stable" },
            rep.mode,
            rep.r_min_m,
            rep.r_max_m,
        );
    }
    // After stdout, so a closed pipe ends the command before anything reaches stderr.
    for w in &r.warnings {
        eprintln!("warning: {w}");
    }
    Ok(())
}
