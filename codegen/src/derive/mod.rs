//! From specs to projected loads: the interpreter ([`eval`]), the magnetic loads ([`field`]),
//! the membrane loads ([`membrane`]), the Galerkin projection ([`project`]) and the closed-form
//! fits ([`fit`]).

pub mod eval;
pub mod field;
pub mod fit;
pub mod fit3;
pub mod jet2;
pub mod membrane;
pub mod project;
pub mod quadratic;
pub mod quadratic_membrane;
