//! `magbubble floquet SCENE [--json] [--variant orbit|paper]`: Floquet stability of the driven
//! scene (FORMULATION §4.6; paper §4 with `--variant paper`).

use crate::analysis::stability::{floquet, FloquetOptions, Variant};
use crate::scene::Scene;
use anyhow::Context;
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
    /// Magnus steps per drive period.
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

/// Loads a scene with `--set` overrides.
// MERGE(scene): becomes `crate::scene::load(path, overrides)` when the scene branch lands.
pub(crate) fn load_scene(path: &Path, overrides: &[String]) -> anyhow::Result<Scene> {
    Ok(crate::scene::load(path, overrides)?)
}

pub fn run(args: &FloquetArgs) -> anyhow::Result<()> {
    let scene = load_scene(&args.scene, &args.set)?;
    let mut opts = FloquetOptions { variant: args.variant.into(), ..FloquetOptions::default() };
    opts.magnus_steps = args.steps.max(1);
    let r = floquet(&scene, &opts).with_context(|| format!("Floquet analysis of {}", args.scene.display()))?;
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&r)?);
    } else {
        outln!(
            "period {:.6e} s ({} × drive period {:.6e} s), max |μ| = {:.6}, {} (mode k = {})",
            r.period_s,
            r.orbit_multiple,
            r.drive_period_s,
            r.max_multiplier,
            if r.unstable { "UNSTABLE" } else { "stable" },
            r.mode
        );
    }
    Ok(())
}
