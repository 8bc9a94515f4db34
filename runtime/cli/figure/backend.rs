//! The model and analysis behind the figure recipes of [`crate::plot::paper`]: a [`Simulator`]
//! on `scene::load` + `model::simulate`, and an [`Analyzer`] on
//! `analysis::{frequencies, ladder}` (critical values by bracketing + bisection of the
//! Floquet criterion, FORMULATION §4.6; paper §4 uses eigenvalues "< 1", we use |μ| < 1; the
//! max-multiplier panel to 1e-7 relative, analysis/ladder.rs).

use crate::analysis::frequencies::natural_frequencies;
use crate::analysis::ladder;
use crate::analysis::stability::{Criterion, CriticalOptions, FloquetOptions, StabilityError};
use crate::model::{simulate, RunStatus};
use crate::plot::paper::{Analyzer, CriticalRow, ModeRow, RunOutput, Simulator, Sweep};
use crate::scene::{self, Scene, SceneTemplate};
use rayon::prelude::*;
use std::path::Path;
use std::time::Instant;

/// Extra overrides of the stability figures with `--quick`: modes up to 8 (a family that sets
/// `modes.max_order` itself keeps its value, see [`ModelAnalyzer::load`]).
pub const QUICK_STABILITY: &[&str] = &["modes.max_order=8"];

/// `scene::load` + `model::simulate`, keeping every sample; `extra` (`figure --set`) is applied
/// after each curve's own overrides.
pub struct ModelSimulator {
    pub extra: Vec<String>,
}

impl Simulator for ModelSimulator {
    fn model(&self) -> Option<String> {
        (!self.extra.is_empty()).then(|| self.extra.join(", "))
    }
    fn overrides(&self) -> Vec<String> {
        self.extra.clone()
    }
    fn simulate(&self, path: &Path, overrides: &[String]) -> Result<RunOutput, String> {
        let all: Vec<String> = overrides.iter().chain(&self.extra).cloned().collect();
        let scene = scene::load(path, &all).map_err(|e| e.to_string())?;
        let start = Instant::now();
        let (mut t_s, mut rows) = (Vec::new(), Vec::new());
        let report = simulate(&scene, &mut |t, row| {
            t_s.push(t);
            rows.push(row.to_vec());
        })
        .map_err(|e| e.to_string())?;
        let columns = report.max_abs.iter().map(|(n, _)| n.clone()).collect();
        let (status, blow_up) = match &report.status {
            RunStatus::Completed => (format!("completed ({:.1} µs)", report.t_end * 1e6), None),
            RunStatus::BlowUp { t, mode } => (
                format!("blow_up of {mode} at t = {:.2} µs", t * 1e6),
                Some((mode.clone(), *t)),
            ),
            RunStatus::Failed { reason } => (
                format!("integrator failed at t = {:.2} µs: {reason}", report.t_end * 1e6),
                None,
            ),
            RunStatus::OutOfCredibleRange { t, mode, bound } => {
                (format!("out_of_credible_range: |{mode}|/R0 > {bound} at t = {:.2} µs", t * 1e6), None)
            }
        };
        Ok(RunOutput {
            columns,
            t_s,
            rows,
            status,
            blow_up,
            wall_seconds: start.elapsed().as_secs_f64(),
        })
    }
}

/// Floquet-based stability analyses; `quick` caps the modes at 8, coarsens the bisection
/// and the Magnus/shooting resolution.
pub struct ModelAnalyzer {
    pub quick: bool,
}

impl ModelAnalyzer {
    /// The scene with the quick overrides first and the family's after (so a family's own
    /// `modes.max_order`, fig 5, wins).
    fn load(&self, path: &Path, overrides: &[String]) -> Result<SceneTemplate, String> {
        let mut all: Vec<String> = Vec::new();
        if self.quick && !overrides.iter().any(|o| o.starts_with("modes.max_order")) {
            all.extend(QUICK_STABILITY.iter().map(|s| s.to_string()));
        }
        all.extend(overrides.iter().cloned());
        SceneTemplate::load(path, &all).map_err(|e| e.to_string())
    }

