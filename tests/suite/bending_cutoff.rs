//! Bending stiffness and the mode cutoff of the fig-5 critical pressure (issue 11 part 2;
//! docs/model.md, "Bending and the mode cutoff"): at 1 MHz without bending the critical ε_p still
//! moves between N = 12 and N = 28 (0.167 → 0.157, the highest modes go first); with
//! k_b = 1e-15 J it is the same for both cutoffs (0.209, mode a12).

use magbubble::analysis::bisect::Outcome;
use magbubble::analysis::stability::{critical_point, CriticalOptions, Criterion, FloquetOptions, SeriesOptions};
use magbubble::scene;

fn critical(n: usize, kb: f64) -> (f64, String) {
    let path = format!("{}/scenes/figures/fig05_modes.toml", env!("CARGO_MANIFEST_DIR"));
    let over = [format!("modes.max_order={n}"), format!("shell.bending_modulus={kb:e}"), "drive.frequency_hz=1e6".into()];
    let base = scene::load(&path, &over).unwrap();
    let at = |eps: f64| {
        let mut s = base.clone();
        s.drive.as_mut().expect("driven").amplitude = eps;
        Ok(s)
    };
    let opts = CriticalOptions {
        criterion: Criterion::Floquet,
        lo: 0.05,
        hi: 0.5,
        scan: 8,
        tol: 1e-3,
        relative_tol: true,
        floquet: FloquetOptions::default(),
        series: SeriesOptions::default(),
    };
    let p = critical_point(&at, &opts).expect("stability analysis runs");
    let Outcome::Critical { value, .. } = p.outcome else { panic!("N = {n}, k_b = {kb}: {:?}", p.outcome) };
    (value, p.mode)
}

#[test]
fn bending_makes_the_critical_pressure_converge_in_the_cutoff() {
    let (c12, m12) = critical(12, 0.0);
    let (c28, m28) = critical(28, 0.0);
    eprintln!("k_b = 0: N = 12 {c12:.4} ({m12}), N = 28 {c28:.4} ({m28})");
    assert!(c12 - c28 > 0.03 * c28, "without bending the cutoff matters: {c12} vs {c28}");
    assert_eq!(m28, "a26");
    let (b12, n12) = critical(12, 1e-15);
    let (b28, n28) = critical(28, 1e-15);
    eprintln!("k_b = 1e-15 J: N = 12 {b12:.4} ({n12}), N = 28 {b28:.4} ({n28})");
    assert!((b12 - b28).abs() < 2e-3 * b28 && n12 == "a12" && n28 == "a12", "{b12} ({n12}) vs {b28} ({n28})");
    assert!(b28 > 1.2 * c28, "bending raises the critical pressure: {b28} vs {c28}");
}
