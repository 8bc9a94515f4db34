//! `magbubble modes SCENE [--kmax N] [--json]`: natural frequencies (corrected eq 3.10,
//! FORMULATION §4.4) and the radial frequency. `--damped`: the damped linear spectrum
//! s = −γ ± iω at R0 with the scene's viscous closure (issue 4 part 6,
//! `model::vorticity::scene::damped_spectrum`). `--plot DIR`: ω_k against k (SVG + PNG).

use crate::api::modes::{damped_of, frequencies, Modes};
use crate::plot::kinds::{omega_vs_k, Curve};
use crate::scene::Scene;
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
    /// Also write the ω_k–k plot (modes.svg/png; with --damped also the decay rates) into DIR.
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
    /// Override a scene key, KEY=VALUE (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

pub fn run(args: &ModesArgs) -> anyhow::Result<()> {
    let scene = crate::scene::load(&args.scene, &args.set)?;
    let label = args.scene.display().to_string();
    if args.damped {
        return damped(args, &scene, &label);
    }
    let f = frequencies(&scene, args.kmax, &label)?;
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&Modes::Frequencies(f.clone()))?);
    } else {
        outln!("radial: ω = {:.6e} rad/s, f = {:.6e} Hz   (t* = {:.4e} s)", f.radial.omega_rad_s, f.radial.f_hz, f.t_star);
        outln!("{:>4} {:>14} {:>14} {:>10}", "k", "omega_rad_s", "f_hz", "omega_t*");
        for m in &f.shape {
            let note = match (m.k % 2 == 0, m.field_couplings) {
                (true, true) => "",
                (false, true) => "  (odd: run/floquet/stability evolve even k only)",
                (true, false) => "  (field couplings not included)",
                (false, false) => "  (odd, field couplings not included)",
            };
            outln!("{:>4} {:>14.6e} {:>14.6e} {:>10.5}{note}", m.k, m.omega_rad_s, m.f_hz, m.omega_nondim);
        }
    }
    if let Some(dir) = &args.plot {
        let k: Vec<f64> = f.shape.iter().map(|m| m.k as f64).collect();
        let w: Vec<f64> = f.shape.iter().map(|m| m.omega_rad_s).collect();
        let fig = omega_vs_k("natural frequencies (corrected eq 3.10)", "ω_k [rad/s]", &[Curve::new("ω_k", k, w)], true);
        save(&fig, dir, "modes")?;
    }
    Ok(())
}

fn save(fig: &crate::plot::Figure, dir: &std::path::Path, stem: &str) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let s = fig.save(dir, stem).with_context(|| format!("plotting {stem} into {}", dir.display()))?;
    noteln!("wrote {} and {}", s.svg.display(), s.png.display());
    Ok(())
}

fn damped(args: &ModesArgs, scene: &Scene, label: &str) -> anyhow::Result<()> {
    let d = damped_of(scene, args.kmax, label)?;
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&Modes::Damped(d.clone()))?);
    } else {
        outln!("closure: {}   (s = −γ ± iω, linearisation at R0)", d.closure);
        outln!("{:>4} {:>14} {:>14} {:>10}", "k", "decay_per_s", "omega_rad_s", "Q = ω/2γ");
        for m in &d.shape {
            // γ = 0 (no damping): Q = ∞; ω = γ = 0 (no stiffness, no damping): Q undefined (issue 29 item 13)
            let q = crate::analysis::frequencies::quality_factor(m.omega_rad_s, m.decay_per_s);
            let q = q.map_or_else(|| "–".to_string(), |q| if q.is_infinite() { "∞".into() } else { format!("{q:.3}") });
            outln!("{:>4} {:>14.6e} {:>14.6e} {:>10}", m.k, m.decay_per_s + 0.0, m.omega_rad_s + 0.0, q);
        }
    }
    if let Some(dir) = &args.plot {
        let k: Vec<f64> = d.shape.iter().map(|m| m.k as f64).collect();
        let curves = [
            Curve::new("ω_k [rad/s]", k.clone(), d.shape.iter().map(|m| m.omega_rad_s).collect()),
            Curve::new("γ_k [1/s]", k, d.shape.iter().map(|m| m.decay_per_s).collect()),
        ];
        let fig = omega_vs_k(&format!("damped spectrum ({})", d.closure), "ω_k, γ_k", &curves, true);
        save(&fig, dir, "modes_damped")?;
    }
    Ok(())
}
