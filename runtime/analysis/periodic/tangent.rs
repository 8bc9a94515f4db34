//! What the period map's RK4 loop ([`super::RkFlow`]) carries beside y: the stage buffers
//! ([`Buf`]), the RK4 tableau, and the tangent ([`Tangent`]: nothing, or Φ with its stage slopes)
//! with the Jacobian workspace.

use crate::integrate::OdeSystem;
use nalgebra::DMatrix;

/// The stage buffers of [`super::RkFlow`]'s `integrate`: an array (length known to the compiler) or a Vec.
pub(super) trait Buf: AsRef<[f64]> + AsMut<[f64]> {
    fn zeros(n: usize) -> Self;
}

impl<const N: usize> Buf for [f64; N] {
    fn zeros(_: usize) -> Self {
        [0.0; N]
    }
}

impl Buf for Vec<f64> {
    fn zeros(n: usize) -> Self {
        vec![0.0; n]
    }
}

/// The RK4 stages: (node c, stage whose slope the stage's point uses).
pub(super) const NODES: [(f64, usize); 4] = [(0.0, 0), (0.5, 0), (0.5, 1), (1.0, 2)];
/// The RK4 weights: (weight, stage).
pub(super) const WEIGHTS: [(f64, usize); 4] = [(1.0, 0), (2.0, 1), (2.0, 2), (1.0, 3)];

/// What [`super::RkFlow`]'s `integrate` carries beside y: nothing, or Φ with its stage slopes K = J Φ.
pub(super) trait Tangent {
    /// The stage point's Φ: Φ (stage 0) or Φ + c h K_from.
    fn stage(&mut self, st: usize, ch: f64, from: usize);
    /// J at the stage point.
    fn jacobian(&mut self, sys: &dyn OdeSystem, t: f64, y: &[f64]);
    /// K_st = J · (the stage point's Φ).
    fn product(&mut self, st: usize);
    /// Φ += h/6 (K_0 + 2K_1 + 2K_2 + K_3).
    fn accumulate(&mut self, h: f64);
    fn is_finite(&self) -> bool;
    /// Keeps Φ, to [`restore`](Self::restore) it (a step redone up to a branch switch).
    fn save(&mut self);
    fn restore(&mut self);
}

/// The period map alone.
pub(super) struct NoTangent;

impl Tangent for NoTangent {
    fn stage(&mut self, _: usize, _: f64, _: usize) {}
    fn jacobian(&mut self, _: &dyn OdeSystem, _: f64, _: &[f64]) {}
    fn product(&mut self, _: usize) {}
    fn accumulate(&mut self, _: f64) {}
    fn is_finite(&self) -> bool {
        true
    }
    fn save(&mut self) {}
    fn restore(&mut self) {}
}

/// Φ as a `DMatrix` (n × n), the products by `gemm`.
pub(super) struct DynTangent<'p> {
    phi: &'p mut DMatrix<f64>,
    kp: [DMatrix<f64>; 4],
    ptmp: DMatrix<f64>,
    ws: VarWork,
    saved: Option<DMatrix<f64>>,
}

impl<'p> DynTangent<'p> {
    pub(super) fn new(phi: &'p mut DMatrix<f64>) -> Self {
        let n = phi.nrows();
        Self { kp: std::array::from_fn(|_| DMatrix::zeros(n, n)), ptmp: DMatrix::zeros(n, n), ws: VarWork::new(n), phi, saved: None }
    }
}

impl Tangent for DynTangent<'_> {
    fn stage(&mut self, st: usize, ch: f64, from: usize) {
        self.ptmp.copy_from(self.phi);
        if st > 0 {
            self.ptmp.zip_apply(&self.kp[from], |a, b| *a += ch * b);
        }
    }
    fn jacobian(&mut self, sys: &dyn OdeSystem, t: f64, y: &[f64]) {
        self.ws.jacobian(sys, t, y);
    }
    fn product(&mut self, st: usize) {
        self.kp[st].gemm(1.0, &self.ws.jac, &self.ptmp, 0.0);
    }
    fn accumulate(&mut self, h: f64) {
        for (w, k) in WEIGHTS {
            self.phi.zip_apply(&self.kp[k], |a, b| *a += w * h / 6.0 * b);
        }
    }
    fn is_finite(&self) -> bool {
        self.phi.iter().all(|v| v.is_finite())
    }
    fn save(&mut self) {
        match &mut self.saved {
            Some(m) => m.copy_from(self.phi),
            None => self.saved = Some(self.phi.clone()),
        }
    }
    fn restore(&mut self) {
        if let Some(m) = &self.saved {
            self.phi.copy_from(m);
        }
    }
}

