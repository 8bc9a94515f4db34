//! Figures: a small typed layer over plotters that writes every figure as SVG and PNG.
//!
//! - [`Figure`], [`Panel`], [`Series`], [`Axis`]: a plain-data description (several named
//!   series, legend, axis labels with units, optional log axes, stacked panels sharing x).
//!   [`Figure::save`]`(dir, stem)` writes `stem.svg` and `stem.png` atomically.
//! - [`kinds`]: one function per kind of output the CLI produces (time series, phase portrait,
//!   ω_k against k, stability diagrams, first unstable mode, Floquet multiplier,
//!   work–precision, convergence), taking plain vectors so every command can call them.
//! - [`series_plot`]: reads a `series.csv` written by `magbubble run` and plots R(t) above the
//!   shape amplitudes; [`stability_plot`]: the diagram from `magbubble stability` CSVs.
//! - [`echo_plot`]: a run's echo (pressure at the receivers against time) above its spectrum.
//! - [`paper`]: the registry and recipes of the paper's figures 3–16 (`magbubble figure`).
//!
//! Non-finite values are skipped (they break a line, they never panic); a panel with no
//! drawable point is a [`PlotError::Empty`]. Text uses an embedded font ([`fonts`]), so PNGs
//! render on a machine without system fonts.

mod echo;
mod figure;
pub mod fonts;
mod from_csv;
pub mod kinds;
mod legend;
mod logshape;
mod logaxis;
pub mod paper;
mod render;
mod series_csv;
pub mod study;

pub use echo::{echo_plot, remove_stale_echo_plot};
pub use figure::{Axis, Figure, Legend, Mark, Panel, Scale, Series, VLine};
pub use logshape::{log_magnitudes, wants_log, LOG_SPAN};
pub use from_csv::{stability_plot, CsvTable};
pub use render::Saved;
pub use series_csv::{remove_stale_plots, remove_stale_series_plot, run_title, series_plot, summary_blow_up, SeriesTable};

use std::path::PathBuf;

/// Everything that can go wrong while making a figure.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    #[error("figure `{figure}`: {what}")]
    Empty { figure: String, what: String },
    #[error("figure `{figure}`: axis `{axis}`: {reason}")]
    Axis {
        figure: String,
        axis: String,
        reason: String,
    },
    #[error("figure `{figure}`: series `{series}` has {x} x values but {y} y values")]
    Length {
        figure: String,
        series: String,
        x: usize,
        y: usize,
    },
    #[error("invalid figure file stem `{stem}`: {reason}")]
    Stem { stem: String, reason: &'static str },
    #[error("cannot write {}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The directory is another process's output ([`crate::output::DirLock`]).
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
    #[error("rendering {} failed: {message}", path.display())]
    Render { path: PathBuf, message: String },
    #[error("{}: line {line}: {reason}", path.display())]
    Csv {
        path: PathBuf,
        line: usize,
        reason: String,
    },
    #[error("font: {0}")]
    Font(String),
}
