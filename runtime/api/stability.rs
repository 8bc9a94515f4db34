//! `stability`: stability diagrams — the critical value of a scene key (ε_p by default)
//! against a frequency, one curve per family member, swept in parallel, resumable and
//! shardable ([`crate::analysis::sweep`]). Definitions: docs/stability.md.

use super::common::Monitor;
use super::scene::Scene;
pub use crate::analysis::stability::Criterion;
use crate::analysis::stability::{check_range, critical_point, CriticalOptions, StabilityError, CRITICAL_HEADER};
use crate::analysis::sweep::{self, Shard, SweepMeta};
pub use crate::analysis::cutoff::CutoffOptions;
use crate::analysis::cutoff::{critical_point_auto, CUTOFF_HEADER};
use crate::scene::schema::fmt_num;
use crate::scene::{numeric_param, path_exists, SceneTemplate};
use anyhow::Context;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The frequency axis: its values [Hz] and how it was written (part of the fingerprint of
/// the resumable CSV).
#[derive(Debug, Clone, PartialEq)]
pub struct FreqAxis {
    pub values: Vec<f64>,
    pub label: String,
}

impl FreqAxis {
    /// START:STOP:N (linear), START:STOP:N:log (logarithmic), or F1,F2,… (a list).
    pub fn parse(text: &str) -> anyhow::Result<FreqAxis> {
        Ok(FreqAxis { values: parse_freq(text)?, label: text.to_string() })
    }

    /// A list of frequencies [Hz], each finite and > 0.
    pub fn list(values: &[f64]) -> anyhow::Result<FreqAxis> {
        let label = values.iter().map(|v| format!("{v:?}")).collect::<Vec<_>>().join(",");
        anyhow::ensure!(!values.is_empty(), "freq: empty list");
        for &v in values {
            anyhow::ensure!(v.is_finite() && v > 0.0, "freq: frequency {v} must be finite and > 0");
        }
        Ok(FreqAxis { values: values.to_vec(), label })
    }
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
    anyhow::ensure!(p.len() == 3 || p.len() == 4, "--freq '{s}': expected START:STOP:N, START:STOP:N:log or a list F1,F2,…");
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

/// A family of curves: one scene key and its values (as `--set` text), one CSV per value.
#[derive(Debug, Clone, PartialEq)]
pub struct Family {
    pub key: String,
    pub values: Vec<String>,
    /// How it was written (`KEY=V1,V2,…`), for messages.
    pub text: String,
}

impl Family {
    /// `KEY=V1,V2,…`.
    pub fn parse(text: &str) -> anyhow::Result<Family> {
        let (k, vs) = text.split_once('=').with_context(|| format!("--family '{text}': expected KEY=V1,V2,…"))?;
        Ok(Family { key: k.trim().to_string(), values: vs.split(',').map(|v| v.trim().to_string()).collect(), text: text.to_string() })
    }

    /// A key and its values (each as `--set` text).
    pub fn new(key: &str, values: Vec<String>) -> Family {
        let text = format!("{key}={}", values.join(","));
        Family { key: key.to_string(), values, text }
    }
}

/// What to compute: every field is checked before any point (issue 15 class 4).
#[derive(Debug, Clone)]
pub struct StabilityRequest {
    pub freq: FreqAxis,
    pub method: Criterion,
    pub family: Option<Family>,
    /// The varied (critical) quantity, a numeric scene key.
    pub vary: String,
    /// The key the frequency axis sets (default: drive.frequency_hz, or
    /// field.coil.current.frequency_hz when `vary` is a current key).
    pub freq_key: Option<String>,
    /// Search range (LO, HI) of the varied quantity.
    pub range: (f64, f64),
    /// Bracket tolerance relative to the critical value (unless `abs_tol`).
    pub tol: f64,
    /// Absolute bracket tolerance in the varied quantity's unit.
    pub abs_tol: Option<f64>,
    /// Coarse scan intervals before bisection.
    pub scan: usize,
    /// The directory of the CSVs (+ `.meta.json`); rows already there are resumed.
    pub out: PathBuf,
    pub shard: Shard,
    /// The mode cutoff: the scene's `modes.max_order`, or raised until the critical value
    /// converges (`--modes auto`, issue 31 part 5; analysis/cutoff.rs).
    pub modes: Modes,
}

/// `--modes`: the scene's cutoff, or `auto` (analysis/cutoff.rs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Modes {
    #[default]
    Scene,
    Auto(CutoffOptions),
}

impl Modes {
    /// `scene` or `auto`, with the largest N `auto` tries.
    pub fn parse(text: &str, limit: Option<usize>) -> anyhow::Result<Modes> {
        let m = match text {
            "scene" => Modes::Scene,
            "auto" => Modes::Auto(CutoffOptions::default()),
            other => anyhow::bail!("--modes '{other}': expected 'auto' or 'scene'"),
        };
        match (m, limit) {
            (Modes::Scene, Some(l)) => anyhow::bail!("--cutoff-limit {l}: only with --modes auto"),
            (Modes::Auto(_), Some(l)) => {
                let top = crate::scene::schema::MAX_ORDER_LIMIT;
                anyhow::ensure!(l >= 4 && l % 2 == 0 && l <= top, "--cutoff-limit {l}: must be even, 4 ≤ N ≤ {top} (the coefficient tables' k_max)");
                Ok(Modes::Auto(CutoffOptions { limit: l }))
            }
            (m, None) => Ok(m),
        }
    }
}

impl StabilityRequest {
    /// The checks that need no scene: tolerance, scan, the varied and frequency keys. Returns
    /// the frequency key.
    pub fn check(&self) -> anyhow::Result<String> {
        let (lo, hi) = self.range;
        anyhow::ensure!(lo.is_finite() && hi.is_finite() && lo < hi, "--range '{lo}:{hi}': need finite LO < HI");
        anyhow::ensure!(self.tol.is_finite() && self.tol > 0.0, "--tol {}: must be a finite number > 0", self.tol);
        anyhow::ensure!(self.scan >= 1, "--scan {}: need at least 1 scan interval", self.scan);
        crate::analysis::stability::varied_param(&self.vary).map_err(|e| anyhow::anyhow!("--vary {}: {e}", self.vary))?;
        let freq_key = self.freq_key.clone().unwrap_or_else(|| {
            if self.vary.starts_with("field.coil.current") { "field.coil.current.frequency_hz".into() } else { "drive.frequency_hz".into() }
        });
        numeric_param(&freq_key).map_err(|e| anyhow::anyhow!("--freq-key {freq_key}: {e}"))?;
        anyhow::ensure!(freq_key != self.vary, "--vary {} is also the frequency axis (--freq-key)", self.vary);
        Ok(freq_key)
    }
}

/// A checked request on a scene: every curve's scene, validated at both ends of the ranges.
pub struct Plan {
    freq_key: String,
    /// (family key, value, the scene with the family's value set); one entry with empty key
    /// and value without a family.
    families: Vec<(String, String, SceneTemplate)>,
}

impl Plan {
    /// Frequency points this call computes at most (every curve, this shard's share).
    pub fn points(&self, req: &StabilityRequest) -> usize {
        self.families.len() * (0..req.freq.values.len()).filter(|&i| req.shard.owns(i)).count()
    }
}

/// Validates `req` against `scene` and the schema: a bad tolerance, scan, key, range or family
/// value is an error before any work, never a CSV of error rows.
pub fn plan(scene: &Scene, req: &StabilityRequest) -> anyhow::Result<Plan> {
    let freq_key = req.check()?;
    let (lo, hi) = req.range;
    let base = scene.template().clone();
    let mut families = Vec::new();
    match &req.family {
        None => families.push((String::new(), String::new(), base)),
        Some(Family { key: k, values, text: f }) => {
            let k = k.as_str();
            anyhow::ensure!(path_exists(k), "--family {k}: no such scene key (list them with `magbubble scene explain`)");
            anyhow::ensure!(
                k != req.vary && k != freq_key,
                "--family {k}: the family key is the {} key, so every curve would be the same; choose another key",
                if k == req.vary { "varied (--vary)" } else { "frequency (--freq-key)" }
            );
            for v in values {
                anyhow::ensure!(!v.is_empty(), "--family '{f}': empty value");
                anyhow::ensure!(!families.iter().any(|(_, w, _)| w == v), "--family '{f}': value {v} given twice");
                let t = base.with_overrides(&[format!("{k}={v}")]).with_context(|| format!("--family {k}={v}"))?;
                families.push((k.to_string(), v.to_string(), t));
            }
        }
    }
    let freqs = &req.freq.values;
    let (f0, f1) = (freqs[0], freqs[freqs.len() - 1]);
    for (k, v, t) in &families {
        let at = if k.is_empty() { String::new() } else { format!(" (--family {k}={v})") };
        if let Modes::Auto(c) = req.modes {
            let n = t.scene().modes.max_order;
            anyhow::ensure!(k != "modes.max_order", "--family modes.max_order: --modes auto chooses the cutoff itself; drop one of them");
            anyhow::ensure!(
                n >= 2 && n < c.limit,
                "--modes auto: modes.max_order = {n}{at} must be ≥ 2 and below the cutoff limit {} (the rungs are the scene's N, 2N, … up to the limit)",
                c.limit
            );
        }
        let sc = |f: f64, p: f64| {
            t.with(&[(freq_key.as_str(), f), (req.vary.as_str(), p)])
                .with_context(|| format!("the scene at {freq_key} = {}, {} = {}{at}", fmt_num(f), req.vary, fmt_num(p)))
        };
        for f in [f0, f1] {
            check_range(&sc(f, lo)?, &sc(f, hi)?, req.method)
                .with_context(|| format!("stability of {} at {freq_key} = {}, {} = {lo}:{hi}{at}", scene.origin(), fmt_num(f), req.vary))?;
        }
    }
    Ok(Plan { freq_key, families })
}

/// Column (in the sweep's fields, after the frequency) of the outcome.
const OUTCOME_FIELD: usize = 2;

/// A row whose point failed: computed again on resume, never kept as done.
fn is_error_row(fields: &[String]) -> bool {
    fields.get(OUTCOME_FIELD).is_some_and(|o| o == "error")
}

/// The [`CRITICAL_HEADER`] fields of a point that failed: outcome `error`, the message in
/// `note`, no `mode` (empty, as a computed row without one), every other cell NaN spelled as
/// the numeric cells of a computed row spell it (`{:e}` of NaN: `NaN`; one spelling of NaN in
/// every CSV).
pub fn error_fields(message: &str) -> Vec<String> {
    error_fields_of(CRITICAL_HEADER.len(), message)
}

/// [`error_fields`] for a header of `len` fields (`--modes auto` has [`CUTOFF_HEADER`] more).
fn error_fields_of(len: usize, message: &str) -> Vec<String> {
    let mut blank: Vec<String> = vec![format!("{:e}", f64::NAN); len];
    blank[1] = "error".into();
    blank[4] = String::new();
    blank[len - 1] = message.to_string();
    blank
}

/// The header of one curve's fields: [`CRITICAL_HEADER`], with [`CUTOFF_HEADER`] before `note`
/// for `--modes auto`.
pub fn point_header(modes: Modes) -> Vec<String> {
    let mut h: Vec<String> = CRITICAL_HEADER.iter().map(|s| s.to_string()).collect();
    if let Modes::Auto(_) = modes {
        let note = h.pop().unwrap_or_default();
        h.extend(CUTOFF_HEADER.iter().map(|s| s.to_string()));
        h.push(note);
    }
    h
}

/// One curve (family member) of a finished stability run.
pub struct CurveOutput {
    /// The family key and value (both empty without a family).
    pub family: (String, String),
    /// The CSV written.
    pub path: PathBuf,
    /// The CSV's header without the leading `index` column.
    pub header: Vec<String>,
    /// The rows (index, fields), how many were computed and resumed.
    pub report: sweep::SweepReport,
}

/// What [`stability`] did: every curve, and one line per curve with failed points.
pub struct StabilityOutput {
    pub curves: Vec<CurveOutput>,
    pub failed: Vec<String>,
    /// Whether the monitor's cancel stopped the run (curves after it are not started; no
    /// point starts, the points in flight are abandoned, the CSVs hold only whole rows).
    pub cancelled: bool,
}

/// Every curve's CSV written into `req.out` (resumable), returned. Progress counts points.
pub fn stability(scene: &Scene, req: &StabilityRequest, monitor: &Monitor) -> anyhow::Result<StabilityOutput> {
    let plan_ = plan(scene, req)?;
    let _lock = crate::output::DirLock::acquire(&req.out)?; // one process at a time (issue 29 item 3)
    let total = plan_.points(req);
    let Plan { freq_key, families } = plan_;
    let freqs = &req.freq.values;
    let (lo, hi) = req.range;
    let finished = AtomicUsize::new(0);
    let on_point = |_: usize, _: usize| {
        let done = finished.fetch_add(1, Ordering::Relaxed) + 1;
        monitor.progress(done as f64, total as f64);
    };
    monitor.progress(0.0, total as f64);
    let mut curves = Vec::new();
    let mut failed = Vec::new();
    for (fkey, fval, template) in families {
        let mut set = scene.overrides().to_vec();
        if !fkey.is_empty() {
            set.push(format!("{fkey}={fval}"));
        }
        let opts = CriticalOptions {
            criterion: req.method,
            lo,
            hi,
            scan: req.scan,
            tol: req.abs_tol.unwrap_or(req.tol),
            relative_tol: req.abs_tol.is_none(),
            floquet: Default::default(),
            series: Default::default(),
        };
        let stem = if fkey.is_empty() { "stability".to_string() } else { format!("stability_{fkey}={fval}") };
        let shard = req.shard;
        let name = if shard == Shard::ALL { format!("{stem}.csv") } else { format!("{stem}.shard-{}-of-{}.csv", shard.index, shard.count) };
        let csv = req.out.join(name);
        let mut header = vec![freq_key.clone()];
        header.extend(point_header(req.modes));
        let meta = SweepMeta {
            fingerprint: format!(
                "scene={:?} set={set:?} vary={} freq_key={freq_key} freq={} method={:?} range={lo}:{hi} tol={} abs_tol={:?} scan={}",
                scene.source_text(),
                req.vary,
                req.freq.label,
                req.method,
                req.tol,
                req.abs_tol,
                req.scan
            ) + &match req.modes {
                Modes::Scene => String::new(),
                Modes::Auto(c) => format!(" modes=auto limit={}", c.limit),
            },
            total: freqs.len(),
            shard,
            header,
        };
        let cancelled = || monitor.cancelled();
        let retry = |_: usize, fields: &[String]| is_error_row(fields);
        let control = sweep::Control { progress_bar: monitor.bar, cancel: monitor.cancel, on_point: Some(&on_point), retry: Some(&retry) };
        let report = sweep::run_with(Some(&csv), &meta, &control, |i| {
            let f = freqs[i];
            let at = |p: f64| {
                if cancelled() {
                    return Err(StabilityError::Scene("cancelled".into()));
                }
                template.with(&[(freq_key.as_str(), f), (req.vary.as_str(), p)]).map_err(|e| StabilityError::Scene(e.to_string()))
            };
            let mut row = vec![format!("{f:.8e}")];
            match req.modes {
                Modes::Scene => match critical_point(&at, &opts) {
                    Ok(c) => row.extend(c.fields()),
                    Err(e) => row.extend(error_fields(&e.to_string())),
                },
                Modes::Auto(cutoff) => {
                    let at_n = |p: f64, n: usize| {
                        if cancelled() {
                            return Err(StabilityError::Scene("cancelled".into()));
                        }
                        template
                            .with(&[(freq_key.as_str(), f), (req.vary.as_str(), p), ("modes.max_order", n as f64)])
                            .map_err(|e| StabilityError::Scene(e.to_string()))
                    };
                    let start = template.scene().modes.max_order;
                    match critical_point_auto(&at_n, start, &opts, &cutoff) {
                        Ok(c) => row.extend(c.fields()),
                        Err(e) => row.extend(error_fields_of(meta.header.len() - 1, &e.to_string())),
                    }
                }
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
        curves.push(CurveOutput { family: (fkey, fval), path: csv, header: meta.header, report });
        if stop {
            return Ok(StabilityOutput { curves, failed, cancelled: true });
        }
    }
    Ok(StabilityOutput { curves, failed, cancelled: false })
}
