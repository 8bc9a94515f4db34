//! `magbubble stability` and `magbubble merge`: stability diagrams (critical ε_p, or any scene
//! key with `--vary`, against a frequency), swept in parallel, resumable and shardable
//! (analysis::sweep). Definitions: docs/stability.md.

use crate::analysis::sweep::{self, Shard};
use crate::api::stability::{stability, Criterion, Family, FreqAxis, Modes, StabilityOutput, StabilityRequest};
use crate::api::{Monitor, Scene};
use anyhow::Context;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct StabilityArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Frequencies [Hz]: START:STOP:N (N points, linear), START:STOP:N:log (logarithmic), or a
    /// list F1,F2,… (e.g. 0.5e6,1e6,2e6).
    #[arg(long)]
    pub freq: String,
    #[arg(long, value_enum, default_value = "floquet")]
    pub method: MethodArg,
    /// A family of curves over a scene key, KEY=V1,V2,… (one CSV per value).
    #[arg(long)]
    pub family: Option<String>,
    /// The varied (critical) quantity; e.g. field.coil.current.amplitude for fig 9.
    #[arg(long, default_value = "drive.amplitude")]
    pub vary: String,
    /// The scene key the frequency axis sets (default: drive.frequency_hz, or the current
    /// frequency field.coil.current.frequency_hz when --vary is the current amplitude).
    #[arg(long)]
    pub freq_key: Option<String>,
    /// Search range LO:HI of the varied quantity.
    #[arg(long, default_value = "0:1")]
    pub range: String,
    /// Bracket tolerance relative to the critical value: unstable − stable ≤ tol · stable.
    #[arg(long, default_value_t = 1e-3)]
    pub tol: f64,
    /// Absolute bracket tolerance in the varied quantity's unit (replaces the relative --tol).
    #[arg(long, value_name = "TOL")]
    pub abs_tol: Option<f64>,
    /// Coarse scan intervals before bisection.
    #[arg(long, default_value_t = 8)]
    pub scan: usize,
    /// Output directory (default: out/<scene file stem>-stability).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Also draw the diagram (stability.svg/png: critical value against frequency, one curve
    /// per family) and the first-unstable-mode staircase (stability_mode.svg/png) into --out.
    /// Ignored for a shard (plot the merged CSV).
    #[arg(long)]
    pub plot: bool,
    /// Shard i/n of the frequency points (default from SLURM_ARRAY_TASK_ID/COUNT).
    #[arg(long)]
    pub shard: Option<String>,
    /// The mode cutoff N: `scene` (modes.max_order) or `auto` (raise N from the scene's value,
    /// doubling, until the critical value moves by less than the bracket tolerance; the CSV
    /// gains max_order_used, cutoff_converged, critical_error, min_tension; docs/stability.md).
    #[arg(long, default_value = "scene")]
    pub modes: String,
    /// The largest N `--modes auto` tries (default: the coefficient tables' k_max, 64).
    #[arg(long, value_name = "N")]
    pub cutoff_limit: Option<usize>,
    /// Override a scene key, KEY=VALUE (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

impl StabilityArgs {
    fn method_label(&self) -> String {
        match self.method {
            MethodArg::Floquet => "Floquet".into(),
            MethodArg::Series => "time series".into(),
        }
    }
}

/// `--method` (the command line's spelling of [`Criterion`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum MethodArg {
    /// Floquet multipliers of the periodic orbit (docs/stability.md).
    Floquet,
    /// Growth of a seeded perturbation in the nonlinear time series.
    Series,
}

impl From<MethodArg> for Criterion {
    fn from(m: MethodArg) -> Criterion {
        match m {
            MethodArg::Floquet => Criterion::Floquet,
            MethodArg::Series => Criterion::Series,
        }
    }
}

#[derive(Debug, clap::Args)]
pub struct MergeArgs {
    /// Shard CSVs (each with its .meta.json).
    #[arg(required = true)]
    pub inputs: Vec<PathBuf>,
    /// Merged CSV.
    #[arg(long)]
    pub out: PathBuf,
}

fn parse_range(s: &str, what: &str) -> anyhow::Result<(f64, f64)> {
    let (a, b) = s.split_once(':').with_context(|| format!("{what} '{s}': expected LO:HI"))?;
    let (a, b): (f64, f64) = (a.trim().parse()?, b.trim().parse()?);
    anyhow::ensure!(a.is_finite() && b.is_finite() && a < b, "{what} '{s}': need finite LO < HI");
    Ok((a, b))
}

