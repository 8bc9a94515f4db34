//! An adaptive Dormand–Prince 5(4) integrator written for the tests' independent references
//! (Hairer, Nørsett & Wanner, *Solving ODEs I*, Table II.5.2), never the runtime's steppers:
//! error per step ≤ rtol·|y| + atol componentwise (max norm), step factor 0.9 (1/err)^(1/5)
//! clipped to [0.2, 5]. It lands exactly on `t1`.

const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0],
    [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0],
    [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0],
];
/// 5th-order weights minus the embedded 4th-order ones.
const E: [f64; 7] = [
    35.0 / 384.0 - 5179.0 / 57600.0,
    0.0,
    500.0 / 1113.0 - 7571.0 / 16695.0,
    125.0 / 192.0 - 393.0 / 640.0,
    -2187.0 / 6784.0 + 92097.0 / 339200.0,
    11.0 / 84.0 - 187.0 / 2100.0,
    -1.0 / 40.0,
];

/// Integrates y' = f(t, y) from t0 to t1 in place; `h` is the first trial step and on return the
/// last accepted one. Panics (a test failure) if the step collapses below 1e-16·|t1 − t0|.
pub fn dopri5(f: &impl Fn(f64, &[f64], &mut [f64]), t0: f64, t1: f64, y: &mut [f64], h: &mut f64, rtol: f64, atol: f64) {
    let n = y.len();
    let mut k = vec![vec![0.0; n]; 7];
    let (mut t, mut ys, mut y5) = (t0, vec![0.0; n], vec![0.0; n]);
    f(t, y, &mut k[0]);
    while t < t1 {
        let hh = h.min(t1 - t);
        assert!(hh > 1e-16 * (t1 - t0), "reference step collapsed at t = {t:e}");
        for s in 1..7 {
            for i in 0..n {
                ys[i] = y[i] + hh * (0..s).map(|j| A[s][j] * k[j][i]).sum::<f64>();
            }
            f(t + C[s] * hh, &ys, &mut k[s]);
        }
        // stage 7 was evaluated at the 5th-order solution (FSAL): ys is y5
        y5.copy_from_slice(&ys);
        let mut err = 0.0f64;
        for i in 0..n {
            let e = hh * (0..7).map(|j| E[j] * k[j][i]).sum::<f64>();
            err = err.max(e.abs() / (atol + rtol * y[i].abs().max(y5[i].abs())));
        }
        if err <= 1.0 {
            t += hh;
            y.copy_from_slice(&y5);
            let (first, rest) = k.split_at_mut(1);
            first[0].copy_from_slice(&rest[5]);
        }
        *h = hh * (0.9 * err.max(1e-10).powf(-0.2)).clamp(0.2, 5.0);
    }
}
