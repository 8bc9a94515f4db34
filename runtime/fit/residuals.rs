//! The fit's residuals r = (model − data)/σ, column by column (R, then each a_k), and their
//! Jacobian in the optimiser's coordinates u (ln p for a log parameter, p/unit otherwise; the
//! time offset's column is the model's time derivative).

use super::data::Data;
use super::params::Param;
use super::sensitivities::{scale_of, Derivative, ModelRates};
use super::solve::{model_time, solve, Curve};
use crate::model::{Model, RunStatus};
use crate::scene::SceneTemplate;
use nalgebra::DMatrix;

/// The problem: the scene, the data, the parameters; counts the solves.
pub struct FitProblem<'a> {
    pub template: &'a SceneTemplate,
    pub data: &'a Data,
    pub params: &'a [Param],
    /// Output-row index of each data column (R = 0, a_k = 1 + 2m).
    pub columns: Vec<usize>,
    pub plain_solves: u64,
    pub sensitivity_solves: u64,
    /// Why the last evaluation failed (for the status).
    pub last_failure: Option<String>,
    /// How ∂f/∂p of each scene parameter is formed (from the last sensitivity solve).
    pub derivative: Vec<Option<Derivative>>,
    pub cancel: &'a dyn Fn() -> bool,
}

/// The model of a point: the scene at the parameter values, the times, the time offset.
pub struct Point {
    pub scene: crate::scene::Scene,
    pub model: Model,
    pub times: Vec<f64>,
    pub values: Vec<f64>,
}

impl<'a> FitProblem<'a> {
    pub fn new(template: &'a SceneTemplate, data: &'a Data, params: &'a [Param], cancel: &'a dyn Fn() -> bool) -> anyhow::Result<FitProblem<'a>> {
        let scene = template.scene();
        let orders: Vec<usize> = scene.modes.orders().collect();
        let mut columns = Vec::new();
        for c in &data.columns {
            if c.name == "R" {
                columns.push(0);
                continue;
            }
            let k: usize = c.name[1..].parse().unwrap_or(0);
            let m = orders.iter().position(|&o| o == k).ok_or_else(|| {
                anyhow::anyhow!("data column {}: the scene simulates shape modes up to modes.max_order = {} (raise it to fit a{k})", c.name, scene.modes.max_order)
            })?;
            columns.push(1 + 2 * m);
        }
        Ok(FitProblem { template, data, params, columns, plain_solves: 0, sensitivity_solves: 0, last_failure: None, derivative: vec![None; params.len()], cancel })
    }

    /// The parameter values of u.
    pub fn values(&self, u: &[f64]) -> Vec<f64> {
        self.params.iter().zip(u).map(|(p, &u)| p.from_u(u)).collect()
    }

    /// The scene and model at u; `Err`: the scene refuses the values.
    pub fn point(&self, u: &[f64]) -> anyhow::Result<Point> {
        let values = self.values(u);
        let set: Vec<(&str, f64)> = self.params.iter().zip(&values).filter(|(p, _)| !p.is_time_offset()).map(|(p, &v)| (p.key.as_str(), v)).collect();
        let scene = if set.is_empty() { self.template.scene().clone() } else { self.template.with(&set)? };
        crate::model::refuse_reduced_thermal(&scene, "the fit's sensitivities do not carry the reduced model's p_b: fit with gas.thermal = \"prosperetti\" or \"polytropic\"")?;
        let model = Model::from_scene(&scene)?;
        let tau = self.params.iter().zip(&values).find(|(p, _)| p.is_time_offset()).map_or(0.0, |(_, &v)| v);
        let times = self.data.t.iter().map(|&t| model_time(t + tau, &model, &scene.run)).collect();
        Ok(Point { scene, model, times, values })
    }

    /// The plain solve at u.
    pub fn curve(&mut self, u: &[f64]) -> Option<(Point, Curve)> {
        let pt = self.point(u).map_err(|e| self.last_failure = Some(format!("{e:#}"))).ok()?;
        self.plain_solves += 1;
        let c = solve(&pt.model, &pt.scene.run, &pt.times, None);
        self.check(&pt, &c)?;
        Some((pt, c))
    }

    fn check(&mut self, pt: &Point, c: &Curve) -> Option<()> {
        if c.reached() < pt.times.len() {
            let why = match &c.status {
                RunStatus::Completed => "the run ended early".to_string(),
                s => serde_json::to_string(s).unwrap_or_default(),
            };
            self.last_failure = Some(format!(
                "the model does not reach the last data point at {}: {why}",
                self.describe(&pt.values)
            ));
            return None;
        }
        Some(())
    }

    /// `key = value, …` of a point.
    pub fn describe(&self, values: &[f64]) -> String {
        self.params.iter().zip(values).map(|(p, v)| format!("{} = {v:e}", p.key)).collect::<Vec<_>>().join(", ")
    }

    /// Weighted residuals of a curve.
    pub fn weighted(&self, c: &Curve) -> Vec<f64> {
        let mut r = Vec::with_capacity(self.data.len());
        for (col, &idx) in self.data.columns.iter().zip(&self.columns) {
            for i in 0..self.data.t.len() {
                r.push((c.rows[i][idx] - col.values[i]) / col.sigma[i]);
            }
        }
        r
    }
}