/// The request of the arguments, checked before the scene is read (the order of the
/// messages: `--freq`, `--range`, `--shard`, `--tol`, `--scan`, `--vary`, `--freq-key`, then
/// the scene, then `--family`).
fn request(args: &StabilityArgs) -> anyhow::Result<(Scene, StabilityRequest)> {
    let freq = FreqAxis::parse(&args.freq)?;
    let range = parse_range(&args.range, "--range")?;
    let shard = match &args.shard {
        Some(s) => Shard::parse(s)?,
        None => Shard::from_env()?.unwrap_or(Shard::ALL),
    };
    let mut req = StabilityRequest {
        freq,
        method: args.method.into(),
        family: None,
        vary: args.vary.clone(),
        freq_key: args.freq_key.clone(),
        range,
        tol: args.tol,
        abs_tol: args.abs_tol,
        scan: args.scan,
        out: args.out.clone().unwrap_or_else(|| super::run::default_out_for(&args.scene, "stability")),
        shard,
        modes: Modes::parse(&args.modes, args.cutoff_limit)?,
    };
    req.check()?;
    let scene = Scene::load(&args.scene, &args.set)?;
    req.family = args.family.as_deref().map(Family::parse).transpose()?;
    Ok((scene, req))
}

pub fn run(args: &StabilityArgs) -> anyhow::Result<()> {
    if matches!(args.method, MethodArg::Floquet)
        && crate::scene::load(&args.scene, &args.set).is_ok_and(|s| s.modes.coupling == crate::scene::Coupling::Quadratic)
    {
        noteln!("note: {}", crate::api::floquet::LINEAR_ONLY);
    }
    let (scene, req) = request(args)?;
    for w in &scene.scene().warnings {
        noteln!("warning: {w}");
    }
    let shard = req.shard;
    // Ctrl-C / SIGTERM: stop starting points, keep the whole rows, say so, exit 128 + signal (as
    // `sweep` does; issue 29 item 13)
    #[cfg(unix)]
    let cancel = Some(crate::output::cancel_on_signal());
    #[cfg(not(unix))]
    let cancel = None;
    let monitor = Monitor { cancel, bar: true, ..Monitor::default() };
    let StabilityOutput { curves, failed, cancelled, .. } = stability(&scene, &req, &monitor)?;
    for c in &curves {
        let r = &c.report;
        noteln!("{}: {} points ({} computed, {} resumed)", c.path.display(), r.rows.len(), r.computed, r.resumed);
    }
    if cancelled {
        noteln!("interrupted: the finished points are kept; rerun the same command to resume");
        crate::output::flush_out()?;
        #[cfg(unix)]
        std::process::exit(128 + crate::output::cancelling_signal().unwrap_or(libc::SIGINT));
        #[cfg(not(unix))]
        std::process::exit(130);
    }
    let plotted: Vec<(String, PathBuf)> = curves
        .into_iter()
        .map(|c| {
            let label = if c.family.0.is_empty() { args.method_label() } else { format!("{} = {}", c.family.0, c.family.1) };
            (label, c.path)
        })
        .collect();
    if args.plot {
        if shard != Shard::ALL {
            noteln!("--plot: skipped for a shard; plot the merged CSV");
        } else {
            let y_label = if args.vary == "drive.amplitude" { "critical ε_p [–]".to_string() } else { format!("critical {}", args.vary) };
            let saved = crate::plot::stability_plot(&plotted, &req.out, "stability", &y_label, false)
                .with_context(|| format!("plotting the stability diagram into {}", req.out.display()))?;
            for s in saved {
                noteln!("wrote {} and {}", s.svg.display(), s.png.display());
            }
        }
    } else if shard == Shard::ALL {
        // an earlier diagram's plot would sit beside the new rows (issue 29 item 9)
        for stale in crate::plot::remove_stale_plots(&req.out, &["stability", "stability_mode"]) {
            noteln!("removed {} (an earlier run's plot; --plot draws a new one)", stale.display());
        }
    }
    anyhow::ensure!(failed.is_empty(), "{}", failed.join("\n"));
    Ok(())
}

pub fn merge(args: &MergeArgs) -> anyhow::Result<()> {
    let meta = sweep::merge(&args.inputs, &args.out)?;
    noteln!("{}: {} points merged from {} files", args.out.display(), meta.total, args.inputs.len());
    Ok(())
}
