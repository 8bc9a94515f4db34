//! Scenes: what a researcher describes.
//!
//! - [`raw`]: the serde structs exactly as written in TOML (unknown keys rejected);
//! - [`schema`]: ONE table of every key (unit, default, range, paper symbol, description), used by
//!   validation, `--set`, `scene new|explain` and `docs/scenes.md`;
//! - `validate`: `TryFrom<RawScene> for Scene`, collecting every problem;
//! - [`types`]: the validated [`Scene`] (every default resolved, SI units), the contract with the model.
//!
//! Entry point: [`load`]`(path, overrides)`; variants of one scene (sweeps, figures):
//! [`SceneTemplate`].

mod derived;
mod drive;
pub mod doc;
mod error;
mod parse;
pub mod raw;
pub mod schema;
mod template;
mod types;
mod validate;

pub use error::{Issue, Issues, SceneError};
pub use parse::{apply_override, load, load_str, parse_toml, path_exists};
pub use derived::{human_bytes, output_estimate};
pub use template::{numeric_param, SceneTemplate};
pub use types::*;
