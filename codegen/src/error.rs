//! The codegen error type.

use thiserror::Error;

#[derive(Debug, Error)]
pub enum CodegenError {
    /// A malformed or unsupported spec, or a derivation step that fails at a spec location.
    #[error("{path}:{line}:{column}: {message}")]
    Spec { path: String, line: usize, column: usize, message: String },
    /// A spec file could not be read.
    #[error("cannot read {path}: {source}")]
    Io { path: String, source: std::io::Error },
    /// The derived loads do not have the structure the tables need.
    #[error("{spec}: {message}")]
    Structure { spec: String, message: String },
    /// The generated code did not parse (a codegen bug).
    #[error("generated code does not parse: {0}")]
    Emit(String),
}
