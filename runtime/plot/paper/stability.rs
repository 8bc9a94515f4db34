//! The recipe of the stability figures (5–11): per family, the critical value of a scene key
//! (ε_p, or I0 for fig 9) against a frequency, and the panels that go with it (ω_k against k,
//! first unstable mode, max Floquet multiplier). The analysis itself comes through
//! [`Analyzer`] (the CLI implements it with `analysis::{frequencies, stability}`).

use super::parts::{exact, exact_opt_vec, parts_dir, reuse_or, PartKey, PartUse};
use super::{write_atomic, FigureError, FigureReport, PaperFigure, StabilitySpec, Variant};
use serde::{Deserialize, Serialize};
use crate::plot::figure::{Axis, Figure, Legend, Panel, Series};
use crate::plot::kinds::{first_unstable_mode, max_multiplier, omega_vs_k, Curve};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// One frequency sweep of one family.
#[derive(Debug, Clone, PartialEq)]
pub struct Sweep<'a> {
    /// Scene key set to each frequency.
    pub freq_key: &'a str,
    pub freqs_hz: &'a [f64],
    /// Scene key whose critical value is bisected, and its search range.
    pub vary: &'a str,
    pub range: (f64, f64),
}

/// One point of a stability curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CriticalRow {
    #[serde(with = "exact")]
    pub frequency_hz: f64,
    /// Critical value of `vary` (SI); NaN when stable throughout or unstable at the bottom.
    #[serde(with = "exact")]
    pub critical: f64,
    /// `critical`, `stable_throughout`, `unstable_at_bottom`.
    pub outcome: String,
    /// The first mode to go unstable (k), when known.
    pub mode: Option<usize>,
}

/// One natural frequency.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeRow {
    pub k: usize,
    #[serde(with = "exact")]
    pub omega_rad_s: f64,
    /// ω t*.
    #[serde(with = "exact")]
    pub omega_nondim: f64,
}

/// Everything one family of a stability figure computes (a finished curve, [`super::parts`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct FamilyPart {
    modes: Vec<ModeRow>,
    #[serde(with = "exact")]
    t_star: f64,
    rows: Vec<CriticalRow>,
    #[serde(with = "exact_opt_vec")]
    mus: Option<Vec<f64>>,
    #[serde(with = "exact")]
    seconds: f64,
}

/// The analyses a stability figure needs.
pub trait Analyzer {
    /// Natural frequencies k = 2…kmax of the scene (with overrides), and t* [s].
    fn modes(
        &self,
        scene: &Path,
        overrides: &[String],
        kmax: usize,
    ) -> Result<(Vec<ModeRow>, f64), String>;
    /// The critical value of `sweep.vary` at each frequency.
    fn critical(
        &self,
        scene: &Path,
        overrides: &[String],
        sweep: &Sweep,
    ) -> Result<Vec<CriticalRow>, String>;
    /// The largest Floquet multiplier |μ| at each frequency, at the scene's own ε_p.
    fn max_multiplier(
        &self,
        scene: &Path,
        overrides: &[String],
        freq_key: &str,
        freqs_hz: &[f64],
    ) -> Result<Vec<f64>, String>;
    /// How [`max_multiplier`](Self::max_multiplier) computes its values and to what tolerance,
    /// for the figure note ("" when there is nothing to say).
    fn max_multiplier_method(&self) -> String {
        String::new()
    }
}

/// Largest k of the ω_k panels.
const OMEGA_KMAX: usize = 32;

fn linspace((a, b, n): (f64, f64, usize)) -> Vec<f64> {
    (0..n)
        .map(|i| {
            if n < 2 {
                a
            } else {
                a + (b - a) * i as f64 / (n - 1) as f64
            }
        })
        .collect()
}

