//! Expanding and validating a grid ([`plan_grid`]): nothing runs and nothing is written until
//! every key, value and combination has passed the scene validator.

use super::GridError;
use crate::scene::schema::{self, Kind};
use crate::analysis::sweep::Shard;
use crate::scene::{path_exists, Scene, SceneTemplate};

/// One value of a grid axis: a `--set` value as text (`1e6`, `vorticity`, `{ 2 = 1e-8 }`), or a
/// number (set as an integer for an integer key when it is integral, else as a float).
#[derive(Debug, Clone, PartialEq)]
pub enum GridValue {
    Text(String),
    Number(f64),
}

/// One key of a grid and its values, in order.
#[derive(Debug, Clone, PartialEq)]
pub struct GridAxis {
    pub key: String,
    pub values: Vec<GridValue>,
}

impl GridAxis {
    /// An axis of numbers (e.g. from Python: `grid={"bubble.radius": [2e-6, 3e-6]}`).
    pub fn numbers(key: impl Into<String>, values: &[f64]) -> GridAxis {
        GridAxis { key: key.into(), values: values.iter().map(|&v| GridValue::Number(v)).collect() }
    }

    /// An axis of `--set` value texts.
    pub fn texts<S: AsRef<str>>(key: impl Into<String>, values: &[S]) -> GridAxis {
        GridAxis { key: key.into(), values: values.iter().map(|v| GridValue::Text(v.as_ref().trim().to_string())).collect() }
    }

    /// Parses `--grid KEY=V1,V2,…` (values as `--set` takes them) or `KEY=START:STOP:N[:log]`
    /// (N numbers from START to STOP, linear or logarithmic, as `stability --freq`).
    pub fn parse(spec: &str) -> Result<GridAxis, GridError> {
        let bad = |why: String| GridError::Grid { what: format!("--grid '{spec}'"), why };
        let (key, list) = spec.split_once('=').ok_or_else(|| bad("expected KEY=V1,V2,… or KEY=START:STOP:N[:log]".into()))?;
        let key = key.trim();
        let list = list.trim();
        let p: Vec<&str> = list.split(':').map(str::trim).collect();
        let is_range = !list.contains(',') && (p.len() == 3 || p.len() == 4) && p[..2].iter().all(|t| t.parse::<f64>().is_ok());
        if !is_range {
            return Ok(GridAxis::texts(key, &list.split(',').collect::<Vec<_>>()));
        }
        let (a, b): (f64, f64) = (p[0].parse().unwrap_or(f64::NAN), p[1].parse().unwrap_or(f64::NAN));
        let n: usize = p[2].parse().map_err(|_| bad(format!("N = '{}' must be a positive integer", p[2])))?;
        let log = match p.get(3).copied() {
            None | Some("lin") => false,
            Some("log") => true,
            Some(other) => return Err(bad(format!("spacing '{other}' must be lin or log"))),
        };
        if !(a.is_finite() && b.is_finite() && a <= b && n >= 1) {
            return Err(bad("need finite START ≤ STOP and N ≥ 1".into()));
        }
        if log && a <= 0.0 {
            return Err(bad("a log range needs START > 0".into()));
        }
        let u = |i: usize| if n == 1 { 0.0 } else { i as f64 / (n - 1) as f64 };
        let values: Vec<f64> = (0..n).map(|i| if log { a * (b / a).powf(u(i)) } else { a + (b - a) * u(i) }).collect();
        Ok(GridAxis::numbers(key, &values))
    }
}

/// A grid planned lazily (issue 29 item 7): the keys, the value texts as set and the scene
/// template; the scene of a point is built from its index when it runs (index → values by
/// mixed-radix arithmetic, [`GridPlan::values`]), so a plan's memory is that of its axes, not of
/// its points.
#[derive(Debug, Clone)]
pub struct GridPlan {
    pub(super) axes: Vec<(String, Vec<String>)>,
    template: SceneTemplate,
    total: usize,
    /// Mode orders with a `max_*` column (those of the largest `modes.max_order` of the grid).
    pub(super) orders: Vec<usize>,
    pub(super) fingerprint: String,
}

/// A grid of up to this many points is validated point by point when it is planned; an axis of
/// up to this many values value by value (a longer one, a range, at its two ends). A larger
/// grid's points are validated shard by shard before the shard runs ([`GridPlan::check_shard`]).
pub const VALIDATE_ALL: usize = 100_000;

