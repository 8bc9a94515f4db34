//! (to be written)

pub mod convergence;
pub mod dispersion;
