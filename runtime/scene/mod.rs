//! Scenes: what a researcher describes. `raw` holds the serde structs as written in TOML;
//! `types` the validated [`Scene`] (every default resolved, SI units).

mod types;
pub use types::*;
