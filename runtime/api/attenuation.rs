//! `attenuation`: the linear attenuation [dB/cm] and backscatter coefficient [1/(m·sr)] of a
//! population against frequency, from each bin's linear response (docs/population.md,
//! "Attenuation"; [`crate::population::attenuation`]). Frequencies are a sweep
//! ([`crate::analysis::sweep`]): resumable, shardable (`attenuation_points.csv`, merged by
//! `magbubble merge`); once every frequency is there, attenuation.csv is written.

use super::common::Monitor;
use super::scene::Scene;
use super::stability::FreqAxis;
use crate::analysis::sweep::{self, Shard, SweepMeta};
use crate::output::AtomicFile;
use crate::population::attenuation::{attenuation_at, AttenuationPoint};
use crate::population::bin_templates;
use anyhow::Context;
use std::io::Write;
use std::path::PathBuf;

/// What to compute.
#[derive(Debug, Clone)]
pub struct AttenuationRequest {
    pub freq: FreqAxis,
    pub out: PathBuf,
    pub shard: Shard,
}

/// The header of the points CSV (after its `index`); `note` holds a failed point's error.
pub const POINTS_HEADER: [&str; 4] = ["frequency_hz", "attenuation_db_per_cm", "backscatter_per_m_sr", "note"];

/// The name of the points CSV of a shard.
pub fn points_name(shard: Shard) -> String {
    if shard == Shard::ALL { "attenuation_points.csv".into() } else { format!("attenuation_points.shard-{}-of-{}.csv", shard.index, shard.count) }
}

/// What [`attenuation`] did.
pub struct AttenuationOutput {
    pub points_csv: PathBuf,
    pub report: sweep::SweepReport,
    /// Every frequency's point, when complete (not a shard, not cancelled, no failure);
    /// attenuation.csv is then written.
    pub points: Option<Vec<AttenuationPoint>>,
    pub failed: Option<String>,
    pub cancelled: bool,
}

/// Every bin's scene and number density n·w [1/m³], checked at the first frequency.
pub fn plan(scene: &Scene, req: &AttenuationRequest) -> anyhow::Result<Vec<(crate::scene::Scene, f64)>> {
    let pop = scene.scene().population.as_ref().with_context(|| format!("{}: no [population] section (docs/population.md)", scene.origin()))?;
    let n_ml = pop.concentration_per_ml.with_context(|| format!("{}: population.concentration [bubbles/mL] is required by attenuation", scene.origin()))?;
    let bins: Vec<(crate::scene::Scene, f64)> =
        bin_templates(scene.template(), pop)?.into_iter().zip(&pop.bins).map(|(t, b)| (t.into_scene(), n_ml * 1e6 * b.weight)).collect();
    attenuation_at(&bins, req.freq.values[0]).with_context(|| format!("attenuation of {}", scene.origin()))?;
    Ok(bins)
}

pub fn attenuation(scene: &Scene, req: &AttenuationRequest, monitor: &Monitor) -> anyhow::Result<AttenuationOutput> {
    let bins = plan(scene, req)?;
    let freqs = &req.freq.values;
    let csv = req.out.join(points_name(req.shard));
    let meta = SweepMeta {
        fingerprint: format!("attenuation scene={:?} set={:?} freq={}", scene.source_text(), scene.overrides(), req.freq.label),
        total: freqs.len(),
        shard: req.shard,
        header: POINTS_HEADER.iter().map(|s| s.to_string()).collect(),
    };
    let failed_row = |fields: &[String]| fields.get(3).is_some_and(|n| !n.is_empty());
    let retry = |_: usize, fields: &[String]| failed_row(fields);
    let control = sweep::Control { progress_bar: monitor.bar, cancel: monitor.cancel, on_point: None, retry: Some(&retry) };
    let report = sweep::run_with(Some(&csv), &meta, &control, |i| {
        Some(match attenuation_at(&bins, freqs[i]) {
            Ok(p) => vec![format!("{:e}", p.frequency_hz), format!("{:e}", p.attenuation_db_per_cm), format!("{:e}", p.backscatter_per_m_sr), String::new()],
            Err(e) => vec![format!("{:e}", freqs[i]), "NaN".into(), "NaN".into(), format!("{e:#}")],
        })
    })?;
    let failed = report.rows.iter().find(|(_, r)| failed_row(r)).map(|(_, r)| format!("{}: the point at {} Hz failed: {}", csv.display(), r[0], r[3]));
    let complete = req.shard == Shard::ALL && !report.cancelled && report.rows.len() == freqs.len() && failed.is_none();
    let points = if complete {
        let num = |s: &str| s.parse::<f64>().unwrap_or(f64::NAN);
        let pts: Vec<AttenuationPoint> = report
            .rows
            .iter()
            .map(|(_, r)| AttenuationPoint { frequency_hz: num(&r[0]), attenuation_db_per_cm: num(&r[1]), backscatter_per_m_sr: num(&r[2]) })
            .collect();
        let mut f = AtomicFile::create(&req.out.join("attenuation.csv"))?;
        writeln!(f, "frequency_hz,attenuation_db_per_cm,backscatter_per_m_sr")?;
        for (_, r) in &report.rows {
            writeln!(f, "{},{},{}", r[0], r[1], r[2])?;
        }
        f.commit()?;
        Some(pts)
    } else {
        None
    };
    let cancelled = report.cancelled;
    Ok(AttenuationOutput { points_csv: csv, report, points, failed, cancelled })
}
