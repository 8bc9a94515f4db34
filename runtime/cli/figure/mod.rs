//! `magbubble figure N|all --out DIR [--quick]`: reproduce the paper's figures 3–16 from the
//! scenes shipped under `scenes/figures/` (registry: [`magbubble::plot::paper`]).

use crate::plot::paper::{
    self, Analyzer, FigureError, FigureReport, PaperFigure, Recipe, Simulator,
};
use anyhow::Context;
use std::path::{Path, PathBuf};

mod backend;
mod extra;
mod notes;

/// Arguments of `magbubble figure`.
#[derive(Debug, clap::Args)]
pub struct FigureArgs {
    /// Figure number (3–16) or `all`; `list` prints the registry.
    pub figure: String,
    /// Output directory (CSV, SVG, PNG and a figNN.md note per figure).
    #[arg(long, default_value = "figures")]
    pub out: PathBuf,
    /// Reduced resolution (short runs, few modes, coarse sweeps) for CI and a first look.
    #[arg(long)]
    pub quick: bool,
    /// Directory of the figure scenes (default: scenes/figures, here or in the source tree).
    #[arg(long)]
    pub scenes: Option<PathBuf>,
    /// Compute every curve again instead of reusing the finished curves kept in
    /// DIR/figNN.parts/ (they are reused only when scene, overrides, resolution and build match).
    #[arg(long)]
    pub fresh: bool,
    /// Override a scene key of every time-series curve, KEY=VALUE (repeatable), e.g.
    /// `--set modes.coupling="quadratic" --set run.duration=100e-6`; the plot title and the
    /// figure note name them. Time-series figures (12–16) only.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

pub fn run(args: &FigureArgs) -> anyhow::Result<()> {
    if args.figure == "list" {
        // the captions with the shipped scenes' values (placeholders where they are absent)
        let list_scenes = scenes_dir(args.scenes.as_deref()).unwrap_or_default();
        for f in paper::FIGURES {
            outln!("{:>2}  {:<32} {}", f.number, f.scene, f.caption(&list_scenes, &[]));
        }
        return Ok(());
    }
    let figures: Vec<&PaperFigure> = if args.figure == "all" {
        paper::FIGURES.iter().collect()
    } else {
        let n: u32 = args.figure.parse().with_context(|| {
            format!(
                "figure `{}`: expected a number 3–16, `all` or `list`",
                args.figure
            )
        })?;
        vec![paper::find(n).ok_or(FigureError::Unknown(n))?]
    };
    let scenes = scenes_dir(args.scenes.as_deref())?;
    let _lock = crate::output::DirLock::acquire(&args.out)?; // one process at a time (issue 29 item 3)
    #[cfg(unix)]
    crate::output::note_on_signal(&format!(
        "finished curves are kept in {}/figNN.parts/; run the same command again to resume",
        args.out.display()
    ));
    let mut done = Vec::new();
    let mut failed = Vec::new();
    for fig in figures {
        noteln!("figure {}: {}", fig.number, fig.caption(&scenes, &paper::caption_overrides(args.quick, &args.set)));
        let parts = paper::parts::parts_dir(&args.out, &fig.stem());
        if args.fresh {
            match std::fs::remove_dir_all(&parts) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                    return Err(e).with_context(|| format!("--fresh: removing {}", parts.display()))
                }
                _ => {}
            }
        }
        remove_stale_temp_files(&args.out);
        remove_stale_temp_files(&parts);
        match make(fig, &scenes, &args.out, args.quick, &args.set) {
            Ok(report) => {
                noteln!("figure {}: done in {:.2} s", fig.number, report.seconds);
                report_parts(&report, &parts);
                for (label, status, wall) in &report.runs {
                    noteln!("  {label}: {status} ({wall:.2} s)");
                }
                done.push(report);
            }
            Err(e) => {
                noteln!("{e}");
                failed.push((fig.number, e));
            }
        }
    }
    if args.figure == "all" {
        write_index(&args.out, &done, &failed, &|f: &PaperFigure| f.caption(&scenes, &paper::caption_overrides(args.quick, &args.set)))?;
    }
    match failed.len() {
        0 => Ok(()),
        1 if done.is_empty() => Err(failed.remove(0).1.into()),
        n => anyhow::bail!(
            "{n} figure(s) failed: {:?}",
            failed.iter().map(|f| f.0).collect::<Vec<_>>()
        ),
    }
}

/// Says which curves came from `parts` (a resumed figure) and why any stored one was redone.
fn report_parts(report: &FigureReport, parts: &Path) {
    use paper::parts::PartUse;
    let reused = report.parts.iter().filter(|p| p.1 == PartUse::Reused).count();
    if reused > 0 {
        noteln!(
            "figure {}: reused {reused} of {} finished curves from {} (same scene, overrides, resolution and build; --fresh recomputes)",
            report.number,
            report.parts.len(),
            parts.display()
        );
    }
    for (label, how) in &report.parts {
        if let PartUse::Recomputed(why) = how {
            noteln!("  {label}: recomputed: {why}");
        }
    }
}

