//! The fraction of a population that is shape-unstable at a pressure amplitude
//! (docs/population.md, "Fraction unstable"): Σ_i w_i [ε_c,i ≤ ε_p] over the bins i.
//!
//! **One window per bin.** A bin's critical search ([`crate::analysis::critical`]) scans ε_p
//! upward from the bottom of the range and brackets the first stable → unstable transition. The
//! bin counts as unstable at every ε_p at or above that first threshold — including where its
//! Floquet verdict turns stable again higher up (a second stable window), since a bubble driven
//! through an unstable window has already been shape-unstable. `population` checks the top of
//! the range for every bin with a threshold and reports a bin that is stable again there
//! (`windows` = `2+`).

/// How a bin enters the fraction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Threshold {
    /// Unstable for every ε_p ≥ this value (the bracket's midpoint; the range's bottom for a
    /// bin already unstable there).
    From(f64),
    /// Stable over the whole range, or its orbit is lost before any instability (`no_orbit`:
    /// not an instability, docs/stability.md): never counted.
    Never,
    /// The bin's point failed: the fraction is NaN (never a partial sum).
    Unknown,
}

impl Threshold {
    /// From a critical point's outcome name ([`crate::analysis::bisect::Outcome::name`]), its
    /// `critical` and `unstable` values.
    pub fn of(outcome: &str, critical: f64, unstable: f64) -> Threshold {
        match outcome {
            "critical" if critical.is_finite() => Threshold::From(critical),
            "unstable_at_bottom" if unstable.is_finite() => Threshold::From(unstable),
            "stable_throughout" | "no_orbit" | "no_orbit_at_bottom" => Threshold::Never,
            _ => Threshold::Unknown,
        }
    }
}

/// Σ w_i [threshold_i ≤ eps], summed in bin order; NaN when a bin is [`Threshold::Unknown`].
pub fn fraction_unstable(bins: &[(Threshold, f64)], eps: f64) -> f64 {
    let mut sum = 0.0;
    for &(t, w) in bins {
        match t {
            Threshold::From(c) if c <= eps => sum += w,
            Threshold::Unknown => return f64::NAN,
            _ => {}
        }
    }
    sum
}

/// `n` values from `lo` to `hi` inclusive (one value: `lo`).
pub fn eps_grid(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n).map(|i| if n == 1 { lo } else { lo + (hi - lo) * (i as f64 / (n - 1) as f64) }).collect()
}
