//! Scene errors: what is wrong, where (key path or line:column), with which value, and why.

use std::fmt;
use std::path::PathBuf;

/// One problem in a scene: the key path (`shell.c1`), the offending value as written (if any)
/// and what is allowed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Issue {
    /// Dotted key path, e.g. `shell.c1` or `bubble.initial.a.3`.
    pub key: String,
    /// The value as written (TOML), when there is one.
    pub value: Option<String>,
    /// Why it is rejected and what is allowed, e.g. "must be > 0".
    pub reason: String,
}

impl Issue {
    pub fn new(key: impl Into<String>, value: Option<String>, reason: impl Into<String>) -> Self {
        Issue {
            key: key.into(),
            value,
            reason: reason.into(),
        }
    }
}

impl fmt::Display for Issue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.value {
            Some(v) => write!(f, "`{}` = {}: {}", self.key, v, self.reason),
            None => write!(f, "`{}`: {}", self.key, self.reason),
        }
    }
}

/// Every problem found in a scene (validation never stops at the first one).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Issues(pub Vec<Issue>);

impl fmt::Display for Issues {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, issue) in self.0.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "  - {issue}")?;
        }
        Ok(())
    }
}

impl std::error::Error for Issues {}

/// Why a scene could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("cannot read scene file {path}: {source}")]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The file is not valid TOML; `line` and `column` are 1-based.
    #[error("{origin}:{line}:{column}: TOML syntax error: {message}")]
    Syntax {
        origin: String,
        line: usize,
        column: usize,
        message: String,
    },
    /// The TOML is well formed but the scene is not valid (all problems listed).
    #[error("{origin}: invalid scene, {} problem{}:\n{issues}", issues.0.len(), if issues.0.len() == 1 { "" } else { "s" })]
    Invalid { origin: String, issues: Issues },
}

impl SceneError {
    /// The list of problems (empty for read and syntax errors).
    pub fn issues(&self) -> &[Issue] {
        match self {
            SceneError::Invalid { issues, .. } => &issues.0,
            _ => &[],
        }
    }
}
