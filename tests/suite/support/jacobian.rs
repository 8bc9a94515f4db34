//! The analytic Jacobian of an assembled system against central differences of its rhs, at a
//! fixed, non-trivial state (R = 1.3, Ṙ = −0.4, small mode amplitudes, t = 0.37).

use magbubble::integrate::OdeSystem;

/// Asserts |∂f_i/∂y_j − FD| ≤ 1e-6 (1 + |FD|) for every entry; `label` names the case.
pub fn assert_jacobian_matches_fd(sys: &dyn OdeSystem, label: &str) {
    assert_jacobian_matches_fd_step(sys, label, 1e-3 * 1e-6);
}

/// The same with the step h_j = max(1e-6 |y_j|, `floor`).
pub fn assert_jacobian_matches_fd_step(sys: &dyn OdeSystem, label: &str, floor: f64) {
    let n = sys.dim();
    let mut y: Vec<f64> = (0..n).map(|i| 0.01 * (i as f64 + 1.0).sin()).collect();
    y[0] = 1.3;
    y[1] = -0.4;
    let t = 0.37;
    let mut jac = vec![0.0; n * n];
    assert!(sys.jacobian(t, &y, &mut jac), "{label}: no analytic Jacobian");
    let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
    for j in 0..n {
        let h = (1e-6 * y[j].abs()).max(floor);
        let (mut yp, mut ym) = (y.clone(), y.clone());
        yp[j] += h;
        ym[j] -= h;
        sys.rhs(t, &yp, &mut fp);
        sys.rhs(t, &ym, &mut fm);
        for i in 0..n {
            let fd = (fp[i] - fm[i]) / (2.0 * h);
            let a = jac[i * n + j];
            assert!((a - fd).abs() <= 1e-6 * (1.0 + fd.abs()), "{label} ∂f{i}/∂y{j}: {a} vs {fd}");
        }
    }
}
