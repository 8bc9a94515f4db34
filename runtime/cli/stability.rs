//! `magbubble stability` and `magbubble merge`: stability diagrams (critical ε_p, or any scene
//! key with `--vary`, against a frequency), swept in parallel, resumable and shardable
//! (analysis::sweep). Definitions: docs/stability.md.

use crate::analysis::stability::{critical_point, Criterion, CriticalOptions, StabilityError, CRITICAL_HEADER};
use crate::analysis::sweep::{self, Shard, SweepMeta};
use crate::scene::{Current, Field, Scene};
use anyhow::Context;
use std::path::{Path, PathBuf};

#[derive(Debug, clap::Args)]
pub struct StabilityArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Frequencies [Hz]: START:STOP:N (N points, linear), START:STOP:N:log (logarithmic), or a
    /// list F1,F2,… (e.g. 0.5e6,1e6,2e6).
    #[arg(long)]
    pub freq: String,
    #[arg(long, value_enum, default_value = "floquet")]
    pub method: Criterion,
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
    #[arg(long, default_value = "stability-out")]
    pub out: PathBuf,
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
            Criterion::Floquet => "Floquet".into(),
            Criterion::Series => "time series".into(),
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

/// Sets a numeric scene key directly when it is one of the swept keys with a fast path;
/// `false` when the key needs the scene loader's `--set` mechanism.
pub(crate) fn set_fast(scene: &mut Scene, key: &str, value: f64) -> bool {
    match key {
        "drive.amplitude" | "drive.frequency_hz" => {
            let d = scene.drive.get_or_insert(crate::scene::Drive { amplitude: 0.0, frequency_hz: 1e6 });
            if key == "drive.amplitude" { d.amplitude = value } else { d.frequency_hz = value }
            true
        }
        "field.coil.current.amplitude" | "field.coil.current.frequency_hz" => match &mut scene.field {
            Some(Field::Coil(c)) => {
                let (amp, f) = match c.current {
                    Current::Cosine { amplitude, frequency_hz } => (amplitude, frequency_hz),
                    Current::Static { value } => (value, 1e6),
                };
                c.current = if key.ends_with("amplitude") {
                    Current::Cosine { amplitude: value, frequency_hz: f }
                } else {
                    Current::Cosine { amplitude: amp, frequency_hz: value }
                };
                true
            }
            _ => false,
        },
        _ => false,
    }
}

fn scene_with(path: &Path, base_set: &[String], base: &Scene, pairs: &[(&str, f64)]) -> Result<Scene, StabilityError> {
    let mut s = base.clone();
    let mut slow = Vec::new();
    for &(k, v) in pairs {
        if !set_fast(&mut s, k, v) {
            slow.push(format!("{k}={v:e}"));
        }
    }
    if slow.is_empty() {
        return Ok(s);
    }
    let mut all = base_set.to_vec();
    all.extend(pairs.iter().map(|(k, v)| format!("{k}={v:e}")));
    super::floquet::load_scene(path, &all).map_err(|e| StabilityError::Scene(format!("{e:#}")))
}

pub fn run(args: &StabilityArgs) -> anyhow::Result<()> {
    let freqs = parse_freq(&args.freq)?;
    let (lo, hi) = parse_range(&args.range, "--range")?;
    let shard = match &args.shard {
        Some(s) => Shard::parse(s)?,
        None => Shard::from_env()?.unwrap_or(Shard::ALL),
    };
    let freq_key = args.freq_key.clone().unwrap_or_else(|| {
        if args.vary.starts_with("field.coil.current") { "field.coil.current.frequency_hz".into() } else { "drive.frequency_hz".into() }
    });
    let family: Vec<(String, String)> = match &args.family {
        None => vec![(String::new(), String::new())],
        Some(f) => {
            let (k, vs) = f.split_once('=').with_context(|| format!("--family '{f}': expected KEY=V1,V2,…"))?;
            vs.split(',').map(|v| (k.trim().to_string(), v.trim().to_string())).collect()
        }
    };
    let scene_text = std::fs::read_to_string(&args.scene).with_context(|| format!("reading {}", args.scene.display()))?;
    let mut plotted: Vec<(String, PathBuf)> = Vec::new();
    for (fkey, fval) in family {
        let mut set = args.set.clone();
        if !fkey.is_empty() {
            set.push(format!("{fkey}={fval}"));
        }
        let base = super::floquet::load_scene(&args.scene, &set)?;
        let opts = CriticalOptions {
            criterion: args.method,
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
        let csv = args.out.join(name);
        let mut header = vec![freq_key.clone()];
        header.extend(CRITICAL_HEADER.iter().map(|s| s.to_string()));
        let meta = SweepMeta {
            fingerprint: format!(
                "scene={scene_text:?} set={set:?} vary={} freq_key={freq_key} freq={} method={:?} range={lo}:{hi} tol={} abs_tol={:?} scan={}",
                args.vary, args.freq, args.method, args.tol, args.abs_tol, args.scan
            ),
            total: freqs.len(),
            shard,
            header,
        };
        let report = sweep::run(&csv, &meta, true, |i| {
            let f = freqs[i];
            let at = |p: f64| scene_with(&args.scene, &set, &base, &[(freq_key.as_str(), f), (args.vary.as_str(), p)]);
            let mut row = vec![format!("{f:.8e}")];
            match critical_point(&at, &opts) {
                Ok(c) => row.extend(c.fields()),
                Err(e) => {
                    let mut blank: Vec<String> = vec![String::from("nan"); CRITICAL_HEADER.len()];
                    blank[1] = "error".into();
                    blank[CRITICAL_HEADER.len() - 1] = e.to_string();
                    row.extend(blank);
                }
            }
            row
        })?;
        eprintln!("{}: {} points ({} computed, {} resumed)", csv.display(), report.rows.len(), report.computed, report.resumed);
        let label = if fkey.is_empty() { args.method_label() } else { format!("{fkey} = {fval}") };
        plotted.push((label, csv));
    }
    if args.plot {
        if shard != Shard::ALL {
            eprintln!("--plot: skipped for a shard; plot the merged CSV");
        } else {
            let y_label = if args.vary == "drive.amplitude" { "critical ε_p".to_string() } else { format!("critical {}", args.vary) };
            let saved = crate::plot::stability_plot(&plotted, &args.out, "stability", &y_label, false)
                .with_context(|| format!("plotting the stability diagram into {}", args.out.display()))?;
            for s in saved {
                eprintln!("wrote {} and {}", s.svg.display(), s.png.display());
            }
        }
    }
    Ok(())
}

pub fn merge(args: &MergeArgs) -> anyhow::Result<()> {
    let meta = sweep::merge(&args.inputs, &args.out)?;
    eprintln!("{}: {} points merged from {} files", args.out.display(), meta.total, args.inputs.len());
    Ok(())
}
