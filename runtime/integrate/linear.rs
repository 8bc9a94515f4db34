//! The linear-solver hook of the implicit steppers (Radau5, Rosenbrock).
//!
//! Both need solves with σI − J (σ = γ/h real and (α + iβ)/h complex for Radau5, σ = 1/(hγ) for
//! the Rosenbrock W = I − hγJ = hγ(σI − J)). A system whose Jacobian has a structure a dense or
//! banded LU cannot exploit (the monolithic vorticity system: bordered tridiagonal blocks) hands
//! the stepper a [`StructuredJacobian`] from [`OdeSystem::structured_jacobian`]; otherwise
//! [`NewtonMatrix`] falls back to the row-major J of `OdeSystem::jacobian` (or finite
//! differences, dense or banded) and the LU of [`super::linalg`].

use super::jacobian::FdJacobian;
use super::linalg::{Scalar, ShiftedLu};
use super::{first_non_finite, OdeSystem, Stats};
use nalgebra::Complex;

/// A factorisation of σI − J: solves (σI − J) x = b in place.
pub trait Factorization<T> {
    fn solve(&self, b: &mut [T]);
}

/// J at one (t, y) in a form only the system understands, factored for any shift.
pub trait StructuredJacobian {
    /// Work spent building it, in right-hand-side evaluations or their equivalent (counted in
    /// [`Stats::rhs_evals`]).
    fn rhs_equivalents(&self) -> u64;
    /// σI − J for real σ; `None` when singular.
    fn factor(&self, sigma: f64) -> Option<Box<dyn Factorization<f64>>>;
    /// σI − J for complex σ; `None` when singular.
    fn factor_complex(&self, sigma: Complex<f64>) -> Option<Box<dyn Factorization<Complex<f64>>>>;
}

/// A [`StructuredJacobian`] built from the system's analytic Jacobian (no rhs calls) whose
/// factorisation is one generic code for both scalars: the boundary-layer splits
/// ([`super::bordered`], [`super::reduced`]) implement this and get the hook from it.
pub(crate) trait AnalyticStructure {
    /// The factorisation of σI − J for a real or complex σ.
    type Lu<T: Scalar + 'static>: Factorization<T> + 'static;
    /// Factors σI − J; `None` when singular.
    fn factor_as<T: Scalar + 'static>(&self, sigma: T) -> Option<Self::Lu<T>>;
}

impl<S: AnalyticStructure> StructuredJacobian for S {
    fn rhs_equivalents(&self) -> u64 {
        0
    }
    fn factor(&self, sigma: f64) -> Option<Box<dyn Factorization<f64>>> {
        self.factor_as(sigma).map(|f| Box::new(f) as Box<dyn Factorization<f64>>)
    }
    fn factor_complex(&self, sigma: Complex<f64>) -> Option<Box<dyn Factorization<Complex<f64>>>> {
        self.factor_as(sigma).map(|f| Box::new(f) as Box<dyn Factorization<Complex<f64>>>)
    }
}

/// Test helper: `lu` (a structured factorisation of σI − J) solves (σI − J) x = b like the dense
/// LU of the row-major n × n `jac`, to 1e-11 relative.
#[cfg(test)]
pub(crate) fn assert_solves_like_dense<T: Scalar + std::fmt::Display>(lu: &dyn Factorization<T>, sigma: T, jac: &[f64], n: usize, b: &[T]) {
    let mut x = b.to_vec();
    lu.solve(&mut x);
    let mut dense = ShiftedLu::<T>::new(n, None);
    dense.factor(sigma, jac, T::from_real).expect("dense LU");
    let mut xd = b.to_vec();
    dense.solve(&mut xd);
    for (&a, &d) in x.iter().zip(&xd) {
        assert!((a - d).mag() <= 1e-11 * d.mag().max(1.0), "{a} vs {d}");
    }
}

enum Kind {
    /// Not evaluated yet (the kind is decided at the first evaluation).
    Unset,
    Dense { jac: Vec<f64>, fd: FdJacobian, real: ShiftedLu<f64>, cplx: Option<ShiftedLu<Complex<f64>>> },
    Structured {
        jac: Box<dyn StructuredJacobian>,
        real: Option<Box<dyn Factorization<f64>>>,
        cplx: Option<Box<dyn Factorization<Complex<f64>>>>,
    },
}

