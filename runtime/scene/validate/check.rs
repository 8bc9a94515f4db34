//! The checks of one key ([`Check`]): a value read with its schema default, its range and its
//! allowed choices, every problem collected as an [`Issue`] naming the key, the value and why.

use super::super::error::Issue;
use super::super::raw::RawModeMap;
use super::super::schema::{self, fmt_num, DefaultValue as D};
use std::collections::BTreeMap;

/// Collects issues while reading values with their schema defaults and ranges.
#[derive(Default)]
pub(super) struct Check {
    pub(super) issues: Vec<Issue>,
}

impl Check {
    pub(super) fn push(&mut self, key: &str, value: Option<String>, reason: impl Into<String>) {
        self.issues.push(Issue::new(key, value, reason));
    }

    pub(super) fn param(key: &str) -> &'static schema::Param {
        // A key missing from the schema is a bug in this file, caught by every test that loads a scene.
        schema::param(key)
            .unwrap_or_else(|| panic!("scene key `{key}` is missing from scene::schema::SCHEMA"))
    }

    /// Checks `x` against the range of `key`.
    pub(super) fn range(&mut self, key: &str, x: f64) {
        self.range_shown(key, x, fmt_num(x));
    }

    /// Checks `x` against the range of `key`, showing the value as `shown`.
    pub(super) fn range_shown(&mut self, key: &str, x: f64, shown: String) {
        let p = Self::param(key);
        if !p.range.admits(x) {
            self.push(key, Some(shown), format!("must be {}", p.range.describe()));
        }
    }

    /// A float with its schema default (`fallback` for `SameAs`/`Derived` defaults).
    pub(super) fn float_or(&mut self, key: &str, v: Option<f64>, fallback: f64) -> f64 {
        match v {
            Some(x) => {
                self.range(key, x);
                x
            }
            None => match Self::param(key).default {
                D::Float(d) => d,
                D::Required { .. } => {
                    let section = key.rsplit_once('.').map_or("", |(s, _)| s);
                    self.push(key, None, format!("required when [{section}] is present"));
                    f64::NAN
                }
                _ => fallback,
            },
        }
    }

    pub(super) fn float(&mut self, key: &str, v: Option<f64>) -> f64 {
        self.float_or(key, v, f64::NAN)
    }

    pub(super) fn int(&mut self, key: &str, v: Option<i64>) -> i64 {
        match v {
            Some(i) => {
                self.range_shown(key, i as f64, i.to_string());
                i
            }
            None => match Self::param(key).default {
                D::Int(d) => d,
                other => panic!("schema default of `{key}` is not an integer: {other:?}"),
            },
        }
    }

    pub(super) fn choice(&mut self, key: &str, v: Option<&str>) -> &'static str {
        let p = Self::param(key);
        let (schema::Kind::Choice(options), D::Str(default)) = (p.kind, p.default) else {
            panic!("schema key `{key}` is not a choice with a string default");
        };
        match v {
            None => default,
            Some(s) => match options.iter().find(|o| **o == s) {
                Some(o) => o,
                None => {
                    let list = options
                        .iter()
                        .map(|o| format!("\"{o}\""))
                        .collect::<Vec<_>>()
                        .join(", ");
                    self.push(
                        key,
                        Some(format!("\"{s}\"")),
                        format!("must be one of {list}"),
                    );
                    default
                }
            },
        }
    }

    pub(super) fn bool(&mut self, key: &str, v: Option<bool>) -> bool {
        v.unwrap_or(match Self::param(key).default {
            D::Bool(b) => b,
            other => panic!("schema default of `{key}` is not a bool: {other:?}"),
        })
    }

    /// A mode map `{ "2" = x }` → `{2: x}`: keys even, 2 ≤ k ≤ max_order, values finite.
    pub(super) fn modes(
        &mut self,
        key: &str,
        v: Option<RawModeMap>,
        max_order: usize,
    ) -> BTreeMap<usize, f64> {
        let mut out = BTreeMap::new();
        for (k, x) in v.unwrap_or_default() {
            let path = format!("{key}.{k}");
            let value = Some(fmt_num(x));
            match k.trim().parse::<usize>() {
                Err(_) => self.push(&path, value, "mode key must be an even integer k >= 2, e.g. { 2 = 1e-8 }"),
                Ok(0) => self.push(&path, value, "k = 0 is the radial mode: use bubble.initial.radius / velocity"),
                Ok(k) if k % 2 == 1 => self.push(
                    &path,
                    value,
                    format!("odd mode k = {k} not simulated (the model has the even modes k = 2, 4, ..., N only)"),
                ),
                Ok(k) if k > max_order => self.push(
                    &path,
                    value,
                    format!("a key for k = {k} > modes.max_order = {max_order} (raise modes.max_order or remove it)"),
                ),
                Ok(k) => {
                    if !x.is_finite() {
                        self.push(&path, value, "must be a finite number");
                    }
                    out.insert(k, x);
                }
            }
        }
        out
    }
}
