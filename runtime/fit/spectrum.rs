//! `fit --attenuation`: scene parameters (typically the shell's) from a measured attenuation
//! spectrum of a suspension (issue 32 part 4, issue 33 part 3 — the de Jong / Hoff / Gorce
//! characterisation). The model is `attenuation`'s, not a copy: the suspension's bins
//! ([`crate::population::bin_templates`], or one bin at bubble.radius for a scene without a
//! `[population]`), each bin's linear response ([`crate::analysis::response`]) and the dilute sum
//! of docs/population.md ([`crate::population::attenuation::attenuation_spectrum`]).
//!
//! The data: CSV columns `f` [Hz] (> 0, strictly increasing), `attenuation_db_per_cm`, optional
//! `sigma` [dB/cm] (weights 1/σ²; absent: one σ for all points, the column's standard deviation,
//! and the covariance scaled by the reduced χ² as for R(t), [`super::data`]).
//!
//! The residuals' Jacobian is central differences in the optimiser's coordinates u (step 1e-5
//! per unit of u, truncation O(h²) ≈ 1e-10 relative): the linear response is a closed form per
//! frequency, so a spectrum costs microseconds per bin and a difference quotient is cheaper to
//! keep correct than a derivative of every term's linearisation. fit.json says
//! `"derivative": "finite_difference"` for every parameter.

use super::data::csv_columns;
use super::driver::{optimise, CurveColumn, FitReport, Settings, Target};
use super::lm;
use super::params::{self, Param};
use crate::population::attenuation::attenuation_spectrum;
use crate::population::bin_templates;
use crate::scene::{Scene, SceneTemplate};
use anyhow::{bail, Context};
use nalgebra::DMatrix;

/// A measured attenuation spectrum.
#[derive(Debug, Clone)]
pub struct Spectrum {
    /// Strictly increasing, > 0 [Hz].
    pub f: Vec<f64>,
    /// [dB/cm]
    pub attenuation: Vec<f64>,
    /// σ per point [dB/cm].
    pub sigma: Vec<f64>,
    /// `true`: σ came with the data.
    pub sigma_given: bool,
}

impl Spectrum {
    pub fn read(path: &std::path::Path) -> anyhow::Result<Spectrum> {
        let text = std::fs::read_to_string(path).with_context(|| format!("cannot read the attenuation file {}", path.display()))?;
        Self::from_columns(csv_columns(&text, "f, attenuation_db_per_cm[, sigma]")?).with_context(|| format!("attenuation file {}", path.display()))
    }

    /// A spectrum from named columns (a CSV file's or a DataFrame's).
    pub fn from_columns(columns: Vec<(String, Vec<f64>)>) -> anyhow::Result<Spectrum> {
        let mut seen = std::collections::BTreeSet::new();
        for (name, v) in &columns {
            anyhow::ensure!(seen.insert(name.as_str()), "column `{name}` appears twice");
            anyhow::ensure!(
                ["f", "attenuation_db_per_cm", "sigma"].contains(&name.as_str()),
                "unknown column `{name}` (expected f [Hz], attenuation_db_per_cm, optional sigma [dB/cm])"
            );
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                bail!("column {name}, row {}: {} (NaN or infinite)", i + 1, v[i]);
            }
        }
        let get = |n: &str| columns.iter().find(|(c, _)| c == n).map(|(_, v)| v.clone());
        let f = get("f").context("no column `f` [Hz]")?;
        let attenuation = get("attenuation_db_per_cm").context("no column `attenuation_db_per_cm`")?;
        anyhow::ensure!(f.len() >= 2, "{} data rows: at least 2 are needed", f.len());
        if let Some(i) = f.iter().position(|&x| !(x > 0.0)) {
            bail!("column f, row {}: {:e} Hz (a frequency must be > 0)", i + 1, f[i]);
        }
        if let Some(i) = (1..f.len()).find(|&i| !(f[i] > f[i - 1])) {
            bail!("column f, row {}: {:e} Hz after {:e} Hz (f must increase strictly)", i + 1, f[i], f[i - 1]);
        }
        let (sigma, sigma_given) = match get("sigma") {
            Some(s) => {
                if let Some(i) = s.iter().position(|&x| !(x > 0.0)) {
                    bail!("column sigma, row {}: {} (an uncertainty must be > 0)", i + 1, s[i]);
                }
                (s, true)
            }
            None => {
                let mean = attenuation.iter().sum::<f64>() / attenuation.len() as f64;
                let sd = (attenuation.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / attenuation.len() as f64).sqrt();
                let sd = if sd > 0.0 { sd } else { 0.01 * mean.abs().max(1e-300) };
                (vec![sd; attenuation.len()], false)
            }
        };
        Ok(Spectrum { f, attenuation, sigma, sigma_given })
    }
}

