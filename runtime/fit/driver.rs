//! The fit from start to report: resolve the parameters, minimise (from `starts` points), the
//! standard errors and correlations at the optimum, and the model curve — a plain solve of the
//! scene at the fitted values, i.e. `run`'s rows at the data's times.

use super::data::Data;
use super::lm::{self, Status};
use super::params::{self, Param, ParamSpec};
use super::residuals::FitProblem;
use super::sensitivities::Derivative;
use crate::scene::SceneTemplate;
use serde::Serialize;

/// Settings of a fit.
#[derive(Debug, Clone)]
pub struct Settings {
    pub params: Vec<ParamSpec>,
    /// Optimisations from this many start points (the scene's values first, then points drawn
    /// in the bounds, log-uniformly for a log parameter; ±1 decade around the start when open).
    pub starts: usize,
    pub max_iterations: usize,
}

/// One fitted parameter of `fit.json`.
#[derive(Debug, Clone, Serialize)]
pub struct Fitted {
    pub key: String,
    pub value: f64,
    pub std_error: f64,
    /// Bounds (null when open).
    pub low: Option<f64>,
    pub high: Option<f64>,
    /// The start value (the scene's).
    pub start: f64,
    /// Fitted in log (a strictly positive key).
    pub log: bool,
    /// How ∂f/∂p was formed: "exact", "finite_difference", or "time" (the time offset: the
    /// model's time derivative).
    pub derivative: String,
}

/// One fitted column of `fit.csv`: data, model, residual at the data's times.
#[derive(Debug, Clone, Serialize)]
pub struct CurveColumn {
    pub name: String,
    pub data: Vec<f64>,
    pub model: Vec<f64>,
    pub residual: Vec<f64>,
    /// √mean(residual²) [m].
    pub rms: f64,
}

/// The result (`fit.json` is its serialisation without the curves).
#[derive(Debug, Clone, Serialize)]
pub struct FitReport {
    pub parameters: Vec<Fitted>,
    /// Correlation matrix, in the order of `parameters`.
    pub correlation: Vec<Vec<f64>>,
    /// √(mean r²) of the weighted residuals r = (model − data)/σ (≈ 1 when σ is the noise).
    pub residual_rms: f64,
    pub iterations: usize,
    /// "converged", "max_iterations" or "failed".
    pub status: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    pub warnings: Vec<String>,
    /// Start points tried and the one that won (0: the scene's values).
    pub starts: usize,
    pub best_start: usize,
    pub plain_solves: u64,
    pub sensitivity_solves: u64,
    /// The `--set` overrides that reproduce the fitted model with `run` (time offset aside).
    pub overrides: Vec<String>,
    /// The time offset [s] (0 unless fitted).
    pub time_offset: f64,
    /// The abscissa of the curves: the data's t [s], or f [Hz] for an attenuation spectrum.
    #[serde(skip)]
    pub t: Vec<f64>,
    #[serde(skip)]
    pub curves: Vec<CurveColumn>,
}

/// A deterministic generator for the start points (xorshift64*).
struct Rng(u64);

