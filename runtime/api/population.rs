//! `population`: per frequency, every bin's critical ε_p (Floquet, as `stability`) and the
//! weighted fraction of the population that is shape-unstable on a grid of ε_p
//! (docs/population.md). The (frequency, bin) points are a sweep ([`crate::analysis::sweep`]):
//! parallel, resumable, shardable (`population_points.csv`, merged by `magbubble merge`); once
//! every point is there, population_bins.csv and population.csv are written from the points.

use super::common::Monitor;
use super::scene::Scene;
use super::stability::{error_fields, FreqAxis};
use crate::analysis::bisect::Verdict;
use crate::analysis::ladder;
use crate::analysis::stability::{check_range, critical_point, CriticalOptions, Criterion, StabilityError};
use crate::analysis::sweep::{self, Shard, SweepMeta};
use crate::population::fraction::{eps_grid, Threshold};
use crate::population::{bin_templates, tables};
use crate::scene::schema::fmt_num;
use crate::scene::PopulationBin;
use crate::scene::SceneTemplate;
use anyhow::Context;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

pub use crate::population::tables::{PopulationTables, POINTS_HEADER};

/// The varied quantity and the frequency key (a population map is ε_p against f_d).
pub const VARY: &str = "drive.amplitude";
pub const FREQ_KEY: &str = "drive.frequency_hz";

/// What to compute.
#[derive(Debug, Clone)]
pub struct PopulationRequest {
    pub freq: FreqAxis,
    /// Search range (LO, HI) of ε_p per bin, as `stability --range`.
    pub range: (f64, f64),
    /// Points of the ε_p grid of population.csv (LO..HI inclusive).
    pub eps_points: usize,
    pub tol: f64,
    pub abs_tol: Option<f64>,
    pub scan: usize,
    /// Evaluate each bin with a threshold once more at the top of the range (a bin stable
    /// again there has a second stable window: reported).
    pub window_check: bool,
    pub out: PathBuf,
    pub shard: Shard,
}

impl PopulationRequest {
    pub fn check(&self) -> anyhow::Result<()> {
        let (lo, hi) = self.range;
        anyhow::ensure!(lo.is_finite() && hi.is_finite() && lo < hi, "--range '{lo}:{hi}': need finite LO < HI");
        anyhow::ensure!(self.tol.is_finite() && self.tol > 0.0, "--tol {}: must be a finite number > 0", self.tol);
        anyhow::ensure!(self.scan >= 1, "--scan {}: need at least 1 scan interval", self.scan);
        anyhow::ensure!(self.eps_points >= 1, "--eps-points {}: need at least 1 point", self.eps_points);
        Ok(())
    }

    fn options(&self) -> CriticalOptions {
        let (lo, hi) = self.range;
        CriticalOptions {
            criterion: Criterion::Floquet,
            lo,
            hi,
            scan: self.scan,
            tol: self.abs_tol.unwrap_or(self.tol),
            relative_tol: self.abs_tol.is_none(),
            floquet: Default::default(),
            series: Default::default(),
        }
    }

    /// What the points depend on (the sweep's fingerprint): not the ε_p grid.
    fn fingerprint(&self, scene: &Scene) -> String {
        let (lo, hi) = self.range;
        format!(
            "population scene={:?} set={:?} freq={} range={lo}:{hi} tol={} abs_tol={:?} scan={} window_check={}",
            scene.source_text(),
            scene.overrides(),
            self.freq.label,
            self.tol,
            self.abs_tol,
            self.scan,
            self.window_check
        )
    }
}

/// The bins of a scene with `[population]`, each its validated scene.
pub struct Plan {
    pub bins: Vec<(SceneTemplate, PopulationBin)>,
}

/// Checks the request and every bin's scene (at both ends of the frequency axis and of the
/// range) before any point: an invalid bin is an error, never a CSV of error rows.
pub fn plan(scene: &Scene, req: &PopulationRequest) -> anyhow::Result<Plan> {
    req.check()?;
    let pop = scene.scene().population.as_ref().with_context(|| format!("{}: no [population] section (docs/population.md)", scene.origin()))?;
    let templates = bin_templates(scene.template(), pop)?;
    let (lo, hi) = req.range;
    let freqs = &req.freq.values;
    let mut bins = Vec::new();
    for (i, (t, b)) in templates.into_iter().zip(pop.bins.iter().copied()).enumerate() {
        for f in [freqs[0], freqs[freqs.len() - 1]] {
            let at = |p: f64| t.with(&[(FREQ_KEY, f), (VARY, p)]).with_context(|| format!("population bin {i} (radius {} m) at {FREQ_KEY} = {}, ε_p = {p}", fmt_num(b.radius), fmt_num(f)));
            check_range(&at(lo)?, &at(hi)?, Criterion::Floquet).with_context(|| format!("population bin {i} (radius {} m) at {FREQ_KEY} = {}", fmt_num(b.radius), fmt_num(f)))?;
        }
        bins.push((t, b));
    }
    Ok(Plan { bins })
}

