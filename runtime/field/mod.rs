//! Coil and dipole fields → magnetic loads at time t.
//! (to be written)

pub mod appendix;
pub mod quadrature;
