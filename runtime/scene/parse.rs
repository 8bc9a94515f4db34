//! Loading a scene: TOML text → `toml::Table` (syntax errors with line:column) → `--set`
//! overrides applied to the tree → a walk of the tree against the schema (unknown keys, wrong
//! types; offending entries are reported and removed so that validation can still report the
//! rest) → [`RawScene`] (serde) → [`Scene`] (`TryFrom`, ranges and cross-key rules).

use super::error::{Issue, Issues, SceneError};
use super::raw::RawScene;
use super::schema::{self, Kind};
use super::types::Scene;
use serde::Deserialize;
use std::path::Path;
use toml::{Table, Value};

/// Reads, overrides and validates a scene file: the entry point everybody uses.
///
/// `overrides` are `key.path=value` strings as given to `--set` (value: a TOML scalar or
/// inline table; a bare word is taken as a string).
pub fn load<S: AsRef<str>>(path: impl AsRef<Path>, overrides: &[S]) -> Result<Scene, SceneError> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    load_str(&text, &path.display().to_string(), overrides)
}

/// [`load`] from text; `origin` names the source in error messages.
pub fn load_str<S: AsRef<str>>(
    text: &str,
    origin: &str,
    overrides: &[S],
) -> Result<Scene, SceneError> {
    Ok(super::SceneTemplate::from_str(text, origin, overrides)?.into_scene())
}

/// Validates a scene tree (overrides already applied; `issues` found so far, e.g. by `--set`):
/// the schema walk, serde, then ranges and cross-key rules. The one path from a TOML tree to a
/// [`Scene`], used by [`load_str`] and by [`super::SceneTemplate`].
pub(crate) fn validate_table(
    mut table: Table,
    origin: &str,
    mut issues: Vec<Issue>,
) -> Result<Scene, SceneError> {
    resolve_paths(&mut table, origin);
    walk(&mut table, "", &mut issues);
    let raw = match RawScene::deserialize(Value::Table(table)) {
        Ok(raw) => Some(raw),
        Err(e) => {
            // The walk checks what serde checks; this is a safety net, not an expected path.
            issues.push(Issue::new("(scene)", None, e.message().to_string()));
            None
        }
    };
    if let Some(raw) = raw {
        match Scene::try_from(raw) {
            Ok(scene) if issues.is_empty() => return Ok(scene),
            Ok(_) => {}
            Err(Issues(more)) => {
                // A key removed by the walk (wrong type) would also show up as "required": keep one.
                for issue in more {
                    if !issues.iter().any(|i| {
                        i.key == issue.key || issue.key.starts_with(&format!("{}.", i.key))
                    }) {
                        issues.push(issue);
                    }
                }
            }
        }
    }
    Err(SceneError::Invalid {
        origin: origin.to_string(),
        issues: Issues(issues),
    })
}

/// A relative `drive.file`, `population.file` or `shell.tension_file` is read from the scene file's directory (when `origin` is a path
/// whose directory exists; otherwise from the working directory).
fn resolve_paths(table: &mut Table, origin: &str) {
    for (section, key) in [("drive", "file"), ("population", "file"), ("shell", "tension_file")] {
        let Some(Value::Table(t)) = table.get_mut(section) else { continue };
        let Some(Value::String(file)) = t.get_mut(key) else { continue };
        let rel = Path::new(file.as_str());
        if rel.is_relative() {
            if let Some(dir) = Path::new(origin).parent().filter(|d| !d.as_os_str().is_empty() && d.is_dir()) {
                *file = dir.join(rel).display().to_string();
            }
        }
    }
}

/// Parses TOML text into a table; a syntax error carries its 1-based line and column.
pub fn parse_toml(text: &str, origin: &str) -> Result<Table, SceneError> {
    text.parse::<Table>().map_err(|e| {
        let (line, column) = e.span().map_or((0, 0), |s| line_col(text, s.start));
        SceneError::Syntax {
            origin: origin.to_string(),
            line,
            column,
            message: e.message().trim().to_string(),
        }
    })
}

