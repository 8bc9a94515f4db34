//! The paper's figures 3–16: which shipped scene (`scenes/figures/`), which curves (scene
//! overrides per curve) and which analysis draws each one. `magbubble figure N|all` walks this
//! registry; the recipes write `figNN.csv`, `figNN.svg`, `figNN.png` and a `figNN.md` note
//! (what was run, how long it took, how each run ended).
//!
//! The recipes do not call the model directly: they get a [`Simulator`] (the CLI passes one
//! built on `model::simulate`), so they can be tested with a synthetic one.

mod timeseries;

pub use timeseries::{make_time_series, FigureReport};

use super::PlotError;
use std::path::{Path, PathBuf};

/// One curve of a figure: its legend text and the scene overrides (`key=value`, as `--set`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Variant {
    pub label: &'static str,
    pub overrides: &'static [&'static str],
}

const fn v(label: &'static str, overrides: &'static [&'static str]) -> Variant {
    Variant { label, overrides }
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
    /// Critical ε_p (or I0) against frequency, per family; `extra` names the other panels.
    Stability { families: &'static [Variant], extra: &'static str },
    TimeSeries(TimeSeriesSpec),
}

impl Recipe {
    /// The analysis a recipe needs, for the "not available yet" error.
    pub fn needs(&self) -> &'static str {
        match self {
            Recipe::Convergence => "the convergence analysis (`magbubble convergence`)",
            Recipe::Compare => "the full vorticity model and `magbubble compare`",
            Recipe::Stability { .. } => "the stability analysis (modes / Floquet / stability sweeps)",
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
    pub recipe: Recipe,
}

impl PaperFigure {
    /// `fig07` …
    pub fn stem(&self) -> String {
        format!("fig{:02}", self.number)
    }
}

/// The registry, figures 3 to 16 in order.
pub static FIGURES: &[PaperFigure] = &[
    PaperFigure {
        number: 3,
        scene: "fig03_convergence.toml",
        shows: "error of the structure (e_s) and the fluid (e_f) against the time step Δt', log–log",
        recipe: Recipe::Convergence,
    },
    PaperFigure {
        number: 4,
        scene: "fig04_compare.toml",
        shows: "full vorticity model against the boundary-layer approximation, a_k(t)",
        recipe: Recipe::Compare,
    },
    PaperFigure {
        number: 5,
        scene: "fig05_modes.toml",
        shows: "critical ε_p against f_d for 12…32 modes; first unstable mode against f_d",
        recipe: Recipe::Stability {
            families: &[
                v("12 modes", &["modes.max_order=12"]),
                v("16 modes", &["modes.max_order=16"]),
                v("20 modes", &["modes.max_order=20"]),
                v("24 modes", &["modes.max_order=24"]),
                v("28 modes", &["modes.max_order=28"]),
                v("32 modes", &["modes.max_order=32"]),
            ],
            extra: "first unstable mode against f_d",
        },
    },
    PaperFigure {
        number: 6,
        scene: "fig06_current.toml",
        shows: "ω_k against k, critical ε_p and max Floquet multiplier against f_d, several static currents",
        recipe: Recipe::Stability {
            families: &[
                v("I = 0", &["field.coil.current=0.0"]),
                v("I = 100 kA", &["field.coil.current=100e3"]),
                v("I = 200 kA", &["field.coil.current=200e3"]),
            ],
            extra: "ω_k against k; max |μ| against f_d",
        },
    },
    PaperFigure {
        number: 7,
        scene: "fig07_radius.toml",
        shows: "ω_k t* against k (collapses in R0) and critical ε_p against ω_d t*, several R0",
        recipe: Recipe::Stability {
            families: &[
                v("R0 = 10 µm", &["bubble.radius=10e-6"]),
                v("R0 = 15 µm", &["bubble.radius=15e-6"]),
                v("R0 = 20 µm", &["bubble.radius=20e-6"]),
            ],
            extra: "ω_k t* against k",
        },
    },
    PaperFigure {
        number: 8,
        scene: "fig08_c1.toml",
        shows: "ω_k against k and critical ε_p against f_d, several c1",
        recipe: Recipe::Stability {
            families: &[
                v("c1 = 0.05 N/m", &["shell.c1=0.05"]),
                v("c1 = 0.1 N/m", &["shell.c1=0.1"]),
                v("c1 = 0.2 N/m", &["shell.c1=0.2"]),
                v("c1 = 0.5 N/m", &["shell.c1=0.5"]),
            ],
            extra: "ω_k against k",
        },
    },
    PaperFigure {
        number: 9,
        scene: "fig09_current_frequency.toml",
        shows: "critical current amplitude I0 against the current frequency f2 at ε_p = 0, several R0",
        recipe: Recipe::Stability {
            families: &[
                v("R0 = 10 µm", &["bubble.radius=10e-6"]),
                v("R0 = 15 µm", &["bubble.radius=15e-6"]),
                v("R0 = 20 µm", &["bubble.radius=20e-6"]),
            ],
            extra: "bisection on I0 instead of ε_p",
        },
    },
    PaperFigure {
        number: 10,
        scene: "fig10_alternating.toml",
        shows: "critical ε_p against f_d with an alternating current: several I0 at f2 = 0.5 MHz, several f2 at I0 = 150 kA",
        recipe: Recipe::Stability {
            families: &[
                v("I0 = 100 kA, f2 = 0.5 MHz", &["field.coil.current={ amplitude = 100e3, frequency_hz = 5e5 }"]),
                v("I0 = 150 kA, f2 = 0.5 MHz", &["field.coil.current={ amplitude = 150e3, frequency_hz = 5e5 }"]),
                v("I0 = 150 kA, f2 = 0.25 MHz", &["field.coil.current={ amplitude = 150e3, frequency_hz = 2.5e5 }"]),
                v("I0 = 150 kA, f2 = 1 MHz", &["field.coil.current={ amplitude = 150e3, frequency_hz = 1e6 }"]),
            ],
            extra: "two panels (I0 family, f2 family)",
        },
    },
    PaperFigure {
        number: 11,
        scene: "fig11_dipole.toml",
        shows: "dipole: critical ε_p against f_d for several M (z = 0.01 m) and several z (M = 1 A m²)",
        recipe: Recipe::Stability {
            families: &[
                v("M = 0.1 A m²", &["field.dipole.moment=0.1"]),
                v("M = 1 A m²", &["field.dipole.moment=1.0"]),
                v("M = 5 A m²", &["field.dipole.moment=5.0"]),
                v("M = 10 A m²", &["field.dipole.moment=10.0"]),
                v("z = 7.5 mm", &["field.dipole.distance=0.0075"]),
                v("z = 5 mm", &["field.dipole.distance=0.005"]),
            ],
            extra: "two panels (M family, z family)",
        },
    },
    PaperFigure {
        number: 12,
        scene: "fig12_chi.toml",
        shows: "R(t) and a_2(t) over 2000 µs for several susceptibilities χ (coil, I = 100 kA)",
        recipe: Recipe::TimeSeries(TimeSeriesSpec {
            variants: &[
                v("χ = 1", &["shell.susceptibility=1.0"]),
                v("χ = 5", &["shell.susceptibility=5.0"]),
                v("χ = 10", &["shell.susceptibility=10.0"]),
            ],
            radius: true,
            shapes: &["a_2"],
            phase_portrait: false,
        }),
    },
    PaperFigure {
        number: 13,
        scene: "fig13_radius.toml",
        shows: "R(t) and a_2(t) over 100 µs for R0 = 10, 15, 20 µm (χ = 1)",
        recipe: Recipe::TimeSeries(TimeSeriesSpec {
            variants: &[
                v("R0 = 10 µm", &["bubble.radius=10e-6"]),
                v("R0 = 15 µm", &["bubble.radius=15e-6"]),
                v("R0 = 20 µm", &["bubble.radius=20e-6"]),
            ],
            radius: true,
            shapes: &["a_2"],
            phase_portrait: false,
        }),
    },
    PaperFigure {
        number: 14,
        scene: "fig14_current_frequency.toml",
        shows: "a_2(t) for several frequencies f2 of an alternating current (I0 = 150 kA, f1 = 1 MHz)",
        recipe: Recipe::TimeSeries(TimeSeriesSpec {
            variants: &[
                v("f2 = 0.25 f1", &["field.coil.current={ amplitude = 150e3, frequency_hz = 2.5e5 }"]),
                v("f2 = 0.5 f1", &["field.coil.current={ amplitude = 150e3, frequency_hz = 5e5 }"]),
                v("f2 = f1", &["field.coil.current={ amplitude = 150e3, frequency_hz = 1e6 }"]),
                v("f2 = 2 f1", &["field.coil.current={ amplitude = 150e3, frequency_hz = 2e6 }"]),
            ],
            radius: false,
            shapes: &["a_2"],
            phase_portrait: false,
        }),
    },
    PaperFigure {
        number: 15,
        scene: "fig15_quasiperiodic.toml",
        shows: "a_2(t) and its phase portrait for f2 = 1.777 f1 (quasi-periodic / chaotic)",
        recipe: Recipe::TimeSeries(TimeSeriesSpec {
            variants: &[v("f2 = 1.777 f1", &[])],
            radius: false,
            shapes: &["a_2"],
            phase_portrait: true,
        }),
    },
    PaperFigure {
        number: 16,
        scene: "fig16_dipole.toml",
        shows: "dipole: R(t), a_2(t), a_4(t) over 2000 µs for several moments M (χ = 5, z = 0.01 m)",
        recipe: Recipe::TimeSeries(TimeSeriesSpec {
            variants: &[
                v("M = 0.1 A m²", &["field.dipole.moment=0.1"]),
                v("M = 1 A m²", &["field.dipole.moment=1.0"]),
                v("M = 10 A m²", &["field.dipole.moment=10.0"]),
            ],
            radius: true,
            shapes: &["a_2", "a_4"],
            phase_portrait: false,
        }),
    },
];

/// The figure with this number.
pub fn find(number: u32) -> Option<&'static PaperFigure> {
    FIGURES.iter().find(|f| f.number == number)
}

/// One simulated run, as the recipes need it (SI units).
#[derive(Debug, Clone, PartialEq)]
pub struct RunOutput {
    /// Output columns after t: `R`, `a2`, `b2`, … (as `model::simulate` names them).
    pub columns: Vec<String>,
    pub t_s: Vec<f64>,
    /// One row per sample, same order as `columns`.
    pub rows: Vec<Vec<f64>>,
    /// How the run ended, in words (`completed`, `blow_up of a12 at t = 35.1 µs`, …).
    pub status: String,
    pub wall_seconds: f64,
}

/// Runs a scene file with overrides. The CLI implements it with `scene::load` + `model::simulate`.
pub trait Simulator {
    fn simulate(&self, scene: &Path, overrides: &[String]) -> Result<RunOutput, String>;
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
    Run { figure: u32, variant: String, message: String },
    #[error(transparent)]
    Plot(#[from] PlotError),
}

/// Overrides that make a figure fast enough for CI (`--quick`): 20 µs, modes up to 4,
/// 20 ns sampling.
pub const QUICK_OVERRIDES: &[&str] = &["run.duration=20e-6", "modes.max_order=4", "run.sample_interval=2e-8"];

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), PlotError> {
    let dir = path.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).map_err(|source| PlotError::Io { path: dir.to_path_buf(), source })?;
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    std::fs::write(&tmp, bytes).map_err(|source| PlotError::Io { path: tmp.clone(), source })?;
    std::fs::rename(&tmp, path).map_err(|source| {
        let _ = std::fs::remove_file(&tmp);
        PlotError::Io { path: path.to_path_buf(), source }
    })
}
