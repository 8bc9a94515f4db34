//! Issue 30's hard cases (scenes/hard/): a 2-cycle Gaussian burst at ε_p = 3 with Keller–Miksis,
//! a measured waveform with noise, a dual-frequency drive with shape modes. Each completes or is
//! classified, with rows finite; the accuracy study: the same run at 100× tighter tolerances
//! agrees in R(t) to the stated fraction of R0.

use magbubble::model::{simulate, RunStatus};
use magbubble::scene::{self, Scene};

fn load(name: &str, overrides: &[String]) -> Scene {
    let path = format!("{}/scenes/hard/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    scene::load(&path, overrides).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn rows(s: &Scene) -> (RunStatus, Vec<(f64, f64)>) {
    let mut v = Vec::new();
    let r = simulate(s, &mut |t, row| {
        assert!(row.iter().all(|x| x.is_finite()), "non-finite row at {t}");
        v.push((t, row[0]));
    })
    .unwrap();
    (r.status, v)
}

/// Runs `name` at its tolerances and 100× tighter; max |ΔR|/R0 over the common rows.
fn study(name: &str) -> (RunStatus, f64, f64) {
    let s = load(name, &[]);
    let (st, a) = rows(&s);
    let tight = [format!("run.integrator.rtol={:e}", s.run.integrator.rtol / 100.0), format!("run.integrator.atol={:e}", s.run.integrator.atol / 100.0)];
    let (_, b) = rows(&load(name, &tight));
    let r0 = s.bubble.radius;
    let diff = a.iter().zip(&b).map(|(x, y)| (x.1 - y.1).abs() / r0).fold(0.0, f64::max);
    let rmin = a.iter().map(|x| x.1 / r0).fold(f64::INFINITY, f64::min);
    println!("{name}: {st:?}, max |ΔR|/R0 = {diff:e}, min R/R0 = {rmin}");
    (st, diff, rmin)
}

#[test]
fn gaussian_burst_collapse() {
    let (st, diff, rmin) = study("burst_gaussian_km");
    assert!(matches!(st, RunStatus::Completed | RunStatus::BlowUp { .. }), "{st:?}");
    assert!(rmin < 0.5, "a violent collapse: min R/R0 = {rmin}");
    assert!(diff < 1e-3, "max |ΔR|/R0 = {diff:e}");
}

#[test]
fn measured_noisy_waveform() {
    let (st, diff, _) = study("measured_noisy");
    assert_eq!(st, RunStatus::Completed);
    assert!(diff < 1e-5, "max |ΔR|/R0 = {diff:e}");
}

#[test]
fn dual_frequency_with_modes() {
    let (st, diff, _) = study("dual_frequency_modes");
    assert!(matches!(st, RunStatus::Completed | RunStatus::BlowUp { .. }), "{st:?}");
    assert!(diff < 1e-5, "max |ΔR|/R0 = {diff:e}");
}