impl Rng {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Fits `template` to `data`. Errors are bad input (which key, which value, why); a fit that
/// fails is a report with status "failed" and its reason.
pub fn fit(template: &SceneTemplate, data: &Data, settings: &Settings, cancel: &dyn Fn() -> bool) -> anyhow::Result<FitReport> {
    let run = &template.scene().run;
    let (t0, t1) = (data.t[0], data.t[data.t.len() - 1]);
    let window = (-t0, run.duration - t1);
    let fits_time = settings.params.iter().any(|p| p.key == params::TIME_OFFSET);
    if !fits_time && (t0 < 0.0 || t1 > run.duration * (1.0 + 1e-12)) {
        anyhow::bail!(
            "data from t = {t0:e} s to {t1:e} s lie outside the run's time window [0, {:e}] s (run.duration; or fit time_offset)",
            run.duration
        );
    }
    anyhow::ensure!(window.0 <= window.1, "the data span {:e} s, longer than the run (run.duration = {:e} s)", t1 - t0, run.duration);
    let params = params::resolve(template, &settings.params, window)?;
    anyhow::ensure!(data.len() > params.len(), "{} residuals for {} parameters: more data are needed", data.len(), params.len());
    let mut problem = FitProblem::new(template, data, &params, cancel)?;
    optimise(&mut problem, settings, cancel)
}

/// What the driver needs of a fit's problem besides the optimiser's: the R(t) fit's
/// [`FitProblem`] and the attenuation spectrum's ([`super::spectrum`]).
pub(crate) trait Target: lm::Problem {
    fn params(&self) -> &[Param];
    /// Number of residuals.
    fn residual_count(&self) -> usize;
    /// The noise is estimated from the residuals (some column came without σ).
    fn sigma_estimated(&self) -> bool;
    fn last_failure(&self) -> Option<String>;
    /// The abscissa (t or f) and the fitted columns at u (`None`: the model fails there).
    fn curves(&mut self, u: &[f64]) -> Option<(Vec<f64>, Vec<CurveColumn>)>;
    /// How the residuals' derivative in parameter j was formed (`fit.json`'s `derivative`).
    fn derivative(&self, j: usize) -> String;
    /// (plain, sensitivity) solves so far.
    fn solves(&self) -> (u64, u64);
    /// Secant Jacobian updates allowed in a row ([`lm::Options::secant_steps`]): where an exact
    /// Jacobian costs several residual evaluations. Default none.
    fn secant_steps(&self) -> usize {
        0
    }
    /// The parameter values of u.
    fn values(&self, u: &[f64]) -> Vec<f64> {
        self.params().iter().zip(u).map(|(p, &u)| p.from_u(u)).collect()
    }
}

/// Levenberg–Marquardt from `settings.starts` points (the scene's values first), the best
/// outcome reported.
pub(crate) fn optimise<P: Target>(problem: &mut P, settings: &Settings, cancel: &dyn Fn() -> bool) -> anyhow::Result<FitReport> {
    let params = problem.params().to_vec();
    let opt = lm::Options {
        max_iterations: settings.max_iterations,
        low: params.iter().map(|p| p.to_u(p.low)).map(|v| if v.is_nan() { f64::NEG_INFINITY } else { v }).collect(),
        high: params.iter().map(|p| p.to_u(p.high)).collect(),
        tolerance: 1e-10,
        // a step under 1e-2 standard errors ends the fit (lm::Options)
        noise_fraction: 5e-5,
        secant_steps: problem.secant_steps(),
    };
    let u_start: Vec<f64> = params.iter().map(|p| p.to_u(p.start)).collect();
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut best: Option<(usize, lm::Outcome)> = None;
    for s in 0..settings.starts.max(1) {
        let u0: Vec<f64> = if s == 0 {
            u_start.clone()
        } else {
            (0..params.len())
                .map(|j| {
                    let (lo, hi) = (opt.low[j], opt.high[j]);
                    let x = rng.uniform();
                    if lo.is_finite() && hi.is_finite() {
                        lo + x * (hi - lo)
                    } else if params[j].log {
                        (u_start[j] + (2.0 * x - 1.0) * std::f64::consts::LN_10).clamp(lo, hi)
                    } else {
                        (u_start[j] * (0.5 + x)).clamp(lo, hi)
                    }
                })
                .collect()
        };
        let out = lm::minimise(problem, &u0, &opt);
        let better = match &best {
            None => true,
            Some((_, b)) => rank(&out) < rank(b) || (rank(&out) == rank(b) && out.cost < b.cost),
        };
        if better {
            best = Some((s, out));
        }
        if cancel() {
            anyhow::bail!("cancelled");
        }
    }
    let (best_start, out) = best.expect("at least one start");
    report(problem, out, best_start, settings.starts.max(1))
}

/// With stated uncertainties (not estimated from the residuals), a fit that does not describe
/// the data: χ²/ν above 1 + 5√(2/ν), five standard deviations of the χ² distribution with
/// ν = m − p degrees of freedom above its mean. A converged fit there is a local minimum or a
/// model that cannot describe the data, and its standard errors (which assume the model fits)
/// are not to be trusted: said, not hidden behind "converged" (a monodisperse attenuation fit
/// started 3× below the truth ended with a weighted rms of 435).
pub fn misfit_warning(chi2: f64, m: usize, p: usize, estimated: bool) -> Option<String> {
    if estimated || m <= p || !chi2.is_finite() {
        return None;
    }
    let nu = (m - p) as f64;
    let reduced = chi2 / nu;
    (reduced > 1.0 + 5.0 * (2.0 / nu).sqrt()).then(|| {
        format!(
            "the model does not fit these data within their stated uncertainties: χ²/ν = {reduced:.4e} for ν = {} (expected 1 ± {:.2}); \
             a local minimum (try other start values or --starts N) or a model that cannot describe the data; the standard errors assume it does",
            m - p,
            (2.0 / nu).sqrt()
        )
    })
}

/// Converged first, then max_iterations, then failed.
fn rank(o: &lm::Outcome) -> u8 {
    match o.status {
        Status::Converged => 0,
        Status::MaxIterations => 1,
        Status::Failed(_) => 2,
    }
}

fn report<P: Target>(problem: &mut P, out: lm::Outcome, best_start: usize, starts: usize) -> anyhow::Result<FitReport> {
    let params = problem.params().to_vec();
    let params = &params[..];
    let p = params.len();
    let values = problem.values(&out.u);
    let (status, mut reason) = match &out.status {
        Status::Converged => ("converged", None),
        Status::MaxIterations => ("max_iterations", Some(format!("{} iterations without convergence", out.iterations))),
        Status::Failed(why) => ("failed", Some(why.clone())),
    };
    if let (Some(r), Some(last)) = (reason.as_mut(), problem.last_failure()) {
        r.push_str(&format!(" (last: {last})"));
    }
    let m = problem.residual_count();
    let estimated = problem.sigma_estimated();
    let chi2: f64 = out.r.iter().map(|v| v * v).sum();
    let s2 = if estimated && m > p { chi2 / (m - p) as f64 } else { 1.0 };
    let cov = out.jac.as_ref().and_then(lm::covariance);
    let mut warnings: Vec<String> = misfit_warning(chi2, m, p, estimated).into_iter().collect();
    if let Some(j) = &out.jac {
        for (k, p) in params.iter().enumerate() {
            if j.column(k).iter().all(|&v| v == 0.0) {
                warnings.push(format!("{} has no effect on the fitted columns in this scene (its sensitivity is zero)", p.key));
            }
        }
    }
    let (std_error, correlation) = match &cov {
        Some(c) => {
            let se: Vec<f64> = (0..p).map(|j| (c[(j, j)] * s2).sqrt() * params[j].dp_du(values[j]).abs()).collect();
            let corr: Vec<Vec<f64>> = (0..p).map(|i| (0..p).map(|j| c[(i, j)] / (c[(i, i)] * c[(j, j)]).sqrt()).collect()).collect();
            (se, corr)
        }
        None => {
            warnings.push("the parameters are not identifiable from these data: JᵀJ is singular (standard errors and correlations are NaN)".to_string());
            (vec![f64::NAN; p], vec![vec![f64::NAN; p]; p])
        }
    };
    for i in 0..p {
        for j in i + 1..p {
            if correlation[i][j].abs() > 0.99 {
                warnings.push(format!(
                    "{} and {} are correlated ({:.4}): not identifiable separately from these data",
                    params[i].key, params[j].key, correlation[i][j]
                ));
            }
        }
        if (values[i] - params[i].low).abs() <= 1e-9 * values[i].abs().max(1e-300) || (values[i] - params[i].high).abs() <= 1e-9 * values[i].abs().max(1e-300) {
            warnings.push(format!("{} = {:e} is at a bound", params[i].key, values[i]));
        }
    }
    // the model curve: a plain solve at the fitted values (the rows `run` gives at these times)
    let (t, curves) = problem.curves(&out.u).unwrap_or_default();
    let parameters = params
        .iter()
        .zip(&values)
        .zip(&std_error)
        .enumerate()
        .map(|(j, ((p, &v), &se))| Fitted {
            key: p.key.clone(),
            value: v,
            std_error: se,
            low: p.low.is_finite().then_some(p.low),
            high: p.high.is_finite().then_some(p.high),
            start: p.start,
            log: p.log,
            derivative: problem.derivative(j),
        })
        .collect();
    let overrides = params.iter().zip(&values).filter(|(p, _)| !p.is_time_offset()).map(|(p, v)| format!("{}={v:?}", p.key)).collect();
    let time_offset = params.iter().zip(&values).find(|(p, _)| p.is_time_offset()).map_or(0.0, |(_, &v)| v);
    Ok(FitReport {
        parameters,
        correlation,
        residual_rms: if out.r.is_empty() { f64::NAN } else { (chi2 / m as f64).sqrt() },
        iterations: out.iterations,
        status: status.into(),
        reason,
        warnings,
        starts,
        best_start,
        plain_solves: problem.solves().0,
        sensitivity_solves: problem.solves().1,
        overrides,
        time_offset,
        t,
        curves,
    })
}

impl Target for FitProblem<'_> {
    fn params(&self) -> &[Param] {
        self.params
    }
    fn residual_count(&self) -> usize {
        self.data.len()
    }
    fn sigma_estimated(&self) -> bool {
        self.data.columns.iter().any(|c| !c.sigma_given)
    }
    fn last_failure(&self) -> Option<String> {
        self.last_failure.clone()
    }
    fn curves(&mut self, u: &[f64]) -> Option<(Vec<f64>, Vec<CurveColumn>)> {
        let (_, c) = self.curve(u)?;
        let n = self.data.t.len();
        let cols = self
            .data
            .columns
            .iter()
            .zip(&self.columns)
            .map(|(col, &idx)| {
                let model: Vec<f64> = (0..n).map(|i| c.rows[i][idx]).collect();
                CurveColumn::new(&col.name, col.values.clone(), model)
            })
            .collect();
        Some((self.data.t.clone(), cols))
    }
    fn derivative(&self, j: usize) -> String {
        match (self.params[j].is_time_offset(), self.derivative[j]) {
            (true, _) => "time".into(),
            (_, Some(Derivative::Exact)) => "exact".into(),
            (_, Some(Derivative::FiniteDifference)) => "finite_difference".into(),
            (_, None) => "none".into(),
        }
    }
    fn solves(&self) -> (u64, u64) {
        (self.plain_solves, self.sensitivity_solves)
    }
    /// A sensitivity solve costs 4–7 plain solves (docs/performance.md, "Fit"): between exact
    /// Jacobians, up to [`SECANT_STEPS`] secant updates.
    fn secant_steps(&self) -> usize {
        SECANT_STEPS
    }
}

