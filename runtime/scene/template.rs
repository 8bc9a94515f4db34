//! One validated in-memory override of a scene: the TOML tree of a scene file (with its `--set`
//! overrides), from which variants are derived by setting keys and validating again through
//! the schema — the one path used by `--set`, stability sweeps and figures. Nothing sets a
//! field of a [`Scene`] behind the validator's back, and the file is read once.

use super::error::{Issue, Issues, SceneError};
use super::parse::{apply_override, parse_toml, set_path, validate_table};
use super::schema::{self, Kind};
use super::types::Scene;
use std::path::Path;
use toml::{Table, Value};

/// A validated scene and the tree it came from.
#[derive(Debug, Clone)]
pub struct SceneTemplate {
    table: Table,
    origin: String,
    scene: Scene,
}

impl SceneTemplate {
    /// Reads and validates a scene file with `--set` overrides (as [`super::load`]).
    pub fn load<S: AsRef<str>>(path: impl AsRef<Path>, overrides: &[S]) -> Result<Self, SceneError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_str(&text, &path.display().to_string(), overrides)
    }

    /// [`SceneTemplate::load`] from text.
    pub fn from_str<S: AsRef<str>>(text: &str, origin: &str, overrides: &[S]) -> Result<Self, SceneError> {
        let table = parse_toml(text, origin)?;
        Self::build(table, origin.to_string(), overrides)
    }

    fn build<S: AsRef<str>>(mut table: Table, origin: String, overrides: &[S]) -> Result<Self, SceneError> {
        let mut issues = Vec::new();
        for o in overrides {
            if let Err(issue) = apply_override(&mut table, o.as_ref()) {
                issues.push(issue);
            }
        }
        let scene = validate_table(table.clone(), &origin, issues)?;
        Ok(SceneTemplate { table, origin, scene })
    }

    /// The validated scene.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Where the scene came from (its file path, or the name given to [`SceneTemplate::from_str`]).
    pub fn origin(&self) -> &str {
        &self.origin
    }

    /// The scene's TOML tree, overrides applied, as TOML text (reads back to the same scene).
    pub fn to_toml(&self) -> Result<String, toml::ser::Error> {
        toml::to_string(&self.table)
    }

    /// The number written at a dotted key (overrides applied); `None` when the scene does not
    /// give it (its default applies) or it is not a number.
    pub fn given_number(&self, key: &str) -> Option<f64> {
        let (path, leaf) = key.rsplit_once('.').unwrap_or(("", key));
        let mut t = &self.table;
        for part in path.split('.').filter(|p| !p.is_empty()) {
            t = t.get(part)?.as_table()?;
        }
        match t.get(leaf)? {
            Value::Float(f) => Some(*f),
            Value::Integer(i) => Some(*i as f64),
            _ => None,
        }
    }

    /// The validated scene, by value.
    pub fn into_scene(self) -> Scene {
        self.scene
    }

    /// A new template with more `key=value` overrides (as `--set` takes them), validated.
    pub fn with_overrides<S: AsRef<str>>(&self, overrides: &[S]) -> Result<Self, SceneError> {
        Self::build(self.table.clone(), self.origin.clone(), overrides)
    }

    /// The scene with numeric keys set (`drive.frequency_hz`, `field.coil.current.amplitude`,
    /// `modes.max_order` …), validated like a scene file.
    pub fn with(&self, values: &[(&str, f64)]) -> Result<Scene, SceneError> {
        let mut table = self.table.clone();
        let mut issues = Vec::new();
        for &(key, v) in values {
            let set = numeric_param(key)
                .and_then(|p| set_path(&mut table, key, number(p.kind, v)).map_err(|i| i.reason));
            if let Err(reason) = set {
                issues.push(Issue::new(key, Some(format!("{v:e}")), reason));
            }
        }
        if issues.is_empty() {
            validate_table(table, &self.origin, issues)
        } else {
            Err(SceneError::Invalid { origin: self.origin.clone(), issues: Issues(issues) })
        }
    }
}

/// A TOML number for a key of this kind (an integral value of an `Int` key as an integer).
fn number(kind: Kind, v: f64) -> Value {
    if kind == Kind::Int && v.fract() == 0.0 && v.abs() < 9e15 {
        Value::Integer(v as i64)
    } else {
        Value::Float(v)
    }
}

/// The schema entry of a key that takes a number (what `stability --vary`/`--freq-key` and
/// `--family` may sweep); the error says why not.
pub fn numeric_param(key: &str) -> Result<&'static schema::Param, String> {
    match schema::param(key) {
        Some(p) if matches!(p.kind, Kind::Float | Kind::Int) => Ok(p),
        Some(p) if p.kind == Kind::FloatOrTable => Err(format!(
            "`{key}` is a number or a table; sweep one of its keys ({})",
            schema::children(key).map(|c| c.key).collect::<Vec<_>>().join(", ")
        )),
        Some(_) => Err(format!("`{key}` is not a number in the scene schema")),
        None => Err(format!(
            "no scene key `{key}` (list them with `magbubble scene explain`)"
        )),
    }
}