/// What [`population`] did.
pub struct PopulationOutput {
    /// The points CSV written (this shard's).
    pub points_csv: PathBuf,
    pub report: sweep::SweepReport,
    /// The tables (and their files in `req.out`) once every point of the whole population is
    /// there: `None` for a shard or a cancelled run.
    pub tables: Option<PopulationTables>,
    /// One line if points failed (they are computed again by a rerun).
    pub failed: Option<String>,
    pub cancelled: bool,
}

/// The name of the points CSV of a shard.
pub fn points_name(shard: Shard) -> String {
    if shard == Shard::ALL { "population_points.csv".into() } else { format!("population_points.shard-{}-of-{}.csv", shard.index, shard.count) }
}

/// One (frequency, bin) point: index = frequency index × bins + bin index.
fn compute_point(t: &SceneTemplate, bin: PopulationBin, f: f64, req: &PopulationRequest, opts: &CriticalOptions, cancelled: &dyn Fn() -> bool) -> Option<Vec<String>> {
    let at = |p: f64| {
        if cancelled() {
            return Err(StabilityError::Scene("cancelled".into()));
        }
        t.with(&[(FREQ_KEY, f), (VARY, p)]).map_err(|e| StabilityError::Scene(e.to_string()))
    };
    let mut row = vec![format!("{f:.8e}"), format!("{:e}", bin.radius), format!("{:e}", bin.weight)];
    let mut windows = String::new();
    match critical_point(&at, opts) {
        Ok(c) => {
            let fields = c.fields();
            let threshold = Threshold::of(&fields[1], c.outcome.value().unwrap_or(f64::NAN), fields[3].parse().unwrap_or(f64::NAN));
            if req.window_check && matches!(threshold, Threshold::From(_)) {
                // the search's own verdict rule (cheap Magnus rungs first, ladder.rs)
                windows = match at(opts.hi).and_then(|s| ladder::evaluate(&s, &opts.floquet)) {
                    Ok((e, _)) if e.verdict == Verdict::Unstable => "1".into(),
                    Ok((e, _)) if e.verdict == Verdict::Stable => "2+".into(),
                    Ok(_) => format!("unknown: no periodic orbit at eps_p = {}", opts.hi),
                    Err(e) => format!("unknown: {e}"),
                };
            }
            row.extend(fields);
        }
        Err(e) => row.extend(error_fields(&e.to_string())),
    }
    row.push(windows);
    (!cancelled()).then_some(row)
}

/// Every point of this shard into `req.out` (resumable); the tables when the population is
/// complete. Progress counts points.
pub fn population(scene: &Scene, req: &PopulationRequest, monitor: &Monitor) -> anyhow::Result<PopulationOutput> {
    let Plan { bins } = plan(scene, req)?;
    let freqs = &req.freq.values;
    let nb = bins.len();
    let total = freqs.len() * nb;
    let opts = req.options();
    let csv = req.out.join(points_name(req.shard));
    let meta = SweepMeta {
        fingerprint: req.fingerprint(scene),
        total,
        shard: req.shard,
        header: POINTS_HEADER.iter().map(|s| s.to_string()).collect(),
    };
    let mine = (0..total).filter(|&i| req.shard.owns(i)).count();
    let finished = AtomicUsize::new(0);
    let on_point = |_: usize, _: usize| {
        let done = finished.fetch_add(1, Ordering::Relaxed) + 1;
        monitor.progress(done as f64, mine as f64);
    };
    monitor.progress(0.0, mine as f64);
    let cancelled = || monitor.cancelled();
    let retry = |_: usize, fields: &[String]| tables::is_error_row(fields);
    let control = sweep::Control { progress_bar: monitor.bar, cancel: monitor.cancel, on_point: Some(&on_point), retry: Some(&retry) };
    let report = sweep::run_with(Some(&csv), &meta, &control, |i| {
        let (t, b) = &bins[i % nb];
        compute_point(t, *b, freqs[i / nb], req, &opts, &cancelled)
    })?;
    let errors: Vec<&(usize, Vec<String>)> = report.rows.iter().filter(|(_, r)| tables::is_error_row(r)).collect();
    let failed = errors.first().map(|(_, first)| {
        format!("{}: {} of {} points failed (first: {}); a rerun computes them again", csv.display(), errors.len(), report.rows.len(), first[first.len() - 2])
    });
    let cancelled = report.cancelled;
    let tables = if req.shard == Shard::ALL && !cancelled && report.rows.len() == total {
        let t = PopulationTables::from_rows(&report.rows, nb, &eps_grid(req.range.0, req.range.1, req.eps_points))?;
        t.write(&req.out)?;
        Some(t)
    } else {
        None
    };
    Ok(PopulationOutput { points_csv: csv, report, tables, failed, cancelled })
}
