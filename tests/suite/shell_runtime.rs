//! The shell laws in the model (issue 11 part 3, issue 10 part 2): `modes` against the closed
//! forms of the linearization, the free radial decay with a dilatational viscosity, and each
//! effect off = the model as before.

use crate::common;
use crate::support::prony::prony;
use magbubble::analysis::frequencies::natural_frequencies;
use magbubble::scene::ShellLaw;
use crate::common::water::*;


#[test]
fn skalak_radial_frequency_has_the_area_modulus_k_equal_gs_1_plus_2c() {
    let r0 = common::R0;
    for &(gs, c) in &[(0.2, 0.0), (0.44, 1.0), (0.1, 30.0)] {
        let mut s = common::scene(4, 0.0, 1e6);
        s.shell.law = ShellLaw::Skalak { shear_modulus: gs, area_dilatation: c };
        let f = natural_frequencies(&s, 4).unwrap();
        let k_mod = gs * (1.0 + 2.0 * c);
        let w2 = (3.0 * 1.4 * P0 + 4.0 * k_mod / r0) / (RHO * r0 * r0);
        assert!((f.radial.omega_rad_s - w2.sqrt()).abs() < 1e-6 * w2.sqrt(), "Gs={gs} C={c}: {} vs {}", f.radial.omega_rad_s, w2.sqrt());
    }
}

#[test]
fn skalak_with_gs_2_c1_plus_c2_and_c_1_has_the_mooney_rivlin_radial_frequency() {
    // small strain: G = 2(c1 + c2), K = 6(c1 + c2) for Mooney–Rivlin; Skalak K = G_s(1 + 2C)
    let mr = natural_frequencies(&common::scene(4, 0.0, 1e6), 4).unwrap();
    let mut s = common::scene(4, 0.0, 1e6);
    s.shell.law = ShellLaw::Skalak { shear_modulus: 2.0 * (common::C1 + common::C2), area_dilatation: 1.0 };
    let sk = natural_frequencies(&s, 4).unwrap();
    assert!((mr.radial.omega_rad_s - sk.radial.omega_rad_s).abs() < 1e-9 * mr.radial.omega_rad_s);
}

#[test]
fn surface_tension_and_bending_add_lamb_and_helfrich_to_every_mode() {
    // ω_k² − ω_k²(membrane only) = (k−1)(k+1)(k+2)[γ + k_b k(k+1)/R0²]/(ρR0³): the linearization
    // with S1 += (k−1)(k+2)γ/R0² + (k−1)k(k+1)(k+2)k_b/R0⁴ and nothing on S2, S11, S12.
    let r0 = common::R0;
    let base = natural_frequencies(&common::scene(16, 0.0, 1e6), 16).unwrap();
    for &(gamma, kb) in &[(0.05, 0.0), (0.0, 1e-15), (0.072, 5e-17)] {
        let mut s = common::scene(16, 0.0, 1e6);
        s.shell.surface_tension = gamma;
        s.shell.bending_modulus = kb;
        let f = natural_frequencies(&s, 16).unwrap();
        for (b, w) in base.shape.iter().zip(&f.shape) {
            assert_eq!(b.k, w.k);
            let k = w.k as f64;
            let extra = (k - 1.0) * (k + 1.0) * (k + 2.0) * (gamma + kb * k * (k + 1.0) / (r0 * r0)) / (RHO * r0.powi(3));
            let got = w.omega_rad_s.powi(2) - b.omega_rad_s.powi(2);
            assert!((got - extra).abs() <= 1e-8 * w.omega_rad_s.powi(2), "γ={gamma} kb={kb} k={}: Δω² {got:e} vs {extra:e}", w.k);
        }
        // radial, at rest in equilibrium at R0 (p_g0 = p0 + 2γ/R0, set explicitly: the default rule
        // is issue 10 part 3): R0 dŜ0/dR adds −2γ/R0 (a sphere's bending energy does not depend on R)
        let pg0 = P0 + 2.0 * gamma / r0;
        s.gas.reference_pressure = pg0;
        let f = natural_frequencies(&s, 16).unwrap();
        let w2 = (3.0 * 1.4 * pg0 + 24.0 * (common::C1 + common::C2) / r0 - 2.0 * gamma / r0) / (RHO * r0 * r0);
        assert!((f.radial.omega_rad_s - w2.sqrt()).abs() < 1e-6 * w2.sqrt(), "{} vs {}", f.radial.omega_rad_s, w2.sqrt());
    }
}

