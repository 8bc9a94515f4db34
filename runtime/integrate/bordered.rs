//! σI − J for a Jacobian that is banded apart from a dense border: the first `border` rows and
//! columns are full, the rest (the interior) has lower / upper bandwidth (ml, mu). A
//! [`StructuredJacobian`] for [`super::linear`], so that Radau5 and the Rosenbrock pair factor
//! such a system in O(n·ml·(ml + mu) + n·border²) instead of O(n³).
//!
//! With B the border and I the interior, M = σI − J = [[M_BB, M_BI], [M_IB, M_II]]:
//!
//! ```text
//! Z = M_II⁻¹ J_IB                      (band LU with partial pivoting, `border` solves)
//! S = σI − J_BB − J_BI Z               (the Schur complement, dense border × border)
//! solve:  y_I = M_II⁻¹ b_I,  S x_B = b_B + J_BI y_I,  x_I = y_I + Z x_B
//! ```
//!
//! (block elimination, e.g. Golub & Van Loan, *Matrix Computations*, 4th ed., §4.5.4 on bordered
//! systems). The boundary-layer model has this shape (docs/architecture.md, "Jacobian
//! structure"): the border is R, Ṙ and the modes R̈ depends on; the interior is the block band of
//! the mode-to-mode couplings (k ± 2 for the paper's coil).

use super::linalg::{Scalar, ShiftedLu};
use super::linear::{AnalyticStructure, Factorization};
use std::rc::Rc;

/// J split into border and interior (row-major pieces), checked against the pattern.
#[derive(Debug)]
struct Parts {
    nb: usize,
    ni: usize,
    band: (usize, usize),
    /// nb × nb
    jbb: Vec<f64>,
    /// nb × ni
    jbi: Vec<f64>,
    /// ni × nb, column after column (jib[c * ni + i] = J_{nb+i, c})
    jib: Vec<f64>,
    /// ni × ni row-major (entries outside the band are zero)
    jii: Vec<f64>,
}

/// J of a bordered-band system at one (t, y), factored for any shift.
#[derive(Debug)]
pub struct BorderedBand(Rc<Parts>);

impl BorderedBand {
    /// Splits the row-major n × n `jac`. `None` when an entry is non-finite or an interior entry
    /// outside the band (ml, mu) is non-zero (the structure does not hold: use a dense LU), or
    /// when the interior is too small for the structure to pay.
    pub fn new(jac: &[f64], n: usize, border: usize, ml: usize, mu: usize) -> Option<Self> {
        if border >= n || n - border <= ml + mu + 1 || jac.len() < n * n || jac[..n * n].iter().any(|v| !v.is_finite()) {
            return None;
        }
        let (nb, ni) = (border, n - border);
        let mut p = Parts {
            nb,
            ni,
            band: (ml, mu),
            jbb: vec![0.0; nb * nb],
            jbi: vec![0.0; nb * ni],
            jib: vec![0.0; ni * nb],
            jii: vec![0.0; ni * ni],
        };
        for r in 0..nb {
            p.jbb[r * nb..(r + 1) * nb].copy_from_slice(&jac[r * n..r * n + nb]);
            p.jbi[r * ni..(r + 1) * ni].copy_from_slice(&jac[r * n + nb..(r + 1) * n]);
        }
        for i in 0..ni {
            let row = &jac[(nb + i) * n..(nb + i + 1) * n];
            for c in 0..nb {
                p.jib[c * ni + i] = row[c];
            }
            for (j, &v) in row[nb..].iter().enumerate() {
                if i > j + ml || j > i + mu {
                    if v != 0.0 {
                        return None;
                    }
                } else {
                    p.jii[i * ni + j] = v;
                }
            }
        }
        Some(BorderedBand(Rc::new(p)))
    }
}

impl AnalyticStructure for BorderedBand {
    type Lu<T: Scalar + 'static> = BorderedLu<T>;

