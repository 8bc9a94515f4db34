//! The fourth-order Magnus monodromy ([`monodromy`], the scheme in the parent module's doc):
//! the steps over a period split at A(t)'s breaks, the 1–3-state blocks on the stack, a dense
//! block through its exponential ([`crate::analysis::expm`]) on buffers kept over the period.

use super::{FloquetError, LinearPeriodic, Monodromy};
use crate::analysis::expm;
use nalgebra::allocator::Allocator;
use nalgebra::{DMatrix, DefaultAllocator, OMatrix, SMatrix};

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
    pq.gemm(1.0, p, q, 0.0);
    qp.gemm(1.0, q, p, 0.0);
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
    let e = expm::expm_generic(&omega);
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
    work: expm::ExpmWork<nalgebra::Dyn>,
}

impl DenseStep {
    fn new(n: usize) -> Self {
        let z = || DMatrix::zeros(n, n);
        DenseStep { pq: z(), qp: z(), omega: z(), e: z(), work: expm::ExpmWork::new(nalgebra::Dyn(n)) }
    }

    /// X ← exp(Ω) X (the product through `pq` as the buffer).
    fn step(&mut self, a1: &DMatrix<f64>, a2: &DMatrix<f64>, h: f64, x: &mut DMatrix<f64>) {
        magnus_omega(a1, a2, h, [&mut self.pq, &mut self.qp], &mut self.omega);
        expm::expm_into(&self.omega, &mut self.work, &mut self.e);
        self.pq.gemm(1.0, &self.e, x, 0.0);
        std::mem::swap(x, &mut self.pq);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
