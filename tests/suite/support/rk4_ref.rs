//! The independent reference of the Keller–Miksis time-series tests: classical RK4 on a
//! right-hand side written in SI units in the test itself (never the runtime's), stepped from
//! [R0, 0] at t = 0 with `per` steps of `dt` between consecutive output rows.

/// R of the reference at each row of `rows` = [(t, R)] (the first row is t = 0); asserts that
/// the reference reaches each row's time to `time_tol` [s].
pub fn rk4_at_rows(f: impl Fn(f64, [f64; 2]) -> [f64; 2], r0: f64, rows: &[(f64, f64)], dt: f64, per: usize, time_tol: f64) -> Vec<f64> {
    let (mut y, mut t) = ([r0, 0.0], 0.0);
    let mut out = Vec::with_capacity(rows.len());
    for (i, &(ts, _)) in rows.iter().enumerate() {
        if i > 0 {
            for _ in 0..per {
                let k1 = f(t, y);
                let k2 = f(t + dt / 2.0, [y[0] + dt / 2.0 * k1[0], y[1] + dt / 2.0 * k1[1]]);
                let k3 = f(t + dt / 2.0, [y[0] + dt / 2.0 * k2[0], y[1] + dt / 2.0 * k2[1]]);
                let k4 = f(t + dt, [y[0] + dt * k3[0], y[1] + dt * k3[1]]);
                for j in 0..2 {
                    y[j] += dt / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
                }
                t += dt;
            }
        }
        assert!((t - ts).abs() < time_tol, "row time {ts} vs reference {t}");
        out.push(y[0]);
    }
    out
}