    fn factor_as<T: Scalar + 'static>(&self, sigma: T) -> Option<BorderedLu<T>> {
        let p = &self.0;
        let (nb, ni) = (p.nb, p.ni);
        let mut inner = ShiftedLu::<T>::new(ni, Some(p.band));
        inner.factor(sigma, &p.jii, T::from_real).ok()?;
        let mut z = vec![T::ZERO; ni * nb];
        for c in 0..nb {
            let col = &mut z[c * ni..(c + 1) * ni];
            for (x, &v) in col.iter_mut().zip(&p.jib[c * ni..(c + 1) * ni]) {
                *x = T::from_real(v);
            }
            inner.solve(col);
        }
        let mut schur = ShiftedLu::<T>::new(nb, None);
        schur
            .factor_matrix(|r, c| {
                let mut s = T::from_real(-p.jbb[r * nb + c]);
                if r == c {
                    s = s + sigma;
                }
                let row = &p.jbi[r * ni..(r + 1) * ni];
                for (&a, &zk) in row.iter().zip(&z[c * ni..(c + 1) * ni]) {
                    if a != 0.0 {
                        s = s - T::from_real(a) * zk;
                    }
                }
                s
            })
            .ok()?;
        Some(BorderedLu { parts: Rc::clone(&self.0), inner, z, schur })
    }
}

/// The factorisation of σI − J (module doc).
pub(crate) struct BorderedLu<T: Scalar> {
    parts: Rc<Parts>,
    inner: ShiftedLu<T>,
    /// M_II⁻¹ J_IB, column after column
    z: Vec<T>,
    schur: ShiftedLu<T>,
}

impl<T: Scalar> Factorization<T> for BorderedLu<T> {
    fn solve(&self, b: &mut [T]) {
        let p = &*self.parts;
        let (nb, ni) = (p.nb, p.ni);
        let (bb, bi) = b.split_at_mut(nb);
        self.inner.solve(bi);
        for (r, x) in bb.iter_mut().enumerate() {
            let mut s = *x;
            for (&a, &y) in p.jbi[r * ni..(r + 1) * ni].iter().zip(bi.iter()) {
                if a != 0.0 {
                    s = s + T::from_real(a) * y;
                }
            }
            *x = s;
        }
        self.schur.solve(bb);
        for (c, &xc) in bb.iter().enumerate() {
            for (y, &zc) in bi.iter_mut().zip(&self.z[c * ni..(c + 1) * ni]) {
                *y = *y + zc * xc;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::linear::{assert_solves_like_dense, StructuredJacobian};
    use nalgebra::Complex;

    /// A bordered-band matrix (border 3, interior band (2, 2)) with a small diagonal, so that
    /// both LUs pivot; the structured solve must agree with the dense one.
    #[test]
    fn agrees_with_the_dense_lu() {
        let (n, nb, ml, mu) = (23, 3, 2, 2);
        let mut jac = vec![0.0; n * n];
        for r in 0..n {
            for c in 0..n {
                let inside = r < nb || c < nb || (r - nb <= c - nb + ml && c - nb <= r - nb + mu);
                if inside {
                    jac[r * n + c] = ((r * 7 + c * 13) % 11) as f64 - 5.0 + if r == c { 0.01 } else { 0.0 };
                }
            }
        }
        let bb = BorderedBand::new(&jac, n, nb, ml, mu).expect("structure holds");
        let b: Vec<f64> = (0..n).map(|i| (i as f64).sin() + 1.0).collect();
        let hook: &dyn StructuredJacobian = &bb;
        assert_solves_like_dense(&*hook.factor(0.3).unwrap(), 0.3, &jac, n, &b);
        let sc = Complex::new(0.3, -2.0);
        let bc: Vec<Complex<f64>> = b.iter().map(|&v| Complex::new(v, -v)).collect();
        assert_solves_like_dense(&*hook.factor_complex(sc).unwrap(), sc, &jac, n, &bc);
        // an entry outside the band: the structure does not hold
        jac[(nb + 10) * n + nb + 1] = 1.0;
        assert!(BorderedBand::new(&jac, n, nb, ml, mu).is_none());
    }
}
