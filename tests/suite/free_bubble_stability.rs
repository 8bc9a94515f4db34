//! Floquet and `figure` on a free bubble (issue 10 part 5): without a membrane (surface tension
//! only) no load depends on b_k, so b_k only relabels material points and its multiplier is
//! R(T)/R(0) = 1 on any orbit — neutral, and before this fix reported as "unstable" at every drive
//! (max|μ| = 1.000000). The verdict now uses the (a, ȧ) blocks (analysis/stability.rs
//! `ShapeSystem::b_free`). Checked against the boundary-layer decay rate written out here, and
//! `figure 5 --quick` on a free-bubble scene finds critical pressures instead of
//! "unstable_at_bottom" everywhere.

use magbubble::analysis::stability::{floquet, FloquetOptions};
use magbubble::scene;
use std::process::Command;

const FREE: &str = "[bubble]\nradius = 10e-6\n[shell]\nc1 = 0.0\nc2 = 0.0\nsurface_tension = 0.072\n\
                    [drive]\namplitude = 1e-4\nfrequency_hz = 1e6\n[modes]\nmax_order = 4\n";

/// |μ| of mode k at rest over one period T: ä + 2γȧ + ω²a = 0 from (N) with the boundary layer,
/// T_w = [2(k+2)/(k+1)] ȧ/(1 + 2δ/R), no tangential load:
/// 2γ = (k+1)η/(ρR²) [2(k+2) + 2k(k+2)/(k+1) · (1 − 2(k+1)δ/R)/(1 + 2δ/R)], δ = min(√(ν/ω_d), R/(2k)).
fn multiplier(k: f64, f: f64) -> f64 {
    let (rho, eta, r) = (1000.0, 1e-3, 10e-6);
    let w = 2.0 * std::f64::consts::PI * f;
    let delta = ((eta / rho) / w).sqrt().min(r / (2.0 * k));
    let two_gamma = (k + 1.0) * eta / (rho * r * r)
        * (2.0 * (k + 2.0) + 2.0 * k * (k + 2.0) / (k + 1.0) * (1.0 - 2.0 * (k + 1.0) * delta / r) / (1.0 + 2.0 * delta / r));
    (-0.5 * two_gamma / f).exp()
}

#[test]
fn free_bubble_floquet_leaves_out_the_neutral_tangential_mode() {
    for f in [1e6, 2e6] {
        let s = scene::load_str(FREE, "free (test)", &[format!("drive.frequency_hz={f:e}")]).unwrap();
        let rep = floquet(&s, &FloquetOptions::default()).unwrap();
        assert_eq!(rep.multipliers.len(), 4, "2 modes × (a, ȧ): the b blocks are left out");
        let want = multiplier(2.0, f);
        eprintln!("f = {f:e}: max|μ| = {:.6} (k = {}), closed form {want:.6}", rep.max_multiplier, rep.mode);
        assert!(!rep.unstable && rep.mode == 2);
        assert!((rep.max_multiplier / want - 1.0).abs() < 1e-3, "{} vs {want}", rep.max_multiplier);
    }
    // with a membrane b_k is stiff and stays in the verdict (3 per mode)
    let coated = FREE.replace("c1 = 0.0\nc2 = 0.0\n", "");
    let rep = floquet(&scene::load_str(&coated, "coated (test)", &[] as &[&str]).unwrap(), &FloquetOptions::default()).unwrap();
    assert_eq!(rep.multipliers.len(), 6);
}

#[test]
fn figure_5_on_a_free_bubble_finds_critical_pressures() {
    let tmp = tempfile::tempdir().unwrap();
    let scenes = tmp.path().join("scenes");
    std::fs::create_dir(&scenes).unwrap();
    std::fs::write(scenes.join("fig05_modes.toml"), FREE.replace("max_order = 4", "max_order = 16")).unwrap();
    let out = tmp.path().join("out");
    let st = Command::new(env!("CARGO_BIN_EXE_magbubble"))
        .args(["figure", "5", "--quick", "--scenes"])
        .arg(&scenes)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(st.status.success(), "{}", String::from_utf8_lossy(&st.stderr));
    let csv = std::fs::read_to_string(out.join("fig05.csv")).unwrap();
    for f in ["fig05.md", "fig05.svg", "fig05.png"] {
        assert!(out.join(f).exists(), "{f}");
    }
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), 12, "{csv}");
    assert!(rows.iter().all(|r| !r.contains("unstable_at_bottom")), "{csv}");
    // near the radial resonance the quadrupole goes unstable; above it the free bubble is stable to ε_p = 1
    assert!(rows.iter().any(|r| r.contains("5e5") && r.contains(",critical,2")), "{csv}");
    assert!(rows.iter().filter(|r| r.contains("stable_throughout")).count() >= 8, "{csv}");
}

/// `modes --damped` on a free bubble: the (a, ȧ) block's eigenvalues, s = −γ ± i√(ω_L² − γ²) with
/// the closed-form γ above and Lamb's ω_L² = (k−1)(k+1)(k+2)σ/(ρR0³).
#[test]
fn free_bubble_damped_spectrum_is_the_boundary_layer_decay_of_lamb_modes() {
    use magbubble::model::vorticity::scene::damped_spectrum;
    let s = scene::load_str(FREE, "free (test)", &[] as &[&str]).unwrap();
    let d = damped_spectrum(&s).unwrap();
    for m in &d.shape {
        let k = m.k as f64;
        let gamma = -multiplier(k, 1e6).ln() * 1e6;
        let wl2 = (k - 1.0) * (k + 1.0) * (k + 2.0) * 0.072 / (1000.0 * 1e-15);
        let w = (wl2 - gamma * gamma).sqrt();
        eprintln!("k = {k}: decay {:.6e} vs {gamma:.6e}, ω {:.6e} vs {w:.6e}", m.decay_per_s, m.omega_rad_s);
        assert!((m.decay_per_s / gamma - 1.0).abs() < 1e-9 && (m.omega_rad_s / w - 1.0).abs() < 1e-9, "{m:?}");
    }
}
