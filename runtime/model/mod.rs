//! (to be written)

pub mod vorticity;
