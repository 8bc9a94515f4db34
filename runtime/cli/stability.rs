//! `magbubble stability` and `magbubble merge`: stability diagrams (critical ε_p, or any scene
//! key with `--vary`, against a frequency), swept in parallel, resumable and shardable
//! (analysis::sweep). Definitions: docs/stability.md.

use crate::analysis::stability::{check_range, critical_point, Criterion, CriticalOptions, StabilityError, CRITICAL_HEADER};
use crate::analysis::sweep::{self, Shard, SweepMeta};
use crate::scene::schema::fmt_num;
use crate::scene::{numeric_param, path_exists, SceneTemplate};
use anyhow::Context;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};

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

/// `--freq`: START:STOP:N (linear), START:STOP:N:log (logarithmic), or F1,F2,… (a list).
pub fn parse_freq(s: &str) -> anyhow::Result<Vec<f64>> {
    let num = |t: &str| -> anyhow::Result<f64> {
        let v: f64 = t.trim().parse().with_context(|| format!("--freq '{s}': '{}' is not a number", t.trim()))?;
        anyhow::ensure!(v.is_finite() && v > 0.0, "--freq '{s}': frequency {v} must be finite and > 0");
        Ok(v)
    };
    if !s.contains(':') {
        let list: Vec<f64> = s.split(',').map(num).collect::<anyhow::Result<_>>()?;
        anyhow::ensure!(!list.is_empty(), "--freq '{s}': empty list");
        return Ok(list);
    }
    let p: Vec<&str> = s.split(':').collect();
    anyhow::ensure!(
        p.len() == 3 || p.len() == 4,
        "--freq '{s}': expected START:STOP:N, START:STOP:N:log or a list F1,F2,…"
    );
    let (a, b) = (num(p[0])?, num(p[1])?);
    let n: usize = p[2].trim().parse().with_context(|| format!("--freq '{s}': N must be a positive integer"))?;
    anyhow::ensure!(n >= 1 && b >= a, "--freq '{s}': need START ≤ STOP and N ≥ 1");
    let log = match p.get(3).map(|t| t.trim()) {
        None | Some("lin") => false,
        Some("log") => true,
        Some(other) => anyhow::bail!("--freq '{s}': spacing '{other}' must be lin or log"),
    };
    let u = |i: usize| if n == 1 { 0.0 } else { i as f64 / (n - 1) as f64 };
    Ok((0..n).map(|i| if log { a * (b / a).powf(u(i)) } else { a + (b - a) * u(i) }).collect())
}

/// Everything a stability run needs, checked before any point is computed.
struct Plan {
    freqs: Vec<f64>,
    lo: f64,
    hi: f64,
    shard: Shard,
    freq_key: String,
    /// (family key, value, the scene with the family's value set); one entry with empty key
    /// and value without `--family`.
    families: Vec<(String, String, SceneTemplate)>,
}

/// Validates every argument against the scene and the schema (issue 15 class 4): a bad
/// `--tol`, `--scan`, `--vary`, `--freq-key`, `--range` or `--family` value is an error before
/// any work, never a CSV of error rows.
fn plan(args: &StabilityArgs) -> anyhow::Result<Plan> {
    let freqs = parse_freq(&args.freq)?;
    let (lo, hi) = parse_range(&args.range, "--range")?;
    let shard = match &args.shard {
        Some(s) => Shard::parse(s)?,
        None => Shard::from_env()?.unwrap_or(Shard::ALL),
    };
    anyhow::ensure!(args.tol.is_finite() && args.tol > 0.0, "--tol {}: must be a finite number > 0", args.tol);
    anyhow::ensure!(args.scan >= 1, "--scan {}: need at least 1 scan interval", args.scan);
    crate::analysis::stability::varied_param(&args.vary).map_err(|e| anyhow::anyhow!("--vary {}: {e}", args.vary))?;
    let freq_key = args.freq_key.clone().unwrap_or_else(|| {
        if args.vary.starts_with("field.coil.current") { "field.coil.current.frequency_hz".into() } else { "drive.frequency_hz".into() }
    });
    numeric_param(&freq_key).map_err(|e| anyhow::anyhow!("--freq-key {freq_key}: {e}"))?;
    anyhow::ensure!(freq_key != args.vary, "--vary {} is also the frequency axis (--freq-key)", args.vary);
    let base = SceneTemplate::load(&args.scene, &args.set)?;
    for w in &base.scene().warnings {
        noteln!("warning: {w}");
    }
    let mut families = Vec::new();
    match &args.family {
        None => families.push((String::new(), String::new(), base)),
        Some(f) => {
            let (k, vs) = f.split_once('=').with_context(|| format!("--family '{f}': expected KEY=V1,V2,…"))?;
            let k = k.trim();
            anyhow::ensure!(path_exists(k), "--family {k}: no such scene key (list them with `magbubble scene explain`)");
            anyhow::ensure!(
                k != args.vary && k != freq_key,
                "--family {k}: the family key is the {} key, so every curve would be the same; choose another key",
                if k == args.vary { "varied (--vary)" } else { "frequency (--freq-key)" }
            );
            for v in vs.split(',').map(str::trim) {
                anyhow::ensure!(!v.is_empty(), "--family '{f}': empty value");
                anyhow::ensure!(!families.iter().any(|(_, w, _)| w == v), "--family '{f}': value {v} given twice");
                let t = base.with_overrides(&[format!("{k}={v}")]).with_context(|| format!("--family {k}={v}"))?;
                families.push((k.to_string(), v.to_string(), t));
            }
        }
    }
    let criterion: Criterion = args.method.into();
    let (f0, f1) = (freqs[0], freqs[freqs.len() - 1]);
    for (k, v, t) in &families {
        let at = if k.is_empty() { String::new() } else { format!(" (--family {k}={v})") };
        let scene = |f: f64, p: f64| {
            t.with(&[(freq_key.as_str(), f), (args.vary.as_str(), p)])
                .with_context(|| format!("the scene at {freq_key} = {}, {} = {}{at}", fmt_num(f), args.vary, fmt_num(p)))
        };
        for f in [f0, f1] {
            check_range(&scene(f, lo)?, &scene(f, hi)?, criterion)
                .with_context(|| format!("stability of {} at {freq_key} = {}, {} = {lo}:{hi}{at}", args.scene.display(), fmt_num(f), args.vary))?;
        }
    }
    Ok(Plan { freqs, lo, hi, shard, freq_key, families })
}

