//! magbubble — radial and non-spherical oscillations of a lipid-coated magnetic microbubble.
//!
//! The model is the self-consistent form of Krishna & Tamadapu, "Nonspherical oscillations of
//! an encapsulated magnetic microbubble", stated in full in `docs/model.md`. Where the paper
//! slips, the code follows docs/model.md; doc comments cite the paper's equation numbers and
//! the sections of docs/model.md (comments saying "FORMULATION §x" or "audit n" refer to §x and
//! audit item n there: the numbering is the same).
//!
//! The tree mirrors the concepts:
//! - [`coefficients`]: the Legendre-coupling tables generated at build time from `derivations/`.
//! - [`scene`]: what a researcher describes (TOML), raw and validated.
//! - [`field`]: coil and dipole fields → magnetic loads at time t.
//! - [`model`]: the equations (a [`integrate::OdeSystem`]), assembled with only the effects a scene asks for.
//! - [`integrate`]: the steppers (fixed RK4, adaptive explicit RK, implicit Radau).
//! - [`analysis`]: natural frequencies, Floquet, stability diagrams, convergence, accuracy.
//! - [`output`]: CSV / JSON writers (atomic), [`plot`]: figures.
//! - [`simd`]: the SIMD policy (CPU features probed once; `MAGBUBBLE_PORTABLE=1` forces the
//!   portable kernels).
//! - [`api`]: the typed library API (load a scene, run, modes, floquet, stability, sweep,
//!   accuracy, coefficients) that the command line ([`cli`]) and the Python binding both call.

#![deny(unsafe_op_in_unsafe_fn)]

pub mod analysis;
pub mod api;
pub mod coefficients;
pub mod drive;
pub mod echo;
pub mod field;
pub mod fit;
pub mod integrate;
pub mod model;
#[macro_use]
pub mod output;
pub mod population;
pub mod plot;
pub mod scene;
pub mod simd;
pub mod cli;
