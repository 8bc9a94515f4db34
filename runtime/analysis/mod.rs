//! Analyses built on the model: natural frequencies, Floquet stability, periodic orbits,
//! stability diagrams and the sweeps that scale them (issue 5), plus convergence and comparison
//! studies (issue 6).
//!
//! The generic numerical pieces ([`floquet`], [`periodic`], [`bisect`], [`sweep`]) know nothing
//! about bubbles and are tested on textbook problems (Mathieu, Duffing); [`frequencies`] and
//! [`stability`] apply them to the model.

pub mod bisect;
pub mod critical;
pub mod critical_accuracy;
pub mod cutoff;
pub mod expm;
pub mod floquet;
pub mod floquet_full;
pub mod frequencies;
pub mod grid;
pub mod ladder;
pub mod periodic;
pub mod response;
pub mod shooting;
pub mod stability;
pub mod sweep;

pub mod accuracy;
pub mod compare;
pub mod convergence;
/// The exact dispersion relation lives with the model it linearises (layering: model never
/// imports analysis); re-exported here for the analyses and tests that use it.
pub use crate::model::dispersion;