/// 1-based line and column (in characters) of byte offset `at`.
fn line_col(text: &str, at: usize) -> (usize, usize) {
    let mut at = at.min(text.len());
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// Whether a dotted path names something a scene may contain: a schema key, or a mode of a
/// mode map (`bubble.initial.a.2`).
pub fn path_exists(path: &str) -> bool {
    if schema::param(path).is_some() {
        return true;
    }
    match path.rsplit_once('.') {
        Some((parent, _)) => schema::param(parent).is_some_and(|p| p.kind == Kind::ModeMap),
        None => false,
    }
}

/// Applies one `key.path=value` override to the tree.
pub fn apply_override(table: &mut Table, spec: &str) -> Result<(), Issue> {
    let Some((path, text)) = spec.split_once('=') else {
        return Err(Issue::new(
            spec,
            None,
            "--set expects key.path=value, e.g. --set drive.amplitude=0.3",
        ));
    };
    let (path, text) = (path.trim(), text.trim());
    if !path_exists(path) {
        return Err(Issue::new(
            path,
            Some(text.to_string()),
            "--set: no such key in the scene schema (list them with `magbubble scene explain`)",
        ));
    }
    let value = parse_value(text).ok_or_else(|| {
        Issue::new(
            path,
            Some(text.to_string()),
            "--set: not a TOML value (a number, true/false, \"string\" or inline table { k = v })",
        )
    })?;
    set_path(table, path, value)
}

/// Puts `value` at the dotted `path` of the tree (creating the tables on the way); an error
/// when a parent on the way is a value, not a table (`field.coil.current.amplitude` on a static
/// `current = 100e3`).
pub(crate) fn set_path(table: &mut Table, path: &str, value: Value) -> Result<(), Issue> {
    let shown = value.to_string();
    let segments: Vec<&str> = path.split('.').collect();
    let (last, parents) = segments
        .split_last()
        .expect("split yields at least one segment");
    let mut node = table;
    for (i, seg) in parents.iter().enumerate() {
        let entry = node
            .entry(seg.to_string())
            .or_insert_with(|| Value::Table(Table::new()));
        node = match entry {
            Value::Table(t) => t,
            other => {
                return Err(Issue::new(
                    path,
                    Some(shown),
                    format!(
                        "--set: `{}` is a {} in the scene, not a table; set `{}` as a whole",
                        segments[..=i].join("."),
                        other.type_str(),
                        segments[..=i].join(".")
                    ),
                ))
            }
        };
    }
    node.insert(last.to_string(), value);
    Ok(())
}

/// A `--set` value: a TOML value, or a bare word taken as a string (`--set modes.viscous=vorticity`).
fn parse_value(text: &str) -> Option<Value> {
    if let Ok(mut t) = format!("v = {text}").parse::<Table>() {
        if t.len() == 1 {
            return t.remove("v");
        }
    }
    let bare = !text.is_empty()
        && text.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
        && text
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
    bare.then(|| Value::String(text.to_string()))
}

fn join(prefix: &str, key: &str) -> String {
    if prefix.is_empty() {
        key.to_string()
    } else {
        format!("{prefix}.{key}")
    }
}

/// Checks the keys and value types of `table` (at `prefix`) against the schema; removes and
/// reports unknown keys and wrongly typed values.
fn walk(table: &mut Table, prefix: &str, issues: &mut Vec<Issue>) {
    let keys: Vec<String> = table.keys().cloned().collect();
    for key in keys {
        let path = join(prefix, &key);
        let Some(param) = schema::param(&path) else {
            issues.push(unknown_key(prefix, &key, table.get(&key)));
            table.remove(&key);
            continue;
        };
        let value = table.get_mut(&key).expect("key taken from the table");
        let mut reported = false;
        let ok = match (param.kind, &mut *value) {
            (Kind::Section, Value::Table(t)) => {
                walk(t, &path, issues);
                true
            }
            (Kind::FloatOrTable, Value::Table(t)) => {
                walk(t, &path, issues);
                true
            }
            (Kind::Float | Kind::FloatOrTable, Value::Float(_) | Value::Integer(_)) => true,
            (Kind::Int, Value::Integer(_)) | (Kind::Bool, Value::Boolean(_)) => true,
            (Kind::Choice(_), Value::String(_)) | (Kind::Text, Value::String(_)) => true,
            (Kind::FloatList, Value::Array(a)) => {
                let bad = a.iter().find(|v| !matches!(v, Value::Float(_) | Value::Integer(_))).map(|v| v.to_string());
                if let Some(v) = &bad {
                    issues.push(Issue::new(path.clone(), Some(v.clone()), "expected an array of numbers"));
                    reported = true;
                }
                bad.is_none()
            }
            (Kind::TableList, Value::Array(a)) => {
                let mut ok = true;
                for v in a.iter_mut() {
                    match v {
                        Value::Table(t) => walk(t, &path, issues),
                        other => {
                            issues.push(Issue::new(path.clone(), Some(other.to_string()), "expected an array of inline tables"));
                            ok = false;
                            reported = true;
                        }
                    }
                }
                ok
            }
            (Kind::ModeMap, Value::Table(t)) => {
                let modes: Vec<String> = t.keys().cloned().collect();
                for k in modes {
                    if !matches!(t[&k], Value::Float(_) | Value::Integer(_)) {
                        issues.push(Issue::new(
                            format!("{path}.{k}"),
                            Some(t[&k].to_string()),
                            format!("expected a number, found {}", article(t[&k].type_str())),
                        ));
                        t.remove(&k);
                    }
                }
                true
            }
            _ => false,
        };
        if !ok && reported {
            table.remove(&key);
        } else if !ok {
            issues.push(Issue::new(
                path.clone(),
                Some(value.to_string()),
                format!(
                    "expected {}, found {}",
                    expected(param.kind),
                    article(value.type_str())
                ),
            ));
            table.remove(&key);
        }
    }
}

fn article(t: &str) -> String {
    match t {
        "integer" | "array" => format!("an {t}"),
        _ => format!("a {t}"),
    }
}

fn expected(kind: Kind) -> String {
    match kind {
        Kind::Section => "a table".into(),
        Kind::Float => "a number".into(),
        Kind::Int => "an integer".into(),
        Kind::Bool => "true or false".into(),
        Kind::Choice(options) => {
            format!(
                "a string, one of {}",
                options
                    .iter()
                    .map(|o| format!("\"{o}\""))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        }
        Kind::ModeMap => "a table of modes, e.g. { 2 = 1e-8 }".into(),
        Kind::FloatOrTable => "a number or an inline table".into(),
        Kind::Text => "a string".into(),
        Kind::FloatList => "an array of numbers".into(),
        Kind::TableList => "an array of inline tables".into(),
    }
}

fn unknown_key(prefix: &str, key: &str, value: Option<&Value>) -> Issue {
    let allowed: Vec<&str> = schema::children(prefix)
        .map(|p| schema::leaf_name(p.key))
        .collect();
    let mut reason = if prefix.is_empty() {
        format!("unknown section; a scene has [{}]", allowed.join("], ["))
    } else {
        format!("unknown key; [{prefix}] accepts {}", allowed.join(", "))
    };
    if let Some(best) = allowed
        .iter()
        .filter(|a| edit_distance(a, key) <= 2)
        .min_by_key(|a| edit_distance(a, key))
    {
        reason.push_str(&format!(" (did you mean `{best}`?)"));
    }
    let shown = value.filter(|v| !v.is_table()).map(|v| v.to_string());
    Issue::new(join(prefix, key), shown, reason)
}

/// Levenshtein distance (for "did you mean").
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != *cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}