impl super::lm::Problem for FitProblem<'_> {
    fn residuals(&mut self, u: &[f64]) -> Option<Vec<f64>> {
        let (_, c) = self.curve(u)?;
        let r = self.weighted(&c);
        r.iter().all(|v| v.is_finite()).then_some(r)
    }

    fn jacobian(&mut self, u: &[f64]) -> Option<DMatrix<f64>> {
        self.sensitivity(u).map(|(_, j)| j)
    }

    /// One sensitivity solve: its rows are the residuals (the start point needs no plain solve).
    fn residuals_and_jacobian(&mut self, u: &[f64]) -> Option<(Vec<f64>, Option<DMatrix<f64>>)> {
        match self.sensitivity(u) {
            Some((r, j)) if r.iter().all(|v| v.is_finite()) => Some((r, Some(j))),
            _ => {
                let r = super::lm::Problem::residuals(self, u)?;
                Some((r, None))
            }
        }
    }

    fn cancelled(&self) -> bool {
        (self.cancel)()
    }
}

impl FitProblem<'_> {
    /// The weighted residuals and their Jacobian from one sensitivity solve at u.
    fn sensitivity(&mut self, u: &[f64]) -> Option<(Vec<f64>, DMatrix<f64>)> {
        let pt = self.point(u).map_err(|e| self.last_failure = Some(format!("{e:#}"))).ok()?;
        let scene_params: Vec<usize> = (0..self.params.len()).filter(|&j| !self.params[j].is_time_offset()).collect();
        let keys: Vec<&str> = scene_params.iter().map(|&j| self.params[j].key.as_str()).collect();
        let vals: Vec<f64> = scene_params.iter().map(|&j| pt.values[j]).collect();
        let rates = ModelRates::new(self.template, &keys, &vals, &pt.model).map_err(|e| self.last_failure = Some(format!("{e:#}"))).ok()?;
        for (k, &j) in scene_params.iter().enumerate() {
            self.derivative[j] = Some(rates.derivative[k]);
        }
        self.sensitivity_solves += 1;
        let c = solve(&pt.model, &pt.scene.run, &pt.times, Some(&rates));
        self.check(&pt, &c)?;
        let n = self.data.t.len();
        let mut jac = DMatrix::zeros(self.data.len(), self.params.len());
        for (ci, (col, &idx)) in self.data.columns.iter().zip(&self.columns).enumerate() {
            for i in 0..n {
                let row = ci * n + i;
                let mut k = 0;
                for (j, p) in self.params.iter().enumerate() {
                    let d = if p.is_time_offset() {
                        c.rates[i][idx] * p.dp_du(pt.values[j])
                    } else {
                        // S is ∂/∂θ with p = p0 + |p0| θ
                        let s = c.sens[i][k][idx] / scale_of(pt.values[j]);
                        k += 1;
                        s * p.dp_du(pt.values[j])
                    };
                    jac[(row, j)] = d / col.sigma[i];
                }
            }
        }
        jac.iter().all(|v| v.is_finite()).then(|| (self.weighted(&c), jac))
    }
}