    fn floquet_options(&self) -> FloquetOptions {
        let mut o = FloquetOptions::default();
        if self.quick {
            o.magnus_steps = 100;
            o.shooting.steps_per_period = 100;
        }
        o
    }
}

/// `a12` → 12.
fn mode_number(mode: &str) -> Option<usize> {
    mode.trim_start_matches(|c: char| !c.is_ascii_digit()).parse().ok()
}

impl Analyzer for ModelAnalyzer {
    fn modes(
        &self,
        path: &Path,
        overrides: &[String],
        kmax: usize,
    ) -> Result<(Vec<ModeRow>, f64), String> {
        let template = self.load(path, overrides)?;
        let f = natural_frequencies(template.scene(), kmax).map_err(|e| e.to_string())?;
        let rows = f
            .shape
            .iter()
            .map(|s| ModeRow {
                k: s.k,
                omega_rad_s: s.omega_rad_s,
                omega_nondim: s.omega_nondim,
            })
            .collect();
        Ok((rows, f.t_star))
    }

    fn critical(
        &self,
        path: &Path,
        overrides: &[String],
        sweep: &Sweep,
    ) -> Result<Vec<CriticalRow>, String> {
        let base = self.load(path, overrides)?;
        let (lo, hi) = sweep.range;
        let opts = CriticalOptions {
            criterion: Criterion::Floquet,
            lo,
            hi,
            scan: if self.quick { 4 } else { 8 },
            tol: (hi - lo) * if self.quick { 2e-2 } else { 2e-3 },
            relative_tol: false,
            floquet: self.floquet_options(),
            series: Default::default(),
        };
        let one = |&f: &f64| -> Result<CriticalRow, String> {
            let at = |p: f64| -> Result<Scene, StabilityError> {
                base.with(&[(sweep.freq_key, f), (sweep.vary, p)])
                    .map_err(|e| StabilityError::Scene(e.to_string()))
            };
            // the figure plots outcome, critical value and mode: not the bracket ends' multipliers
            let (outcome, mode) = ladder::critical_outcome(&at, &opts)
                .map_err(|e| format!("at {} = {f:e} Hz: {e}", sweep.freq_key))?;
            Ok(CriticalRow {
                frequency_hz: f,
                critical: outcome.value().unwrap_or(f64::NAN),
                outcome: outcome.name().to_string(),
                mode: mode_number(&mode),
            })
        };
        sweep.freqs_hz.par_iter().map(one).collect()
    }

    fn max_multiplier(
        &self,
        path: &Path,
        overrides: &[String],
        freq_key: &str,
        freqs_hz: &[f64],
    ) -> Result<Vec<f64>, String> {
        let base = self.load(path, overrides)?;
        let opts = self.floquet_options();
        freqs_hz
            .par_iter()
            .map(|&f| {
                let s = base.with(&[(freq_key, f)]).map_err(|e| e.to_string())?;
                // No periodic orbit (collapse, blow-up) is drawn as a gap, not an error.
                Ok(ladder::max_multiplier(&s, &opts).unwrap_or(f64::NAN))
            })
            .collect()
    }

    fn max_multiplier_method(&self) -> String {
        let n = self.floquet_options().magnus_steps;
        format!(
            "max |μ| over the orbit's period at the scene's ε_p, the Richardson value of the first rung of \
             the Magnus ladder {:?} steps per drive period whose estimated error is ≤ {:e} of max |μ|, or the \
             {n}-step value where no rung reaches that (analysis/ladder.rs)",
            ladder::rungs(n),
            ladder::MULTIPLIER_TOLERANCE
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mode_numbers_parse() {
        assert_eq!(mode_number("a12"), Some(12));
        assert_eq!(mode_number("a2"), Some(2));
        assert_eq!(mode_number(""), None);
    }
}
