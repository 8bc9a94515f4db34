//! `magbubble modes SCENE [--kmax N] [--json]`: natural frequencies (corrected eq 3.10,
//! FORMULATION §4.4) and the radial frequency. `--damped`: the damped linear spectrum
//! s = −γ ± iω at R0 with the scene's viscous closure (issue 4 part 6,
//! `model::vorticity::scene::damped_spectrum`). `--plot DIR`: ω_k against k (SVG + PNG).

use crate::analysis::frequencies::{natural_frequencies, Frequencies};
use crate::model::vorticity::scene::{damped_spectrum, DampedSpectrum};
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
    let scene = super::floquet::load_scene(&args.scene, &args.set)?;
    let label = args.scene.display().to_string();
    if args.damped {
        return damped(args, &scene, &label);
    }
    let f = frequencies(&scene, args.kmax, &label)?;
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&frequencies_json(&f))?);
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

/// What `modes --json` prints (`damped`: `modes --damped --json`); `label` names the scene in
/// errors. The one JSON builder of the CLI and the Python package.
pub fn modes_json(scene: &Scene, kmax: Option<usize>, damped: bool, label: &str) -> anyhow::Result<serde_json::Value> {
    Ok(if damped { damped_json(&damped_of(scene, kmax, label)?) } else { frequencies_json(&frequencies(scene, kmax, label)?) })
}

/// Natural frequencies up to `kmax` (default: the scene's modes.max_order, at least 2).
pub fn frequencies(scene: &Scene, kmax: Option<usize>, label: &str) -> anyhow::Result<Frequencies> {
    let kmax = kmax.unwrap_or(scene.modes.max_order.max(2));
    natural_frequencies(scene, kmax).with_context(|| format!("natural frequencies of {label}"))
}

/// The JSON object of `modes --json`.
pub fn frequencies_json(f: &Frequencies) -> serde_json::Value {
    serde_json::json!({
        "radial": { "omega_rad_s": f.radial.omega_rad_s, "f_hz": f.radial.f_hz },
        "shape": f.shape.iter().map(|m| serde_json::json!({
            "k": m.k, "omega_rad_s": m.omega_rad_s, "f_hz": m.f_hz, "omega_nondim": m.omega_nondim,
            "field_couplings": m.field_couplings,
            // run, floquet and stability evolve the even-mode set (docs/user-guide.md)
            "evolved": m.k % 2 == 0,
        })).collect::<Vec<_>>(),
        "t_star_s": f.t_star,
    })
}

/// The damped spectrum of the scene's closure, modes k = 2, 4, …, N with N = `kmax` (even
/// part) or the scene's max_order. NaN (JSON null) where a root was not found.
pub fn damped_of(scene: &Scene, kmax: Option<usize>, label: &str) -> anyhow::Result<DampedSpectrum> {
    let mut scene = scene.clone();
    if let Some(kmax) = kmax {
        crate::analysis::frequencies::check_kmax(kmax)?;
        scene.modes.max_order = kmax - kmax % 2;
    }
    anyhow::ensure!(
        scene.modes.max_order >= 2,
        "--damped: the scene has no shape modes (modes.max_order = {}); set modes.max_order ≥ 2",
        scene.modes.max_order
    );
    damped_spectrum(&scene).with_context(|| format!("damped spectrum of {label}"))
}

/// The JSON object of `modes --damped --json`.
pub fn damped_json(d: &DampedSpectrum) -> serde_json::Value {
    serde_json::json!({
        "closure": d.closure,
        "shape": d.shape.iter().map(|m| serde_json::json!({
            "k": m.k, "decay_per_s": m.decay_per_s, "omega_rad_s": m.omega_rad_s,
        })).collect::<Vec<_>>(),
    })
}

fn damped(args: &ModesArgs, scene: &Scene, label: &str) -> anyhow::Result<()> {
    let d = damped_of(scene, args.kmax, label)?;
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&damped_json(&d))?);
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
