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

use nalgebra::allocator::Allocator;
use nalgebra::{Complex, DMatrix, DVector, DefaultAllocator, OMatrix, SMatrix};

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

/// The monodromy of a [`LinearPeriodic`] system, kept per block.
#[derive(Debug, Clone)]
pub struct Monodromy {
    pub dim: usize,
    /// The state indices of each block (as returned by [`LinearPeriodic::blocks`]).
    pub blocks: Vec<Vec<usize>>,
    /// X(T) restricted to each block.
    pub matrices: Vec<DMatrix<f64>>,
}

impl Monodromy {
    /// The full n × n monodromy matrix (zero between blocks).
    pub fn full(&self) -> DMatrix<f64> {
        let mut x = DMatrix::zeros(self.dim, self.dim);
        for (idx, m) in self.blocks.iter().zip(&self.matrices) {
            for (bi, &i) in idx.iter().enumerate() {
                for (bj, &j) in idx.iter().enumerate() {
                    x[(i, j)] = m[(bi, bj)];
                }
            }
        }
        x
    }

    /// Trace of X(T).
    pub fn trace(&self) -> f64 {
        self.matrices.iter().map(|m| m.trace()).sum()
    }

    /// The Floquet multipliers (eigenvalues of X(T)) and which one has the largest modulus.
    pub fn spectrum(&self) -> Spectrum {
        let mut multipliers = Vec::with_capacity(self.dim);
        let mut owner = Vec::with_capacity(self.dim);
        for (b, m) in self.matrices.iter().enumerate() {
            for mu in eigenvalues(m) {
                multipliers.push(mu);
                owner.push(b);
            }
        }
        let (imax, max_modulus) = multipliers
            .iter()
            .enumerate()
            .map(|(i, mu)| (i, mu.norm()))
            .fold((0, f64::NEG_INFINITY), |acc, x| if x.1 > acc.1 { x } else { acc });
        let block = owner.get(imax).copied().unwrap_or(0);
        // Which state component carries the critical multiplier: inverse iteration on its block.
        let weights = multipliers
            .get(imax)
            .map(|&mu| eigenvector_weights(&self.matrices[block], mu))
            .unwrap_or_default();
        let components: Vec<(usize, f64)> =
            self.blocks[block].iter().copied().zip(weights.iter().copied()).collect();
        Spectrum { multipliers, max_modulus, block, components }
    }
}

/// Floquet multipliers of a monodromy.
#[derive(Debug, Clone)]
pub struct Spectrum {
    /// All multipliers μ_i, block after block.
    pub multipliers: Vec<Complex<f64>>,
    /// max_i |μ_i| (paper: "maximum eigenvalue"; audit 14: the modulus decides).
    pub max_modulus: f64,
    /// Index of the block holding the largest multiplier.
    pub block: usize,
    /// (state index, |v_i|²/‖v‖²) of the eigenvector of the largest multiplier, within its block.
    pub components: Vec<(usize, f64)>,
}

/// Eigenvalues of a general real square matrix (real Schur form). A matrix with a non-finite
/// entry, or one whose QR iteration does not converge in a bounded number of sweeps, gives
/// NaN eigenvalues (the callers report NaN as a status): nalgebra's unbounded
/// `complex_eigenvalues` never returns on such a matrix.
pub fn eigenvalues(m: &DMatrix<f64>) -> Vec<Complex<f64>> {
    let n = m.nrows();
    let nan = || vec![Complex::new(f64::NAN, f64::NAN); n];
    if m.iter().any(|v| !v.is_finite()) {
        return nan();
    }
    match n {
        0 => Vec::new(),
        1 => vec![Complex::new(m[(0, 0)], 0.0)],
        _ => match nalgebra::linalg::Schur::try_new(m.clone(), f64::EPSILON, SCHUR_SWEEPS * n) {
            Some(schur) => schur.complex_eigenvalues().iter().copied().collect(),
            None => nan(),
        },
    }
}

/// QR sweeps per row allowed to the real Schur form (LAPACK's dhseqr allows 30 per
/// eigenvalue; a converging iteration needs 2–4).
const SCHUR_SWEEPS: usize = 30;