/// Runs every family of `fig` and writes into `out_dir`: `figNN.csv/.svg/.png` (critical
/// value against frequency), and as the spec asks `figNN_omega.*`, `figNN_mode.*`,
/// `figNN_mu.*`, plus the `figNN.md` note. `--quick` keeps two families and the coarse
/// frequency grid.
pub fn make_stability(
    fig: &PaperFigure,
    spec: &StabilitySpec,
    scenes_dir: &Path,
    out_dir: &Path,
    quick: bool,
    analyzer: &dyn Analyzer,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<FigureReport, FigureError> {
    let start = Instant::now();
    let scene = fig.scene_in(scenes_dir)?;
    let families: Vec<(usize, &Variant)> = spec
        .families
        .iter()
        .enumerate()
        .take(if quick { 2 } else { usize::MAX })
        .collect();
    let freqs = linspace(if quick { spec.quick_freqs } else { spec.freqs });
    let sweep = Sweep {
        freq_key: spec.freq_key,
        freqs_hz: &freqs,
        vary: spec.vary,
        range: spec.range,
    };
    let stem = fig.stem();
    let title = format!(
        "Figure {}{}",
        fig.number,
        if quick { " (quick)" } else { "" }
    );
    let mut files: Vec<PathBuf> = Vec::new();
    let mut runs = Vec::new();

    let mut crit = Vec::new(); // (family index, rows, t*)
    let mut omegas = Vec::new();
    let mut mus = Vec::new();
    // Each finished family is stored in figNN.parts/ and reused by a rerun of the same request.
    let dir = parts_dir(out_dir, &stem);
    let resolution = format!(
        "{} at {:?} Hz; {} in {:?}; omega_k {} (k <= {OMEGA_KMAX}), multiplier {}",
        spec.freq_key, freqs, spec.vary, spec.range, spec.omega_k || spec.nondimensional, spec.multiplier
    );
    let mut parts = Vec::new();
    for &(i, fam) in &families {
        let ov: Vec<String> = fam.overrides.iter().map(|s| s.to_string()).collect();
        let err = |message: String| FigureError::Run {
            figure: fig.number,
            variant: fam.label.into(),
            message,
        };
        let key = PartKey::new(fig.number, i, fam.label, &scene, &ov, quick, resolution.clone())?;
        let (part, how) = reuse_or(&dir, &key, || -> Result<FamilyPart, FigureError> {
            let t0 = Instant::now();
            let (modes, t_star) = if spec.omega_k || spec.nondimensional {
                analyzer.modes(&scene, &ov, OMEGA_KMAX).map_err(err)?
            } else {
                (Vec::new(), f64::NAN)
            };
            let rows = analyzer.critical(&scene, &ov, &sweep).map_err(err)?;
            let mus = if spec.multiplier {
                Some(analyzer.max_multiplier(&scene, &ov, spec.freq_key, &freqs).map_err(err)?)
            } else {
                None
            };
            Ok(FamilyPart { modes, t_star, rows, mus, seconds: t0.elapsed().as_secs_f64() })
        })?;
        match how {
            PartUse::Reused => progress(&format!("{} (reused)", fam.label)),
            _ => progress(fam.label),
        }
        parts.push((fam.label.to_string(), how));
        let FamilyPart { modes, t_star, rows, mus: family_mus, seconds } = part;
        if let Some(m) = family_mus {
            mus.push((fam.label, m));
        }
        let found = rows.iter().filter(|r| r.critical.is_finite()).count();
        runs.push((
            fam.label.to_string(),
            format!(
                "critical value found at {found} of {} frequencies",
                rows.len()
            ),
            seconds,
        ));
        omegas.push((fam.label, modes));
        crit.push((i, rows, t_star));
    }

    // Critical value against frequency (ω_d t* when nondimensional).
    let x_of = |f: f64, t_star: f64| {
        if spec.nondimensional {
            2.0 * std::f64::consts::PI * f * t_star
        } else {
            f * 1e-6
        }
    };
    let x_label = match (spec.nondimensional, spec.freq_key) {
        (true, _) => "ω_d t* [–]",
        (false, "field.coil.current.frequency_hz") => "f2 [MHz]",
        _ => "f_d [MHz]",
    };
    let curve = |i: usize| -> Option<Curve> {
        let (_, rows, t_star) = crit.iter().find(|c| c.0 == i)?;
        Some(Curve::new(
            spec.families[i].label,
            rows.iter().map(|r| x_of(r.frequency_hz, *t_star)).collect(),
            rows.iter().map(|r| r.critical * spec.vary_scale).collect(),
        ))
    };
    let groups: Vec<(String, Vec<usize>)> = if spec.panels.is_empty() {
        vec![(String::new(), crit.iter().map(|c| c.0).collect())]
    } else {
        spec.panels
            .iter()
            .map(|(t, idx)| (t.to_string(), idx.to_vec()))
            .collect()
    };
    let mut panels = Vec::new();
    for (t, idx) in &groups {
        let mut p = Panel::new(Axis::linear(x_label), Axis::linear(spec.vary_label))
            .legend(Legend::UpperLeft);
        if !t.is_empty() {
            p = p.title(t.clone());
        }
        let mut any = false;
        let (mut xlo, mut xhi) = (f64::INFINITY, f64::NEG_INFINITY);
        for (j, c) in idx.iter().filter_map(|&i| curve(i)).enumerate() {
            any |=
                c.x.iter()
                    .zip(&c.y)
                    .any(|(x, y)| x.is_finite() && y.is_finite());
            for &x in c.x.iter().filter(|x| x.is_finite()) {
                (xlo, xhi) = (xlo.min(x), xhi.max(x));
            }
            p.push(Series::line_points(c.label, c.x, c.y).color(j));
        }
        if p.series.is_empty() {
            continue;
        }
        if !any && xlo < xhi {
            // Nothing went unstable in the search range: a result, drawn as an empty diagram
            // over the searched region, not an error.
            let (lo, hi) = (
                spec.range.0 * spec.vary_scale,
                spec.range.1 * spec.vary_scale,
            );
            p.x.range = Some((xlo, xhi));
            p.y.range = Some((lo, hi));
            let what = format!("no critical value in [{lo}, {hi}]");
            p.title = Some(if t.is_empty() {
                what
            } else {
                format!("{t}: {what}")
            });
        }
        panels.push(p);
    }
    let csv = out_dir.join(format!("{stem}.csv"));
    write_atomic(&csv, critical_csv(spec, &crit).as_bytes())?;
    files.push(csv);
    let saved = Figure::new(panels)
        .title(title.clone())
        .save(out_dir, &stem)?;
    files.extend([saved.svg, saved.png]);

    if spec.omega_k {
        let y_label = if spec.nondimensional {
            "ω_k t* [–]"
        } else {
            "ω_k [10⁶ rad/s]"
        };
        let curves: Vec<Curve> = omegas
            .iter()
            .map(|(label, rows)| {
                let y = rows.iter().map(|r| {
                    if spec.nondimensional {
                        r.omega_nondim
                    } else {
                        r.omega_rad_s * 1e-6
                    }
                });
                Curve::new(
                    *label,
                    rows.iter().map(|r| r.k as f64).collect(),
                    y.collect(),
                )
            })
            .collect();
        let mut s = String::from("family,k,omega_rad_s,omega_nondim\n");
        for (label, rows) in &omegas {
            for r in rows {
                let _ = writeln!(
                    s,
                    "\"{label}\",{},{:e},{:e}",
                    r.k, r.omega_rad_s, r.omega_nondim
                );
            }
        }
        let csv = out_dir.join(format!("{stem}_omega.csv"));
        write_atomic(&csv, s.as_bytes())?;
        files.push(csv);
        let saved = omega_vs_k(
            &format!("{title}: natural frequencies"),
            y_label,
            &curves,
            false,
        )
        .save(out_dir, &format!("{stem}_omega"))?;
        files.extend([saved.svg, saved.png]);
    }
    if spec.first_mode {
        let curves: Vec<Curve> = crit
            .iter()
            .map(|(i, rows, t)| {
                let y = rows.iter().map(|r| r.mode.map_or(f64::NAN, |k| k as f64));
                Curve::new(
                    spec.families[*i].label,
                    rows.iter().map(|r| x_of(r.frequency_hz, *t)).collect(),
                    y.collect(),
                )
            })
            .collect();
        let saved = first_unstable_mode(&format!("{title}: first unstable mode"), x_label, &curves)
            .save(out_dir, &format!("{stem}_mode"))?;
        files.extend([saved.svg, saved.png]);
    }
    if spec.multiplier {
        let x: Vec<f64> = freqs.iter().map(|f| f * 1e-6).collect();
        let curves: Vec<Curve> = mus
            .iter()
            .map(|(l, m)| Curve::new(*l, x.clone(), m.clone()))
            .collect();
        let mut s = String::from("family,frequency_hz,max_multiplier\n");
        for (label, m) in &mus {
            for (f, v) in freqs.iter().zip(m) {
                let _ = writeln!(s, "\"{label}\",{f:e},{v:e}");
            }
        }
        let csv = out_dir.join(format!("{stem}_mu.csv"));
        write_atomic(&csv, s.as_bytes())?;
        files.push(csv);
        let saved = max_multiplier(
            &format!("{title}: Floquet multiplier"),
            "f_d [MHz]",
            &curves,
            false,
        )
        .save(out_dir, &format!("{stem}_mu"))?;
        files.extend([saved.svg, saved.png]);
    }

    let seconds = start.elapsed().as_secs_f64();
    let mut report = FigureReport {
        number: fig.number,
        files,
        seconds,
        runs,
        quick,
        parts,
    };
    let md = out_dir.join(format!("{stem}.md"));
    let caption = fig.caption(scenes_dir, &super::caption_overrides(quick, &[]));
    let mut note = super::timeseries::note(fig, &caption, &report, &scene);
    let _ = writeln!(
        note,
        "\nSweep: `{}` over {} points {:.3}…{:.3} MHz; critical `{}` searched in [{}, {}].",
        spec.freq_key,
        freqs.len(),
        freqs.first().copied().unwrap_or(f64::NAN) * 1e-6,
        freqs.last().copied().unwrap_or(f64::NAN) * 1e-6,
        spec.vary,
        spec.range.0,
        spec.range.1
    );
    let method = analyzer.max_multiplier_method();
    if spec.multiplier && !method.is_empty() {
        let _ = writeln!(note, "\nMax multiplier (`{stem}_mu.csv`): {method}.");
    }
    write_atomic(&md, note.as_bytes())?;
    report.files.push(md);
    Ok(report)
}

fn critical_csv(spec: &StabilitySpec, crit: &[(usize, Vec<CriticalRow>, f64)]) -> String {
    let mut s = format!(
        "family,frequency_hz,critical_{},outcome,first_unstable_mode\n",
        spec.vary.replace('.', "_")
    );
    for (i, rows, _) in crit {
        for r in rows {
            let mode = r.mode.map(|k| k.to_string()).unwrap_or_default();
            let _ = writeln!(
                s,
                "\"{}\",{:e},{:e},{},{mode}",
                spec.families[*i].label, r.frequency_hz, r.critical, r.outcome
            );
        }
    }
    s
}