/// The most points one process (one shard) runs: each point's row is kept until the CSV is
/// written, and its points are validated before the first runs. A larger shard is refused with
/// the shard count that would do.
pub const MAX_SHARD_POINTS: usize = 1_000_000;

impl GridPlan {
    /// Number of points (runs) of the whole grid.
    pub fn len(&self) -> usize {
        self.total
    }

    /// Whether the grid has no point (never: [`plan_grid`] refuses an empty axis).
    pub fn is_empty(&self) -> bool {
        self.total == 0
    }

    /// The number of points shard `shard` owns (`index % count == index of the shard`).
    pub fn shard_len(&self, shard: Shard) -> usize {
        if shard.index >= self.total {
            0
        } else {
            (self.total - shard.index).div_ceil(shard.count)
        }
    }

    /// The points of `shard`, in order, without listing the others.
    pub fn shard_points(&self, shard: Shard) -> impl Iterator<Item = usize> {
        (shard.index..self.total).step_by(shard.count.max(1))
    }

    /// Refuses a shard larger than [`MAX_SHARD_POINTS`] (naming the shard count that would do)
    /// and validates every point of the shard (the messages of `--set`, naming the point), before
    /// any of them runs. Returns the shard's number of points.
    pub fn check_shard(&self, shard: Shard) -> Result<usize, GridError> {
        let n = self.shard_len(shard);
        if n > MAX_SHARD_POINTS {
            return Err(GridError::Grid {
                what: format!("--shard {}/{}", shard.index, shard.count),
                why: format!(
                    "the shard holds {n} of the grid's {} points, more than the {MAX_SHARD_POINTS} one process runs; split the grid into at least {} shards",
                    self.total,
                    self.total.div_ceil(MAX_SHARD_POINTS)
                ),
            });
        }
        if self.total > VALIDATE_ALL {
            for i in self.shard_points(shard) {
                self.scene(i)?;
            }
        }
        Ok(n)
    }

    /// The grid keys, in axis order.
    pub fn keys(&self) -> Vec<&str> {
        self.axes.iter().map(|(k, _)| k.as_str()).collect()
    }

    /// The axes: each key with its values as set (the text of the CSV's parameter columns).
    pub fn axes(&self) -> &[(String, Vec<String>)] {
        &self.axes
    }

    /// The value texts of point `index`, one per axis (first axis slowest: mixed radix with the
    /// axis lengths as digits).
    pub fn values(&self, index: usize) -> Vec<&str> {
        let mut rest = index;
        let mut out = vec![""; self.axes.len()];
        for (slot, (_, vs)) in out.iter_mut().zip(&self.axes).rev() {
            *slot = &vs[rest % vs.len()];
            rest /= vs.len();
        }
        out
    }

    /// The validated scene of point `index`, built from the template.
    pub fn scene(&self, index: usize) -> Result<Scene, GridError> {
        let sets: Vec<String> = self.keys().iter().zip(self.values(index)).map(|(k, v)| format!("{k}={v}")).collect();
        Ok(self
            .template
            .with_overrides(&sets)
            .map_err(|source| GridError::Scene { context: format!("grid point {index} ({})", sets.join(", ")), source })?
            .into_scene())
    }

    /// The CSV header after `index`: the grid keys, then [`super::row::result_header`] (one
    /// `max_a<k>`, `max_b<k>` pair per mode of the grid's largest `modes.max_order`).
    pub fn header(&self) -> Vec<String> {
        let mut h: Vec<String> = self.axes.iter().map(|(k, _)| k.clone()).collect();
        h.extend(super::row::result_header(&self.orders));
        h
    }

    /// What the grid computes (the resolved base scene and the axes): a CSV of another
    /// fingerprint is never appended to, and shards merge only with equal fingerprints.
    pub fn fingerprint(&self) -> &str {
        &self.fingerprint
    }
}

/// A grid value as `--set` text.
fn value_text(key: &str, v: &GridValue) -> Result<String, String> {
    match v {
        GridValue::Text(t) if t.is_empty() => Err("empty value".into()),
        GridValue::Text(t) if t.contains([',', '\n', '\r']) => Err(format!("value '{t}' contains a comma or a line break")),
        GridValue::Text(t) => Ok(t.clone()),
        GridValue::Number(x) if !x.is_finite() => Err(format!("value {x} is not a finite number")),
        GridValue::Number(x) => {
            let int = schema::param(key).is_some_and(|p| p.kind == Kind::Int);
            Ok(if int && x.fract() == 0.0 && x.abs() < 9e15 { format!("{}", *x as i64) } else { format!("{x:e}") })
        }
    }
}