/// Normalised |v_i|² of the eigenvector of `m` for the eigenvalue `mu`, by two steps of
/// inverse iteration with a slightly perturbed shift (complex arithmetic).
pub(crate) fn eigenvector_weights(m: &DMatrix<f64>, mu: Complex<f64>) -> Vec<f64> {
    let n = m.nrows();
    if n == 0 {
        return Vec::new();
    }
    let scale = m.norm().max(f64::MIN_POSITIVE);
    let shift = mu + Complex::new(1e-10 * scale, 1e-10 * scale);
    let mut c: DMatrix<Complex<f64>> = m.map(|v| Complex::new(v, 0.0));
    for i in 0..n {
        c[(i, i)] -= shift;
    }
    let lu = c.lu();
    let mut v = DVector::from_element(n, Complex::new(1.0, 0.0));
    for _ in 0..3 {
        match lu.solve(&v) {
            Some(w) => {
                let norm = w.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt();
                if !(norm.is_finite() && norm > 0.0) {
                    break;
                }
                v = w / Complex::new(norm, 0.0);
            }
            None => break, // exact eigenvalue hit: v is already the best we have
        }
    }
    let total: f64 = v.iter().map(|z| z.norm_sqr()).sum();
    v.iter().map(|z| z.norm_sqr() / total).collect()
}

fn check_blocks(dim: usize, blocks: &[Vec<usize>]) -> Result<(), FloquetError> {
    let mut seen = vec![false; dim];
    for &i in blocks.iter().flatten() {
        if i >= dim || seen[i] {
            return Err(FloquetError::BadBlocks { dim });
        }
        seen[i] = true;
    }
    if seen.iter().all(|&s| s) {
        Ok(())
    } else {
        Err(FloquetError::BadBlocks { dim })
    }
}

/// A monodromy's period must be positive and finite and its step count positive.
pub(crate) fn check_period_and_steps(period: f64, steps: usize) -> Result<(), FloquetError> {
    if !(period.is_finite() && period > 0.0) {
        return Err(FloquetError::BadPeriod { period });
    }
    if steps == 0 {
        return Err(FloquetError::NoSteps { steps });
    }
    Ok(())
}

/// Monodromy X(t0 + T) of x' = A(t) x, X(t0) = I, with `steps` fourth-order Magnus steps.
///
/// The error is O(h⁴) in the smooth parts of A(t); the result is exact for constant A. A step
/// holding one of the system's [`LinearPeriodic::breaks`] is taken as two (or more) Magnus steps
/// split there, so no step straddles a jump of A (issue 31: the Gauss nodes of a straddling step
/// sample both sides, and the order falls to 1 there).
pub fn monodromy(
    sys: &dyn LinearPeriodic,
    t0: f64,
    period: f64,
    steps: usize,
) -> Result<Monodromy, FloquetError> {
    check_period_and_steps(period, steps)?;
    let n = sys.dim();
    let blocks = sys.blocks();
    check_blocks(n, &blocks)?;
    let mut x: Vec<DMatrix<f64>> =
        blocks.iter().map(|b| DMatrix::identity(b.len(), b.len())).collect();
    let c = 3f64.sqrt() / 6.0;
    let mut a1: Vec<DMatrix<f64>> = blocks.iter().map(|b| DMatrix::zeros(b.len(), b.len())).collect();
    let mut a2 = a1.clone();
    let mut dense: Vec<Option<DenseStep>> = blocks.iter().map(|b| (b.len() > 3).then(|| DenseStep::new(b.len()))).collect();
    let mut step = |t: f64, h: f64| -> Result<(), FloquetError> {
        let (ta, tb) = (t + (0.5 - c) * h, t + (0.5 + c) * h);
        sys.block_matrices(ta, &blocks, &mut a1);
        check_finite(&a1, &blocks, ta)?;
        sys.block_matrices(tb, &blocks, &mut a2);
        check_finite(&a2, &blocks, tb)?;
        for b in 0..blocks.len() {
            match &mut dense[b] {
                Some(w) => w.step(&a1[b], &a2[b], h, &mut x[b]),
                None => step_block(&a1[b], &a2[b], h, &mut x[b]),
            }
        }
        Ok(())
    };
    split_steps(t0, period, steps, &break_times(&sys.breaks(), t0, period), &mut step)?;
    for (b, m) in x.iter().enumerate() {
        if m.iter().any(|v| !v.is_finite()) {
            return Err(FloquetError::NonFiniteMonodromy { block: b });
        }
    }
    Ok(Monodromy { dim: n, blocks, matrices: x })
}

