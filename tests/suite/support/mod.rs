pub mod prony;
pub mod shell_energy;
pub mod quadrature;
pub mod quadrature_h4;
pub mod jacobian;
pub mod potential_flow;
pub mod rk4_ref;
pub mod membrane_loads;
