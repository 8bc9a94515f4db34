//! The fitted parameters: `--param KEY[=LOW:HIGH]`, any numeric scene key or the nuisance
//! `time_offset` [s] (the camera's t = 0 is not the drive's: the model is compared at
//! t_data + time_offset). Start values are the scene's (overrides applied); a strictly positive
//! key (schema range > 0) is fitted in log, so its steps are relative and it stays positive.

use crate::scene::schema::{self, DefaultValue, Range};
use crate::scene::SceneTemplate;
use anyhow::{bail, Context};

/// The nuisance parameter's key.
pub const TIME_OFFSET: &str = "time_offset";

/// `KEY[=LOW:HIGH]` as given.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamSpec {
    pub key: String,
    pub low: Option<f64>,
    pub high: Option<f64>,
}

impl std::str::FromStr for ParamSpec {
    type Err = anyhow::Error;
    fn from_str(s: &str) -> anyhow::Result<ParamSpec> {
        let (key, bounds) = match s.split_once('=') {
            Some((k, b)) => (k.trim(), Some(b.trim())),
            None => (s.trim(), None),
        };
        if key.is_empty() {
            bail!("--param {s}: no key (expected KEY or KEY=LOW:HIGH)");
        }
        let (low, high) = match bounds {
            None => (None, None),
            Some(b) => {
                let (lo, hi) = b.split_once(':').with_context(|| format!("--param {s}: bounds `{b}` are not LOW:HIGH"))?;
                let num = |x: &str, which: &str| -> anyhow::Result<Option<f64>> {
                    if x.trim().is_empty() {
                        return Ok(None);
                    }
                    let v: f64 = x.trim().parse().map_err(|_| anyhow::anyhow!("--param {s}: {which} bound `{x}` is not a number"))?;
                    anyhow::ensure!(v.is_finite(), "--param {s}: {which} bound {x} is not finite");
                    Ok(Some(v))
                };
                (num(lo, "lower")?, num(hi, "upper")?)
            }
        };
        if let (Some(l), Some(h)) = (low, high) {
            anyhow::ensure!(l < h, "--param {s}: reversed or empty bounds ({l} is not below {h})");
        }
        Ok(ParamSpec { key: key.to_string(), low, high })
    }
}

/// A fitted parameter, resolved against the scene and the data.
#[derive(Debug, Clone)]
pub struct Param {
    pub key: String,
    pub start: f64,
    /// Bounds in the parameter's own units (±∞ when open).
    pub low: f64,
    pub high: f64,
    /// Fitted as ln p.
    pub log: bool,
    /// The unit of the fit's coordinate of a linear parameter: u = p/unit.
    pub unit: f64,
}

impl Param {
    pub fn is_time_offset(&self) -> bool {
        self.key == TIME_OFFSET
    }
    /// p → the optimiser's coordinate u.
    pub fn to_u(&self, p: f64) -> f64 {
        if self.log { p.ln() } else { p / self.unit }
    }
    /// u → p.
    pub fn from_u(&self, u: f64) -> f64 {
        if self.log { u.exp() } else { u * self.unit }
    }
    /// dp/du at p.
    pub fn dp_du(&self, p: f64) -> f64 {
        if self.log { p } else { self.unit }
    }
}

/// The scene's value of a numeric key (overrides applied; the schema's default when absent).
pub fn scene_value(template: &SceneTemplate, key: &str) -> anyhow::Result<f64> {
    let table: toml::Table = template.to_toml().context("the scene as TOML")?.parse().context("the scene as TOML")?;
    let mut node = Some(&toml::Value::Table(table));
    for part in key.split('.') {
        node = node.and_then(|n| n.as_table()).and_then(|t| t.get(part));
    }
    match node {
        Some(toml::Value::Float(v)) => Ok(*v),
        Some(toml::Value::Integer(v)) => Ok(*v as f64),
        Some(other) => bail!("--param {key}: the scene's value `{other}` is not a number"),
        None => match schema::param(key).map(|p| p.default) {
            Some(DefaultValue::Float(v)) => Ok(v),
            Some(DefaultValue::Int(v)) => Ok(v as f64),
            Some(DefaultValue::SameAs(other)) => scene_value(template, other),
            _ => bail!("--param {key}: the scene gives no value and the key has no numeric default (set one with --set {key}=VALUE)"),
        },
    }
}

/// Resolves the specs: known numeric keys, each once, bounds in order and around the start;
/// `window` is the time offsets that keep the data inside the run, [−t_first, duration − t_last].
pub fn resolve(template: &SceneTemplate, specs: &[ParamSpec], window: (f64, f64)) -> anyhow::Result<Vec<Param>> {
    anyhow::ensure!(!specs.is_empty(), "no --param given: name at least one scene key to fit");
    let mut out: Vec<Param> = Vec::new();
    for spec in specs {
        let key = spec.key.as_str();
        if out.iter().any(|p| p.key == key) {
            bail!("--param {key} is given twice");
        }
        let (start, mut low, mut high, log) = if key == TIME_OFFSET {
            (0.0, window.0, window.1, false)
        } else {
            let p = crate::scene::numeric_param(key).map_err(|e| anyhow::anyhow!("--param {key}: {e}"))?;
            if p.kind == schema::Kind::Int {
                bail!("--param {key}: an integer key cannot be fitted");
            }
            let start = scene_value(template, key)?;
            let (lo, hi) = match p.range {
                Range::Positive => (0.0, f64::INFINITY),
                Range::NonNegative => (0.0, f64::INFINITY),
                Range::Between { lo, hi, .. } => (lo, hi),
                _ => (f64::NEG_INFINITY, f64::INFINITY),
            };
            (start, lo, hi, p.range == Range::Positive)
        };
        let range = (low, high);
        if let Some(l) = spec.low {
            anyhow::ensure!(l >= range.0, "--param {key}: lower bound {l} is outside the key's range (≥ {})", range.0);
            low = l;
        }
        if let Some(h) = spec.high {
            anyhow::ensure!(h <= range.1, "--param {key}: upper bound {h} is outside the key's range (≤ {})", range.1);
            high = h;
        }
        anyhow::ensure!(low < high, "--param {key}: reversed or empty bounds ({low} is not below {high})");
        // the time offset starts at 0 or the nearest bound
        let start = if key == TIME_OFFSET { start.clamp(low, high) } else { start };
        anyhow::ensure!(
            start >= low && start <= high,
            "--param {key}: the start value {start} (the scene's) is outside the bounds [{low}, {high}]"
        );
        let log = log || (low > 0.0 && start > 0.0);
        let unit = if key == TIME_OFFSET { (window.1 - window.0).abs().max(1e-30) * 1e-3 } else { super::sensitivities::scale_of(start) };
        out.push(Param { key: key.to_string(), start, low, high, log, unit });
    }
    Ok(out)
}