/// Break times ([`LinearPeriodic::breaks`], reduced mod `period`) as times in (t0, t0 + period),
/// sorted.
pub(crate) fn break_times(breaks: &[f64], t0: f64, period: f64) -> Vec<f64> {
    let mut b: Vec<f64> = breaks.iter().map(|&tb| t0 + (tb - t0).rem_euclid(period)).filter(|&tb| tb > t0).collect();
    b.sort_by(f64::total_cmp);
    b
}

/// The `steps` uniform steps (t, h) from t0 over `period`, each one holding break times (sorted,
/// from [`break_times`]) taken in parts between them; `step(t, h)` for each. Without breaks
/// the steps are t0 + s·h, h = period/steps, exactly.
pub(crate) fn split_steps<E>(
    t0: f64,
    period: f64,
    steps: usize,
    breaks: &[f64],
    step: &mut dyn FnMut(f64, f64) -> Result<(), E>,
) -> Result<(), E> {
    let h = period / steps as f64;
    let mut next = 0;
    for s in 0..steps {
        let t = t0 + s as f64 * h;
        // the breaks inside (t, t + h): the step in parts between them
        let mut ta = t;
        while next < breaks.len() && breaks[next] < t + h {
            if breaks[next] > ta {
                step(ta, breaks[next] - ta)?;
                ta = breaks[next];
            }
            next += 1;
        }
        if ta == t {
            step(t, h)?;
        } else {
            step(ta, t + h - ta)?;
        }
    }
    Ok(())
}

/// Whether every entry is finite: x − x is 0 for a finite x and NaN otherwise, summed in eight
/// independent lanes (vectorised; no early exit needed on the common, finite path).
fn all_finite(s: &[f64]) -> bool {
    let mut acc = [0.0f64; 8];
    let mut chunks = s.chunks_exact(8);
    for c in &mut chunks {
        for (a, x) in acc.iter_mut().zip(c) {
            *a += x - x;
        }
    }
    acc.iter().sum::<f64>() == 0.0 && chunks.remainder().iter().all(|x| x.is_finite())
}

fn check_finite(a: &[DMatrix<f64>], blocks: &[Vec<usize>], t: f64) -> Result<(), FloquetError> {
    if a.iter().all(|m| all_finite(m.as_slice())) {
        return Ok(());
    }
    for (m, idx) in a.iter().zip(blocks) {
        if let Some(p) = m.iter().position(|v| !v.is_finite()) {
            return Err(FloquetError::NonFiniteMatrix { t, row: idx[p % m.nrows()], col: idx[p / m.nrows()] });
        }
    }
    Ok(())
}

/// One Magnus step of a block of 1, 2 or 3 states (the shape modes without a field): X ←
/// exp(Ω) X, Ω from the block's A at the two Gauss nodes, on stack-allocated matrices.
fn step_block(a1: &DMatrix<f64>, a2: &DMatrix<f64>, h: f64, x: &mut DMatrix<f64>) {
    match a1.nrows() {
        1 => step_fixed::<1>(a1, a2, h, x),
        2 => step_fixed::<2>(a1, a2, h, x),
        _ => step_fixed::<3>(a1, a2, h, x),
    }
}

/// Ω = h/2 (A₁ + A₂) + (√3 h²/12) [A₂, A₁] (module doc) into `omega`; `pq`, `qp` are buffers.
fn magnus_omega<D: nalgebra::Dim>(
    p: &OMatrix<f64, D, D>,
    q: &OMatrix<f64, D, D>,
    h: f64,
    [pq, qp]: [&mut OMatrix<f64, D, D>; 2],
    omega: &mut OMatrix<f64, D, D>,
) where
    DefaultAllocator: Allocator<D, D>,
{
    let k = 3f64.sqrt() * h * h / 12.0;
    let mul = super::matmul::product();
    super::matmul::square(mul, pq, p, q);
    super::matmul::square(mul, qp, q, p);
    let pairs = p.as_slice().iter().zip(q.as_slice()).zip(qp.as_slice().iter().zip(pq.as_slice()));
    for (o, ((a, b), (c, d))) in omega.as_mut_slice().iter_mut().zip(pairs) {
        *o = (a + b) * (0.5 * h) + (c - d) * k;
    }
}

fn step_fixed<const N: usize>(a1: &DMatrix<f64>, a2: &DMatrix<f64>, h: f64, x: &mut DMatrix<f64>) {
    let p = SMatrix::<f64, N, N>::from_column_slice(a1.as_slice());
    let q = SMatrix::<f64, N, N>::from_column_slice(a2.as_slice());
    let (mut pq, mut qp, mut omega) = (SMatrix::<f64, N, N>::zeros(), SMatrix::zeros(), SMatrix::zeros());
    magnus_omega(&p, &q, h, [&mut pq, &mut qp], &mut omega);
    let e = super::expm::expm_generic(&omega);
    let y = e * SMatrix::<f64, N, N>::from_column_slice(x.as_slice());
    x.as_mut_slice().copy_from_slice(y.as_slice());
}

