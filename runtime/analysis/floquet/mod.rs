//! Floquet theory for linear periodic systems x' = A(t) x, A(t + T) = A(t) (paper §4, eqs 4.1–4.2;
//! FORMULATION §4.6 and audit 14: stability is decided by the *moduli* of the multipliers).
//!
//! The monodromy X(T) (the fundamental matrix after one period, X(0) = I) is computed with the
//! fourth-order Magnus integrator
//!
//! ```text
//! Ω_n = h/2 (A₁ + A₂) + (√3 h²/12) [A₂, A₁],   A_{1,2} = A(t_n + (1/2 ∓ √3/6) h),
//! X_{n+1} = exp(Ω_n) X_n
//! ```
//!
//! (Blanes, Casas, Oteo & Ros, Phys. Rep. 470, 2009, eq. 4.10). The matrix exponential makes the
//! scheme exact for constant A and unconditionally stable on the stiff decaying directions of the
//! boundary-layer system (FORMULATION audit 12: τ_b ≈ 0.4 ns at k ≈ 32 against a 1 µs period),
//! which an explicit Runge–Kutta scheme would need thousands of steps per period to survive.
//! Blocks of the state that A(t) never couples (the shape modes without a field) are propagated
//! separately, which turns one n×n exponential into n/3 exponentials of 3×3 matrices.
//!
//! Not on the run loop ([`crate::integrate::run_loop`]): the state is the matrix X itself,
//! advanced by exp(Ω) on a fixed grid of `steps` per period (no error control, samples, budget
//! or events); the run loop's steppers integrate vector states of an `OdeSystem`.
//!
//! The pieces: [`magnus`] (the Magnus steps and the monodromy), [`spectrum`] (the multipliers
//! of a monodromy and the eigenvector of the largest).

use nalgebra::DMatrix;

mod magnus;
mod spectrum;
pub use magnus::monodromy;
pub(crate) use magnus::{break_times, check_period_and_steps, split_steps};
pub use spectrum::{eigenvalues, Monodromy, Spectrum};
pub(crate) use spectrum::eigenvector_weights;

/// A linear system x' = A(t) x whose matrix is periodic (the period is given to [`monodromy`]).
pub trait LinearPeriodic {
    /// Dimension n of x.
    fn dim(&self) -> usize;
    /// Writes A(t) into `a` (n × n, already sized; overwrite every entry).
    fn matrix(&self, t: f64, a: &mut DMatrix<f64>);
    /// The instants where A(t) jumps (a kinked law's branch switches along the orbit), as times
    /// reduced to [0, T) (t mod T); [`monodromy`] splits its steps there. Default: none.
    fn breaks(&self) -> Vec<f64> {
        Vec::new()
    }
    /// Groups of state indices that A(t) never couples, for every t (each index in exactly one
    /// group). Default: a single group holding the whole state.
    fn blocks(&self) -> Vec<Vec<usize>> {
        vec![(0..self.dim()).collect()]
    }
    /// Writes A(t) restricted to each block of `blocks` (as returned by
    /// [`blocks`](Self::blocks)) into `out` (one |b| × |b| matrix per block, already sized).
    /// Default: the dense [`matrix`](Self::matrix), restricted; a system whose blocks it can
    /// assemble directly overrides this (the shape modes without a field: O(M) instead of O(M²)).
    fn block_matrices(&self, t: f64, blocks: &[Vec<usize>], out: &mut [DMatrix<f64>]) {
        let n = self.dim();
        if blocks.len() == 1 && blocks[0].iter().enumerate().all(|(i, &j)| i == j) {
            return self.matrix(t, &mut out[0]);
        }
        let mut a = DMatrix::zeros(n, n);
        self.matrix(t, &mut a);
        for (idx, o) in blocks.iter().zip(out) {
            for (bj, &j) in idx.iter().enumerate() {
                for (bi, &i) in idx.iter().enumerate() {
                    o[(bi, bj)] = a[(i, j)];
                }
            }
        }
    }
}

/// Errors of the Floquet computation. They carry the numbers that went wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FloquetError {
    #[error("the period must be finite and > 0 (got {period})")]
    BadPeriod { period: f64 },
    #[error("at least one Magnus step per period is needed (got {steps})")]
    NoSteps { steps: usize },
    #[error("A(t) has a non-finite entry at t = {t} (row {row}, column {col})")]
    NonFiniteMatrix { t: f64, row: usize, col: usize },
    #[error("the monodromy matrix overflowed or became NaN (block {block}): the system grows faster than f64 can hold")]
    NonFiniteMonodromy { block: usize },
    #[error("singular stage matrix σI − A(t) at t = {t} in the implicit monodromy")]
    SingularStage { t: f64 },
    #[error("the blocks returned by LinearPeriodic::blocks do not partition 0..{dim}")]
    BadBlocks { dim: usize },
}