/// Φ for N state components on stack arrays; the same stages and sums as [`DynTangent`], Φ to
/// rounding (the products' summation order).
pub(super) struct FixedTangent<const N: usize> {
    p: [[f64; N]; N],
    saved: [[f64; N]; N],
    pt: [[f64; N]; N],
    kp: [[[f64; N]; N]; 4],
    jac: [[f64; N]; N],
    ws: VarWork,
}

impl<const N: usize> FixedTangent<N> {
    pub(super) fn new(phi: &DMatrix<f64>) -> Self {
        let p = std::array::from_fn(|i| std::array::from_fn(|j| phi[(i, j)]));
        Self { p, saved: p, pt: p, kp: [[[0.0; N]; N]; 4], jac: [[0.0; N]; N], ws: VarWork::new(N) }
    }
    pub(super) fn store(&self, phi: &mut DMatrix<f64>) {
        for i in 0..N {
            for j in 0..N {
                phi[(i, j)] = self.p[i][j];
            }
        }
    }
}

impl<const N: usize> Tangent for FixedTangent<N> {
    fn stage(&mut self, st: usize, ch: f64, from: usize) {
        self.pt = self.p;
        if st > 0 {
            for i in 0..N {
                for j in 0..N {
                    self.pt[i][j] += ch * self.kp[from][i][j];
                }
            }
        }
    }
    fn jacobian(&mut self, sys: &dyn OdeSystem, t: f64, y: &[f64]) {
        self.ws.jacobian_into(sys, t, y, self.jac.as_flattened_mut());
    }
    fn product(&mut self, st: usize) {
        for i in 0..N {
            for j in 0..N {
                self.kp[st][i][j] = (0..N).map(|k| self.jac[i][k] * self.pt[k][j]).sum();
            }
        }
    }
    fn accumulate(&mut self, h: f64) {
        for (w, k) in WEIGHTS {
            for i in 0..N {
                for j in 0..N {
                    self.p[i][j] += w * h / 6.0 * self.kp[k][i][j];
                }
            }
        }
    }
    fn is_finite(&self) -> bool {
        self.p.as_flattened().iter().all(|v| v.is_finite())
    }
    fn save(&mut self) {
        self.saved = self.p;
    }
    fn restore(&mut self) {
        self.p = self.saved;
    }
}

/// Jacobian workspace of [`super::RkFlow::advance_variational`].
pub(super) struct VarWork {
    jac: DMatrix<f64>,
    row_major: Vec<f64>,
    yp: Vec<f64>,
    fp: Vec<f64>,
    fm: Vec<f64>,
}

impl VarWork {
    fn new(n: usize) -> Self {
        Self { jac: DMatrix::zeros(n, n), row_major: vec![0.0; n * n], yp: vec![0.0; n], fp: vec![0.0; n], fm: vec![0.0; n] }
    }

    /// J(t, y) into `self.jac`.
    fn jacobian(&mut self, sys: &dyn OdeSystem, t: f64, y: &[f64]) {
        let n = y.len();
        let mut rm = std::mem::take(&mut self.row_major);
        self.jacobian_into(sys, t, y, &mut rm);
        for i in 0..n {
            for j in 0..n {
                self.jac[(i, j)] = rm[i * n + j];
            }
        }
        self.row_major = rm;
    }

    /// J(t, y) row-major into `out` (n²): the analytic one, else central differences.
    fn jacobian_into(&mut self, sys: &dyn OdeSystem, t: f64, y: &[f64], out: &mut [f64]) {
        if sys.jacobian(t, y, out) {
            return;
        }
        let n = y.len();
        let scale = y.iter().fold(1e-8f64, |m, v| m.max(v.abs()));
        self.yp.copy_from_slice(y);
        for j in 0..n {
            let hj = 1e-6 * y[j].abs().max(scale);
            self.yp[j] = y[j] + hj;
            sys.rhs(t, &self.yp, &mut self.fp);
            self.yp[j] = y[j] - hj;
            sys.rhs(t, &self.yp, &mut self.fm);
            self.yp[j] = y[j];
            for i in 0..n {
                out[i * n + j] = (self.fp[i] - self.fm[i]) / (2.0 * hj);
            }
        }
    }
}
