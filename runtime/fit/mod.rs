//! `fit`: the model's parameters from measured R(t) and shape amplitudes a_k(t) (issue 32;
//! docs/model.md, "Fitting"). Levenberg–Marquardt on weighted residuals whose Jacobian comes
//! from forward sensitivities along the trajectory ([`sensitivities`], integrated with the
//! state by [`crate::integrate::sensitivity`]); the data ([`data`]), the parameters and their
//! bounds ([`params`]), the residuals ([`residuals`]) and the optimiser ([`lm`]) are separate.

pub mod sensitivities;
pub mod solve;