/// J and the factorisations of σI − J that an implicit stepper keeps between steps.
pub(crate) struct NewtonMatrix {
    n: usize,
    complex: bool,
    kind: Kind,
}

impl std::fmt::Debug for NewtonMatrix {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kind = match self.kind {
            Kind::Unset => "unset",
            Kind::Dense { .. } => "dense",
            Kind::Structured { .. } => "structured",
        };
        write!(f, "NewtonMatrix {{ n: {}, kind: {kind} }}", self.n)
    }
}

impl NewtonMatrix {
    /// `complex`: the stepper also factors a complex shift (Radau5).
    pub(crate) fn new(n: usize, complex: bool) -> Self {
        NewtonMatrix { n, complex, kind: Kind::Unset }
    }

    /// Evaluates J at (t, y), f0 = f(t, y); invalidates the factorisations. Counts one Jacobian
    /// evaluation and its rhs cost. `Err(component)` when J has a non-finite entry.
    pub(crate) fn evaluate(&mut self, sys: &dyn OdeSystem, t: f64, y: &[f64], f0: &[f64], stats: &mut Stats) -> Result<(), usize> {
        // A system may decline the structured form at some states (the bordered-band split of
        // the boundary-layer model when J has a non-finite entry): the dense path then runs.
        if let Some(jac) = sys.structured_jacobian(t, y) {
            stats.jac_evals += 1;
            stats.rhs_evals += jac.rhs_equivalents();
            self.kind = Kind::Structured { jac, real: None, cplx: None };
            return Ok(());
        }
        if !matches!(self.kind, Kind::Dense { .. }) {
            let (n, band) = (self.n, sys.bandwidth());
            self.kind = Kind::Dense {
                jac: vec![0.0; n * n],
                fd: FdJacobian::new(n),
                real: ShiftedLu::new(n, band),
                cplx: self.complex.then(|| ShiftedLu::new(n, band)),
            };
        }
        let Kind::Dense { jac, fd, .. } = &mut self.kind else { unreachable!("set above") };
        fd.evaluate(sys, t, y, f0, jac, stats);
        match first_non_finite(jac) {
            Some(c) => Err(c % self.n),
            None => Ok(()),
        }
    }

    /// Factors σI − J (and, when `complex`, σ_c I − J). Counts one LU decomposition (a real and
    /// a complex factorisation together count as one, as RADAU5's NDEC). `false`: singular.
    pub(crate) fn factor(&mut self, sigma: f64, sigma_c: Complex<f64>, stats: &mut Stats) -> bool {
        stats.lu_decompositions += 1;
        let complex = self.complex;
        match &mut self.kind {
            Kind::Unset => false,
            Kind::Dense { jac, real, cplx, .. } => {
                real.factor(sigma, jac, |x| x).is_ok()
                    && cplx.as_mut().is_none_or(|c| c.factor(sigma_c, jac, |x| Complex::new(x, 0.0)).is_ok())
            }
            Kind::Structured { jac, real, cplx } => {
                *real = jac.factor(sigma);
                *cplx = if complex { jac.factor_complex(sigma_c) } else { None };
                real.is_some() && (!complex || cplx.is_some())
            }
        }
    }

    /// x ← (σI − J)⁻¹ x with the real factorisation.
    pub(crate) fn solve(&self, x: &mut [f64]) {
        match &self.kind {
            Kind::Dense { real, .. } => real.solve(x),
            Kind::Structured { real: Some(f), .. } => f.solve(x),
            _ => x.iter_mut().for_each(|v| *v = f64::NAN),
        }
    }

    /// x ← (σ_c I − J)⁻¹ x with the complex factorisation.
    pub(crate) fn solve_complex(&self, x: &mut [Complex<f64>]) {
        match &self.kind {
            Kind::Dense { cplx: Some(c), .. } => c.solve(x),
            Kind::Structured { cplx: Some(f), .. } => f.solve(x),
            _ => x.iter_mut().for_each(|v| *v = Complex::new(f64::NAN, f64::NAN)),
        }
    }
}