/// The free radial decay rate of R(t) − R0 from a small initial displacement (Prony fit).
fn radial_decay(kappa_s: f64) -> f64 {
    let mut s = common::scene(0, 0.0, 1e6);
    s.drive = None;
    s.shell.dilatational_viscosity = kappa_s;
    let r0 = common::R0;
    s.bubble.initial.radius = r0 * (1.0 + 1e-6);
    let w0 = natural_frequencies(&common::scene(2, 0.0, 1e6), 2).unwrap().radial.omega_rad_s;
    let period = 2.0 * std::f64::consts::PI / w0;
    s.run.sample_interval = period / 60.0;
    s.run.duration = 3.0 * period;
    s.run.integrator.rtol = 1e-11;
    s.run.integrator.atol = 1e-20;
    let mut xs = vec![];
    let rep = magbubble::model::simulate(&s, &mut |_, row| xs.push(row[0] - r0)).unwrap();
    assert!(matches!(rep.status, magbubble::model::RunStatus::Completed), "{:?}", rep.status);
    let roots = prony(&xs, s.run.sample_interval, 2);
    let z = roots.iter().find(|r| r.im > 0.0).copied().expect("an oscillatory exponent");
    -z.re
}

#[test]
fn dilatational_viscosity_adds_2_kappa_s_over_rho_r0_cubed_to_the_radial_decay() {
    let r0 = common::R0;
    let base = radial_decay(0.0);
    // the liquid's own rate 2η/(ρR0²) first (same fit, same linearization)
    let eta_rate = 2.0 * 1e-3 / (RHO * r0 * r0);
    assert!((base - eta_rate).abs() < 1e-3 * eta_rate, "base {base:e} vs 2η/(ρR0²) {eta_rate:e}");
    for kappa_s in [1e-9, 5e-9] {
        let got = radial_decay(kappa_s) - base;
        let expect = 2.0 * kappa_s / (RHO * r0.powi(3));
        assert!((got - expect).abs() < 1e-3 * expect, "κs={kappa_s}: Δ decay {got:e} vs 2κs/(ρR0³) {expect:e}");
    }
}

#[test]
fn effects_off_assemble_nothing_new() {
    let s = common::scene(4, 0.0, 1e6);
    let m = magbubble::model::Model::from_scene(&s).unwrap();
    let eq = m.boundary_layer().unwrap().equations();
    for name in ["surface tension", "bending", "shell viscosity"] {
        assert!(!eq.has(name), "{name} assembled although off");
    }
    let mut on = s.clone();
    on.shell.surface_tension = 0.05;
    on.shell.bending_modulus = 1e-18;
    let m = magbubble::model::Model::from_scene(&on).unwrap();
    let eq = m.boundary_layer().unwrap().equations();
    assert!(eq.has("surface tension") && eq.has("bending"));
}

#[test]
fn scene_keys_select_the_law_and_the_effects() {
    let s = magbubble::scene::load_str(
        "[shell]\nlaw = \"skalak\"\narea_dilatation = 3.0\nsurface_tension = 0.04\nbending_modulus = 2e-19\n",
        "test.toml",
        &[] as &[&str],
    )
    .unwrap();
    // G_s defaults to 2 (c1 + c2) of the (default) Mooney–Rivlin constants
    assert_eq!(s.shell.law, ShellLaw::Skalak { shear_modulus: 2.0 * (0.1 + 0.12), area_dilatation: 3.0 });
    assert_eq!((s.shell.surface_tension, s.shell.bending_modulus), (0.04, 2e-19));
    for (toml, key) in [
        ("[shell]\nlaw = \"neo-hookean\"\n", "shell.law"),
        ("[shell]\nsurface_tension = -1.0\n", "shell.surface_tension"),
        ("[shell]\nshear_viscosity = -1e-9\n", "shell.shear_viscosity"),
        ("[shell]\nshear_viscosity = 1e-9\n[modes]\nviscous = \"vorticity\"\n", "shell.shear_viscosity"),
        ("[shell]\ndilatational_viscosity = 1e-9\n[modes]\nmax_order = 4\nviscous = \"vorticity\"\n", "shell.dilatational_viscosity"),
    ] {
        let e = magbubble::scene::load_str(toml, "test.toml", &[] as &[&str]).unwrap_err().to_string();
        assert!(e.contains(key), "{toml}: {e}");
    }
    let radial = magbubble::scene::load_str("[shell]\ndilatational_viscosity = 1e-9\n[modes]\nmax_order = 0\n", "test.toml", &[] as &[&str]).unwrap();
    assert_eq!(radial.shell.dilatational_viscosity, 1e-9);
    // with shape modes and the boundary layer both are wired (tests/suite/shell_viscosity.rs)
    let shape = magbubble::scene::load_str("[shell]\ndilatational_viscosity = 1e-9\nshear_viscosity = 1e-9\n[modes]\nmax_order = 4\n", "test.toml", &[] as &[&str]).unwrap();
    assert_eq!((shape.shell.dilatational_viscosity, shape.shell.shear_viscosity), (1e-9, 1e-9));
}
