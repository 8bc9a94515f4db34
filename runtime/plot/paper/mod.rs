//! The paper's figures 3–16: which shipped scene (`scenes/figures/`), which curves (scene
//! overrides per curve) and which analysis draws each one. `magbubble figure N|all` walks this
//! registry; the recipes write `figNN.csv`, `figNN.svg`, `figNN.png` and a `figNN.md` note
//! (what was run, how long it took, how each run ended).
//!
//! The recipes do not call the model directly: they get a [`Simulator`] (the CLI passes one
//! built on `model::simulate`), so they can be tested with a synthetic one.

pub mod parts;
mod registry;
mod stability;
mod timeseries;

pub use registry::FIGURES;
pub use stability::{make_stability, Analyzer, CriticalRow, ModeRow, Sweep};
pub use timeseries::{make_time_series, FigureReport};

use super::PlotError;
use std::path::{Path, PathBuf};

/// One curve of a figure: its legend text and the scene overrides (`key=value`, as `--set`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Variant {
    pub label: &'static str,
    pub overrides: &'static [&'static str],
}

/// A stability figure (figs 5–11): for each family, a sweep of the frequency set by
/// `freq_key`, bisecting on `vary` for its critical value; optional extra panels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StabilitySpec {
    pub families: &'static [Variant],
    /// Panels of the critical-value plot: (title, indices into `families`); empty: one panel.
    pub panels: &'static [(&'static str, &'static [usize])],
    /// Scene key the frequency axis sets (`drive.frequency_hz`, `field.coil.current.frequency_hz`).
    pub freq_key: &'static str,
    /// Frequencies [Hz]: (start, stop, points) at full resolution, and with `--quick`.
    pub freqs: (f64, f64, usize),
    pub quick_freqs: (f64, f64, usize),
    /// Scene key whose critical value is bisected (`drive.amplitude`, `field.coil.current.amplitude`).
    pub vary: &'static str,
    /// Search range of `vary`.
    pub range: (f64, f64),
    /// Axis label of the critical value (with unit) and the factor from SI to it.
    pub vary_label: &'static str,
    pub vary_scale: f64,
    /// Panels: ω_k against k (fig 6a, 7a, 8a); nondimensional axes ω t* (fig 7);
    /// first unstable mode (fig 5b); max Floquet multiplier (fig 6c).
    pub omega_k: bool,
    pub nondimensional: bool,
    pub first_mode: bool,
    pub multiplier: bool,
}

/// A time-series figure (figs 12–16): one run per variant, panels sharing the time axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeSeriesSpec {
    pub variants: &'static [Variant],
    /// Draw the R(t) panel.
    pub radius: bool,
    /// One panel per shape column (`"a_2"`, `"a_4"`).
    pub shapes: &'static [&'static str],
    /// Add a phase portrait a_2 against da_2/dt (fig 15).
    pub phase_portrait: bool,
}

/// What draws a figure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Recipe {
    /// Time-step convergence of the full model (`magbubble convergence`).
    Convergence,
    /// Full vorticity model against the boundary-layer approximation (`magbubble compare`).
    Compare,
    /// Critical ε_p (or I0) against frequency per family, and the related panels.
    Stability(StabilitySpec),
    TimeSeries(TimeSeriesSpec),
}

impl Recipe {
    /// The analysis a recipe needs, for the "not available yet" error.
    pub fn needs(&self) -> &'static str {
        match self {
            Recipe::Convergence => "the convergence analysis (`magbubble convergence`)",
            Recipe::Compare => "the full vorticity model and `magbubble compare`",
            Recipe::Stability(_) => "the stability analysis (modes / Floquet / stability sweeps)",
            Recipe::TimeSeries(_) => "the model (`model::simulate`)",
        }
    }
}

/// One figure of the paper.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaperFigure {
    pub number: u32,
    /// File under `scenes/figures/`.
    pub scene: &'static str,
    /// One line: what the figure shows.
    pub shows: &'static str,
    /// One line: what the paper reports from it (compared in the figure's note).
    pub paper: &'static str,
    pub recipe: Recipe,
}

impl PaperFigure {
    /// `fig07` …
    pub fn stem(&self) -> String {
        format!("fig{:02}", self.number)
    }