/// Column (in the sweep's fields, after the frequency) of the outcome.
const OUTCOME_FIELD: usize = 2;

/// A row whose point failed: computed again on resume, never kept as done.
fn is_error_row(fields: &[String]) -> bool {
    fields.get(OUTCOME_FIELD).is_some_and(|o| o == "error")
}

/// The [`CRITICAL_HEADER`] fields of a point that failed: outcome `error`, the message in `note`,
/// no `mode` (empty, as a computed row without one), every other cell NaN spelled as the numeric cells of a computed row spell it (`{:e}` of NaN:
/// `NaN`; one spelling of NaN in every CSV).
pub fn error_fields(message: &str) -> Vec<String> {
    let mut blank: Vec<String> = vec![format!("{:e}", f64::NAN); CRITICAL_HEADER.len()];
    blank[1] = "error".into();
    blank[4] = String::new();
    blank[CRITICAL_HEADER.len() - 1] = message.to_string();
    blank
}

/// Hooks of a stability run driven from elsewhere (the Python package).
#[derive(Clone, Copy, Default)]
pub struct Hooks<'a> {
    /// Checked before each point and each scene evaluation of a point: once set, no point
    /// starts and the points in flight are abandoned (no row), so the CSV holds only whole,
    /// finished rows; [`StabilityOutput::cancelled`] is set and a rerun resumes.
    pub cancel: Option<&'a AtomicBool>,
    /// Called after each finished point with (points finished, points to compute) of the curve.
    pub on_point: Option<&'a (dyn Fn(usize, usize) + Sync)>,
    /// The terminal progress bar of the CLI (shown on a terminal only).
    pub progress_bar: bool,
}

/// One curve (family member) of a finished stability run.
pub struct CurveOutput {
    /// The family key and value (both empty without `--family`).
    pub family: (String, String),
    pub csv: PathBuf,
    /// The CSV's header without the leading `index` column.
    pub header: Vec<String>,
    pub report: sweep::SweepReport,
}

/// What [`run_with`] did: every curve, and one line per curve with failed points.
pub struct StabilityOutput {
    pub curves: Vec<CurveOutput>,
    pub failed: Vec<String>,
    pub shard: Shard,
    /// Whether [`Hooks::cancel`] stopped the run (curves after the cancel are not started).
    pub cancelled: bool,
}

/// Frequency points of this run (all curves, this shard's share): what the hooks count.
pub fn points_of(args: &StabilityArgs) -> anyhow::Result<usize> {
    let p = plan(args)?;
    Ok(p.families.len() * (0..p.freqs.len()).filter(|&i| p.shard.owns(i)).count())
}

pub fn run(args: &StabilityArgs) -> anyhow::Result<()> {
    // Ctrl-C / SIGTERM: stop starting points, keep the whole rows, say so, exit 128 + signal (as
    // `sweep` does; issue 29 item 13)
    #[cfg(unix)]
    let cancel = Some(crate::output::cancel_on_signal());
    #[cfg(not(unix))]
    let cancel = None;
    let hooks = Hooks { progress_bar: true, cancel, ..Hooks::default() };
    if matches!(args.method, MethodArg::Floquet)
        && crate::scene::load(&args.scene, &args.set).is_ok_and(|s| s.modes.coupling == crate::scene::Coupling::Quadratic)
    {
        noteln!("note: {}", super::floquet::LINEAR_ONLY);
    }
    let StabilityOutput { curves, failed, shard, cancelled } = run_with(args, &hooks)?;
    for c in &curves {
        let r = &c.report;
        noteln!("{}: {} points ({} computed, {} resumed)", c.csv.display(), r.rows.len(), r.computed, r.resumed);
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
            (label, c.csv)
        })
        .collect();
    if args.plot {
        if shard != Shard::ALL {
            noteln!("--plot: skipped for a shard; plot the merged CSV");
        } else {
            let y_label = if args.vary == "drive.amplitude" { "critical ε_p [–]".to_string() } else { format!("critical {}", args.vary) };
            let out_dir = args.out.clone().unwrap_or_else(|| super::run::default_out_for(&args.scene, "stability"));
            let saved = crate::plot::stability_plot(&plotted, &out_dir, "stability", &y_label, false)
                .with_context(|| format!("plotting the stability diagram into {}", out_dir.display()))?;
            for s in saved {
                noteln!("wrote {} and {}", s.svg.display(), s.png.display());
            }
        }
    }
    anyhow::ensure!(failed.is_empty(), "{}", failed.join("\n"));
    Ok(())
}