/// Plans and validates a grid over `template` (the scene with its `--set` overrides; the grid
/// values override those). Errors, before anything runs: no axis, a key given twice or not in
/// the schema, an empty axis, a value given twice, a value the scene rejects (the `--set`
/// message, naming key and value), a combination the scene rejects (naming the point; every
/// combination of a grid of up to [`VALIDATE_ALL`] points, else those of a shard in
/// [`GridPlan::check_shard`]), or a grid of more points than a `usize` counts. Nothing is
/// stored per point: planning 10^12 points takes the memory of the axes.
pub fn plan_grid(template: &SceneTemplate, axes: &[GridAxis]) -> Result<GridPlan, GridError> {
    let grid_err = |what: String, why: String| GridError::Grid { what, why };
    if axes.is_empty() {
        return Err(grid_err("grid".into(), "no axis: give at least one --grid KEY=V1,V2,…".into()));
    }
    let mut texts: Vec<(String, Vec<String>)> = Vec::new();
    let mut total: u64 = 1;
    for axis in axes {
        let key = axis.key.trim();
        let what = format!("--grid {key}");
        if texts.iter().any(|(k, _)| k == key) {
            return Err(grid_err(what, "key given twice; list all its values in one --grid".into()));
        }
        if !path_exists(key) {
            // The message of `--set` for an unknown key.
            let shown = axis.values.first().and_then(|v| value_text(key, v).ok()).unwrap_or_else(|| "0".into());
            let e = template.with_overrides(&[format!("{key}={shown}")]).err();
            return match e {
                Some(source) => Err(GridError::Scene { context: what, source }),
                None => Err(grid_err(what, "no such scene key".into())),
            };
        }
        if axis.values.is_empty() {
            return Err(grid_err(what, "no values".into()));
        }
        let mut vs = Vec::with_capacity(axis.values.len());
        let mut seen = std::collections::HashSet::with_capacity(axis.values.len());
        for v in &axis.values {
            let t = value_text(key, v).map_err(|why| grid_err(what.clone(), why))?;
            if !seen.insert(t.clone()) {
                return Err(grid_err(what, format!("value {t} given twice")));
            }
            vs.push(t);
        }
        let n = vs.len();
        let check: Vec<&String> = if n <= VALIDATE_ALL { vs.iter().collect() } else { vec![&vs[0], &vs[n - 1]] };
        for t in check {
            template
                .with_overrides(&[format!("{key}={t}")])
                .map_err(|source| GridError::Scene { context: format!("--grid {key}={t}"), source })?;
        }
        total = total.checked_mul(n as u64).ok_or_else(|| {
            grid_err("grid".into(), format!("more than {} points (2^64 − 1): the product of the axis lengths overflows", u64::MAX))
        })?;
        texts.push((key.to_string(), vs));
    }
    let total = usize::try_from(total).map_err(|_| grid_err("grid".into(), format!("{total} points: more than this machine counts")))?;
    let mut plan = GridPlan { axes: texts, template: template.clone(), total, orders: Vec::new(), fingerprint: String::new() };
    if total <= VALIDATE_ALL {
        for index in 0..total {
            plan.scene(index)?;
        }
    }
    // the largest modes.max_order of the grid: that of the template or of its own axis
    let max_order = match plan.axes.iter().find(|(k, _)| k == "modes.max_order") {
        Some((k, vs)) => vs
            .iter()
            .filter_map(|v| template.with_overrides(&[format!("{k}={v}")]).ok())
            .map(|t| t.scene().modes.max_order)
            .max()
            .unwrap_or(0),
        None => template.scene().modes.max_order,
    };
    plan.orders = (2..=max_order).step_by(2).collect();
    let base = serde_json::to_string(template.scene()).unwrap_or_default();
    let axes_text: Vec<String> = plan.axes.iter().map(|(k, vs)| format!("{k}={}", vs.join(","))).collect();
    plan.fingerprint = format!("magbubble sweep v1; grid {}; scene {base}", axes_text.join(" "));
    Ok(plan)
}
