//! (to be written)

pub mod compare;
pub mod convergence;
pub mod dispersion;
