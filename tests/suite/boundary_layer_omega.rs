//! δ_k's ω_k (FORMULATION audit 13; issue 31 part 3): from the full stiffness of the assembled
//! laws, against the closed forms — Lamb's for surface tension, §4.4's for Mooney–Rivlin.

use crate::common;
use crate::common::water::*;
use magbubble::model::Model;
use magbubble::scene::load;

/// √(ν/ω_k) in SI of each mode of a scene.
fn viscous_lengths(s: &magbubble::scene::Scene) -> Vec<(f64, f64)> {
    let m = Model::from_scene(s).unwrap();
    let len = s.bubble.radius;
    m.boundary_layer().unwrap().modes().iter().map(|md| (md.k, md.viscous_length * len)).collect()
}

#[test]
fn free_bubble_with_surface_tension_takes_lambs_omega_k() {
    // the scene: k = 2 at R0 = 10 µm, γ = 0.072 N/m: ω_2 = 9.30e5 rad/s, δ_2 = 1.04 µm
    let s = load(
        "scenes/free_bubble.toml",
        &["shell.surface_tension=0.072", "bubble.radius=10e-6", "gas.vapour_pressure=0", "drive.amplitude=0", "modes.max_order=8"],
    )
    .unwrap();
    let r0: f64 = 10e-6;
    for (k, vl) in viscous_lengths(&s) {
        let w2 = (k - 1.0) * (k + 1.0) * (k + 2.0) * GAMMA / (RHO * r0.powi(3));
        let want = (ETA / RHO / w2.sqrt()).sqrt();
        assert!((vl - want).abs() < 1e-12 * want, "k={k}: {vl:e} vs {want:e}");
    }
}

#[test]
fn mooney_rivlin_takes_the_closed_form_of_section_4_4() {
    let mut s = common::scene(12, 0.0, 1e6);
    s.drive = None;
    let r0 = common::R0;
    for (k, vl) in viscous_lengths(&s) {
        let w2 = 12.0 * (common::C1 + common::C2) * (k - 1.0) * (k + 1.0) * (k + 2.0) / (RHO * r0.powi(3) * (2.0 * k * k + 2.0 * k - 1.0));
        let want = (ETA / RHO / w2.sqrt()).sqrt();
        assert!((vl - want).abs() < 1e-12 * want, "k={k}: {vl:e} vs {want:e}");
    }
}
