//! `fit`: the scene's parameters from measured R(t) (and a_k(t)) (issue 32). The physics is in
//! [`crate::fit`]; this is the typed entry point the CLI and Python share.

use super::common::{Cancelled, Monitor};
use super::scene::Scene;
pub use crate::fit::driver::{CurveColumn, FitReport, Fitted};
pub use crate::fit::spectrum::Spectrum;
pub use crate::fit::{Data, ParamSpec};

/// What to fit, and how.
#[derive(Debug, Clone)]
pub struct FitRequest {
    /// The measurements (from a CSV file: [`Data::read`]; from columns: [`Data::from_columns`]).
    pub data: Data,
    /// `KEY[=LOW:HIGH]` per fitted parameter ([`ParamSpec`] parses the text).
    pub params: Vec<ParamSpec>,
    /// Start points (1: the scene's values only).
    pub starts: usize,
    /// Levenberg–Marquardt iterations per start.
    pub max_iterations: usize,
}

impl FitRequest {
    pub fn new(data: Data, params: Vec<ParamSpec>) -> FitRequest {
        FitRequest { data, params, starts: 1, max_iterations: 100 }
    }
}

/// Fits `scene` to the request's data. Bad input is an error naming the key, column or value;
/// a fit that fails is a report with `status = "failed"` and its reason.
pub fn fit(scene: &Scene, request: &FitRequest, monitor: &Monitor) -> anyhow::Result<FitReport> {
    let settings = crate::fit::Settings { params: request.params.clone(), starts: request.starts, max_iterations: request.max_iterations };
    anyhow::ensure!(request.starts >= 1, "--starts {}: at least 1", request.starts);
    let cancel = || monitor.cancelled();
    let r = crate::fit::fit(scene.template(), &request.data, &settings, &cancel);
    if monitor.cancelled() {
        return Err(Cancelled.into());
    }
    r.map_err(|e| e.context(format!("fit of {}", scene.origin())))
}

/// A fit of a measured attenuation spectrum (`fit --attenuation`, issue 32 part 4 and issue 33
/// part 3): the suspension of the scene's `[population]` (with population.concentration), or a
/// monodisperse one at bubble.radius with `concentration` [bubbles/mL].
#[derive(Debug, Clone)]
pub struct AttenuationFitRequest {
    /// The measured spectrum ([`Spectrum::read`], [`Spectrum::from_columns`]).
    pub data: Spectrum,
    pub params: Vec<ParamSpec>,
    /// Bubbles per mL of a scene without `[population]`.
    pub concentration: Option<f64>,
    pub starts: usize,
    pub max_iterations: usize,
}

impl AttenuationFitRequest {
    pub fn new(data: Spectrum, params: Vec<ParamSpec>, concentration: Option<f64>) -> AttenuationFitRequest {
        AttenuationFitRequest { data, params, concentration, starts: 1, max_iterations: 100 }
    }
}

/// Fits `scene` to a measured attenuation spectrum (report as [`fit`]'s; its curve's abscissa
/// is the frequency [Hz]).
pub fn fit_attenuation(scene: &Scene, request: &AttenuationFitRequest, monitor: &Monitor) -> anyhow::Result<FitReport> {
    anyhow::ensure!(request.starts >= 1, "--starts {}: at least 1", request.starts);
    let settings = crate::fit::Settings { params: request.params.clone(), starts: request.starts, max_iterations: request.max_iterations };
    let cancel = || monitor.cancelled();
    let r = crate::fit::spectrum::fit_attenuation(scene.template(), &request.data, request.concentration, &settings, &cancel);
    if monitor.cancelled() {
        return Err(Cancelled.into());
    }
    r.map_err(|e| e.context(format!("attenuation fit of {}", scene.origin())))
}
