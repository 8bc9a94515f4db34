//! The font used for every text in the figures.
//!
//! plotters is built without its system-font backend (`ab_glyph` only), so the PNG renderer
//! needs a font registered from bytes; it must work on a fresh machine with no fonts installed.
//! The bytes come from the `dejavu` crate (DejaVu Sans 2.37, the DejaVu fonts licence — a
//! permissive Bitstream Vera derivative — shipped inside that crate as
//! `assets/dejavu-fonts-ttf-2.37/LICENSE`). DejaVu Sans covers the Greek letters, the
//! subscripts and the dotted letters (ω, ε, χ, ₖ, ȧ) used in the axis labels.

use super::PlotError;
use std::sync::OnceLock;

/// The family name every text style asks for.
pub const FAMILY: &str = "sans-serif";

/// Registers DejaVu Sans as [`FAMILY`] (once per process; later calls return the first result).
pub fn register() -> Result<(), PlotError> {
    static DONE: OnceLock<Result<(), String>> = OnceLock::new();
    DONE.get_or_init(|| {
        plotters::style::register_font(
            FAMILY,
            plotters::style::FontStyle::Normal,
            dejavu::sans::regular(),
        )
        .map_err(|_| "the embedded DejaVu Sans font could not be parsed".to_string())
    })
    .clone()
    .map_err(PlotError::Font)
}