/// The suspension of `template`: each bin's scene and number density [1/m³] — the population's
/// bins with population.concentration, or, without a `[population]`, one bin at bubble.radius
/// with `concentration` [bubbles/mL].
pub fn suspension(template: &SceneTemplate, concentration: Option<f64>) -> anyhow::Result<Vec<(Scene, f64)>> {
    let scene = template.scene();
    match (&scene.population, concentration) {
        (Some(_), Some(_)) => bail!("--concentration is for a scene without [population]: set population.concentration instead (--set population.concentration=N)"),
        (Some(pop), None) => {
            let n_ml = pop.concentration_per_ml.context("population.concentration [bubbles/mL] is required to fit an attenuation spectrum")?;
            Ok(bin_templates(template, pop)?.into_iter().zip(&pop.bins).map(|(t, b)| (t.into_scene(), n_ml * 1e6 * b.weight)).collect())
        }
        (None, Some(n_ml)) => {
            anyhow::ensure!(n_ml > 0.0 && n_ml.is_finite(), "--concentration {n_ml}: must be a positive number of bubbles/mL");
            Ok(vec![(scene.clone(), n_ml * 1e6)])
        }
        (None, None) => bail!(
            "no concentration: the scene has no [population] (a monodisperse suspension at bubble.radius needs --concentration N [bubbles/mL]; \
             a size distribution needs [population] with population.concentration)"
        ),
    }
}

/// Fits `template` to a measured spectrum (see the module doc).
pub fn fit_attenuation(template: &SceneTemplate, data: &Spectrum, concentration: Option<f64>, settings: &Settings, cancel: &dyn Fn() -> bool) -> anyhow::Result<FitReport> {
    if let Some(p) = settings.params.iter().find(|p| p.key == params::TIME_OFFSET) {
        bail!("--param {}: an attenuation spectrum has no time axis", p.key);
    }
    let params = params::resolve(template, &settings.params, (0.0, 0.0))?;
    anyhow::ensure!(data.f.len() > params.len(), "{} frequencies for {} parameters: more data are needed", data.f.len(), params.len());
    // the model at the start: bad input (no concentration, a refused bin) is an error here
    let mut problem = SpectrumProblem { template, data, params: &params, concentration, evaluations: 0, last_failure: None };
    let start: Vec<f64> = params.iter().map(|p| p.to_u(p.start)).collect();
    problem.model(&start).map_err(|e| e.context("the model spectrum at the scene's values"))?;
    optimise(&mut problem, settings, cancel)
}

struct SpectrumProblem<'a> {
    template: &'a SceneTemplate,
    data: &'a Spectrum,
    params: &'a [Param],
    concentration: Option<f64>,
    /// Spectra computed.
    evaluations: u64,
    last_failure: Option<String>,
}

impl SpectrumProblem<'_> {
    /// The model's attenuation [dB/cm] at the data's frequencies at u.
    fn model(&mut self, u: &[f64]) -> anyhow::Result<Vec<f64>> {
        let set: Vec<String> = self.params.iter().zip(u).map(|(p, &u)| format!("{}={:?}", p.key, p.from_u(u))).collect();
        let template = self.template.with_overrides(&set)?;
        let bins = suspension(&template, self.concentration)?;
        self.evaluations += 1;
        Ok(attenuation_spectrum(&bins, &self.data.f)?.iter().map(|p| p.attenuation_db_per_cm).collect())
    }

    fn residuals_at(&mut self, u: &[f64]) -> Option<Vec<f64>> {
        let m = self.model(u).map_err(|e| self.last_failure = Some(format!("{e:#}"))).ok()?;
        let r: Vec<f64> = m.iter().zip(&self.data.attenuation).zip(&self.data.sigma).map(|((m, d), s)| (m - d) / s).collect();
        r.iter().all(|v| v.is_finite()).then_some(r)
    }
}

impl lm::Problem for SpectrumProblem<'_> {
    fn residuals(&mut self, u: &[f64]) -> Option<Vec<f64>> {
        self.residuals_at(u)
    }

    /// Central differences, h = 1e-5 per unit of u (module doc).
    fn jacobian(&mut self, u: &[f64]) -> Option<DMatrix<f64>> {
        let mut jac = DMatrix::zeros(self.data.f.len(), u.len());
        let mut v = u.to_vec();
        for j in 0..u.len() {
            let h = 1e-5 * u[j].abs().max(1.0);
            v[j] = u[j] + h;
            let plus = self.residuals_at(&v)?;
            v[j] = u[j] - h;
            let minus = self.residuals_at(&v)?;
            v[j] = u[j];
            for (i, (a, b)) in plus.iter().zip(&minus).enumerate() {
                jac[(i, j)] = (a - b) / (2.0 * h);
            }
        }
        Some(jac)
    }
}

impl Target for SpectrumProblem<'_> {
    fn params(&self) -> &[Param] {
        self.params
    }
    fn residual_count(&self) -> usize {
        self.data.f.len()
    }
    fn sigma_estimated(&self) -> bool {
        !self.data.sigma_given
    }
    fn last_failure(&self) -> Option<String> {
        self.last_failure.clone()
    }
    fn curves(&mut self, u: &[f64]) -> Option<(Vec<f64>, Vec<CurveColumn>)> {
        let model = self.model(u).ok()?;
        Some((self.data.f.clone(), vec![CurveColumn::new("attenuation_db_per_cm", self.data.attenuation.clone(), model)]))
    }
    fn derivative(&self, _j: usize) -> String {
        "finite_difference".into()
    }
    /// Spectra count as plain solves; there are no sensitivity solves.
    fn solves(&self) -> (u64, u64) {
        (self.evaluations, 0)
    }
}
