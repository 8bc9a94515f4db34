//! Load, override and validate a scene: the one path from a file or TOML text (and
//! `key=value` overrides, as `--set` takes them) to a validated [`crate::scene::Scene`].

use crate::scene::{SceneError, SceneTemplate};
use std::path::Path;

/// A validated scene, with what it came from: the text of the file (or the TOML given), where
/// it came from, and the overrides applied since. Cheap to clone; every variant is validated.
#[derive(Debug, Clone)]
pub struct Scene {
    template: SceneTemplate,
    /// The scene file's text (or the TOML text given), before any override: part of the
    /// fingerprint of a resumable sweep, so a rerun on an edited file does not resume.
    text: String,
    overrides: Vec<String>,
}

impl Scene {
    /// Reads a scene file and validates it with `overrides` (`key=value`, as `--set`) in one
    /// validation: every problem (key, value, reason) in one error.
    pub fn load<S: AsRef<str>>(path: impl AsRef<Path>, overrides: &[S]) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read { path: path.to_path_buf(), source })?;
        Self::from_toml(&text, &path.display().to_string(), overrides)
    }

    /// A scene from TOML text; `origin` names it in error messages and summaries.
    pub fn from_toml<S: AsRef<str>>(text: &str, origin: &str, overrides: &[S]) -> Result<Scene, SceneError> {
        let template = SceneTemplate::from_str(text, origin, overrides)?;
        let overrides = overrides.iter().map(|o| o.as_ref().to_string()).collect();
        Ok(Scene { template, text: text.to_string(), overrides })
    }

    /// A new scene with more overrides, validated (the earlier overrides stay applied).
    pub fn with_overrides<S: AsRef<str>>(&self, overrides: &[S]) -> Result<Scene, SceneError> {
        let template = self.template.with_overrides(overrides)?;
        let mut all = self.overrides.clone();
        all.extend(overrides.iter().map(|o| o.as_ref().to_string()));
        Ok(Scene { template, text: self.text.clone(), overrides: all })
    }

    /// The validated parameters (defaults applied, SI units).
    pub fn scene(&self) -> &crate::scene::Scene {
        self.template.scene()
    }

    /// The TOML tree with the overrides applied, from which variants are derived.
    pub fn template(&self) -> &SceneTemplate {
        &self.template
    }

    /// The file the scene was read from, or the origin given to [`Scene::from_toml`].
    pub fn origin(&self) -> &str {
        self.template.origin()
    }

    /// The overrides applied since the file or text, as `key=value` strings.
    pub fn overrides(&self) -> &[String] {
        &self.overrides
    }

    /// The file's text (or the TOML text given), without the overrides.
    pub fn source_text(&self) -> &str {
        &self.text
    }

    /// The scene as TOML text, overrides applied ([`Scene::from_toml`] reads it back).
    pub fn to_toml(&self) -> Result<String, toml::ser::Error> {
        self.template.to_toml()
    }
}