/// `magbubble stability` without the plot: every curve's CSV written (resumable), returned.
pub fn run_with(args: &StabilityArgs, hooks: &Hooks) -> anyhow::Result<StabilityOutput> {
    let Plan { freqs, lo, hi, shard, freq_key, families } = plan(args)?;
    let out_dir = args.out.clone().unwrap_or_else(|| super::run::default_out_for(&args.scene, "stability"));
    let _lock = crate::output::DirLock::acquire(&out_dir)?; // one process at a time (issue 29 item 3)
    let scene_text = std::fs::read_to_string(&args.scene).with_context(|| format!("reading {}", args.scene.display()))?;
    let mut curves = Vec::new();
    let mut failed = Vec::new();
    for (fkey, fval, template) in families {
        let mut set = args.set.clone();
        if !fkey.is_empty() {
            set.push(format!("{fkey}={fval}"));
        }
        let opts = CriticalOptions {
            criterion: args.method.into(),
            lo,
            hi,
            scan: args.scan,
            tol: args.abs_tol.unwrap_or(args.tol),
            relative_tol: args.abs_tol.is_none(),
            floquet: Default::default(),
            series: Default::default(),
        };
        let stem = if fkey.is_empty() { "stability".to_string() } else { format!("stability_{fkey}={fval}") };
        let name = if shard == Shard::ALL { format!("{stem}.csv") } else { format!("{stem}.shard-{}-of-{}.csv", shard.index, shard.count) };
        let csv = out_dir.join(name);
        let mut header = vec![freq_key.clone()];
        header.extend(CRITICAL_HEADER.iter().map(|s| s.to_string()));
        let meta = SweepMeta {
            fingerprint: format!(
                "scene={scene_text:?} set={set:?} vary={} freq_key={freq_key} freq={} method={:?} range={lo}:{hi} tol={} abs_tol={:?} scan={}",
                args.vary, args.freq, Criterion::from(args.method), args.tol, args.abs_tol, args.scan
            ),
            total: freqs.len(),
            shard,
            header,
        };
        let cancelled = || hooks.cancel.is_some_and(|c| c.load(Ordering::Relaxed));
        let retry = |_: usize, fields: &[String]| is_error_row(fields);
        let control = sweep::Control { progress_bar: hooks.progress_bar, cancel: hooks.cancel, on_point: hooks.on_point, retry: Some(&retry) };
        let report = sweep::run_with(Some(&csv), &meta, &control, |i| {
            let f = freqs[i];
            let at = |p: f64| {
                if cancelled() {
                    return Err(StabilityError::Scene("cancelled".into()));
                }
                template
                    .with(&[(freq_key.as_str(), f), (args.vary.as_str(), p)])
                    .map_err(|e| StabilityError::Scene(e.to_string()))
            };
            let mut row = vec![format!("{f:.8e}")];
            match critical_point(&at, &opts) {
                Ok(c) => row.extend(c.fields()),
                Err(e) => row.extend(error_fields(&e.to_string())),
            }
            // a point cut short by the cancel is abandoned, not written as an error
            (!cancelled()).then_some(row)
        })?;
        let stop = report.cancelled;
        let errors: Vec<&(usize, Vec<String>)> = report.rows.iter().filter(|(_, r)| is_error_row(r)).collect();
        if let Some((_, first)) = errors.first() {
            failed.push(format!(
                "{}: {} of {} points failed (first at {freq_key} = {}: {}); a rerun computes them again",
                csv.display(),
                errors.len(),
                report.rows.len(),
                first[0],
                first[first.len() - 1]
            ));
        }
        curves.push(CurveOutput { family: (fkey, fval), csv, header: meta.header, report });
        if stop {
            return Ok(StabilityOutput { curves, failed, shard, cancelled: true });
        }
    }
    Ok(StabilityOutput { curves, failed, shard, cancelled: false })
}

pub fn merge(args: &MergeArgs) -> anyhow::Result<()> {
    let meta = sweep::merge(&args.inputs, &args.out)?;
    noteln!("{}: {} points merged from {} files", args.out.display(), meta.total, args.inputs.len());
    Ok(())
}
