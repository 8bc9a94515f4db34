//! `magbubble modes SCENE [--kmax N] [--json]`: natural frequencies (corrected eq 3.10,
//! FORMULATION §4.4) and the radial frequency. `--damped` (damped spectrum) is wired in when
//! the dispersion analysis (issue 6) lands.

use crate::analysis::frequencies::natural_frequencies;
use anyhow::Context;
use std::path::PathBuf;

/// Arguments of `magbubble modes`.
#[derive(Debug, clap::Args)]
pub struct ModesArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Largest mode order k (default: the scene's modes.max_order, at least 2).
    #[arg(long)]
    pub kmax: Option<usize>,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Damped linear spectrum (decay rates) instead of the undamped frequencies.
    #[arg(long)]
    pub damped: bool,
    /// Override a scene key, KEY=VALUE (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

pub fn run(args: &ModesArgs) -> anyhow::Result<()> {
    if args.damped {
        anyhow::bail!("--damped: the damped spectrum (issue 6, analysis::dispersion) is not merged yet");
    }
    let scene = super::floquet::load_scene(&args.scene, &args.set)?;
    let kmax = args.kmax.unwrap_or(scene.modes.max_order.max(2));
    let f = natural_frequencies(&scene, kmax).with_context(|| format!("natural frequencies of {}", args.scene.display()))?;
    if args.json {
        let v = serde_json::json!({
            "radial": { "omega_rad_s": f.radial.omega_rad_s, "f_hz": f.radial.f_hz },
            "shape": f.shape.iter().map(|m| serde_json::json!({
                "k": m.k, "omega_rad_s": m.omega_rad_s, "f_hz": m.f_hz, "omega_nondim": m.omega_nondim,
                "field_couplings": m.field_couplings,
            })).collect::<Vec<_>>(),
            "t_star_s": f.t_star,
        });
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        println!("radial: ω = {:.6e} rad/s, f = {:.6e} Hz   (t* = {:.4e} s)", f.radial.omega_rad_s, f.radial.f_hz, f.t_star);
        println!("{:>4} {:>14} {:>14} {:>10}", "k", "omega_rad_s", "f_hz", "omega_t*");
        for m in &f.shape {
            let note = if m.field_couplings { "" } else { "  (field couplings not included)" };
            println!("{:>4} {:>14.6e} {:>14.6e} {:>10.5}{note}", m.k, m.omega_rad_s, m.f_hz, m.omega_nondim);
        }
    }
    Ok(())
}