/// The buffers of the Magnus step of one dense block (the coupled modes with a field): no
/// allocation per step.
struct DenseStep {
    pq: DMatrix<f64>,
    qp: DMatrix<f64>,
    omega: DMatrix<f64>,
    e: DMatrix<f64>,
    work: super::expm::ExpmWork<nalgebra::Dyn>,
}

impl DenseStep {
    fn new(n: usize) -> Self {
        let z = || DMatrix::zeros(n, n);
        DenseStep { pq: z(), qp: z(), omega: z(), e: z(), work: super::expm::ExpmWork::new(nalgebra::Dyn(n)) }
    }

    /// X ← exp(Ω) X (the product through `pq` as the buffer).
    fn step(&mut self, a1: &DMatrix<f64>, a2: &DMatrix<f64>, h: f64, x: &mut DMatrix<f64>) {
        magnus_omega(a1, a2, h, [&mut self.pq, &mut self.qp], &mut self.omega);
        super::expm::expm_into(&self.omega, &mut self.work, &mut self.e);
        let n = x.nrows();
        super::matmul::mul(n, n, n, self.e.as_slice(), x.as_slice(), self.pq.as_mut_slice());
        std::mem::swap(x, &mut self.pq);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A non-finite matrix returns NaN eigenvalues at once (nalgebra's unbounded QR iteration
    /// never returned on one: a fuzzed scene hung `modes`); a finite one its eigenvalues.
    #[test]
    fn eigenvalues_of_non_finite_matrices_are_nan_not_a_hang() {
        let mut m = DMatrix::from_row_slice(3, 3, &[0.0, 1.0, 0.0, -4.0, 0.0, 1.0, 0.0, 0.0, -1.0]);
        let mut finite = eigenvalues(&m);
        finite.sort_by(|a, b| a.im.total_cmp(&b.im));
        assert!((finite[0] - Complex::new(0.0, -2.0)).norm() < 1e-12 && (finite[2] - Complex::new(0.0, 2.0)).norm() < 1e-12);
        for bad in [f64::NAN, f64::INFINITY] {
            m[(1, 2)] = bad;
            let mu = eigenvalues(&m);
            assert_eq!(mu.len(), 3);
            assert!(mu.iter().all(|z| z.re.is_nan()));
        }
    }

    /// x' = diag(λ) x with λ constant: the Magnus scheme is exact.
    struct Diagonal(Vec<f64>);
    impl LinearPeriodic for Diagonal {
        fn dim(&self) -> usize {
            self.0.len()
        }
        fn matrix(&self, _t: f64, a: &mut DMatrix<f64>) {
            a.fill(0.0);
            for (i, l) in self.0.iter().enumerate() {
                a[(i, i)] = *l;
            }
        }
        fn blocks(&self) -> Vec<Vec<usize>> {
            (0..self.0.len()).map(|i| vec![i]).collect()
        }
    }

    #[test]
    fn constant_diagonal_is_exact_and_stiff_safe() {
        let sys = Diagonal(vec![-1e4, 0.3, -2.0]);
        let m = monodromy(&sys, 0.0, 2.0, 3).unwrap();
        let s = m.spectrum();
        assert!((s.max_modulus - (0.6f64).exp()).abs() < 1e-13);
        assert_eq!(s.block, 1);
        assert_eq!(s.components, vec![(1, 1.0)]);
        let mut mods: Vec<f64> = s.multipliers.iter().map(|z| z.norm()).collect();
        mods.sort_by(f64::total_cmp);
        assert!(mods[0] < 1e-300 || mods[0] == 0.0);
    }

    #[test]
    fn rejects_bad_input() {
        let sys = Diagonal(vec![1.0]);
        assert!(matches!(monodromy(&sys, 0.0, 0.0, 3), Err(FloquetError::BadPeriod { .. })));
        assert!(matches!(monodromy(&sys, 0.0, 1.0, 0), Err(FloquetError::NoSteps { .. })));
        let big = Diagonal(vec![1e4]);
        assert!(matches!(monodromy(&big, 0.0, 1.0, 4), Err(FloquetError::NonFiniteMonodromy { .. })));
    }
}