/// Removes the `.NAME.PID….tmp…` files an interrupted figure left in `dir` (the atomic writes'
/// temp files), when no process PID is running (a figure writing there now keeps its own).
fn remove_stale_temp_files(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let pid = name.split('.').find(|w| !w.is_empty() && w.bytes().all(|b| b.is_ascii_digit()));
        let alive = pid.is_some_and(|p| Path::new("/proc").join(p).exists());
        if name.starts_with('.') && name.contains(".tmp") && !alive && e.path().is_file() {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// The scenes directory: the one given, else `scenes/figures` in the working directory, else
/// the one in the source tree this binary was built from.
fn scenes_dir(given: Option<&Path>) -> anyhow::Result<PathBuf> {
    if let Some(d) = given {
        anyhow::ensure!(d.is_dir(), "--scenes {}: not a directory", d.display());
        return Ok(d.to_path_buf());
    }
    let here = PathBuf::from("scenes/figures");
    if here.is_dir() {
        return Ok(here);
    }
    let built = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/figures");
    anyhow::ensure!(
        built.is_dir(),
        "no scenes/figures directory here nor in {}; pass --scenes DIR",
        built.display()
    );
    Ok(built)
}

fn make(
    fig: &PaperFigure,
    scenes: &Path,
    out: &Path,
    quick: bool,
    set: &[String],
) -> Result<FigureReport, FigureError> {
    if !set.is_empty() && !matches!(fig.recipe, Recipe::TimeSeries(_)) {
        return Err(FigureError::Run {
            figure: fig.number,
            variant: "--set".into(),
            message: "`figure --set` applies to the time-series figures (12–16) only".into(),
        });
    }
    let progress = indicatif::ProgressBar::new(match &fig.recipe {
        Recipe::TimeSeries(s) => s.variants.len() as u64,
        Recipe::Stability(s) => s.families.len() as u64,
        _ => 1,
    });
    progress.set_style(
        indicatif::ProgressStyle::with_template("  [{elapsed_precise}] {bar:30} {pos}/{len} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let tick = |label: &str| {
        progress.inc(1);
        progress.set_message(format!("{label} done"));
    };
    let result = match &fig.recipe {
        Recipe::TimeSeries(spec) => match simulator(set) {
            Some(sim) => {
                paper::make_time_series(fig, spec, scenes, out, quick, sim.as_ref(), &tick)
            }
            None => Err(FigureError::NotAvailable {
                figure: fig.number,
                needs: fig.recipe.needs(),
            }),
        },
        Recipe::Stability(spec) => match analyzer(quick) {
            Some(a) => paper::make_stability(fig, spec, scenes, out, quick, a.as_ref(), &tick),
            None => Err(FigureError::NotAvailable {
                figure: fig.number,
                needs: fig.recipe.needs(),
            }),
        },
        Recipe::Convergence => extra::make_convergence(fig, scenes, out, quick),
        Recipe::Compare => extra::make_compare(fig, scenes, out, quick),
    };
    progress.finish_and_clear();
    let report = result?;
    notes::append(fig, &report, out, set)?;
    Ok(report)
}

/// The model-backed simulator (`scene::load` + `model::simulate`).
fn simulator(set: &[String]) -> Option<Box<dyn Simulator>> {
    Some(Box::new(backend::ModelSimulator { extra: set.to_vec() }))
}

/// The analysis-backed analyzer (natural_frequencies + the ladder's critical_outcome and max_multiplier).
fn analyzer(quick: bool) -> Option<Box<dyn Analyzer>> {
    Some(Box::new(backend::ModelAnalyzer { quick }))
}

/// `DIR/figures.md`: one line per figure, its time and its files (the README gallery's source).
fn write_index(
    out: &Path,
    done: &[FigureReport],
    failed: &[(u32, FigureError)],
    caption: &dyn Fn(&PaperFigure) -> String,
) -> anyhow::Result<()> {
    let mut s = String::from("# magbubble: the paper's figures\n\n| figure | what it shows | time [s] | files |\n|---|---|---|---|\n");
    let mut rows: Vec<(u32, String)> = Vec::new();
    for r in done {
        let shows = paper::find(r.number).map(caption).unwrap_or_default();
        let files: Vec<String> = r
            .files
            .iter()
            .filter_map(|p| p.file_name())
            .map(|n| format!("[{0}]({0})", n.to_string_lossy()))
            .collect();
        rows.push((
            r.number,
            format!(
                "| {} | {} | {:.2} | {} |\n",
                r.number,
                shows,
                r.seconds,
                files.join(" ")
            ),
        ));
    }
    for (n, e) in failed {
        rows.push((*n, format!("| {n} | not produced: {e} | – | – |\n")));
    }
    rows.sort_by_key(|r| r.0);
    for (_, row) in rows {
        s += &row;
    }
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    std::fs::write(out.join("figures.md"), s)
        .with_context(|| format!("writing {}/figures.md", out.display()))
}
