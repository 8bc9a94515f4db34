//! Radau5's loops over the components (HW II, sec. IV.8; `radau5.f`): the stage
//! transformations W = (T⁻¹ ⊗ I) Z and back, the Newton right-hand sides, the error-estimate
//! right-hand side, the dense-output coefficients and the scaled norms.
//!
//! Each loop is one pass over pre-cut slices (no bounds checks, no allocation), fused where one
//! pass can do the work of several (the Newton norm with the W/Z update; the non-finite checks
//! with the pass that reads the values anyway). Per component the operations and their order are
//! those of the scalar code they replace, so the results are the same to the bit; the sums of
//! the norms stay sequential in the component order (the compiler vectorises the element-wise
//! part and adds the terms in order), for the build's baseline (x86-64: SSE2). An AVX build of
//! them earned about 1 % (SIMD policy, docs/performance.md) and was removed.

use nalgebra::Complex;

/// `pub(super) fn $name(args) -> ret`.
macro_rules! kernel {
    ($(#[$doc:meta])* fn $name:ident($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)? $body:block) => {
        $(#[$doc])*
        pub(super) fn $name($($arg: $ty),*) $(-> $ret)? $body
    };
}

/// `x` is NaN or ±∞: x − x is NaN exactly then (a floating-point compare the compiler
/// vectorises with AVX, where a 4-lane integer compare is not available).
#[inline(always)]
fn bad(x: f64) -> bool {
    #[allow(clippy::eq_op)]
    let d = x - x;
    d != 0.0
}

/// Σ_m sq_m in the component order (the terms formed in a vectorised pass before, the sum the
/// sequential one to the bit).
#[inline(always)]
fn ordered_sum(sq: &[f64]) -> f64 {
    sq.iter().fold(0.0, |s, &x| s + x)
}

kernel! {
    /// The first index of a non-finite entry of `v`.
    fn first_non_finite(v: &[f64]) -> Option<usize> {
        if !v.iter().fold(false, |acc, &x| acc | bad(x)) {
            return None;
        }
        v.iter().position(|&x| bad(x))
    }
}

kernel! {
    /// out = a + b.
    fn add(a: &[f64], b: &[f64], out: &mut [f64]) {
        let n = out.len();
        let (a, b) = (&a[..n], &b[..n]);
        for m in 0..n {
            out[m] = a[m] + b[m];
        }
    }
}

kernel! {
    /// Z and W = T⁻¹Z from the collocation polynomial of the last step at the nodes
    /// q_i = c_i h/h_old (RADAU5, label 20): z_i = q_i (a₁ + d2_i (a₂ + d1_i a₃)) with
    /// d2_i = q_i − (c₂ − 1), d1_i = q_i − (c₁ − 1).
    fn starting_values(q: [f64; 3], d1: [f64; 3], d2: [f64; 3], ti: &[[f64; 3]; 3], a: [&[f64]; 3], z: [&mut [f64]; 3], w: [&mut [f64]; 3]) {
        let [z0, z1, z2] = z;
        let [w0, w1, w2] = w;
        let n = z0.len();
        let (a1, a2, a3) = (&a[0][..n], &a[1][..n], &a[2][..n]);
        let (z1, z2, w0, w1, w2) = (&mut z1[..n], &mut z2[..n], &mut w0[..n], &mut w1[..n], &mut w2[..n]);
        for m in 0..n {
            let (a1, a2, a3) = (a1[m], a2[m], a3[m]);
            let zm: [f64; 3] = std::array::from_fn(|i| q[i] * (a1 + d2[i] * (a2 + d1[i] * a3)));
            z0[m] = zm[0];
            z1[m] = zm[1];
            z2[m] = zm[2];
            let w = |i: usize| ti[i][0] * zm[0] + ti[i][1] * zm[1] + ti[i][2] * zm[2];
            w0[m] = w(0);
            w1[m] = w(1);
            w2[m] = w(2);
        }
    }
}

kernel! {
    /// The right-hand sides of the two Newton systems (RADAU5, label 40): with
    /// (a₀, a₁, a₂) = T⁻¹(f₀, f₁, f₂) per component, z0 = a₀ − (γ/h) w₀ and
    /// rc = (a₁ − (α/h) w₁ + (β/h) w₂) + i (a₂ − (β/h) w₁ − (α/h) w₂). `true` when some f_i has
    /// a non-finite entry (the outputs are then not to be used).
    fn newton_rhs(ti: &[[f64; 3]; 3], fac: [f64; 3], f: [&[f64]; 3], w: [&[f64]; 3], z0: &mut [f64], rc: &mut [Complex<f64>]) -> bool {
        let [fac1, alphn, betan] = fac;
        let n = z0.len();
        let (f0, f1, f2, w0, w1, w2) = (&f[0][..n], &f[1][..n], &f[2][..n], &w[0][..n], &w[1][..n], &w[2][..n]);
        let rc = &mut rc[..n];
        let mut any_bad = false;
        for m in 0..n {
            let f = [f0[m], f1[m], f2[m]];
            any_bad |= bad(f[0]) | bad(f[1]) | bad(f[2]);
            let a = |i: usize| ti[i][0] * f[0] + ti[i][1] * f[1] + ti[i][2] * f[2];
            let (w1, w2, w3) = (w0[m], w1[m], w2[m]);
            z0[m] = a(0) - fac1 * w1;
            rc[m] = Complex::new(a(1) - alphn * w2 + betan * w3, a(2) - betan * w2 - alphn * w3);
        }
        any_bad
    }
}

kernel! {
    /// One Newton update (RADAU5, after label 40), the norm and the update in one pass: returns
    /// Σ_m (Δz0² + Δrc.re² + Δrc.im²)/scal² of the increments (z0, rc) (summed in the component
    /// order), then W += (z0, rc) and Z = T W.
    fn newton_update(t: &[[f64; 3]; 3], scal: &[f64], rc: &[Complex<f64>], w: [&mut [f64]; 3], z: [&mut [f64]; 3], sq: &mut [f64]) -> f64 {
        let [w0, w1, w2] = w;
        let [z0, z1, z2] = z;
        let n = z0.len();
        let (scal, rc, sq) = (&scal[..n], &rc[..n], &mut sq[..n]);
        let (w0, w1, w2, z1, z2) = (&mut w0[..n], &mut w1[..n], &mut w2[..n], &mut z1[..n], &mut z2[..n]);
        for m in 0..n {
            let (d0, c) = (z0[m], rc[m]);
            let s2 = scal[m] * scal[m];
            sq[m] = (d0.powi(2) + c.re.powi(2) + c.im.powi(2)) / s2;
            w0[m] += d0;
            w1[m] += c.re;
            w2[m] += c.im;
            let w = [w0[m], w1[m], w2[m]];
            let zz = |i: usize| t[i][0] * w[0] + t[i][1] * w[1] + t[i][2] * w[2];
            z0[m] = zz(0);
            z1[m] = zz(1);
            z2[m] = zz(2);
        }
        ordered_sum(sq)
    }
}

kernel! {
    /// The error estimate's right-hand side (RADAU5's ESTRAD): f2 = Σ_i (e_i/h) z_i and
    /// err = f2 + f0.
    fn error_rhs(hee: [f64; 3], z: [&[f64]; 3], f0: &[f64], f2: &mut [f64], err: &mut [f64]) {
        let n = err.len();
        let (z0, z1, z2, f0, f2) = (&z[0][..n], &z[1][..n], &z[2][..n], &f0[..n], &mut f2[..n]);
        for m in 0..n {
            f2[m] = hee[0] * z0[m] + hee[1] * z1[m] + hee[2] * z2[m];
            err[m] = f2[m] + f0[m];
        }
    }
}

kernel! {
    /// Σ_m (v_m / scal_m)², in the component order.
    fn scaled_sum_sq(v: &[f64], scal: &[f64], sq: &mut [f64]) -> f64 {
        let n = v.len();
        let (scal, sq) = (&scal[..n], &mut sq[..n]);
        for m in 0..n {
            sq[m] = (v[m] / scal[m]).powi(2);
        }
        ordered_sum(sq)
    }
}

kernel! {
    /// v += a.
    fn add_assign(v: &mut [f64], a: &[f64]) {
        let n = v.len();
        let a = &a[..n];
        for m in 0..n {
            v[m] += a[m];
        }
    }
}

kernel! {
    /// The accepted step (RADAU5, label 60): y += z₃, the coefficients of the collocation
    /// polynomial (RADAU5's CONT) and the new scale atol + rtol |y|. `true` when y has a
    /// non-finite entry.
    fn accept(c1: f64, c2: f64, tol: (&[f64], f64), z: [&[f64]; 3], y: &mut [f64], cont: [&mut [f64]; 4], scal: &mut [f64]) -> bool {
        let (atol, rtol) = tol;
        let n = y.len();
        let atol = &atol[..n];
        let (zz0, zz1, zz2) = (&z[0][..n], &z[1][..n], &z[2][..n]);
        let [k0, k1, k2, k3] = cont;
        let (k0, k1, k2, k3, scal) = (&mut k0[..n], &mut k1[..n], &mut k2[..n], &mut k3[..n], &mut scal[..n]);
        let mut any_bad = false;
        for m in 0..n {
            let (z1, z2, z3) = (zz0[m], zz1[m], zz2[m]);
            y[m] += z3;
            any_bad |= bad(y[m]);
            let ak = (z1 - z2) / (c1 - c2);
            let acont3 = (ak - z1 / c1) / c2;
            k0[m] = y[m];
            k1[m] = (z2 - z3) / (c2 - 1.0);
            k2[m] = (ak - k1[m]) / (c1 - 1.0);
            k3[m] = k2[m] - acont3;
            scal[m] = atol[m] + rtol * y[m].abs();
        }
        any_bad
    }
}

kernel! {
    /// The collocation polynomial at s = (t − t_n)/h_old (RADAU5's CONTR5).
    fn interpolate(c1: f64, c2: f64, s: f64, cont: [&[f64]; 4], out: &mut [f64]) {
        let n = out.len();
        let (k0, k1, k2, k3) = (&cont[0][..n], &cont[1][..n], &cont[2][..n], &cont[3][..n]);
        for m in 0..n {
            out[m] = k0[m] + s * (k1[m] + (s - (c2 - 1.0)) * (k2[m] + (s - (c1 - 1.0)) * k3[m]));
        }
    }
}
