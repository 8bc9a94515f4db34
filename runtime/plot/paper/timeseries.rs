//! The recipe of the time-series figures (12–16): one run per curve, stacked panels sharing
//! the time axis, a long-format CSV and a note with timings and how each run ended.

use super::parts::{parts_dir, reuse_or, PartKey, PartUse};
use super::{
    write_atomic, FigureError, PaperFigure, RunOutput, Simulator, TimeSeriesSpec, QUICK_OVERRIDES,
};
use crate::plot::kinds::{
    derivative, mode_name, phase_portrait, time_series_panels, Curve, TimeSeries,
};
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What a recipe wrote and how long it took.
#[derive(Debug, Clone, PartialEq)]
pub struct FigureReport {
    pub number: u32,
    pub files: Vec<PathBuf>,
    /// Wall time of the whole figure [s].
    pub seconds: f64,
    /// Per curve: label, how the run ended, wall time [s].
    pub runs: Vec<(String, String, f64)>,
    pub quick: bool,
    /// Per curve kept in `figNN.parts/` ([`super::parts`]): label and whether it was computed
    /// or reused (empty for the recipes without parts, figs 3 and 4).
    pub parts: Vec<(String, PartUse)>,
}

/// `a2` → `a_2`; other names unchanged.
fn shape_column(name: &str) -> Option<String> {
    let (head, digits) = name.split_at(1);
    ((head == "a" || head == "b")
        && !digits.is_empty()
        && digits.bytes().all(|b| b.is_ascii_digit()))
    .then(|| format!("{head}_{digits}"))
}

fn to_time_series(label: &str, out: &RunOutput) -> Result<TimeSeries, String> {
    let col = |i: usize| {
        out.rows
            .iter()
            .map(|r| r.get(i).copied().unwrap_or(f64::NAN))
            .collect::<Vec<f64>>()
    };
    let r = out
        .columns
        .iter()
        .position(|c| c == "R")
        .ok_or("the run has no R column")?;
    let shapes = out
        .columns
        .iter()
        .enumerate()
        .filter_map(|(i, c)| shape_column(c).map(|n| (n, col(i))))
        .collect();
    Ok(TimeSeries {
        label: label.to_string(),
        t_s: out.t_s.clone(),
        radius_m: col(r),
        shapes,
        blow_up: out.blow_up.clone(),
    })
}

