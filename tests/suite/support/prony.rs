//! Prony / linear-prediction fit shared by the time-domain decay tests
//! (`#[path = "support/prony.rs"] mod prony;`).

use magbubble::analysis::dispersion::C64;

/// Prony / linear-prediction fit of x_n = Σ_{j=1..p} c_j x_{n−j} to uniformly sampled data;
/// returns the continuous-time exponents s_j = ln(z_j)/Δ of the characteristic roots z_j. The
/// free decay contains, besides the shape mode, a slowly decaying non-oscillatory vorticity tail
/// (diffusion rates from νk(k+1)/R0² ≈ 6·10⁴ s⁻¹ up, slower than the mode), which a simple
/// peak-ratio fit would mistake for damping; the extra exponents absorb it.
pub fn prony(x: &[f64], dt: f64, p: usize) -> Vec<C64> {
    let rows = x.len() - p;
    let mut a = nalgebra::DMatrix::<f64>::zeros(rows, p);
    let mut rhs = nalgebra::DVector::<f64>::zeros(rows);
    for n in p..x.len() {
        for j in 1..=p {
            a[(n - p, j - 1)] = x[n - j];
        }
        rhs[n - p] = x[n];
    }
    let c = a.svd(true, true).solve(&rhs, 1e-14).unwrap();
    // companion matrix of z^p − c1 z^{p−1} − … − cp
    let mut comp = nalgebra::DMatrix::<f64>::zeros(p, p);
    for j in 0..p {
        comp[(0, j)] = c[j];
    }
    for i in 1..p {
        comp[(i, i - 1)] = 1.0;
    }
    comp.complex_eigenvalues().iter().map(|z| C64::new(z.norm().ln(), z.arg()) / dt).collect()
}
