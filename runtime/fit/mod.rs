//! `fit`: the model's parameters from measured R(t) and shape amplitudes a_k(t) (issue 32;
//! docs/model.md, "Fitting"). Levenberg–Marquardt ([`lm`]) on weighted residuals
//! ([`residuals`]) whose Jacobian comes from forward sensitivities along the trajectory
//! ([`sensitivities`]: ∂f/∂p of the model; integrated with the state by
//! [`crate::integrate::sensitivity`]; sampled at the data's times by [`solve`]); the data
//! ([`data`]) and the parameters with their bounds ([`params`]) are read and checked first;
//! [`driver::fit`] runs it all and reports. [`spectrum`] fits an attenuation spectrum of a
//! suspension through the linear response instead (`fit --attenuation`).

pub mod data;
pub mod driver;
pub mod lm;
pub mod params;
pub mod residuals;
pub mod sensitivities;
pub mod solve;
pub mod spectrum;

pub use data::Data;
pub use driver::{fit, FitReport, Settings};
pub use params::ParamSpec;
