//! The constants of the 3-stage Radau IIA method (Ehle 1969; HW II, Table IV.5.6): nodes, the
//! error-estimate weights and the transformation T that block-diagonalises A⁻¹ (HW II, eq.
//! IV.8.16), computed from the exact tableau and checked by a test.

use nalgebra::{Complex, Matrix3, Vector3};

/// The constants of the 3-stage Radau IIA method.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RadauConsts {
    pub c: [f64; 3],
    /// Error-estimate weights e_i (RADAU5's DD1..DD3).
    pub dd: [f64; 3],
    /// Real eigenvalue of A⁻¹ and the complex pair α ± iβ.
    pub gamma: f64,
    pub alpha: f64,
    pub beta: f64,
    /// T and T⁻¹, row-major.
    pub t: [[f64; 3]; 3],
    pub ti: [[f64; 3]; 3],
}

/// The coefficient matrix A of Radau IIA with 3 stages (Ehle 1969; HW II, Table IV.5.6).
fn radau_iia_matrix() -> Matrix3<f64> {
    let s6 = 6f64.sqrt();
    Matrix3::new(
        (88.0 - 7.0 * s6) / 360.0,
        (296.0 - 169.0 * s6) / 1800.0,
        (-2.0 + 3.0 * s6) / 225.0,
        (296.0 + 169.0 * s6) / 1800.0,
        (88.0 + 7.0 * s6) / 360.0,
        (-2.0 - 3.0 * s6) / 225.0,
        (16.0 - s6) / 36.0,
        (16.0 + s6) / 36.0,
        1.0 / 9.0,
    )
}

impl RadauConsts {
    /// Radau IIA (Ehle 1969) with c = ((4 − √6)/10, (4 + √6)/10, 1) and its coefficient matrix
    /// (HW II, Table IV.5.6); T from the eigenvectors of A⁻¹.
    pub(crate) fn new() -> Self {
        let s6 = 6f64.sqrt();
        let a = radau_iia_matrix();
        let ainv = a.try_inverse().expect("Radau IIA matrix is invertible");
        let (c3, c23) = (3f64.cbrt(), 3f64.powf(2.0 / 3.0));
        let gamma = 3.0 + c23 - c3;
        let alpha = 3.0 + 0.5 * (c3 - c23);
        let beta = 0.5 * (3f64.powf(5.0 / 6.0) + 3f64.powf(7.0 / 6.0));
        // Null vector of a rank-2 3×3 matrix: cross product of two rows (bilinear, no conjugate).
        let cross = |m: &[[Complex<f64>; 3]; 3]| -> [Complex<f64>; 3] {
            let (r, s) = (m[0], m[1]);
            [r[1] * s[2] - r[2] * s[1], r[2] * s[0] - r[0] * s[2], r[0] * s[1] - r[1] * s[0]]
        };
        let shifted = |lam: Complex<f64>| {
            let mut m = [[Complex::new(0.0, 0.0); 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    m[i][j] = Complex::new(ainv[(i, j)], 0.0) - if i == j { lam } else { Complex::new(0.0, 0.0) };
                }
            }
            m
        };
        let v1 = cross(&shifted(Complex::new(gamma, 0.0)));
        let v1 = Vector3::new(v1[0].re, v1[1].re, v1[2].re);
        let v1 = v1 / (v1.norm() * v1[2].signum());
        let v = cross(&shifted(Complex::new(alpha, beta)));
        let v: Vec<Complex<f64>> = v.iter().map(|x| x / v[2]).collect();
        // A⁻¹(t2 − i t3) = (α + iβ)(t2 − i t3)  ⇔  A⁻¹[t2 t3] = [t2 t3] [[α, −β], [β, α]].
        let t = Matrix3::new(v1[0], v[0].re, -v[0].im, v1[1], v[1].re, -v[1].im, v1[2], v[2].re, -v[2].im);
        let ti = t.try_inverse().expect("eigenvector matrix is invertible");
        RadauConsts {
            c: [(4.0 - s6) / 10.0, (4.0 + s6) / 10.0, 1.0],
            dd: [-(13.0 + 7.0 * s6) / 3.0, (-13.0 + 7.0 * s6) / 3.0, -1.0 / 3.0],
            gamma,
            alpha,
            beta,
            t: std::array::from_fn(|i| std::array::from_fn(|j| t[(i, j)])),
            ti: std::array::from_fn(|i| std::array::from_fn(|j| ti[(i, j)])),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transformation_block_diagonalises_a_inverse() {
        let k = RadauConsts::new();
        let a = radau_iia_matrix();
        let (t, ti) = (Matrix3::from_fn(|i, j| k.t[i][j]), Matrix3::from_fn(|i, j| k.ti[i][j]));
        let lam = ti * a.try_inverse().unwrap() * t;
        let want = Matrix3::new(k.gamma, 0.0, 0.0, 0.0, k.alpha, -k.beta, 0.0, k.beta, k.alpha);
        assert!((lam - want).abs().max() < 1e-12, "{lam}");
        // Row sums of A are c (collocation), and b = last row (stiffly accurate).
        for i in 0..3 {
            assert!(((0..3).map(|j| a[(i, j)]).sum::<f64>() - k.c[i]).abs() < 1e-15);
        }
        // Hairer's RADAU5 values with the same normalisation (first column unit, T32 = 1, T33 = 0).
        assert!((k.t[0][0] - 9.1232394870892942792e-02).abs() < 1e-12);
        assert!((k.t[1][2] - 0.38294211275726193779).abs() < 1e-12);
        assert!((k.ti[2][1] - 2.5719269498556054292).abs() < 1e-12);
    }
}
