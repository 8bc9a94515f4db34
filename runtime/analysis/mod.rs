//! (to be written)

pub mod dispersion;