/// Secant Jacobian updates in a row in the R(t) fit ([`lm::Options::secant_steps`]).
pub const SECANT_STEPS: usize = 3;

impl CurveColumn {
    /// A column from data and model: residual = model − data, rms its root mean square.
    pub fn new(name: &str, data: Vec<f64>, model: Vec<f64>) -> CurveColumn {
        let residual: Vec<f64> = model.iter().zip(&data).map(|(m, d)| m - d).collect();
        let rms = (residual.iter().map(|v| v * v).sum::<f64>() / residual.len().max(1) as f64).sqrt();
        CurveColumn { name: name.into(), data, model, residual, rms }
    }
}

#[cfg(test)]
mod tests {
    use super::misfit_warning;

    #[test]
    fn a_misfit_is_said_only_with_stated_uncertainties_and_beyond_five_sigma() {
        // ν = 28: 1 + 5·√(2/28) = 2.336
        assert!(misfit_warning(28.0 * 2.3, 30, 2, false).is_none());
        let w = misfit_warning(28.0 * 2.4, 30, 2, false).expect("beyond 5σ");
        assert!(w.contains("χ²/ν = 2.4000e0") && w.contains("ν = 28"), "{w}");
        // weighted rms 435 over 30 points
        assert!(misfit_warning(30.0 * 435.0f64.powi(2), 30, 2, false).is_some());
        // σ estimated from the residuals: χ²/ν is 1 by construction, nothing to say
        assert!(misfit_warning(30.0 * 435.0f64.powi(2), 30, 2, true).is_none());
        assert!(misfit_warning(1.0, 2, 2, false).is_none());
    }
}