/// Runs every curve of `fig` and writes `figNN.csv`, `figNN.svg/.png` (and `figNN_phase.*`
/// for a phase portrait) and `figNN.md` into `out_dir`. The curves run in parallel (rayon);
/// `progress` gets each curve's label when it is done.
pub fn make_time_series(
    fig: &PaperFigure,
    spec: &TimeSeriesSpec,
    scenes_dir: &Path,
    out_dir: &Path,
    quick: bool,
    sim: &dyn Simulator,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<FigureReport, FigureError> {
    let start = Instant::now();
    let scene = fig.scene_in(scenes_dir)?;
    // The curves are independent runs: run them in parallel (results in registry order). Each
    // finished run is stored in figNN.parts/ and reused by a rerun of the same request.
    let dir = parts_dir(out_dir, &fig.stem());
    let results: Vec<Result<(TimeSeries, RunOutput, PartUse), FigureError>> = spec
        .variants
        .par_iter()
        .enumerate()
        .map(|(index, variant)| {
            let mut overrides: Vec<String> =
                variant.overrides.iter().map(|s| s.to_string()).collect();
            if quick {
                overrides.extend(QUICK_OVERRIDES.iter().map(|s| s.to_string()));
            }
            // the key holds the simulator's own overrides (`figure --set`) too: a quadratic
            // rerun never reuses a linear curve
            let keyed: Vec<String> = overrides.iter().cloned().chain(sim.model()).collect();
            let run_err = |message: String| FigureError::Run {
                figure: fig.number,
                variant: variant.label.into(),
                message,
            };
            let key = PartKey::new(fig.number, index, variant.label, &scene, &keyed, quick, "time series".into())?;
            let (out, how) = reuse_or(&dir, &key, || sim.simulate(&scene, &overrides).map_err(run_err))?;
            let label = match &out.blow_up {
                Some((mode, t)) => {
                    format!("{} ({mode} blew up at {:.1} µs)", variant.label, t * 1e6)
                }
                None => variant.label.to_string(),
            };
            let ts = to_time_series(&label, &out).map_err(|m| run_err(m.to_string()))?;
            match how {
                PartUse::Reused => progress(&format!("{} (reused)", variant.label)),
                _ => progress(variant.label),
            }
            Ok((ts, out, how))
        })
        .collect();
    let mut runs = Vec::new();
    let mut outputs = Vec::new();
    let mut report_runs = Vec::new();
    let mut parts = Vec::new();
    for (variant, result) in spec.variants.iter().zip(results) {
        let (ts, out, how) = result?;
        parts.push((variant.label.to_string(), how));
        report_runs.push((
            variant.label.to_string(),
            out.status.clone(),
            out.wall_seconds,
        ));
        runs.push(ts);
        outputs.push(out);
    }

    let stem = fig.stem();
    let mut files = Vec::new();
    let csv = out_dir.join(format!("{stem}.csv"));
    write_atomic(&csv, long_csv(spec, &outputs).as_bytes())?;
    files.push(csv);

    let title = format!(
        "Figure {}{}{}",
        fig.number,
        if quick { " (quick)" } else { "" },
        sim.model().map(|m| format!(", {m}")).unwrap_or_default()
    );
    let saved = time_series_panels(&title, &runs, spec.radius, spec.shapes).save(out_dir, &stem)?;
    files.extend([saved.svg, saved.png]);
    if spec.phase_portrait {
        let curves: Vec<Curve> = runs
            .iter()
            .filter_map(|r| {
                // The second half of the run: past the transient (which decays over ~50 µs,
                // FORMULATION §4.6 — the whole run with --quick is shorter than that).
                let (_, a) = r.shapes.iter().find(|(n, _)| n == "a_2")?;
                let da = derivative(&r.t_s, a);
                let from = a.len() / 2;
                Some(Curve::new(
                    r.label.clone(),
                    a[from..].iter().map(|v| v * 1e6).collect(),
                    da[from..].to_vec(),
                ))
            })
            .collect();
        let name = mode_name("a_2");
        let saved = phase_portrait(
            &format!("{title}: phase portrait, second half of the run"),
            &format!("{name} [µm]"),
            &format!("d{name}/dt [m/s]"),
            &curves,
        )
        .save(out_dir, &format!("{stem}_phase"))?;
        files.extend([saved.svg, saved.png]);
    }

    let seconds = start.elapsed().as_secs_f64();
    let md = out_dir.join(format!("{stem}.md"));
    let report = FigureReport {
        number: fig.number,
        files,
        seconds,
        runs: report_runs,
        quick,
        parts,
    };
    let caption = fig.caption(scenes_dir, &super::caption_overrides(quick, &sim.overrides()));
    let mut text = note(fig, &caption, &report, &scene);
    text.push_str(&amplitudes(spec, &runs));
    write_atomic(&md, text.as_bytes())?;
    let mut report = report;
    report.files.push(md);
    Ok(report)
}

/// `variant,t_s,<columns…>` with one row per sample of every run (NaN where a run lacks a column).
fn long_csv(spec: &TimeSeriesSpec, outputs: &[RunOutput]) -> String {
    let mut columns: Vec<&str> = Vec::new();
    for o in outputs {
        for c in &o.columns {
            if !columns.contains(&c.as_str()) {
                columns.push(c);
            }
        }
    }
    let mut s = String::from("variant,t_s");
    for c in &columns {
        let _ = write!(s, ",{c}_m");
    }
    s.push('\n');
    for (variant, o) in spec.variants.iter().zip(outputs) {
        let idx: Vec<Option<usize>> = columns
            .iter()
            .map(|c| o.columns.iter().position(|x| x == c))
            .collect();
        for (t, row) in o.t_s.iter().zip(&o.rows) {
            let _ = write!(s, "\"{}\",{t:e}", variant.label);
            for i in &idx {
                let v = i.and_then(|i| row.get(i).copied()).unwrap_or(f64::NAN);
                let _ = write!(s, ",{v:e}");
            }
            s.push('\n');
        }
    }
    s
}

pub(super) fn note(fig: &PaperFigure, caption: &str, r: &FigureReport, scene: &Path) -> String {
    let mut s = format!(
        "# Figure {}\n\n{caption}.\n\nThe paper reports: {}.\n\n",
        fig.number, fig.paper
    );
    let _ = writeln!(
        s,
        "- scene: `{}`{}",
        scene.display(),
        if r.quick {
            " with `--quick` (20 µs, modes up to 4)"
        } else {
            ""
        }
    );
    let _ = writeln!(s, "- total wall time: {:.2} s\n", r.seconds);
    s.push_str("| curve | how the run ended | wall time [s] |\n|---|---|---|\n");
    for (label, status, wall) in &r.runs {
        let _ = writeln!(s, "| {label} | {status} | {wall:.2} |");
    }
    s.push_str("\nFiles: ");
    let names: Vec<String> = r
        .files
        .iter()
        .filter_map(|p| p.file_name().map(|n| format!("`{}`", n.to_string_lossy())))
        .collect();
    s.push_str(&names.join(", "));
    s.push('\n');
    s
}

/// Max |x| over the finite values of the second half of a series (past the transient).
fn late_max(v: &[f64]) -> f64 {
    v[v.len() / 2..]
        .iter()
        .filter(|x| x.is_finite())
        .fold(f64::NAN, |m, x| x.abs().max(m))
}

/// The measured amplitudes, per shape column: max |a_k| over the second half of each run and
/// its ratio to the first curve (what the paper quotes for fig 13: ≈2.25× and 4×).
fn amplitudes(spec: &TimeSeriesSpec, runs: &[TimeSeries]) -> String {
    let mut s = String::new();
    for shape in spec.shapes {
        let name = mode_name(shape);
        let maxima: Vec<f64> = runs
            .iter()
            .map(|r| {
                r.shapes
                    .iter()
                    .find(|(n, _)| n == shape)
                    .map_or(f64::NAN, |(_, v)| late_max(v))
            })
            .collect();
        let _ = writeln!(
            s,
            "\n| curve | max \\|{name}\\| over the second half [µm] | ratio to the first curve |\n|---|---|---|"
        );
        for (run, m) in runs.iter().zip(&maxima) {
            let _ = writeln!(
                s,
                "| {} | {:.4e} | {:.3} |",
                run.label,
                m * 1e6,
                m / maxima[0]
            );
        }
    }
    s
}