    /// What the figure shows with its parameters as run (issue 29 item 14): the registry's
    /// `shows` with `{duration}` → the scene's run.duration [µs] and `{current}` → the coil's
    /// static current [kA], from the figure's scene in `scenes_dir` with `overrides` (the
    /// `--quick` and `--set` ones). Where the scene cannot be read, the placeholders say so.
    pub fn caption(&self, scenes_dir: &Path, overrides: &[String]) -> String {
        let scene = self.scene_in(scenes_dir).ok().and_then(|p| crate::scene::load(p, overrides).ok());
        let num = |v: f64| {
            let s = format!("{v:.3}");
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        };
        let duration = scene.as_ref().map_or("the scene's duration".to_string(), |s| format!("{} µs", num(s.run.duration * 1e6)));
        let current = match scene.as_ref().and_then(|s| s.field.as_ref()) {
            Some(crate::scene::Field::Coil(c)) => match c.current {
                crate::scene::Current::Static { value } => format!("{} kA", num(value / 1e3)),
                crate::scene::Current::Cosine { amplitude, frequency_hz } => format!("{} kA at {} MHz", num(amplitude / 1e3), num(frequency_hz / 1e6)),
            },
            _ => "the scene's current".to_string(),
        };
        self.shows.replace("{duration}", &duration).replace("{current}", &current)
    }

    /// The figure's scene file in `scenes_dir`; [`FigureError::MissingScene`] when it is not a file.
    pub fn scene_in(&self, scenes_dir: &Path) -> Result<PathBuf, FigureError> {
        let path = scenes_dir.join(self.scene);
        if path.is_file() {
            Ok(path)
        } else {
            Err(FigureError::MissingScene { figure: self.number, path })
        }
    }
}

/// The figure with this number.
pub fn find(number: u32) -> Option<&'static PaperFigure> {
    FIGURES.iter().find(|f| f.number == number)
}

/// One simulated run, as the recipes need it (SI units). Serialized exactly as a finished
/// curve of a figure ([`parts`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunOutput {
    /// Output columns after t: `R`, `a2`, `b2`, … (as `model::simulate` names them).
    pub columns: Vec<String>,
    #[serde(with = "parts::exact_vec")]
    pub t_s: Vec<f64>,
    /// One row per sample, same order as `columns`.
    #[serde(with = "parts::exact_rows")]
    pub rows: Vec<Vec<f64>>,
    /// How the run ended, in words (`completed`, `blow_up of a12 at t = 35.1 µs`, …).
    pub status: String,
    /// When the run stopped at a blow-up: the mode and the time [s] (shown in the legend).
    #[serde(with = "parts::exact_blow_up")]
    pub blow_up: Option<(String, f64)>,
    #[serde(with = "parts::exact")]
    pub wall_seconds: f64,
}

/// Runs a scene file with overrides. The CLI implements it with `scene::load` + `model::simulate`.
/// `Sync`: the curves of a figure run in parallel.
pub trait Simulator: Sync {
    fn simulate(&self, scene: &Path, overrides: &[String]) -> Result<RunOutput, String>;
    /// The model, when it is not the scenes' own (e.g. "modes.coupling=\"quadratic\"" from
    /// `figure --set`): named in the plot title and the figure note.
    fn model(&self) -> Option<String> {
        None
    }
    /// The overrides the simulator adds to every run (`figure --set`), for the caption.
    fn overrides(&self) -> Vec<String> {
        Vec::new()
    }
}

/// The overrides a figure's runs get besides their variant's: `--quick`'s, then `--set`'s (the
/// order [`make_time_series`] applies them in); what [`PaperFigure::caption`] reads.
pub fn caption_overrides(quick: bool, set: &[String]) -> Vec<String> {
    let quick = if quick { QUICK_OVERRIDES } else { &[] };
    quick.iter().map(|s| s.to_string()).chain(set.iter().cloned()).collect()
}

/// Errors of the figure pipeline.
#[derive(Debug, thiserror::Error)]
pub enum FigureError {
    #[error("no figure {0}: the paper's reproducible figures are 3 to 16")]
    Unknown(u32),
    #[error("figure {figure}: needs {needs}, which is not available in this build yet")]
    NotAvailable { figure: u32, needs: &'static str },
    #[error("figure {figure}: scene {} not found (looked in the scenes directory)", path.display())]
    MissingScene { figure: u32, path: PathBuf },
    #[error("figure {figure}, curve `{variant}`: {message}")]
    Run {
        figure: u32,
        variant: String,
        message: String,
    },
    #[error(transparent)]
    Plot(#[from] PlotError),
}

/// Overrides that make a figure fast enough for CI (`--quick`): 20 µs, modes up to 4,
/// 20 ns sampling.
pub const QUICK_OVERRIDES: &[&str] = &[
    "run.duration=20e-6",
    "modes.max_order=4",
    "run.sample_interval=2e-8",
];

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), PlotError> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let _lock = crate::output::DirLock::acquire(dir)?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    std::fs::write(&tmp, bytes).map_err(|source| PlotError::Io {
        path: tmp.clone(),
        source,
    })?;
    std::fs::rename(&tmp, path).map_err(|source| {
        let _ = std::fs::remove_file(&tmp);
        PlotError::Io {
            path: path.to_path_buf(),
            source,
        }
    })
}
